//! The integrators' settings in words, for the summary a render prints
//! ([`super::Integrator::settings_words`]).

use super::{DirectMode, Radius, RenderSettings};
use std::ops::Range;

/// Significant digits of a number a person reads (radii, alpha).
const SIGNIFICANT_DIGITS: i32 = 4;

/// `x` to [`SIGNIFICANT_DIGITS`] significant digits without trailing zeros, so that a
/// summary reads `radius 0.03 -> 0.01051 (alpha 0.6667)`, not the float noise of
/// `0.010510092` and `0.6666667`; values given short (`0.7`, `200`) print as given.
pub(crate) fn significant(x: f32) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let x = f64::from(x);
    let exponent = x.abs().log10().floor() as i32;
    if !(-4..7).contains(&exponent) {
        let text = format!("{:.*e}", (SIGNIFICANT_DIGITS - 1) as usize, x);
        let (mantissa, power) = text.split_once('e').unwrap_or((&text, "0"));
        return format!("{}e{power}", trim_zeros(mantissa));
    }
    let decimals = (SIGNIFICANT_DIGITS - 1 - exponent).max(0) as usize;
    trim_zeros(&format!("{x:.decimals$}")).to_string()
}

/// `1.2300` -> `1.23`, `2.000` -> `2`; a number without a decimal point is left alone.
fn trim_zeros(text: &str) -> &str {
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.')
    } else {
        text
    }
}

/// The radius schedule's value in the first and the last of the iterations `image` (0-based)
/// holds: r_{start+1} and r_end (a shard of iterations 4..8 used r_5 to r_8).
pub(crate) fn schedule_range(settings: &RenderSettings, image: Range<u64>) -> (f32, f32) {
    let at = |iteration: u64| settings.radius_schedule_at(iteration.max(1)).radius();
    (at(image.start + 1), at(image.end))
}

/// The radius of a schedule shared by every pixel (scaled per pixel by a per-pixel rule,
/// which `rule_words(rule)` describes, `rule` being `auto` or `photons`): `0.03 -> 0.0112`,
/// or `<rule_words>, shrunk x1 -> x0.37`.
pub(crate) fn scheduled_radius(
    settings: &RenderSettings,
    image: Range<u64>,
    rule_words: impl Fn(&str) -> String,
) -> String {
    let (first, last) = schedule_range(settings, image);
    match settings.radius {
        Radius::World(_) => format!("{} -> {}", significant(first), significant(last)),
        Radius::Auto | Radius::Photons => format!(
            "{}, shrunk x{} -> x{}",
            rule_words(&settings.radius.to_string()),
            significant(first),
            significant(last)
        ),
    }
}

/// Photon mapping's settings: `seed 1, 200000 photons (light paths) per iteration, radius
/// <radius> (alpha 0.7), direct light sampled`.
pub(crate) fn photon_mapping(settings: &RenderSettings, radius: &str) -> String {
    format!(
        "seed {}, {} photons (light paths) per iteration, radius {radius} (alpha {}), \
         direct light {}",
        settings.seed,
        settings.photons,
        significant(settings.alpha),
        match settings.direct {
            DirectMode::Photons => "from photons",
            DirectMode::Sampled => "sampled",
        }
    )
}

#[cfg(test)]
mod tests {
    use super::significant;

    #[test]
    fn numbers_print_without_float_noise() {
        assert_eq!(significant(0.010510092), "0.01051");
        assert_eq!(significant(2.0 / 3.0), "0.6667");
        assert_eq!(significant(0.7), "0.7");
        assert_eq!(significant(0.03), "0.03");
        assert_eq!(significant(200.0), "200");
        assert_eq!(significant(123456.0), "123456");
        assert_eq!(significant(-1.5), "-1.5");
        assert_eq!(significant(0.0), "0");
        assert_eq!(significant(1.23456e-7), "1.235e-7");
        assert_eq!(significant(9.99996), "10");
    }
}
