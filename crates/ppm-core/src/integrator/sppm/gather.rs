//! The density estimate of SPPM: each visible point gathers the photons of a batch that fell
//! inside its disc.

use super::photon_grid::PhotonGrid;
use super::pixel::{Accumulator, FixedPoint};
use super::visible_point::SplatPoint;

/// What the gathers of one batch counted.
#[derive(Clone, Copy, Debug, Default)]
pub struct SplatCounters {
    /// Photons deposited (on surfaces with a diffuse lobe).
    pub photons: u64,
    /// (photon, visible point) pairs added.
    pub splats: u64,
    /// Pairs dropped because the weighted flux was NaN or infinite.
    pub rejected: u64,
}

impl SplatCounters {
    /// Both counts added.
    pub fn merge(self, other: SplatCounters) -> SplatCounters {
        SplatCounters {
            photons: self.photons + other.photons,
            splats: self.splats + other.splats,
            rejected: self.rejected + other.rejected,
        }
    }
}

/// Adds to `acc` every photon of `grid` inside the disc of `point`.
///
/// For visible point x with weight beta f (see [`SplatPoint::weight`]) and radius R, the
/// photon p at x_p with flux Phi_p and incoming direction wi_p contributes
///   Phi += beta f Phi_p w(wi_p),  M += 1,   if |x - x_p| <= R, w(wi_p) > 0 and b_p <= b_max,
/// the uniform-kernel (disc) density estimate of Hachisuka et al. 2008 that the statistics
/// of [`super::pixel::PixelStatistics`] assume. w is the photon's weight for the visible
/// point's normals ([`crate::photon::GatherNormals::weight`]): 1 on a flat surface, the
/// ratio of the shading to the geometric cosine on one with interpolated normals, and 0 for
/// photons that arrived from the other side (they lit the back of a thin wall), as in `ppm`.
/// b_p is the photon's bounce and b_max the visible point's [`SplatPoint::max_bounce`]: the
/// path the pair closes has at most max_depth bounces, as in `ppm`
/// ([`crate::integrator::density_estimate`]).
///
/// The sums are fixed-point integers ([`FixedPoint`]): whether photons are splatted into
/// points or points gather photons, in any batches and any order, each pixel's M and Phi
/// are the same integers.
#[inline]
pub fn gather(
    grid: &PhotonGrid,
    point: &SplatPoint,
    acc: &mut Accumulator,
    code: &FixedPoint,
    counters: &mut SplatCounters,
) {
    let Some((x, r2)) = point.disc() else {
        return;
    };
    grid.for_each_candidate(x, r2, |xp, photon| {
        let inside = x.distance_squared(xp) <= r2;
        if !inside || photon.bounce > u32::from(point.max_bounce) {
            return;
        }
        let w = point.normals.weight(photon.wi);
        if w <= 0.0 {
            return;
        }
        let phi = point.weight * photon.flux * w;
        if !phi.is_finite() || phi.min_element() < 0.0 {
            counters.rejected += 1;
            return;
        }
        code.splat(acc, phi);
        counters.splats += 1;
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrator::sppm::photon::SppmPhoton;
    use crate::photon::GatherNormals;
    use crate::sampling::Rng;
    use glam::Vec3;

    /// Visible points in a unit cube with radii from 0.02 to 0.3, some without a point,
    /// some with interpolated normals, and bounce limits from 0 to 4.
    fn points(rng: &mut Rng) -> Vec<SplatPoint> {
        (0..400)
            .map(|i| {
                let p = Vec3::new(rng.uniform(), rng.uniform(), rng.uniform());
                let r = if i % 13 == 0 {
                    0.3
                } else {
                    0.02 + 0.08 * rng.uniform()
                };
                let n = Vec3::new(rng.uniform() - 0.5, rng.uniform() - 0.5, 1.0).normalize();
                let shading = if i % 3 == 0 {
                    (n + Vec3::new(0.3 * rng.uniform(), 0.0, 0.0)).normalize()
                } else {
                    n
                };
                SplatPoint {
                    p,
                    normals: GatherNormals {
                        geometric: n,
                        shading,
                    },
                    weight: Vec3::new(0.5, 1.0, 2.0) * (1.0 + rng.uniform()),
                    r2: r * r,
                    max_bounce: (i % 5) as u16,
                    found: i % 9 != 4,
                }
            })
            .collect()
    }

    /// Photons in and around the cube, from every direction, of bounces 0 to 5.
    fn photons(rng: &mut Rng, n: usize) -> Vec<SppmPhoton> {
        (0..n)
            .map(|_| SppmPhoton {
                position: Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * 1.2 - 0.1,
                wi: (Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) - 0.5).normalize(),
                flux: Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()),
                bounce: (rng.uniform() * 6.0) as u32,
            })
            .collect()
    }

    /// Each point's (M, Phi codes) by brute force: every photon against every point, in the
    /// estimate's own terms (disc, bounce limit, normals weight), each pair coded alone.
    fn brute_force(points: &[SplatPoint], photons: &[SppmPhoton]) -> Vec<(u64, [u64; 3])> {
        points
            .iter()
            .map(|vp| {
                let mut sum = (0u64, [0u64; 3]);
                for ph in photons {
                    let w = vp.normals.weight(ph.wi);
                    let inside = vp.p.distance_squared(ph.position) <= vp.r2;
                    if vp.found && inside && ph.bounce <= u32::from(vp.max_bounce) && w > 0.0 {
                        sum.0 += 1;
                        let phi = vp.weight * ph.flux * w;
                        for (s, v) in sum.1.iter_mut().zip(phi.to_array()) {
                            *s += (v as f64 * FixedPoint::FINE_SCALE).round() as u64;
                        }
                    }
                }
                sum
            })
            .collect()
    }

    /// The gathers over batches of any size (one batch, several, single photons, an empty
    /// one) add exactly the integers of brute force, pixel for pixel: no pair is missed or
    /// counted twice, and cutting the photons into batches changes no bit.
    #[test]
    fn batched_gathers_equal_brute_force_bit_for_bit() {
        let mut rng = Rng::new(11, 0, 0);
        let points = points(&mut rng);
        let photons = photons(&mut rng, 3000);
        let want = brute_force(&points, &photons);
        let pairs: u64 = want.iter().map(|w| w.0).sum();
        assert!(pairs > 1000, "the test must gather: {pairs}");
        let code = FixedPoint::new(1.0, FixedPoint::FINE_SCALE);
        let mut grid = PhotonGrid::new();
        grid.cover(&points);
        for batch in [3000usize, 1000, 7, 1] {
            let mut accumulators = vec![Accumulator::default(); points.len()];
            let mut counters = SplatCounters::default();
            for chunk in photons.chunks(batch).chain([&[][..]]) {
                grid.build(chunk);
                for (vp, acc) in points.iter().zip(&mut accumulators) {
                    gather(&grid, vp, acc, &code, &mut counters);
                }
            }
            assert_eq!(counters.splats, pairs, "batches of {batch}");
            assert_eq!(counters.rejected, 0);
            for (i, (acc, want)) in accumulators.iter_mut().zip(&want).enumerate() {
                let (m, phi) = code.take(acc);
                let phi = phi.map(|v| (v * FixedPoint::FINE_SCALE).round() as u64);
                assert_eq!((m, phi), *want, "point {i}, batches of {batch}");
            }
        }
    }
}
