//! MTL material libraries: a small parser (with line numbers in its errors) and the mapping
//! of the classic MTL parameters to ppm's four BSDFs.
//!
//! tobj parses MTL files too, but panics on short colour statements (`Kd 0.5`), does not
//! report lines, and we need `Tf`; so the OBJ loader hands tobj the material names only.

use crate::error::LoadError;
use glam::Vec3;
use ppm_core::bsdf::{Bsdf, Phong};
use ppm_core::material::Material;
use std::collections::HashSet;
use std::path::{Path, PathBuf};

/// Diffuse albedo of materials without `Kd`, and of faces without a usable material.
pub const DEFAULT_ALBEDO: f32 = 0.5;

/// Index of refraction of glass materials whose `Ni` is missing or not above 1.
pub const DEFAULT_IOR: f32 = 1.5;

/// The statements of one `newmtl` block that ppm uses. `None` = not given.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MtlMaterial {
    pub name: String,
    /// Diffuse reflectance.
    pub kd: Option<Vec3>,
    /// Specular reflectance.
    pub ks: Option<Vec3>,
    /// Emitted radiance.
    pub ke: Option<Vec3>,
    /// Transmission filter.
    pub tf: Option<Vec3>,
    /// Specular exponent.
    pub ns: Option<f32>,
    /// Index of refraction ("optical density").
    pub ni: Option<f32>,
    /// Dissolve (opacity), in [0, 1].
    pub d: Option<f32>,
    /// Illumination model.
    pub illum: Option<u32>,
    /// `map_Kd`: an image for the diffuse reflectance (see `mtl_texture.rs`).
    pub map_kd: Option<crate::mtl_texture::MtlTexture>,
    /// `map_Ks`: an image for the specular reflectance.
    pub map_ks: Option<crate::mtl_texture::MtlTexture>,
    /// Where the material is defined, `file.mtl:<line of its newmtl>`, for warnings about
    /// it (empty when built in code: the warnings then name the file they are given).
    pub defined_at: String,
}

/// Parses the text of an MTL file. `path` names the file in messages and warnings.
pub fn parse_mtl(
    text: &str,
    path: &Path,
    warnings: &mut Vec<String>,
) -> Result<Vec<MtlMaterial>, LoadError> {
    let mut materials: Vec<MtlMaterial> = Vec::new();
    // Texture statements ignored, each with its first line.
    let mut ignored: Vec<(String, usize)> = Vec::new();
    // Statements of no MTL dialect ppm knows (often a typo: `Kdd`), with their first line.
    let mut unknown: Vec<(String, usize)> = Vec::new();
    let mut defined: HashSet<String> = HashSet::new();
    for (i, raw) in text.lines().enumerate() {
        let line_no = i + 1;
        let line = raw.split('#').next().unwrap_or("").trim();
        let mut words = line.split_whitespace();
        let Some(keyword) = words.next() else {
            continue;
        };
        let args: Vec<&str> = words.collect();
        let err = |message: String| LoadError::parse(path, line_no, message);
        if keyword == "newmtl" {
            let name = args.join(" ");
            if name.is_empty() {
                return Err(err("`newmtl` needs a material name".into()));
            }
            if !defined.insert(name.clone()) {
                warnings.push(format!(
                    "{}:{line_no}: material `{name}` is defined again; the last definition is used",
                    path.display()
                ));
            }
            materials.push(MtlMaterial {
                defined_at: format!("{}:{line_no}", path.display()),
                name,
                ..Default::default()
            });
            continue;
        }
        let Some(m) = materials.last_mut() else {
            warnings.push(format!(
                "{}:{line_no}: `{keyword}` before any `newmtl` is ignored",
                path.display()
            ));
            continue;
        };
        match keyword.to_ascii_lowercase().as_str() {
            "kd" => m.kd = color(&args, keyword, path, line_no, warnings)?.or(m.kd),
            "ks" => m.ks = color(&args, keyword, path, line_no, warnings)?.or(m.ks),
            "ke" => m.ke = color(&args, keyword, path, line_no, warnings)?.or(m.ke),
            "tf" => m.tf = color(&args, keyword, path, line_no, warnings)?.or(m.tf),
            "ns" => m.ns = Some(scalar(&args, keyword, path, line_no)?),
            "ni" => m.ni = Some(scalar(&args, keyword, path, line_no)?),
            "d" => {
                // `d -halo 0.5` is a view-dependent dissolve; we take its factor.
                let args = if args.first() == Some(&"-halo") {
                    &args[1..]
                } else {
                    &args[..]
                };
                let d = scalar(args, keyword, path, line_no)?;
                if d > 1.0 {
                    return Err(err(format!("`d` is {d}, expected a dissolve in [0, 1]")));
                }
                m.d = Some(d);
            }
            "illum" => match args.as_slice() {
                [x] => match x.parse::<u32>() {
                    Ok(n) => m.illum = Some(n),
                    Err(_) => {
                        return Err(err(format!(
                            "`illum` needs a whole number >= 0, found `{x}`"
                        )))
                    }
                },
                _ => return Err(err("`illum` needs one whole number".into())),
            },
            "map_kd" => m.map_kd = Some(crate::mtl_texture::parse(&args, path, line_no)?),
            "map_ks" => m.map_ks = Some(crate::mtl_texture::parse(&args, path, line_no)?),
            k if (k.starts_with("map_")
                || matches!(k, "bump" | "disp" | "decal" | "refl" | "norm"))
                && !ignored.iter().any(|(s, _)| s == keyword) =>
            {
                ignored.push((keyword.to_string(), line_no));
            }
            // Ka (ambient), Tr (its meaning differs between exporters), sharpness and the PBR
            // extension (Pr, Pm, ...) have no counterpart in ppm's BSDFs.
            "ka" | "tr" | "sharpness" | "pr" | "pm" | "ps" | "pc" | "pcr" | "aniso" | "anisor" => {}
            _ => {
                if !unknown.iter().any(|(k, _)| k == keyword) {
                    unknown.push((keyword.to_string(), line_no));
                }
            }
        }
    }
    if let Some((_, first)) = unknown.first() {
        let names: Vec<&str> = unknown.iter().take(8).map(|(k, _)| k.as_str()).collect();
        warnings.push(format!(
            "{}:{first}: ignored unknown statements: {} (the first on this line)",
            path.display(),
            names.join(", ")
        ));
    }
    if let Some((_, first)) = ignored.first() {
        let names: Vec<&str> = ignored.iter().map(|(k, _)| k.as_str()).collect();
        warnings.push(format!(
            "{}:{first}: texture maps other than map_Kd and map_Ks are not supported; ignored {} (the first on this line)",
            path.display(),
            names.join(", ")
        ));
    }
    Ok(materials)
}

/// `Kd r g b` or `Kd r`; `None` (with a warning) for the unsupported `spectral` and `xyz` forms.
fn color(
    args: &[&str],
    keyword: &str,
    path: &Path,
    line_no: usize,
    warnings: &mut Vec<String>,
) -> Result<Option<Vec3>, LoadError> {
    if matches!(args.first(), Some(&"spectral") | Some(&"xyz")) {
        warnings.push(format!(
            "{}:{line_no}: `{keyword} {}` is not supported; statement ignored",
            path.display(),
            args[0]
        ));
        return Ok(None);
    }
    let values: Vec<f32> = args
        .iter()
        .map(|a| number(a, keyword, path, line_no))
        .collect::<Result<_, _>>()?;
    match values.as_slice() {
        [g] => Ok(Some(Vec3::splat(*g))),
        [r, g, b] => Ok(Some(Vec3::new(*r, *g, *b))),
        _ => Err(LoadError::parse(
            path,
            line_no,
            format!("`{keyword}` needs 1 or 3 numbers, found {}", values.len()),
        )),
    }
}

fn scalar(args: &[&str], keyword: &str, path: &Path, line_no: usize) -> Result<f32, LoadError> {
    match args {
        [a] => number(a, keyword, path, line_no),
        _ => Err(LoadError::parse(
            path,
            line_no,
            format!("`{keyword}` needs one number"),
        )),
    }
}

/// A finite number >= 0: every numeric MTL parameter ppm reads is one.
fn number(a: &str, keyword: &str, path: &Path, line_no: usize) -> Result<f32, LoadError> {
    match a.parse::<f32>() {
        Ok(x) if x.is_finite() && x >= 0.0 => Ok(x),
        _ => Err(LoadError::parse(
            path,
            line_no,
            format!("`{keyword}`: `{a}` is not a finite number >= 0"),
        )),
    }
}

/// Maps an MTL material to a ppm material, first rule that applies:
///
/// | MTL                                            | ppm                                  |
/// |------------------------------------------------|--------------------------------------|
/// | `Ke`                                           | emission (any type)                  |
/// | `illum` 3 or 5, `Ks` > 0                       | mirror, colour `Ks`                  |
/// | `illum` 4, 6 or 7, or `d` < 1 with `Ni` > 1    | glass, ior `Ni` (1.5 if `Ni` <= 1 or missing), colour `Tf` (default 1) |
/// | `Ks` > 0 and `Ns` > 0                          | phong (`Kd`, `Ks`, exponent `Ns`)    |
/// | otherwise                                      | diffuse, albedo `Kd` (default 0.5)   |
///
/// `Tf` alone never makes glass: exporters write `Tf 1 1 1` and `Ni 1.5` on opaque materials.
/// Reflectances above 1 (in a channel of `Kd`, of `Ks`, of `Kd + Ks` for phong) are scaled
/// down uniformly to a maximum of 1, keeping the hue, with a warning naming the material.
pub fn mtl_to_material(m: &MtlMaterial, path: &Path, warnings: &mut Vec<String>) -> Material {
    // Warnings name the MTL file and line that define the material, not the OBJ using it.
    let defined_at = PathBuf::from(&m.defined_at);
    let path = if m.defined_at.is_empty() {
        path
    } else {
        defined_at.as_path()
    };
    let emission = m.ke.unwrap_or(Vec3::ZERO);
    let mut bad_ior = None;
    let kd = m.kd.unwrap_or(Vec3::splat(DEFAULT_ALBEDO));
    let ks = m.ks.unwrap_or(Vec3::ZERO);
    let d = m.d.unwrap_or(1.0);
    let ni = m.ni.unwrap_or(1.0);
    let mut conserve = |what: &str, c: Vec3| energy_scale(what, c, m, path, warnings);
    let bsdf = if matches!(m.illum, Some(3 | 5)) && ks.max_element() > 0.0 {
        Bsdf::mirror(ks * conserve("Ks", ks))
    } else if matches!(m.illum, Some(4 | 6 | 7)) || (d < 1.0 && ni > 1.0) {
        let ior = match m.ni {
            Some(n) if n > 1.0 => n,
            Some(n) if n != 1.0 => {
                bad_ior = Some(n);
                DEFAULT_IOR
            }
            _ => DEFAULT_IOR,
        };
        let tf = m.tf.unwrap_or(Vec3::ONE);
        Bsdf::glass(ior, tf * conserve("Tf", tf))
    } else if ks.max_element() > 0.0 && m.ns.unwrap_or(0.0) > 0.0 {
        let s = conserve("Kd + Ks", kd + ks);
        let ns = m.ns.unwrap_or(0.0);
        if ns > Phong::MAX_EXPONENT {
            warnings.push(format!(
                "{}: material `{}`: Ns {ns:e} is rendered as {:e}, the largest exponent ppm renders",
                path.display(),
                m.name,
                Phong::MAX_EXPONENT
            ));
        }
        Bsdf::phong(kd * s, ks * s, ns)
    } else {
        Bsdf::diffuse(kd * conserve("Kd", kd))
    };
    if let Some(n) = bad_ior {
        warnings.push(format!(
            "{}: material `{}`: Ni {n} is not a glass index of refraction (> 1); using {DEFAULT_IOR}",
            path.display(),
            m.name
        ));
    }
    Material::new(bsdf, emission).named(m.name.clone())
}

/// 1, or 1 / max channel (with a warning) when reflectance `c` exceeds 1 somewhere.
fn energy_scale(
    what: &str,
    c: Vec3,
    m: &MtlMaterial,
    path: &Path,
    warnings: &mut Vec<String>,
) -> f32 {
    let max = c.max_element();
    if max > 1.0 {
        warnings.push(format!(
            "{}: material `{}`: {what} reaches {max} > 1 in a channel (it would create energy); scaled by 1/{max}",
            path.display(),
            m.name
        ));
        1.0 / max
    } else {
        1.0
    }
}

/// The material of faces whose OBJ names no usable material: diffuse, albedo 0.5.
pub fn default_material() -> Material {
    Material::new(Bsdf::diffuse(Vec3::splat(DEFAULT_ALBEDO)), Vec3::ZERO).named("default")
}
