//! Texture plugins in place of a BSDF colour: `bitmap` (filename, filter_type, wrap_mode,
//! raw, to_uv) and `checkerboard` (color0, color1, to_uv), nested or by `<ref>`.
//!
//! BSDF builders read a colour with [`colour_or_texture`]: a constant as before, or a
//! texture, whose mean is returned as the BSDF's nominal colour and which is recorded, with
//! the BSDF colour it drives, for the material being built ([`textured_bsdf`] collects
//! them, so the BSDF functions keep returning a plain `Bsdf`).

use crate::image_file::read_rgb_image;
use crate::mitsuba::props::Props;
use crate::mitsuba::spectrum::Role;
use crate::mitsuba::tree::{SceneTree, Value};
use crate::LoadError;
use glam::{DMat4, DVec3, Vec3};
use ppm_core::bsdf::Bsdf;
use ppm_core::texture::{Bitmap, Checkerboard, ColourSlot, Filter, Texture, UvTransform, WrapMode};
use std::cell::RefCell;

thread_local! {
    /// The textures read while one material's BSDF is built (see [`textured_bsdf`]).
    static COLLECTED: RefCell<Option<Vec<(ColourSlot, Texture)>>> = const { RefCell::new(None) };
}

/// The BSDF of object `index` and the textures its colours read, in reading order.
pub fn textured_bsdf(
    tree: &SceneTree,
    index: usize,
    warnings: &mut Vec<String>,
) -> Result<(Bsdf, Vec<(ColourSlot, Texture)>), LoadError> {
    COLLECTED.with(|c| *c.borrow_mut() = Some(Vec::new()));
    let bsdf = super::bsdf::bsdf(tree, index, warnings);
    let textures = COLLECTED
        .with(|c| c.borrow_mut().take())
        .unwrap_or_default();
    Ok((bsdf?, textures))
}

/// The BSDF colour a Mitsuba parameter of this name drives.
fn slot(name: &str) -> ColourSlot {
    match name {
        "specular_reflectance" => ColourSlot::SpecularReflectance,
        "specular_transmittance" => ColourSlot::SpecularTransmittance,
        "alpha" => ColourSlot::Roughness,
        _ => ColourSlot::DiffuseReflectance,
    }
}

/// Colour `name` of `p` (default `default`): a constant, or a texture (recorded for the
/// material, its mean returned).
pub fn colour_or_texture(
    p: &Props,
    name: &str,
    default: DVec3,
    role: Role,
) -> Result<DVec3, LoadError> {
    let texture = match p.get(name).map(|prop| &prop.value) {
        Some(Value::Object(i)) if p.tree.objects[*i].class == "texture" => *i,
        _ => return p.colour(name, default, role),
    };
    let t = Props::new(p.tree, texture);
    let loaded = match t.object.plugin.as_str() {
        "bitmap" => bitmap(&t)?,
        "checkerboard" => checkerboard(&t)?,
        _ => {
            return Err(t.error(format!(
                "{} (as `{name}` of {}) is not supported: ppm reads the textures bitmap and checkerboard",
                t.object.describe(),
                p.object.describe()
            )))
        }
    };
    t.finish()?;
    let mean = loaded.mean().as_dvec3();
    COLLECTED.with(|c| match c.borrow_mut().as_mut() {
        Some(list) => {
            list.push((slot(name), loaded));
            Ok(mean)
        }
        None => Err(p.error(format!(
            "a texture as `{name}` of {} is not supported here",
            p.object.describe()
        ))),
    })
}

/// Mitsuba's `to_uv`: a 4 x 4 transform of which the uv map takes the x and y rows and the
/// x, y and translation columns: `u' = m00 u + m01 v + m03`, `v' = m10 u + m11 v + m13`.
fn to_uv(p: &Props) -> Result<UvTransform, LoadError> {
    let m: DMat4 = p.transform("to_uv")?;
    let at = |r: usize, c: usize| m.col(c)[r] as f32;
    let t = UvTransform {
        m: [at(0, 0), at(0, 1), at(0, 3), at(1, 0), at(1, 1), at(1, 3)],
    };
    if t.m.iter().all(|x| x.is_finite()) {
        Ok(t)
    } else {
        Err(p.error("to_uv is not finite"))
    }
}

/// `bitmap`: the image file (relative to the XML file or a `<path>`), `filter_type` bilinear (default) or
/// nearest, `wrap_mode` repeat (default), mirror or clamp, `raw` (8-bit values taken as
/// they are instead of sRGB-decoded).
fn bitmap(p: &Props) -> Result<Texture, LoadError> {
    let name = p
        .string_opt("filename")?
        .ok_or_else(|| p.error(format!("{} needs a string `filename`", p.object.describe())))?;
    let path = p.tree.resolve(&p.location().file, name);
    let filter = match p.string_opt("filter_type")?.unwrap_or("bilinear") {
        "bilinear" => Filter::Bilinear,
        "nearest" => Filter::Nearest,
        other => {
            return Err(p.error(format!(
                "bitmap: filter_type `{other}` is not bilinear or nearest"
            )))
        }
    };
    let wrap = match p.string_opt("wrap_mode")?.unwrap_or("repeat") {
        "repeat" => WrapMode::Repeat,
        "mirror" => WrapMode::Mirror,
        "clamp" => WrapMode::Clamp,
        other => {
            return Err(p.error(format!(
                "bitmap: wrap_mode `{other}` is not repeat, mirror or clamp"
            )))
        }
    };
    let raw = p.boolean("raw", false)?;
    p.ignore(&["format", "accel"]);
    let what = format!("bitmap texture image ({})", p.location());
    let image = read_rgb_image(&path, &what, raw)?;
    let bitmap = Bitmap::new(
        image.width,
        image.height,
        image.texels,
        filter,
        wrap,
        to_uv(p)?,
    )
    .ok_or_else(|| p.error(format!("bitmap: {} is empty", path.display())))?;
    let texture = Texture::Bitmap(bitmap);
    let max = texture.max_value();
    if !(0.0..=1.0).contains(&max) {
        return Err(p.error(format!(
            "bitmap: {} reaches {max}; ppm takes reflectances in [0, 1]",
            path.display()
        )));
    }
    Ok(texture)
}

/// `checkerboard`: `color0` (default 0.4) and `color1` (default 0.2).
fn checkerboard(p: &Props) -> Result<Texture, LoadError> {
    let colour = |name: &str, default: f64| -> Result<Vec3, LoadError> {
        let c = p.colour(name, DVec3::splat(default), Role::Reflectance)?;
        if c.min_element() < 0.0 || c.max_element() > 1.0 {
            return Err(p.error(format!("checkerboard: `{name}` is {c}, expected [0, 1]")));
        }
        Ok(c.as_vec3())
    };
    Ok(Texture::Checkerboard(Checkerboard {
        color0: colour("color0", 0.4)?,
        color1: colour("color1", 0.2)?,
        transform: to_uv(p)?,
    }))
}
