//! Colours that may be textures in scene format v1: a material's colour field holds either
//! `[r, g, b]` or a texture description `{ texture: bitmap | checkerboard, ... }` (see
//! `docs/scene-format.md`), and [`textures`] loads a material's textures into the
//! (slot, texture) list that [`ppm_core::material::Material::textured`] takes.

use crate::image_file::read_rgb_image;
use crate::values::{Reflectance, Triple, TripleVisitor};
use crate::yaml::{MaterialDesc, MaterialType};
use crate::LoadError;
use glam::{Vec2, Vec3};
use ppm_core::texture::{
    texture_scalar, Bitmap, Checkerboard, ColourSlot, Filter, Texture, UvTransform, WrapMode,
};
use serde::de::{value::MapAccessDeserializer, Deserializer, MapAccess, SeqAccess, Visitor};
use serde::Deserialize;
use std::cell::OnceCell;
use std::fmt;
use std::marker::PhantomData;
use std::path::Path;

/// A colour field: a constant or a texture.
pub enum Colour {
    Value(Triple<Reflectance>),
    /// A texture and, once [`textures`] has loaded it, its mean (what [`Colour::value`]
    /// gives: the material's nominal colour).
    Texture(Box<TextureDesc>, OnceCell<Vec3>),
}

impl Colour {
    /// The constant, or the loaded texture's mean.
    pub fn value(&self) -> Vec3 {
        match self {
            Colour::Value(t) => t.value(),
            Colour::Texture(_, mean) => mean.get().copied().unwrap_or(Vec3::ZERO),
        }
    }
}

/// `alpha` of a rough material: a number >= 0 or a texture whose values (their
/// [`texture_scalar`]: luminance, a grey as it is) are the roughness over the
/// surface ([`ColourSlot::Roughness`]).
pub enum RoughnessValue {
    Value(f32),
    /// A texture and, once [`textures`] has loaded it, its mean (the material's nominal
    /// roughness).
    Texture(Box<TextureDesc>, OnceCell<Vec3>),
}

impl RoughnessValue {
    /// The constant, or the luminance of the loaded texture's mean.
    pub fn value(&self) -> f32 {
        match self {
            RoughnessValue::Value(a) => *a,
            RoughnessValue::Texture(_, mean) => {
                texture_scalar(mean.get().copied().unwrap_or(Vec3::ZERO))
            }
        }
    }
}

impl<'de> Deserialize<'de> for RoughnessValue {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl V {
            fn check<E: serde::de::Error>(x: f64) -> Result<RoughnessValue, E> {
                let a = x as f32;
                if a.is_finite() && a >= 0.0 {
                    Ok(RoughnessValue::Value(a))
                } else {
                    Err(E::custom(format!(
                        "{x} is out of range, expected a finite number >= 0"
                    )))
                }
            }
        }
        impl<'de> Visitor<'de> for V {
            type Value = RoughnessValue;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(
                    "a roughness (a number >= 0) or a texture { texture: bitmap | checkerboard, ... }",
                )
            }
            fn visit_f64<E: serde::de::Error>(self, x: f64) -> Result<RoughnessValue, E> {
                V::check(x)
            }
            fn visit_i64<E: serde::de::Error>(self, x: i64) -> Result<RoughnessValue, E> {
                V::check(x as f64)
            }
            fn visit_u64<E: serde::de::Error>(self, x: u64) -> Result<RoughnessValue, E> {
                V::check(x as f64)
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<RoughnessValue, A::Error> {
                let desc = TextureDesc::deserialize(MapAccessDeserializer::new(map))?;
                Ok(RoughnessValue::Texture(Box::new(desc), OnceCell::new()))
            }
        }
        d.deserialize_any(V)
    }
}

impl fmt::Debug for RoughnessValue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RoughnessValue::Value(a) => a.fmt(f),
            RoughnessValue::Texture(t, _) => write!(f, "texture {:?}", t.texture),
        }
    }
}

/// The texture models.
#[derive(Deserialize, Clone, Copy, Debug, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum TextureType {
    Bitmap,
    Checkerboard,
}

/// `filter:` of a bitmap.
#[derive(Deserialize, Clone, Copy, Debug, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum FilterName {
    Nearest,
    Bilinear,
}

/// `wrap:` of a bitmap.
#[derive(Deserialize, Clone, Copy, Debug, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum WrapName {
    Repeat,
    Mirror,
    Clamp,
}

/// One texture description; which fields apply depends on `texture`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TextureDesc {
    pub texture: TextureType,
    /// Bitmap: the image file, relative to the scene file.
    pub file: Option<String>,
    pub filter: Option<FilterName>,
    pub wrap: Option<WrapName>,
    /// Bitmap: take an 8-bit image's values as they are (no sRGB decoding).
    pub raw: Option<bool>,
    /// uv -> uv * scale + offset before the look-up.
    pub scale: Option<[f32; 2]>,
    pub offset: Option<[f32; 2]>,
    /// uv -> the affine map of 6 numbers `[a, b, c, d, e, f]`: u' = a u + b v + c,
    /// v' = d u + e v + f (Mitsuba's `to_uv`, e.g. a rotation); instead of scale and offset.
    pub to_uv: Option<[f32; 6]>,
    /// Checkerboard's two colours.
    pub color0: Option<Triple<Reflectance>>,
    pub color1: Option<Triple<Reflectance>>,
}

impl<'de> Deserialize<'de> for Colour {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Colour;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(
                    "a list of three numbers, each a reflectance in [0, 1], or a texture \
                     { texture: bitmap | checkerboard, ... }",
                )
            }
            fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<Colour, A::Error> {
                TripleVisitor::<Reflectance>(PhantomData)
                    .visit_seq(seq)
                    .map(Colour::Value)
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<Colour, A::Error> {
                let desc = TextureDesc::deserialize(MapAccessDeserializer::new(map))?;
                Ok(Colour::Texture(Box::new(desc), OnceCell::new()))
            }
        }
        d.deserialize_any(V)
    }
}

/// A texture from its description at `field` (e.g. `materials.wood.color`); image files
/// are relative to the directory `dir`. Values must be reflectances: at most 1.
pub(crate) fn load_texture(
    t: &TextureDesc,
    field: &str,
    path: &Path,
    dir: &Path,
) -> Result<Texture, LoadError> {
    let err = |message: String| LoadError::invalid(path, field, message);
    let finite = |v: [f32; 2]| v.iter().all(|x| x.is_finite());
    let scale = t.scale.unwrap_or([1.0, 1.0]);
    let offset = t.offset.unwrap_or([0.0, 0.0]);
    if !finite(scale) || !finite(offset) {
        return Err(err("texture scale and offset must be finite".into()));
    }
    let transform = match t.to_uv {
        Some(_) if t.scale.is_some() || t.offset.is_some() => {
            return Err(err(
                "give either `to_uv` or `scale` and `offset`, not both".into()
            ))
        }
        Some(m) if !m.iter().all(|x| x.is_finite()) => {
            return Err(err("texture to_uv must be finite".into()))
        }
        Some(m) => UvTransform { m },
        None => UvTransform::scale_offset(Vec2::from(scale), Vec2::from(offset)),
    };
    let only = |allowed: &[&str]| -> Result<(), LoadError> {
        let present = [
            ("file", t.file.is_some()),
            ("filter", t.filter.is_some()),
            ("wrap", t.wrap.is_some()),
            ("raw", t.raw.is_some()),
            ("color0", t.color0.is_some()),
            ("color1", t.color1.is_some()),
        ];
        match present.iter().find(|(n, p)| *p && !allowed.contains(n)) {
            Some((n, _)) => Err(err(format!("`{n}` does not apply to this texture"))),
            None => Ok(()),
        }
    };
    let texture = match t.texture {
        TextureType::Checkerboard => {
            only(&["color0", "color1"])?;
            Texture::Checkerboard(Checkerboard {
                color0: t.color0.as_ref().map_or(Vec3::splat(0.4), |c| c.value()),
                color1: t.color1.as_ref().map_or(Vec3::splat(0.2), |c| c.value()),
                transform,
            })
        }
        TextureType::Bitmap => {
            only(&["file", "filter", "wrap", "raw"])?;
            let file = t
                .file
                .as_deref()
                .ok_or_else(|| err("a bitmap texture needs `file`, its image".into()))?;
            let image_path = dir.join(file);
            let what = format!("texture image of {field} in {}", path.display());
            let image = read_rgb_image(&image_path, &what, t.raw.unwrap_or(false))?;
            let filter = match t.filter.unwrap_or(FilterName::Bilinear) {
                FilterName::Nearest => Filter::Nearest,
                FilterName::Bilinear => Filter::Bilinear,
            };
            let wrap = match t.wrap.unwrap_or(WrapName::Repeat) {
                WrapName::Repeat => WrapMode::Repeat,
                WrapName::Mirror => WrapMode::Mirror,
                WrapName::Clamp => WrapMode::Clamp,
            };
            let bitmap = Bitmap::new(
                image.width,
                image.height,
                image.texels,
                filter,
                wrap,
                transform,
            )
            .ok_or_else(|| err(format!("{}: the image is empty", image_path.display())))?;
            Texture::Bitmap(bitmap)
        }
    };
    let max = texture.max_value();
    if !(0.0..=1.0).contains(&max) || !texture.mean().is_finite() {
        return Err(err(format!(
            "a texture's values are reflectances in [0, 1]; this one reaches {max}"
        )));
    }
    Ok(texture)
}

/// The textured colours of material `d` (at `field`), loaded, each with the BSDF colour it
/// drives; their means are stored in the fields, so that `Colour::value` gives them. A
/// `twosided` material's nested `bsdf` is included.
pub(crate) fn textures(
    d: &MaterialDesc,
    field: &str,
    path: &Path,
    dir: &Path,
) -> Result<Vec<(ColourSlot, Texture)>, LoadError> {
    use ColourSlot::*;
    let colour_slot = match d.kind {
        MaterialType::Mirror => SpecularReflectance,
        MaterialType::Glass => SpecularTransmittance,
        _ => DiffuseReflectance,
    };
    let fields = [
        ("color", &d.color, colour_slot),
        ("diffuse", &d.diffuse, DiffuseReflectance),
        ("specular", &d.specular, SpecularReflectance),
        (
            "diffuse_reflectance",
            &d.diffuse_reflectance,
            DiffuseReflectance,
        ),
        (
            "specular_reflectance",
            &d.specular_reflectance,
            SpecularReflectance,
        ),
        (
            "specular_transmittance",
            &d.specular_transmittance,
            SpecularTransmittance,
        ),
    ];
    let mut slots = Vec::new();
    for (name, colour, slot) in fields {
        if let Some(Colour::Texture(t, mean)) = colour {
            let texture = load_texture(t, &format!("{field}.{name}"), path, dir)?;
            let _ = mean.set(texture.mean());
            slots.push((slot, texture));
        }
    }
    if let Some(RoughnessValue::Texture(t, mean)) = &d.alpha {
        if matches!(d.kind, MaterialType::RoughPlastic) {
            return Err(LoadError::invalid(
                path,
                format!("{field}.alpha"),
                "a roughness texture is not supported on roughplastic (its coating's \
                 reflectance tables are computed per roughness): give a number",
            ));
        }
        let texture = load_texture(t, &format!("{field}.alpha"), path, dir)?;
        let _ = mean.set(texture.mean());
        slots.push((ColourSlot::Roughness, texture));
    }
    if let Some(nested) = &d.bsdf {
        slots.extend(textures(nested, &format!("{field}.bsdf"), path, dir)?);
    }
    Ok(slots)
}

impl fmt::Debug for Colour {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Colour::Value(t) => t.fmt(f),
            Colour::Texture(t, _) => write!(f, "texture {:?}", t.texture),
        }
    }
}
