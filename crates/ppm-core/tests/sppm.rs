//! Stochastic progressive photon mapping: the furnace, thread-count determinism, the
//! per-pixel radius rule, and the photon count default. (Convergence to the path tracer on
//! the shipped scenes: tests/sppm.rs of the workspace.)

use ppm_test_support::test_scenes;

use ppm_core::prelude::*;
use test_scenes::{
    assert_uniform_image, cornell, furnace, render_on_threads, sppm_stats, BoxContents,
};

#[test]
fn sppm_furnace_converges_to_five() {
    // L = Le + a L => 5 for albedo 0.8 in every pixel, with photons for direct light or not.
    let scene = furnace(0.8, 6);
    for direct in [DirectMode::Photons, DirectMode::Sampled] {
        let settings = RenderSettings {
            max_depth: 100_000,
            photons: 5_000,
            radius: ppm_core::integrator::Radius::World(0.05),
            direct,
            seed: 100,
            ..RenderSettings::for_algorithm(&scene, Algorithm::Sppm)
        };
        let stats = sppm_stats(&scene, &settings, 16, 12);
        // 16 renders: the standardised errors follow Student's t with 15 degrees of freedom,
        // P(|t| > 6) = 2.4e-5 per value (216 values here).
        assert_uniform_image(&stats, 5.0, 6.0, &format!("sppm {direct:?}"));
    }
}

#[test]
fn sppm_same_seed_same_image_at_any_thread_count() {
    // 48 x 48: the passes' pixel runs are several tasks, dealt to the threads out of image
    // order (integrator/task_order.rs).
    let scene = cornell(48, BoxContents::Glass);
    for direct in [DirectMode::Photons, DirectMode::Sampled] {
        let settings = RenderSettings {
            photons: 5_000,
            direct,
            ..RenderSettings::for_algorithm(&scene, Algorithm::Sppm)
        };
        let render = |threads| render_on_threads(&scene, &settings, 3, threads);
        let one = render(1);
        assert_eq!(one, render(2), "{direct:?}: 1 vs 2 threads");
        assert_eq!(one, render(3), "{direct:?}: 1 vs 3 threads");
        assert!(one.mean().max_element() > 0.0);
    }
}

#[test]
fn radii_shrink_only_where_photons_arrive() {
    // Per-pixel radii: after some iterations every pixel that saw photons has a smaller
    // radius, pixels that see nothing (the black lamp-less sky) keep theirs; N grows by
    // alpha M, so with alpha = 2/3 the radius of a lit pixel shrinks strictly.
    let scene = cornell(8, BoxContents::Diffuse);
    let settings = RenderSettings {
        photons: 20_000,
        radius: ppm_core::integrator::Radius::World(0.05),
        ..RenderSettings::for_algorithm(&scene, Algorithm::Sppm)
    };
    let mut renderer = Renderer::new(&scene, &settings);
    for _ in 0..4 {
        renderer.iterate(&scene);
    }
    let Renderer::Sppm(r) = &renderer else {
        unreachable!("-a sppm renders with SppmRenderer")
    };
    let r0 = 0.05f64 * 0.05;
    let shrunk = r.statistics().iter().filter(|s| s.r2 < r0 * 0.999).count();
    assert_eq!(
        shrunk,
        r.statistics().len(),
        "every pixel of the closed box gets photons"
    );
    for s in r.statistics() {
        assert!(s.n > 0.0 && s.tau.iter().all(|t| t.is_finite() && *t >= 0.0));
    }
}

#[test]
fn sppm_traces_one_light_path_per_pixel_unless_told() {
    let scene = cornell(10, BoxContents::Diffuse); // built in code: no photon count given
    assert_eq!(scene.defaults.photons, None);
    let sppm = RenderSettings::for_algorithm(&scene, Algorithm::Sppm);
    assert_eq!(sppm.photons, 100);
    let ppm = RenderSettings::for_algorithm(&scene, Algorithm::Ppm);
    assert_eq!(ppm.photons, ppm_core::integrator::DEFAULT_PHOTONS);
    let mut builder = test_scenes::cornell_builder(10, BoxContents::Diffuse);
    builder.defaults.photons = Some(1234);
    let told = builder.build().unwrap();
    assert_eq!(
        RenderSettings::for_algorithm(&told, Algorithm::Sppm).photons,
        1234
    );
}

/// A furnace of a bright glossy phong surface (specular 0.9, diffuse 0.05): each camera
/// vertex must choose its diffuse or glossy part, and a choice whose probability ignored the
/// albedos multiplied a path's weight by 1.8 per glossy bounce (a fixed one half), which
/// measured 60-120 times the mean in single pixels after 20 iterations. With the BSDF's own
/// lobe probability both choices weigh about the total albedo: no pixel far above the mean,
/// and the mean the path tracer's.
#[test]
fn sppm_on_a_bright_glossy_furnace_has_no_fireflies() {
    let camera = Camera::new(
        Vec3::new(0.1, 0.2, 0.3),
        Vec3::new(-0.1, -0.2, -1.3).normalize(),
        Vec3::Y,
        90.0,
        (16, 16),
    )
    .unwrap();
    let mut b = SceneBuilder::new(camera);
    let bsdf = Bsdf::phong(Vec3::splat(0.05), Vec3::splat(0.9), 20.0);
    let m = b.add_material(Material::new(bsdf, Vec3::ONE));
    b.add_sphere(Sphere::new(Vec3::ZERO, 1.0, m).inward());
    let scene = b.build().unwrap();
    let render = |algorithm, iterations| {
        let settings = RenderSettings {
            photons: 2_000,
            seed: 3,
            ..RenderSettings::for_algorithm(&scene, algorithm)
        };
        render_on_threads(&scene, &settings, iterations, 2)
    };
    let sppm = render(Algorithm::Sppm, 20);
    let pt = render(Algorithm::Path, 64);
    let (mean, reference) = (sppm.mean().x, pt.mean().x);
    let brightest = sppm.pixels.iter().map(|p| p.x).fold(0.0, f32::max);
    assert!(
        brightest < 3.0 * mean,
        "a firefly: the brightest pixel is {brightest}, the mean {mean}"
    );
    assert!(
        (mean / reference - 1.0).abs() < 0.03,
        "sppm mean {mean} against the path tracer's {reference}"
    );
}
