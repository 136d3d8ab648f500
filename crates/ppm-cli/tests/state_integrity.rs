//! Render-state EXRs are checked before they are merged or resumed: a flipped bit anywhere
//! in the pixel data or the offset table, and header fields that contradict each other or
//! the data, are refused with an error naming the file (and the field), never joined into
//! another image. Files written before the checksum still load, with a warning.

mod common;

use common::*;
use exr::meta::attribute::{AttributeValue, Text};
use std::path::Path;

/// Renders the two shards of a 2-iteration render of the tiny scene as part_0.exr and
/// part_1.exr.
fn shards(dir: &Path) {
    tiny_scene(dir);
    for i in 0..2 {
        let shard = format!("{i}/2");
        let out = format!("part_{i}");
        let args = [
            "tiny.yml", "-a", "pt", "-n", "2", "--shard", &shard, "-o", &out,
        ];
        assert_ok(&run(dir, &args));
    }
}

/// `ppm merge part_0.exr part_1.exr -o merged`, expected to be refused (status 1) with an
/// error naming part_1.exr; returns stderr.
fn merge_refused(dir: &Path, what: &str) -> String {
    let args = ["merge", "part_0.exr", "part_1.exr", "-o", "merged"];
    let err = assert_fails(&run(dir, &args), 1);
    assert!(err.contains("part_1.exr"), "{what}: {err}");
    assert!(!dir.join("merged.exr").exists(), "{what}");
    err
}

/// Rewrites the EXR at `path` with its `ppm.*` attributes changed by `edit` (pixels kept),
/// every one written back as a string (as ppm wrote them before they were typed).
fn edit_attributes(path: &Path, edit: impl Fn(&mut Vec<(String, String)>)) {
    use exr::prelude::WritableImage;
    let mut image = exr::prelude::read_all_flat_layers_from_file(path).unwrap();
    let other = &mut image.layer_data[0].attributes.other;
    let mut text: Vec<(String, String)> = other
        .iter()
        .filter_map(|(k, v)| match v {
            AttributeValue::Text(t) => Some((k.to_string(), t.to_string())),
            AttributeValue::I32(v) => Some((k.to_string(), v.to_string())),
            AttributeValue::F32(v) => Some((k.to_string(), v.to_string())),
            AttributeValue::F64(v) => Some((k.to_string(), v.to_string())),
            _ => None,
        })
        .filter(|(k, _)| k.starts_with("ppm."))
        .collect();
    edit(&mut text);
    other.retain(|k, _| !k.to_string().starts_with("ppm."));
    for (k, v) in text {
        other.insert(
            Text::from(k.as_str()),
            AttributeValue::Text(Text::from(v.as_str())),
        );
    }
    image.write().to_file(path).unwrap();
}

#[test]
fn flipped_bits_in_the_state_data_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    shards(dir.path());
    let path = dir.path().join("part_1.exr");
    let original = std::fs::read(&path).unwrap();
    // The offset table (one u64 a block of scan lines, the first pointing just past the
    // table) and the compressed blocks end the file.
    let (_, _, _) = read_exr(&path);
    let meta = exr::meta::MetaData::read_from_file(&path, false).unwrap();
    let blocks = meta.headers[0].chunk_count;
    let u64_at = |at: usize| u64::from_le_bytes(original[at..at + 8].try_into().unwrap());
    let start = (0..original.len() - 8)
        .find(|&at| u64_at(at) as usize == at + 8 * blocks)
        .expect("the offset table");
    let data = original.len() - start;
    // 48 flips spread over the data and the table, each a different bit.
    for k in 0..48 {
        let offset = start + k * (data - 1) / 47;
        let mut bytes = original.clone();
        bytes[offset] ^= 1 << (k % 8);
        std::fs::write(&path, &bytes).unwrap();
        merge_refused(dir.path(), &format!("bit {} of byte {offset}", k % 8));
    }
    // Every block pointed at the table itself: each reads the table as pixels.
    let mut bytes = original.clone();
    let table = start;
    for block in 0..blocks {
        let at = table + 8 * block;
        bytes[at..at + 8].copy_from_slice(&(table as u64).to_le_bytes());
    }
    std::fs::write(&path, &bytes).unwrap();
    merge_refused(dir.path(), "offset table pointing at itself");
    // The untouched file merges.
    std::fs::write(&path, &original).unwrap();
    let args = ["merge", "part_0.exr", "part_1.exr", "-o", "merged"];
    assert_ok(&run(dir.path(), &args));
}

#[test]
fn edited_header_fields_are_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    shards(dir.path());
    let path = dir.path().join("part_1.exr");
    let original = std::fs::read(&path).unwrap();
    let set = |name: &'static str, value: &'static str| {
        move |text: &mut Vec<(String, String)>| {
            for (k, v) in text.iter_mut() {
                if k == name {
                    *v = value.to_string();
                }
            }
        }
    };
    // With the checksum kept, any edit is caught by it.
    edit_attributes(&path, set("ppm.seed", "7"));
    let err = merge_refused(dir.path(), "seed edited");
    assert!(err.contains("ppm.stateHash"), "{err}");

    // Without the checksum (a file of an older ppm) the fields are checked one by one.
    let no_hash = |text: &mut Vec<(String, String)>| text.retain(|(k, _)| k != "ppm.stateHash");
    std::fs::write(&path, &original).unwrap();
    edit_attributes(&path, no_hash);
    let args = ["merge", "part_0.exr", "part_1.exr", "-o", "merged"];
    let output = run(dir.path(), &args);
    assert_ok(&output);
    let warning = stderr(&output);
    assert!(
        warning.contains("part_1.exr has no checksum"),
        "an old file loads with a warning: {warning}"
    );
    std::fs::remove_file(dir.path().join("merged.exr")).unwrap();
    std::fs::remove_file(dir.path().join("merged.png")).unwrap();
    for (field, value) in [
        ("ppm.iterations", "0"),
        ("ppm.iterations", "18446744073709551615"),
        ("ppm.sumWords", "1"),
        ("ppm.rejected", "100000"),
        ("ppm.firstIteration", "18446744073709551615"),
    ] {
        std::fs::write(&path, &original).unwrap();
        edit_attributes(&path, |text| {
            no_hash(text);
            set(field, value)(text);
        });
        let err = merge_refused(dir.path(), &format!("{field} {value}"));
        assert!(err.contains(field), "{field} {value}: {err}");
    }
    // The image edited apart from its sums.
    std::fs::write(&path, &original).unwrap();
    edit_attributes(&path, |text| {
        no_hash(text);
        set("ppm.iterations", "3")(text);
    });
    let args = [
        "tiny.yml",
        "-a",
        "pt",
        "--resume",
        "part_1.exr",
        "-n",
        "1",
        "-o",
        "more",
    ];
    let err = assert_fails(&run(dir.path(), &args), 1);
    assert!(
        err.contains("part_1.exr") && err.contains("disagree"),
        "{err}"
    );
}
