//! Every kind of bad scene file gives a `LoadError` naming the file and the line/column,
//! field or path, and saying what is valid.

mod common;

use common::{write_files, CAMERA, VALID};
use ppm_core::integrator::{Radius, RenderSettings};
use ppm_scene::{load_scene_builder, parse_scene, LoadError};
use std::path::Path;

/// The error message for scene text `text` (read as `dir/bad.yml`).
fn error(text: &str) -> String {
    match parse_scene(text, Path::new("dir/bad.yml")) {
        Ok(_) => panic!("no error for:\n{text}"),
        Err(e) => {
            assert_eq!(e.path(), Path::new("dir/bad.yml"));
            e.to_string()
        }
    }
}

/// The error loading the scene file at `path`.
fn load_err(path: &Path) -> LoadError {
    match load_scene_builder(path) {
        Ok(_) => panic!("no error for {}", path.display()),
        Err(e) => e,
    }
}

/// Asserts that `message` contains every needle.
fn has(message: &str, needles: &[&str]) {
    for n in needles {
        assert!(message.contains(n), "`{n}` missing from: {message}");
    }
}

/// VALID with `from` replaced by `to` (which must occur).
fn valid_with(from: &str, to: &str) -> String {
    assert!(VALID.contains(from), "{from}");
    VALID.replacen(from, to, 1)
}

#[test]
fn the_valid_scene_loads() {
    let (b, warnings) = parse_scene(VALID, Path::new("dir/ok.yml")).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!((b.camera.width, b.camera.height), (64, 48));
    assert_eq!(b.materials.len(), 2);
    assert_eq!(b.materials[0].name, "white");
    assert_eq!(b.meshes.len(), 1);
    assert_eq!(b.spheres.len(), 1);
}

#[test]
fn yaml_syntax_errors_give_line_and_column() {
    let e = error(&format!(
        "{CAMERA}materials:\n  white: {{ type: diffuse, color: [0.5, 0.5, 0.5]\n"
    ));
    assert!(e.starts_with("dir/bad.yml:"), "{e}");
    let line: usize = e.split(':').nth(1).unwrap().parse().unwrap();
    assert!((2..=4).contains(&line), "{e}");
    let e = error(&format!(
        "{CAMERA}objects:\n  - type: quad\n   bad_indent: 1\n"
    ));
    assert!(e.starts_with("dir/bad.yml:4:"), "{e}");
}

#[test]
fn unknown_keys_are_errors() {
    let e = error(&format!("{CAMERA}objets: []\n"));
    has(
        &e,
        &["dir/bad.yml:2:1:", "unknown field `objets`", "objects"],
    );
    let e = error(&valid_with(
        "color: [0.7, 0.7, 0.7]",
        "colour: [0.7, 0.7, 0.7]",
    ));
    has(
        &e,
        &[
            "dir/bad.yml:4:",
            "materials.white",
            "unknown field `colour`",
        ],
    );
    let e = error(&valid_with("fov: 38", "fov: 38, aperture: 2"));
    has(
        &e,
        &["dir/bad.yml:1:", "camera", "unknown field `aperture`"],
    );
    let e = error(&format!("{VALID}render: {{ photon: 5 }}\n"));
    has(
        &e,
        &[
            "dir/bad.yml:9:",
            "render",
            "unknown field `photon`",
            "photons",
        ],
    );
}

#[test]
fn unknown_types_list_the_valid_ones() {
    let e = error(&valid_with("type: diffuse", "type: difuse"));
    has(
        &e,
        &[
            "dir/bad.yml:4:",
            "materials.white.type",
            "`difuse`",
            "diffuse",
            "mirror",
            "glass",
            "phong",
        ],
    );
    let e = error(&valid_with("type: sphere", "type: cube"));
    has(
        &e,
        &[
            "dir/bad.yml:8:",
            "objects[1].type",
            "`cube`",
            "mesh",
            "sphere",
            "quad",
        ],
    );
    let e = error(&format!(
        "{VALID}lights:\n  - {{ type: distant, position: [0, 1, 0], intensity: [1, 1, 1] }}\n"
    ));
    has(
        &e,
        &[
            "dir/bad.yml:10:",
            "lights[0].type",
            "`distant`",
            "point",
            "spot",
        ],
    );
    let e = error(&valid_with("type: diffuse, color", "color"));
    has(&e, &["materials.white", "missing field `type`"]);
}

#[test]
fn fields_must_fit_the_type() {
    let e = error(&valid_with(
        "color: [0.7, 0.7, 0.7] }",
        "color: [0.7, 0.7, 0.7], ior: 1.5 }",
    ));
    has(
        &e,
        &[
            "dir/bad.yml: materials.white:",
            "`ior` does not apply to a diffuse material",
            "color, emission",
        ],
    );
    let e = error(&valid_with("radius: 0.1,", "radius: 0.1, file: a.obj,"));
    has(&e, &["objects[1]", "`file` does not apply to a sphere"]);
    let e = error(&valid_with(
        "{ type: diffuse, color: [0.7, 0.7, 0.7] }",
        "{ type: diffuse }",
    ));
    has(&e, &["materials.white", "diffuse material needs `color`"]);
    let e = error(&valid_with(
        "{ type: diffuse, color: [0.7, 0.7, 0.7] }",
        "{ type: glass }",
    ));
    has(&e, &["materials.white", "glass material needs `ior`"]);
    let e = error(&valid_with("radius: 0.1, ", ""));
    has(&e, &["objects[1]", "sphere needs `radius`"]);
    let e = error(&valid_with(", material: lamp", ""));
    has(&e, &["objects[1]", "sphere needs `material`"]);
    let e = error(&format!("{VALID}  - {{ type: mesh }}\n"));
    has(&e, &["objects[2]", "mesh needs `file`"]);
}

#[test]
fn undefined_materials_are_named_with_the_defined_ones() {
    let e = error(&valid_with("material: lamp", "material: lmap"));
    has(
        &e,
        &[
            "dir/bad.yml: objects[1].material:",
            "undefined material `lmap`",
            "defined: white, lamp",
        ],
    );
}

#[test]
fn duplicate_material_names_are_errors() {
    let e = error(&valid_with("  lamp:", "  white: { type: mirror }\n  lamp:"));
    has(&e, &["dir/bad.yml:5:", "material `white` is defined twice"]);
}

#[test]
fn degenerate_cameras_are_errors() {
    let e = error(&valid_with("up: [0, 1, 0]", "up: [0, 0, 1]"));
    has(&e, &["dir/bad.yml: camera:", "parallel"]);
    let e = error(&valid_with("up: [0, 1, 0]", "up: [0, 0, 0]"));
    has(&e, &["camera:", "up"]);
    let e = error(&valid_with("look_at: [0, 1, 0]", "look_at: [0, 1, 3.9]"));
    has(&e, &["camera:", "look_at"]);
    for fov in ["0", "180", "-5", "200", ".nan"] {
        let e = error(&valid_with("fov: 38", &format!("fov: {fov}")));
        has(&e, &["dir/bad.yml:1:", "camera.fov", "(0, 180) degrees"]);
    }
    let e = error(&valid_with(
        "position: [0, 1, 3.9]",
        "position: [0, .inf, 3.9]",
    ));
    has(
        &e,
        &["dir/bad.yml:1:", "camera.position", "component 1", "finite"],
    );
    let e = error("resolution: [4, 4]\n");
    has(&e, &["dir/bad.yml", "missing field `camera`"]);
}

#[test]
fn bad_resolutions_are_errors() {
    for (res, needle) in [
        ("[0, 48]", "width 0"),
        ("[64, 0]", "height 0"),
        ("[100000, 48]", "width 100000"),
        ("[-64, 48]", "width -64"),
    ] {
        let e = error(&valid_with("[64, 48]", res));
        has(&e, &["dir/bad.yml:2:", "resolution", needle, "1..=16384"]);
    }
    let e = error(&valid_with("[64, 48]", "[64]"));
    has(&e, &["dir/bad.yml:2:", "resolution", "[width, height]"]);
    let e = error(&valid_with("[64, 48]", "[64.5, 48]"));
    has(
        &e,
        &[
            "dir/bad.yml:2:",
            "resolution[0]: 64.5 is not a whole number",
        ],
    );
    let e = error(&valid_with("[64, 48]", "[64, 1e30]"));
    has(&e, &["resolution[1]: 1e30 is out of range", "1..=16384"]);
}

/// YAML reads `2e5` as a float: a count or a size written that way is taken when it is
/// whole (scene format v1 extended; whole numbers written as integers load as before).
#[test]
fn whole_numbers_may_be_written_with_an_exponent() {
    let text = format!(
        "{}render: {{ photons: 2e5, max_depth: 1.2e1 }}\n",
        valid_with("[64, 48]", "[6.4e1, 48.0]")
    );
    let (b, _) = parse_scene(&text, Path::new("dir/ok.yml")).unwrap();
    assert_eq!((b.camera.width, b.camera.height), (64, 48));
    assert_eq!(b.defaults.photons, Some(200_000));
    assert_eq!(b.defaults.max_depth, 12);
}

#[test]
fn bad_numbers_say_what_is_valid() {
    let cases = [
        (
            "color: [0.7, 0.7, 0.7]",
            "color: [0.7, -0.5, 0.7]",
            "materials.white.color",
            "component 1 is -0.5",
        ),
        (
            "color: [0.7, 0.7, 0.7]",
            "color: [0.7, .nan, 0.7]",
            "materials.white.color",
            "[0, 1]",
        ),
        (
            "color: [0.7, 0.7, 0.7]",
            "color: [1.5, 0.7, 0.7]",
            "materials.white.color",
            "reflectance in [0, 1]",
        ),
        (
            "color: [0.7, 0.7, 0.7]",
            "color: [0.7, 0.7]",
            "materials.white.color",
            "three numbers",
        ),
        (
            "color: [0.7, 0.7, 0.7]",
            "color: [0.7, 0.7, red]",
            "materials.white.color[2]",
            "invalid type",
        ),
        (
            "emission: [10, 10, 10]",
            "emission: [10, -1, 10]",
            "materials.lamp.emission",
            ">= 0",
        ),
        (
            "emission: [10, 10, 10]",
            "emission: [10, .inf, 10]",
            "materials.lamp.emission",
            "finite",
        ),
        ("radius: 0.1", "radius: 0", "objects[1].radius", "> 0"),
        ("radius: 0.1", "radius: -2", "objects[1].radius", "> 0"),
        (
            "center: [0, 1.5, 0]",
            "center: [0, .nan, 0]",
            "objects[1].center",
            "finite",
        ),
        (
            "edge_u: [0, 0, 2]",
            "edge_u: [0, 0, 1e39]",
            "objects[0].edge_u",
            "finite",
        ),
    ];
    for (from, to, field, needle) in cases {
        let e = error(&valid_with(from, to));
        assert!(e.starts_with("dir/bad.yml:"), "{e}");
        has(&e, &[field, needle]);
        // Line and column are given.
        let mut parts = e.split(':');
        parts.next();
        assert!(
            parts.next().unwrap().parse::<usize>().is_ok()
                && parts.next().unwrap().parse::<usize>().is_ok(),
            "{e}"
        );
    }
    let glass = |ior: &str| {
        valid_with(
            "lamp: {",
            &format!("glass: {{ type: glass, ior: {ior} }}\n  lamp: {{"),
        )
    };
    for ior in ["0", "-1.5", ".nan"] {
        let e = error(&glass(ior));
        has(&e, &["dir/bad.yml:5:", "materials.glass.ior", "> 0"]);
    }
    for (render, needle) in [
        ("alpha: 1.5", "render.alpha"),
        ("alpha: 0", "render.alpha"),
        ("photons: 0", "render.photons"),
        ("max_depth: -1", "render.max_depth"),
        ("radius: -0.1", "render.radius"),
        (
            "photons: 1e10",
            "render.photons: 10000000000 is out of range",
        ),
        (
            "photons: 2.5e-1",
            "render.photons: 0.25 is not a whole number",
        ),
        (
            "max_depth: 8.5",
            "render.max_depth: 8.5 is not a whole number",
        ),
    ] {
        let e = error(&format!("{VALID}render: {{ {render} }}\n"));
        has(&e, &["dir/bad.yml:9:", needle]);
    }
    let e = error(&format!(
        "{VALID}lights:\n  - {{ type: point, position: [0, 1, 0], intensity: [1, -1, 1] }}\n"
    ));
    has(&e, &["dir/bad.yml:10:", "lights[0].intensity", ">= 0"]);
}

#[test]
fn phong_creating_energy_is_an_error_naming_the_material() {
    let phong =
        "shiny: { type: phong, diffuse: [0.5, 0.2, 0.2], specular: [0.6, 0.3, 0.3], exponent: 20 }";
    let e = error(&valid_with("lamp: {", &format!("{phong}\n  lamp: {{")));
    has(
        &e,
        &[
            "dir/bad.yml: materials.shiny:",
            "diffuse + specular",
            "red channel",
            "<= 1",
        ],
    );
    let ok =
        "shiny: { type: phong, diffuse: [0.5, 0.2, 0.2], specular: [0.5, 0.3, 0.3], exponent: 20 }";
    parse_scene(
        &valid_with("lamp: {", &format!("{ok}\n  lamp: {{")),
        Path::new("ok.yml"),
    )
    .unwrap();
}

#[test]
fn quads_without_area_are_errors() {
    let e = error(&valid_with("edge_v: [2, 0, 0]", "edge_v: [0, 0, 4]"));
    has(&e, &["dir/bad.yml: objects[0]:", "no area"]);
    let e = error(&valid_with("edge_v: [2, 0, 0]", "edge_v: [0, 0, 0]"));
    has(&e, &["objects[0]", "no area"]);
}

#[test]
fn missing_and_unreadable_files_name_the_path_tried() {
    let dir = write_files(
        "errors_missing_obj",
        &[(
            "s.yml",
            &format!("{VALID}  - {{ type: mesh, file: meshes/missing.obj }}\n"),
        )],
    );
    let e = load_err(&dir.join("s.yml"));
    assert!(matches!(e, LoadError::Io { .. }));
    let e = e.to_string();
    has(
        &e,
        &[
            &dir.join("meshes/missing.obj").display().to_string(),
            "objects[2].file",
            "s.yml",
        ],
    );
    // A folder is not a mesh.
    let dir = write_files(
        "errors_dir_obj",
        &[("s.yml", &format!("{VALID}  - {{ type: mesh, file: . }}\n"))],
    );
    let e = load_err(&dir.join("s.yml")).to_string();
    has(&e, &["not a regular file"]);
    // The scene file itself.
    let e = load_err(Path::new("no/such/scene.yml")).to_string();
    has(&e, &["no/such/scene.yml", "cannot read scene file"]);
}

#[test]
fn obj_errors_name_the_obj_file_and_line() {
    let dir = write_files(
        "errors_bad_obj",
        &[
            (
                "s.yml",
                &format!("{VALID}  - {{ type: mesh, file: bad.obj, material: white }}\n"),
            ),
            ("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n"),
        ],
    );
    let e = load_err(&dir.join("s.yml")).to_string();
    assert!(
        e.starts_with(&format!("{}:4:", dir.join("bad.obj").display())),
        "{e}"
    );
}

#[test]
fn odd_documents_are_errors() {
    has(&error(""), &["dir/bad.yml", "missing field `camera`"]);
    has(
        &error(&format!("{VALID}---\n{VALID}")),
        &["dir/bad.yml", "more than one document"],
    );
    has(&error("- 1\n- 2\n"), &["dir/bad.yml:1:1:", "invalid type"]);
    has(
        &error(&format!("{CAMERA}objects: {{}}\n")),
        &["dir/bad.yml:2:", "objects"],
    );
}

#[test]
fn a_non_yaml_file_is_quoted_by_one_short_line() {
    // An OBJ read as a scene: YAML folds its lines into one 40 KB string.
    let obj: String = (0..2000)
        .map(|i| format!("v {i} 0.5 0.25\n"))
        .chain((1..1000).map(|i| format!("f {i} {} {}\n", i + 1, i + 2)))
        .collect();
    let msg = error(&obj);
    has(&msg, &["dir/bad.yml", "invalid type", "\"v 0 0.5 0.25"]);
    assert!(msg.lines().count() == 1 && msg.len() < 200, "{msg}");
}

#[test]
fn warnings_for_suspicious_but_valid_scenes() {
    let dark = valid_with("emission: [10, 10, 10]", "emission: [0, 0, 0]");
    let (_, warnings) = parse_scene(&dark, Path::new("dir/dark.yml")).unwrap();
    assert!(
        warnings
            .iter()
            .any(|w| w.starts_with("dir/dark.yml") && w.contains("no light")),
        "{warnings:?}"
    );
    let unused = valid_with("materials:\n", "materials:\n  spare: { type: mirror }\n");
    let (_, warnings) = parse_scene(&unused, Path::new("dir/unused.yml")).unwrap();
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("materials.spare") && w.contains("never used")),
        "{warnings:?}"
    );
    // A point light is a light.
    let lit = format!(
        "{dark}lights:\n  - {{ type: point, position: [0, 1, 0], intensity: [1, 1, 1] }}\n"
    );
    let (b, warnings) = parse_scene(&lit, Path::new("dir/lit.yml")).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!(b.lights.len(), 1);
    // A Phong exponent beyond what ppm renders is said, with the value used.
    let sharp = valid_with(
        "white: { type: diffuse, color: [0.7, 0.7, 0.7] }",
        "white: { type: phong, diffuse: [0.1, 0.1, 0.1], specular: [0.8, 0.8, 0.8], exponent: 1e25 }",
    );
    let (b, warnings) = parse_scene(&sharp, Path::new("dir/sharp.yml")).unwrap();
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    has(
        &warnings[0],
        &[
            "dir/sharp.yml: materials.white.exponent: 1e25 is rendered as 1e10",
            "type: mirror",
        ],
    );
    match b.materials[0].bsdf {
        ppm_core::bsdf::Bsdf::Phong(p) => assert_eq!(p.exponent, 1e10),
        ref other => panic!("{other:?}"),
    }
}

/// A lamp quad in the plane of the floor is named; lifted by a millimetre it is not.
#[test]
fn a_lamp_in_another_surfaces_plane_is_warned_about() {
    for (y, warned) in [("0", true), ("0.001", false)] {
        let text = format!(
            "{VALID}  - {{ type: quad, corner: [-0.2, {y}, -0.2], edge_u: [0.4, 0, 0], edge_v: [0, 0, 0.4], material: lamp }}\n"
        );
        let dir = write_files(&format!("coplanar_lamp_{y}"), &[("lamp.yml", &text)]);
        let loaded = ppm_scene::load_scene(&dir.join("lamp.yml")).unwrap();
        let found = loaded
            .warnings
            .iter()
            .any(|w| w.contains("light of material `lamp` lies in the plane of another surface"));
        assert_eq!(found, warned, "lamp at y = {y}: {:?}", loaded.warnings);
    }
}

/// A lamp quad far smaller than the f32 spacing at its distance from the camera loses its
/// area when the scene is built: the loader names it (beside a lamp sphere of the same
/// material, which still emits); a quad of 1 cm there is not named.
#[test]
fn a_lamp_without_area_in_single_precision_is_warned_about() {
    for (side, warned) in [("1e-9", true), ("0.01", false)] {
        let text = format!(
            "{VALID}  - {{ type: quad, corner: [0.3, 1.5, 0], edge_u: [{side}, 0, 0], edge_v: [0, 0, {side}], material: lamp }}\n"
        );
        let dir = write_files(&format!("tiny_lamp_{side}"), &[("lamp.yml", &text)]);
        let loaded = ppm_scene::load_scene(&dir.join("lamp.yml")).unwrap();
        let found = loaded.warnings.iter().any(|w| {
            w.contains("the 2 triangles of light material `lamp` emit nothing")
                && w.contains("single precision")
        });
        assert_eq!(found, warned, "side {side}: {:?}", loaded.warnings);
    }
}

#[test]
fn optional_parts_have_documented_defaults() {
    let text = format!("{CAMERA}materials:\n  m: {{ type: mirror }}\n  g: {{ type: glass, ior: 1.5 }}\nobjects:\n  - {{ type: sphere, center: [0, 1, 0], radius: 0.5, material: m, inward: true }}\n  - {{ type: sphere, center: [0, 1, 0], radius: 0.2, material: g }}\n");
    let (b, _) = parse_scene(&text, Path::new("d.yml")).unwrap();
    assert_eq!(
        (b.camera.width, b.camera.height),
        ppm_scene::DEFAULT_RESOLUTION
    );
    assert_eq!(b.defaults, ppm_core::scene::RenderDefaults::default());
    assert!(
        matches!(b.materials[0].bsdf, ppm_core::bsdf::Bsdf::Mirror(m) if m.color == glam::Vec3::ONE)
    );
    assert!(
        matches!(b.materials[1].bsdf, ppm_core::bsdf::Bsdf::Glass(g) if g.color == glam::Vec3::ONE)
    );
    assert!(b.spheres[0].inward && !b.spheres[1].inward);
    // Empty sections are allowed.
    let (b, warnings) = parse_scene(
        &format!("{CAMERA}materials:\nobjects:\nlights:\n"),
        Path::new("d.yml"),
    )
    .unwrap();
    assert!(b.materials.is_empty() && b.meshes.is_empty());
    assert!(warnings.iter().any(|w| w.contains("no light")));
    // render: values are taken over.
    let (b, _) = parse_scene(
        &format!("{VALID}render: {{ max_depth: 7, photons: 1234, radius: 0.05, alpha: 0.5 }}\n"),
        Path::new("d.yml"),
    )
    .unwrap();
    assert_eq!(
        (
            b.defaults.max_depth,
            b.defaults.photons,
            b.defaults.radius,
            b.defaults.alpha
        ),
        (7, Some(1234), Some(Radius::World(0.05)), 0.5)
    );
}

#[test]
fn render_algorithm_names_an_integrator_as_the_command_line_does() {
    use ppm_core::integrator::Algorithm;
    let algorithm = |value: &str| {
        parse_scene(
            &format!("{VALID}render: {{ algorithm: {value} }}\n"),
            Path::new("d.yml"),
        )
        .map(|(b, _)| b.defaults.algorithm)
    };
    for (name, expected) in [
        ("pt", Algorithm::Path),
        ("ppm", Algorithm::Ppm),
        ("sppm", Algorithm::Sppm),
        ("vcm", Algorithm::Vcm),
    ] {
        assert_eq!(algorithm(name).unwrap(), Some(expected), "{name}");
    }
    let e = error(&format!("{VALID}render: {{ algorithm: mlt }}\n"));
    has(&e, &["dir/bad.yml:9:", "render.algorithm", "vcm"]);
}

/// `render.algorithm` takes what `-a` takes: every name and alias of the algorithm table.
#[test]
fn render_algorithm_takes_every_name_and_alias_of_the_table() {
    use ppm_core::integrator::Algorithm;
    for entry in Algorithm::TABLE {
        for name in std::iter::once(&entry.name).chain(entry.aliases) {
            let (builder, _) = parse_scene(
                &format!("{VALID}render: {{ algorithm: {name} }}\n"),
                Path::new("d.yml"),
            )
            .unwrap();
            assert_eq!(builder.defaults.algorithm, Some(entry.algorithm), "{name}");
        }
    }
    let e = error(&format!("{VALID}render: {{ algorithm: PPM }}\n"));
    has(&e, &["render.algorithm", "`pt`, `ppm`, `sppm`, `vcm`"]);
}

#[test]
fn render_radius_is_a_number_or_auto() {
    let radius = |value: &str| {
        parse_scene(
            &format!("{VALID}render: {{ radius: {value} }}\n"),
            Path::new("d.yml"),
        )
        .map(|(b, _)| b.defaults.radius)
    };
    // `auto` keeps meaning per-pixel footprints, also spelt `footprint`; `photons` is the
    // default (None: no radius in the file); numbers keep their meaning (format v1).
    assert_eq!(radius("auto").unwrap(), Some(Radius::Auto));
    assert_eq!(radius("footprint").unwrap(), Some(Radius::Auto));
    assert_eq!(radius("photons").unwrap(), Some(Radius::Photons));
    assert_eq!(radius("2").unwrap(), Some(Radius::World(2.0)));
    assert_eq!(radius("0.05").unwrap(), Some(Radius::World(0.05)));
    let (b, _) = parse_scene(VALID, Path::new("d.yml")).unwrap();
    assert_eq!(b.defaults.radius, None);
    assert_eq!(
        RenderSettings::new(&b.build().unwrap()).radius,
        Radius::Photons
    );
    for (bad, needle) in [
        ("Auto", "`Auto` is not a radius"),
        ("0", "> 0"),
        ("-1", "> 0"),
        (".nan", "> 0"),
        ("[1, 2]", "`photons`, `footprint`, `auto`"),
        ("photon", "`photon` is not a radius"),
    ] {
        let e = error(&format!("{VALID}render: {{ radius: {bad} }}\n"));
        has(&e, &["render.radius", needle]);
        assert!(e.starts_with("dir/bad.yml:"), "{e}");
    }
}

#[test]
fn relative_mesh_paths_are_relative_to_the_scene_file() {
    let dir = write_files(
        "errors_relative",
        &[
            (
                "sub/s.yml",
                &format!("{VALID}  - {{ type: mesh, file: ../meshes/t.obj }}\n"),
            ),
            (
                "meshes/t.obj",
                "mtllib t.mtl\nusemtl red\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
            ),
            ("meshes/t.mtl", "newmtl red\nKd 0.9 0.1 0.1\n"),
        ],
    );
    let (b, warnings) = load_scene_builder(&dir.join("sub/s.yml")).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    // MTL materials follow the scene's own; the mesh's triangles point at them.
    assert_eq!(b.materials.len(), 3);
    assert_eq!(b.materials[2].name, "red");
    assert_eq!(b.meshes.last().unwrap().materials, vec![2]);
}
