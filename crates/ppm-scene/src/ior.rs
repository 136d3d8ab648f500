//! Indices of refraction as the scene file writes them: a number, or a medium's name from
//! Mitsuba 3's table (`int_ior: water`, `ext_ior: air`).

use crate::mitsuba::ior::NAMED_IOR;
use serde::de::{self, Deserialize, Deserializer, Visitor};
use std::fmt;

/// The index of a named medium of Mitsuba 3's table ([`NAMED_IOR`]), case-insensitive.
pub fn named_ior(name: &str) -> Option<f32> {
    NAMED_IOR
        .iter()
        .find(|(n, _)| n.eq_ignore_ascii_case(name))
        .map(|&(_, v)| v as f32)
}

/// An index of refraction: a finite number >= 1, or a name of [`NAMED_IOR`].
#[derive(Clone, Copy, Debug)]
pub struct Ior(pub f32);

impl<'de> Deserialize<'de> for Ior {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl V {
            fn check<E: de::Error>(x: f64) -> Result<Ior, E> {
                let y = x as f32;
                if y.is_finite() && y >= 1.0 {
                    Ok(Ior(y))
                } else {
                    Err(E::custom(format!(
                        "{x} is out of range, expected an index of refraction >= 1 or a medium's name"
                    )))
                }
            }
        }
        impl Visitor<'_> for V {
            type Value = Ior;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("an index of refraction >= 1 or a medium's name (e.g. `water`)")
            }
            fn visit_f64<E: de::Error>(self, x: f64) -> Result<Ior, E> {
                Self::check(x)
            }
            fn visit_i64<E: de::Error>(self, x: i64) -> Result<Ior, E> {
                Self::check(x as f64)
            }
            fn visit_u64<E: de::Error>(self, x: u64) -> Result<Ior, E> {
                Self::check(x as f64)
            }
            fn visit_str<E: de::Error>(self, s: &str) -> Result<Ior, E> {
                named_ior(s).map(Ior).ok_or_else(|| {
                    let names: Vec<&str> = NAMED_IOR.iter().map(|(n, _)| *n).collect();
                    E::custom(format!("unknown medium `{s}`; known: {}", names.join(", ")))
                })
            }
        }
        d.deserialize_any(V)
    }
}
