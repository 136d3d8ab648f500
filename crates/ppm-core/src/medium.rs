//! Absorbing media bounded by surfaces: Beer-Lambert attenuation along the segments of a path.
//!
//! A medium here only absorbs (no scattering, no emission), with a per-channel absorption
//! coefficient `sigma_a` in 1 / scene unit. Radiance (or flux) travelling a distance `t`
//! through it is multiplied by the transmittance (Beer-Lambert; pbrt-v4 sec. 11.2, eq. 11.6
//! with sigma_t = sigma_a):
//!
//! `T(t) = exp(-sigma_a t)`, per channel.
//!
//! Since nothing is sampled in the medium (no free-flight distances), `T` is a factor of the
//! path's contribution only, never of a pdf: the MIS weights of every estimator are those of
//! the same scene without absorption.
//!
//! # Which medium a segment is in: the stateless rule
//!
//! Every surface carries a [`MediumInterface`]: the medium on the side its geometric normal
//! points to (`exterior`) and on the other side (`interior`), as Mitsuba 3's shapes carry an
//! `exterior` and `interior` medium and pbrt-v4's a `MediumInterface`. A ray segment from one
//! surface point to the next crosses no surface in between (that is what the nearest hit
//! means), so it lies in one medium, and both of its ends agree which one it is. ppm asks the
//! surface the segment ends on (or, for shadow rays and connections, the one it leaves, which
//! is the same medium): the side the segment arrives from, `dot(d, ng) < 0` => the
//! exterior medium of that surface, else its interior ([`MediumInterface::toward`]).
//!
//! The rule needs no state on the path (no medium stack, no "current medium" handed from
//! vertex to vertex): every estimator (camera paths, photons, light subpaths, shadow rays,
//! connections between two subpaths in any order) asks the segment's end point, so they agree
//! by construction, and a camera inside a medium needs no declaration of its own. A medium
//! stack (pbrt-v4 and Mitsuba 3 track the ray's current medium and switch it at each
//! transmission through a surface with a medium interface) gives the same answer for closed,
//! properly labelled surfaces, but each connection then needs the media of both subpaths'
//! vertices and the camera and lights need media of their own.
//!
//! It is exact when the labels are consistent: every surface bounding a medium is closed and
//! says on which side the medium is, and where two media touch (water in a glass) the one
//! surface between them names both (water inside, glass outside). Its failure cases, where the
//! answer is that of whatever the surface declares:
//! - a surface inside a medium that does not name it (a diffuse floor at the bottom of a pool
//!   whose material has no exterior absorption): the segment ending on it is not attenuated;
//! - open meshes, or closed ones with flipped normals: the sides are swapped or undefined;
//! - overlapping volumes (two glass spheres intersecting): inside both, the segment takes the
//!   medium of whichever surface it ends on;
//! - a ray that escapes the scene ends on no surface and is taken as clear; from inside a
//!   closed medium no ray escapes, so this too is the open-mesh case.

use glam::Vec3;

/// The absorbing media on the two sides of a surface: per-channel absorption coefficients
/// `sigma_a` (1 / scene unit), zero for a clear medium (vacuum or air).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MediumInterface {
    /// `sigma_a` on the side opposite the geometric normal (inside a closed surface with
    /// outward normals).
    pub interior: Vec3,
    /// `sigma_a` on the side the geometric normal points to.
    pub exterior: Vec3,
}

impl MediumInterface {
    /// Clear on both sides.
    pub const CLEAR: MediumInterface = MediumInterface {
        interior: Vec3::ZERO,
        exterior: Vec3::ZERO,
    };

    /// True if neither side absorbs.
    #[inline]
    pub fn is_clear(&self) -> bool {
        self.interior == Vec3::ZERO && self.exterior == Vec3::ZERO
    }

    /// `sigma_a` of the medium on the side of the surface that the direction `w` (leaving the
    /// surface) points into: the exterior if `dot(w, ng) > 0`, the interior otherwise. A
    /// segment arriving along `d` came from the side `-d` points to: `toward(-d, ng)`.
    #[inline]
    pub fn toward(&self, w: Vec3, ng: Vec3) -> Vec3 {
        if w.dot(ng) > 0.0 {
            self.exterior
        } else {
            self.interior
        }
    }
}

/// Beer-Lambert transmittance `exp(-sigma_a t)` over a distance `t >= 0`, per channel.
/// Exactly 1 for a clear medium, whatever `t` (also infinite).
#[inline]
pub fn transmittance(sigma_a: Vec3, t: f32) -> Vec3 {
    if sigma_a == Vec3::ZERO {
        return Vec3::ONE;
    }
    let tau = sigma_a * t;
    // exp(-0 * inf) would be NaN: a clear channel transmits fully at any distance.
    Vec3::new(
        channel(sigma_a.x, tau.x),
        channel(sigma_a.y, tau.y),
        channel(sigma_a.z, tau.z),
    )
}

#[inline]
fn channel(sigma_a: f32, tau: f32) -> f32 {
    if sigma_a == 0.0 {
        1.0
    } else {
        (-tau).exp()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transmittance_is_beer_lambert_per_channel() {
        let sigma = Vec3::new(0.5, 0.0, 2.0);
        let t = transmittance(sigma, 1.5);
        assert_eq!(t.y, 1.0);
        assert!((t.x - (-0.75f32).exp()).abs() < 1e-7);
        assert!((t.z - (-3.0f32).exp()).abs() < 1e-7);
        // Multiplicative over consecutive segments.
        let two = transmittance(sigma, 0.5) * transmittance(sigma, 1.0);
        assert!((two - t).abs().max_element() < 1e-6);
        // Clear media and infinite distances give no NaN.
        assert_eq!(transmittance(Vec3::ZERO, f32::INFINITY), Vec3::ONE);
        assert_eq!(
            transmittance(sigma, f32::INFINITY),
            Vec3::new(0.0, 1.0, 0.0)
        );
    }

    #[test]
    fn the_side_a_direction_points_to_decides_the_medium() {
        let m = MediumInterface {
            interior: Vec3::X,
            exterior: Vec3::Y,
        };
        let ng = Vec3::Z;
        assert_eq!(m.toward(Vec3::new(0.3, 0.0, 0.9), ng), Vec3::Y);
        assert_eq!(m.toward(Vec3::new(0.3, 0.0, -0.9), ng), Vec3::X);
        // A ray arriving from outside (d . ng < 0) travelled in the exterior.
        let d = Vec3::new(0.0, 0.6, -0.8);
        assert_eq!(m.toward(-d, ng), Vec3::Y);
        assert!(MediumInterface::CLEAR.is_clear() && !m.is_clear());
    }
}
