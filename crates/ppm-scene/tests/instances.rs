//! Instances in the scene formats: scene format v1's `instances:` (an identity placement hits
//! bit for bit like the mesh without it; transformed placements like the same mesh placed by
//! `transform`), Mitsuba's `shapegroup`/`instance` like the shapes placed directly, the
//! fingerprint, the errors; and `transform:` on lights, equal to the light written already
//! placed.

mod common;

use common::write_files;
use glam::{Vec2, Vec3};
use ppm_core::geometry::Hit;
use ppm_core::light::Light;
use ppm_core::scene::{Scene, SceneBuilder};
use ppm_scene::mitsuba::parse_mitsuba;
use ppm_scene::{content_hash, parse_scene};
use std::path::Path;

/// A bumpy tetrahedron-like OBJ with vertex normals.
const OBJ: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n\
vn -1 -1 -1\nvn 1 0 0\nvn 0 1 0\nvn 0 0 1\n\
f 1//1 3//3 2//2\nf 1//1 2//2 4//4\nf 1//1 4//4 3//3\nf 2//2 3//3 4//4\n";

/// A scene with `objects` (YAML list items) and `lights`, camera at `camera`, the OBJ as
/// `tet.obj`.
fn load(test: &str, camera: &str, objects: &str, lights: &str) -> Result<SceneBuilder, String> {
    let yaml = format!(
        "camera: {{ position: {camera}, look_at: [0.3, 0.3, -3], up: [0, 1, 0], fov: 60 }}\n\
         resolution: [32, 32]\n\
         materials:\n  white: {{ type: diffuse, color: [0.7, 0.7, 0.7] }}\n\
         objects:\n  - {{ type: quad, corner: [-5, -1, -9], edge_u: [0, 0, 9], edge_v: [10, 0, 0], material: white }}\n{objects}\n\
         lights: [{lights}]\n"
    );
    let dir = write_files(test, &[("scene.yml", &yaml), ("tet.obj", OBJ)]);
    parse_scene(&yaml, &dir.join("scene.yml"))
        .map(|(b, _)| b)
        .map_err(|e| e.to_string())
}

const POINT: &str = "{ type: point, position: [0, 3, 0], intensity: [5, 5, 5] }";

/// The camera rays' hits through a grid of film points.
fn hits(scene: &Scene) -> Vec<Option<Hit>> {
    let (w, h) = (scene.camera.width, scene.camera.height);
    (0..w * h)
        .map(|i| {
            let film = Vec2::new((i % w) as f32 + 0.37, (i / w) as f32 + 0.61);
            scene.intersect(&scene.camera.generate_ray(film))
        })
        .collect()
}

fn bits(h: &Hit) -> Vec<u32> {
    let v = |v: Vec3| v.to_array().map(f32::to_bits);
    let mut out = vec![h.t.to_bits(), h.material, h.prim];
    out.extend(v(h.p));
    out.extend(v(h.ng));
    out.extend(v(h.ns));
    out.extend(h.uv.to_array().map(f32::to_bits));
    out
}

/// `instances: [{}]` (camera at the origin) hits bit for bit like the mesh without it.
#[test]
fn an_identity_instance_hits_like_the_mesh_bit_for_bit() {
    let plain = "  - { type: mesh, file: tet.obj, material: white }";
    let identity = "  - { type: mesh, file: tet.obj, material: white, instances: [{}] }";
    let at_origin = "[0, 0, 0]";
    let a = load("inst_plain", at_origin, plain, POINT).unwrap();
    let b = load("inst_identity", at_origin, identity, POINT).unwrap();
    assert_eq!((b.instanced_meshes.len(), b.instances.len()), (1, 1));
    assert_ne!(content_hash(&a), content_hash(&b));
    // Rays from around the origin in all directions (the tetrahedron sits at the origin).
    let (a, b) = (a.build().unwrap(), b.build().unwrap());
    let (mut seen, mut mesh_hits) = (0, 0);
    for dir in 0..2000 {
        let u = ppm_core::sampling::Rng::new(1, 0, dir).uniform2();
        let d = ppm_core::sampling::uniform_sphere(u);
        let ray = ppm_core::geometry::Ray::new(Vec3::new(0.2, 0.3, 0.25) * (dir % 3) as f32, d);
        let (x, y) = (a.intersect(&ray), b.intersect(&ray));
        assert_eq!(x.as_ref().map(bits), y.as_ref().map(bits), "ray {dir}");
        assert_eq!(a.occluded(&ray), b.occluded(&ray));
        seen += x.is_some() as usize;
        mesh_hits += x.is_some_and(|h| h.prim >= 2) as usize;
    }
    assert!(seen > 500 && mesh_hits > 200, "{seen} {mesh_hits}");
}

/// Placements by `instances` answer like the same mesh placed by `transform` as separate
/// objects, mirror included (to float precision; the camera away from the origin, so the
/// camera-relative shift is composed into every placement).
#[test]
fn instances_hit_like_transformed_copies() {
    let steps = [
        "[{ translate: [0, 0, -3] }]",
        "[{ rotate: { axis: [0, 1, 0], angle: 40 } }, { translate: [1.5, 0, -4] }]",
        "[{ scale: [-1, 1.5, 1] }, { translate: [-1.5, 0.2, -3.5] }]",
    ];
    let copies: Vec<String> = (steps.iter())
        .map(|s| format!("  - {{ type: mesh, file: tet.obj, material: white, transform: {s} }}"))
        .collect();
    let list: Vec<String> = steps
        .iter()
        .map(|s| format!("{{ transform: {s} }}"))
        .collect();
    let placed = format!(
        "  - {{ type: mesh, file: tet.obj, material: white, instances: [{}] }}",
        list.join(", ")
    );
    let camera = "[0.2, 0.3, 3]";
    let a = load("inst_copies", camera, &copies.join("\n"), POINT).unwrap();
    let b = load("inst_placed", camera, &placed, POINT).unwrap();
    assert_eq!((b.instanced_meshes.len(), b.instances.len()), (1, 3));
    let (a, b) = (a.build().unwrap(), b.build().unwrap());
    let (mut compared, mut differ) = (0, 0);
    for (i, (x, y)) in hits(&a).iter().zip(hits(&b)).enumerate() {
        match (x, y) {
            (Some(x), Some(y)) if x.prim == y.prim => {
                assert!((x.t - y.t).abs() < 1e-4 * x.t, "{i}: {x:?} {y:?}");
                assert!(x.ng.abs_diff_eq(y.ng, 1e-5), "{i}: {x:?} {y:?}");
                assert!(x.ns.abs_diff_eq(y.ns, 1e-4), "{i}: {x:?} {y:?}");
                compared += (x.prim >= 2) as usize;
            }
            (None, None) => {}
            _ => differ += 1,
        }
    }
    assert!(compared > 20 && differ < 4, "{compared} {differ}");
}

#[test]
fn instance_errors_name_the_field() {
    let cases = [
        (
            "  - { type: mesh, file: tet.obj, material: white, instances: [] }",
            "objects[1].instances: an empty list",
        ),
        (
            "  - { type: mesh, file: tet.obj, material: white, instances: [{ transform: [{ scale: [1, 0, 1] }] }] }",
            "objects[1].instances[0].transform[0].scale",
        ),
        (
            "  - { type: sphere, center: [0, 0, 0], radius: 1, material: white, instances: [{}] }",
            "instances",
        ),
        (
            "  - { type: mesh, file: tet.obj, material: white, instances: [{ move: 1 }] }",
            "unknown field `move`",
        ),
    ];
    for (objects, needle) in cases {
        let e = load("inst_errors", "[0, 0, 3]", objects, POINT)
            .err()
            .expect(objects);
        assert!(e.contains(needle), "{needle}: {e}");
    }
}

/// Mitsuba's `shapegroup` placed by two `instance`s: one mesh, two placements, hitting like
/// the same rectangles placed directly.
#[test]
fn mitsuba_shapegroups_become_instances() {
    let head = r#"<scene version="3.0.0">
<sensor type="perspective"><transform name="to_world"><lookat origin="0,0,5" target="0,0,0" up="0,1,0"/></transform>
<film type="hdrfilm"><integer name="width" value="24"/><integer name="height" value="24"/></film></sensor>
<emitter type="point"><point name="position" x="0" y="3" z="3"/><rgb name="intensity" value="5"/></emitter>
<bsdf type="diffuse" id="w"/>"#;
    let placements = [
        r#"<translate x="-1"/>"#,
        r#"<rotate y="1" angle="30"/><scale x="-0.5"/><translate x="1" z="-1"/>"#,
    ];
    let shape = r#"<shape type="rectangle"><ref id="w"/><transform name="to_world"><rotate x="1" angle="20"/></transform></shape>"#;
    let direct: String = placements
        .iter()
        .map(|p| format!(r#"<shape type="rectangle"><ref id="w"/><transform name="to_world"><rotate x="1" angle="20"/>{p}</transform></shape>"#))
        .collect();
    let grouped = format!(
        r#"<shape type="shapegroup" id="g">{shape}</shape>{}"#,
        placements
            .iter()
            .map(|p| format!(r#"<shape type="instance"><ref id="g"/><transform name="to_world">{p}</transform></shape>"#))
            .collect::<String>()
    );
    let load = |body: &str| {
        parse_mitsuba(
            &format!("{head}{body}</scene>"),
            Path::new("scene.xml"),
            &[],
        )
        .unwrap()
        .0
    };
    let (a, b) = (load(&direct), load(&grouped));
    assert_eq!((b.instanced_meshes.len(), b.instances.len()), (1, 2));
    let (a, b) = (a.build().unwrap(), b.build().unwrap());
    let mut compared = 0;
    for (i, (x, y)) in hits(&a).iter().zip(hits(&b)).enumerate() {
        match (x, y) {
            (Some(x), Some(y)) => {
                assert!((x.t - y.t).abs() < 1e-4 * x.t, "{i}: {x:?} {y:?}");
                assert!(x.ng.abs_diff_eq(y.ng, 1e-5), "{i}: {x:?} {y:?}");
                compared += 1;
            }
            (x, y) => assert_eq!(x.is_some(), y.is_some(), "{i}"),
        }
    }
    assert!(compared > 100, "{compared}");
}

/// The lights a scene with `lights` (YAML list items) gets, camera at (0, 0, 3).
fn lights(test: &str, lights: &str) -> Vec<Light> {
    load(test, "[0, 0, 3]", "", lights).unwrap().lights
}

/// Intensity arriving at a few points from a delta light, for comparison.
fn received(light: &Light) -> Vec<Vec3> {
    let points = [
        Vec3::new(0.3, -1.0, 0.2),
        Vec3::new(-2.0, 0.5, -1.0),
        Vec3::new(1.0, 1.0, -4.0),
    ];
    points
        .iter()
        .map(|&p| {
            light
                .sample_direct(p, Vec2::splat(0.5))
                .map_or(Vec3::ZERO, |s| s.li * s.wi.dot(Vec3::Y).abs().max(1.0))
        })
        .collect()
}

/// A transformed light equals the light written already placed: a spot rotated and moved,
/// a point moved, a directional rotated (to float precision), an environment turned by a
/// transform as by `rotate` (bit for bit).
#[test]
fn transformed_lights_equal_the_lights_placed_by_hand() {
    let pairs = [
        (
            "{ type: spot, intensity: [4, 4, 4], direction: [0, 0, -1], cone_angle: 30, transform: [{ rotate: { axis: [1, 0, 0], angle: -90 } }, { translate: [0.5, 2, -1] }] }",
            "{ type: spot, position: [0.5, 2, -1], intensity: [4, 4, 4], direction: [0, -1, 0], cone_angle: 30 }",
        ),
        (
            "{ type: spot, position: [1, 0, 0], intensity: [4, 4, 4], look_at: [1, -1, 0], cone_angle: 50, falloff_start: 20, transform: [{ rotate: { axis: [0, 0, 1], angle: 90 } }] }",
            "{ type: spot, position: [0, 1, 0], intensity: [4, 4, 4], direction: [1, 0, 0], cone_angle: 50, falloff_start: 20 }",
        ),
        (
            "{ type: point, position: [1, 1, 1], intensity: [3, 2, 1], transform: [{ scale: 2 }, { translate: [0, 1, -2] }] }",
            "{ type: point, position: [2, 3, 0], intensity: [3, 2, 1] }",
        ),
        (
            "{ type: directional, direction: [0, -1, 0], irradiance: [1, 1, 1], transform: [{ rotate: { axis: [0, 0, 1], angle: 30 } }] }",
            "{ type: directional, direction: [0.5, -0.8660254, 0], irradiance: [1, 1, 1] }",
        ),
    ];
    for (i, (placed, by_hand)) in pairs.iter().enumerate() {
        let (a, b) = (
            lights(&format!("light_t{i}"), placed),
            lights(&format!("light_h{i}"), by_hand),
        );
        for (x, y) in received(&a[0]).iter().zip(received(&b[0])) {
            assert!(
                (*x - y).abs().max_element() <= 1e-5 * y.max_element().max(1e-3),
                "{placed}: {x} {y}"
            );
        }
    }
    let a = lights("env_t", "{ type: environment, color: [1, 1, 1], transform: [{ rotate: { axis: [0, 1, 0], angle: 30 } }] }");
    let b = lights(
        "env_r",
        "{ type: environment, color: [1, 1, 1], rotate: { axis: [0, 1, 0], angle: 30 } }",
    );
    assert_eq!(format!("{:?}", a[0]), format!("{:?}", b[0]));
    let e = load(
        "env_scale",
        "[0, 0, 3]",
        "",
        "{ type: environment, color: [1, 1, 1], transform: [{ scale: 2 }] }",
    )
    .err()
    .unwrap();
    assert!(
        e.contains("lights[0].transform") && e.contains("only rotations"),
        "{e}"
    );
}
