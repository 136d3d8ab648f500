//! The microfacet parameters of `roughconductor`, `roughdielectric` and `roughplastic`:
//! `distribution`, `alpha` or `alpha_u`/`alpha_v`, `sample_visible`.

use crate::mitsuba::build::texture::colour_or_texture;
use crate::mitsuba::props::Props;
use crate::mitsuba::spectrum::Role;
use crate::LoadError;
use glam::DVec3;
use ppm_core::bsdf::{Beckmann, Ggx, Microfacet};
use ppm_core::texture::texture_scalar;

/// Mitsuba 3's default roughness.
const DEFAULT_ALPHA: f64 = 0.1;

/// The microfacet distribution of the object: `distribution` `beckmann` (Mitsuba 3's default)
/// or `ggx`, of roughness `alpha` (default 0.1), or `alpha_u` along the tangent and `alpha_v`
/// along the bitangent when `anisotropic` is allowed (both, and not with `alpha`, as Mitsuba 3
/// requires). Both distributions are ppm's own, with the same D and separable Smith G as
/// Mitsuba's. `sample_visible` only changes Mitsuba's sampling, not the image: ppm samples
/// the visible normals for GGX and `D(m) cos(theta_m)` for Beckmann either way.
pub fn roughness(p: &Props, anisotropic: bool) -> Result<Microfacet, LoadError> {
    let beckmann = match p.string_opt("distribution")?.unwrap_or("beckmann") {
        "ggx" => false,
        "beckmann" => true,
        other => {
            return Err(p.error(format!(
                "{}: unknown distribution `{other}` (Mitsuba's are `beckmann` and `ggx`)",
                p.object.describe()
            )))
        }
    };
    p.boolean("sample_visible", true)?;
    let (alpha, u, v) = (
        alpha(p, "alpha")?,
        if anisotropic {
            alpha(p, "alpha_u")?
        } else {
            None
        },
        if anisotropic {
            alpha(p, "alpha_v")?
        } else {
            None
        },
    );
    let (ax, ay) = match (alpha, u, v) {
        (Some(_), Some(_), _) | (Some(_), _, Some(_)) => {
            return Err(p.error(format!(
                "{}: give either `alpha` or `alpha_u` and `alpha_v`, not both",
                p.object.describe()
            )))
        }
        (None, Some(u), Some(v)) => (u, v),
        (None, Some(_), None) | (None, None, Some(_)) => {
            return Err(p.error(format!(
                "{}: an anisotropic roughness needs both `alpha_u` and `alpha_v`",
                p.object.describe()
            )))
        }
        (a, None, None) => {
            let a = a.unwrap_or(DEFAULT_ALPHA);
            (a, a)
        }
    };
    Ok(if beckmann {
        Beckmann::new(ax as f32, ay as f32).into()
    } else {
        Ggx::new(ax as f32, ay as f32).into()
    })
}

/// A roughness: a finite, non-negative float, or for `alpha` of `roughconductor` and
/// `roughdielectric` a texture (bitmap or checkerboard), recorded for the material as its
/// [`ColourSlot::Roughness`](ppm_core::texture::ColourSlot::Roughness), whose mean's
/// [`texture_scalar`] is the nominal roughness. Other textures (anisotropic ones, roughplastic's,
/// whose coating tables are computed per roughness) are errors naming them.
fn alpha(p: &Props, name: &str) -> Result<Option<f64>, LoadError> {
    if let Some(prop) = p.get(name) {
        if let crate::mitsuba::tree::Value::Object(i) = prop.value {
            let o = &p.tree.objects[i];
            if name == "alpha" && o.class == "texture" && p.object.plugin != "roughplastic" {
                let mean = colour_or_texture(p, name, DVec3::splat(DEFAULT_ALPHA), Role::Index)?;
                return Ok(Some(texture_scalar(mean.as_vec3()) as f64));
            }
            return Err(o.location.error(format!(
                "{} (as `{name}` of {}) is not supported: ppm takes a texture roughness only as \
                 `alpha` of roughconductor and roughdielectric",
                o.describe(),
                p.object.describe()
            )));
        }
    }
    let a = p.float_opt(name)?;
    if let Some(a) = a {
        if !(a >= 0.0 && a.is_finite()) {
            return Err(p.error(format!(
                "{}: `{name}` {a} is not a roughness (a finite number >= 0)",
                p.object.describe()
            )));
        }
    }
    Ok(a)
}
