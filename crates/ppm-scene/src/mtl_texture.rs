//! MTL texture maps: `map_Kd` and `map_Ks` as bitmap textures on the diffuse and specular
//! reflectance. The image replaces the constant (`Kd`, `Ks`), as pbrt-v4's and Blender's
//! OBJ importers do; the file is relative to the MTL file. Options: `-s u v [w]` (uv scale)
//! and `-o u v [w]` (uv offset), `-clamp on` (clamp wrapping, else repeat); others are
//! read past with a warning. Filtering is bilinear, 8-bit images are sRGB.

use crate::error::LoadError;
use crate::image_file::read_rgb_image;
use crate::mtl::MtlMaterial;
use glam::Vec2;
use ppm_core::material::Material;
use ppm_core::texture::{Bitmap, ColourSlot, Filter, Texture, UvTransform, WrapMode};
use std::path::{Path, PathBuf};

/// One `map_` statement: the image (resolved against the MTL file's directory) and its
/// options.
#[derive(Clone, Debug, PartialEq)]
pub struct MtlTexture {
    pub file: PathBuf,
    /// The MTL file and line, for messages.
    pub mtl: PathBuf,
    pub line: usize,
    pub scale: Vec2,
    pub offset: Vec2,
    pub clamp: bool,
    /// Options read past.
    pub ignored: Vec<String>,
}

/// Parses the arguments of a `map_Kd` / `map_Ks` statement at `path`:`line`.
pub fn parse(args: &[&str], path: &Path, line: usize) -> Result<MtlTexture, LoadError> {
    let err = |message: String| LoadError::parse(path, line, message);
    let mut t = MtlTexture {
        file: PathBuf::new(),
        mtl: path.to_path_buf(),
        line,
        scale: Vec2::ONE,
        offset: Vec2::ZERO,
        clamp: false,
        ignored: Vec::new(),
    };
    let mut i = 0;
    let number = |s: &str| s.parse::<f32>().ok().filter(|x| x.is_finite());
    while i < args.len() && args[i].starts_with('-') && i + 1 < args.len() {
        let option = args[i];
        // The numbers that follow (up to three).
        let count = args[i + 1..]
            .iter()
            .take(3)
            .take_while(|a| number(a).is_some())
            .count();
        let values: Vec<f32> = args[i + 1..i + 1 + count]
            .iter()
            .filter_map(|a| number(a))
            .collect();
        match option {
            "-s" | "-o" => {
                if values.len() < 2 {
                    return Err(err(format!("`{option}` needs u v [w]")));
                }
                let v = Vec2::new(values[0], values[1]);
                if option == "-s" {
                    t.scale = v;
                } else {
                    t.offset = v;
                }
                i += 1 + count;
            }
            "-clamp" => {
                t.clamp = args[i + 1] == "on";
                i += 2;
            }
            _ => {
                t.ignored.push(option.to_string());
                i += 1 + count.max(1);
            }
        }
    }
    let name = args[i.min(args.len())..].join(" ");
    if name.is_empty() {
        return Err(err("a texture map needs an image file name".into()));
    }
    t.file = path.parent().unwrap_or(Path::new("")).join(name);
    Ok(t)
}

/// `material` (made from `m` by `mtl_to_material`) with `m`'s texture maps; a map on a
/// BSDF without that colour (a glass's `map_Kd`) is ignored with a warning. A missing or
/// broken image is an error naming it and the MTL line.
pub fn textured(
    material: Material,
    m: &MtlMaterial,
    warnings: &mut Vec<String>,
) -> Result<Material, LoadError> {
    let mut slots = Vec::new();
    for (map, slot, name) in [
        (&m.map_kd, ColourSlot::DiffuseReflectance, "map_Kd"),
        (&m.map_ks, ColourSlot::SpecularReflectance, "map_Ks"),
    ] {
        let Some(t) = map else { continue };
        let place = format!("{}:{}", t.mtl.display(), t.line);
        if !t.ignored.is_empty() {
            warnings.push(format!(
                "{place}: {name}: options {} ignored",
                t.ignored.join(", ")
            ));
        }
        if slot.set(material.bsdf, glam::Vec3::ONE).is_none() {
            warnings.push(format!(
                "{place}: {name} ignored: material `{}` is rendered as {} without that colour",
                m.name,
                bsdf_name(&material)
            ));
            continue;
        }
        let what = format!("{name} image of material `{}` ({place})", m.name);
        let image = read_rgb_image(&t.file, &what, false)?;
        let wrap = if t.clamp {
            WrapMode::Clamp
        } else {
            WrapMode::Repeat
        };
        let transform = UvTransform::scale_offset(t.scale, t.offset);
        let bitmap = Bitmap::new(
            image.width,
            image.height,
            image.texels,
            Filter::Bilinear,
            wrap,
            transform,
        )
        .ok_or_else(|| LoadError::parse(&t.mtl, t.line, format!("{name}: the image is empty")))?;
        slots.push((slot, Texture::Bitmap(bitmap)));
    }
    // Every slot was checked against the BSDF above, so this does not fail.
    let mtl = m
        .map_kd
        .as_ref()
        .or(m.map_ks.as_ref())
        .map(|t| (t.mtl.clone(), t.line));
    material.textured(slots).map_err(|slot| {
        let (file, line) = mtl.unwrap_or_default();
        LoadError::parse(
            &file,
            line,
            format!("material `{}` has no {}", m.name, slot.name()),
        )
    })
}

fn bsdf_name(m: &Material) -> &'static str {
    use ppm_core::bsdf::Bsdf;
    match m.bsdf {
        Bsdf::Diffuse(_) => "diffuse",
        Bsdf::Mirror(_) => "a mirror",
        Bsdf::Glass(_) => "glass",
        Bsdf::Phong(_) => "phong",
        _ => "another model",
    }
}
