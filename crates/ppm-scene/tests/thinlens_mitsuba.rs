//! A Mitsuba `thinlens` scene (tests/data/mitsuba/cbox_thinlens.xml) rendered by ppm's path
//! tracer matches Mitsuba 3's own render (scripts/mitsuba/thinlens.py, committed table
//! thinlens_mitsuba.txt): the image mean within 1% and each quadrant's within 2%, which checks
//! the importer's mapping of `thinlens` (fov along x, aperture, focus) and that the lens keeps
//! the image's brightness. The blur itself is checked analytically in ppm-core's
//! tests/thin_lens.rs: at this aperture the pinhole's means are within these bounds too.

use ppm_core::integrator::{Algorithm, RenderSettings, Renderer};
use ppm_scene::load_scene_builder;
use std::path::Path;

fn data(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/mitsuba")
        .join(name)
}

/// The table's rows: region name and mean RGB.
fn mitsuba_table() -> Vec<(String, [f64; 3])> {
    let text = std::fs::read_to_string(data("thinlens_mitsuba.txt")).unwrap();
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with("se_"))
        .map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            let v = [1, 2, 3].map(|i| f[i].parse::<f64>().unwrap());
            (f[0].to_string(), v)
        })
        .collect()
}

#[test]
fn a_thinlens_cornell_box_renders_as_mitsuba_renders_it() {
    let (builder, warnings) = load_scene_builder(&data("cbox_thinlens.xml")).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!(builder.camera.lens_radius(), 0.15);
    let scene = builder.build().unwrap();
    let settings = RenderSettings {
        seed: 5,
        ..RenderSettings::for_algorithm(&scene, Algorithm::Path)
    };
    let mut r = Renderer::new(&scene, &settings);
    for _ in 0..512 {
        assert_eq!(r.iterate(&scene).rejected, 0);
    }
    let image = r.image();
    let (w, h) = (image.width as usize, image.height as usize);
    let region = |x0: usize, x1: usize, y0: usize, y1: usize| {
        let mut sum = [0.0f64; 3];
        for y in y0..y1 {
            for x in x0..x1 {
                let p = image.pixels[y * w + x];
                for c in 0..3 {
                    sum[c] += p[c] as f64;
                }
            }
        }
        sum.map(|s| s / ((x1 - x0) * (y1 - y0)) as f64)
    };
    let (hw, hh) = (w / 2, h / 2);
    for (name, mitsuba) in mitsuba_table() {
        let (ppm, bound) = match name.as_str() {
            "all" => (region(0, w, 0, h), 0.01),
            "top_left" => (region(0, hw, 0, hh), 0.02),
            "top_right" => (region(hw, w, 0, hh), 0.02),
            "bottom_left" => (region(0, hw, hh, h), 0.02),
            "bottom_right" => (region(hw, w, hh, h), 0.02),
            other => panic!("unknown region {other}"),
        };
        for c in 0..3 {
            let rel = (ppm[c] - mitsuba[c]) / mitsuba[c];
            eprintln!(
                "{name} channel {c}: ppm {:.5} mitsuba {:.5} ({rel:+.4})",
                ppm[c], mitsuba[c]
            );
            assert!(
                rel.abs() < bound,
                "{name} channel {c}: ppm {} mitsuba {}",
                ppm[c],
                mitsuba[c]
            );
        }
    }
}
