//! End-to-end: stochastic progressive photon mapping converges to the path tracer's image on
//! the four shipped scenes (small), by image mean and per pixel.

use ppm_test_support::test_scenes;

use ppm_core::prelude::*;
use ppm_tests::{load_small, SCENES};

use test_scenes::{assert_converges_to_pt, render_stats, sppm_stats};

/// Per scene: resolution and path-traced iterations of the reference.
///
/// The water and glossy boxes need more: on cornell_box_water.yml the water's surface mirrors
/// the lamp onto the ceiling and walls (caustics of light paths L-S-D-E that the path tracer
/// finds only when a BSDF-sampled direction meets the lamp's mirror image and the Fresnel
/// choice picks reflection). At 1000 iterations most pixels have not seen one such path, so
/// the path tracer's per-pixel means and variance estimates both fall short: measured at
/// 48x40, 722 of 5760 channels beyond 4 sigma, every one with the path tracer below SPPM;
/// at 5000 iterations 43, at 10000 iterations 3 (mean z^2 1.17). 48x40 halves the
/// standard error of the image mean against 24x20, where pixel sampling of the lamp's edge
/// dominates it.
const CASES: [(&str, u32, u32, u32); 4] = [
    ("cornell_box.yml", 24, 20, 1000),
    ("cornell_box_specular.yml", 24, 20, 1000),
    ("cornell_box_water.yml", 48, 40, 10_000),
    ("cornell_box_glossy.yml", 48, 40, 2000),
];

#[test]
fn sppm_converges_to_the_path_traced_image_on_every_scene() {
    assert_eq!(CASES.map(|c| c.0), SCENES);
    for (name, width, height, pt_iterations) in CASES {
        let scene = load_small(name, width, height).build().unwrap();
        let pt = render_stats(
            &scene,
            &RenderSettings {
                seed: 1,
                ..RenderSettings::for_algorithm(&scene, Algorithm::Path)
            },
            pt_iterations,
        );
        let settings = RenderSettings {
            photons: SPPM_PHOTONS,
            seed: 1000,
            ..RenderSettings::for_algorithm(&scene, Algorithm::Sppm)
        };
        let sppm = sppm_stats(&scene, &settings, SPPM_SEEDS, SPPM_ITERATIONS);
        // Per pixel: z = difference over its standard error, the SPPM side estimated from the
        // spread of independent renders (Student's t with seeds - 1 degrees of freedom, so a
        // few |z| > 4 are expected by chance: P = 1e-3 per value at 15 degrees of freedom).
        // SPPM is consistent, not unbiased: its remaining bias within a radius of concave
        // corners may show in a few more pixels; an error in a factor or a pdf moves most.
        // Where caustics are sharp (glass, water, the glossy scene's chrome) the disc blurs
        // them: a bias that does not vanish at 24 iterations and is large against the small
        // standard error of 16 whole renders, so mean z^2 exceeds 1 there (measured: 2.0 on
        // cornell_box_specular.yml, 1.09 on cornell_box.yml).
        let bound = if name == "cornell_box.yml" {
            1.5
        } else {
            MEAN_Z2_CAUSTICS
        };
        assert_converges_to_pt(name, "sppm", &pt, &sppm, bound);
    }
}

/// Bound on mean z^2 for the scenes with caustics (see the test).
const MEAN_Z2_CAUSTICS: f64 = 2.5;
const SPPM_PHOTONS: u32 = 20_000;
const SPPM_SEEDS: u64 = 16;
const SPPM_ITERATIONS: u32 = 24;
