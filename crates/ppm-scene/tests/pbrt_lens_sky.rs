//! pbrt-v4 features ppm shares with its other formats: the thin lens (`lensradius`,
//! `focaldistance`) builds the camera Mitsuba's `thinlens` builds, and the constant
//! `infinite` light is the YAML constant environment and lights a diffuse sphere to a L.

use glam::{Vec2, Vec3};
use ppm_core::camera::Camera;
use ppm_core::integrator::{Algorithm, RenderSettings, Renderer};
use ppm_core::scene::SceneBuilder;
use ppm_scene::mitsuba::parse_mitsuba;
use ppm_scene::pbrt::parse_pbrt;
use ppm_scene::{parse_scene, LoadError};
use std::path::Path;

fn pbrt(text: &str) -> Result<(SceneBuilder, Vec<String>), LoadError> {
    parse_pbrt(text, Path::new("scene.pbrt"))
}

fn pbrt_camera(transform: &str, lens: &str) -> Camera {
    let text = format!(
        "{transform}\nLookAt 0 1 3.9  0 1 0  0 1 0\nCamera \"perspective\" \"float fov\" 40 {lens}\n\
         Film \"rgb\" \"integer xresolution\" 48 \"integer yresolution\" 32\nWorldBegin\nLightSource \"point\""
    );
    pbrt(&text).unwrap().0.camera
}

/// The same camera as Mitsuba 3's `thinlens`: pbrt's fov spans the shorter axis (Mitsuba's
/// `fov_axis` "smaller"), its `lensradius` / `focaldistance` are `aperture_radius` /
/// `focus_distance`. Every lens ray agrees, with or without pbrt's mirroring `Scale -1 1 1`
/// (the world mirror keeps distances, so the lens is the same).
#[test]
fn a_pbrt_lens_is_mitsubas_thinlens() {
    let xml = r#"<scene version="3.0.0">
        <sensor type="thinlens">
            <float name="aperture_radius" value="0.15"/>
            <float name="focus_distance" value="3.3"/>
            <float name="fov" value="40"/>
            <string name="fov_axis" value="smaller"/>
            <transform name="to_world"><lookat origin="0, 1, 3.9" target="0, 1, 0" up="0, 1, 0"/></transform>
            <film type="hdrfilm"><integer name="width" value="48"/><integer name="height" value="32"/></film>
        </sensor>
    </scene>"#;
    let mitsuba = parse_mitsuba(xml, Path::new("scene.xml"), &[])
        .unwrap()
        .0
        .camera;
    let lens = "\"float lensradius\" 0.15 \"float focaldistance\" 3.3";
    for transform in ["Scale -1 1 1", ""] {
        let c = pbrt_camera(transform, lens);
        assert_eq!((c.lens_radius(), c.focus_distance()), (0.15, 3.3));
        for (film, u) in [
            (Vec2::new(0.5, 0.5), Vec2::new(0.1, 0.9)),
            (Vec2::new(24.0, 16.0), Vec2::new(0.5, 0.5)),
            (Vec2::new(40.3, 7.1), Vec2::new(0.8, 0.3)),
            (Vec2::new(3.0, 30.0), Vec2::new(0.0, 1.0)),
        ] {
            let (a, b) = (
                c.generate_lens_ray(film, u),
                mitsuba.generate_lens_ray(film, u),
            );
            assert!(
                (a.origin - b.origin).length() < 1e-5 && (a.dir - b.dir).length() < 1e-5,
                "`{transform}` {film} {u}: {a:?} vs {b:?}"
            );
        }
    }
}

/// pbrt's defaults: no lens (the pinhole) and, with a lens, focus at 10^6; the lens lives in
/// camera space, so a camera transform's uniform scale scales it.
#[test]
fn pbrt_lens_defaults_and_camera_scale() {
    assert!(pbrt_camera("Scale -1 1 1", "").is_pinhole());
    let c = pbrt_camera("Scale -1 1 1", "\"float lensradius\" 0.1");
    assert_eq!((c.lens_radius(), c.focus_distance()), (0.1, 1e6));
    // camera-from-world scaled by 1/2: camera space's unit is 2 world units.
    let c = pbrt_camera(
        "Scale -0.5 0.5 0.5",
        "\"float lensradius\" 0.1 \"float focaldistance\" 2",
    );
    assert_eq!((c.lens_radius(), c.focus_distance()), (0.2, 4.0));
    let Err(e) =
        pbrt("Camera \"perspective\" \"float lensradius\" -1\nWorldBegin\nLightSource \"point\"")
    else {
        panic!("a negative lens radius loaded")
    };
    let e = e.to_string();
    assert!(
        e.starts_with("scene.pbrt:1:1: Camera \"perspective\": ") && e.contains("aperture"),
        "{e}"
    );
}

/// A sphere of `reflectance` 0.5 seen from z = 5 under `LightSource "infinite"` `light`.
fn sky_scene(light: &str) -> String {
    format!(
        "Scale -1 1 1\nLookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 20\n\
         Film \"rgb\" \"integer xresolution\" 16 \"integer yresolution\" 16\nWorldBegin\n\
         LightSource \"infinite\" {light}\n\
         Material \"diffuse\" \"rgb reflectance\" [0.5 0.5 0.5]\nShape \"sphere\""
    )
}

/// pbrt's `L` (an RGB illuminant renders as its RGB) times `scale` is the YAML constant
/// environment's `color` times its `scale`; `illuminance` E rescales L to give an upward
/// surface irradiance E (L = E / pi for unit L).
#[test]
fn a_constant_infinite_light_is_the_yaml_constant_environment() {
    let (b, warnings) = pbrt(&sky_scene("\"rgb L\" [0.4 0.8 1.2] \"float scale\" 2")).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    let yaml = "camera: { position: [0, 0, 5], look_at: [0, 0, 0], up: [0, 1, 0], fov: 20 }
materials:
  white: { type: diffuse, color: [0.5, 0.5, 0.5] }
objects:
  - { type: sphere, center: [0, 0, 0], radius: 1, material: white }
lights:
  - { type: environment, color: [0.4, 0.8, 1.2], scale: 2 }
";
    let (y, _) = parse_scene(yaml, Path::new("sky.yml")).unwrap();
    for d in [Vec3::X, Vec3::Y, Vec3::new(-0.3, -0.5, 0.8).normalize()] {
        assert_eq!(b.lights[0].le_infinite(d), y.lights[0].le_infinite(d));
        assert_eq!(b.lights[0].le_infinite(d), Vec3::new(0.8, 1.6, 2.4));
    }
    let (b, _) = pbrt(&sky_scene("\"float illuminance\" 3.14159265")).unwrap();
    let l = b.lights[0].le_infinite(Vec3::Z);
    assert!((l - Vec3::ONE).abs().max_element() < 1e-6, "{l}");
}

/// Path traces `b` (a [`sky_scene`]) and checks the furnace: a convex Lambertian sphere of
/// albedo a = 0.5 under a constant sky L reflects L_o = a L in every direction (the rendering
/// equation with L_i = L over the hemisphere: a / pi * L * pi), and the sky around it is L.
fn assert_sphere_reflects_half_the_sky(b: SceneBuilder, sky: Vec3) {
    let scene = b.build().unwrap();
    let settings = RenderSettings {
        seed: 3,
        ..RenderSettings::for_algorithm(&scene, Algorithm::Path)
    };
    let mut r = Renderer::new(&scene, &settings);
    for _ in 0..64 {
        r.iterate(&scene);
    }
    let image = r.image();
    // Corner pixels look at least 12 degrees off axis; the sphere subtends 11.5.
    for (x, y) in [(0, 0), (15, 0), (0, 15), (15, 15)] {
        let c = image.get(x, y);
        assert!((c - sky).abs().max_element() < 1e-5, "({x}, {y}): {c}");
    }
    // The central 6 x 6 pixels see only the sphere.
    let mut sum = Vec3::ZERO;
    for y in 5..11 {
        for x in 5..11 {
            sum += image.get(x, y);
        }
    }
    let (mean, want) = (sum / 36.0, 0.5 * sky);
    assert!(
        ((mean - want) / want).abs().max_element() < 0.02,
        "{mean} vs {want}"
    );
}

/// The furnace of [`assert_sphere_reflects_half_the_sky`] under pbrt's constant `L`.
#[test]
fn a_diffuse_sphere_under_a_constant_sky_reflects_a_l() {
    let (b, _) = pbrt(&sky_scene("\"rgb L\" [0.4 0.8 1.2] \"float scale\" 2")).unwrap();
    assert_sphere_reflects_half_the_sky(b, Vec3::new(0.8, 1.6, 2.4));
}

/// Writes an 8 x 8 equal-area map into a fresh folder and returns the folder: radiance 0.1
/// everywhere but near the light-space directions +z (the square's centre: 2 x 2 texels of
/// A), +x (the right edge's middle: C), +y (the bottom edge's middle: D) and -z (the four
/// corners: B). Each marks two texels across the line the direction lies on, so that a
/// rounding of the rotation cannot move it out.
fn write_equal_area_sky(tag: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("ppm_equal_area_{tag}_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let texel = |x: usize, y: usize| -> (f32, f32, f32) {
        match (x, y) {
            (3..=4, 3..=4) => (1.0, 2.0, 3.0), // A: +z
            (7, 3..=4) => (4.0, 0.0, 0.0),     // C: +x
            (3..=4, 7) => (0.0, 5.0, 0.0),     // D: +y
            (0 | 7, 0 | 7) => (0.0, 0.0, 6.0), // B: -z
            _ => (0.1, 0.1, 0.1),
        }
    };
    exr::prelude::write_rgb_file(dir.join("sky.exr"), 8, 8, texel).unwrap();
    dir
}

/// pbrt-v4's image `infinite` light: an equal-area octahedral map (the square's centre is
/// light-space +z, its right edge +x, its bottom edge +y, its corners -z), turned into the
/// world by the light's transform; the common `Rotate -90 1 0 0` makes its +z the world's
/// +y. The same file as a YAML environment with `mapping: equal_area` and the same rotation
/// is the same light.
#[test]
fn an_image_infinite_light_reads_pbrts_equal_area_frame() {
    let dir = write_equal_area_sky("frame");
    let text = sky_scene("\"string filename\" \"sky.exr\" \"float scale\" 2")
        .replace(
            "LightSource",
            "AttributeBegin\nRotate -90 1 0 0\nLightSource",
        )
        .replace("Material", "AttributeEnd\nMaterial");
    let (b, warnings) = parse_pbrt(&text, &dir.join("scene.pbrt")).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    let le = |d: Vec3| b.lights[0].le_infinite(d.normalize());
    // Rotate -90 about x: light +z -> world +y, +y -> -z, -z -> -y, +x stays.
    assert_eq!(le(Vec3::Y), Vec3::new(2.0, 4.0, 6.0));
    assert_eq!(le(Vec3::X), Vec3::new(8.0, 0.0, 0.0));
    assert_eq!(le(Vec3::NEG_Z), Vec3::new(0.0, 10.0, 0.0));
    assert_eq!(le(Vec3::NEG_Y), Vec3::new(0.0, 0.0, 12.0));
    assert_eq!(le(Vec3::new(-1.0, 0.3, 0.2)), Vec3::splat(0.2));
    let yaml = "camera: { position: [0, 0, 5], look_at: [0, 0, 0], up: [0, 1, 0], fov: 20 }
materials:
  white: { type: diffuse, color: [0.5, 0.5, 0.5] }
objects:
  - { type: sphere, center: [0, 0, 0], radius: 1, material: white }
lights:
  - { type: environment, file: sky.exr, mapping: equal_area, scale: 2, rotate: { axis: [1, 0, 0], angle: -90 } }
";
    let (y, _) = parse_scene(yaml, &dir.join("sky.yml")).unwrap();
    for k in 0..200 {
        let u = Vec2::new((k as f32 * 0.618034) % 1.0, (k as f32 + 0.5) / 200.0);
        let d = ppm_core::sampling::uniform_sphere(u);
        assert_eq!(
            b.lights[0].le_infinite(d),
            y.lights[0].le_infinite(d),
            "{d}"
        );
    }
    // `mapping` without a file, and a map that is not square, are errors naming them.
    let no_file = yaml.replace("file: sky.exr,", "color: [1, 1, 1],");
    let e = parse_scene(&no_file, &dir.join("sky.yml"))
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("mapping"), "{e}");
    exr::prelude::write_rgb_file(dir.join("wide.exr"), 8, 4, |_, _| (1.0f32, 1.0f32, 1.0f32))
        .unwrap();
    let wide = text.replace("sky.exr", "wide.exr");
    let e = parse_pbrt(&wide, &dir.join("scene.pbrt"))
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("square") && e.contains("8x4"), "{e}");
    std::fs::remove_dir_all(&dir).ok();
}

/// The furnace of [`assert_sphere_reflects_half_the_sky`] with the sky as a constant
/// equal-area image: the map's integral, sampling density and lookup together.
#[test]
fn a_diffuse_sphere_under_a_constant_equal_area_sky_reflects_a_l() {
    let dir = std::env::temp_dir().join(format!("ppm_equal_area_furnace_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    exr::prelude::write_rgb_file(dir.join("sky.exr"), 6, 6, |_, _| (0.4f32, 0.8f32, 1.2f32))
        .unwrap();
    let (b, _) = parse_pbrt(
        &sky_scene("\"string filename\" \"sky.exr\""),
        &dir.join("scene.pbrt"),
    )
    .unwrap();
    std::fs::remove_dir_all(&dir).ok();
    assert_sphere_reflects_half_the_sky(b, Vec3::new(0.4, 0.8, 1.2));
}
