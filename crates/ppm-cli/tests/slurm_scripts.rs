//! The Slurm scripts' argument handling, without a cluster: `render_shard.sbatch` and
//! `merge.sbatch` run under bash with the array variables Slurm would set and a stand-in `ppm`
//! that writes the words it was given, one per line; `submit.sh` runs with a stand-in `sbatch`
//! that runs the shard script at once. (`scripts/slurm/test_local.sh` runs them on a real
//! Slurm.)

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn slurm_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scripts/slurm")
}

/// A temporary folder holding a stand-in `ppm` that writes its arguments to `args.txt`.
fn sandbox(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("ppm-slurm-args-{name}-{}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).unwrap();
    let stub = dir.join("ppm");
    fs::write(
        &stub,
        format!(
            "#!/bin/bash\nprintf '%s\\n' \"$@\" > '{}'\n",
            dir.join("args.txt").display()
        ),
    )
    .unwrap();
    make_executable(&stub);
    dir
}

fn make_executable(path: &Path) {
    use std::os::unix::fs::PermissionsExt;
    fs::set_permissions(path, fs::Permissions::from_mode(0o755)).unwrap();
}

/// Runs `render_shard.sbatch` as array task 1 of 4 with `PPM_ARGS` set to `ppm_args`.
fn shard(dir: &Path, ppm_args: &str) -> Output {
    Command::new("bash")
        .arg(slurm_dir().join("render_shard.sbatch"))
        .current_dir(dir)
        .env("PPM", dir.join("ppm"))
        .env("SCENE", "scene.yml")
        .env("ITERATIONS", "12")
        .env("OUT_DIR", dir)
        .env("PPM_ARGS", ppm_args)
        .env("SLURM_ARRAY_TASK_ID", "1")
        .env("SLURM_ARRAY_TASK_COUNT", "4")
        .env("SLURM_CPUS_PER_TASK", "3")
        .output()
        .unwrap()
}

fn words(dir: &Path) -> Vec<String> {
    fs::read_to_string(dir.join("args.txt"))
        .unwrap()
        .lines()
        .map(str::to_owned)
        .collect()
}

/// The words that follow `flag`'s every occurrence.
fn values_of<'a>(words: &'a [String], flag: &str) -> Vec<&'a str> {
    words
        .windows(2)
        .filter(|w| w[0] == flag)
        .map(|w| w[1].as_str())
        .collect()
}

#[test]
fn a_short_or_long_thread_count_in_ppm_args_replaces_the_scripts_own() {
    let dir = sandbox("threads");
    for (ppm_args, threads) in [
        ("", None),
        ("-t 2", Some("-t")),
        ("-t2", Some("-t2")),
        ("--threads 2", Some("--threads")),
        ("--threads=2", Some("--threads=2")),
    ] {
        let out = shard(&dir, ppm_args);
        assert!(out.status.success(), "{ppm_args:?}: {out:?}");
        let w = words(&dir);
        let script_threads = values_of(&w, "--threads");
        match threads {
            None => assert_eq!(script_threads, ["3"], "{w:?}"),
            Some(flag) => {
                // The script adds no --threads of its own; the user's is passed on once.
                assert_eq!(w.iter().filter(|x| x.starts_with(flag)).count(), 1, "{w:?}");
                assert!(!w.contains(&"3".to_owned()), "{ppm_args:?}: {w:?}");
            }
        }
        assert_eq!(values_of(&w, "--shard"), ["1/4"]);
        assert_eq!(values_of(&w, "--checkpoint"), ["300"]);
    }
}

#[test]
fn ppm_args_keep_quoted_spaces_and_glob_characters_as_written() {
    let dir = sandbox("quoting");
    // A file in the folder that an unquoted `*` would expand to.
    fs::write(dir.join("decoy.txt"), "").unwrap();
    let out = shard(
        &dir,
        r#"--error-log "a b/errors.csv" --label '*' --x it\'s"#,
    );
    assert!(out.status.success(), "{out:?}");
    let w = words(&dir);
    assert_eq!(values_of(&w, "--error-log"), ["a b/errors.csv"]);
    assert_eq!(values_of(&w, "--label"), ["*"]);
    assert_eq!(values_of(&w, "--x"), ["it's"]);

    let out = shard(&dir, "--seed 'unclosed");
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("unmatched quote"));
}

#[test]
fn flags_the_shard_script_sets_are_refused_in_ppm_args() {
    let dir = sandbox("owned");
    for flag in [
        "-n 4",
        "-n4",
        "--spp 2",
        "--shard 0/2",
        "-o x",
        "--output=x",
        "--resume x",
    ] {
        let out = shard(&dir, flag);
        assert_eq!(out.status.code(), Some(2), "{flag}");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(stderr.contains("may not contain"), "{flag}: {stderr}");
    }
}

#[test]
fn submit_passes_each_flag_to_the_shards_as_one_word() {
    let dir = sandbox("submit");
    // A stand-in sbatch: the shard script runs at once as task 0 of 1; the merge job is skipped.
    let sbatch = dir.join("sbatch");
    fs::write(
        &sbatch,
        "#!/bin/bash\nscript=${!#}\ncase $script in *render_shard.sbatch)\n  \
         SLURM_ARRAY_TASK_ID=0 SLURM_ARRAY_TASK_COUNT=1 bash \"$script\" || exit 1;;\nesac\necho 42\n",
    )
    .unwrap();
    make_executable(&sbatch);
    fs::write(dir.join("scene.yml"), "").unwrap();
    let path = format!(
        "{}:{}",
        dir.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let out = Command::new("bash")
        .arg(slurm_dir().join("submit.sh"))
        .args([
            "scene.yml",
            "8",
            "1",
            "out",
            "--error-log",
            "a b/it's *.csv",
            "-t",
            "2",
        ])
        .current_dir(&dir)
        .env("PATH", path)
        .env("PPM", dir.join("ppm"))
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    let w = words(&dir);
    assert_eq!(values_of(&w, "--error-log"), ["a b/it's *.csv"], "{w:?}");
    assert_eq!(values_of(&w, "-t"), ["2"]);
    assert!(values_of(&w, "--threads").is_empty(), "{w:?}");
}

#[test]
fn the_merge_job_takes_the_parts_and_not_their_aov_images() {
    let dir = sandbox("merge");
    for name in [
        "part_0.exr",
        "part_1.exr",
        "part_10.exr",
        "part_0.radius.exr",
        "part_1.photons.exr",
    ] {
        fs::write(dir.join(name), "").unwrap();
    }
    let out = Command::new("bash")
        .arg(slurm_dir().join("merge.sbatch"))
        .env("PPM", dir.join("ppm"))
        .env("OUT_DIR", &dir)
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    let w = words(&dir);
    let parts: Vec<&str> = w
        .iter()
        .filter(|x| x.ends_with(".exr"))
        .map(|x| x.rsplit('/').next().unwrap())
        .collect();
    assert_eq!(parts, ["part_0.exr", "part_1.exr", "part_10.exr"], "{w:?}");
}
