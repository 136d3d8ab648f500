//! Integrators: the path tracer, progressive photon mapping and its stochastic variant, and
//! vertex connection and merging, each an [`Integrator`], behind one [`Renderer`].
//!
//! A render is a sequence of iterations; after each one the image (the average of all
//! iteration estimates) is a valid result, so a render can stop at any iteration.

mod algorithm;
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
mod radius_moments;
mod radius_photons;
mod radius_scale;
mod renderer;
mod runner;
mod settings;
mod shading;
mod snapshot;
mod sppm;
mod start;
mod summary;
mod task_order;
mod vcm;

pub use algorithm::{Algorithm, AlgorithmEntry, Setting, UnknownAlgorithm};
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
pub use radius::{smallest_radius, RadiusSchedule};
pub use radius_moments::pixel_moments;
pub use radius_photons::{
    initial_pixel_radii, nearest_photon_distance, nearest_photon_radii, photon_radii,
    photon_radii_with, CAP, NEAREST_PHOTONS, PILOT_LIGHT_PATHS, PILOT_PHOTON_STREAM,
};
pub use radius_scale::{
    bias_variance_scale, gather_share, nominal_iterations, schedule_constants, PixelMoments,
    BIAS_ORDERS, MAX_SCALE, MIN_SCALE, NOMINAL_RAYS, VISIT_COST,
};
pub use renderer::{Aov, Features, Integrator, Renderer};
pub use runner::Stop;
pub use settings::{
    bounded_depth, DirectMode, LightStrategy, Radius, RenderSettings, DEFAULT_PHOTONS, MAX_DEPTH,
};
pub use shading::ShadingFrame;
pub use snapshot::{PixelChannel, Snapshot};
pub use sppm::{PixelStatistics, SplatPoint, SppmRenderer};
pub use start::RenderStart;
pub use vcm::{
    Bpm, BpmRenderer, Bpt, BptRenderer, Lt, LtRenderer, TechniqueSet, Techniques, VcmRenderer,
    VcmSubset,
};

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
    /// (`auto`) the one the photon grid was built for (see `PpmRenderer`'s `iterate_until`).
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
