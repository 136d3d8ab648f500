//! The scene fingerprint (`content_hash`) that saved renders record: old scenes keep the value
//! they always had (so their renders still resume and merge), and every kind of content
//! changes it.

mod common;

use common::{scenes_dir, write_files};
use ppm_scene::{content_hash, load_scene_builder, parse_scene};
use std::path::Path;

/// A scene with every part the shipped scenes lack: point lights, an inward sphere, every
/// render default, numbers Rust prints in exponent form, an OBJ with vertex normals and a
/// quoted material name.
const EVERY_FIELD: &str = "\
camera: { position: [0.5, 1, 3.9], look_at: [0, 1, 0], up: [0, 1, 0.1], fov: 45 }
resolution: [64, 48]
materials:
  white: { type: diffuse, color: [0.7, 0.7, 0.7] }
  \"odd \\\"name\\\"\": { type: phong, diffuse: [0.1, 0.2, 0.3], specular: [0.5, 0.5, 0.5], exponent: 1e12 }
  glass: { type: glass, ior: 1.33, color: [0.9, 1, 0.9] }
  mirror: { type: mirror }
  lamp: { type: diffuse, color: [0.5, 0.5, 0.5], emission: [1e-7, 10, 3e17] }
objects:
  - { type: mesh, file: tri.obj, material: white }
  - { type: sphere, center: [0, 1, 0], radius: 5, material: white, inward: true }
  - { type: sphere, center: [0.2, 0.3, 0.1], radius: 0.0000125, material: lamp }
  - { type: quad, corner: [-1, 0, -1], edge_u: [0, 0, 2], edge_v: [2, 0, 0], material: \"odd \\\"name\\\"\" }
  - { type: sphere, center: [0.5, 0.5, 0.5], radius: 0.2, material: glass }
  - { type: sphere, center: [-0.5, 0.5, 0.5], radius: 0.2, material: mirror }
lights:
  - { type: point, position: [0, 1.9, 0], intensity: [10, 10, 10] }
  - { type: point, position: [0.1, 1e-9, -0.3], intensity: [0.5, 0, 2] }
render: { max_depth: 7, photons: 1234, radius: 0.05, alpha: 0.5, algorithm: vcm }
";

/// Vertex normals, one of them repaired by the loader, and a triangle and a quad.
const TRI_OBJ: &str = "\
v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\n\
vn 0 0 1\nvn 0 0 1\nvn 0 0.6 0.8\nvn 0 0 0\n\
f 1//1 2//2 3//3 4//4\nf 1 2 5\n";

/// The fingerprints of scenes as computed from the `Debug` text of the scene's parts, the
/// way ppm computed them before the fingerprint was written field by field. Renders saved
/// by earlier versions record these values: they must never change for these files.
#[test]
fn old_scenes_keep_their_fingerprint() {
    let shipped = [
        ("cornell_box.yml", 0x28ec_7d66_d86a_a9fcu64),
        ("cornell_box_glossy.yml", 0x51cb_10b7_42dd_3229),
        ("cornell_box_specular.yml", 0x4ca3_922a_56f1_7c1c),
        ("cornell_box_water.yml", 0x3508_2008_e2bd_d9b0),
        ("compare/smallvcm_mirror_ceiling.yml", 0x0b7b_d913_a145_8617),
    ];
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../ppm-cli/tests/data");
    let dir = write_files(
        "fingerprint_every_field",
        &[("every.yml", EVERY_FIELD), ("tri.obj", TRI_OBJ)],
    );
    let files = shipped
        .iter()
        .map(|(name, hash)| (scenes_dir().join(name), *hash))
        .chain([
            // The scene of the saved render state that `cluster.rs` resumes.
            (data.join("state_format1.yml"), 0xe93e_e35d_5c52_1f4d),
            (dir.join("every.yml"), 0x79f5_581b_06e4_1f1d),
        ]);
    let mut wrong = Vec::new();
    for (path, expected) in files {
        let (builder, _) = load_scene_builder(&path).unwrap_or_else(|e| panic!("{e}"));
        let hash = content_hash(&builder);
        if hash != expected {
            wrong.push(format!("{}: {hash:#018x}", path.display()));
        }
    }
    assert!(wrong.is_empty(), "{wrong:#?}");
}

/// A scene with one of everything that can change: camera, materials, a mesh from an OBJ,
/// a sphere, a point light, a spot light, render defaults.
const BASE: &str = "\
camera: { position: [0, 1, 3.9], look_at: [0, 1, 0], up: [0, 1, 0], fov: 38 }
resolution: [32, 24]
materials:
  white: { type: diffuse, color: [0.7, 0.7, 0.7] }
  lamp: { type: diffuse, color: [0.5, 0.5, 0.5], emission: [10, 10, 10] }
objects:
  - { type: mesh, file: tri.obj, material: white }
  - { type: sphere, center: [0, 1.5, 0], radius: 0.1, material: lamp }
lights:
  - { type: point, position: [0, 1.9, 0], intensity: [1, 1, 1] }
  - { type: spot, position: [0.5, 1.9, 0], direction: [0, -1, 0], intensity: [2, 2, 2], cone_angle: 30, falloff_start: 20 }
render: { max_depth: 8 }
";

/// The OBJ of [`BASE`].
const OBJ: &str = "v -1 0 -1\nv 1 0 -1\nv 0 0 1\nf 1 3 2\n";

fn fingerprint(test: &str, yaml: &str, obj: &str) -> u64 {
    let dir = write_files(test, &[("scene.yml", yaml), ("tri.obj", obj)]);
    let (builder, _) = parse_scene(yaml, &dir.join("scene.yml")).unwrap_or_else(|e| panic!("{e}"));
    content_hash(&builder)
}

#[test]
fn every_kind_of_content_changes_the_fingerprint() {
    let base = fingerprint("fingerprint_base", BASE, OBJ);
    assert_eq!(base, fingerprint("fingerprint_base_again", BASE, OBJ));
    // (what changes, from, to) in the scene file.
    let edits = [
        ("camera", "position: [0, 1, 3.9]", "position: [0, 1, 3.8]"),
        ("field of view", "fov: 38", "fov: 39"),
        (
            "the field of view's axis",
            "fov: 38",
            "fov: 38, fov_axis: x",
        ),
        ("an aperture", "fov: 38", "fov: 38, aperture_radius: 0.1"),
        (
            "the focus distance",
            "fov: 38",
            "fov: 38, aperture_radius: 0.1, focus_distance: 2",
        ),
        ("resolution", "[32, 24]", "[32, 25]"),
        ("a material's colour", "[0.7, 0.7, 0.7]", "[0.7, 0.71, 0.7]"),
        ("a material's emission", "[10, 10, 10]", "[10, 10, 11]"),
        (
            "a material's type",
            "type: diffuse, color: [0.7",
            "type: mirror, color: [0.7",
        ),
        ("a sphere", "radius: 0.1", "radius: 0.11"),
        (
            "a mesh's transform",
            "file: tri.obj, material: white }",
            "file: tri.obj, material: white, transform: [{ rotate: { axis: [0, 1, 0], angle: 5 } }] }",
        ),
        (
            "a sphere's transform",
            "radius: 0.1, material: lamp }",
            "radius: 0.1, material: lamp, transform: [{ translate: [0, 0.01, 0] }] }",
        ),
        (
            "the point light's position",
            "[0, 1.9, 0], intensity: [1",
            "[0, 1.8, 0], intensity: [1",
        ),
        (
            "the point light's intensity",
            "intensity: [1, 1, 1]",
            "intensity: [1, 1, 2]",
        ),
        (
            "the spot light's position",
            "[0.5, 1.9, 0]",
            "[0.5, 1.9, 0.1]",
        ),
        (
            "the spot light's axis",
            "direction: [0, -1, 0]",
            "direction: [0.1, -1, 0]",
        ),
        (
            "the spot light's intensity",
            "intensity: [2, 2, 2]",
            "intensity: [2, 3, 2]",
        ),
        ("the spot light's cone", "cone_angle: 30", "cone_angle: 31"),
        (
            "the spot light's falloff",
            "falloff_start: 20",
            "falloff_start: 21",
        ),
        ("a render default", "max_depth: 8", "max_depth: 9"),
        (
            "the algorithm",
            "max_depth: 8",
            "max_depth: 8, algorithm: pt",
        ),
    ];
    let mut seen = vec![("nothing", base)];
    for (what, from, to) in edits {
        assert!(BASE.contains(from), "{what}: {from}");
        let hash = fingerprint("fingerprint_edit", &BASE.replacen(from, to, 1), OBJ);
        if let Some((other, _)) = seen.iter().find(|(_, h)| *h == hash) {
            panic!("changing {what} gives the fingerprint of changing {other}");
        }
        seen.push((what, hash));
    }
    // A mesh vertex (in the OBJ file), and the order of the lights.
    let moved = fingerprint(
        "fingerprint_obj",
        BASE,
        &OBJ.replace("v 0 0 1", "v 0 0 0.9"),
    );
    assert!(seen.iter().all(|(_, h)| *h != moved), "a vertex moved");
    let lights: Vec<&str> = BASE
        .lines()
        .filter(|l| l.contains("type: point") || l.contains("type: spot"))
        .collect();
    let swapped = BASE.replace(
        &format!("{}\n{}", lights[0], lights[1]),
        &format!("{}\n{}", lights[1], lights[0]),
    );
    assert_ne!(swapped, BASE);
    let swapped = fingerprint("fingerprint_swapped", &swapped, OBJ);
    assert!(seen.iter().all(|(_, h)| *h != swapped), "lights reordered");
}

/// An absorbing medium changes the fingerprint (its interior and its exterior alike, each
/// channel), and an explicit zero absorption keeps the fingerprint of none.
#[test]
fn absorption_changes_the_fingerprint() {
    let with = |material: &str| {
        let yaml = BASE.replace(
            "objects:\n",
            &format!("  water: {material}\nobjects:\n  - {{ type: sphere, center: [0, 0.5, 0], radius: 0.3, material: water }}\n"),
        );
        fingerprint("fingerprint_absorption", &yaml, OBJ)
    };
    let clear = with("{ type: dielectric, int_ior: water, ext_ior: bk7 }");
    let zero = with(
        "{ type: dielectric, int_ior: water, ext_ior: bk7, absorption: [0, 0, 0], ext_absorption: [0, 0, 0] }",
    );
    assert_eq!(clear, zero);
    let hashes = [
        clear,
        with("{ type: dielectric, int_ior: water, ext_ior: bk7, absorption: [0.1, 0, 0] }"),
        with("{ type: dielectric, int_ior: water, ext_ior: bk7, absorption: [0, 0.1, 0] }"),
        with("{ type: dielectric, int_ior: water, ext_ior: bk7, ext_absorption: [0.1, 0, 0] }"),
        with("{ type: glass, ior: 1.33, absorption: [0.1, 0, 0] }"),
        with("{ type: glass, ior: 1.33 }"),
    ];
    for (i, a) in hashes.iter().enumerate() {
        for b in &hashes[i + 1..] {
            assert_ne!(a, b, "absorption edit {i} collides");
        }
    }
}
