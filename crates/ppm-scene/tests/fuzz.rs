//! Fuzzing (proptest, fixed seed): the YAML, OBJ and MTL loaders never panic, whatever the
//! input, and what they accept is sane (finite, energy-conserving, indices in range); what
//! they reject has a message naming a file.

mod common;

use common::{scenes_dir, write_files};
use glam::Vec3;
use ppm_core::bsdf::Bsdf;
use ppm_core::geometry::TriangleMesh;
use ppm_core::material::Material;
use ppm_core::scene::SceneBuilder;
use ppm_scene::mtl::{mtl_to_material, parse_mtl};
use ppm_scene::obj::{parse_obj, ObjMaterials};
use ppm_scene::{parse_scene, LoadError};
use proptest::collection::vec;
use proptest::prelude::*;
use proptest::sample::{select, Index};
use proptest::test_runner::RngSeed;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

fn config() -> ProptestConfig {
    ProptestConfig {
        cases: 256,
        rng_seed: RngSeed::Fixed(0x00C0_FFEE),
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

/// A BSDF that cannot create energy or produce NaN.
fn check_material(m: &Material) {
    let unit = |c: Vec3| c.is_finite() && c.min_element() >= 0.0 && c.max_element() <= 1.0 + 1e-6;
    assert!(
        m.emission.is_finite() && m.emission.min_element() >= 0.0,
        "{m:?}"
    );
    match m.bsdf {
        Bsdf::Diffuse(d) => assert!(unit(d.albedo), "{m:?}"),
        Bsdf::Mirror(r) => assert!(unit(r.color), "{m:?}"),
        Bsdf::Glass(g) => assert!(unit(g.color) && g.ior.is_finite() && g.ior > 0.0, "{m:?}"),
        Bsdf::Phong(p) => {
            assert!(
                unit(p.diffuse) && unit(p.specular) && unit(p.diffuse + p.specular),
                "{m:?}"
            );
            assert!(p.exponent.is_finite() && p.exponent >= 0.0, "{m:?}");
        }
        Bsdf::Conductor(_)
        | Bsdf::Dielectric(_)
        | Bsdf::ThinDielectric(_)
        | Bsdf::Plastic(_)
        | Bsdf::TwoSidedConductor(_)
        | Bsdf::TwoSidedPlastic(_) => panic!("the fuzzer writes no such material: {m:?}"),
    }
}

/// A mesh's normals are unit length or absent, and its triangles name existing materials and
/// existing, finite vertices.
fn check_mesh(mesh: &TriangleMesh, n_materials: u32) {
    assert!(mesh.normals.is_empty() || mesh.normals.len() == mesh.positions.len());
    assert!(mesh
        .normals
        .iter()
        .all(|n| n.is_finite() && (n.length() - 1.0).abs() < 1e-3));
    for (t, &m) in mesh.indices.iter().zip(&mesh.materials) {
        assert!(m < n_materials);
        for &i in t {
            assert!(mesh
                .positions
                .get(i as usize)
                .is_some_and(|p| p.is_finite()));
        }
    }
}

/// Everything a loaded scene hands to the core is finite and in range.
fn check_builder(b: &SceneBuilder) {
    let n_materials = b.materials.len() as u32;
    b.materials.iter().for_each(check_material);
    assert!(b.camera.width >= 1 && b.camera.height >= 1);
    for mesh in &b.meshes {
        assert_eq!(mesh.indices.len(), mesh.materials.len());
        check_mesh(mesh, n_materials);
    }
    for s in &b.spheres {
        assert!(
            s.center.is_finite()
                && s.radius.is_finite()
                && s.radius > 0.0
                && s.material < n_materials
        );
    }
    for l in &b.lights {
        let power = l.power();
        assert!(power.is_finite() && power.min_element() >= 0.0, "{l:?}");
    }
    let d = b.defaults;
    assert!(d.max_depth >= 1 && d.alpha > 0.0 && d.alpha <= 1.0);
    assert!(d.photons.is_none_or(|p| p >= 1));
    assert!(
        !matches!(d.radius, Some(ppm_core::integrator::Radius::World(r)) if !(r.is_finite() && r > 0.0))
    );
}

/// Errors name a file: the message starts with a path ending in a known extension.
fn check_error(e: &LoadError) {
    let msg = e.to_string();
    let file = e.path().display().to_string();
    assert!(msg.starts_with(&file), "{msg}");
    assert!(
        [".yml", ".obj", ".mtl"]
            .iter()
            .any(|ext| file.ends_with(ext))
            || file.ends_with('.'),
        "{msg}"
    );
}

fn load_scene_text(text: &str, path: &Path) {
    match parse_scene(text, path) {
        Ok((builder, _)) => check_builder(&builder),
        Err(e) => check_error(&e),
    }
}

/// Text with a lot of YAML punctuation and scene-format words.
fn yaml_soup() -> impl Strategy<Value = String> {
    let token = select(vec![
        "camera:",
        "position:",
        "look_at:",
        "up:",
        "fov:",
        "resolution:",
        "materials:",
        "objects:",
        "lights:",
        "render:",
        "type:",
        "diffuse",
        "mirror",
        "glass",
        "phong",
        "mesh",
        "sphere",
        "quad",
        "point",
        "color:",
        "emission:",
        "ior:",
        "radius:",
        "center:",
        "corner:",
        "edge_u:",
        "edge_v:",
        "file:",
        "material:",
        "{",
        "}",
        "[",
        "]",
        ",",
        ":",
        "- ",
        "\n",
        "\n  ",
        "\n    ",
        " ",
        "0",
        "1",
        "-1",
        "0.5",
        "38",
        "1e40",
        ".nan",
        ".inf",
        "&a",
        "*a",
        "!!str",
        "'",
        "\"",
        "#",
        "---",
        "~",
        "null",
        "white",
        "x",
    ]);
    vec(token, 0..80).prop_map(|t| t.concat())
}

/// One edit of a scene text.
#[derive(Clone, Debug)]
enum Mutation {
    Delete(Index, usize),
    Insert(Index, &'static str),
    Replace(Index, usize, &'static str),
    DuplicateLine(Index),
    SwapLines(Index, Index),
    /// Replace the i-th number with another (likely keeping the YAML valid).
    ReplaceNumber(Index, &'static str),
}

const NUMBERS: &[&str] = &[
    "-1",
    "0",
    "-0.0",
    ".nan",
    ".inf",
    "-.inf",
    "1e40",
    "1e-40",
    "0.5",
    "2",
    "180",
    "100000",
    "4294967296",
    "1.0e+3",
];

const SNIPPETS: &[&str] = &[
    "-1",
    "0",
    ".nan",
    ".inf",
    "-.inf",
    "1e40",
    "1e-40",
    "999999999999",
    "{",
    "}",
    "[",
    "]",
    ":",
    ",",
    "\n",
    "\n  ",
    "  ",
    "\t",
    "- ",
    "type: ",
    "mesh",
    "sphere",
    "quad",
    "glass",
    "phong",
    "mirror",
    "diffuse",
    "point",
    "material: white",
    "file: ",
    "tall_block.obj",
    "water.obj",
    "nope.obj",
    "/dev/zero",
    ".",
    "..",
    "&a ",
    "*a",
    "!!str ",
    "'",
    "\"",
    "#",
    "---",
    "~",
    "null",
    "true",
    "[0, 0, 0]",
    "[1, 1]",
    "ior: 0",
    "radius: -1",
    "inward: true",
    "emission: [1, 1, 1]",
    "exponent: 1e30",
    "[100000, 1]",
];

fn mutation() -> impl Strategy<Value = Mutation> {
    let snippet = select(SNIPPETS);
    prop_oneof![
        1 => (any::<Index>(), 1..30usize).prop_map(|(i, n)| Mutation::Delete(i, n)),
        1 => (any::<Index>(), snippet.clone()).prop_map(|(i, s)| Mutation::Insert(i, s)),
        1 => (any::<Index>(), 1..8usize, snippet).prop_map(|(i, n, s)| Mutation::Replace(i, n, s)),
        1 => any::<Index>().prop_map(Mutation::DuplicateLine),
        1 => (any::<Index>(), any::<Index>()).prop_map(|(a, b)| Mutation::SwapLines(a, b)),
        4 => (any::<Index>(), select(NUMBERS)).prop_map(|(i, s)| Mutation::ReplaceNumber(i, s)),
    ]
}

fn mutate(text: &str, mutations: &[Mutation]) -> String {
    let mut chars: Vec<char> = text.chars().collect();
    for m in mutations {
        let len = chars.len().max(1);
        match *m {
            Mutation::ReplaceNumber(i, s) => {
                // Spans of digits (with sign and decimal point) in the text.
                let mut spans = Vec::new();
                let mut k = 0;
                while k < chars.len() {
                    if chars[k].is_ascii_digit() {
                        let mut a = k;
                        while a > 0 && matches!(chars[a - 1], '-' | '.') {
                            a -= 1;
                        }
                        while k < chars.len() && (chars[k].is_ascii_digit() || chars[k] == '.') {
                            k += 1;
                        }
                        spans.push((a, k));
                    } else {
                        k += 1;
                    }
                }
                if !spans.is_empty() {
                    let (a, b) = spans[i.index(spans.len())];
                    chars.splice(a..b, s.chars());
                }
            }
            Mutation::Delete(i, n) => {
                let a = i.index(len).min(chars.len());
                chars.drain(a..(a + n).min(chars.len()));
            }
            Mutation::Insert(i, s) => {
                let a = i.index(len + 1).min(chars.len());
                chars.splice(a..a, s.chars());
            }
            Mutation::Replace(i, n, s) => {
                let a = i.index(len).min(chars.len());
                chars.splice(a..(a + n).min(chars.len()), s.chars());
            }
            Mutation::DuplicateLine(i) | Mutation::SwapLines(i, _) => {
                let text: String = chars.iter().collect();
                let mut lines: Vec<&str> = text.lines().collect();
                if lines.is_empty() {
                    continue;
                }
                let a = i.index(lines.len());
                match *m {
                    Mutation::SwapLines(_, j) => {
                        let b = j.index(lines.len());
                        lines.swap(a, b);
                    }
                    _ => lines.insert(a, lines[a]),
                }
                chars = lines.join("\n").chars().collect();
            }
        }
    }
    chars.into_iter().collect()
}

/// The shipped scenes small enough to reload hundreds of times (the water mesh is not).
fn base_scenes() -> &'static [(PathBuf, String)] {
    static SCENES: OnceLock<Vec<(PathBuf, String)>> = OnceLock::new();
    SCENES.get_or_init(|| {
        [
            "cornell_box.yml",
            "cornell_box_specular.yml",
            "cornell_box_glossy.yml",
        ]
        .iter()
        .map(|name| {
            let path = scenes_dir().join(name);
            let text = std::fs::read_to_string(&path).unwrap();
            (path, text)
        })
        .collect()
    })
}

fn number() -> impl Strategy<Value = String> {
    prop_oneof![
        40 => (-3.0f32..3.0).prop_map(|x| x.to_string()),
        2 => select(vec!["nan", "inf", "-inf", "1e39", "-1e39", "0", "-0", "1e-45", "3.4e38"]).prop_map(String::from),
    ]
}

/// A face index into (at least) 4 elements: mostly valid, sometimes not.
fn index(count: i64) -> impl Strategy<Value = String> {
    prop_oneof![
        400 => (1..=count).prop_map(|i| i.to_string()),
        200 => (-count..0).prop_map(|i| i.to_string()),
        1 => (-12i64..13).prop_map(|i| i.to_string()),
        1 => select(vec!["99999999999999999999", "-9223372036854775808", "", "a", "+1"]).prop_map(String::from),
    ]
}

fn face_vertex() -> impl Strategy<Value = String> {
    let form = prop_oneof![300 => 0..4u8, 1 => Just(4u8)];
    (index(4), index(2), index(1), form).prop_map(|(v, t, n, form)| match form {
        0 => v,
        1 => format!("{v}/{t}"),
        2 => format!("{v}//{n}"),
        3 => format!("{v}/{t}/{n}"),
        _ => format!("{v}/{t}/{n}/{v}"),
    })
}

/// Mostly well-formed OBJ statements, with the odd malformed one.
fn obj_line() -> impl Strategy<Value = String> {
    let triple =
        |k: &'static str| vec(number(), 3).prop_map(move |v| format!("{k} {}", v.join(" ")));
    let garbage = prop_oneof![
        vec(number(), 0..8).prop_map(|v| format!("v {}", v.join(" "))),
        vec(number(), 0..5).prop_map(|v| format!("vn {}", v.join(" "))),
        Just("v 1 x 2".to_string()),
        "\\PC{0,20}",
    ];
    prop_oneof![
        40 => triple("v"),
        10 => triple("vn"),
        6 => Just("vt 0.5 0.5".to_string()),
        120 => vec(face_vertex(), 0..7).prop_map(|v| format!("f {}", v.join(" "))),
        8 => select(vec!["usemtl a", "usemtl b", "usemtl c", "usemtl missing", "usemtl", "usemtl\tb"]).prop_map(String::from),
        4 => select(vec!["mtllib m.mtl", "mtllib nope.mtl", "mtllib ../m.mtl", "mtllib C:\\x\\m.mtl", "mtllib", "mtllib m.mtl m.mtl", "mtllib /dev/zero", "mtllib ."]).prop_map(String::from),
        8 => select(vec!["o x", "g", "g a b", "s 1", "s off", "l 1 2", "p 1", "# c", "", "curv 0 1 1 2", "f 1 2 \\", "\\"]).prop_map(String::from),
        1 => garbage,
    ]
}

/// Mostly well-formed MTL statements, with the odd malformed one.
fn mtl_line() -> impl Strategy<Value = String> {
    let value = || prop_oneof![10 => (0.0f32..1.5).prop_map(|x| x.to_string()), 1 => (0u32..1000).prop_map(|x| x.to_string())];
    let color = select(vec!["Kd", "Ks", "Ke", "Tf", "Ka", "kd"]);
    let scalar = select(vec!["Ns", "Ni", "d", "Tr"]);
    let odd = select(vec![
        "Kd spectral a.rfl",
        "Kd xyz 1 1 1",
        "d -halo 0.5",
        "map_Kd x.png",
        "bump b.png",
        "Kd -1 0 0",
        "Ks nan",
        "Ni inf",
        "Kd 1 2",
        "d 2",
        "illum x",
        "illum",
        "newmtl",
        "junk 1",
        "# c",
        "",
    ]);
    prop_oneof![
        4 => (0..4u8).prop_map(|i| format!("newmtl m{i}")),
        10 => (color, vec(value(), 3)).prop_map(|(k, v)| format!("{k} {}", v.join(" "))),
        2 => (select(vec!["Kd", "Ks", "Tf"]), value()).prop_map(|(k, v)| format!("{k} {v}")),
        6 => (scalar, value()).prop_map(|(k, v)| format!("{k} {v}")),
        4 => (0u32..11).prop_map(|i| format!("illum {i}")),
        1 => odd.prop_map(String::from),
    ]
}

/// A folder with an MTL library for the OBJ fuzzing.
fn obj_dir() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let mtl = "newmtl a\nKd 0.8 0.2 0.2\nKs 0.9 0.9 0.9\nNs 20\nnewmtl b\nillum 7\nNi 1.5\nnewmtl c\nKe 5 5 5\n";
        write_files("fuzz_obj", &[("m.mtl", mtl)])
    })
}

fn load_obj_text(text: &str) {
    let mut warnings = Vec::new();
    let path = obj_dir().join("f.obj");
    match parse_obj(text, &path, ObjMaterials::FromMtl, &mut warnings) {
        Ok(data) => {
            data.materials.iter().for_each(check_material);
            for mesh in &data.meshes {
                check_mesh(mesh, data.materials.len() as u32);
                for t in &mesh.indices {
                    // No degenerate triangle survives.
                    let p = t.map(|i| mesh.positions[i as usize]);
                    assert!((p[1] - p[0]).cross(p[2] - p[0]).length() > 0.0);
                }
            }
        }
        Err(e) => check_error(&e),
    }
    for w in &warnings {
        assert!(w.starts_with(&obj_dir().display().to_string()), "{w}");
    }
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn yaml_loader_never_panics_on_arbitrary_text(text in any::<String>()) {
        load_scene_text(&text, &scenes_dir().join("fuzz.yml"));
    }

    #[test]
    fn yaml_loader_never_panics_on_yaml_like_text(text in yaml_soup()) {
        load_scene_text(&text, &scenes_dir().join("fuzz.yml"));
    }

    #[test]
    fn yaml_loader_never_panics_on_mutated_scenes(scene in 0..3usize, edits in vec(mutation(), 1..5)) {
        let (path, text) = &base_scenes()[scene];
        load_scene_text(&mutate(text, &edits), path);
    }

    #[test]
    fn obj_loader_never_panics_on_arbitrary_text(text in any::<String>()) {
        load_obj_text(&text);
    }

    #[test]
    fn obj_loader_never_panics_on_obj_like_text(
        positions in vec(vec(-2.0f32..2.0, 3), 4..10),
        normals in vec(vec(number(), 3), 1..3),
        lines in vec(obj_line(), 0..40),
    ) {
        // Vertices and normals first, so that faces have something to refer to.
        let mut text: String = positions.iter().map(|p| format!("v {} {} {}\n", p[0], p[1], p[2])).collect();
        text.extend(normals.iter().map(|n| format!("vn {}\n", n.join(" "))));
        text.push_str(&lines.join("\n"));
        load_obj_text(&text);
    }

    #[test]
    fn mtl_loader_never_panics_and_conserves_energy(lines in vec(mtl_line(), 0..24)) {
        let mut warnings = Vec::new();
        let path = Path::new("fuzz/m.mtl");
        match parse_mtl(&format!("newmtl m\n{}", lines.join("\n")), path, &mut warnings) {
            Ok(mats) => {
                for m in &mats {
                    check_material(&mtl_to_material(m, path, &mut warnings));
                }
            }
            Err(e) => check_error(&e),
        }
    }
}
