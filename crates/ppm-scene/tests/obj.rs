//! OBJ quirks, degenerate geometry, MTL libraries and the MTL -> BSDF mapping table.

mod common;

use common::write_files;
use glam::Vec3;
use ppm_core::bsdf::Bsdf;
use ppm_core::geometry::TriangleMesh;
use ppm_scene::mtl::{mtl_to_material, parse_mtl};
use ppm_scene::obj::{load_obj, parse_obj, ObjData, ObjMaterials};
use ppm_scene::LoadError;
use std::path::Path;

fn parse(text: &str) -> (ObjData, Vec<String>) {
    let mut warnings = Vec::new();
    let data = parse_obj(
        text,
        Path::new("mem/test.obj"),
        ObjMaterials::FromMtl,
        &mut warnings,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    (data, warnings)
}

fn parse_err(text: &str) -> String {
    let mut warnings = Vec::new();
    match parse_obj(
        text,
        Path::new("mem/test.obj"),
        ObjMaterials::Ignore,
        &mut warnings,
    ) {
        Ok(_) => panic!("no error for {text:?}"),
        Err(e) => e.to_string(),
    }
}

/// All triangles as position triples, in order.
fn triangles(data: &ObjData) -> Vec<[Vec3; 3]> {
    data.meshes
        .iter()
        .flat_map(|m| m.indices.iter().map(|t| t.map(|i| m.positions[i as usize])))
        .collect()
}

fn load(dir: &Path, name: &str) -> (ObjData, Vec<String>) {
    let mut warnings = Vec::new();
    let data = load_obj(&dir.join(name), ObjMaterials::FromMtl, &mut warnings)
        .unwrap_or_else(|e| panic!("{e}"));
    (data, warnings)
}

const SQUARE: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";

#[test]
fn quads_and_polygons_are_triangulated() {
    let (data, _) = parse(&format!("{SQUARE}f 1 2 3 4\n"));
    assert_eq!(triangles(&data).len(), 2);
    let (data, _) = parse("v 0 0 0\nv 2 0 0\nv 3 1 0\nv 1 2 0\nv -1 1 0\nf 1 2 3 4 5\n");
    let tris = triangles(&data);
    assert_eq!(tris.len(), 3);
    // A fan with the winding kept: every normal is +z.
    for [a, b, c] in tris {
        assert!((b - a).cross(c - a).normalize().abs_diff_eq(Vec3::Z, 1e-6));
    }
}

#[test]
fn negative_indices_match_absolute_ones() {
    let absolute = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\nv 5 0 0\nv 6 0 0\nv 5 1 0\nf 4 5 6\n";
    let relative = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf -3//-1 -2//-1 -1//-1\nv 5 0 0\nv 6 0 0\nv 5 1 0\nf -3 -2 -1\n";
    let (a, _) = parse(absolute);
    let (r, _) = parse(relative);
    assert_eq!(triangles(&a), triangles(&r));
    assert_eq!(triangles(&a).len(), 2);
    assert_eq!(a.meshes[0].normals, r.meshes[0].normals);
}

#[test]
fn tabs_comments_after_values_and_texcoords_are_accepted() {
    let text = "# a comment\n\
                mtllib\tm.mtl  # library\n\
                v\t0 0 0 # first\n\
                v 1\t0 0\n\
                v 0 1 0   # third\n\
                vt 0 0\nvt 1 0\nvt 0 1\n\
                vn 0 0 1 # up\n\
                s off\n\
                usemtl\tred\t# red material\n\
                f 1/1/1\t2/2/1 3/3/1 # the face\n\
                f 1/1 2/2 3/3\n";
    let dir = write_files(
        "obj_tabs",
        &[
            ("a.obj", text),
            ("m.mtl", "newmtl red # comment\nKd\t0.8 0.1 0.1 # red\n"),
        ],
    );
    let (data, warnings) = load(&dir, "a.obj");
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!(triangles(&data).len(), 2);
    assert_eq!(data.materials.len(), 1);
    assert!(
        matches!(data.materials[0].bsdf, Bsdf::Diffuse(d) if d.albedo == Vec3::new(0.8, 0.1, 0.1))
    );
    assert_eq!(data.materials[0].name, "red");
}

#[test]
fn line_continuations_join_lines() {
    let (data, _) = parse(&format!("{SQUARE}f 1 2 \\\n 3 4\n"));
    assert_eq!(triangles(&data).len(), 2);
}

#[test]
fn vertex_normals_are_used_and_normalized() {
    let (data, warnings) =
        parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 2\nvn 0 1 1\nf 1//1 2//1 3//2\n");
    assert!(
        !warnings.iter().any(|w| w.contains("normal")),
        "{warnings:?}"
    );
    let m = &data.meshes[0];
    assert_eq!(m.normals.len(), m.positions.len());
    for n in &m.normals {
        assert!((n.length() - 1.0).abs() < 1e-6);
    }
    assert!(m.normals.contains(&Vec3::Z));
    assert!(m
        .normals
        .iter()
        .any(|n| n.abs_diff_eq(Vec3::new(0.0, 1.0, 1.0).normalize(), 1e-6)));
}

#[test]
fn lines_points_and_free_form_statements_are_ignored() {
    let (data, warnings) = parse(&format!("{SQUARE}l 1 2\np 3\ncstype bezier\nf 1 2 3\n"));
    assert_eq!(triangles(&data).len(), 1);
    assert!(
        warnings.iter().any(|w| w.contains("line and point")),
        "{warnings:?}"
    );
    assert!(
        warnings.iter().any(|w| w.contains("cstype")),
        "{warnings:?}"
    );
}

#[test]
fn face_errors_name_the_file_and_line() {
    let e = parse_err(&format!("{SQUARE}f 1 2 3\n\nf 1 2 9\n"));
    assert!(e.starts_with("mem/test.obj:7:"), "{e}");
    assert!(
        e.contains("vertex index 9") && e.contains("4 vertices defined"),
        "{e}"
    );
    let e = parse_err(&format!("{SQUARE}f 0 1 2\n"));
    assert!(
        e.starts_with("mem/test.obj:5:") && e.contains("index 0"),
        "{e}"
    );
    // Relative index reaching before the first vertex: tobj 4 overflows on these.
    let e = parse_err(&format!("{SQUARE}f -1 -2 -5\n"));
    assert!(e.starts_with("mem/test.obj:5:") && e.contains("-5"), "{e}");
    let e = parse_err(&format!("{SQUARE}vn 0 0 1\nf 1//1 2//2 3//1\n"));
    assert!(
        e.starts_with("mem/test.obj:6:") && e.contains("normal index 2"),
        "{e}"
    );
    let e = parse_err(&format!("{SQUARE}f 1 2 x\n"));
    assert!(e.starts_with("mem/test.obj:5:") && e.contains("`x`"), "{e}");
    let e = parse_err(&format!("{SQUARE}f 1/1/1/1 2 3\n"));
    assert!(e.starts_with("mem/test.obj:5:"), "{e}");
    // Positive indices may not point forward (the vertex must be defined first).
    let e = parse_err("v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n");
    assert!(e.starts_with("mem/test.obj:3:"), "{e}");
}

#[test]
fn vertex_errors_name_the_file_and_line() {
    for (text, line, needle) in [
        ("v 1 2\n", 1, "x y z"),
        ("v 0 0 0\nv 1 2 abc\n", 2, "`abc`"),
        ("v 1 2 3 0\n", 1, "w is 0"),
        ("v 1 2 3\nvn 1 2\n", 2, "vn"),
    ] {
        let e = parse_err(text);
        assert!(
            e.starts_with(&format!("mem/test.obj:{line}:")) && e.contains(needle),
            "{e}"
        );
    }
}

#[test]
fn homogeneous_coordinates_are_divided() {
    let (data, _) = parse("v 0 0 0 2\nv 2 0 0 2\nv 0 4 0 2\nf 1 2 3\n");
    assert_eq!(
        triangles(&data)[0],
        [Vec3::ZERO, Vec3::X, Vec3::new(0.0, 2.0, 0.0)]
    );
}

#[test]
fn degenerate_triangles_are_skipped_with_a_warning() {
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nv 1 0 0\nv nan 0 0\nv inf 1 1\n\
                f 1 2 3\n\
                f 1 1 2\n\
                f 1 2 4\n\
                f 2 5 3\n\
                f 6 2 3\n\
                f 7 2 3\n";
    let (data, warnings) = parse(text);
    assert_eq!(triangles(&data), vec![[Vec3::ZERO, Vec3::X, Vec3::Y]]);
    let w = warnings
        .iter()
        .find(|w| w.contains("degenerate"))
        .expect("warning");
    assert!(
        w.starts_with("mem/test.obj") && w.contains("skipped 5"),
        "{w}"
    );
}

#[test]
fn unusable_vertex_normals_are_repaired() {
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn nan nan nan\nvn 0 0 0\nvn 0 0 1\nvn inf 0 0\n\
                f 1//1 2//2 3//3\nv 1 1 0\nf 2//4 4//3 3//3\n";
    let (data, warnings) = parse(text);
    let m = &data.meshes[0];
    assert_eq!(m.normals.len(), m.positions.len());
    for n in &m.normals {
        assert!(n.is_finite() && (n.length() - 1.0).abs() < 1e-6, "{n}");
    }
    // The repaired ones take the face normal +z.
    assert!(
        m.normals.iter().all(|n| n.abs_diff_eq(Vec3::Z, 1e-6)),
        "{:?}",
        m.normals
    );
    let w = warnings
        .iter()
        .find(|w| w.contains("vertex normals"))
        .expect("warning");
    assert!(
        w.starts_with("mem/test.obj") && w.contains("replaced 3"),
        "{w}"
    );
}

#[test]
fn faces_without_normals_next_to_faces_with_normals_are_shaded_flat() {
    // Square in the z = 0 plane; the first face has tilted vertex normals, the second none,
    // the third normals on one vertex only (which counts as none).
    let text = format!("{SQUARE}vn 0 1 1\nf 1//1 2//1 3//1\nf 1 3 4\nf 4 1//1 3\n");
    let (data, warnings) = parse(&text);
    assert!(
        !warnings.iter().any(|w| w.contains("normal")),
        "{warnings:?}"
    );
    let m = &data.meshes[0];
    assert_eq!(m.normals.len(), m.positions.len());
    let tilted = Vec3::new(0.0, 1.0, 1.0).normalize();
    let per_face: Vec<[Vec3; 3]> = m
        .indices
        .iter()
        .map(|t| t.map(|i| m.normals[i as usize]))
        .collect();
    assert_eq!(per_face.len(), 3);
    assert!(
        per_face[0].iter().all(|n| n.abs_diff_eq(tilted, 1e-6)),
        "{per_face:?}"
    );
    assert!(
        per_face[1..]
            .iter()
            .flatten()
            .all(|n| n.abs_diff_eq(Vec3::Z, 1e-6)),
        "{per_face:?}"
    );
    // Relative normal indices still refer to the file's own normals after the added ones.
    let (data, _) = parse(&format!("{SQUARE}vn 0 1 1\nf 1 2 3\nf 1//-1 3//-1 4//-1\n"));
    let m = &data.meshes[0];
    let last: Vec<Vec3> = m.indices[1]
        .iter()
        .map(|&i| m.normals[i as usize])
        .collect();
    assert!(last.iter().all(|n| n.abs_diff_eq(tilted, 1e-6)), "{last:?}");
}

#[test]
fn winding_disagreeing_with_normals_is_reported() {
    let (_, warnings) = parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 -1\nf 1//1 2//1 3//1\n");
    assert!(
        warnings.iter().any(|w| w.contains("facing away")),
        "{warnings:?}"
    );
}

#[test]
fn empty_obj_warns() {
    let (data, warnings) = parse("# nothing\nv 0 0 0\n");
    assert!(data.meshes.is_empty());
    assert!(
        warnings.iter().any(|w| w.contains("no triangles")),
        "{warnings:?}"
    );
}

#[test]
fn missing_mtl_warns_and_uses_the_default_grey() {
    let dir = write_files(
        "obj_missing_mtl",
        &[(
            "a.obj",
            &format!("mtllib nowhere.mtl\nusemtl red\n{SQUARE}f 1 2 3\n"),
        )],
    );
    let (data, warnings) = load(&dir, "a.obj");
    let w = warnings
        .iter()
        .find(|w| w.contains("nowhere.mtl"))
        .expect("warning naming the library");
    assert!(
        w.contains("a.obj:1")
            && w.contains("not found")
            && w.contains(&dir.join("nowhere.mtl").display().to_string()),
        "{w}"
    );
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("a.obj:2") && w.contains("`red`")),
        "{warnings:?}"
    );
    assert_eq!(data.materials.len(), 1);
    assert!(matches!(data.materials[0].bsdf, Bsdf::Diffuse(d) if d.albedo == Vec3::splat(0.5)));
}

#[test]
fn obj_without_materials_gets_the_default_grey_with_a_warning() {
    let dir = write_files("obj_no_mtllib", &[("a.obj", &format!("{SQUARE}f 1 2 3\n"))]);
    let (data, warnings) = load(&dir, "a.obj");
    assert!(
        warnings.iter().any(|w| w.contains("no material library")),
        "{warnings:?}"
    );
    assert!(matches!(data.materials[0].bsdf, Bsdf::Diffuse(d) if d.albedo == Vec3::splat(0.5)));
}

#[test]
fn mtllib_falls_back_to_the_bare_file_name() {
    let mtl = "newmtl red\nKd 0.9 0.1 0.1\n";
    for (case, mtllib) in [
        ("unix", "../textures/m.mtl"),
        ("windows", "C:\\Users\\me\\m.mtl"),
    ] {
        let obj = format!("mtllib {mtllib}\nusemtl red\n{SQUARE}f 1 2 3\n");
        let dir = write_files(
            &format!("obj_bare_{case}"),
            &[("a.obj", &obj), ("m.mtl", mtl)],
        );
        let (data, warnings) = load(&dir, "a.obj");
        assert!(
            matches!(data.materials[0].bsdf, Bsdf::Diffuse(d) if d.albedo == Vec3::new(0.9, 0.1, 0.1)),
            "{case}"
        );
        assert!(
            warnings
                .iter()
                .any(|w| w.contains("not found as written") && w.contains("m.mtl")),
            "{warnings:?}"
        );
    }
}

#[test]
fn several_libraries_and_materials_per_file() {
    let obj = format!("mtllib a.mtl b.mtl\n{SQUARE}usemtl one\nf 1 2 3\nusemtl two\nf 1 3 4\nusemtl one\nf 2 3 4\n");
    let dir = write_files(
        "obj_two_libs",
        &[
            ("x.obj", &obj),
            ("a.mtl", "newmtl one\nKd 0.1 0.2 0.3\n"),
            ("b.mtl", "newmtl two\nKd 0.4 0.5 0.6\n"),
        ],
    );
    let (data, warnings) = load(&dir, "x.obj");
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!(data.materials.len(), 2);
    let albedo = |m: u32| match data.materials[m as usize].bsdf {
        Bsdf::Diffuse(d) => d.albedo,
        _ => panic!(),
    };
    let per_triangle: Vec<Vec3> = data
        .meshes
        .iter()
        .flat_map(|m| m.materials.iter().map(|&i| albedo(i)))
        .collect();
    let (one, two) = (Vec3::new(0.1, 0.2, 0.3), Vec3::new(0.4, 0.5, 0.6));
    assert_eq!(per_triangle.iter().filter(|&&a| a == one).count(), 2);
    assert_eq!(per_triangle.iter().filter(|&&a| a == two).count(), 1);
}

#[test]
fn mtl_errors_name_the_mtl_file_and_line() {
    for (mtl, line, needle) in [
        ("newmtl a\nKd 0.5 abc 0.5\n", 2, "`abc`"),
        ("newmtl a\n\nKs -1 0 0\n", 3, "-1"),
        ("newmtl a\nKd 1 2\n", 2, "1 or 3 numbers"),
        ("newmtl a\nd 1.5\n", 2, "[0, 1]"),
        ("newmtl a\nNi nan\n", 2, "nan"),
        ("newmtl a\nillum x\n", 2, "illum"),
        ("newmtl\n", 1, "name"),
    ] {
        let obj = format!("mtllib m.mtl\n{SQUARE}f 1 2 3\n");
        let dir = write_files("mtl_errors", &[("a.obj", &obj), ("m.mtl", mtl)]);
        let mut warnings = Vec::new();
        let e = load_obj(&dir.join("a.obj"), ObjMaterials::FromMtl, &mut warnings).unwrap_err();
        let msg = e.to_string();
        assert!(matches!(e, LoadError::Parse { .. }), "{msg}");
        assert!(
            msg.starts_with(&format!("{}:{line}:", dir.join("m.mtl").display()))
                && msg.contains(needle),
            "{msg}"
        );
    }
}

#[test]
fn material_override_ignores_the_mtl() {
    let dir = write_files(
        "obj_override",
        &[(
            "a.obj",
            &format!("mtllib missing.mtl\nusemtl x\n{SQUARE}f 1 2 3\n"),
        )],
    );
    let mut warnings = Vec::new();
    let data = load_obj(&dir.join("a.obj"), ObjMaterials::Ignore, &mut warnings).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    assert!(data.materials.is_empty());
    assert!(data
        .meshes
        .iter()
        .all(|m: &TriangleMesh| m.materials.iter().all(|&i| i == 0)));
}

/// Maps one MTL material (given as MTL text) and returns its BSDF, emission and warnings.
fn map(mtl: &str) -> (Bsdf, Vec3, Vec<String>) {
    let mut warnings = Vec::new();
    let mats = parse_mtl(
        &format!("newmtl m\n{mtl}"),
        Path::new("t.mtl"),
        &mut warnings,
    )
    .unwrap();
    let m = mtl_to_material(&mats[0], Path::new("t.mtl"), &mut warnings);
    (m.bsdf, m.emission, warnings)
}

#[test]
fn mtl_mapping_table() {
    // Diffuse: Kd, or 0.5 grey without Kd.
    assert!(
        matches!(map("Kd 0.2 0.3 0.4\n").0, Bsdf::Diffuse(d) if d.albedo == Vec3::new(0.2, 0.3, 0.4))
    );
    assert!(matches!(map("Ka 1 1 1\n").0, Bsdf::Diffuse(d) if d.albedo == Vec3::splat(0.5)));
    assert!(matches!(map("Kd 0.25\n").0, Bsdf::Diffuse(d) if d.albedo == Vec3::splat(0.25)));
    // Emission on any type.
    let (b, e, _) = map("Kd 0.78 0.78 0.78\nKe 17 12 4\n");
    assert!(matches!(b, Bsdf::Diffuse(_)) && e == Vec3::new(17.0, 12.0, 4.0));
    let (b, e, _) = map("illum 3\nKs 1 1 1\nKe 1 1 1\n");
    assert!(matches!(b, Bsdf::Mirror(_)) && e == Vec3::ONE);
    // Mirror: illum 3 or 5 with Ks; without Ks it is not a mirror.
    assert!(
        matches!(map("illum 3\nKs 0.9 0.8 0.7\nNs 10\n").0, Bsdf::Mirror(m) if m.color == Vec3::new(0.9, 0.8, 0.7))
    );
    assert!(matches!(
        map("illum 5\nKs 0.9 0.9 0.9\n").0,
        Bsdf::Mirror(_)
    ));
    assert!(matches!(
        map("illum 3\nKd 0.3 0.3 0.3\n").0,
        Bsdf::Diffuse(_)
    ));
    assert!(matches!(map("illum 3\nKs 0 0 0\n").0, Bsdf::Diffuse(_)));
    // Glass: illum 4, 6, 7 (ior Ni, 1.5 when missing or <= 1), or d < 1 with Ni > 1.
    assert!(
        matches!(map("illum 4\nNi 1.33\n").0, Bsdf::Glass(g) if g.ior == 1.33 && g.color == Vec3::ONE)
    );
    assert!(matches!(map("illum 6\nNi 1.7\n").0, Bsdf::Glass(g) if g.ior == 1.7));
    assert!(matches!(map("illum 7\n").0, Bsdf::Glass(g) if g.ior == 1.5));
    assert!(matches!(map("illum 7\nNi 1\n").0, Bsdf::Glass(g) if g.ior == 1.5));
    let (b, _, w) = map("illum 7\nNi 0.0001\n");
    assert!(
        matches!(b, Bsdf::Glass(g) if g.ior == 1.5)
            && w.iter().any(|w| w.contains("`m`") && w.contains("Ni"))
    );
    assert!(
        matches!(map("illum 2\nd 0.5\nNi 1.6\nKd 0.5 0.5 0.5\n").0, Bsdf::Glass(g) if g.ior == 1.6)
    );
    assert!(matches!(map("d -halo 0.5\nNi 1.6\n").0, Bsdf::Glass(g) if g.ior == 1.6));
    assert!(
        matches!(map("illum 4\nNi 1.5\nTf 0.9 0.8 0.7\n").0, Bsdf::Glass(g) if g.color == Vec3::new(0.9, 0.8, 0.7))
    );
    // d < 1 without Ni > 1 is not glass.
    assert!(matches!(
        map("d 0.5\nNi 1\nKd 0.5 0.5 0.5\n").0,
        Bsdf::Diffuse(_)
    ));
    // Phong: Ks > 0 and Ns > 0.
    let (b, _, w) = map("Kd 0.5 0.4 0.3\nKs 0.2 0.2 0.2\nNs 50\n");
    assert!(w.is_empty(), "{w:?}");
    assert!(
        matches!(b, Bsdf::Phong(p) if p.diffuse == Vec3::new(0.5, 0.4, 0.3) && p.specular == Vec3::splat(0.2) && p.exponent == 50.0)
    );
    assert!(matches!(
        map("Kd 0.5 0.5 0.5\nKs 0.2 0.2 0.2\nNs 0\n").0,
        Bsdf::Diffuse(_)
    ));
    assert!(matches!(
        map("Kd 0.5 0.5 0.5\nKs 0.2 0.2 0.2\n").0,
        Bsdf::Diffuse(_)
    ));
    // illum 2 with Ks and Ns is phong, not mirror.
    assert!(matches!(
        map("illum 2\nKs 0.5 0.5 0.5\nNs 100\nKd 0.1 0.1 0.1\n").0,
        Bsdf::Phong(_)
    ));
}

#[test]
fn transmission_filter_alone_never_makes_glass() {
    // What many exporters write on opaque materials.
    let (b, _, _) =
        map("Ns 0\nKa 1 1 1\nKd 0.8 0.8 0.8\nKs 0 0 0\nTf 1 1 1\nNi 1.5\nd 1\nillum 2\n");
    assert!(matches!(b, Bsdf::Diffuse(d) if d.albedo == Vec3::splat(0.8)));
    let (b, _, _) = map("Kd 0.8 0.8 0.8\nTf 0.5 0.5 0.5\n");
    assert!(matches!(b, Bsdf::Diffuse(_)));
}

#[test]
fn mtl_energy_gain_is_scaled_down_with_a_warning() {
    let (b, _, w) = map("Kd 0.49 0.49 0.49\nKs 0.9 0.9 0.9\nNs 20\n");
    let Bsdf::Phong(p) = b else { panic!("{b:?}") };
    let sum = p.diffuse + p.specular;
    assert!((sum.max_element() - 1.0).abs() < 1e-6, "{sum}");
    // Scaled uniformly: the ratio diffuse / specular is kept.
    assert!((p.diffuse.x / p.specular.x - 0.49 / 0.9).abs() < 1e-6);
    assert!(
        w.iter()
            .any(|w| w.starts_with("t.mtl") && w.contains("`m`") && w.contains("Kd + Ks")),
        "{w:?}"
    );
    // A single over-bright channel.
    let (b, _, w) = map("Kd 1.2 0.6 0.3\n");
    assert!(
        matches!(b, Bsdf::Diffuse(d) if (d.albedo - Vec3::new(1.0, 0.5, 0.25)).length() < 1e-6)
    );
    assert_eq!(w.len(), 1);
    // Mirror and glass tints above 1 too.
    assert!(
        matches!(map("illum 3\nKs 2 1 1\n").0, Bsdf::Mirror(m) if m.color.max_element() <= 1.0)
    );
    assert!(
        matches!(map("illum 4\nTf 1.5 1 1\n").0, Bsdf::Glass(g) if g.color.max_element() <= 1.0)
    );
}

#[test]
fn mtl_oddities_warn_instead_of_failing() {
    let mut warnings = Vec::new();
    let text = "Kd 1 1 1\nnewmtl a\nKd spectral x.rfl\nmap_Kd tex.png\nnewmtl a\nKd 0.1 0.1 0.1\n";
    let mats = parse_mtl(text, Path::new("t.mtl"), &mut warnings).unwrap();
    assert_eq!(mats.len(), 2);
    assert_eq!(mats[0].kd, None);
    for needle in ["before any `newmtl`", "spectral", "map_Kd", "defined again"] {
        assert!(
            warnings
                .iter()
                .any(|w| w.starts_with("t.mtl") && w.contains(needle)),
            "{needle}: {warnings:?}"
        );
    }
}

/// A byte order mark before an OBJ's and its MTL's first statement is dropped: left in, it
/// glued itself to the first `v`, which was then ignored with a warning and the faces that
/// used that vertex were refused.
#[test]
fn byte_order_marks_of_obj_and_mtl_files_are_ignored() {
    let dir = write_files(
        "obj_bom",
        &[
            (
                "bom.obj",
                "\u{feff}v 0 0 0\nv 1 0 0\nv 0 1 0\nmtllib bom.mtl\nusemtl red\nf 1 2 3\n",
            ),
            ("bom.mtl", "\u{feff}newmtl red\nKd 0.8 0.1 0.1\n"),
        ],
    );
    let (data, warnings) = load(&dir, "bom.obj");
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!(triangles(&data).len(), 1);
}
