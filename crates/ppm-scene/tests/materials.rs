//! The Mitsuba-style materials of scene format v1: each type with Mitsuba's parameter names and
//! defaults maps to the ppm-core BSDF with those values, and bad parameters are errors naming
//! the field.

mod common;

use common::VALID;
use glam::Vec3;
use ppm_core::bsdf::metals::metal;
use ppm_core::bsdf::{Beckmann, Bsdf, Ggx};
use ppm_scene::{content_hash, parse_scene};
use std::path::Path;

/// VALID with the floor's material replaced by `material` (a YAML flow map).
fn scene_with(material: &str) -> String {
    let from = "white: { type: diffuse, color: [0.7, 0.7, 0.7] }";
    assert!(VALID.contains(from));
    VALID.replacen(from, &format!("white: {material}"), 1)
}

/// The floor's BSDF.
fn bsdf(material: &str) -> Bsdf {
    let (b, warnings) = parse_scene(&scene_with(material), Path::new("dir/m.yml"))
        .unwrap_or_else(|e| panic!("{material}: {e}"));
    assert!(warnings.is_empty(), "{warnings:?}");
    b.materials[0].bsdf
}

/// The error message for the floor's material.
fn error(material: &str) -> String {
    match parse_scene(&scene_with(material), Path::new("dir/m.yml")) {
        Ok(_) => panic!("no error for {material}"),
        Err(e) => e.to_string(),
    }
}

fn has(message: &str, needles: &[&str]) {
    for n in needles {
        assert!(message.contains(n), "`{n}` missing from: {message}");
    }
}

const AIR: f32 = 1.000277;

#[test]
fn conductors_take_a_named_metal_or_eta_and_k() {
    let au = metal("Au").unwrap();
    match bsdf("{ type: conductor, material: Au }") {
        Bsdf::Conductor(c) => {
            assert_eq!((c.eta, c.k, c.roughness), (au.eta, au.k, None));
            assert_eq!(c.specular_reflectance, Vec3::ONE);
        }
        b => panic!("{b:?}"),
    }
    // Mitsuba's default is `none`: a perfect mirror, eta 0 and k 1.
    match bsdf("{ type: conductor }") {
        Bsdf::Conductor(c) => assert_eq!((c.eta, c.k), (Vec3::ZERO, Vec3::ONE)),
        b => panic!("{b:?}"),
    }
    match bsdf(
        "{ type: roughconductor, eta: [0.2, 0.9, 1.1], k: [3.9, 2.4, 2.2], alpha_u: 0.05, \
         alpha_v: 0.3, specular_reflectance: [0.9, 0.8, 0.7], distribution: ggx }",
    ) {
        Bsdf::Conductor(c) => {
            assert_eq!(c.eta, Vec3::new(0.2, 0.9, 1.1));
            assert_eq!(c.roughness, Some(Ggx::new(0.05, 0.3).into()));
            assert_eq!(c.specular_reflectance, Vec3::new(0.9, 0.8, 0.7));
        }
        b => panic!("{b:?}"),
    }
    // Mitsuba's default roughness; ppm's default distribution, GGX.
    match bsdf("{ type: roughconductor, material: Cu }") {
        Bsdf::Conductor(c) => assert_eq!(c.roughness, Some(Ggx::isotropic(0.1).into())),
        b => panic!("{b:?}"),
    }
    match bsdf("{ type: roughconductor, material: Cu, alpha_u: 0.1, alpha_v: 0.2, distribution: beckmann }") {
        Bsdf::Conductor(c) => assert_eq!(c.roughness, Some(Beckmann::new(0.1, 0.2).into())),
        b => panic!("{b:?}"),
    }
}

#[test]
fn dielectrics_take_two_indices_by_number_or_name() {
    match bsdf("{ type: dielectric }") {
        Bsdf::Dielectric(d) => {
            assert_eq!(d.eta, 1.5046 / AIR);
            assert_eq!(d.roughness, None);
        }
        b => panic!("{b:?}"),
    }
    // Water in glass: one surface, relative index below 1.
    match bsdf("{ type: roughdielectric, int_ior: water, ext_ior: 1.5, alpha: 0.2 }") {
        Bsdf::Dielectric(d) => {
            assert_eq!(d.eta, 1.333 / 1.5);
            assert_eq!(d.roughness, Some(Ggx::isotropic(0.2).into()));
        }
        b => panic!("{b:?}"),
    }
    match bsdf("{ type: thindielectric, int_ior: 1.5, ext_ior: 1, specular_transmittance: [0.9, 0.9, 0.8] }") {
        Bsdf::ThinDielectric(t) => {
            assert_eq!(t.eta, 1.5);
            assert_eq!(t.specular_transmittance, Vec3::new(0.9, 0.9, 0.8));
        }
        b => panic!("{b:?}"),
    }
}

#[test]
fn plastics_and_two_sided() {
    match bsdf("{ type: plastic }") {
        Bsdf::Plastic(p) => {
            assert_eq!(p.diffuse_reflectance, Vec3::splat(0.5));
            assert_eq!(p.eta, 1.49 / AIR);
            assert_eq!(p.roughness, None);
        }
        b => panic!("{b:?}"),
    }
    match bsdf("{ type: roughplastic, diffuse_reflectance: [0.2, 0.5, 0.8], alpha: 0.3 }") {
        Bsdf::Plastic(p) => assert_eq!(p.roughness, Some(Ggx::isotropic(0.3).into())),
        b => panic!("{b:?}"),
    }
    match bsdf("{ type: roughplastic, alpha: 0.3, distribution: Beckmann }") {
        Bsdf::Plastic(p) => assert_eq!(p.roughness, Some(Beckmann::isotropic(0.3).into())),
        b => panic!("{b:?}"),
    }
    match bsdf("{ type: twosided, bsdf: { type: roughconductor, material: Al } }") {
        Bsdf::TwoSidedConductor(t) => assert_eq!(t.0.eta, metal("Al").unwrap().eta),
        b => panic!("{b:?}"),
    }
    match bsdf("{ type: twosided, bsdf: { type: plastic }, emission: [1, 1, 1] }") {
        Bsdf::TwoSidedPlastic(_) => {}
        b => panic!("{b:?}"),
    }
    // Already two-sided: unchanged.
    match bsdf("{ type: twosided, bsdf: { type: diffuse, color: [0.5, 0.5, 0.5] } }") {
        Bsdf::Diffuse(d) => assert_eq!(d.albedo, Vec3::splat(0.5)),
        b => panic!("{b:?}"),
    }
}

#[test]
fn bad_parameters_name_the_field() {
    has(
        &error("{ type: conductor, material: Unobtainium }"),
        &[
            "materials.white.material",
            "unknown conductor `Unobtainium`",
            "Au",
            "Ag",
        ],
    );
    has(
        &error("{ type: conductor, material: Au, eta: [1, 1, 1] }"),
        &["materials.white", "either `material` or `eta` and `k`"],
    );
    has(
        &error("{ type: conductor, alpha: 0.1 }"),
        &[
            "materials.white",
            "`alpha` does not apply to a conductor material",
        ],
    );
    has(
        &error("{ type: roughconductor, distribution: phong }"),
        &[
            "materials.white.distribution",
            "`phong` is not a microfacet distribution",
            "`ggx` or `beckmann`",
        ],
    );
    has(
        &error("{ type: roughconductor, alpha_u: 0.1 }"),
        &["materials.white", "needs both `alpha_u` and `alpha_v`"],
    );
    has(
        &error("{ type: roughconductor, alpha: 0.1, alpha_u: 0.1, alpha_v: 0.2 }"),
        &["materials.white", "either `alpha` or `alpha_u`"],
    );
    has(
        &error("{ type: roughplastic, alpha_u: 0.1, alpha_v: 0.2 }"),
        &["`alpha_u` does not apply to a roughplastic material"],
    );
    has(
        &error("{ type: dielectric, int_ior: 1.5, ext_ior: 1.5 }"),
        &["materials.white", "int_ior and ext_ior are both 1.5"],
    );
    has(
        &error("{ type: dielectric, int_ior: unobtanium }"),
        &[
            "dir/m.yml:4:",
            "materials.white.int_ior",
            "unknown medium `unobtanium`",
            "water",
        ],
    );
    has(
        &error("{ type: dielectric, int_ior: 0.5 }"),
        &[
            "materials.white.int_ior",
            "expected an index of refraction >= 1",
        ],
    );
    has(
        &error("{ type: plastic, diffuse_reflectance: [1.5, 0, 0] }"),
        &[
            "materials.white.diffuse_reflectance",
            "expected a reflectance in [0, 1]",
        ],
    );
    has(
        &error("{ type: twosided, bsdf: { type: dielectric } }"),
        &["materials.white.bsdf", "refracts"],
    );
    has(
        &error("{ type: plastic, int_ior: 4, ext_ior: 1 }"),
        &["materials.white", "relative index in (1, 3]"],
    );
    has(
        &error("{ type: twosided }"),
        &["materials.white", "twosided material needs `bsdf`"],
    );
    has(
        &error("{ type: twosided, bsdf: { type: plastic, emission: [1, 1, 1] } }"),
        &[
            "materials.white.bsdf",
            "`emission` belongs to the twosided material",
        ],
    );
    has(
        &error("{ type: twosided, bsdf: { type: conductor, alpha: 0.2 } }"),
        &[
            "materials.white.bsdf",
            "`alpha` does not apply to a conductor",
        ],
    );
    has(
        &error("{ type: diffuse, color: [0.5, 0.5, 0.5], int_ior: 1.5 }"),
        &["`int_ior` does not apply to a diffuse material"],
    );
}

/// The scene fingerprint (what `--resume` and `ppm merge` check) tells the new materials and
/// their parameters apart.
#[test]
fn the_fingerprint_sees_every_parameter() {
    let hash = |m: &str| {
        let (b, _) = parse_scene(&scene_with(m), Path::new("dir/m.yml")).unwrap();
        content_hash(&b)
    };
    let materials = [
        "{ type: conductor, material: Au }",
        "{ type: conductor, material: Cu }",
        "{ type: roughconductor, material: Au, alpha: 0.2 }",
        "{ type: roughconductor, material: Au, alpha: 0.3 }",
        "{ type: roughconductor, material: Au, alpha_u: 0.2, alpha_v: 0.3 }",
        "{ type: roughconductor, material: Au, alpha: 0.2, distribution: beckmann }",
        "{ type: roughdielectric, distribution: beckmann }",
        "{ type: roughplastic, distribution: beckmann }",
        "{ type: twosided, bsdf: { type: roughconductor, material: Au, alpha: 0.2 } }",
        "{ type: dielectric }",
        "{ type: dielectric, specular_transmittance: [0.9, 0.9, 0.9] }",
        "{ type: roughdielectric }",
        "{ type: thindielectric }",
        "{ type: plastic }",
        "{ type: plastic, diffuse_reflectance: [0.4, 0.5, 0.5] }",
        "{ type: roughplastic }",
        "{ type: twosided, bsdf: { type: plastic } }",
    ];
    let hashes: Vec<u64> = materials.iter().map(|m| hash(m)).collect();
    // `ggx` is the default and is not written: scenes that name it hash as they did before.
    assert_eq!(
        hash("{ type: roughconductor, material: Au, alpha: 0.2, distribution: ggx }"),
        hashes[2]
    );
    for i in 0..hashes.len() {
        for j in 0..i {
            assert_ne!(
                hashes[i], hashes[j],
                "{} and {}",
                materials[i], materials[j]
            );
        }
    }
}
