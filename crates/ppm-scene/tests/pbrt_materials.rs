//! The pbrt-v4 build layer, entity by entity: materials (named metals, roughness remapping,
//! dielectrics, the coated-diffuse approximation), lights (photometric scale, power), shapes
//! and the camera (fov on the shorter axis, handedness); what ppm cannot render is an error
//! naming it and its place.

use glam::{Vec2, Vec3};
use ppm_core::bsdf::metals::metal;
use ppm_core::bsdf::Bsdf;
use ppm_core::light::Light;
use ppm_core::scene::SceneBuilder;
use ppm_scene::pbrt::parse_pbrt;
use ppm_scene::LoadError;
use std::f32::consts::PI;
use std::path::Path;

fn scene_with(camera: &str, body: &str) -> String {
    format!(
        "{camera}\nFilm \"rgb\" \"integer xresolution\" 40 \"integer yresolution\" 20\nWorldBegin\n{body}"
    )
}

/// A right-handed camera at z = 5 looking at the origin, then `body`.
fn scene(body: &str) -> String {
    scene_with(
        "Scale -1 1 1\nLookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"",
        &format!("LightSource \"point\"\n{body}"),
    )
}

fn load(text: &str) -> Result<(SceneBuilder, Vec<String>), LoadError> {
    parse_pbrt(text, Path::new("scene.pbrt"))
}

fn error(text: &str) -> String {
    match load(text) {
        Ok(_) => panic!("loaded:\n{text}"),
        Err(e) => e.to_string(),
    }
}

/// The BSDF of a sphere made of `material` (a `Material` directive's arguments).
fn bsdf(material: &str) -> (Bsdf, Vec<String>) {
    let (b, w) = load(&scene(&format!("Material {material}\nShape \"sphere\""))).unwrap();
    (b.materials[b.spheres[0].material as usize].bsdf, w)
}

#[test]
fn conductors_take_named_metals_rgb_or_a_reflectance() {
    let Bsdf::Conductor(c) = bsdf("\"conductor\"").0 else {
        panic!()
    };
    let cu = metal("Cu").unwrap();
    assert_eq!((c.eta, c.k, c.roughness.is_none()), (cu.eta, cu.k, true));
    let (b, _) =
        bsdf("\"conductor\" \"spectrum eta\" \"metal-Au-eta\" \"spectrum k\" \"metal-Au-k\"");
    let Bsdf::Conductor(c) = b else { panic!() };
    let au = metal("Au").unwrap();
    assert_eq!((c.eta, c.k), (au.eta, au.k));
    let Bsdf::Conductor(c) = bsdf("\"conductor\" \"rgb eta\" [0.2 0.3 0.4] \"rgb k\" [3 2 1]").0
    else {
        panic!()
    };
    assert_eq!(
        (c.eta, c.k),
        (Vec3::new(0.2, 0.3, 0.4), Vec3::new(3.0, 2.0, 1.0))
    );
    // reflectance r: eta 1, k = 2 sqrt(r) / sqrt(1 - r), whose normal-incidence Fresnel
    // reflectance ((eta - 1)^2 + k^2) / ((eta + 1)^2 + k^2) is r again.
    let Bsdf::Conductor(c) = bsdf("\"conductor\" \"rgb reflectance\" [0.5 0.5 0.5]").0 else {
        panic!()
    };
    let k = c.k.x;
    assert_eq!(c.eta, Vec3::ONE);
    assert!((k * k / (4.0 + k * k) - 0.5).abs() < 1e-6, "{k}");
    let e = error(&scene(
        "Material \"conductor\" \"spectrum eta\" \"metal-CuZn-eta\"",
    ));
    assert!(e.starts_with("scene.pbrt:7:22: Material \"conductor\": \"spectrum eta\": \"metal-CuZn-eta\" is not a named metal ppm knows"), "{e}");
}

#[test]
fn roughness_is_remapped_to_alpha_by_a_square_root() {
    let alpha = |m: &str| match bsdf(m).0 {
        Bsdf::Conductor(c) => c.roughness.map(|g| (g.alpha_x(), g.alpha_y())),
        Bsdf::Dielectric(d) => d.roughness.map(|g| (g.alpha_x(), g.alpha_y())),
        Bsdf::Plastic(p) => p.roughness.map(|g| (g.alpha_x(), g.alpha_y())),
        other => panic!("{other:?}"),
    };
    assert_eq!(
        alpha("\"conductor\" \"float roughness\" 0.04"),
        Some((0.2, 0.2))
    );
    assert_eq!(
        alpha("\"conductor\" \"float uroughness\" 0.09 \"float vroughness\" 0.09"),
        Some((0.3, 0.3))
    );
    assert_eq!(
        alpha("\"conductor\" \"float roughness\" 0.04 \"bool remaproughness\" false"),
        Some((0.04, 0.04))
    );
    assert_eq!(
        alpha("\"dielectric\" \"float roughness\" 0.25"),
        Some((0.5, 0.5))
    );
    assert_eq!(
        alpha("\"coateddiffuse\" \"float roughness\" 0.01"),
        Some((0.1, 0.1))
    );
    // Below alpha 1e-3 pbrt treats the surface as smooth.
    assert_eq!(alpha("\"conductor\" \"float roughness\" 0.0000009"), None);
    let e = error(&scene(
        "Material \"conductor\" \"float uroughness\" 0.1 \"float vroughness\" 0.2",
    ));
    assert!(
        e.contains("anisotropic roughness (u 0.1, v 0.2) is not supported yet"),
        "{e}"
    );
}

#[test]
fn dielectrics_and_the_coated_diffuse_approximation() {
    let Bsdf::Dielectric(d) = bsdf("\"dielectric\"").0 else {
        panic!()
    };
    assert_eq!((d.eta, d.roughness.is_none()), (1.5, true));
    let Bsdf::Dielectric(d) = bsdf("\"dielectric\" \"float eta\" 1.33").0 else {
        panic!()
    };
    assert_eq!(d.eta, 1.33);
    let Bsdf::Dielectric(d) = bsdf("\"dielectric\" \"spectrum eta\" \"glass-BK7\"").0 else {
        panic!()
    };
    assert!((d.eta - 1.5185).abs() < 5e-4, "{}", d.eta);
    let Bsdf::ThinDielectric(t) = bsdf("\"thindielectric\" \"float eta\" 1.2").0 else {
        panic!()
    };
    assert_eq!(t.eta, 1.2);
    let (b, w) = bsdf("\"coateddiffuse\" \"rgb reflectance\" [0.2 0.3 0.4]");
    let Bsdf::Plastic(p) = b else { panic!() };
    assert_eq!(
        (p.diffuse_reflectance, p.eta),
        (Vec3::new(0.2, 0.3, 0.4), 1.5)
    );
    assert!(
        w.iter()
            .any(|w| w.contains("coateddiffuse approximated by ppm's plastic")),
        "{w:?}"
    );
    let Bsdf::Diffuse(d) = bsdf("\"diffuse\" \"spectrum reflectance\" [300 0.25 800 0.25]").0
    else {
        panic!()
    };
    assert!(
        (d.albedo - Vec3::splat(0.25)).abs().max_element() < 0.01,
        "{}",
        d.albedo
    );
}

#[test]
fn unsupported_materials_and_textures_are_errors_naming_them() {
    let cases: &[(&str, &str)] = &[
        ("Material \"mix\"", "scene.pbrt:7:1: Material \"mix\": material type \"mix\" is not supported yet"),
        ("Material \"diffusetransmission\"", "material type \"diffusetransmission\" is not supported yet"),
        ("Material \"interface\"", "medium boundary) is not supported yet"),
        ("Material \"diffuse\" \"rgb reflectance\" [1.5 0 0]", "scene.pbrt:7:20: Material \"diffuse\": \"rgb reflectance\": the reflectance [1.5, 0, 0] has a component outside [0, 1]"),
        ("Material \"diffuse\" \"float displacement\" 1", "unknown or unsupported parameter \"float displacement\""),
        ("Texture \"t\" \"spectrum\" \"marble\"\nMaterial \"diffuse\" \"texture reflectance\" \"t\"", "scene.pbrt:8:20: Material \"diffuse\": \"texture reflectance\": texture \"t\" (spectrum \"marble\" at scene.pbrt:7:1) is not supported yet"),
        ("Texture \"t\" \"spectrum\" \"checkerboard\"\nMaterial \"conductor\" \"texture reflectance\" \"t\"", "texture \"t\" (spectrum \"checkerboard\" at scene.pbrt:7:1) is not supported yet here"),
        ("Material \"conductor\" \"texture roughness\" \"r\"", "no texture \"r\""),
        ("Material \"coateddiffuse\" \"rgb albedo\" [0.5 0.5 0.5]", "a scattering coating (albedo > 0) is not supported yet"),
    ];
    for (body, want) in cases {
        let e = error(&scene(&format!("{body}\nShape \"sphere\"")));
        assert!(e.contains(want), "{body}:\n  got  {e}\n  want {want}");
    }
    // A constant texture is its value.
    let (b, _) = load(&scene("Texture \"t\" \"spectrum\" \"constant\" \"rgb value\" [0.1 0.2 0.3]\nMaterial \"diffuse\" \"texture reflectance\" \"t\"\nShape \"sphere\"")).unwrap();
    let Bsdf::Diffuse(d) = b.materials[b.spheres[0].material as usize].bsdf else {
        panic!()
    };
    assert_eq!(d.albedo, Vec3::new(0.1, 0.2, 0.3));
}

fn lights(body: &str) -> Vec<Light> {
    let text = scene_with(
        "Scale -1 1 1\nLookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"",
        &format!("{body}\nShape \"sphere\""),
    );
    load(&text).unwrap().0.lights
}

#[test]
fn lights_scale_as_pbrt_v4_normalises_them() {
    // An rgb intensity is that RGB, times scale; power P is P / (4 pi) per unit.
    let l = lights("Translate 1 0 0\nLightSource \"point\" \"rgb I\" [1 2 3] \"float scale\" 2 \"point3 from\" [0 1 0]");
    let Light::Point(p) = l[0] else { panic!() };
    assert_eq!(
        (p.position, p.intensity),
        (Vec3::new(1.0, 1.0, 0.0), Vec3::new(2.0, 4.0, 6.0))
    );
    let l = lights("LightSource \"point\" \"float power\" 12.566370614359172");
    let Light::Point(p) = l[0] else { panic!() };
    assert!(p.intensity.abs_diff_eq(Vec3::ONE, 1e-6), "{}", p.intensity);
    // A black body has luminance 1.
    let l = lights("LightSource \"point\" \"blackbody I\" 3000");
    let Light::Point(p) = l[0] else { panic!() };
    let y = 0.2126 * p.intensity.x + 0.7152 * p.intensity.y + 0.0722 * p.intensity.z;
    assert!(
        (y - 1.0).abs() < 1e-5 && p.intensity.x > p.intensity.z,
        "{}",
        p.intensity
    );
    // Spot: smoothstep from coneangle - conedeltaangle to coneangle.
    let l = lights("LightSource \"spot\" \"point3 from\" [0 4 0] \"point3 to\" [0 0 0] \"float coneangle\" 20 \"float conedeltaangle\" 5");
    let Light::Spot(s) = l[0] else { panic!() };
    assert!(s.direction().abs_diff_eq(-Vec3::Y, 1e-6));
    assert!((s.cone_angle() - 20f32.to_radians()).abs() < 1e-6);
    assert!((s.falloff_start() - 15f32.to_radians()).abs() < 1e-6);
    // Power P over k_e = 2 pi ((1 - cos 15) + (cos 15 - cos 20) / 2).
    let l = lights(
        "LightSource \"spot\" \"float coneangle\" 20 \"float conedeltaangle\" 5 \"float power\" 1",
    );
    let Light::Spot(s) = l[0] else { panic!() };
    let (c15, c20) = (15f32.to_radians().cos(), 20f32.to_radians().cos());
    let k_e = 2.0 * PI * ((1.0 - c15) + (c15 - c20) / 2.0);
    assert!(
        (s.intensity.x - 1.0 / k_e).abs() < 1e-4 * s.intensity.x,
        "{}",
        s.intensity
    );
    // Distant: light travels from `from` to `to`.
    let l = lights(
        "LightSource \"distant\" \"point3 from\" [0 0 0] \"point3 to\" [1 0 0] \"rgb L\" [3 3 3]",
    );
    let Light::Directional(d) = l[0] else {
        panic!()
    };
    assert!(d.direction().abs_diff_eq(Vec3::X, 1e-6));
    assert_eq!(d.irradiance, Vec3::splat(3.0));
}

#[test]
fn area_lights_emit_their_l_or_their_power() {
    let emission = |body: &str| {
        let (b, _) = load(&scene(&format!(
            "AttributeBegin\n{body}\nAttributeEnd\nShape \"sphere\""
        )))
        .unwrap();
        let lit: Vec<Vec3> = b
            .materials
            .iter()
            .map(|m| m.emission)
            .filter(|e| *e != Vec3::ZERO)
            .collect();
        (lit, b)
    };
    let (lit, b) = emission("AreaLightSource \"diffuse\" \"rgb L\" [1 2 3] \"float scale\" 3\nShape \"sphere\" \"float radius\" 2");
    assert_eq!(lit, vec![Vec3::new(3.0, 6.0, 9.0)]);
    // The sphere after AttributeEnd does not emit.
    assert!(!b.materials[b.spheres[1].material as usize].is_emissive());
    // power P: L = P / (pi area), area 4 pi r^2.
    let (lit, _) = emission(
        "AreaLightSource \"diffuse\" \"float power\" 100\nShape \"sphere\" \"float radius\" 2",
    );
    let want = 100.0 / (PI * 4.0 * PI * 4.0);
    assert!((lit[0].x - want).abs() < 1e-5 * want, "{lit:?} {want}");
    let e = error(&scene(
        "AreaLightSource \"diffuse\" \"bool twosided\" true\nShape \"sphere\"",
    ));
    assert!(e.starts_with("scene.pbrt:7:1: AreaLightSource \"diffuse\": twosided area lights are not supported yet"), "{e}");
    let e = error(&scene(
        "LightSource \"infinite\" \"string filename\" \"sky.exr\" \"float illuminance\" 2",
    ));
    assert!(
        e.starts_with(
            "scene.pbrt:7:1: LightSource \"infinite\": illuminance with an image map is not supported yet"
        ),
        "{e}"
    );
    // A map that is not there is named.
    let e = error(&scene(
        "LightSource \"infinite\" \"string filename\" \"sky.exr\"",
    ));
    assert!(e.contains("filename \"") && e.contains("sky.exr"), "{e}");
    let e = error(&scene("LightSource \"goniometric\""));
    assert!(e.contains("light type not supported yet"), "{e}");
}

#[test]
fn shapes_and_their_limits() {
    let (b, _) = load(&scene(
        "Shape \"disk\" \"float radius\" 2 \"float height\" 1",
    ))
    .unwrap();
    let m = &b.meshes[0];
    assert!(m
        .positions
        .iter()
        .all(|p| p.z == 1.0 && p.truncate().length() <= 2.0 + 1e-6));
    let [a, p, q] = m.indices[0].map(|i| m.positions[i as usize]);
    assert!((p - a).cross(q - a).z > 0.0, "a disk faces +z");
    // A cylinder faces outward (inward with ReverseOrientation), with radial normals.
    for (reverse, sign) in [("", 1.0), ("ReverseOrientation", -1.0)] {
        let body = format!(
            "{reverse} Shape \"cylinder\" \"float radius\" 2 \"float zmin\" 0 \"float zmax\" 3"
        );
        let (b, _) = load(&scene(&body)).unwrap();
        let m = &b.meshes[0];
        assert!(m
            .positions
            .iter()
            .all(|p| (p.truncate().length() - 2.0).abs() < 1e-5 && (p.z == 0.0 || p.z == 3.0)));
        for t in &m.indices {
            let [a, p, q] = t.map(|i| m.positions[i as usize]);
            let radial = ((a + p + q) / 3.0).truncate().extend(0.0);
            assert!(sign * (p - a).cross(q - a).dot(radial) > 0.0, "{reverse}");
            assert!(
                sign * m.normals[t[0] as usize].dot(radial) > 0.0,
                "{reverse}"
            );
        }
    }
    let (_, w) = load(&scene(
        "Shape \"bilinearmesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0  1 1 1]",
    ))
    .unwrap();
    assert!(
        w.iter()
            .any(|w| w.contains("1 of 1 bilinear patches are not planar")),
        "{w:?}"
    );
    let cases: &[(&str, &str)] = &[
        (
            "Shape \"sphere\" \"float zmax\" 0.5",
            "a partial sphere (zmin, zmax or phimax) is not supported yet",
        ),
        (
            "Shape \"cone\"",
            "Shape \"cone\": shape type not supported yet",
        ),
        (
            "Shape \"cylinder\" \"float phimax\" 90",
            "a partial cylinder (phimax < 360) is not supported yet",
        ),
        (
            "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [0 1 3]",
            "index 3 is outside the 3 vertices",
        ),
        (
            "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 0]",
            "needs \"integer indices\" (3 per face)",
        ),
        (
            "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"float alpha\" 0.5",
            "alpha cut-outs are not supported yet",
        ),
        (
            "Shape \"plymesh\" \"string filename\" \"nope.ply\"",
            "nope.ply: cannot read",
        ),
        (
            "Scale 1 2 1\nShape \"sphere\"",
            "non-uniform scale or shear",
        ),
    ];
    for (body, want) in cases {
        let e = error(&scene(body));
        assert!(e.contains(want), "{body}:\n  got  {e}\n  want {want}");
    }
}

#[test]
fn the_field_of_view_spans_the_shorter_axis() {
    let tan_half = |film: &str| {
        let text = format!("Scale -1 1 1\nLookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 60\nFilm \"rgb\" {film}\nWorldBegin\nLightSource \"point\"");
        load(&text).unwrap().0.camera.frame().3
    };
    let t = 30f32.to_radians().tan();
    // Wide: the vertical. Tall: the horizontal, so the vertical is t / aspect.
    assert!((tan_half("\"integer xresolution\" 40 \"integer yresolution\" 20") - t).abs() < 1e-6);
    assert!(
        (tan_half("\"integer xresolution\" 20 \"integer yresolution\" 40") - 2.0 * t).abs() < 1e-6
    );
    let e = error(&scene_with("Camera \"orthographic\"", ""));
    assert!(
        e.contains("Camera \"orthographic\": not supported yet"),
        "{e}"
    );
}

#[test]
fn pbrts_left_handed_camera_shows_plus_x_on_the_left_of_a_lookat_down_minus_z() {
    // pbrt's LookAt puts up x dir = (0, 1, 0) x (0, 0, -1) = -x on the image's right: a
    // sphere at x = +1 appears on the left, unless `Scale -1 1 1` turns the camera
    // right-handed. Film 40 x 20, fov 20 (vertical): x = 1 at distance 5 is at
    // 1 / (5 tan 10°) = 0.57 of the half width from the centre, pixel 20 -/+ 11.3.
    let sphere =
        "AttributeBegin\nTranslate 1 0 0\nShape \"sphere\" \"float radius\" 0.3\nAttributeEnd";
    for (scale, left) in [("", true), ("Scale -1 1 1", false)] {
        let text = scene_with(
            &format!(
                "{scale}\nLookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 20"
            ),
            &format!("LightSource \"point\"\n{sphere}"),
        );
        let scene = load(&text).unwrap().0.build().unwrap();
        let hit = |x: f32| {
            scene
                .intersect(&scene.camera.generate_ray(Vec2::new(x, 10.0)))
                .is_some()
        };
        assert_eq!((hit(8.7), hit(31.3)), (left, !left), "`{scale}`");
    }
}
