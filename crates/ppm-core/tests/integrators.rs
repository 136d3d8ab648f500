//! Integrator tests: analytic furnaces, estimators that must agree, power conservation,
//! thread-count determinism and light leaks.

use ppm_test_support::test_scenes;

use ppm_core::integrator::LightStrategy;
use ppm_core::prelude::*;
use test_scenes::{
    assert_uniform_image, cornell, cornell_builder, furnace, render_on_threads, render_stats,
    z_scores, BoxContents,
};

fn pt_settings(scene: &Scene) -> RenderSettings {
    RenderSettings {
        algorithm: Algorithm::Path,
        ..RenderSettings::new(scene)
    }
}

#[test]
fn path_tracer_furnace_sees_one_over_one_minus_albedo() {
    // L = Le + a L  =>  L = 1 / (1 - 0.8) = 5 in every pixel, for every light strategy.
    let scene = furnace(0.8, 6);
    for strategy in [
        LightStrategy::Mis,
        LightStrategy::LightOnly,
        LightStrategy::BsdfOnly,
    ] {
        let settings = RenderSettings {
            max_depth: 100_000,
            light_strategy: strategy,
            ..pt_settings(&scene)
        };
        let stats = render_stats(&scene, &settings, 256);
        assert_uniform_image(&stats, 5.0, 5.0, &format!("{strategy:?}"));
    }
}

#[test]
fn ppm_furnace_converges_to_five() {
    let scene = furnace(0.8, 6);
    for direct in [DirectMode::Photons, DirectMode::Sampled] {
        let settings = RenderSettings {
            max_depth: 100_000,
            photons: 20_000,
            radius: Radius::World(0.03),
            direct,
            ..RenderSettings::new(&scene)
        };
        let stats = render_stats(&scene, &settings, 24);
        assert_uniform_image(&stats, 5.0, 5.0, &format!("ppm {direct:?}"));
    }
}

#[test]
fn light_sampling_bsdf_sampling_and_mis_agree() {
    // On the diffuse box and on the glossy one (phong floor, sharp phong sphere).
    for contents in [BoxContents::Diffuse, BoxContents::Glossy] {
        let scene = cornell(10, contents);
        let run = |strategy| {
            let settings = RenderSettings {
                light_strategy: strategy,
                seed: strategy as u64,
                ..pt_settings(&scene)
            };
            render_stats(&scene, &settings, 3000)
        };
        let mis = run(LightStrategy::Mis);
        for other in [LightStrategy::LightOnly, LightStrategy::BsdfOnly] {
            let z = z_scores(&mis, &run(other));
            let beyond = z.iter().filter(|z| z.abs() > 4.0).count();
            let mean_z2 = z.iter().map(|z| z * z).sum::<f64>() / z.len() as f64;
            // For agreeing estimators z is about standard normal: |z| > 4 has probability
            // 6e-5 per value (300 values here), and the mean of z^2 is 1.
            assert!(
                beyond <= 1,
                "{other:?}: {beyond} of {} values beyond 4 sigma",
                z.len()
            );
            assert!(
                (0.6..1.5).contains(&mean_z2),
                "{other:?}: mean z^2 = {mean_z2}"
            );
        }
    }
}

/// Renders `scene` with the path tracer and with photon mapping and checks that they agree:
/// image means within 4 standard errors of their difference and within `tolerance`, and per
/// pixel (see the callers for why a few pixels may differ).
fn assert_ppm_matches_pt(scene: &Scene, pt_iterations: u32, ppm_iterations: u32, tolerance: f64) {
    let ppm_settings = RenderSettings {
        photons: 50_000,
        radius: Radius::World(0.04),
        seed: 2,
        ..RenderSettings::new(scene)
    };
    assert_matches_pt(
        scene,
        pt_iterations,
        &ppm_settings,
        ppm_iterations,
        tolerance,
    );
}

/// [`assert_ppm_matches_pt`] for any estimator (`settings`, `iterations` of it) whose
/// iterations are independent estimates; returns the relative difference of the image means,
/// (other - pt) / pt.
fn assert_matches_pt(
    scene: &Scene,
    pt_iterations: u32,
    settings: &RenderSettings,
    iterations: u32,
    tolerance: f64,
) -> f64 {
    let pt = render_stats(
        scene,
        &RenderSettings {
            seed: 1,
            max_depth: settings.max_depth,
            ..pt_settings(scene)
        },
        pt_iterations,
    );
    let ppm = render_stats(scene, settings, iterations);
    // Iterations are independent; the pixels of one photon-mapping iteration share a photon
    // map, so the standard error of the image mean comes from the spread of iteration means.
    let (a, b) = (pt.image_mean(), ppm.image_mean());
    let se = (pt.image_mean_se().powi(2) + ppm.image_mean_se().powi(2)).sqrt();
    assert!(
        (a - b).abs() < 4.0 * se,
        "image means: pt {a} {:?} {b}, se of difference {se}",
        settings.algorithm
    );
    assert!(
        (a - b).abs() / a < tolerance,
        "image means: pt {a} {:?} {b}",
        settings.algorithm
    );
    // Per pixel: photon mapping is consistent, not unbiased. Its remaining bias (brightening
    // within a radius of concave corners, where photons of the adjacent wall are gathered)
    // shows in a few pixels; an error in a factor or a pdf would move most of them.
    let z = z_scores(&pt, &ppm);
    let beyond = z.iter().filter(|z| z.abs() > 4.0).count();
    assert!(
        beyond * 200 <= z.len(),
        "{beyond} of {} pixel channels differ beyond 4 sigma",
        z.len()
    );
    let mean_z2 = z.iter().map(|z| z * z).sum::<f64>() / z.len() as f64;
    assert!(mean_z2 < 1.5, "mean z^2 = {mean_z2}");
    (b - a) / a
}

#[test]
fn ppm_and_path_tracing_converge_to_the_same_image() {
    // A closed Cornell box with a glass sphere (caustics) at 24x24: within 1%.
    assert_ppm_matches_pt(&cornell(24, BoxContents::Glass), 1500, 64, 0.01);
}

#[test]
fn ppm_glossy_handling_matches_path_tracing() {
    // A phong floor and a sharp phong sphere: the glossy lobe is traced with MIS on emission,
    // the diffuse lobe density-estimated (6.4); nothing may be counted twice or missed. The
    // sphere's glossy caustics make photon mapping noisier here (the standard error of its
    // image mean is about 1%), hence the 3% sanity bound next to the 4-sigma test.
    assert_ppm_matches_pt(&cornell(24, BoxContents::Glossy), 1500, 64, 0.03);
}

/// VCM's settings for the cross-checks: a merge radius of the photon mapper's.
fn vcm_settings(scene: &Scene) -> RenderSettings {
    RenderSettings {
        radius: Radius::World(0.04),
        seed: 2,
        ..RenderSettings::for_algorithm(scene, Algorithm::Vcm)
    }
}

#[test]
fn vcm_furnace_converges_to_five() {
    // Inside the sphere the light vertices within chord distance r of a point cover a cap of
    // area exactly pi r^2 (Archimedes), and the radiance is uniform: merging is unbiased here,
    // so every technique and every MIS weight is checked against the exact answer. With 256
    // light paths, r = 0.03 leaves merging a small share (eta_VCM = pi r^2 N = 0.7), r = 0.3
    // makes it the dominant technique (eta_VCM = 72).
    let scene = furnace(0.8, 16);
    for radius in [0.03, 0.3] {
        let settings = RenderSettings {
            max_depth: 100_000,
            radius: Radius::World(radius),
            ..vcm_settings(&scene)
        };
        let stats = render_stats(&scene, &settings, 128);
        assert_uniform_image(&stats, 5.0, 5.0, &format!("vcm, radius {radius}"));
    }
}

#[test]
fn vcm_and_path_tracing_converge_to_the_same_image() {
    // The diffuse box, the glass sphere's caustics (light tracing and merging carry them),
    // and the glossy box (connections and merges weighted against the glossy lobe's pdfs).
    for (contents, name, tolerance) in [
        (BoxContents::Diffuse, "diffuse", 0.01),
        (BoxContents::Glass, "glass", 0.01),
        (BoxContents::Glossy, "glossy", 0.03),
    ] {
        let scene = cornell(24, contents);
        let rel = assert_matches_pt(&scene, 1500, &vcm_settings(&scene), 400, tolerance);
        eprintln!("vcm vs pt, {name} box: relative difference of image means {rel:+.2e}");
    }
}

/// A Phong lobe so narrow that its pdf squared overflows f32 (exponent 1e25, written by a
/// user who wanted a mirror) is rendered at `Phong::MAX_EXPONENT`: vcm's MIS weights, which
/// multiply squared pdfs, stay finite and it agrees with the path tracer.
#[test]
fn vcm_agrees_with_path_tracing_on_a_near_mirror_phong_lobe() {
    let mut b = cornell_builder(24, BoxContents::Diffuse);
    let shiny = b.add_material(Material::new(
        Bsdf::phong(Vec3::splat(0.05), Vec3::splat(0.9), 1e25),
        Vec3::ZERO,
    ));
    b.add_sphere(Sphere::new(Vec3::new(0.4, 0.4, 0.0), 0.4, shiny));
    let scene = b.build().unwrap();
    let rel = assert_matches_pt(&scene, 1500, &vcm_settings(&scene), 200, 0.03);
    eprintln!("vcm vs pt, near-mirror phong: relative difference of image means {rel:+.2e}");
}

#[test]
fn first_hit_photons_carry_the_lights_power() {
    // In a closed box every light path hits a wall, so the first-hit photons of N paths
    // carry the total power of the lights: sum Phi_p / N -> sum of light powers, per channel.
    // A coloured point light next to the area light makes the light choice matter.
    let mut builder = cornell_builder(4, BoxContents::Diffuse);
    builder.add_point_light(PointLight {
        position: Vec3::new(0.3, 1.5, 0.2),
        intensity: Vec3::new(0.5, 2.0, 4.0),
    });
    let scene = builder.build().unwrap();
    let settings = RenderSettings {
        max_depth: 1,
        photons: 200_000,
        direct: DirectMode::Photons, // first-hit photons are stored
        ..RenderSettings::new(&scene)
    };
    let mut renderer = Renderer::new(&scene, &settings);
    renderer.iterate(&scene);
    let Renderer::Ppm(r) = &renderer else {
        unreachable!("-a ppm renders with PpmRenderer")
    };
    let photons = r.photon_map().photons();
    assert_eq!(photons.len(), settings.photons as usize);
    let n = settings.photons as f64;
    let power = scene.total_power();
    for c in 0..3 {
        let sum: f64 = photons.iter().map(|p| p.flux[c] as f64).sum();
        let sum2: f64 = photons.iter().map(|p| (p.flux[c] as f64).powi(2)).sum();
        let mean = sum / n;
        let se = ((sum2 / n - mean * mean) / n).sqrt();
        let d = (mean - power[c] as f64).abs();
        assert!(
            d < 5.0 * se + 1e-6 * mean,
            "channel {c}: {mean} vs {} (se {se})",
            power[c]
        );
    }
}

#[test]
fn same_seed_same_image_at_any_thread_count() {
    // 48 x 48: the passes' pixel runs are several tasks, dealt to the threads out of image
    // order (integrator/task_order.rs).
    let scene = cornell(48, BoxContents::Glass);
    for algorithm in [Algorithm::Path, Algorithm::Ppm, Algorithm::Vcm] {
        let settings = RenderSettings {
            algorithm,
            photons: 5_000,
            ..RenderSettings::new(&scene)
        };
        let render = |threads| render_on_threads(&scene, &settings, 3, threads);
        let one = render(1);
        assert_eq!(one, render(2), "{algorithm:?}: 1 vs 2 threads");
        assert_eq!(one, render(3), "{algorithm:?}: 1 vs 3 threads");
        assert!(one.mean().max_element() > 0.0);
    }
}

#[test]
fn photons_never_leak_through_a_thin_wall() {
    // A two-sided diffuse wall lit from one side, seen from the other: the dark side receives
    // no light at all, even with a gather radius a hundred times the wall's thickness.
    for thickness in [0.0f32, 1e-3] {
        let camera =
            Camera::new(Vec3::new(0.0, 0.0, -2.0), Vec3::ZERO, Vec3::Y, 40.0, (8, 8)).unwrap();
        let mut b = SceneBuilder::new(camera);
        let wall = b.add_material(Material::new(Bsdf::diffuse(Vec3::splat(0.8)), Vec3::ZERO));
        let lamp = b.add_material(Material::new(Bsdf::diffuse(Vec3::ZERO), Vec3::splat(5.0)));
        // The lit face at z = 0 faces +z; the dark face at z = -thickness faces -z.
        b.add_mesh(TriangleMesh::quad(
            Vec3::new(-2.0, -2.0, 0.0),
            Vec3::X * 4.0,
            Vec3::Y * 4.0,
            wall,
        ));
        if thickness > 0.0 {
            let z = -thickness;
            b.add_mesh(TriangleMesh::quad(
                Vec3::new(-2.0, -2.0, z),
                Vec3::Y * 4.0,
                Vec3::X * 4.0,
                wall,
            ));
        }
        // A light facing the wall from +z.
        b.add_mesh(TriangleMesh::quad(
            Vec3::new(-0.5, -0.5, 1.0),
            Vec3::Y,
            Vec3::X,
            lamp,
        ));
        let scene = b.build().unwrap();
        // Photons of every bounce (the lit side is covered with first-hit photons), and
        // light sampling at the gather point (its shadow ray must not pass the wall either).
        for direct in [DirectMode::Photons, DirectMode::Sampled] {
            let settings = RenderSettings {
                photons: 20_000,
                radius: Radius::World(0.1),
                direct,
                ..RenderSettings::new(&scene)
            };
            let mut r = Renderer::new(&scene, &settings);
            r.iterate(&scene);
            assert!(
                r.image().pixels.iter().all(|p| *p == Vec3::ZERO),
                "thickness {thickness}, {direct:?}: light leaked"
            );
            // The lit side does receive photons (the test can fail).
            if let (Renderer::Ppm(ppm), DirectMode::Photons) = (&r, direct) {
                assert!(ppm.photon_map().len() > 10_000);
            }
        }
    }
}
