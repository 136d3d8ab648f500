//! Checked numbers, RGB triples and counts for the YAML schema.
//!
//! The range checks run inside the serde visitors, while the YAML deserializer still knows
//! where the value is: a bad value is reported with its field path, line and column
//! (`materials.white.color: component 1 is -0.5, expected a reflectance in [0, 1]`).

use glam::{DVec3, Vec3};
use ppm_core::camera::MAX_RESOLUTION;
use ppm_core::integrator::MAX_DEPTH;
use serde::de::{self, Deserialize, Deserializer, IgnoredAny, SeqAccess, Visitor};
use std::fmt;
use std::marker::PhantomData;

/// A range a number must lie in.
pub trait Rule {
    /// What a valid value is, for messages ("a finite number > 0").
    const WHAT: &'static str;
    /// True if `x` is valid.
    fn ok(x: f32) -> bool;
}

/// Any finite number (coordinates, directions).
pub struct Finite;
/// A finite number >= 0 (emitted radiance, intensity, Phong exponent).
pub struct NonNegative;
/// A finite number > 0 (radius, index of refraction).
pub struct Positive;
/// A reflectance in [0, 1] (albedo, mirror and glass tint).
pub struct Reflectance;
/// A vertical field of view in (0, 180) degrees.
pub struct FieldOfView;
/// The radius reduction parameter alpha of PPM, in (0, 1].
pub struct Alpha;

impl Rule for Finite {
    const WHAT: &'static str = "a finite number";
    fn ok(x: f32) -> bool {
        x.is_finite()
    }
}
impl Rule for NonNegative {
    const WHAT: &'static str = "a finite number >= 0";
    fn ok(x: f32) -> bool {
        x.is_finite() && x >= 0.0
    }
}
impl Rule for Positive {
    const WHAT: &'static str = "a finite number > 0";
    fn ok(x: f32) -> bool {
        x.is_finite() && x > 0.0
    }
}
impl Rule for Reflectance {
    const WHAT: &'static str = "a reflectance in [0, 1]";
    fn ok(x: f32) -> bool {
        (0.0..=1.0).contains(&x)
    }
}
impl Rule for FieldOfView {
    const WHAT: &'static str = "an angle in (0, 180) degrees";
    fn ok(x: f32) -> bool {
        x > 0.0 && x < 180.0
    }
}
impl Rule for Alpha {
    const WHAT: &'static str = "a number in (0, 1]";
    fn ok(x: f32) -> bool {
        x > 0.0 && x <= 1.0
    }
}

/// A number checked against rule `R`.
pub struct Num<R>(pub f32, PhantomData<R>);

/// Three numbers `[x, y, z]` (or `[r, g, b]`), each checked against rule `R`, kept as
/// written (`f64`): points are made camera-relative before they are rounded to `f32`
/// ([`Triple::relative_to`]), everything else is rounded as it is ([`Triple::value`]).
pub struct Triple<R>(pub DVec3, PhantomData<R>);

impl<R> Triple<R> {
    /// The three numbers rounded to `f32`.
    pub fn value(&self) -> Vec3 {
        self.0.as_vec3()
    }

    /// The point minus `origin`, subtracted in double precision and then rounded: a scene
    /// far from the world origin keeps the detail near its camera (1e6 + 0.001 is 1e6 in
    /// f32, but 0.001 after the subtraction).
    pub fn relative_to(&self, origin: DVec3) -> Vec3 {
        (self.0 - origin).as_vec3()
    }
}

/// A point or direction.
pub type Point = Triple<Finite>;

/// A positive whole number (photons per iteration, path depth).
pub struct Count(pub u32);

/// A path depth in bounces: a whole number >= 0 (0: only emission seen directly).
pub struct Depth(pub u32);

/// An image size `[width, height]`, each side in 1..=MAX_RESOLUTION.
pub struct Resolution(pub u32, pub u32);

/// `render.pixel_bounds`: `[x0, x1, y0, y1]`, whole numbers of pixels, the half-open window
/// x0..x1 by y0..y1 from the image's top-left corner (checked against the resolution by the
/// scene's build).
pub struct PixelWindow(pub [u32; 4]);

impl<R> fmt::Debug for Num<R> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.0.fmt(f)
    }
}
impl<R> fmt::Debug for Triple<R> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.value().fmt(f)
    }
}

impl<'de, R: Rule> Deserialize<'de> for Num<R> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_f64(NumVisitor::<R>(PhantomData))
    }
}

struct NumVisitor<R>(PhantomData<R>);

impl<R: Rule> Num<R> {
    /// `x` as a number if the rule accepts it, else the error saying what is expected.
    pub(crate) fn check<E: de::Error>(x: f64) -> Result<Num<R>, E> {
        NumVisitor::check(x)
    }
}

impl<R: Rule> NumVisitor<R> {
    fn check<E: de::Error>(x: f64) -> Result<Num<R>, E> {
        let y = x as f32;
        if R::ok(y) {
            Ok(Num(y, PhantomData))
        } else {
            Err(E::custom(format!(
                "{x} is out of range, expected {}",
                R::WHAT
            )))
        }
    }
}

impl<R: Rule> Visitor<'_> for NumVisitor<R> {
    type Value = Num<R>;
    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(R::WHAT)
    }
    fn visit_f64<E: de::Error>(self, x: f64) -> Result<Num<R>, E> {
        Self::check(x)
    }
    fn visit_i64<E: de::Error>(self, x: i64) -> Result<Num<R>, E> {
        Self::check(x as f64)
    }
    fn visit_u64<E: de::Error>(self, x: u64) -> Result<Num<R>, E> {
        Self::check(x as f64)
    }
}

/// The initial gather radius of `render:`: a number > 0 in scene units, `auto` or
/// `footprint` (each pixel's from its footprint), or `photons` (each pixel's from the
/// photons; the default).
pub struct GatherRadius(pub ppm_core::integrator::Radius);

impl<'de> Deserialize<'de> for GatherRadius {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl Visitor<'_> for V {
            type Value = GatherRadius;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                write!(f, "{} or `photons`, `footprint`, `auto`", Positive::WHAT)
            }
            fn visit_f64<E: de::Error>(self, x: f64) -> Result<GatherRadius, E> {
                NumVisitor::<Positive>::check(x)
                    .map(|n| GatherRadius(ppm_core::integrator::Radius::World(n.0)))
            }
            fn visit_i64<E: de::Error>(self, x: i64) -> Result<GatherRadius, E> {
                self.visit_f64(x as f64)
            }
            fn visit_u64<E: de::Error>(self, x: u64) -> Result<GatherRadius, E> {
                self.visit_f64(x as f64)
            }
            fn visit_str<E: de::Error>(self, s: &str) -> Result<GatherRadius, E> {
                use ppm_core::integrator::Radius;
                match s {
                    "photons" => Ok(GatherRadius(Radius::Photons)),
                    "auto" | "footprint" => Ok(GatherRadius(Radius::Auto)),
                    _ => Err(E::custom(format!(
                        "`{s}` is not a radius, expected {} or `photons`, `footprint`, `auto`",
                        Positive::WHAT
                    ))),
                }
            }
        }
        d.deserialize_any(V)
    }
}

impl<'de, R: Rule> Deserialize<'de> for Triple<R> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_seq(TripleVisitor::<R>(PhantomData))
    }
}

/// One component of a [`Triple`]: any YAML number, or an error that says "a number" (not
/// serde's "f64").
struct Number(f64);

impl<'de> Deserialize<'de> for Number {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct NumberVisitor;
        impl Visitor<'_> for NumberVisitor {
            type Value = Number;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a number")
            }
            fn visit_f64<E: de::Error>(self, x: f64) -> Result<Number, E> {
                Ok(Number(x))
            }
            fn visit_i64<E: de::Error>(self, x: i64) -> Result<Number, E> {
                Ok(Number(x as f64))
            }
            fn visit_u64<E: de::Error>(self, x: u64) -> Result<Number, E> {
                Ok(Number(x as f64))
            }
        }
        d.deserialize_f64(NumberVisitor)
    }
}

pub(crate) struct TripleVisitor<R>(pub(crate) PhantomData<R>);

impl<'de, R: Rule> Visitor<'de> for TripleVisitor<R> {
    type Value = Triple<R>;
    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "a list of three numbers, each {}", R::WHAT)
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Triple<R>, A::Error> {
        let mut v = [0.0f64; 3];
        for (i, vi) in v.iter_mut().enumerate() {
            let Number(x) = seq
                .next_element()?
                .ok_or_else(|| de::Error::invalid_length(i, &self))?;
            *vi = x;
            // The check is of the value the renderer sees, rounded to f32.
            if !R::ok(x as f32) {
                return Err(de::Error::custom(format!(
                    "component {i} is {x}, expected {}",
                    R::WHAT
                )));
            }
        }
        if seq.next_element::<IgnoredAny>()?.is_some() {
            return Err(de::Error::invalid_length(4, &self));
        }
        Ok(Triple(DVec3::from_array(v), PhantomData))
    }
}

/// A whole number in `min..=max` as YAML may write it: `200000`, or `2e5` (which YAML reads
/// as a float) as long as it is exactly whole. `what` says what is valid, for messages.
struct WholeVisitor {
    what: String,
    min: i64,
    max: i64,
}

impl WholeVisitor {
    fn check<E: de::Error>(&self, x: i128) -> Result<i64, E> {
        if (i128::from(self.min)..=i128::from(self.max)).contains(&x) {
            Ok(x as i64)
        } else {
            Err(E::custom(format!("{x} is out of range, expected {self}")))
        }
    }
}

impl fmt::Display for WholeVisitor {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.what)
    }
}

impl Visitor<'_> for WholeVisitor {
    type Value = i64;
    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{self}")
    }
    fn visit_u64<E: de::Error>(self, x: u64) -> Result<i64, E> {
        self.check(x.into())
    }
    fn visit_i64<E: de::Error>(self, x: i64) -> Result<i64, E> {
        self.check(x.into())
    }
    fn visit_f64<E: de::Error>(self, x: f64) -> Result<i64, E> {
        if !x.is_finite() || x.fract() != 0.0 {
            return Err(E::custom(format!(
                "{x} is not a whole number, expected {self}"
            )));
        }
        if x.abs() >= i64::MAX as f64 {
            return Err(E::custom(format!("{x:e} is out of range, expected {self}")));
        }
        self.check(x as i128)
    }
}

/// A whole number in `min..=u32::MAX`.
fn whole_u32<'de, D: Deserializer<'de>>(d: D, min: u32) -> Result<u32, D::Error> {
    let n = d.deserialize_any(WholeVisitor {
        what: format!("a whole number >= {min} (at most {})", u32::MAX),
        min: min.into(),
        max: u32::MAX.into(),
    })?;
    Ok(n as u32)
}

impl<'de> Deserialize<'de> for Count {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        whole_u32(d, 1).map(Count)
    }
}

impl<'de> Deserialize<'de> for Depth {
    /// Any whole number of bounces from 0 on: one above what a `u32` holds is kept as
    /// `u32::MAX`, which the scene's build then lowers to the supported maximum with a
    /// warning, as it does any depth above that maximum.
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let n = d.deserialize_any(WholeVisitor {
            what: format!("a whole number of bounces >= 0 (above {MAX_DEPTH} used as {MAX_DEPTH})"),
            min: 0,
            max: i64::MAX,
        })?;
        Ok(Depth(n.min(u32::MAX.into()) as u32))
    }
}

/// One side of [`Resolution`]: any whole number (the caller checks the range and names the
/// side).
struct Side(i64);

impl<'de> Deserialize<'de> for Side {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(WholeVisitor {
            what: format!("a whole number of pixels in 1..={MAX_RESOLUTION}"),
            min: i64::MIN,
            max: i64::MAX,
        })
        .map(Side)
    }
}

impl<'de> Deserialize<'de> for PixelWindow {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = PixelWindow;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                write!(
                    f,
                    "[x0, x1, y0, y1] in pixels, each in 0..={MAX_RESOLUTION}"
                )
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<PixelWindow, A::Error> {
                let mut edge = [0u32; 4];
                for (i, e) in edge.iter_mut().enumerate() {
                    let Side(x) = seq
                        .next_element()?
                        .ok_or_else(|| de::Error::invalid_length(i, &self))?;
                    if !(0..=i64::from(MAX_RESOLUTION)).contains(&x) {
                        let name = ["x0", "x1", "y0", "y1"][i];
                        return Err(de::Error::custom(format!(
                            "{name} {x} is out of range, expected 0..={MAX_RESOLUTION} pixels"
                        )));
                    }
                    *e = x as u32;
                }
                if seq.next_element::<IgnoredAny>()?.is_some() {
                    return Err(de::Error::invalid_length(5, &self));
                }
                Ok(PixelWindow(edge))
            }
        }
        d.deserialize_seq(V)
    }
}

impl<'de> Deserialize<'de> for Resolution {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Resolution;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                write!(f, "[width, height] in pixels, each in 1..={MAX_RESOLUTION}")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Resolution, A::Error> {
                let mut side = [0u32; 2];
                for (i, s) in side.iter_mut().enumerate() {
                    let Side(x) = seq
                        .next_element()?
                        .ok_or_else(|| de::Error::invalid_length(i, &self))?;
                    if !(1..=i64::from(MAX_RESOLUTION)).contains(&x) {
                        let name = ["width", "height"][i];
                        return Err(de::Error::custom(format!(
                            "{name} {x} is out of range, expected 1..={MAX_RESOLUTION} pixels"
                        )));
                    }
                    *s = x as u32;
                }
                if seq.next_element::<IgnoredAny>()?.is_some() {
                    return Err(de::Error::invalid_length(3, &self));
                }
                Ok(Resolution(side[0], side[1]))
            }
        }
        d.deserialize_seq(V)
    }
}
