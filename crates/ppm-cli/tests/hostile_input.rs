//! Hostile and unusual input: deep nesting, overflowing light power, extreme `max_depth`,
//! byte order marks, special files. Each is an error naming its place, or works as documented.

mod common;

use common::*;

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
