//! Provenance, `--resume`, `--shard` and `ppm merge` through the binary: joined and resumed
//! renders equal single renders bit for bit (pt and ppm, 1 and 2 threads), checkpoints are
//! resumable, and every mismatch is refused with a message naming it.

mod common;

use common::*;
use exr::meta::attribute::AttributeValue;
use std::collections::BTreeMap;
use std::path::Path;

/// Runs ppm in `dir` and asserts success.
fn ok(dir: &Path, args: &[&str]) {
    assert_ok(&run(dir, args));
}

/// The RGB bits of an EXR (so the last bit counts).
fn exr_bits(path: &Path) -> Vec<[u32; 3]> {
    read_exr(path)
        .2
        .iter()
        .map(|p| p.map(f32::to_bits))
        .collect()
}

/// The text, int, float and double attributes of an EXR's first layer, as text.
fn attributes(path: &Path) -> BTreeMap<String, String> {
    let image = exr::prelude::read_all_flat_layers_from_file(path).unwrap();
    image.layer_data[0]
        .attributes
        .other
        .iter()
        .filter_map(|(k, v)| match v {
            AttributeValue::Text(t) => Some((k.to_string(), t.to_string())),
            AttributeValue::I32(v) => Some((k.to_string(), v.to_string())),
            AttributeValue::F32(v) => Some((k.to_string(), v.to_string())),
            AttributeValue::F64(v) => Some((k.to_string(), v.to_string())),
            _ => None,
        })
        .collect()
}

/// Asserts `a.exr` and `b.exr` hold the same image bit for bit (and their PNGs the same bytes).
fn assert_same_image(dir: &Path, a: &str, b: &str, what: &str) {
    assert_eq!(
        exr_bits(&dir.join(format!("{a}.exr"))),
        exr_bits(&dir.join(format!("{b}.exr"))),
        "{what}"
    );
    assert_eq!(
        std::fs::read(dir.join(format!("{a}.png"))).unwrap(),
        std::fs::read(dir.join(format!("{b}.png"))).unwrap(),
        "{what}: PNG"
    );
}

/// Runs ppm in `dir`, expects exit status 1 and returns stderr.
fn refused(dir: &Path, args: &[&str]) -> String {
    assert_fails(&run(dir, args), 1)
}

#[test]
fn shards_merged_equal_a_single_render_for_pt_ppm_and_vcm_at_1_and_2_threads() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    tiny_scene(d);
    for algorithm in ["pt", "ppm", "vcm"] {
        ok(
            d,
            &[
                "tiny.yml",
                "-a",
                algorithm,
                "-n",
                "7",
                "--seed",
                "3",
                "--threads",
                "1",
                "-o",
                "single",
            ],
        );
        for threads in ["1", "2"] {
            for i in 0..3 {
                let shard = format!("{i}/3");
                let out = format!("part{i}");
                let args = ["tiny.yml", "-a", algorithm, "-n", "7", "--seed", "3"];
                ok(
                    d,
                    &[
                        &args[..],
                        &["--shard", &shard, "--threads", threads, "-o", &out],
                    ]
                    .concat(),
                );
            }
            // Any order on the command line.
            ok(
                d,
                &[
                    "merge",
                    "part2.exr",
                    "part0.exr",
                    "part1.exr",
                    "-o",
                    "merged",
                ],
            );
            assert_same_image(
                d,
                "merged",
                "single",
                &format!("{algorithm}, shards on {threads} threads"),
            );
            let a = attributes(&d.join("merged.exr"));
            assert_eq!(a["ppm.firstIteration"], "0");
            assert_eq!(a["ppm.iterations"], "7");
            assert!(
                !a.contains_key("ppm.shard"),
                "a merged image is not a shard"
            );
        }
    }
}

#[test]
fn resumed_render_equals_an_uninterrupted_one_for_pt_ppm_and_vcm() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    tiny_scene(d);
    for algorithm in ["pt", "ppm", "vcm"] {
        let base = ["tiny.yml", "-a", algorithm, "--seed", "5"];
        ok(
            d,
            &[&base[..], &["-n", "6", "--threads", "2", "-o", "whole"]].concat(),
        );
        ok(
            d,
            &[&base[..], &["-n", "4", "--threads", "1", "-o", "first"]].concat(),
        );
        ok(
            d,
            &[
                &base[..],
                &[
                    "-n",
                    "2",
                    "--threads",
                    "2",
                    "--resume",
                    "first.exr",
                    "-o",
                    "resumed",
                ],
            ]
            .concat(),
        );
        assert_same_image(d, "resumed", "whole", algorithm);
        // Resuming into the file it reads from works too (the write is atomic).
        ok(
            d,
            &[
                &base[..],
                &["-n", "2", "--resume", "first.exr", "-o", "first"],
            ]
            .concat(),
        );
        assert_same_image(d, "first", "whole", algorithm);
        let a = attributes(&d.join("first.exr"));
        assert_eq!(
            (a["ppm.iterations"].as_str(), a["ppm.threads"].as_str()),
            ("6", "1,2")
        );
    }
}

/// The error log of a resumed render goes on counting the render's iterations and time
/// where the file it continues stopped, so the logs of one render split across runs join.
#[test]
fn a_resumed_renders_error_log_continues_the_count() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    tiny_scene(d);
    ok(
        d,
        &[
            "tiny.yml", "-a", "pt", "-n", "3", "--seed", "9", "-o", "ref",
        ],
    );
    let base = ["tiny.yml", "-a", "pt", "--reference", "ref.exr"];
    ok(
        d,
        &[&base[..], &["-n", "4", "--error-log", "a.csv", "-o", "r"]].concat(),
    );
    ok(
        d,
        &[
            &base[..],
            &[
                "-n",
                "2",
                "--resume",
                "r.exr",
                "--error-log",
                "b.csv",
                "-o",
                "r",
            ],
        ]
        .concat(),
    );
    let rows = |name: &str| -> Vec<(u64, f64)> {
        std::fs::read_to_string(d.join(name))
            .unwrap()
            .lines()
            .skip(1)
            .map(|l| {
                let mut f = l.split(',');
                (
                    f.next().unwrap().parse().unwrap(),
                    f.next().unwrap().parse().unwrap(),
                )
            })
            .collect()
    };
    let (a, b) = (rows("a.csv"), rows("b.csv"));
    assert_eq!(a.iter().map(|r| r.0).collect::<Vec<_>>(), [1, 2, 3, 4]);
    assert_eq!(b.iter().map(|r| r.0).collect::<Vec<_>>(), [5, 6]);
    // The file keeps its render time to the millisecond.
    assert!(b[0].1 >= a[3].1 - 1e-3, "{a:?} then {b:?}");
}

/// The PNG beside a render holds no state: `merge` and `--resume` say so instead of an EXR
/// parser's "file identifier missing".
#[test]
fn a_png_is_refused_as_a_render_state_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    tiny_scene(d);
    ok(d, &["tiny.yml", "-n", "1", "-o", "r"]);
    for args in [
        &["merge", "r.png", "r.exr", "-o", "m"][..],
        &["tiny.yml", "-n", "1", "--resume", "r.png", "-o", "m"],
    ] {
        let err = refused(d, args);
        assert!(err.contains("r.png is not an EXR"), "{args:?}: {err}");
    }
    let err = refused(
        d,
        &[
            "converge",
            "tiny.yml",
            "--reference",
            "r.exr",
            "--time-limit",
            "0.1",
            "--out",
            "r.png",
        ],
    );
    assert!(err.contains("--out r.png is a file"), "{err}");
}

/// A crop records its pixels, and is neither resumed nor merged as a whole image of its own
/// size (its pixels sit elsewhere in a whole image: the result would mix two images).
#[test]
fn a_crop_is_neither_resumed_nor_merged_as_a_whole_image() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    tiny_scene(d);
    ok(
        d,
        &[
            "tiny.yml",
            "-n",
            "2",
            "--pixelbounds",
            "8",
            "16",
            "0",
            "6",
            "-o",
            "crop",
        ],
    );
    assert_eq!(
        attributes(&d.join("crop.exr"))["ppm.crop"],
        "8 16 0 6 of 16x12"
    );
    // A whole render of the crop's size would otherwise pass every other check.
    let same_size = ["tiny.yml", "--width", "8", "--height", "6"];
    ok(
        d,
        &[&same_size[..], &["-n", "2", "--shard", "1/2", "-o", "half"]].concat(),
    );
    let err = refused(
        d,
        &[
            &same_size[..],
            &["-n", "1", "--resume", "crop.exr", "-o", "x"],
        ]
        .concat(),
    );
    assert!(
        err.contains("cannot resume crop.exr: it is a crop"),
        "{err}"
    );
    let err = refused(d, &["merge", "crop.exr", "half.exr", "-o", "x"]);
    assert!(err.contains("cannot merge crop.exr: it is a crop"), "{err}");
    assert!(!d.join("x.exr").exists());
}

/// A requeued shard job whose part file already holds the whole shard renders nothing,
/// says so and succeeds (exit 0, not "interrupted"), leaving a part the merge still takes.
#[test]
fn resuming_a_complete_shard_renders_nothing_and_succeeds() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    tiny_scene(d);
    let shard = |i: &'static str| ["tiny.yml", "-n", "4", "--shard", i];
    ok(d, &[&shard("0/2")[..], &["-o", "p0"]].concat());
    ok(d, &[&shard("1/2")[..], &["-o", "p1"]].concat());
    let before = exr_bits(&d.join("p1.exr"));
    // `ppm info`'s lines, sorted: the EXR writer orders the attributes as it likes.
    let info = || {
        let mut lines: Vec<String> = stdout(&run(d, &["info", "p1.exr"]))
            .lines()
            .map(str::to_string)
            .collect();
        lines.sort();
        lines
    };
    let info_before = info();
    let output = run(
        d,
        &[&shard("1/2")[..], &["--resume", "p1.exr", "-o", "p1"]].concat(),
    );
    assert_ok(&output);
    // Nor does it count as a run that contributed (the header's threads per run).
    assert_eq!(info(), info_before);
    let log = stderr(&output);
    assert!(
        log.contains("already holds every iteration of shard 1/2"),
        "{log}"
    );
    assert_eq!(exr_bits(&d.join("p1.exr")), before);
    ok(d, &["merge", "p0.exr", "p1.exr", "-o", "merged"]);
    ok(d, &["tiny.yml", "-n", "4", "-o", "whole"]);
    assert_same_image(
        d,
        "merged",
        "whole",
        "merge after a complete shard was resumed",
    );
}

/// A setting the algorithm does not read does not stop a render from continuing (or its parts
/// from merging): a path-traced render continued with another `--photons` and `--radius` is
/// still the uninterrupted render, and the same flags still refuse a ppm render.
#[test]
fn resume_and_merge_ignore_settings_the_algorithm_does_not_read() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    tiny_scene(d);
    let base = ["tiny.yml", "-a", "pt", "--seed", "3"];
    ok(d, &[&base[..], &["-n", "3", "-o", "whole"]].concat());
    ok(d, &[&base[..], &["-n", "2", "-o", "first"]].concat());
    let unread = ["--photons", "777", "--radius", "0.3"];
    let resumed = [&base[..], &unread, &["-n", "1", "--resume", "first.exr"]].concat();
    ok(d, &[&resumed[..], &["-o", "resumed"]].concat());
    assert_same_image(d, "resumed", "whole", "pt resumed with unread flags");
    ok(
        d,
        &[
            &base[..],
            &unread,
            &["-n", "3", "--shard", "1/3", "-o", "s1"],
        ]
        .concat(),
    );
    ok(
        d,
        &[&base[..], &["-n", "3", "--shard", "0/3", "-o", "s0"]].concat(),
    );
    ok(
        d,
        &[&base[..], &["-n", "3", "--shard", "2/3", "-o", "s2"]].concat(),
    );
    ok(d, &["merge", "s0.exr", "s1.exr", "s2.exr", "-o", "merged"]);
    assert_same_image(d, "merged", "whole", "pt merged with unread flags");
    ok(d, &["tiny.yml", "-a", "ppm", "-n", "1", "-o", "p"]);
    let err = refused(
        d,
        &[
            "tiny.yml",
            "-a",
            "ppm",
            "--photons",
            "777",
            "-n",
            "1",
            "--resume",
            "p.exr",
            "-o",
            "q",
        ],
    );
    assert!(err.contains("ppm.photons"), "{err}");
}

/// A render killed after a checkpoint resumes from that checkpoint to exactly the image of an
/// uninterrupted render of as many iterations.
#[test]
fn a_checkpoint_of_a_killed_render_resumes_exactly() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    tiny_scene(d);
    let mut child = ppm(d)
        .args([
            "tiny.yml",
            "-a",
            "ppm",
            "-n",
            "100000",
            "--checkpoint",
            "0.05",
            "-o",
            "ck",
        ])
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let checkpoint = d.join("ck.exr");
    let start = std::time::Instant::now();
    while !checkpoint.exists() {
        assert!(start.elapsed().as_secs() < 60, "no checkpoint within 60 s");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    let done: u64 = attributes(&checkpoint)["ppm.iterations"].parse().unwrap();
    assert!(done > 0 && done < 100_000, "{done}");
    ok(
        d,
        &[
            "tiny.yml", "-a", "ppm", "-n", "3", "--resume", "ck.exr", "-o", "resumed",
        ],
    );
    let total = (done + 3).to_string();
    ok(d, &["tiny.yml", "-a", "ppm", "-n", &total, "-o", "whole"]);
    assert_same_image(d, "resumed", "whole", &format!("checkpoint at {done} + 3"));
}

/// A scene's `render.algorithm` is the default of `-a`: the render without `-a` is the one
/// with `-a vcm`, and records its algorithm; `-a` overrides it.
#[test]
fn the_scene_may_name_the_algorithm() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scene = common::TINY_SCENE.replace("render:\n", "render:\n  algorithm: vcm\n");
    assert_ne!(scene, common::TINY_SCENE);
    std::fs::write(d.join("named.yml"), scene).unwrap();
    let base = ["named.yml", "-n", "2", "--seed", "4"];
    ok(d, &[&base[..], &["-o", "default"]].concat());
    ok(d, &[&base[..], &["-a", "vcm", "-o", "vcm"]].concat());
    ok(d, &[&base[..], &["-a", "pt", "-o", "pt"]].concat());
    assert_same_image(d, "default", "vcm", "render.algorithm: vcm without -a");
    assert_eq!(attributes(&d.join("default.exr"))["ppm.algorithm"], "vcm");
    assert_eq!(attributes(&d.join("pt.exr"))["ppm.algorithm"], "pt");
}

#[test]
fn every_exr_records_its_provenance() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    tiny_scene(d);
    ok(
        d,
        &[
            "tiny.yml",
            "-n",
            "4",
            "--shard",
            "1/2",
            "--seed",
            "9",
            "--threads",
            "2",
            "--photons",
            "1500",
            "-o",
            "p",
        ],
    );
    let a = attributes(&d.join("p.exr"));
    for (name, value) in [
        ("ppm.version", env!("CARGO_PKG_VERSION")),
        ("ppm.scene", "tiny.yml"),
        ("ppm.algorithm", "ppm"),
        ("ppm.seed", "9"),
        ("ppm.firstIteration", "2"),
        ("ppm.iterations", "2"),
        ("ppm.photons", "1500"),
        ("ppm.radius", "0.1"),
        ("ppm.alpha", "0.7"),
        ("ppm.maxDepth", "6"),
        ("ppm.threads", "2"),
        ("ppm.shard", "1/2 of 4"),
        ("ppm.direct", "sampled"),
    ] {
        assert_eq!(a.get(name).map(String::as_str), Some(value), "{name}");
    }
    assert_eq!(a["ppm.sceneHash"].len(), 16);
    assert!(a["ppm.renderSeconds"].parse::<f64>().unwrap() > 0.0);
}

#[test]
fn merge_refuses_parts_of_other_scenes_seeds_algorithms_or_settings() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    tiny_scene(d);
    // The same content under another name is the same scene; a brighter light is not.
    std::fs::copy(d.join("tiny.yml"), d.join("copy.yml")).unwrap();
    std::fs::write(
        d.join("brighter.yml"),
        TINY_SCENE.replace("[8.0, 8.0, 8.0]", "[9.0, 8.0, 8.0]"),
    )
    .unwrap();
    let shard = |scene: &str, i: &str, extra: &[&str], out: &str| {
        let args = [scene, "-n", "4", "--shard", i, "-o", out];
        ok(d, &[&args[..], extra].concat());
    };
    shard("tiny.yml", "0/2", &[], "a0");
    shard("tiny.yml", "1/2", &[], "a1");
    shard("copy.yml", "1/2", &[], "copy1");
    ok(d, &["merge", "a0.exr", "copy1.exr", "-o", "m"]);
    shard("brighter.yml", "1/2", &[], "scene1");
    shard("tiny.yml", "1/2", &["--seed", "1"], "seed1");
    shard("tiny.yml", "1/2", &["-a", "pt"], "pt1");
    shard("tiny.yml", "1/2", &["--photons", "999"], "photons1");
    shard("tiny.yml", "1/2", &["--width", "8"], "size1");
    for (part, expected) in [
        ("scene1.exr", "scene content"),
        ("seed1.exr", "ppm.seed: 0 vs 1"),
        ("pt1.exr", "ppm.algorithm: ppm vs pt"),
        ("photons1.exr", "ppm.photons: 2000 vs 999"),
        ("size1.exr", "resolution: 16x12 vs 8x6"),
    ] {
        let err = refused(d, &["merge", "a0.exr", part, "-o", "m"]);
        assert!(
            err.contains(expected) && err.contains(part),
            "{part}: {err}"
        );
    }
}

#[test]
fn merge_refuses_overlapping_or_missing_slices() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    tiny_scene(d);
    for i in 0..3 {
        ok(
            d,
            &[
                "tiny.yml",
                "-n",
                "6",
                "--shard",
                &format!("{i}/3"),
                "-o",
                &format!("s{i}"),
            ],
        );
    }
    let err = refused(
        d,
        &["merge", "s0.exr", "s1.exr", "s1.exr", "s2.exr", "-o", "m"],
    );
    assert!(err.contains("overlap") && err.contains("2..4"), "{err}");
    let err = refused(d, &["merge", "s0.exr", "s2.exr", "-o", "m"]);
    assert!(err.contains("iterations 2..4 are missing"), "{err}");
    let err = refused(d, &["merge", "s1.exr", "s2.exr", "-o", "m"]);
    assert!(err.contains("iterations 0..2 are missing"), "{err}");
    let err = refused(d, &["merge", "s0.exr", "s1.exr", "-o", "m"]);
    assert!(
        err.contains("iterations 4..6") && err.contains("missing"),
        "{err}"
    );
    // An EXR without a render state (another renderer's) is named.
    write_exr(&d.join("other.exr"), 16, 12, |_, _| [1.0; 3]);
    let err = refused(d, &["merge", "s0.exr", "other.exr", "-o", "m"]);
    assert!(
        err.contains("other.exr") && err.contains("ppm.state"),
        "{err}"
    );
    assert!(!d.join("m.exr").exists(), "nothing written on refusal");
    ok(d, &["merge", "s2.exr", "s1.exr", "s0.exr", "-o", "m"]);
    // The output may not replace a part: the shard would be gone.
    let err = refused(d, &["merge", "s2.exr", "s1.exr", "s0.exr", "-o", "s1"]);
    assert!(err.contains("s1.exr") && err.contains("own input"), "{err}");
}

#[test]
fn resume_refuses_another_scene_or_settings_and_shard_needs_iterations() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    tiny_scene(d);
    std::fs::write(
        d.join("brighter.yml"),
        TINY_SCENE.replace("[8.0, 8.0, 8.0]", "[9.0, 8.0, 8.0]"),
    )
    .unwrap();
    ok(d, &["tiny.yml", "-n", "2", "-o", "r"]);
    for (args, expected) in [
        (&["tiny.yml", "--seed", "4"][..], "ppm.seed: 4 vs 0"),
        (&["tiny.yml", "-a", "pt"], "ppm.algorithm: pt vs ppm"),
        (&["tiny.yml", "--alpha", "0.5"], "ppm.alpha: 0.5 vs 0.7"),
        (&["brighter.yml"], "scene content"),
    ] {
        let err = refused(
            d,
            &[args, &["-n", "1", "--resume", "r.exr", "-o", "x"]].concat(),
        );
        assert!(
            err.contains(expected) && err.contains("r.exr"),
            "{args:?}: {err}"
        );
    }
    let err = refused(
        d,
        &["tiny.yml", "-n", "1", "--resume", "missing.exr", "-o", "x"],
    );
    assert!(err.contains("missing.exr"), "{err}");
    // A shard resumed as another shard.
    ok(d, &["tiny.yml", "-n", "4", "--shard", "0/2", "-o", "s0"]);
    let err = refused(
        d,
        &[
            "tiny.yml", "-n", "4", "--shard", "1/2", "--resume", "s0.exr", "-o", "x",
        ],
    );
    assert!(err.contains("0..2") && err.contains("2..4"), "{err}");
    // Usage errors: --shard without -n, or out of range.
    assert_fails(&run(d, &["tiny.yml", "--shard", "0/2"]), 2);
    assert_fails(&run(d, &["tiny.yml", "-n", "4", "--shard", "2/2"]), 2);
    let err = assert_fails(&run(d, &["tiny.yml", "-n", "2", "--shard", "0/3"]), 2);
    assert!(err.contains("empty"), "{err}");
    // SPPM's iterations depend on all before them: refused at once, for every shard (a
    // usage error too).
    for shard in ["0/2", "1/2"] {
        let err = assert_fails(
            &run(d, &["tiny.yml", "-a", "sppm", "-n", "4", "--shard", shard]),
            2,
        );
        assert!(err.contains("sppm cannot be split into shards"), "{err}");
    }
}

/// A state file of format 1 (before the sums were cut to the words they need: all four words,
/// RLE), written by a format-1 build (main at aa796d8, whose state code is 69e6fb8's) from
/// `tests/data/state_format1.yml` with `-a ppm --seed 5 -n 2 --threads 1`, still resumes and
/// merges exactly. That scene's light
/// (emission 2e6), seen by the camera, is bright enough that the sums reach their third word,
/// so reading fewer words of the old file, or refusing its format, fails the test.
#[test]
fn a_state_file_of_format_1_still_resumes_and_merges_exactly() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    std::fs::copy(data.join("state_format1.yml"), d.join("bright.yml")).unwrap();
    std::fs::copy(data.join("state_format1.exr"), d.join("old.exr")).unwrap();
    let old = attributes(&d.join("old.exr"));
    assert_eq!(old["ppm.state"], "1");
    assert!(!old.contains_key("ppm.sumWords"));
    // The premise: the old file's third words are not all zero.
    let image = exr::prelude::read_all_flat_layers_from_file(d.join("old.exr")).unwrap();
    let third_word = image.layer_data[0]
        .channel_data
        .list
        .iter()
        .find(|c| c.name.to_string() == "ppm.sum.R.2")
        .map(|c| match &c.sample_data {
            exr::prelude::FlatSamples::U32(v) => v.iter().any(|&w| w != 0),
            _ => false,
        });
    assert_eq!(
        third_word,
        Some(true),
        "a pixel's sum reaches its third word"
    );
    let base = ["bright.yml", "-a", "ppm", "--seed", "5", "--threads", "1"];
    ok(d, &[&base[..], &["-n", "3", "-o", "whole"]].concat());
    let whole = attributes(&d.join("whole.exr"));
    assert_eq!(
        (whole["ppm.state"].as_str(), whole["ppm.sumWords"].as_str()),
        ("2", "3"),
        "the premise: this scene's sums need a third word"
    );
    ok(
        d,
        &[
            &base[..],
            &["-n", "1", "--resume", "old.exr", "-o", "resumed"],
        ]
        .concat(),
    );
    assert_same_image(d, "resumed", "whole", "resumed from a format 1 file");
    ok(
        d,
        &[&base[..], &["-n", "3", "--shard", "2/3", "-o", "last"]].concat(),
    );
    ok(d, &["merge", "old.exr", "last.exr", "-o", "merged"]);
    assert_same_image(d, "merged", "whole", "a format 1 file merged");
    ok(d, &["info", "old.exr"]);
}
