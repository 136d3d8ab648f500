//! Command-line behavior that needs no rendering: usage errors, path checks and `ppm compare`.
//! Each test runs the real binary; none may panic.

mod common;

use common::*;
use std::path::Path;

#[test]
fn help_lists_subcommands_and_exit_codes() {
    let dir = tempfile::tempdir().unwrap();
    let out = run(dir.path(), &["--help"]);
    assert_ok(&out);
    let help = stdout(&out);
    for word in [
        "compare",
        "converge",
        "render",
        "--time-limit",
        "--error-log",
        "130",
    ] {
        assert!(help.contains(word), "help lacks {word}: {help}");
    }
}

#[test]
fn unknown_scene_names_the_paths_tried() {
    let dir = tempfile::tempdir().unwrap();
    let err = assert_fails(&run(dir.path(), &["missing_scene.yml", "-n", "1"]), 1);
    assert!(
        err.contains("missing_scene.yml") && err.contains("scenes/missing_scene.yml"),
        "{err}"
    );
    let err = assert_fails(&run(dir.path(), &["render", "missing_scene.yml"]), 1);
    assert!(err.contains("scenes/missing_scene.yml"), "{err}");
}

#[test]
fn bad_flag_values_are_usage_errors() {
    let dir = tempfile::tempdir().unwrap();
    tiny_scene(dir.path());
    for (args, flag) in [
        (&["tiny.yml", "-n", "0"][..], "--iterations"),
        (&["tiny.yml", "-n", "ten"], "--iterations"),
        (&["tiny.yml", "--radius", "-1"], "--radius"),
        (&["tiny.yml", "--alpha", "1.5"], "--alpha"),
        (&["tiny.yml", "--threads", "0"], "--threads"),
        (&["tiny.yml", "--width", "0"], "--width"),
        // Negative numbers are values out of range, not unknown options `-1`.
        (&["tiny.yml", "--seed", "-1"], "--seed"),
        (&["tiny.yml", "--max-depth", "-1"], "--max-depth"),
        (&["tiny.yml", "-n", "4", "--shard", "-1/4"], "--shard"),
        (&["tiny.yml", "--time-limit", "soon"], "--time-limit"),
        (&["tiny.yml", "-a", "mlt"], "--algorithm"),
        (&["tiny.yml", "--direct", "maybe"], "--direct"),
        (&["tiny.yml", "--error-log", "e.csv"], "--reference"),
        (&["tiny.yml", "--no-such-flag"], "--no-such-flag"),
        (&["compare", "only_one.exr"], "<B>"),
        (
            &["converge", "tiny.yml", "--time-limit", "1"],
            "--reference",
        ),
        (
            &[
                "converge",
                "tiny.yml",
                "--reference",
                "r.exr",
                "--time-limit",
                "1",
                "--seeds",
                "0",
            ],
            "--seeds",
        ),
    ] {
        let err = assert_fails(&run(dir.path(), args), 2);
        assert!(
            err.contains(flag),
            "{args:?}: the message should name {flag}: {err}"
        );
    }
    assert!(
        file_names(dir.path()) == ["tiny.yml"],
        "nothing may be written"
    );
}

#[test]
fn unwritable_output_fails_before_rendering() {
    let dir = tempfile::tempdir().unwrap();
    tiny_scene(dir.path());
    let err = assert_fails(&run(dir.path(), &["tiny.yml", "-o", "tiny.yml/out.png"]), 1);
    assert!(err.contains("tiny.yml"), "{err}");
    let err = assert_fails(&run(dir.path(), &["tiny.yml", "-o", "out.jpg"]), 1);
    assert!(err.contains("out.jpg"), "{err}");
    let args = [
        "tiny.yml",
        "--reference",
        "r.exr",
        "--error-log",
        "no_such_folder/e.csv",
    ];
    let err = assert_fails(&run(dir.path(), &args), 1);
    assert!(err.contains("no_such_folder"), "{err}");
    assert_eq!(file_names(dir.path()), ["tiny.yml"]);
}

#[test]
fn missing_reference_is_named() {
    let dir = tempfile::tempdir().unwrap();
    tiny_scene(dir.path());
    let err = assert_fails(
        &run(dir.path(), &["tiny.yml", "--reference", "absent_ref.exr"]),
        1,
    );
    assert!(
        err.contains("absent_ref.exr") && err.contains("--reference"),
        "{err}"
    );
}

#[test]
fn compare_prints_the_metrics() {
    let dir = tempfile::tempdir().unwrap();
    // A is 0.5 everywhere, B is 1: every term is (0.5)^2 / (1 + 0.01), RMSE 0.5.
    write_exr(&dir.path().join("a.exr"), 4, 3, |_, _| [0.5; 3]);
    write_exr(&dir.path().join("b.exr"), 4, 3, |_, _| [1.0; 3]);
    let out = run(dir.path(), &["compare", "a.exr", "b.exr"]);
    assert_ok(&out);
    let text = stdout(&out);
    let expected = format!("{:.6e}", 0.25 / 1.01);
    assert!(
        text.contains(&format!("relMSE (B is the reference): {expected}")),
        "{text}"
    );
    assert!(
        text.contains("RMSE:                        5.000000e-1"),
        "{text}"
    );
    assert!(text.contains(&format!("trimmed:  {expected}")), "{text}");
    assert!(
        text.contains("a.exr: 4x3, mean RGB (0.500000, 0.500000, 0.500000)"),
        "{text}"
    );
    assert!(
        text.contains("b.exr: 4x3, mean RGB (1.000000, 1.000000, 1.000000)"),
        "{text}"
    );
}

/// `ppm compare A B | head -1`: the reader closes the pipe early; ppm exits 0 without a panic.
#[test]
fn compare_into_a_closed_pipe_does_not_panic() {
    let dir = tempfile::tempdir().unwrap();
    write_exr(&dir.path().join("a.exr"), 4, 3, |_, _| [0.5; 3]);
    write_exr(&dir.path().join("b.exr"), 4, 3, |_, _| [1.0; 3]);
    let mut child = ppm(dir.path())
        .args(["compare", "a.exr", "b.exr"])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // Closed before ppm has read its two images, so its first write finds no reader.
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    assert_ok(&out);
}

#[test]
fn compare_reads_png_as_srgb() {
    let dir = tempfile::tempdir().unwrap();
    // sRGB code 188 is linear 0.5029: compare against an EXR of exactly that.
    let code = 188u8;
    let c = code as f64 / 255.0;
    let linear = ((c + 0.055) / 1.055).powf(2.4) as f32;
    image::save_buffer(
        dir.path().join("a.png"),
        &[code; 2 * 2 * 3],
        2,
        2,
        image::ExtendedColorType::Rgb8,
    )
    .unwrap();
    write_exr(&dir.path().join("b.exr"), 2, 2, |_, _| [linear; 3]);
    let out = run(dir.path(), &["compare", "a.png", "b.exr"]);
    assert_ok(&out);
    let text = stdout(&out);
    let rel: f64 = text
        .lines()
        .find_map(|l| l.strip_prefix("relMSE (B is the reference): "))
        .expect("a relMSE line")
        .trim()
        .parse()
        .unwrap();
    assert!(rel < 1e-10, "{text}");
}

#[test]
fn compare_errors_name_the_files() {
    let dir = tempfile::tempdir().unwrap();
    write_exr(&dir.path().join("small.exr"), 2, 2, |_, _| [1.0; 3]);
    write_exr(&dir.path().join("wide.exr"), 3, 2, |_, _| [1.0; 3]);
    std::fs::write(dir.path().join("junk.exr"), b"this is not an EXR file").unwrap();
    let err = assert_fails(&run(dir.path(), &["compare", "small.exr", "wide.exr"]), 1);
    assert!(
        err.contains("small.exr") && err.contains("wide.exr") && err.contains("3x2"),
        "{err}"
    );
    let err = assert_fails(&run(dir.path(), &["compare", "small.exr", "junk.exr"]), 1);
    assert!(err.contains("junk.exr"), "{err}");
    let err = assert_fails(
        &run(dir.path(), &["compare", "nowhere.exr", "small.exr"]),
        1,
    );
    assert!(err.contains("nowhere.exr"), "{err}");
}

/// A Mitsuba XML scene renders from the command line, and `-D NAME=VALUE` sets its `$NAME`
/// over the file's `<default>` (its `$res` is the image size); a malformed `-D` is refused.
#[test]
fn a_mitsuba_scene_takes_its_parameters_from_dash_d() {
    let dir = tempfile::tempdir().unwrap();
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../ppm-scene/tests/data/mitsuba");
    for file in ["cbox.xml", "short_block.serialized", "tall_block.ply"] {
        std::fs::copy(data.join(file), dir.path().join(file)).unwrap();
    }
    let out = run(
        dir.path(),
        &["cbox.xml", "-D", "res=12", "-n", "1", "-a", "pt", "-q"],
    );
    assert_ok(&out);
    let (w, h, pixels) = read_exr(&dir.path().join("cbox.exr"));
    assert_eq!((w, h), (12, 12), "-D res=12 sets the film's size");
    assert!(pixels.iter().any(|p| p[0] > 0.0), "a black Cornell box");
    let err = assert_fails(&run(dir.path(), &["cbox.xml", "-D", "res"]), 2);
    assert!(err.contains("NAME=VALUE"), "{err}");
}
