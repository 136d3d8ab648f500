//! Spot lights in scene format v1: the fields, their defaults and the errors that name them.

mod common;

use common::CAMERA;
use glam::Vec3;
use ppm_core::light::{Light, LightKind};
use ppm_core::scene::SceneBuilder;
use ppm_scene::parse_scene;
use std::path::Path;

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
    parse_scene(&scene(lights), Path::new("dir/spot.yml")).unwrap_or_else(|e| panic!("{e}"))
}

fn error(lights: &str) -> String {
    match parse_scene(&scene(lights), Path::new("dir/spot.yml")) {
        Ok(_) => panic!("no error for {lights}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn a_spot_light_loads_with_its_axis_and_angles() {
    let (b, warnings) = load(
        "  - { type: spot, position: [0, 1.9, 0], direction: [0, -2, 0], intensity: [3, 2, 1], cone_angle: 30, falloff_start: 20 }\n",
    );
    // Lit by a spot light only: no "no light" warning.
    assert!(warnings.is_empty(), "{warnings:?}");
    let [Light::Spot(spot)] = b.lights[..] else {
        panic!("{:?}", b.lights);
    };
    assert_eq!(spot.position, Vec3::new(0.0, 1.9, 0.0));
    assert_eq!(spot.direction(), Vec3::NEG_Y);
    assert_eq!(spot.intensity, Vec3::new(3.0, 2.0, 1.0));
    assert_eq!(spot.cone_angle(), 30f32.to_radians());
    assert_eq!(spot.falloff_start(), 20f32.to_radians());
    assert_eq!(b.lights[0].kind(), LightKind::DeltaPosition);
    // `look_at` gives the same axis; without `falloff_start` the edge is sharp.
    let (b, _) = load(
        "  - { type: spot, position: [0, 1.9, 0], look_at: [0, 0, 0], intensity: [3, 2, 1], cone_angle: 30 }\n",
    );
    let [Light::Spot(aimed)] = b.lights[..] else {
        panic!("{:?}", b.lights);
    };
    assert_eq!(aimed.direction(), spot.direction());
    assert_eq!(aimed.falloff_start(), aimed.cone_angle());
}

#[test]
fn a_scene_without_lights_is_still_warned_about() {
    let (_, warnings) = load("");
    assert!(
        warnings.iter().any(|w| w.contains("no light")),
        "{warnings:?}"
    );
}

#[test]
fn spot_light_errors_name_the_field() {
    let spot = |fields: &str| {
        error(&format!(
            "  - {{ type: point, position: [0, 1, 0], intensity: [1, 1, 1] }}\n  - {{ type: spot, position: [0, 1.9, 0], intensity: [1, 1, 1], {fields} }}\n"
        ))
    };
    let cases = [
        (
            "direction: [0, -1, 0]",
            "lights[1]: a spot light needs `cone_angle`",
        ),
        (
            "cone_angle: 30",
            "lights[1]: a spot light needs `direction` or `look_at`",
        ),
        (
            "direction: [0, -1, 0], look_at: [0, 0, 0], cone_angle: 30",
            "lights[1]: a spot light takes `direction` or `look_at`, not both",
        ),
        (
            "direction: [0, 0, 0], cone_angle: 30",
            "lights[1].direction: the axis has no direction",
        ),
        (
            "look_at: [0, 1.9, 0], cone_angle: 30",
            "lights[1].look_at: the axis has no direction",
        ),
        (
            "direction: [0, -1, 0], cone_angle: 30, falloff_start: 31",
            "lights[1].falloff_start: 31 degrees is beyond cone_angle (30 degrees)",
        ),
        (
            "direction: [0, -1, 0], cone_angle: 190",
            "lights[1].cone_angle: 190 degrees is more than 180",
        ),
        (
            "direction: [0, -1, 0], cone_angle: 0",
            "lights[1].cone_angle",
        ),
        (
            "direction: [0, -1, 0], cone_angle: 30, falloff_start: -1",
            "lights[1].falloff_start",
        ),
        ("direction: [0, -1, 0], cone_angle: 30, radius: 1", "radius"),
    ];
    for (fields, expected) in cases {
        let err = spot(fields);
        assert!(
            err.starts_with("dir/spot.yml") && err.contains(expected),
            "{fields}: {err}"
        );
    }
    // A point light takes none of a spot light's fields.
    let err =
        error("  - { type: point, position: [0, 1, 0], intensity: [1, 1, 1], cone_angle: 30 }\n");
    assert!(
        err.contains("lights[0]") && err.contains("`cone_angle` does not apply to a point light"),
        "{err}"
    );
}
