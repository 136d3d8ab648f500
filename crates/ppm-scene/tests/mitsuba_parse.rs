//! The Mitsuba parse layer: `$name` defaults and defines, includes, ids and refs, transforms
//! against hand-computed matrices, old and new property names, spectra against values
//! computed here independently, and messages that name the file and line.

mod common;

use common::write_files;
use glam::{DMat4, DVec3};
use ppm_scene::mitsuba::parse::{parse_file, parse_str};
use ppm_scene::mitsuba::spectrum::{self, Role};
use ppm_scene::mitsuba::tree::{SceneTree, Spectrum, Value};
use ppm_scene::LoadError;
use std::path::Path;

fn parse(xml: &str) -> Result<SceneTree, LoadError> {
    parse_str(xml, Path::new("scene.xml"), &[])
}

fn defines(list: &[(&str, &str)]) -> Vec<(String, String)> {
    list.iter()
        .map(|(a, b)| (a.to_string(), b.to_string()))
        .collect()
}

/// The value of property `name` of the first object of `class` (or of the scene).
fn value<'a>(tree: &'a SceneTree, class: &str, name: &str) -> &'a Value {
    let object = if class == "scene" {
        tree.root()
    } else {
        tree.objects.iter().find(|o| o.class == class).unwrap()
    };
    &object
        .properties
        .iter()
        .find(|p| p.name == name)
        .unwrap()
        .value
}

fn transform_of(xml_ops: &str) -> DMat4 {
    let xml = format!(
        r#"<scene version="3.0.0"><shape type="rectangle"><transform name="to_world">{xml_ops}</transform></shape></scene>"#
    );
    match value(&parse(&xml).unwrap(), "shape", "to_world") {
        Value::Transform(m) => *m,
        v => panic!("{v:?}"),
    }
}

fn message(e: LoadError) -> String {
    e.to_string()
}

#[test]
fn defaults_apply_and_defines_override_them() {
    let xml = r#"<scene version="3.0.0">
        <default name="spp" value="16"/>
        <default name="colour" value="0.25"/>
        <bsdf type="diffuse"><rgb name="reflectance" value="$colour, 0.5, $colour"/></bsdf>
        <integrator type="path"><integer name="max_depth" value="$spp"/></integrator>
    </scene>"#;
    let tree = parse(xml).unwrap();
    assert_eq!(value(&tree, "integrator", "max_depth"), &Value::Integer(16));
    assert_eq!(
        value(&tree, "bsdf", "reflectance"),
        &Value::Rgb(DVec3::new(0.25, 0.5, 0.25))
    );
    let tree = parse_str(xml, Path::new("scene.xml"), &defines(&[("spp", "7")])).unwrap();
    assert_eq!(value(&tree, "integrator", "max_depth"), &Value::Integer(7));
}

#[test]
fn an_undefined_parameter_is_an_error_naming_it() {
    let xml = "<scene version=\"3.0.0\">\n<integrator type=\"path\">\n<integer name=\"max_depth\" value=\"$depth\"/></integrator></scene>";
    let m = message(parse(xml).unwrap_err());
    assert!(m.starts_with("scene.xml:3: "), "{m}");
    assert!(m.contains("undefined parameter `$depth`"), "{m}");
    // Defined by the caller, it parses.
    parse_str(xml, Path::new("scene.xml"), &defines(&[("depth", "4")])).unwrap();
}

#[test]
fn includes_splice_their_objects_and_cycles_are_errors() {
    let dir = write_files(
        "mitsuba_include",
        &[
            (
                "main.xml",
                "<scene version=\"3.0.0\">\n  <include filename=\"parts/bsdfs.xml\"/>\n  <shape type=\"cube\"><ref id=\"grey\"/></shape>\n</scene>",
            ),
            (
                "parts/bsdfs.xml",
                "<scene version=\"3.0.0\"><bsdf type=\"diffuse\" id=\"grey\"/></scene>",
            ),
            ("a.xml", "<scene version=\"3.0.0\">\n<include filename=\"b.xml\"/></scene>"),
            ("b.xml", "<scene version=\"3.0.0\">\n\n<include filename=\"a.xml\"/></scene>"),
        ],
    );
    let tree = parse_file(&dir.join("main.xml"), &[]).unwrap();
    let shape = tree.objects.iter().find(|o| o.class == "shape").unwrap();
    let Value::Object(bsdf) = shape.properties[0].value else {
        panic!()
    };
    assert_eq!(tree.objects[bsdf].id.as_deref(), Some("grey"));
    assert!(tree.objects[bsdf]
        .location
        .file
        .ends_with("parts/bsdfs.xml"));
    assert_eq!(tree.files.len(), 2);

    let m = message(parse_file(&dir.join("a.xml"), &[]).unwrap_err());
    assert!(m.contains("b.xml:3: "), "{m}");
    assert!(m.contains("includes itself"), "{m}");
}

/// `<path value="dir"/>` (Mitsuba 3's file resolver, as `docs/scenes/*.xml` of mitsuba-data
/// use it: `<path value="../../common"/>`): a file named by a plugin is looked for in the
/// `<path>` directories, the latest first, before the directory of the file naming it; a
/// missing directory, or a `<path>` outside `<scene>`, is an error.
#[test]
fn path_elements_add_directories_searched_for_files() {
    let dir = write_files(
        "mitsuba_path",
        &[
            (
                "scenes/main.xml",
                "<scene version=\"3.0.0\">\n  <path value=\"../common\"/>\n  <path value=\"../later\"/>\n</scene>",
            ),
            ("common/meshes/a.obj", "v 0 0 0"),
            ("common/meshes/both.obj", "v 0 0 0"),
            ("later/meshes/both.obj", "v 0 0 0"),
            ("scenes/meshes/both.obj", "v 0 0 0"),
            ("scenes/local.obj", "v 0 0 0"),
            ("scenes/parts/inc.xml", "<scene version=\"3.0.0\"/>"),
            ("scenes/missing.xml", "<scene version=\"3.0.0\">\n\n  <path value=\"nowhere\"/>\n</scene>"),
            (
                "scenes/nested.xml",
                "<scene version=\"3.0.0\">\n  <shape type=\"obj\">\n    <path value=\".\"/>\n  </shape>\n</scene>",
            ),
        ],
    );
    let main = dir.join("scenes/main.xml");
    let tree = parse_file(&main, &[]).unwrap();
    let canonical = |p: &Path| std::fs::canonicalize(p).unwrap();
    // Only in a <path> directory.
    assert_eq!(
        canonical(&tree.resolve(&main, "meshes/a.obj")),
        canonical(&dir.join("common/meshes/a.obj"))
    );
    // In both <path>s and next to the scene: the latest <path> wins.
    assert_eq!(
        canonical(&tree.resolve(&main, "meshes/both.obj")),
        canonical(&dir.join("later/meshes/both.obj"))
    );
    // Only next to the scene.
    assert_eq!(
        canonical(&tree.resolve(&main, "local.obj")),
        canonical(&dir.join("scenes/local.obj"))
    );
    // Named in an included file one folder down: next to the main scene, as Mitsuba finds it.
    assert_eq!(
        canonical(&tree.resolve(&dir.join("scenes/parts/inc.xml"), "local.obj")),
        canonical(&dir.join("scenes/local.obj"))
    );
    // Nowhere: next to the scene, for the error to name.
    assert_eq!(tree.resolve(&main, "none.obj"), dir.join("scenes/none.obj"));

    let m = message(parse_file(&dir.join("scenes/missing.xml"), &[]).unwrap_err());
    assert!(m.contains("missing.xml:3: "), "{m}");
    assert!(m.contains("<path value=\"nowhere\">: no directory"), "{m}");
    let m = message(parse_file(&dir.join("scenes/nested.xml"), &[]).unwrap_err());
    assert!(m.contains("nested.xml:3: "), "{m}");
    assert!(m.contains("<path> must be a child of <scene>"), "{m}");
}

#[test]
fn a_ref_to_an_unknown_id_names_it_and_its_line() {
    let xml =
        "<scene version=\"3.0.0\">\n<shape type=\"cube\">\n<ref id=\"nowhere\"/>\n</shape></scene>";
    let m = message(parse(xml).unwrap_err());
    assert!(m.starts_with("scene.xml:3: "), "{m}");
    assert!(m.contains("nowhere"), "{m}");
    // A <ref> may come before its object, as in Mitsuba 3, but not inside it.
    let forward = "<scene version=\"3.0.0\">\n<shape type=\"cube\"><ref id=\"later\"/></shape>\n<bsdf type=\"diffuse\" id=\"later\"/></scene>";
    let tree = parse(forward).unwrap();
    let shape = tree.objects.iter().find(|o| o.class == "shape").unwrap();
    let Value::Object(bsdf) = shape.properties[0].value else {
        panic!()
    };
    assert_eq!(tree.objects[bsdf].id.as_deref(), Some("later"));
    let cycle = "<scene version=\"3.0.0\">\n<bsdf type=\"twosided\" id=\"a\">\n<ref id=\"a\"/></bsdf></scene>";
    let m = message(parse(cycle).unwrap_err());
    assert!(
        m.contains("scene.xml:2: ") && m.contains("contains itself"),
        "{m}"
    );
    let dup = "<scene version=\"3.0.0\">\n<bsdf type=\"diffuse\" id=\"a\"/>\n<bsdf type=\"diffuse\" id=\"a\"/></scene>";
    let m = message(parse(dup).unwrap_err());
    assert!(
        m.contains("scene.xml:3: ") && m.contains("already used at scene.xml:2"),
        "{m}"
    );
}

#[rustfmt::skip]
fn rows(r: [f64; 16]) -> DMat4 {
    DMat4::from_cols_array(&r).transpose()
}

#[test]
fn each_transform_gives_the_hand_computed_matrix() {
    let close = |a: DMat4, b: DMat4| assert!(a.abs_diff_eq(b, 1e-12), "\n{a}\n!=\n{b}");
    #[rustfmt::skip]
    close(transform_of(r#"<translate x="1" y="2" z="3"/>"#), rows([
        1., 0., 0., 1.,
        0., 1., 0., 2.,
        0., 0., 1., 3.,
        0., 0., 0., 1.]));
    close(
        transform_of(r#"<translate value="1, 2, 3"/>"#),
        transform_of(r#"<translate x="1" y="2" z="3"/>"#),
    );
    #[rustfmt::skip]
    close(transform_of(r#"<scale value="2"/><scale y="3"/>"#), rows([
        2., 0., 0., 0.,
        0., 6., 0., 0.,
        0., 0., 2., 0.,
        0., 0., 0., 1.]));
    // 90 degrees about +x: y -> z, z -> -y.
    #[rustfmt::skip]
    close(transform_of(r#"<rotate x="1" angle="90"/>"#), rows([
        1., 0.,  0., 0.,
        0., 0., -1., 0.,
        0., 1.,  0., 0.,
        0., 0.,  0., 1.]));
    // 120 degrees about (1, 1, 1) cycles the axes: x -> y -> z -> x.
    #[rustfmt::skip]
    close(transform_of(r#"<rotate value="1, 1, 1" angle="120"/>"#), rows([
        0., 0., 1., 0.,
        1., 0., 0., 0.,
        0., 1., 0., 0.,
        0., 0., 0., 1.]));
    // Operations compose in order: scale by 2, then move by +x: (1, 0, 0) -> (3, 0, 0).
    let m = transform_of(r#"<scale value="2"/><translate x="1"/>"#);
    assert_eq!(m.transform_point3(DVec3::X), DVec3::new(3.0, 0.0, 0.0));
    let m = transform_of(r#"<translate x="1"/><scale value="2"/>"#);
    assert_eq!(m.transform_point3(DVec3::X), DVec3::new(4.0, 0.0, 0.0));
    // A camera at (1, 2, 3) looking down -x with +y up: dir = -x, left = up x dir = +z.
    #[rustfmt::skip]
    close(transform_of(r#"<lookat origin="1, 2, 3" target="0, 2, 3" up="0, 1, 0"/>"#), rows([
        0., 0., -1., 1.,
        0., 1.,  0., 2.,
        1., 0.,  0., 3.,
        0., 0.,  0., 1.]));
    let m: Vec<f64> = (1..=16).map(f64::from).collect();
    let text = m
        .iter()
        .map(|v| v.to_string())
        .collect::<Vec<_>>()
        .join(" ");
    close(
        transform_of(&format!(r#"<matrix value="{text}"/>"#)),
        rows(m.try_into().unwrap()),
    );
    let bad = r#"<scene version="3.0.0"><shape type="cube"><transform name="to_world">
        <matrix value="1 2 3"/></transform></shape></scene>"#;
    assert!(message(parse(bad).unwrap_err())
        .contains("scene.xml:2: <matrix> needs 16 or 9 values, got 3"));
}

#[test]
fn old_and_new_names_give_the_same_tree() {
    let new = r#"<scene version="3.0.0">
        <sensor type="perspective"><string name="fov_axis" value="x"/><float name="near_clip" value="0.1"/>
            <transform name="to_world"><lookat origin="0,0,1" target="0,0,0" up="0,1,0"/></transform></sensor>
        <bsdf type="dielectric"><string name="int_ior" value="bk7"/><float name="ext_ior" value="1"/>
            <rgb name="specular_reflectance" value="1"/></bsdf>
        <shape type="obj"><boolean name="flip_normals" value="true"/><boolean name="face_normals" value="true"/></shape>
        <integrator type="path"><integer name="max_depth" value="5"/></integrator>
    </scene>"#;
    let old = r#"<scene version="0.6.0">
        <sensor type="perspective"><string name="fovAxis" value="x"/><float name="nearClip" value="0.1"/>
            <transform name="toWorld"><lookAt origin="0,0,1" target="0,0,0" up="0,1,0"/></transform></sensor>
        <bsdf type="dielectric"><string name="intIOR" value="bk7"/><float name="extIOR" value="1"/>
            <rgb name="specularReflectance" value="1"/></bsdf>
        <shape type="obj"><boolean name="flipNormals" value="true"/><boolean name="faceNormals" value="true"/></shape>
        <integrator type="path"><integer name="maxDepth" value="5"/></integrator>
    </scene>"#;
    assert_eq!(parse(old).unwrap(), parse(new).unwrap());
    // A version 3 file keeps its names as written.
    let kept = parse(&old.replace("0.6.0", "3.0.0")).unwrap();
    assert!(matches!(
        value(&kept, "integrator", "maxDepth"),
        Value::Integer(5)
    ));
}

/// Wyman, Sloan and Shirley 2013, "Simple analytic approximations to the CIE XYZ colour
/// matching functions", JCGT 2(2), the multi-lobe fit (eq. 2 to 4): independent of the table.
fn cie_fit(l: f64) -> DVec3 {
    let g = |x: f64, mu: f64, s1: f64, s2: f64| {
        let t = (x - mu) / if x < mu { s1 } else { s2 };
        (-0.5 * t * t).exp()
    };
    DVec3::new(
        1.056 * g(l, 599.8, 37.9, 31.0) + 0.362 * g(l, 442.0, 16.0, 26.7)
            - 0.065 * g(l, 501.1, 20.4, 26.2),
        0.821 * g(l, 568.8, 46.9, 40.5) + 0.286 * g(l, 530.9, 16.3, 31.1),
        1.217 * g(l, 437.0, 11.8, 36.0) + 0.681 * g(l, 459.0, 26.0, 13.8),
    )
}

#[test]
fn a_blackbody_matches_plancks_law_integrated_here() {
    // Planck's law in W m^-2 sr^-1 nm^-1, written out again; a midpoint sum at 0.5 nm.
    let planck = |nm: f64, t: f64| {
        let (h, c, k) = (6.62607015e-34, 299792458.0, 1.380649e-23);
        let l = nm * 1e-9;
        2.0 * h * c * c / l.powi(5) / ((h * c / (l * k * t)).exp() - 1.0) * 1e-9
    };
    for t in [2700.0, 6500.0] {
        let (mut xyz, mut y_norm) = (DVec3::ZERO, 0.0);
        for i in 0..940 {
            let l = 360.25 + 0.5 * i as f64;
            xyz += planck(l, t) * cie_fit(l);
            y_norm += cie_fit(l).y;
        }
        let expected = spectrum::xyz_to_srgb(xyz / y_norm);
        let got = spectrum::to_rgb(
            &Spectrum::Blackbody {
                temperature: t,
                scale: 1.0,
            },
            Role::Emission,
        )
        .unwrap();
        let rel = (got - expected).abs() / expected.max_element();
        assert!(rel.max_element() < 0.02, "{t} K: {got} vs {expected}");
    }
    // The XML forms of Mitsuba 3 and 0.6 give the same value.
    let v3 = r#"<scene version="3.0.0"><emitter type="point"><spectrum type="blackbody" name="intensity"><float name="temperature" value="4000"/></spectrum></emitter></scene>"#;
    let v06 = r#"<scene version="0.6.0"><emitter type="point"><blackbody name="intensity" temperature="4000K"/></emitter></scene>"#;
    assert_eq!(
        value(&parse(v3).unwrap(), "emitter", "intensity"),
        &Value::Spectrum(Spectrum::Blackbody {
            temperature: 4000.0,
            scale: 1.0
        })
    );
    assert_eq!(
        parse(v3).unwrap().objects[1],
        parse(v06).unwrap().objects[1]
    );
}

#[test]
fn spectra_convert_as_mitsuba_converts_them() {
    // A constant is grey as a reflectance and the equal-energy white, M (1, 1, 1), as an
    // emission, M the XYZ-to-sRGB matrix (row sums computed by hand from IEC 61966-2-1).
    let c = Spectrum::Uniform(2.0);
    assert_eq!(
        spectrum::to_rgb(&c, Role::Reflectance).unwrap(),
        DVec3::splat(2.0)
    );
    let e = spectrum::to_rgb(&c, Role::Emission).unwrap();
    assert!(
        e.abs_diff_eq(2.0 * DVec3::new(1.2047843, 0.9483008, 0.9088427), 1e-6),
        "{e}"
    );
    // Samples: the values Mitsuba 3.9.1 (scalar_rgb) gives for this spectrum,
    // mi.spectrum_list_to_srgb([400, 500, 600, 700], [0.2, 0.5, 0.8, 0.3], bounded, d65).
    let s = Spectrum::Samples(vec![(400.0, 0.2), (500.0, 0.5), (600.0, 0.8), (700.0, 0.3)]);
    let r = spectrum::to_rgb(&s, Role::Reflectance).unwrap();
    assert!(
        r.abs_diff_eq(DVec3::new(0.755029, 0.641416, 0.323239), 0.01),
        "{r}"
    );
    let e = spectrum::to_rgb(&s, Role::Emission).unwrap();
    assert!(
        e.abs_diff_eq(DVec3::new(0.886932, 0.614419, 0.285147), 0.01),
        "{e}"
    );
    // The XML.
    let xml = r#"<scene version="3.0.0"><bsdf type="diffuse"><spectrum name="reflectance" value="400:0.2, 500:0.5, 600:0.8, 700:0.3"/></bsdf></scene>"#;
    assert_eq!(
        value(&parse(xml).unwrap(), "bsdf", "reflectance"),
        &Value::Spectrum(s)
    );
    let bad = r#"<scene version="3.0.0"><bsdf type="diffuse"><spectrum name="reflectance" value="500:0.2, 400:0.5"/></bsdf></scene>"#;
    assert!(message(parse(bad).unwrap_err()).contains("does not increase"));
}

#[test]
fn malformed_files_get_errors_with_file_and_line() {
    let cases = [
        ("<scene>\n</scene>", "scene.xml:1: ", "version"),
        ("<scene version=\"3.0.0\">\n<shape type=\"cube\">\n</scene>", "scene.xml:3", "not well-formed XML"),
        ("<scene version=\"3.0.0\">\n\n<float name=\"x\" value=\"abc\"/></scene>", "scene.xml:3: ", "not a finite number"),
        ("<scene version=\"3.0.0\">\n<shape type=\"cube\"><float name=\"a\" value=\"1\"/>\n<float name=\"a\" value=\"2\"/></shape></scene>", "scene.xml:3: ", "given twice"),
        ("<scene version=\"3.0.0\">\n<wobble/></scene>", "scene.xml:2: ", "unknown element <wobble>"),
        ("<shape type=\"cube\"/>", "scene.xml:1: ", "root element is <shape>"),
    ];
    for (xml, place, what) in cases {
        let m = message(parse(xml).unwrap_err());
        assert!(m.starts_with(place) && m.contains(what), "{xml}\n{m}");
    }
}

#[test]
fn nesting_is_limited() {
    let deep = format!(
        "<scene version=\"3.0.0\">{}{}</scene>",
        "<bsdf type=\"twosided\">".repeat(100),
        "</bsdf>".repeat(100)
    );
    assert!(message(parse(&deep).unwrap_err()).contains("nested more than"));
}
