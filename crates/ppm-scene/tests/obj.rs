//! OBJ parsing: quirks of the format (polygons, negative indices, continuations, free-form
//! statements), vertex normals, degenerate geometry and errors naming the file and line.
//! MTL libraries and the MTL -> BSDF mapping are tested in mtl.rs.

mod common;

use common::{load, write_files, SQUARE};
use glam::Vec3;
use ppm_core::bsdf::Bsdf;
use ppm_scene::obj::{parse_obj, ObjData, ObjMaterials};
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

/// Skipped faces and texture coordinates out of range are counted, with the line of the
/// first, so a user can find them in a large export.
#[test]
fn skipped_and_odd_faces_are_warned_about_with_their_first_line() {
    let (data, warnings) = parse(&format!(
        "{SQUARE}vt 0 0\nf 1 2\nf 1/1 2/1 3/1\nf 1/2 2/2 3/2\nf 2 3\nf 1/-3 3/1 4/1\n"
    ));
    assert_eq!(triangles(&data).len(), 3, "{warnings:?}");
    let find = |needle: &str| {
        warnings
            .iter()
            .find(|w| w.contains(needle))
            .unwrap_or_else(|| panic!("no `{needle}` in {warnings:?}"))
            .clone()
    };
    let short = find("fewer than 3 vertices");
    assert!(
        short.starts_with("mem/test.obj:6: skipped 2 faces") && short.contains("first"),
        "{short}"
    );
    let texcoords = find("texture coordinate index out of range");
    assert!(
        texcoords.starts_with("mem/test.obj:8: 2 faces have"),
        "{texcoords}"
    );
    let (_, warnings) = parse(&format!("{SQUARE}f 1 2\nl 1 2\n"));
    assert!(
        warnings
            .iter()
            .any(|w| w.starts_with("mem/test.obj:5: skipped 1 face with")),
        "{warnings:?}"
    );
    assert!(
        warnings
            .iter()
            .any(|w| w.starts_with("mem/test.obj:6: ignored 1 line or point element")),
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
