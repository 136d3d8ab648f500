//! A scene far from the world origin loads as the same scene at the origin: with the camera
//! farther than `FAR_CAMERA` from the origin, points are made camera-relative in double
//! precision before they are rounded to f32. Rounded first, a
//! scene 1e6 units away snapped to a grid of 1/16 unit (a lamp 2 cm under the ceiling landed
//! on it, and pt's image lost 40% of its light).

mod common;

use common::write_files;
use glam::{Vec2, Vec3};
use ppm_core::light::Light;
use ppm_core::scene::SceneBuilder;
use ppm_scene::{load_scene, load_scene_builder};

/// A camera, a sphere, a quad 1 mm above a floor quad, a point light, a spot light aimed at
/// a point 1 cm from the floor's centre and an OBJ triangle 2 mm above the floor, all moved
/// by `offset`.
fn files(offset: [f64; 3]) -> Vec<(&'static str, String)> {
    let p = |x: f64, y: f64, z: f64| {
        format!("[{}, {}, {}]", x + offset[0], y + offset[1], z + offset[2])
    };
    let yaml = format!(
        "camera: {{ position: {}, look_at: {}, up: [0, 1, 0], fov: 40 }}
resolution: [16, 16]
materials:
  white: {{ type: diffuse, color: [0.7, 0.7, 0.7] }}
  lamp: {{ type: diffuse, color: [0.5, 0.5, 0.5], emission: [10, 10, 10] }}
objects:
  - {{ type: quad, corner: {}, edge_u: [0, 0, 2], edge_v: [2, 0, 0], material: white }}
  - {{ type: quad, corner: {}, edge_u: [0, 0, 0.5], edge_v: [0.5, 0, 0], material: lamp }}
  - {{ type: sphere, center: {}, radius: 0.3, material: white }}
  - {{ type: mesh, file: tri.obj, material: white }}
lights:
  - {{ type: point, position: {}, intensity: [1, 1, 1] }}
  - {{ type: spot, position: {}, look_at: {}, intensity: [1, 1, 1], cone_angle: 20 }}
",
        p(0.0, 1.0, 3.9),
        p(0.0, 0.5, 0.0),
        p(-1.0, 0.0, -1.0),
        p(-0.25, 0.001, -0.25),
        p(0.4, 0.3, 0.1),
        p(0.0, 1.9, 0.0),
        p(0.0, 1.9, 0.0),
        p(0.01, 0.0, 0.0),
    );
    let v = |x: f64, y: f64, z: f64| {
        format!("v {} {} {}\n", x + offset[0], y + offset[1], z + offset[2])
    };
    let obj = format!(
        "{}{}{}f 1 2 3\n",
        v(-0.5, 0.002, 0.5),
        v(0.5, 0.002, 0.5),
        v(0.0, 0.002, -0.5)
    );
    vec![("far.yml", yaml), ("tri.obj", obj)]
}

fn load(test: &str, offset: [f64; 3]) -> SceneBuilder {
    let files = files(offset);
    let files: Vec<(&str, &str)> = files.iter().map(|(n, t)| (*n, t.as_str())).collect();
    let dir = write_files(test, &files);
    let (builder, warnings) = load_scene_builder(&dir.join("far.yml")).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    let scene = load_scene(&dir.join("far.yml")).unwrap().scene;
    let world_camera = Vec3::new(
        offset[0] as f32,
        1.0 + offset[1] as f32,
        3.9 + offset[2] as f32,
    );
    assert!(
        (scene.origin - world_camera).abs().max_element()
            <= 1e-7 * world_camera.abs().max_element().max(1.0),
        "{} against {world_camera}",
        scene.origin
    );
    builder
}

#[test]
fn a_scene_far_from_the_origin_loads_as_it_does_at_the_origin() {
    let near = load("far_scene_near", [0.0, 0.0, 0.0]);
    for offset in [[1e6, -2e6, 5e5], [3.3e5, 0.0, -7.7e6]] {
        let far = load("far_scene_far", offset);
        let close = |a: Vec3, b: Vec3, what: &str| {
            assert!(
                (a - b).abs().max_element() < 1e-6,
                "{what} at {offset:?}: {a} against {b}"
            );
        };
        // Compared as the renderer stores them: relative to the camera.
        let (far_camera, near_camera) = (far.camera.position, near.camera.position);
        close(far_camera, Vec3::ZERO, "the camera (made relative at load)");
        let centre = |b: &SceneBuilder| b.camera.generate_ray(Vec2::new(8.0, 8.0)).dir;
        close(centre(&far), centre(&near), "the centre pixel's ray");
        for (a, b) in far.meshes.iter().zip(&near.meshes) {
            for (pa, pb) in a.positions.iter().zip(&b.positions) {
                close(*pa - far_camera, *pb - near_camera, "a mesh vertex");
            }
        }
        assert_eq!(far.meshes.len(), near.meshes.len());
        close(
            far.spheres[0].center - far_camera,
            near.spheres[0].center - near_camera,
            "the sphere",
        );
        let (Light::Point(far_point), Light::Point(near_point)) =
            (far.lights[0].clone(), near.lights[0].clone())
        else {
            panic!("{:?}", far.lights);
        };
        close(
            far_point.position - far_camera,
            near_point.position - near_camera,
            "the point light",
        );
        let (Light::Spot(far_spot), Light::Spot(near_spot)) =
            (far.lights[1].clone(), near.lights[1].clone())
        else {
            panic!("{:?}", far.lights);
        };
        close(
            far_spot.position - far_camera,
            near_spot.position - near_camera,
            "the spot light",
        );
        // Its axis from two points 1.9 apart: rounded before the subtraction it would be off
        // by 1/16 unit at 1e6 (2 degrees).
        close(
            far_spot.direction(),
            near_spot.direction(),
            "the spot's axis",
        );
    }
}
