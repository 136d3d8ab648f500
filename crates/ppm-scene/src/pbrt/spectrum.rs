//! pbrt-v4's spectra as the RGB that renders the same in an RGB renderer with pbrt-v4's
//! default sRGB output.
//!
//! pbrt-v4 turns an `rgb` value into a spectrum by its role (pbrt-v4 book, section 4.6.6):
//! - a reflectance becomes an `RGBAlbedoSpectrum`, the smooth spectrum whose reflection of
//!   the colour space's illuminant (D65 for sRGB) has that RGB: it renders as the RGB itself;
//! - a light's `L` or `I` becomes an `RGBIlluminantSpectrum`, that albedo spectrum times the
//!   illuminant D65, and the light's `scale` is divided by `SpectrumToPhotometric(L)`, the
//!   luminance of the illuminant alone (`lights.cpp`): so an `rgb L [r g b]` is radiance
//!   whose sRGB is (r, g, b), luminance 0.2126 r + 0.7152 g + 0.0722 b;
//! - any other emission spectrum (a `blackbody`, sampled values, a named illuminant) is
//!   divided by its own luminance: it emits luminance 1 (times `scale`) with the
//!   chromaticity of the spectrum. Its RGB here is `M XYZ / Y`, XYZ integrated against the
//!   CIE 1931 colour-matching functions (`mitsuba/spectrum.rs`, which has the tables).
//! - `eta` and `k` (unbounded spectra) are RGB per channel, or pbrt's named metals, which
//!   map to the metals table ppm has (Mitsuba's measured data reduced to RGB; pbrt-v4 ships
//!   its own measurements of the same metals, so the colours differ slightly).

use crate::mitsuba::spectrum::{to_rgb, Role};
use crate::mitsuba::tree::Spectrum;
use glam::DVec3;
use ppm_core::bsdf::metals;

/// A spectrum-valued parameter as written.
#[derive(Clone, Debug, PartialEq)]
pub enum SpectrumValue {
    Rgb(DVec3),
    /// A black body at this temperature, kelvin.
    Blackbody(f64),
    /// (wavelength nm, value) pairs, increasing.
    Samples(Vec<(f64, f64)>),
    /// A named spectrum (`metal-Au-eta`, `stdillum-D65`, `glass-BK7`) or a file name.
    Named(String),
    /// A texture's name (resolved by the build layer).
    Texture(String),
}

/// The luminance of a linear sRGB colour (the Y row of sRGB-to-XYZ).
pub fn luminance(c: DVec3) -> f64 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}

/// A reflectance (pbrt's `SpectrumType::Albedo`): each channel in [0, 1].
pub fn albedo_rgb(s: &SpectrumValue) -> Result<DVec3, String> {
    match s {
        SpectrumValue::Rgb(c) => {
            if c.min_element() < 0.0 || c.max_element() > 1.0 {
                Err(format!(
                    "the reflectance {c} has a component outside [0, 1]"
                ))
            } else {
                Ok(*c)
            }
        }
        SpectrumValue::Samples(samples) => {
            to_rgb(&Spectrum::Samples(samples.clone()), Role::Reflectance)
        }
        SpectrumValue::Blackbody(_) => Err("a blackbody is an emission, not a reflectance".into()),
        SpectrumValue::Named(n) => Err(format!(
            "the named spectrum \"{n}\" is not supported as a reflectance"
        )),
        SpectrumValue::Texture(_) => Err("a texture, resolved elsewhere".into()),
    }
}

/// An emission spectrum (pbrt's `SpectrumType::Illuminant`) after pbrt-v4's photometric
/// normalisation, as linear sRGB (see the module documentation).
pub fn illuminant_rgb(s: &SpectrumValue) -> Result<DVec3, String> {
    let per_luminance = |spectrum: Spectrum| -> Result<DVec3, String> {
        let rgb = to_rgb(&spectrum, Role::Emission)?;
        let y = luminance(rgb);
        if !(y > 0.0 && y.is_finite()) {
            return Err("the spectrum has no luminance".into());
        }
        Ok(rgb / y)
    };
    match s {
        SpectrumValue::Rgb(c) => {
            if c.min_element() < 0.0 || !c.is_finite() {
                Err(format!("the emission {c} is negative"))
            } else {
                Ok(*c)
            }
        }
        SpectrumValue::Blackbody(t) => {
            if !(*t > 0.0 && t.is_finite()) {
                return Err(format!("blackbody temperature {t} is not positive"));
            }
            per_luminance(Spectrum::Blackbody {
                temperature: *t,
                scale: 1.0,
            })
        }
        SpectrumValue::Samples(samples) => {
            if samples.iter().any(|s| s.1 < 0.0) {
                return Err("the spectrum has negative values".into());
            }
            per_luminance(Spectrum::Samples(samples.clone()))
        }
        // The colour space's white: D65, luminance 1, is sRGB (1, 1, 1).
        SpectrumValue::Named(n) if n == "stdillum-D65" => Ok(DVec3::ONE),
        SpectrumValue::Named(n) => Err(format!(
            "the named spectrum \"{n}\" is not supported as an emission yet (stdillum-D65, rgb, blackbody or sampled spectra are)"
        )),
        SpectrumValue::Texture(_) => Err("a texture cannot be an emission".into()),
    }
}

/// Which half of a complex index of refraction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum IorPart {
    Eta,
    K,
}

/// pbrt-v4's named metals (`metal-<X>-eta`, `metal-<X>-k`) that ppm's table has.
pub const METALS: [&str; 6] = ["Ag", "Al", "Au", "Cu", "MgO", "TiO2"];

/// An `eta` or `k` of a conductor: RGB, or a named metal's spectrum.
pub fn conductor_rgb(s: &SpectrumValue, part: IorPart) -> Result<DVec3, String> {
    let suffix = match part {
        IorPart::Eta => "-eta",
        IorPart::K => "-k",
    };
    match s {
        SpectrumValue::Rgb(c) if c.min_element() >= 0.0 => Ok(*c),
        SpectrumValue::Named(n) => {
            let metal = n
                .strip_prefix("metal-")
                .and_then(|m| m.strip_suffix(suffix))
                .filter(|m| METALS.contains(m))
                .and_then(metals::metal)
                .ok_or_else(|| {
                    format!(
                        "\"{n}\" is not a named metal ppm knows (metal-<X>{suffix} with X one of {})",
                        METALS.join(", ")
                    )
                })?;
            Ok(match part {
                IorPart::Eta => metal.eta,
                IorPart::K => metal.k,
            }
            .as_dvec3())
        }
        SpectrumValue::Rgb(c) => Err(format!("{c} is negative")),
        _ => Err("only rgb values and named metals are supported yet".into()),
    }
}

/// pbrt-v4's named glasses as a single index of refraction: their Sellmeier dispersion
/// evaluated at 550 nm (ppm does not render dispersion). `None` for other names.
pub fn glass_eta(name: &str) -> Option<f64> {
    // Sellmeier coefficients (B1, B2, B3, C1, C2, C3), C in um^2, from the manufacturers'
    // catalogues (SCHOTT) as pbrt-v4's `glass-*` spectra are sampled from.
    let c: [f64; 6] = match name {
        "glass-BK7" => [
            1.03961212,
            0.231792344,
            1.01046945,
            0.00600069867,
            0.0200179144,
            103.560653,
        ],
        "glass-BAF10" => [
            1.5851495,
            0.143559385,
            1.08521269,
            0.00926681282,
            0.0424489805,
            105.613573,
        ],
        "glass-FK51A" => [
            0.971247817,
            0.216901417,
            0.904651666,
            0.00472301995,
            0.0153575612,
            168.68133,
        ],
        "glass-LASF9" => [
            2.00029547,
            0.298926886,
            1.80691843,
            0.0121426017,
            0.0538736236,
            156.530829,
        ],
        "glass-F5" => [
            1.3104463,
            0.19603426,
            0.96612977,
            0.00958633048,
            0.0457627627,
            115.011883,
        ],
        "glass-F10" => [
            1.62153902,
            0.256287842,
            1.64447552,
            0.0122241457,
            0.0595736775,
            147.468793,
        ],
        "glass-F11" => [
            1.73759695,
            0.313747346,
            1.89878101,
            0.013188707,
            0.0623068142,
            155.23629,
        ],
        _ => return None,
    };
    let l2 = 0.55f64 * 0.55;
    let n2 = 1.0 + c[0] * l2 / (l2 - c[3]) + c[1] * l2 / (l2 - c[4]) + c[2] * l2 / (l2 - c[5]);
    Some(n2.sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rgb_light_is_its_rgb_and_blackbody_has_unit_luminance() {
        let c = DVec3::new(17.0, 12.0, 4.0);
        assert_eq!(illuminant_rgb(&SpectrumValue::Rgb(c)).unwrap(), c);
        for t in [2700.0, 6500.0, 10000.0] {
            let rgb = illuminant_rgb(&SpectrumValue::Blackbody(t)).unwrap();
            assert!((luminance(rgb) - 1.0).abs() < 1e-9, "{t}: {rgb}");
        }
        // A warm black body is redder than a cool one.
        let warm = illuminant_rgb(&SpectrumValue::Blackbody(2700.0)).unwrap();
        let cool = illuminant_rgb(&SpectrumValue::Blackbody(10000.0)).unwrap();
        assert!(warm.x > warm.z && cool.z > cool.x, "{warm} {cool}");
        // 6504 K is close to D65, sRGB's white.
        let d65 = illuminant_rgb(&SpectrumValue::Blackbody(6504.0)).unwrap();
        assert!((d65 - DVec3::ONE).abs().max_element() < 0.12, "{d65}");
    }

    #[test]
    fn named_metals_and_glasses() {
        let au = conductor_rgb(&SpectrumValue::Named("metal-Au-eta".into()), IorPart::Eta);
        assert_eq!(au.unwrap(), metals::metal("Au").unwrap().eta.as_dvec3());
        let k = conductor_rgb(&SpectrumValue::Named("metal-Cu-k".into()), IorPart::K);
        assert_eq!(k.unwrap(), metals::metal("Cu").unwrap().k.as_dvec3());
        let e = conductor_rgb(&SpectrumValue::Named("metal-Au-k".into()), IorPart::Eta);
        assert!(e.unwrap_err().contains("metal-<X>-eta"));
        assert!(
            conductor_rgb(&SpectrumValue::Named("metal-CuZn-eta".into()), IorPart::Eta).is_err()
        );
        // BK7's index at the sodium d line region is 1.5168; at 550 nm, 1.5185.
        let bk7 = glass_eta("glass-BK7").unwrap();
        assert!((bk7 - 1.5185).abs() < 5e-4, "{bk7}");
        assert!(glass_eta("glass-XYZ").is_none());
    }

    #[test]
    fn reflectances_are_bounded() {
        assert!(albedo_rgb(&SpectrumValue::Rgb(DVec3::new(0.5, 1.2, 0.0))).is_err());
        let flat = albedo_rgb(&SpectrumValue::Samples(vec![(300.0, 0.5), (900.0, 0.5)])).unwrap();
        assert!(
            (flat - DVec3::splat(0.5)).abs().max_element() < 0.01,
            "{flat}"
        );
    }
}
