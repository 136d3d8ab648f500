//! `ppm info FILE.exr`: what an EXR records about itself: its size, its channels and every
//! attribute of its header, standard or custom (such as how the image was rendered).
//!
//! The header is read directly (OpenEXR file layout, "Reading and Writing OpenEXR Image
//! Files", section "Header"): the magic number 20000630, a 4-byte version field, then
//! attributes, each `name\0 type\0 u32 size` and `size` bytes of value (little-endian), until
//! an empty name. Reading it ourselves shows every attribute exactly as stored, including
//! types a library would not know; values of unknown types are shown by their size.

use anyhow::{bail, Context, Result};
use std::fmt::Write as _;
use std::io::Read;
use std::path::Path;

/// One header attribute: name, type name and raw value.
#[derive(Clone, Debug, PartialEq)]
pub struct Attribute {
    pub name: String,
    pub kind: String,
    pub value: Vec<u8>,
}

/// The attributes of the first (or only) header of an EXR file's bytes.
pub fn read_header(bytes: &[u8]) -> Result<Vec<Attribute>> {
    if bytes.len() < 8 || bytes[..4] != [0x76, 0x2f, 0x31, 0x01] {
        bail!("not an OpenEXR file (no magic number 76 2f 31 01 at the start)");
    }
    let mut at = 8;
    let mut attributes = Vec::new();
    let take_str = |at: &mut usize| -> Result<String> {
        let rest = &bytes[*at..];
        let end = rest
            .iter()
            .position(|&b| b == 0)
            .context("the header ends inside an attribute name")?;
        *at += end + 1;
        Ok(String::from_utf8_lossy(&rest[..end]).into_owned())
    };
    loop {
        let name = take_str(&mut at)?;
        if name.is_empty() {
            return Ok(attributes);
        }
        let kind = take_str(&mut at)?;
        let size = bytes
            .get(at..at + 4)
            .with_context(|| format!("the header ends inside attribute `{name}`"))?;
        let size = u32::from_le_bytes(size.try_into().unwrap()) as usize;
        at += 4;
        let value = bytes
            .get(at..at + size)
            .with_context(|| format!("attribute `{name}` claims {size} bytes past the end"))?;
        at += size;
        attributes.push(Attribute {
            name,
            kind,
            value: value.to_vec(),
        });
    }
}

fn i32s(v: &[u8]) -> Vec<i32> {
    v.chunks_exact(4)
        .map(|c| i32::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

fn f32s(v: &[u8]) -> Vec<f32> {
    v.chunks_exact(4)
        .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

fn list<T: std::fmt::Display>(items: &[T]) -> String {
    let parts: Vec<String> = items.iter().map(|x| x.to_string()).collect();
    format!("({})", parts.join(", "))
}

/// The channels of a `chlist` value: `name\0 i32 pixel type, u8 pLinear, 3 reserved,
/// i32 xSampling, i32 ySampling`, until an empty name.
pub fn channels(value: &[u8]) -> Vec<(String, &'static str)> {
    let mut out = Vec::new();
    let mut at = 0;
    while let Some(end) = value[at..].iter().position(|&b| b == 0) {
        if end == 0 {
            break;
        }
        let name = String::from_utf8_lossy(&value[at..at + end]).into_owned();
        at += end + 1;
        let Some(t) = value.get(at..at + 4) else {
            break;
        };
        let kind = match i32::from_le_bytes(t.try_into().unwrap()) {
            0 => "uint",
            1 => "half",
            2 => "float",
            _ => "unknown",
        };
        out.push((name, kind));
        at += 16;
        if at > value.len() {
            break;
        }
    }
    out
}

/// An attribute's value as text.
pub fn format_value(a: &Attribute) -> String {
    let v = &a.value;
    match a.kind.as_str() {
        "string" => format!("{:?}", String::from_utf8_lossy(v)),
        "int" if v.len() == 4 => i32s(v)[0].to_string(),
        "float" if v.len() == 4 => f32s(v)[0].to_string(),
        "double" if v.len() == 8 => f64::from_le_bytes(v[..].try_into().unwrap()).to_string(),
        "v2i" | "v3i" | "box2i" => list(&i32s(v)),
        "v2f" | "v3f" | "box2f" | "chromaticities" | "m33f" | "m44f" => list(&f32s(v)),
        "rational" if v.len() == 8 => {
            let n = i32s(&v[..4])[0];
            let d = u32::from_le_bytes(v[4..8].try_into().unwrap());
            format!("{n}/{d}")
        }
        "compression" if v.len() == 1 => match v[0] {
            0 => "none",
            1 => "rle",
            2 => "zips",
            3 => "zip",
            4 => "piz",
            5 => "pxr24",
            6 => "b44",
            7 => "b44a",
            8 => "dwaa",
            9 => "dwab",
            _ => "unknown",
        }
        .into(),
        "lineOrder" if v.len() == 1 => match v[0] {
            0 => "increasing y",
            1 => "decreasing y",
            2 => "random y",
            _ => "unknown",
        }
        .into(),
        "chlist" => channels(v)
            .iter()
            .map(|(n, t)| format!("{n} ({t})"))
            .collect::<Vec<_>>()
            .join(", "),
        "stringvector" => {
            let mut items = Vec::new();
            let mut at = 0;
            while let Some(len) = v.get(at..at + 4) {
                let len = u32::from_le_bytes(len.try_into().unwrap()) as usize;
                let Some(s) = v.get(at + 4..at + 4 + len) else {
                    break;
                };
                items.push(format!("{:?}", String::from_utf8_lossy(s)));
                at += 4 + len;
            }
            format!("[{}]", items.join(", "))
        }
        _ => format!("<{} bytes>", v.len()),
    }
}

/// The report `ppm info` prints for an EXR file's bytes.
pub fn report(path: &Path, bytes: &[u8]) -> Result<String> {
    let attributes = read_header(bytes).with_context(|| format!("{}", path.display()))?;
    let mut out = String::new();
    let _ = writeln!(out, "{}", path.display());
    if let Some(w) = attributes.iter().find(|a| a.name == "dataWindow") {
        let b = i32s(&w.value);
        if b.len() == 4 {
            let _ = writeln!(out, "size: {}x{}", b[2] - b[0] + 1, b[3] - b[1] + 1);
        }
    }
    if let Some(c) = attributes.iter().find(|a| a.name == "channels") {
        let _ = writeln!(out, "channels: {}", format_value(c));
    }
    if bytes.len() > 7 && bytes[5] & 0x10 != 0 {
        let _ = writeln!(out, "(a multi-part file: the first part's header is shown)");
    }
    let _ = writeln!(out, "header attributes:");
    for a in &attributes {
        let _ = writeln!(out, "  {} ({}) = {}", a.name, a.kind, format_value(a));
    }
    Ok(out)
}

/// `ppm info FILE.exr`: prints the report to stdout.
pub fn run(path: &Path) -> Result<()> {
    let mut file = std::fs::File::open(path)
        .with_context(|| format!("cannot open image {}", path.display()))?;
    // A header is small; 1 MiB covers any plausible one (a preview image included).
    let mut bytes = Vec::new();
    file.by_ref()
        .take(1 << 20)
        .read_to_end(&mut bytes)
        .with_context(|| format!("cannot read image {}", path.display()))?;
    crate::console::print_stdout(&report(path, &bytes)?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use exr::prelude::*;

    #[test]
    fn every_attribute_is_printed_with_its_value() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.exr");
        let mut layer = Layer::new(
            (3, 2),
            LayerAttributes::named("rgb"),
            Encoding::FAST_LOSSLESS,
            SpecificChannels::rgb(|_: Vec2<usize>| (0.5f32, 0.25f32, 1.0f32)),
        );
        layer.attributes.other.insert(
            Text::from("ppm:seed"),
            AttributeValue::Text(Text::from("42")),
        );
        layer
            .attributes
            .other
            .insert(Text::from("ppm:radius"), AttributeValue::F32(0.03));
        Image::from_layer(layer).write().to_file(&path).unwrap();
        let text = report(&path, &std::fs::read(&path).unwrap()).unwrap();
        for line in [
            "size: 3x2",
            "channels: B (float), G (float), R (float)",
            "  ppm:seed (string) = \"42\"",
            "  ppm:radius (float) = 0.03",
            "  name (string) = \"rgb\"",
            "  dataWindow (box2i) = (0, 0, 2, 1)",
        ] {
            assert!(
                text.lines().any(|l| l == line.trim_end()),
                "no `{line}` in:\n{text}"
            );
        }
        let err = report(&path, b"P6 not an exr").unwrap_err();
        assert!(
            format!("{err:#}").contains("not an OpenEXR file"),
            "{err:#}"
        );
        let truncated = &std::fs::read(&path).unwrap()[..40];
        assert!(report(&path, truncated).is_err());
    }
}
