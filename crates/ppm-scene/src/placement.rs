//! Placing geometry by a 4x4 transform, shared by scene format v1's `transform:` and the
//! Mitsuba importer's `to_world`: points by the matrix M, normals by its inverse transpose
//! M^-T (a normal n stays perpendicular to every transformed tangent t: (M^-T n) . (M t) =
//! n . t = 0), and a mirroring M (det < 0) reverses each triangle's winding, so the geometric
//! normal cross(v1 - v0, v2 - v0), which fixes the emitting side and a dielectric's outside,
//! is the transformed one rather than its opposite (cross(M a, M b) = det(M) M^-T (a x b)).

use glam::{DMat3, DMat4, DVec3, Vec3};
use ppm_core::geometry::TriangleMesh;

/// Why a transform cannot place a shape.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlacementError {
    /// Determinant zero or not finite: the shape would be flattened.
    Singular,
    /// A transformed point or radius leaves single precision.
    OutOfRange,
    /// Not a rotation times a uniform scale plus a translation: a sphere would not stay one.
    NotSimilar,
}

impl PlacementError {
    /// The error in words, after what it is about (e.g. "to_world" or "transform").
    pub fn describe(self, what: &str) -> String {
        match self {
            PlacementError::Singular => format!("{what} is singular (it flattens the shape)"),
            PlacementError::OutOfRange => {
                format!("{what} takes points out of single-precision range")
            }
            PlacementError::NotSimilar => format!(
                "{what} does not keep a sphere a sphere (non-uniform scale or shear); only rotation, uniform scale and translation"
            ),
        }
    }
}

/// Moves `mesh` by `m` in double precision: points by `m`, shading normals by its inverse
/// transpose (negated with `flip`), and the winding reversed when exactly one of a mirroring
/// `m` and `flip` holds. Returns false when some shading normals became zero or not finite
/// (they are then dropped: the mesh is shaded by its faces' normals).
pub fn place_mesh(mesh: &mut TriangleMesh, m: DMat4, flip: bool) -> Result<bool, PlacementError> {
    let linear = DMat3::from_mat4(m);
    let det = linear.determinant();
    if !(det.is_finite() && det != 0.0) {
        return Err(PlacementError::Singular);
    }
    for x in &mut mesh.positions {
        *x = m.transform_point3(x.as_dvec3()).as_vec3();
    }
    if mesh.positions.iter().any(|x| !x.is_finite()) {
        return Err(PlacementError::OutOfRange);
    }
    let normal_matrix = linear.inverse().transpose();
    let sign = if flip { -1.0 } else { 1.0 };
    for n in &mut mesh.normals {
        *n = (sign * (normal_matrix * n.as_dvec3()).normalize_or_zero()).as_vec3();
    }
    let normals_ok = mesh
        .normals
        .iter()
        .all(|n| n.is_finite() && (n.length() - 1.0).abs() <= 1e-3);
    if !normals_ok {
        mesh.normals.clear();
    }
    if (det < 0.0) != flip {
        for t in &mut mesh.indices {
            t.swap(1, 2);
        }
    }
    Ok(normals_ok)
}

/// The centre and radius of the sphere (`center`, `radius`) moved by `m`, which must be a
/// similarity (rotation or mirror, uniform scale s, translation): the radius becomes s r.
/// A mirror keeps the sphere's outside outside, so the sphere's facing is unchanged.
pub fn place_sphere(center: DVec3, radius: f64, m: DMat4) -> Result<(Vec3, f32), PlacementError> {
    let linear = DMat3::from_mat4(m);
    let lengths = [linear.x_axis, linear.y_axis, linear.z_axis].map(|a| a.length());
    let s = lengths[0];
    let similar = lengths.iter().all(|l| (l - s).abs() <= 1e-6 * s)
        && linear.x_axis.dot(linear.y_axis).abs() <= 1e-6 * s * s
        && linear.y_axis.dot(linear.z_axis).abs() <= 1e-6 * s * s
        && linear.x_axis.dot(linear.z_axis).abs() <= 1e-6 * s * s;
    if !(s.is_finite() && s > 0.0) {
        return Err(PlacementError::Singular);
    }
    if !similar {
        return Err(PlacementError::NotSimilar);
    }
    let c = m.transform_point3(center).as_vec3();
    let r = (radius * s) as f32;
    if !(c.is_finite() && r.is_finite() && r > 0.0) {
        return Err(PlacementError::OutOfRange);
    }
    Ok((c, r))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A mirror keeps the geometric normal the transformed one: a quad facing +z mirrored in
    /// x still faces +z, and mirrored in z faces -z.
    #[test]
    fn mirrors_reverse_the_winding_and_keep_the_transformed_normal() {
        let quad = || TriangleMesh::quad(Vec3::ZERO, Vec3::X, Vec3::Y, 0);
        let normal = |m: &TriangleMesh| {
            let p = m.indices[0].map(|i| m.positions[i as usize]);
            (p[1] - p[0]).cross(p[2] - p[0]).normalize()
        };
        for (scale, expected) in [
            (DVec3::new(-1.0, 1.0, 1.0), Vec3::Z),
            (DVec3::new(1.0, 1.0, -2.0), Vec3::NEG_Z),
            (DVec3::new(3.0, 1.0, 1.0), Vec3::Z),
        ] {
            let mut q = quad();
            place_mesh(&mut q, DMat4::from_scale(scale), false).unwrap();
            assert!(normal(&q).abs_diff_eq(expected, 1e-6), "{scale}");
        }
        let mut q = quad();
        let flat = DMat4::from_scale(DVec3::new(1.0, 0.0, 1.0));
        assert_eq!(
            place_mesh(&mut q, flat, false),
            Err(PlacementError::Singular)
        );
    }

    #[test]
    fn spheres_take_similarities_only() {
        let m = DMat4::from_scale_rotation_translation(
            DVec3::splat(2.0),
            glam::DQuat::from_rotation_y(0.3),
            DVec3::new(1.0, 2.0, 3.0),
        );
        let (c, r) = place_sphere(DVec3::X, 0.5, m).unwrap();
        assert_eq!(r, 1.0);
        assert!(c.abs_diff_eq(m.transform_point3(DVec3::X).as_vec3(), 1e-6));
        let stretch = DMat4::from_scale(DVec3::new(1.0, 2.0, 1.0));
        assert_eq!(
            place_sphere(DVec3::ZERO, 1.0, stretch),
            Err(PlacementError::NotSimilar)
        );
    }
}
