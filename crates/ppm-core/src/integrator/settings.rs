//! What the user asked for: the render settings, separate from the scene and the render state.

use super::{Algorithm, RadiusSchedule};
use crate::scene::Scene;

/// The longest path any render traces, in bounces. A longer `max_depth` is clamped to it: in a
/// closed box of perfect mirrors Russian roulette never ends a path (the throughput never
/// drops), so only this bound keeps an iteration finite. 1024 bounces are far beyond what any
/// non-pathological scene needs (the shipped scenes use 6 to 32) and keep one iteration of a
/// 512x512 mirror box under a few seconds.
pub const MAX_DEPTH: u32 = 1024;

/// `max_depth` as renders use it: at most [`MAX_DEPTH`]. The one place the bound is applied
/// (the scene loader and the command line call it to warn about a larger value they were
/// given; [`RenderSettings::normalised`] for every render).
pub fn bounded_depth(max_depth: u32) -> u32 {
    max_depth.min(MAX_DEPTH)
}

/// Light paths per photon-mapping iteration when neither the scene nor the command line
/// says (`ppm`; `sppm` scales its default with the image, see [`RenderSettings::for_algorithm`]).
pub const DEFAULT_PHOTONS: u32 = 200_000;

/// How the path tracer finds light at non-specular vertices (all three converge to the same
/// image; only MIS is meant for production, the others exist to cross-check it).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LightStrategy {
    /// Light sampling and BSDF sampling combined by the power heuristic.
    Mis,
    /// Light sampling only (emission found by BSDF sampling is ignored after the first vertex).
    LightOnly,
    /// BSDF sampling only (no shadow rays; point lights are then invisible).
    BsdfOnly,
}

/// How photon mapping computes direct light at diffuse gather points.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DirectMode {
    /// Photons of every bounce are stored and density-estimated (Hachisuka et al. 2008).
    Photons,
    /// Direct light by light sampling at the gather point; photons are stored from their
    /// second bounce on.
    Sampled,
}

/// The initial gather radius of photon mapping.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Radius {
    /// One initial radius for every pixel, in scene units (`--radius R`, `render: { radius: R }`).
    World(f32),
    /// Each pixel's initial radius from its footprint at its first diffuse visible point
    /// (`--radius auto` or `footprint`, `render: { radius: auto }`): see
    /// [`crate::integrator::footprint_radius`].
    Auto,
    /// Each pixel's initial radius from the photons: its distance to the k-th nearest photon
    /// of a pilot photon map at its first diffuse visible point (`--radius photons`,
    /// `render: { radius: photons }`, and the default): see
    /// [`crate::integrator::photon_radii`].
    Photons,
}

impl Radius {
    /// Whether every pixel has its own initial radius, set by a pilot pass before the first
    /// iteration (`auto`, `photons`), rather than one for all (a world radius).
    pub fn per_pixel(&self) -> bool {
        !matches!(self, Radius::World(_))
    }
}

impl std::fmt::Display for Radius {
    /// As the command line and the scene format spell it: the radius in scene units, `auto`
    /// (the footprint rule, also spelt `footprint`) or `photons`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Radius::World(r) => write!(f, "{r}"),
            Radius::Auto => f.write_str("auto"),
            Radius::Photons => f.write_str("photons"),
        }
    }
}

/// Everything the user can set for one render.
#[derive(Clone, Debug)]
pub struct RenderSettings {
    pub algorithm: Algorithm,
    /// Seed of every random stream.
    pub seed: u64,
    /// Most bounces between the camera and a light, whichever technique built the path (0:
    /// only emission seen directly; Mitsuba's `max_depth` minus 1); renders use at most
    /// [`MAX_DEPTH`] ([`RenderSettings::normalised`]).
    pub max_depth: u32,
    /// Russian roulette starts after this many bounces.
    pub rr_depth: u32,
    /// Path tracer: how light is found.
    pub light_strategy: LightStrategy,
    /// Photon mapping: light paths per iteration (VCM traces one per pixel and ignores it).
    pub photons: u32,
    /// Photon mapping: initial gather radius (scene units, or per pixel from its footprint or
    /// from the pilot photons); VCM: initial merge radius (scene units, or the median of the
    /// per-pixel rule's radii).
    pub radius: Radius,
    /// Photon mapping and VCM: radius reduction r_{i+1}^2 = r_i^2 (i + alpha) / (i + 1).
    pub alpha: f32,
    /// Photon mapping: direct light from photons or from light sampling.
    pub direct: DirectMode,
}

impl RenderSettings {
    /// Defaults, taking what the scene file says where it says anything (the algorithm:
    /// `ppm` unless the file names one). Without a radius in the scene the initial radius is
    /// [`Radius::Photons`]: each pixel's distance to its k-th nearest photon of a pilot photon
    /// map of fixed size, which depends neither on the scene's units, nor on its extent, nor
    /// on the image's resolution. alpha
    /// defaults to 2/3, the asymptotically best value for surfaces (Knaus and Zwicker 2011).
    pub fn new(scene: &Scene) -> Self {
        let d = scene.defaults;
        RenderSettings {
            algorithm: d.algorithm.unwrap_or(Algorithm::DEFAULT),
            seed: 0,
            max_depth: d.max_depth,
            rr_depth: 3,
            light_strategy: LightStrategy::Mis,
            photons: d.photons.unwrap_or(DEFAULT_PHOTONS),
            radius: d.radius.unwrap_or(Radius::Photons),
            alpha: d.alpha,
            // Light sampling removes the noisiest part of the density estimate (direct light)
            // for one shadow ray per pixel: the lower error at equal time on the shipped
            // scenes (docs/performance.md, "Direct light by default").
            direct: DirectMode::Sampled,
        }
    }

    /// [`RenderSettings::new`] for `algorithm`. Where the scene gives no photon count, `sppm`
    /// traces one light path per pixel per iteration (as pbrt-v4's SPPM integrator does by
    /// default; the choice is measured in docs/sppm.md): its memory and its per-iteration
    /// visible-point pass scale with the pixels, so its photon pass should too.
    pub fn for_algorithm(scene: &Scene, algorithm: Algorithm) -> Self {
        let mut settings = RenderSettings::new(scene);
        settings.algorithm = algorithm;
        if algorithm == Algorithm::Sppm && scene.defaults.photons.is_none() {
            let pixels = scene.camera.width as u64 * scene.camera.height as u64;
            settings.photons = pixels.clamp(1, u32::MAX as u64) as u32;
        }
        settings
    }

    /// The settings every integrator renders with: `max_depth` at most [`MAX_DEPTH`]
    /// ([`bounded_depth`]). `Renderer` normalises what it is given, so an integrator never
    /// sees a larger depth; a front end that records the settings (in a saved render's
    /// header) normalises them first, so that the record is what was rendered.
    pub fn normalised(&self) -> Self {
        RenderSettings {
            max_depth: bounded_depth(self.max_depth),
            ..self.clone()
        }
    }

    /// The radius schedule at the 1-based `iteration` (Knaus and Zwicker's r_i for a world
    /// radius; for per-pixel radii the factor s_i every pixel's own r_1 has shrunk by, started at 1):
    /// the one place the schedule's start is read from the settings, so that every render,
    /// shard and summary of these settings uses the same radii bit for bit.
    pub fn radius_schedule_at(&self, iteration: u64) -> RadiusSchedule {
        let start = match self.radius {
            Radius::World(r) => r,
            Radius::Auto | Radius::Photons => 1.0,
        };
        RadiusSchedule::at_iteration(start, self.alpha, iteration)
    }
}
