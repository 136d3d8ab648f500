//! `transform:` on the objects of scene format v1: a transformed mesh, quad and sphere are the
//! pre-transformed ones (to rounding) and render the same image; a mirroring transform keeps
//! an area light emitting on its side; errors name the step and field.

mod common;

use common::write_files;
use glam::Vec3;
use ppm_core::integrator::{Algorithm, RenderSettings, Renderer};
use ppm_core::scene::SceneBuilder;
use ppm_scene::parse_scene;

/// A scene with `objects` (YAML list items) and `obj` as `tri.obj`, seen from (0, 1, 5).
fn load(test: &str, objects: &str, obj: &str) -> Result<SceneBuilder, String> {
    let yaml = format!(
        "camera: {{ position: [0, 1, 5], look_at: [0, 1, 0], up: [0, 1, 0], fov: 50 }}\n\
         resolution: [16, 16]\n\
         materials:\n  white: {{ type: diffuse, color: [0.7, 0.7, 0.7] }}\n  \
         lamp: {{ type: diffuse, color: [0, 0, 0], emission: [4, 4, 4] }}\n\
         objects:\n{objects}\n\
         lights: [{{ type: point, position: [0, 3, 3], intensity: [5, 5, 5] }}]\n"
    );
    let dir = write_files(test, &[("scene.yml", &yaml), ("tri.obj", obj)]);
    parse_scene(&yaml, &dir.join("scene.yml"))
        .map(|(b, _)| b)
        .map_err(|e| e.to_string())
}

fn positions(b: &SceneBuilder) -> Vec<Vec3> {
    b.meshes.iter().flat_map(|m| m.positions.clone()).collect()
}

fn image_mean(b: SceneBuilder) -> Vec3 {
    let scene = b.build().unwrap();
    let settings = RenderSettings {
        seed: 3,
        ..RenderSettings::for_algorithm(&scene, Algorithm::Path)
    };
    let mut r = Renderer::new(&scene, &settings);
    for _ in 0..16 {
        assert_eq!(r.iterate(&scene).rejected, 0);
    }
    r.image().mean()
}

/// (x, y, z) scaled by 2, rotated 90 degrees about +y ((x, y, z) -> (z, y, -x)), moved by
/// (1, 0.5, 0): the steps in the order written.
fn by_hand(p: Vec3) -> Vec3 {
    let s = 2.0 * p;
    Vec3::new(s.z, s.y, -s.x) + Vec3::new(1.0, 0.5, 0.0)
}

const STEPS: &str =
    "[{ scale: 2 }, { rotate: { axis: [0, 1, 0], angle: 90 } }, { translate: [1, 0.5, 0] }]";

#[test]
fn transformed_objects_are_the_pre_transformed_ones() {
    let corners = [
        Vec3::new(-0.5, 0.0, 0.25),
        Vec3::new(0.5, 0.0, -0.25),
        Vec3::new(0.0, 0.75, 0.0),
    ];
    let obj_of = |c: &[Vec3; 3]| {
        let v: String = c
            .iter()
            .map(|p| format!("v {} {} {}\n", p.x, p.y, p.z))
            .collect();
        v + "f 1 2 3\n"
    };
    let moved = corners.map(by_hand);
    let transformed = load(
        "transform_mesh",
        &format!(
            "  - {{ type: mesh, file: tri.obj, material: white, transform: {STEPS} }}\n  \
             - {{ type: quad, corner: [0, 0, 0], edge_u: [0.5, 0, 0], edge_v: [0, 0.5, 0], material: lamp, transform: {STEPS} }}\n  \
             - {{ type: sphere, center: [0.2, 0.3, 0.4], radius: 0.1, material: white, transform: {STEPS} }}"
        ),
        &obj_of(&corners),
    )
    .unwrap();
    let (u, v, c) = (
        by_hand(Vec3::new(0.5, 0.0, 0.0)) - by_hand(Vec3::ZERO),
        by_hand(Vec3::new(0.0, 0.5, 0.0)) - by_hand(Vec3::ZERO),
        by_hand(Vec3::new(0.2, 0.3, 0.4)),
    );
    let fmt = |v: Vec3| format!("[{}, {}, {}]", v.x, v.y, v.z);
    let written = load(
        "transform_mesh_written",
        &format!(
            "  - {{ type: mesh, file: tri.obj, material: white }}\n  \
             - {{ type: quad, corner: {}, edge_u: {}, edge_v: {}, material: lamp }}\n  \
             - {{ type: sphere, center: {}, radius: 0.2, material: white }}",
            fmt(by_hand(Vec3::ZERO)),
            fmt(u),
            fmt(v),
            fmt(c)
        ),
        &obj_of(&moved),
    )
    .unwrap();
    let (a, b) = (positions(&transformed), positions(&written));
    assert_eq!(a.len(), b.len());
    for (a, b) in a.iter().zip(&b) {
        assert!(a.abs_diff_eq(*b, 1e-6), "{a} vs {b}");
    }
    let (sa, sb) = (&transformed.spheres[0], &written.spheres[0]);
    assert!(sa.center.abs_diff_eq(sb.center, 1e-6) && (sa.radius - sb.radius).abs() < 1e-7);
    let (ia, ib) = (image_mean(transformed), image_mean(written));
    eprintln!("transformed {ia}, written {ib}");
    assert!(ia.max_element() > 0.0);
    assert!(ia.abs_diff_eq(ib, 1e-5 * ib.max_element()), "{ia} vs {ib}");
}

/// A lamp facing the camera mirrored in x (scale [-1, 1, 1]) still faces it: the mirror
/// reverses the triangles' winding, so the geometric normal is the mirrored one (+z) and the
/// image is the unmirrored lamp's (it is symmetric about x = 0).
#[test]
fn a_mirrored_area_light_keeps_emitting_toward_its_side() {
    let lamp = |transform: &str| {
        load(
            "transform_mirror",
            &format!(
                "  - {{ type: quad, corner: [-0.5, 0.5, 0], edge_u: [1, 0, 0], edge_v: [0, 1, 0], material: lamp{transform} }}"
            ),
            "",
        )
        .unwrap()
    };
    let plain = image_mean(lamp(""));
    let mirrored = image_mean(lamp(", transform: [{ scale: [-1, 1, 1] }]"));
    let turned = image_mean(lamp(
        ", transform: [{ rotate: { axis: [0, 1, 0], angle: 180 } }]",
    ));
    eprintln!("plain {plain}, mirrored {mirrored}, turned away {turned}");
    assert!(plain.x > 0.1, "{plain}");
    assert!(mirrored.abs_diff_eq(plain, 1e-6), "{mirrored} vs {plain}");
    // Turning it around (no mirror) shows its back: no emission reaches the camera.
    assert!(turned.x < 0.01 * plain.x, "{turned}");
}

#[test]
fn transform_errors_name_the_step() {
    let sphere = |t: &str| {
        format!("  - {{ type: sphere, center: [0, 1, 0], radius: 0.5, material: white, transform: {t} }}")
    };
    for (objects, expected) in [
        (
            sphere("[{ translate: [0, 1, 0] }, { rotate: { axis: [0, 0, 0], angle: 3 } }]"),
            "objects[0].transform[1].rotate.axis",
        ),
        (sphere("[{ scale: [1, 2, 1] }]"), "objects[0].transform"),
        (
            sphere("[{ scale: 2, translate: [0, 1, 0] }]"),
            "objects[0].transform[0]",
        ),
        (
            sphere("[{ matrix: [1, 0, 0] }]"),
            "objects[0].transform[0].matrix",
        ),
        (sphere("[{ scale: 0 }]"), "objects[0].transform[0].scale"),
        (sphere("[{ shear: 2 }]"), "shear"),
        (
            sphere("[{ look_at: { origin: [0, 0, 0], target: [0, 0, 0], up: [0, 1, 0] } }]"),
            "objects[0].transform[0].look_at",
        ),
    ] {
        let Err(e) = load("transform_errors", &objects, "") else {
            panic!("loaded: {objects}");
        };
        assert!(e.contains(expected), "{objects}: {e}");
    }
    // A sphere takes rotations, mirrors and uniform scales.
    let b = load(
        "transform_sphere",
        &sphere(
            "[{ scale: -2 }, { look_at: { origin: [0, 1, 0], target: [1, 1, 1], up: [0, 1, 0] } }]",
        ),
        "",
    )
    .unwrap();
    assert_eq!(b.spheres[0].radius, 1.0);
}
