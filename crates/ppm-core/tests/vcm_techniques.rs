//! The technique sets of the VCM code (`bpt`, `bpm`, `lt`; see `integrator/vcm/techniques.rs`):
//! each converges to the analytic furnace and renders the same image at any thread count.

use ppm_test_support::test_scenes;

use ppm_core::integrator::{Techniques, VcmRenderer};
use ppm_core::pixel_bounds::PixelBounds;
use ppm_core::prelude::*;
use test_scenes::{assert_uniform_image, cornell, furnace, BoxContents, PixelStats};

/// The sets other than `vcm`, which the integrator tests check already.
const SETS: [Techniques; 3] = [Techniques::BPT, Techniques::BPM, Techniques::LT];

/// A fresh render of the whole image with technique set `techniques`.
fn renderer(scene: &Scene, settings: &RenderSettings, techniques: Techniques) -> Renderer {
    let bounds = PixelBounds::full(scene.camera.width, scene.camera.height);
    Renderer::Vcm(Box::new(VcmRenderer::with_techniques(
        settings.clone(),
        bounds,
        techniques,
    )))
}

fn settings(scene: &Scene) -> RenderSettings {
    RenderSettings {
        radius: Radius::World(0.1),
        seed: 3,
        ..RenderSettings::for_algorithm(scene, Algorithm::Vcm)
    }
}

#[test]
fn every_technique_set_sees_five_in_the_furnace() {
    // L = Le + a L = 1 / (1 - 0.8) in every pixel. Light tracing renders the sphere's
    // emission seen directly with the camera rays and every bounce by splatting; bpm merges
    // at every camera vertex (unbiased here: within chord distance r the sphere's cap has area
    // pi r^2 exactly); bpt weighs all its connections. 5 standard errors per pixel channel.
    let scene = furnace(0.8, 16);
    let settings = RenderSettings {
        max_depth: 100_000,
        ..settings(&scene)
    };
    for techniques in SETS {
        let mut r = renderer(&scene, &settings, techniques);
        let mut stats = PixelStats::new((scene.camera.width * scene.camera.height) as usize);
        for _ in 0..128 {
            r.iterate(&scene);
            stats.add(r.last_estimates());
        }
        assert_eq!(r.rejected(), 0, "{}: NaN or Inf samples", techniques.name());
        eprintln!(
            "{}: furnace image mean {} (se {})",
            techniques.name(),
            stats.image_mean(),
            stats.image_mean_se()
        );
        assert_uniform_image(&stats, 5.0, 5.0, techniques.name());
    }
}

#[test]
fn every_technique_set_renders_the_same_image_at_any_thread_count() {
    // 48 x 48 with a glass sphere: light tracing splats land anywhere, camera passes are dealt
    // to the threads out of image order.
    let scene = cornell(48, BoxContents::Glass);
    let settings = settings(&scene);
    for techniques in SETS {
        let render = |threads| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                let mut r = renderer(&scene, &settings, techniques);
                for _ in 0..3 {
                    r.iterate(&scene);
                }
                r.image()
            })
        };
        let one = render(1);
        let name = techniques.name();
        assert_eq!(one, render(2), "{name}: 1 vs 2 threads");
        assert_eq!(one, render(3), "{name}: 1 vs 3 threads");
        assert!(one.mean().max_element() > 0.0, "{name}: black image");
    }
}
