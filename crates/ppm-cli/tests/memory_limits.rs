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

/// `ppm args...` in `dir` under the shell's `ulimit -v kib` (the process's virtual-size
/// limit, RLIMIT_AS, in KiB), with the extra environment `env`.
fn run_under_ulimit(dir: &Path, kib: u64, args: &[&str], env: &[(&str, &str)]) -> Output {
    std::process::Command::new("sh")
        .arg("-c")
        .arg(format!("ulimit -v {kib} && exec \"$0\" \"$@\""))
        .arg(env!("CARGO_BIN_EXE_ppm"))
        .args(args)
        .env_remove("PPM_MEMORY_LIMIT")
        .envs(env.iter().copied())
        .current_dir(dir)
        .output()
        .unwrap()
}

/// The process's own limits are part of the memory check, and an allocation that fails
/// anyway is an error, never an abort: under `ulimit -v` a render that needs more is refused
/// up front with the limit named, one that fits renders, and with the check overridden the
/// failed allocation ends with status 1 naming the bytes, not SIGABRT. (Linux: the limit is
/// compared with /proc/self/status.)
#[test]
fn a_virtual_memory_limit_is_respected_and_never_aborts() {
    use std::os::unix::process::ExitStatusExt;
    if !Path::new("/proc/self/status").exists() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    tiny_scene(dir.path());
    let small = ["tiny.yml", "-n", "1", "-t", "2"];
    // The baseline: the smallest of these limits a small render runs under (the binary's
    // mappings, thread stacks and the check's reserve for them), doubled.
    let baseline = [256u64, 512, 1024, 2048, 4096, 8192]
        .into_iter()
        .map(|mib| mib << 10)
        .find(|&kib| {
            run_under_ulimit(dir.path(), kib, &small, &[])
                .status
                .success()
        })
        .expect("a small render runs under an 8 GiB virtual-size limit");
    let limit = 2 * baseline;
    assert_ok(&run_under_ulimit(dir.path(), limit, &small, &[]));
    // 10^8 light paths per iteration need tens of GiB of photon storage.
    let big = ["tiny.yml", "-n", "1", "-t", "2", "--photons", "100000000"];
    let refused = run_under_ulimit(dir.path(), limit, &big, &[]);
    assert_eq!(refused.status.signal(), None, "{}", stderr(&refused));
    let err = assert_fails(&refused, 1);
    assert!(
        err.contains("not enough memory") && err.contains("--photons"),
        "{err}"
    );
    let available = std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|m| {
            let line = m
                .lines()
                .find(|l| l.starts_with("MemAvailable:"))?
                .to_owned();
            line.split_whitespace().nth(1)?.parse::<u64>().ok()
        })
        .unwrap_or(u64::MAX);
    if available > limit {
        assert!(err.contains("RLIMIT_AS (ulimit -v)"), "{err}");
    }
    // The check overridden: the allocation itself fails, and is an error with status 1.
    let failed = run_under_ulimit(dir.path(), limit, &big, &[("PPM_MEMORY_LIMIT", "1T")]);
    assert_eq!(failed.status.signal(), None, "{}", stderr(&failed));
    let err = assert_fails(&failed, 1);
    assert!(
        err.contains("error: out of memory: allocating")
            && err.contains("while allocating the render state (the film, the photon buffer")
            && err.contains("ulimit -v (RLIMIT_AS) is")
            && err.contains("lower --photons"),
        "{err}"
    );
}
