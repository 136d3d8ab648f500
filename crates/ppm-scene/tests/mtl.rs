//! MTL libraries (missing, several per file, found by bare file name, overridden) and the
//! MTL -> BSDF mapping table, with its warnings and errors naming the MTL file and line.

mod common;

use common::{load, write_files, SQUARE};
use glam::Vec3;
use ppm_core::bsdf::Bsdf;
use ppm_core::geometry::TriangleMesh;
use ppm_scene::mtl::{mtl_to_material, parse_mtl};
use ppm_scene::obj::{load_obj, ObjMaterials};
use ppm_scene::LoadError;
use std::path::Path;

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
    let text =
        "Kd 1 1 1\nnewmtl a\nKd spectral x.rfl\nmap_bump tex.png\nnewmtl a\nKd 0.1 0.1 0.1\n";
    let mats = parse_mtl(text, Path::new("t.mtl"), &mut warnings).unwrap();
    assert_eq!(mats.len(), 2);
    assert_eq!(mats[0].kd, None);
    for needle in [
        "before any `newmtl`",
        "spectral",
        "map_bump",
        "defined again",
    ] {
        assert!(
            warnings
                .iter()
                .any(|w| w.starts_with("t.mtl") && w.contains(needle)),
            "{needle}: {warnings:?}"
        );
    }
}

/// A statement of no MTL dialect (a typo, usually) is named with its first line; the ones
/// exporters write and ppm has no use for (Ka, Tr, the PBR extension) are ignored silently.
#[test]
fn unknown_mtl_statements_are_named_and_known_unused_ones_are_not() {
    let mut warnings = Vec::new();
    let text = "newmtl a\nKa 0 0 0\nTr 0\nPr 0.5\nKdd 0.5 0.5 0.5\nKdd 1 1 1\nNss 10\n";
    parse_mtl(text, Path::new("t.mtl"), &mut warnings).unwrap();
    assert_eq!(
        warnings,
        ["t.mtl:5: ignored unknown statements: Kdd, Nss (the first on this line)"]
    );
}

/// An `Ns` beyond what ppm renders is said, with the exponent used.
#[test]
fn an_mtl_exponent_beyond_the_largest_is_said() {
    let mut warnings = Vec::new();
    let text = "newmtl sharp\nKd 0.1 0.1 0.1\nKs 0.8 0.8 0.8\nNs 1e30\n";
    let mats = parse_mtl(text, Path::new("t.mtl"), &mut warnings).unwrap();
    let material = mtl_to_material(&mats[0], Path::new("t.mtl"), &mut warnings);
    assert_eq!(
        warnings,
        ["t.mtl:1: material `sharp`: Ns 1e30 is rendered as 1e10, the largest exponent ppm renders"]
    );
    match material.bsdf {
        Bsdf::Phong(p) => assert_eq!(p.exponent, 1e10),
        other => panic!("{other:?}"),
    }
}

/// A material's warnings, met while loading the OBJ that uses it, name the MTL file and the
/// line of its `newmtl`, not the OBJ; ignored texture maps name their first line.
#[test]
fn material_warnings_name_the_mtl_line_not_the_obj() {
    let dir = write_files(
        "mtl_warning_lines",
        &[
            (
                "a.obj",
                &format!("mtllib m.mtl\nusemtl hot\n{SQUARE}f 1 2 3\n"),
            ),
            (
                "m.mtl",
                "# a library\nnewmtl plain\nKd 0.5 0.5 0.5\nnewmtl hot\nKd 3 0 0\nbump t.png\n",
            ),
        ],
    );
    let (_, warnings) = load(&dir, "a.obj");
    let mtl = dir.join("m.mtl").display().to_string();
    assert!(
        warnings
            .iter()
            .any(|w| w.starts_with(&format!("{mtl}:4: material `hot`: Kd reaches 3"))),
        "{warnings:?}"
    );
    assert!(
        warnings.iter().any(|w| w.starts_with(&format!(
            "{mtl}:6: texture maps other than map_Kd and map_Ks are not supported"
        ))),
        "{warnings:?}"
    );
}
