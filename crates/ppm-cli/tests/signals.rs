//! Stop signals: a render stopped by a signal writes its finished iterations, a stop during
//! the first iteration writes nothing, an inherited ignored signal stays ignored. Signals are
//! real ones sent to a child `ppm` with `kill`.

mod common;

use common::process::*;
use common::*;
use std::io::{BufRead, BufReader};
use std::process::Stdio;
use std::sync::mpsc;
use std::time::Duration;

/// A closed box of perfect mirrors lit by a point light: no path ever ends (no diffuse
/// surface stores a photon or stops an eye path, Russian roulette never fires), so an
/// iteration costs max_depth bounces for every pixel and light path.
const MIRROR_BOX: &str = r#"
camera: { position: [0.0, 1.0, 0.5], look_at: [0.0, 1.0, -1.0], up: [0.0, 1.0, 0.0], fov: 60.0 }
resolution: [256, 256]
materials:
  mirror: { type: mirror, color: [1.0, 1.0, 1.0] }
objects:
  - { type: quad, corner: [-1, 0, -1], edge_u: [0, 0, 2], edge_v: [2, 0, 0], material: mirror }
  - { type: quad, corner: [-1, 2, -1], edge_u: [2, 0, 0], edge_v: [0, 0, 2], material: mirror }
  - { type: quad, corner: [-1, 0, -1], edge_u: [2, 0, 0], edge_v: [0, 2, 0], material: mirror }
  - { type: quad, corner: [-1, 0, 1], edge_u: [0, 2, 0], edge_v: [2, 0, 0], material: mirror }
  - { type: quad, corner: [-1, 0, -1], edge_u: [0, 2, 0], edge_v: [0, 0, 2], material: mirror }
  - { type: quad, corner: [1, 0, -1], edge_u: [0, 0, 2], edge_v: [0, 2, 0], material: mirror }
lights:
  - { type: point, position: [0.0, 1.5, 0.0], intensity: [5.0, 5.0, 5.0] }
render:
  photons: 100000
"#;

/// SIGTERM (timeout, systemd, docker stop, batch schedulers), SIGHUP (a closed terminal),
/// SIGUSR1 and SIGUSR2 (Slurm's `--signal` before a time limit) and SIGXCPU (a CPU-time
/// limit) stop a render like Ctrl-C: the finished iterations are written and the status is
/// 130.
#[cfg(unix)]
#[test]
fn stop_signals_write_the_finished_iterations_and_exit_130() {
    for signal in ["TERM", "HUP", "USR1", "USR2", "XCPU"] {
        let dir = tempfile::tempdir().unwrap();
        tiny_scene(dir.path());
        let args = ["tiny.yml", "--time-limit", "1000", "--checkpoint", "0.01"];
        let (child, lines) = spawn(dir.path(), &args);
        // A checkpoint exists once an iteration has finished.
        wait_for_file(&dir.path().join("tiny.exr"));
        kill(&child, signal);
        let (code, err) = finish(child, lines);
        assert_eq!(code, Some(130), "SIG{signal}: {err}");
        assert!(err.contains("wrote"), "SIG{signal}: {err}");
        let (w, h, pixels) = read_exr(&dir.path().join("tiny.exr"));
        assert_eq!((w, h), (16, 12));
        assert!(pixels.iter().flatten().any(|v| *v > 0.0));
        assert_eq!(
            file_names(dir.path()),
            ["tiny.exr", "tiny.png", "tiny.yml"],
            "SIG{signal}: no temporary file left"
        );
    }
}

/// A signal ppm inherits as ignored stays ignored: `nohup ppm ...` (here `trap "" HUP`, the
/// same disposition) renders on after a hang-up, as a background job of a script does after
/// SIGINT. SIGTERM still stops it.
#[cfg(unix)]
#[test]
fn a_signal_inherited_as_ignored_does_not_stop_the_render() {
    for (signal, trap) in [("HUP", "HUP"), ("INT", "INT")] {
        let dir = tempfile::tempdir().unwrap();
        tiny_scene(dir.path());
        let mut child = std::process::Command::new("sh")
            .current_dir(dir.path())
            .args([
                "-c",
                &format!(
                    "trap '' {trap}; exec \"$0\" tiny.yml --time-limit 1000 --checkpoint 0.01"
                ),
                env!("CARGO_BIN_EXE_ppm"),
            ])
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let stderr = child.stderr.take().unwrap();
        let (send, lines) = mpsc::channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stderr).split(b'\n').map_while(Result::ok) {
                let _ = send.send(String::from_utf8_lossy(&line).into_owned());
            }
        });
        wait_for_file(&dir.path().join("tiny.exr"));
        kill(&child, signal);
        // A handled stop ends the render within milliseconds; an ignored one changes nothing.
        std::thread::sleep(Duration::from_millis(1500));
        assert!(
            child.try_wait().unwrap().is_none(),
            "SIG{signal}, inherited as ignored, stopped the render"
        );
        kill(&child, "TERM");
        let (code, err) = finish(child, lines);
        assert_eq!(code, Some(130), "SIG{signal} then SIGTERM: {err}");
        assert!(!err.contains("interrupted twice"), "{err}");
    }
}

/// One stop delivered twice at once, as coreutils `timeout` does (the child, then its
/// process group) and as Slurm may: the same stop, not "quit without writing". Whether the
/// kernel merges the two into one pending signal is a race, so each signal is tried four
/// times: a handler that took the second for "quit" fails this almost surely.
#[cfg(unix)]
#[test]
fn a_stop_signal_delivered_twice_at_once_still_writes_the_image() {
    for signal in ["INT", "TERM", "INT", "TERM", "INT", "TERM", "INT", "TERM"] {
        let dir = tempfile::tempdir().unwrap();
        tiny_scene(dir.path());
        let args = ["tiny.yml", "--time-limit", "1000", "--checkpoint", "0.01"];
        let (child, lines) = spawn(dir.path(), &args);
        wait_for_file(&dir.path().join("tiny.exr"));
        let status = std::process::Command::new("sh")
            .args(["-c", &format!("kill -{signal} {0} {0}", child.id())])
            .status()
            .unwrap();
        assert!(status.success());
        let (code, err) = finish(child, lines);
        assert_eq!(code, Some(130), "SIG{signal}: {err}");
        assert!(
            err.contains("wrote") && !err.contains("without writing"),
            "SIG{signal}: {err}"
        );
    }
}

/// A stop during the first iteration (or the scene's loading) writes nothing: the previous
/// render of the same name survives. The mirror box's first iteration is millions of
/// bounces, so the stop arrives inside it, and the passes must see it: the test
/// fails if the iteration is completed (files replaced) or never ends (the guard).
#[cfg(unix)]
#[test]
fn a_stop_before_the_first_iteration_finishes_keeps_the_previous_files() {
    for signal in ["INT", "TERM"] {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("mirror.yml"), MIRROR_BOX).unwrap();
        std::fs::write(dir.path().join("shot.png"), b"previous png").unwrap();
        std::fs::write(dir.path().join("shot.exr"), b"previous exr").unwrap();
        let args = ["mirror.yml", "--max-depth", "4294967295", "-o", "shot"];
        let (child, lines) = spawn(dir.path(), &args);
        // Printed after loading, just before rendering starts.
        let mut err = wait_for_line(&lines, "above the supported 1024");
        kill(&child, signal);
        let (code, rest) = finish(child, lines);
        err.push_str(&rest);
        assert_eq!(code, Some(130), "SIG{signal}: {err}");
        assert!(err.contains("nothing written"), "SIG{signal}: {err}");
        assert_eq!(
            std::fs::read(dir.path().join("shot.png")).unwrap(),
            b"previous png"
        );
        assert_eq!(
            std::fs::read(dir.path().join("shot.exr")).unwrap(),
            b"previous exr"
        );
        assert_eq!(
            file_names(dir.path()),
            ["mirror.yml", "shot.exr", "shot.png"]
        );
    }
}

/// A closed sphere seen from inside, white and emissive: every path bounces max_depth times
/// (albedo 1, Russian roulette never ends it), and in VCM every camera vertex connects to
/// every vertex of its light subpath, so one pixel is about a million shadow rays.
const GLOWING_SPHERE: &str = r#"
camera: { position: [0.0, 0.0, 0.0], look_at: [0.0, 0.0, -1.0], up: [0.0, 1.0, 0.0], fov: 60.0 }
resolution: [16, 16]
materials:
  glow: { type: diffuse, color: [1.0, 1.0, 1.0], emission: [1.0, 1.0, 1.0] }
objects:
  - { type: sphere, center: [0, 0, 0], radius: 1.0, material: glow, inward: true }
render:
  photons: 2048
"#;

/// A stop is seen within a moment whatever the algorithm and depth: the passes ask between
/// paths and pixels, and VCM between camera vertices, not only between work items (a work
/// item of 256 pixels of the glowing sphere is a minute of VCM). The bound is a loose guard
/// (a stop is seen in well under a second; the item before this fix took a minute), not a
/// timing.
#[cfg(unix)]
#[test]
fn a_stop_in_a_deep_closed_scene_is_seen_at_once_by_every_algorithm() {
    for algorithm in ["vcm", "bpt", "bpm", "lt", "sppm", "ppm", "pt"] {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("sphere.yml"), GLOWING_SPHERE).unwrap();
        // Iterations enough that no algorithm finishes before the stop (light tracing alone
        // runs 32 iterations of this scene in about a second).
        let args = [
            "sphere.yml",
            "-a",
            algorithm,
            "--max-depth",
            "4294967295",
            "-n",
            "1000000",
        ];
        let (child, lines) = spawn(dir.path(), &args);
        // Printed after loading, just before rendering starts; then well into the iteration.
        let mut err = wait_for_line(&lines, "above the supported 1024");
        std::thread::sleep(Duration::from_millis(1500));
        let asked = std::time::Instant::now();
        kill(&child, "TERM");
        let (code, rest) = finish(child, lines);
        let waited = asked.elapsed();
        err.push_str(&rest);
        // Light tracing alone finishes iterations in this scene (nothing connects to a
        // camera path): a stop then writes them, as any stop does.
        assert_eq!(code, Some(130), "-a {algorithm}: {err}");
        assert!(
            waited < Duration::from_secs(15),
            "-a {algorithm}: the stop took {waited:?} to be seen"
        );
    }
}
