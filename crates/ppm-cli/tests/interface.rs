//! The interface conventions, through the binary: the tev preview, crop windows,
//! black images explained, --spp/-q/-v/-t, scenes found from anywhere, the settings in the
//! summary, a bare OBJ refused in one line and `ppm info`.

mod common;

use common::*;
use std::io::Read;
use std::net::TcpListener;
use std::path::Path;

/// Runs `ppm` in `dir` and asserts success; returns stderr.
fn ok(dir: &Path, args: &[&str]) -> String {
    let out = run(dir, args);
    assert_ok(&out);
    stderr(&out)
}

/// What a tev server received: the image named in the last create packet, assembled from the
/// update packets that followed (the last write to a pixel wins).
#[derive(Debug, Default)]
struct Received {
    name: String,
    width: usize,
    height: usize,
    pixels: Vec<[f32; 3]>,
    updates: usize,
}

/// Reads a NUL-terminated string at `*at`.
fn take_str(p: &[u8], at: &mut usize) -> String {
    let end = p[*at..].iter().position(|&b| b == 0).expect("NUL");
    let s = String::from_utf8(p[*at..*at + end].to_vec()).unwrap();
    *at += end + 1;
    s
}

fn take_i32(p: &[u8], at: &mut usize) -> i32 {
    let v = i32::from_le_bytes(p[*at..*at + 4].try_into().unwrap());
    *at += 4;
    v
}

fn take_i64(p: &[u8], at: &mut usize) -> i64 {
    let v = i64::from_le_bytes(p[*at..*at + 8].try_into().unwrap());
    *at += 8;
    v
}

/// Decodes a stream of tev packets (tev's IPC protocol: u32 length including itself, u8 type;
/// 4 = create image, 6 = update image v3), independently of ppm's encoder.
fn decode(stream: &[u8]) -> Received {
    let mut r = Received::default();
    let mut at = 0;
    while at < stream.len() {
        let len = u32::from_le_bytes(stream[at..at + 4].try_into().unwrap()) as usize;
        let p = &stream[at..at + len];
        at += len;
        let mut i = 5;
        match p[4] {
            4 => {
                let _grab_focus = p[i];
                i += 1;
                r.name = take_str(p, &mut i);
                r.width = take_i32(p, &mut i) as usize;
                r.height = take_i32(p, &mut i) as usize;
                let n = take_i32(p, &mut i);
                let names: Vec<String> = (0..n).map(|_| take_str(p, &mut i)).collect();
                assert_eq!(names, ["R", "G", "B"]);
                r.pixels = vec![[f32::NAN; 3]; r.width * r.height];
                assert_eq!(i, len, "create packet length");
            }
            6 => {
                i += 1;
                assert_eq!(take_str(p, &mut i), r.name);
                let n = take_i32(p, &mut i) as usize;
                let names: Vec<String> = (0..n).map(|_| take_str(p, &mut i)).collect();
                let [x0, y0, w, h] = [0; 4].map(|_| take_i32(p, &mut i) as usize);
                let offsets: Vec<i64> = (0..n).map(|_| take_i64(p, &mut i)).collect();
                let strides: Vec<i64> = (0..n).map(|_| take_i64(p, &mut i)).collect();
                let data: Vec<f32> = p[i..]
                    .chunks_exact(4)
                    .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
                    .collect();
                for (c, name) in names.iter().enumerate() {
                    let channel = ["R", "G", "B"].iter().position(|n| n == name).unwrap();
                    for k in 0..w * h {
                        let (x, y) = (x0 + k % w, y0 + k / w);
                        r.pixels[y * r.width + x][channel] =
                            data[(offsets[c] + k as i64 * strides[c]) as usize];
                    }
                }
                r.updates += 1;
            }
            t => panic!("unexpected packet type {t}"),
        }
    }
    r
}

/// A tev stand-in on an ephemeral port: returns the address and a thread that accepts one
/// connection and returns every byte received until it closes.
fn listener() -> (String, std::thread::JoinHandle<Vec<u8>>) {
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let address = listener.local_addr().unwrap().to_string();
    let thread = std::thread::spawn(move || {
        let (mut stream, _) = listener.accept().unwrap();
        let mut bytes = Vec::new();
        stream.read_to_end(&mut bytes).unwrap();
        bytes
    });
    (address, thread)
}

#[test]
fn the_display_server_receives_the_final_image() {
    let dir = tempfile::tempdir().unwrap();
    tiny_scene(dir.path());
    for (algorithm, crop) in [("ppm", None), ("pt", Some(["2", "13", "1", "9"]))] {
        let (address, server) = listener();
        let mut args = vec![
            "tiny.yml",
            "-n",
            "3",
            "--seed",
            "1",
            "-a",
            algorithm,
            "--display-server",
            &address,
        ];
        if let Some(c) = &crop {
            args.push("--pixelbounds");
            args.extend(c);
        }
        let log = ok(dir.path(), &args);
        assert!(!log.contains("warning"), "{log}");
        let received = decode(&server.join().unwrap());
        let (w, h, pixels) = read_exr(&dir.path().join("tiny.exr"));
        assert_eq!(received.name, "ppm tiny");
        assert_eq!((received.width, received.height), (w, h), "{algorithm}");
        assert!(received.updates >= 1);
        assert_eq!(
            received.pixels, pixels,
            "{algorithm}: the last frame is the image"
        );
    }
}

#[test]
fn an_unreachable_display_server_is_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    tiny_scene(dir.path());
    // A port that was just free: nothing listens there.
    let port = TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port();
    let address = format!("127.0.0.1:{port}");
    let log = ok(
        dir.path(),
        &["tiny.yml", "-n", "1", "--display-server", &address],
    );
    assert!(
        log.contains(&format!("warning: display server {address}")),
        "{log}"
    );
    assert!(dir.path().join("tiny.exr").is_file());
}

/// A viewer that accepts the connection but never reads holds the render at its end for at
/// most the display's final wait (2 s), with a warning, instead of the socket timeouts of every
/// blocked write: the image is written, and a stop signal's grace period (10 s) is not spent.
#[test]
fn a_viewer_that_stops_reading_does_not_hold_the_render() {
    let dir = tempfile::tempdir().unwrap();
    tiny_scene(dir.path());
    let stalled = TcpListener::bind("127.0.0.1:0").unwrap();
    let address = stalled.local_addr().unwrap().to_string();
    // Accepts and keeps the connection open without reading until the test ends.
    let holder = std::thread::spawn(move || stalled.accept().map(|(stream, _)| stream));
    // 1024 x 768 RGB f32 is 9 MiB a frame, far beyond the loopback socket's buffers.
    let args = [
        "tiny.yml", "-n", "1", "-a", "pt", "--width", "1024", "--height", "768",
    ];
    let start = std::time::Instant::now();
    ok(dir.path(), &args);
    let alone = start.elapsed();
    let mut with_viewer = args.to_vec();
    with_viewer.extend(["--display-server", &address]);
    let start = std::time::Instant::now();
    let log = ok(dir.path(), &with_viewer);
    let held = start.elapsed().saturating_sub(alone);
    assert!(
        log.contains("did not take the final image"),
        "no warning about the stalled viewer: {log}"
    );
    // A bound, not a timing: before, each blocked write waited out a 5 s timeout (13-15 s).
    assert!(
        held < std::time::Duration::from_secs(5),
        "the stalled viewer held the render {held:?}"
    );
    assert!(dir.path().join("tiny.exr").is_file());
    drop(holder);
}

#[test]
fn a_crop_has_the_full_renders_pixels() {
    let dir = tempfile::tempdir().unwrap();
    tiny_scene(dir.path());
    for algorithm in ["pt", "ppm"] {
        let common = ["tiny.yml", "-n", "2", "--seed", "3", "-a", algorithm];
        ok(dir.path(), &[&common[..], &["-o", "full.exr"]].concat());
        // 16x12: x in [ceil(0.25 * 16), ceil(0.8 * 16)) = [4, 13), y in [ceil(0.1 * 12),
        // ceil(0.7 * 12)) = [2, 9).
        let log = ok(
            dir.path(),
            &[
                &common[..],
                &[
                    "-o",
                    "crop.exr",
                    "--cropwindow",
                    "0.25",
                    "0.8",
                    "0.1",
                    "0.7",
                ],
            ]
            .concat(),
        );
        assert!(
            log.contains("9x7 "),
            "the summary gives the crop's size: {log}"
        );
        let (fw, _, full) = read_exr(&dir.path().join("full.exr"));
        let (w, h, crop) = read_exr(&dir.path().join("crop.exr"));
        assert_eq!((w, h), (9, 7));
        for y in 0..h {
            for x in 0..w {
                assert_eq!(
                    crop[y * w + x],
                    full[(y + 2) * fw + x + 4],
                    "{algorithm} ({x}, {y})"
                );
            }
        }
    }
    let err = assert_fails(
        &run(
            dir.path(),
            &["tiny.yml", "--pixelbounds", "0", "17", "0", "1"],
        ),
        2,
    );
    assert!(
        err.contains("--pixelbounds") && err.contains("16x12"),
        "{err}"
    );
}

/// A scene's own crop window (`render.pixel_bounds`, as a Mitsuba or pbrt film's crop
/// loads): rendered as `--pixelbounds` would be, replaced by the command line's window, and
/// moved with the resolution.
#[test]
fn a_scenes_crop_window_is_rendered_unless_the_command_line_gives_one() {
    let dir = tempfile::tempdir().unwrap();
    tiny_scene(dir.path());
    let cropped = TINY_SCENE.replace("render:\n", "render:\n  pixel_bounds: [4, 13, 2, 9]\n");
    assert_ne!(cropped, TINY_SCENE);
    std::fs::write(dir.path().join("cropped.yml"), cropped).unwrap();
    let common = ["-n", "2", "--seed", "3", "-a", "pt"];
    ok(
        dir.path(),
        &[&["tiny.yml"], &common[..], &["-o", "full.exr"]].concat(),
    );
    ok(
        dir.path(),
        &[&["cropped.yml"], &common[..], &["-o", "crop.exr"]].concat(),
    );
    let (fw, _, full) = read_exr(&dir.path().join("full.exr"));
    let (w, h, crop) = read_exr(&dir.path().join("crop.exr"));
    assert_eq!((w, h), (9, 7));
    for y in 0..h {
        for x in 0..w {
            assert_eq!(crop[y * w + x], full[(y + 2) * fw + x + 4], "({x}, {y})");
        }
    }
    // The command line's window replaces the scene's.
    ok(
        dir.path(),
        &[
            &["cropped.yml"],
            &common[..],
            &["-o", "whole.exr", "--cropwindow", "0", "1", "0", "1"],
        ]
        .concat(),
    );
    assert_eq!(read_exr(&dir.path().join("whole.exr")).2, full);
    // Twice the resolution: every edge doubles.
    ok(
        dir.path(),
        &[
            &["cropped.yml"],
            &common[..],
            &["-o", "big.exr", "--width", "32", "--height", "24"],
        ]
        .concat(),
    );
    let (w, h, _) = read_exr(&dir.path().join("big.exr"));
    assert_eq!((w, h), (18, 14));
}

#[test]
fn a_black_image_is_explained() {
    let dir = tempfile::tempdir().unwrap();
    // The tiny box without its ceiling, the lamp raised to the walls' top (y = 2) and its
    // edges swapped: it emits upward, where nothing is.
    let lamp = "{ type: quad, corner: [-0.3, 1.98, -0.3], edge_u: [0.6, 0, 0], edge_v: [0, 0, 0.6], material: light }";
    assert!(TINY_SCENE.contains(lamp));
    let ceiling = "  - { type: quad, corner: [-1, 2, -1], edge_u: [2, 0, 0], edge_v: [0, 0, 2], material: white }\n";
    assert!(TINY_SCENE.contains(ceiling));
    let flipped = TINY_SCENE.replace(ceiling, "").replace(
        lamp,
        "{ type: quad, corner: [-0.3, 2.0, -0.3], edge_u: [0, 0, 0.6], edge_v: [0.6, 0, 0], material: light }",
    );
    std::fs::write(dir.path().join("flipped.yml"), flipped).unwrap();
    for algorithm in ["ppm", "pt"] {
        let log = ok(dir.path(), &["flipped.yml", "-n", "1", "-a", algorithm]);
        assert!(log.contains("warning: the image is black"), "{log}");
        assert!(
            log.contains("warning: light `light` in flipped.yml (2 triangles) emits away from all other geometry")
                && log.contains("(0.000, 1.000, 0.000)"),
            "{log}"
        );
        let path_line = if algorithm == "ppm" {
            "none of the 2000 light paths stored a photon"
        } else {
            "no camera path reached a light"
        };
        assert!(log.contains(path_line), "{log}");
    }
    // Lights only (`objects:` may be empty): every algorithm renders it (the `auto` radius
    // once panicked here) and says why it is black.
    let lights_only =
        "camera: { position: [0, 1, 4], look_at: [0, 1, 0], up: [0, 1, 0], fov: 40 }\n\
                       resolution: [8, 8]\nobjects:\nlights:\n  \
                       - { type: point, position: [0, 2, 0], intensity: [1, 1, 1] }\n";
    std::fs::write(dir.path().join("lights_only.yml"), lights_only).unwrap();
    for algorithm in ["ppm", "sppm", "vcm", "pt"] {
        let log = ok(dir.path(), &["lights_only.yml", "-n", "2", "-a", algorithm]);
        assert!(
            log.contains("0 rejected samples")
                && log.contains("warning: lights_only.yml has no geometry"),
            "{algorithm}: {log}"
        );
    }
    tiny_scene(dir.path());
    let log = ok(dir.path(), &["tiny.yml", "-n", "1"]);
    assert!(!log.contains("black"), "{log}");
}

/// The path tracer says when a scene has light it cannot render: a point light seen
/// through a mirror or glass. Photon mapping renders that light and does not warn; nor does
/// the path tracer without the mirror.
#[test]
fn the_path_tracer_names_the_point_light_paths_it_misses() {
    let dir = tempfile::tempdir().unwrap();
    let mirror_box = TINY_SCENE
        .replace(
            "  white: { type: diffuse",
            "  shiny: { type: mirror, color: [0.9, 0.9, 0.9] }\n  white: { type: diffuse",
        )
        .replace(
            "edge_u: [0, 2, 0], edge_v: [0, 0, 2], material: red",
            "edge_u: [0, 2, 0], edge_v: [0, 0, 2], material: shiny",
        )
        .replace(
            "render:",
            "lights:\n  - { type: point, position: [0, 1.5, 0], intensity: [1, 1, 1] }\nrender:",
        );
    std::fs::write(dir.path().join("mirror.yml"), &mirror_box).unwrap();
    let warning = "the path tracer cannot render point-light light that passes a mirror";
    let log = ok(dir.path(), &["mirror.yml", "-n", "1", "-a", "pt"]);
    assert!(log.contains(warning), "{log}");
    let log = ok(dir.path(), &["mirror.yml", "-n", "1", "-a", "ppm"]);
    assert!(!log.contains(warning), "{log}");
    let diffuse_box = mirror_box.replace("material: shiny", "material: red");
    std::fs::write(dir.path().join("diffuse.yml"), diffuse_box).unwrap();
    let log = ok(dir.path(), &["diffuse.yml", "-n", "1", "-a", "pt"]);
    assert!(!log.contains(warning), "{log}");
}

/// A flag the chosen algorithm does not read is named in a warning (the render goes on:
/// scripts pass one set of flags to every algorithm); a flag it reads is not.
#[test]
fn flags_the_algorithm_ignores_are_named() {
    let dir = tempfile::tempdir().unwrap();
    tiny_scene(dir.path());
    let both = |algorithm| {
        let flags = ["--photons", "500", "--light-strategy", "mis"];
        ok(
            dir.path(),
            &[&["tiny.yml", "-n", "1", "-a", algorithm][..], &flags].concat(),
        )
    };
    let log = both("pt");
    assert!(
        log.contains("--photons has no effect with -a pt") && !log.contains("--light-strategy has"),
        "{log}"
    );
    let log = both("ppm");
    assert!(
        log.contains("--light-strategy has no effect with -a ppm")
            && !log.contains("--photons has"),
        "{log}"
    );
    let log = ok(
        dir.path(),
        &["tiny.yml", "-n", "1", "-a", "vcm", "--radius", "0.2"],
    );
    assert!(!log.contains("warning"), "{log}");
}

#[test]
fn spp_quiet_verbose_and_threads() {
    let dir = tempfile::tempdir().unwrap();
    tiny_scene(dir.path());
    let log = ok(
        dir.path(),
        &["tiny.yml", "-a", "pt", "--spp", "3", "-t", "1"],
    );
    assert!(
        log.contains("16x12 pt: 3 iterations")
            && log.contains("3 samples per pixel, max depth 6, 1 thread"),
        "{log}"
    );
    let err = assert_fails(&run(dir.path(), &["tiny.yml", "--spp", "3"]), 2);
    assert!(
        err.contains("--spp is for the path tracer") && err.contains("-n"),
        "{err}"
    );
    assert_eq!(
        ok(dir.path(), &["tiny.yml", "-n", "1", "-q"]),
        "",
        "-q prints nothing"
    );
    let log = ok(dir.path(), &["tiny.yml", "-n", "1", "-v", "--seed", "4"]);
    assert!(
        log.contains("scene tiny.yml")
            && log.contains("image 16x12")
            && log.contains("seed 4, 2000 photons"),
        "{log}"
    );
}

#[test]
fn the_summary_says_seed_photons_and_radius() {
    let dir = tempfile::tempdir().unwrap();
    tiny_scene(dir.path());
    // The tiny scene's radius 0.1 and alpha 0.7: r_2 = 0.1 sqrt(1.7 / 2) = 0.092195...
    let log = ok(
        dir.path(),
        &["tiny.yml", "-n", "2", "--seed", "9", "-t", "2"],
    );
    assert!(
        log.contains("seed 9, 2000 photons (light paths) per iteration, radius 0.1 -> 0.0922 (")
            && log.contains("(alpha 0.7), direct light sampled, max depth 6, 2 threads"),
        "{log}"
    );
}

#[test]
fn scenes_are_found_from_anywhere() {
    let elsewhere = tempfile::tempdir().unwrap();
    // The shipped scenes, from a folder that has none: found in the source tree.
    let log = ok(
        elsewhere.path(),
        &[
            "cornell_box.yml",
            "--width",
            "4",
            "-n",
            "1",
            "--photons",
            "100",
            "-v",
        ],
    );
    assert!(log.contains("scenes/cornell_box.yml"), "{log}");
    assert!(elsewhere.path().join("cornell_box.exr").is_file());
    // PPM_SCENES: a folder of the user's scenes.
    let mine = tempfile::tempdir().unwrap();
    std::fs::write(mine.path().join("mine.yml"), TINY_SCENE).unwrap();
    let out = ppm(elsewhere.path())
        .args(["mine.yml", "-n", "1"])
        .env("PPM_SCENES", mine.path())
        .output()
        .unwrap();
    assert_ok(&out);
    assert!(elsewhere.path().join("mine.exr").is_file());
    let err = assert_fails(&run(elsewhere.path(), &["mine.yml", "-n", "1"]), 1);
    assert!(err.contains("PPM_SCENES"), "{err}");
}

#[test]
fn a_bare_obj_is_refused_in_one_line_with_the_wrapper() {
    let dir = tempfile::tempdir().unwrap();
    let obj: String = (0..3000)
        .map(|i| {
            format!(
                "v {i} 0 0\nv {i} 1 0\nv {i} 0 1\nf {} {} {}\n",
                3 * i + 1,
                3 * i + 2,
                3 * i + 3
            )
        })
        .collect();
    std::fs::write(dir.path().join("model.obj"), &obj).unwrap();
    let err = assert_fails(&run(dir.path(), &["model.obj"]), 1);
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines.len(), 4, "{err}");
    assert!(
        lines[0].starts_with("error: model.obj is a mesh, not a scene"),
        "{err}"
    );
    assert_eq!(lines[2], "objects:");
    assert_eq!(lines[3], "  - { type: mesh, file: model.obj }");
    // The same text under a scene's name: a YAML error quoting at most one short line.
    std::fs::write(dir.path().join("model.yml"), &obj).unwrap();
    let err = assert_fails(&run(dir.path(), &["model.yml"]), 1);
    assert!(err.lines().count() == 1 && err.len() < 300, "{err}");
}

#[test]
fn info_prints_the_exr_header() {
    let dir = tempfile::tempdir().unwrap();
    tiny_scene(dir.path());
    ok(dir.path(), &["tiny.yml", "-n", "1"]);
    let out = run(dir.path(), &["info", "tiny.exr"]);
    assert_ok(&out);
    let text = stdout(&out);
    for line in [
        "size: 16x12",
        "channels: B (float), G (float), R (float)",
        "  compression (compression) =",
    ] {
        assert!(
            text.lines().any(|l| l.starts_with(line)),
            "no `{line}` in:\n{text}"
        );
    }
    let err = assert_fails(&run(dir.path(), &["info", "tiny.png"]), 1);
    assert!(
        err.contains("tiny.png") && err.contains("not an OpenEXR file"),
        "{err}"
    );
}

#[test]
fn aov_images_are_written_beside_the_render() {
    let dir = tempfile::tempdir().unwrap();
    tiny_scene(dir.path());
    for algorithm in ["ppm", "sppm"] {
        let out = format!("{algorithm}.exr");
        ok(
            dir.path(),
            &[
                "tiny.yml", "-n", "3", "-a", algorithm, "--aov", "radius", "--aov", "photons",
                "-o", &out,
            ],
        );
        let (w, h, _) = read_exr(&dir.path().join(&out));
        let (rw, rh, radius) = read_exr(&dir.path().join(format!("{algorithm}.radius.exr")));
        let (pw, ph, photons) = read_exr(&dir.path().join(format!("{algorithm}.photons.exr")));
        assert_eq!((rw, rh, pw, ph), (w, h, w, h), "{algorithm}");
        assert!(
            radius.iter().all(|p| p[0] > 0.0 && p[0].is_finite()),
            "{algorithm}"
        );
        // Grey, non-negative counts (sppm's N is alpha-weighted, so not always whole), and
        // some pixel gathered photons.
        assert!(
            photons.iter().all(|p| p[0] >= 0.0 && p == &[p[0]; 3]),
            "{algorithm}"
        );
        assert!(
            photons.iter().any(|p| p[0] > 0.0),
            "{algorithm}: no photons"
        );
    }
    for algorithm in ["pt", "vcm"] {
        let err = assert_fails(
            &run(
                dir.path(),
                &["tiny.yml", "-a", algorithm, "--aov", "photons"],
            ),
            2,
        );
        assert!(
            err.contains("--aov photons needs photon mapping"),
            "{algorithm}: {err}"
        );
    }
}
