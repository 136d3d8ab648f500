//! `ppm converge`: every algorithm gets the same render-time budget per seed; the error against
//! the reference is measured on a log schedule and written as a CSV and a log-log plot.

use crate::args::ConvergeArgs;
use crate::error_log::{ErrorSample, ErrorTracker};
use crate::output;
use crate::plot::{self, Curve};
use crate::progress::Progress;
use crate::render::Outcome;
use crate::render_loop::{render_loop, StopRule};
use crate::setup;
use crate::signal::Interrupt;
use anyhow::{bail, Context, Result};
use ppm_core::integrator::{Algorithm, Radius, Renderer, Setting};
use std::fmt::Write as _;
use std::path::PathBuf;

/// The error curve of one algorithm and seed.
#[derive(Clone, Debug)]
pub struct Run {
    pub algorithm: Algorithm,
    pub seed: u64,
    pub iterations: u64,
    /// Photon mapping: light paths per iteration and initial radius (None for pt).
    pub photons: Option<u32>,
    pub radius: Option<Radius>,
    pub samples: Vec<ErrorSample>,
}

/// What all runs of a `ppm converge` share, recorded in every CSV row.
pub struct CsvContext<'a> {
    pub threads: usize,
    /// The reference image's path.
    pub reference: &'a str,
}

/// The CSV columns: the first six as before, the settings after them (empty photons and
/// radius for the path tracer).
pub const CSV_HEADER: &str =
    "algorithm,seed,iteration,seconds,relmse,rmse,threads,photons,radius,reference";

/// A CSV field, quoted when it holds a comma, quote or line break.
fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// [`CSV_HEADER`] and one row per sample.
pub fn csv(runs: &[Run], context: &CsvContext<'_>) -> String {
    let mut s = format!("{CSV_HEADER}\n");
    let reference = csv_field(context.reference);
    for run in runs {
        let photons = run.photons.map(|p| p.to_string()).unwrap_or_default();
        let radius = run.radius.map(|r| r.to_string()).unwrap_or_default();
        for sample in &run.samples {
            let _ = writeln!(
                s,
                "{},{},{},{},{photons},{radius},{reference}",
                run.algorithm.name(),
                run.seed,
                sample.csv_row(),
                context.threads,
            );
        }
    }
    s
}

/// One plot curve per algorithm (in order of first appearance), one run per seed.
pub fn curves(runs: &[Run]) -> Vec<Curve> {
    let mut curves: Vec<(Algorithm, Curve)> = Vec::new();
    for run in runs {
        let points = run.samples.iter().map(|s| (s.seconds, s.rel_mse)).collect();
        match curves.iter_mut().find(|(a, _)| *a == run.algorithm) {
            Some((_, curve)) => curve.runs.push(points),
            None => curves.push((
                run.algorithm,
                Curve {
                    label: run.algorithm.name().into(),
                    runs: vec![points],
                },
            )),
        }
    }
    curves.into_iter().map(|(_, c)| c).collect()
}

/// The curves' legend labels with the settings their algorithm reads: `ppm (200000 photons,
/// r 0.03)`, `vcm (r auto)`, `pt`.
fn labelled(mut curves: Vec<Curve>, runs: &[Run]) -> Vec<Curve> {
    for curve in &mut curves {
        let Some(run) = runs.iter().find(|r| r.algorithm.name() == curve.label) else {
            continue;
        };
        let parts: Vec<String> = [
            run.photons.map(|p| format!("{p} photons")),
            run.radius.map(|r| format!("r {r}")),
        ]
        .into_iter()
        .flatten()
        .collect();
        if !parts.is_empty() {
            curve.label = format!("{} ({})", curve.label, parts.join(", "));
        }
    }
    curves
}

/// Where each algorithm ended: final relMSE (geometric mean, min and max over seeds) and
/// iterations.
pub fn final_report(runs: &[Run]) -> String {
    let mut out = String::new();
    for curve_algorithm in unique(runs.iter().map(|r| r.algorithm)) {
        let finals: Vec<(f64, u64)> = runs
            .iter()
            .filter(|r| r.algorithm == curve_algorithm)
            .filter_map(|r| r.samples.last().map(|s| (s.rel_mse, r.iterations)))
            .collect();
        if finals.is_empty() {
            continue;
        }
        let n = finals.len() as f64;
        let geo = (finals
            .iter()
            .map(|f| f.0.max(f64::MIN_POSITIVE).ln())
            .sum::<f64>()
            / n)
            .exp();
        let iterations = finals.iter().map(|f| f.1).sum::<u64>() as f64 / n;
        let _ = write!(out, "{:>4}: final relMSE {geo:.4e}", curve_algorithm.name());
        if finals.len() > 1 {
            let min = finals.iter().map(|f| f.0).fold(f64::MAX, f64::min);
            let max = finals.iter().map(|f| f.0).fold(f64::MIN, f64::max);
            let _ = write!(
                out,
                " (geometric mean of {} seeds, min {min:.4e}, max {max:.4e})",
                finals.len()
            );
        }
        let _ = writeln!(out, ", {iterations:.1} iterations");
    }
    out
}

fn unique<T: PartialEq>(items: impl IntoIterator<Item = T>) -> Vec<T> {
    let mut out = Vec::new();
    for item in items {
        if !out.contains(&item) {
            out.push(item);
        }
    }
    out
}

/// The CSV and plot paths for a scene in `dir`.
pub fn converge_paths(dir: &std::path::Path, scene: &std::path::Path) -> (PathBuf, PathBuf) {
    let stem = scene
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "scene".into());
    (
        dir.join(format!("{stem}_convergence.csv")),
        dir.join(format!("{stem}_convergence.png")),
    )
}

/// Runs the subcommand.
pub fn run(args: &ConvergeArgs, interrupt: &Interrupt) -> Result<Outcome> {
    let scene_path = setup::locate_scene(&args.scene)?;
    if args.out.exists() && !args.out.is_dir() {
        bail!(
            "--out {} is a file: give the folder to write the CSV and the plot in",
            args.out.display()
        );
    }
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create folder {}", args.out.display()))?;
    let (csv_path, plot_path) = converge_paths(&args.out, &scene_path);
    output::check_writable(&csv_path)?;
    output::check_writable(&plot_path)?;
    let reference = output::read_reference(&args.reference).context("reading --reference")?;
    let mut scene = setup::load_scene(&scene_path, &args.settings.define)?;
    setup::apply_resolution(
        &mut scene,
        &args.settings,
        Some((reference.width, reference.height)),
    )?;

    let stop = StopRule {
        iterations: None,
        time_limit: Some(args.time_limit),
    };
    let algorithms = unique(args.algorithm.iter().copied());
    setup::warn_unread_flags(&args.settings, &algorithms);
    for &algorithm in &algorithms {
        setup::warn_missing_light(&scene, algorithm, &scene_path);
        let settings = setup::render_settings(&scene, algorithm, &args.settings);
        setup::check_radius(&scene, &settings, &args.settings, &scene_path)?;
    }
    let mut runs = Vec::new();
    let mut threads = 0;
    setup::warn_if_threads_capped(args.settings.threads);
    setup::with_threads(args.settings.threads, || -> Result<()> {
        threads = rayon::current_num_threads();
        for &algorithm in &algorithms {
            for seed in (0..args.seeds as u64).map(|k| args.settings.seed.unwrap_or(0) + k) {
                if interrupt.requested() {
                    return Ok(());
                }
                let mut settings = setup::render_settings(&scene, algorithm, &args.settings);
                settings.seed = seed;
                let mut renderer = Renderer::new(&scene, &settings);
                let mut tracker = ErrorTracker::new(reference.clone());
                let progress = Progress::new(&stop, &format!("{} seed {seed}", algorithm.name()));
                let totals = render_loop(
                    &scene,
                    &mut renderer,
                    &stop,
                    interrupt,
                    |renderer, totals, last| {
                        progress.update(totals);
                        tracker.observe(totals.iterations, totals.seconds, last, || {
                            renderer.image()
                        })?;
                        Ok(())
                    },
                );
                progress.finish();
                let totals = totals?;
                let final_error = tracker
                    .samples
                    .last()
                    .map(|s| s.rel_mse)
                    .unwrap_or(f64::NAN);
                status!(
                    "{} seed {seed}: {} iterations in {:.2} s, relMSE {final_error:.4e}",
                    algorithm.name(),
                    totals.iterations,
                    totals.seconds
                );
                let reads = |setting| algorithm.reads(setting);
                runs.push(Run {
                    algorithm,
                    seed,
                    iterations: totals.iterations,
                    photons: reads(Setting::Photons).then_some(settings.photons),
                    radius: reads(Setting::Radius).then_some(settings.radius),
                    samples: tracker.samples,
                });
            }
        }
        Ok(())
    })??;

    let reference_name = args.reference.display().to_string();
    let context = CsvContext {
        threads,
        reference: &reference_name,
    };
    output::write_atomic(&csv_path, |w| {
        Ok(std::io::Write::write_all(
            w,
            csv(&runs, &context).as_bytes(),
        )?)
    })?;
    let title = format!(
        "{}: relMSE against render time ({}x{}, {threads} threads, reference {})",
        scene_path.file_stem().unwrap_or_default().to_string_lossy(),
        reference.width,
        reference.height,
        args.reference
            .file_name()
            .unwrap_or_default()
            .to_string_lossy()
    );
    plot::write_plot(&plot_path, &title, &labelled(curves(&runs), &runs))?;
    status!("wrote {} and {}", csv_path.display(), plot_path.display());
    crate::console::print_stdout(&final_report(&runs))?;
    Ok(if interrupt.requested() {
        Outcome::Interrupted
    } else {
        Outcome::Finished
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(algorithm: Algorithm, seed: u64, errors: &[f64]) -> Run {
        let samples = errors
            .iter()
            .enumerate()
            .map(|(i, &e)| ErrorSample {
                iteration: i as u64 + 1,
                seconds: 0.5 * (i + 1) as f64,
                rel_mse: e,
                rmse: e.sqrt(),
            })
            .collect();
        let ppm = algorithm == Algorithm::Ppm;
        let vcm = algorithm == Algorithm::Vcm;
        Run {
            algorithm,
            seed,
            iterations: errors.len() as u64,
            photons: ppm.then_some(1000),
            radius: (ppm || vcm).then_some(Radius::World(0.25)),
            samples,
        }
    }

    #[test]
    fn csv_has_one_row_per_sample() {
        let runs = [
            run(Algorithm::Path, 0, &[0.25, 0.0625]),
            run(Algorithm::Ppm, 3, &[1.0]),
            run(Algorithm::Vcm, 1, &[0.5]),
        ];
        let context = CsvContext {
            threads: 2,
            reference: "refs/a,b.exr",
        };
        assert_eq!(
            csv(&runs, &context),
            "algorithm,seed,iteration,seconds,relmse,rmse,threads,photons,radius,reference\n\
             pt,0,1,0.500000,2.500000e-1,5.000000e-1,2,,,\"refs/a,b.exr\"\n\
             pt,0,2,1.000000,6.250000e-2,2.500000e-1,2,,,\"refs/a,b.exr\"\n\
             ppm,3,1,0.500000,1.000000e0,1.000000e0,2,1000,0.25,\"refs/a,b.exr\"\n\
             vcm,1,1,0.500000,5.000000e-1,7.071068e-1,2,,0.25,\"refs/a,b.exr\"\n"
        );
        let labels: Vec<String> = labelled(curves(&runs), &runs)
            .into_iter()
            .map(|c| c.label)
            .collect();
        assert_eq!(labels, ["pt", "ppm (1000 photons, r 0.25)", "vcm (r 0.25)"]);
    }

    #[test]
    fn curves_group_seeds_by_algorithm() {
        let runs = [
            run(Algorithm::Ppm, 0, &[1.0, 0.5]),
            run(Algorithm::Path, 0, &[2.0]),
            run(Algorithm::Ppm, 1, &[0.8, 0.4]),
        ];
        let curves = curves(&runs);
        assert_eq!(
            curves.iter().map(|c| c.label.as_str()).collect::<Vec<_>>(),
            ["ppm", "pt"]
        );
        assert_eq!(
            curves[0].runs,
            vec![vec![(0.5, 1.0), (1.0, 0.5)], vec![(0.5, 0.8), (1.0, 0.4)]]
        );
        let report = final_report(&runs);
        // Geometric mean of 0.5 and 0.4 = sqrt(0.2) = 0.44721.
        assert!(report.contains("ppm: final relMSE 4.4721e-1 (geometric mean of 2 seeds, min 4.0000e-1, max 5.0000e-1), 2.0 iterations"), "{report}");
        assert!(
            report.contains("pt: final relMSE 2.0000e0, 1.0 iterations"),
            "{report}"
        );
    }

    #[test]
    fn output_names_follow_the_scene() {
        let (csv, png) = converge_paths(
            std::path::Path::new("out"),
            std::path::Path::new("scenes/box.yml"),
        );
        assert_eq!(
            (csv, png),
            (
                PathBuf::from("out/box_convergence.csv"),
                PathBuf::from("out/box_convergence.png")
            )
        );
    }
}
