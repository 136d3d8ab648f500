//! Memory is estimated before it is allocated: a render that cannot fit is refused up front,
//! and the estimate covers the measured peak.

mod common;

use common::*;
use std::path::Path;
use std::process::Output;

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
