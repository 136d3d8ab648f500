//! The photon pass of SPPM, in batches: a batch of light paths stores its photons, a hash
//! grid is built over them, and every visible point gathers the photons inside its disc.
//!
//! The statistics need, per pixel, the count M and the weighted flux Phi of the iteration's
//! photons inside its disc (Hachisuka and Jensen 2009). Splatting each photon into the
//! visible points around it, as it arrives, finds the same (photon, point) pairs, but every
//! photon lands somewhere unrelated to the one before: each splat was a chain of dependent
//! reads missing the cache (docs/performance.md, 2026-12-06). Gathering in pixel order
//! reads the grid where the pixel before read it, and writes each pixel's accumulator once,
//! from one thread, without atomics.
//!
//! Memory stays bounded by the pixels whatever `--photons` is: a batch holds at most
//! [`BATCH_PHOTONS_PER_PIXEL`] photons per pixel (at least [`MIN_BATCH_PHOTONS`]); more
//! light paths make more batches, not bigger ones. M and Phi are fixed-point integer sums, so
//! cutting the light paths into batches (and the order of the pairs) changes no bit.

use super::gather::{gather, SplatCounters};
use super::pixel::{self, FixedPoint};
use super::{SppmRenderer, COARSER, PATHS_PER_TASK, PIXELS_PER_TASK};
use crate::integrator::runner::{reduce_until, Poll};
use crate::integrator::{
    trace_light_path, PhotonCounters, Stop, Stopwatch, MAX_LIGHT_PATHS, PHOTONS_PER_PATH,
};
use crate::scene::Scene;
use rayon::prelude::*;

/// Photons per pixel one batch holds at most (four per light path at one light path per
/// pixel, the default: a closed box of albedo 0.7 stores about three).
pub const BATCH_PHOTONS_PER_PIXEL: usize = 4;

/// Photons a batch holds at least, whatever the image size (about 6 MB).
pub const MIN_BATCH_PHOTONS: usize = 1 << 16;

/// The largest batch for `pixels` pixels and `paths` light paths per iteration, in photons:
/// [`BATCH_PHOTONS_PER_PIXEL`] per pixel (at least [`MIN_BATCH_PHOTONS`]), and no more than
/// [`PHOTONS_PER_PATH`] per light path (the buffer grows up to the first bound if a scene
/// stores more).
pub fn batch_photons(pixels: usize, paths: u32) -> (usize, usize) {
    let limit = pixels
        .saturating_mul(BATCH_PHOTONS_PER_PIXEL)
        .max(MIN_BATCH_PHOTONS);
    let paths = paths.clamp(1, MAX_LIGHT_PATHS) as usize;
    (paths.saturating_mul(PHOTONS_PER_PATH).min(limit), limit)
}

/// What the photon pass returns: the code of its sums, its counts, the light-path rays and
/// the seconds spent building grids.
pub struct PhotonPass {
    pub code: FixedPoint,
    pub counters: SplatCounters,
    pub rays: u64,
    pub grid_seconds: f64,
}

impl SppmRenderer {
    /// The photon pass, gathering into the accumulators. If a fixed-point sum overflows, the
    /// accumulators are cleared and the pass redone with a coarser code: light paths are
    /// keyed by (seed, iteration, path), so the redone pass brings the same photons.
    /// `None` (accumulators cleared) if `stop` says yes before one of its work items starts.
    pub(super) fn photon_pass(
        &mut self,
        scene: &Scene,
        iteration: u64,
        stop: Stop,
    ) -> Option<PhotonPass> {
        let paths = self.settings.photons;
        let flux_unit = scene.total_power().max_element();
        let mut scale = FixedPoint::FINE_SCALE;
        let poll = Poll::new(stop);
        let mut grid_seconds = 0.0;
        self.grid.cover(&self.points);
        loop {
            let code = FixedPoint::new(flux_unit, scale);
            let mut counters = SplatCounters::default();
            let mut rays = 0;
            let mut first = 0;
            while first < paths {
                let end = first.saturating_add(self.paths_per_batch).min(paths);
                let Some(light) = self.trace_batch(scene, iteration, first..end, &poll) else {
                    pixel::clear(&mut self.accumulators);
                    return None;
                };
                let (stored, overflowed) = (self.photons.pushed(), self.photons.overflowed());
                // (May grow the buffer, which clears it: read the overflow before.)
                self.adapt_batch(end - first, stored, overflowed);
                if overflowed {
                    // Redo the batch, grown or cut to fit (the same photons come again).
                    continue;
                }
                let mut clock = Stopwatch::start();
                self.grid.build(self.photons.as_slice());
                grid_seconds += clock.lap();
                counters = counters.merge(self.gather_batch(&code));
                counters.photons += light.photons;
                rays += light.rays;
                first = end;
            }
            if !code.overflowed() {
                return Some(PhotonPass {
                    code,
                    counters,
                    rays,
                    grid_seconds,
                });
            }
            pixel::clear(&mut self.accumulators);
            scale /= COARSER;
        }
    }

    /// Traces light paths `paths` of `iteration` into the (cleared) photon buffer. `None` if
    /// `poll` stopped the pass.
    fn trace_batch(
        &mut self,
        scene: &Scene,
        iteration: u64,
        paths: std::ops::Range<u32>,
        poll: &Poll,
    ) -> Option<PhotonCounters> {
        self.photons.clear();
        let (settings, buffer) = (&self.settings, &self.photons);
        let tasks = (paths.end - paths.start).div_ceil(PATHS_PER_TASK);
        reduce_until(
            0..tasks,
            poll,
            |task| {
                let mut light = PhotonCounters::default();
                let mut writer = buffer.writer();
                let start = paths.start + task * PATHS_PER_TASK;
                for path in start..(start + PATHS_PER_TASK).min(paths.end) {
                    // A path is up to max_depth bounces: ask between paths.
                    if poll.stopped() {
                        break;
                    }
                    trace_light_path(scene, settings, iteration, path, &mut writer, &mut light);
                }
                light
            },
            |a, b| PhotonCounters {
                rays: a.rays + b.rays,
                photons: a.photons + b.photons,
            },
        )
    }

    /// After a batch of `paths` light paths that stored `stored` photons: grows the buffer
    /// towards the batch limit if it overflowed, and sets the next batch's light paths to fill
    /// about 3/4 of it.
    fn adapt_batch(&mut self, paths: u32, stored: usize, overflowed: bool) {
        let limit = self.batch_limit;
        if overflowed && self.photons.capacity() < limit {
            self.photons.grow((stored + stored / 4).min(limit));
        }
        if paths == 1 && stored > self.photons.capacity() {
            // One path with more photons than a batch holds (a max_depth beyond it).
            self.photons.grow(stored);
        }
        let per_path = stored.max(1) as f64 / paths as f64;
        let fit = (0.75 * self.photons.capacity() as f64 / per_path) as u32;
        self.paths_per_batch = fit.max(1);
    }

    /// Every visible point gathers the batch's photons, in pixel order.
    fn gather_batch(&mut self, code: &FixedPoint) -> SplatCounters {
        let grid = &self.grid;
        self.points
            .par_chunks(PIXELS_PER_TASK)
            .zip(self.accumulators.par_chunks_mut(PIXELS_PER_TASK))
            .map(|(points, accumulators)| {
                let mut counters = SplatCounters::default();
                for (point, acc) in points.iter().zip(accumulators) {
                    gather(grid, point, acc, code, &mut counters);
                }
                counters
            })
            .reduce(SplatCounters::default, SplatCounters::merge)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrator::{Algorithm, DirectMode, Integrator, RenderSettings, RenderStart};
    use crate::photon::PhotonBuffer;
    use crate::pixel_bounds::PixelBounds;
    use crate::prelude::*;

    /// A closed diffuse box seen at 12 x 12 pixels, lit from under the ceiling.
    fn closed_box() -> Scene {
        let camera = Camera::new(
            Vec3::new(0.0, 1.0, 0.9),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::Y,
            70.0,
            (12, 12),
        )
        .unwrap();
        let mut b = SceneBuilder::new(camera);
        let white = b.add_material(Material::new(Bsdf::diffuse(Vec3::splat(0.7)), Vec3::ZERO));
        let lamp = b.add_material(Material::new(Bsdf::diffuse(Vec3::ZERO), Vec3::splat(10.0)));
        let walls = [
            ([-1.0, 0.0, -1.0], [0.0, 0.0, 2.0], [2.0, 0.0, 0.0]),
            ([-1.0, 2.0, -1.0], [2.0, 0.0, 0.0], [0.0, 0.0, 2.0]),
            ([-1.0, 0.0, -1.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]),
            ([-1.0, 0.0, 1.0], [0.0, 2.0, 0.0], [2.0, 0.0, 0.0]),
            ([-1.0, 0.0, -1.0], [0.0, 2.0, 0.0], [0.0, 0.0, 2.0]),
            ([1.0, 0.0, -1.0], [0.0, 0.0, 2.0], [0.0, 2.0, 0.0]),
        ];
        for (c, u, v) in walls {
            let (c, u, v) = (Vec3::from(c), Vec3::from(u), Vec3::from(v));
            b.add_mesh(TriangleMesh::quad(c, u, v, white));
        }
        let (c, u, v) = (Vec3::new(-0.25, 1.98, -0.25), Vec3::X * 0.5, Vec3::Z * 0.5);
        b.add_mesh(TriangleMesh::quad(c, u, v, lamp));
        b.build().unwrap()
    }

    /// Batches that overflow their buffer (redone, grown, then cut to a few light paths)
    /// give the image and statistics of one batch holding every photon, bit for bit.
    #[test]
    fn overflowing_and_cut_batches_equal_one_batch() {
        let scene = closed_box();
        let settings = RenderSettings {
            photons: 3000,
            direct: DirectMode::Photons,
            ..RenderSettings::for_algorithm(&scene, Algorithm::Sppm)
        };
        let start =
            || SppmRenderer::start(RenderStart::fresh(&settings, PixelBounds::full(12, 12)));
        let mut one = start();
        one.photons = PhotonBuffer::of_records(1 << 16);
        one.paths_per_batch = u32::MAX;
        let mut many = start();
        many.photons = PhotonBuffer::of_records(8);
        many.batch_limit = 64;
        for _ in 0..3 {
            let a = one.iterate_until(&scene, &|| false).unwrap();
            let b = many.iterate_until(&scene, &|| false).unwrap();
            assert_eq!(a.photons, b.photons);
            assert!(
                a.photons > 3000,
                "the test must store photons: {}",
                a.photons
            );
        }
        assert!(many.photons.capacity() <= 64 && many.paths_per_batch < 30);
        assert_eq!(one.statistics, many.statistics);
        assert_eq!(one.image, many.image);
    }
}
