//! Progressive photon mapping (Hachisuka et al. 2008), in the probabilistic formulation of
//! Knaus and Zwicker 2011: every iteration is an independent photon-mapping estimate with
//! the iteration's radius, and the image is their average.
//!
//! The radius is global (`Radius::World`) or per pixel (`Radius::Photons`, `Radius::Auto`):
//! each pixel p then starts at its own r_1(p), fixed by a pilot pass before the first
//! iteration ([`initial_pixel_radii`]), and runs its own Knaus-Zwicker sequence
//! r_{i+1}(p)^2 = r_i(p)^2 (i + alpha) / (i + 1) (their eq. 19). This is still their
//! estimator, pixel by pixel: their analysis is of one measurement point, whose radius
//! sequence is any deterministic sequence with that ratio; nothing in it couples pixels. The
//! pilot's random numbers are drawn from its own stream, independent of every iteration's
//! photons and eye paths, so conditioned on the pilot each r_1(p) is a constant, each
//! iteration's estimate at p has the bias and variance of their analysis at radius r_i(p), and
//! the average converges to the pixel's value as there. (A radius chosen from an iteration's
//! own photons or paths would correlate with the estimate it scales and bias it.) Since the
//! ratio does not depend on p, r_i(p) = r_1(p) s_i with s_i the schedule started at 1.
//!
//! One iteration: the photon pass (light paths of [`trace_light_path`]) fills the shared
//! append buffer, the hash grid is rebuilt over those photons, the eye pass ([`eye_pass`])
//! gathers them at the first diffuse hit of each camera path, the estimate joins the film,
//! and the radius shrinks ([`RadiusSchedule`]).

mod eye_pass;

pub(crate) use eye_pass::trace_eye_path;
pub use eye_pass::{density_estimate, gather_limit, GatherContext};

use super::camera_walk::RayCounters;
use super::footprint::{pilot_points, quantile};
use super::radius_photons::initial_pixel_radii;
use super::runner::{reduce_until, Poll};
use super::task_order::interleaved;
use super::{
    image_bytes, summary, trace_light_path, Aov, Features, Integrator, IterationStats,
    MemoryEstimate, MemoryPart, PassTimes, PhotonCounters, RadiusSchedule, RenderSettings,
    RenderStart, Stop, Stopwatch, BYTES_PER_PHOTON, MAX_LIGHT_PATHS, PHOTONS_PER_PATH,
};
use crate::film::{Film, Image};
use crate::photon::{HashGrid, Kernel, PhotonBuffer};
use crate::pixel_bounds::PixelBounds;
use crate::scene::Scene;
use glam::Vec3;
use rayon::prelude::*;
use std::ops::Range;

/// Light paths per parallel work item of the photon pass.
const PATHS_PER_TASK: u32 = 512;
/// Pixels per parallel work item of the eye pass.
const PIXELS_PER_TASK: usize = 1024;
/// With per-pixel radii the grid's cells are built for this quantile of them: queries up to
/// it visit 2 x 2 x 2 cells, larger ones (pixels that see far surfaces) visit more cells and
/// stay exact. Building for the largest radius instead would make every query scan cells
/// sized for the farthest pixel: a floor reaching 30 times further would cost the near pixels
/// up to 900 times the photons per cell.
const GRID_QUANTILE: f32 = 0.9;

/// Per-pixel initial radii (`Radius::Photons`, `Radius::Auto`), fixed at the first iteration.
struct PixelRadii {
    /// r_1(p) for each pixel, row-major.
    initial: Vec<f32>,
    /// The [`GRID_QUANTILE`] quantile of `initial`: the grid is built for it times s_i.
    grid: f32,
}

/// The render state of progressive photon mapping.
pub struct PpmRenderer {
    settings: RenderSettings,
    film: Film,
    /// The pixels rendered (the whole image unless cropped); photons are traced for the
    /// whole scene either way, keyed by light path, so a crop changes no pixel.
    bounds: PixelBounds,
    /// The radius of the iteration (`Radius::World`), or the factor s_i by which every
    /// pixel's radius has shrunk (per-pixel radii, started at 1).
    schedule: RadiusSchedule,
    /// Per-pixel radii: each pixel's r_1, from the pilot pass (made by the first iteration).
    pixel_radii: Option<PixelRadii>,
    /// The schedule's value in the last iteration (for [`PpmRenderer::radius_image`]).
    last_scale: Option<f32>,
    /// Allocated once, grown when an iteration stores more photons than it holds.
    photons: PhotonBuffer,
    grid: HashGrid,
    estimates: Vec<Vec3>,
}

impl PpmRenderer {
    /// The photon pass: all light paths of this iteration, in parallel, into the shared buffer.
    /// If the buffer overflows, it grows and the pass is redone: light paths are keyed by
    /// (seed, iteration, path) so the redone pass stores exactly the same photons. `None` if
    /// `stop` said yes before one of the work items (the pass is then incomplete).
    fn photon_pass(&mut self, scene: &Scene, iteration: u64, stop: Stop) -> Option<PhotonCounters> {
        let paths = self.settings.photons;
        let poll = Poll::new(stop);
        loop {
            self.photons.clear();
            let buffer = &self.photons;
            let settings = &self.settings;
            let tasks = paths.div_ceil(PATHS_PER_TASK);
            let counters = reduce_until(
                0..tasks,
                &poll,
                |task| {
                    let mut counters = PhotonCounters::default();
                    let mut writer = buffer.writer();
                    let end = ((task + 1) * PATHS_PER_TASK).min(paths);
                    for path in task * PATHS_PER_TASK..end {
                        // A path is up to max_depth bounces: ask between paths.
                        if poll.stopped() {
                            break;
                        }
                        trace_light_path(
                            scene,
                            settings,
                            iteration,
                            path,
                            &mut writer,
                            &mut counters,
                        );
                    }
                    counters
                },
                |a, b| PhotonCounters {
                    rays: a.rays + b.rays,
                    photons: a.photons + b.photons,
                },
            )?;
            if !self.photons.overflowed() {
                return Some(counters);
            }
            let needed = self.photons.pushed();
            self.photons.grow(needed + needed / 4);
        }
    }

    /// The radius the next iteration will use; with per-pixel radii the one its photon grid
    /// will be built for (the [`GRID_QUANTILE`] quantile of the pixels'; before the first
    /// iteration, the schedule's factor 1).
    pub fn radius(&self) -> f32 {
        let mut schedule = self.schedule;
        schedule.advance_to(self.film.next_iteration() + 1, &|| false);
        let scale = schedule.radius();
        self.pixel_radii.as_ref().map_or(scale, |p| p.grid * scale)
    }

    /// The photons stored by the last iteration, in the grid's (deterministic) order.
    pub fn photon_map(&self) -> &HashGrid {
        &self.grid
    }
}

impl Integrator for PpmRenderer {
    fn features() -> Features {
        Features {
            aovs: &[Aov::Radius, Aov::Photons],
            aov_refusal: "",
            shard_refusal: None,
            sample_per_iteration: false,
            photon_map: true,
            delta_light_caustics: true,
            snapshot_channels: 0,
        }
    }

    /// The per-pixel buffers, and the photon buffer and hash grid sized for
    /// [`PHOTONS_PER_PATH`] photons per light path (both grow if a scene stores more).
    fn memory_estimate(width: u32, height: u32, settings: &RenderSettings) -> MemoryEstimate {
        let paths = settings.photons.clamp(1, MAX_LIGHT_PATHS) as u64;
        let mut estimate = MemoryEstimate::default();
        estimate.add(MemoryPart::Image, image_bytes(width, height));
        estimate.add(
            MemoryPart::Photons,
            paths * PHOTONS_PER_PATH as u64 * BYTES_PER_PHOTON,
        );
        estimate
    }

    /// The photons, the radius from the image's first iteration to its last (for `auto` the
    /// factor every pixel's own radius shrank by), alpha and the direct light.
    fn settings_words(settings: &RenderSettings, image: Range<u64>) -> String {
        let radius =
            summary::scheduled_radius(settings, image, |rule| format!("{rule} (per pixel)"));
        summary::photon_mapping(settings, &radius)
    }

    /// A render from `start`; the number of light paths is capped at [`MAX_LIGHT_PATHS`].
    /// Knaus and Zwicker's PPM carries nothing but the film between iterations (the default
    /// [`Integrator::from_snapshot`]): iteration i's photons and eye paths depend on
    /// (seed, i) and its radius on i alone, so the schedule restarts at the film's next
    /// iteration (and the per-pixel radii's pilot, keyed by the seed, is traced again to the
    /// same radii).
    fn start(start: RenderStart) -> Self {
        let RenderStart {
            mut settings,
            bounds,
            film,
        } = start;
        settings.photons = settings.photons.clamp(1, MAX_LIGHT_PATHS);
        // Grown on demand when a scene stores more photons per path.
        let capacity = settings.photons as usize * PHOTONS_PER_PATH;
        PpmRenderer {
            // 1-based: 0-based iteration k uses the (k + 1)-th radius. A render that starts
            // later (a shard, a resumed render) replays the schedule to its first iteration
            // in `iterate_until`, where a stop request can cut the replay short.
            schedule: settings.radius_schedule_at(1),
            pixel_radii: None,
            last_scale: None,
            settings,
            film,
            bounds,
            photons: PhotonBuffer::with_capacity(capacity),
            grid: HashGrid::new(),
            estimates: vec![Vec3::ZERO; bounds.len()],
        }
    }

    /// Renders one iteration. With per-pixel radii the first one starts with the pilot pass
    /// (its rays count as eye rays, its time as the eye pass's).
    ///
    /// Abandoned (film and radius untouched, `None`) if `stop` says
    /// yes before one of the photon or eye pass's work items starts.
    fn iterate_until(&mut self, scene: &Scene, stop: Stop) -> Option<IterationStats> {
        let iteration = self.film.next_iteration();
        if !self.schedule.advance_to(iteration + 1, &stop) {
            return None;
        }
        let mut passes = PassTimes::default();
        let mut clock = Stopwatch::start();
        let mut pilot = RayCounters::default();
        if self.settings.radius.per_pixel() && self.pixel_radii.is_none() {
            if let Some(initial) = initial_pixel_radii(scene, &self.settings, &mut pilot, stop)? {
                let grid = quantile(&initial, GRID_QUANTILE);
                self.pixel_radii = Some(PixelRadii { initial, grid });
            }
        }
        passes.eye = clock.lap();
        let scale = self.schedule.radius();
        let radius = self.pixel_radii.as_ref().map_or(scale, |p| p.grid * scale);
        let photon_counters = self.photon_pass(scene, iteration, stop)?;
        passes.photon = clock.lap();
        self.grid.build(self.photons.as_slice(), radius);
        passes.grid = clock.lap();

        let ctx = GatherContext {
            grid: &self.grid,
            kernel: Kernel::new(radius),
            radius,
            inv_paths: 1.0 / self.settings.photons as f32,
        };
        let width = scene.camera.width as usize;
        let settings = &self.settings;
        let pixel_radii = self.pixel_radii.as_ref().map(|p| &p.initial[..]);
        let bounds = self.bounds;
        let poll = Poll::new(stop);
        let eye = reduce_until(
            interleaved(self.estimates.chunks_mut(PIXELS_PER_TASK)),
            &poll,
            |(task, pixels)| {
                let mut counters = RayCounters::default();
                for (i, out) in pixels.iter_mut().enumerate() {
                    if poll.stopped() {
                        break;
                    }
                    let pixel = bounds.full_index(task * PIXELS_PER_TASK + i);
                    // This pixel's radius r_1(p) s_i, and its kernel.
                    let own;
                    let ctx = match pixel_radii {
                        None => &ctx,
                        Some(initial) => {
                            let r = initial[pixel] * scale;
                            own = GatherContext {
                                kernel: Kernel::new(r),
                                radius: r,
                                ..ctx
                            };
                            &own
                        }
                    };
                    *out = trace_eye_path(
                        scene,
                        settings,
                        ctx,
                        iteration,
                        pixel,
                        width,
                        &mut counters,
                    );
                }
                counters
            },
            RayCounters::merge,
        )?; // Abandoned: the grid is rebuilt by the next iteration.
        passes.eye += clock.lap();

        let before = self.film.rejected();
        self.film.add_iteration(&self.estimates);
        passes.film = clock.lap();
        self.schedule.advance();
        self.last_scale = Some(scale);
        Some(IterationStats {
            rays: eye.rays + pilot.rays + photon_counters.rays,
            photon_rays: photon_counters.rays,
            shadow_rays: eye.shadow_rays + pilot.shadow_rays,
            light_paths: self.settings.photons as u64,
            photons: photon_counters.photons,
            radius,
            rejected: self.film.rejected() - before,
            passes,
        })
    }

    /// The per-pixel estimates of the last iteration alone (row-major), for variance
    /// estimates in statistical tests.
    fn last_estimates(&self) -> &[Vec3] {
        &self.estimates
    }

    /// The accumulated image.
    fn film(&self) -> &Film {
        &self.film
    }

    /// The gather radius of every pixel in the last iteration as a grey image (`None` before
    /// the first iteration).
    fn radius_image(&self) -> Option<Image> {
        let scale = self.last_scale?;
        let mut image = Image::new(self.film.width, self.film.height);
        match &self.pixel_radii {
            None => image.pixels.fill(Vec3::splat(scale)),
            Some(p) => {
                for (local, out) in image.pixels.iter_mut().enumerate() {
                    *out = Vec3::splat(p.initial[self.bounds.full_index(local)] * scale);
                }
            }
        }
        Some(image)
    }

    /// How many photons of the last iteration lie within each pixel's gather radius at the
    /// pixel's first diffuse visible point, as a grey image (`None` before the first
    /// iteration): what the pixel's density estimate of that iteration rests on (its relative
    /// noise is about one over the square root). The visible point is the pixel's pilot point
    /// ([`pilot_points`]: the path through the pixel's centre), found by tracing once more;
    /// pixels whose path finds no diffuse surface read 0. With `--direct sampled` the
    /// first-bounce photons are not stored and not counted.
    fn photon_count_image(&self, scene: &Scene) -> Option<Image> {
        let scale = self.last_scale?;
        let s = &self.settings;
        let points = pilot_points(
            scene,
            s.seed,
            s.max_depth,
            s.rr_depth,
            &mut RayCounters::default(),
        );
        let mut image = Image::new(self.film.width, self.film.height);
        image
            .pixels
            .par_iter_mut()
            .enumerate()
            .for_each(|(local, out)| {
                let pixel = self.bounds.full_index(local);
                let radius = self
                    .pixel_radii
                    .as_ref()
                    .map_or(scale, |p| p.initial[pixel] * scale);
                let mut count = 0u32;
                if let Some(point) = points[pixel] {
                    // The photons the estimate there counts (see `density_estimate`).
                    let max_bounce = gather_limit(s.max_depth, point.depth);
                    self.grid
                        .for_each_in_radius(point.position, radius, |photon, _| {
                            count += (photon.bounce() <= max_bounce) as u32;
                        });
                }
                *out = Vec3::splat(count as f32);
            });
        Some(image)
    }

    /// Bytes held by the render state (film, photon buffer, grid, per-pixel estimates).
    fn memory_bytes(&self) -> usize {
        self.estimates.len() * std::mem::size_of::<Vec3>()
            + self.film.memory_bytes()
            + self
                .pixel_radii
                .as_ref()
                .map_or(0, |p| p.initial.len() * std::mem::size_of::<f32>())
            + self.photons.memory_bytes()
            + self.grid.memory_bytes()
    }
}
