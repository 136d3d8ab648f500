//! The default initial radius (`Radius::Photons`, each pixel's distance to its k-th nearest
//! pilot photon): the same (up to rounding) when the scene is scaled by 1000 and when the
//! image has 4 times the width, where the footprint rule's shrinks 4 times; bit-identical at
//! any thread count for ppm, sppm and vcm; the default of every photon mapper.

use ppm_test_support::test_scenes;

use ppm_core::integrator::{
    nearest_photon_radii, photon_radii, pilot_radii, RayCounters, Renderer, CAP, MAX_SCALE,
    MIN_SCALE, NEAREST_PHOTONS,
};
use ppm_core::prelude::*;

/// A glass sphere and a diffuse block on a 6 x 6 diffuse floor under a small one-sided lamp,
/// seen from above at an angle, `resolution` pixels square; everything scaled by `scale`.
fn sphere_on_floor(scale: f32, resolution: u32) -> Scene {
    let s = |v: Vec3| v * scale;
    let mut b = SceneBuilder::new(camera(scale, resolution));
    let white = b.add_material(Material::new(Bsdf::diffuse(Vec3::splat(0.7)), Vec3::ZERO));
    let glass = b.add_material(Material::new(Bsdf::glass(1.5, Vec3::ONE), Vec3::ZERO));
    let lamp = b.add_material(Material::new(Bsdf::diffuse(Vec3::ZERO), Vec3::splat(60.0)));
    b.add_mesh(TriangleMesh::quad(
        s(Vec3::new(-3.0, 0.0, -3.0)),
        s(Vec3::new(0.0, 0.0, 6.0)),
        s(Vec3::new(6.0, 0.0, 0.0)),
        white,
    ));
    b.add_sphere(Sphere::new(
        s(Vec3::new(0.25, 0.5, 0.0)),
        0.5 * scale,
        glass,
    ));
    test_scenes::add_block(
        &mut b,
        s(Vec3::new(-0.6, 0.0, 0.2)),
        0.3 * scale,
        0.3 * scale,
        white,
    );
    b.add_mesh(TriangleMesh::quad(
        s(Vec3::new(0.55, 2.2, -0.45)),
        s(Vec3::new(0.3, 0.0, 0.0)),
        s(Vec3::new(0.0, 0.0, 0.3)),
        lamp,
    ));
    b.build().unwrap()
}

/// The camera of [`sphere_on_floor`].
fn camera(scale: f32, resolution: u32) -> Camera {
    Camera::new(
        Vec3::new(0.0, 1.6, 2.6) * scale,
        Vec3::new(0.0, 0.35, 0.0) * scale,
        Vec3::Y,
        38.0,
        (resolution, resolution),
    )
    .unwrap()
}

fn settings(scene: &Scene) -> RenderSettings {
    RenderSettings {
        seed: 3,
        ..RenderSettings::new(scene)
    }
}

fn median(values: &[f32]) -> f32 {
    let mut v = values.to_vec();
    v.sort_by(f32::total_cmp);
    v[v.len() / 2]
}

#[test]
fn the_default_radius_is_the_photons_rule_for_every_photon_mapper() {
    let scene = sphere_on_floor(1.0, 8);
    for algorithm in [Algorithm::Ppm, Algorithm::Sppm, Algorithm::Vcm] {
        let s = RenderSettings::for_algorithm(&scene, algorithm);
        assert_eq!(s.radius, Radius::Photons, "{algorithm:?}");
    }
}

/// Scaling the scene by 1000 scales every radius by 1000: the same light paths land on the
/// same (scaled) points. Rounding may move a few photons or pilot points, so per pixel
/// 95% agree within 1e-3 and the medians within 1e-3.
#[test]
fn the_photon_radius_scales_with_the_scene() {
    let (small, large) = (sphere_on_floor(1.0, 24), sphere_on_floor(1000.0, 24));
    let a = photon_radii(&small, &settings(&small), &mut RayCounters::default());
    let b = photon_radii(&large, &settings(&large), &mut RayCounters::default());
    let close = a
        .iter()
        .zip(&b)
        .filter(|(a, b)| ((*b / 1000.0) / **a - 1.0).abs() < 1e-3)
        .count();
    assert!(close * 100 >= 95 * a.len(), "{close} of {}", a.len());
    let (ma, mb) = (median(&a), median(&b) / 1000.0);
    assert!((mb / ma - 1.0).abs() < 1e-3, "{ma} vs {mb}");
}

/// At 4 times the width (16 times the pixels, the same pilot photons) the k-nearest
/// distances are those of the same surface points: the median changes by sampling alone (the
/// pilot points move within their pixels), under 5%; the footprint rule's median shrinks 4
/// times. The scale changes with an iteration's cost (the gathers' share and the nominal
/// iterations, both set by the light paths' rays at these sizes) and with the sample of
/// pixels it is measured on: under 10%.
#[test]
fn the_photon_radius_does_not_depend_on_the_resolution() {
    let (low, high) = (sphere_on_floor(1.0, 24), sphere_on_floor(1.0, 96));
    let nearest = |scene: &Scene| {
        nearest_photon_radii(
            scene,
            &settings(scene),
            NEAREST_PHOTONS,
            &mut RayCounters::default(),
        )
    };
    let ratio = median(&nearest(&high)) / median(&nearest(&low));
    assert!((ratio - 1.0).abs() < 0.05, "photons: x{ratio}");
    let (m_low, m_high) = (scale(&low, &settings(&low)), scale(&high, &settings(&high)));
    assert!(
        (m_high / m_low - 1.0).abs() < 0.1,
        "scale {m_low} -> {m_high}"
    );
    let b = photon_radii(&high, &settings(&high), &mut RayCounters::default());
    let footprint =
        |scene: &Scene| median(&pilot_radii(scene, 3, 32, 3, &mut RayCounters::default()));
    let ratio = footprint(&high) / footprint(&low);
    assert!((ratio - 0.25).abs() < 0.02, "footprint: x{ratio}");
    // Every radius is positive, finite and at most the cap times the median.
    let cap = CAP * median(&b);
    assert!(b
        .iter()
        .all(|r| r.is_finite() && *r > 0.0 && *r <= cap * (1.0 + 1e-6)));
}

/// The k-nearest distance grows as sqrt(k) where the photon density is smooth: from k to 4k
/// the median doubles (within 10%: the density is not uniform over 4 times the area).
#[test]
fn the_nearest_photon_radius_grows_as_the_square_root_of_k() {
    let scene = sphere_on_floor(1.0, 24);
    let s = settings(&scene);
    let k = NEAREST_PHOTONS;
    let a = median(&nearest_photon_radii(
        &scene,
        &s,
        k,
        &mut RayCounters::default(),
    ));
    let b = median(&nearest_photon_radii(
        &scene,
        &s,
        4 * k,
        &mut RayCounters::default(),
    ));
    assert!((b / a / 2.0 - 1.0).abs() < 0.1, "{a} -> {b}");
}

/// The bias-variance scale m of every pixel's radius (the default over the k-nearest
/// distance alone, the same for every pixel).
fn scale(scene: &Scene, s: &RenderSettings) -> f32 {
    let scaled = photon_radii(scene, s, &mut RayCounters::default());
    let nearest = nearest_photon_radii(scene, s, NEAREST_PHOTONS, &mut RayCounters::default());
    let m = scaled[0] / nearest[0];
    for (a, b) in scaled.iter().zip(&nearest) {
        assert!((a / b / m - 1.0).abs() < 1e-5, "{a} / {b} vs {m}");
    }
    m
}

/// Where the light changes fast (the glass sphere's caustic, the block's shadow under a small
/// lamp) the scale is smaller than under light that is smooth everywhere (a lamp as large as
/// the floor, nothing on it): the pilot measures the bias, which a photon count does not.
#[test]
fn the_scale_is_larger_where_the_light_is_smooth() {
    let caustic = sphere_on_floor(1.0, 32);
    let mut b = SceneBuilder::new(camera(1.0, 32));
    let white = b.add_material(Material::new(Bsdf::diffuse(Vec3::splat(0.7)), Vec3::ZERO));
    let lamp = b.add_material(Material::new(Bsdf::diffuse(Vec3::ZERO), Vec3::splat(2.0)));
    b.add_mesh(TriangleMesh::quad(
        Vec3::new(-3.0, 0.0, -3.0),
        Vec3::new(0.0, 0.0, 6.0),
        Vec3::new(6.0, 0.0, 0.0),
        white,
    ));
    b.add_mesh(TriangleMesh::quad(
        Vec3::new(-3.0, 3.0, -3.0),
        Vec3::new(6.0, 0.0, 0.0),
        Vec3::new(0.0, 0.0, 6.0),
        lamp,
    ));
    let smooth = b.build().unwrap();
    // Direct light from photons: the smooth scene has no other light to gather.
    let photons = |scene: &Scene| RenderSettings {
        direct: DirectMode::Photons,
        ..settings(scene)
    };
    let (m_caustic, m_smooth) = (
        scale(&caustic, &photons(&caustic)),
        scale(&smooth, &photons(&smooth)),
    );
    for m in [m_caustic, m_smooth] {
        assert!((MIN_SCALE..=MAX_SCALE).contains(&m), "{m}");
    }
    assert!(
        m_smooth > 2.0 * m_caustic,
        "smooth {m_smooth}, caustic {m_caustic}"
    );
}

/// ppm, sppm and vcm with the default radius render the same image and radii at 1 and 2
/// threads, bit for bit.
#[test]
fn the_photon_radius_is_the_same_at_any_thread_count() {
    let scene = sphere_on_floor(1.0, 16);
    for algorithm in [Algorithm::Ppm, Algorithm::Sppm, Algorithm::Vcm] {
        let s = RenderSettings {
            photons: 4_000,
            ..RenderSettings::for_algorithm(&scene, algorithm)
        };
        assert_eq!(s.radius, Radius::Photons);
        let render = |threads| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                let mut r = Renderer::new(&scene, &s);
                for _ in 0..2 {
                    r.iterate(&scene);
                }
                (r.image(), r.radius_image())
            })
        };
        let one = render(1);
        assert_eq!(one, render(2), "{algorithm:?}: 1 vs 2 threads");
        assert!(one.0.mean().max_element() > 0.0, "{algorithm:?}");
    }
}

/// Only ppm takes the bias-variance scale: sppm, vcm and bpm start at the k-nearest
/// distances themselves (docs/radius.md, "Why only `ppm`"), while ppm's differ from them.
#[test]
fn only_ppm_takes_the_scale() {
    let scene = sphere_on_floor(1.0, 16);
    for algorithm in [
        Algorithm::Ppm,
        Algorithm::Sppm,
        Algorithm::Vcm,
        Algorithm::Bpm,
    ] {
        let s = RenderSettings {
            seed: 3,
            ..RenderSettings::for_algorithm(&scene, algorithm)
        };
        let radii = photon_radii(&scene, &s, &mut RayCounters::default());
        let nearest =
            nearest_photon_radii(&scene, &s, NEAREST_PHOTONS, &mut RayCounters::default());
        assert_eq!(
            radii == nearest,
            algorithm != Algorithm::Ppm,
            "{algorithm:?}"
        );
    }
}
