//! The spot light against closed forms (irradiance under it, its power by quadrature), in
//! scenes (every integrator renders a spot-lit box alike; the path tracer's warning for delta
//! lights behind a mirror), and the builder's one list of lights. The contract checks common
//! to every light are in `light_harness.rs`.

use ppm_test_support::test_scenes;

use ppm_core::light::{Light, LightKind};
use ppm_core::prelude::*;
use ppm_core::sampling::Rng;
use std::f64::consts::PI;
use test_scenes::{render_stats, spot_box, sppm_stats};

/// pbrt-v4's smoothstep falloff in f64, from the angles: 1 inside `start`, 0 beyond `end`.
fn falloff(cos_theta: f64, start: f64, end: f64) -> f64 {
    let (cos_start, cos_end) = (start.cos(), end.cos());
    if cos_theta >= cos_start {
        1.0
    } else if cos_theta <= cos_end {
        0.0
    } else {
        let t = (cos_theta - cos_end) / (cos_start - cos_end);
        t * t * (3.0 - 2.0 * t)
    }
}

/// A spot light 2 above the floor y = 0, pointing straight down, intensity 5 on its axis.
const HEIGHT: f64 = 2.0;
const CONE: f64 = 40.0;
const START: f64 = 25.0;
fn downward_spot() -> Light {
    Light::spot(
        Vec3::new(0.0, HEIGHT as f32, 0.0),
        Vec3::NEG_Y,
        Vec3::splat(5.0),
        (CONE as f32).to_radians(),
        (START as f32).to_radians(),
    )
    .unwrap()
}

/// The irradiance next-event estimation gives at `p` on the floor (normal +y): li cos / 1
/// (the light is a delta: pdf 1), zero when no sample.
fn floor_irradiance(light: &Light, p: Vec3) -> f64 {
    light
        .sample_direct(p, Vec2::new(0.3, 0.7))
        .map_or(0.0, |s| s.li.x as f64 * s.wi.y.max(0.0) as f64)
}

#[test]
fn irradiance_on_the_floor_is_intensity_times_cosine_over_distance_squared() {
    // E(r) = I0 s(theta) cos(theta) / d^2 with d^2 = h^2 + r^2 and cos = h / d; the radius
    // where the cone ends is h tan(40 degrees) = 1.678.
    let light = downward_spot();
    let (start, end) = (START.to_radians(), CONE.to_radians());
    for r in [0.0, 0.5, 0.9, 1.0, 1.2, 1.4, 1.6, 1.67, 1.69, 2.5, 10.0] {
        for phi in [0.0f64, 1.0, 4.0] {
            let p = Vec3::new((r * phi.cos()) as f32, 0.0, (r * phi.sin()) as f32);
            let d2 = HEIGHT * HEIGHT + r * r;
            let cos = HEIGHT / d2.sqrt();
            let exact = 5.0 * falloff(cos, start, end) * cos / d2;
            let e = floor_irradiance(&light, p);
            assert!(
                (e - exact).abs() <= 1e-5 * exact + 1e-7,
                "r {r}, phi {phi}: E {e}, expected {exact}"
            );
            if r > HEIGHT * end.tan() {
                assert_eq!(e, 0.0, "r {r}: outside the cone");
            }
        }
    }
    // Under the axis E = I0 / h^2, and nothing above the light.
    assert!((floor_irradiance(&light, Vec3::ZERO) - 5.0 / 4.0).abs() < 1e-6);
    assert!(light
        .sample_direct(Vec3::new(0.0, 3.0, 0.0), Vec2::ZERO)
        .is_none());
}

#[test]
fn power_is_the_irradiance_integrated_over_the_floor() {
    // The cone (40 degrees) lies wholly on the floor, so Phi = integral of E over the disc
    // of radius h tan(40 degrees): midpoint rule in r (E is smooth: C1 at the band's edges),
    // against Phi = 2 pi I0 ((1 - cos 25) + (cos 25 - cos 40) / 2).
    let light = downward_spot();
    let radius = HEIGHT * CONE.to_radians().tan();
    let n = 20_000;
    let dr = radius / n as f64;
    let integral: f64 = (0..n)
        .map(|i| {
            let r = (i as f64 + 0.5) * dr;
            2.0 * PI * r * dr * floor_irradiance(&light, Vec3::new(r as f32, 0.0, 0.0))
        })
        .sum();
    let (cs, ce) = (START.to_radians().cos(), CONE.to_radians().cos());
    let exact = 2.0 * PI * 5.0 * ((1.0 - cs) + 0.5 * (cs - ce));
    let power = light.power().x as f64;
    assert!((power - exact).abs() <= 1e-5 * exact, "{power} vs {exact}");
    assert!(
        (integral - exact).abs() <= 1e-4 * exact,
        "{integral} vs {exact}"
    );
}

#[test]
fn emission_stays_inside_the_cone() {
    let light = downward_spot();
    let cos_end = CONE.to_radians().cos() as f32;
    let mut rng = Rng::new(11, 0, 0);
    let mut below_start = 0;
    for _ in 0..100_000 {
        let s = light.sample_emission(rng.uniform2(), rng.uniform2());
        let cos = -s.dir.y;
        assert!(cos >= cos_end - 1e-6, "a photon leaves at cos {cos}");
        below_start += (cos < START.to_radians().cos() as f32) as u32;
    }
    // Uniform in the cone: the band between 25 and 40 degrees is (cos 25 - cos 40) / (1 -
    // cos 40) = 0.60 of its solid angle (binomial standard error 0.0015).
    let (cs, ce) = (START.to_radians().cos(), CONE.to_radians().cos());
    let band = below_start as f64 / 1e5;
    assert!((band - (cs - ce) / (1.0 - ce)).abs() < 0.008, "{band}");
}

/// Image means of `iterations` of `settings` on `scene`: (mean, standard error).
fn image_mean(scene: &Scene, settings: &RenderSettings, iterations: u32) -> (f64, f64) {
    let stats = render_stats(scene, settings, iterations);
    (stats.image_mean(), stats.image_mean_se())
}

#[test]
fn pt_ppm_sppm_and_vcm_agree_on_a_box_lit_by_a_spot_light() {
    // The spot light is only found by light sampling (pt, and vcm's connections) and only
    // starts photons (ppm, sppm, vcm's merging and light tracing): the four agree only if
    // sample_direct, sample_emission and pdf_emission describe the same light.
    let scene = spot_box(12).build().unwrap();
    assert!(scene
        .lights
        .iter()
        .all(|l| l.kind() == LightKind::DeltaPosition));
    let settings = |algorithm, seed| RenderSettings {
        algorithm,
        seed,
        max_depth: 8,
        photons: 10_000,
        radius: Radius::World(0.05),
        ..RenderSettings::for_algorithm(&scene, algorithm)
    };
    let pt = image_mean(&scene, &settings(Algorithm::Path, 1), 400);
    for algorithm in [Algorithm::Ppm, Algorithm::Sppm, Algorithm::Vcm] {
        let other = match algorithm {
            // SPPM's iterations share per-pixel state: whole renders are the samples.
            Algorithm::Sppm => {
                let stats = sppm_stats(&scene, &settings(algorithm, 2), 8, 30);
                (stats.image_mean(), stats.image_mean_se())
            }
            Algorithm::Ppm => image_mean(&scene, &settings(algorithm, 2), 40),
            _ => image_mean(&scene, &settings(algorithm, 2), 200),
        };
        let se = pt.1.hypot(other.1);
        eprintln!("spot box: pt {pt:?}, {algorithm:?} {other:?}");
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
fn the_path_tracer_warning_names_a_spot_light_behind_a_mirror() {
    // The spot box has no specular surface: nothing is missing from a path-traced image.
    assert!(!spot_box(4)
        .build()
        .unwrap()
        .has_delta_light_behind_specular());
    let mut b = spot_box(4);
    let mirror = b.add_material(Material::new(Bsdf::mirror(Vec3::ONE), Vec3::ZERO));
    b.add_sphere(Sphere::new(Vec3::new(0.5, 0.3, 0.0), 0.3, mirror));
    assert!(b.build().unwrap().has_delta_light_behind_specular());
}

#[test]
fn lights_keep_their_order_and_are_named_by_their_place_in_the_list() {
    let mut b = spot_box(4);
    b.add_point_light(PointLight {
        position: Vec3::new(0.0, 1.0, 0.0),
        intensity: Vec3::ONE,
    });
    let hot = Light::spot(Vec3::Y, Vec3::NEG_Y, Vec3::splat(1e30), 0.5, 0.2).unwrap();
    b.add_light(hot);
    let err = b
        .build()
        .err()
        .expect("a spot light of 1e30 W/sr")
        .to_string();
    assert!(
        err.contains("spot light 2") && err.contains("power"),
        "{err}"
    );
    // The area lights first (primitive order), then the added lights as added.
    let mut b = spot_box(4);
    let lamp = b.add_material(Material::new(Bsdf::diffuse(Vec3::ZERO), Vec3::ONE));
    b.add_sphere(Sphere::new(Vec3::new(0.0, 1.0, 0.0), 0.1, lamp));
    b.add_point_light(PointLight {
        position: Vec3::new(0.0, 1.0, 0.0),
        intensity: Vec3::ONE,
    });
    let kinds: Vec<LightKind> = b.build().unwrap().lights.iter().map(|l| l.kind()).collect();
    assert_eq!(
        kinds,
        [
            LightKind::Area,
            LightKind::DeltaPosition,
            LightKind::DeltaPosition
        ]
    );
    // An area light cannot be added as a light: it would have no geometry to hit.
    let mut b = spot_box(4);
    b.add_light(Light::sphere(Sphere::new(Vec3::Y, 0.1, 0), Vec3::ONE, 0));
    assert!(b.build().is_err());
}

#[test]
fn spot_lights_with_unusable_axes_or_angles_are_refused() {
    let spot = |direction: Vec3, cone: f32, start: f32| {
        Light::spot(Vec3::ZERO, direction, Vec3::ONE, cone, start)
    };
    assert!(spot(Vec3::Y, 0.5, 0.2).is_some());
    assert!(spot(Vec3::Y, 0.5, 0.5).is_some(), "a sharp edge");
    assert!(
        spot(Vec3::Y, std::f32::consts::PI, 0.0).is_some(),
        "the whole sphere"
    );
    assert!(spot(Vec3::ZERO, 0.5, 0.2).is_none());
    assert!(spot(Vec3::new(f32::NAN, 1.0, 0.0), 0.5, 0.2).is_none());
    assert!(spot(Vec3::Y, 0.0, 0.0).is_none());
    assert!(spot(Vec3::Y, 0.5, 0.6).is_none());
    assert!(spot(Vec3::Y, 0.5, -0.1).is_none());
    assert!(spot(Vec3::Y, 3.5, 0.1).is_none());
}

#[test]
fn a_moved_and_scaled_delta_light_lights_the_moved_points_alike() {
    // `Light::transform` (the scene-moving test helpers use it): with every point p taken to
    // p s + o, the radiance arriving at the image of p is what arrived at p (to f32 rounding
    // of the moved points, magnified by the falloff's slope).
    let point = Light::Point(PointLight {
        position: Vec3::new(0.2, 1.5, -0.3),
        intensity: Vec3::new(1.0, 2.0, 3.0),
    });
    let mut rng = Rng::new(3, 0, 0);
    for light in [downward_spot(), point] {
        for (scale, offset) in [
            (1.0, Vec3::new(10.0, -2.0, 5.0)),
            (0.01, Vec3::X),
            (40.0, Vec3::ZERO),
        ] {
            let mut moved = light.clone();
            moved.transform(scale, offset);
            assert_eq!(moved.kind(), light.kind());
            for _ in 0..200 {
                let p = Vec3::new(
                    rng.uniform() * 4.0 - 2.0,
                    rng.uniform() * 2.0,
                    rng.uniform() - 0.5,
                );
                let li = |l: &Light, p: Vec3| {
                    l.sample_direct(p, Vec2::ZERO).map_or(Vec3::ZERO, |s| s.li)
                };
                let (before, after) = (li(&light, p), li(&moved, p * scale + offset));
                assert!(
                    (before - after).abs().max_element() <= 1e-3 * before.max_element() + 1e-6,
                    "{}: at {p}, scale {scale}: {before} then {after}",
                    light.name()
                );
            }
        }
    }
}
