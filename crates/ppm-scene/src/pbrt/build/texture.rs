//! `Texture "name" "spectrum" "imagemap"` and `"checkerboard"` as a material's reflectance,
//! and `Texture "name" "float" ...` (`constant`, `imagemap`, `checkerboard`) as a conductor's
//! or dielectric's roughness, to ppm's [`Bitmap`] and [`Checkerboard`].
//!
//! # uv conventions
//! pbrt-v4's `UVMapping` maps the surface's (u, v) to (s, t) = (uscale u + udelta,
//! vscale v + vdelta). Its `ImageTexture` looks the image up at (s, 1 - t), with image row 0
//! the file's top row (`textures.cpp`): t grows upward. ppm's textures (Mitsuba's) look
//! up (u', v') with v' growing downward from the top row, so an image map becomes the
//! [`UvTransform`] u' = s, v' = 1 - t. pbrt's 2D `checkerboard` is tex1 where
//! floor(s) + floor(t) is even and tex2 elsewhere (unit squares, no flip); ppm's checkerboard
//! has squares of half a uv unit with `color0` at the origin, so u' = s / 2, v' = t / 2 and
//! color0 = tex1.

use super::super::params::{Param, ParamSet};
use super::super::scene::{Description, TextureEntity};
use super::super::spectrum::{self, SpectrumValue};
use crate::image_file::read_rgb_image;
use crate::LoadError;
use glam::{DVec3, Vec2, Vec3};
use ppm_core::texture::{Bitmap, Checkerboard, Filter, Texture, UvTransform, WrapMode};

/// What a texture's values become: a reflectance (RGB in [0, 1]), or the GGX alpha of a
/// float roughness r (pbrt-v4's `RoughnessToAlpha`: alpha = sqrt(r) when `remap`, else r),
/// stored as a grey colour for [`ColourSlot::Roughness`](ppm_core::texture::ColourSlot).
#[derive(Clone, Copy)]
enum Values {
    Reflectance,
    Alpha { remap: bool },
}

impl Values {
    /// The alpha of roughness `r`.
    fn alpha(remap: bool, r: f64) -> f64 {
        if remap {
            r.sqrt()
        } else {
            r
        }
    }
}

/// The texture `name` that parameter `param` of `p` names, as a reflectance; `None` for a
/// `constant` texture (the caller reads its value).
pub fn reflectance_texture(
    desc: &Description,
    p: &ParamSet,
    param: &Param,
    name: &str,
    warnings: &mut Vec<String>,
) -> Result<Option<Texture>, LoadError> {
    let t = desc
        .textures
        .get(name)
        .ok_or_else(|| p.error_at(param, format!("no texture \"{name}\"")))?;
    if t.value_type != "spectrum" || !matches!(t.entity.kind.as_str(), "imagemap" | "checkerboard")
    {
        return Ok(None);
    }
    uv_texture(desc, t, name, Values::Reflectance, warnings).map(Some)
}

/// A float roughness given as texture `name` (parameter `param` of `p`): a `constant`
/// texture's roughness r as `Ok(r)`, an `imagemap` (a grey image: pbrt reads a float image's
/// first channel, which ppm takes only where the three are equal) or a `checkerboard` (float
/// `tex1`, `tex2`) as the texture of its GGX alphas (alpha = sqrt(r) per texel when `remap`).
pub fn roughness_texture(
    desc: &Description,
    p: &ParamSet,
    param: &Param,
    name: &str,
    remap: bool,
    warnings: &mut Vec<String>,
) -> Result<Result<f64, Texture>, LoadError> {
    let t = desc
        .textures
        .get(name)
        .ok_or_else(|| p.error_at(param, format!("no texture \"{name}\"")))?;
    let supported = t.value_type == "float"
        && matches!(
            t.entity.kind.as_str(),
            "constant" | "imagemap" | "checkerboard"
        );
    if !supported {
        return Err(p.error_at(
            param,
            format!(
                "texture \"{name}\" ({} \"{}\" at {}) is not supported yet as a roughness: float constant, imagemap and checkerboard textures are",
                t.value_type, t.entity.kind, t.entity.loc
            ),
        ));
    }
    if t.entity.kind == "constant" {
        let tp = texture_params(t, name);
        let r = match tp.float_or_texture("value")? {
            None => 1.0,
            Some(Ok(r)) => r,
            Some(Err((_, param))) => {
                return Err(tp.error_at(param, "a texture's value cannot be another texture"))
            }
        };
        tp.finish()?;
        return Ok(Ok(r));
    }
    uv_texture(desc, t, name, Values::Alpha { remap }, warnings).map(Err)
}

/// The parameters of texture `t` (named `name`).
fn texture_params<'a>(t: &'a TextureEntity, name: &str) -> ParamSet<'a> {
    ParamSet::new(
        format!("Texture \"{name}\""),
        t.entity.loc.clone(),
        &t.entity.params,
        &[],
    )
}

/// An `imagemap` or `checkerboard` texture under its uv mapping, its values as `values` says.
fn uv_texture(
    desc: &Description,
    t: &TextureEntity,
    name: &str,
    values: Values,
    warnings: &mut Vec<String>,
) -> Result<Texture, LoadError> {
    let tp = texture_params(t, name);
    let mapping = tp.string_opt("mapping")?.unwrap_or("uv");
    if mapping != "uv" {
        return Err(tp.error(format!(
            "mapping \"{mapping}\" is not supported yet (only uv is)"
        )));
    }
    let scale = Vec2::new(
        tp.float("uscale", 1.0)? as f32,
        tp.float("vscale", 1.0)? as f32,
    );
    let delta = Vec2::new(
        tp.float("udelta", 0.0)? as f32,
        tp.float("vdelta", 0.0)? as f32,
    );
    let texture = if t.entity.kind == "imagemap" {
        imagemap(desc, &tp, scale, delta, values, warnings)?
    } else {
        checkerboard(&tp, scale, delta, values)?
    };
    tp.finish()?;
    Ok(texture)
}

/// `imagemap`: `filename` (relative to the main file's folder), `filter` (point: nearest;
/// bilinear; trilinear and ewa approximated by bilinear, with a warning), `wrap` (repeat,
/// clamp), `encoding` (sRGB, linear; default sRGB for 8-bit PNG), `scale`, `invert` false.
fn imagemap(
    desc: &Description,
    tp: &ParamSet,
    scale: Vec2,
    delta: Vec2,
    values: Values,
    warnings: &mut Vec<String>,
) -> Result<Texture, LoadError> {
    let name = tp
        .string_opt("filename")?
        .ok_or_else(|| tp.error("needs a \"string filename\""))?;
    let path = desc.main_folder.join(name);
    let filter = match tp.string_opt("filter")?.unwrap_or("bilinear") {
        "point" => Filter::Nearest,
        "bilinear" => Filter::Bilinear,
        f @ ("trilinear" | "ewa") => {
            warnings.push(format!(
                "{}: {}: filter \"{f}\" approximated by bilinear (ppm has no MIP maps)",
                tp.loc, tp.what
            ));
            Filter::Bilinear
        }
        other => {
            return Err(tp.error(format!(
                "filter \"{other}\" is not point, bilinear, trilinear or ewa"
            )))
        }
    };
    let wrap = match tp.string_opt("wrap")?.unwrap_or("repeat") {
        "repeat" => WrapMode::Repeat,
        "clamp" => WrapMode::Clamp,
        other => {
            return Err(tp.error(format!(
                "wrap \"{other}\" is not supported yet (repeat and clamp are)"
            )))
        }
    };
    let raw = match tp.string_opt("encoding")?.unwrap_or("sRGB") {
        "sRGB" => false,
        "linear" => true,
        other => {
            return Err(tp.error(format!(
                "encoding \"{other}\" is not supported yet (sRGB and linear are)"
            )))
        }
    };
    let gain = tp.float("scale", 1.0)? as f32;
    if tp.bool("invert", false)? {
        return Err(tp.error("invert is not supported yet"));
    }
    let what = format!("imagemap texture image ({})", tp.loc);
    let image = read_rgb_image(&path, &what, raw)?;
    let texels: Vec<Vec3> = image.texels.iter().map(|&c| c * gain).collect();
    let texels = match values {
        Values::Reflectance => {
            let max = texels.iter().fold(0.0f32, |m, c| m.max(c.max_element()));
            if !(0.0..=1.0).contains(&max) || texels.iter().any(|c| c.min_element() < 0.0) {
                return Err(tp.error(format!(
                    "{} times scale {gain} reaches {max}; ppm takes reflectances in [0, 1]",
                    path.display()
                )));
            }
            texels
        }
        Values::Alpha { remap } => {
            if texels.iter().any(|c| c.x != c.y || c.y != c.z) {
                return Err(tp.error(format!(
                    "{} is not grey: as a float texture pbrt reads its first channel; give a greyscale image",
                    path.display()
                )));
            }
            if texels.iter().any(|c| !(c.x >= 0.0 && c.x.is_finite())) {
                return Err(tp.error(format!(
                    "{} times scale {gain} has a negative roughness",
                    path.display()
                )));
            }
            texels
                .iter()
                .map(|c| Vec3::splat(Values::alpha(remap, c.x as f64) as f32))
                .collect()
        }
    };
    // u' = s, v' = 1 - t (module docs).
    let transform = UvTransform {
        m: [scale.x, 0.0, delta.x, 0.0, -scale.y, 1.0 - delta.y],
    };
    let bitmap = Bitmap::new(image.width, image.height, texels, filter, wrap, transform)
        .ok_or_else(|| tp.error(format!("{} is empty", path.display())))?;
    Ok(Texture::Bitmap(bitmap))
}

/// `checkerboard`, 2D: `tex1` (default 1) and `tex2` (default 0), constant reflectances or
/// (float textures) constant roughnesses.
fn checkerboard(
    tp: &ParamSet,
    scale: Vec2,
    delta: Vec2,
    values: Values,
) -> Result<Texture, LoadError> {
    let dimension = tp.int("dimension", 2)?;
    if dimension != 2 {
        return Err(tp.error(format!(
            "dimension {dimension} is not supported yet (only 2 is)"
        )));
    }
    let colour = |name: &str, default: f64| -> Result<Vec3, LoadError> {
        if let Values::Alpha { remap } = values {
            return match tp.float_or_texture(name)? {
                None => Ok(Vec3::splat(Values::alpha(remap, default) as f32)),
                Some(Ok(r)) if r >= 0.0 && r.is_finite() => {
                    Ok(Vec3::splat(Values::alpha(remap, r) as f32))
                }
                Some(Ok(r)) => Err(tp.error(format!("roughness {name} {r} is negative"))),
                Some(Err((t, param))) => Err(tp.error_at(
                    param,
                    format!("a texture (\"{t}\") is not supported here yet"),
                )),
            };
        }
        let Some((value, param)) = tp.spectrum(name)? else {
            return Ok(Vec3::splat(default as f32));
        };
        if let SpectrumValue::Texture(t) = value {
            return Err(tp.error_at(
                param,
                format!("a texture (\"{t}\") is not supported here yet"),
            ));
        }
        let c: DVec3 = spectrum::albedo_rgb(&value).map_err(|e| tp.error_at(param, e))?;
        Ok(c.as_vec3())
    };
    // u' = s / 2, v' = t / 2 (module docs).
    Ok(Texture::Checkerboard(Checkerboard {
        color0: colour("tex1", 1.0)?,
        color1: colour("tex2", 0.0)?,
        transform: UvTransform::scale_offset(scale * 0.5, delta * 0.5),
    }))
}
