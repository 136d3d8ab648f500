//! Fuzzing (proptest, fixed seed): random mutations of a valid Mitsuba scene, PLY and
//! serialized mesh give a scene that is sane or an error naming the file; never a panic or
//! a hang.

use ppm_core::scene::SceneBuilder;
use ppm_scene::mitsuba::parse_mitsuba;
use ppm_scene::ply::parse_ply;
use ppm_scene::serialized::parse_serialized;
use ppm_scene::LoadError;
use proptest::prelude::*;
use proptest::sample::{select, Index};
use proptest::test_runner::RngSeed;
use std::path::{Path, PathBuf};

fn config(cases: u32) -> ProptestConfig {
    ProptestConfig {
        cases,
        rng_seed: RngSeed::Fixed(0x0BAD_F00D),
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/mitsuba")
        .join(name)
}

/// One edit of a text or file: replace a range with a token, delete it, or duplicate it.
#[derive(Clone, Debug)]
enum Edit {
    Replace(Index, usize, &'static str),
    Delete(Index, usize),
    Duplicate(Index, usize),
    Byte(Index, u8),
    /// The text between the quotes of one `value="..."`, replaced: valid XML, odd values.
    Value(Index, &'static str),
}

fn edit(tokens: Vec<&'static str>) -> impl Strategy<Value = Edit> {
    prop_oneof![
        (any::<Index>(), 0usize..8, select(tokens)).prop_map(|(i, n, t)| Edit::Replace(i, n, t)),
        (any::<Index>(), 1usize..40).prop_map(|(i, n)| Edit::Delete(i, n)),
        (any::<Index>(), 1usize..200).prop_map(|(i, n)| Edit::Duplicate(i, n)),
        (any::<Index>(), any::<u8>()).prop_map(|(i, b)| Edit::Byte(i, b)),
    ]
}

fn apply(bytes: &[u8], edits: &[Edit]) -> Vec<u8> {
    let mut out = bytes.to_vec();
    for e in edits {
        if out.is_empty() {
            break;
        }
        let at = |i: &Index, out: &Vec<u8>| i.index(out.len());
        match e {
            Edit::Replace(i, n, t) => {
                let s = at(i, &out);
                let end = (s + n).min(out.len());
                out.splice(s..end, t.bytes());
            }
            Edit::Delete(i, n) => {
                let s = at(i, &out);
                out.drain(s..(s + n).min(out.len()));
            }
            Edit::Duplicate(i, n) => {
                let s = at(i, &out);
                let piece = out[s..(s + n).min(out.len())].to_vec();
                out.splice(s..s, piece);
            }
            Edit::Byte(i, b) => {
                let s = at(i, &out);
                out[s] = *b;
            }
            Edit::Value(i, v) => {
                let key = b"value=\"";
                let starts: Vec<usize> = (0..out.len().saturating_sub(key.len()))
                    .filter(|&k| out[k..].starts_with(key))
                    .map(|k| k + key.len())
                    .collect();
                if starts.is_empty() {
                    continue;
                }
                let s = starts[i.index(starts.len())];
                let end = out[s..]
                    .iter()
                    .position(|&c| c == b'"')
                    .map_or(out.len(), |e| s + e);
                out.splice(s..end, v.bytes());
            }
        }
    }
    out
}

/// Everything a loaded scene hands to the core is finite and in range.
fn check_builder(b: &SceneBuilder) {
    let n = b.materials.len() as u32;
    for m in &b.materials {
        assert!(
            m.emission.is_finite() && m.emission.min_element() >= 0.0,
            "{m:?}"
        );
    }
    for mesh in &b.meshes {
        assert_eq!(mesh.indices.len(), mesh.materials.len());
        assert!(mesh.normals.is_empty() || mesh.normals.len() == mesh.positions.len());
        assert!(mesh
            .normals
            .iter()
            .all(|v| v.is_finite() && (v.length() - 1.0).abs() < 1e-3));
        assert!(mesh.positions.iter().all(|p| p.is_finite()));
        for (t, &m) in mesh.indices.iter().zip(&mesh.materials) {
            assert!(m < n && t.iter().all(|&i| (i as usize) < mesh.positions.len()));
        }
    }
    for s in &b.spheres {
        assert!(s.center.is_finite() && s.radius.is_finite() && s.radius > 0.0 && s.material < n);
    }
    for l in &b.lights {
        let power = l.power();
        assert!(power.is_finite() && power.min_element() >= 0.0, "{l:?}");
    }
}

/// The message starts with the file it is about.
fn check_error(e: &LoadError) {
    let msg = e.to_string();
    assert!(msg.starts_with(&e.path().display().to_string()), "{msg}");
}

/// Values for `value="..."`: out of range, not finite, the wrong kind or count.
const VALUES: &[&str] = &[
    "1e39",
    "-1e39",
    "-1",
    "0",
    "1e-45",
    "NaN",
    "inf",
    "",
    "1, 2",
    "1 2 3 4",
    "abc",
    "$res",
    "$undefined",
    "x",
    "y",
    "diagonal",
    "none",
    "bk7",
    "0.5, -0.2, 0.1",
    "400:1, 500:1e40",
    "9999999999999999999",
    "16385",
    "2",
];

const XML_TOKENS: &[&str] = &[
    "<",
    ">",
    "/>",
    "</shape>",
    "\"",
    "=",
    "$res",
    "$nothing",
    "<include filename=\"cbox.xml\"/>",
    "<ref id=\"white\"/>",
    "<ref id=\"red\"/>",
    "<bsdf type=\"twosided\">",
    "<transform name=\"to_world\">",
    "<scale value=\"0\"/>",
    "<scale x=\"-1\"/>",
    "<rotate angle=\"1e308\" x=\"1\"/>",
    "<matrix value=\"1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\"/>",
    "<float name=\"radius\" value=\"-1\"/>",
    "<rgb name=\"radiance\" value=\"1e39\"/>",
    "<spectrum name=\"radiance\" value=\"550:5\"/>",
    "<spectrum name=\"reflectance\" value=\"400:1, 700:2\"/>",
    "<shape type=\"sphere\">",
    "<shape type=\"disk\"/>",
    "<shape type=\"cylinder\"/>",
    "<emitter type=\"point\"/>",
    "NaN",
    "inf",
    "-1",
    "0",
    "1e30",
    "version=\"0.6.0\"",
    "toWorld",
    "<default name=\"x\" value=\"$x\"/>",
    "<!--",
    "-->",
    "&amp;",
    "&#0;",
];

/// The Cornell box of `data/` with `edits`: a sane scene or an error naming a file.
fn load_mutated_cbox(edits: &[Edit]) {
    let path = data("cbox.xml");
    let text = apply(&std::fs::read(&path).unwrap(), edits);
    let text = String::from_utf8_lossy(&text);
    let defines = [("res".to_string(), "16".to_string())];
    match parse_mitsuba(&text, &path, &defines) {
        Ok((b, _)) => check_builder(&b),
        Err(e) => check_error(&e),
    }
}

proptest! {
    #![proptest_config(config(300))]

    #[test]
    fn mutated_mitsuba_scenes_never_panic(edits in prop::collection::vec(edit(XML_TOKENS.to_vec()), 1..6)) {
        load_mutated_cbox(&edits);
    }

    #[test]
    fn mitsuba_scenes_with_odd_values_never_panic(
        values in prop::collection::vec((any::<Index>(), select(VALUES)), 1..4),
    ) {
        let edits: Vec<Edit> = values.into_iter().map(|(i, v)| Edit::Value(i, v)).collect();
        load_mutated_cbox(&edits);
    }

    #[test]
    fn mutated_ply_meshes_never_panic(
        edits in prop::collection::vec(edit(vec!["element face 99999999\n", "property list uchar int vertex_indices\n", "-1", "255 ", "nan ", "format binary_big_endian 1.0\n", "\n"]), 1..5),
        binary in any::<bool>(),
    ) {
        let ascii = std::fs::read(data("tall_block.ply")).unwrap();
        let bytes = if binary {
            // The same mesh in binary little endian.
            let mesh = parse_ply(&ascii, Path::new("t.ply")).unwrap();
            let mut out = format!(
                "ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n",
                mesh.positions.len(), mesh.indices.len()
            ).into_bytes();
            for p in &mesh.positions {
                p.to_array().iter().for_each(|v| out.extend(v.to_le_bytes()));
            }
            for t in &mesh.indices {
                out.push(3);
                t.iter().for_each(|&i| out.extend((i as i32).to_le_bytes()));
            }
            out
        } else {
            ascii
        };
        let path = Path::new("mutated.ply");
        match parse_ply(&apply(&bytes, &edits), path) {
            Ok(mesh) => {
                assert!(mesh.positions.iter().all(|p| p.is_finite()));
                assert!(mesh.indices.iter().flatten().all(|&i| (i as usize) < mesh.positions.len()));
            }
            Err(e) => check_error(&e),
        }
    }

    #[test]
    fn mutated_serialized_meshes_never_panic(edits in prop::collection::vec(edit(vec!["\0", "\u{1c}\u{4}\u{4}\0", "\u{ff}\u{ff}\u{ff}\u{ff}"]), 1..4), index in 0u32..3) {
        let bytes = std::fs::read(data("short_block.serialized")).unwrap();
        let path = Path::new("mutated.serialized");
        match parse_serialized(&apply(&bytes, &edits), path, index) {
            Ok(mesh) => assert!(mesh.indices.iter().flatten().all(|&i| (i as usize) < mesh.positions.len())),
            Err(e) => check_error(&e),
        }
    }
}
