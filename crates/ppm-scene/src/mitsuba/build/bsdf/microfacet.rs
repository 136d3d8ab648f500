//! The microfacet parameters of `roughconductor`, `roughdielectric` and `roughplastic`:
//! `distribution`, `alpha` or `alpha_u`/`alpha_v`, `sample_visible`.

use crate::mitsuba::props::Props;
use crate::LoadError;
use ppm_core::bsdf::{Beckmann, Ggx, Microfacet};

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

/// A roughness: a finite, non-negative float (a texture is an error naming it).
fn alpha(p: &Props, name: &str) -> Result<Option<f64>, LoadError> {
    if let Some(prop) = p.get(name) {
        if let crate::mitsuba::tree::Value::Object(i) = prop.value {
            let o = &p.tree.objects[i];
            return Err(o.location.error(format!(
                "{} (as `{name}` of {}) is not supported yet: ppm takes a constant roughness",
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
