//! Vertex connection and merging (Georgiev, Krivanek, Davidovic, Slusallek 2012, "Light
//! transport simulation with vertex connection and merging", SIGGRAPH Asia), as its technical
//! report ("Implementing vertex connection and merging", Georgiev 2012) and SmallVCM describe
//! it: bidirectional path tracing and photon mapping combined by multiple importance
//! sampling. See docs/vcm.md for the estimators together.
//!
//! One iteration:
//! 1. the light pass ([`light_path`]): one light subpath per pixel of the full image
//!    (N_light = width x height), its non-delta vertices stored and connected to the camera;
//!    those contributions are splatted into exact fixed-point sums ([`SplatBuffer`]) in path
//!    order, so the image does not depend on the thread count;
//! 2. a hash grid over the light vertices, built for the iteration's merge radius r_i;
//! 3. the camera pass ([`camera_path`]): per pixel, a camera subpath paired with the light
//!    subpath of the same index, with emission, next-event estimation, connections to that
//!    light subpath's vertices and merging with every light vertex within r_i, each weighted
//!    by the recursive MIS of [`mis`];
//! 4. the pixel's estimate is its camera-pass estimate plus its splats; the film averages the
//!    iterations, and the radius shrinks.
//!
//! Radius: r_i follows progressive photon mapping's schedule (Knaus and Zwicker 2011,
//! r_{i+1}^2 = r_i^2 (i + alpha) / (i + 1), [`RadiusSchedule`]), which shrinks as
//! i^((alpha - 1) / 2) like the VCM paper's r_i = r_1 i^((alpha - 1) / 2) (sec. 5) up to a
//! constant factor. r_1 is `--radius` in scene units, or with a per-pixel rule (`photons`,
//! the default, or `auto`) the median of the pixels' radii ([`initial_pixel_radii`]; for
//! `photons` their k-nearest distances, without ppm's bias-variance scale): VCM
//! merges at every non-delta camera vertex,
//! not only the first, so it needs one radius for the whole grid. `--photons` is not used:
//! the light subpaths are one per pixel, as in the paper and SmallVCM.
//!
//! The same code renders SmallVCM's other algorithms as subsets of these techniques
//! ([`Techniques`]: `bpt`, `bpm`, `lt`), each with MIS weights over exactly its set; a set
//! without merging builds no grid and uses no radius.

mod camera_path;
mod light_path;
mod mis;
mod subsets;
mod techniques;
mod vertex;

pub use subsets::{Bpm, BpmRenderer, Bpt, BptRenderer, Lt, LtRenderer, TechniqueSet, VcmSubset};
pub use techniques::Techniques;

use super::camera_walk::RayCounters;
use super::footprint::quantile;
use super::radius_photons::initial_pixel_radii;
use super::runner::{collect_until, reduce_until, Poll};
use super::task_order::interleaved;
use super::{
    image_bytes, summary, Features, Integrator, IterationStats, MemoryEstimate, MemoryPart,
    PassTimes, RadiusSchedule, RenderSettings, RenderStart, Snapshot, Stop, Stopwatch,
    BYTES_PER_PHOTON, PHOTONS_PER_PATH,
};
use crate::film::{Film, SplatBuffer};
use crate::photon::{HashGrid, Photon};
use crate::pixel_bounds::PixelBounds;
use crate::scene::Scene;
use crate::StateError;
use camera_path::CameraPass;
use glam::Vec3;
use light_path::{trace_light_subpath, LightPathParams, Splat};
use mis::MisConstants;
use rayon::prelude::*;
use std::ops::Range;
use vertex::{LightVertex, MergeVertex};

/// Light subpaths per parallel work item of the light pass.
const PATHS_PER_TASK: u32 = 256;
/// Pixels per parallel work item of the camera pass.
const PIXELS_PER_TASK: usize = 256;

/// Bytes per stored light vertex: the vertex, its record in the hash grid and what merging
/// reads of it.
const BYTES_PER_LIGHT_VERTEX: u64 = (std::mem::size_of::<LightVertex>()
    + std::mem::size_of::<MergeVertex>()) as u64
    + BYTES_PER_PHOTON;

/// What one work item of the light pass produces, for its paths in order: their vertices,
/// the end of each path's vertices (relative to the item's first), the camera splats, and
/// the rays traced.
#[derive(Default)]
struct LightTask {
    vertices: Vec<LightVertex>,
    ends: Vec<u32>,
    splats: Vec<Splat>,
    counters: RayCounters,
}

/// The render state of vertex connection and merging.
pub struct VcmRenderer {
    settings: RenderSettings,
    techniques: Techniques,
    film: Film,
    /// The pixels rendered (the whole image unless cropped); light subpaths are traced for
    /// the whole image either way, keyed by their index, so a crop changes no pixel.
    bounds: PixelBounds,
    /// The radius (`Radius::World`), or the factor by which r_1 has shrunk (per-pixel rules).
    schedule: RadiusSchedule,
    /// Per-pixel rules: r_1, the median of the pixels', from the pilot pass (made by the
    /// first iteration).
    auto_radius: Option<f32>,
    /// The merge radius of the last iteration.
    last_radius: Option<f32>,
    /// The light vertices of the iteration, path after path; reused.
    vertices: Vec<LightVertex>,
    /// Light path i's vertices are `vertices[path_start[i]..path_start[i + 1]]`.
    path_start: Vec<u32>,
    /// The light vertices as grid records (`path` = index into `vertices`); reused.
    records: Vec<Photon>,
    grid: HashGrid,
    /// What merging reads of the light vertices, in the grid's order; reused.
    merge_vertices: Vec<MergeVertex>,
    splats: SplatBuffer,
    estimates: Vec<Vec3>,
}

impl VcmRenderer {
    /// A render from `start` with the technique set `techniques` (the registered `vcm`
    /// renders [`Techniques::VCM`]; `bpt`, `bpm` and `lt` are its subsets). Like the path
    /// tracer, VCM carries nothing but the film between iterations: iteration i's subpaths
    /// depend on (seed, i) and its radius on i alone (a per-pixel rule's pilot, keyed by the
    /// seed, is traced again to the same r_1).
    pub fn start_with(start: RenderStart, techniques: Techniques) -> Self {
        let RenderStart {
            settings,
            bounds,
            film,
        } = start;
        VcmRenderer {
            // 1-based: 0-based iteration k uses the (k + 1)-th radius. A render that starts
            // later (a shard, a resumed render) replays the schedule to its first iteration
            // in `iterate_until`, where a stop request can cut the replay short.
            schedule: settings.radius_schedule_at(1),
            auto_radius: None,
            last_radius: None,
            settings,
            techniques,
            film,
            bounds,
            vertices: Vec::new(),
            path_start: Vec::new(),
            records: Vec::new(),
            grid: HashGrid::new(),
            merge_vertices: Vec::new(),
            splats: SplatBuffer::new(bounds.len()),
            estimates: vec![Vec3::ZERO; bounds.len()],
        }
    }

    /// A fresh render of the pixels in `bounds` (see [`PixelBounds`]) with the technique set
    /// `techniques`.
    pub fn with_techniques(
        settings: RenderSettings,
        bounds: PixelBounds,
        techniques: Techniques,
    ) -> Self {
        Self::start_with(RenderStart::fresh(&settings, bounds), techniques)
    }

    /// A render continuing from `snapshot` (whole images only) with the technique set
    /// `techniques`, which must be the one the snapshot was rendered with (the film does not
    /// record it).
    pub fn from_snapshot_with_techniques(
        scene: &Scene,
        settings: RenderSettings,
        snapshot: Snapshot,
        techniques: Techniques,
    ) -> Result<Self, StateError> {
        let start = RenderStart::resumed(scene, &settings, snapshot)?;
        Ok(Self::start_with(start, techniques))
    }

    /// The technique set this render uses.
    pub fn techniques(&self) -> Techniques {
        self.techniques
    }

    /// [`Integrator::memory_estimate`] for the technique set `techniques`: light tracing
    /// alone stores no light vertices.
    pub fn memory_estimate_with_techniques(
        width: u32,
        height: u32,
        _settings: &RenderSettings,
        techniques: Techniques,
    ) -> MemoryEstimate {
        let pixels = width as u64 * height as u64;
        // The splat sums, and each light path's first vertex index.
        let per_pixel = (std::mem::size_of::<[u128; 3]>() + std::mem::size_of::<u32>()) as u64;
        let mut estimate = MemoryEstimate::default();
        estimate.add(
            MemoryPart::Image,
            image_bytes(width, height).saturating_add(pixels.saturating_mul(per_pixel)),
        );
        if techniques.stores_light_vertices() {
            estimate.add(
                MemoryPart::Photons,
                pixels
                    .saturating_mul(PHOTONS_PER_PATH as u64)
                    .saturating_mul(BYTES_PER_LIGHT_VERTEX),
            );
        }
        estimate
    }

    /// The merge radius of the next iteration, and a per-pixel rule's pilot pass if it is due;
    /// `None` if `stop` said yes during the pilot pass.
    fn radius(&mut self, scene: &Scene, counters: &mut RayCounters, stop: Stop) -> Option<f32> {
        let s = &self.settings;
        if s.radius.per_pixel() && self.auto_radius.is_none() {
            if let Some(radii) = initial_pixel_radii(scene, s, counters, stop)? {
                self.auto_radius = Some(quantile(&radii, 0.5));
            }
        }
        Some(self.schedule.radius() * self.auto_radius.unwrap_or(1.0))
    }

    /// The light pass: every light subpath of `iteration`, in parallel, collected in path
    /// order; `None` if `poll` said stop before or during one of the work items.
    fn light_pass(
        &mut self,
        scene: &Scene,
        params: &LightPathParams,
        paths: u32,
        poll: &Poll,
    ) -> Option<RayCounters> {
        let tasks = collect_until(0..paths.div_ceil(PATHS_PER_TASK), poll, |task| {
            let mut out = LightTask::default();
            for path in task * PATHS_PER_TASK..((task + 1) * PATHS_PER_TASK).min(paths) {
                // A light subpath of a deep scene is max_depth vertices, each connected to
                // the camera: ask between paths.
                if poll.stopped() {
                    break;
                }
                trace_light_subpath(
                    scene,
                    params,
                    path,
                    &mut out.vertices,
                    &mut out.splats,
                    &mut out.counters,
                );
                out.ends.push(out.vertices.len() as u32);
            }
            out
        })?;
        self.vertices.clear();
        self.path_start.clear();
        self.path_start.push(0);
        self.splats.clear();
        let mut counters = RayCounters::default();
        for task in &tasks {
            let base = self.vertices.len() as u32;
            self.path_start.extend(task.ends.iter().map(|e| base + e));
            self.vertices.extend_from_slice(&task.vertices);
            for s in &task.splats {
                self.splats.add(s.pixel as usize, s.value);
            }
            counters = RayCounters::merge(counters, task.counters);
        }
        Some(counters)
    }

    /// The hash grid over the iteration's light vertices for merge radius `radius`, and what
    /// merging reads of them in the grid's order.
    fn build_grid(&mut self, radius: f32) {
        self.records.clear();
        self.records.extend(
            self.vertices
                .iter()
                .enumerate()
                .map(|(i, y)| Photon::new(y.vertex.hit.p, y.vertex.wo, y.throughput, i as u32)),
        );
        self.grid.build(&self.records, radius);
        self.merge_vertices.clear();
        let vertices = &self.vertices;
        self.merge_vertices.par_extend(
            self.grid
                .photons()
                .par_iter()
                .map(|photon| MergeVertex::of(&vertices[photon.path as usize])),
        );
    }

    /// The merge radius of the last iteration (`None` before the first, and for technique sets
    /// without merging).
    pub fn last_radius(&self) -> Option<f32> {
        self.last_radius
    }
}

impl Integrator for VcmRenderer {
    fn features() -> Features {
        Features {
            aovs: &[],
            aov_refusal: "VCM merges with one radius for every pixel (the summary prints it) and \
                          weights its merges by MIS",
            shard_refusal: None,
            sample_per_iteration: false,
            photon_map: false,
            delta_light_caustics: true,
            snapshot_channels: 0,
        }
    }

    /// [`VcmRenderer::memory_estimate_with_techniques`] for [`Techniques::VCM`].
    fn memory_estimate(width: u32, height: u32, settings: &RenderSettings) -> MemoryEstimate {
        Self::memory_estimate_with_techniques(width, height, settings, Techniques::VCM)
    }

    /// One light path per pixel, the merge radius from the image's first iteration to its
    /// last (for `auto` the factor r_1 shrank by) and alpha.
    fn settings_words(settings: &RenderSettings, image: Range<u64>) -> String {
        format!(
            "seed {}, one light path per pixel per iteration, merge radius {} (alpha {})",
            settings.seed,
            summary::scheduled_radius(settings, image, |rule| match rule {
                "auto" => "auto (median footprint)".to_string(),
                _ => format!("{rule} (median over pixels)"),
            }),
            summary::significant(settings.alpha),
        )
    }

    /// [`VcmRenderer::start_with`] all techniques ([`Techniques::VCM`]).
    fn start(start: RenderStart) -> Self {
        Self::start_with(start, Techniques::VCM)
    }

    /// Renders one iteration; abandoned (film and radius untouched, `None`) if `stop` says yes
    /// during the light or camera pass (asked between light subpaths and between camera
    /// vertices).
    fn iterate_until(&mut self, scene: &Scene, stop: Stop) -> Option<IterationStats> {
        let iteration = self.film.next_iteration();
        let merging = self.techniques.merging();
        if merging && !self.schedule.advance_to(iteration + 1, &stop) {
            return None;
        }
        let mut passes = PassTimes::default();
        let mut clock = Stopwatch::start();
        let mut pilot = RayCounters::default();
        let radius = if merging {
            self.radius(scene, &mut pilot, stop)?
        } else {
            0.0
        };
        let camera = &scene.camera;
        let light_paths = camera.width * camera.height;
        let mis = MisConstants::new(self.techniques, radius, light_paths);
        let max_edges = self.settings.max_depth + 1;
        let params = LightPathParams {
            seed: self.settings.seed,
            iteration,
            max_edges,
            mis,
            bounds: self.bounds,
        };
        passes.eye = clock.lap();
        if self.path_start.capacity() == 0 && self.techniques.stores_light_vertices() {
            // What the memory estimate states; grown when a scene stores more vertices.
            let paths = light_paths as usize;
            self.path_start.reserve_exact(paths + 1);
            self.vertices.reserve_exact(paths * PHOTONS_PER_PATH);
            self.records.reserve_exact(paths * PHOTONS_PER_PATH);
            self.merge_vertices.reserve_exact(paths * PHOTONS_PER_PATH);
        }
        let poll = Poll::new(stop);
        let light = self.light_pass(scene, &params, light_paths, &poll)?;
        passes.photon = clock.lap();
        if merging {
            self.build_grid(radius);
        }
        passes.grid = clock.lap();

        let pass = CameraPass {
            scene,
            seed: self.settings.seed,
            iteration,
            max_edges,
            rr_depth: self.settings.rr_depth,
            mis,
            radius,
            grid: &self.grid,
            vertices: &self.vertices,
            path_start: &self.path_start,
            merge_vertices: &self.merge_vertices,
            poll: &poll,
        };
        let bounds = self.bounds;
        let splats = &self.splats;
        let eye = reduce_until(
            interleaved(self.estimates.chunks_mut(PIXELS_PER_TASK)),
            &poll,
            |(task, pixels)| {
                let mut counters = RayCounters::default();
                for (i, out) in pixels.iter_mut().enumerate() {
                    let local = task * PIXELS_PER_TASK + i;
                    let pixel = bounds.full_index(local);
                    *out = pass.pixel(pixel, &mut counters) + splats.value(local);
                }
                counters
            },
            RayCounters::merge,
        )?;
        passes.eye += clock.lap();

        let before = self.film.rejected();
        self.film.count_rejected(self.splats.rejected());
        self.film.add_iteration(&self.estimates);
        passes.film = clock.lap();
        if merging {
            self.schedule.advance();
            self.last_radius = Some(radius);
        }
        Some(IterationStats {
            rays: eye.rays + light.rays + pilot.rays,
            photon_rays: light.rays,
            shadow_rays: eye.shadow_rays + light.shadow_rays + pilot.shadow_rays,
            light_paths: light_paths as u64,
            photons: self.vertices.len() as u64,
            radius,
            rejected: self.film.rejected() - before,
            passes,
        })
    }

    /// The per-pixel estimates of the last iteration alone (row-major), splats included.
    fn last_estimates(&self) -> &[Vec3] {
        &self.estimates
    }

    /// The accumulated image.
    fn film(&self) -> &Film {
        &self.film
    }

    /// Bytes held by the render state.
    fn memory_bytes(&self) -> usize {
        self.estimates.len() * std::mem::size_of::<Vec3>()
            + self.film.memory_bytes()
            + self.splats.memory_bytes()
            + self.vertices.capacity() * std::mem::size_of::<LightVertex>()
            + self.path_start.capacity() * std::mem::size_of::<u32>()
            + self.records.capacity() * std::mem::size_of::<Photon>()
            + self.merge_vertices.capacity() * std::mem::size_of::<MergeVertex>()
            + self.grid.memory_bytes()
    }
}
