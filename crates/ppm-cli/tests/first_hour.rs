//! What a new user meets in a first hour, through the binary: `-q` on a terminal, bare `ppm`,
//! pbrt's `--outfile`, output folders that do not exist yet, printed numbers, where `-v` says
//! the scene was found.

mod common;

use common::*;
use std::fs::File;
use std::io::Read;
use std::path::Path;
use std::process::Stdio;

/// A pseudo-terminal: the master side to read from and the slave side's path.
struct Pty {
    master: File,
    slave: std::path::PathBuf,
}

/// Opens a pseudo-terminal (POSIX `posix_openpt`, `grantpt`, `unlockpt`, `ptsname`).
fn open_pty() -> Pty {
    use std::os::fd::FromRawFd;
    // SAFETY: plain libc calls on a descriptor this function owns; `ptsname` returns a
    // NUL-terminated string valid until the next call, copied at once.
    unsafe {
        let fd = libc::posix_openpt(libc::O_RDWR | libc::O_NOCTTY);
        assert!(fd >= 0, "posix_openpt failed");
        assert_eq!(libc::grantpt(fd), 0);
        assert_eq!(libc::unlockpt(fd), 0);
        let name = libc::ptsname(fd);
        assert!(!name.is_null());
        let slave = std::ffi::CStr::from_ptr(name).to_str().unwrap().into();
        Pty {
            master: File::from_raw_fd(fd),
            slave,
        }
    }
}

/// Runs `ppm args` in `dir` with stderr on a terminal; returns what the terminal showed.
fn stderr_on_terminal(dir: &Path, args: &[&str]) -> String {
    let mut pty = open_pty();
    let slave = File::options()
        .read(true)
        .write(true)
        .open(&pty.slave)
        .unwrap();
    let mut child = ppm(dir)
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::from(slave))
        .spawn()
        .unwrap();
    let status = child.wait().unwrap();
    assert!(status.success(), "ppm {args:?}: {status:?}");
    // The slave is closed (the child exited and ours moved into it): read until EIO.
    let mut shown = Vec::new();
    let mut buffer = [0u8; 4096];
    while let Ok(n) = pty.master.read(&mut buffer) {
        if n == 0 {
            break;
        }
        shown.extend_from_slice(&buffer[..n]);
    }
    String::from_utf8_lossy(&shown).into_owned()
}

/// `-q` draws no progress bar even on a terminal, where the bar is drawn without it.
#[test]
fn quiet_draws_no_progress_bar_on_a_terminal() {
    let dir = tempfile::tempdir().unwrap();
    tiny_scene(dir.path());
    let shown = stderr_on_terminal(dir.path(), &["tiny.yml", "-n", "2", "-o", "a"]);
    assert!(shown.contains("iterations"), "no bar without -q: {shown:?}");
    let shown = stderr_on_terminal(dir.path(), &["tiny.yml", "-n", "2", "-o", "b", "-q"]);
    assert!(!shown.contains('['), "a bar under -q: {shown:?}");
    assert!(shown.trim().is_empty(), "output under -q: {shown:?}");
}

/// Bare `ppm` is a usage error that shows the subcommands, not only `Usage: ppm <SCENE>`.
#[test]
fn bare_ppm_lists_the_subcommands() {
    let dir = tempfile::tempdir().unwrap();
    let out = run(dir.path(), &[]);
    assert_eq!(out.status.code(), Some(2));
    let shown = format!("{}{}", stdout(&out), stderr(&out));
    for command in ["render", "compare", "converge", "info", "merge"] {
        assert!(shown.contains(command), "{command} missing: {shown}");
    }
}

/// pbrt's `--outfile` is `-o`; `-o` (render and merge) creates a missing folder, as
/// `converge --out` does.
#[test]
fn outfile_is_o_and_missing_folders_are_created() {
    let dir = tempfile::tempdir().unwrap();
    tiny_scene(dir.path());
    assert_ok(&run(
        dir.path(),
        &["tiny.yml", "-n", "1", "-q", "--outfile", "pbrt.exr"],
    ));
    assert!(dir.path().join("pbrt.exr").is_file() && dir.path().join("pbrt.png").is_file());
    assert_ok(&run(
        dir.path(),
        &["tiny.yml", "-n", "1", "-q", "-o", "refs/deep/x.exr"],
    ));
    assert!(dir.path().join("refs/deep/x.exr").is_file());
    assert_ok(&run(
        dir.path(),
        &["merge", "refs/deep/x.exr", "--outfile", "merged/all.exr"],
    ));
    assert!(dir.path().join("merged/all.png").is_file());
    // A file where the folder would be is still an error naming it.
    let err = assert_fails(&run(dir.path(), &["tiny.yml", "-o", "tiny.yml/out.png"]), 1);
    assert!(err.contains("tiny.yml"), "{err}");
}

/// `-v` prints the scene's path without `..` and the rule of the scene search that found it.
#[test]
fn verbose_says_where_and_how_the_scene_was_found() {
    let dir = tempfile::tempdir().unwrap();
    let mine = tempfile::tempdir().unwrap();
    tiny_scene(mine.path());
    let out = ppm(dir.path())
        .args(["tiny.yml", "-n", "1", "-v", "-o", "a"])
        .env("PPM_SCENES", mine.path())
        .output()
        .unwrap();
    assert_ok(&out);
    let log = stderr(&out);
    let expected = format!(
        "scene {} (found in $PPM_SCENES)",
        mine.path().join("tiny.yml").display()
    );
    assert!(log.contains(&expected), "{log}");
    // The source tree's scenes, reached from the crate's folder through `../..`.
    let out = ppm(dir.path())
        .args(["cornell_box.yml", "-a", "pt", "-n", "1", "--width", "8"])
        .args(["-v", "-o", "b"])
        .env_remove("PPM_SCENES")
        .output()
        .unwrap();
    assert_ok(&out);
    let log = stderr(&out);
    let line = log.lines().find(|l| l.starts_with("scene ")).unwrap();
    assert!(
        !line.contains("..") && line.ends_with("scenes/cornell_box.yml (found in the scenes/ of the source tree ppm was built from)"),
        "{line}"
    );
}

/// The repository's Markdown files a user copies commands from: README.md and docs/*.md.
fn markdown_files() -> Vec<std::path::PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut files = vec![root.join("README.md")];
    let mut docs: Vec<_> = std::fs::read_dir(root.join("docs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    docs.sort();
    files.extend(docs);
    files
}

/// The `ppm ...` lines of the ```sh blocks of `text` (continuation lines joined, comments
/// cut), split into words as the shell would (no quotes or variables in these commands).
fn printed_ppm_commands(text: &str) -> Vec<Vec<String>> {
    let mut commands = Vec::new();
    let mut in_sh = false;
    let mut pending = String::new();
    for line in text.lines() {
        if line.starts_with("```") {
            in_sh = !in_sh && line.trim_start_matches('`').trim() == "sh";
            continue;
        }
        if !in_sh {
            continue;
        }
        pending.push_str(line.trim_end_matches('\\'));
        pending.push(' ');
        if line.ends_with('\\') {
            continue;
        }
        let command = pending.split(" #").next().unwrap_or("").trim().to_string();
        pending.clear();
        if let Some(args) = command.strip_prefix("ppm ") {
            commands.push(args.split_whitespace().map(String::from).collect());
        }
    }
    commands
}

/// Every `ppm` command of a ```sh block in the README and docs/ runs as printed from any
/// folder: its command line parses (not exit status 2) and its scene is found (not "not
/// found"). It runs under `PPM_MEMORY_LIMIT=1`, so a render is refused by the memory check
/// after the scene is loaded, before any work; commands whose inputs an earlier command of
/// the block would have written fail on those, with status 1. Inline commands carry no shell
/// pipe: `-a pt|ppm` pasted into a shell pipes into a program `ppm`.
#[test]
fn printed_commands_run_as_printed() {
    let dir = tempfile::tempdir().unwrap();
    let mut checked = 0;
    for file in markdown_files() {
        let text = std::fs::read_to_string(&file).unwrap();
        for args in printed_ppm_commands(&text) {
            let out = ppm(dir.path())
                .args(&args)
                .env("PPM_MEMORY_LIMIT", "1")
                .env_remove("PPM_SCENES")
                .output()
                .unwrap();
            let err = stderr(&out);
            assert_ne!(
                out.status.code(),
                Some(2),
                "{}: ppm {args:?}: {err}",
                file.display()
            );
            assert!(
                !err.contains("not found") && !err.contains("panicked"),
                "{}: ppm {args:?}: {err}",
                file.display()
            );
            checked += 1;
        }
        for span in text.split('`').skip(1).step_by(2) {
            if span.starts_with("ppm ") && span.contains('|') && !span.contains("| head") {
                panic!("{}: `{span}` is a shell pipe when pasted", file.display());
            }
        }
    }
    assert!(checked >= 8, "only {checked} printed commands found");
}

/// `ppm --resume FILE -n N` takes the scene and every setting from FILE: the result equals
/// one render of all the iterations bit for bit, and the summary gives the totals. A flag
/// that disagrees with the file is still refused.
#[test]
fn resume_takes_the_settings_from_the_file() {
    let dir = tempfile::tempdir().unwrap();
    tiny_scene(dir.path());
    let settings = [
        "-a",
        "sppm",
        "--seed",
        "5",
        "--radius",
        "0.2",
        "--alpha",
        "0.5",
        "--max-depth",
        "4",
        "--photons",
        "500",
        "--width",
        "20",
        "-q",
    ];
    let render = |n: &str, out: &str| {
        let mut args = vec!["tiny.yml", "-n", n, "-o", out];
        args.extend(settings);
        assert_ok(&run(dir.path(), &args));
    };
    render("3", "part");
    render("5", "whole");
    let out = run(
        dir.path(),
        &["--resume", "part.exr", "-n", "2", "-o", "resumed"],
    );
    assert_ok(&out);
    let log = stderr(&out);
    assert!(log.contains("2 iterations in"), "{log}");
    assert!(log.contains("the render now holds 5 iterations"), "{log}");
    let resumed = read_exr(&dir.path().join("resumed.exr"));
    let whole = read_exr(&dir.path().join("whole.exr"));
    assert_eq!(resumed, whole, "resumed with the file's settings");
    let err = assert_fails(
        &run(
            dir.path(),
            &["--resume", "part.exr", "-n", "2", "-o", "x", "--seed", "6"],
        ),
        1,
    );
    assert!(err.contains("ppm.seed"), "{err}");
}

/// `--threads` far beyond the machine's cores is capped at 16 per core (at least 64) with a
/// warning, and renders the same image as one thread: 4096 threads on 2 cores once made a
/// 32 x 32 iteration take a minute.
#[test]
fn a_huge_thread_count_is_capped_with_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    tiny_scene(dir.path());
    let many = run(
        dir.path(),
        &["tiny.yml", "-t", "4096", "-n", "2", "-o", "many.exr"],
    );
    assert_ok(&many);
    let err = stderr(&many);
    assert!(
        err.contains("warning: --threads 4096 is more than this machine can use; using"),
        "{err}"
    );
    let one = run(
        dir.path(),
        &["tiny.yml", "-t", "1", "-n", "2", "-o", "one.exr"],
    );
    assert_ok(&one);
    assert!(!stderr(&one).contains("--threads"), "{}", stderr(&one));
    assert_eq!(
        read_exr(&dir.path().join("many.exr")).2,
        read_exr(&dir.path().join("one.exr")).2
    );
}

/// [`TINY_SCENE`] with its lamp's emission set to `emission` (all three channels).
fn tiny_scene_emitting(dir: &Path, name: &str, emission: &str) {
    let text = TINY_SCENE.replace(
        "emission: [8.0, 8.0, 8.0]",
        &format!("emission: [{emission}, {emission}, {emission}]"),
    );
    assert_ne!(text, TINY_SCENE);
    std::fs::write(dir.join(name), text).unwrap();
}

/// The accepted emission and the film's exact range agree: a lamp at the top of the range
/// (2^40) renders with no sample dropped by any algorithm, and its image is the emission-1
/// image times 2^40 (a power of two: every f32 product scales exactly); just above, the
/// scene is refused naming the field and the limit.
#[test]
fn emission_at_the_top_of_the_accepted_range_loses_no_sample() {
    let dir = tempfile::tempdir().unwrap();
    let top = (1u64 << 40) as f32;
    tiny_scene_emitting(dir.path(), "one.yml", "1.0");
    tiny_scene_emitting(dir.path(), "top.yml", "1099511627776");
    for algorithm in ["pt", "ppm", "sppm", "vcm"] {
        let render = |scene: &str| {
            let out = format!("{scene}-{algorithm}.exr");
            let output = run(
                dir.path(),
                &[scene, "-a", algorithm, "-n", "2", "--seed", "3", "-o", &out],
            );
            assert_ok(&output);
            let err = stderr(&output);
            assert!(
                err.contains(" 0 rejected samples"),
                "{algorithm} {scene}: {err}"
            );
            read_exr(&dir.path().join(out)).2
        };
        let (one, hot) = (render("one.yml"), render("top.yml"));
        assert!(one.iter().any(|p| p[0] > 0.0), "{algorithm}: black");
        for (a, b) in one.iter().flatten().zip(hot.iter().flatten()) {
            let expected = a * top;
            assert!(
                (b - expected).abs() <= 1e-5 * expected + 1e-30,
                "{algorithm}: {b:e} against {expected:e}"
            );
        }
    }
    tiny_scene_emitting(dir.path(), "above.yml", "1.2e12");
    let err = assert_fails(&run(dir.path(), &["above.yml", "-n", "1"]), 1);
    assert!(
        err.contains("material `light`")
            && err.contains("`emission` 1.200e12")
            && err.contains("2^40")
            && err.contains("2^56"),
        "{err}"
    );
}

/// A merge radius below what single precision resolves at the scene's scale is refused up
/// front naming `--radius` (or the scene's `render.radius`) by every algorithm that reads
/// one; the smallest accepted radius renders.
#[test]
fn a_merge_radius_too_small_for_the_scene_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    tiny_scene(dir.path());
    for algorithm in ["ppm", "sppm", "vcm"] {
        // 1e-25: pi r^2 underflows f32; 1e-9: finer than f32 resolves a 3.5-unit scene.
        for radius in ["1e-25", "1e-9"] {
            let output = run(
                dir.path(),
                &["tiny.yml", "-a", algorithm, "--radius", radius, "-n", "1"],
            );
            let err = assert_fails(&output, 2);
            assert!(
                err.contains(&format!("--radius {radius} is too small for tiny.yml"))
                    && err.contains("the smallest merge radius is 2.06")
                    && err.contains("2^-24 of the scene's extent 3.46"),
                "{algorithm} {radius}: {err}"
            );
        }
        let output = run(
            dir.path(),
            &["tiny.yml", "-a", algorithm, "--radius", "2.1e-7", "-n", "1"],
        );
        assert_ok(&output);
    }
    // Set in the scene file: an error naming render.radius; --radius overrides it.
    let text = TINY_SCENE.replace("radius: 0.1", "radius: 1e-25");
    std::fs::write(dir.path().join("small.yml"), text).unwrap();
    let err = assert_fails(&run(dir.path(), &["small.yml", "-a", "ppm", "-n", "1"]), 1);
    assert!(
        err.contains("small.yml: render.radius 1e-25 is too small") && err.contains("--radius"),
        "{err}"
    );
    assert_ok(&run(
        dir.path(),
        &["small.yml", "-a", "ppm", "--radius", "0.1", "-n", "1"],
    ));
}

/// A black image from a merge radius that is accepted but far too small for the photons
/// (direct light from photons, the lamp out of view) is blamed on the radius, with the
/// radius at which a disc would expect one photon, not on the lights.
#[test]
fn a_black_image_from_a_tiny_radius_names_the_radius() {
    let dir = tempfile::tempdir().unwrap();
    // The floor and ceiling of the tiny box seen from above: the lamp is out of view.
    let scene = TINY_SCENE
        .replace(
            "position: [0.0, 1.0, 3.9], look_at: [0.0, 1.0, 0.0]",
            "position: [0.0, 1.5, 0.5], look_at: [0.0, 0.0, 0.0]",
        )
        .replace("fov: 38.0", "fov: 30.0");
    std::fs::write(dir.path().join("floor.yml"), scene).unwrap();
    for algorithm in ["ppm", "sppm"] {
        let args = [
            "floor.yml",
            "-a",
            algorithm,
            "--direct",
            "photons",
            "-n",
            "2",
        ];
        let tiny = run(dir.path(), &[&args[..], &["--radius", "1e-6"]].concat());
        assert_ok(&tiny);
        let err = stderr(&tiny);
        assert!(
            err.contains("the image is black")
                && err.contains("the merge radius 1e-6 (--radius) is too small for the scene")
                && err.contains("a disc expects one photon at a radius of")
                && !err.contains("reached a light")
                && !err.contains("emits away"),
            "{algorithm}: {err}"
        );
        // The same render at the scene's radius is lit, and not diagnosed.
        let lit = run(dir.path(), &args);
        assert_ok(&lit);
        assert!(!stderr(&lit).contains("black"), "{}", stderr(&lit));
    }
}
