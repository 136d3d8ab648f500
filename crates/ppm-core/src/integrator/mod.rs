//! Integrators: the path tracer, progressive photon mapping and its stochastic variant, and
//! vertex connection and merging, behind one [`Renderer`].
//!
//! A render is a sequence of iterations; after each one the image (the average of all
//! iteration estimates) is a valid result, so a render can stop at any iteration.

mod camera_path;
mod camera_walk;
mod direct;
mod footprint;
mod light_path;
mod memory;
mod path;
mod photon_sink;
mod ppm;
mod radius;
mod settings;
mod shading;
mod snapshot;
mod sppm;
mod task_order;
mod vcm;

pub use camera_path::CameraPath;
pub use camera_walk::{
    walk, walk_to_visible_point, Next, RayCounters, Vertex, VisiblePoint, Walk, WalkParams,
};
pub use direct::{emission_mis_weight, estimate_direct};
pub use footprint::{
    footprint_radius, pilot_points, pilot_radii, PilotPoint, FOOTPRINT_PIXELS, PILOT_STREAM,
};
pub use light_path::{stores_photons, trace_light_path, PhotonCounters, MAX_LIGHT_PATHS};
pub use memory::{
    image_bytes, MemoryEstimate, MemoryItem, MemoryPart, BYTES_PER_PHOTON, BYTES_PER_PIXEL,
    PHOTONS_PER_PATH,
};
pub use path::PathTracer;
pub use photon_sink::PhotonSink;
pub use ppm::{density_estimate, gather_limit, GatherContext, PpmRenderer};
pub use radius::RadiusSchedule;
pub use settings::{
    Algorithm, DirectMode, LightStrategy, Radius, RenderSettings, Setting, DEFAULT_PHOTONS,
    MAX_DEPTH,
};
pub use shading::ShadingFrame;
pub use snapshot::{PixelChannel, Snapshot};
pub use sppm::{PixelStatistics, SplatPoint, SppmRenderer};
pub use vcm::{Techniques, VcmRenderer};

use crate::film::Image;
use crate::pixel_bounds::PixelBounds;
use crate::scene::Scene;
use crate::StateError;

/// What one iteration did, for progress and speed reports.
#[derive(Clone, Copy, Debug, Default)]
pub struct IterationStats {
    /// Closest-hit rays traced.
    pub rays: u64,
    /// Those of them traced by the photon pass (photon mapping); the rest are camera paths'.
    pub photon_rays: u64,
    /// Shadow (any-hit) rays traced.
    pub shadow_rays: u64,
    /// Light paths traced and photons stored (photon mapping).
    pub light_paths: u64,
    pub photons: u64,
    /// Gather radius used in this iteration (photon mapping); with per-pixel radii
    /// (`auto`) the one the photon grid was built for (see `PpmRenderer::iterate`).
    pub radius: f32,
    /// Samples dropped as NaN or infinite.
    pub rejected: u64,
    /// Wall-clock time of each pass.
    pub passes: PassTimes,
}

/// Wall-clock seconds spent in each pass of an iteration (or summed over iterations), to show
/// which pass dominates and how each one scales with threads.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PassTimes {
    /// Light paths traced and photons stored (photon mapping).
    pub photon: f64,
    /// Hash grid built over the photons (photon mapping).
    pub grid: f64,
    /// Camera paths, with the photon gathers for photon mapping.
    pub eye: f64,
    /// Estimates added to the film.
    pub film: f64,
}

/// Seconds between consecutive laps, for [`PassTimes`].
pub(crate) struct Stopwatch(std::time::Instant);

impl Stopwatch {
    pub(crate) fn start() -> Self {
        Stopwatch(std::time::Instant::now())
    }

    /// Seconds since the start or the previous lap; starts the next lap.
    pub(crate) fn lap(&mut self) -> f64 {
        let now = std::time::Instant::now();
        let seconds = (now - self.0).as_secs_f64();
        self.0 = now;
        seconds
    }
}

impl PassTimes {
    /// The sum of all passes.
    pub fn total(&self) -> f64 {
        self.photon + self.grid + self.eye + self.film
    }

    /// Pass-by-pass sum.
    pub fn add(&mut self, other: &PassTimes) {
        self.photon += other.photon;
        self.grid += other.grid;
        self.eye += other.eye;
        self.film += other.film;
    }
}

/// The render state of one of the integrators.
pub enum Renderer {
    Path(PathTracer),
    /// Boxed: its photon buffer and grid make it several times the path tracer's size.
    Ppm(Box<PpmRenderer>),
    Sppm(Box<SppmRenderer>),
    Vcm(Box<VcmRenderer>),
}

impl Renderer {
    /// A fresh render of `scene` with `settings` (uses the current rayon thread pool).
    pub fn new(scene: &Scene, settings: &RenderSettings) -> Self {
        let (w, h) = (scene.camera.width, scene.camera.height);
        Self::with_bounds(settings, PixelBounds::full(w, h))
    }

    /// A render of the pixels in `bounds` only (a crop window of the camera's image): the
    /// image is `bounds`' size and each pixel equals the full render's at the same seed.
    pub fn with_bounds(settings: &RenderSettings, bounds: PixelBounds) -> Self {
        match settings.algorithm {
            Algorithm::Path => Renderer::Path(PathTracer::with_bounds(settings.clone(), bounds)),
            Algorithm::Ppm => {
                Renderer::Ppm(Box::new(PpmRenderer::with_bounds(settings.clone(), bounds)))
            }
            Algorithm::Sppm => Renderer::Sppm(Box::new(SppmRenderer::with_bounds(
                settings.clone(),
                bounds,
            ))),
            Algorithm::Vcm => {
                Renderer::Vcm(Box::new(VcmRenderer::with_bounds(settings.clone(), bounds)))
            }
        }
    }

    /// What [`Renderer::new`] will allocate for `scene` with `settings`, before allocating it.
    pub fn memory_estimate(scene: &Scene, settings: &RenderSettings) -> MemoryEstimate {
        let (w, h) = (scene.camera.width, scene.camera.height);
        match settings.algorithm {
            Algorithm::Path => PathTracer::memory_estimate(w, h, settings),
            Algorithm::Ppm => PpmRenderer::memory_estimate(w, h, settings),
            Algorithm::Sppm => SppmRenderer::memory_estimate(w, h, settings),
            Algorithm::Vcm => VcmRenderer::memory_estimate(w, h, settings),
        }
    }

    /// A render continuing from a saved state (`--resume`), or starting at a later iteration
    /// (a shard: [`Snapshot::starting_at`]); each integrator checks and takes what it saved.
    pub fn from_snapshot(
        scene: &Scene,
        settings: &RenderSettings,
        snapshot: Snapshot,
    ) -> Result<Self, StateError> {
        Ok(match settings.algorithm {
            Algorithm::Path => Renderer::Path(PathTracer::from_snapshot(
                scene,
                settings.clone(),
                snapshot,
            )?),
            Algorithm::Ppm => Renderer::Ppm(Box::new(PpmRenderer::from_snapshot(
                scene,
                settings.clone(),
                snapshot,
            )?)),
            Algorithm::Sppm => Renderer::Sppm(Box::new(SppmRenderer::from_snapshot(
                scene,
                settings.clone(),
                snapshot,
            )?)),
            Algorithm::Vcm => Renderer::Vcm(Box::new(VcmRenderer::from_snapshot(
                scene,
                settings.clone(),
                snapshot,
            )?)),
        })
    }

    /// Everything [`Renderer::from_snapshot`] needs to continue this render exactly.
    pub fn snapshot(&self) -> Snapshot {
        match self {
            Renderer::Path(r) => r.snapshot(),
            Renderer::Ppm(r) => r.snapshot(),
            Renderer::Sppm(r) => r.snapshot(),
            Renderer::Vcm(r) => r.snapshot(),
        }
    }

    /// Renders one more iteration.
    pub fn iterate(&mut self, scene: &Scene) -> IterationStats {
        match self.iterate_until(scene, &|| false) {
            Some(stats) => stats,
            None => unreachable!("an iteration that is never asked to stop completes"),
        }
    }

    /// Renders one more iteration unless `stop` returns true while it runs: the passes ask
    /// `stop` before each parallel work item (a few hundred paths), and an iteration during
    /// which it said yes is abandoned whole and `None` returned. The film, the radius schedule
    /// and the iteration count are then as before the call, so [`Renderer::image`] stays the
    /// average of complete iterations and the next call renders the same iteration again.
    pub fn iterate_until<F: Fn() -> bool + Sync>(
        &mut self,
        scene: &Scene,
        stop: &F,
    ) -> Option<IterationStats> {
        match self {
            Renderer::Path(r) => r.iterate_until(scene, stop),
            Renderer::Ppm(r) => r.iterate_until(scene, stop),
            Renderer::Sppm(r) => r.iterate_until(scene, stop),
            Renderer::Vcm(r) => r.iterate_until(scene, stop),
        }
    }

    /// The average of all iterations so far.
    pub fn image(&self) -> Image {
        match self {
            Renderer::Path(r) => r.film().image(),
            Renderer::Ppm(r) => r.film().image(),
            Renderer::Sppm(r) => r.image(),
            Renderer::Vcm(r) => r.film().image(),
        }
    }

    /// The per-pixel estimates of the last iteration alone (for `sppm`, whose iterations
    /// share per-pixel statistics, the current image).
    pub fn last_estimates(&self) -> &[glam::Vec3] {
        match self {
            Renderer::Path(r) => r.last_estimates(),
            Renderer::Ppm(r) => r.last_estimates(),
            Renderer::Sppm(r) => r.last_estimates(),
            Renderer::Vcm(r) => r.last_estimates(),
        }
    }

    /// The index of the first iteration in the image (0 unless a shard or a slice).
    pub fn first_iteration(&self) -> u64 {
        match self {
            Renderer::Path(r) => r.film().first_iteration(),
            Renderer::Ppm(r) => r.film().first_iteration(),
            Renderer::Sppm(r) => r.first_iteration(),
            Renderer::Vcm(r) => r.film().first_iteration(),
        }
    }

    /// Iterations in the image (resumed ones included).
    pub fn iterations(&self) -> u64 {
        match self {
            Renderer::Path(r) => r.film().iterations(),
            Renderer::Ppm(r) => r.film().iterations(),
            Renderer::Sppm(r) => r.iterations(),
            Renderer::Vcm(r) => r.film().iterations(),
        }
    }

    /// Samples dropped as NaN or infinite so far.
    pub fn rejected(&self) -> u64 {
        match self {
            Renderer::Path(r) => r.film().rejected(),
            Renderer::Ppm(r) => r.film().rejected(),
            Renderer::Sppm(r) => r.rejected(),
            Renderer::Vcm(r) => r.film().rejected(),
        }
    }

    /// (iteration, pixel) of the first sample dropped as NaN, infinite or negative: random
    /// streams are keyed by (seed, iteration, pixel), so that path can be traced again.
    pub fn first_rejected(&self) -> Option<(u64, u32)> {
        match self {
            Renderer::Path(r) => r.film().first_rejected(),
            Renderer::Ppm(r) => r.film().first_rejected(),
            Renderer::Sppm(r) => r.first_rejected(),
            Renderer::Vcm(r) => r.film().first_rejected(),
        }
    }

    /// The gather radius of every pixel in the last iteration (photon mapping; `None` for the
    /// path tracer, VCM (one merge radius: [`VcmRenderer::last_radius`]) or before the first
    /// iteration), as a grey image.
    pub fn radius_image(&self) -> Option<Image> {
        match self {
            Renderer::Path(_) | Renderer::Vcm(_) => None,
            Renderer::Ppm(r) => r.radius_image(),
            Renderer::Sppm(r) => Some(r.radius_image()),
        }
    }

    /// How many photons each pixel's estimate rests on, as a grey image (photon mapping; `None`
    /// for the path tracer, VCM or before the first iteration): for `sppm` its accumulated count N,
    /// for `ppm` the last iteration's photons within its radius at its first diffuse visible
    /// point ([`PpmRenderer::photon_count_image`]).
    pub fn photon_count_image(&self, scene: &Scene) -> Option<Image> {
        match self {
            Renderer::Path(_) | Renderer::Vcm(_) => None,
            Renderer::Ppm(r) => r.photon_count_image(scene),
            Renderer::Sppm(r) => Some(r.photon_count_image()),
        }
    }

    /// Bytes of the render state's large buffers (film, photons or visible points, grid).
    pub fn memory_bytes(&self) -> usize {
        match self {
            Renderer::Path(r) => r.memory_bytes(),
            Renderer::Ppm(r) => r.memory_bytes(),
            Renderer::Sppm(r) => r.memory_bytes(),
            Renderer::Vcm(r) => r.memory_bytes(),
        }
    }
}
