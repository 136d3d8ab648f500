//! The `ppm.*` header attributes of a render's EXR, stored with their EXR types: counts as
//! `int`, the blending exponent as `float`, the render time as `double`, the rest (names,
//! hashes, ranges, `auto`) as `string`.
//!
//! [`crate::provenance::Provenance`] keeps every value as its text; this module decides how
//! that text is stored and gives it back. A value is stored typed only when the type gives
//! back the same text: an integer that fits in i32 (every iteration count and depth of a
//! practical render; an EXR `int` is 32-bit), an f32 or f64 whose shortest form is the text.
//! Otherwise (a seed or photon count past 2^31 - 1) it stays a `string`, the same decimal
//! text: a reader takes either type for these attributes (OpenEXR has no 64-bit integer
//! attribute, and a pair of ints would be a format of our own). Files written before the
//! types hold every attribute as a `string`; they read the same way.
//!
//! The state checksum covers each attribute as stored ([`hash_value`]): a `string` exactly as
//! before (so the checksums of older files still verify), a typed one marked by a byte that
//! text never holds (0xff is not UTF-8) and its type, then its little-endian bytes.

use exr::prelude::{AttributeValue, Text};

/// Attributes stored as `int` when they fit.
const INTEGERS: &[&str] = &[
    "ppm.state",
    "ppm.seed",
    "ppm.maxDepth",
    "ppm.rrDepth",
    "ppm.photons",
    "ppm.firstIteration",
    "ppm.iterations",
    "ppm.rejected",
    "ppm.sumWords",
];
/// Attributes stored as `float`.
const FLOATS: &[&str] = &["ppm.alpha"];
/// Attributes stored as `double`.
const DOUBLES: &[&str] = &["ppm.renderSeconds"];

/// The EXR value of attribute `name` whose text is `text`.
pub fn to_exr(name: &str, text: &str) -> AttributeValue {
    if INTEGERS.contains(&name) {
        if let Some(v) = text.parse::<i32>().ok().filter(|v| v.to_string() == text) {
            return AttributeValue::I32(v);
        }
    } else if FLOATS.contains(&name) {
        if let Some(v) = text.parse::<f32>().ok().filter(|v| v.to_string() == text) {
            return AttributeValue::F32(v);
        }
    } else if DOUBLES.contains(&name) {
        if let Some(v) = text.parse::<f64>().ok().filter(|v| v.to_string() == text) {
            return AttributeValue::F64(v);
        }
    }
    AttributeValue::Text(Text::from(text))
}

/// The text of an attribute value as [`to_exr`] stored it; `None` for a type ppm does not
/// write for its own attributes (a matrix, a list).
pub fn to_text(value: &AttributeValue) -> Option<String> {
    match value {
        AttributeValue::Text(t) => Some(t.to_string()),
        AttributeValue::I32(v) => Some(v.to_string()),
        AttributeValue::F32(v) => Some(v.to_string()),
        AttributeValue::F64(v) => Some(v.to_string()),
        _ => None,
    }
}

/// What the state checksum takes of a value: its type marker (none for `string`) and bytes.
pub fn hash_value(value: &AttributeValue) -> (Option<&'static str>, Vec<u8>) {
    match value {
        AttributeValue::Text(t) => (None, t.to_string().into_bytes()),
        AttributeValue::I32(v) => (Some("int"), v.to_le_bytes().to_vec()),
        AttributeValue::F32(v) => (Some("float"), v.to_bits().to_le_bytes().to_vec()),
        AttributeValue::F64(v) => (Some("double"), v.to_bits().to_le_bytes().to_vec()),
        // Never written by ppm: hashed by its kind alone, so the checksum fails.
        _ => (Some("other"), Vec::new()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_are_typed_only_when_the_type_gives_back_the_text() {
        let cases = [
            ("ppm.iterations", "12", AttributeValue::I32(12)),
            ("ppm.seed", "2147483647", AttributeValue::I32(i32::MAX)),
            (
                "ppm.seed",
                "2147483648",
                AttributeValue::Text(Text::from("2147483648")),
            ),
            ("ppm.alpha", "0.7", AttributeValue::F32(0.7)),
            ("ppm.renderSeconds", "1.234", AttributeValue::F64(1.234)),
            (
                "ppm.radius",
                "auto",
                AttributeValue::Text(Text::from("auto")),
            ),
            (
                "ppm.photons",
                "007",
                AttributeValue::Text(Text::from("007")),
            ),
        ];
        for (name, text, expected) in cases {
            let value = to_exr(name, text);
            assert_eq!(value, expected, "{name} = {text}");
            assert_eq!(to_text(&value).as_deref(), Some(text), "{name}");
        }
    }
}
