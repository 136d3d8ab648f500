//! Files a render must not touch: its own scene, inputs named as outputs, other files; and
//! the leftovers of a killed run, cleaned up.

mod common;

use common::*;
use std::time::Duration;

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
