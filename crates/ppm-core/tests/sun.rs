//! The directional light (the sun) against closed forms: the irradiance E cos(theta) that
//! next-event estimation gives a plane, the radiance rho E cos(theta) / pi of a diffuse floor
//! by the path tracer and by photon density alone; every integrator alike on a box open to
//! the sun; the path tracer's warning; the light moving with a scaled scene. The contract
//! checks common to every light are in `light_harness.rs`; the caustic against Mitsuba 3 is
//! in `crates/ppm-scene/tests/sun.rs`.

use ppm_test_support::test_scenes;

use ppm_core::light::{Light, LightKind};
use ppm_core::prelude::*;
use test_scenes::{add_block, assert_uniform_image, render_stats, sppm_stats};

/// Irradiance on a surface facing the sun (W/m^2), per channel.
const E: Vec3 = Vec3::new(3.0, 2.0, 1.0);

/// The direction the light travels: down, at `theta` degrees from the vertical, turned
/// about the vertical by `phi` degrees.
fn travelling(theta: f32, phi: f32) -> Vec3 {
    let (t, p) = (theta.to_radians(), phi.to_radians());
    Vec3::new(t.sin() * p.cos(), -t.cos(), t.sin() * p.sin())
}

#[test]
fn next_event_irradiance_on_a_plane_is_e_cos_theta() {
    // A plane with normal n receives E max(0, n . wi) from every point: no 1/d^2.
    let mut light = Light::directional(travelling(35.0, 20.0), E).unwrap();
    light.preprocess((Vec3::splat(-2.0), Vec3::splat(2.0)));
    assert_eq!(light.kind(), LightKind::DeltaDirection);
    for n in [
        Vec3::Y,
        Vec3::new(0.3, 1.0, -0.2).normalize(),
        Vec3::X,
        -Vec3::Y,
    ] {
        let cos = n.dot(-travelling(35.0, 20.0)).max(0.0);
        for p in [
            Vec3::ZERO,
            Vec3::new(1.5, -1.9, 0.7),
            Vec3::new(-2.0, 2.0, 2.0),
        ] {
            let s = light.sample_direct(p, Vec2::new(0.4, 0.6)).unwrap();
            let e = s.li * n.dot(s.wi).max(0.0) / s.pdf;
            assert!(
                (e - E * cos).abs().max_element() < 1e-5,
                "n {n}, p {p}: {e} vs {}",
                E * cos
            );
        }
    }
}

/// The floor's irradiance, the same in every channel (one expected value per pixel).
const GRAY: f32 = 2.0;

/// A 4 x 4 diffuse floor (reflectance `rho`) at y = 0 under the sun at `theta` degrees, seen
/// straight down from 1.5 above with a 40 degree field of view (every pixel on the floor,
/// 0.55 from its centre at most, far from its edges). Nothing else: the floor's radiance
/// toward the camera is rho E cos(theta) / pi everywhere.
fn sunlit_floor(theta: f32, rho: f32, resolution: u32) -> Scene {
    let camera = Camera::new(
        Vec3::new(0.0, 1.5, 0.0),
        Vec3::ZERO,
        Vec3::NEG_Z,
        40.0,
        (resolution, resolution),
    )
    .unwrap();
    let mut b = SceneBuilder::new(camera);
    let m = b.add_material(Material::new(Bsdf::diffuse(Vec3::splat(rho)), Vec3::ZERO));
    let (c, u, v) = (Vec3::new(-2.0, 0.0, -2.0), Vec3::Z * 4.0, Vec3::X * 4.0);
    b.add_mesh(TriangleMesh::quad(c, u, v, m));
    b.add_light(Light::directional(travelling(theta, 30.0), Vec3::splat(GRAY)).unwrap());
    b.build().unwrap()
}

#[test]
fn a_sunlit_floor_has_radiance_rho_e_cos_theta_over_pi_by_nee_and_by_photons() {
    let (theta, rho) = (50.0f32, 0.6f32);
    let scene = sunlit_floor(theta, rho, 6);
    let expected =
        rho as f64 * GRAY as f64 * (theta as f64).to_radians().cos() / std::f64::consts::PI;
    let settings = |algorithm| RenderSettings {
        algorithm,
        seed: 3,
        max_depth: 4,
        photons: 20_000,
        radius: Radius::World(0.1),
        direct: DirectMode::Photons,
        ..RenderSettings::for_algorithm(&scene, algorithm)
    };
    // Path tracing: next-event estimation alone (the sun cannot be hit), exact per sample.
    let pt = render_stats(&scene, &settings(Algorithm::Path), 4);
    for p in 0..pt.pixels() {
        for c in 0..3 {
            let relative = (pt.mean(p, c) - expected).abs() / expected;
            assert!(
                relative < 1e-5,
                "pt: pixel {p}: {} vs {expected}",
                pt.mean(p, c)
            );
        }
    }
    // Photon mapping with every bounce's photons density-estimated: the photon density on
    // the floor, E cos theta per unit area (the disk's flux E pi R^2 spread over pi R^2 /
    // cos theta of floor), times rho / pi. Uniform density: the kernel adds no bias.
    let ppm = render_stats(&scene, &settings(Algorithm::Ppm), 20);
    assert_uniform_image(&ppm, expected, 5.0, "ppm photon density");
    let relative = (ppm.image_mean() - expected).abs() / expected;
    assert!(
        relative < 0.01,
        "ppm image mean {} vs {expected}",
        ppm.image_mean()
    );
}

/// A floor, a back and a left wall and a block, open at the top and the front, lit only by
/// the sun from above, behind the camera and to the right: shadows of the block and walls,
/// light between the walls.
fn sun_box(resolution: u32) -> SceneBuilder {
    let camera = Camera::new(
        Vec3::new(0.0, 1.0, 3.6),
        Vec3::new(0.0, 0.7, 0.0),
        Vec3::Y,
        40.0,
        (resolution, resolution),
    )
    .unwrap();
    let mut b = SceneBuilder::new(camera);
    let white = b.add_material(Material::new(Bsdf::diffuse(Vec3::splat(0.7)), Vec3::ZERO));
    let red = b.add_material(Material::new(
        Bsdf::diffuse(Vec3::new(0.6, 0.1, 0.1)),
        Vec3::ZERO,
    ));
    let quad = |c: [f32; 3], u: [f32; 3], v: [f32; 3], m| {
        TriangleMesh::quad(Vec3::from(c), Vec3::from(u), Vec3::from(v), m)
    };
    b.add_mesh(quad(
        [-1.0, 0.0, -1.0],
        [0.0, 0.0, 2.0],
        [2.0, 0.0, 0.0],
        white,
    ));
    b.add_mesh(quad(
        [-1.0, 0.0, -1.0],
        [2.0, 0.0, 0.0],
        [0.0, 2.0, 0.0],
        white,
    ));
    b.add_mesh(quad(
        [-1.0, 0.0, -1.0],
        [0.0, 2.0, 0.0],
        [0.0, 0.0, 2.0],
        red,
    ));
    add_block(&mut b, Vec3::new(0.2, 0.0, -0.1), 0.5, 0.8, white);
    b.add_light(Light::directional(Vec3::new(-0.5, -1.0, -0.6), E).unwrap());
    b
}

#[test]
fn pt_ppm_sppm_and_vcm_agree_on_a_box_open_to_the_sun() {
    // The sun is only found by light sampling (pt, vcm's connections) and only starts photons
    // (ppm, sppm, vcm's merging and light tracing): the four agree only if sample_direct,
    // sample_emission and the densities VCM weighs them with describe the same light.
    let scene = sun_box(12).build().unwrap();
    let settings = |algorithm, seed| RenderSettings {
        algorithm,
        seed,
        max_depth: 8,
        photons: 10_000,
        radius: Radius::World(0.05),
        ..RenderSettings::for_algorithm(&scene, algorithm)
    };
    let mean = |stats: test_scenes::PixelStats| (stats.image_mean(), stats.image_mean_se());
    let pt = mean(render_stats(&scene, &settings(Algorithm::Path, 1), 300));
    for algorithm in [Algorithm::Ppm, Algorithm::Sppm, Algorithm::Vcm] {
        let other = match algorithm {
            // SPPM's iterations share per-pixel state: whole renders are the samples.
            Algorithm::Sppm => mean(sppm_stats(&scene, &settings(algorithm, 2), 8, 30)),
            Algorithm::Ppm => mean(render_stats(&scene, &settings(algorithm, 2), 40)),
            _ => mean(render_stats(&scene, &settings(algorithm, 2), 150)),
        };
        let se = pt.1.hypot(other.1);
        eprintln!("sun box: pt {pt:?}, {algorithm:?} {other:?}");
        assert!(
            (pt.0 - other.0).abs() < 4.0 * se && (pt.0 - other.0).abs() < 0.02 * pt.0,
            "{algorithm:?}: image mean {} +- {} against pt {} +- {}",
            other.0,
            other.1,
            pt.0,
            pt.1
        );
    }
}

#[test]
fn the_path_tracer_warning_names_a_sun_behind_glass() {
    assert!(!sun_box(4)
        .build()
        .unwrap()
        .has_delta_light_behind_specular());
    let mut b = sun_box(4);
    let glass = b.add_material(Material::new(Bsdf::glass(1.5, Vec3::ONE), Vec3::ZERO));
    b.add_sphere(Sphere::new(Vec3::new(-0.4, 0.3, 0.3), 0.3, glass));
    assert!(b.build().unwrap().has_delta_light_behind_specular());
}

#[test]
fn power_is_irradiance_times_the_disk_over_the_bounding_sphere_and_follows_the_scene() {
    // The box's bounds are [-1, 1] x [0, 2] x [-1, 1]: R = sqrt(3) (enlarged by 0.1%).
    let scene = sun_box(4).build().unwrap();
    let sun = scene.lights.iter().find(|l| l.is_delta()).unwrap();
    let r = 3f32.sqrt() * 1.001;
    let power = E * std::f32::consts::PI * r * r;
    assert!(
        (sun.power() - power).abs().max_element() < 1e-5 * power.max_element(),
        "{} vs {power}",
        sun.power()
    );
    // Scaled by 2 and moved: the same irradiance, the disk twice as wide (power x4), from
    // the same direction.
    let mut moved = sun.clone();
    moved.transform(2.0, Vec3::new(5.0, -3.0, 1.0));
    let p = Vec3::new(5.0, -3.0, 1.0);
    let (a, b) = (
        sun.sample_direct(Vec3::ZERO, Vec2::ZERO).unwrap(),
        moved.sample_direct(p, Vec2::ZERO).unwrap(),
    );
    assert_eq!((a.li, a.wi), (b.li, b.wi));
    assert!(
        (moved.power() / sun.power() - Vec3::splat(4.0))
            .abs()
            .max_element()
            < 1e-5
    );
}
