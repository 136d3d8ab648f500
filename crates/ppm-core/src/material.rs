//! A material: a BSDF and an optional emitted radiance.

use crate::bsdf::Bsdf;
use crate::medium::MediumInterface;
use glam::Vec3;

/// What a surface does with light: scatter it by `bsdf` and, when `emission` is non-zero,
/// emit radiance `emission` from the side its geometric normal points to.
#[derive(Clone, Debug)]
pub struct Material {
    pub bsdf: Bsdf,
    pub emission: Vec3,
    /// Name for messages (the scene's material name).
    pub name: String,
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

    /// True if the surface emits light.
    pub fn is_emissive(&self) -> bool {
        self.emission.max_element() > 0.0
    }
}
