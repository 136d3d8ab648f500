//! `max_depth` bounds the paths of every integrator as it bounds the path tracer's: at most
//! `max_depth` bounces between the camera and the light, whichever technique closed the path.
//!
//! Photon mapping joins a camera subpath and a light subpath at a gather, so the bound holds
//! only if a gather behind a specular chain counts fewer photon bounces than one at the first
//! vertex. The glass box at a small `max_depth` makes that visible: a floor seen through the
//! sphere (two refractions) may take only the photons that arrived straight from the lamp,
//! which with `--direct sampled` are not stored at all (its direct light is sampled instead),
//! and counting the deeper ones brightens the image by several percent. Both direct modes
//! are checked; vcm, whose merges bound the path's edges themselves, with them.

use ppm_test_support::test_scenes;

use ppm_core::integrator::Setting;
use ppm_core::prelude::*;
use test_scenes::{assert_converges_to_pt, cornell, render_stats, sppm_stats, BoxContents};

/// Small enough that a camera path through the glass sphere reaches the floor with one bounce
/// left.
const MAX_DEPTH: u32 = 3;

#[test]
fn every_integrator_stops_at_max_depth_as_the_path_tracer_does() {
    let scene = cornell(24, BoxContents::Glass);
    let settings = |algorithm| RenderSettings {
        max_depth: MAX_DEPTH,
        radius: Radius::World(0.04),
        seed: 2,
        ..RenderSettings::for_algorithm(&scene, algorithm)
    };
    let pt = render_stats(
        &scene,
        &RenderSettings {
            seed: 1,
            ..settings(Algorithm::Path)
        },
        2000,
    );
    let cases = Algorithm::ALL
        .into_iter()
        .flat_map(|a| [DirectMode::Sampled, DirectMode::Photons].map(move |d| (a, d)));
    for (algorithm, direct) in cases {
        if !algorithm.reads(Setting::Direct) && direct == DirectMode::Photons {
            continue; // no direct mode: one case is enough
        }
        let label = format!("{algorithm:?} {direct:?}");
        let settings = |algorithm| RenderSettings {
            direct,
            ..settings(algorithm)
        };
        // The per-pixel bound allows for photon mapping's bias within a radius of concave
        // corners and in the sphere's caustic, as the other cross-checks do; a path counted
        // past max_depth moves the image mean (checked within 4 standard errors and 1%).
        match algorithm {
            Algorithm::Path => continue,
            Algorithm::Ppm => {
                let s = RenderSettings {
                    photons: 50_000,
                    ..settings(algorithm)
                };
                let ppm = render_stats(&scene, &s, 64);
                assert_converges_to_pt("glass box", &label, &pt, &ppm, 2.0);
            }
            Algorithm::Sppm => {
                let s = RenderSettings {
                    photons: 20_000,
                    ..settings(algorithm)
                };
                let sppm = sppm_stats(&scene, &s, 16, 24);
                assert_converges_to_pt("glass box", &label, &pt, &sppm, 2.5);
            }
            Algorithm::Vcm => {
                let vcm = render_stats(&scene, &settings(algorithm), 400);
                assert_converges_to_pt("glass box", &label, &pt, &vcm, 2.0);
            }
            // VCM's technique subsets trace the same light and camera subpaths under the same
            // bound as vcm (`max_edges` in `VcmRenderer::iterate_until`), which vcm checks;
            // lt cannot see the floor through the glass at all.
            Algorithm::Bpt | Algorithm::Bpm | Algorithm::Lt => continue,
        }
    }
}
