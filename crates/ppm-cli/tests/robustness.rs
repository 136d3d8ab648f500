//! Never losing a render (issue 17): stop signals, a stop before the first iteration, a pass
//! that must see a stop request, full disks, memory refused up front, hostile inputs and
//! files a render must not touch. Signals are real ones sent to a child `ppm` with `kill`.

mod common;

use common::*;
use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Child, Output, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

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

/// Sends `signal` (TERM, HUP, INT...) to the child.
fn kill(child: &Child, signal: &str) {
    let status = std::process::Command::new("kill")
        .args([&format!("-{signal}"), &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
}

/// Spawns `ppm args` in `dir` with stderr read line by line into a channel.
fn spawn(dir: &Path, args: &[&str]) -> (Child, mpsc::Receiver<String>) {
    let mut child = ppm(dir).args(args).stderr(Stdio::piped()).spawn().unwrap();
    let (send, receive) = mpsc::channel();
    let stderr = child.stderr.take().unwrap();
    std::thread::spawn(move || {
        for line in BufReader::new(stderr).split(b'\n').map_while(Result::ok) {
            let _ = send.send(String::from_utf8_lossy(&line).into_owned());
        }
    });
    (child, receive)
}

/// Waits (at most two minutes, a guard against a hang, not a timing) for a stderr line
/// containing `needle`; returns the lines read so far.
fn wait_for_line(lines: &mpsc::Receiver<String>, needle: &str) -> String {
    let mut seen = String::new();
    let deadline = Instant::now() + Duration::from_secs(120);
    while Instant::now() < deadline {
        if let Ok(line) = lines.recv_timeout(Duration::from_millis(100)) {
            seen.push_str(&line);
            seen.push('\n');
            if line.contains(needle) {
                return seen;
            }
        }
    }
    panic!("no line with {needle:?} on stderr: {seen}");
}

/// Waits for the child to exit (a two-minute guard against a hang); returns its status and
/// the rest of its stderr.
fn finish(mut child: Child, lines: mpsc::Receiver<String>) -> (Option<i32>, String) {
    let deadline = Instant::now() + Duration::from_secs(120);
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            std::thread::sleep(Duration::from_millis(50));
            let rest: Vec<String> = lines.try_iter().collect();
            return (status.code(), rest.join("\n"));
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            panic!("ppm did not stop within two minutes of the stop request");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// Polls (two-minute guard) until `path` exists.
fn wait_for_file(path: &Path) {
    let deadline = Instant::now() + Duration::from_secs(120);
    while !path.exists() {
        assert!(
            Instant::now() < deadline,
            "{} never appeared",
            path.display()
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

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

/// A file-size limit (`ulimit -f`) makes a write fail like a full disk, with a message and
/// status 1, instead of killing ppm with SIGXFSZ. The limit holds in the rescue folder too,
/// so the error says the render is lost, and no partial file is left in either folder.
#[cfg(unix)]
#[test]
fn a_file_size_limit_is_an_error_not_a_kill() {
    let dir = tempfile::tempdir().unwrap();
    tiny_scene(dir.path());
    let rescue = dir.path().join("rescue");
    std::fs::create_dir(&rescue).unwrap();
    let out = std::process::Command::new("sh")
        .current_dir(dir.path())
        .args([
            "-c",
            "ulimit -f 1; exec \"$0\" tiny.yml -n 1",
            env!("CARGO_BIN_EXE_ppm"),
        ])
        .env("PPM_RESCUE_DIR", &rescue)
        .env("TMPDIR", &rescue)
        .env("HOME", &rescue)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        (err.contains("was replaced") || err.contains("too large"))
            && err.contains("the render is lost"),
        "{err}"
    );
    assert_eq!(
        file_names(dir.path()),
        ["rescue", "tiny.yml"],
        "no partial or temporary file"
    );
    assert!(file_names(&rescue).is_empty(), "{:?}", file_names(&rescue));
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
/// bounces, so the stop arrives inside it, and the passes must see it (item 7): the test
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

/// The memory a render needs is estimated before allocating: a render that cannot fit is
/// refused with the setting to lower and the two numbers, never an allocator abort.
#[test]
fn renders_that_cannot_fit_in_memory_are_refused_up_front() {
    let dir = tempfile::tempdir().unwrap();
    tiny_scene(dir.path());
    let run_limited = |args: &[&str]| -> Output {
        ppm(dir.path())
            .args(args)
            .env("PPM_MEMORY_LIMIT", "8G")
            .output()
            .unwrap()
    };
    let err = assert_fails(
        &run_limited(&["tiny.yml", "--width", "16384", "--height", "16384"]),
        1,
    );
    assert!(
        err.contains("not enough memory")
            && err.contains("16384x16384")
            && err.contains("--width/--height")
            && err.contains("8.00 GiB is available")
            && err.contains("PPM_MEMORY_LIMIT"),
        "{err}"
    );
    let err = assert_fails(&run_limited(&["tiny.yml", "--photons", "4294967295"]), 1);
    assert!(
        err.contains("not enough memory") && err.contains("--photons"),
        "{err}"
    );
    // The same render fits with the override raised, and a small one fits 8 GiB.
    assert_ok(&run_limited(&["tiny.yml", "-n", "1"]));
    assert_eq!(file_names(dir.path()), ["tiny.exr", "tiny.png", "tiny.yml"]);
}

/// The estimate covers the peak the render reaches (its summary's VmHWM), the saving of its
/// state at the end included: with the memory limit 3% below a render's measured peak the
/// same render is refused, and with 50% to spare it runs. (Linux only: the peak is read from
/// /proc/self/status.)
#[test]
fn the_memory_estimate_covers_the_measured_peak() {
    if !Path::new("/proc/self/status").exists() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    tiny_scene(dir.path());
    for algorithm in ["pt", "ppm", "sppm", "vcm"] {
        let args = [
            "tiny.yml",
            "-a",
            algorithm,
            "--width",
            "384",
            "--height",
            "384",
            "-n",
            "1",
            "--photons",
            "1000",
            "-t",
            "1",
        ];
        let output = run(dir.path(), &args);
        assert_ok(&output);
        let log = stderr(&output);
        let peak_mib: f64 = log
            .split("peak memory ")
            .nth(1)
            .and_then(|rest| rest.split(" MiB").next())
            .and_then(|v| v.parse().ok())
            .unwrap_or_else(|| panic!("{algorithm}: no peak memory in {log}"));
        let limited = |fraction: f64| {
            let bytes = (peak_mib * fraction * (1 << 20) as f64) as u64;
            ppm(dir.path())
                .args(args)
                .env("PPM_MEMORY_LIMIT", bytes.to_string())
                .output()
                .unwrap()
        };
        let err = assert_fails(&limited(0.97), 1);
        assert!(err.contains("not enough memory"), "{algorithm}: {err}");
        if algorithm != "vcm" {
            // vcm's light vertices are estimated for the longest paths, not the ones traced.
            assert_ok(&limited(1.5));
        }
    }
}

/// 100,000 levels of nesting fail at once with the file and line, before the YAML parser.
#[test]
fn deeply_nested_yaml_is_refused_with_its_place() {
    let dir = tempfile::tempdir().unwrap();
    let text = format!("camera:\n  position: {}\n", "[".repeat(100_000));
    std::fs::write(dir.path().join("deep.yml"), text).unwrap();
    let err = assert_fails(&run(dir.path(), &["deep.yml"]), 1);
    assert!(
        err.contains("deep.yml:2:") && err.contains("64 levels"),
        "{err}"
    );
    let text: String = (0..100_000).map(|_| "- ").collect::<String>() + "1\n";
    std::fs::write(dir.path().join("items.yml"), text).unwrap();
    let err = assert_fails(&run(dir.path(), &["items.yml"]), 1);
    assert!(
        err.contains("items.yml:1:") && err.contains("levels"),
        "{err}"
    );
}

/// A light whose power does not fit f32 arithmetic is an error naming it, never a silent
/// black render.
#[test]
fn an_overflowing_light_power_is_an_error_naming_the_light() {
    let dir = tempfile::tempdir().unwrap();
    let scene = TINY_SCENE.replace(
        "render:",
        "lights:\n  - { type: point, position: [0, 1, 0], intensity: [1e37, 1e37, 1e37] }\nrender:",
    );
    std::fs::write(dir.path().join("hot.yml"), scene).unwrap();
    let err = assert_fails(&run(dir.path(), &["hot.yml", "-n", "1"]), 1);
    assert!(
        err.contains("hot.yml") && err.contains("point light 0") && err.contains("power"),
        "{err}"
    );
    let scene = TINY_SCENE.replace("emission: [8.0, 8.0, 8.0]", "emission: [1e35, 1e35, 1e35]");
    std::fs::write(dir.path().join("hot_area.yml"), scene).unwrap();
    let err = assert_fails(&run(dir.path(), &["hot_area.yml", "-n", "1"]), 1);
    assert!(err.contains("material `light`"), "{err}");
    assert_eq!(file_names(dir.path()), ["hot.yml", "hot_area.yml"]);
}

/// `max_depth` 0 means the same on the command line and in the scene file.
#[test]
fn max_depth_zero_is_accepted_alike_by_the_cli_and_the_scene_file() {
    let dir = tempfile::tempdir().unwrap();
    tiny_scene(dir.path());
    let zero = TINY_SCENE.replace("max_depth: 6", "max_depth: 0");
    std::fs::write(dir.path().join("zero.yml"), zero).unwrap();
    for a in ["pt", "ppm"] {
        let cli = run(
            dir.path(),
            &[
                "tiny.yml",
                "-a",
                a,
                "-n",
                "2",
                "--max-depth",
                "0",
                "-o",
                "cli",
            ],
        );
        assert_ok(&cli);
        let yaml = run(dir.path(), &["zero.yml", "-a", a, "-n", "2", "-o", "yaml"]);
        assert_ok(&yaml);
        let cli = read_exr(&dir.path().join("cli.exr"));
        let yaml = read_exr(&dir.path().join("yaml.exr"));
        assert_eq!(cli, yaml, "-a {a}");
    }
}

/// A `max_depth` above the supported 1024, even one beyond 32 bits, is used as 1024 with a
/// warning, on the command line and in the scene file alike (as documented), and renders the
/// image of 1024; a negative one is refused with the expected range.
#[test]
fn a_huge_max_depth_is_used_as_the_maximum_alike_by_the_cli_and_the_scene_file() {
    let dir = tempfile::tempdir().unwrap();
    tiny_scene(dir.path());
    let huge = TINY_SCENE.replace("max_depth: 6", "max_depth: 1e10");
    std::fs::write(dir.path().join("huge.yml"), huge).unwrap();
    let base = ["-a", "pt", "-n", "1", "--width", "8", "--height", "8"];
    let render = |args: &[&str]| run(dir.path(), &[args, &base[..]].concat());
    let max = render(&["tiny.yml", "--max-depth", "1024", "-o", "max"]);
    assert_ok(&max);
    for (args, name) in [
        (
            &["tiny.yml", "--max-depth", "99999999999", "-o", "cli"][..],
            "cli",
        ),
        (&["huge.yml", "-o", "yaml"][..], "yaml"),
    ] {
        let out = render(args);
        assert_ok(&out);
        assert!(stderr(&out).contains("using 1024") || stderr(&out).contains("supported 1024"));
        assert_eq!(
            read_exr(&dir.path().join(format!("{name}.exr"))),
            read_exr(&dir.path().join("max.exr")),
            "{name}"
        );
    }
    let err = assert_fails(&render(&["tiny.yml", "--max-depth", "-3"]), 2);
    assert!(err.contains("--max-depth") && err.contains(">= 0"), "{err}");
}

/// A scene file saved with a UTF-8 byte order mark loads.
#[test]
fn a_utf8_byte_order_mark_is_accepted() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("bom.yml"), format!("\u{feff}{TINY_SCENE}")).unwrap();
    assert_ok(&run(dir.path(), &["bom.yml", "-n", "1"]));
    assert!(dir.path().join("bom.exr").exists());
}

/// A path that exists but is no regular file is reported as what it is, not "not found".
#[cfg(unix)]
#[test]
fn special_files_are_reported_as_what_they_are() {
    let dir = tempfile::tempdir().unwrap();
    let err = assert_fails(&run(dir.path(), &["/dev/zero"]), 1);
    assert!(
        err.contains("character device") && !err.contains("not found"),
        "{err}"
    );
    let fifo = dir.path().join("pipe.yml");
    assert!(std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap()
        .success());
    let err = assert_fails(&run(dir.path(), &["pipe.yml"]), 1);
    assert!(err.contains("FIFO") && !err.contains("not found"), "{err}");
    std::os::unix::fs::symlink("loop_b.yml", dir.path().join("loop_a.yml")).unwrap();
    std::os::unix::fs::symlink("loop_a.yml", dir.path().join("loop_b.yml")).unwrap();
    let err = assert_fails(&run(dir.path(), &["loop_a.yml"]), 1);
    assert!(
        err.contains("loop_a.yml") && err.contains("symbolic links") && !err.contains("not found"),
        "{err}"
    );
}

/// A dot in an output name is not always an extension: `-o shot.0001` writes
/// shot.0001.png and shot.0001.exr.
#[test]
fn an_output_name_with_a_numbered_suffix_keeps_it() {
    let dir = tempfile::tempdir().unwrap();
    tiny_scene(dir.path());
    assert_ok(&run(
        dir.path(),
        &["tiny.yml", "-n", "1", "-o", "shot.0001"],
    ));
    assert_eq!(
        file_names(dir.path()),
        ["shot.0001.exr", "shot.0001.png", "tiny.yml"]
    );
}

/// `ppm scene.png` where scene.png is the YAML scene refuses to overwrite its own input.
#[test]
fn a_render_never_overwrites_its_own_scene_file() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("scene.png"), TINY_SCENE).unwrap();
    let err = assert_fails(&run(dir.path(), &["scene.png", "-n", "1"]), 1);
    assert!(
        err.contains("scene.png") && err.contains("overwrite its own input"),
        "{err}"
    );
    assert_eq!(
        std::fs::read_to_string(dir.path().join("scene.png")).unwrap(),
        TINY_SCENE
    );
    assert_eq!(file_names(dir.path()), ["scene.png"]);
    // With another output name it renders.
    assert_ok(&run(dir.path(), &["scene.png", "-n", "1", "-o", "render"]));
}

/// The error log and the extra images never replace an input (the scene, the reference, the
/// file resumed from), an image of the render or a file that is not an error log; an earlier
/// error log may be replaced. Every refused file is left as it was.
#[test]
fn the_error_log_and_extra_images_never_overwrite_inputs() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    tiny_scene(d);
    assert_ok(&run(d, &["tiny.yml", "-n", "1", "-o", "ref"]));
    assert_ok(&run(d, &["tiny.yml", "-n", "1", "-o", "base"]));
    std::fs::copy(d.join("ref.exr"), d.join("r.radius.exr")).unwrap();
    std::fs::write(d.join("mesh.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let before = |name: &str| std::fs::read(d.join(name)).unwrap();
    let kept: Vec<(&str, Vec<u8>)> = [
        "ref.exr",
        "base.exr",
        "tiny.yml",
        "mesh.obj",
        "r.radius.exr",
    ]
    .into_iter()
    .map(|name| (name, before(name)))
    .collect();
    let reference = ["tiny.yml", "-n", "1", "--reference", "ref.exr"];
    for (extra, expected) in [
        (
            &["--error-log", "ref.exr", "-o", "a"][..],
            "is the --reference",
        ),
        (&["--error-log", "tiny.yml", "-o", "a"], "is the scene file"),
        (&["--error-log", "a.png", "-o", "a"], "is the output a.png"),
        (
            &["--resume", "base.exr", "--error-log", "base.exr", "-o", "a"],
            "is the --resume file",
        ),
        (
            &["--error-log", "mesh.obj", "-o", "a"],
            "is not an error log",
        ),
        (
            &["--aov", "radius", "-o", "r"],
            "r.radius.exr is the --reference",
        ),
        (
            &["--aov", "radius", "--error-log", "a.radius.exr", "-o", "a"],
            "is the --aov radius image",
        ),
    ] {
        let args = if extra.contains(&"--aov") {
            [
                &["tiny.yml", "-n", "1", "--reference", "r.radius.exr"][..],
                extra,
            ]
            .concat()
        } else {
            [&reference[..], extra].concat()
        };
        let err = assert_fails(&run(d, &args), 1);
        assert!(err.contains(expected), "{extra:?}: {err}");
    }
    for (name, bytes) in &kept {
        assert_eq!(&before(name), bytes, "{name} was changed");
    }
    // An earlier error log is replaced, as a rerun of the same command does.
    for _ in 0..2 {
        assert_ok(&run(
            d,
            &[&reference[..], &["--error-log", "e.csv", "-o", "e"]].concat(),
        ));
    }
    assert!(std::fs::read_to_string(d.join("e.csv"))
        .unwrap()
        .starts_with("iteration,"));
}

/// Hidden temporary files a killed run left behind are removed by the next run of the same
/// output, but only stale ones of exactly our pattern.
#[test]
fn stale_temporary_files_of_a_killed_run_are_cleaned_up() {
    let dir = tempfile::tempdir().unwrap();
    tiny_scene(dir.path());
    let hour_ago = std::time::SystemTime::now() - Duration::from_secs(3600);
    // No process has a pid above 2^22 (Linux's pid_max limit).
    let stale = [".tiny.png.tmp-999999999-0", ".tiny.exr.tmp-999999999-3"];
    let kept_old = [
        ".other.png.tmp-999999999-0",
        ".tiny.png.tmp-x-0",
        ".tiny.png.old",
    ];
    for name in stale.iter().chain(&kept_old) {
        let file = std::fs::File::create(dir.path().join(name)).unwrap();
        file.set_modified(hour_ago).unwrap();
    }
    // A fresh one may belong to a run writing right now (on another machine sharing the
    // folder): kept.
    std::fs::write(dir.path().join(".tiny.png.tmp-999999999-7"), b"fresh").unwrap();
    let out = run(dir.path(), &["tiny.yml", "-n", "1"]);
    assert_ok(&out);
    assert!(
        stderr(&out).contains(".tiny.png.tmp-999999999-0"),
        "{}",
        stderr(&out)
    );
    let mut expected = vec![
        ".other.png.tmp-999999999-0",
        ".tiny.png.old",
        ".tiny.png.tmp-999999999-7",
        ".tiny.png.tmp-x-0",
        "tiny.exr",
        "tiny.png",
        "tiny.yml",
    ];
    expected.sort();
    assert_eq!(file_names(dir.path()), expected);
}

/// `compare` with a NaN in the reference is an error naming the file, not "relMSE NaN".
#[test]
fn compare_refuses_a_reference_with_nan() {
    let dir = tempfile::tempdir().unwrap();
    write_exr(&dir.path().join("a.exr"), 4, 3, |_, _| [0.5; 3]);
    write_exr(&dir.path().join("b.exr"), 4, 3, |x, y| {
        if (x, y) == (2, 1) {
            [f32::NAN, 1.0, 1.0]
        } else {
            [1.0; 3]
        }
    });
    let err = assert_fails(&run(dir.path(), &["compare", "a.exr", "b.exr"]), 1);
    assert!(
        err.contains("b.exr") && err.contains("NaN") && err.contains("(2, 1)"),
        "{err}"
    );
    let err = assert_fails(&run(dir.path(), &["compare", "b.exr", "a.exr"]), 1);
    assert!(err.contains("b.exr") && err.contains("NaN"), "{err}");
}

/// A render or `converge` against a reference with a NaN pixel is refused before it starts,
/// as `compare` refuses it, instead of logging "relMSE NaN" (or a meaningless number) and
/// exiting 0.
#[test]
fn render_and_converge_refuse_a_reference_with_nan() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    tiny_scene(d);
    write_exr(&d.join("nan.exr"), 16, 12, |x, y| {
        if (x, y) == (5, 7) {
            [1.0, f32::NAN, 1.0]
        } else {
            [0.2; 3]
        }
    });
    for args in [
        &["tiny.yml", "-n", "1", "--reference", "nan.exr"][..],
        &[
            "converge",
            "tiny.yml",
            "--reference",
            "nan.exr",
            "--time-limit",
            "0.1",
        ],
    ] {
        let err = assert_fails(&run(d, args), 1);
        assert!(
            err.contains("nan.exr") && err.contains("NaN") && err.contains("(5, 7)"),
            "{args:?}: {err}"
        );
    }
    assert_eq!(file_names(d), ["nan.exr", "tiny.yml"]);
}

/// Unmounts a test's tmpfs when dropped.
struct Unmount(std::path::PathBuf);

impl Drop for Unmount {
    fn drop(&mut self) {
        let _ = std::process::Command::new("umount")
            .arg("-l")
            .arg(&self.0)
            .status();
    }
}

/// Mounts a 1 MiB tmpfs at `dir`; `None` (the test then skips) where that is not permitted.
fn small_disk(dir: &Path) -> Option<Unmount> {
    std::fs::create_dir_all(dir).unwrap();
    let mounted = std::process::Command::new("mount")
        .args(["-t", "tmpfs", "-o", "size=1m", "tmpfs"])
        .arg(dir)
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    mounted.then(|| Unmount(dir.to_path_buf()))
}

/// Fills the disk holding `dir` with one file, then frees `slack` bytes of it.
fn fill_disk(dir: &Path, slack: u64) -> std::path::PathBuf {
    use std::io::Write;
    let path = dir.join("filler");
    let mut file = std::fs::File::create(&path).unwrap();
    let chunk = [0u8; 4096];
    let mut len = 0u64;
    while file.write_all(&chunk).is_ok() {
        len += chunk.len() as u64;
    }
    file.set_len(len.saturating_sub(slack)).unwrap();
    file.sync_all().unwrap();
    path
}

/// A full disk (a real one: a 1 MiB tmpfs; skipped where mounting is not permitted).
/// A final write with room for the new PNG but not the new EXR replaces neither, and says
/// so; the render is then written to the rescue folder ($TMPDIR here), from which it resumes,
/// or said to be lost when no rescue folder takes it; a failed checkpoint is a warning, the
/// render goes on and its final write succeeds.
#[cfg(target_os = "linux")]
#[test]
fn a_full_disk_never_leaves_a_mismatched_pair_or_stops_the_render() {
    let dir = tempfile::tempdir().unwrap();
    tiny_scene(dir.path());
    let disk = dir.path().join("disk");
    let Some(_unmount) = small_disk(&disk) else {
        eprintln!("skipped: cannot mount a tmpfs here (needs root)");
        return;
    };
    let size = ["--width", "64", "--height", "64"];
    let render = |extra: &[&str]| {
        let mut args = vec!["tiny.yml", "-n", "1"];
        args.extend_from_slice(&size);
        args.extend_from_slice(extra);
        run(dir.path(), &args)
    };
    assert_ok(&render(&["--seed", "1", "-o", "disk/shot"]));
    let old_png = std::fs::read(disk.join("shot.png")).unwrap();
    let old_exr = std::fs::read(disk.join("shot.exr")).unwrap();
    assert!(
        old_exr.len() > old_png.len() + 16384,
        "the EXR must be the larger file for this test"
    );
    // Room for the new PNG (about the old one's size) but not the EXR.
    let filler = fill_disk(&disk, old_png.len() as u64 + 8192);
    let rescue = dir.path().join("rescue");
    std::fs::create_dir(&rescue).unwrap();
    let render_with = |tmpdir: &Path, home: &Path| {
        let mut args = vec!["tiny.yml", "-n", "1", "--seed", "2", "-o", "disk/shot"];
        args.extend_from_slice(&size);
        ppm(dir.path())
            .args(&args)
            .env("TMPDIR", tmpdir)
            .env("HOME", home)
            .env_remove("PPM_RESCUE_DIR")
            .output()
            .unwrap()
    };
    let nowhere = dir.path().join("no such folder");
    let err = assert_fails(&render_with(&nowhere, &nowhere), 1);
    assert!(
        err.contains("neither") && err.contains("the render is lost"),
        "{err}"
    );
    let err = assert_fails(&render_with(&rescue, &nowhere), 1);
    assert!(
        err.contains("neither") && err.contains("shot.exr") && err.contains("shot.png"),
        "{err}"
    );
    assert_eq!(std::fs::read(disk.join("shot.png")).unwrap(), old_png);
    assert_eq!(std::fs::read(disk.join("shot.exr")).unwrap(), old_exr);
    assert_eq!(file_names(&disk), ["filler", "shot.exr", "shot.png"]);
    std::fs::remove_file(&filler).unwrap();
    // The rescued pair is the render that could not be written: it resumes, and the EXR
    // the error names is the one on disk.
    let rescued = file_names(&rescue);
    assert_eq!(rescued.len(), 2, "{rescued:?}");
    assert!(
        rescued[0].starts_with("shot.rescued-") && rescued[0].ends_with(".exr"),
        "{rescued:?}"
    );
    assert!(
        err.contains("the render is safe in") && err.contains(&rescued[0]),
        "{err}"
    );
    let rescued_exr = rescue.join(&rescued[0]);
    let resumed = render(&[
        "--seed",
        "2",
        "--resume",
        rescued_exr.to_str().unwrap(),
        "-o",
        "resumed",
    ]);
    assert_ok(&resumed);
    let mut whole = vec!["tiny.yml", "-n", "2", "--seed", "2", "-o", "whole"];
    whole.extend_from_slice(&size);
    assert_ok(&run(dir.path(), &whole));
    assert_eq!(
        read_exr(&dir.path().join("resumed.exr")),
        read_exr(&dir.path().join("whole.exr")),
        "the rescued render resumes as if written where asked"
    );

    // Checkpoints: fill the disk after the first one, let some fail, free it, stop.
    let mut args = vec!["tiny.yml", "--time-limit", "1000", "--checkpoint", "0.01"];
    args.extend_from_slice(&size);
    args.extend_from_slice(&["-o", "disk/cp"]);
    let (child, lines) = spawn(dir.path(), &args);
    wait_for_file(&disk.join("cp.exr"));
    let filler = fill_disk(&disk, 0);
    let mut err = wait_for_line(&lines, "checkpoint not written");
    let (w, h, _) = read_exr(&disk.join("cp.exr"));
    assert_eq!((w, h), (64, 64), "the last good checkpoint is intact");
    std::fs::remove_file(&filler).unwrap();
    kill(&child, "TERM");
    let (code, rest) = finish(child, lines);
    err.push_str(&rest);
    assert_eq!(
        code,
        Some(130),
        "the render went on after the failed checkpoint: {err}"
    );
    assert!(
        err.contains("last good checkpoint is kept") && err.contains("wrote"),
        "{err}"
    );
    let (w, h, pixels) = read_exr(&disk.join("cp.exr"));
    assert_eq!((w, h), (64, 64));
    assert!(pixels.iter().flatten().all(|v| v.is_finite()));
    assert_eq!(
        file_names(&disk),
        ["cp.exr", "cp.png", "shot.exr", "shot.png"]
    );
}
