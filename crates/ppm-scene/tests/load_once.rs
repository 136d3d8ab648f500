//! Loading stays linear in the size of the scene: a file named by many objects is read and
//! parsed once per load (counted by [`ppm_scene::LoadStats`], never timed), its warnings given
//! once, and scenes with hundreds of thousands of materials load.

mod common;

use common::write_files;
use ppm_scene::{load_scene, LoadStats};

/// A triangle and a degenerate one (its warning must be given once, not once per object).
const TRI_OBJ: &str = "v 0 0 -1\nv 1 0 -1\nv 0 1 -1\nv 2 2 -1\nf 1 2 3\nf 1 1 4\n";

/// Writes a 2 x 1 PNG (red, blue).
fn png(path: &std::path::Path) {
    let img = image::RgbImage::from_raw(2, 1, vec![255, 0, 0, 0, 0, 255]).unwrap();
    img.save(path).unwrap();
}

/// 10 000 objects name one OBJ (a YAML anchor and its aliases), two OBJs share one MTL
/// library whose material has a texture image: every file is read once, and parsed once.
#[test]
fn a_file_named_by_ten_thousand_objects_is_read_once() {
    let mut scene = String::from(common::CAMERA);
    scene.push_str(
        "materials:\n  white: { type: diffuse, color: [0.5, 0.5, 0.5] }\n  \
         lamp: { type: diffuse, color: [0.5, 0.5, 0.5], emission: [5, 5, 5] }\nobjects:\n  \
         - { type: sphere, center: [0, 3, 0], radius: 0.1, material: lamp }\n  \
         - &tri { type: mesh, file: tri.obj, material: white }\n",
    );
    for _ in 1..10_000 {
        scene.push_str("  - *tri\n");
    }
    // Two OBJs with their MTL materials, the second named through `./` and `..`.
    scene.push_str("  - { type: mesh, file: a.obj }\n  - { type: mesh, file: ./sub/../b.obj }\n");
    scene.push_str("  - { type: mesh, file: a.obj }\n");
    let obj = |x: f32| {
        format!("mtllib lib.mtl\nv {x} 0 -2\nv {x} 1 -2\nv 1 0 -2\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl tex\nf 1/1 2/2 3/3\n")
    };
    let mtl = "newmtl tex\nKd 1 1 1\nmap_Kd t.png\n";
    let dir = write_files(
        "load_once",
        &[
            ("scene.yml", scene.as_str()),
            ("tri.obj", TRI_OBJ),
            ("a.obj", obj(0.0).as_str()),
            ("b.obj", obj(0.5).as_str()),
            ("lib.mtl", mtl),
            ("sub/keep", ""),
        ],
    );
    png(&dir.join("t.png"));
    let loaded = load_scene(&dir.join("scene.yml")).unwrap_or_else(|e| panic!("{e}"));
    // scene.yml, tri.obj, a.obj, b.obj, lib.mtl, t.png.
    assert_eq!(
        loaded.stats,
        LoadStats {
            files_read: 6,
            files_parsed: 5
        }
    );
    // Every object still has its mesh: 10 000 from tri.obj (the built scene drops the
    // repeated triangles), one each from the three uses of a.obj and b.obj, and each MTL use
    // its own material (as before).
    let (builder, _, stats) =
        ppm_scene::load_scene_builder_with_stats(&dir.join("scene.yml"), &[]).unwrap();
    assert_eq!(stats, loaded.stats);
    assert_eq!(builder.meshes.len(), 10_003);
    assert_eq!(loaded.scene.materials.len(), 2 + 3);
    let degenerate: Vec<_> = loaded
        .warnings
        .iter()
        .filter(|w| w.contains("tri.obj") && w.contains("degenerate"))
        .collect();
    assert_eq!(degenerate.len(), 1, "{:#?}", loaded.warnings);
}

/// A Mitsuba scene naming one PLY and one OBJ from 500 shapes each reads three files.
#[test]
fn mitsuba_shapes_sharing_a_mesh_read_it_once() {
    let mut xml = String::from(
        r#"<scene version="3.0.0">
<sensor type="perspective"><transform name="to_world"><lookat origin="0,0,5" target="0,0,0" up="0,1,0"/></transform>
<film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/></film></sensor>
<emitter type="point"><point name="position" x="0" y="3" z="3"/><rgb name="intensity" value="5"/></emitter>
"#,
    );
    for i in 0..500 {
        let x = i as f32 * 0.01;
        for file in ["tri.ply", "tri.obj"] {
            let kind = &file[4..];
            xml.push_str(&format!(
                r#"<shape type="{kind}"><string name="filename" value="{file}"/><transform name="to_world"><translate x="{x}"/></transform></shape>
"#
            ));
        }
    }
    xml.push_str("</scene>\n");
    let ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
               property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n\
               0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    let dir = write_files(
        "load_once_mitsuba",
        &[
            ("scene.xml", xml.as_str()),
            ("tri.ply", ply),
            ("tri.obj", TRI_OBJ),
        ],
    );
    let loaded = load_scene(&dir.join("scene.xml")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(loaded.stats.files_read, 3, "{:?}", loaded.stats);
    assert_eq!(loaded.scene.geometry.triangle_count(), 1000);
}

/// 200 000 materials, each on its own sphere, load: one file read, every material kept in
/// order. (Untimed: the scaling itself is measured by scripts/load_scaling.py.)
#[test]
fn two_hundred_thousand_materials_load() {
    const N: usize = 200_000;
    let mut scene = String::from(common::CAMERA);
    scene.push_str(
        "materials:\n  lamp: { type: diffuse, color: [0.5, 0.5, 0.5], emission: [5, 5, 5] }\n",
    );
    for i in 0..N {
        scene.push_str(&format!(
            "  m{i}: {{ type: diffuse, color: [{}, 0.5, 0.5] }}\n",
            (i % 100) as f32 / 100.0
        ));
    }
    scene.push_str(
        "objects:\n  - { type: sphere, center: [0, 3, 0], radius: 0.1, material: lamp }\n",
    );
    for i in 0..N {
        scene.push_str(&format!(
            "  - {{ type: sphere, center: [{}, {}, -1], radius: 0.001, material: m{i} }}\n",
            (i % 500) as f32 * 0.003,
            (i / 500) as f32 * 0.003
        ));
    }
    let dir = write_files("load_once_materials", &[("scene.yml", scene.as_str())]);
    let loaded = load_scene(&dir.join("scene.yml")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(loaded.stats.files_read, 1);
    assert_eq!(loaded.scene.materials.len(), N + 1);
    assert_eq!(loaded.scene.materials[N].name, format!("m{}", N - 1));
    assert!(loaded.warnings.is_empty(), "{:?}", &loaded.warnings[..1]);
}
