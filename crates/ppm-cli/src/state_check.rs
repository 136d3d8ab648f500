//! The integrity of a render-state EXR: a checksum over everything the state is made of, and
//! checks of the header fields against each other and against the data, so that a damaged or
//! edited file is refused (naming the file and the field) instead of being merged or resumed
//! into a different image.
//!
//! The checksum, attribute `ppm.stateHash` (16 hex digits), is FNV-1a 64 (Fowler, Noll, Vo)
//! over a canonical byte string: a version tag, the image size, every `ppm.*` attribute but
//! the checksum itself (name and value as stored, in name order; a `string` as its text, a
//! typed value marked by its type, see `state_attributes`), then every channel in
//! name order (its name, its sample type, its samples' bits, little-endian). Each FNV-1a step
//! h = (h xor byte) * p is a bijection of h for a given byte, so a change of any one byte of
//! the data, or of any attribute, always changes the checksum; the checksum covers R, G, B,
//! the exact sums and the integrator's pixel state alike. Like the scene fingerprint it
//! guards against accidents (a flipped bit, a truncated copy, an edited header), not a
//! forger. Files written before the checksum load with a warning.

use crate::state_attributes;
use anyhow::{bail, Result};
use exr::prelude::{AttributeValue, FlatSamples};
use std::collections::BTreeMap;

/// The attribute holding the checksum.
pub const STATE_HASH: &str = "ppm.stateHash";

const FNV_OFFSET: u64 = 0xcbf2_9ce4_8422_2325;
const FNV_PRIME: u64 = 0x0000_0100_0000_01b3;
/// Opens the canonical string: a new layout of it takes a new tag.
const TAG: &[u8] = b"ppm state hash 1\0";

/// FNV-1a 64 over the bytes written to it.
struct Fnv(u64);

impl Fnv {
    fn bytes(&mut self, bytes: &[u8]) {
        for b in bytes {
            self.0 = (self.0 ^ *b as u64).wrapping_mul(FNV_PRIME);
        }
    }

    /// A string, ended by a NUL (so that ("ab", "c") and ("a", "bc") differ).
    fn text(&mut self, s: &str) {
        self.bytes(s.as_bytes());
        self.bytes(&[0]);
    }
}

/// The checksum of a state of `width` x `height` pixels with the header `attributes` (those
/// not starting with `ppm.`, and the checksum itself, are left out) and the `channels` (name
/// and samples, in any order).
pub fn state_hash<'a>(
    (width, height): (u32, u32),
    attributes: impl IntoIterator<Item = (&'a str, &'a AttributeValue)>,
    channels: impl IntoIterator<Item = (&'a str, &'a FlatSamples)>,
) -> u64 {
    let mut h = Fnv(FNV_OFFSET);
    h.bytes(TAG);
    h.bytes(&width.to_le_bytes());
    h.bytes(&height.to_le_bytes());
    let attributes: BTreeMap<&str, &AttributeValue> = attributes
        .into_iter()
        .filter(|(name, _)| name.starts_with("ppm.") && *name != STATE_HASH)
        .collect();
    for (name, value) in attributes {
        h.text(name);
        // A string as its text (as before types), a typed value after 0xff (never in
        // UTF-8 text) and its type name.
        let (kind, bytes) = state_attributes::hash_value(value);
        if let Some(kind) = kind {
            h.bytes(&[0xff]);
            h.text(kind);
        }
        h.bytes(&bytes);
        h.bytes(&[0]);
    }
    let channels: BTreeMap<&str, &FlatSamples> = channels.into_iter().collect();
    for (name, samples) in channels {
        h.text(name);
        match samples {
            FlatSamples::F16(v) => {
                h.text("f16");
                v.iter().for_each(|x| h.bytes(&x.to_bits().to_le_bytes()));
            }
            FlatSamples::F32(v) => {
                h.text("f32");
                v.iter().for_each(|x| h.bytes(&x.to_bits().to_le_bytes()));
            }
            FlatSamples::U32(v) => {
                h.text("u32");
                v.iter().for_each(|x| h.bytes(&x.to_le_bytes()));
            }
        }
    }
    h.0
}

/// The checksum as the attribute holds it.
pub fn format_hash(hash: u64) -> String {
    format!("{hash:016x}")
}

/// What [`verify_hash`] found.
#[derive(Debug, PartialEq)]
pub enum HashCheck {
    /// The checksum is there and matches.
    Verified,
    /// No checksum (a file written before it existed).
    Absent,
}

/// Compares the checksum attribute (if any) with `computed`; an error if it is malformed or
/// does not match.
pub fn verify_hash(stored: Option<&str>, computed: u64) -> Result<HashCheck> {
    let Some(stored) = stored else {
        return Ok(HashCheck::Absent);
    };
    let Ok(value) = u64::from_str_radix(stored.trim(), 16) else {
        bail!("attribute {STATE_HASH} is {stored:?}, not a 64-bit hexadecimal checksum");
    };
    if value != computed {
        bail!(
            "the file's data or header does not match its checksum ({STATE_HASH} {stored}, \
             contents hash to {}): it was changed or damaged after ppm wrote it",
            format_hash(computed)
        );
    }
    Ok(HashCheck::Verified)
}

/// The header fields of a state, as read.
pub struct Header {
    pub width: u32,
    pub height: u32,
    pub first_iteration: u64,
    pub iterations: u64,
    pub rejected: u64,
    pub first_rejected: Option<(u64, u32)>,
}

/// Checks the header fields against each other: the state holds at least one iteration, its
/// range first .. first + iterations fits in 64 bits, the rejected estimates are at most one
/// per pixel and iteration, and the first rejected one lies in the range and the image.
/// Errors name the field.
pub fn check_header(h: &Header) -> Result<()> {
    if h.width == 0 || h.height == 0 {
        bail!(
            "the image is {}x{} pixels: it holds no pixel",
            h.width,
            h.height
        );
    }
    if h.iterations == 0 {
        bail!("attribute ppm.iterations is 0: a saved render holds at least one iteration");
    }
    let Some(end) = h.first_iteration.checked_add(h.iterations) else {
        bail!(
            "attributes ppm.firstIteration ({}) and ppm.iterations ({}): the range of \
             iterations ends past 2^64",
            h.first_iteration,
            h.iterations
        );
    };
    let pixels = h.width as u64 * h.height as u64;
    let most = h.iterations.saturating_mul(pixels);
    if h.rejected > most {
        bail!(
            "attribute ppm.rejected is {}, more than one per pixel and iteration ({most})",
            h.rejected
        );
    }
    match h.first_rejected {
        None if h.rejected > 0 => {
            bail!(
                "attribute ppm.firstRejected is missing although ppm.rejected is {}",
                h.rejected
            )
        }
        Some(_) if h.rejected == 0 => {
            bail!("attribute ppm.firstRejected is present although ppm.rejected is 0")
        }
        Some((iteration, _)) if !(h.first_iteration..end).contains(&iteration) => bail!(
            "attribute ppm.firstRejected names iteration {iteration}, outside the file's \
             iterations {}..{end}",
            h.first_iteration
        ),
        Some((_, pixel)) if pixel as u64 >= pixels => bail!(
            "attribute ppm.firstRejected names pixel {pixel}, outside the {}x{} image",
            h.width,
            h.height
        ),
        _ => Ok(()),
    }
}

/// Checks that the sum channels are exactly words 0 .. `words` of R, G and B: a word past
/// `ppm.sumWords` would be dropped on reading, changing the image.
pub fn check_sum_channels<'a>(
    words: usize,
    channel_names: impl IntoIterator<Item = &'a str>,
    prefix: &str,
) -> Result<()> {
    for name in channel_names {
        let Some(rest) = name.strip_prefix(prefix) else {
            continue;
        };
        let word = rest
            .split_once('.')
            .filter(|(c, _)| ["R", "G", "B"].contains(c))
            .and_then(|(_, w)| w.parse::<usize>().ok());
        match word {
            Some(w) if w < words => {}
            Some(w) => bail!(
                "channel {name} is word {w} of a sum, but attribute ppm.sumWords says the sums \
                 have {words} word(s)"
            ),
            None => bail!("channel {name} is not a sum word (ppm.sum.<R|G|B>.<word>)"),
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hash_of(attrs: &[(&str, &str)], samples: &FlatSamples) -> u64 {
        let values: Vec<(&str, AttributeValue)> = attrs
            .iter()
            .map(|(k, v)| (*k, AttributeValue::Text(exr::prelude::Text::from(*v))))
            .collect();
        state_hash(
            (2, 1),
            values.iter().map(|(k, v)| (*k, v)),
            [("R", samples)],
        )
    }

    /// A typed value hashes apart from the same text, and from another type of it.
    #[test]
    fn typed_attributes_hash_apart_from_their_text() {
        let samples = FlatSamples::U32(vec![1, 2]);
        let hash =
            |v: AttributeValue| state_hash((2, 1), [("ppm.iterations", &v)], [("R", &samples)]);
        let text = hash(AttributeValue::Text(exr::prelude::Text::from("3")));
        let int = hash(AttributeValue::I32(3));
        let float = hash(AttributeValue::F32(f32::from_bits(3)));
        assert!(text != int && int != float && text != float);
        assert_eq!(text, hash_of(&[("ppm.iterations", "3")], &samples));
        assert_ne!(int, hash(AttributeValue::I32(4)));
    }

    #[test]
    fn every_bit_of_the_data_and_header_changes_the_checksum() {
        let attrs = [("ppm.iterations", "3"), ("ppm.seed", "0")];
        let base = FlatSamples::U32(vec![0x1234_5678, 0x9abc_def0]);
        let h0 = hash_of(&attrs, &base);
        for word in 0..2 {
            for bit in 0..32 {
                let mut v = vec![0x1234_5678u32, 0x9abc_def0];
                v[word] ^= 1 << bit;
                assert_ne!(hash_of(&attrs, &FlatSamples::U32(v)), h0, "{word}:{bit}");
            }
        }
        assert_ne!(
            hash_of(&[("ppm.iterations", "4"), ("ppm.seed", "0")], &base),
            h0
        );
        // The checksum itself and attributes that are not ppm's do not count.
        let with = [
            ("ppm.iterations", "3"),
            ("ppm.seed", "0"),
            (STATE_HASH, "x"),
            ("owner", "y"),
        ];
        assert_eq!(hash_of(&with, &base), h0);
        // The sample type counts: the same bits as f32 hash differently.
        let f = FlatSamples::F32(vec![
            f32::from_bits(0x1234_5678),
            f32::from_bits(0x9abc_def0),
        ]);
        assert_ne!(hash_of(&attrs, &f), h0);
        assert_eq!(
            verify_hash(Some(&format_hash(h0)), h0).unwrap(),
            HashCheck::Verified
        );
        assert_eq!(verify_hash(None, h0).unwrap(), HashCheck::Absent);
        assert!(verify_hash(Some(&format_hash(h0 ^ 1)), h0).is_err());
        assert!(verify_hash(Some("zz"), h0).is_err());
    }

    #[test]
    fn inconsistent_header_fields_are_refused_by_name() {
        let ok = Header {
            width: 4,
            height: 2,
            first_iteration: 10,
            iterations: 5,
            rejected: 1,
            first_rejected: Some((12, 7)),
        };
        check_header(&ok).unwrap();
        let refused = |h: Header, field: &str| {
            let e = check_header(&h).unwrap_err().to_string();
            assert!(e.contains(field), "{e}");
        };
        refused(
            Header {
                iterations: 0,
                ..ok
            },
            "ppm.iterations",
        );
        refused(
            Header {
                iterations: u64::MAX,
                ..ok
            },
            "ppm.iterations",
        );
        refused(Header { rejected: 41, ..ok }, "ppm.rejected");
        refused(
            Header {
                first_rejected: None,
                ..ok
            },
            "ppm.firstRejected",
        );
        refused(
            Header {
                first_rejected: Some((15, 0)),
                ..ok
            },
            "ppm.firstRejected",
        );
        refused(
            Header {
                first_rejected: Some((12, 8)),
                ..ok
            },
            "ppm.firstRejected",
        );
        refused(Header { rejected: 0, ..ok }, "ppm.firstRejected");
        let names = ["R", "ppm.sum.R.0", "ppm.sum.G.1", "ppm.pixel.n"];
        check_sum_channels(2, names, "ppm.sum.").unwrap();
        let e = check_sum_channels(1, names, "ppm.sum.")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("ppm.sum.G.1") && e.contains("ppm.sumWords"),
            "{e}"
        );
        assert!(check_sum_channels(2, ["ppm.sum.X.0"], "ppm.sum.").is_err());
    }
}
