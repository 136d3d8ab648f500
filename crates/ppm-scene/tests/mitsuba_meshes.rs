//! PLY (ASCII, binary little and big endian) and Mitsuba serialized meshes (versions 3 and 4),
//! written here byte by byte and read back; the Cornell box blocks shipped as test data equal
//! the OBJs of `scenes/`.

mod common;

use common::scenes_dir;
use flate2::write::ZlibEncoder;
use flate2::Compression;
use glam::{Vec2, Vec3};
use ppm_scene::obj::{load_obj, ObjMaterials};
use ppm_scene::ply::{load_ply, parse_ply, MeshData};
use ppm_scene::serialized::{load_serialized, parse_serialized};
use std::io::Write;
use std::path::Path;

/// A unit square as one quad and a triangle beside it, with normals and uvs.
fn positions() -> Vec<[f32; 3]> {
    vec![
        [0., 0., 0.],
        [1., 0., 0.],
        [1., 1., 0.],
        [0., 1., 0.],
        [2., 0., 0.],
    ]
}
fn normals() -> Vec<[f32; 3]> {
    vec![[0., 0., 1.]; 5]
}
fn uvs() -> Vec<[f32; 2]> {
    vec![[0., 0.], [1., 0.], [1., 1.], [0., 1.], [0.5, 0.25]]
}
fn faces() -> Vec<Vec<u32>> {
    vec![vec![0, 1, 2, 3], vec![1, 4, 2]]
}

/// The PLY of the test mesh in `format`, with uvs named `u_name`/`v_name`.
fn ply(format: &str, u_name: &str, v_name: &str) -> Vec<u8> {
    let mut out = format!(
        "ply\nformat {format} 1.0\ncomment written by the test\nelement vertex 5\n\
         property float x\nproperty float y\nproperty float z\n\
         property float nx\nproperty float ny\nproperty float nz\n\
         property float {u_name}\nproperty float {v_name}\nproperty uchar flags\n\
         element face 2\nproperty list uchar int vertex_indices\nproperty int material\n\
         element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n"
    )
    .into_bytes();
    let (p, n, t) = (positions(), normals(), uvs());
    if format == "ascii" {
        for i in 0..5 {
            let v = [
                p[i][0], p[i][1], p[i][2], n[i][0], n[i][1], n[i][2], t[i][0], t[i][1],
            ];
            let text: Vec<String> = v.iter().map(|x| x.to_string()).collect();
            out.extend(format!("{} 7\n", text.join(" ")).bytes());
        }
        for f in faces() {
            let text: Vec<String> = f.iter().map(|x| x.to_string()).collect();
            out.extend(format!("{} {} 3\n", f.len(), text.join(" ")).bytes());
        }
        out.extend(b"0 1\n");
        return out;
    }
    let big = format == "binary_big_endian";
    let f32b = |v: f32| {
        if big {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        }
    };
    let i32b = |v: i32| {
        if big {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        }
    };
    for i in 0..5 {
        for v in [
            p[i][0], p[i][1], p[i][2], n[i][0], n[i][1], n[i][2], t[i][0], t[i][1],
        ] {
            out.extend(f32b(v));
        }
        out.push(7);
    }
    for f in faces() {
        out.push(f.len() as u8);
        for i in f {
            out.extend(i32b(i as i32));
        }
        out.extend(i32b(3));
    }
    out.extend(i32b(0));
    out.extend(i32b(1));
    out
}

fn expected() -> MeshData {
    MeshData {
        positions: positions().into_iter().map(Vec3::from).collect(),
        normals: normals().into_iter().map(Vec3::from).collect(),
        uvs: uvs().into_iter().map(Vec2::from).collect(),
        // The quad as a fan around its first vertex.
        indices: vec![[0, 1, 2], [0, 2, 3], [1, 4, 2]],
    }
}

#[test]
fn ply_ascii_and_both_binary_orders_load_the_same_mesh() {
    let path = Path::new("mesh.ply");
    for format in ["ascii", "binary_little_endian", "binary_big_endian"] {
        for (u, v) in [("u", "v"), ("s", "t"), ("texture_u", "texture_v")] {
            let mesh = parse_ply(&ply(format, u, v), path).unwrap();
            assert_eq!(mesh, expected(), "{format} {u} {v}");
        }
    }
}

#[test]
fn ply_errors_name_the_file_and_the_element() {
    let path = Path::new("bad.ply");
    let good = String::from_utf8(ply("ascii", "u", "v")).unwrap();
    let cases = [
        (
            good.replace("4 0 1 2 3", "4 0 1 2 9"),
            "bad.ply: element `face` 0: vertex index 9 is out of range (5 vertices)",
        ),
        (
            good.replace("element vertex 5", "element vertex 5000000"),
            "element `vertex` declares 5000000 instances",
        ),
        (
            good.replace("format ascii", "format utf9"),
            "bad.ply:2: unknown format `utf9`",
        ),
        (
            good.replace("property float z\n", ""),
            "needs properties x, y and z",
        ),
        (
            good.replace("end_header", "end_heder"),
            "bad.ply:20: unexpected header line",
        ),
        (
            good.replace("0.25 7", "0.25x 7"),
            "line 25: `0.25x` is not a number",
        ),
        ("obj\n".into(), "bad.ply:1: not a PLY file"),
    ];
    for (text, expected) in cases {
        let m = parse_ply(text.as_bytes(), path).unwrap_err().to_string();
        assert!(m.contains(expected), "{m}\nexpected {expected}");
    }
    let mut truncated = ply("binary_little_endian", "u", "v");
    truncated.truncate(truncated.len() - 3);
    let m = parse_ply(&truncated, path).unwrap_err().to_string();
    assert!(
        m.contains("bad.ply: element `edge` declares 1 instances"),
        "{m}"
    );
    // Without its last newline an ASCII file is whole.
    let good = ply("ascii", "u", "v");
    assert_eq!(
        parse_ply(&good[..good.len() - 1], path).unwrap(),
        expected()
    );
}

/// One mesh of a serialized file, as Mitsuba writes it.
fn serialized_mesh(version: u16, double: bool, name: &str, shift: f32) -> Vec<u8> {
    let mut body = Vec::new();
    let flags: u32 = 0x0001 | 0x0002 | 0x0008 | if double { 0x2000 } else { 0x1000 };
    body.extend(flags.to_le_bytes());
    if version == 4 {
        body.extend(name.as_bytes());
        body.push(0);
    }
    body.extend(5u64.to_le_bytes());
    body.extend(3u64.to_le_bytes());
    let real = |body: &mut Vec<u8>, v: f32| {
        if double {
            body.extend((v as f64).to_le_bytes())
        } else {
            body.extend(v.to_le_bytes())
        }
    };
    for p in positions() {
        p.iter().for_each(|&v| real(&mut body, v + shift));
    }
    for n in normals() {
        n.iter().for_each(|&v| real(&mut body, v));
    }
    for t in uvs() {
        t.iter().for_each(|&v| real(&mut body, v));
    }
    for _ in 0..5 {
        [0.1, 0.2, 0.3].iter().for_each(|&v| real(&mut body, v));
    }
    for t in expected().indices {
        t.iter().for_each(|i| body.extend(i.to_le_bytes()));
    }
    let mut z = ZlibEncoder::new(Vec::new(), Compression::default());
    z.write_all(&body).unwrap();
    let mut out = 0x041Cu16.to_le_bytes().to_vec();
    out.extend(version.to_le_bytes());
    out.extend(z.finish().unwrap());
    out
}

/// A file of two meshes (the second shifted by 10) with its table of offsets.
fn serialized_file(version: u16, double: bool) -> Vec<u8> {
    let first = serialized_mesh(version, double, "first", 0.0);
    let second = serialized_mesh(version, double, "second", 10.0);
    let mut out = first.clone();
    out.extend(&second);
    for offset in [0, first.len() as u64] {
        if version == 4 {
            out.extend(offset.to_le_bytes());
        } else {
            out.extend((offset as u32).to_le_bytes());
        }
    }
    out.extend(2u32.to_le_bytes());
    out
}

#[test]
fn serialized_meshes_of_versions_3_and_4_load_back() {
    let path = Path::new("mesh.serialized");
    for version in [3, 4] {
        for double in [false, true] {
            let file = serialized_file(version, double);
            assert_eq!(parse_serialized(&file, path, 0).unwrap(), expected());
            let second = parse_serialized(&file, path, 1).unwrap();
            let shifted: Vec<Vec3> = expected().positions.iter().map(|p| *p + 10.0).collect();
            assert_eq!(second.positions, shifted, "v{version} double {double}");
            assert_eq!(second.indices, expected().indices);
            let m = parse_serialized(&file, path, 2).unwrap_err().to_string();
            assert!(
                m.contains("mesh.serialized: mesh 2: the file has 2 meshes"),
                "{m}"
            );
        }
    }
    let mut bad = serialized_file(4, false);
    bad[2] = 5;
    let m = parse_serialized(&bad, path, 0).unwrap_err().to_string();
    assert!(m.contains("format version 5 is not supported"), "{m}");
    let truncated = &serialized_file(4, false)[..40];
    assert!(parse_serialized(truncated, path, 0).is_err());
}

/// A mesh's triangles as point triples, for comparing meshes indexed differently.
fn triangles(positions: &[Vec3], indices: &[[u32; 3]]) -> Vec<[Vec3; 3]> {
    indices
        .iter()
        .map(|t| t.map(|i| positions[i as usize]))
        .collect()
}

#[test]
fn the_shipped_blocks_are_the_obj_blocks() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/mitsuba");
    let mut warnings = Vec::new();
    for (file, obj) in [
        ("short_block.serialized", "short_block.obj"),
        ("tall_block.ply", "tall_block.obj"),
    ] {
        let mesh = if file.ends_with("ply") {
            load_ply(&data.join(file)).unwrap()
        } else {
            load_serialized(&data.join(file), 0).unwrap()
        };
        let obj = load_obj(&scenes_dir().join(obj), ObjMaterials::Ignore, &mut warnings).unwrap();
        let o = &obj.meshes[0];
        let (a, b) = (
            triangles(&mesh.positions, &mesh.indices),
            triangles(&o.positions, &o.indices),
        );
        assert_eq!(a.len(), b.len());
        for (x, y) in a.iter().zip(&b) {
            for k in 0..3 {
                assert!(x[k].abs_diff_eq(y[k], 1e-6), "{file}: {x:?} {y:?}");
            }
        }
    }
}
