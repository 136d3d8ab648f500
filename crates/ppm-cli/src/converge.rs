//! `ppm converge`: every algorithm gets the same render-time budget per seed; the error against
//! the reference is measured on a log schedule and written as a CSV and a log-log plot.

use crate::args::{AlgorithmArg, ConvergeArgs};
use crate::error_log::{ErrorSample, ErrorTracker};
use crate::output;
use crate::plot::{self, Curve};
use crate::progress::Progress;
use crate::render::{render_loop, Outcome, StopRule};
use crate::setup;
use crate::signal::Interrupt;
use anyhow::{Context, Result};
use ppm_core::integrator::Renderer;
use std::fmt::Write as _;
use std::path::PathBuf;

/// The error curve of one algorithm and seed.
#[derive(Clone, Debug)]
pub struct Run {
    pub algorithm: AlgorithmArg,
    pub seed: u64,
    pub iterations: u64,
    pub samples: Vec<ErrorSample>,
}

/// `algorithm,seed,iteration,seconds,relmse,rmse` with one row per sample.
pub fn csv(runs: &[Run]) -> String {
    let mut s = String::from("algorithm,seed,iteration,seconds,relmse,rmse\n");
    for run in runs {
        for sample in &run.samples {
            let _ = writeln!(
                s,
                "{},{},{}",
                run.algorithm.name(),
                run.seed,
                sample.csv_row()
            );
        }
    }
    s
}

/// One plot curve per algorithm (in order of first appearance), one run per seed.
pub fn curves(runs: &[Run]) -> Vec<Curve> {
    let mut curves: Vec<(AlgorithmArg, Curve)> = Vec::new();
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
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create folder {}", args.out.display()))?;
    let (csv_path, plot_path) = converge_paths(&args.out, &scene_path);
    output::check_writable(&csv_path)?;
    output::check_writable(&plot_path)?;
    let reference = output::read_image(&args.reference).context("reading --reference")?;
    let mut scene = setup::load_scene(&scene_path)?;
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
    let mut runs = Vec::new();
    setup::with_threads(args.settings.threads, || -> Result<()> {
        for &algorithm in &algorithms {
            for seed in (0..args.seeds as u64).map(|k| args.settings.seed + k) {
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
                runs.push(Run {
                    algorithm,
                    seed,
                    iterations: totals.iterations,
                    samples: tracker.samples,
                });
            }
        }
        Ok(())
    })??;

    output::write_atomic(&csv_path, |w| {
        Ok(std::io::Write::write_all(w, csv(&runs).as_bytes())?)
    })?;
    let title = format!(
        "{}: relMSE against render time ({}x{})",
        scene_path.file_stem().unwrap_or_default().to_string_lossy(),
        reference.width,
        reference.height
    );
    plot::write_plot(&plot_path, &title, &curves(&runs))?;
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

    fn run(algorithm: AlgorithmArg, seed: u64, errors: &[f64]) -> Run {
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
        Run {
            algorithm,
            seed,
            iterations: errors.len() as u64,
            samples,
        }
    }

    #[test]
    fn csv_has_one_row_per_sample() {
        let runs = [
            run(AlgorithmArg::Pt, 0, &[0.25, 0.0625]),
            run(AlgorithmArg::Ppm, 3, &[1.0]),
        ];
        assert_eq!(
            csv(&runs),
            "algorithm,seed,iteration,seconds,relmse,rmse\n\
             pt,0,1,0.500000,2.500000e-1,5.000000e-1\n\
             pt,0,2,1.000000,6.250000e-2,2.500000e-1\n\
             ppm,3,1,0.500000,1.000000e0,1.000000e0\n"
        );
    }

    #[test]
    fn curves_group_seeds_by_algorithm() {
        let runs = [
            run(AlgorithmArg::Ppm, 0, &[1.0, 0.5]),
            run(AlgorithmArg::Pt, 0, &[2.0]),
            run(AlgorithmArg::Ppm, 1, &[0.8, 0.4]),
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
