//! The render command: checks, the render loop with its observers, and the outputs.

use crate::args::{RenderArgs, DEFAULT_ITERATIONS};
use crate::error_log::{ErrorLog, ErrorTracker};
use crate::output::{self, OutputPaths};
use crate::progress::{peak_rss_bytes, Progress, Summary};
use crate::provenance::Provenance;
use crate::render_loop::{render_loop, LoopTotals, StopRule};
use crate::resume::{self, StartArgs};
use crate::signal::Interrupt;
use crate::state_file;
use crate::{guard, memory, setup};
use anyhow::{Context, Result};
use ppm_core::integrator::{Algorithm, Renderer};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

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
                state_file::write_image_and_state(paths, &renderer.image(), &snapshot, provenance)
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

/// The options that depend on what the integrator supports ([`Algorithm::features`]):
/// `--spp` (returns the iterations asked for), `--aov` and `--shard`.
fn check_algorithm_options(args: &RenderArgs, algorithm: Algorithm) -> Result<Option<u64>> {
    let iterations = crate::report::requested_iterations(args, algorithm)?;
    let features = algorithm.features();
    if let Some(aov) = args.aov.iter().find(|a| !features.aovs.contains(&a.aov())) {
        let writers = crate::report::names(|f| f.aovs.contains(&aov.aov()));
        usage_bail!(
            "--aov {} needs photon mapping (-a {writers}): {}",
            aov.name(),
            features.aov_refusal
        );
    }
    if let (Some((index, count)), Some(refusal)) = (args.shard, features.shard_refusal) {
        if count > 1 {
            usage_bail!(
                "--shard {index}/{count}: {} cannot be split into shards: {refusal}. Shard \
                 -a {}, or continue an {} render with --resume",
                algorithm.name(),
                crate::report::names(|f| f.shard_refusal.is_none()),
                algorithm.name()
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
    output::create_folder_and_check(&paths.png)?;
    output::create_folder_and_check(&paths.exr)?;
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
    // `--resume FILE`: the settings not given come from the file, which records them all.
    let recorded;
    let args = match &args.resume {
        Some(path) => {
            recorded = crate::resume_flags::with_recorded_settings(
                args,
                &state_file::read(path)?.provenance,
            )?;
            &recorded
        }
        None => args,
    };
    // With `-a` given, its options are checked before anything else; without, once the
    // scene (which may name the algorithm) is loaded.
    if let Some(algorithm) = args.algorithm {
        check_algorithm_options(args, algorithm)?;
    }
    let scene_arg = args.scene.as_deref().context("no scene file given")?;
    let (scene_path, found_by) = setup::locate_scene_found(scene_arg)?;
    let paths = output::output_paths(args.output.as_deref(), &scene_path)?;
    check_outputs(args, &paths, &scene_path)?;
    let reference = args
        .reference
        .as_deref()
        .map(|p| output::read_reference(p).context("reading --reference"))
        .transpose()?;

    let (mut scene, scene_hash) = setup::load_scene_hashed(&scene_path, &args.settings.define)?;
    let algorithm = crate::args::resolve_algorithm(args.algorithm, scene.defaults.algorithm);
    let iterations = check_algorithm_options(args, algorithm)?;
    setup::apply_resolution(
        &mut scene,
        &args.settings,
        reference.as_ref().map(|r| (r.width, r.height)),
    )?;
    let settings = setup::render_settings(&scene, algorithm, &args.settings);
    setup::warn_unread_flags(&args.settings, &[algorithm]);
    setup::warn_missing_light(&scene, algorithm, &scene_path);
    setup::check_radius(&scene, &settings, &args.settings, &scene_path)?;
    memory::check(&scene, &settings)?;
    let camera = &scene.camera;
    // The command line's crop window replaces the scene's (`render.pixel_bounds`, a
    // Mitsuba or pbrt film's crop).
    let bounds = match (&args.cropwindow, &args.pixelbounds, scene.defaults.crop) {
        (None, None, Some(crop)) => crop,
        _ => crate::crop::pixel_bounds(
            camera.width,
            camera.height,
            args.cropwindow.as_deref(),
            args.pixelbounds.as_deref(),
        )?,
    };
    let cropped = bounds != ppm_core::pixel_bounds::PixelBounds::full(camera.width, camera.height);
    if args.verbose {
        status!(
            "{}",
            crate::report::verbose_lines(
                &scene_path,
                found_by,
                camera.width,
                camera.height,
                &bounds
            )
        );
    }
    let mut preview = args.display_server.as_deref().map(|address| {
        let name = scene_path.file_stem().unwrap_or_default().to_string_lossy();
        crate::display::Display::start(address, &format!("ppm {name}"))
    });
    if cropped && (args.shard.is_some() || args.resume.is_some()) {
        usage_bail!(
            "--cropwindow, --pixelbounds and a scene's crop window (render.pixel_bounds, a \
             Mitsuba or pbrt film's crop) render a part of the image, which --shard and \
             --resume do not take: render whole images to shard or resume them \
             (--cropwindow 0 1 0 1 renders the whole image of a cropped scene)"
        );
    }
    let size = (scene.camera.width, scene.camera.height);
    setup::warn_if_threads_capped(args.settings.threads);
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
    provenance.camera = Some(crate::camera_matrices::CameraMatrices::new(
        &scene.camera,
        scene.origin.as_dvec3(),
    ));
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
            crate::oom::set_phase(crate::oom::Phase::Starting);
            let mut renderer = if !cropped {
                Renderer::from_snapshot(&scene, &settings, start.snapshot)
                    .context("cannot continue the saved render")?
            } else {
                Renderer::with_bounds(&settings, bounds)
            };
            crate::oom::set_phase(crate::oom::Phase::Rendering);
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
            crate::oom::set_phase(crate::oom::Phase::Writing);
            let totals = totals?;
            let aovs: Vec<_> = args
                .aov
                .iter()
                .filter_map(|&aov| Some((aov, renderer.aov_image(aov.aov(), &scene)?)))
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
    crate::rescue::write_or_rescue(&paths, &image, &snapshot, &provenance_after(&totals))?;
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
    if args.resume.is_some() {
        let total = provenance_after(&totals);
        info!(
            "the render now holds {} iterations, {:.2} s of render time over all its runs",
            snapshot.film.iterations(),
            total.render_seconds
        );
    }
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
            settings.seed
        );
    }
    crate::black_image::warn_if_black(
        &image,
        &scene_path,
        &scene,
        &settings,
        args.settings.radius.is_some(),
        &totals,
    );
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
