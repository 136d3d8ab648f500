//! The photon pass of SPPM: light paths whose photons are splatted straight into the visible
//! points they fall near, and never stored.

use super::grid::{prefetch, VisiblePointGrid};
use super::pixel::{Accumulator, FixedPoint};
use super::visible_point::SplatPoint;
use crate::integrator::PhotonSink;
use glam::Vec3;

/// What one worker of the photon pass counted.
#[derive(Clone, Copy, Debug, Default)]
pub struct SplatCounters {
    /// Photons deposited (on surfaces with a diffuse lobe).
    pub photons: u64,
    /// (photon, visible point) pairs splatted.
    pub splats: u64,
    /// Splats dropped because the weighted flux was NaN or infinite.
    pub rejected: u64,
}

/// A [`PhotonSink`] that adds each photon to every visible point whose disc contains it.
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
/// path the splat closes has at most max_depth bounces, as in `ppm`
/// ([`crate::integrator::density_estimate`]).
///
/// Photons land anywhere in the scene, so each splat is a chain of reads that miss the
/// cache: the grid bucket's bounds, its entries, then the candidates' discs, visible points
/// and accumulators, each address known only once the read before it arrived. A photon is
/// therefore splatted [`DELAY`] deposits after it arrives, and each later deposit starts the
/// next read of the chain for the photons waiting ([`Splatter::deposit`]): the reads
/// then arrive while the light paths trace their next rays. The sums are integers, so the
/// order of the splats changes nothing. [`Splatter::finish`] splats the photons still
/// waiting; every pass must call it.
pub struct Splatter<'a> {
    grid: &'a VisiblePointGrid,
    points: &'a [SplatPoint],
    accumulators: &'a [Accumulator],
    code: &'a FixedPoint,
    counters: SplatCounters,
    /// The photons waiting, the newest first: `waiting[k]` arrived k deposits ago.
    waiting: [Option<Waiting>; DELAY],
}

/// Deposits between a photon's arrival and its splat.
const DELAY: usize = 3;

/// A photon waiting for its reads (see [`Splatter`]).
#[derive(Clone, Copy, Debug)]
struct Waiting {
    position: Vec3,
    wi: Vec3,
    flux: Vec3,
    bounce: u32,
    /// The bucket of the position's cell (`None`: outside every disc).
    bucket: Option<usize>,
}

impl<'a> Splatter<'a> {
    /// A splatter into `accumulators` (one per visible point of `points`, found through
    /// `grid`), in fixed-point code `code`.
    pub fn new(
        grid: &'a VisiblePointGrid,
        points: &'a [SplatPoint],
        accumulators: &'a [Accumulator],
        code: &'a FixedPoint,
    ) -> Self {
        Splatter {
            grid,
            points,
            accumulators,
            code,
            counters: SplatCounters::default(),
            waiting: [None; DELAY],
        }
    }

    /// Splats the photons still waiting and returns what was counted.
    pub fn finish(mut self) -> SplatCounters {
        for k in (0..DELAY).rev() {
            if let Some(photon) = self.waiting[k].take() {
                self.splat(&photon);
            }
        }
        self.counters
    }

    /// Starts the reads of the candidates of `photon`: their discs, visible points and
    /// accumulators (the bucket's entries should be in cache).
    #[inline]
    fn prefetch_candidates(&self, photon: &Waiting) {
        for pixel in self.grid.candidates_in(photon.bucket) {
            self.grid.prefetch_disc(pixel);
            let vp = &self.points[pixel];
            prefetch(vp);
            // A point may straddle two cache lines.
            prefetch(&vp.max_bounce);
            prefetch(&self.accumulators[pixel]);
        }
    }

    /// Adds `photon` to every visible point whose disc contains it.
    #[inline]
    fn splat(&mut self, photon: &Waiting) {
        for pixel in self.grid.candidates_in(photon.bucket) {
            if !self.grid.contains(pixel, photon.position) {
                continue;
            }
            let vp = &self.points[pixel];
            if photon.bounce > u32::from(vp.max_bounce) {
                continue;
            }
            let w = vp.normals.weight(photon.wi);
            if w <= 0.0 {
                continue;
            }
            let phi = vp.weight * photon.flux * w;
            if !phi.is_finite() || phi.min_element() < 0.0 {
                self.counters.rejected += 1;
                continue;
            }
            self.code.splat(&self.accumulators[pixel], phi);
            self.counters.splats += 1;
        }
    }
}

impl PhotonSink for Splatter<'_> {
    /// Splats the photon that arrived [`DELAY`] deposits ago, and starts the reads of the
    /// others: this photon's bucket bounds, the entries of the one before, the candidates of
    /// the one before that.
    #[inline]
    fn deposit(&mut self, position: Vec3, wi: Vec3, flux: Vec3, _path: u32, bounce: u32) {
        self.counters.photons += 1;
        if let Some(oldest) = self.waiting[DELAY - 1].take() {
            self.splat(&oldest);
        }
        self.waiting.rotate_right(1);
        let bucket = self.grid.bucket(position);
        self.grid.prefetch_bucket(bucket);
        self.waiting[0] = Some(Waiting {
            position,
            wi,
            flux,
            bounce,
            bucket,
        });
        if let Some(photon) = &self.waiting[1] {
            self.grid.prefetch_entries(photon.bucket);
        }
        if let Some(photon) = &self.waiting[2] {
            self.prefetch_candidates(photon);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::photon::GatherNormals;
    use crate::sampling::Rng;

    /// The delayed splats add exactly what splatting each photon at once into every point
    /// whose disc contains it adds (brute force over all points): no photon is lost in the
    /// queue, none splatted twice, whether a pass ends with 0, 1, 2 or more photons waiting.
    #[test]
    fn delayed_splats_equal_brute_force() {
        let mut rng = Rng::new(11, 0, 0);
        let points: Vec<SplatPoint> = (0..300)
            .map(|i| {
                let p = Vec3::new(rng.uniform(), rng.uniform(), 0.0);
                let r = 0.03 + 0.1 * rng.uniform();
                SplatPoint {
                    p,
                    normals: GatherNormals::flat(Vec3::Z),
                    weight: Vec3::new(0.5, 1.0, 2.0) * (1.0 + rng.uniform()),
                    r2: r * r,
                    max_bounce: 3,
                    found: i % 9 != 4,
                }
            })
            .collect();
        let mut grid = VisiblePointGrid::new();
        grid.build(points.len(), |i| points[i].disc());
        let code = FixedPoint::new(1.0, FixedPoint::FINE_SCALE);
        for photons in [0usize, 1, 2, 3, 4, 57] {
            let accumulators: Vec<Accumulator> =
                (0..points.len()).map(|_| Accumulator::default()).collect();
            let mut want = vec![(0u64, [0u64; 3]); points.len()];
            let mut splatter = Splatter::new(&grid, &points, &accumulators, &code);
            for _ in 0..photons {
                let x = Vec3::new(rng.uniform(), rng.uniform(), 0.0);
                let flux = Vec3::new(rng.uniform(), rng.uniform(), rng.uniform());
                let bounce = (rng.uniform() * 5.0) as u32;
                splatter.deposit(x, Vec3::Z, flux, 0, bounce);
                for (vp, want) in points.iter().zip(&mut want) {
                    if vp.found && vp.p.distance_squared(x) <= vp.r2 && bounce <= 3 {
                        let phi = vp.weight * flux;
                        want.0 += 1;
                        for (w, v) in want.1.iter_mut().zip(phi.to_array()) {
                            *w += (v as f64 * FixedPoint::FINE_SCALE).round() as u64;
                        }
                    }
                }
            }
            let counters = splatter.finish();
            assert_eq!(counters.photons, photons as u64);
            let mut accumulators = accumulators;
            for (acc, want) in accumulators.iter_mut().zip(&want) {
                let (m, phi) = code.take(acc);
                assert_eq!(m, want.0, "{photons} photons");
                let phi = phi.map(|v| (v * FixedPoint::FINE_SCALE).round() as u64);
                assert_eq!(phi, want.1, "{photons} photons");
            }
            let splats: u64 = want.iter().map(|w| w.0).sum();
            assert_eq!(counters.splats, splats);
            assert!(
                photons < 50 || splats > 100,
                "the test must splat: {splats}"
            );
        }
    }
}
