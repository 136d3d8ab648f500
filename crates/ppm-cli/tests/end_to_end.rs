//! The `ppm` binary rendering a tiny scene: outputs, error logs, time limits, Ctrl-C and
//! `ppm converge`. These need the scene loader and both integrators.

mod common;

use common::*;
use std::time::{Duration, Instant};

/// Renders `tiny.yml` in `dir` with extra arguments and asserts success.
fn render(dir: &std::path::Path, args: &[&str]) -> String {
    let mut all = vec!["tiny.yml"];
    all.extend_from_slice(args);
    let out = run(dir, &all);
    assert_ok(&out);
    stderr(&out)
}

#[test]
fn render_writes_png_and_exr_with_default_names() {
    let dir = tempfile::tempdir().unwrap();
    tiny_scene(dir.path());
    let log = render(dir.path(), &["-n", "2"]);
    assert_eq!(
        file_names(dir.path()),
        ["tiny.exr", "tiny.png", "tiny.yml"],
        "no temporary files left"
    );
    assert!(log.contains("16x12 ppm: 2 iterations"), "{log}");
    assert!(
        log.contains("rays/s") && log.contains("photons/s") && log.contains("rejected"),
        "{log}"
    );
    let (w, h, pixels) = read_exr(&dir.path().join("tiny.exr"));
    assert_eq!((w, h), (16, 12));
    assert!(pixels.iter().flatten().all(|v| v.is_finite() && *v >= 0.0));
    assert!(
        pixels.iter().flatten().any(|v| *v > 0.0),
        "the lit box is not black"
    );
    let png = image::open(dir.path().join("tiny.png")).unwrap().to_rgb8();
    assert_eq!(png.dimensions(), (16, 12));
}

/// `ppm tiny.yml 2>&1 | head -1`: stderr closed before the render's status lines; the render
/// still finishes, is written, and ppm exits 0 without a panic.
#[test]
fn render_with_stderr_closed_still_writes_the_image() {
    let dir = tempfile::tempdir().unwrap();
    tiny_scene(dir.path());
    let mut child = ppm(dir.path())
        .args(["tiny.yml", "-n", "2"])
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stderr.take());
    let status = child.wait().unwrap();
    assert!(status.success(), "{status:?}");
    assert_eq!(file_names(dir.path()), ["tiny.exr", "tiny.png", "tiny.yml"]);
}

#[test]
fn output_flag_and_resolution_overrides() {
    let dir = tempfile::tempdir().unwrap();
    tiny_scene(dir.path());
    std::fs::create_dir(dir.path().join("renders")).unwrap();
    render(
        dir.path(),
        &[
            "-n",
            "1",
            "-a",
            "pt",
            "-o",
            "renders/a.exr",
            "--width",
            "8",
            "--height",
            "4",
        ],
    );
    render(dir.path(), &["-n", "1", "-o", "renders/b", "--width", "8"]); // aspect kept: 8x6
    assert_eq!(
        file_names(&dir.path().join("renders")),
        ["a.exr", "a.png", "b.exr", "b.png"]
    );
    assert_eq!(read_exr(&dir.path().join("renders/a.exr")).0, 8);
    assert_eq!(read_exr(&dir.path().join("renders/a.exr")).1, 4);
    assert_eq!(read_exr(&dir.path().join("renders/b.exr")).1, 6);
    let out = run(
        dir.path(),
        &["render", "tiny.yml", "-n", "1", "-o", "renders/c.png"],
    );
    assert_ok(&out);
    assert!(dir.path().join("renders/c.exr").exists());
}

#[test]
fn same_seed_gives_the_same_image_on_any_thread_count() {
    let dir = tempfile::tempdir().unwrap();
    tiny_scene(dir.path());
    for algorithm in ["pt", "ppm"] {
        let render_with = |seed: &str, threads: &str, out: &str| {
            let args = [
                "-a",
                algorithm,
                "-n",
                "3",
                "--seed",
                seed,
                "--threads",
                threads,
                "-o",
                out,
            ];
            render(dir.path(), &args)
        };
        render_with("5", "1", "one");
        render_with("5", "2", "two");
        render_with("6", "2", "other");
        let one = read_exr(&dir.path().join("one.exr")).2;
        assert_eq!(one, read_exr(&dir.path().join("two.exr")).2, "{algorithm}");
        assert_ne!(
            one,
            read_exr(&dir.path().join("other.exr")).2,
            "{algorithm}: the seed must matter"
        );
    }
}

#[test]
fn error_log_follows_the_log_schedule() {
    let dir = tempfile::tempdir().unwrap();
    tiny_scene(dir.path());
    // The reference uses another seed: a shared seed would correlate its noise with the render's.
    render(
        dir.path(),
        &["-a", "pt", "-n", "400", "--seed", "1000", "-o", "ref"],
    );
    let log = render(
        dir.path(),
        &[
            "-a",
            "pt",
            "-n",
            "20",
            "-o",
            "run",
            "--reference",
            "ref.exr",
            "--error-log",
            "run.csv",
        ],
    );
    assert!(log.contains("relMSE"), "{log}");
    let csv = std::fs::read_to_string(dir.path().join("run.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("iteration,seconds,relmse,rmse"));
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    let iterations: Vec<u64> = rows.iter().map(|r| r[0] as u64).collect();
    let mut expected: Vec<u64> = (1..=16).collect();
    expected.extend([18, 20]);
    assert_eq!(iterations, expected);
    assert!(
        rows.windows(2).all(|w| w[1][1] >= w[0][1]),
        "seconds increase"
    );
    assert!(rows
        .iter()
        .all(|r| r[2].is_finite() && r[2] > 0.0 && r[3] > 0.0));
    // 20 iterations against 1: the error must have dropped (by about 20x in expectation).
    assert!(
        rows[17][2] < rows[0][2] / 4.0,
        "relMSE {} -> {}",
        rows[0][2],
        rows[17][2]
    );
    // The logged final error is what `ppm compare` measures on the written image.
    let out = run(dir.path(), &["compare", "run.exr", "ref.exr"]);
    assert_ok(&out);
    assert!(
        stdout(&out).contains(&format!("{:.6e}", rows[17][2])),
        "{}",
        stdout(&out)
    );
}

#[test]
fn reference_of_another_size_is_an_error_before_rendering() {
    let dir = tempfile::tempdir().unwrap();
    tiny_scene(dir.path());
    write_exr(&dir.path().join("ref.exr"), 16, 12, |_, _| [0.1; 3]);
    let err = assert_fails(
        &run(
            dir.path(),
            &["tiny.yml", "--width", "8", "--reference", "ref.exr"],
        ),
        1,
    );
    assert!(err.contains("16x12") && err.contains("8x6"), "{err}");
}

#[test]
fn broken_scene_file_is_named() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("broken.yml"), "camera: [1, 2\nobjects: {").unwrap();
    let err = assert_fails(&run(dir.path(), &["broken.yml"]), 1);
    assert!(err.contains("broken.yml"), "{err}");
}

#[test]
fn time_limit_stops_after_the_crossing_iteration() {
    let dir = tempfile::tempdir().unwrap();
    tiny_scene(dir.path());
    let start = Instant::now();
    let log = render(
        dir.path(),
        &[
            "-a",
            "pt",
            "--time-limit",
            "0.5",
            "--checkpoint",
            "0.1",
            "-o",
            "t",
        ],
    );
    assert!(
        start.elapsed() < Duration::from_secs(20),
        "{:?}",
        start.elapsed()
    );
    // "16x12 pt: N iterations in S s": S is at least the limit, by less than an iteration or so.
    let summary = log
        .lines()
        .find(|l| l.starts_with("16x12 pt:"))
        .expect("a summary line");
    let seconds: f64 = summary
        .split(" in ")
        .nth(1)
        .unwrap()
        .split(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!((0.5..2.0).contains(&seconds), "{summary}");
    assert_eq!(
        file_names(dir.path()),
        ["t.exr", "t.png", "tiny.yml"],
        "checkpoints leave no temp files"
    );
}

#[cfg(unix)]
#[test]
fn ctrl_c_writes_the_finished_iterations_and_exits_130() {
    let dir = tempfile::tempdir().unwrap();
    tiny_scene(dir.path());
    let child = ppm(dir.path())
        .args(["tiny.yml", "--time-limit", "120", "-o", "stopped"])
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(1500));
    let status = std::process::Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    let start = Instant::now();
    let out = child.wait_with_output().unwrap();
    assert!(
        start.elapsed() < Duration::from_secs(10),
        "stopped after the current iteration"
    );
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(130), "{err}");
    assert!(
        err.contains("interrupted") && err.contains("wrote"),
        "{err}"
    );
    let (w, h, pixels) = read_exr(&dir.path().join("stopped.exr"));
    assert_eq!((w, h), (16, 12));
    assert!(pixels.iter().flatten().any(|v| *v > 0.0));
    assert!(dir.path().join("stopped.png").exists());
}

#[test]
fn converge_writes_csv_and_plot() {
    let dir = tempfile::tempdir().unwrap();
    tiny_scene(dir.path());
    render(
        dir.path(),
        &["-a", "pt", "-n", "200", "--seed", "1000", "-o", "ref"],
    );
    let args = [
        "converge",
        "tiny.yml",
        "--reference",
        "ref.exr",
        "--time-limit",
        "1",
        "-a",
        "pt,ppm",
        "--seeds",
        "2",
        "--out",
        "plots",
    ];
    let out = run(dir.path(), &args);
    assert_ok(&out);
    let report = stdout(&out);
    assert!(
        report.contains("pt: final relMSE") && report.contains("ppm: final relMSE"),
        "{report}"
    );
    assert_eq!(
        file_names(&dir.path().join("plots")),
        ["tiny_convergence.csv", "tiny_convergence.png"]
    );

    let csv = std::fs::read_to_string(dir.path().join("plots/tiny_convergence.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some("algorithm,seed,iteration,seconds,relmse,rmse,threads,photons,radius,reference"),
        "the first six columns as before, the settings after them"
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    for (algorithm, seed) in [("pt", "0"), ("pt", "1"), ("ppm", "0"), ("ppm", "1")] {
        let run: Vec<&Vec<&str>> = rows
            .iter()
            .filter(|r| r[0] == algorithm && r[1] == seed)
            .collect();
        assert!(
            run.len() >= 2,
            "{algorithm} seed {seed}: {} rows",
            run.len()
        );
        assert_eq!(run[0][2], "1", "the first iteration is logged");
        let last_seconds: f64 = run.last().unwrap()[3].parse().unwrap();
        assert!(
            last_seconds >= 1.0,
            "{algorithm} seed {seed} ran its budget: {last_seconds}"
        );
    }
    let plot = image::open(dir.path().join("plots/tiny_convergence.png")).unwrap();
    assert_eq!((plot.width(), plot.height()), (1024, 720));
}
