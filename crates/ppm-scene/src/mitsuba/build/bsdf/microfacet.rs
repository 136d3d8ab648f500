//! The microfacet parameters of `roughconductor`, `roughdielectric` and `roughplastic`:
//! `distribution`, `alpha` or `alpha_u`/`alpha_v`, `sample_visible`.

use crate::mitsuba::props::Props;
use crate::LoadError;
use ppm_core::bsdf::Ggx;

/// Mitsuba 3's default roughness.
const DEFAULT_ALPHA: f64 = 0.1;

/// The GGX distribution of the object's roughness: `alpha` (default 0.1), or `alpha_u` along
/// the tangent and `alpha_v` along the bitangent when `anisotropic` is allowed (both, and
/// not with `alpha`, as Mitsuba 3 requires).
///
/// ppm's one microfacet distribution is GGX (Trowbridge-Reitz). Mitsuba 3's default
/// `distribution` is `beckmann`; it is rendered as GGX of the same alpha, with a warning: the
/// two agree near the mirror direction's peak for small alpha (both tend to the same
/// Gaussian-like lobe of width alpha), but GGX has longer tails (its D falls off as
/// `1 / tan^4 theta`, Beckmann's as `exp(-tan^2 theta / alpha^2)`), so highlights get a
/// wider glow and rough surfaces look slightly different. `sample_visible` only changes
/// Mitsuba's sampling, not the image: ppm always samples the visible normals.
pub fn roughness(
    p: &Props,
    anisotropic: bool,
    warnings: &mut Vec<String>,
) -> Result<Ggx, LoadError> {
    let distribution = p.string_opt("distribution")?.unwrap_or("beckmann");
    match distribution {
        "ggx" => {}
        "beckmann" => warnings.push(format!(
            "{}: {}: distribution `beckmann`{} is rendered as GGX of the same alpha: ppm has only GGX, whose highlights have longer tails",
            p.location(),
            p.object.describe(),
            if p.get("distribution").is_some() { "" } else { " (Mitsuba's default)" }
        )),
        other => {
            return Err(p.error(format!(
                "{}: unknown distribution `{other}` (Mitsuba's are `beckmann` and `ggx`)",
                p.object.describe()
            )))
        }
    }
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
    Ok(Ggx::new(ax as f32, ay as f32))
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
