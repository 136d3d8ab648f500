//! The generic BSDF checks behind `bsdf_harness!` (chi-square of `sample` against `pdf`,
//! consistency, reciprocity, energy, grazing angles, lobe decomposition), shared by the test
//! files that run them.

// Each test file uses a different subset.
#![allow(dead_code)]

use crate::common::{chi2_directions, close, close3, direction, seed, sidak, Stats};
use glam::Vec3;
use ppm_core::bsdf::{Bsdf, BsdfFlags, Lobe, TransportMode};
use ppm_core::sampling::{uniform_sphere, Rng};
use std::f32::consts::PI;

pub const RADIANCE: TransportMode = TransportMode::Radiance;
pub const IMPORTANCE: TransportMode = TransportMode::Importance;

/// Polar angles (degrees) of the incident directions of the generic tests; each is used above
/// the surface and mirrored below it (two-sided models), at an azimuth off the histogram grid.
pub const THETA_O_DEG: [f64; 5] = [0.0, 30.0, 60.0, 85.0, 89.9];

/// Samples per chi-square test.
pub const CHI2_SAMPLES: usize = 1_000_000;
/// Family-wise significance of all chi-square tests together.
pub const CHI2_ALPHA: f64 = 0.01;

/// The incident directions: `THETA_O_DEG` above, then the same mirrored below the surface.
pub fn incident_directions() -> Vec<Vec3> {
    let phi = 1.0f64;
    let above = THETA_O_DEG.iter().map(|&deg| {
        let (s, c) = deg.to_radians().sin_cos();
        Vec3::new((s * phi.cos()) as f32, (s * phi.sin()) as f32, c as f32).normalize()
    });
    let below = above.clone().map(|w| Vec3::new(w.x, w.y, -w.z));
    above.chain(below).collect()
}

/// The directional albedo where it is known in closed form: constant for Lambertian, and
/// diffuse + specular at normal incidence for Phong (the (n + 2) / (2 pi) normalisation).
pub fn known_albedo(bsdf: &Bsdf, wo: Vec3) -> Option<Vec3> {
    match bsdf {
        Bsdf::Diffuse(d) => Some(d.albedo),
        Bsdf::Phong(p) => (wo.z.abs() == 1.0).then_some(p.diffuse + p.specular),
        Bsdf::Mirror(_)
        | Bsdf::Glass(_)
        | Bsdf::Conductor(_)
        | Bsdf::Dielectric(_)
        | Bsdf::ThinDielectric(_)
        | Bsdf::Plastic(_)
        | Bsdf::TwoSidedConductor(_)
        | Bsdf::TwoSidedPlastic(_) => None,
    }
}

// ---------------------------------------------------------------------------------------------
// Generic checks for non-delta BSDFs.
// ---------------------------------------------------------------------------------------------

/// Chi-square goodness of fit of `sample` against `pdf`, and the mean of pdf(wi) against the
/// integral of pdf^2 (see [`chi2_directions`]), for every incident direction. Each statistic
/// is tested at the Sidak-corrected level so that all `chi2_tests` runs of the file together
/// (two statistics each) reject a correct sampler with probability `CHI2_ALPHA`.
pub fn check_chi2(name: &str, bsdf: &Bsdf, chi2_tests: usize) {
    let level = sidak(CHI2_ALPHA, 2 * chi2_tests);
    let mut failures = Vec::new();
    for (k, wo) in incident_directions().into_iter().enumerate() {
        let mut rng = Rng::new(seed(name), k as u64, 0);
        let sample = |rng: &mut Rng| {
            let (u_lobe, u) = (rng.uniform(), rng.uniform2());
            // A delta lobe of a model that mixes it with non-delta ones (smooth plastic) has no
            // density: its samples count as "no sample", expected 1 - integral of pdf.
            bsdf.sample(wo, u_lobe, u, RADIANCE)
                .filter(|s| s.lobe != Lobe::Specular)
                .map(|s| s.wi)
        };
        let o = match chi2_directions(CHI2_SAMPLES, &mut rng, sample, |wi| bsdf.pdf(wo, wi) as f64)
        {
            Ok(o) => o,
            Err(e) => {
                failures.push(format!("wo = {wo}: {e}"));
                continue;
            }
        };
        // Shown with --nocapture: the p-values should look uniform on [0, 1].
        println!(
            "{name}: wo = {wo}: chi2 = {:.1}, dof = {}, p = {:.4}; mean pdf(wi) p = {:.4}",
            o.statistic, o.dof, o.p_value, o.collision_p_value
        );
        if o.p_value < level {
            failures.push(format!(
                "wo = {wo}: chi2 = {:.1}, dof = {}, p = {:.3e} < {level:.3e}, pdf mass {:.6}, \
                 worst cells (theta, phi, observed, expected) {:?}",
                o.statistic, o.dof, o.p_value, o.pdf_mass, o.worst
            ));
        }
        if o.collision_p_value < level {
            let (mean, se) = o.collision_observed;
            failures.push(format!(
                "wo = {wo}: mean pdf(wi) = {mean:.6} +- {se:.1e} but integral of pdf^2 = {:.6} \
                 (p = {:.3e} < {level:.3e})",
                o.collision_expected, o.collision_p_value
            ));
        }
    }
    assert!(
        failures.is_empty(),
        "{name}: sample does not follow pdf:\n{}",
        failures.join("\n")
    );
}

/// What `sample` returns agrees with `pdf` and `eval`: pdf(wo, wi) equals the returned pdf,
/// weight = f |cos(wi)| / pdf, the lobe is not a delta unless the flags have one (then its pdf
/// is a probability, its weight finite); and `pdf > 0` wherever `f > 0` (otherwise the
/// estimator would miss part of the integrand).
pub fn check_consistency(name: &str, bsdf: &Bsdf) {
    let mut rng = Rng::new(seed(name), 1, 1);
    let mut directions = incident_directions();
    directions.extend((0..30).map(|_| uniform_sphere(rng.uniform2())));
    for wo in directions {
        for _ in 0..2000 {
            let (u_lobe, u) = (rng.uniform(), rng.uniform2());
            let Some(s) = bsdf.sample(wo, u_lobe, u, RADIANCE) else {
                continue;
            };
            if s.lobe == Lobe::Specular {
                assert!(
                    bsdf.flags().contains(BsdfFlags::SPECULAR),
                    "{name}: a non-delta BSDF returned a delta lobe"
                );
                assert!(
                    s.pdf > 0.0 && s.pdf <= 1.0 && s.weight.is_finite(),
                    "{name}: delta sample {s:?}"
                );
                continue;
            }
            assert!(
                (s.wi.length() - 1.0).abs() < 1e-4,
                "{name}: wi = {} not unit",
                s.wi
            );
            assert!(
                s.pdf > 0.0 && s.pdf.is_finite(),
                "{name}: sample pdf {}",
                s.pdf
            );
            let pdf = bsdf.pdf(wo, s.wi);
            assert!(
                close(s.pdf, pdf, 1e-4),
                "{name}: wo {wo} wi {}: sample pdf {} != pdf {pdf}",
                s.wi,
                s.pdf
            );
            let expected = bsdf.eval(wo, s.wi, RADIANCE) * s.wi.z.abs() / pdf;
            assert!(
                s.weight.is_finite()
                    && s.weight.min_element() >= 0.0
                    && close3(s.weight, expected, 1e-4),
                "{name}: wo {wo} wi {}: weight {} != f |cos| / pdf = {expected}",
                s.wi,
                s.weight
            );
        }
        for _ in 0..2000 {
            let wi = uniform_sphere(rng.uniform2());
            let f = bsdf.eval(wo, wi, RADIANCE);
            let pdf = bsdf.pdf(wo, wi);
            assert!(
                f.min_element() >= 0.0 && pdf >= 0.0,
                "{name}: negative f {f} or pdf {pdf}"
            );
            assert!(
                f.max_element() == 0.0 || pdf > 0.0,
                "{name}: wo {wo} wi {wi}: f = {f} but pdf = 0"
            );
        }
    }
}

/// The adjoint BSDF (light paths) is the radiance one with its arguments swapped,
/// f*(wo, wi) = f(wi, wo) (Veach 1997, eq. 3.21), for every pair; and f(wo, wi) = f(wi, wo)
/// (Helmholtz) for reflection, and for refraction too where the model does not refract
/// (there the two modes agree). Refraction by a relative index eta is reciprocal only up to
/// eta^2 (Veach 1997, eq. 5.14), which the adjoint check covers. On random pairs and on sampled
/// pairs (which find the narrow glossy peaks).
pub fn check_reciprocity(name: &str, bsdf: &Bsdf) {
    let refracts = bsdf.flags().contains(BsdfFlags::TRANSMISSION);
    let mut rng = Rng::new(seed(name), 2, 2);
    for _ in 0..20_000 {
        let wo = uniform_sphere(rng.uniform2());
        let (u_lobe, u) = (rng.uniform(), rng.uniform2());
        let random = uniform_sphere(rng.uniform2());
        let sampled = bsdf.sample(wo, u_lobe, u, RADIANCE).map(|s| s.wi);
        for wi in std::iter::once(random).chain(sampled) {
            let f = bsdf.eval(wo, wi, RADIANCE);
            let f_swapped = bsdf.eval(wi, wo, RADIANCE);
            let adjoint = bsdf.eval(wo, wi, IMPORTANCE);
            assert!(
                close3(adjoint, f_swapped, 1e-4),
                "{name}: f*({wo}, {wi}) = {adjoint} != f(wi, wo) = {f_swapped}"
            );
            if !refracts || wo.z * wi.z > 0.0 {
                assert!(
                    close3(f, f_swapped, 1e-4),
                    "{name}: f({wo}, {wi}) = {f} != f(wi, wo) = {f_swapped}"
                );
                assert_eq!(f, adjoint, "{name}: eval depends on the transport mode");
            }
        }
    }
}

/// Directional albedo rho(wo) = integral of f |cos(wi)| dwi, by two estimators: the mean sample
/// weight (lost samples count 0) and uniform sphere sampling, f |cos| / (1 / (4 pi)). Both must
/// be <= 1 within noise, agree with each other, and match the closed form where known. The
/// albedo is the fraction of flux scattered, so it is taken on light paths (importance mode):
/// on camera paths a refraction out of a dense medium multiplies radiance by eta^2.
pub fn check_energy(name: &str, bsdf: &Bsdf) {
    const N: usize = 100_000;
    for (k, wo) in incident_directions().into_iter().enumerate() {
        let mut rng = Rng::new(seed(name), 3, k as u64);
        let mut by_sampling = [Stats::default(); 3];
        let mut by_uniform = [Stats::default(); 3];
        for _ in 0..N {
            let (u_lobe, u) = (rng.uniform(), rng.uniform2());
            // Delta samples of a mixed model add their albedo to the first estimator only.
            let (w, delta) = match bsdf.sample(wo, u_lobe, u, IMPORTANCE) {
                Some(s) if s.lobe == Lobe::Specular => (s.weight, s.weight),
                Some(s) => (s.weight, Vec3::ZERO),
                None => (Vec3::ZERO, Vec3::ZERO),
            };
            let wi = uniform_sphere(rng.uniform2());
            let g = bsdf.eval(wo, wi, IMPORTANCE) * wi.z.abs() * (4.0 * PI) + delta;
            for c in 0..3 {
                by_sampling[c].push(w[c] as f64);
                by_uniform[c].push(g[c] as f64);
            }
        }
        let known = known_albedo(bsdf, wo);
        for c in 0..3 {
            let (a, b) = (by_sampling[c], by_uniform[c]);
            let (sa, sb) = (5.0 * a.std_error() + 1e-4, 5.0 * b.std_error() + 1e-4);
            let ctx = format!(
                "{name}: wo {wo}, channel {c}: albedo by sampling {:.5} (+-{sa:.1e}), \
                               by uniform directions {:.5} (+-{sb:.1e})",
                a.mean(),
                b.mean()
            );
            assert!(
                a.mean() <= 1.0 + sa && b.mean() <= 1.0 + sb,
                "{ctx}: exceeds 1"
            );
            assert!(
                (a.mean() - b.mean()).abs() <= (sa * sa + sb * sb).sqrt(),
                "{ctx}: disagree"
            );
            if let Some(rho) = known {
                let rho = rho[c] as f64;
                assert!(
                    (a.mean() - rho).abs() <= sa && (b.mean() - rho).abs() <= sb,
                    "{ctx}: expected {rho}"
                );
            }
        }
    }
}

/// Directions a hair above and below the tangent plane, for `wo` and `wi`.
pub fn grazing_directions() -> Vec<Vec3> {
    let mut dirs = Vec::new();
    for cos in [1e-7f32, -1e-7, 1e-6, -1e-6, 0.0] {
        for phi in [0.0f32, 0.7, 2.0, 4.5] {
            dirs.push(direction(cos, phi));
        }
    }
    dirs
}

/// eval, pdf and sample give finite non-negative values for grazing `wo` and `wi`, in both modes.
pub fn check_grazing(name: &str, bsdf: &Bsdf) {
    let mut rng = Rng::new(seed(name), 4, 4);
    let dirs = grazing_directions();
    for &wo in &dirs {
        let mut others = dirs.clone();
        others.extend((0..50).map(|_| uniform_sphere(rng.uniform2())));
        for &wi in &others {
            for (a, b) in [(wo, wi), (wi, wo)] {
                let f = bsdf.eval(a, b, RADIANCE);
                let pdf = bsdf.pdf(a, b);
                assert!(
                    f.is_finite() && f.min_element() >= 0.0,
                    "{name}: f({a}, {b}) = {f}"
                );
                assert!(
                    pdf.is_finite() && pdf >= 0.0,
                    "{name}: pdf({a}, {b}) = {pdf}"
                );
            }
        }
        for mode in [RADIANCE, IMPORTANCE] {
            for _ in 0..2000 {
                let (u_lobe, u) = (rng.uniform(), rng.uniform2());
                if let Some(s) = bsdf.sample(wo, u_lobe, u, mode) {
                    assert!(
                        s.wi.is_finite() && (s.wi.length() - 1.0).abs() < 1e-4,
                        "{name}: wo {wo}: sampled wi {}",
                        s.wi
                    );
                    assert!(
                        s.weight.is_finite() && s.weight.min_element() >= 0.0,
                        "{name}: wo {wo}: weight {}",
                        s.weight
                    );
                    assert!(
                        s.pdf.is_finite() && s.pdf > 0.0,
                        "{name}: wo {wo}: pdf {}",
                        s.pdf
                    );
                }
            }
        }
    }
}

/// The flag a sampled lobe must find among the BSDF's flags.
pub fn lobe_flag(lobe: Lobe) -> BsdfFlags {
    match lobe {
        Lobe::Diffuse => BsdfFlags::DIFFUSE,
        Lobe::Glossy => BsdfFlags::GLOSSY,
        Lobe::Specular => BsdfFlags::SPECULAR,
    }
}

/// The lobe decomposition agrees with the whole BSDF (every model, delta ones included):
/// - what `sample` returns is among the flags: its lobe kind, and reflection or transmission
///   by the side `wi` leaves on; in both transport modes;
/// - the diffuse part exists exactly when the flags say DIFFUSE and is a diffuse reflection
///   with no other lobe; the non-diffuse part exists exactly when they say GLOSSY or SPECULAR,
///   has no diffuse lobe and never samples one; the parts' kinds together are the whole's;
/// - eval(whole) = eval(diffuse part) + eval(non-diffuse part) on random and sampled pairs;
/// - the directional albedo (mean sample weight, delta lobes included) of the whole is the sum
///   of the parts' within noise (5 standard errors), per incident direction;
/// - a non-delta non-diffuse part is a BSDF of its own: its samples agree with its eval and
///   pdf ([`check_consistency`]).
pub fn check_decomposition(name: &str, bsdf: &Bsdf) {
    let flags = bsdf.flags();
    let diffuse = bsdf.diffuse_part().map(Bsdf::Diffuse);
    let non_diffuse = bsdf.non_diffuse_part();
    let kinds = BsdfFlags::DIFFUSE | BsdfFlags::GLOSSY | BsdfFlags::SPECULAR;
    assert_eq!(
        diffuse.is_some(),
        flags.contains(BsdfFlags::DIFFUSE),
        "{name}: diffuse part {diffuse:?} but flags {flags:?}"
    );
    assert_eq!(
        non_diffuse.is_some(),
        flags.intersects(BsdfFlags::GLOSSY | BsdfFlags::SPECULAR),
        "{name}: non-diffuse part {non_diffuse:?} but flags {flags:?}"
    );
    let mut part_kinds = BsdfFlags::NONE;
    if let Some(d) = &diffuse {
        assert_eq!(
            d.flags(),
            BsdfFlags::DIFFUSE | BsdfFlags::REFLECTION,
            "{name}: diffuse part"
        );
        part_kinds |= BsdfFlags::DIFFUSE;
    }
    if let Some(nd) = &non_diffuse {
        let f = nd.flags();
        assert!(
            !f.contains(BsdfFlags::DIFFUSE) && f.intersects(kinds),
            "{name}: non-diffuse part has flags {f:?}"
        );
        for k in [BsdfFlags::GLOSSY, BsdfFlags::SPECULAR] {
            if f.contains(k) {
                part_kinds |= k;
            }
        }
        if !nd.is_delta() {
            check_consistency(&format!("{name} (non-diffuse part)"), nd);
        }
    }
    for k in [BsdfFlags::DIFFUSE, BsdfFlags::GLOSSY, BsdfFlags::SPECULAR] {
        assert_eq!(
            flags.contains(k),
            part_kinds.contains(k),
            "{name}: the parts' kinds {part_kinds:?} are not the whole's {flags:?}"
        );
    }
    let eval_part = |part: &Option<Bsdf>, wo: Vec3, wi: Vec3| {
        part.as_ref()
            .map_or(Vec3::ZERO, |b| b.eval(wo, wi, RADIANCE))
    };
    let sample_part = |part: &Option<Bsdf>, wo: Vec3, rng: &mut Rng, mode: TransportMode| {
        let (u_lobe, u) = (rng.uniform(), rng.uniform2());
        part.as_ref().and_then(|b| b.sample(wo, u_lobe, u, mode))
    };

    let mut rng = Rng::new(seed(name), 5, 5);
    for (k, wo) in incident_directions().into_iter().enumerate() {
        let mut albedo = [[Stats::default(); 3]; 3];
        for _ in 0..50_000 {
            for mode in [RADIANCE, IMPORTANCE] {
                let (u_lobe, u) = (rng.uniform(), rng.uniform2());
                if let Some(s) = bsdf.sample(wo, u_lobe, u, mode) {
                    let side = if s.wi.z * wo.z > 0.0 {
                        BsdfFlags::REFLECTION
                    } else {
                        BsdfFlags::TRANSMISSION
                    };
                    assert!(
                        flags.contains(lobe_flag(s.lobe) | side),
                        "{name}: wo {wo}: sampled {:?} {side:?} but flags {flags:?}",
                        s.lobe
                    );
                    let wi = s.wi;
                    let sum = eval_part(&diffuse, wo, wi) + eval_part(&non_diffuse, wo, wi);
                    let whole = bsdf.eval(wo, wi, RADIANCE);
                    assert!(
                        close3(whole, sum, 1e-5),
                        "{name}: wo {wo} wi {wi}: eval {whole} != parts' sum {sum}"
                    );
                }
                if let Some(s) = sample_part(&diffuse, wo, &mut rng, mode) {
                    assert_eq!(s.lobe, Lobe::Diffuse, "{name}: diffuse part");
                }
                if let Some(s) = sample_part(&non_diffuse, wo, &mut rng, mode) {
                    assert_ne!(s.lobe, Lobe::Diffuse, "{name}: non-diffuse part");
                    assert!(
                        non_diffuse.unwrap().flags().contains(lobe_flag(s.lobe)),
                        "{name}: non-diffuse part sampled {:?}",
                        s.lobe
                    );
                }
            }
            let wi = uniform_sphere(rng.uniform2());
            let sum = eval_part(&diffuse, wo, wi) + eval_part(&non_diffuse, wo, wi);
            let whole = bsdf.eval(wo, wi, RADIANCE);
            assert!(
                close3(whole, sum, 1e-5),
                "{name}: wo {wo} wi {wi}: eval {whole} != parts' sum {sum}"
            );
            let whole = {
                let (u_lobe, u) = (rng.uniform(), rng.uniform2());
                bsdf.sample(wo, u_lobe, u, RADIANCE)
            };
            let weights = [
                whole,
                sample_part(&diffuse, wo, &mut rng, RADIANCE),
                sample_part(&non_diffuse, wo, &mut rng, RADIANCE),
            ]
            .map(|s| s.map_or(Vec3::ZERO, |s| s.weight));
            for (stats, w) in albedo.iter_mut().zip(weights) {
                for c in 0..3 {
                    stats[c].push(w[c] as f64);
                }
            }
        }
        for c in 0..3 {
            let [whole, d, nd] = albedo.map(|stats| stats[c]);
            let se =
                (whole.std_error().powi(2) + d.std_error().powi(2) + nd.std_error().powi(2)).sqrt();
            assert!(
                (whole.mean() - d.mean() - nd.mean()).abs() <= 5.0 * se + 1e-6,
                "{name}: wo {wo} ({k}), channel {c}: albedo {:.5} but parts {:.5} + {:.5} \
                 (+-{se:.1e})",
                whole.mean(),
                d.mean(),
                nd.mean()
            );
        }
    }
}
