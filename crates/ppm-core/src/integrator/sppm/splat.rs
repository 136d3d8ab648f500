//! The photon pass of SPPM: light paths whose photons are splatted straight into the visible
//! points they fall near, and never stored.

use super::grid::VisiblePointGrid;
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
pub struct Splatter<'a> {
    pub grid: &'a VisiblePointGrid,
    pub points: &'a [SplatPoint],
    pub accumulators: &'a [Accumulator],
    pub code: &'a FixedPoint,
    pub counters: SplatCounters,
}

impl PhotonSink for Splatter<'_> {
    #[inline]
    fn deposit(&mut self, position: Vec3, wi: Vec3, flux: Vec3, _path: u32, bounce: u32) {
        self.counters.photons += 1;
        for pixel in self.grid.candidates(position) {
            let vp = &self.points[pixel];
            if vp.p.distance_squared(position) > vp.r2 || bounce > u32::from(vp.max_bounce) {
                continue;
            }
            let w = vp.normals.weight(wi);
            if w <= 0.0 {
                continue;
            }
            let phi = vp.weight * flux * w;
            if !phi.is_finite() || phi.min_element() < 0.0 {
                self.counters.rejected += 1;
                continue;
            }
            self.code.splat(&self.accumulators[pixel], phi);
            self.counters.splats += 1;
        }
    }
}
