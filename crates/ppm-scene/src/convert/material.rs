//! Writing ppm-core materials back as scene format v1 materials: each BSDF model is the
//! YAML type that builds it (`crates/ppm-scene/src/materials.rs` and `build.rs` read them),
//! with the values it holds, so that reading the YAML makes the same BSDF bit for bit.
//! A relative index `eta` is written as `int_ior: eta` over `ext_ior: 1` (eta / 1 = eta), or
//! below 1 as `int_ior: 1` over the `ext_ior` whose reciprocal is eta.

use super::text::{list, num, quoted, triple, Yaml};
use super::Context;
use crate::error::LoadError;
use glam::Vec3;
use ppm_core::bsdf::{Bsdf, Microfacet};
use ppm_core::material::Material;
use ppm_core::texture::{ColourSlot, Filter, Texture, UvTransform, WrapMode};

/// A field's value: text, or a texture to write in its place.
enum Value<'a> {
    Text(String),
    Texture(&'a Texture),
}

/// The YAML type of `bsdf`, its fields, and the field each textured colour slot drives.
struct Fields<'a> {
    kind: &'static str,
    fields: Vec<(&'static str, Value<'a>)>,
    /// For `twosided`: the material it wraps.
    nested: Option<Box<Fields<'a>>>,
}

fn text(s: String) -> Value<'static> {
    Value::Text(s)
}

/// The fields of a microfacet roughness: `alpha`, or `alpha_u` and `alpha_v`, and the
/// distribution when it is not the default GGX.
fn roughness(r: &Microfacet, fields: &mut Vec<(&'static str, Value<'_>)>) {
    let (ax, ay, beckmann) = match r {
        Microfacet::Ggx(g) => (g.alpha_x, g.alpha_y, false),
        Microfacet::Beckmann(b) => (b.alpha_x, b.alpha_y, true),
    };
    if beckmann {
        fields.push(("distribution", text("beckmann".into())));
    }
    if ax == ay {
        fields.push(("alpha", text(num(ax))));
    } else {
        fields.push(("alpha_u", text(num(ax))));
        fields.push(("alpha_v", text(num(ay))));
    }
}

/// The type and fields of `bsdf` (colours as constants; textures are put in afterwards).
fn bsdf_fields<'a>(bsdf: &Bsdf) -> Fields<'a> {
    let mut f: Vec<(&'static str, Value)> = Vec::new();
    let ior = |f: &mut Vec<(&'static str, Value)>, eta: f32| {
        let (int, ext) = ior_pair(eta);
        f.push(("int_ior", text(num(int))));
        f.push(("ext_ior", text(num(ext))));
    };
    let kind = match bsdf {
        Bsdf::Diffuse(b) => {
            f.push(("color", text(triple(b.albedo))));
            "diffuse"
        }
        Bsdf::Mirror(b) => {
            f.push(("color", text(triple(b.color))));
            "mirror"
        }
        Bsdf::Glass(b) => {
            f.push(("ior", text(num(b.ior))));
            f.push(("color", text(triple(b.color))));
            "glass"
        }
        Bsdf::Phong(b) => {
            f.push(("diffuse", text(triple(b.diffuse))));
            f.push(("specular", text(triple(b.specular))));
            f.push(("exponent", text(num(b.exponent))));
            "phong"
        }
        Bsdf::Conductor(b) => {
            f.push(("eta", text(triple(b.eta))));
            f.push(("k", text(triple(b.k))));
            f.push(("specular_reflectance", text(triple(b.specular_reflectance))));
            match &b.roughness {
                Some(r) => {
                    roughness(r, &mut f);
                    "roughconductor"
                }
                None => "conductor",
            }
        }
        Bsdf::Dielectric(b) => {
            ior(&mut f, b.eta);
            f.push(("specular_reflectance", text(triple(b.specular_reflectance))));
            f.push((
                "specular_transmittance",
                text(triple(b.specular_transmittance)),
            ));
            match &b.roughness {
                Some(r) => {
                    roughness(r, &mut f);
                    "roughdielectric"
                }
                None => "dielectric",
            }
        }
        Bsdf::ThinDielectric(b) => {
            ior(&mut f, b.eta);
            f.push(("specular_reflectance", text(triple(b.specular_reflectance))));
            f.push((
                "specular_transmittance",
                text(triple(b.specular_transmittance)),
            ));
            "thindielectric"
        }
        Bsdf::Plastic(b) => {
            ior(&mut f, b.eta);
            f.push(("diffuse_reflectance", text(triple(b.diffuse_reflectance))));
            f.push(("specular_reflectance", text(triple(b.specular_reflectance))));
            match &b.roughness {
                Some(r) => {
                    roughness(r, &mut f);
                    "roughplastic"
                }
                None => "plastic",
            }
        }
        Bsdf::TwoSidedConductor(t) => {
            return Fields {
                kind: "twosided",
                fields: f,
                nested: Some(Box::new(bsdf_fields(&Bsdf::Conductor(t.0)))),
            }
        }
        Bsdf::TwoSidedPlastic(t) => {
            return Fields {
                kind: "twosided",
                fields: f,
                nested: Some(Box::new(bsdf_fields(&Bsdf::Plastic(t.0)))),
            }
        }
    };
    Fields {
        kind,
        fields: f,
        nested: None,
    }
}

/// The field of a material of type `kind` that the colour `slot` is.
fn slot_field(kind: &str, slot: ColourSlot) -> Option<&'static str> {
    use ColourSlot::*;
    Some(match (kind, slot) {
        ("diffuse", DiffuseReflectance)
        | ("mirror", SpecularReflectance)
        | ("glass", SpecularTransmittance) => "color",
        ("phong", DiffuseReflectance) => "diffuse",
        ("phong", SpecularReflectance) => "specular",
        ("plastic" | "roughplastic", DiffuseReflectance) => "diffuse_reflectance",
        (_, SpecularReflectance) => "specular_reflectance",
        (_, SpecularTransmittance) => "specular_transmittance",
        _ => return None,
    })
}

/// Material `index` of the scene as a `materials:` entry.
pub(crate) fn write_material(
    y: &mut Yaml,
    ctx: &mut Context,
    m: &Material,
    index: usize,
) -> Result<(), LoadError> {
    let unsupported = |what: String| {
        LoadError::invalid(
            &ctx.source,
            format!("material `{}`", m.name),
            format!("{what}: scene format v1 cannot express it, so `ppm convert` cannot write it"),
        )
    };
    let mut fields = bsdf_fields(&m.bsdf);
    if let Some(textures) = &m.textures {
        for (slot, texture) in textures.slots() {
            let target = match fields.nested.as_deref_mut() {
                Some(nested) => nested,
                None => &mut fields,
            };
            let name = slot_field(target.kind, *slot).ok_or_else(|| {
                unsupported(format!(
                    "a texture on the {} of a {}",
                    slot.name(),
                    target.kind
                ))
            })?;
            match target.fields.iter_mut().find(|(n, _)| *n == name) {
                Some(field) => field.1 = Value::Texture(texture),
                None => target.fields.push((name, Value::Texture(texture))),
            }
        }
    }
    let kind = fields.kind;
    let interior = m.medium.interior != Vec3::ZERO;
    let exterior = m.medium.exterior != Vec3::ZERO;
    if interior && !matches!(kind, "glass" | "dielectric" | "roughdielectric") {
        return Err(unsupported(format!(
            "an absorbing medium inside a {kind} material"
        )));
    }
    if exterior && !matches!(kind, "dielectric" | "roughdielectric") {
        return Err(unsupported(format!(
            "an absorbing medium outside a {kind} material"
        )));
    }
    y.line(1, &format!("{}:", quoted(&m.name)));
    write_fields(y, ctx, &fields, 2, index)?;
    if m.emission != Vec3::ZERO {
        y.field(2, "emission", &triple(m.emission));
    }
    if interior {
        y.field(2, "absorption", &triple(m.medium.interior));
    }
    if exterior {
        y.field(2, "ext_absorption", &triple(m.medium.exterior));
    }
    Ok(())
}

/// `type:` and the fields of `f` at `depth`, the nested material of a `twosided` under `bsdf:`.
fn write_fields(
    y: &mut Yaml,
    ctx: &mut Context,
    f: &Fields,
    depth: usize,
    index: usize,
) -> Result<(), LoadError> {
    y.field(depth, "type", f.kind);
    for (name, value) in &f.fields {
        match value {
            Value::Text(t) => y.field(depth, name, t),
            Value::Texture(t) => {
                y.line(depth, &format!("{name}:"));
                write_texture(y, ctx, t, depth + 1, &format!("material{index}_{name}"))?;
            }
        }
    }
    if let Some(nested) = &f.nested {
        y.line(depth, "bsdf:");
        write_fields(y, ctx, nested, depth + 1, index)?;
    }
    Ok(())
}

/// The uv transform's fields: nothing for the identity, `scale` and `offset` when it is one,
/// else the general `to_uv`.
fn write_transform(y: &mut Yaml, t: &UvTransform, depth: usize) {
    let m = t.m;
    if *t == UvTransform::IDENTITY {
        return;
    }
    if m[1] == 0.0 && m[3] == 0.0 {
        y.field(depth, "scale", &list(&[m[0], m[4]]));
        y.field(depth, "offset", &list(&[m[2], m[5]]));
    } else {
        y.field(depth, "to_uv", &list(&m));
    }
}

/// A texture description at `depth`; a bitmap's texels go to an EXR file named from `stem`.
fn write_texture(
    y: &mut Yaml,
    ctx: &mut Context,
    t: &Texture,
    depth: usize,
    stem: &str,
) -> Result<(), LoadError> {
    match t {
        Texture::Constant(c) => {
            // Not a texture in the file: the constant colour itself.
            y.text.pop();
            y.text.push(' ');
            y.text.push_str(&triple(*c));
            y.text.push('\n');
        }
        Texture::Checkerboard(c) => {
            y.field(depth, "texture", "checkerboard");
            y.field(depth, "color0", &triple(c.color0));
            y.field(depth, "color1", &triple(c.color1));
            write_transform(y, &c.transform, depth);
        }
        Texture::Bitmap(b) => {
            let (width, height) = b.size();
            let (path, relative) = ctx.side_file(&format!("{stem}.exr"))?;
            super::files::write_exr(
                &path,
                width as usize,
                height as usize,
                b.texels(),
                "texture",
            )?;
            y.field(depth, "texture", "bitmap");
            y.field(depth, "file", &quoted(&relative));
            let filter = match b.filter {
                Filter::Nearest => "nearest",
                Filter::Bilinear => "bilinear",
            };
            let wrap = match b.wrap {
                WrapMode::Repeat => "repeat",
                WrapMode::Mirror => "mirror",
                WrapMode::Clamp => "clamp",
            };
            y.field(depth, "filter", filter);
            y.field(depth, "wrap", wrap);
            write_transform(y, &b.transform, depth);
        }
    }
    Ok(())
}

/// Indices whose ratio int / ext (in single precision, as the loader divides) is `eta`
/// exactly, each at least 1 as scene format v1 requires: `eta` over 1 for eta >= 1, else 1
/// over the single-precision number nearest 1 / eta whose reciprocal is `eta` (searched a few
/// ulps around 1 / eta; the nearest one is kept if none divides back exactly).
fn ior_pair(eta: f32) -> (f32, f32) {
    if eta >= 1.0 || eta.is_nan() || eta <= 0.0 {
        return (eta, 1.0);
    }
    let guess = 1.0 / eta;
    let mut candidates = vec![guess];
    let (mut up, mut down) = (guess, guess);
    for _ in 0..8 {
        up = f32::from_bits(up.to_bits() + 1);
        down = f32::from_bits(down.to_bits() - 1);
        candidates.push(up);
        candidates.push(down);
    }
    let ext = candidates
        .into_iter()
        .find(|&e| 1.0 / e == eta)
        .unwrap_or(guess);
    (1.0, ext)
}
