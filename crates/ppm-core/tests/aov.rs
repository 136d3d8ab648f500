//! The photon-count image (`--aov photons`): for `ppm`, each pixel's count equals a brute-force
//! count over every photon of the last iteration at the pixel's pilot point; for `sppm`, it is
//! each pixel's accumulated N. The path tracer has none.

use ppm_test_support::test_scenes;

use ppm_core::integrator::{pilot_points, RayCounters, Renderer};
use ppm_core::prelude::*;
use test_scenes::{cornell, BoxContents};

#[test]
fn ppm_photon_counts_equal_a_brute_force_count() {
    let scene = cornell(16, BoxContents::Glass);
    for radius in [Radius::Auto, Radius::World(0.08)] {
        let settings = RenderSettings {
            photons: 20_000,
            radius,
            direct: DirectMode::Photons,
            seed: 7,
            ..RenderSettings::for_algorithm(&scene, Algorithm::Ppm)
        };
        let mut renderer = Renderer::new(&scene, &settings);
        assert!(
            renderer.photon_count_image(&scene).is_none(),
            "before any iteration"
        );
        for _ in 0..3 {
            renderer.iterate(&scene);
        }
        let counts = renderer.photon_count_image(&scene).unwrap();
        let radii = renderer.radius_image().unwrap();
        let Renderer::Ppm(ppm) = &renderer else {
            unreachable!()
        };
        let photons = ppm.photon_map().photons();
        let points = pilot_points(
            &scene,
            7,
            settings.max_depth,
            settings.rr_depth,
            &mut RayCounters::default(),
        );
        let mut total = 0.0;
        for (pixel, point) in points.iter().enumerate() {
            let r = radii.pixels[pixel].x;
            let expected = point.map_or(0, |p| {
                photons
                    .iter()
                    .filter(|q| (q.position - p.position).length_squared() <= r * r)
                    .count()
            });
            assert_eq!(
                counts.pixels[pixel],
                Vec3::splat(expected as f32),
                "{radius}: pixel {pixel}"
            );
            total += expected as f64;
        }
        assert!(total > 100.0, "{radius}: only {total} photons counted");
    }
}

#[test]
fn sppm_photon_counts_are_the_pixels_n() {
    let scene = cornell(8, BoxContents::Diffuse);
    let settings = RenderSettings {
        photons: 10_000,
        ..RenderSettings::for_algorithm(&scene, Algorithm::Sppm)
    };
    let mut renderer = Renderer::new(&scene, &settings);
    for _ in 0..4 {
        renderer.iterate(&scene);
    }
    let counts = renderer.photon_count_image(&scene).unwrap();
    let Renderer::Sppm(sppm) = &renderer else {
        unreachable!()
    };
    for (c, s) in counts.pixels.iter().zip(sppm.statistics()) {
        assert_eq!(*c, Vec3::splat(s.n as f32));
    }
    assert!(counts.pixels.iter().any(|c| c.x > 0.0));
}

#[test]
fn the_path_tracer_has_no_photon_counts() {
    let scene = cornell(4, BoxContents::Diffuse);
    let settings = RenderSettings::for_algorithm(&scene, Algorithm::Path);
    let mut renderer = Renderer::new(&scene, &settings);
    renderer.iterate(&scene);
    assert!(renderer.photon_count_image(&scene).is_none());
}
