//! What a render used, in words: the settings line of the summary (seed, photons, radius) and
//! the `-v` lines printed before rendering.

use crate::args::RenderArgs;
use anyhow::Result;
use ppm_core::integrator::{Algorithm, Features, RenderSettings};
use ppm_core::pixel_bounds::PixelBounds;
use std::ops::Range;
use std::path::Path;

/// The iterations a render with `algorithm` asks for: `-n`, or `--spp` (for an integrator
/// that takes one sample per pixel per iteration, so N samples per pixel are N iterations).
pub fn requested_iterations(args: &RenderArgs, algorithm: Algorithm) -> Result<Option<u64>> {
    match args.spp {
        None => Ok(args.iterations),
        Some(spp) if algorithm.features().sample_per_iteration => Ok(Some(spp)),
        Some(_) => usage_bail!(
            "--spp is for the path tracer (-a {}), where it equals -n. Photon mapping (-a ppm) \
             and VCM (-a vcm) render in iterations, each one camera path per pixel gathering a new photon map \
             with a smaller radius: give -n ITERATIONS instead",
            names(|f| f.sample_per_iteration)
        ),
    }
}

/// The names of the algorithms whose features `have`, as `-a` takes them: `ppm or -a sppm`.
pub fn names(have: impl Fn(&Features) -> bool) -> String {
    Algorithm::ALL
        .into_iter()
        .filter(|a| have(&a.features()))
        .map(Algorithm::name)
        .collect::<Vec<_>>()
        .join(" or -a ")
}

/// The summary's settings line, e.g. `seed 1, 200000 photons (light paths) per iteration,
/// radius 0.03 -> 0.0112 (alpha 0.7), direct light sampled, max depth 32, 2 threads` for
/// photon mapping and `seed 1, 16 samples per pixel, max depth 32, 2 threads` for the path
/// tracer: the integrator's own words ([`Algorithm::settings_words`]) for `image`, the range
/// of iterations (0-based) the image holds (a resumed render's or a shard's radii are those of
/// its own iterations, and its samples per pixel are all those in the image).
pub fn settings_line(settings: &RenderSettings, image: Range<u64>, threads: usize) -> String {
    format!(
        "{}, max depth {}, {threads} thread{}",
        settings.algorithm.settings_words(settings, image),
        settings.max_depth,
        if threads == 1 { "" } else { "s" }
    )
}

/// The `-v` lines: where the scene was found and by which rule of the scene search
/// ([`crate::scene_search`]), the image and the crop window.
pub fn verbose_lines(
    scene_path: &Path,
    found_by: &str,
    width: u32,
    height: u32,
    bounds: &PixelBounds,
) -> String {
    let mut s = format!(
        "scene {} (found {found_by})\nimage {width}x{height}",
        scene_path.display()
    );
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
    use ppm_core::integrator::{DirectMode, LightStrategy, Radius};

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
        assert_eq!(
            settings(Algorithm::Ppm).radius_schedule_at(1).radius(),
            0.04
        );
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
