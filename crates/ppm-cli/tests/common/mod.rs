//! Helpers for the command-line tests: running the binary, small scenes and images.

#![allow(dead_code)] // each test file uses a different subset

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub mod process;

/// The `ppm` binary, run in `dir`, with the stop signals at their default disposition, as
/// from an interactive shell. A test run under `nohup` (SIGHUP ignored) or as a background
/// job (SIGINT ignored) would otherwise hand those dispositions on to the child, which keeps
/// an inherited ignored signal ignored (as it should), and a test that sends it would wait
/// for a stop that never comes.
pub fn ppm(dir: &Path) -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_ppm"));
    command.current_dir(dir);
    #[cfg(unix)]
    default_stop_signals(&mut command);
    command
}

/// Resets the stop signals (those of ppm's `signal.rs`) to SIG_DFL in the child.
#[cfg(unix)]
fn default_stop_signals(command: &mut Command) {
    use std::os::unix::process::CommandExt;
    const STOP_SIGNALS: [libc::c_int; 6] = [
        libc::SIGINT,
        libc::SIGTERM,
        libc::SIGHUP,
        libc::SIGUSR1,
        libc::SIGUSR2,
        libc::SIGXCPU,
    ];
    // SAFETY: between fork and exec the closure only calls signal(2), which is
    // async-signal-safe, and allocates nothing.
    unsafe {
        command.pre_exec(|| {
            for signal in STOP_SIGNALS {
                libc::signal(signal, libc::SIG_DFL);
            }
            Ok(())
        });
    }
}

/// Runs `ppm args...` in `dir` and returns its output.
pub fn run(dir: &Path, args: &[&str]) -> Output {
    ppm(dir).args(args).output().expect("the ppm binary runs")
}

/// Stderr as text.
pub fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// Stdout as text.
pub fn stdout(output: &Output) -> String {
    String::from_utf8_lossy(&output.stdout).into_owned()
}

/// Asserts the process failed with `code` and did not panic.
pub fn assert_fails(output: &Output, code: i32) -> String {
    let err = stderr(output);
    assert_eq!(output.status.code(), Some(code), "stderr: {err}");
    assert!(
        !err.contains("panicked"),
        "a panic instead of an error: {err}"
    );
    err
}

/// Asserts the process succeeded.
pub fn assert_ok(output: &Output) {
    assert!(
        output.status.success(),
        "status {:?}\nstderr: {}",
        output.status,
        stderr(output)
    );
}

/// A small closed white box lit by a ceiling quad light (scene format v1), 16x12 pixels and
/// cheap settings, so a render iteration takes milliseconds.
pub const TINY_SCENE: &str = r#"
camera: { position: [0.0, 1.0, 3.9], look_at: [0.0, 1.0, 0.0], up: [0.0, 1.0, 0.0], fov: 38.0 }
resolution: [16, 12]
materials:
  white: { type: diffuse, color: [0.7, 0.7, 0.7] }
  red:   { type: diffuse, color: [0.6, 0.1, 0.1] }
  light: { type: diffuse, color: [0.0, 0.0, 0.0], emission: [8.0, 8.0, 8.0] }
objects:
  - { type: quad, corner: [-1, 0, -1], edge_u: [0, 0, 2], edge_v: [2, 0, 0], material: white }
  - { type: quad, corner: [-1, 2, -1], edge_u: [2, 0, 0], edge_v: [0, 0, 2], material: white }
  - { type: quad, corner: [-1, 0, -1], edge_u: [2, 0, 0], edge_v: [0, 2, 0], material: white }
  - { type: quad, corner: [-1, 0, -1], edge_u: [0, 2, 0], edge_v: [0, 0, 2], material: red }
  - { type: quad, corner: [1, 0, -1], edge_u: [0, 0, 2], edge_v: [0, 2, 0], material: white }
  - { type: quad, corner: [-0.3, 1.98, -0.3], edge_u: [0.6, 0, 0], edge_v: [0, 0, 0.6], material: light }
render:
  max_depth: 6
  photons: 2000
  radius: 0.1
  alpha: 0.7
"#;

/// Writes [`TINY_SCENE`] as `dir/tiny.yml`.
pub fn tiny_scene(dir: &Path) -> PathBuf {
    let path = dir.join("tiny.yml");
    std::fs::write(&path, TINY_SCENE).unwrap();
    path
}

/// Writes a linear RGB EXR whose pixel (x, y) is `f(x, y)`.
pub fn write_exr(
    path: &Path,
    width: usize,
    height: usize,
    f: impl Fn(usize, usize) -> [f32; 3] + Sync,
) {
    exr::prelude::write_rgb_file(path, width, height, |x, y| {
        let [r, g, b] = f(x, y);
        (r, g, b)
    })
    .unwrap();
}

/// Reads an EXR as rows of RGB.
pub fn read_exr(path: &Path) -> (usize, usize, Vec<[f32; 3]>) {
    let image = exr::prelude::read_first_rgba_layer_from_file(
        path,
        |size, _| {
            (
                size.width(),
                size.height(),
                vec![[0.0f32; 3]; size.width() * size.height()],
            )
        },
        |(w, _, pixels): &mut (usize, usize, Vec<[f32; 3]>),
         pos,
         (r, g, b, _a): (f32, f32, f32, f32)| {
            pixels[pos.y() * *w + pos.x()] = [r, g, b];
        },
    )
    .unwrap();
    image.layer_data.channel_data.pixels
}

/// File names in a folder, sorted.
pub fn file_names(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}
