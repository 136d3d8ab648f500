//! The serde schema of scene format v1 (see `docs/scene-format.md`).
//!
//! Materials and objects are flat structs with a `type` tag and every field optional, rather
//! than internally tagged enums: serde buffers tagged enums and loses the field path and line
//! of errors inside them. Which fields a type takes is checked afterwards in `build.rs`.

use crate::ior::Ior;
use crate::texture_desc::{Colour, RoughnessValue};
use crate::values::{
    Alpha, Count, Depth, FieldOfView, Finite, GatherRadius, NonNegative, Num, PixelWindow, Point,
    Positive, Resolution, Triple,
};
use ppm_core::integrator::Algorithm;
use serde::de::{self, DeserializeSeed, Deserializer, MapAccess, Visitor};
use serde::Deserialize;
use std::collections::HashSet;
use std::fmt;

/// A whole scene file.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    pub camera: CameraDesc,
    pub resolution: Option<Resolution>,
    pub materials: Option<Materials>,
    pub objects: Option<Vec<ObjectDesc>>,
    pub lights: Option<Vec<LightDesc>>,
    pub render: Option<RenderDesc>,
}

/// `camera:` a pinhole or thin-lens camera.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraDesc {
    pub position: Point,
    pub look_at: Point,
    pub up: Point,
    /// Field of view in degrees along `fov_axis`; either this or `focal_length`.
    pub fov: Option<Num<FieldOfView>>,
    /// The axis `fov` spans (default `y`).
    pub fov_axis: Option<crate::fov::FovAxis>,
    /// Focal length in mm on 36 x 24 mm film (the diagonal field of view).
    pub focal_length: Option<Num<Positive>>,
    /// Radius of the thin lens's aperture (default 0, a pinhole).
    pub aperture_radius: Option<Num<NonNegative>>,
    /// Distance to the plane in focus (default: from `position` to `look_at`).
    pub focus_distance: Option<Num<Positive>>,
}

/// `materials:` name -> material, in file order; a repeated name is an error.
pub struct Materials(pub Vec<(String, MaterialDesc)>);

/// The material types.
#[derive(Deserialize, Clone, Copy, Debug, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum MaterialType {
    Diffuse,
    Mirror,
    Glass,
    Phong,
    Conductor,
    RoughConductor,
    Dielectric,
    RoughDielectric,
    ThinDielectric,
    Plastic,
    RoughPlastic,
    TwoSided,
}

/// One material; which fields apply depends on `type`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialDesc {
    #[serde(rename = "type")]
    pub kind: MaterialType,
    pub color: Option<Colour>,
    pub emission: Option<Triple<NonNegative>>,
    pub ior: Option<Num<Positive>>,
    pub diffuse: Option<Colour>,
    pub specular: Option<Colour>,
    pub exponent: Option<Num<NonNegative>>,
    // The Mitsuba-style materials (conductor ... twosided), with Mitsuba's parameter names.
    pub alpha: Option<RoughnessValue>,
    pub alpha_u: Option<Num<NonNegative>>,
    pub alpha_v: Option<Num<NonNegative>>,
    pub distribution: Option<String>,
    pub int_ior: Option<Ior>,
    pub ext_ior: Option<Ior>,
    pub eta: Option<Triple<NonNegative>>,
    pub k: Option<Triple<NonNegative>>,
    pub material: Option<String>,
    pub specular_reflectance: Option<Colour>,
    pub specular_transmittance: Option<Colour>,
    pub diffuse_reflectance: Option<Colour>,
    /// The material a `twosided` shows on both sides.
    pub bsdf: Option<Box<MaterialDesc>>,
    /// Absorption coefficient sigma_a (1 / scene unit, per channel) of the medium inside a
    /// `glass`, `dielectric` or `roughdielectric` (on the side opposite the normal).
    pub absorption: Option<Triple<NonNegative>>,
    /// sigma_a of the medium outside a `dielectric` or `roughdielectric` (the side of the
    /// normal: the glass around water), as `ext_ior` names its index.
    pub ext_absorption: Option<Triple<NonNegative>>,
}

/// The object types.
#[derive(Deserialize, Clone, Copy, Debug, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum ObjectType {
    Mesh,
    Sphere,
    Quad,
}

/// One object; which fields apply depends on `type`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObjectDesc {
    #[serde(rename = "type")]
    pub kind: ObjectType,
    pub material: Option<String>,
    pub file: Option<String>,
    pub center: Option<Point>,
    pub radius: Option<Num<Positive>>,
    pub inward: Option<bool>,
    pub corner: Option<Point>,
    pub edge_u: Option<Point>,
    pub edge_v: Option<Point>,
    /// Steps placing the object, applied in order (any type).
    pub transform: Option<Vec<crate::object_transform::TransformStep>>,
    /// Placements of a mesh, each by its own transform after the object's: the mesh is
    /// stored once however many there are (`mesh` only).
    pub instances: Option<Vec<InstanceDesc>>,
}

/// One placement in an object's `instances:` list.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InstanceDesc {
    /// Steps placing this copy, applied after the object's `transform` (none: the identity).
    pub transform: Option<Vec<crate::object_transform::TransformStep>>,
}

/// The light types (lights without geometry).
#[derive(Deserialize, Clone, Copy, Debug, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum LightType {
    Point,
    Spot,
    Directional,
    Environment,
}

/// One light without geometry; which fields apply, and which are required, depends on
/// `type` (checked in `build.rs`).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LightDesc {
    #[serde(rename = "type")]
    pub kind: LightType,
    /// Where a point or spot light is.
    pub position: Option<Point>,
    /// Radiant intensity in W/sr per channel (a spot light's on its axis).
    pub intensity: Option<Triple<NonNegative>>,
    /// A directional light's irradiance in W/m^2 per channel (on a surface facing it).
    pub irradiance: Option<Triple<NonNegative>>,
    /// A spot light's axis, as a direction or as a point it aims at; the direction a
    /// directional light travels (`direction` only).
    pub direction: Option<Point>,
    pub look_at: Option<Point>,
    /// A spot light's cone angle and falloff start, degrees from the axis (or
    /// `{ radians: x }`).
    pub cone_angle: Option<crate::angle::Angle<Positive>>,
    pub falloff_start: Option<crate::angle::Angle<NonNegative>>,
    /// An environment light's constant radiance, W/(m^2 sr) per channel.
    pub color: Option<Triple<NonNegative>>,
    /// An environment light's lat-long radiance map (EXR, HDR or PNG), relative to the scene
    /// file; its texels are radiance in W/(m^2 sr).
    pub file: Option<String>,
    /// Multiplies an environment light's radiance (default 1).
    pub scale: Option<Num<NonNegative>>,
    /// Rotates an environment light's map: `angle` degrees about `axis` (right-handed).
    pub rotate: Option<RotateDesc>,
    /// Turns an environment light's map by this 3 x 3 rotation, 9 numbers row by row
    /// (instead of `rotate`; `ppm convert` writes it for a Mitsuba `to_world`).
    pub to_world: Option<Vec<Num<Finite>>>,
    /// How an environment light's `file` maps onto the sphere (default `latlong`).
    pub mapping: Option<MapMapping>,
    /// Steps placing the light, as an object's `transform`: a point or spot light's position
    /// (default the origin) by the matrix, a spot or directional light's direction by its
    /// linear part; an environment's map turned by it (a rotation only), after `rotate`.
    pub transform: Option<Vec<crate::object_transform::TransformStep>>,
}

/// The parameterisation of an environment map's image: Mitsuba's latitude-longitude
/// (`envmap.rs` in ppm-core) or pbrt-v4's equal-area octahedral square (`equal_area.rs`).
#[derive(Deserialize, Clone, Copy, Debug, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum MapMapping {
    Latlong,
    EqualArea,
}

/// A rotation by `angle` degrees about `axis` (right-handed: counter-clockwise looking down
/// the axis), Mitsuba's `<rotate>`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RotateDesc {
    pub axis: Point,
    pub angle: Num<Finite>,
}

/// `render:` defaults the command line may override.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RenderDesc {
    pub max_depth: Option<Depth>,
    pub photons: Option<Count>,
    pub radius: Option<GatherRadius>,
    pub alpha: Option<Num<Alpha>>,
    pub algorithm: Option<AlgorithmName>,
    /// The window of pixels to render, `[x0, x1, y0, y1]` (default: the whole image).
    pub pixel_bounds: Option<PixelWindow>,
}

/// `render.algorithm`: the integrator, named as on the command line (`-a`): a name or an
/// alias of [`Algorithm::TABLE`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AlgorithmName(pub Algorithm);

impl<'de> Deserialize<'de> for AlgorithmName {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        // The error must come from a visitor to carry the value's line and field.
        d.deserialize_str(AlgorithmVisitor)
    }
}

/// Parses an algorithm's name; an unknown one is reported as serde reports an unknown
/// variant, with the names to choose from.
struct AlgorithmVisitor;

impl Visitor<'_> for AlgorithmVisitor {
    type Value = AlgorithmName;
    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "one of {}", Algorithm::NAMES.join(", "))
    }
    fn visit_str<E: de::Error>(self, name: &str) -> Result<AlgorithmName, E> {
        name.parse()
            .map(AlgorithmName)
            .map_err(|_| E::unknown_variant(name, &Algorithm::NAMES))
    }
}

/// A seed that rejects the definition of a material name seen before.
struct Duplicate(String);

impl<'de> DeserializeSeed<'de> for Duplicate {
    type Value = ();
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        // The error must come from a visitor to carry the value's line.
        d.deserialize_any(self)
    }
}

impl<'de> Visitor<'de> for Duplicate {
    type Value = ();
    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "no second definition of material `{}`", self.0)
    }
    fn visit_map<A: MapAccess<'de>>(self, _: A) -> Result<(), A::Error> {
        Err(de::Error::custom(format!(
            "material `{}` is defined twice",
            self.0
        )))
    }
}

impl<'de> Deserialize<'de> for Materials {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Materials;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a map from material names to materials")
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Materials, A::Error> {
                let mut out: Vec<(String, MaterialDesc)> = Vec::new();
                let mut seen: HashSet<String> = HashSet::new();
                while let Some(name) = map.next_key::<String>()? {
                    if !seen.insert(name.clone()) {
                        // Fail inside the value, so the error points at the second definition.
                        return map
                            .next_value_seed(Duplicate(name))
                            .map(|_| Materials(Vec::new()));
                    }
                    let m = map.next_value()?;
                    out.push((name, m));
                }
                Ok(Materials(out))
            }
        }
        d.deserialize_map(V)
    }
}
