//! A material: a BSDF (whose colours may be textures) and an optional emitted radiance.

use crate::bsdf::Bsdf;
use crate::medium::MediumInterface;
use crate::texture::{ColourSlot, Texture, TexturedColours};
use glam::{Vec2, Vec3};

/// What a surface does with light: scatter it by `bsdf` and, when `emission` is non-zero,
/// emit radiance `emission` from the side its geometric normal points to.
#[derive(Clone, Debug)]
pub struct Material {
    /// The BSDF; with `textures`, its textured colours hold the textures' means (the
    /// nominal BSDF the code that needs one constant reads), and a hit reads
    /// [`Material::bsdf_at`].
    pub bsdf: Bsdf,
    pub emission: Vec3,
    /// Name for messages (the scene's material name).
    pub name: String,
    /// The BSDF colours that vary over the surface; `None` for a constant material (which
    /// then costs one branch per hit).
    pub textures: Option<Box<TexturedColours>>,
    /// The absorbing media on the surface's two sides (clear unless the scene says so);
    /// see [`crate::medium`] for the rule that decides which medium a segment is in.
    pub medium: MediumInterface,
}

impl Material {
    /// An unnamed material.
    pub fn new(bsdf: Bsdf, emission: Vec3) -> Self {
        Material {
            bsdf,
            emission,
            name: String::new(),
            textures: None,
            medium: MediumInterface::CLEAR,
        }
    }

    /// The same material bounding the absorbing media `medium`.
    pub fn with_medium(mut self, medium: MediumInterface) -> Self {
        self.medium = medium;
        self
    }

    /// The same material with a name.
    pub fn named(mut self, name: impl Into<String>) -> Self {
        self.name = name.into();
        self
    }

    /// The same material with the colours of `slots` given by textures (none: unchanged).
    /// Fails with the first slot the BSDF model does not have.
    pub fn textured(mut self, slots: Vec<(ColourSlot, Texture)>) -> Result<Self, ColourSlot> {
        if slots.is_empty() {
            return Ok(self);
        }
        let textures = TexturedColours::new(&self.bsdf, slots)?;
        self.bsdf = textures.mean_bsdf(self.bsdf);
        self.textures = Some(Box::new(textures));
        Ok(self)
    }

    /// True if the surface emits light.
    pub fn is_emissive(&self) -> bool {
        self.emission.max_element() > 0.0
    }

    /// The BSDF at texture coordinates `uv`: `bsdf` itself for a constant material, else
    /// a copy with every textured colour evaluated at `uv`. The one place textures meet
    /// shading: integrators ask [`crate::scene::Scene::bsdf`], which calls this.
    #[inline]
    pub fn bsdf_at(&self, uv: Vec2) -> Bsdf {
        match &self.textures {
            None => self.bsdf,
            Some(t) => t.apply(self.bsdf, uv),
        }
    }
}
