//! The Mitsuba importer's BSDF and emitter plugins map to ppm's models with Mitsuba 3's
//! parameters and defaults (checked against what Mitsuba 3.9.1 prints for the same plugin),
//! and what ppm cannot honour is an error naming the plugin, the property and the line, or a
//! warning saying what is approximated. Renders against Mitsuba are in `mitsuba_renders.rs`.

use glam::Vec3;
use ppm_core::bsdf::metals::metal;
use ppm_core::bsdf::{Beckmann, Bsdf, Ggx};
use ppm_core::light::Light;
use ppm_core::scene::SceneBuilder;
use ppm_scene::mitsuba::parse_mitsuba;
use ppm_scene::LoadError;
use std::path::Path;

/// A scene of a camera, a point light and `body`.
fn load(body: &str) -> Result<(SceneBuilder, Vec<String>), LoadError> {
    let xml = format!(
        r#"<scene version="3.0.0">
<sensor type="perspective">
<film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film></sensor>
<emitter type="point"><point name="position" x="0" y="3" z="3"/></emitter>
{body}
</scene>"#
    );
    parse_mitsuba(&xml, Path::new("scene.xml"), &[])
}

/// The BSDF of a sphere whose BSDF is `bsdf`, with the loader's warnings.
fn bsdf_of(bsdf: &str) -> (Bsdf, Vec<String>) {
    let (b, warnings) = load(&format!("<shape type=\"sphere\">{bsdf}</shape>"))
        .unwrap_or_else(|e| panic!("{bsdf}: {e}"));
    (b.materials[b.spheres[0].material as usize].bsdf, warnings)
}

fn error(body: &str) -> String {
    match load(body) {
        Ok(_) => panic!("loaded: {body}"),
        Err(e) => e.to_string(),
    }
}

/// Mitsuba's default relative indices: bk7 in air (1.50418, as Mitsuba 3.9.1 prints for a
/// default `dielectric`) and polypropylene in air (1.48959, a default `plastic`).
const BK7_IN_AIR: f32 = 1.5046 / 1.000277;
const PP_IN_AIR: f32 = 1.49 / 1.000277;

#[test]
fn conductors_take_mitsubas_presets_indices_and_default_mirror() {
    // Mitsuba 3's default material is `none` (eta 0, k 1): the perfect mirror.
    let (b, w) = bsdf_of(r#"<bsdf type="conductor"/>"#);
    assert!(
        matches!(b, Bsdf::Mirror(m) if m.color == Vec3::ONE),
        "{b:?}"
    );
    assert!(w.is_empty(), "{w:?}");
    let gold = metal("Au").unwrap();
    let (b, _) = bsdf_of(
        r#"<bsdf type="conductor"><string name="material" value="Au"/><rgb name="specular_reflectance" value="0.5, 0.6, 0.7"/></bsdf>"#,
    );
    let Bsdf::Conductor(c) = b else {
        panic!("{b:?}")
    };
    assert_eq!((c.eta, c.k, c.roughness), (gold.eta, gold.k, None));
    assert_eq!(c.specular_reflectance, Vec3::new(0.5, 0.6, 0.7));
    // eta and k as an rgb and a float.
    let (b, _) = bsdf_of(
        r#"<bsdf type="conductor"><rgb name="eta" value="0.2, 0.9, 1.1"/><float name="k" value="3"/></bsdf>"#,
    );
    let Bsdf::Conductor(c) = b else {
        panic!("{b:?}")
    };
    assert_eq!((c.eta, c.k), (Vec3::new(0.2, 0.9, 1.1), Vec3::splat(3.0)));
    // A sampled spectrum converts as Mitsuba 3.9.1's scalar_rgb converts it (printed by
    // mi.traverse of the same bsdf): like a reflectance under D65, but not clamped to 1.
    let (b, _) = bsdf_of(
        r#"<bsdf type="conductor"><spectrum name="eta" value="400:0.2, 500:0.5, 600:1.5, 700:2.5"/>
           <spectrum name="k" value="400:1.2, 500:2.5, 600:3.5, 700:4.5"/></bsdf>"#,
    );
    let Bsdf::Conductor(c) = b else {
        panic!("{b:?}")
    };
    let close = |a: Vec3, b: Vec3| (a - b).abs().max_element() < 2e-3 * b.max_element();
    assert!(
        close(c.eta, Vec3::new(1.93468, 0.90251, 0.271398)),
        "{}",
        c.eta
    );
    assert!(close(c.k, Vec3::new(3.89693, 2.94056, 1.74589)), "{}", c.k);
}

#[test]
fn rough_models_read_alpha_and_distribution_beckmann_by_default() {
    let (b, w) =
        bsdf_of(r#"<bsdf type="roughconductor"><string name="material" value="Cu"/></bsdf>"#);
    let Bsdf::Conductor(c) = b else {
        panic!("{b:?}")
    };
    assert_eq!(c.roughness, Some(Beckmann::isotropic(0.1).into()));
    assert_eq!(c.eta, metal("Cu").unwrap().eta);
    assert!(w.is_empty(), "{w:?}");
    let (b, w) = bsdf_of(
        r#"<bsdf type="roughdielectric"><string name="distribution" value="beckmann"/><float name="alpha_u" value="0.1"/>
           <float name="alpha_v" value="0.4"/></bsdf>"#,
    );
    let Bsdf::Dielectric(d) = b else {
        panic!("{b:?}")
    };
    assert_eq!(d.roughness, Some(Beckmann::new(0.1, 0.4).into()));
    assert!(w.is_empty(), "{w:?}");
    let (b, w) = bsdf_of(
        r#"<bsdf type="roughconductor"><string name="distribution" value="ggx"/><float name="alpha_u" value="0.05"/>
           <float name="alpha_v" value="0.3"/><boolean name="sample_visible" value="false"/></bsdf>"#,
    );
    let Bsdf::Conductor(c) = b else {
        panic!("{b:?}")
    };
    assert_eq!(c.roughness, Some(Ggx::new(0.05, 0.3).into()));
    assert_eq!((c.eta, c.k), (Vec3::ZERO, Vec3::ONE));
    assert!(w.is_empty(), "{w:?}");

    let (b, _) = bsdf_of(
        r#"<bsdf type="roughdielectric"><string name="distribution" value="ggx"/><float name="alpha" value="0.3"/>
           <string name="int_ior" value="water"/><string name="ext_ior" value="bk7"/></bsdf>"#,
    );
    let Bsdf::Dielectric(d) = b else {
        panic!("{b:?}")
    };
    assert_eq!(d.roughness, Some(Ggx::isotropic(0.3).into()));
    assert!((d.eta - 1.333 / 1.5046).abs() < 1e-6, "{}", d.eta);

    let (b, _) = bsdf_of(
        r#"<bsdf type="roughplastic"><string name="distribution" value="ggx"/><float name="alpha" value="0.2"/>
           <rgb name="diffuse_reflectance" value="0.1, 0.2, 0.3"/><float name="int_ior" value="1.6"/></bsdf>"#,
    );
    let Bsdf::Plastic(p) = b else { panic!("{b:?}") };
    assert_eq!(p.roughness, Some(Ggx::isotropic(0.2).into()));
    assert_eq!(p.diffuse_reflectance, Vec3::new(0.1, 0.2, 0.3));
    assert!((p.eta - 1.6 / 1.000277).abs() < 1e-6);
}

#[test]
fn dielectrics_and_plastics_take_mitsubas_defaults() {
    let (b, _) = bsdf_of(r#"<bsdf type="dielectric"/>"#);
    let Bsdf::Dielectric(d) = b else {
        panic!("{b:?}")
    };
    assert!((d.eta - BK7_IN_AIR).abs() < 1e-6 && (d.eta - 1.50418).abs() < 1e-5);
    assert_eq!(d.roughness, None);
    let (b, _) = bsdf_of(
        r#"<bsdf type="dielectric"><rgb name="specular_reflectance" value="0.5"/><rgb name="specular_transmittance" value="0.9, 0.8, 0.7"/></bsdf>"#,
    );
    let Bsdf::Dielectric(d) = b else {
        panic!("{b:?}")
    };
    assert_eq!(d.specular_reflectance, Vec3::splat(0.5));
    assert_eq!(d.specular_transmittance, Vec3::new(0.9, 0.8, 0.7));
    let (b, _) = bsdf_of(r#"<bsdf type="thindielectric"/>"#);
    assert!(matches!(b, Bsdf::ThinDielectric(t) if (t.eta - BK7_IN_AIR).abs() < 1e-6));
    let (b, _) = bsdf_of(r#"<bsdf type="plastic"/>"#);
    let Bsdf::Plastic(p) = b else { panic!("{b:?}") };
    assert!((p.eta - PP_IN_AIR).abs() < 1e-6 && (p.eta - 1.48959).abs() < 1e-5);
    assert_eq!(p.diffuse_reflectance, Vec3::splat(0.5));
    assert_eq!(p.specular_reflectance, Vec3::ONE);
    assert_eq!(p.roughness, None);
}

#[test]
fn twosided_wraps_any_reflecting_bsdf() {
    let (b, _) = bsdf_of(
        r#"<bsdf type="twosided"><bsdf type="roughplastic"><string name="distribution" value="ggx"/></bsdf></bsdf>"#,
    );
    assert!(matches!(b, Bsdf::TwoSidedPlastic(_)), "{b:?}");
    let (b, _) = bsdf_of(
        r#"<bsdf type="twosided"><bsdf type="conductor"><string name="material" value="Ag"/></bsdf></bsdf>"#,
    );
    assert!(matches!(b, Bsdf::TwoSidedConductor(_)), "{b:?}");
    // The same BSDF twice (a reference on both sides) is one BSDF on both sides.
    let (b, _) = load(
        r#"<bsdf type="plastic" id="p"/><shape type="sphere"><bsdf type="twosided"><ref id="p"/><ref id="p"/></bsdf></shape>"#,
    )
    .unwrap();
    assert!(matches!(
        b.materials[b.spheres[0].material as usize].bsdf,
        Bsdf::TwoSidedPlastic(_)
    ));
}

#[test]
fn what_the_bsdfs_cannot_honour_is_an_error_naming_it() {
    let cases = [
        (
            "<shape type=\"sphere\"><bsdf type=\"roughplastic\">\n<texture type=\"bitmap\" name=\"alpha\"/></bsdf></shape>",
            "scene.xml:6: texture `bitmap` (as `alpha` of bsdf `roughplastic`) is not supported",
        ),
        (
            "<shape type=\"sphere\"><bsdf type=\"plastic\">\n<texture type=\"mesh_attribute\" name=\"diffuse_reflectance\"/></bsdf></shape>",
            "scene.xml:6: texture `mesh_attribute` (as `diffuse_reflectance` of bsdf `plastic`) is not supported",
        ),
        (
            "<shape type=\"sphere\">\n<bsdf type=\"twosided\"><bsdf type=\"diffuse\"/><bsdf type=\"plastic\"/></bsdf></shape>",
            "scene.xml:6: twosided with two different BSDFs (bsdf `diffuse` at scene.xml:6 in front, bsdf `plastic` at scene.xml:6 behind) is not supported yet",
        ),
        (
            "<shape type=\"sphere\">\n<bsdf type=\"twosided\"><bsdf type=\"roughdielectric\"/></bsdf></shape>",
            "scene.xml:6: twosided around bsdf `roughdielectric` at scene.xml:6: it refracts",
        ),
        (
            "<shape type=\"sphere\">\n<bsdf type=\"conductor\"><string name=\"material\" value=\"Au\"/><float name=\"eta\" value=\"2\"/></bsdf></shape>",
            "scene.xml:6: bsdf `conductor`: give either `eta` and `k` or `material` (`Au`), not both",
        ),
        (
            "<shape type=\"sphere\">\n<bsdf type=\"conductor\"><string name=\"material\" value=\"Unobtainium\"/></bsdf></shape>",
            "scene.xml:6: bsdf `conductor`: unknown material `Unobtainium`; Mitsuba's conductors: none, a-C, Ag,",
        ),
        (
            "<shape type=\"sphere\"><bsdf type=\"conductor\"><string name=\"material\" value=\"Au\"/>\n<float name=\"k\" value=\"2\"/></bsdf></shape>",
            "scene.xml:6: unreferenced property `k` of bsdf `conductor`",
        ),
        (
            "<shape type=\"sphere\">\n<bsdf type=\"roughplastic\"><float name=\"alpha_u\" value=\"0.1\"/></bsdf></shape>",
            "scene.xml:6: unreferenced property `alpha_u` of bsdf `roughplastic`",
        ),
        (
            "<shape type=\"sphere\">\n<bsdf type=\"roughconductor\"><float name=\"alpha_u\" value=\"0.1\"/></bsdf></shape>",
            "needs both `alpha_u` and `alpha_v`",
        ),
        (
            "<shape type=\"sphere\">\n<bsdf type=\"roughdielectric\"><string name=\"distribution\" value=\"phong\"/></bsdf></shape>",
            "scene.xml:6: bsdf `roughdielectric`: unknown distribution `phong`",
        ),
        (
            "<shape type=\"sphere\">\n<bsdf type=\"plastic\"><boolean name=\"nonlinear\" value=\"true\"/></bsdf></shape>",
            "scene.xml:6: bsdf `plastic`: nonlinear=\"true\"",
        ),
        (
            "<shape type=\"sphere\">\n<bsdf type=\"dielectric\"><float name=\"int_ior\" value=\"1.2\"/><float name=\"ext_ior\" value=\"1.2\"/></bsdf></shape>",
            "the interface would not be there",
        ),
    ];
    for (body, expected) in cases {
        let e = error(body);
        assert!(
            e.contains(expected),
            "{body}\n  gave: {e}\n  expected: {expected}"
        );
    }
}

#[test]
fn spot_and_directional_emitters_map_to_ppms() {
    let (b, w) = load(
        r#"<emitter type="spot"><transform name="to_world"><lookat origin="1, 2, 3" target="1, 0, 3" up="0, 0, 1"/></transform>
             <rgb name="intensity" value="4, 5, 6"/><float name="cutoff_angle" value="30"/></emitter>
           <emitter type="directional"><vector name="direction" x="0" y="-2" z="0"/><rgb name="irradiance" value="2"/></emitter>
           <emitter type="directional"><transform name="to_world"><rotate x="1" angle="90"/></transform></emitter>"#,
    )
    .unwrap();
    let Light::Spot(s) = b.lights[1] else {
        panic!("{:?}", b.lights)
    };
    assert_eq!(s.position, Vec3::new(1.0, 2.0, 3.0));
    assert!(s.direction().abs_diff_eq(Vec3::new(0.0, -1.0, 0.0), 1e-6));
    assert_eq!(s.intensity, Vec3::new(4.0, 5.0, 6.0));
    assert!((s.cone_angle() - 30f32.to_radians()).abs() < 1e-6);
    // beam_width defaults to 3/4 of the cutoff, as Mitsuba 3.9.1 prints for a default spot.
    assert!((s.falloff_start() - 22.5f32.to_radians()).abs() < 1e-6);
    // The power difference at this band, from the formulas in emitter.rs: Mitsuba's
    // 1 + (sin 22.5° - sin 30°) / (7.5° in radians) = 0.103767, ppm's
    // (1 - cos 22.5°) + (cos 22.5° - cos 30°) / 2 = 0.105048.
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].contains("scene.xml:5: emitter `spot`: between beam_width 22.5° and cutoff_angle 30° Mitsuba's falloff is linear in the angle, ppm's a smoothstep in its cosine: the light's power differs by +1.23 %"),
        "{w:?}"
    );
    let Light::Directional(d) = b.lights[2] else {
        panic!("{:?}", b.lights)
    };
    assert_eq!(d.direction(), Vec3::new(0.0, -1.0, 0.0));
    assert_eq!(d.irradiance, Vec3::splat(2.0));
    let Light::Directional(d) = b.lights[3] else {
        panic!("{:?}", b.lights)
    };
    assert!(
        d.direction().abs_diff_eq(Vec3::new(0.0, -1.0, 0.0), 1e-6),
        "{}",
        d.direction()
    );
    assert_eq!(d.irradiance, Vec3::ONE);

    for (body, expected) in [
        (
            "\n<emitter type=\"directional\"><vector name=\"direction\" x=\"1\" y=\"0\" z=\"0\"/><transform name=\"to_world\"/></emitter>",
            "scene.xml:6: emitter `directional`: give either `direction` or `to_world`, not both",
        ),
        (
            "\n<emitter type=\"spot\"><float name=\"cutoff_angle\" value=\"10\"/><float name=\"beam_width\" value=\"20\"/></emitter>",
            "scene.xml:6: emitter `spot`: needs 0 <= beam_width <= cutoff_angle",
        ),
        (
            "<emitter type=\"spot\">\n<texture type=\"bitmap\" name=\"texture\"/></emitter>",
            "scene.xml:6: unreferenced property texture `bitmap` `texture` of emitter `spot`",
        ),
        (
            "\n<emitter type=\"projector\"/>",
            "scene.xml:6: emitter `projector` at scene.xml:6 is not supported yet",
        ),
    ] {
        let e = error(body);
        assert!(e.contains(expected), "{body}\n  gave: {e}\n  expected: {expected}");
    }
}

#[test]
fn integrators_that_render_the_path_image_give_their_depth() {
    let depth = |integrator: &str| {
        load(&format!("<shape type=\"sphere\"/>{integrator}"))
            .map(|(b, w)| (b.defaults.max_depth, w.len()))
    };
    for name in ["path", "volpath", "volpathmis", "prb", "ptracer", "bdpt"] {
        let xml = format!(
            "<integrator type=\"{name}\"><integer name=\"max_depth\" value=\"5\"/></integrator>"
        );
        assert_eq!(depth(&xml).unwrap(), (4, 0), "{name}");
    }
    assert_eq!(depth("<integrator type=\"direct\"/>").unwrap(), (1, 0));
    assert_eq!(
        depth("<integrator type=\"sppm\"><integer name=\"photon_count\" value=\"100\"/><integer name=\"max_depth\" value=\"3\"/></integrator>")
            .unwrap(),
        (2, 1)
    );
    let e = depth("\n<integrator type=\"aov\"/>")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("scene.xml:6: integrator `aov` at scene.xml:6 is not supported yet"),
        "{e}"
    );
}

/// Mitsuba 3 gives a shape without a BSDF a diffuse of reflectance 0.5, but an emitting one
/// a black diffuse (Mitsuba 3.9.1 renders an area light with no BSDF as with reflectance 0,
/// and 0.5 % brighter below it with reflectance 0.5 in tests/data/mitsuba/renders/lamp.xml's
/// setting, as `mitsuba_renders.rs` checks).
#[test]
fn an_emitter_without_a_bsdf_reflects_nothing() {
    let (b, _) = load(
        r#"<shape type="sphere"><emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>
           <shape type="sphere"/>"#,
    )
    .unwrap();
    let material = |i: usize| &b.materials[b.spheres[i].material as usize];
    assert!(matches!(material(0).bsdf, Bsdf::Diffuse(d) if d.albedo == Vec3::ZERO));
    assert_eq!(material(0).emission, Vec3::ONE);
    assert!(matches!(material(1).bsdf, Bsdf::Diffuse(d) if d.albedo == Vec3::splat(0.5)));
}
