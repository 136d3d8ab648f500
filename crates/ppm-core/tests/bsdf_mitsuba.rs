//! ppm's microfacet and coated BSDFs against Mitsuba 3, the oracle.
//!
//! `tests/data/mitsuba_bsdf_values.csv` holds values Mitsuba 3.9.1 (`scalar_rgb`) computed for
//! a fixed table of directions and parameters (`scripts/mitsuba/bsdf_values.py`, which also
//! explains the columns). CI never runs Mitsuba: it only reads that file. Directions are in
//! ppm's convention (`wo` toward the viewer, Mitsuba's `si.wi`). Mitsuba's `eval` includes
//! |cos(wi)|, ppm's does not: ppm's f is multiplied by it here.

mod common;

use common::{seed, Stats};
use glam::{Vec2, Vec3};
use ppm_core::bsdf::metals::metal;
use ppm_core::bsdf::{Beckmann, Bsdf, Ggx, Lobe, Microfacet, TransportMode};
use ppm_core::sampling::Rng;

/// Relative tolerance of f |cos| and of the pdf against Mitsuba's, over an absolute floor of
/// this times the larger of 1 and the value's scale. Both evaluate the same formulas in f32;
/// what differs is rounding (a few ulps, amplified near the peak of a narrow lobe where D
/// varies fast with the half vector) and, for rough plastic, the quadrature of the coating's
/// transmittance table (Gauss-Legendre over two different parametrisations of the visible
/// normals), which agrees to about 1e-4.
const VALUE_TOLERANCE: f32 = 2e-3;

/// Relative tolerance of the rough plastic's pdf. Its coating is sampled with a probability
/// that depends on the coating's transmittance table, which Mitsuba integrates with 32 x 32
/// Gauss-Legendre points over its parametrisation of the visible normals: at alpha 0.1 its
/// table is 3e-4 off the converged integral (ppm's, with 64 x 64 points, 2e-5), and the
/// probability, proportional to 1 - T, moves by up to 1%.
const ROUGH_PLASTIC_PDF_TOLERANCE: f32 = 1e-2;

/// Relative tolerance of the Beckmann cases' f |cos|: ppm's Smith G1 is exact (erf), Mitsuba's
/// Walter's rational approximation of it, within 0.35 %; f holds two of them (measured: 0.6 %
/// at most, at grazing angles).
const BECKMANN_VALUE_TOLERANCE: f32 = 8e-3;

/// Mitsuba's default exterior index (`air`).
const AIR: f32 = 1.000277;

/// The ppm BSDF of each case of the script, with the same parameters.
fn case(name: &str) -> Bsdf {
    let gold = metal("Au").unwrap();
    let copper = metal("Cu").unwrap();
    let aluminium = metal("Al").unwrap();
    let iso = |a: f32| Some(Microfacet::from(Ggx::isotropic(a)));
    let beckmann = |a: f32| Some(Microfacet::from(Beckmann::isotropic(a)));
    match name {
        "rc_au_010" => Bsdf::conductor(gold.eta, gold.k, Vec3::ONE, iso(0.1)),
        "rc_cu_030" => Bsdf::conductor(copper.eta, copper.k, Vec3::ONE, iso(0.3)),
        "rc_al_100" => Bsdf::conductor(aluminium.eta, aluminium.k, Vec3::ONE, iso(1.0)),
        "rc_aniso" => Bsdf::conductor(
            Vec3::new(0.2, 0.9, 1.1),
            Vec3::new(3.9, 2.4, 2.2),
            Vec3::new(0.9, 0.8, 0.7),
            Some(Ggx::new(0.05, 0.3).into()),
        ),
        "rd_010" => Bsdf::dielectric(1.5, iso(0.1)),
        "rd_050" => Bsdf::dielectric(1.5046 / AIR, iso(0.5)),
        "rd_water_glass" => Bsdf::dielectric(1.33 / 1.5, iso(0.2)),
        "rd_aniso" => Bsdf::dielectric(1.5, Some(Ggx::new(0.1, 0.4).into())),
        "rp_010" => Bsdf::plastic(Vec3::new(0.2, 0.5, 0.8), Vec3::ONE, 1.49 / AIR, iso(0.1)),
        "rp_040" => Bsdf::plastic(
            Vec3::splat(0.5),
            Vec3::new(0.9, 0.7, 0.5),
            1.6 / AIR,
            iso(0.4),
        ),
        "pl" => Bsdf::plastic(Vec3::new(0.2, 0.5, 0.8), Vec3::ONE, 1.49 / AIR, None),
        "pl_tinted" => Bsdf::plastic(
            Vec3::new(0.6, 0.3, 0.1),
            Vec3::new(0.5, 0.6, 0.7),
            1.7 / AIR,
            None,
        ),
        "tw_rc_cu_030" => Bsdf::conductor(copper.eta, copper.k, Vec3::ONE, iso(0.3))
            .two_sided()
            .unwrap(),
        "c_au" => Bsdf::conductor(gold.eta, gold.k, Vec3::ONE, None),
        "c_none" => {
            let none = metal("none").unwrap();
            Bsdf::conductor(none.eta, none.k, Vec3::ONE, None)
        }
        "d_15" => Bsdf::dielectric(1.5, None),
        "d_water_glass" => Bsdf::dielectric(1.33 / 1.5, None),
        "td_15" => Bsdf::thin_dielectric(1.5),
        "rcb_au_010" => Bsdf::conductor(gold.eta, gold.k, Vec3::ONE, beckmann(0.1)),
        "rcb_aniso" => Bsdf::conductor(
            Vec3::new(0.2, 0.9, 1.1),
            Vec3::new(3.9, 2.4, 2.2),
            Vec3::ONE,
            Some(Beckmann::new(0.05, 0.3).into()),
        ),
        "rdb_030" => Bsdf::dielectric(1.5, beckmann(0.3)),
        "rpb_020" => Bsdf::plastic(
            Vec3::new(0.2, 0.5, 0.8),
            Vec3::ONE,
            1.49 / AIR,
            beckmann(0.2),
        ),
        _ => panic!("unknown case {name}"),
    }
}

/// One row of the CSV.
struct Row {
    kind: String,
    case: String,
    mode: TransportMode,
    wo: Vec3,
    wi: Vec3,
    value: Vec3,
    pdf: f32,
    u: (f32, Vec2),
    se: Vec3,
}

fn rows() -> Vec<Row> {
    let text = include_str!("data/mitsuba_bsdf_values.csv");
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header = lines.next().unwrap();
    assert!(header.starts_with("kind,case,mode,"), "{header}");
    lines
        .map(|line| {
            let f: Vec<&str> = line.split(',').collect();
            assert_eq!(f.len(), 19, "{line}");
            let x: Vec<f32> = f[3..].iter().map(|s| s.parse().unwrap()).collect();
            let v3 = |i: usize| Vec3::new(x[i], x[i + 1], x[i + 2]);
            Row {
                kind: f[0].to_string(),
                case: f[1].to_string(),
                mode: match f[2] {
                    "radiance" => TransportMode::Radiance,
                    "importance" => TransportMode::Importance,
                    m => panic!("mode {m}"),
                },
                wo: v3(0).normalize(),
                wi: v3(3).normalize(),
                value: v3(6),
                pdf: x[9],
                u: (x[10], Vec2::new(x[11], x[12])),
                se: v3(13),
            }
        })
        .collect()
}

fn agree(ours: f32, theirs: f32, scale: f32) -> bool {
    (ours - theirs).abs() <= VALUE_TOLERANCE * (theirs.abs().max(scale))
}

/// eval (times |cos(wi)|) and pdf at every tabulated pair, in the tabulated transport mode.
#[test]
fn eval_and_pdf_agree_with_mitsuba() {
    let mut failures = Vec::new();
    let mut compared = 0;
    for r in rows().iter().filter(|r| r.kind == "eval") {
        let bsdf = case(&r.case);
        let f = bsdf.eval(r.wo, r.wi, r.mode) * r.wi.z.abs();
        let pdf = bsdf.pdf(r.wo, r.wi);
        // The scale below which a difference counts as absolute: values of order one.
        let pdf_ok = if r.case.starts_with("rp") {
            (pdf - r.pdf).abs() <= ROUGH_PLASTIC_PDF_TOLERANCE * r.pdf.max(1.0)
        } else if r.case == "rdb_030" {
            // Mitsuba samples visible Beckmann normals here, ppm D(m) cos(m): other pdfs.
            true
        } else {
            agree(pdf, r.pdf, 1.0)
        };
        let f_ok = |c: usize| {
            if r.case.starts_with("rcb") || r.case.starts_with("rdb") || r.case.starts_with("rpb") {
                (f[c] - r.value[c]).abs() <= BECKMANN_VALUE_TOLERANCE * r.value[c].abs().max(1.0)
            } else {
                agree(f[c], r.value[c], 1.0)
            }
        };
        let ok = (0..3).all(f_ok) && pdf_ok;
        if !ok {
            failures.push(format!(
                "{} {:?} wo {} wi {}: f|cos| {} vs Mitsuba {}, pdf {} vs {}",
                r.case, r.mode, r.wo, r.wi, f, r.value, pdf, r.pdf
            ));
        }
        compared += 1;
    }
    assert!(compared > 1000, "only {compared} rows");
    assert!(
        failures.is_empty(),
        "{} of {compared} disagree:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// The delta models' samples: the same direction, weight and lobe probability.
#[test]
fn delta_samples_agree_with_mitsuba() {
    let mut compared = 0;
    for r in rows().iter().filter(|r| r.kind == "sample") {
        let bsdf = case(&r.case);
        let s = bsdf
            .sample(r.wo, r.u.0, r.u.1, r.mode)
            .unwrap_or_else(|| panic!("{}: wo {}: no sample but Mitsuba has one", r.case, r.wo));
        assert_eq!(s.lobe, Lobe::Specular, "{}", r.case);
        assert!(
            (s.wi - r.wi).length() < 1e-5,
            "{}: wo {}: wi {} vs Mitsuba {}",
            r.case,
            r.wo,
            s.wi,
            r.wi
        );
        for c in 0..3 {
            assert!(
                (s.weight[c] - r.value[c]).abs() <= 1e-5 * r.value[c].max(1.0),
                "{} {:?}: wo {}: weight {} vs Mitsuba {}",
                r.case,
                r.mode,
                r.wo,
                s.weight,
                r.value
            );
        }
        assert!(
            (s.pdf - r.pdf).abs() <= 1e-5,
            "{}: wo {}: lobe probability {} vs Mitsuba {}",
            r.case,
            r.wo,
            s.pdf,
            r.pdf
        );
        compared += 1;
    }
    assert!(compared > 50, "only {compared} rows");
}

/// The directional albedo by ppm's sampling against Mitsuba's (each its own estimator with
/// its own noise): within 5 combined standard errors, plus 1e-3 for the rough plastic's
/// transmittance table.
#[test]
fn albedo_agrees_with_mitsuba() {
    const N: usize = 200_000;
    for (k, r) in rows().iter().filter(|r| r.kind == "albedo").enumerate() {
        let bsdf = case(&r.case);
        let mut rng = Rng::new(seed(&r.case), 7, k as u64);
        let mut stats = [Stats::default(); 3];
        for _ in 0..N {
            let (u_lobe, u) = (rng.uniform(), rng.uniform2());
            let w = bsdf
                .sample(r.wo, u_lobe, u, r.mode)
                .map_or(Vec3::ZERO, |s| s.weight);
            for c in 0..3 {
                stats[c].push(w[c] as f64);
            }
        }
        for (c, stats) in stats.iter().enumerate() {
            let ours = stats.mean();
            let se = (stats.std_error().powi(2) + (r.se[c] as f64).powi(2)).sqrt();
            let theirs = r.value[c] as f64;
            assert!(
                (ours - theirs).abs() <= 5.0 * se + 1e-3,
                "{} wo {} channel {c}: albedo {ours:.5} vs Mitsuba {theirs:.5} (+-{se:.1e})",
                r.case,
                r.wo
            );
        }
    }
}

/// The named conductors are Mitsuba's: at least the ten the documentation names most.
#[test]
fn named_metals_include_the_common_ones() {
    for name in [
        "Au", "Ag", "Al", "Cu", "Cr", "Ni_palik", "W", "Hg", "Rh", "TiN", "none",
    ] {
        let m = metal(name).unwrap_or_else(|| panic!("no metal {name}"));
        assert!(m.eta.is_finite() && m.k.is_finite() && m.k.min_element() >= 0.0);
    }
    assert!(metal("Unobtainium").is_none());
}
