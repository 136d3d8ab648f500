//! An angle field of scene format v1: a number of degrees (`cone_angle: 30`), or
//! `{ radians: x }` for a value that must be exact in radians (`ppm convert` writes it when
//! no `f32` number of degrees converts to the angle the scene holds: multiplying by pi / 180
//! in single precision cannot reach every `f32`).

use crate::values::{Num, Rule};
use serde::de::{value::MapAccessDeserializer, Deserializer, MapAccess, Visitor};
use serde::Deserialize;
use std::fmt;
use std::marker::PhantomData;

/// An angle, as degrees and as the radians the scene uses; `R` checks whichever was written.
pub struct Angle<R> {
    pub degrees: f32,
    pub radians: f32,
    rule: PhantomData<R>,
}

impl<R> Angle<R> {
    fn from_degrees(degrees: f32) -> Self {
        Angle {
            degrees,
            radians: degrees.to_radians(),
            rule: PhantomData,
        }
    }
}

/// `{ radians: x }`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields, bound(deserialize = "R: Rule"))]
struct InRadians<R: Rule> {
    radians: Num<R>,
}

impl<'de, R: Rule> Deserialize<'de> for Angle<R> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V<R>(PhantomData<R>);
        impl<'de, R: Rule> Visitor<'de> for V<R> {
            type Value = Angle<R>;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                write!(f, "{} (degrees), or {{ radians: x }}", R::WHAT)
            }
            fn visit_f64<E: serde::de::Error>(self, x: f64) -> Result<Angle<R>, E> {
                Num::<R>::check(x).map(|n| Angle::from_degrees(n.0))
            }
            fn visit_i64<E: serde::de::Error>(self, x: i64) -> Result<Angle<R>, E> {
                self.visit_f64(x as f64)
            }
            fn visit_u64<E: serde::de::Error>(self, x: u64) -> Result<Angle<R>, E> {
                self.visit_f64(x as f64)
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<Angle<R>, A::Error> {
                let r = InRadians::<R>::deserialize(MapAccessDeserializer::new(map))?;
                Ok(Angle {
                    degrees: r.radians.0.to_degrees(),
                    radians: r.radians.0,
                    rule: PhantomData,
                })
            }
        }
        d.deserialize_any(V(PhantomData))
    }
}
