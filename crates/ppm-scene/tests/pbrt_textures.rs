//! pbrt-v4 `imagemap` and `checkerboard` textures as a diffuse reflectance: the texel each
//! uv reads under pbrt's conventions (image lookups at (s, 1 - t), unit checker squares
//! with tex1 where floor(s) + floor(t) is even), and the shapes that cannot carry them.

use glam::{Vec2, Vec3};
use ppm_core::scene::SceneBuilder;
use ppm_core::texture::Texture;
use ppm_scene::pbrt::parse_pbrt;
use ppm_scene::LoadError;
use std::path::{Path, PathBuf};

/// A directory of its own under the target's temporary folder.
fn dir(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("pbrt-textures")
        .join(name);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A unit quad in z = 0 with uv = xy, of a diffuse material whose reflectance is texture
/// "t", declared by `texture` (the arguments after `Texture "t" "spectrum"`).
fn scene(texture: &str, shape: &str) -> String {
    format!(
        "Scale -1 1 1\nLookAt 0.5 0.5 3  0.5 0.5 0  0 1 0\nCamera \"perspective\"\n\
         Film \"rgb\" \"integer xresolution\" 8 \"integer yresolution\" 8\nWorldBegin\n\
         LightSource \"point\" \"point3 from\" [0 0 2]\n\
         Texture \"t\" \"spectrum\" {texture}\n\
         Material \"diffuse\" \"texture reflectance\" \"t\"\n{shape}"
    )
}

const QUAD: &str = "Shape \"trianglemesh\" \"point3 P\" [0 0 0  1 0 0  1 1 0  0 1 0] \
     \"integer indices\" [0 1 2  0 2 3] \"point2 uv\" [0 0  1 0  1 1  0 1]";

fn load(dir: &Path, text: &str) -> Result<(SceneBuilder, Vec<String>), LoadError> {
    parse_pbrt(text, &dir.join("scene.pbrt"))
}

/// The quad's texture.
fn texture(b: &SceneBuilder) -> Texture {
    let m = &b.materials[b.meshes[0].materials[0] as usize];
    m.textures.as_ref().expect("textured").slots()[0].1.clone()
}

/// A 2 x 2 PNG: top row red, green; bottom row blue, white (8-bit 0 or 255: the same
/// linear values under either encoding).
fn write_png(path: &Path) {
    let mut img = image::RgbImage::new(2, 2);
    img.put_pixel(0, 0, image::Rgb([255, 0, 0]));
    img.put_pixel(1, 0, image::Rgb([0, 255, 0]));
    img.put_pixel(0, 1, image::Rgb([0, 0, 255]));
    img.put_pixel(1, 1, image::Rgb([255, 255, 255]));
    img.save(path).unwrap();
}

const RED: Vec3 = Vec3::X;
const GREEN: Vec3 = Vec3::Y;
const BLUE: Vec3 = Vec3::Z;
const WHITE: Vec3 = Vec3::ONE;

#[test]
fn an_imagemap_reads_the_texel_at_s_and_one_minus_t() {
    let d = dir("imagemap");
    write_png(&d.join("rgbw.png"));
    let (b, w) = load(
        &d,
        &scene(
            "\"imagemap\" \"string filename\" \"rgbw.png\" \"string filter\" \"point\"",
            QUAD,
        ),
    )
    .unwrap();
    assert!(w.is_empty(), "{w:?}");
    let t = texture(&b);
    // t grows upward: the bottom row at t < 1/2.
    for (uv, want) in [
        ((0.25, 0.25), BLUE),
        ((0.75, 0.25), WHITE),
        ((0.25, 0.75), RED),
        ((0.75, 0.75), GREEN),
    ] {
        assert_eq!(t.eval(Vec2::new(uv.0, uv.1)), want, "uv {uv:?}");
    }
    // s = 2 u + 0.5 (repeat), t = v + 0.5; scale halves every texel.
    let (b, _) = load(
        &d,
        &scene(
            "\"imagemap\" \"string filename\" \"rgbw.png\" \"string filter\" \"point\" \
             \"float uscale\" 2 \"float udelta\" 0.5 \"float vdelta\" 0.5 \"float scale\" 0.5",
            QUAD,
        ),
    )
    .unwrap();
    let t = texture(&b);
    // u 0.1: s 0.7 (right column); v 0.1: t 0.6 (top row).
    assert_eq!(t.eval(Vec2::new(0.1, 0.1)), GREEN * 0.5);
    // u 0.4: s 1.3 -> 0.3 (left column); v 0.7: t 1.2 -> 0.2 (bottom row).
    assert_eq!(t.eval(Vec2::new(0.4, 0.7)), BLUE * 0.5);
}

#[test]
fn a_checkerboard_is_tex1_where_floor_s_plus_floor_t_is_even() {
    let d = dir("checkerboard");
    let (b, _) = load(
        &d,
        &scene(
            "\"checkerboard\" \"rgb tex1\" [0.8 0.1 0.1] \"rgb tex2\" [0.1 0.1 0.8] \
             \"float uscale\" 4 \"float vscale\" 4",
            QUAD,
        ),
    )
    .unwrap();
    let t = texture(&b);
    let (tex1, tex2) = (Vec3::new(0.8, 0.1, 0.1), Vec3::new(0.1, 0.1, 0.8));
    for (uv, want) in [
        ((0.1, 0.1), tex1), // (0.4, 0.4): 0 + 0
        ((0.3, 0.1), tex2), // (1.2, 0.4): 1 + 0
        ((0.3, 0.3), tex1), // (1.2, 1.2): 1 + 1
        ((0.1, 0.6), tex1), // (0.4, 2.4): 0 + 2
        ((0.9, 0.6), tex2), // (3.6, 2.4): 3 + 2
    ] {
        assert_eq!(t.eval(Vec2::new(uv.0, uv.1)), want, "uv {uv:?}");
    }
    // Defaults: tex1 1, tex2 0; the BSDF's nominal colour is the mean.
    let (b, _) = load(&d, &scene("\"checkerboard\"", QUAD)).unwrap();
    assert_eq!(texture(&b).eval(Vec2::new(0.5, 0.5)), Vec3::ONE);
    assert_eq!(texture(&b).eval(Vec2::new(1.5, 0.5)), Vec3::ZERO);
}

#[test]
fn what_cannot_carry_a_texture_is_an_error() {
    let d = dir("errors");
    write_png(&d.join("rgbw.png"));
    let cases = [
        (
            "\"checkerboard\"",
            "Shape \"sphere\"",
            "this shape has no uv",
        ),
        (
            "\"checkerboard\" \"integer dimension\" 3",
            QUAD,
            "dimension 3 is not supported yet",
        ),
        (
            "\"imagemap\" \"string filename\" \"rgbw.png\" \"string wrap\" \"black\"",
            QUAD,
            "wrap \"black\" is not supported yet",
        ),
        (
            "\"imagemap\" \"string filename\" \"rgbw.png\" \"float scale\" 2",
            QUAD,
            "ppm takes reflectances in [0, 1]",
        ),
        (
            "\"checkerboard\" \"string mapping\" \"spherical\"",
            QUAD,
            "mapping \"spherical\" is not supported yet",
        ),
    ];
    for (texture, shape, want) in cases {
        let Err(e) = load(&d, &scene(texture, shape)) else {
            panic!("loaded {texture} {shape}")
        };
        let e = e.to_string();
        assert!(e.contains(want), "{texture}:\n  got  {e}\n  want {want}");
    }
}

/// Through the camera (and the importer's world mirror, with and without pbrt's
/// `Scale -1 1 1`), the image stands upright on a quad whose uv is its xy, as pbrt shows it:
/// the file's top row (red, green) at the quad's top. The camera looks down -z at the quad's
/// centre; with `Scale -1 1 1` +x is on the image's right, without it on the left.
#[test]
fn an_imagemap_stands_upright_on_a_uv_quad() {
    use ppm_core::bsdf::Bsdf;
    let d = dir("upright");
    write_png(&d.join("rgbw.png"));
    for (transform, x_right) in [("Scale -1 1 1", true), ("", false)] {
        let text = scene(
            "\"imagemap\" \"string filename\" \"rgbw.png\" \"string filter\" \"point\"",
            QUAD,
        )
        .replacen("Scale -1 1 1", transform, 1);
        let scene = load(&d, &text).unwrap().0.build().unwrap();
        // Film 8 x 8, fov 90 at distance 3: the quad spans pixels 3.33 to 4.67.
        let albedo = |film: Vec2| {
            let hit = scene.intersect(&scene.camera.generate_ray(film)).unwrap();
            match scene.bsdf(&hit) {
                Bsdf::Diffuse(b) => b.albedo,
                other => panic!("{other:?}"),
            }
        };
        let (left, right) = (3.6, 4.4);
        let (top, bottom) = (3.6, 4.4);
        let (small_x, large_x) = if x_right {
            (left, right)
        } else {
            (right, left)
        };
        assert_eq!(albedo(Vec2::new(small_x, top)), RED, "`{transform}`");
        assert_eq!(albedo(Vec2::new(large_x, top)), GREEN, "`{transform}`");
        assert_eq!(albedo(Vec2::new(small_x, bottom)), BLUE, "`{transform}`");
        assert_eq!(albedo(Vec2::new(large_x, bottom)), WHITE, "`{transform}`");
    }
}

/// A bilinear patch with `uv` and a PLY mesh with u, v carry a texture: the uv arrive per
/// vertex as given (pbrt's conventions then apply in the lookup). A patch whose uv is not
/// affine is named in a warning (two triangles interpolate it linearly, pbrt bilinearly).
#[test]
fn bilinear_patches_and_ply_meshes_carry_their_uv() {
    let d = dir("uv_shapes");
    let checker = "\"checkerboard\"";
    let patch = "Shape \"bilinearmesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0  1 1 0] \
                 \"integer indices\" [0 1 2 3] \"point2 uv\" [0 0  2 0  0 2  2 2]";
    let (b, warnings) = load(&d, &scene(checker, patch)).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    let uvs = &b.meshes[0].uvs;
    assert_eq!(
        uvs,
        &[0.0, 0.0, 2.0, 0.0, 0.0, 2.0, 2.0, 2.0]
            .chunks(2)
            .map(|c| Vec2::new(c[0], c[1]))
            .collect::<Vec<_>>()
    );
    let warped = patch.replace("[0 0  2 0  0 2  2 2]", "[0 0  2 0  0 2  3 3]");
    let (_, warnings) = load(&d, &scene(checker, &warped)).unwrap();
    assert!(
        warnings.len() == 1 && warnings[0].contains("not affine"),
        "{warnings:?}"
    );
    std::fs::write(
        d.join("quad.ply"),
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n\
         property float z\nproperty float u\nproperty float v\nelement face 1\n\
         property list uchar int vertex_indices\nend_header\n\
         0 0 0 0 0\n1 0 0 0.5 0\n1 1 0 0.5 0.25\n0 1 0 0 0.25\n4 0 1 2 3\n",
    )
    .unwrap();
    let ply = "Shape \"plymesh\" \"string filename\" \"quad.ply\"";
    let (b, warnings) = load(&d, &scene(checker, ply)).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!(b.meshes[0].uvs[2], Vec2::new(0.5, 0.25));
    // Without uv in the file, the texture has nothing to read: an error naming the shape.
    std::fs::write(
        d.join("bare.ply"),
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
         property float z\nelement face 1\nproperty list uchar int vertex_indices\n\
         end_header\n0 0 0\n1 0 0\n1 1 0\n3 0 1 2\n",
    )
    .unwrap();
    let e = load(&d, &scene(checker, &ply.replace("quad", "bare")))
        .err()
        .unwrap()
        .to_string();
    assert!(
        e.contains("Shape \"plymesh\"") && e.contains("no uv"),
        "{e}"
    );
}
