//! Textures: colours that vary over a surface with its (u, v) coordinates.
//!
//! A closed set of models, one file per model, dispatched by a thin `match` (as the BSDFs
//! are): [`Texture::Constant`], [`Bitmap`] (an RGB image, filtered and wrapped) and
//! [`Checkerboard`]. The conventions are Mitsuba 3's (`bitmap`, `checkerboard`): a texture
//! first maps the surface's uv by its [`UvTransform`] (Mitsuba's `to_uv`), then looks it up;
//! uv = (0, 0) is the image's top-left corner, u grows to the right and v downward.
//!
//! Textures hold linear RGB values: decoding a file (and sRGB to linear) is the scene
//! loader's job. Integrators never see a texture: a [`crate::material::Material`] resolves
//! its textures at a hit to a plain [`crate::bsdf::Bsdf`] (`Material::bsdf_at`).

mod bitmap;
mod checkerboard;
mod colours;
mod srgb;

pub use bitmap::{Bitmap, Filter, WrapMode};
pub use checkerboard::Checkerboard;
pub use colours::{texture_scalar, ColourSlot, TexturedColours};
pub use srgb::srgb_to_linear;

use glam::{Vec2, Vec3};

/// The affine map a texture applies to the surface's uv before the look-up: Mitsuba's
/// `to_uv` (the upper-left 3 x 3 of its 4 x 4 matrix applied to the point (u, v, 1)).
/// `u' = m[0] u + m[1] v + m[2]`, `v' = m[3] u + m[4] v + m[5]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UvTransform {
    pub m: [f32; 6],
}

impl UvTransform {
    /// uv unchanged.
    pub const IDENTITY: UvTransform = UvTransform {
        m: [1.0, 0.0, 0.0, 0.0, 1.0, 0.0],
    };

    /// `uv * scale + offset`, per coordinate (Mitsuba's `to_uv` of a `scale` then a
    /// `translate`; pbrt-v4's `uscale`, `vscale`, `udelta`, `vdelta`).
    pub fn scale_offset(scale: Vec2, offset: Vec2) -> Self {
        UvTransform {
            m: [scale.x, 0.0, offset.x, 0.0, scale.y, offset.y],
        }
    }

    /// The transformed uv.
    #[inline]
    pub fn apply(&self, uv: Vec2) -> Vec2 {
        let m = &self.m;
        Vec2::new(
            m[0] * uv.x + m[1] * uv.y + m[2],
            m[3] * uv.x + m[4] * uv.y + m[5],
        )
    }
}

/// A colour over the surface's uv.
#[derive(Clone, Debug)]
pub enum Texture {
    /// The same colour everywhere.
    Constant(Vec3),
    /// An RGB image (see [`Bitmap`]).
    Bitmap(Bitmap),
    /// Two colours in a checkerboard (see [`Checkerboard`]).
    Checkerboard(Checkerboard),
}

impl Texture {
    /// The colour at surface coordinates `uv`.
    #[inline]
    pub fn eval(&self, uv: Vec2) -> Vec3 {
        match self {
            Texture::Constant(c) => *c,
            Texture::Bitmap(b) => b.eval(uv),
            Texture::Checkerboard(c) => c.eval(uv),
        }
    }

    /// The colour averaged over one period of the texture (the unit square of transformed
    /// uv): what stands in for the texture where a constant is needed (a material's nominal
    /// BSDF, which the light-power and diagnosis code read, and the BSDF's lobe flags).
    pub fn mean(&self) -> Vec3 {
        match self {
            Texture::Constant(c) => *c,
            Texture::Bitmap(b) => b.mean(),
            Texture::Checkerboard(c) => c.mean(),
        }
    }

    /// The largest value of any channel anywhere (a texel or a colour): the lobe flags use
    /// it, so that a lobe black on average but not everywhere is still sampled.
    pub fn max_value(&self) -> f32 {
        match self {
            Texture::Constant(c) => c.max_element(),
            Texture::Bitmap(b) => b.max_value(),
            Texture::Checkerboard(c) => c.color0.max_element().max(c.color1.max_element()),
        }
    }
}
