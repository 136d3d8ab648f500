//! Textures in scene format v1 and MTL: bitmap and checkerboard values against Mitsuba 3's
//! (committed table), a textured floor rendered by ppm against Mitsuba 3's image means and
//! the analytic mean, the integrators agreeing on it, MTL `map_Kd`, the errors that name
//! the field and the file, and the fingerprint following the image's content.
//! The Mitsuba values come from scripts/mitsuba/texture_reference.py (never run here).

mod common;

use common::write_files;
use glam::{Vec2, Vec3};
use ppm_core::prelude::*;
use ppm_core::texture::{Bitmap, Checkerboard, Filter, Texture, UvTransform, WrapMode};
use ppm_scene::image_file::read_rgb_image;
use ppm_scene::{content_hash, load_scene, load_scene_builder};
use std::path::{Path, PathBuf};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/textures")
        .join(name)
}

/// Every row of bitmap_values.csv: ppm's bitmap (grid.png decoded by `image_file`) and
/// checkerboard at the same uvs give Mitsuba 3's values: filters, wrap modes, sRGB or raw
/// decoding, the uv transform, and which corner of the image uv (0, 0) is.
#[test]
fn bitmap_and_checkerboard_values_match_mitsuba() {
    let text = std::fs::read_to_string(data("bitmap_values.csv")).unwrap();
    let srgb = read_rgb_image(&data("grid.png"), "test image", false).unwrap();
    let raw = read_rgb_image(&data("grid.png"), "test image", true).unwrap();
    assert_eq!((srgb.width, srgb.height), (4, 3));
    let pair = |s: &str| {
        let v: Vec<f32> = s.split(' ').map(|x| x.parse().unwrap()).collect();
        Vec2::new(v[0], v[1])
    };
    let mut rows = 0;
    for line in text.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        let transform = UvTransform::scale_offset(pair(f[4]), pair(f[5]));
        let texture = match f[0] {
            "bitmap" => {
                let image = if f[3] == "1" { &raw } else { &srgb };
                let filter = match f[1] {
                    "nearest" => Filter::Nearest,
                    _ => Filter::Bilinear,
                };
                let wrap = match f[2] {
                    "repeat" => WrapMode::Repeat,
                    "mirror" => WrapMode::Mirror,
                    _ => WrapMode::Clamp,
                };
                let texels = image.texels.clone();
                Texture::Bitmap(Bitmap::new(4, 3, texels, filter, wrap, transform).unwrap())
            }
            _ => Texture::Checkerboard(Checkerboard {
                color0: Vec3::new(0.8, 0.2, 0.1),
                color1: Vec3::new(0.1, 0.5, 0.9),
                transform,
            }),
        };
        let num = |i: usize| f[i].parse::<f32>().unwrap();
        let uv = Vec2::new(num(6), num(7));
        let want = Vec3::new(num(8), num(9), num(10));
        let got = texture.eval(uv);
        assert!(
            (got - want).abs().max_element() < 2e-5,
            "{line}: ppm gives {got}"
        );
        rows += 1;
    }
    assert!(rows > 300, "{rows} rows");
}

/// 8-bit sRGB decoding of the image file: code 128 is 0.21586 linear, 10 is 0.0030353
/// (the linear segment), 255 is 1; raw keeps code / 255.
#[test]
fn eight_bit_images_are_decoded_from_srgb() {
    let srgb = read_rgb_image(&data("grid.png"), "test image", false).unwrap();
    let raw = read_rgb_image(&data("grid.png"), "test image", true).unwrap();
    // Row 1 (from the top), column 0 is (128, 64, 32); column 1 is (10, 200, 90).
    let t = srgb.texels[4];
    assert!((t.x - 0.215_861).abs() < 1e-5, "{t}");
    assert!((srgb.texels[5].x - 0.003_035_3).abs() < 1e-6);
    assert_eq!(srgb.texels[0], Vec3::new(1.0, 0.0, 0.0));
    assert!((raw.texels[4].x - 128.0 / 255.0).abs() < 1e-6);
}

fn mitsuba_means() -> Vec3 {
    let text = std::fs::read_to_string(data("floor_mitsuba.txt")).unwrap();
    let line = text.lines().find_map(|l| l.strip_prefix("mean ")).unwrap();
    let v: Vec<f32> = line.split(' ').map(|x| x.parse().unwrap()).collect();
    Vec3::new(v[0], v[1], v[2])
}

fn render_mean(scene: &Scene, algorithm: Algorithm, iterations: u32) -> Vec3 {
    let settings = RenderSettings {
        seed: 3,
        ..RenderSettings::for_algorithm(scene, algorithm)
    };
    let mut renderer = Renderer::new(scene, &settings);
    for _ in 0..iterations {
        renderer.iterate(scene);
    }
    let image = renderer.image();
    image.pixels.iter().copied().sum::<Vec3>() / image.pixels.len() as f32
}

/// The textured floor: ppm's path tracer within 1% of Mitsuba 3's per-channel means.
#[test]
fn a_textured_floor_matches_mitsuba() {
    let scene = load_scene(&data("textured_floor.yml")).unwrap().scene;
    let ppm = render_mean(&scene, Algorithm::Path, 64);
    let mitsuba = mitsuba_means();
    eprintln!("textured floor: ppm {ppm}, Mitsuba 3 {mitsuba}");
    let rel = ((ppm - mitsuba) / mitsuba).abs().max_element();
    assert!(rel < 0.01, "ppm {ppm}, Mitsuba 3 {mitsuba}: {rel}");
}

/// pt, ppm, sppm and vcm agree on the textured floor (photon mapping blurs the texture by
/// its radius, which leaves the image mean).
#[test]
fn the_integrators_agree_on_a_textured_floor() {
    let scene = load_scene(&data("textured_floor.yml")).unwrap().scene;
    let pt = render_mean(&scene, Algorithm::Path, 32);
    for algorithm in [Algorithm::Ppm, Algorithm::Sppm, Algorithm::Vcm] {
        let other = render_mean(&scene, algorithm, 16);
        let rel = ((other - pt) / pt).abs().max_element();
        eprintln!("{algorithm:?}: {other} vs pt {pt}");
        assert!(rel < 0.03, "{algorithm:?} {other} vs pt {pt}: {rel}");
    }
}

/// A checkerboard of two albedos under a light from straight above with irradiance pi
/// reflects radiance equal to the albedo, and over many squares the image averages to the
/// mean of the two albedos.
#[test]
fn a_checkerboard_floor_averages_its_two_albedos() {
    let (a, b) = (Vec3::new(0.9, 0.1, 0.5), Vec3::new(0.1, 0.7, 0.3));
    let text = format!(
        "camera: {{ position: [0, 2, 0], look_at: [0, 0, 0], up: [0, 0, -1], fov: 40 }}
resolution: [32, 32]
materials:
  checks:
    type: diffuse
    color: {{ texture: checkerboard, color0: [{}, {}, {}], color1: [{}, {}, {}], scale: [40, 40] }}
objects:
  - {{ type: quad, corner: [-2, 0, 2], edge_u: [4, 0, 0], edge_v: [0, 0, -4], material: checks }}
lights:
  - {{ type: directional, direction: [0, -1, 0], irradiance: [3.14159265, 3.14159265, 3.14159265] }}
",
        a.x, a.y, a.z, b.x, b.y, b.z
    );
    let dir = write_files("checkerboard_floor", &[("floor.yml", &text)]);
    let scene = load_scene(&dir.join("floor.yml")).unwrap().scene;
    let mean = render_mean(&scene, Algorithm::Path, 64);
    let want = 0.5 * (a + b);
    let rel = ((mean - want) / want).abs().max_element();
    assert!(rel < 0.01, "{mean} vs {want}");
}

const SCENE_HEAD: &str =
    "camera: { position: [0, 2, 0], look_at: [0, 0, 0], up: [0, 0, -1], fov: 40 }
objects:
  - { type: quad, corner: [-1, 0, 1], edge_u: [2, 0, 0], edge_v: [0, 0, -2], material: m }
";

fn error_of(files: &[(&str, &str)], test: &str) -> String {
    let dir = write_files(test, files);
    match load_scene_builder(&dir.join("s.yml")) {
        Ok(_) => panic!("no error"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn a_missing_or_broken_image_is_an_error_naming_the_field_and_file() {
    let scene = format!(
        "{SCENE_HEAD}materials:\n  m: {{ type: diffuse, color: {{ texture: bitmap, file: wood.png }} }}\n"
    );
    let e = error_of(&[("s.yml", &scene)], "texture_missing");
    assert!(
        e.contains("wood.png") && e.contains("materials.m.color"),
        "{e}"
    );
    let e = error_of(
        &[("s.yml", &scene), ("wood.png", "not a png")],
        "texture_broken",
    );
    assert!(
        e.contains("wood.png") && e.contains("materials.m.color"),
        "{e}"
    );
    // A bitmap without a file, and a field that does not apply.
    let e = error_of(
        &[(
            "s.yml",
            &format!(
                "{SCENE_HEAD}materials:\n  m: {{ type: diffuse, color: {{ texture: bitmap }} }}\n"
            ),
        )],
        "texture_no_file",
    );
    assert!(e.contains("materials.m.color") && e.contains("file"), "{e}");
    let e = error_of(
        &[(
            "s.yml",
            &format!("{SCENE_HEAD}materials:\n  m: {{ type: diffuse, color: {{ texture: checkerboard, wrap: clamp }} }}\n"),
        )],
        "texture_wrong_field",
    );
    assert!(e.contains("wrap"), "{e}");
}

fn png(path: &Path, pixels: &[[u8; 3]], width: u32) {
    let height = pixels.len() as u32 / width;
    let image = image::RgbImage::from_fn(width, height, |x, y| {
        image::Rgb(pixels[(y * width + x) as usize])
    });
    image.save(path).unwrap();
}

/// The fingerprint changes with the texture's image content, and constant materials keep
/// theirs whatever the meshes' uvs.
#[test]
fn the_fingerprint_follows_the_image_content() {
    let scene = format!(
        "{SCENE_HEAD}materials:\n  m: {{ type: diffuse, color: {{ texture: bitmap, file: t.png }} }}\n"
    );
    let dir = write_files("texture_hash", &[("s.yml", &scene)]);
    png(&dir.join("t.png"), &[[10, 20, 30], [40, 50, 60]], 2);
    let hash = || content_hash(&load_scene_builder(&dir.join("s.yml")).unwrap().0);
    let first = hash();
    assert_eq!(first, hash());
    png(&dir.join("t.png"), &[[10, 20, 30], [40, 50, 61]], 2);
    assert_ne!(first, hash());
    let checker = format!(
        "{SCENE_HEAD}materials:\n  m: {{ type: diffuse, color: {{ texture: checkerboard }} }}\n"
    );
    let scaled = format!(
        "{SCENE_HEAD}materials:\n  m: {{ type: diffuse, color: {{ texture: checkerboard, scale: [2, 2] }} }}\n"
    );
    let constant =
        format!("{SCENE_HEAD}materials:\n  m: {{ type: diffuse, color: [0.3, 0.3, 0.3] }}\n");
    let hash_of = |text: &str, name: &str| {
        let dir = write_files(name, &[("s.yml", text)]);
        content_hash(&load_scene_builder(&dir.join("s.yml")).unwrap().0)
    };
    let (a, b, c) = (
        hash_of(&checker, "hash_checker"),
        hash_of(&scaled, "hash_scaled"),
        hash_of(&constant, "hash_constant"),
    );
    assert!(a != b && b != c && a != c);
}

/// MTL `map_Kd`: a bitmap on the diffuse reflectance, relative to the MTL file, with the
/// OBJ's `vt` (v flipped: OBJ's v runs up the image); a missing image names the MTL line.
#[test]
fn mtl_map_kd_loads_as_a_bitmap_texture() {
    let obj = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 0 -1\nvt 0 0\nvt 1 0\nvt 1 1\nusemtl tex\nf 1/1 2/2 3/3\n";
    let mtl = "newmtl tex\nKd 1 1 1\nmap_Kd -s 2 2 1 maps/t.png\n";
    let dir = write_files("mtl_map_kd", &[("a.obj", obj), ("m.mtl", mtl)]);
    std::fs::create_dir_all(dir.join("maps")).unwrap();
    // Top row red, bottom row blue.
    png(&dir.join("maps/t.png"), &[[255, 0, 0], [0, 0, 255]], 1);
    let mut warnings = Vec::new();
    let data = ppm_scene::obj::load_obj(
        &dir.join("a.obj"),
        ppm_scene::obj::ObjMaterials::FromMtl,
        &mut warnings,
    )
    .unwrap();
    let m = &data.materials[0];
    let textures = m.textures.as_ref().expect("a textured material");
    assert_eq!(textures.slots().len(), 1);
    // Nearest to the bottom of the image (v near 1 after the flip of OBJ's v = 0): blue.
    assert_eq!(data.meshes[0].uvs[0], Vec2::new(0.0, 1.0));
    let Texture::Bitmap(b) = &textures.slots()[0].1 else {
        panic!("not a bitmap")
    };
    assert_eq!(
        b.transform,
        UvTransform::scale_offset(Vec2::splat(2.0), Vec2::ZERO)
    );
    // The material's nominal albedo is the image's mean.
    let ppm_core::bsdf::Bsdf::Diffuse(d) = m.bsdf else {
        panic!("not diffuse")
    };
    assert!((d.albedo - Vec3::new(0.5, 0.0, 0.5)).abs().max_element() < 1e-6);
    let bsdf = m.bsdf_at(Vec2::new(0.25, 0.125));
    let ppm_core::bsdf::Bsdf::Diffuse(d) = bsdf else {
        panic!("not diffuse")
    };
    assert!(d.albedo.x > 0.99 && d.albedo.z < 0.01, "{}", d.albedo);
    // A missing image: an error naming it and the MTL file.
    let mtl = "newmtl tex\nmap_Kd nowhere.png\n";
    let dir = write_files("mtl_map_kd_missing", &[("a.obj", obj), ("m.mtl", mtl)]);
    let e = ppm_scene::obj::load_obj(
        &dir.join("a.obj"),
        ppm_scene::obj::ObjMaterials::FromMtl,
        &mut warnings,
    )
    .err()
    .unwrap()
    .to_string();
    assert!(e.contains("nowhere.png") && e.contains("m.mtl:2"), "{e}");
}

/// The same floor as a Mitsuba 3 scene (bitmap nested, checkerboard by `<ref>`), through
/// ppm's importer: at every pixel's hit the BSDF equals the YAML scene's (uv of the turned
/// rectangle, `to_uv`, filtering and wrapping all read as Mitsuba means them).
#[test]
fn the_mitsuba_importer_reads_bitmap_and_checkerboard() {
    let xml = load_scene(&data("textured_floor.xml")).unwrap().scene;
    let yaml = load_scene(&data("textured_floor.yml")).unwrap().scene;
    assert_eq!(
        xml.materials
            .iter()
            .filter(|m| m.textures.is_some())
            .count(),
        2
    );
    // The albedo seen through a pixel; black where the ray misses the floor (the view
    // reaches past its far edge).
    let albedo = |scene: &Scene, ray: &ppm_core::geometry::Ray| match scene.intersect(ray) {
        None => Vec3::ZERO,
        Some(hit) => match scene.bsdf(&hit) {
            ppm_core::bsdf::Bsdf::Diffuse(d) => d.albedo,
            other => panic!("{other:?}"),
        },
    };
    let mut distinct = Vec::new();
    for j in 0..32 {
        for i in 0..32 {
            let film = glam::Vec2::new(i as f32 + 0.3, j as f32 + 0.6);
            let a = albedo(&yaml, &yaml.camera.generate_ray(film));
            let b = albedo(&xml, &xml.camera.generate_ray(film));
            assert!(
                (a - b).abs().max_element() < 1e-4,
                "pixel {i} {j}: {a} vs {b}"
            );
            if !distinct
                .iter()
                .any(|d: &Vec3| (*d - a).abs().max_element() < 1e-3)
            {
                distinct.push(a);
            }
        }
    }
    // The view holds both checkerboard colours and many bitmap values.
    assert!(distinct.len() > 100, "{}", distinct.len());
}

/// A texture ppm does not read, and a missing bitmap file, are errors naming them.
#[test]
fn mitsuba_texture_errors_name_the_plugin_and_file() {
    let xml = |texture: &str| {
        format!(
            r#"<scene version="3.0.0">
  <sensor type="perspective"/>
  <shape type="rectangle"><bsdf type="diffuse">{texture}</bsdf></shape>
</scene>"#
        )
    };
    let load = |name: &str, text: &str| {
        let dir = write_files(name, &[("s.xml", text)]);
        match load_scene_builder(&dir.join("s.xml")) {
            Ok(_) => panic!("no error"),
            Err(e) => e.to_string(),
        }
    };
    let e = load(
        "mitsuba_texture_unknown",
        &xml(r#"<texture type="mesh_attribute" name="reflectance"/>"#),
    );
    assert!(e.contains("mesh_attribute") && e.contains("s.xml"), "{e}");
    let e = load(
        "mitsuba_texture_missing",
        &xml(
            r#"<texture type="bitmap" name="reflectance"><string name="filename" value="gone.png"/></texture>"#,
        ),
    );
    assert!(e.contains("gone.png"), "{e}");
}

/// A gold floor whose roughness is a checkerboard of `alpha` (`{a0}` and `{a1}` replaced),
/// lit from above and seen from above at an angle, with the highlight on the squares.
fn rough_floor(alpha: &str) -> String {
    format!(
        "camera: {{ position: [0, 2, 1.2], look_at: [0, 0, 0], up: [0, 1, 0], fov: 60 }}
resolution: [24, 24]
materials:
  gold: {{ type: roughconductor, material: Au, distribution: ggx, alpha: {alpha} }}
  lamp: {{ type: diffuse, color: [0, 0, 0], emission: [8, 8, 8] }}
objects:
  - {{ type: quad, corner: [-2, 0, 2], edge_u: [4, 0, 0], edge_v: [0, 0, -4], material: gold }}
  - {{ type: quad, corner: [-0.5, 3, -1.5], edge_u: [1, 0, 0], edge_v: [0, 0, 1], material: lamp }}
"
    )
}

/// The microfacet roughness of the BSDF at the film point `film` (`None`: the ray misses).
fn alpha_at(scene: &Scene, film: glam::Vec2) -> Option<f32> {
    let hit = scene.intersect(&scene.camera.generate_ray(film))?;
    match scene.bsdf(&hit) {
        ppm_core::bsdf::Bsdf::Conductor(c) => c.roughness.map(|d| d.alpha_x()),
        other => panic!("{other:?}"),
    }
}

/// A checkerboard roughness renders, pixel for pixel, as the render with the constant
/// roughness of the square the pixel sees (same seed, so the same samples: bit for bit on
/// every pixel whose footprint lies inside one square), and both roughnesses are seen.
#[test]
fn a_checkerboard_roughness_renders_as_the_constant_roughnesses() {
    let checker = "{ texture: checkerboard, color0: [0.05, 0.05, 0.05], color1: [0.5, 0.5, 0.5] }";
    let dir = write_files(
        "rough_checker",
        &[
            ("checker.yml", &rough_floor(checker)),
            ("smooth.yml", &rough_floor("0.05")),
            ("rough.yml", &rough_floor("0.5")),
        ],
    );
    let load = |name: &str| load_scene(&dir.join(name)).unwrap().scene;
    let (checker, smooth, rough) = (load("checker.yml"), load("smooth.yml"), load("rough.yml"));
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
                .map(|(x, y)| alpha_at(&checker, glam::Vec2::new(i as f32 + x, j as f32 + y)));
            let Some(a) = corners[0] else { continue };
            if corners.iter().any(|x| *x != Some(a)) {
                continue;
            }
            let k = (j * 24 + i) as usize;
            let (want, n) = if a == 0.05 { (s[k], 0) } else { (r[k], 1) };
            assert_eq!(c[k], want, "pixel {i} {j}, alpha {a}");
            seen[n] += 1;
        }
    }
    assert!(seen[0] > 20 && seen[1] > 20, "{seen:?}");
    // The two constant renders differ where the test compares them.
    assert_ne!(s, r);
}

/// Mitsuba's `alpha` given a checkerboard reads as the YAML's; roughplastic's is an error.
#[test]
fn the_mitsuba_importer_reads_a_roughness_texture() {
    let xml = |plugin: &str| {
        format!(
            r#"<scene version="3.0.0">
    <sensor type="perspective">
        <film type="hdrfilm">
            <integer name="width" value="8"/>
            <integer name="height" value="8"/>
        </film>
    </sensor>
    <shape type="rectangle">
        <bsdf type="{plugin}">
            <texture type="checkerboard" name="alpha">
                <rgb name="color0" value="0.05, 0.05, 0.05"/>
                <rgb name="color1" value="0.5, 0.5, 0.5"/>
            </texture>
        </bsdf>
    </shape>
    <emitter type="point">
        <point name="position" x="0" y="0" z="2"/>
    </emitter>
</scene>"#
        )
    };
    let dir = write_files(
        "mitsuba_rough_checker",
        &[
            ("conductor.xml", &xml("roughconductor")),
            ("dielectric.xml", &xml("roughdielectric")),
            ("plastic.xml", &xml("roughplastic")),
        ],
    );
    for name in ["conductor.xml", "dielectric.xml"] {
        let (builder, _) = load_scene_builder(&dir.join(name)).unwrap();
        let scene = builder.build().unwrap();
        let m = scene
            .materials
            .iter()
            .find(|m| m.textures.is_some())
            .expect("a textured material");
        let alpha = |uv: glam::Vec2| match m.bsdf_at(uv) {
            ppm_core::bsdf::Bsdf::Conductor(c) => c.roughness.unwrap().alpha_x(),
            ppm_core::bsdf::Bsdf::Dielectric(d) => d.roughness.unwrap().alpha_x(),
            other => panic!("{other:?}"),
        };
        assert_eq!(alpha(glam::Vec2::new(0.25, 0.25)), 0.05, "{name}");
        assert_eq!(alpha(glam::Vec2::new(0.75, 0.25)), 0.5, "{name}");
    }
    let Err(e) = load_scene_builder(&dir.join("plastic.xml")) else {
        panic!("a roughness texture on roughplastic loaded");
    };
    let e = e.to_string();
    assert!(
        e.contains("checkerboard") && e.contains("roughplastic"),
        "{e}"
    );
}

/// YAML: a roughness texture on roughplastic is an error naming the field.
#[test]
fn a_roughness_texture_on_roughplastic_is_an_error() {
    let e = error_of(
        &[(
            "s.yml",
            &format!("{SCENE_HEAD}materials:\n  m: {{ type: roughplastic, alpha: {{ texture: checkerboard }} }}\n"),
        )],
        "roughplastic_alpha_texture",
    );
    assert!(
        e.contains("materials.m.alpha") && e.contains("roughplastic"),
        "{e}"
    );
}
