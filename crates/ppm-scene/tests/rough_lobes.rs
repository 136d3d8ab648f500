//! Rough lobes and photon mapping (docs/rough-lobes.md): at every roughness from a
//! near-mirror (alpha 0.001) to a wide lobe (alpha 0.5), `ppm`, `sppm` and `vcm` render the
//! caustic a rough gold sphere reflects onto a diffuse floor, and the one a frosted glass
//! sphere focuses onto it, as the path tracer does. The rule that makes this hold has no
//! roughness threshold: photon mapping density-estimates only Lambertian lobes and traces
//! every other lobe, whatever its alpha; VCM merges at every non-delta vertex and weighs the
//! merge against its other techniques by their pdfs, which are continuous in alpha. A
//! threshold below which a rough lobe were taken for a delta (no photons through it, no
//! merging at it) would lose the caustic, as a LuxCore user saw below roughness 0.23.
//!
//! The scenes are tests/data/mitsuba/renders/rough_lobe_{metal,glass}.xml with their `alpha`
//! defined at load; their image means are also checked against Mitsuba 3's (references.csv,
//! from scripts/mitsuba/importer_references.py).

use ppm_core::integrator::{Algorithm, Radius, RenderSettings};
use ppm_core::scene::Scene;
use ppm_scene::load_scene_builder_with_defines;
use ppm_test_support::test_scenes::{render_stats, sppm_stats, z_scores, PixelStats};
use std::path::{Path, PathBuf};

/// The roughnesses of the study: a near-mirror to a wide lobe, with 0.23 (LuxCore's report).
const ROUGHNESSES: [&str; 6] = ["0.001", "0.01", "0.05", "0.1", "0.23", "0.5"];

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/mitsuba/renders")
        .join(name)
}

/// `rough_lobe_<kind>.xml` with roughness `alpha`, loaded through the Mitsuba importer.
fn scene(kind: &str, alpha: &str) -> Scene {
    let defines = [("alpha".to_string(), alpha.to_string())];
    let (builder, warnings) =
        load_scene_builder_with_defines(&data(&format!("rough_lobe_{kind}.xml")), &defines)
            .unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    builder.build().unwrap()
}

/// Small seeded settings of `algorithm`: 4096 light paths an iteration for the photon
/// mappers (the scene is 32 x 32).
fn settings(scene: &Scene, algorithm: Algorithm, seed: u64) -> RenderSettings {
    RenderSettings {
        seed,
        photons: 4096,
        ..RenderSettings::for_algorithm(scene, algorithm)
    }
}

/// Mitsuba 3's image mean (mean of the channels) and its standard error from references.csv.
fn mitsuba(name: &str) -> (f64, f64) {
    let csv = std::fs::read_to_string(data("references.csv")).unwrap();
    let row: Vec<f64> = csv
        .lines()
        .map(|l| l.split(',').collect::<Vec<_>>())
        .find(|r| r[0] == name)
        .unwrap_or_else(|| panic!("no reference for {name}"))[3..9]
        .iter()
        .map(|x| x.parse().unwrap())
        .collect();
    let se = (row[3] * row[3] + row[4] * row[4] + row[5] * row[5]).sqrt() / 3.0;
    ((row[0] + row[1] + row[2]) / 3.0, se)
}

/// The path tracer's statistics on `scene`, checked against Mitsuba's image mean (within 4
/// combined standard errors or 1 %).
fn path_traced(scene: &Scene, name: &str) -> PixelStats {
    let pt = render_stats(scene, &settings(scene, Algorithm::Path, 1), 512);
    let (m, se_m) = mitsuba(name);
    let (p, se_p) = (pt.image_mean(), pt.image_mean_se());
    eprintln!("{name}: pt {p} (se {se_p}), mitsuba {m} (se {se_m})");
    let bound = (0.01 * m).max(4.0 * (se_p * se_p + se_m * se_m).sqrt());
    assert!((p - m).abs() < bound, "{name}: pt {p}, mitsuba {m}");
    pt
}

/// `other` against the path tracer: image means within 4 standard errors of their difference
/// and 2 % (a lost caustic moves the mean by more: see docs/rough-lobes.md), at most 3 % of
/// pixel channels beyond 4 sigma and mean z^2 below 4 (photon mapping's radius blurs a sharp
/// caustic's edge, a bias the per-pixel statistics see at a few pixels).
fn assert_agrees(name: &str, label: &str, pt: &PixelStats, other: &PixelStats) {
    let (a, b) = (pt.image_mean(), other.image_mean());
    let se = (pt.image_mean_se().powi(2) + other.image_mean_se().powi(2)).sqrt();
    let z = z_scores(pt, other);
    let beyond = z.iter().filter(|z| z.abs() > 4.0).count();
    let mean_z2 = z.iter().map(|z| z * z).sum::<f64>() / z.len() as f64;
    eprintln!(
        "{name}: pt {a} {label} {b} (se of difference {se}, relative {:+.2e}); {beyond} of {} \
         beyond 4 sigma, mean z^2 {mean_z2:.2}",
        (b - a) / a,
        z.len()
    );
    let bound = (4.0 * se).min(0.02 * a);
    assert!(
        (a - b).abs() < bound,
        "{name}: image means pt {a} {label} {b}, se of difference {se}"
    );
    assert!(
        beyond * 100 <= 3 * z.len(),
        "{name} {label}: {beyond} beyond 4 sigma"
    );
    assert!(mean_z2 < 4.0, "{name} {label}: mean z^2 {mean_z2}");
}

/// ppm, sppm and vcm against the path tracer on `kind` at every roughness ([`assert_agrees`]).
fn agree_at_every_roughness(kind: &str) {
    for alpha in ROUGHNESSES {
        let name = format!("rough_lobe_{kind}/{alpha}");
        let scene = scene(kind, alpha);
        let pt = path_traced(&scene, &name);
        let ppm = render_stats(&scene, &settings(&scene, Algorithm::Ppm, 2), 64);
        assert_agrees(&name, "ppm", &pt, &ppm);
        // A fixed merge radius of 0.05, a quarter of the auto one (the pixel footprint): at
        // the auto radius merging on the curved rough surfaces keeps a kernel bias of up to 2 %
        // at 128 iterations, which shrinks with the radius (docs/rough-lobes.md).
        let vcm_settings = RenderSettings {
            radius: Radius::World(0.05),
            ..settings(&scene, Algorithm::Vcm, 3)
        };
        let vcm = render_stats(&scene, &vcm_settings, 512);
        assert_agrees(&name, "vcm", &pt, &vcm);
        let sppm = sppm_stats(&scene, &settings(&scene, Algorithm::Sppm, 4), 16, 32);
        assert_agrees(&name, "sppm", &pt, &sppm);
    }
}

#[test]
fn rough_metal_caustic_at_every_roughness() {
    agree_at_every_roughness("metal");
}

#[test]
fn frosted_glass_caustic_at_every_roughness() {
    agree_at_every_roughness("glass");
}
