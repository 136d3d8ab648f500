//! The BSDF test harness.
//!
//! Every non-delta BSDF goes through [`bsdf_harness!`]: one line gives it a chi-square test of
//! `sample` against `pdf`, sample/eval/pdf consistency, reciprocity, energy conservation,
//! finiteness at grazing angles and the lobe decomposition (flags, diffuse part, non-diffuse
//! part), which the delta models also go through. The checks are in `bsdf_checks/mod.rs`, the
//! statistics behind them (common/mod.rs) are tested in `statistics.rs`. The delta models
//! (mirror, glass), the Fresnel term and the shading-normal correction have their own tests in
//! `bsdf_specular.rs`; microfacet models at alpha 0.001 and the lossless dielectrics' flux
//! are in `bsdf_limits.rs`, values against Mitsuba 3 in `bsdf_mitsuba.rs`.
//!
//! All randomness is seeded: every run draws the same numbers.

mod bsdf_checks;
mod common;

use bsdf_checks::*;
use common::{direction, IORS};
use glam::{Vec2, Vec3};
use ppm_core::bsdf::{Beckmann, Bsdf, Ggx, Microfacet};

/// Registers the generic tests for each listed BSDF: `name: constructor,` makes a module
/// `name` with six tests. The chi-square level is corrected for the number of models listed.
macro_rules! bsdf_harness {
    ($($name:ident: $bsdf:expr,)*) => {
        /// Number of chi-square tests in this file (models x incident directions).
        const CHI2_TESTS: usize = [$(stringify!($name)),*].len() * 2 * THETA_O_DEG.len();
        $(
            mod $name {
                use super::*;
                fn bsdf() -> Bsdf {
                    $bsdf
                }
                #[test]
                fn chi2_sample_matches_pdf() {
                    check_chi2(stringify!($name), &bsdf(), CHI2_TESTS);
                }
                #[test]
                fn sample_agrees_with_eval_and_pdf() {
                    check_consistency(stringify!($name), &bsdf());
                }
                #[test]
                fn eval_is_reciprocal() {
                    check_reciprocity(stringify!($name), &bsdf());
                }
                #[test]
                fn albedo_at_most_one() {
                    check_energy(stringify!($name), &bsdf());
                }
                #[test]
                fn finite_at_grazing_angles() {
                    check_grazing(stringify!($name), &bsdf());
                }
                #[test]
                fn decomposition_agrees_with_the_whole() {
                    check_decomposition(stringify!($name), &bsdf());
                }
            }
        )*
    };
}

bsdf_harness! {
    diffuse_grey: Bsdf::diffuse(Vec3::splat(0.8)),
    diffuse_coloured: Bsdf::diffuse(Vec3::new(1.0, 0.5, 0.0)),
    phong_n1: Bsdf::phong(Vec3::new(0.2, 0.4, 0.5), Vec3::new(0.8, 0.6, 0.5), 1.0),
    phong_n10: Bsdf::phong(Vec3::new(0.2, 0.4, 0.5), Vec3::new(0.8, 0.6, 0.5), 10.0),
    phong_n100: Bsdf::phong(Vec3::new(0.2, 0.4, 0.5), Vec3::new(0.8, 0.6, 0.5), 100.0),
    phong_n1000: Bsdf::phong(Vec3::new(0.2, 0.4, 0.5), Vec3::new(0.8, 0.6, 0.5), 1000.0),
    phong_n0: Bsdf::phong(Vec3::splat(0.3), Vec3::splat(0.5), 0.0),
    phong_glossy_only: Bsdf::phong(Vec3::ZERO, Vec3::new(0.9, 0.7, 1.0), 50.0),
    phong_diffuse_only: Bsdf::phong(Vec3::splat(0.7), Vec3::ZERO, 20.0),
    rough_conductor_a0_05: rough_gold(Ggx::isotropic(0.05)),
    rough_conductor_a0_3: rough_gold(Ggx::isotropic(0.3)),
    rough_conductor_a1: rough_gold(Ggx::isotropic(1.0)),
    rough_conductor_anisotropic: rough_gold(Ggx::new(0.05, 0.4)),
    rough_conductor_two_sided: rough_gold(Ggx::isotropic(0.2)).two_sided().unwrap(),
    rough_dielectric_a0_05: Bsdf::dielectric(1.5, Some(Ggx::isotropic(0.05).into())),
    rough_dielectric_a0_3: Bsdf::dielectric(1.5, Some(Ggx::isotropic(0.3).into())),
    rough_dielectric_a1: Bsdf::dielectric(2.4, Some(Ggx::isotropic(1.0).into())),
    rough_dielectric_water_in_glass: Bsdf::dielectric(1.33 / 1.5, Some(Ggx::isotropic(0.2).into())),
    rough_dielectric_anisotropic: Bsdf::dielectric(1.5, Some(Ggx::new(0.4, 0.08).into())),
    rough_plastic_a0_1: Bsdf::plastic(
        Vec3::new(0.2, 0.5, 0.8), Vec3::ONE, 1.49, Some(Ggx::isotropic(0.1).into())
    ),
    rough_plastic_a0_6_tinted: Bsdf::plastic(
        Vec3::splat(0.5), Vec3::new(0.9, 0.7, 0.5), 1.6, Some(Ggx::isotropic(0.6).into())
    ),
    rough_conductor_beckmann_a0_3: rough_gold(Beckmann::isotropic(0.3)),
    rough_conductor_beckmann_anisotropic: rough_gold(Beckmann::new(0.08, 0.5)),
    rough_dielectric_beckmann_a0_2: Bsdf::dielectric(1.5, Some(Beckmann::isotropic(0.2).into())),
    rough_dielectric_beckmann_water_in_glass: Bsdf::dielectric(
        1.33 / 1.5, Some(Beckmann::new(0.5, 0.15).into())
    ),
    rough_plastic_beckmann_a0_3: Bsdf::plastic(
        Vec3::new(0.2, 0.5, 0.8), Vec3::new(0.9, 0.7, 0.5), 1.49, Some(Beckmann::isotropic(0.3).into())
    ),
    smooth_plastic: Bsdf::plastic(Vec3::new(0.2, 0.5, 0.8), Vec3::ONE, 1.49, None),
    smooth_plastic_two_sided: Bsdf::plastic(Vec3::splat(0.6), Vec3::splat(0.8), 1.7, None)
        .two_sided()
        .unwrap(),
}

/// Gold's RGB index (Mitsuba's `Au`), rough.
fn rough_gold(dist: impl Into<Microfacet>) -> Bsdf {
    Bsdf::conductor(
        Vec3::new(0.143036, 0.375307, 1.44205),
        Vec3::new(3.983, 2.38556, 1.60336),
        Vec3::ONE,
        Some(dist.into()),
    )
}

/// The lobe decomposition of the delta models (the rest of their tests are in
/// `bsdf_specular.rs`), and of a black phong, which has no lobe at all.
#[test]
fn delta_models_decompose_into_their_traced_part() {
    check_decomposition("mirror", &Bsdf::mirror(Vec3::new(0.9, 0.8, 0.7)));
    for ior in IORS {
        check_decomposition("glass", &Bsdf::glass(ior, Vec3::new(0.9, 0.8, 0.7)));
    }
    check_decomposition(
        "conductor",
        &Bsdf::conductor(Vec3::splat(0.2), Vec3::splat(3.0), Vec3::ONE, None),
    );
    for eta in [1.5, 1.33 / 1.5] {
        check_decomposition("dielectric", &Bsdf::dielectric(eta, None));
        check_decomposition("thin dielectric", &Bsdf::thin_dielectric(eta));
    }
    let black = Bsdf::phong(Vec3::ZERO, Vec3::ZERO, 10.0);
    assert!(black.flags().is_empty() && !black.is_delta());
    check_decomposition("black phong", &black);
}

/// Grazing angles for the delta models too, and the glass at its critical angle from inside.
#[test]
fn every_bsdf_is_finite_at_grazing_angles() {
    check_grazing("mirror", &Bsdf::mirror(Vec3::new(0.9, 0.8, 0.7)));
    check_grazing(
        "conductor",
        &Bsdf::conductor(Vec3::splat(0.2), Vec3::splat(3.0), Vec3::ONE, None),
    );
    for eta in [1.5, 1.33 / 1.5] {
        check_grazing("dielectric", &Bsdf::dielectric(eta, None));
        check_grazing("thin dielectric", &Bsdf::thin_dielectric(eta));
    }
    for ior in IORS {
        let glass = Bsdf::glass(ior, Vec3::new(0.9, 0.8, 0.7));
        check_grazing("glass", &glass);
        let cos_c = (1.0 - 1.0 / (ior * ior)).sqrt();
        for cos in [
            cos_c,
            cos_c * (1.0 + 1e-6),
            cos_c * (1.0 - 1e-6),
            cos_c + 1e-7,
            cos_c - 1e-7,
        ] {
            let wo = direction(-cos, 0.3);
            for (mode, u_lobe) in [
                (RADIANCE, 0.0),
                (RADIANCE, 0.99999994),
                (IMPORTANCE, 0.99999994),
            ] {
                let s = glass
                    .sample(wo, u_lobe, Vec2::ZERO, mode)
                    .expect("glass always scatters");
                assert!(
                    s.wi.is_finite() && s.weight.is_finite() && s.pdf.is_finite() && s.pdf > 0.0,
                    "{s:?}"
                );
            }
        }
    }
}
