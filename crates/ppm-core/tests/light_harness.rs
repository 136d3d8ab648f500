//! The light test harness.
//!
//! Every light model goes through [`light_harness!`]: one line (a light and the points it is
//! seen from) gives it the same checks of the contract in `light/mod.rs`:
//!
//! - `pdf_direct` integrates over the sphere of directions to the probability that
//!   `sample_direct` returns a sample (1 for a light wholly facing the point, the facing
//!   fraction for a sphere seen from outside); a delta light has `pdf_direct = 0` and is
//!   sampled with pdf 1, from each point always or never (never where it sends no light);
//! - `sample_direct` and `pdf_direct` agree: the pdf of each sample is `pdf_direct` of its
//!   point, bit for bit, and the samples are distributed by that pdf (the estimate
//!   E[g(wi) / pdf] equals the integral of g over the directions that see the light);
//! - the mean of `sample_emission`'s flux is `power()`;
//! - a delta light's radiant intensity, seen by `sample_direct` as li d^2, is what its
//!   emission samples carry (flux pdf_dir), integrates over the sphere to `power()`, and
//!   its emission directions follow `pdf_emission`;
//! - `le` is one-sided (Lambertian: constant on the side the normal points to, zero on the
//!   other), zero for a delta light, and agrees with the emission samples' flux;
//! - a light at infinity (an environment) gives every point the same `le_infinite`, whose
//!   `pdf_infinite` is `pdf_direct` toward it, and its emission samples carry L over their
//!   densities from origins upstream of the scene.
//!
//! The geometry a direction meets is found by [`light_surface`], one exhaustive match: a new
//! model does not compile here until it says where its surface is. Tests specific to one
//! model, and closed-form irradiance, are in `lights.rs`. All randomness is seeded.

mod common;

use common::{seed, Stats};
use glam::Mat3;
use glam::Vec3;
use ppm_core::geometry::{intersect_triangle, Sphere, Triangle};
use ppm_core::light::{
    EnvironmentLight, EnvironmentMap, EqualAreaMap, LatLongMap, Light, LightKind, PointLight,
};
use ppm_core::sampling::{uniform_sphere, Rng};
use std::f64::consts::PI;
use std::sync::Arc;

/// Samples per Monte Carlo estimate.
const SAMPLES: usize = 200_000;

/// The first point of the light's surface along the ray `p + t w` (t > 0) and its emitting
/// normal; `None` for a miss and for lights without a surface.
fn light_surface(light: &Light, p: Vec3, w: Vec3) -> Option<(Vec3, Vec3)> {
    match light {
        Light::Triangle(l) => {
            intersect_triangle(&l.tri, p, w, f32::INFINITY).map(|(t, _, _)| (p + w * t, l.normal))
        }
        Light::Sphere(l) => l.sphere.intersect(p, w, f32::INFINITY).map(|t| {
            let q = p + w * t;
            let outward = (q - l.sphere.center).normalize();
            (q, if l.sphere.inward { -outward } else { outward })
        }),
        // A light at infinity: every direction that it radiates from meets it, its "surface"
        // facing the point (black directions emit nothing, as the back of an area light).
        Light::Environment(_) => (light.le_infinite(w) != Vec3::ZERO).then(|| (p + w * 1e4, -w)),
        Light::Point(_) | Light::Spot(_) | Light::Directional(_) => None,
    }
}

/// |a - b| within 5 combined standard errors (plus float slack).
fn assert_agree(a: &Stats, b: &Stats, what: &str) {
    let tol = 5.0 * a.std_error().hypot(b.std_error()) + 1e-6 * a.mean().abs().max(1e-3);
    assert!(
        (a.mean() - b.mean()).abs() <= tol,
        "{what}: {} +- {} vs {} +- {}",
        a.mean(),
        a.std_error(),
        b.mean(),
        b.std_error()
    );
}

/// The integral of `pdf_direct` over all directions (uniform directions: 4 pi E[pdf at the
/// surface met]) against the fraction of `sample_direct` calls that return a sample.
fn check_pdf_integrates(name: &str, light: &Light, points: &[Vec3]) {
    let mut rng = Rng::new(seed(name), 1, 0);
    let mut some_light_seen = false;
    for &p in points {
        let mut sampled = Stats::default();
        for _ in 0..SAMPLES {
            sampled.push(light.sample_direct(p, rng.uniform2()).is_some() as u64 as f64);
        }
        if light.is_delta() {
            // A discrete choice: the light, with pdf 1, whatever the random numbers (or
            // never, where it sends no light); no density over directions.
            let mean = sampled.mean();
            assert!(mean == 1.0 || mean == 0.0, "{name}: delta light from {p}");
            some_light_seen |= mean == 1.0;
            continue;
        }
        let mut integral = Stats::default();
        for _ in 0..SAMPLES {
            let w = uniform_sphere(rng.uniform2());
            let pdf = light_surface(light, p, w).map_or(0.0, |(q, n)| light.pdf_direct(p, q, n));
            assert!(pdf.is_finite() && pdf >= 0.0, "{name}: pdf {pdf}");
            integral.push(4.0 * PI * pdf as f64);
        }
        assert_agree(
            &integral,
            &sampled,
            &format!("{name}: integral of pdf from {p}"),
        );
        some_light_seen |= sampled.mean() > 0.1;
    }
    assert!(some_light_seen, "{name}: no point sees the light");
}

/// `sample_direct`'s pdf is `pdf_direct` of the same point, and its samples follow that pdf:
/// E[g(wi) / pdf] over samples equals the integral of g over the directions that meet the
/// light's emitting side (uniform directions, 4 pi E[g 1{seen}]), for g(w) = 2 + w.x - w.z.
fn check_sample_matches_pdf(name: &str, light: &Light, points: &[Vec3]) {
    let mut rng = Rng::new(seed(name), 2, 0);
    let g = |w: Vec3| 2.0 + w.x as f64 - w.z as f64;
    for &p in points {
        let mut weighted = Stats::default();
        for _ in 0..SAMPLES {
            let Some(s) = light.sample_direct(p, rng.uniform2()) else {
                weighted.push(0.0);
                continue;
            };
            assert!(
                (s.wi.length() - 1.0).abs() < 1e-5
                    && ((s.p - p).length() - s.dist).abs() <= 1e-4 * s.dist
                    && (s.p - p).normalize().dot(s.wi) > 1.0 - 1e-5,
                "{name}: {s:?} from {p}"
            );
            assert!(
                s.li.is_finite() && s.pdf.is_finite() && s.pdf > 0.0,
                "{name}: {s:?}"
            );
            assert_eq!(s.is_delta, light.is_delta(), "{name}");
            if light.is_delta() {
                assert_eq!(s.pdf, 1.0, "{name}: a delta light's discrete pdf");
                assert_eq!(light.pdf_direct(p, s.p, s.n), 0.0, "{name}");
                // The intensity it gives is checked against emission in
                // `check_delta_intensity`.
            } else if light.kind() == LightKind::Infinite {
                // A direction, not a point: `pdf_infinite` of the sampled direction bit for
                // bit (what an escaping camera path is weighted with); `pdf_direct` of the
                // far point gets the direction back only to rounding.
                assert_eq!(
                    light.pdf_infinite(s.wi).to_bits(),
                    s.pdf.to_bits(),
                    "{name}: pdf_infinite of a sample from {p}"
                );
                let pdf = light.pdf_direct(p, s.p, s.n);
                assert!(
                    (pdf - s.pdf).abs() <= 1e-3 * s.pdf,
                    "{name}: {pdf} vs {s:?}"
                );
                assert_eq!(s.li, light.le_infinite(s.wi), "{name}");
                weighted.push(g(s.wi) / s.pdf as f64);
            } else {
                assert_eq!(
                    light.pdf_direct(p, s.p, s.n).to_bits(),
                    s.pdf.to_bits(),
                    "{name}: pdf_direct of a sample from {p}"
                );
                // The radiance arriving is what the point emits toward p.
                assert_eq!(s.li, light.le(s.n, -s.wi), "{name}");
                weighted.push(g(s.wi) / s.pdf as f64);
            }
        }
        if light.is_delta() {
            continue;
        }
        let mut integral = Stats::default();
        for _ in 0..SAMPLES {
            let w = uniform_sphere(rng.uniform2());
            let seen = light_surface(light, p, w).is_some_and(|(_, n)| n.dot(-w) > 0.0);
            integral.push(if seen { 4.0 * PI * g(w) } else { 0.0 });
        }
        assert_agree(&weighted, &integral, &format!("{name}: E[g/pdf] from {p}"));
    }
}

/// The mean flux of emission samples is the light's power, channel by channel; directions
/// are unit and leave the emitting side; pdfs are positive and finite.
fn check_emitted_power(name: &str, light: &Light) {
    let mut rng = Rng::new(seed(name), 3, 0);
    let mut flux = [Stats::default(); 3];
    let mut direction = [Stats::default(); 3];
    for _ in 0..SAMPLES {
        let s = light.sample_emission(rng.uniform2(), rng.uniform2());
        assert!(
            s.flux.is_finite() && s.flux.min_element() >= 0.0,
            "{name}: {s:?}"
        );
        assert!((s.dir.length() - 1.0).abs() < 1e-5, "{name}: {s:?}");
        assert!(s.pdf_pos.is_finite() && s.pdf_pos > 0.0, "{name}: {s:?}");
        assert!(s.pdf_dir.is_finite() && s.pdf_dir >= 0.0, "{name}: {s:?}");
        assert!(light.is_delta() || s.dir.dot(s.n) >= 0.0, "{name}: {s:?}");
        for c in 0..3 {
            flux[c].push(s.flux[c] as f64);
            direction[c].push(s.dir[c] as f64);
        }
    }
    let power = light.power();
    for c in 0..3 {
        let exact = power[c] as f64;
        let tol = 5.0 * flux[c].std_error() + 1e-5 * exact;
        assert!(
            (flux[c].mean() - exact).abs() <= tol,
            "{name}: mean flux {} +- {} vs power {exact}",
            flux[c].mean(),
            flux[c].std_error()
        );
    }
    if light.kind() == LightKind::DeltaDirection {
        // One direction, the opposite of the one next-event estimation sees the light in.
        let wi = light.sample_direct(Vec3::ZERO, rng.uniform2()).unwrap().wi;
        for _ in 0..1000 {
            let s = light.sample_emission(rng.uniform2(), rng.uniform2());
            assert_eq!(s.dir, -wi, "{name}: a directional light's one direction");
        }
    } else if light.is_delta() {
        // Delta lights emit from one point: every direction's density is `pdf_emission`'s,
        // so E[dir] over the samples is 4 pi E_uniform[w pdf(w)] (5 standard errors).
        let mut expected = [Stats::default(); 3];
        for _ in 0..SAMPLES {
            let w = uniform_sphere(rng.uniform2());
            let pdf = light.pdf_emission(Vec3::ZERO, w).1 as f64;
            for c in 0..3 {
                expected[c].push(4.0 * PI * w[c] as f64 * pdf);
            }
        }
        for c in 0..3 {
            assert_agree(
                &direction[c],
                &expected[c],
                &format!("{name}: mean emitted direction, component {c}"),
            );
        }
    }
}

/// A delta light at point x0 (the origin of its emission samples): the radiant intensity
/// I(w) = li d^2 that `sample_direct` gives at x0 + d w (inverse-square law) is the one its
/// emission samples carry along w (flux pdf_dir = I(w)), and integrates over the sphere to
/// its power (uniform directions: 4 pi E[I(w)], 5 standard errors).
fn check_delta_intensity(name: &str, light: &Light) {
    if light.kind() == LightKind::DeltaDirection {
        check_delta_direction(name, light);
        return;
    }
    if light.kind() != LightKind::DeltaPosition {
        return;
    }
    let mut rng = Rng::new(seed(name), 6, 0);
    let x0 = light
        .sample_emission(rng.uniform2(), rng.uniform2())
        .ray_origin;
    let intensity = |w: Vec3, d: f32, rng: &mut Rng| {
        light
            .sample_direct(x0 + w * d, rng.uniform2())
            .map_or(Vec3::ZERO, |s| s.li * s.dist * s.dist)
    };
    for _ in 0..20_000 {
        let s = light.sample_emission(rng.uniform2(), rng.uniform2());
        assert_eq!(s.ray_origin, x0, "{name}: emits from one point");
        let carried = s.flux * s.pdf_dir;
        let seen = intensity(s.dir, 3.0, &mut rng);
        assert!(
            (carried - seen).abs().max_element() <= 1e-4 * seen.max_element() + 1e-6,
            "{name}: along {}: emission carries {carried}, sample_direct sees {seen}",
            s.dir
        );
    }
    let mut total = [Stats::default(); 3];
    for _ in 0..SAMPLES {
        let w = uniform_sphere(rng.uniform2());
        let i = intensity(w, 0.5, &mut rng);
        for c in 0..3 {
            total[c].push(4.0 * PI * i[c] as f64);
        }
    }
    let power = light.power();
    for c in 0..3 {
        let tol = 5.0 * total[c].std_error() + 1e-5 * power[c] as f64;
        assert!(
            (total[c].mean() - power[c] as f64).abs() <= tol,
            "{name}: intensity integrates to {} +- {}, power {}",
            total[c].mean(),
            total[c].std_error(),
            power[c]
        );
    }
}

/// A light at infinity along one direction d (a delta in direction): `sample_direct` sees
/// the same direction -d and irradiance E from every point, with a shadow ray that leaves the
/// scene (its end outside the bounding sphere the disk covers); emission origins
/// are uniform on a disk perpendicular to d, of area 1 / pdf_pos (the mean squared distance
/// from its centre is R^2 / 2, and the fraction inside radius R/2 is 1/4, 5 standard errors),
/// upstream of every point seen from, and carry flux pdf_pos = E: the photon density on a
/// surface facing the light is its irradiance.
fn check_delta_direction(name: &str, light: &Light) {
    let mut rng = Rng::new(seed(name), 7, 0);
    let first = light.sample_direct(Vec3::ZERO, rng.uniform2()).unwrap();
    let (wi, irradiance) = (first.wi, first.li);
    let samples: Vec<_> = (0..SAMPLES)
        .map(|_| light.sample_emission(rng.uniform2(), rng.uniform2()))
        .collect();
    let pdf_pos = samples[0].pdf_pos;
    let radius = (1.0 / (PI * pdf_pos as f64)).sqrt();
    let n = samples.len() as f64;
    let centre = samples
        .iter()
        .map(|s| s.ray_origin.as_dvec3())
        .sum::<glam::DVec3>()
        / n;
    let (mut r2, mut inner) = (Stats::default(), Stats::default());
    for s in &samples {
        assert_eq!(s.pdf_pos, pdf_pos, "{name}: uniform on the disk");
        assert_eq!(light.pdf_emission(s.n, s.dir), (pdf_pos, 1.0), "{name}");
        let carried = s.flux * s.pdf_pos;
        assert!(
            (carried - irradiance).abs().max_element() <= 1e-5 * irradiance.max_element(),
            "{name}: emission carries {carried} per unit area, sample_direct sees {irradiance}"
        );
        let offset = s.ray_origin.as_dvec3() - centre;
        let along = offset.dot(wi.as_dvec3());
        assert!(
            along.abs() <= 1e-4 * radius,
            "{name}: origin off the disk's plane"
        );
        let d2 = offset.length_squared();
        // The centre is estimated from the samples (standard error about R / 900).
        assert!(d2 <= radius * radius * 1.02, "{name}: origin off the disk");
        r2.push(d2 / (radius * radius));
        inner.push((d2 <= 0.25 * radius * radius) as u64 as f64);
    }
    for (stats, exact, what) in [
        (&r2, 0.5, "mean r^2 / R^2"),
        (&inner, 0.25, "inner fraction"),
    ] {
        assert!(
            (stats.mean() - exact).abs() <= 5.0 * stats.std_error() + 1e-3,
            "{name}: {what} {} +- {}, uniform gives {exact}",
            stats.mean(),
            stats.std_error()
        );
    }
    for p in [
        Vec3::ZERO,
        Vec3::new(0.7, -0.4, 0.9),
        Vec3::new(-1.0, 1.0, 1.0),
    ] {
        let s = light.sample_direct(p, rng.uniform2()).unwrap();
        assert_eq!(
            (s.wi, s.li, s.pdf),
            (wi, irradiance, 1.0),
            "{name}: from {p}"
        );
        // Upstream: the disk lies toward the light from the point, and the shadow ray ends
        // outside the scene's bounding sphere (radius R, touching the disk at its centre).
        let upstream = (centre - p.as_dvec3()).dot(wi.as_dvec3());
        assert!(upstream > 0.0, "{name}: the disk is not upstream of {p}");
        let sphere_centre = centre - wi.as_dvec3() * radius;
        assert!(
            (s.p.as_dvec3() - sphere_centre).length() >= radius * 0.999,
            "{name}: the shadow ray from {p} ends inside the scene"
        );
    }
}

/// `pdf_emission` gives the densities each emission sample was drawn with (the same values,
/// so bidirectional MIS weights use the densities of the sampler), and its direction density
/// integrates to 1 over the sphere (Monte Carlo with uniform directions, 5 standard errors).
fn check_pdf_emission(name: &str, light: &Light) {
    let mut rng = Rng::new(seed(name), 5, 0);
    let mut integral = Stats::default();
    for _ in 0..SAMPLES {
        let s = light.sample_emission(rng.uniform2(), rng.uniform2());
        let (pdf_pos, pdf_dir) = light.pdf_emission(s.n, s.dir);
        assert!(
            (pdf_pos - s.pdf_pos).abs() <= 1e-6 * s.pdf_pos
                && (pdf_dir - s.pdf_dir).abs() <= 1e-4 * s.pdf_dir + 1e-6,
            "{name}: pdf_emission ({pdf_pos}, {pdf_dir}) vs sampled ({}, {})",
            s.pdf_pos,
            s.pdf_dir
        );
        let w = uniform_sphere(rng.uniform2());
        integral.push(4.0 * PI * light.pdf_emission(s.n, w).1 as f64);
    }
    if light.kind() == LightKind::DeltaDirection {
        // A delta in direction has no density over the sphere (`check_delta_direction`).
        return;
    }
    assert!(
        (integral.mean() - 1.0).abs() <= 5.0 * integral.std_error() + 1e-6,
        "{name}: the emission direction pdf integrates to {} +- {}",
        integral.mean(),
        integral.std_error()
    );
}

/// `le` is Lambertian and one-sided: the same radiance toward every direction on the side the
/// normal points to, zero on the other (and zero everywhere for a delta light); and the
/// emission samples carry it: flux = le pi / pdf_pos (pi A Le with pdf_pos = 1/A).
fn check_le_one_sided(name: &str, light: &Light) {
    let mut rng = Rng::new(seed(name), 4, 0);
    if light.kind() == LightKind::Infinite {
        check_le_infinite(name, light, &mut rng);
        return;
    }
    for _ in 0..20_000 {
        let s = light.sample_emission(rng.uniform2(), rng.uniform2());
        let w = uniform_sphere(rng.uniform2());
        let (front, back) = if w.dot(s.n) >= 0.0 { (w, -w) } else { (-w, w) };
        assert_eq!(light.le(s.n, back), Vec3::ZERO, "{name}: emits backward");
        let le = light.le(s.n, front);
        if light.is_delta() {
            assert_eq!(le, Vec3::ZERO, "{name}: a delta light has no radiance");
            continue;
        }
        if front.dot(s.n) > 0.0 {
            assert_eq!(le, light.le(s.n, s.n), "{name}: not Lambertian");
            assert!(le.max_element() > 0.0, "{name}: no emission in front");
        }
        if s.flux != Vec3::ZERO {
            let expected = light.le(s.n, s.n) * std::f32::consts::PI / s.pdf_pos;
            assert!(
                (s.flux - expected).abs().max_element() <= 1e-5 * expected.max_element(),
                "{name}: flux {} vs le pi A = {expected}",
                s.flux
            );
        }
    }
}

/// A light at infinity radiates L(w) from every direction, the same seen from every point:
/// `le(n, -w)` is `le_infinite(w)` (what a ray escaping along w sees) whatever `n`, and
/// `pdf_infinite(w)` is `pdf_direct` toward w; its emission samples carry L(-dir) over the
/// densities they were drawn with (flux = L / (pdf_pos pdf_dir), the disk perpendicular to
/// the direction), from origins upstream of the scene's bounding sphere (the disk's area is
/// 1 / pdf_pos, its centre R from the sphere's centre).
fn check_le_infinite(name: &str, light: &Light, rng: &mut Rng) {
    for _ in 0..20_000 {
        let w = uniform_sphere(rng.uniform2());
        let le = light.le_infinite(w);
        assert!(le.is_finite() && le.min_element() >= 0.0, "{name}: {le}");
        assert_eq!(light.le(Vec3::ZERO, -w), le, "{name}");
        assert_eq!(light.le(Vec3::X, -w), le, "{name}: le depends on n");
        let pdf = light.pdf_direct(Vec3::ZERO, w * 10.0, Vec3::ZERO);
        let rel = (pdf - light.pdf_infinite(w)).abs() / pdf.max(1e-6);
        assert!(rel <= 1e-3, "{name}: pdf_direct {pdf} vs pdf_infinite");
        let s = light.sample_emission(rng.uniform2(), rng.uniform2());
        if s.flux == Vec3::ZERO {
            continue;
        }
        let expected = light.le_infinite(-s.dir) / (s.pdf_pos * s.pdf_dir);
        assert!(
            (s.flux - expected).abs().max_element() <= 1e-5 * expected.max_element(),
            "{name}: flux {} vs L / (pdf_pos pdf_dir) = {expected}",
            s.flux
        );
        // Every origin lies on a plane R (the disk's radius) upstream of the sphere's
        // centre, which the test lights put inside the box [-1, 2] x [-1, 1] x [-1, 1].
        let radius = (1.0 / (std::f32::consts::PI * s.pdf_pos)).sqrt();
        let centre = Vec3::new(0.5, 0.0, 0.0);
        let along = (s.ray_origin - centre).dot(s.dir);
        assert!(
            (along + radius).abs() <= 1e-4 * radius,
            "{name}: origin {} not upstream of the scene",
            s.ray_origin
        );
    }
}

/// `light_harness! { name: light => [points it is seen from], ... }`: the checks above for
/// each light, as one module of tests per light.
macro_rules! light_harness {
    ($($name:ident: $light:expr => [$($p:expr),* $(,)?],)*) => {
        $(
            mod $name {
                use super::*;
                fn light() -> Light {
                    $light
                }
                fn points() -> Vec<Vec3> {
                    vec![$($p),*]
                }
                #[test]
                fn pdf_direct_integrates_to_the_sampled_fraction() {
                    check_pdf_integrates(stringify!($name), &light(), &points());
                }
                #[test]
                fn sample_direct_follows_pdf_direct() {
                    check_sample_matches_pdf(stringify!($name), &light(), &points());
                }
                #[test]
                fn mean_emitted_flux_is_the_power() {
                    check_emitted_power(stringify!($name), &light());
                }
                #[test]
                fn pdf_emission_matches_sample_emission() {
                    check_pdf_emission(stringify!($name), &light());
                }
                #[test]
                fn delta_intensity_matches_emission_and_power() {
                    check_delta_intensity(stringify!($name), &light());
                }
                #[test]
                fn le_is_one_sided() {
                    check_le_one_sided(stringify!($name), &light());
                }
            }
        )*
    };
}

/// A triangle in the plane y = 1 facing down (-y).
fn downward_triangle() -> Light {
    let tri = Triangle {
        v: [
            Vec3::new(-1.0, 1.0, -0.5),
            Vec3::new(1.2, 1.0, -0.7),
            Vec3::new(0.1, 1.0, 1.0),
        ],
    };
    assert!(tri.cross().y < 0.0);
    Light::triangle(tri, Vec3::new(1.0, 2.0, 3.0), 0).unwrap()
}

/// A small, slanted, strongly coloured triangle.
fn slanted_triangle() -> Light {
    let tri = Triangle {
        v: [
            Vec3::new(-0.3, 1.0, 0.0),
            Vec3::new(0.2, 1.4, -0.2),
            Vec3::new(0.1, 1.2, 0.3),
        ],
    };
    Light::triangle(tri, Vec3::new(5.0, 0.1, 0.0), 3).unwrap()
}

fn sphere(inward: bool) -> Light {
    let s = Sphere::new(Vec3::new(0.3, 2.0, -0.2), 0.7, 0);
    Light::sphere(
        if inward { s.inward() } else { s },
        Vec3::new(2.0, 1.0, 0.5),
        1,
    )
}

fn point() -> Light {
    Light::Point(PointLight {
        position: Vec3::new(1.0, 2.0, 3.0),
        intensity: Vec3::new(1.0, 0.5, 2.0),
    })
}

/// A spot light pointing down and sideways, with a 40 degree cone whose last 15 degrees
/// fall off.
fn spot() -> Light {
    Light::spot(
        Vec3::new(0.5, 2.0, -1.0),
        Vec3::new(0.3, -1.0, 0.2),
        Vec3::new(2.0, 1.0, 0.5),
        40f32.to_radians(),
        25f32.to_radians(),
    )
    .unwrap()
}

/// A spot light with a sharp edge (no falloff) and a cone wider than a hemisphere.
fn spot_wide() -> Light {
    Light::spot(
        Vec3::ZERO,
        Vec3::X,
        Vec3::ONE,
        120f32.to_radians(),
        120f32.to_radians(),
    )
    .unwrap()
}

/// A sun: irradiance (2, 1, 0.5) W/m^2 travelling down and sideways, over a scene whose
/// bounds are the box [-1, 2] x [-1, 1] x [-1, 1].
fn sun() -> Light {
    let mut light =
        Light::directional(Vec3::new(0.3, -1.0, 0.2), Vec3::new(2.0, 1.0, 0.5)).unwrap();
    light.preprocess((Vec3::new(-1.0, -1.0, -1.0), Vec3::new(2.0, 1.0, 1.0)));
    light
}

light_harness! {
    triangle: downward_triangle() => [
        Vec3::new(0.1, 0.4, 0.0),            // below, in front of it
        Vec3::new(2.0, -1.0, 0.5),           // off to the side
        Vec3::new(0.0, 3.0, 0.0),            // behind: never sampled, pdf 0
    ],
    triangle_slanted: slanted_triangle() => [
        Vec3::ZERO,
        Vec3::new(-1.0, 0.5, 1.0),
    ],
    sphere_outward: sphere(false) => [
        Vec3::new(0.0, 0.5, 0.3),            // outside: the facing cap only
        Vec3::new(0.3, 2.0, 1.2),            // close to the surface
    ],
    sphere_inward: sphere(true) => [
        Vec3::new(0.5, 2.1, 0.0),            // inside: every point faces it
        Vec3::new(0.3, 2.0, -0.2),           // at the centre
    ],
    point_light: point() => [
        Vec3::ZERO,
        Vec3::new(1.0, 2.0, 2.0),
    ],
    spot_light: spot() => [
        Vec3::new(0.8, 1.0, -0.8),           // on the axis
        Vec3::new(0.5, -1.0, -1.0),          // 20 degrees off it
        Vec3::new(0.5, 0.0, -1.6),           // 32 degrees off: in the falloff band
        Vec3::new(0.5, 3.0, -1.0),           // behind: no light
    ],
    spot_light_wide: spot_wide() => [
        Vec3::new(-0.3, 1.0, 0.0),           // behind the plane of the light, in the cone
        Vec3::new(-1.0, 0.2, 0.0),           // outside the cone
    ],
    sun: sun() => [
        Vec3::ZERO,
        Vec3::new(2.0, -1.0, 1.0),           // a corner of the bounds
    ],
    environment_constant: environment_constant() => [
        Vec3::ZERO,
        Vec3::new(2.0, -1.0, 1.0),
    ],
    environment_image: environment_image() => [
        Vec3::ZERO,
        Vec3::new(-1.0, 0.5, 0.3),
    ],
    environment_equal_area: environment_equal_area() => [
        Vec3::ZERO,
        Vec3::new(1.5, -0.5, -0.8),
    ],
}

/// A 12 x 12 equal-area map (pbrt-v4's) with a gradient, a bright texel in the lower
/// hemisphere (a corner triangle) and a black row, turned and mirrored (determinant -1, as
/// pbrt's importer mirrors a world).
fn environment_equal_area() -> Light {
    let n = 12;
    let texels = (0..n * n)
        .map(|k| {
            let (x, y) = ((k % n) as f32, (k / n) as f32);
            if y == 7.0 {
                Vec3::ZERO
            } else if (x, y) == (1.0, 10.0) {
                Vec3::new(300.0, 400.0, 100.0)
            } else {
                Vec3::new(0.1 + 0.04 * x, 0.5, 0.2 + 0.06 * y)
            }
        })
        .collect();
    let map = EnvironmentMap::EqualArea(Arc::new(EqualAreaMap::new(n, texels).unwrap()));
    let turn = Mat3::from_diagonal(Vec3::new(-1.0, 1.0, 1.0))
        * Mat3::from_rotation_x(-std::f32::consts::FRAC_PI_2)
        * Mat3::from_rotation_z(0.4);
    let mut light = Light::Environment(EnvironmentLight::new(map, 1.3, turn).unwrap());
    light.preprocess(BOUNDS);
    light
}

/// The bounds the lights at infinity are preprocessed with: the box [-1, 2] x [-1, 1] x
/// [-1, 1] (`check_le_infinite` knows its centre).
const BOUNDS: (Vec3, Vec3) = (Vec3::new(-1.0, -1.0, -1.0), Vec3::new(2.0, 1.0, 1.0));

/// A constant environment of radiance (0.5, 1, 2).
fn environment_constant() -> Light {
    let map = EnvironmentMap::Constant(Vec3::new(0.5, 1.0, 2.0));
    let mut light = Light::Environment(EnvironmentLight::new(map, 1.5, Mat3::IDENTITY).unwrap());
    light.preprocess(BOUNDS);
    light
}

/// A 16 x 8 map with nothing symmetric about it: a sky brightening toward the top and
/// coloured along u, a bright 1-texel "sun", and a black band (zero luminance: never
/// sampled, pdf 0), rotated 30 degrees about x and 70 about y.
fn environment_image() -> Light {
    let (w, h) = (16, 8);
    let texels = (0..w * h)
        .map(|k| {
            let (x, y) = ((k % w) as f32, (k / w) as f32);
            if y == 5.0 {
                Vec3::ZERO
            } else if (x, y) == (11.0, 2.0) {
                Vec3::new(400.0, 300.0, 200.0)
            } else {
                Vec3::new(0.2 + 0.05 * x, 0.3, 1.0 - 0.1 * y)
            }
        })
        .collect();
    let map = EnvironmentMap::Image(Arc::new(LatLongMap::new(w, h, texels).unwrap()));
    let rotation = Mat3::from_rotation_y(70f32.to_radians())
        * Mat3::from_rotation_x(std::f32::consts::FRAC_PI_6);
    let mut light = Light::Environment(EnvironmentLight::new(map, 0.8, rotation).unwrap());
    light.preprocess(BOUNDS);
    light
}
