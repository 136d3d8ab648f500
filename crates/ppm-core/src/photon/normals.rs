//! The normals of a gather point, and what a photon arriving there is worth to a density
//! estimate when the surface is shaded with interpolated normals.

use glam::Vec3;

/// The geometric and the shading normal of a gather point, both turned toward the viewer.
///
/// The radiance a diffuse lobe reflects is L(x, wo) = f ∫ L_i(wi) |wi . ns| dwi: the cosine
/// is the shading normal's, as in the path tracer. Photons land on the geometric surface,
/// so their density per unit area estimates the irradiance ∫ L_i(wi) |wi . ng| dwi, the
/// geometric normal's. Each photon is therefore weighted by
///
/// ```text
/// w(wi) = (wi . ns) / (wi . ng)   if wi . ng > 0 and wi . ns > 0,   else 0,
/// ```
///
/// which turns one integral into the other (Veach 1997, sec. 5.3: the same ratio as the
/// adjoint BSDF's correction on the light path, `crate::bsdf::shading_normal_correction`).
/// A photon from behind the geometric surface lit the back of a thin wall, and one from
/// below the shading hemisphere meets a BSDF that reflects nothing toward it (the path
/// tracer's [`crate::integrator::ShadingFrame::consistent`] rejects the same directions).
/// With flat shading (ns = ng) the weight is exactly 1 on the viewer's side.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GatherNormals {
    /// The geometric normal on the viewer's side.
    pub geometric: Vec3,
    /// The shading normal on the viewer's side (equal to `geometric` when flat).
    pub shading: Vec3,
}

impl GatherNormals {
    /// A flat-shaded gather point with normal `n` (on the viewer's side).
    pub fn flat(n: Vec3) -> Self {
        GatherNormals {
            geometric: n,
            shading: n,
        }
    }

    /// True if the two normals are the same: every photon from the viewer's side weighs 1.
    #[inline]
    pub fn is_flat(&self) -> bool {
        self.geometric == self.shading
    }

    /// The weight w(wi) of a photon that arrived from direction `wi` (pointing away from the
    /// surface, of any positive length); 0 for a direction from the wrong side and when
    /// the ratio is not finite (wi in the geometric plane).
    #[inline]
    pub fn weight(&self, wi: Vec3) -> f32 {
        let (cos_g, cos_s) = (wi.dot(self.geometric), wi.dot(self.shading));
        let w = cos_s / cos_g;
        if cos_g > 0.0 && cos_s > 0.0 && w < f32::INFINITY {
            w
        } else {
            0.0
        }
    }

    /// [`GatherNormals::weight`] for a light vertex on either side of the surface, as VCM's
    /// merging needs at a vertex whose BSDF transmits (a rough dielectric): light that
    /// arrived from the far side is refracted toward the viewer, and the irradiance it
    /// brings has the same cosine ratio |wi . ns| / |wi . ng|. 0 when wi lies on different
    /// sides of the two normals (a direction the shading normal would leak through) or in
    /// the geometric plane. A BSDF that only reflects evaluates to zero for the far side, so
    /// there this is [`GatherNormals::weight`].
    #[inline]
    pub fn weight_either_side(&self, wi: Vec3) -> f32 {
        let w = wi.dot(self.shading) / wi.dot(self.geometric);
        if w > 0.0 && w < f32::INFINITY {
            w
        } else {
            0.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn photons_weigh_the_ratio_of_the_cosines_on_the_viewers_side() {
        let up = Vec3::Y;
        let tilted = Vec3::new(0.6, 0.8, 0.0);
        let normals = GatherNormals {
            geometric: up,
            shading: tilted,
        };
        let wi = Vec3::new(0.0, 1.0, 0.0);
        assert!((normals.weight(wi) - 0.8).abs() < 1e-6);
        let wi = Vec3::new(0.6, 0.8, 0.0);
        assert!((normals.weight(wi) - 1.0 / 0.8).abs() < 1e-6);
        // Above the geometric surface, below the shading hemisphere: nothing.
        assert_eq!(normals.weight(Vec3::new(-0.9, 0.1, 0.0)), 0.0);
        // From behind the surface, and in its plane.
        assert_eq!(normals.weight(Vec3::new(0.6, -0.1, 0.0)), 0.0);
        assert_eq!(normals.weight(Vec3::X), 0.0);
        // Length does not matter (the grid stores unnormalised directions).
        assert_eq!(
            normals.weight(Vec3::new(0.3, 0.5, 0.2)),
            normals.weight(Vec3::new(0.3, 0.5, 0.2) * 1.7)
        );
        // Flat: 1 exactly on the viewer's side.
        let flat = GatherNormals::flat(up);
        assert!(flat.is_flat() && !normals.is_flat());
        assert_eq!(flat.weight(Vec3::new(0.3, 0.01, -0.4)), 1.0);
        assert_eq!(flat.weight(Vec3::new(0.3, -0.01, -0.4)), 0.0);
    }

    /// VCM's merge at a transmitting vertex: a light vertex from the far side weighs the
    /// same cosine ratio as its mirror image on the viewer's side; one between the two
    /// normals' planes (opposite sides of them) or in the geometric plane weighs nothing.
    #[test]
    fn light_vertices_from_the_far_side_weigh_the_same_ratio() {
        let normals = GatherNormals {
            geometric: Vec3::Y,
            shading: Vec3::new(0.6, 0.8, 0.0),
        };
        for wi in [Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.3, 0.5, 0.2)] {
            assert_eq!(normals.weight_either_side(wi), normals.weight(wi));
            assert_eq!(normals.weight_either_side(-wi), normals.weight(wi));
        }
        assert_eq!(normals.weight_either_side(Vec3::new(-0.9, 0.1, 0.0)), 0.0);
        assert_eq!(normals.weight_either_side(Vec3::new(0.9, -0.1, 0.0)), 0.0);
        assert_eq!(normals.weight_either_side(Vec3::Z), 0.0);
    }
}
