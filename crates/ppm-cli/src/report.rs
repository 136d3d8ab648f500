//! What a render used, in words: the settings line of the summary (seed, photons, radius) and
//! the `-v` lines printed before rendering.

use crate::args::{AlgorithmArg, RenderArgs};
use anyhow::Result;
use ppm_core::integrator::{Algorithm, DirectMode, Radius, RadiusSchedule, RenderSettings};
use ppm_core::pixel_bounds::PixelBounds;
use std::ops::Range;
use std::path::Path;

/// The iterations a render with `algorithm` asks for: `-n`, or `--spp` (path tracing only:
/// one sample per pixel per iteration, so N samples per pixel are N iterations).
pub fn requested_iterations(args: &RenderArgs, algorithm: AlgorithmArg) -> Result<Option<u64>> {
    match (args.spp, algorithm.algorithm()) {
        (None, _) => Ok(args.iterations),
        (Some(spp), Algorithm::Path) => Ok(Some(spp)),
        (Some(_), Algorithm::Ppm | Algorithm::Sppm | Algorithm::Vcm) => usage_bail!(
            "--spp is for the path tracer (-a pt), where it equals -n. Photon mapping (-a ppm) \
             and VCM (-a vcm) render in iterations, each one camera path per pixel gathering a new photon map \
             with a smaller radius: give -n ITERATIONS instead"
        ),
    }
}

/// The radius `ppm` used in iteration `iteration` (1-based): in scene units for a world
/// radius; for `auto` the factor every pixel's footprint radius has shrunk by.
pub fn radius_at(settings: &RenderSettings, iteration: u64) -> f32 {
    let start = match settings.radius {
        Radius::World(r) => r,
        Radius::Auto => 1.0,
    };
    let mut schedule = RadiusSchedule::new(start, settings.alpha);
    for _ in 1..iteration.max(1) {
        schedule.advance();
    }
    schedule.radius()
}

/// The summary's settings line, e.g. `seed 1, 200000 photons (light paths) per iteration,
/// radius 0.03 -> 0.0112 (alpha 0.7), direct light sampled, max depth 32, 2 threads` for
/// photon mapping and `seed 1, 16 samples per pixel, max depth 32, 2 threads` for the path
/// tracer. `image` is the range of iterations (0-based) the image holds: a resumed render's
/// or a shard's radii are those of its own iterations (a shard of iterations 4..8 of a render
/// used r_5 to r_8), and its samples per pixel are all those in the image.
pub fn settings_line(settings: &RenderSettings, image: Range<u64>, threads: usize) -> String {
    let iterations = image.end - image.start;
    let common = format!(
        "max depth {}, {threads} thread{}",
        settings.max_depth,
        if threads == 1 { "" } else { "s" }
    );
    match settings.algorithm {
        Algorithm::Path => format!(
            "seed {}, {iterations} sample{} per pixel, {common}",
            settings.seed,
            if iterations == 1 { "" } else { "s" }
        ),
        Algorithm::Ppm | Algorithm::Sppm => format!(
            "seed {}, {} photons (light paths) per iteration, radius {} (alpha {}), \
             direct light {}, {common}",
            settings.seed,
            settings.photons,
            radius_words(settings, image.clone()),
            settings.alpha,
            match settings.direct {
                DirectMode::Photons => "from photons",
                DirectMode::Sampled => "sampled",
            }
        ),
        Algorithm::Vcm => format!(
            "seed {}, one light path per pixel per iteration, merge radius {} (alpha {}), \
             {common}",
            settings.seed,
            radius_words(settings, image.clone()),
            settings.alpha,
        ),
    }
}

/// The radius part of the settings line: `ppm`'s first -> last radius (world) or factor
/// (`auto`), or for `sppm` the start (each pixel's radius then shrinks with its own photons).
fn radius_words(settings: &RenderSettings, image: Range<u64>) -> String {
    let first = radius_at(settings, image.start + 1);
    let last = radius_at(settings, image.end);
    match (settings.algorithm, settings.radius) {
        (Algorithm::Sppm, Radius::World(r)) => format!("{r} at the start, then per pixel"),
        (Algorithm::Sppm, Radius::Auto) => "auto (per pixel)".to_string(),
        (Algorithm::Vcm, Radius::Auto) => {
            format!("auto (median footprint), shrunk x{first} -> x{last}")
        }
        (_, Radius::World(_)) => format!("{first} -> {last}"),
        (_, Radius::Auto) => format!("auto (per pixel), shrunk x{first} -> x{last}"),
    }
}

/// The `-v` lines: where the scene was found, the image and the crop window.
pub fn verbose_lines(scene_path: &Path, width: u32, height: u32, bounds: &PixelBounds) -> String {
    let mut s = format!("scene {}\nimage {width}x{height}", scene_path.display());
    if bounds.len() != width as usize * height as usize {
        s += &format!(
            ", rendering pixels {}..{} x {}..{} ({}x{})",
            bounds.x0,
            bounds.x1,
            bounds.y0,
            bounds.y1,
            bounds.width(),
            bounds.height()
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use ppm_core::integrator::LightStrategy;

    fn settings(algorithm: Algorithm) -> RenderSettings {
        RenderSettings {
            algorithm,
            seed: 5,
            max_depth: 8,
            rr_depth: 3,
            light_strategy: LightStrategy::Mis,
            photons: 1000,
            radius: Radius::World(0.04),
            alpha: 0.5,
            direct: DirectMode::Sampled,
        }
    }

    #[test]
    fn the_settings_used_are_said() {
        assert_eq!(
            settings_line(&settings(Algorithm::Path), 0..16, 2),
            "seed 5, 16 samples per pixel, max depth 8, 2 threads"
        );
        // r_i^2 = r_1^2 prod_{k=1}^{i-1} (k + alpha) / (k + 1): with alpha 0.5, r_3^2 =
        // 0.0016 * 0.75 * 2.5 / 3 = 0.001, r_3 = 0.0316...
        let line = settings_line(&settings(Algorithm::Ppm), 0..3, 1);
        assert!(
            line.starts_with(
                "seed 5, 1000 photons (light paths) per iteration, radius 0.04 -> 0.0316"
            ) && line.ends_with("(alpha 0.5), direct light sampled, max depth 8, 1 thread"),
            "{line}"
        );
        assert_eq!(radius_at(&settings(Algorithm::Ppm), 1), 0.04);
        // A resumed render or a shard holding iterations 2..3: r_3 only, one sample.
        let line = settings_line(&settings(Algorithm::Ppm), 2..3, 1);
        assert!(
            line.contains("radius 0.0316") && line.contains("-> 0.0316"),
            "{line}"
        );
        assert_eq!(
            settings_line(&settings(Algorithm::Path), 4..16, 2),
            "seed 5, 12 samples per pixel, max depth 8, 2 threads"
        );
    }
}
