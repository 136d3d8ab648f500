//! The render loop (shared by `ppm render` and `ppm converge`) and the render command.

use crate::args::{AlgorithmArg, AovArg, RenderArgs, DEFAULT_ITERATIONS};
use crate::error_log::{ErrorLog, ErrorTracker};
use crate::output::{self, OutputPaths};
use crate::progress::{peak_rss_bytes, Progress, Summary};
use crate::provenance::Provenance;
use crate::resume::{self, StartArgs};
use crate::signal::Interrupt;
use crate::state_file;
use crate::{guard, memory, setup};
use anyhow::{Context, Result};
use ppm_core::integrator::{PassTimes, Renderer};
use ppm_core::scene::Scene;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// When a render stops: after `iterations`, or after the iteration that crosses `time_limit`
/// seconds of render time, whichever comes first.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StopRule {
    pub iterations: Option<u64>,
    pub time_limit: Option<f64>,
}

impl StopRule {
    /// True when a render with these totals is finished.
    pub fn done(&self, iterations: u64, seconds: f64) -> bool {
        self.iterations.is_some_and(|n| iterations >= n)
            || self.time_limit.is_some_and(|t| seconds >= t)
    }
}

/// Counts over all iterations so far.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LoopTotals {
    pub iterations: u64,
    /// Render time: the sum of the iterations' times, without the observer's work.
    pub seconds: f64,
    pub rays: u64,
    /// Closest-hit rays of the photon pass (included in `rays`).
    pub photon_rays: u64,
    pub shadow_rays: u64,
    pub light_paths: u64,
    pub photons: u64,
    /// Render time by pass.
    pub passes: PassTimes,
    /// True if the loop stopped because of an interrupt.
    pub interrupted: bool,
}

/// Renders iterations until `stop` says so or `interrupt` is raised, calling `after` after each
/// with the renderer, the totals and whether it was the last iteration. The time `after` takes
/// (error measurement, checkpoints) is not render time.
///
/// An interrupt abandons the iteration in progress (its passes poll the flag), so a stop
/// request is seen within one parallel work item even when an iteration is very long; the
/// renderer's image stays the average of the finished iterations. `after` is then called once
/// more with `last` set, for the final measurement, if any iteration finished.
pub fn render_loop(
    scene: &Scene,
    renderer: &mut Renderer,
    stop: &StopRule,
    interrupt: &Interrupt,
    mut after: impl FnMut(&Renderer, &LoopTotals, bool) -> Result<()>,
) -> Result<LoopTotals> {
    let mut totals = LoopTotals::default();
    while !stop.done(totals.iterations, totals.seconds) && !interrupt.requested() {
        let start = Instant::now();
        let Some(stats) = renderer.iterate_until(scene, &|| interrupt.requested()) else {
            if totals.iterations > 0 {
                after(renderer, &totals, true)?;
            }
            break;
        };
        totals.seconds += start.elapsed().as_secs_f64();
        totals.iterations += 1;
        totals.rays += stats.rays;
        totals.photon_rays += stats.photon_rays;
        totals.shadow_rays += stats.shadow_rays;
        totals.light_paths += stats.light_paths;
        totals.photons += stats.photons;
        totals.passes.add(&stats.passes);
        let last = stop.done(totals.iterations, totals.seconds) || interrupt.requested();
        after(renderer, &totals, last)?;
    }
    totals.interrupted = interrupt.requested();
    Ok(totals)
}

/// Writes the current image every `every` (wall-clock) while rendering.
struct Checkpoints {
    every: Duration,
    last: Instant,
}

impl Checkpoints {
    /// Writes the render's image and state (resumable with `--resume`) if it is time. A
    /// failed checkpoint (a full disk, a removed folder) is a warning, not the end of the
    /// render: the previous checkpoint's files are intact (both are replaced together or not
    /// at all), the render goes on, and the next checkpoint or the final write tries again.
    fn maybe_write(&mut self, renderer: &Renderer, paths: &OutputPaths, provenance: &Provenance) {
        if self.last.elapsed() >= self.every {
            let snapshot = renderer.snapshot();
            if let Err(e) =
                state_file::write_outputs(paths, &renderer.image(), &snapshot, provenance)
            {
                status!(
                    "\nwarning: checkpoint not written: {e:#}; the last good checkpoint is kept \
                     and rendering goes on"
                );
            }
            self.last = Instant::now();
        }
    }
}

/// How a render command ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outcome {
    Finished,
    /// Stopped by Ctrl-C; the image of the finished iterations was written.
    Interrupted,
}

/// The options that depend on the algorithm: `--spp` (path tracing only; returns the
/// iterations asked for) and `--aov` (photon mapping only).
fn check_algorithm_options(args: &RenderArgs, algorithm: AlgorithmArg) -> Result<Option<u64>> {
    let iterations = crate::report::requested_iterations(args, algorithm)?;
    if !args.aov.is_empty() && algorithm == AlgorithmArg::Pt {
        usage_bail!(
            "--aov {} needs photon mapping (-a ppm or -a sppm): the path tracer gathers no photons",
            args.aov[0].name()
        );
    }
    if !args.aov.is_empty() && algorithm == AlgorithmArg::Vcm {
        usage_bail!(
            "--aov {} needs photon mapping (-a ppm or -a sppm): VCM merges with one radius for \
             every pixel (the summary prints it) and weights its merges by MIS",
            args.aov[0].name()
        );
    }
    if let (Some((_, count)), AlgorithmArg::Sppm) = (args.shard, algorithm) {
        if count > 1 {
            usage_bail!(
                "--shard {}/{count}: sppm cannot be split into shards: each iteration's \
                 per-pixel radii and statistics depend on all iterations before it. Shard \
                 -a ppm or -a vcm, or continue an sppm render with --resume",
                args.shard.map_or(0, |s| s.0)
            );
        }
    }
    Ok(iterations)
}

/// Checks every output path before anything is rendered: none replaces an input or another
/// output (see [`guard`]), stale temporaries of a killed run are removed, and each folder is
/// writable. Fail now, not after an hour of rendering.
fn check_outputs(args: &RenderArgs, paths: &output::OutputPaths, scene_path: &Path) -> Result<()> {
    let mut inputs = vec![("scene file", scene_path)];
    inputs.extend(args.reference.as_deref().map(|r| ("--reference", r)));
    guard::refuse_overwriting_inputs(paths, &inputs)?;
    inputs.extend(args.resume.as_deref().map(|r| ("--resume file", r)));
    let aov_paths: Vec<(String, PathBuf)> = args
        .aov
        .iter()
        .map(|aov| (format!("--aov {} image", aov.name()), paths.aov(aov.name())))
        .collect();
    let mut extras: Vec<(&str, &Path)> = aov_paths
        .iter()
        .map(|(role, path)| (role.as_str(), path.as_path()))
        .collect();
    extras.extend(args.error_log.as_deref().map(|log| ("--error-log", log)));
    guard::refuse_replacing_by_extras(&extras, &inputs, paths)?;
    if let Some(log) = &args.error_log {
        guard::refuse_replacing_non_log(log, crate::error_log::ErrorSample::CSV_HEADER)?;
    }
    for stale in guard::clean_stale_temporaries(paths) {
        status!("removed {}, left by a run that was killed", stale.display());
    }
    output::check_writable(&paths.png)?;
    output::check_writable(&paths.exr)?;
    if let Some(log) = &args.error_log {
        output::check_writable(log)?;
    }
    for aov in &args.aov {
        output::check_writable(&paths.aov(aov.name()))?;
    }
    Ok(())
}

/// `ppm [render] SCENE ...`: checks every input and output path, loads the scene, renders,
/// writes the PNG and EXR and prints a summary.
pub fn run(args: &RenderArgs, interrupt: &Interrupt) -> Result<Outcome> {
    crate::console::set_quiet(args.quiet);
    // With `-a` given, its options are checked before anything else; without, once the
    // scene (which may name the algorithm) is loaded.
    if let Some(algorithm) = args.algorithm {
        check_algorithm_options(args, algorithm)?;
    }
    let scene_arg = args.scene.as_deref().context("no scene file given")?;
    let scene_path = setup::locate_scene(scene_arg)?;
    let paths = output::output_paths(args.output.as_deref(), &scene_path)?;
    check_outputs(args, &paths, &scene_path)?;
    let reference = args
        .reference
        .as_deref()
        .map(|p| output::read_reference(p).context("reading --reference"))
        .transpose()?;

    let (mut scene, scene_hash) = setup::load_scene_hashed(&scene_path)?;
    let algorithm = AlgorithmArg::resolve(args.algorithm, scene.defaults.algorithm);
    let iterations = check_algorithm_options(args, algorithm)?;
    setup::apply_resolution(
        &mut scene,
        &args.settings,
        reference.as_ref().map(|r| (r.width, r.height)),
    )?;
    let settings = setup::render_settings(&scene, algorithm, &args.settings);
    setup::warn_unread_flags(&args.settings, &[algorithm]);
    setup::warn_missing_light(&scene, algorithm, &scene_path);
    memory::check(&scene, &settings)?;
    let camera = &scene.camera;
    let bounds = crate::crop::pixel_bounds(
        camera.width,
        camera.height,
        args.cropwindow.as_deref(),
        args.pixelbounds.as_deref(),
    )?;
    let cropped = bounds != ppm_core::pixel_bounds::PixelBounds::full(camera.width, camera.height);
    if args.verbose {
        status!(
            "{}",
            crate::report::verbose_lines(&scene_path, camera.width, camera.height, &bounds)
        );
    }
    let mut preview = args.display_server.as_deref().map(|address| {
        let name = scene_path.file_stem().unwrap_or_default().to_string_lossy();
        crate::display::Display::start(address, &format!("ppm {name}"))
    });
    if cropped && (args.shard.is_some() || args.resume.is_some()) {
        usage_bail!(
            "--cropwindow and --pixelbounds render a part of the image, which --shard and \
             --resume do not take: render whole images to shard or resume them"
        );
    }
    let size = (scene.camera.width, scene.camera.height);
    let threads = setup::with_threads(args.settings.threads, rayon::current_num_threads)?;
    let start = resume::plan(
        &StartArgs {
            iterations,
            shard: args.shard,
            resume: args.resume.as_deref(),
        },
        &Provenance::new(
            &scene_arg.display().to_string(),
            scene_hash,
            &settings,
            size,
            threads,
        ),
    )?;
    // A shard resumed from a file that already holds all its iterations (a requeued job
    // whose work was done): nothing to render; the file's image is written as it is.
    let already_complete = start.iterations == Some(0);
    if let (true, Some(resumed), Some(shard)) =
        (already_complete, &args.resume, start.provenance.shard)
    {
        status!(
            "{} already holds every iteration of shard {shard}: nothing to render",
            resumed.display()
        );
    }
    let mut provenance = start.provenance;
    if cropped {
        provenance.crop = Some(format!(
            "{} {} {} {} of {}x{}",
            bounds.x0, bounds.x1, bounds.y0, bounds.y1, camera.width, camera.height
        ));
    }
    // Render time of this run added to the earlier runs' of a resumed render.
    let provenance_after = |totals: &LoopTotals| Provenance {
        render_seconds: provenance.render_seconds + totals.seconds,
        ..provenance.clone()
    };
    let stop = StopRule {
        iterations: start.iterations.or(if args.time_limit.is_some() {
            None
        } else {
            Some(DEFAULT_ITERATIONS)
        }),
        time_limit: args.time_limit,
    };
    let mut tracker = reference.map(ErrorTracker::new);
    // The error log counts the iterations and render time of the whole render: a resumed
    // one goes on from those of the file it continues.
    let (earlier_iterations, earlier_seconds) =
        (start.snapshot.film.iterations(), provenance.render_seconds);
    let mut log = match &args.error_log {
        Some(path) => Some(ErrorLog::open(path, earlier_iterations)?),
        None => None,
    };
    let mut checkpoints = args.checkpoint.map(|s| Checkpoints {
        every: Duration::from_secs_f64(s),
        last: Instant::now(),
    });

    let (totals, image, snapshot, rejected, state_bytes, aovs, threads) =
        setup::with_threads(args.settings.threads, || -> Result<_> {
            if args.verbose {
                status!(
                    "{}",
                    crate::report::settings_line(
                        &settings,
                        {
                            let next = start.snapshot.film.next_iteration();
                            next..next + stop.iterations.unwrap_or(1)
                        },
                        rayon::current_num_threads()
                    )
                );
            }
            let mut renderer = if !cropped {
                Renderer::from_snapshot(&scene, &settings, start.snapshot)
                    .context("cannot continue the saved render")?
            } else {
                Renderer::with_bounds(&settings, bounds)
            };
            let progress = Progress::new(&stop, algorithm.name());
            let totals = render_loop(
                &scene,
                &mut renderer,
                &stop,
                interrupt,
                |renderer, totals, last| {
                    progress.update(totals);
                    if let Some(tracker) = &mut tracker {
                        let sample = tracker
                            .observe(
                                earlier_iterations + totals.iterations,
                                earlier_seconds + totals.seconds,
                                last,
                                || renderer.image(),
                            )
                            .context("comparing with --reference")?;
                        if let (Some(sample), Some(log)) = (sample, &mut log) {
                            if let Some(warning) = log.record(&sample) {
                                status!("\n{warning}");
                            }
                        }
                    }
                    if let Some(checkpoints) = &mut checkpoints {
                        checkpoints.maybe_write(renderer, &paths, &provenance_after(totals));
                    }
                    if let Some(preview) = &mut preview {
                        preview.offer(|| renderer.image());
                    }
                    Ok(())
                },
            );
            progress.finish();
            let totals = totals?;
            let aovs: Vec<_> = args
                .aov
                .iter()
                .filter_map(|&aov| match aov {
                    AovArg::Radius => renderer.radius_image().map(|image| (aov, image)),
                    AovArg::Photons => renderer
                        .photon_count_image(&scene)
                        .map(|image| (aov, image)),
                })
                .collect();
            Ok((
                totals,
                renderer.image(),
                renderer.snapshot(),
                (renderer.rejected(), renderer.first_rejected()),
                renderer.memory_bytes(),
                aovs,
                rayon::current_num_threads(),
            ))
        })??;
    if let Some(preview) = preview {
        preview.finish(image.clone());
    }

    if totals.iterations == 0 && !already_complete {
        // Stopped during loading or the first iteration: an image of no iteration is black,
        // and must not replace the previous render of the same name.
        status!(
            "stopped before the first iteration finished: nothing written ({} and {} left as \
             they were)",
            paths.png.display(),
            paths.exr.display()
        );
        return Ok(Outcome::Interrupted);
    }
    crate::rescue::write_outputs(&paths, &image, &snapshot, &provenance_after(&totals))?;
    info!("wrote {} and {}", paths.png.display(), paths.exr.display());
    for (aov, aov_image) in &aovs {
        let path = paths.aov(aov.name());
        output::write_exr(&path, aov_image)?;
        info!("wrote {}", path.display());
    }
    let (rejected, first_rejected) = rejected;
    let summary = Summary {
        width: bounds.width(),
        height: bounds.height(),
        algorithm: algorithm.name(),
        totals: &totals,
        rejected,
        render_state_bytes: state_bytes,
        peak_rss_bytes: peak_rss_bytes(),
    };
    info!("{}", summary.line());
    info!("{}", summary.passes_line());
    info!(
        "{}",
        crate::report::settings_line(
            &settings,
            snapshot.film.first_iteration()..snapshot.film.next_iteration(),
            threads
        )
    );
    if let Some((iteration, pixel)) = first_rejected {
        // The film's pixel index counts pixels of the crop window.
        status!(
            "first rejected sample (NaN, infinite, negative or above 7.2e16: left out of the \
             image): iteration {iteration} (0-based), pixel ({}, {}), seed {}",
            bounds.x0 + pixel % bounds.width(),
            bounds.y0 + pixel / bounds.width(),
            args.settings.seed
        );
    }
    crate::black_image::warn_if_black(&image, &scene_path, &scene, &settings, &totals);
    if let Some(last) = tracker.as_ref().and_then(|t| t.samples.last()) {
        info!(
            "error against {}: relMSE {:.4e}, RMSE {:.4e}",
            display(args.reference.as_deref()),
            last.rel_mse,
            last.rmse
        );
    }
    Ok(if totals.interrupted {
        Outcome::Interrupted
    } else {
        Outcome::Finished
    })
}

fn display(path: Option<&Path>) -> String {
    path.map(|p| p.display().to_string()).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stop_rule_stops_at_the_first_limit_reached() {
        let n = StopRule {
            iterations: Some(3),
            time_limit: None,
        };
        assert!(!n.done(2, 1e9) && n.done(3, 0.0));
        let t = StopRule {
            iterations: None,
            time_limit: Some(1.5),
        };
        assert!(!t.done(1_000_000, 1.49) && t.done(1, 1.5));
        let both = StopRule {
            iterations: Some(10),
            time_limit: Some(1.0),
        };
        assert!(both.done(10, 0.1) && both.done(2, 1.0) && !both.done(9, 0.9));
        assert!(
            !StopRule::default().done(u64::MAX, f64::MAX),
            "no limit: only an interrupt stops"
        );
    }
}
