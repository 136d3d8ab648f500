//! End-to-end: every shipped scene renders with both algorithms, with no NaN or Inf, and the
//! renders survive moving the scene far from the origin or shrinking it.

use ppm_test_support::test_scenes;

use ppm_core::light::Light;
use ppm_core::prelude::*;
use ppm_tests::{load_small, SCENES};
use test_scenes::{z_scores, PixelStats};

#[test]
fn every_scene_renders_with_both_algorithms_without_nan() {
    for name in SCENES {
        let scene = load_small(name, 48, 40).build().unwrap();
        for algorithm in [Algorithm::Path, Algorithm::Ppm] {
            let settings = RenderSettings {
                algorithm,
                photons: 20_000,
                ..RenderSettings::new(&scene)
            };
            let mut r = Renderer::new(&scene, &settings);
            for _ in 0..3 {
                let stats = r.iterate(&scene);
                assert_eq!(stats.rejected, 0, "{name} {algorithm:?}: NaN/Inf samples");
            }
            let image = r.image();
            assert!(image
                .pixels
                .iter()
                .all(|p| p.is_finite() && p.min_element() >= 0.0));
            let mean = image.mean();
            assert!(
                mean.min_element() > 0.01,
                "{name} {algorithm:?}: too dark ({mean})"
            );
        }
    }
}

/// Moves and scales every position of a scene (and the camera): world' = world * scale + offset.
fn transform(mut b: SceneBuilder, scale: f32, offset: Vec3) -> SceneBuilder {
    for m in &mut b.meshes {
        for p in &mut m.positions {
            *p = *p * scale + offset;
        }
    }
    for s in &mut b.spheres {
        s.center = s.center * scale + offset;
        s.radius *= scale;
    }
    for l in &mut b.lights {
        l.transform(scale, offset); // keeps the irradiance it gives at scaled distances
    }
    b.camera = b.camera.with_position(b.camera.position * scale + offset);
    b
}

fn render(scene: &Scene, settings: &RenderSettings, iterations: u32) -> PixelStats {
    let mut r = Renderer::new(scene, settings);
    let mut stats = PixelStats::new((scene.camera.width * scene.camera.height) as usize);
    for _ in 0..iterations {
        r.iterate(scene);
        stats.add(r.last_estimates());
    }
    assert_eq!(r.rejected(), 0);
    stats
}

#[test]
fn far_and_tiny_scenes_render_like_the_original() {
    // Radiance is invariant under moving or uniformly scaling a scene (camera, lights and
    // geometry together): the renders must agree within noise (independent seeds).
    //
    // Positions are f32: 10^5 units from the origin their spacing is 2^-7 = 7.8 mm, coarser
    // than the 3 mm gaps between the water volume and the walls, so the input itself cannot
    // be represented there; the water scene is moved 10^4 units (spacing 1 mm) instead.
    for (name, far) in [
        ("cornell_box_specular.yml", 1e5),
        ("cornell_box_glossy.yml", 1e5),
        ("cornell_box_water.yml", 1e4),
    ] {
        let original = load_small(name, 24, 20).build().unwrap();
        let base = RenderSettings {
            algorithm: Algorithm::Path,
            seed: 1,
            ..RenderSettings::new(&original)
        };
        let reference = render(&original, &base, 400);
        for (scale, offset) in [(1.0, Vec3::splat(far)), (1e-3, Vec3::ZERO)] {
            let scene = transform(load_small(name, 24, 20), scale, offset)
                .build()
                .unwrap();
            let settings = RenderSettings {
                seed: 2,
                ..base.clone()
            };
            let moved = render(&scene, &settings, 400);
            let z = z_scores(&reference, &moved);
            let beyond = z.iter().filter(|z| z.abs() > 4.5).count();
            let mean_z2 = z.iter().map(|z| z * z).sum::<f64>() / z.len() as f64;
            assert!(
                beyond <= 2 && mean_z2 < 1.5,
                "{name} scale {scale} offset {offset}: {beyond} of {} beyond 4.5 sigma, mean z^2 {mean_z2}",
                z.len()
            );
            let (a, b) = (reference.image_mean(), moved.image_mean());
            let se = (reference.image_mean_se().powi(2) + moved.image_mean_se().powi(2)).sqrt();
            assert!(
                (a - b).abs() < 4.0 * se,
                "{name} scale {scale}: image mean {a} vs {b}"
            );
        }
    }
}

/// A scene of lights only (`objects:` empty, which the format allows; a point and a spot
/// light) renders black with
/// every algorithm: nothing to gather on, yet the `auto` radius must still be a valid one
/// (it fell back to a fraction of the scene's diagonal, 0 here, and the photon grid
/// refused it with a panic).
#[test]
fn a_scene_without_geometry_renders_black_with_every_algorithm() {
    let mut builder = load_small("cornell_box.yml", 16, 16);
    builder.meshes.clear();
    builder.spheres.clear();
    builder.add_point_light(PointLight {
        position: Vec3::new(0.0, 1.0, 0.0),
        intensity: Vec3::ONE,
    });
    let spot = Light::spot(Vec3::Y, Vec3::NEG_Y, Vec3::ONE, 0.5, 0.3).unwrap();
    builder.add_light(spot);
    let scene = builder.build().unwrap();
    for algorithm in Algorithm::ALL {
        let settings = RenderSettings {
            algorithm,
            photons: 1000,
            radius: Radius::Auto,
            ..RenderSettings::new(&scene)
        };
        let mut r = Renderer::new(&scene, &settings);
        for _ in 0..2 {
            let stats = r.iterate(&scene);
            assert_eq!(stats.rejected, 0, "{algorithm:?}: rejected samples");
        }
        let image = r.image();
        assert!(
            image.pixels.iter().all(|p| *p == Vec3::ZERO),
            "{algorithm:?}: light from nowhere"
        );
    }
}
