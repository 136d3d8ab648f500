//! The photon record: 32 bytes, as the photon pass stores it and the hash grid sorts it.
//!
//! The density estimate does not read records: the grid copies position, flux and the
//! unfolded direction into columns (see `grid`), 8 candidates per block.

use glam::Vec3;

/// A photon stored on a surface: where it landed, where it came from and what it carries.
///
/// # Layout (`repr(C)`, 32 bytes, 32-byte aligned)
///
/// | offset | bytes | field      | encoding                                        |
/// |-------:|------:|------------|-------------------------------------------------|
/// |      0 |    12 | `position` | 3 x `f32`, world space                          |
/// |     12 |     4 | `wi`       | octahedral map, 2 x `i16` snorm (private)       |
/// |     16 |    12 | `flux`     | 3 x `f32`, linear RGB flux Φ in watts           |
/// |     28 |     4 | `path`     | `u32` index of the light path that deposited it |
///
/// The size is a power of two and the alignment equals it, so a record never straddles a
/// cache line: the append buffer, the counting sort and the per-bucket sort move whole
/// records, and [`super::HashGrid::for_each_in_radius`] hands them out.
///
/// # Direction convention
///
/// [`Photon::wi`] points *away* from the surface, back toward where the photon came from:
/// it is the negated direction of the ray that deposited the photon, the same convention as
/// the `wi` argument of [`crate::bsdf::Bsdf::eval`]. The radiance estimate at a gather point
/// with outgoing direction `wo` is then `Σ f(wo, photon.wi()) · photon.flux · k(d²)`.
#[repr(C, align(32))]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Photon {
    /// Where the photon landed.
    pub position: Vec3,
    /// Incoming direction, octahedral-encoded (see [`Photon::wi`]).
    wi: [i16; 2],
    /// Flux Φ carried by the photon (RGB, watts).
    pub flux: Vec3,
    /// Index of the light path that deposited the photon (several photons may share one).
    /// The photon pass of `ppm` stores its key here, the path index and the bounce
    /// ([`Photon::key`]); vcm stores the light vertex's index.
    pub path: u32,
}

/// Bits at the bottom of a photon-pass key ([`Photon::key`]) that hold the bounce; the light
/// path's index takes the other 26.
pub const BOUNCE_BITS: u32 = 6;

/// The deepest bounce a key tells apart: a photon of more bounces is recorded at this one.
pub const MAX_KEY_BOUNCE: u32 = (1 << BOUNCE_BITS) - 1;

const _: () = assert!(std::mem::size_of::<Photon>() == 32);
const _: () = assert!(std::mem::align_of::<Photon>() == 32);

impl Photon {
    /// An all-zero photon (no flux), used to fill unused storage.
    pub const ZERO: Photon = Photon {
        position: Vec3::ZERO,
        wi: [0, 0],
        flux: Vec3::ZERO,
        path: 0,
    };

    /// A photon at `position` that arrived from unit direction `wi` (pointing away from the
    /// surface), carrying `flux`, deposited by light path `path`.
    #[inline]
    pub fn new(position: Vec3, wi: Vec3, flux: Vec3, path: u32) -> Self {
        Photon {
            position,
            wi: oct_encode(wi),
            flux,
            path,
        }
    }

    /// The incoming direction (unit length, pointing away from the surface), decoded.
    ///
    /// The angular error of the 2 x 16-bit encoding is below 1e-4 radians.
    #[inline]
    pub fn wi(&self) -> Vec3 {
        oct_unfold(self.wi).normalize()
    }

    /// True if the photon arrived from the side of the surface that `n` points to
    /// (`wi . n > 0`). Cheaper than [`Photon::wi`]: the sign needs no normalisation.
    #[inline]
    pub fn arrived_from(&self, n: Vec3) -> bool {
        FluxRecord::from(self).arrived_from(n)
    }

    /// The incoming direction as stored, decoded but not normalised: the vector whose dot
    /// product with a normal decides [`Photon::arrived_from`].
    #[inline]
    pub(crate) fn wi_unfolded(&self) -> Vec3 {
        oct_unfold(self.wi)
    }

    /// The key of the photon that light path `path` (below 2^26) left at its hit number
    /// `bounce + 1`: `path << BOUNCE_BITS | min(bounce, MAX_KEY_BOUNCE)`. It orders a photon
    /// map by (path, bounce) whatever the thread schedule, and lets a gather count only the
    /// photons of few enough bounces ([`Photon::bounce`]).
    #[inline]
    pub fn key(path: u32, bounce: u32) -> u32 {
        (path << BOUNCE_BITS) | bounce.min(MAX_KEY_BOUNCE)
    }

    /// The bounce held in a key's low bits ([`Photon::key`]); exact up to [`MAX_KEY_BOUNCE`].
    #[inline]
    pub fn bounce(&self) -> u32 {
        self.path & MAX_KEY_BOUNCE
    }

    /// A total order key: the path index first, then every other bit of the record.
    ///
    /// Two photons with equal keys are identical, so sorting by this key gives an order that
    /// depends only on the set of photons, never on the order they were stored in.
    #[inline]
    pub(crate) fn order_key(&self) -> [u32; 8] {
        let p = self.position;
        let f = self.flux;
        let wi = (self.wi[0] as u16 as u32) << 16 | self.wi[1] as u16 as u32;
        [
            self.path,
            p.x.to_bits(),
            p.y.to_bits(),
            p.z.to_bits(),
            f.x.to_bits(),
            f.y.to_bits(),
            f.z.to_bits(),
            wi,
        ]
    }
}

/// What a density estimate needs of a photon inside the gather disc: its flux and the side
/// it arrived from, 16 bytes (handed out by [`super::HashGrid::for_each_flux_in_radius`]).
#[repr(C, align(16))]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FluxRecord {
    /// Flux Φ carried by the photon (RGB, watts).
    pub flux: Vec3,
    /// Incoming direction, octahedral-encoded as in [`Photon`].
    wi: [i16; 2],
}

const _: () = assert!(std::mem::size_of::<FluxRecord>() == 16);

impl From<&Photon> for FluxRecord {
    #[inline]
    fn from(photon: &Photon) -> Self {
        FluxRecord {
            flux: photon.flux,
            wi: photon.wi,
        }
    }
}

impl FluxRecord {
    /// True if the photon arrived from the side of the surface that `n` points to, exactly
    /// as [`Photon::arrived_from`].
    #[inline]
    pub fn arrived_from(&self, n: Vec3) -> bool {
        oct_unfold(self.wi).dot(n) > 0.0
    }
}

/// ±1 with the sign of `x` (+1 for ±0), so that the fold below never multiplies by zero.
#[inline]
fn sign_not_zero(x: f32) -> f32 {
    1.0f32.copysign(x)
}

/// Octahedral map (Cigolle et al. 2014): project the unit vector onto the octahedron
/// |x| + |y| + |z| = 1, fold the lower half over the diagonals onto the square [-1, 1]²,
/// and quantise each coordinate to a 16-bit signed normalised integer.
#[inline]
fn oct_encode(v: Vec3) -> [i16; 2] {
    let l1 = v.x.abs() + v.y.abs() + v.z.abs();
    let (mut u, mut w) = (v.x / l1, v.y / l1);
    if v.z < 0.0 {
        (u, w) = (
            (1.0 - w.abs()) * sign_not_zero(u),
            (1.0 - u.abs()) * sign_not_zero(w),
        );
    }
    let q = |x: f32| (x.clamp(-1.0, 1.0) * 32767.0).round() as i16;
    [q(u), q(w)]
}

/// Inverse of [`oct_encode`] up to length: unfold the square back onto the octahedron
/// (|x| + |y| + |z| = 1); normalising gives the direction.
#[inline]
fn oct_unfold(e: [i16; 2]) -> Vec3 {
    let u = e[0] as f32 * (1.0 / 32767.0);
    let w = e[1] as f32 * (1.0 / 32767.0);
    let z = 1.0 - u.abs() - w.abs();
    let (x, y) = if z < 0.0 {
        (
            (1.0 - w.abs()) * sign_not_zero(u),
            (1.0 - u.abs()) * sign_not_zero(w),
        )
    } else {
        (u, w)
    };
    Vec3::new(x, y, z)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::{uniform_sphere, Rng};

    /// Angle between two unit vectors, accurate for tiny angles (atan2 of |cross| and dot).
    fn angle(a: Vec3, b: Vec3) -> f32 {
        a.cross(b).length().atan2(a.dot(b))
    }

    #[test]
    fn wi_round_trip_error_is_small() {
        let mut max_err = 0.0f32;
        let mut check = |v: Vec3| {
            let photon = Photon::new(Vec3::ZERO, v, Vec3::ONE, 0);
            let d = photon.wi();
            assert!(
                (d.length() - 1.0).abs() < 1e-6,
                "{v} decoded to non-unit {d}"
            );
            max_err = max_err.max(angle(v, d));
        };
        let mut rng = Rng::new(7, 0, 0);
        for _ in 0..200_000 {
            check(uniform_sphere(rng.uniform2()));
        }
        // The axes, the octahedron's edges and the fold seam (z = 0) are the special cases.
        for v in [Vec3::X, Vec3::Y, Vec3::Z, -Vec3::X, -Vec3::Y, -Vec3::Z] {
            check(v);
        }
        for (x, y, z) in [
            (1.0, 1.0, 0.0),
            (-1.0, 1.0, 0.0),
            (1.0, -1.0, -1e-7),
            (0.0, 1.0, -1.0),
        ] {
            check(Vec3::new(x, y, z).normalize());
        }
        assert!(max_err < 1e-4, "max angular error {max_err} rad");
        // And the error is not suspiciously zero (the encoding does quantise).
        assert!(max_err > 1e-6, "max angular error {max_err} rad");
    }

    #[test]
    fn fields_round_trip() {
        let wi = Vec3::new(0.3, -0.4, 0.5).normalize();
        let photon = Photon::new(Vec3::new(-1.0, 2.0, 3.5), wi, Vec3::new(0.1, 0.2, 0.3), 42);
        assert_eq!(photon.position, Vec3::new(-1.0, 2.0, 3.5));
        assert_eq!(photon.flux, Vec3::new(0.1, 0.2, 0.3));
        assert_eq!(photon.path, 42);
        assert!(angle(photon.wi(), wi) < 1e-4);
    }

    #[test]
    fn order_key_distinguishes_every_field() {
        let base = Photon::new(Vec3::ONE, Vec3::Z, Vec3::ONE, 1);
        let variants = [
            Photon { path: 2, ..base },
            Photon {
                position: Vec3::new(1.0, 1.0, 2.0),
                ..base
            },
            Photon {
                flux: Vec3::new(1.0, 0.5, 1.0),
                ..base
            },
            Photon::new(Vec3::ONE, Vec3::X, Vec3::ONE, 1),
        ];
        for v in variants {
            assert_ne!(v.order_key(), base.order_key(), "{v:?}");
        }
        assert!(Photon { path: 0, ..base }.order_key() < base.order_key());
    }
}
