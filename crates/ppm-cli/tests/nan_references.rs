//! References with NaN pixels are refused by `compare`, a render's error log and `converge`,
//! naming the file and the pixel.

mod common;

use common::*;

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
