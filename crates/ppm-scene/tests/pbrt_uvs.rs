//! pbrt-v4's uv on shapes whose file gives none, under a textured material: a
//! `trianglemesh` gets (0, 0), (1, 0), (1, 1) at each triangle's vertices; a `disk` u = phi /
//! 2 pi, v = (radius - r) / radius; a `cylinder` u = phi / 2 pi, v = (z - zmin) / (zmax -
//! zmin) (pbrt-v4 shapes.h). Each test traces a ray to a chosen point of the built scene and
//! compares the uv a texture reads there with the formula at that point in the shape's
//! object space.

use glam::{Vec2, Vec3};
use ppm_core::geometry::Ray;
use ppm_core::scene::Scene;
use ppm_scene::pbrt::parse_pbrt;
use std::f32::consts::TAU;
use std::path::Path;

/// A right-handed camera (no world mirror), a checkerboard texture "t" as the diffuse
/// reflectance, and `shapes`.
fn scene(shapes: &str) -> String {
    format!(
        "Scale -1 1 1\nLookAt 0 0 10  0 0 0  0 1 0\nCamera \"perspective\"\n\
         Film \"rgb\" \"integer xresolution\" 8 \"integer yresolution\" 8\nWorldBegin\n\
         LightSource \"point\" \"point3 from\" [0 0 5]\n\
         Texture \"t\" \"spectrum\" \"checkerboard\"\n\
         Material \"diffuse\" \"texture reflectance\" \"t\"\n{shapes}"
    )
}

fn build(shapes: &str) -> Scene {
    let (b, w) = parse_pbrt(&scene(shapes), Path::new("uv.pbrt")).unwrap();
    assert!(w.is_empty(), "{w:?}");
    b.build().unwrap()
}

/// The uv a texture reads where the ray from world point `from` along `dir` first hits.
fn uv_seen(scene: &Scene, from: Vec3, dir: Vec3) -> Vec2 {
    let hit = scene
        .intersect(&Ray::new(from - scene.origin, dir.normalize()))
        .expect("a hit");
    scene.geometry.texture_uv(&hit)
}

fn assert_uv(what: &str, got: Vec2, want: Vec2, tolerance: f32) {
    assert!(
        (got - want).abs().max_element() <= tolerance,
        "{what}: uv {got}, pbrt's {want}"
    );
}

#[test]
fn a_trianglemesh_without_uv_gets_pbrts_per_triangle_uv() {
    // Two triangles of the unit square, moved to x, y in [3, 4] and mirrored in z (a
    // mirroring transform reorders each triangle's vertices in ppm: the uv must follow).
    let s = build(
        "Translate 3 3 0\nScale 1 1 -1\nShape \"trianglemesh\" \"point3 P\" [0 0 0  1 0 0  1 1 0  0 1 0] \
         \"integer indices\" [0 1 2  0 2 3]",
    );
    // Barycentrics (b0, b1, b2) of the point in its triangle; pbrt's uv = (b1 + b2, b2).
    // First triangle (P0, P1, P2): p = b1 (1, 0) + b2 (1, 1), so b2 = y, b1 = x - y.
    for (x, y) in [(0.6, 0.2), (0.9, 0.85), (0.3, 0.1)] {
        let (b1, b2) = (x - y, y);
        let got = uv_seen(&s, Vec3::new(3.0 + x, 3.0 + y, 5.0), -Vec3::Z);
        assert_uv("first triangle", got, Vec2::new(b1 + b2, b2), 1e-5);
    }
    // Second (P0, P2, P3): p = b1 (1, 1) + b2 (0, 1), so b1 = x, b2 = y - x.
    for (x, y) in [(0.25, 0.75), (0.1, 0.9)] {
        let (b1, b2) = (x, y - x);
        let got = uv_seen(&s, Vec3::new(3.0 + x, 3.0 + y, 5.0), -Vec3::Z);
        assert_uv("second triangle", got, Vec2::new(b1 + b2, b2), 1e-5);
    }
}

#[test]
fn a_disk_has_pbrts_polar_uv() {
    let radius = 2.0;
    let s = build("Translate 1 -1 0\nShape \"disk\" \"float radius\" 2 \"float height\" 0.5");
    for (r, degrees) in [(1.5f32, 40.0f32), (0.5, 200.0), (1.9, 359.0), (1.0, 1.0)] {
        let phi = degrees.to_radians();
        let p = Vec3::new(1.0 + r * phi.cos(), -1.0 + r * phi.sin(), 0.5);
        let got = uv_seen(&s, p + Vec3::Z * 4.0, -Vec3::Z);
        // Linear interpolation over the fan's triangles: u within 1 / (2 * 128) of pbrt's
        // near the centre, v within the polygon's chord error.
        assert_uv(
            &format!("r {r}, phi {degrees}"),
            got,
            Vec2::new(phi / TAU, (radius - r) / radius),
            1.0 / 256.0,
        );
    }
}

#[test]
fn a_cylinder_has_pbrts_uv() {
    let s = build(
        "Shape \"cylinder\" \"float radius\" 1 \"float zmin\" 2 \"float zmax\" -1 \"float phimax\" 360",
    );
    for (degrees, z) in [(100.0f32, 0.5f32), (10.0, -0.9), (350.0, 1.9)] {
        let phi = degrees.to_radians();
        let radial = Vec3::new(phi.cos(), phi.sin(), 0.0);
        let got = uv_seen(&s, radial * 3.0 + Vec3::Z * z, -radial);
        // zmin is the smaller of the two: v = (z + 1) / 3.
        assert_uv(
            &format!("phi {degrees}, z {z}"),
            got,
            Vec2::new(phi / TAU, (z + 1.0) / 3.0),
            1e-4,
        );
    }
}

/// Untextured shapes keep the vertices they always had (no seam copies, no unshared
/// triangles), so their scenes render and hash as before.
#[test]
fn untextured_shapes_are_unchanged() {
    let text = "Scale -1 1 1\nLookAt 0 0 10  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n\
                Shape \"disk\"\nShape \"cylinder\"\n\
                Shape \"trianglemesh\" \"point3 P\" [0 0 0  1 0 0  1 1 0  0 1 0] \"integer indices\" [0 1 2  0 2 3]";
    let (b, _) = parse_pbrt(text, Path::new("plain.pbrt")).unwrap();
    let counts: Vec<(usize, usize)> = b
        .meshes
        .iter()
        .map(|m| (m.positions.len(), m.uvs.len()))
        .collect();
    assert_eq!(counts, [(129, 0), (256, 0), (4, 0)]);
}

/// Where ppm has no pbrt uv to give, a texture is an error naming the shape.
#[test]
fn shapes_without_pbrts_uv_are_errors() {
    for (kind, shape) in [
        ("sphere", "Shape \"sphere\""),
        (
            "bilinearmesh",
            "Shape \"bilinearmesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0  1 1 0]",
        ),
    ] {
        let e = parse_pbrt(&scene(shape), Path::new("uv.pbrt"))
            .err()
            .expect("an error")
            .to_string();
        assert!(
            e.contains("uv.pbrt:9") && e.contains("no uv") && e.contains(kind),
            "{shape}: {e}"
        );
    }
}
