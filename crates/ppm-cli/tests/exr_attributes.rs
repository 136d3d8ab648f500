//! The render EXR's header: `ppm.*` attributes with their EXR types, pbrt-v4's camera
//! matrices `worldToCamera` and `worldToNDC`, ZIP compression; and the pixels and exact sums
//! bit for bit those the uncompressed all-string writer wrote (a file of that writer, kept in
//! tests/data, still resumes and merges into the same image).

mod common;

use common::*;
use exr::meta::attribute::AttributeValue;
use exr::prelude::{Compression, FlatSamples};
use glam::DVec3;
use std::collections::BTreeMap;
use std::path::Path;

type Layer = exr::prelude::Layer<exr::prelude::AnyChannels<FlatSamples>>;

fn read_layer(path: &Path) -> Layer {
    let image = exr::prelude::read_all_flat_layers_from_file(path).unwrap();
    image.layer_data.into_iter().next().unwrap()
}

fn attribute<'a>(layer: &'a Layer, name: &str) -> &'a AttributeValue {
    layer
        .attributes
        .other
        .get(&exr::prelude::Text::from(name))
        .unwrap_or_else(|| panic!("no attribute {name}"))
}

/// Every channel's samples as bits, by name.
fn channel_bits(layer: &Layer) -> BTreeMap<String, Vec<u32>> {
    layer
        .channel_data
        .list
        .iter()
        .map(|c| {
            let bits = match &c.sample_data {
                FlatSamples::F32(v) => v.iter().map(|x| x.to_bits()).collect(),
                FlatSamples::U32(v) => v.clone(),
                FlatSamples::F16(v) => v.iter().map(|x| x.to_bits() as u32).collect(),
            };
            (c.name.to_string(), bits)
        })
        .collect()
}

/// (M p) / w for the row-major 4x4 `m` (pbrt's layout: translation in the last column).
fn project(m: &[f32; 16], p: DVec3) -> DVec3 {
    let row = |i: usize| {
        m[4 * i] as f64 * p.x
            + m[4 * i + 1] as f64 * p.y
            + m[4 * i + 2] as f64 * p.z
            + m[4 * i + 3] as f64
    };
    DVec3::new(row(0), row(1), row(2)) / row(3)
}

#[test]
fn attributes_are_typed_the_camera_recorded_and_the_file_compressed() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    std::fs::copy(data.join("state_format1.yml"), d.join("bright.yml")).unwrap();
    let base = [
        "bright.yml",
        "-a",
        "ppm",
        "--seed",
        "5",
        "--threads",
        "1",
        "-n",
        "2",
    ];
    assert_ok(&run(d, &[&base[..], &["-o", "new"]].concat()));
    let layer = read_layer(&d.join("new.exr"));

    for name in [
        "ppm.state",
        "ppm.seed",
        "ppm.iterations",
        "ppm.maxDepth",
        "ppm.sumWords",
    ] {
        assert!(
            matches!(attribute(&layer, name), AttributeValue::I32(_)),
            "{name}: {:?}",
            attribute(&layer, name)
        );
    }
    assert_eq!(attribute(&layer, "ppm.iterations"), &AttributeValue::I32(2));
    assert_eq!(attribute(&layer, "ppm.seed"), &AttributeValue::I32(5));
    assert_eq!(attribute(&layer, "ppm.alpha"), &AttributeValue::F32(0.7));
    assert!(matches!(
        attribute(&layer, "ppm.renderSeconds"),
        AttributeValue::F64(s) if *s >= 0.0
    ));
    assert!(matches!(
        attribute(&layer, "ppm.sceneHash"),
        AttributeValue::Text(_)
    ));
    assert_eq!(layer.encoding.compression, Compression::ZIP16);

    // The camera of state_format1.yml: at (0, 1, 3.9) looking at (0, 1, 0), y up, 38 degrees
    // vertically on a 16 x 12 image (wider than tall: the fov spans the shorter axis).
    // The standard attributes `worldToCamera` and `worldToNDC` (m44f), which the exr crate
    // reads into fields of their own.
    let to_camera = layer.attributes.world_to_camera.expect("worldToCamera");
    let to_ndc = layer
        .attributes
        .world_to_normalized_device
        .expect("worldToNDC");
    let eye = DVec3::new(0.0, 1.0, 3.9);
    // Camera space: +x right (world +x), +y up, +z forward (world -z), origin at the eye.
    for (world, camera) in [
        (eye, DVec3::ZERO),
        (DVec3::new(0.0, 1.0, 0.0), DVec3::new(0.0, 0.0, 3.9)),
        (DVec3::new(1.0, 1.5, 2.9), DVec3::new(1.0, 0.5, 1.0)),
    ] {
        let got = project(&to_camera, world);
        assert!(
            (got - camera).length() < 1e-5,
            "{world} -> {got}, not {camera}"
        );
    }
    // pbrt's NDC: (screen + 1) / 2, screen y up, the shorter (vertical) axis spanning
    // [-1, 1]: the top-right image corner is at screen (16/12, 1).
    let tan = (19.0f64).to_radians().tan();
    let aspect = 16.0 / 12.0;
    let corner = eye + 2.0 * DVec3::new(aspect * tan, tan, -1.0);
    let ndc = project(&to_ndc, corner);
    assert!((ndc.x - (aspect + 1.0) / 2.0).abs() < 1e-5, "{ndc}");
    assert!((ndc.y - 1.0).abs() < 1e-5, "{ndc}");
    let centre = project(&to_ndc, DVec3::new(0.0, 1.0, 0.0));
    assert!(
        (centre.truncate() - glam::DVec2::splat(0.5)).length() < 1e-6,
        "{centre}"
    );

    // `ppm info` shows the types' values.
    let info = stdout(&run(d, &["info", "new.exr"]));
    assert!(
        info.contains("ppm.iterations") && info.contains("worldToNDC"),
        "{info}"
    );
}

/// A state file of the all-string writer (format 2 before typed attributes and compression,
/// `tests/data/state_strings.exr`, written by main at 4abec1b from
/// `tests/data/state_format1.yml` with `-a ppm --seed 5 -n 2 --threads 1`): the new writer's
/// pixels and sums are the same bits; the old file resumes and merges exactly.
#[test]
fn a_state_file_with_string_attributes_still_resumes_and_merges_exactly() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    std::fs::copy(data.join("state_format1.yml"), d.join("bright.yml")).unwrap();
    std::fs::copy(data.join("state_strings.exr"), d.join("old.exr")).unwrap();
    let old = read_layer(&d.join("old.exr"));
    assert!(matches!(
        attribute(&old, "ppm.iterations"),
        AttributeValue::Text(_)
    ));
    assert_eq!(old.encoding.compression, Compression::Uncompressed);

    let base = ["bright.yml", "-a", "ppm", "--seed", "5", "--threads", "1"];
    let ok = |args: &[&str]| assert_ok(&run(d, &[&base[..], args].concat()));
    ok(&["-n", "2", "-o", "new"]);
    assert_eq!(
        channel_bits(&read_layer(&d.join("new.exr"))),
        channel_bits(&old),
        "pixels and sums bit for bit"
    );
    ok(&["-n", "3", "-o", "whole"]);
    ok(&["-n", "1", "--resume", "old.exr", "-o", "resumed"]);
    let whole = channel_bits(&read_layer(&d.join("whole.exr")));
    assert_eq!(channel_bits(&read_layer(&d.join("resumed.exr"))), whole);
    ok(&["-n", "3", "--shard", "2/3", "-o", "last"]);
    assert_ok(&run(d, &["merge", "old.exr", "last.exr", "-o", "merged"]));
    assert_eq!(channel_bits(&read_layer(&d.join("merged.exr"))), whole);
}
