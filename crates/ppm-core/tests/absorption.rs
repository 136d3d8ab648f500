//! Absorbing media (Beer-Lambert, `ppm_core::medium`): index-matched slabs in front of a
//! uniform emitter transmit exp(-sigma_a d / cos) in every pixel (computed here by
//! quadrature over the pixel), a camera inside an absorbing sphere sees exp(-sigma_a R)
//! exactly, nested media (water in glass) multiply their transmittances, and every
//! estimator agrees with the path tracer on caustics through coloured glass.

use ppm_core::bsdf::{Dielectric, Ggx};
use ppm_core::medium::MediumInterface;
use ppm_core::prelude::*;
use ppm_test_support::test_scenes::{
    add_block, assert_agrees_with_pt, cornell_builder, render_stats, sppm_stats, BoxContents,
};

/// Absorption of the outer medium (glass), per unit length: clearly different per channel.
const SIGMA_GLASS: Vec3 = Vec3::new(0.3, 0.9, 1.6);
/// Absorption of the inner medium (water in the glass).
const SIGMA_WATER: Vec3 = Vec3::new(1.2, 0.4, 0.05);

/// Every camera-path estimator: each must see the emitter through the media alike.
const CAMERA_ALGORITHMS: [Algorithm; 4] = [
    Algorithm::Path,
    Algorithm::Ppm,
    Algorithm::Sppm,
    Algorithm::Vcm,
];

/// A camera at `position` looking at the origin (up +z when it looks along y), 6x6 pixels,
/// inside an inward-facing sphere of radius 30 that emits 1 and reflects nothing.
fn emitter_scene(position: Vec3, look_at: Vec3, up: Vec3, fov: f32) -> SceneBuilder {
    let camera = Camera::new(position, look_at, up, fov, (6, 6)).unwrap();
    let mut b = SceneBuilder::new(camera);
    let emitter = b.add_material(Material::new(Bsdf::diffuse(Vec3::ZERO), Vec3::ONE));
    b.add_sphere(Sphere::new(Vec3::ZERO, 30.0, emitter).inward());
    b
}

/// Index-matched glass (ior 1: no reflection, no refraction) filled with `sigma_a`.
fn matched_glass(sigma_a: Vec3) -> Material {
    Material::new(Bsdf::glass(1.0, Vec3::ONE), Vec3::ZERO).with_medium(MediumInterface {
        interior: sigma_a,
        exterior: Vec3::ZERO,
    })
}

/// Renders `iterations` iterations of `algorithm` and returns the per-pixel means.
fn render(scene: &Scene, algorithm: Algorithm, iterations: u32) -> Vec<Vec3> {
    // Russian roulette off: its noise is not what is tested here.
    let settings = RenderSettings {
        photons: 200,
        radius: Radius::World(0.05),
        rr_depth: 1000,
        ..RenderSettings::for_algorithm(scene, algorithm)
    };
    let mut r = Renderer::new(scene, &settings);
    for _ in 0..iterations {
        r.iterate(scene);
    }
    assert_eq!(r.rejected(), 0, "{algorithm:?}: NaN or Inf samples");
    r.image().pixels
}

/// The mean over pixel (x, y)'s square of `transmittance(dir)`, by a Q x Q midpoint rule
/// over film positions (the pixel's box filter), in f64.
fn pixel_mean(scene: &Scene, x: u32, y: u32, transmittance: impl Fn(Vec3) -> [f64; 3]) -> Vec3 {
    const Q: u32 = 48;
    let mut sum = [0.0f64; 3];
    for i in 0..Q {
        for j in 0..Q {
            let film = Vec2::new(
                x as f32 + (i as f32 + 0.5) / Q as f32,
                y as f32 + (j as f32 + 0.5) / Q as f32,
            );
            let t = transmittance(scene.camera.generate_ray(film).dir);
            for c in 0..3 {
                sum[c] += t[c];
            }
        }
    }
    let n = (Q * Q) as f64;
    Vec3::new(
        (sum[0] / n) as f32,
        (sum[1] / n) as f32,
        (sum[2] / n) as f32,
    )
}

/// Checks every pixel of every camera-path estimator against `expected` (per pixel, from
/// [`pixel_mean`]) within `rel` (the pixel-jitter noise of `iterations` samples).
fn assert_pixels(scene: &Scene, expected: &[Vec3], iterations: u32, rel: f32, what: &str) {
    for algorithm in CAMERA_ALGORITHMS {
        let got = render(scene, algorithm, iterations);
        for (i, (g, e)) in got.iter().zip(expected).enumerate() {
            let err = ((*g - *e) / *e).abs().max_element();
            assert!(
                err < rel,
                "{what}, {algorithm:?}: pixel {i}: {g} against {e} (relative error {err})"
            );
        }
    }
}

/// exp(-sum_k sigma_k d_k / |cos|) per channel, in f64: a ray through slabs of thickness
/// d_k along y at angle acos(|cos|) to their normal.
fn through_slabs(dir: Vec3, slabs: &[(Vec3, f64)]) -> [f64; 3] {
    let cos = (dir.y as f64).abs();
    let mut out = [0.0; 3];
    for (c, o) in out.iter_mut().enumerate() {
        let tau: f64 = slabs.iter().map(|(s, d)| s[c] as f64 * d).sum();
        *o = (-tau / cos).exp();
    }
    out
}

/// The camera above a slab (y in [-0.5, 0.5], 40 units wide) of index-matched absorbing glass,
/// looking down through it at the emitter: L = exp(-sigma_a 1 / |cos|) along each ray.
#[test]
fn an_index_matched_slab_transmits_beer_lambert() {
    let mut b = emitter_scene(Vec3::new(0.0, 3.0, 0.0), Vec3::ZERO, Vec3::Z, 40.0);
    let glass = b.add_material(matched_glass(SIGMA_GLASS));
    add_block(&mut b, Vec3::new(0.0, -0.5, 0.0), 40.0, 1.0, glass);
    let scene = b.build().unwrap();
    let expected: Vec<Vec3> = (0..36)
        .map(|i| {
            pixel_mean(&scene, i % 6, i / 6, |d| {
                through_slabs(d, &[(SIGMA_GLASS, 1.0)])
            })
        })
        .collect();
    // The centre of the image looks straight through: exp(-sigma_a) to a percent or so.
    let centre = expected[3 * 6 + 3];
    let straight = (-SIGMA_GLASS).exp();
    assert!(((centre - straight) / straight).abs().max_element() < 0.05);
    assert_pixels(&scene, &expected, 256, 0.01, "slab");
}

/// Water (sigma_w) in an index-matched glass (sigma_g): the camera looks down through glass
/// (0.5), water (1), glass (0.5). The water|glass surface is one interface (a dielectric of
/// relative index 1) naming both media; L = exp(-(sigma_g + sigma_w) / |cos|), the product
/// of the two media's transmittances.
#[test]
fn nested_media_multiply_their_transmittances() {
    let mut b = emitter_scene(Vec3::new(0.0, 3.0, 0.0), Vec3::ZERO, Vec3::Z, 40.0);
    let glass = b.add_material(matched_glass(SIGMA_GLASS));
    let water = b.add_material(
        Material::new(Bsdf::dielectric(1.0, None), Vec3::ZERO).with_medium(MediumInterface {
            interior: SIGMA_WATER,
            exterior: SIGMA_GLASS,
        }),
    );
    add_block(&mut b, Vec3::new(0.0, -1.0, 0.0), 40.0, 2.0, glass);
    add_block(&mut b, Vec3::new(0.0, -0.5, 0.0), 36.0, 1.0, water);
    let scene = b.build().unwrap();
    let slabs = [(SIGMA_GLASS, 1.0), (SIGMA_WATER, 1.0)];
    let expected: Vec<Vec3> = (0..36)
        .map(|i| pixel_mean(&scene, i % 6, i / 6, |d| through_slabs(d, &slabs)))
        .collect();
    assert_pixels(&scene, &expected, 256, 0.01, "water in glass");
}

/// The camera at the centre of an absorbing, index-matched glass sphere of radius 2: every
/// ray travels exactly 2 in the medium, so every sample of every pixel is exp(-2 sigma_a).
#[test]
fn a_camera_inside_a_medium_sees_through_it() {
    let mut b = emitter_scene(Vec3::ZERO, Vec3::NEG_Z, Vec3::Y, 60.0);
    let glass = b.add_material(matched_glass(SIGMA_GLASS));
    b.add_sphere(Sphere::new(Vec3::ZERO, 2.0, glass));
    let scene = b.build().unwrap();
    let expected = vec![(-2.0 * SIGMA_GLASS).exp(); 36];
    assert_pixels(&scene, &expected, 4, 1e-4, "camera inside");
}

/// The diffuse Cornell box with a coloured glass sphere (ior 1.5: a caustic tinted by the
/// path length through it) and a rough absorbing dielectric sphere (connections and merges
/// between its inner surface points cross its medium). With `fog`, the box itself is
/// filled with a weakly absorbing medium, which every surface in it names as its exterior
/// (the walls' normals point into the box): the camera, the lamp, shadow rays, connections
/// and light tracing to the camera are all inside a medium.
fn coloured_glass_box(fog: Vec3) -> Scene {
    let mut b = cornell_builder(16, BoxContents::Diffuse);
    let glass = b.add_material(
        Material::new(Bsdf::glass(1.5, Vec3::ONE), Vec3::ZERO).with_medium(MediumInterface {
            interior: Vec3::new(0.5, 2.0, 4.0),
            exterior: Vec3::ZERO,
        }),
    );
    b.add_sphere(Sphere::new(Vec3::new(0.45, 0.35, 0.1), 0.35, glass));
    let rough = b.add_material(
        Material::new(
            Bsdf::Dielectric(Dielectric {
                eta: 1.33,
                specular_reflectance: Vec3::ONE,
                specular_transmittance: Vec3::ONE,
                roughness: Some(Ggx::isotropic(0.3).into()),
            }),
            Vec3::ZERO,
        )
        .with_medium(MediumInterface {
            interior: Vec3::new(3.0, 1.0, 0.3),
            exterior: Vec3::ZERO,
        }),
    );
    b.add_sphere(Sphere::new(Vec3::new(-0.4, 1.2, -0.3), 0.3, rough));
    for m in &mut b.materials {
        m.medium.exterior = fog;
    }
    b.build().unwrap()
}

#[test]
fn every_estimator_agrees_with_the_path_tracer_through_coloured_glass() {
    for (fog, name) in [
        (Vec3::ZERO, "coloured glass"),
        (
            Vec3::new(0.3, 0.2, 0.1),
            "coloured glass in an absorbing box",
        ),
    ] {
        agree_with_pt(&coloured_glass_box(fog), name);
    }
}

/// Renders `scene` with pt, ppm, vcm, bpt and sppm and checks that each agrees with pt.
fn agree_with_pt(scene: &Scene, name: &str) {
    assert!(scene.has_absorption());
    let pt = render_stats(
        scene,
        &RenderSettings {
            seed: 1,
            ..RenderSettings::for_algorithm(scene, Algorithm::Path)
        },
        2000,
    );
    let settings = |algorithm| RenderSettings {
        seed: 2,
        radius: Radius::World(0.04),
        photons: 20_000,
        ..RenderSettings::for_algorithm(scene, algorithm)
    };
    for (algorithm, iterations) in [
        (Algorithm::Ppm, 64),
        (Algorithm::Vcm, 400),
        (Algorithm::Bpt, 400),
    ] {
        let other = render_stats(scene, &settings(algorithm), iterations);
        let label = format!("{algorithm:?}");
        assert_agrees_with_pt(name, &label, &pt, &other, Some(0.02), 1.6);
    }
    let sppm = sppm_stats(
        scene,
        &RenderSettings {
            photons: 2000,
            ..settings(Algorithm::Sppm)
        },
        12,
        48,
    );
    assert_agrees_with_pt(name, "Sppm", &pt, &sppm, Some(0.02), 1.6);
}
