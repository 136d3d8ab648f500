//! pbrt-v4 roughness given as a float texture (`"texture roughness" "name"`) on a conductor
//! or dielectric: a checkerboard of two roughnesses renders, pixel for pixel, as the two
//! constant roughnesses; `remaproughness` applies per texel (alpha = sqrt(roughness), or the
//! roughness itself when false); a grey image map reads its texels; what ppm cannot render
//! (a roughness texture on coateddiffuse, different u and v textures, a coloured image, a
//! spectrum texture) is an error naming it.

use glam::Vec2;
use ppm_core::bsdf::Bsdf;
use ppm_core::integrator::{Algorithm, RenderSettings, Renderer};
use ppm_core::scene::{Scene, SceneBuilder};
use ppm_scene::pbrt::parse_pbrt;
use ppm_scene::LoadError;
use std::path::{Path, PathBuf};

/// A folder of its own under the target's temporary folder.
fn dir(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("pbrt-roughness")
        .join(name);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A 4 x 4 floor (uv 0 to 1 across it) of `material` under a point light, seen from above
/// at an angle (24 x 24 pixels), with `textures` declared before it.
fn scene(textures: &str, material: &str) -> String {
    format!(
        "LookAt 0 -1.2 2  0 0 0  0 0 1\nCamera \"perspective\" \"float fov\" 60\n\
         Film \"rgb\" \"integer xresolution\" 24 \"integer yresolution\" 24\nWorldBegin\n\
         LightSource \"point\" \"point3 from\" [0.3 0.5 2.5] \"rgb I\" [6 6 6]\n{textures}\n\
         Material {material}\n\
         Shape \"trianglemesh\" \"point3 P\" [-2 -2 0  2 -2 0  2 2 0  -2 2 0] \
         \"integer indices\" [0 1 2  0 2 3] \"point2 uv\" [0 0  1 0  1 1  0 1]\n"
    )
}

fn load(dir: &Path, text: &str) -> Result<(SceneBuilder, Vec<String>), LoadError> {
    parse_pbrt(text, &dir.join("scene.pbrt"))
}

fn build(text: &str) -> Scene {
    let (b, w) = load(&dir("build"), text).unwrap();
    assert!(w.is_empty(), "{w:?}");
    b.build().unwrap()
}

/// The roughness alpha of the floor's BSDF at uv (the textured material's value there).
fn alpha_at_uv(scene: &Scene, uv: Vec2) -> f32 {
    let m = scene
        .materials
        .iter()
        .find(|m| m.textures.is_some())
        .expect("a textured material");
    match m.bsdf_at(uv) {
        Bsdf::Conductor(c) => c.roughness.unwrap().alpha_x(),
        Bsdf::Dielectric(d) => d.roughness.unwrap().alpha_x(),
        other => panic!("{other:?}"),
    }
}

/// The roughness alpha of the BSDF hit through film point `film` (`None`: the ray misses).
fn alpha_at(scene: &Scene, film: Vec2) -> Option<f32> {
    let hit = scene.intersect(&scene.camera.generate_ray(film))?;
    match scene.bsdf(&hit) {
        Bsdf::Conductor(c) => c.roughness.map(|d| d.alpha_x()),
        other => panic!("{other:?}"),
    }
}

const CHECKER: &str =
    "Texture \"r\" \"float\" \"checkerboard\" \"float uscale\" 4 \"float vscale\" 4 \
     \"float tex1\" 0.0025 \"float tex2\" 0.25";

/// A checkerboard roughness (0.0025 and 0.25: alphas 0.05 and 0.5) renders as the renders with
/// the constant roughness of the square each pixel sees (same seed, the same samples: bit for
/// bit wherever a pixel's footprint lies inside one square), and both squares are seen.
#[test]
fn a_checkerboard_roughness_renders_as_the_constant_roughnesses() {
    let conductor = |roughness: &str| format!("\"conductor\" {roughness}");
    let checker = build(&scene(CHECKER, &conductor("\"texture roughness\" \"r\"")));
    let smooth = build(&scene("", &conductor("\"float roughness\" 0.0025")));
    let rough = build(&scene("", &conductor("\"float roughness\" 0.25")));
    let image = |scene: &Scene| {
        let settings = RenderSettings {
            seed: 5,
            ..RenderSettings::for_algorithm(scene, Algorithm::Path)
        };
        let mut r = Renderer::new(scene, &settings);
        for _ in 0..8 {
            r.iterate(scene);
        }
        r.image().pixels
    };
    let (c, s, r) = (image(&checker), image(&smooth), image(&rough));
    let mut seen = [0; 2];
    for j in 0..24u32 {
        for i in 0..24u32 {
            let corners = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)]
                .map(|(x, y)| alpha_at(&checker, Vec2::new(i as f32 + x, j as f32 + y)));
            let Some(a) = corners[0] else { continue };
            if corners.iter().any(|x| *x != Some(a)) {
                continue;
            }
            let k = (j * 24 + i) as usize;
            let (want, n) = if a == 0.05 { (s[k], 0) } else { (r[k], 1) };
            assert!((a - 0.05).abs() < 1e-7 || (a - 0.5).abs() < 1e-7, "{a}");
            assert_eq!(c[k], want, "pixel {i} {j}, alpha {a}");
            seen[n] += 1;
        }
    }
    assert!(seen[0] > 20 && seen[1] > 20, "{seen:?}");
    assert_ne!(s, r);
}

/// pbrt's checkerboard has tex1 where floor(s) + floor(t) is even; `remaproughness` false
/// takes each texel as the alpha itself; a dielectric takes the texture too.
#[test]
fn remaproughness_applies_per_texel() {
    let uv = |s: f32, t: f32| Vec2::new(s / 4.0, t / 4.0);
    let remapped = build(&scene(CHECKER, "\"conductor\" \"texture roughness\" \"r\""));
    assert!((alpha_at_uv(&remapped, uv(0.5, 0.5)) - 0.05).abs() < 1e-7);
    assert!((alpha_at_uv(&remapped, uv(1.5, 0.5)) - 0.5).abs() < 1e-7);
    let raw = build(&scene(
        CHECKER,
        "\"conductor\" \"texture roughness\" \"r\" \"bool remaproughness\" false",
    ));
    assert_eq!(alpha_at_uv(&raw, uv(0.5, 0.5)), 0.0025);
    assert_eq!(alpha_at_uv(&raw, uv(1.5, 1.5)), 0.0025);
    assert_eq!(alpha_at_uv(&raw, uv(0.5, 1.5)), 0.25);
    let glass = build(&scene(
        CHECKER,
        "\"dielectric\" \"texture uroughness\" \"r\" \"texture vroughness\" \"r\"",
    ));
    assert!((alpha_at_uv(&glass, uv(2.5, 3.5)) - 0.5).abs() < 1e-7);
    // A constant float texture is its value; a texture of alphas all below 1e-3 is smooth.
    let constant = build(&scene(
        "Texture \"r\" \"float\" \"constant\" \"float value\" 0.09",
        "\"conductor\" \"texture roughness\" \"r\"",
    ));
    let Bsdf::Conductor(c) = constant.materials[0].bsdf else {
        panic!()
    };
    assert!((c.roughness.unwrap().alpha_x() - 0.3).abs() < 1e-6);
    let smooth = build(&scene(
        "Texture \"r\" \"float\" \"checkerboard\" \"float tex1\" 0 \"float tex2\" 1e-7",
        "\"conductor\" \"texture roughness\" \"r\"",
    ));
    assert!(smooth.materials.iter().all(|m| m.textures.is_none()));
}

/// A grey 8-bit image map (linear encoding) gives each texel's roughness, remapped.
#[test]
fn a_grey_image_map_gives_the_texels_roughness() {
    let d = dir("imagemap");
    let mut img = image::RgbImage::new(2, 1);
    img.put_pixel(0, 0, image::Rgb([255, 255, 255]));
    img.put_pixel(1, 0, image::Rgb([64, 64, 64]));
    img.save(d.join("grey.png")).unwrap();
    img.put_pixel(1, 0, image::Rgb([64, 0, 64]));
    img.save(d.join("colour.png")).unwrap();
    let text = |file: &str| {
        scene(
            &format!("Texture \"r\" \"float\" \"imagemap\" \"string filename\" \"{file}\" \"string filter\" \"point\" \"string encoding\" \"linear\""),
            "\"conductor\" \"texture roughness\" \"r\"",
        )
    };
    let (b, _) = load(&d, &text("grey.png")).unwrap();
    let scene = b.build().unwrap();
    assert_eq!(alpha_at_uv(&scene, Vec2::new(0.25, 0.5)), 1.0);
    let want = (64.0f32 / 255.0).sqrt();
    assert!((alpha_at_uv(&scene, Vec2::new(0.75, 0.5)) - want).abs() < 1e-6);
    let Err(e) = load(&d, &text("colour.png")) else {
        panic!("a coloured roughness image loaded")
    };
    assert!(e.to_string().contains("is not grey"), "{e}");
}

#[test]
fn roughness_textures_ppm_cannot_render_are_errors_naming_them() {
    let cases: &[(&str, &str, &str)] = &[
        (
            CHECKER,
            "\"coateddiffuse\" \"texture roughness\" \"r\"",
            "a roughness texture on coateddiffuse is not supported yet",
        ),
        (
            "Texture \"r\" \"float\" \"constant\" \"float value\" 0.1\nTexture \"q\" \"float\" \"constant\" \"float value\" 0.1",
            "\"conductor\" \"texture uroughness\" \"r\" \"texture vroughness\" \"q\"",
            "anisotropic roughness (uroughness and vroughness not the same texture)",
        ),
        (
            CHECKER,
            "\"conductor\" \"texture uroughness\" \"r\" \"float vroughness\" 0.1",
            "anisotropic roughness",
        ),
        (
            "Texture \"r\" \"spectrum\" \"checkerboard\"",
            "\"conductor\" \"texture roughness\" \"r\"",
            "scene.pbrt:7:22: Material \"conductor\": \"texture roughness\": texture \"r\" (spectrum \"checkerboard\" at ",
        ),
        (
            "Texture \"r\" \"float\" \"scale\"",
            "\"dielectric\" \"texture roughness\" \"r\"",
            "scene.pbrt:6:1) is not supported yet as a roughness: float constant, imagemap and checkerboard textures are",
        ),
        (
            "",
            "\"conductor\" \"texture roughness\" \"r\"",
            "no texture \"r\"",
        ),
        (
            "Texture \"r\" \"float\" \"checkerboard\" \"float tex1\" -1",
            "\"conductor\" \"texture roughness\" \"r\"",
            "roughness tex1 -1 is negative",
        ),
    ];
    for (textures, material, want) in cases {
        let Err(e) = load(&dir("errors"), &scene(textures, material)) else {
            panic!("loaded: {material}")
        };
        let e = e.to_string();
        assert!(e.contains(want), "{material}:\n  got  {e}\n  want {want}");
    }
}
