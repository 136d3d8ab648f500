//! Tests of the delta BSDFs (mirror, glass), the dielectric Fresnel term and Veach's
//! shading-normal correction. The non-delta models go through `bsdf_harness.rs`.

mod common;

use common::{close, close3, direction, seed, Stats, IORS};
use glam::{Vec2, Vec3};
use ppm_core::bsdf::{
    fresnel_dielectric, reflect, shading_normal_correction, Bsdf, Lobe, TransportMode,
};
use ppm_core::sampling::{uniform_sphere, Rng};

const RADIANCE: TransportMode = TransportMode::Radiance;
const IMPORTANCE: TransportMode = TransportMode::Importance;

// ---------------------------------------------------------------------------------------------
// Fresnel.
// ---------------------------------------------------------------------------------------------

/// Unpolarised Fresnel reflectance in the sin/tan form (Born & Wolf), independent of the
/// implementation's cosine form: F = [sin^2(i - t) / sin^2(i + t) + tan^2(i - t) / tan^2(i + t)] / 2.
fn fresnel_reference(theta_i: f64, eta_i: f64, eta_t: f64) -> f64 {
    let sin_t = theta_i.sin() * eta_i / eta_t;
    if sin_t >= 1.0 {
        return 1.0;
    }
    let theta_t = sin_t.asin();
    let (d, s) = (theta_i - theta_t, theta_i + theta_t);
    0.5 * ((d.sin() / s.sin()).powi(2) + (d.tan() / s.tan()).powi(2))
}

#[test]
fn fresnel_at_normal_incidence_is_r0_from_both_sides() {
    for ior in IORS {
        let r0 = ((ior - 1.0) / (ior + 1.0)).powi(2);
        assert!(
            close(fresnel_dielectric(1.0, ior), r0, 1e-5),
            "ior {ior}: {} != {r0}",
            fresnel_dielectric(1.0, ior)
        );
        assert!(
            close(fresnel_dielectric(-1.0, ior), r0, 1e-5),
            "ior {ior}, from inside"
        );
    }
}

#[test]
fn fresnel_matches_the_sin_tan_form_from_both_sides() {
    for ior in IORS {
        for k in 1..180 {
            let theta = (k as f64 * 0.5).to_radians();
            let cos = theta.cos() as f32;
            let outside = fresnel_dielectric(cos, ior) as f64;
            let inside = fresnel_dielectric(-cos, ior) as f64;
            let (ref_out, ref_in) = (
                fresnel_reference(theta, 1.0, ior as f64),
                fresnel_reference(theta, ior as f64, 1.0),
            );
            assert!(
                (outside - ref_out).abs() < 2e-6,
                "ior {ior}, theta {theta}: {outside} != {ref_out}"
            );
            // Inside, within 0.5 degrees of the critical angle the f32 cosine moves F by ~1e-4.
            assert!(
                (inside - ref_in).abs() < 2e-4,
                "ior {ior}, theta {theta} inside: {inside} != {ref_in}"
            );
        }
    }
}

#[test]
fn fresnel_is_one_beyond_the_critical_angle() {
    for ior in IORS {
        let theta_c = (1.0 / ior as f64).asin();
        for k in 1..=100 {
            let theta = theta_c + (std::f64::consts::FRAC_PI_2 - theta_c) * k as f64 / 100.0;
            let cos = theta.cos() as f32 + 1e-7 * (k == 100) as i32 as f32; // and a grazing 1e-7
            assert_eq!(
                fresnel_dielectric(-cos * (1.0 - 1e-6), ior),
                1.0,
                "ior {ior}, theta {theta}"
            );
        }
    }
}

#[test]
fn fresnel_is_continuous_at_the_critical_angle() {
    for ior in IORS {
        let theta_c = (1.0 / ior as f64).asin();
        let mut previous_gap = f64::INFINITY;
        for delta in [1e-1, 1e-2, 1e-3, 1e-4, 1e-5] {
            let theta = theta_c - delta;
            let f = fresnel_dielectric(-(theta.cos() as f32), ior) as f64;
            let gap = 1.0 - f;
            // 1 - F ~ sqrt(delta) near the critical angle: it shrinks to 0 without a jump.
            assert!(
                gap > 0.0 && gap < previous_gap,
                "ior {ior}, delta {delta}: 1 - F = {gap}"
            );
            assert!(
                (f - fresnel_reference(theta, ior as f64, 1.0)).abs() < 2e-3,
                "ior {ior}, delta {delta}"
            );
            previous_gap = gap;
        }
        assert!(
            previous_gap < 0.05,
            "ior {ior}: F = {} just below the critical angle",
            1.0 - previous_gap
        );
        let past = fresnel_dielectric(-((theta_c + 1e-5).cos() as f32), ior);
        assert_eq!(past, 1.0, "ior {ior}: just beyond the critical angle");
    }
}

/// F is the same for the two directions of a refracted pair (Stokes relations).
#[test]
fn fresnel_is_symmetric_for_snell_pairs() {
    for ior in IORS {
        for k in 0..90 {
            let theta_i = (k as f64).to_radians();
            let theta_t = (theta_i.sin() / ior as f64).asin();
            let entering = fresnel_dielectric(theta_i.cos() as f32, ior);
            let leaving = fresnel_dielectric(-(theta_t.cos() as f32), ior);
            // Near grazing the inside cosine sits at the critical angle, where F has infinite
            // slope: the f32 rounding of cos(theta_t) moves F by ~1e-7 ior^2 / cos(theta_i).
            let tolerance = 1e-6 + 1e-6 / theta_i.cos() as f32;
            assert!(
                (entering - leaving).abs() < tolerance,
                "ior {ior}, theta {k}: {entering} != {leaving}"
            );
        }
    }
}

#[test]
fn fresnel_stays_in_unit_interval() {
    let mut rng = Rng::new(seed("fresnel_range"), 0, 0);
    for _ in 0..100_000 {
        let cos = 2.0 * rng.uniform() - 1.0;
        let eta = 1.0 + 3.0 * rng.uniform();
        for c in [cos, 1e-7, -1e-7, 0.0, 1.0, -1.0] {
            let f = fresnel_dielectric(c, eta);
            assert!((0.0..=1.0).contains(&f), "F({c}, {eta}) = {f}");
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Glass.
// ---------------------------------------------------------------------------------------------

/// The largest f32 below 1: as `u_lobe` it picks refraction whenever F < 1.
const REFRACT: f32 = 0.99999994;

/// (index on wo's side, index on the other side) for a glass of `ior`.
fn indices(wo: Vec3, ior: f32) -> (f32, f32) {
    if wo.z > 0.0 {
        (1.0, ior)
    } else {
        (ior, 1.0)
    }
}

/// Glass incident directions: outside and inside, including beyond the critical angle.
fn glass_directions() -> Vec<Vec3> {
    let mut dirs = Vec::new();
    for deg in [0.0f32, 20.0, 40.0, 45.0, 60.0, 80.0, 89.9] {
        let cos = deg.to_radians().cos();
        dirs.push(direction(cos, 0.4));
        dirs.push(direction(-cos, 2.2));
    }
    dirs
}

#[test]
fn glass_chooses_lobes_by_fresnel_and_refracts_by_snell() {
    const N: usize = 100_000;
    for ior in IORS {
        let glass = Bsdf::glass(ior, Vec3::new(0.9, 0.8, 0.7));
        for (k, wo) in glass_directions().into_iter().enumerate() {
            let f = fresnel_dielectric(wo.z, ior);
            let (eta_o, eta_t) = indices(wo, ior);
            let mut rng = Rng::new(seed("glass_lobes"), k as u64, ior.to_bits() as u64);
            let mut reflected = 0usize;
            for _ in 0..N {
                let s = glass
                    .sample(wo, rng.uniform(), rng.uniform2(), RADIANCE)
                    .expect("glass always scatters");
                assert_eq!(s.lobe, Lobe::Specular);
                if s.wi.z * wo.z > 0.0 {
                    reflected += 1;
                    assert_eq!(s.wi, reflect(wo), "reflection must be exact");
                    assert_eq!(s.pdf, f, "reflection probability");
                } else {
                    assert_eq!(s.pdf, 1.0 - f, "refraction probability");
                    assert!(
                        (s.wi.length() - 1.0).abs() < 1e-5,
                        "refracted wi {} not unit",
                        s.wi
                    );
                    let (sin_o, sin_t) = (wo.truncate().length(), s.wi.truncate().length());
                    assert!(
                        (eta_o * sin_o - eta_t * sin_t).abs() < 1e-5,
                        "Snell: wo {wo}, wi {}",
                        s.wi
                    );
                    // In the plane of incidence, on the far side of the normal.
                    let (a, b) = (wo.truncate(), s.wi.truncate());
                    assert!(
                        a.perp_dot(b).abs() < 1e-5 && a.dot(b) <= 0.0,
                        "wo {wo}, wi {}",
                        s.wi
                    );
                }
            }
            let fraction = reflected as f64 / N as f64;
            let sigma = (f as f64 * (1.0 - f as f64) / N as f64).sqrt();
            assert!(
                (fraction - f as f64).abs() <= 5.0 * sigma + 1e-6,
                "ior {ior}, wo {wo}: reflected {fraction}, F = {f}"
            );
        }
    }
}

#[test]
fn glass_weights_depend_on_transport_mode_only_for_refraction() {
    let color = Vec3::new(0.9, 0.8, 0.7);
    for ior in IORS {
        let glass = Bsdf::glass(ior, color);
        for wo in glass_directions() {
            let f = fresnel_dielectric(wo.z, ior);
            let (eta_o, eta_t) = indices(wo, ior);
            for mode in [RADIANCE, IMPORTANCE] {
                let r = glass.sample(wo, 0.0, Vec2::ZERO, mode).unwrap();
                assert_eq!(
                    (r.weight, r.wi),
                    (Vec3::ONE, reflect(wo)),
                    "reflection is colourless"
                );
                if f < 1.0 {
                    let t = glass.sample(wo, REFRACT, Vec2::ZERO, mode).unwrap();
                    // Radiance: L / eta^2 is invariant, so weight = color (eta_o / eta_t)^2.
                    let expected = match mode {
                        TransportMode::Radiance => color * (eta_o / eta_t).powi(2),
                        TransportMode::Importance => color,
                    };
                    assert!(
                        close3(t.weight, expected, 1e-5),
                        "{mode:?} wo {wo}: {} != {expected}",
                        t.weight
                    );
                }
            }
        }
    }
}

#[test]
fn glass_conserves_energy() {
    const N: usize = 50_000;
    for ior in IORS {
        let glass = Bsdf::glass(ior, Vec3::ONE);
        for (k, wo) in glass_directions().into_iter().enumerate() {
            let f = fresnel_dielectric(wo.z, ior) as f64;
            let (eta_o, eta_t) = indices(wo, ior);
            let mut rng = Rng::new(seed("glass_energy"), k as u64, ior.to_bits() as u64);
            let (mut flux, mut radiance) = (Stats::default(), Stats::default());
            for _ in 0..N {
                let (u_lobe, u) = (rng.uniform(), rng.uniform2());
                flux.push(glass.sample(wo, u_lobe, u, IMPORTANCE).unwrap().weight.x as f64);
                radiance.push(glass.sample(wo, u_lobe, u, RADIANCE).unwrap().weight.x as f64);
            }
            // Photons: reflected + transmitted flux = incident flux, every sample has weight 1.
            assert!(
                (flux.mean() - 1.0).abs() < 1e-6,
                "ior {ior}, wo {wo}: mean photon weight {}",
                flux.mean()
            );
            // Camera paths: E[weight] = F + (1 - F) (eta_o / eta_t)^2.
            let expected = f + (1.0 - f) * ((eta_o / eta_t) as f64).powi(2);
            let bound = 5.0 * radiance.std_error() + 1e-5;
            assert!(
                (radiance.mean() - expected).abs() <= bound,
                "ior {ior}, wo {wo}: {} != {expected}",
                radiance.mean()
            );
        }
    }
}

/// Refraction is not symmetric, but obeys Veach's generalized reciprocity (1997, sec. 5.2):
/// f(wo, wi) / eta_o^2 = f(wi, wo) / eta_i^2, and the adjoint BSDF used by photons is
/// f*(wo, wi) = f(wi, wo). Both sides are deltas, the forward one in wi's projected solid angle
/// with coefficient c(wo -> wi) = weight * pdf, the backward one in wo's. Etendue conservation,
/// eta_o^2 dσ⊥(wo) = eta_i^2 dσ⊥(wi), turns a delta in wo into (eta_o / eta_i)^2 times a delta in
/// wi, so with c' = c(wi -> wo) (eta_o / eta_i)^2:
///   radiance:   c_R(wo -> wi) / eta_o^2 = c'_R / eta_i^2;
///   importance: c_I(wo -> wi) = c'_R.
#[test]
fn glass_refraction_obeys_generalized_reciprocity() {
    for ior in IORS {
        let glass = Bsdf::glass(ior, Vec3::new(0.9, 0.8, 0.7));
        for wo in glass_directions() {
            if fresnel_dielectric(wo.z, ior) >= 1.0 {
                continue;
            }
            let (eta_o, eta_i) = indices(wo, ior);
            let fwd = glass.sample(wo, REFRACT, Vec2::ZERO, RADIANCE).unwrap();
            let fwd_importance = glass.sample(wo, REFRACT, Vec2::ZERO, IMPORTANCE).unwrap();
            let bwd = glass.sample(fwd.wi, REFRACT, Vec2::ZERO, RADIANCE).unwrap();
            // When the vacuum side grazes, the glass side is at its critical angle and the f32
            // rounding of fwd.wi.z (~6e-8) moves the way back by ~1e-7 / cos(vacuum side).
            let cos_vacuum = if wo.z > 0.0 { wo.z } else { fwd.wi.z.abs() };
            let back_error = (bwd.wi - wo).length();
            assert!(
                back_error < 1e-5 + 2e-7 / cos_vacuum,
                "not an involution: {wo} -> {} -> {}",
                fwd.wi,
                bwd.wi
            );
            let c_bwd = bwd.weight * bwd.pdf * (eta_o / eta_i).powi(2);
            let lhs = fwd.weight * fwd.pdf / (eta_o * eta_o);
            let rhs = c_bwd / (eta_i * eta_i);
            // Likewise 1 - F recomputed from the reversed direction: relative error about
            // 1e-7 / cos_vacuum^2, 3% at 89.9 degrees, still far below the eta^2 factors tested.
            let tolerance = 1e-5 + 1e-7 / (cos_vacuum * cos_vacuum);
            assert!(
                close3(lhs, rhs, tolerance),
                "ior {ior}, wo {wo}: radiance {lhs} != {rhs}"
            );
            let adjoint = fwd_importance.weight * fwd_importance.pdf;
            assert!(
                close3(adjoint, c_bwd, tolerance),
                "ior {ior}, wo {wo}: importance {adjoint} != {c_bwd}"
            );
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Mirror and the delta contract.
// ---------------------------------------------------------------------------------------------

#[test]
fn mirror_reflects_exactly_with_weight_color_on_both_sides() {
    let color = Vec3::new(0.9, 0.5, 0.2);
    let mirror = Bsdf::mirror(color);
    let mut rng = Rng::new(seed("mirror"), 0, 0);
    for _ in 0..10_000 {
        let wo = uniform_sphere(rng.uniform2());
        for mode in [RADIANCE, IMPORTANCE] {
            let s = mirror
                .sample(wo, rng.uniform(), rng.uniform2(), mode)
                .unwrap();
            assert_eq!(s.wi, Vec3::new(-wo.x, -wo.y, wo.z));
            assert_eq!((s.weight, s.pdf, s.lobe), (color, 1.0, Lobe::Specular));
        }
    }
}

#[test]
fn delta_bsdfs_have_zero_eval_and_pdf() {
    let mut rng = Rng::new(seed("delta"), 0, 0);
    for bsdf in [Bsdf::mirror(Vec3::ONE), Bsdf::glass(1.5, Vec3::ONE)] {
        assert!(bsdf.is_delta());
        for _ in 0..1000 {
            let wo = uniform_sphere(rng.uniform2());
            let wi = bsdf
                .sample(wo, rng.uniform(), rng.uniform2(), RADIANCE)
                .unwrap()
                .wi;
            for w in [wi, uniform_sphere(rng.uniform2())] {
                assert_eq!(bsdf.eval(wo, w, RADIANCE), Vec3::ZERO);
                assert_eq!(bsdf.eval(wo, w, IMPORTANCE), Vec3::ZERO);
                assert_eq!(bsdf.pdf(wo, w), 0.0);
            }
        }
    }
    assert!(
        !Bsdf::diffuse(Vec3::ONE).is_delta() && !Bsdf::phong(Vec3::ONE, Vec3::ZERO, 1.0).is_delta()
    );
}

// ---------------------------------------------------------------------------------------------
// Shading normals (Veach 1997, eq. 5.19).
// ---------------------------------------------------------------------------------------------

#[test]
fn shading_normal_correction_matches_eq_5_19() {
    let ng = Vec3::Z;
    let ns = Vec3::new(0.0, 30f32.to_radians().sin(), 30f32.to_radians().cos());
    let wo = Vec3::Z;
    let wi = Vec3::new(0.0, 1.0, 1.0).normalize();
    // |wo.ns| |wi.ng| / (|wo.ng| |wi.ns|) = cos 30 cos 45 / (1 cos 15).
    let expected = 30f32.to_radians().cos() * 45f32.to_radians().cos() / 15f32.to_radians().cos();
    let c = shading_normal_correction(IMPORTANCE, wo, wi, ng, ns);
    assert!(close(c, expected, 1e-5), "{c} != {expected}");
    assert_eq!(shading_normal_correction(RADIANCE, wo, wi, ng, ns), 1.0);
    assert!(close(
        shading_normal_correction(IMPORTANCE, wo, wi, ng, ng),
        1.0,
        1e-6
    ));
}

#[test]
fn shading_normal_correction_is_finite_and_inverts_when_swapped() {
    let mut rng = Rng::new(seed("shading_normal"), 0, 0);
    for _ in 0..100_000 {
        let ng = uniform_sphere(rng.uniform2());
        let ns = (ng + 0.5 * uniform_sphere(rng.uniform2())).normalize();
        let (wo, wi) = (
            uniform_sphere(rng.uniform2()),
            uniform_sphere(rng.uniform2()),
        );
        let c = shading_normal_correction(IMPORTANCE, wo, wi, ng, ns);
        let swapped = shading_normal_correction(IMPORTANCE, wi, wo, ng, ns);
        assert!(c.is_finite() && c >= 0.0, "{c}");
        if c > 0.0 && swapped > 0.0 {
            assert!(close(c * swapped, 1.0, 1e-3), "c {c}, swapped {swapped}");
        }
    }
    // Directions in the geometric or shading plane give 0, not inf or NaN.
    let (ng, ns) = (Vec3::Z, Vec3::new(0.0, 0.6, 0.8));
    let in_geometric_plane = Vec3::X;
    let in_shading_plane = Vec3::new(0.0, 0.8, -0.6);
    assert_eq!(
        shading_normal_correction(IMPORTANCE, in_geometric_plane, Vec3::Z, ng, ns),
        0.0
    );
    assert_eq!(
        shading_normal_correction(IMPORTANCE, Vec3::Z, in_shading_plane, ng, ns),
        0.0
    );
    assert_eq!(
        shading_normal_correction(IMPORTANCE, Vec3::Z, Vec3::ZERO, ng, ns),
        0.0
    );
}
