//! The environment light in every integrator: a diffuse sphere under a constant sky (the
//! furnace: radiance a L on the sphere, L beside it), a sun-and-sky map over a floor where
//! every algorithm agrees with the path tracer, and the share of environment photons that
//! reach the scene. The contract checks common to every light are in `light_harness.rs`;
//! the image against Mitsuba 3 is in `crates/ppm-scene/tests/environment.rs`.

use ppm_test_support::test_scenes;

use glam::Mat3;
use ppm_core::light::{EnvironmentLight, EnvironmentMap, LatLongMap, Light};
use ppm_core::prelude::*;
use std::sync::Arc;
use test_scenes::{assert_agrees_with_pt, render_stats, sppm_stats, PixelStats};

/// The sky's radiance (W/(m^2 sr)), per channel.
const SKY: Vec3 = Vec3::new(0.8, 1.0, 1.3);
/// The sphere's albedo.
const ALBEDO: f32 = 0.6;

fn constant_sky() -> Light {
    Light::Environment(
        EnvironmentLight::new(EnvironmentMap::Constant(SKY), 1.0, Mat3::IDENTITY).unwrap(),
    )
}

/// A unit diffuse sphere at the origin under the constant sky, seen from 4 away with a
/// 40 degree field of view (the sphere covers the middle of the image, the sky the corners).
fn sphere_under_sky(resolution: u32) -> Scene {
    let camera = Camera::new(
        Vec3::new(0.0, 0.0, 4.0),
        Vec3::ZERO,
        Vec3::Y,
        40.0,
        (resolution, resolution),
    )
    .unwrap();
    let mut b = SceneBuilder::new(camera);
    let m = b.add_material(Material::new(
        Bsdf::diffuse(Vec3::splat(ALBEDO)),
        Vec3::ZERO,
    ));
    b.add_sphere(Sphere::new(Vec3::ZERO, 1.0, m));
    b.add_light(constant_sky());
    b.build().unwrap()
}

/// Which pixels lie wholly on the sphere (all four corner rays hit it) and wholly off it
/// (all four pass it by more than 2% of its radius): the silhouette is convex, so a pixel
/// whose corners are all on it is on it.
fn classify(scene: &Scene) -> (Vec<usize>, Vec<usize>) {
    let (w, h) = (scene.camera.width as usize, scene.camera.height as usize);
    let (mut on, mut off) = (Vec::new(), Vec::new());
    // The scene is camera-relative: the sphere's centre is at minus the camera position.
    let centre = -scene.origin;
    for pixel in 0..w * h {
        let (x, y) = ((pixel % w) as f32, (pixel / w) as f32);
        let miss_distance = |dx: f32, dy: f32| {
            let ray = scene.camera.generate_ray(Vec2::new(x + dx, y + dy));
            let to_centre = centre - ray.origin;
            (to_centre - ray.dir * to_centre.dot(ray.dir)).length()
        };
        let d = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)].map(|(a, b)| miss_distance(a, b));
        if d.iter().all(|&d| d < 1.0) {
            on.push(pixel);
        } else if d.iter().all(|&d| d > 1.02) {
            off.push(pixel);
        }
    }
    (on, off)
}

/// The mean over `pixels` and its standard error from the spread of the iterations (the
/// pixels of one photon-mapping iteration share its photons).
fn region_mean(stats: &[Vec<Vec3>], pixels: &[usize], c: usize) -> (f64, f64) {
    let means: Vec<f64> = stats
        .iter()
        .map(|image| pixels.iter().map(|&p| image[p][c] as f64).sum::<f64>() / pixels.len() as f64)
        .collect();
    let n = means.len() as f64;
    let m = means.iter().sum::<f64>() / n;
    let var = means.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (n - 1.0);
    (m, (var / n).sqrt())
}

/// Every iteration's estimates (or, for sppm, each independent render's final image).
fn images(scene: &Scene, settings: &RenderSettings, samples: u32) -> Vec<Vec<Vec3>> {
    if settings.algorithm == Algorithm::Sppm {
        return (0..samples as u64)
            .map(|seed| {
                let s = RenderSettings {
                    seed: settings.seed + seed,
                    ..settings.clone()
                };
                let mut r = Renderer::new(scene, &s);
                for _ in 0..10 {
                    r.iterate(scene);
                }
                assert_eq!(r.rejected(), 0);
                r.image().pixels
            })
            .collect();
    }
    let mut r = Renderer::new(scene, settings);
    let out = (0..samples)
        .map(|_| {
            r.iterate(scene);
            r.last_estimates().to_vec()
        })
        .collect();
    assert_eq!(r.rejected(), 0, "NaN or Inf samples");
    out
}

#[test]
fn a_diffuse_sphere_under_a_constant_sky_is_albedo_times_sky_in_every_algorithm() {
    // A convex sphere sees only the sky: the radiance it reflects is (a / pi) integral of
    // L cos over the hemisphere = a L, after one bounce; pixels beside it see L itself, with
    // weight 1 on every sample (the camera ray is the only technique for them).
    let scene = sphere_under_sky(16);
    let (on, off) = classify(&scene);
    assert!(
        on.len() > 40 && off.len() > 40,
        "{} {}",
        on.len(),
        off.len()
    );
    for algorithm in [
        Algorithm::Path,
        Algorithm::Ppm,
        Algorithm::Sppm,
        Algorithm::Vcm,
        Algorithm::Bpt,
    ] {
        let settings = RenderSettings {
            algorithm,
            seed: 5,
            max_depth: 6,
            photons: 20_000,
            // The sphere's irradiance is uniform, and the part of a sphere within distance r
            // of a point on it has area pi r^2 exactly (Archimedes): a large radius adds no
            // bias here.
            radius: Radius::World(0.15),
            // The photon density is what ppm and sppm are tested on (with direct light
            // sampled, a convex sphere stores no photon at all).
            direct: DirectMode::Photons,
            ..RenderSettings::for_algorithm(&scene, algorithm)
        };
        let samples = match algorithm {
            Algorithm::Sppm => 16,
            _ => 200,
        };
        let stats = images(&scene, &settings, samples);
        for image in &stats {
            for &p in &off {
                assert_eq!(image[p], SKY, "{algorithm:?}: pixel {p} sees the sky");
            }
        }
        for c in 0..3 {
            let (mean, se) = region_mean(&stats, &on, c);
            let expected = (ALBEDO * SKY[c]) as f64;
            eprintln!("{algorithm:?} channel {c}: {mean} +- {se} vs {expected}");
            // Within 4 standard errors, and those small: 0.4% of the answer at most.
            assert!(
                (mean - expected).abs() < 4.0 * se + 1e-6 && se < 0.004 * expected,
                "{algorithm:?} channel {c}: sphere {mean} +- {se}, expected a L = {expected}"
            );
        }
    }
}

#[test]
fn environment_photons_hit_the_sphere_in_proportion_to_its_cross_section() {
    // Light paths leave a disk of radius R (the bounding sphere of the scene, sqrt(3) 1.001
    // for the unit sphere's bounding box) in directions that do not matter for a sphere: a
    // fraction pi 1^2 / (pi R^2) = 1 / (3 1.001^2) of them hits it and, at depth 1 with
    // every bounce stored, stores one photon. The rest never reach the scene.
    let scene = sphere_under_sky(4);
    let settings = RenderSettings {
        algorithm: Algorithm::Ppm,
        seed: 1,
        max_depth: 1,
        photons: 200_000,
        radius: Radius::World(0.05),
        direct: DirectMode::Photons,
        ..RenderSettings::for_algorithm(&scene, Algorithm::Ppm)
    };
    let mut r = Renderer::new(&scene, &settings);
    let stats = r.iterate(&scene);
    let fraction = stats.photons as f64 / stats.light_paths as f64;
    let expected = 1.0 / (3.0 * 1.001f64.powi(2));
    let se = (expected * (1.0 - expected) / stats.light_paths as f64).sqrt();
    eprintln!("stored per light path {fraction}, expected {expected} (se {se})");
    assert!(
        (fraction - expected).abs() < 5.0 * se,
        "{fraction} vs {expected}"
    );
}

/// A 32 x 16 map: a sky brightening toward the zenith over a dark ground, and a 2 x 1 texel
/// sun 1000 times brighter than the sky, 45 degrees up and off to the side.
pub fn sun_and_sky_map() -> LatLongMap {
    let (w, h) = (32, 16);
    let texels = (0..w * h)
        .map(|k| {
            let (x, y) = (k % w, k / w);
            if (x == 5 || x == 6) && y == 4 {
                Vec3::new(900.0, 800.0, 600.0)
            } else if y < h / 2 {
                Vec3::new(0.3, 0.5, 0.9) * (1.5 - y as f32 / h as f32)
            } else {
                Vec3::new(0.1, 0.08, 0.05)
            }
        })
        .collect();
    LatLongMap::new(w, h, texels).unwrap()
}

/// A 4 x 4 diffuse floor at y = 0 and a diffuse sphere resting on it under the sun-and-sky
/// map, rotated 20 degrees about the vertical.
fn sunny_floor(resolution: u32) -> Scene {
    sunny_floor_of_size(resolution, 4.0)
}

/// [`sunny_floor`] with a floor `size` units wide.
fn sunny_floor_of_size(resolution: u32, size: f32) -> Scene {
    let camera = Camera::new(
        Vec3::new(0.0, 1.2, 3.0),
        Vec3::new(0.0, 0.3, 0.0),
        Vec3::Y,
        45.0,
        (resolution, resolution),
    )
    .unwrap();
    let mut b = SceneBuilder::new(camera);
    let floor = b.add_material(Material::new(Bsdf::diffuse(Vec3::splat(0.5)), Vec3::ZERO));
    let ball = b.add_material(Material::new(
        Bsdf::diffuse(Vec3::new(0.7, 0.3, 0.2)),
        Vec3::ZERO,
    ));
    b.add_mesh(TriangleMesh::quad(
        Vec3::new(-0.5 * size, 0.0, -0.5 * size),
        Vec3::Z * size,
        Vec3::X * size,
        floor,
    ));
    b.add_sphere(Sphere::new(Vec3::new(0.0, 0.5, 0.0), 0.5, ball));
    let map = EnvironmentMap::Image(Arc::new(sun_and_sky_map()));
    let rotation = Mat3::from_rotation_y(20f32.to_radians());
    b.add_light(Light::Environment(
        EnvironmentLight::new(map, 1.0, rotation).unwrap(),
    ));
    b.build().unwrap()
}

#[test]
fn every_algorithm_agrees_with_the_path_tracer_under_a_sun_and_sky_map() {
    let scene = sunny_floor(12);
    let settings = |algorithm, seed| RenderSettings {
        algorithm,
        seed,
        max_depth: 6,
        photons: 20_000,
        radius: Radius::World(0.04),
        ..RenderSettings::for_algorithm(&scene, algorithm)
    };
    let pt = render_stats(&scene, &settings(Algorithm::Path, 1), 200);
    for algorithm in [
        Algorithm::Ppm,
        Algorithm::Sppm,
        Algorithm::Vcm,
        Algorithm::Bpt,
    ] {
        let other: PixelStats = match algorithm {
            Algorithm::Sppm => sppm_stats(&scene, &settings(algorithm, 2), 8, 20),
            Algorithm::Ppm => render_stats(&scene, &settings(algorithm, 2), 40),
            _ => render_stats(&scene, &settings(algorithm, 2), 150),
        };
        let label = format!("{algorithm:?}");
        match algorithm {
            // Photon mapping's kernel blurs the sun's shadow edge, a consistent estimator's
            // bias there that pixels this size resolve: its image mean is compared.
            Algorithm::Ppm | Algorithm::Sppm => {
                let (a, b) = (pt.image_mean(), other.image_mean());
                let se = pt.image_mean_se().hypot(other.image_mean_se());
                eprintln!("sun and sky: pt {a} {label} {b} (se of difference {se})");
                assert!(
                    (a - b).abs() < 4.0 * se && (a - b).abs() < 0.02 * a,
                    "{label}: image mean {b} against pt {a} (se {se})"
                );
            }
            _ => assert_agrees_with_pt("sun and sky", &label, &pt, &other, Some(0.02), 2.0),
        }
    }
}

/// Of `n` light paths of `scene`'s lights: the fraction whose first hit is on the geometry,
/// the fraction whose first hit the camera sees (inside the image, unoccluded), and the
/// fraction of those within the square |x|, |z| <= 2 (world coordinates) around the
/// sphere, each with its standard error.
fn landing_fractions(scene: &Scene, n: u32) -> [(f64, f64); 3] {
    let mut rng = ppm_core::sampling::Rng::new(11, 0, 0);
    let (mut hit, mut seen, mut near) = (0u32, 0u32, 0u32);
    for _ in 0..n {
        let (u_light, u_pos, u_dir) = (rng.uniform(), rng.uniform2(), rng.uniform2());
        let Some(s) = scene.sample_emission(u_light, u_pos, u_dir) else {
            continue;
        };
        let Some(h) = scene.intersect(&ppm_core::geometry::Ray::new(s.ray_origin, s.dir)) else {
            continue;
        };
        hit += 1;
        if scene.camera.raster_position(h.p).is_some() {
            let to_camera = ppm_core::geometry::Ray::spawn_to(h.p, h.ng, Vec3::ZERO, Vec3::ZERO);
            // The stored scene is camera-relative: the camera is at the origin.
            if !scene.occluded(&to_camera) && h.ng.dot(-h.p) > 0.0 {
                seen += 1;
                let world = h.p + scene.origin;
                near += (world.x.abs() <= 2.0 && world.z.abs() <= 2.0) as u32;
            }
        }
    }
    [hit, seen, near].map(|k| {
        let p = k as f64 / n as f64;
        (p, (p * (1.0 - p) / n as f64).sqrt())
    })
}

#[test]
fn the_share_of_environment_photons_the_camera_sees_is_the_visible_cross_section() {
    // The unit sphere under the constant sky, from 4 away: a third of the light paths hit
    // it (pi 1^2 / pi R^2, R = sqrt(3) 1.001), spread uniformly over it, and the camera sees
    // the cap within cos theta > 1/4 of the sphere's area: 2 pi (1 - 1/4) / (4 pi) = 3/8.
    let scene = sphere_under_sky(16);
    let [(hit, hit_se), (seen, seen_se), _] = landing_fractions(&scene, 400_000);
    let r2 = 3.0 * 1.001f64.powi(2);
    eprintln!("sphere: hit {hit} +- {hit_se}, seen {seen} +- {seen_se}");
    assert!((hit - 1.0 / r2).abs() < 5.0 * hit_se, "{hit}");
    assert!((seen - 0.375 / r2).abs() < 5.0 * seen_se, "{seen}");
}

#[test]
fn a_larger_ground_leaves_fewer_environment_photons_in_view() {
    // The same sphere on grounds of 4, 40 and 400 units under the sun-and-sky map: the disk
    // of origins covers the whole ground, so the share of photons the camera sees around
    // the sphere (the 4 x 4 square under it) falls about as the inverse square of the
    // ground's size (numbers in docs/environment.md).
    let mut seen = Vec::new();
    for size in [4.0f32, 40.0, 400.0] {
        let scene = sunny_floor_of_size(12, size);
        let [(hit, _), (anywhere, _), (s, se)] = landing_fractions(&scene, 400_000);
        eprintln!("ground {size}: hit {hit:.4}, seen {anywhere:.5}, seen near the sphere {s:.6} +- {se:.6}");
        seen.push((s, se));
    }
    for pair in seen.windows(2) {
        assert!(pair[1].0 * 20.0 < pair[0].0 + 5.0 * pair[0].1, "{seen:?}");
    }
}
