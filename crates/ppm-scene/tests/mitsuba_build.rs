//! The Mitsuba build layer: the Cornell box written in Mitsuba's XML loads to the same scene
//! as `scenes/cornell_box.yml` and renders to the same image mean (and to Mitsuba's own);
//! sensors, shapes and their transforms, BSDFs and emitters map as `docs/mitsuba.md` says;
//! what ppm cannot render is an error naming the plugin, file and line.

mod common;

use common::{scenes_dir, write_files};
use glam::{Vec2, Vec3};
use ppm_core::bsdf::Bsdf;
use ppm_core::integrator::{Algorithm, RenderSettings, Renderer, MAX_DEPTH};
use ppm_core::light::Light;
use ppm_core::scene::SceneBuilder;
use ppm_scene::mitsuba::parse_mitsuba;
use ppm_scene::{load_scene_builder, load_scene_builder_with_defines, LoadError};
use std::path::{Path, PathBuf};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/mitsuba")
        .join(name)
}

fn load(xml: &str) -> Result<(SceneBuilder, Vec<String>), LoadError> {
    parse_mitsuba(xml, Path::new("scene.xml"), &[])
}

/// A scene around `body`: a camera and a light, so that only `body` is under test.
fn scene(body: &str) -> String {
    format!(
        r#"<scene version="3.0.0">
<sensor type="perspective"><transform name="to_world"><lookat origin="0,0,5" target="0,0,0" up="0,1,0"/></transform>
<film type="hdrfilm"><integer name="width" value="40"/><integer name="height" value="20"/></film></sensor>
<emitter type="point"><point name="position" x="0" y="3" z="3"/><rgb name="intensity" value="5"/></emitter>
{body}
</scene>"#
    )
}

fn error(xml: &str) -> String {
    match load(xml) {
        Ok(_) => panic!("loaded:\n{xml}"),
        Err(e) => e.to_string(),
    }
}

/// The mean of a path-traced image of `builder` at `iterations` samples per pixel.
fn render_mean(builder: SceneBuilder, iterations: u32) -> Vec3 {
    let scene = builder.build().unwrap();
    let settings = RenderSettings {
        seed: 7,
        ..RenderSettings::for_algorithm(&scene, Algorithm::Path)
    };
    let mut r = Renderer::new(&scene, &settings);
    for _ in 0..iterations {
        assert_eq!(r.iterate(&scene).rejected, 0);
    }
    r.image().mean()
}

#[test]
fn the_xml_cornell_box_is_the_yaml_one() {
    let defines = [("res".to_string(), "32".to_string())];
    let (xml, warnings) = load_scene_builder_with_defines(&data("cbox.xml"), &defines).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    let (mut yaml, _) = load_scene_builder(&scenes_dir().join("cornell_box.yml")).unwrap();
    yaml.camera.set_resolution(32, 32).unwrap();
    assert_eq!(xml.defaults.max_depth, yaml.defaults.max_depth);
    // The same primary rays.
    for film in [
        Vec2::new(0.5, 0.5),
        Vec2::new(31.0, 3.0),
        Vec2::new(16.0, 30.0),
    ] {
        let (a, b) = (
            xml.camera.generate_ray(film),
            yaml.camera.generate_ray(film),
        );
        assert!(a.origin.abs_diff_eq(b.origin, 1e-6), "{a:?} {b:?}");
        assert!(a.dir.abs_diff_eq(b.dir, 1e-6), "{a:?} {b:?}");
    }
    // The same triangles, area by area and normal by normal (sorted, since the order of
    // the shapes and the diagonal that splits a quad differ), within the same bounds.
    let triangles = |b: &SceneBuilder| {
        let mut t: Vec<[i64; 3]> = b
            .meshes
            .iter()
            .flat_map(|m| {
                m.indices.iter().map(|t| {
                    let p = t.map(|i| m.positions[i as usize]);
                    let n = (p[1] - p[0]).cross(p[2] - p[0]);
                    [n.x, n.y, n.z].map(|v| (v * 1e4).round() as i64)
                })
            })
            .collect();
        t.sort();
        t
    };
    assert_eq!(triangles(&xml), triangles(&yaml));
    let bounds = |b: &SceneBuilder| {
        let points = b.meshes.iter().flat_map(|m| m.positions.iter().copied());
        points.fold((Vec3::MAX, Vec3::MIN), |(lo, hi), p| (lo.min(p), hi.max(p)))
    };
    let (a, b) = (bounds(&xml), bounds(&yaml));
    assert!(
        a.0.abs_diff_eq(b.0, 1e-6) && a.1.abs_diff_eq(b.1, 1e-6),
        "{a:?} {b:?}"
    );
    let emission = |b: &SceneBuilder| -> Vec<Vec3> {
        b.materials
            .iter()
            .map(|m| m.emission)
            .filter(|e| *e != Vec3::ZERO)
            .collect()
    };
    assert_eq!(emission(&xml), emission(&yaml));

    let (a, b) = (render_mean(xml, 64), render_mean(yaml, 64));
    let rel = ((a - b) / b).abs();
    assert!(rel.max_element() < 0.02, "xml {a} yaml {b}");
    // Mitsuba 3.9.1 (scalar_rgb, `path`, 4096 spp) renders cbox.xml at 32 x 32 to this mean
    // (ppm at 1024 spp: within 0.1 %).
    let mitsuba = Vec3::new(0.30339, 0.19986, 0.05836);
    let rel = ((a - mitsuba) / mitsuba).abs();
    assert!(rel.max_element() < 0.02, "ppm {a} mitsuba {mitsuba}");
}

#[test]
fn the_field_of_view_converts_for_each_axis() {
    // A 40 x 20 film (aspect 2) and fov 60: tan(30°) = 0.57735.
    let t = 30f64.to_radians().tan();
    let cases = [
        ("x", t / 2.0),
        ("y", t),
        ("diagonal", t / 5f64.sqrt()),
        ("smaller", t),
        ("larger", t / 2.0),
    ];
    for (axis, tan_vertical) in cases {
        let xml = scene(&format!(
            r#"<sensor type="perspective"><float name="fov" value="60"/><string name="fov_axis" value="{axis}"/>
            <film type="hdrfilm"><integer name="width" value="40"/><integer name="height" value="20"/></film></sensor>"#
        ))
        .replacen("<sensor", "<!-- first sensor replaced --><sensor", 1);
        // Keep only the second sensor: drop the first one's element.
        let start = xml.find("<sensor").unwrap();
        let end = xml.find("</sensor>").unwrap() + "</sensor>".len();
        let xml = format!("{}{}", &xml[..start], &xml[end..]);
        let (b, _) = load(&xml).unwrap();
        // pixel_angle = 2 tan(vertical / 2) / height.
        let got = b.camera.pixel_angle() as f64 * 20.0 / 2.0;
        assert!(
            (got - tan_vertical).abs() < 1e-6,
            "{axis}: {got} vs {tan_vertical}"
        );
    }
    // focal_length 50mm: the 36 x 24 mm diagonal.
    let xml = scene("").replace(
        "<film",
        r#"<string name="focal_length" value="50mm"/><film"#,
    );
    let (b, _) = load(&xml).unwrap();
    let got = b.camera.pixel_angle() as f64 * 10.0;
    let expected = (36f64.hypot(24.0) / 100.0) / 5f64.sqrt();
    assert!((got - expected).abs() < 1e-6, "{got} vs {expected}");
}

#[test]
fn max_depth_is_mitsubas_minus_one() {
    for (mitsuba, ppm) in [("-1", MAX_DEPTH), ("1", 0), ("6", 5)] {
        let xml = scene(&format!(
            r#"<integrator type="path"><integer name="max_depth" value="{mitsuba}"/></integrator>"#
        ));
        assert_eq!(load(&xml).unwrap().0.defaults.max_depth, ppm);
    }
    let m = error(&scene(
        r#"<integrator type="path"><integer name="max_depth" value="0"/></integrator>"#,
    ));
    assert!(m.contains("renders nothing"), "{m}");
}

/// The geometric normal of the first triangle of the last mesh.
fn first_normal(b: &SceneBuilder) -> Vec3 {
    let m = b.meshes.last().unwrap();
    let p = m.indices[0].map(|i| m.positions[i as usize]);
    (p[1] - p[0]).cross(p[2] - p[0]).normalize()
}

#[test]
fn mirroring_transforms_and_flip_normals_keep_the_sides_right() {
    let rect = |ops: &str, flip: bool| {
        let xml = scene(&format!(
            r#"<shape type="rectangle"><transform name="to_world">{ops}</transform><boolean name="flip_normals" value="{flip}"/></shape>"#
        ));
        first_normal(&load(&xml).unwrap().0)
    };
    assert!(rect("", false).abs_diff_eq(Vec3::Z, 1e-6));
    assert!(rect("", true).abs_diff_eq(-Vec3::Z, 1e-6));
    // A mirror in x leaves the plane's normal alone (the inverse transpose of diag(-1, 1, 1)
    // maps +z to +z), so the winding is reversed to keep it.
    assert!(rect(r#"<scale x="-1"/>"#, false).abs_diff_eq(Vec3::Z, 1e-6));
    assert!(rect(r#"<scale x="-1"/>"#, true).abs_diff_eq(-Vec3::Z, 1e-6));
    // A mirror in z turns it over.
    assert!(rect(r#"<scale z="-1"/>"#, false).abs_diff_eq(-Vec3::Z, 1e-6));
    // Rotated to face +y.
    assert!(rect(r#"<rotate x="1" angle="-90"/>"#, false).abs_diff_eq(Vec3::Y, 1e-6));
}

#[test]
fn tessellated_shapes_have_their_size_and_face_outward() {
    let (b, _) = load(&scene(
        r#"<shape type="disk"><transform name="to_world"><scale value="2"/></transform></shape>
           <shape type="cube"/>
           <shape type="cylinder"><float name="radius" value="0.5"/><point name="p1" x="0" y="0" z="3"/></shape>"#,
    ))
    .unwrap();
    let area = |m: &ppm_core::geometry::TriangleMesh| -> f64 {
        m.indices
            .iter()
            .map(|t| {
                let p = t.map(|i| m.positions[i as usize].as_dvec3());
                0.5 * (p[1] - p[0]).cross(p[2] - p[0]).length()
            })
            .sum()
    };
    let polygon = |r: f64| {
        let n = ppm_scene::mitsuba::SEGMENTS as f64;
        0.5 * n * r * r * (std::f64::consts::TAU / n).sin()
    };
    let (disk, cube, cylinder) = (&b.meshes[0], &b.meshes[1], &b.meshes[2]);
    assert!((area(disk) - polygon(2.0)).abs() < 1e-4);
    assert!((area(disk) / (std::f64::consts::PI * 4.0) - 1.0).abs() < 5e-4);
    assert!((area(cube) - 24.0).abs() < 1e-5);
    // The open tube: circumference of the 128-gon times the height.
    let side = 2.0 * 0.5 * (std::f64::consts::PI / 128.0).sin() * 128.0;
    assert!((area(cylinder) - side * 3.0).abs() < 1e-4);
    // Every face of the cube and the tube points away from the axis / centre.
    for (m, axis_only) in [(cube, false), (cylinder, true)] {
        for t in &m.indices {
            let p = t.map(|i| m.positions[i as usize]);
            let n = (p[1] - p[0]).cross(p[2] - p[0]);
            let mut c = (p[0] + p[1] + p[2]) / 3.0;
            if axis_only {
                c.z = 0.0;
            }
            assert!(n.dot(c) > 0.0, "{p:?}");
        }
    }
    // Vertex normals of the tube are radial and unit.
    for (p, n) in cylinder.positions.iter().zip(&cylinder.normals) {
        assert!(n.abs_diff_eq(Vec3::new(p.x, p.y, 0.0) / 0.5, 1e-5));
    }
}

#[test]
fn spheres_are_analytic_and_bsdfs_map_to_ppms() {
    let (b, _) = load(&scene(
        r#"<shape type="sphere"><point name="center" x="1" y="0" z="0"/><float name="radius" value="0.5"/>
             <transform name="to_world"><scale value="2"/><translate y="1"/></transform>
             <bsdf type="dielectric"><string name="int_ior" value="water"/><float name="ext_ior" value="1"/></bsdf></shape>
           <shape type="sphere"><boolean name="flip_normals" value="true"/>
             <bsdf type="conductor"><string name="material" value="none"/><rgb name="specular_reflectance" value="0.9"/></bsdf></shape>
           <shape type="cube"><bsdf type="twosided"><bsdf type="diffuse"><spectrum name="reflectance" value="0.3"/></bsdf></bsdf></shape>
           <shape type="cube"/>"#,
    ))
    .unwrap();
    let s = &b.spheres[0];
    assert!(s.center.abs_diff_eq(Vec3::new(2.0, 1.0, 0.0), 1e-6) && s.radius == 1.0 && !s.inward);
    assert!(b.spheres[1].inward);
    let bsdf = |m: u32| b.materials[m as usize].bsdf;
    assert!(
        matches!(bsdf(s.material), Bsdf::Dielectric(d) if (d.eta - 1.333).abs() < 1e-6 && d.specular_transmittance == Vec3::ONE)
    );
    assert!(matches!(bsdf(b.spheres[1].material), Bsdf::Mirror(m) if m.color == Vec3::splat(0.9)));
    assert!(
        matches!(bsdf(b.meshes[0].materials[0]), Bsdf::Diffuse(d) if d.albedo == Vec3::splat(0.3))
    );
    // No BSDF: Mitsuba's default, a diffuse of reflectance 0.5.
    assert!(
        matches!(bsdf(b.meshes[1].materials[0]), Bsdf::Diffuse(d) if d.albedo == Vec3::splat(0.5))
    );
    let Light::Point(point) = b.lights[0] else {
        panic!("{:?}", b.lights)
    };
    assert_eq!(point.intensity, Vec3::splat(5.0));
    assert_eq!(point.position, Vec3::new(0.0, 3.0, 3.0));
}

#[test]
fn what_ppm_cannot_render_is_an_error_naming_it_and_its_place() {
    let cases = [
        (
            "<shape type=\"cube\">\n<bsdf type=\"blendbsdf\"/></shape>",
            "scene.xml:6: bsdf `blendbsdf` at scene.xml:6 is not supported yet",
        ),
        (
            "<shape type=\"cube\">\n<bsdf type=\"diffuse\"><float name=\"reflectancex\" value=\"0.5\"/></bsdf></shape>",
            "scene.xml:6: unreferenced property `reflectancex` of bsdf `diffuse` at scene.xml:6",
        ),
        (
            "<shape type=\"cube\"><bsdf type=\"diffuse\">\n<texture type=\"mesh_attribute\" name=\"reflectance\"/></bsdf></shape>",
            "scene.xml:6: texture `mesh_attribute` (as `reflectance` of bsdf `diffuse`) is not supported",
        ),
        (
            "\n<emitter type=\"sunsky\"/>",
            "scene.xml:6: emitter `sunsky` at scene.xml:6 is not supported yet",
        ),
        (
            "<shape type=\"cube\"><bsdf type=\"dielectric\">\n<string name=\"int_ior\" value=\"unobtainium\"/></bsdf></shape>",
            "is not a known material (known: vacuum,",
        ),
        (
            "\n<shape type=\"instance\"/>",
            "scene.xml:6: shape `instance` needs exactly one shapegroup (nested or by <ref>)",
        ),
        (
            "\n<medium type=\"homogeneous\"/>",
            "scene.xml:6: medium `homogeneous` at scene.xml:6 is not supported yet",
        ),
        (
            "<shape type=\"ply\">\n<string name=\"filename\" value=\"missing.ply\"/></shape>",
            "missing.ply: cannot read PLY file",
        ),
        (
            "<shape type=\"sphere\"><transform name=\"to_world\"><scale x=\"2\"/></transform></shape>",
            "non-uniform scale",
        ),
    ];
    for (body, expected) in cases {
        let m = error(&scene(body));
        assert!(m.contains(expected), "{body}\n{m}");
    }
}

#[test]
fn mesh_files_load_relative_to_the_xml_that_names_them() {
    let dir = write_files(
        "mitsuba_meshes_relative",
        &[(
            "models/quad.obj",
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nvn 0 0 1\nvn 0 0 1\nvn 0 0 1\nf 1//1 2//2 3//3 4//4\n",
        )],
    );
    let xml = scene(
        r#"<shape type="obj"><string name="filename" value="models/quad.obj"/>
           <transform name="to_world"><scale x="-2"/></transform></shape>
           <shape type="obj"><string name="filename" value="models/quad.obj"/><boolean name="face_normals" value="true"/></shape>"#,
    );
    std::fs::write(dir.join("scene.xml"), xml).unwrap();
    let (b, warnings) = load_scene_builder(&dir.join("scene.xml")).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    let m = &b.meshes[0];
    assert!(m.positions.iter().all(|p| p.x <= 0.0));
    // Mirrored: the vertex normals (by the inverse transpose) and the winding both stay +z.
    assert!(m.normals.iter().all(|n| n.abs_diff_eq(Vec3::Z, 1e-6)));
    let p = m.indices[0].map(|i| m.positions[i as usize]);
    assert!((p[1] - p[0]).cross(p[2] - p[0]).z > 0.0);
    assert!(b.meshes[1].normals.is_empty());
}

#[test]
fn a_mesh_file_without_normals_is_smoothed_as_mitsuba_does() {
    // A cube [-1, 1]^3 of 8 shared corners: each corner's three faces meet it at right angles
    // however they are split, so the angle-weighted normal is the corner's direction.
    let corners: Vec<Vec3> = (0..8)
        .map(|i| {
            Vec3::new(
                [-1.0, 1.0][i & 1],
                [-1.0, 1.0][(i >> 1) & 1],
                [-1.0, 1.0][i >> 2],
            )
        })
        .collect();
    let faces = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let mut ply = String::from(
        "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\n\
         element face 6\nproperty list uchar int vertex_indices\nend_header\n",
    );
    for c in &corners {
        ply += &format!("{} {} {}\n", c.x, c.y, c.z);
    }
    for f in faces {
        ply += &format!("4 {} {} {} {}\n", f[0], f[1], f[2], f[3]);
    }
    let dir = write_files("mitsuba_smooth", &[("cube.ply", &ply)]);
    let xml = scene(
        r#"<shape type="ply"><string name="filename" value="cube.ply"/></shape>
           <shape type="ply"><string name="filename" value="cube.ply"/><boolean name="face_normals" value="true"/></shape>"#,
    );
    std::fs::write(dir.join("scene.xml"), xml).unwrap();
    let (b, _) = load_scene_builder(&dir.join("scene.xml")).unwrap();
    let smooth = &b.meshes[0];
    assert_eq!(smooth.indices.len(), 12);
    for (p, n) in smooth.positions.iter().zip(&smooth.normals) {
        assert!(n.abs_diff_eq(p.normalize(), 1e-6), "{p} {n}");
    }
    // Outward: every face's winding agrees with the normals.
    for t in &smooth.indices {
        let p = t.map(|i| smooth.positions[i as usize]);
        assert!((p[1] - p[0]).cross(p[2] - p[0]).dot(p[0] + p[1] + p[2]) > 0.0);
    }
    assert!(b.meshes[1].normals.is_empty());
}
