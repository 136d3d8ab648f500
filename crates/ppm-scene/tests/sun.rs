//! Directional lights (the sun) in scene format v1: the fields, the errors that name them,
//! the fingerprint; and the sun's caustic through a glass sphere against Mitsuba 3.

mod common;

use common::CAMERA;
use glam::Vec3;
use ppm_core::light::{Light, LightKind};
use ppm_core::prelude::*;
use ppm_scene::{content_hash, load_scene, parse_scene};
use std::path::{Path, PathBuf};

/// A floor, no emissive material, and `lights` as the `lights:` list.
fn scene(lights: &str) -> String {
    format!(
        "{CAMERA}materials:
  white: {{ type: diffuse, color: [0.7, 0.7, 0.7] }}
objects:
  - {{ type: quad, corner: [-1, 0, -1], edge_u: [0, 0, 2], edge_v: [2, 0, 0], material: white }}
lights:
{lights}"
    )
}

fn load(lights: &str) -> (SceneBuilder, Vec<String>) {
    parse_scene(&scene(lights), Path::new("dir/sun.yml")).unwrap_or_else(|e| panic!("{e}"))
}

fn error(lights: &str) -> String {
    match parse_scene(&scene(lights), Path::new("dir/sun.yml")) {
        Ok(_) => panic!("no error for {lights}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn a_directional_light_loads_with_its_direction_and_irradiance() {
    let (b, warnings) =
        load("  - { type: directional, direction: [0, -2, 0], irradiance: [3, 2, 1] }\n");
    assert!(warnings.is_empty(), "{warnings:?}");
    let [Light::Directional(sun)] = b.lights[..] else {
        panic!("{:?}", b.lights);
    };
    assert_eq!(sun.direction(), Vec3::NEG_Y);
    assert_eq!(sun.irradiance, Vec3::new(3.0, 2.0, 1.0));
    assert_eq!(b.lights[0].kind(), LightKind::DeltaDirection);
    // Built, it covers the floor's bounding sphere: R = sqrt(2) (plus 0.1%), Phi = E pi R^2.
    let scene = b.build().unwrap();
    let power = scene.lights[0].power().x;
    let exact = 3.0 * std::f32::consts::PI * 2.0 * 1.001f32.powi(2);
    assert!((power - exact).abs() < 1e-5 * exact, "{power} vs {exact}");
}

#[test]
fn errors_name_the_field() {
    let has = |lights: &str, parts: &[&str]| {
        let e = error(lights);
        for part in parts {
            assert!(e.contains(part), "{e:?} lacks {part:?}");
        }
    };
    has(
        "  - { type: directional, direction: [0, -1, 0] }\n",
        &["dir/sun.yml", "lights[0]", "needs `irradiance`"],
    );
    has(
        "  - { type: directional, irradiance: [1, 1, 1] }\n",
        &["lights[0]", "needs `direction`"],
    );
    has(
        "  - { type: directional, direction: [0, 0, 0], irradiance: [1, 1, 1] }\n",
        &["lights[0].direction", "zero direction"],
    );
    has(
        "  - { type: directional, direction: [0, -1, 0], irradiance: [1, -1, 1] }\n",
        &["lights[0].irradiance", ">= 0"],
    );
    has(
        "  - { type: directional, position: [0, 1, 0], direction: [0, -1, 0], irradiance: [1, 1, 1] }\n",
        &["lights[0]", "`position` does not apply to a directional light"],
    );
    // Point and spot lights still name what they lack.
    has(
        "  - { type: point, intensity: [1, 1, 1] }\n",
        &["lights[0]", "a point light needs `position`"],
    );
    has(
        "  - { type: spot, position: [0, 1, 0], direction: [0, -1, 0], cone_angle: 30 }\n",
        &["lights[0]", "a spot light needs `intensity`"],
    );
    has(
        "  - { type: point, position: [0, 1, 0], irradiance: [1, 1, 1] }\n",
        &["`irradiance` does not apply to a point light"],
    );
}

#[test]
fn the_fingerprint_sees_the_direction_and_the_irradiance() {
    let hash = |lights: &str| content_hash(&load(lights).0);
    let base = hash("  - { type: directional, direction: [0, -1, 0], irradiance: [1, 1, 1] }\n");
    for other in [
        "  - { type: directional, direction: [0, -1, 0.1], irradiance: [1, 1, 1] }\n",
        "  - { type: directional, direction: [0, -1, 0], irradiance: [1, 1, 2] }\n",
        "  - { type: point, position: [0, -1, 0], intensity: [1, 1, 1] }\n",
    ] {
        assert_ne!(hash(other), base, "{other}");
    }
    let same = hash("  - { type: directional, direction: [0, -3, 0], irradiance: [1, 1, 1] }\n");
    assert_eq!(same, base, "the direction's length does not matter");
}

/// `crates/ppm-core/tests/data/<name>`.
fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../ppm-core/tests/data")
        .join(name)
}

/// The mean and standard error that `scripts/mitsuba/sun_caustic.py` wrote.
fn mitsuba_reference() -> (f64, f64) {
    let text = std::fs::read_to_string(data("sun_caustic_mitsuba.txt")).unwrap();
    let value = |key: &str| -> f64 {
        text.lines()
            .find_map(|l| l.strip_prefix(key))
            .unwrap_or_else(|| panic!("no {key} in the table"))
            .trim()
            .parse()
            .unwrap()
    };
    (value("mean "), value("standard_error "))
}

#[test]
fn the_sun_caustic_through_a_glass_sphere_matches_mitsuba() {
    // Mitsuba 3's light tracer (ptracer) and ppm's photon mapping on the same scene, written
    // by hand in both formats: the floor lit by the sun, the sphere's shadow and its caustic.
    // ppm: independent iterations of 50k photons; their spread gives the standard error.
    let loaded = load_scene(&data("sun_caustic.yml")).unwrap();
    let scene = loaded.scene;
    let settings = RenderSettings {
        seed: 7,
        photons: 50_000,
        ..RenderSettings::for_algorithm(&scene, Algorithm::Ppm)
    };
    let mut renderer = Renderer::new(&scene, &settings);
    let mut means = Vec::new();
    for _ in 0..24 {
        renderer.iterate(&scene);
        let estimates = renderer.last_estimates();
        let sum: f64 = estimates.iter().map(|v| v.element_sum() as f64).sum();
        means.push(sum / (3 * estimates.len()) as f64);
    }
    let n = means.len() as f64;
    let mean = means.iter().sum::<f64>() / n;
    let var = means.iter().map(|m| (m - mean).powi(2)).sum::<f64>() / (n - 1.0);
    let se = (var / n).sqrt();
    let (reference, reference_se) = mitsuba_reference();
    eprintln!("sun caustic: ppm {mean} +- {se}, Mitsuba {reference} +- {reference_se}");
    assert!(
        (mean - reference).abs() < 0.01 * reference,
        "ppm image mean {mean} +- {se}, Mitsuba 3 {reference} +- {reference_se}"
    );
}
