//! Stochastic progressive photon mapping (Hachisuka and Jensen 2009), organised as pbrt-v4's
//! SPPMIntegrator: every iteration
//!
//! 1. traces one jittered camera path per pixel to a visible point ([`visible_point`], on
//!    the shared camera-path walk), collecting emission and sampled direct light on the way (radiance transport);
//! 2. traces the iteration's light paths (importance transport, the same walk as `ppm`) in
//!    batches ([`photon_pass`]): each batch's photons go into a hash grid ([`photon_grid`])
//!    and every visible point gathers those inside its disc ([`gather`]); a batch holds a
//!    few photons per pixel, so memory is bounded by the pixels, not by the photons;
//! 3. updates each pixel's statistics (N, tau, R) ([`pixel`]).
//!
//! The pixel value after i iterations is L = Ld_avg + tau_i / (N_e pi R_i^2): the average of
//! the camera paths' emission and direct light, plus the progressive density estimate.
//! Every sum over threads is an integer sum or is merged in pixel order, so the same seed
//! gives the same image at any thread count.

mod gather;
mod photon;
mod photon_grid;
mod photon_pass;
mod pixel;
pub(crate) mod snapshot;
mod visible_point;

pub use photon::SppmPhoton;
pub use photon_grid::PhotonGrid;
pub use pixel::{Accumulator, PixelStatistics};
pub use visible_point::{trace_camera_path, SplatPoint};

use super::camera_walk::RayCounters;
use super::radius_photons::initial_pixel_radii;
use super::runner::{reduce_until, Poll};
use super::task_order::interleaved;
use super::{
    image_bytes, summary, Aov, Features, Integrator, IterationStats, MemoryEstimate, MemoryPart,
    PassTimes, Radius, RenderSettings, RenderStart, Snapshot, Stop, Stopwatch, MAX_LIGHT_PATHS,
    PHOTONS_PER_PATH,
};
use crate::film::{Film, Image};
use crate::photon::PhotonBuffer;
use crate::pixel_bounds::PixelBounds;
use crate::scene::Scene;
use crate::StateError;
use glam::Vec3;
use photon_pass::{batch_photons, PhotonPass};
use rayon::prelude::*;
use std::ops::Range;

/// Light paths per parallel work item of the photon pass.
const PATHS_PER_TASK: u32 = 512;
/// Pixels per parallel work item of the camera pass.
const PIXELS_PER_TASK: usize = 1024;
/// How much coarser the fixed-point code gets after an overflowed photon pass.
const COARSER: f64 = 65_536.0;

/// The render state of stochastic progressive photon mapping. Every buffer has one entry per
/// pixel, or holds one batch of photons (at most a few per pixel); none grows with the
/// photons per iteration.
pub struct SppmRenderer {
    settings: RenderSettings,
    /// The pixels rendered (the whole image unless cropped); every per-pixel buffer is the
    /// window's size, and only its visible points gather photons.
    bounds: PixelBounds,
    /// Emission and sampled direct light of the camera paths, averaged over iterations.
    direct: Film,
    /// This iteration's camera-path radiance per pixel, before it joins `direct`.
    direct_estimates: Vec<Vec3>,
    statistics: Vec<PixelStatistics>,
    points: Vec<SplatPoint>,
    accumulators: Vec<Accumulator>,
    /// The photons of the batch of light paths being traced.
    photons: PhotonBuffer<SppmPhoton>,
    /// Light paths in the next batch (set from the photons the last batch stored).
    paths_per_batch: u32,
    /// Photons a batch may hold at most (the photon buffer grows up to it).
    batch_limit: usize,
    grid: PhotonGrid,
    /// Light paths traced over all iterations (N_e).
    emitted: u64,
    /// The current image, L per pixel.
    image: Vec<Vec3>,
    /// Splats dropped as NaN or infinite, and pixels whose photon estimate was not finite.
    rejected: u64,
    /// A per-pixel rule before the first iteration: every pixel's R_1 is still to be set
    /// ([`initial_pixel_radii`]).
    radii_pending: bool,
}

impl SppmRenderer {
    /// The image from the direct-light average and the statistics:
    /// L = Ld_avg + tau / (N_e pi R^2); returns the pixels whose photon part was not finite
    /// (left out).
    fn update_image(&mut self) -> u64 {
        let direct = self.direct.image();
        let emitted = self.emitted as f64;
        self.image
            .par_iter_mut()
            .zip(direct.pixels.par_iter().zip(self.statistics.par_iter()))
            .map(|(l, (ld, s))| {
                let photons = s.radiance(emitted);
                let ok = photons.is_finite();
                *l = *ld + if ok { photons } else { Vec3::ZERO };
                (!ok) as u64
            })
            .sum::<u64>()
    }

    /// The root mean square of the pixels' radii for the next iteration.
    pub fn rms_radius(&self) -> f32 {
        let n = self.statistics.len().max(1) as f64;
        (self.statistics.iter().map(|s| s.r2).sum::<f64>() / n).sqrt() as f32
    }

    /// Each pixel's statistics (row-major).
    pub fn statistics(&self) -> &[PixelStatistics] {
        &self.statistics
    }
}

impl Integrator for SppmRenderer {
    fn features() -> Features {
        Features {
            aovs: &[Aov::Radius, Aov::Photons],
            aov_refusal: "",
            shard_refusal: Some(
                "each iteration's per-pixel radii and statistics depend on all iterations \
                 before it",
            ),
            sample_per_iteration: false,
            photon_map: false,
            delta_light_caustics: true,
            snapshot_channels: snapshot::CHANNELS,
        }
    }

    /// Per pixel (statistics, visible point, accumulator, the direct-light film, the image it
    /// keeps and the copy `image()` returns) and one batch of photons: at most
    /// [`photon_pass::BATCH_PHOTONS_PER_PIXEL`] per pixel, fewer when the light paths per
    /// iteration need fewer; never more with more light paths.
    fn memory_estimate(width: u32, height: u32, settings: &RenderSettings) -> MemoryEstimate {
        let pixels = width as u64 * height as u64;
        let per_pixel = (std::mem::size_of::<PixelStatistics>()
            + std::mem::size_of::<SplatPoint>()
            + std::mem::size_of::<Accumulator>()
            + std::mem::size_of::<Vec3>()
            + photon_grid::BYTES_PER_PIXEL) as u64;
        let mut estimate = MemoryEstimate::default();
        estimate.add(MemoryPart::Image, image_bytes(width, height));
        estimate.add(MemoryPart::Image, pixels.saturating_mul(per_pixel));
        let (batch, limit) = batch_photons(pixels as usize, settings.photons);
        let part = if batch < limit {
            MemoryPart::Photons
        } else {
            MemoryPart::Image
        };
        estimate.add(
            part,
            (batch as u64).saturating_mul(photon_grid::BYTES_PER_PHOTON as u64),
        );
        estimate
    }

    /// The photons, the radius at the start (each pixel's then shrinks with its own
    /// photons), alpha and the direct light.
    fn settings_words(settings: &RenderSettings, _image: Range<u64>) -> String {
        let radius = match settings.radius {
            Radius::World(r) => {
                format!("{} at the start, then per pixel", summary::significant(r))
            }
            Radius::Auto | Radius::Photons => format!("{} (per pixel)", settings.radius),
        };
        summary::photon_mapping(settings, &radius)
    }

    /// A render from `start`; every pixel starts at radius `settings.radius`
    /// (`Radius::World`), or at its own radius from a per-pixel rule (`Radius::Photons`,
    /// `Radius::Auto`, set by the first iteration's pilot pass: [`initial_pixel_radii`],
    /// shared with `ppm` and `vcm`). The number of light paths per iteration is capped at [`MAX_LIGHT_PATHS`]. Each
    /// pixel's camera paths and photons are those of the full render, so a crop changes no
    /// pixel. SPPM's iterations share per-pixel statistics: its direct-light film starts
    /// empty, and a saved state comes in by [`Integrator::from_snapshot`].
    fn start(start: RenderStart) -> Self {
        let RenderStart {
            mut settings,
            bounds,
            film,
        } = start;
        settings.photons = settings.photons.clamp(1, MAX_LIGHT_PATHS);
        let pixels = bounds.len();
        let (radius, radii_pending) = match settings.radius {
            Radius::World(r) => (r, false),
            Radius::Auto | Radius::Photons => (0.0, true),
        };
        let (batch, batch_limit) = batch_photons(pixels, settings.photons);
        let photons = PhotonBuffer::of_records(batch);
        let paths_per_batch = (photons.capacity() / PHOTONS_PER_PATH).max(1) as u32;
        SppmRenderer {
            direct: film,
            direct_estimates: vec![Vec3::ZERO; pixels],
            statistics: vec![PixelStatistics::new(radius); pixels],
            points: vec![SplatPoint::default(); pixels],
            accumulators: vec![Accumulator::default(); pixels],
            photons,
            paths_per_batch,
            batch_limit,
            grid: PhotonGrid::new(),
            emitted: 0,
            image: vec![Vec3::ZERO; pixels],
            rejected: 0,
            radii_pending,
            bounds,
            settings,
        }
    }

    /// A render continuing from `snapshot` (whole images only): the direct-light film and
    /// every pixel's statistics, bit for bit. A state without statistics is refused unless it
    /// starts at iteration 0 (SPPM's iterations cannot be cut into shards: see
    /// [`snapshot`](self::snapshot)).
    fn from_snapshot(
        scene: &Scene,
        settings: &RenderSettings,
        snapshot: Snapshot,
    ) -> Result<Self, StateError> {
        let (w, h) = (scene.camera.width, scene.camera.height);
        snapshot.check_size(w, h)?;
        let mut renderer = Self::start(RenderStart::fresh(settings, PixelBounds::full(w, h)));
        if snapshot.pixels.is_empty() {
            if snapshot.film.next_iteration() > 0 {
                return Err(StateError::Unsupported(
                    "sppm carries per-pixel statistics from one iteration to the next: a \
                     render can be resumed from its own state, but not started at a later \
                     iteration (no --shard) or from another algorithm's state"
                        .into(),
                ));
            }
            return Ok(renderer);
        }
        if snapshot.film.first_iteration() != 0 {
            return Err(StateError::Unsupported(
                "an sppm state must cover its render from the first iteration".into(),
            ));
        }
        renderer.statistics = snapshot::from_channels(&snapshot.pixels, renderer.image.len())?;
        renderer.radii_pending = false;
        renderer.emitted = renderer.settings.photons as u64 * snapshot.film.next_iteration();
        renderer.direct = snapshot.film;
        renderer.rejected = renderer.update_image();
        Ok(renderer)
    }

    /// What [`Integrator::from_snapshot`] needs to continue: the direct-light film and the
    /// statistics (whole images only: a crop's state has the crop's size and is refused by a
    /// whole render).
    fn snapshot(&self) -> Snapshot {
        Snapshot {
            film: self.direct.clone(),
            pixels: snapshot::to_channels(&self.statistics),
        }
    }

    /// Renders one iteration.
    ///
    /// Abandoned (`None`) if `stop` says yes before one of the
    /// camera or photon pass's work items starts. The pixel statistics, the direct-light film
    /// and the photon count change only after both passes, so an abandoned iteration leaves
    /// the render as it was (the visible points and the grid are rebuilt by every iteration).
    fn iterate_until(&mut self, scene: &Scene, stop: Stop) -> Option<IterationStats> {
        let iteration = self.direct.next_iteration();
        let mut passes = PassTimes::default();
        let mut clock = Stopwatch::start();

        // 0. With a per-pixel rule, each pixel's R_1 from the pilot pass. The pilot draws
        // from its own random streams, so R_1 does not depend on any iteration's samples.
        let mut pilot = RayCounters::default();
        if self.radii_pending {
            // Pending only under a per-pixel rule, which always gives radii.
            if let Some(radii) = initial_pixel_radii(scene, &self.settings, &mut pilot, stop)? {
                for (local, statistics) in self.statistics.iter_mut().enumerate() {
                    *statistics = PixelStatistics::new(radii[self.bounds.full_index(local)]);
                }
            }
            self.radii_pending = false;
        }

        // 1. Camera paths to visible points, in pixel order.
        let width = scene.camera.width as usize;
        let settings = &self.settings;
        let statistics = &self.statistics;
        let bounds = self.bounds;
        let tasks = self
            .direct_estimates
            .chunks_mut(PIXELS_PER_TASK)
            .zip(self.points.chunks_mut(PIXELS_PER_TASK));
        let poll = Poll::new(stop);
        let camera = reduce_until(
            interleaved(tasks),
            &poll,
            |(task, (ld, points))| {
                let mut counters = RayCounters::default();
                for (i, (ld, vp)) in ld.iter_mut().zip(points).enumerate() {
                    if poll.stopped() {
                        break;
                    }
                    let local = task * PIXELS_PER_TASK + i;
                    let pixel = bounds.full_index(local);
                    let (l, mut point) =
                        trace_camera_path(scene, settings, iteration, pixel, width, &mut counters);
                    point.r2 = statistics[local].r2 as f32;
                    *ld = l;
                    *vp = point;
                }
                counters
            },
            RayCounters::merge,
        )?;
        passes.eye = clock.lap();

        // 2. Photons, batch by batch, gathered by the visible points.
        let PhotonPass {
            code,
            counters: splats,
            rays: photon_rays,
            grid_seconds,
        } = self.photon_pass(scene, iteration, stop)?;
        passes.grid = grid_seconds;
        passes.photon = clock.lap() - grid_seconds;

        // 3. Per-pixel statistics and the image.
        let alpha = self.settings.alpha as f64;
        self.statistics
            .par_iter_mut()
            .zip(self.accumulators.par_iter_mut())
            .for_each(|(s, acc)| {
                let (m, phi) = code.take(acc);
                s.update(m, phi, alpha);
            });
        self.emitted += self.settings.photons as u64;
        let before = self.direct.rejected();
        self.direct.add_iteration(&self.direct_estimates);
        let bad_pixels = self.update_image();
        self.rejected += splats.rejected + bad_pixels;
        passes.film = clock.lap();

        Some(IterationStats {
            rays: camera.rays + pilot.rays + photon_rays,
            photon_rays,
            shadow_rays: camera.shadow_rays + pilot.shadow_rays,
            light_paths: self.settings.photons as u64,
            photons: splats.photons,
            radius: self.rms_radius(),
            rejected: self.direct.rejected() - before + splats.rejected + bad_pixels,
            passes,
        })
    }

    /// The camera paths' direct-light film: it counts the iterations.
    fn film(&self) -> &Film {
        &self.direct
    }

    /// Every pixel's gather radius R for the next iteration, as a grey image.
    fn radius_image(&self) -> Option<Image> {
        let (w, h) = (self.direct.width, self.direct.height);
        let mut image = Image::new(w, h);
        for (out, s) in image.pixels.iter_mut().zip(&self.statistics) {
            *out = Vec3::splat(s.r2.sqrt() as f32);
        }
        Some(image)
    }

    /// Every pixel's accumulated photon count N (Hachisuka, Ogaki and Jensen 2008, sec. 4.2:
    /// the alpha-weighted count that sets the radius), as a grey image: what the pixel's
    /// estimate rests on (its relative noise is about one over the square root).
    fn photon_count_image(&self, _scene: &Scene) -> Option<Image> {
        let (w, h) = (self.direct.width, self.direct.height);
        let mut image = Image::new(w, h);
        for (out, s) in image.pixels.iter_mut().zip(&self.statistics) {
            *out = Vec3::splat(s.n as f32);
        }
        Some(image)
    }

    /// The current image, one value per pixel (row-major). SPPM's iterations are not
    /// independent estimates (the statistics carry over), so unlike `ppm` this is the image
    /// after the last iteration, not that iteration's estimate alone.
    fn last_estimates(&self) -> &[Vec3] {
        &self.image
    }

    /// The current image.
    fn image(&self) -> Image {
        Image {
            width: self.direct.width,
            height: self.direct.height,
            pixels: self.image.clone(),
        }
    }

    /// Samples dropped as NaN, infinite or negative: camera-path radiance, splats and pixels.
    fn rejected(&self) -> u64 {
        self.direct.rejected() + self.rejected
    }

    /// Bytes held by the render state: per pixel (statistics, visible points, accumulators,
    /// films) and one batch of photons (buffer and grid).
    fn memory_bytes(&self) -> usize {
        let per_pixel = std::mem::size_of::<PixelStatistics>()
            + std::mem::size_of::<SplatPoint>()
            + std::mem::size_of::<Accumulator>()
            + 2 * std::mem::size_of::<Vec3>();
        self.image.len() * per_pixel
            + self.direct.memory_bytes()
            + self.photons.memory_bytes()
            + self.grid.memory_bytes()
    }
}
