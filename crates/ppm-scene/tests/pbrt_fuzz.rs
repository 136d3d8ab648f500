//! Fuzzing (proptest, fixed seed): random mutations of the pbrt-v4 Cornell box give a scene
//! that is sane or an error naming the file; never a panic or a hang.

use ppm_core::light::Light;
use ppm_core::scene::SceneBuilder;
use ppm_scene::pbrt::parse_pbrt;
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

fn cbox() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/pbrt/cbox.pbrt")
}

/// One edit of the text: replace a range with a token, delete it, duplicate it, or replace
/// one number with an odd value.
#[derive(Clone, Debug)]
enum Edit {
    Replace(Index, usize, &'static str),
    Delete(Index, usize),
    Duplicate(Index, usize),
    Byte(Index, u8),
    Number(Index, &'static str),
}

fn edit() -> impl Strategy<Value = Edit> {
    prop_oneof![
        (any::<Index>(), 0usize..8, select(TOKENS)).prop_map(|(i, n, t)| Edit::Replace(i, n, t)),
        (any::<Index>(), 1usize..40).prop_map(|(i, n)| Edit::Delete(i, n)),
        (any::<Index>(), 1usize..300).prop_map(|(i, n)| Edit::Duplicate(i, n)),
        (any::<Index>(), any::<u8>()).prop_map(|(i, b)| Edit::Byte(i, b)),
        (any::<Index>(), select(NUMBERS)).prop_map(|(i, v)| Edit::Number(i, v)),
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
            Edit::Number(i, v) => {
                // The start of a number: a digit or '-' after a space.
                let starts: Vec<usize> = (1..out.len())
                    .filter(|&k| out[k - 1] == b' ' && (out[k].is_ascii_digit() || out[k] == b'-'))
                    .collect();
                if starts.is_empty() {
                    continue;
                }
                let s = starts[i.index(starts.len())];
                let end = out[s..]
                    .iter()
                    .position(|&c| c == b' ' || c == b'\n' || c == b']')
                    .map_or(out.len(), |e| s + e);
                out.splice(s..end, v.bytes());
            }
        }
    }
    out
}

const NUMBERS: &[&str] = &[
    "1e39",
    "-1e39",
    "-1",
    "0",
    "1e-45",
    "1e308",
    "-1e308",
    "2.5",
    "9999999999",
    "16385",
    "100000",
    "3e38",
];

const TOKENS: &[&str] = &[
    "[",
    "]",
    "\"",
    "#",
    "\n",
    "AttributeBegin\n",
    "AttributeEnd\n",
    "WorldBegin\n",
    "ObjectBegin \"white wall\"\n",
    "ObjectEnd\n",
    "ObjectInstance \"white wall\"\n",
    "ReverseOrientation\n",
    "Scale 0 0 0\n",
    "Scale -1 1 1\n",
    "Rotate 1e308 1 0 0\n",
    "Transform [1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1]\n",
    "Identity\n",
    "CoordSysTransform \"camera\"\n",
    "Include \"cbox.pbrt\"\n",
    "Import \"nothing.pbrt\"\n",
    "NamedMaterial \"red\"\n",
    "Shape \"sphere\" \"float radius\" 1e30\n",
    "Shape \"disk\"\n",
    "Shape \"sphere\"\n",
    "LightSource \"spot\" \"float coneangle\" 1e30\n",
    "LightSource \"point\" \"rgb I\" [1e38 1e38 1e38] \"float power\" 1e38\n",
    "AreaLightSource \"diffuse\" \"float power\" 1e30\n",
    "Material \"conductor\" \"float roughness\" 1e30\n",
    "Material \"coateddiffuse\"\n",
    "\"blackbody L\" [0]",
    "\"spectrum L\" [400 1 300 2]",
    "\"rgb L\" [-1 0 0]",
    "\"float fov\" [179.9999]",
    "\"integer indices\" [0 1 99]",
    "\"normal N\" [0 0 0]",
    "NaN",
    "inf",
    "-",
];

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
        if let Light::Point(p) = l {
            assert!(p.position.is_finite(), "{l:?}");
        }
    }
}

fn load_mutated_cbox(edits: &[Edit]) {
    let path = cbox();
    let text = apply(&std::fs::read(&path).unwrap(), edits);
    let text = String::from_utf8_lossy(&text);
    match parse_pbrt(&text, &path) {
        Ok((b, _)) => {
            check_builder(&b);
            // The core accepts or refuses it with an error, never a panic.
            let _ = b.build();
        }
        Err(e) => check_error(&e),
    }
}

/// The message starts with the file it is about.
fn check_error(e: &LoadError) {
    let msg = e.to_string();
    assert!(msg.starts_with(&e.path().display().to_string()), "{msg}");
}

proptest! {
    #![proptest_config(config(300))]

    #[test]
    fn mutated_pbrt_scenes_never_panic(edits in prop::collection::vec(edit(), 1..6)) {
        load_mutated_cbox(&edits);
    }

    #[test]
    fn pbrt_scenes_with_odd_numbers_never_panic(
        numbers in prop::collection::vec((any::<Index>(), select(NUMBERS)), 1..4),
    ) {
        let edits: Vec<Edit> = numbers.into_iter().map(|(i, v)| Edit::Number(i, v)).collect();
        load_mutated_cbox(&edits);
    }
}
