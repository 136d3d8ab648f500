//! The statistics behind the BSDF and light harnesses (common/mod.rs) are themselves right:
//! the chi-square survival function against reference values, Gauss-Legendre quadrature
//! against exact integrals, and the chi-square test of a sampler, which must accept the right
//! pdf and reject wrong ones.

mod common;

use common::{chi2_directions, chi2_sf, gauss_legendre, seed};
use glam::Vec3;
use ppm_core::sampling::{cosine_hemisphere, Rng};
use std::f32::consts::PI;

#[test]
fn chi2_survival_function_matches_reference_values() {
    // Reference: mpmath.gammainc(k / 2, x / 2, regularized=True) at 30 digits, rounded to f64.
    let cases = [
        (1000.0, 1000, 0.494_052_853_829_239_6),
        (4000.0, 3800, 0.011_826_617_436_760_39),
        (23.209251158954356, 10, 0.010_000_000_000_000_013),
        (1.0, 3, 0.801_251_956_901_200_8),
        (0.5, 7, 0.999_446_481_390_425),
    ];
    for (x, dof, p) in cases {
        let q = chi2_sf(x, dof);
        assert!(
            (q - p).abs() < 1e-10 * p.max(1e-3),
            "chi2_sf({x}, {dof}) = {q} != {p}"
        );
    }
    for x in [0.1, 1.0, 10.0, 50.0] {
        assert!(
            (chi2_sf(x, 2) - (-x / 2.0f64).exp()).abs() < 1e-12,
            "2 dof at {x}"
        );
    }
}

#[test]
fn gauss_legendre_is_exact_to_degree_2n_minus_1() {
    let rule = gauss_legendre(6);
    for degree in 0..12 {
        let integral: f64 = rule.iter().map(|&(x, w)| w * x.powi(degree)).sum();
        let exact = if degree % 2 == 1 {
            0.0
        } else {
            2.0 / (degree + 1) as f64
        };
        assert!(
            (integral - exact).abs() < 1e-13,
            "x^{degree}: {integral} != {exact}"
        );
    }
}

/// The chi-square test itself can fail: a cosine sampler passes against its own pdf and is
/// rejected against the uniform pdf, against 99% of its pdf, and against 101% of it.
#[test]
fn chi2_test_accepts_the_right_pdf_and_rejects_wrong_ones() {
    let run = |pdf: &dyn Fn(Vec3) -> f64| {
        let mut rng = Rng::new(seed("chi2_self_test"), 0, 0);
        chi2_directions(
            200_000,
            &mut rng,
            |r| Some(cosine_hemisphere(r.uniform2())),
            pdf,
        )
    };
    let cosine = |w: Vec3| (w.z.max(0.0) / PI) as f64;
    assert!(run(&cosine).unwrap().p_value > 0.01);
    assert!(
        run(&|w: Vec3| if w.z > 0.0 {
            0.5 / std::f64::consts::PI
        } else {
            0.0
        })
        .unwrap()
        .p_value
            < 1e-10
    );
    assert!(run(&|w: Vec3| 0.99 * cosine(w)).unwrap().p_value < 1e-10);
    assert!(run(&|w: Vec3| 1.01 * cosine(w)).is_err());
}
