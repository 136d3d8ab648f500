//! The pbrt-v4 parse layer, directive by directive: transforms, the graphics state,
//! includes, object instances, attributes; and its errors, each naming the file, line and
//! column.

mod common;

use common::write_files;
use glam::Vec3;
use ppm_core::scene::SceneBuilder;
use ppm_scene::pbrt::parse_pbrt;
use ppm_scene::{load_scene_builder, LoadError};
use std::path::Path;

/// A right-handed camera (`Scale -1 1 1`: no world mirror, so positions are as written),
/// then WorldBegin and `body`.
fn scene(body: &str) -> String {
    format!(
        "Scale -1 1 1\nLookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\nFilm \"rgb\" \"integer xresolution\" 40 \"integer yresolution\" 20\nWorldBegin\nLightSource \"point\" \"point3 from\" [0 3 3]\n{body}"
    )
}

fn load(text: &str) -> Result<(SceneBuilder, Vec<String>), LoadError> {
    parse_pbrt(text, Path::new("scene.pbrt"))
}

fn file_error(path: &Path) -> String {
    match load_scene_builder(path) {
        Ok(_) => panic!("loaded {}", path.display()),
        Err(e) => e.to_string(),
    }
}

fn error(text: &str) -> String {
    match load(text) {
        Ok(_) => panic!("loaded:\n{text}"),
        Err(e) => e.to_string(),
    }
}

/// One triangle (0,0,0), (1,0,0), (0,1,0), facing +z.
const TRIANGLE: &str =
    "Shape \"trianglemesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0] \"integer indices\" [0 1 2]\n";

/// The corners of the first triangle of mesh `i`, in winding order.
fn corners(b: &SceneBuilder, i: usize) -> [Vec3; 3] {
    let m = &b.meshes[i];
    m.indices[0].map(|k| m.positions[k as usize])
}

fn close(a: [Vec3; 3], b: [Vec3; 3]) -> bool {
    a.iter().zip(&b).all(|(a, b)| a.abs_diff_eq(*b, 1e-5))
}

#[test]
fn transforms_compose_as_pbrt_post_multiplies_them() {
    let cases: &[(&str, [Vec3; 3])] = &[
        ("", [Vec3::ZERO, Vec3::X, Vec3::Y]),
        ("Translate 1 2 3", [Vec3::new(1.0, 2.0, 3.0), Vec3::new(2.0, 2.0, 3.0), Vec3::new(1.0, 3.0, 3.0)]),
        ("Scale 2 3 4", [Vec3::ZERO, 2.0 * Vec3::X, 3.0 * Vec3::Y]),
        ("Rotate 90 0 0 1", [Vec3::ZERO, Vec3::Y, -Vec3::X]),
        // CTM = T * S: the triangle is scaled, then moved.
        ("Translate 1 0 0 Scale 2 2 2", [Vec3::X, 3.0 * Vec3::X, Vec3::new(1.0, 2.0, 0.0)]),
        ("Scale 2 2 2 Translate 1 0 0", [2.0 * Vec3::X, 4.0 * Vec3::X, Vec3::new(2.0, 2.0, 0.0)]),
        // 16 numbers, column-major: the translation is the last four but one.
        ("Transform [1 0 0 0  0 1 0 0  0 0 1 0  5 6 7 1]", [Vec3::new(5.0, 6.0, 7.0), Vec3::new(6.0, 6.0, 7.0), Vec3::new(5.0, 7.0, 7.0)]),
        ("Translate 9 9 9 Transform [2 0 0 0  0 2 0 0  0 0 2 0  0 0 0 1]", [Vec3::ZERO, 2.0 * Vec3::X, 2.0 * Vec3::Y]),
        ("Translate 0 0 1 ConcatTransform [1 0 0 0  0 1 0 0  0 0 1 0  1 0 0 1]", [Vec3::new(1.0, 0.0, 1.0), Vec3::new(2.0, 0.0, 1.0), Vec3::new(1.0, 1.0, 1.0)]),
        ("Translate 9 9 9 Identity", [Vec3::ZERO, Vec3::X, Vec3::Y]),
        ("Translate 1 0 0 CoordinateSystem \"a\" Identity Translate 0 5 0 CoordSysTransform \"a\"", [Vec3::X, 2.0 * Vec3::X, Vec3::new(1.0, 1.0, 0.0)]),
        ("TransformBegin Translate 4 0 0 TransformEnd", [Vec3::ZERO, Vec3::X, Vec3::Y]),
        ("AttributeBegin Translate 4 0 0 AttributeEnd", [Vec3::ZERO, Vec3::X, Vec3::Y]),
        ("ActiveTransform All TransformTimes 0 1", [Vec3::ZERO, Vec3::X, Vec3::Y]),
    ];
    for (transform, want) in cases {
        let (b, _) = load(&scene(&format!("{transform}\n{TRIANGLE}"))).unwrap();
        let got = corners(&b, 0);
        assert!(close(got, *want), "{transform}: {got:?} != {want:?}");
    }
    // LookAt as a transform, and the camera's coordinate system.
    let (b, _) = load(&scene(&format!("CoordSysTransform \"camera\"\n{TRIANGLE}"))).unwrap();
    assert!(b.meshes[0].positions[0].abs_diff_eq(Vec3::new(0.0, 0.0, 5.0), 1e-5));
}

#[test]
fn reverse_orientation_mirrors_and_normals_decide_the_facing() {
    let normal = |b: &SceneBuilder| {
        let [a, p, q] = corners(b, 0);
        (p - a).cross(q - a).normalize()
    };
    let (b, _) = load(&scene(TRIANGLE)).unwrap();
    assert!(normal(&b).abs_diff_eq(Vec3::Z, 1e-6));
    let (b, _) = load(&scene(&format!("ReverseOrientation\n{TRIANGLE}"))).unwrap();
    assert!(normal(&b).abs_diff_eq(-Vec3::Z, 1e-6));
    // A mirroring transform keeps the facing (pbrt's transformSwapsHandedness), unless
    // combined with ReverseOrientation.
    let (b, _) = load(&scene(&format!("Scale 1 1 -1\n{TRIANGLE}"))).unwrap();
    assert!(normal(&b).abs_diff_eq(-Vec3::Z, 1e-6), "{:?}", normal(&b));
    let (b, _) = load(&scene(&format!("Scale 1 -1 1\n{TRIANGLE}"))).unwrap();
    assert!(normal(&b).abs_diff_eq(Vec3::Z, 1e-6), "{:?}", normal(&b));
    let (b, _) = load(&scene(&format!(
        "Scale 1 -1 1 ReverseOrientation\n{TRIANGLE}"
    )))
    .unwrap();
    assert!(normal(&b).abs_diff_eq(-Vec3::Z, 1e-6));
    // AttributeEnd restores the orientation.
    let (b, _) = load(&scene(&format!(
        "AttributeBegin ReverseOrientation AttributeEnd\n{TRIANGLE}"
    )))
    .unwrap();
    assert!(normal(&b).abs_diff_eq(Vec3::Z, 1e-6));
    // Vertex normals decide: the triangle turns to face them.
    let with_n = "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"normal N\" [0 0 -1 0 0 -1 0 0 -1]";
    let (b, _) = load(&scene(with_n)).unwrap();
    assert!(normal(&b).abs_diff_eq(-Vec3::Z, 1e-6));
    assert!(b.meshes[0].normals[0].abs_diff_eq(-Vec3::Z, 1e-6));
    let (b, _) = load(&scene(&format!("ReverseOrientation {with_n}"))).unwrap();
    assert!(normal(&b).abs_diff_eq(Vec3::Z, 1e-6));
    assert!(b.meshes[0].normals[0].abs_diff_eq(Vec3::Z, 1e-6));
}

#[test]
fn includes_are_relative_to_the_including_file_and_cycles_are_errors() {
    let dir = write_files(
        "pbrt_include",
        &[
            (
                "main.pbrt",
                &scene("Include \"parts/a.pbrt\"\nImport \"parts/c.pbrt\"\n"),
            ),
            ("parts/a.pbrt", "Translate 1 0 0\nInclude \"b.pbrt\"\n"),
            ("parts/b.pbrt", TRIANGLE),
            ("parts/c.pbrt", "Translate 0 1 0\nShape \"sphere\"\n"),
            ("loop.pbrt", &scene("Include \"loop2.pbrt\"")),
            ("loop2.pbrt", "\n\nInclude \"loop.pbrt\""),
            ("missing.pbrt", &scene("Include \"nope.pbrt\"")),
        ],
    );
    let (b, _) = load_scene_builder(&dir.join("main.pbrt")).unwrap();
    assert!(close(
        corners(&b, 0),
        [Vec3::X, 2.0 * Vec3::X, Vec3::new(1.0, 1.0, 0.0)]
    ));
    // The included file's transform carries on (Include shares the graphics state).
    assert!(b.spheres[0]
        .center
        .abs_diff_eq(Vec3::new(1.0, 1.0, 0.0), 1e-6));
    let e = file_error(&dir.join("loop.pbrt"));
    assert!(
        e.contains("loop2.pbrt:3:9: ") && e.contains("loop.pbrt includes itself"),
        "{e}"
    );
    let e = file_error(&dir.join("missing.pbrt"));
    assert!(e.contains("nope.pbrt: cannot read pbrt scene file"), "{e}");
}

#[test]
fn object_instances_place_one_mesh_under_the_instance_transform() {
    let body = format!(
        "ObjectBegin \"t\"\nTranslate 0 0 1\n{TRIANGLE}ObjectEnd\nTranslate 2 0 0\nObjectInstance \"t\"\nTranslate 2 0 0\nObjectInstance \"t\"\n"
    );
    let (mut b, _) = load(&scene(&body)).unwrap();
    // One mesh (in the object's space), two placements; flattened to read their corners.
    assert!(b.meshes.is_empty());
    assert_eq!(b.instanced_meshes.len(), 1);
    assert_eq!(b.instances.len(), 2);
    for p in std::mem::take(&mut b.instances) {
        let mut mesh = b.instanced_meshes[p.mesh as usize].clone();
        ppm_scene::placement::place_mesh(&mut mesh, p.to_world, false).unwrap();
        b.meshes.push(mesh);
    }
    assert!(close(
        corners(&b, 0),
        [
            Vec3::new(2.0, 0.0, 1.0),
            Vec3::new(3.0, 0.0, 1.0),
            Vec3::new(2.0, 1.0, 1.0)
        ]
    ));
    assert!(close(
        corners(&b, 1),
        [
            Vec3::new(4.0, 0.0, 1.0),
            Vec3::new(5.0, 0.0, 1.0),
            Vec3::new(4.0, 1.0, 1.0)
        ]
    ));
    let e = error(&scene("ObjectInstance \"none\""));
    assert!(
        e.starts_with("scene.pbrt:7:16: ObjectInstance: no object \"none\""),
        "{e}"
    );
    let e = error(&scene(
        "ObjectBegin \"x\"\nAreaLightSource \"diffuse\"\nShape \"sphere\"\nObjectEnd",
    ));
    assert!(
        e.starts_with("scene.pbrt:9:1: ") && e.contains("area light"),
        "{e}"
    );
}

#[test]
fn attributes_give_defaults_and_named_materials_resolve_late() {
    let (b, _) = load(&scene("Attribute \"shape\" \"float radius\" 2\nShape \"sphere\"\nShape \"sphere\" \"float radius\" 3")).unwrap();
    assert_eq!(b.spheres[0].radius, 2.0);
    assert_eq!(b.spheres[1].radius, 3.0);
    // NamedMaterial before MakeNamedMaterial, as pbrt-v4 allows.
    let (b, _) = load(&scene("NamedMaterial \"m\"\nShape \"sphere\"\nMakeNamedMaterial \"m\" \"string type\" \"diffuse\" \"rgb reflectance\" [0.1 0.2 0.3]")).unwrap();
    let m = &b.materials[b.spheres[0].material as usize];
    assert_eq!(m.name, "m");
    assert_eq!(
        format!("{:?}", m.bsdf),
        "Diffuse(Diffuse { albedo: Vec3(0.1, 0.2, 0.3) })"
    );
    // Without a material, pbrt's default diffuse 0.5.
    let (b, _) = load(&scene("Shape \"sphere\"")).unwrap();
    let m = &b.materials[b.spheres[0].material as usize];
    assert_eq!(
        format!("{:?}", m.bsdf),
        "Diffuse(Diffuse { albedo: Vec3(0.5, 0.5, 0.5) })"
    );
    // Comments, bare single values, bools bare or quoted.
    load(&scene("# c\nShape \"sphere\" \"float radius\" 1 # c\nMaterial \"conductor\" \"bool remaproughness\" false\nMaterial \"conductor\" \"bool remaproughness\" \"true\"\nShape \"sphere\"")).unwrap();
}

#[test]
fn errors_name_the_file_line_and_column() {
    let cases: &[(&str, &str)] = &[
        (
            "Shap \"sphere\"",
            "scene.pbrt:7:1: unknown directive `Shap`",
        ),
        (
            "Shape \"sphere\" \"float radius\" [1] \"float radiu\" 2",
            "scene.pbrt:7:35: Shape \"sphere\": unknown or unsupported parameter \"float radiu\"",
        ),
        (
            "Shape \"sphere\" \"rgb radius\" [1 1 1]",
            "scene.pbrt:7:16: Shape \"sphere\": \"rgb radius\": expected type float",
        ),
        (
            "Shape \"sphere\" \"float radius\" [1 2]",
            "scene.pbrt:7:16: Shape \"sphere\": \"float radius\": 2 values, expected one",
        ),
        (
            "Shape \"sphere\" \"flot radius\" [1]",
            "scene.pbrt:7:16: \"flot radius\": unknown parameter type `flot`",
        ),
        (
            "Shape \"sphere\" \"float radius\" [1 \"a\"]",
            "scene.pbrt:7:34: \"float radius\": \"a\" mixed with values of another kind",
        ),
        (
            "Shape \"sphere\" \"float radius\" [x]",
            "scene.pbrt:7:32: expected a value for \"float radius\", found `x`",
        ),
        (
            "Shape \"sphere\" \"float radius\" [1",
            "scene.pbrt:7:33: expected `]`, found the end of the file",
        ),
        (
            "Shape \"sphere\" \"integer n\" [1.5]",
            "scene.pbrt:7:16: \"integer n\": expected integers",
        ),
        (
            "Shape \"sphere\" \"point3 p\" [1 2]",
            "scene.pbrt:7:16: \"point3 p\": 2 numbers, expected a multiple of 3",
        ),
        (
            "Shape \"sphere\" \"float radius\" 1 \"float radius\" 2",
            "scene.pbrt:7:33: parameter `radius` given twice",
        ),
        (
            "Shape \"sphere",
            "scene.pbrt:7:7: string not closed before the end of the file",
        ),
        (
            "Translate 1 2",
            "scene.pbrt:7:14: expected 3 numbers after Translate, found the end of the file",
        ),
        (
            "Rotate 10 0 0 0",
            "scene.pbrt:7:1: Rotate: the axis is zero",
        ),
        (
            "AttributeEnd",
            "scene.pbrt:7:1: AttributeEnd without a matching begin",
        ),
        (
            "AttributeBegin\nTransformEnd",
            "scene.pbrt:8:1: TransformEnd does not match the block begun at scene.pbrt:7:1",
        ),
        (
            "AttributeBegin",
            "scene.pbrt:7:1: AttributeBegin (or ObjectBegin) never ended",
        ),
        (
            "Camera \"perspective\"",
            "scene.pbrt:7:1: Camera must come before WorldBegin",
        ),
        ("WorldBegin", "scene.pbrt:7:1: a second WorldBegin"),
        (
            "CoordSysTransform \"x\"",
            "scene.pbrt:7:19: CoordSysTransform: no coordinate system \"x\"",
        ),
        (
            "ColorSpace \"aces2065-1\"",
            "scene.pbrt:7:12: ColorSpace \"aces2065-1\" is not supported yet",
        ),
        (
            "MakeNamedMedium \"fog\" \"string type\" \"homogeneous\"\nMakeNamedMedium \"fog\"",
            "scene.pbrt:8:1: medium \"fog\" defined twice",
        ),
        (
            "Attribute \"medium\" \"float sigma_s\" 0",
            "scene.pbrt:7:11: Attribute \"medium\" is not supported yet",
        ),
        (
            "ActiveTransform StartTime",
            "scene.pbrt:7:17: ActiveTransform `StartTime`: motion blur is not supported yet",
        ),
        (
            "NamedMaterial \"m\" Shape \"sphere\"",
            "scene.pbrt:7:15: NamedMaterial: no material \"m\"",
        ),
        (
            "[ 1 ]",
            "scene.pbrt:7:1: expected a directive (Shape, Material, ...), found `[`",
        ),
        (
            "Shape \"sphere\" \"float radius\" [nan]",
            "scene.pbrt:7:32: expected a value for \"float radius\", found `nan`",
        ),
    ];
    for (body, want) in cases {
        let e = error(&scene(body));
        assert!(e.starts_with(want), "{body}:\n  got  {e}\n  want {want}");
    }
    let e = error("Shape \"sphere\"");
    assert!(
        e.starts_with("scene.pbrt:1:1: Shape must come after WorldBegin"),
        "{e}"
    );
    let e = error("Camera \"perspective\"");
    assert!(e.contains("no WorldBegin"), "{e}");
}

#[test]
fn directive_and_nesting_limits_are_errors_not_crashes() {
    let deep = "AttributeBegin\n".repeat(5000);
    let e = error(&scene(&deep));
    assert!(e.contains("nested deeper than 4096"), "{e}");
    let dir = write_files("pbrt_deep_include", &[("a.pbrt", "Include \"a.pbrt\"")]);
    let e = file_error(&dir.join("a.pbrt"));
    assert!(e.contains("includes itself"), "{e}");
    // A chain of distinct files deeper than the limit.
    let files: Vec<(String, String)> = (0..40)
        .map(|i| (format!("f{i}.pbrt"), format!("Include \"f{}.pbrt\"", i + 1)))
        .collect();
    let refs: Vec<(&str, &str)> = files
        .iter()
        .map(|(a, b)| (a.as_str(), b.as_str()))
        .collect();
    let dir = write_files("pbrt_include_chain", &refs);
    let e = file_error(&dir.join("f0.pbrt"));
    assert!(e.contains("includes nested deeper than 32"), "{e}");
}

#[test]
fn spectra_can_be_read_from_files() {
    let dir = write_files(
        "pbrt_spectrum_file",
        &[
            ("main.pbrt", &scene("Material \"diffuse\" \"spectrum reflectance\" \"spds/flat.spd\"\nShape \"sphere\"")),
            ("spds/flat.spd", "# a flat reflectance\n300 0.25\n800 0.25\n"),
            ("bad.pbrt", &scene("Material \"diffuse\" \"spectrum reflectance\" \"bad.spd\"")),
            ("bad.spd", "300 0.25\n800 x\n"),
        ],
    );
    let (b, _) = load_scene_builder(&dir.join("main.pbrt")).unwrap();
    let m = &b.materials[b.spheres[0].material as usize];
    let ppm_core::bsdf::Bsdf::Diffuse(d) = m.bsdf else {
        panic!("{:?}", m.bsdf)
    };
    assert!(
        (d.albedo - Vec3::splat(0.25)).abs().max_element() < 0.01,
        "{}",
        d.albedo
    );
    let e = file_error(&dir.join("bad.pbrt"));
    assert!(e.contains("bad.spd:2: `x` is not a number"), "{e}");
}
