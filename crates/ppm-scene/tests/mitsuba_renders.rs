//! Renders of the Mitsuba importer's plugins against Mitsuba 3 itself: each scene of
//! `tests/data/mitsuba/renders/` (one per BSDF or emitter plugin, 32 x 32) is loaded through
//! ppm's importer, path traced, and its image mean compared with the mean Mitsuba 3.9.1
//! (`scalar_rgb`, the scene's own `path` integrator) renders from the same file, committed in
//! `references.csv` by `scripts/mitsuba/importer_references.py`.
//!
//! The bound, per channel: |ppm - mitsuba| within 1 % of Mitsuba's mean, or within 4
//! combined standard errors (sqrt(se_ppm^2 + se_mitsuba^2)) when that is larger. ppm's
//! standard error comes from independent seeds, as Mitsuba's does.

use glam::Vec3;
use ppm_core::integrator::{Algorithm, RenderSettings, Renderer};
use ppm_core::scene::SceneBuilder;
use ppm_scene::load_scene_builder;
use std::path::{Path, PathBuf};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/mitsuba/renders")
        .join(name)
}

/// Mitsuba's mean and standard error of the image mean of `scene`, from references.csv.
fn mitsuba(scene: &str) -> (Vec3, Vec3) {
    let csv = std::fs::read_to_string(data("references.csv")).unwrap();
    let row = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect::<Vec<_>>())
        .find(|r| r[0] == scene)
        .unwrap_or_else(|| panic!("no reference for {scene}"));
    let v: Vec<f32> = row[3..9].iter().map(|x| x.parse().unwrap()).collect();
    (Vec3::new(v[0], v[1], v[2]), Vec3::new(v[3], v[4], v[5]))
}

/// Loads `scene`.xml through the importer; its warnings must be `warnings` (substrings).
fn load(scene: &str, warnings: &[&str]) -> SceneBuilder {
    let (builder, w) = load_scene_builder(&data(&format!("{scene}.xml")))
        .unwrap_or_else(|e| panic!("{scene}: {e}"));
    assert_eq!(w.len(), warnings.len(), "{scene}: {w:?}");
    for (w, expected) in w.iter().zip(warnings) {
        assert!(w.contains(expected), "{scene}: {w} (expected {expected})");
    }
    builder
}

/// The mean over `seeds` independent renders by `algorithm` of `iterations` iterations each,
/// and its standard error.
fn render(
    builder: SceneBuilder,
    algorithm: Algorithm,
    seeds: u64,
    iterations: u32,
) -> (Vec3, Vec3) {
    let scene = builder.build().unwrap();
    let means: Vec<Vec3> = (0..seeds)
        .map(|seed| {
            let settings = RenderSettings {
                seed: 1000 + seed,
                ..RenderSettings::for_algorithm(&scene, algorithm)
            };
            let mut r = Renderer::new(&scene, &settings);
            for _ in 0..iterations {
                assert_eq!(r.iterate(&scene).rejected, 0);
            }
            let m = r.image().mean();
            assert!(m.is_finite(), "{m}");
            m
        })
        .collect();
    let n = means.len() as f32;
    let mean = means.iter().sum::<Vec3>() / n;
    let var = means
        .iter()
        .map(|m| (*m - mean) * (*m - mean))
        .sum::<Vec3>()
        / (n - 1.0);
    (mean, (var / n).powf(0.5))
}

/// Asserts `a` (with standard error `se_a`) within 1 % or 4 combined standard errors of `b`.
fn assert_close(what: &str, a: Vec3, se_a: Vec3, b: Vec3, se_b: Vec3) {
    let bound = (0.01 * b).max(4.0 * (se_a * se_a + se_b * se_b).powf(0.5));
    let diff = (a - b).abs();
    let rel = diff / b;
    eprintln!("{what}: ppm {a} ± {se_a}, reference {b} ± {se_b}, relative {rel}");
    assert!(
        diff.cmple(bound).all(),
        "{what}: ppm {a} ± {se_a}, reference {b} ± {se_b}: off by {diff} > {bound}"
    );
}

/// Renders `scene` with ppm's path tracer and compares it with Mitsuba's mean.
fn check_against_mitsuba(scene: &str, warnings: &[&str], iterations: u32) -> (Vec3, Vec3) {
    let (m, se_m) = mitsuba(scene);
    let (p, se_p) = render(load(scene, warnings), Algorithm::Path, 4, iterations);
    assert_close(&format!("{scene} (pt)"), p, se_p, m, se_m);
    (p, se_p)
}

#[test]
fn rough_gold_matches_mitsuba() {
    check_against_mitsuba("rough_gold", &[], 64);
}

#[test]
fn frosted_glass_matches_mitsuba() {
    check_against_mitsuba("frosted_glass", &[], 64);
}

#[test]
fn plastic_matches_mitsuba() {
    check_against_mitsuba("plastic", &[], 64);
}

#[test]
fn rough_plastic_matches_mitsuba_and_bpt_and_vcm_agree() {
    let (p, se_p) = check_against_mitsuba("rough_plastic", &[], 64);
    for algorithm in [Algorithm::Bpt, Algorithm::Vcm] {
        let (a, se_a) = render(load("rough_plastic", &[]), algorithm, 4, 32);
        assert_close(
            &format!("rough_plastic ({algorithm:?} vs pt)"),
            a,
            se_a,
            p,
            se_p,
        );
    }
}

#[test]
fn thin_pane_matches_mitsuba() {
    check_against_mitsuba("thin_pane", &[], 64);
}

#[test]
fn spot_matches_mitsuba() {
    // The falloff band (27 to 30 degrees) differs in shape (see emitter.rs): 0.3 % of power.
    check_against_mitsuba("spot", &["emitter `spot`: between beam_width 27°"], 64);
}

#[test]
fn directional_matches_mitsuba_and_bpt_vcm_sppm_agree() {
    let (p, se_p) = check_against_mitsuba("directional", &[], 64);
    for algorithm in [Algorithm::Bpt, Algorithm::Vcm, Algorithm::Sppm] {
        let (a, se_a) = render(load("directional", &[]), algorithm, 4, 32);
        assert_close(
            &format!("directional ({algorithm:?} vs pt)"),
            a,
            se_a,
            p,
            se_p,
        );
    }
}

/// Mitsuba's default distribution, beckmann, is ppm's Beckmann: no warning, and the same
/// bound as the other scenes.
#[test]
fn rough_gold_beckmann_matches_mitsuba() {
    check_against_mitsuba("rough_gold_beckmann", &[], 64);
}
