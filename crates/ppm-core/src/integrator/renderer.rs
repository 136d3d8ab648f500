//! One interface for every integrator ([`Integrator`]), the registration of each one
//! ([`for_each_integrator!`]: its `Algorithm` variant and render-state type), and the
//! [`Renderer`] that holds the render state of whichever the settings name.
//!
//! The front end asks the interface, never the algorithm: what an integrator supports
//! ([`Features`]), what it will allocate, how its settings read, and, once it renders, its
//! image, counts, extra images and snapshot. Dispatch happens once per call (per iteration,
//! not per path); the kernels inside each integrator stay statically dispatched.

use super::{
    Algorithm, IterationStats, MemoryEstimate, RenderSettings, RenderStart, Setting, Snapshot, Stop,
};
use super::{
    BpmRenderer, BptRenderer, LtRenderer, PathTracer, PpmRenderer, SppmRenderer, VcmRenderer,
};
use crate::film::{Film, Image};
use crate::pixel_bounds::PixelBounds;
use crate::scene::Scene;
use crate::StateError;
use std::ops::Range;

/// An image an integrator may write besides the render (`--aov`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Aov {
    /// Each pixel's gather radius in the last iteration ([`Integrator::radius_image`]).
    Radius,
    /// How many photons each pixel's estimate rests on ([`Integrator::photon_count_image`]).
    Photons,
}

/// What an integrator supports, known before a render starts (the front end refuses options
/// it cannot honour before loading the scene).
#[derive(Clone, Copy, Debug)]
pub struct Features {
    /// The extra images it writes once an iteration is done.
    pub aovs: &'static [Aov],
    /// Why it writes none of the others (for the refusal).
    pub aov_refusal: &'static str,
    /// `None` if its iterations can be cut into shards (a render that starts at a later
    /// iteration, [`Snapshot::starting_at`]) and merged; else why not. Every integrator resumes
    /// from its own snapshot.
    pub shard_refusal: Option<&'static str>,
    /// One sample per pixel per iteration: samples per pixel (`--spp`) are iterations.
    pub sample_per_iteration: bool,
    /// It keeps each iteration's photons in a photon map (its statistics count them as stored).
    pub photon_map: bool,
    /// It renders the light of a delta light (point or spot) that passes a mirror or glass
    /// before a diffuse surface (a path tracer cannot sample such a path).
    pub delta_light_caustics: bool,
    /// Per-pixel channels its snapshot carries besides the film ([`Snapshot::pixels`]).
    pub snapshot_channels: usize,
}

/// The render state of an integrator: a sequence of iterations, after each of which the image
/// is a valid average of the finished ones.
///
/// The associated functions (`where Self: Sized`) describe and build the integrator before a
/// render exists; the methods are what a render loop calls.
pub trait Integrator: Send + Sync {
    /// What it supports.
    fn features() -> Features
    where
        Self: Sized;

    /// What a render of a `width` x `height` image with `settings` will allocate, stated before
    /// allocating it (see `integrator/memory.rs`).
    fn memory_estimate(width: u32, height: u32, settings: &RenderSettings) -> MemoryEstimate
    where
        Self: Sized;

    /// Its settings in words for the summary, e.g. `seed 1, 16 samples per pixel` or the
    /// photons and the radius from the first to the last iteration of `image` (0-based
    /// iterations the image holds: a shard's or a resumed render's own).
    fn settings_words(settings: &RenderSettings, image: Range<u64>) -> String
    where
        Self: Sized;

    /// A render from `start` (its settings normalised, its film empty or a saved one's).
    fn start(start: RenderStart) -> Self
    where
        Self: Sized;

    /// A render continuing from `snapshot` (`--resume`, or a shard:
    /// [`Snapshot::starting_at`]). By default the film is all that carries over
    /// ([`RenderStart::resumed`]); an integrator with per-pixel state checks and takes it.
    fn from_snapshot(
        scene: &Scene,
        settings: &RenderSettings,
        snapshot: Snapshot,
    ) -> Result<Self, StateError>
    where
        Self: Sized,
    {
        Ok(Self::start(RenderStart::resumed(
            scene, settings, snapshot,
        )?))
    }

    /// Renders one more iteration unless `stop` says yes while it runs (asked before each
    /// parallel work item); an abandoned iteration changes nothing and returns `None`.
    fn iterate_until(&mut self, scene: &Scene, stop: Stop) -> Option<IterationStats>;

    /// The film whose iterations the image holds (for `sppm`, the camera paths' direct light,
    /// which counts the same iterations).
    fn film(&self) -> &Film;

    /// The average of all iterations so far.
    fn image(&self) -> Image {
        self.film().image()
    }

    /// The per-pixel estimates of the last iteration alone (row-major).
    fn last_estimates(&self) -> &[glam::Vec3];

    /// The index of the first iteration in the image (0 unless a shard or a slice).
    fn first_iteration(&self) -> u64 {
        self.film().first_iteration()
    }

    /// Iterations in the image (resumed ones included).
    fn iterations(&self) -> u64 {
        self.film().iterations()
    }

    /// Samples dropped as NaN or infinite so far.
    fn rejected(&self) -> u64 {
        self.film().rejected()
    }

    /// (iteration, pixel) of the first sample dropped as NaN, infinite or negative.
    fn first_rejected(&self) -> Option<(u64, u32)> {
        self.film().first_rejected()
    }

    /// Everything [`Integrator::from_snapshot`] needs to continue this render exactly.
    fn snapshot(&self) -> Snapshot {
        Snapshot::of_film(self.film())
    }

    /// Bytes of the render state's large buffers.
    fn memory_bytes(&self) -> usize;

    /// [`Aov::Radius`]: the gather radius of every pixel in the last iteration, as a grey
    /// image (`None` if it has no per-pixel radius, or before the first iteration).
    fn radius_image(&self) -> Option<Image> {
        None
    }

    /// [`Aov::Photons`]: how many photons each pixel's estimate rests on, as a grey image
    /// (`None` if it gathers no photons, or before the first iteration).
    fn photon_count_image(&self, _scene: &Scene) -> Option<Image> {
        None
    }
}

/// The registered integrators: each one's `Algorithm` (and `Renderer`) variant and its render
/// state's type. Adding an integrator adds one line here; the macro hands the list to `$m`.
macro_rules! for_each_integrator {
    ($m:ident!($($args:tt)*)) => {
        $m! {
            [$($args)*]
            Path: PathTracer,
            Ppm: PpmRenderer,
            Sppm: SppmRenderer,
            Vcm: VcmRenderer,
            Bpt: BptRenderer,
            Bpm: BpmRenderer,
            Lt: LtRenderer,
        }
    };
}

/// Defines [`Renderer`] with one variant per registered integrator.
macro_rules! define_renderer {
    ([] $($variant:ident: $state:ty,)*) => {
        /// The render state of one of the integrators: the integrator [`Algorithm`] names, boxed
        /// (a photon buffer and grid make some several times another's size). Every method
        /// forwards to its [`Integrator`].
        pub enum Renderer {
            $(
                #[doc = concat!("The render state of `Algorithm::", stringify!($variant), "`.")]
                $variant(Box<$state>),
            )*
        }
    };
}

for_each_integrator!(define_renderer!());

/// `$body` with `$r` bound to the render state of `$renderer`, whichever integrator it is.
macro_rules! forward {
    ([$renderer:expr, $r:ident => $body:expr] $($variant:ident: $state:ty,)*) => {
        match $renderer {
            $(Renderer::$variant($r) => $body,)*
        }
    };
}

/// `$body` with the type `$T` the render state of `$algorithm`, and `$wrap` a function
/// putting a `$T` in its `Renderer` variant.
macro_rules! with_integrator {
    ([$algorithm:expr, $T:ident, $wrap:ident => $body:expr] $($variant:ident: $state:ty,)*) => {
        match $algorithm {
            $(Algorithm::$variant => {
                type $T = $state;
                #[allow(unused)]
                let $wrap = |state: $state| Renderer::$variant(Box::new(state));
                $body
            })*
        }
    };
}

impl Algorithm {
    /// What its integrator supports.
    pub fn features(self) -> Features {
        for_each_integrator!(with_integrator!(self, T, _wrap => T::features()))
    }

    /// [`Integrator::memory_estimate`] of its integrator.
    pub fn memory_estimate(
        self,
        width: u32,
        height: u32,
        settings: &RenderSettings,
    ) -> MemoryEstimate {
        let settings = settings.normalised();
        let mut estimate = for_each_integrator!(with_integrator!(self, T, _wrap => {
            T::memory_estimate(width, height, &settings)
        }));
        if self.reads(Setting::Radius) {
            super::radius_photons::add_pilot_memory(&mut estimate, width, height, &settings);
        }
        estimate
    }

    /// [`Integrator::settings_words`] of its integrator.
    pub fn settings_words(self, settings: &RenderSettings, image: Range<u64>) -> String {
        for_each_integrator!(with_integrator!(self, T, _wrap => T::settings_words(settings, image)))
    }
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
        let start = RenderStart::fresh(settings, bounds);
        for_each_integrator!(with_integrator!(settings.algorithm, T, wrap => {
            wrap(T::start(start))
        }))
    }

    /// What [`Renderer::new`] will allocate for `scene` with `settings`, before allocating it.
    pub fn memory_estimate(scene: &Scene, settings: &RenderSettings) -> MemoryEstimate {
        let (w, h) = (scene.camera.width, scene.camera.height);
        settings.algorithm.memory_estimate(w, h, settings)
    }

    /// A render continuing from a saved state (`--resume`), or starting at a later iteration
    /// (a shard: [`Snapshot::starting_at`]); each integrator checks and takes what it saved.
    pub fn from_snapshot(
        scene: &Scene,
        settings: &RenderSettings,
        snapshot: Snapshot,
    ) -> Result<Self, StateError> {
        let settings = settings.normalised();
        Ok(for_each_integrator!(
            with_integrator!(settings.algorithm, T, wrap => {
                wrap(T::from_snapshot(scene, &settings, snapshot)?)
            })
        ))
    }

    /// The integrator behind the render state.
    pub fn integrator(&self) -> &dyn Integrator {
        for_each_integrator!(forward!(self, r => &**r))
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
        for_each_integrator!(forward!(self, r => r.iterate_until(scene, stop)))
    }

    /// Everything [`Renderer::from_snapshot`] needs to continue this render exactly.
    pub fn snapshot(&self) -> Snapshot {
        self.integrator().snapshot()
    }

    /// The average of all iterations so far.
    pub fn image(&self) -> Image {
        self.integrator().image()
    }

    /// The per-pixel estimates of the last iteration alone (for `sppm`, whose iterations
    /// share per-pixel statistics, the current image).
    pub fn last_estimates(&self) -> &[glam::Vec3] {
        self.integrator().last_estimates()
    }

    /// The index of the first iteration in the image (0 unless a shard or a slice).
    pub fn first_iteration(&self) -> u64 {
        self.integrator().first_iteration()
    }

    /// Iterations in the image (resumed ones included).
    pub fn iterations(&self) -> u64 {
        self.integrator().iterations()
    }

    /// Samples dropped as NaN or infinite so far.
    pub fn rejected(&self) -> u64 {
        self.integrator().rejected()
    }

    /// (iteration, pixel) of the first sample dropped as NaN, infinite or negative: random
    /// streams are keyed by (seed, iteration, pixel), so that path can be traced again.
    pub fn first_rejected(&self) -> Option<(u64, u32)> {
        self.integrator().first_rejected()
    }

    /// The image of `aov` after the last iteration, if the integrator writes it
    /// ([`Features::aovs`]) and an iteration is done.
    pub fn aov_image(&self, aov: Aov, scene: &Scene) -> Option<Image> {
        match aov {
            Aov::Radius => self.radius_image(),
            Aov::Photons => self.photon_count_image(scene),
        }
    }

    /// [`Integrator::radius_image`].
    pub fn radius_image(&self) -> Option<Image> {
        self.integrator().radius_image()
    }

    /// [`Integrator::photon_count_image`].
    pub fn photon_count_image(&self, scene: &Scene) -> Option<Image> {
        self.integrator().photon_count_image(scene)
    }

    /// Bytes of the render state's large buffers (film, photons or visible points, grid).
    pub fn memory_bytes(&self) -> usize {
        self.integrator().memory_bytes()
    }
}
