//! Textured roughness: a checkerboard of two alphas on a rough conductor (one- and two-sided)
//! and a rough dielectric resolves, at a uv in each square, to exactly the BSDF of that
//! constant alpha (values and pdfs over many direction pairs), keeps its distribution (GGX or
//! Beckmann), and is refused by models without a microfacet roughness.

use glam::{Vec2, Vec3};
use ppm_core::bsdf::{Beckmann, Bsdf, Ggx, Microfacet, TransportMode};
use ppm_core::material::Material;
use ppm_core::sampling::Rng;
use ppm_core::texture::{Checkerboard, ColourSlot, Texture, UvTransform};

const GOLD_ETA: Vec3 = Vec3::new(0.143, 0.374, 1.442);
const GOLD_K: Vec3 = Vec3::new(3.983, 2.385, 1.603);

/// Alpha 0.05 on the squares of color0 (uv near (0.25, 0.25)), 0.5 on color1's.
fn checker() -> Texture {
    Texture::Checkerboard(Checkerboard {
        color0: Vec3::splat(0.05),
        color1: Vec3::splat(0.5),
        transform: UvTransform::IDENTITY,
    })
}

/// A direction on the sphere from two uniforms.
fn sphere(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * std::f32::consts::PI * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// `textured` at `uv` against `constant`: the same f and pdf, bit for bit, at 2000 pairs.
fn same_bsdf(textured: &Material, uv: Vec2, constant: &Bsdf, what: &str) {
    let at = textured.bsdf_at(uv);
    let mut rng = Rng::new(7, 0, 0);
    for _ in 0..2000 {
        let wo = sphere(rng.uniform2());
        let wi = sphere(rng.uniform2());
        for mode in [TransportMode::Radiance, TransportMode::Importance] {
            assert_eq!(at.eval(wo, wi, mode), constant.eval(wo, wi, mode), "{what}");
        }
        assert_eq!(at.pdf(wo, wi), constant.pdf(wo, wi), "{what}");
    }
}

fn textured(bsdf: Bsdf) -> Material {
    Material::new(bsdf, Vec3::ZERO)
        .textured(vec![(ColourSlot::Roughness, checker())])
        .unwrap()
}

#[test]
fn checkerboard_roughness_is_the_constant_roughness_per_square() {
    let ggx = |a: f32| -> Option<Microfacet> { Some(Ggx::new(a, a).into()) };
    let beckmann = |a: f32| -> Option<Microfacet> { Some(Beckmann::new(a, a).into()) };
    let (square0, square1) = (Vec2::new(0.25, 0.25), Vec2::new(0.75, 0.25));
    for dist in [ggx, beckmann] {
        let conductor = |a| Bsdf::conductor(GOLD_ETA, GOLD_K, Vec3::ONE, dist(a));
        let dielectric = |a| Bsdf::dielectric(1.5, dist(a));
        let two_sided = |a| {
            Bsdf::conductor(GOLD_ETA, GOLD_K, Vec3::ONE, dist(a))
                .two_sided()
                .unwrap()
        };
        let models: [(&str, &dyn Fn(f32) -> Bsdf); 3] = [
            ("conductor", &conductor),
            ("dielectric", &dielectric),
            ("two-sided conductor", &two_sided),
        ];
        for (name, model) in models {
            // The nominal alpha (0.2) is replaced wherever the texture is read.
            let m = textured(model(0.2));
            same_bsdf(&m, square0, &model(0.05), &format!("{name} at alpha 0.05"));
            same_bsdf(&m, square1, &model(0.5), &format!("{name} at alpha 0.5"));
            // The two squares do differ: the test could tell them apart.
            let (wo, wi) = (Vec3::new(0.3, 0.0, 0.954), Vec3::new(-0.3, 0.0, 0.954));
            let f0 = m.bsdf_at(square0).eval(wo, wi, TransportMode::Radiance);
            let f1 = m.bsdf_at(square1).eval(wo, wi, TransportMode::Radiance);
            assert!(f0.x > 2.0 * f1.x, "{name}: {f0} vs {f1}");
        }
    }
}

#[test]
fn roughness_texture_needs_a_rough_model() {
    for bsdf in [
        Bsdf::diffuse(Vec3::splat(0.5)),
        Bsdf::conductor(GOLD_ETA, GOLD_K, Vec3::ONE, None),
        Bsdf::dielectric(1.5, None),
    ] {
        let refused = Material::new(bsdf, Vec3::ZERO)
            .textured(vec![(ColourSlot::Roughness, checker())])
            .unwrap_err();
        assert_eq!(refused, ColourSlot::Roughness, "{bsdf:?}");
    }
}
