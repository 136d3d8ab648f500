//! Never losing a render, at the core: a path depth bound that keeps every
//! iteration finite, iterations that can be abandoned without touching the image, memory
//! stated before it is allocated, and light powers that must fit f32 arithmetic.

use ppm_test_support::test_scenes;

use ppm_core::integrator::{MemoryPart, Setting, Snapshot, MAX_DEPTH, PILOT_LIGHT_PATHS};
use ppm_core::light::MAX_EMISSION;
use ppm_core::prelude::*;
use std::sync::atomic::{AtomicU32, Ordering};
use test_scenes::{cornell, BoxContents};

/// An inward perfect mirror sphere around the camera, lit by a point light: Russian roulette
/// never ends a path (the mirror keeps all the throughput) and no surface stores a photon.
fn mirror_sphere(resolution: u32) -> Scene {
    let camera = Camera::new(
        Vec3::ZERO,
        Vec3::NEG_Z,
        Vec3::Y,
        60.0,
        (resolution, resolution),
    )
    .unwrap();
    let mut b = SceneBuilder::new(camera);
    let mirror = b.add_material(Material::new(Bsdf::mirror(Vec3::ONE), Vec3::ZERO));
    b.add_sphere(Sphere::new(Vec3::ZERO, 1.0, mirror).inward());
    b.add_point_light(PointLight {
        position: Vec3::new(0.0, 0.5, 0.0),
        intensity: Vec3::ONE,
    });
    b.build().unwrap()
}

/// A depth far above the bound traces at most MAX_DEPTH bounces per path: an eye path makes
/// at most MAX_DEPTH + 1 intersection tests (the last one only collects emission) and a light
/// path MAX_DEPTH. Without the bound this iteration would trace 100,001 rays per path.
#[test]
fn max_depth_is_bounded_in_a_mirror_box() {
    let scene = mirror_sphere(4);
    for algorithm in [Algorithm::Path, Algorithm::Ppm, Algorithm::Vcm] {
        let settings = RenderSettings {
            algorithm,
            max_depth: 100_000,
            photons: 64,
            ..RenderSettings::new(&scene)
        };
        let mut renderer = Renderer::new(&scene, &settings);
        let stats = renderer.iterate(&scene);
        let pixels = 16u64;
        // Photon mapping adds its light paths, and with the default `photons` radius the
        // first iteration's pilot: one path per pixel, bounded like an eye path, and the
        // pilot photon map's light paths, bounded like light paths. In this all-mirror box no
        // pixel finds a diffuse point, so the rule falls back to `footprint` at the same pilot
        // points, tracing nothing more.
        // VCM traces one light path per pixel, and the same pilot.
        let pilot = pixels * (MAX_DEPTH as u64 + 1) + PILOT_LIGHT_PATHS as u64 * MAX_DEPTH as u64;
        let bound = pixels * (MAX_DEPTH as u64 + 1)
            + match algorithm {
                Algorithm::Ppm => 64 * MAX_DEPTH as u64 + pilot,
                Algorithm::Vcm => pixels * MAX_DEPTH as u64 + pilot,
                _ => 0,
            };
        assert!(
            stats.rays <= bound && stats.rays >= pixels * MAX_DEPTH as u64,
            "{algorithm:?}: {} rays, bound {bound}",
            stats.rays
        );
        assert!(renderer.image().pixels.iter().all(|p| p.is_finite()));
    }
}

/// An iteration stopped part-way is discarded whole: the image is bit for bit the one
/// before it, and the render then continues exactly as if it had never been started.
#[test]
fn an_abandoned_iteration_leaves_no_trace() {
    let scene = cornell(24, BoxContents::Diffuse);
    for algorithm in Algorithm::ALL {
        let settings = RenderSettings {
            algorithm,
            photons: 5000,
            ..RenderSettings::new(&scene)
        };
        let mut reference = Renderer::new(&scene, &settings);
        let mut renderer = Renderer::new(&scene, &settings);
        for _ in 0..2 {
            reference.iterate(&scene);
            renderer.iterate(&scene);
        }
        let before = renderer.image();
        // Say "stop" from the third work item on: some of the pass ran, some did not.
        for allowed in [0u32, 2] {
            let calls = AtomicU32::new(0);
            let stop = || calls.fetch_add(1, Ordering::Relaxed) >= allowed;
            assert!(
                renderer.iterate_until(&scene, &stop).is_none(),
                "{algorithm:?}: a stopped iteration is reported as abandoned"
            );
            assert_eq!(renderer.iterations(), 2, "{algorithm:?}");
            assert_eq!(
                renderer.image(),
                before,
                "{algorithm:?}: the image is untouched"
            );
        }
        for _ in 0..2 {
            reference.iterate(&scene);
            let stats = renderer.iterate_until(&scene, &|| false);
            assert!(stats.is_some());
        }
        assert_eq!(
            renderer.image(),
            reference.image(),
            "{algorithm:?}: the render goes on as if nothing was abandoned"
        );
    }
}

/// Each integrator states what it will allocate: at least what it holds after an iteration
/// (the photon buffer did not need to grow in this box), and the photon part only for
/// photon mapping and the VCM sets that keep light vertices to connect or merge (all but lt,
/// which splats each vertex as it is traced).
#[test]
fn memory_estimates_cover_what_the_integrators_allocate() {
    let scene = cornell(32, BoxContents::Diffuse);
    for algorithm in Algorithm::ALL {
        let settings = RenderSettings {
            algorithm,
            photons: 20_000,
            ..RenderSettings::new(&scene)
        };
        let estimate = Renderer::memory_estimate(&scene, &settings);
        let mut renderer = Renderer::new(&scene, &settings);
        renderer.iterate(&scene);
        let held = renderer.memory_bytes() as u64;
        // What the render holds between iterations; the pilot map of the default radius is
        // freed after the first iteration's pilot pass.
        let kept: u64 = estimate
            .items
            .iter()
            .filter(|i| i.part != MemoryPart::Pilot)
            .map(|i| i.bytes)
            .sum();
        assert!(
            kept >= held && kept <= 2 * held + 32 * 32 * 12,
            "{algorithm:?}: estimate {kept} vs {held} held"
        );
        let pilot = estimate.items.iter().any(|i| i.part == MemoryPart::Pilot);
        assert_eq!(
            pilot,
            algorithm.reads(Setting::Radius),
            "{algorithm:?}: the photons radius's pilot"
        );
        // The saved state the render's end copies is counted exactly.
        let snapshot = renderer.snapshot();
        assert_eq!(
            Snapshot::estimate_bytes(32, 32, algorithm),
            snapshot.memory_bytes() as u64,
            "{algorithm:?}: snapshot"
        );
        let photons = estimate.items.iter().any(|i| i.part == MemoryPart::Photons);
        assert_eq!(
            photons,
            matches!(
                algorithm,
                Algorithm::Ppm | Algorithm::Vcm | Algorithm::Bpt | Algorithm::Bpm
            ),
            "{algorithm:?}: photon part"
        );
    }
    // The largest requests do not overflow and name their part.
    let huge = RenderSettings {
        algorithm: Algorithm::Ppm,
        photons: u32::MAX,
        ..RenderSettings::new(&scene)
    };
    let estimate = Renderer::memory_estimate(&scene, &huge);
    assert_eq!(estimate.largest().unwrap().part, MemoryPart::Photons);
    assert!(estimate.total() > 8 << 30);
}

fn scene_with_point_light(intensity: f32) -> Result<Scene, SceneError> {
    let camera = Camera::new(Vec3::ZERO, Vec3::NEG_Z, Vec3::Y, 60.0, (4, 4)).unwrap();
    let mut b = SceneBuilder::new(camera);
    let white = b.add_material(Material::new(Bsdf::diffuse(Vec3::splat(0.5)), Vec3::ZERO));
    b.add_sphere(Sphere::new(Vec3::ZERO, 1.0, white).inward());
    b.add_point_light(PointLight {
        position: Vec3::ZERO,
        intensity: Vec3::ONE,
    });
    b.add_point_light(PointLight {
        position: Vec3::new(0.0, 0.5, 0.0),
        intensity: Vec3::splat(intensity),
    });
    b.build()
}

/// A light power that overflows f32 (or comes near enough for the density estimate to) is an
/// error naming the light, never a silent black image.
#[test]
fn light_powers_must_fit_f32_arithmetic() {
    for intensity in [1e37f32, 1e35, f32::MAX] {
        let Err(err) = scene_with_point_light(intensity) else {
            panic!("intensity {intensity:e} accepted");
        };
        let err = err.to_string();
        assert!(
            err.contains("point light 1") && err.contains("power"),
            "{err}"
        );
    }
    // An intensity above MAX_EMISSION (2^40, the film's exact range less the estimators'
    // gain) is an error naming the field, even though its power is far below
    // MAX_LIGHT_POWER; at the bound the render drops nothing.
    let Err(err) = scene_with_point_light(MAX_EMISSION * 1.01) else {
        panic!("intensity above MAX_EMISSION accepted");
    };
    let err = err.to_string();
    assert!(
        err.contains("point light 1") && err.contains("`intensity`") && err.contains("2^40"),
        "{err}"
    );
    let scene = scene_with_point_light(MAX_EMISSION).unwrap();
    let settings = RenderSettings {
        photons: 2000,
        ..RenderSettings::new(&scene)
    };
    let mut renderer = Renderer::new(&scene, &settings);
    renderer.iterate(&scene);
    let image = renderer.image();
    assert!(image.pixels.iter().all(|p| p.is_finite()));
    assert_eq!(renderer.rejected(), 0);
    assert!(image.pixels.iter().any(|p| p.max_element() > 1e10));
    // Area lights: the emissive material is named.
    let camera = Camera::new(Vec3::ZERO, Vec3::NEG_Z, Vec3::Y, 60.0, (4, 4)).unwrap();
    let mut b = SceneBuilder::new(camera);
    let hot =
        b.add_material(Material::new(Bsdf::diffuse(Vec3::ZERO), Vec3::splat(1e36)).named("sun"));
    b.add_sphere(Sphere::new(Vec3::ZERO, 1.0, hot).inward());
    let Err(err) = b.build() else {
        panic!("an emissive sphere of 1e36 accepted");
    };
    let err = err.to_string();
    assert!(
        err.contains("emissive sphere") && err.contains("`sun`"),
        "{err}"
    );
}
