//! The colours of a BSDF that textures drive, and how a textured material resolves to a
//! plain [`Bsdf`] at a hit.

use super::Texture;
use crate::bsdf::{luminance, Bsdf};

/// The scalar a colour texture gives where a float is wanted (a roughness): its luminance,
/// as Mitsuba 3 reads a colour texture as a float one; a grey is its own value exactly.
#[inline]
pub fn texture_scalar(c: Vec3) -> f32 {
    if c.x == c.y && c.y == c.z {
        c.x
    } else {
        luminance(c)
    }
}
use glam::{Vec2, Vec3};

/// A colour parameter of a BSDF (the names are Mitsuba 3's).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColourSlot {
    /// The Lambertian albedo: diffuse's `reflectance`, Phong's diffuse, plastic's
    /// `diffuse_reflectance`.
    DiffuseReflectance,
    /// The tint of specular or glossy reflection: a mirror's colour, Phong's specular,
    /// conductor's, plastic's and dielectric's `specular_reflectance`.
    SpecularReflectance,
    /// The tint of transmission: glass's colour, dielectric's `specular_transmittance`.
    SpecularTransmittance,
    /// The isotropic microfacet roughness alpha of a rough conductor or dielectric
    /// (Mitsuba's `alpha`): the texture's [`texture_scalar`] (its luminance, as Mitsuba reads
    /// a colour texture as a float one), clamped as a constant alpha is. A scalar, so the lobe changes
    /// width over the surface but keeps its distribution (GGX or Beckmann).
    Roughness,
}

impl ColourSlot {
    /// The name used in messages.
    pub fn name(self) -> &'static str {
        match self {
            ColourSlot::DiffuseReflectance => "diffuse reflectance",
            ColourSlot::SpecularReflectance => "specular reflectance",
            ColourSlot::SpecularTransmittance => "specular transmittance",
            ColourSlot::Roughness => "roughness",
        }
    }

    /// `bsdf` with this colour set to `c`; `None` if the model has no such colour.
    #[inline]
    pub fn set(self, bsdf: Bsdf, c: Vec3) -> Option<Bsdf> {
        use ColourSlot::*;
        let mut b = bsdf;
        match (&mut b, self) {
            (Bsdf::Diffuse(d), DiffuseReflectance) => d.albedo = c,
            (Bsdf::Phong(p), DiffuseReflectance) => p.diffuse = c,
            (Bsdf::Phong(p), SpecularReflectance) => p.specular = c,
            (Bsdf::Plastic(p), DiffuseReflectance) => {
                *p = p.with_reflectances(c, p.specular_reflectance)
            }
            (Bsdf::Plastic(p), SpecularReflectance) => {
                *p = p.with_reflectances(p.diffuse_reflectance, c)
            }
            (Bsdf::TwoSidedPlastic(t), DiffuseReflectance) => {
                t.0 = t.0.with_reflectances(c, t.0.specular_reflectance)
            }
            (Bsdf::TwoSidedPlastic(t), SpecularReflectance) => {
                t.0 = t.0.with_reflectances(t.0.diffuse_reflectance, c)
            }
            (Bsdf::Mirror(m), SpecularReflectance) => m.color = c,
            (Bsdf::Conductor(m), SpecularReflectance) => m.specular_reflectance = c,
            (Bsdf::TwoSidedConductor(t), SpecularReflectance) => t.0.specular_reflectance = c,
            (Bsdf::Dielectric(d), SpecularReflectance) => d.specular_reflectance = c,
            (Bsdf::Dielectric(d), SpecularTransmittance) => d.specular_transmittance = c,
            (Bsdf::ThinDielectric(d), SpecularReflectance) => d.specular_reflectance = c,
            (Bsdf::ThinDielectric(d), SpecularTransmittance) => d.specular_transmittance = c,
            (Bsdf::Glass(g), SpecularTransmittance) => g.color = c,
            (Bsdf::Conductor(m), Roughness) if m.roughness.is_some() => {
                m.roughness = m.roughness.map(|d| d.with_alpha(texture_scalar(c)))
            }
            (Bsdf::TwoSidedConductor(t), Roughness) if t.0.roughness.is_some() => {
                t.0.roughness = t.0.roughness.map(|d| d.with_alpha(texture_scalar(c)))
            }
            (Bsdf::Dielectric(d), Roughness) if d.roughness.is_some() => {
                d.roughness = d.roughness.map(|m| m.with_alpha(texture_scalar(c)))
            }
            (Bsdf::Diffuse(_), _)
            | (Bsdf::Phong(_), _)
            | (Bsdf::Plastic(_), _)
            | (Bsdf::TwoSidedPlastic(_), _)
            | (Bsdf::Mirror(_), _)
            | (Bsdf::Conductor(_), _)
            | (Bsdf::TwoSidedConductor(_), _)
            | (Bsdf::Dielectric(_), _)
            | (Bsdf::ThinDielectric(_), _)
            | (Bsdf::Glass(_), _) => return None,
        }
        Some(b)
    }
}

/// The textured colours of a material: each slot's texture, evaluated at a hit's uv and
/// written into a copy of the material's BSDF.
#[derive(Clone, Debug)]
pub struct TexturedColours {
    slots: Vec<(ColourSlot, Texture)>,
}

impl TexturedColours {
    /// The textures of `slots` over `bsdf`; an error names the first slot the model lacks.
    pub fn new(bsdf: &Bsdf, slots: Vec<(ColourSlot, Texture)>) -> Result<Self, ColourSlot> {
        for (slot, texture) in &slots {
            slot.set(*bsdf, texture.mean()).ok_or(*slot)?;
        }
        Ok(TexturedColours { slots })
    }

    /// The (slot, texture) pairs.
    pub fn slots(&self) -> &[(ColourSlot, Texture)] {
        &self.slots
    }

    /// `bsdf` with each slot's colour replaced by its texture's mean: the material's
    /// nominal BSDF, for the code that needs one constant (light power, diagnosis).
    pub fn mean_bsdf(&self, bsdf: Bsdf) -> Bsdf {
        self.slots
            .iter()
            .fold(bsdf, |b, (slot, t)| slot.set(b, t.mean()).unwrap_or(b))
    }

    /// `bsdf` with each slot's colour its texture's value at `uv`.
    #[inline]
    pub fn apply(&self, bsdf: Bsdf, uv: Vec2) -> Bsdf {
        self.slots
            .iter()
            .fold(bsdf, |b, (slot, t)| slot.set(b, t.eval(uv)).unwrap_or(b))
    }
}
