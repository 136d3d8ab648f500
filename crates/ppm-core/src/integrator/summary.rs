//! The integrators' settings in words, for the summary a render prints
//! ([`super::Integrator::settings_words`]).

use super::{DirectMode, Radius, RenderSettings};
use std::ops::Range;

/// The radius schedule's value in the first and the last of the iterations `image` (0-based)
/// holds: r_{start+1} and r_end (a shard of iterations 4..8 used r_5 to r_8).
pub(crate) fn schedule_range(settings: &RenderSettings, image: Range<u64>) -> (f32, f32) {
    let at = |iteration: u64| settings.radius_schedule_at(iteration.max(1)).radius();
    (at(image.start + 1), at(image.end))
}

/// The radius of a schedule shared by every pixel (scaled per pixel with `auto`, which
/// `auto_words` describes): `0.03 -> 0.0112`, or `<auto_words>, shrunk x1 -> x0.37`.
pub(crate) fn scheduled_radius(
    settings: &RenderSettings,
    image: Range<u64>,
    auto_words: &str,
) -> String {
    let (first, last) = schedule_range(settings, image);
    match settings.radius {
        Radius::World(_) => format!("{first} -> {last}"),
        Radius::Auto => format!("{auto_words}, shrunk x{first} -> x{last}"),
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
        settings.alpha,
        match settings.direct {
            DirectMode::Photons => "from photons",
            DirectMode::Sampled => "sampled",
        }
    )
}
