//! Light sampling: pdfs that integrate to what they should, consistent direct-lighting pdfs,
//! emitted flux equal to power, and irradiance against closed forms.

use glam::{DVec3, Vec3};
use ppm_core::geometry::{intersect_triangle, Sphere, Triangle};
use ppm_core::light::{Light, PointLight, SphereLight, TriangleLight};
use ppm_core::prelude::{Bsdf, Camera, Material, SceneBuilder, TriangleMesh};
use ppm_core::sampling::{uniform_sphere, Rng};
use std::f64::consts::PI;

/// Mean and standard error of the mean of `n` samples of `f`.
fn estimate(n: usize, mut f: impl FnMut() -> f64) -> (f64, f64) {
    let (mut sum, mut sum2) = (0.0, 0.0);
    for _ in 0..n {
        let x = f();
        assert!(x.is_finite(), "non-finite sample {x}");
        sum += x;
        sum2 += x * x;
    }
    let mean = sum / n as f64;
    let var = (sum2 / n as f64 - mean * mean).max(0.0);
    (mean, (var / n as f64).sqrt())
}

/// |estimate - exact| within 5 standard errors (plus a little float slack).
fn assert_close((mean, stderr): (f64, f64), exact: f64, what: &str) {
    let tol = 5.0 * stderr + 1e-5 * exact.abs().max(1e-3);
    assert!(
        (mean - exact).abs() <= tol,
        "{what}: estimate {mean} +- {stderr}, expected {exact}"
    );
}

/// A triangle light facing -y (toward a receiver below it).
fn downward_triangle(a: Vec3, b: Vec3, c: Vec3) -> Triangle {
    let tri = Triangle { v: [a, b, c] };
    if tri.cross().y > 0.0 {
        Triangle { v: [a, c, b] }
    } else {
        tri
    }
}

fn triangle_light() -> Light {
    let tri = downward_triangle(
        Vec3::new(-1.0, 1.0, -0.5),
        Vec3::new(1.2, 1.0, -0.7),
        Vec3::new(0.1, 1.0, 1.0),
    );
    Light::triangle(tri, Vec3::new(1.0, 2.0, 3.0), 0).unwrap()
}

fn sphere_light(inward: bool) -> Light {
    let s = Sphere::new(Vec3::new(0.3, 2.0, -0.2), 0.7, 0);
    Light::sphere(
        if inward { s.inward() } else { s },
        Vec3::new(2.0, 1.0, 0.5),
        0,
    )
}

fn triangle_area() -> f64 {
    let Light::Triangle(light) = triangle_light() else {
        unreachable!()
    };
    light.area as f64
}

/// The fraction of a sphere's area that faces a point at distance `d` from its center.
fn visible_fraction(r: f64, d: f64) -> f64 {
    0.5 * (1.0 - r / d)
}

#[test]
fn area_pdf_integrates_to_the_visible_fraction() {
    // Points uniform on the light's area (the origins of emission samples), and the area pdf
    // p_A = p_w cos_l / d^2 recovered from the solid-angle pdf: A E[p_A] = integral of p_A dA.
    let p = Vec3::new(0.2, -0.4, 0.1);
    let mut rng = Rng::new(1, 0, 0);
    for (light, area, expected) in [
        (triangle_light(), triangle_area(), 1.0),
        (
            sphere_light(false),
            4.0 * PI * 0.49,
            visible_fraction(0.7, (Vec3::new(0.3, 2.0, -0.2) - p).length() as f64),
        ),
    ] {
        let result = estimate(200_000, || {
            let s = light.sample_emission(rng.uniform2(), rng.uniform2());
            let d = s.ray_origin - p;
            let cos_l = (-d.normalize().dot(s.n)).max(0.0) as f64;
            area * light.pdf_direct(p, s.ray_origin, s.n) as f64 * cos_l / d.length_squared() as f64
        });
        assert_close(result, expected, "area pdf");
    }
    // From inside an inward sphere every point faces p.
    let light = sphere_light(true);
    let inside = Vec3::new(0.5, 2.1, 0.0);
    let result = estimate(200_000, || {
        let s = light.sample_emission(rng.uniform2(), rng.uniform2());
        let d = s.ray_origin - inside;
        let cos_l = (-d.normalize().dot(s.n)).max(0.0) as f64;
        4.0 * PI * 0.49 * light.pdf_direct(inside, s.ray_origin, s.n) as f64 * cos_l
            / d.length_squared() as f64
    });
    assert_close(result, 1.0, "area pdf, inward sphere");
}

#[test]
fn solid_angle_pdf_integrates_over_directions() {
    // Integral over all directions of pdf_direct(p, q(w), n(w)), q(w) the point of the light
    // seen along w: uniform directions, 4 pi E[pdf]. One for a triangle seen from its front,
    // the visible fraction for a sphere seen from outside, one from inside an inward sphere.
    let mut rng = Rng::new(2, 0, 0);
    let p = Vec3::new(0.1, 0.4, 0.0);
    let Light::Triangle(TriangleLight { tri, normal, .. }) = triangle_light() else {
        unreachable!()
    };
    let light = triangle_light();
    let result = estimate(400_000, || {
        let w = uniform_sphere(rng.uniform2());
        intersect_triangle(&tri, p, w, f32::INFINITY).map_or(0.0, |(t, _, _)| {
            4.0 * PI * light.pdf_direct(p, p + w * t, normal) as f64
        })
    });
    assert_close(result, 1.0, "triangle solid-angle pdf");

    for (inward, p) in [
        (false, Vec3::new(0.0, 0.5, 0.3)),
        (true, Vec3::new(0.5, 2.1, 0.0)),
    ] {
        let light = sphere_light(inward);
        let Light::Sphere(SphereLight { sphere, .. }) = light else {
            unreachable!()
        };
        let expected = if inward {
            1.0
        } else {
            visible_fraction(0.7, (sphere.center - p).length() as f64)
        };
        let result = estimate(400_000, || {
            let w = uniform_sphere(rng.uniform2());
            sphere.intersect(p, w, f32::INFINITY).map_or(0.0, |t| {
                let q = p + w * t;
                let n = (q - sphere.center).normalize() * if inward { -1.0 } else { 1.0 };
                4.0 * PI * light.pdf_direct(p, q, n) as f64
            })
        });
        assert_close(result, expected, "sphere solid-angle pdf");
    }
}

#[test]
fn sample_direct_pdf_equals_pdf_direct() {
    let mut rng = Rng::new(3, 0, 0);
    let p = Vec3::new(0.2, -0.3, 0.1);
    let point = Light::Point(PointLight {
        position: Vec3::new(0.0, 3.0, 0.0),
        intensity: Vec3::ONE,
    });
    for light in [
        triangle_light(),
        sphere_light(false),
        sphere_light(true),
        point,
    ] {
        let (mut some, mut none) = (0, 0);
        for _ in 0..20_000 {
            let Some(s) = light.sample_direct(p, rng.uniform2()) else {
                none += 1;
                continue;
            };
            some += 1;
            assert!(
                (s.wi.length() - 1.0).abs() < 1e-5
                    && ((s.p - p).length() - s.dist).abs() < 1e-4 * s.dist
            );
            if light.is_delta() {
                assert!(s.is_delta && s.pdf == 1.0 && light.pdf_direct(p, s.p, s.n) == 0.0);
                assert!((s.li - Vec3::ONE / (s.dist * s.dist)).length() < 1e-6);
            } else {
                let pdf = light.pdf_direct(p, s.p, s.n);
                assert_eq!(pdf, s.pdf);
                // The sampled point emits toward p.
                assert!(light.le(s.n, -s.wi).max_element() > 0.0);
            }
        }
        // Samples on the side of a sphere that faces away from p are rejected, nothing else
        // (p is outside both spheres).
        assert_eq!(
            none > 0,
            matches!(light, Light::Sphere(_)),
            "{some} samples, {none} rejected"
        );
    }
}

#[test]
fn emission_samples_carry_the_light_power() {
    let mut rng = Rng::new(4, 0, 0);
    let point = Light::Point(PointLight {
        position: Vec3::new(1.0, 2.0, 3.0),
        intensity: Vec3::new(1.0, 0.5, 2.0),
    });
    for light in [
        triangle_light(),
        sphere_light(false),
        sphere_light(true),
        point.clone(),
    ] {
        let n = 100_000;
        let (mut flux, mut cos) = (DVec3::ZERO, 0.0);
        for _ in 0..n {
            let s = light.sample_emission(rng.uniform2(), rng.uniform2());
            assert!(s.flux.is_finite() && (s.dir.length() - 1.0).abs() < 1e-5);
            flux += s.flux.as_dvec3();
            if !light.is_delta() {
                // Cosine-distributed about the emitting normal: E[cos] = 2/3.
                assert!(s.dir.dot(s.n) >= 0.0 && s.pdf_dir >= 0.0);
                cos += s.dir.dot(s.n) as f64;
            }
        }
        let mean = flux / n as f64;
        let power = light.power().as_dvec3();
        assert!(
            (mean - power).abs().max_element() <= 1e-4 * power.max_element(),
            "{mean} vs {power}"
        );
        if !light.is_delta() {
            // Standard deviation of cos under pdf cos/pi is sqrt(1/2 - 4/9) ~ 0.236.
            assert!((cos / n as f64 - 2.0 / 3.0).abs() < 5.0 * 0.236 / (n as f64).sqrt());
        }
    }
    // Point lights: isotropic directions, mean direction ~ 0.
    let mut mean_dir = Vec3::ZERO;
    for _ in 0..100_000 {
        mean_dir += point.sample_emission(rng.uniform2(), rng.uniform2()).dir;
    }
    assert!((mean_dir / 100_000.0).length() < 0.01);
}

#[test]
fn scene_emission_mean_flux_is_the_total_power() {
    let camera = Camera::new(Vec3::new(0.0, 1.0, 5.0), Vec3::ZERO, Vec3::Y, 40.0, (4, 4)).unwrap();
    let mut builder = SceneBuilder::new(camera);
    let white = builder.add_material(Material::new(Bsdf::diffuse(Vec3::splat(0.5)), Vec3::ZERO));
    let warm = builder.add_material(Material::new(
        Bsdf::diffuse(Vec3::ZERO),
        Vec3::new(4.0, 2.0, 1.0),
    ));
    let cold = builder.add_material(Material::new(
        Bsdf::diffuse(Vec3::ZERO),
        Vec3::new(0.5, 1.0, 8.0),
    ));
    builder.add_mesh(TriangleMesh::quad(
        Vec3::new(-1.0, 0.0, -1.0),
        Vec3::Z * 2.0,
        Vec3::X * 2.0,
        white,
    ));
    builder.add_mesh(TriangleMesh::quad(
        Vec3::new(-0.2, 1.9, -0.2),
        Vec3::X * 0.4,
        Vec3::Z * 0.3,
        warm,
    ));
    builder.add_sphere(Sphere::new(Vec3::new(0.5, 0.5, 0.0), 0.2, cold));
    builder.add_sphere(Sphere::new(Vec3::ZERO, 10.0, warm).inward());
    builder.add_point_light(PointLight {
        position: Vec3::new(0.0, 1.0, 0.0),
        intensity: Vec3::new(3.0, 3.0, 0.1),
    });
    let scene = builder.build().unwrap();
    // Two light triangles, two spheres, one point light.
    assert_eq!(scene.lights.len(), 5);
    let mut rng = Rng::new(5, 0, 0);
    let n = 400_000;
    let mut sum = DVec3::ZERO;
    let mut sum2 = DVec3::ZERO;
    for _ in 0..n {
        let s = scene
            .sample_emission(rng.uniform(), rng.uniform2(), rng.uniform2())
            .unwrap();
        let f = s.flux.as_dvec3();
        sum += f;
        sum2 += f * f;
    }
    let mean = sum / n as f64;
    let stderr = ((sum2 / n as f64 - mean * mean).max(DVec3::ZERO) / n as f64).powf(0.5);
    let power = scene.total_power().as_dvec3();
    for c in 0..3 {
        assert_close((mean[c], stderr[c]), power[c], "scene flux");
    }
    // Each light is chosen in proportion to its power (mean over channels).
    let total = power.element_sum() / 3.0;
    for (i, light) in scene.lights.iter().enumerate() {
        let expected = light.power().element_sum() as f64 / 3.0 / total;
        let chosen = (0..100_000)
            .filter(|_| std::ptr::eq(scene.choose_light(rng.uniform()).unwrap().0, light))
            .count();
        assert!(
            (chosen as f64 / 1e5 - expected).abs() < 5.0 * (expected / 1e5).sqrt() + 1e-4,
            "light {i}"
        );
    }
}

/// Irradiance at `p` (normal `n`) from a Lambertian polygon of radiance `le` facing p and
/// entirely above p's horizon, by Lambert's formula: E = le/2 sum_i gamma_i (n . g_i), gamma_i the
/// angle between the directions to vertices i and i+1 and g_i the unit normal of their plane.
fn lambert_irradiance(p: Vec3, n: Vec3, polygon: &[Vec3], le: f64) -> f64 {
    let (p, n) = (p.as_dvec3(), n.as_dvec3());
    let r: Vec<DVec3> = polygon
        .iter()
        .map(|v| (v.as_dvec3() - p).normalize())
        .collect();
    let sum: f64 = (0..r.len())
        .map(|i| {
            let (a, b) = (r[i], r[(i + 1) % r.len()]);
            a.dot(b).clamp(-1.0, 1.0).acos() * n.dot(a.cross(b).normalize())
        })
        .sum();
    0.5 * le * sum.abs()
}

/// Monte Carlo irradiance E = integral of Li cos dw from light samples: E[Li cos / pdf].
fn sampled_irradiance(light: &Light, p: Vec3, n: Vec3, samples: usize, seed: u64) -> (f64, f64) {
    let mut rng = Rng::new(seed, 0, 0);
    estimate(samples, || {
        light.sample_direct(p, rng.uniform2()).map_or(0.0, |s| {
            let cos = s.wi.dot(n).max(0.0) as f64;
            s.li.x as f64 * cos / s.pdf as f64
        })
    })
}

#[test]
fn irradiance_from_small_area_lights_matches_closed_forms() {
    let le = Vec3::splat(3.0);
    // A square of side 0.2 at height 1 facing down, as two triangles; receivers below it
    // (centered, off to the side, tilted), each must see the sum of both halves.
    let (a, b, c, d) = (
        Vec3::new(-0.1, 1.0, -0.1),
        Vec3::new(0.1, 1.0, -0.1),
        Vec3::new(0.1, 1.0, 0.1),
        Vec3::new(-0.1, 1.0, 0.1),
    );
    let halves = [downward_triangle(a, b, c), downward_triangle(a, c, d)]
        .map(|t| Light::triangle(t, le, 0).unwrap());
    let receivers = [
        (Vec3::ZERO, Vec3::Y),
        (Vec3::new(0.7, 0.2, -0.3), Vec3::Y),
        (
            Vec3::new(-0.3, 0.0, 0.2),
            Vec3::new(0.3, 1.0, -0.2).normalize(),
        ),
    ];
    for (k, (p, n)) in receivers.into_iter().enumerate() {
        let exact = lambert_irradiance(p, n, &[a, b, c, d], 3.0);
        let (m0, s0) = sampled_irradiance(&halves[0], p, n, 100_000, 10 + k as u64);
        let (m1, s1) = sampled_irradiance(&halves[1], p, n, 100_000, 20 + k as u64);
        assert_close(
            (m0 + m1, s0.hypot(s1)),
            exact,
            &format!("square light, receiver {k}"),
        );
        if k == 0 {
            // The small-source limit: E ~ le A / d^2 for a source of area A = 0.04 at d = 1.
            assert!((exact - 3.0 * 0.04).abs() < 0.02 * 0.12, "{exact}");
        }
    }
    // A single slanted triangle.
    let tri = Triangle {
        v: [
            Vec3::new(-0.3, 1.0, 0.0),
            Vec3::new(0.2, 1.4, -0.2),
            Vec3::new(0.1, 1.2, 0.3),
        ],
    };
    let tri = if tri.cross().dot(-Vec3::Y) > 0.0 {
        tri
    } else {
        Triangle {
            v: [tri.v[0], tri.v[2], tri.v[1]],
        }
    };
    let light = Light::triangle(tri, le, 0).unwrap();
    let exact = lambert_irradiance(Vec3::ZERO, Vec3::Y, &tri.v, 3.0);
    assert_close(
        sampled_irradiance(&light, Vec3::ZERO, Vec3::Y, 200_000, 30),
        exact,
        "triangle light",
    );

    // A sphere entirely above the horizon: E = pi le (r/D)^2 cos(theta), like a point source.
    let sphere = Sphere::new(Vec3::new(0.3, 2.0, 0.1), 0.25, 0);
    let light = Light::sphere(sphere, le, 0);
    for n in [Vec3::Y, Vec3::new(0.4, 1.0, 0.0).normalize()] {
        let to_center = sphere.center - Vec3::ZERO;
        let exact = PI
            * 3.0
            * (0.25 / to_center.length() as f64).powi(2)
            * n.dot(to_center.normalize()) as f64;
        assert_close(
            sampled_irradiance(&light, Vec3::ZERO, n, 200_000, 40),
            exact,
            "sphere light",
        );
    }
}

#[test]
fn grazing_and_degenerate_reference_points_give_finite_values() {
    let mut rng = Rng::new(6, 0, 0);
    let light = triangle_light();
    let Light::Triangle(TriangleLight { tri, normal, .. }) = light else {
        unreachable!()
    };
    let sphere = sphere_light(false);
    let Light::Sphere(SphereLight { sphere: s, .. }) = sphere else {
        unreachable!()
    };
    let points = [
        // In the light's plane, on its edge, at a vertex, just behind it.
        tri.v[0] + (tri.v[1] - tri.v[0]) * 3.0,
        tri.v[0].lerp(tri.v[1], 0.5),
        tri.v[2],
        (tri.v[0] + tri.v[1] + tri.v[2]) / 3.0 - normal * 1e-6,
        // On the sphere and just outside it.
        s.center + Vec3::X * s.radius,
        s.center + Vec3::Y * s.radius * (1.0 + 1e-6),
    ];
    for p in points {
        for light in [light.clone(), sphere.clone()] {
            for _ in 0..2_000 {
                if let Some(ds) = light.sample_direct(p, rng.uniform2()) {
                    assert!(
                        ds.pdf.is_finite()
                            && ds.pdf > 0.0
                            && ds.li.is_finite()
                            && ds.wi.is_finite(),
                        "{p} {ds:?}"
                    );
                    let pdf = light.pdf_direct(p, ds.p, ds.n);
                    assert!(pdf.is_finite() && pdf >= 0.0, "{p} {pdf}");
                }
                let e = light.sample_emission(rng.uniform2(), rng.uniform2());
                let pdf = light.pdf_direct(p, e.ray_origin, e.n);
                assert!(
                    pdf.is_finite() && pdf >= 0.0,
                    "pdf_direct({p}, {}) = {pdf}",
                    e.ray_origin
                );
            }
            // The reference point on the light itself.
            let pdf = light.pdf_direct(tri.v[2], tri.v[2], normal);
            assert!(
                pdf.is_finite() && pdf >= 0.0,
                "pdf_direct at the point itself = {pdf}"
            );
        }
    }
}
