//! The texture coordinates a hit reports (`Geometry::texture_uv`): vertex uvs interpolated
//! by the barycentrics, the barycentrics themselves without uvs, a quad's (s, t) and a
//! sphere's (phi / 2 pi, theta / pi) against the values Mitsuba 3 reports for the same
//! points (from its `SurfaceInteraction.uv`, scalar_rgb variant).

use glam::{Vec2, Vec3};
use ppm_core::geometry::{Geometry, Ray, Sphere, TriangleMesh};

fn close(a: Vec2, b: Vec2, tol: f32) -> bool {
    (a - b).abs().max_element() < tol
}

/// A ray straight down -z onto the plane z = 0 at (x, y).
fn down(x: f32, y: f32) -> Ray {
    Ray::new(Vec3::new(x, y, 5.0), -Vec3::Z)
}

#[test]
fn triangle_uvs_are_interpolated_by_the_barycentrics() {
    let positions = vec![Vec3::ZERO, Vec3::X, Vec3::Y];
    let mut textured = TriangleMesh::new(positions.clone(), vec![[0, 1, 2]], 0);
    textured.uvs = vec![
        Vec2::new(0.1, 0.2),
        Vec2::new(0.5, 0.2),
        Vec2::new(0.1, 0.9),
    ];
    // A second mesh without uvs, 10 units away, in the same geometry.
    let far = positions.iter().map(|p| *p + Vec3::X * 10.0).collect();
    let plain = TriangleMesh::new(far, vec![[0, 1, 2]], 0);
    // An exact duplicate of the plain triangle: dropped, and the uvs of the others must
    // stay with their triangles.
    let duplicate = plain.clone();
    let g = Geometry::new(&[duplicate, textured, plain], &[]);
    assert_eq!(g.duplicate_triangles(), 1);
    for (x, y) in [(0.25f32, 0.25f32), (0.6, 0.1), (0.05, 0.9)] {
        let hit = g.intersect(&down(x, y)).unwrap();
        // On this triangle b1 = x, b2 = y: uv = (1 - x - y) uv0 + x uv1 + y uv2.
        let want = Vec2::new(0.1 + 0.4 * x, 0.2 + 0.7 * y);
        assert!(
            close(g.texture_uv(&hit), want, 1e-6),
            "{x} {y}: {}",
            g.texture_uv(&hit)
        );
        // Without uvs: the barycentrics (Mitsuba's default).
        let hit = g.intersect(&down(10.0 + x, y)).unwrap();
        assert!(close(g.texture_uv(&hit), Vec2::new(x, y), 1e-6));
    }
}

#[test]
fn quads_take_their_edge_parameters_as_uv() {
    // Mitsuba's rectangle: [-1, 1]^2, uv = ((x + 1) / 2, (y + 1) / 2).
    let quad = TriangleMesh::quad(Vec3::new(-1.0, -1.0, 0.0), Vec3::X * 2.0, Vec3::Y * 2.0, 0);
    let g = Geometry::new(&[quad], &[]);
    // Mitsuba 3: the rectangle hit at (0.5, -0.5) has uv (0.75, 0.25).
    for (x, y) in [(0.5f32, -0.5f32), (-0.9, 0.3), (0.2, 0.95)] {
        let hit = g.intersect(&down(x, y)).unwrap();
        let want = Vec2::new((x + 1.0) / 2.0, (y + 1.0) / 2.0);
        assert!(close(g.texture_uv(&hit), want, 1e-6));
    }
}

#[test]
fn sphere_uvs_match_mitsuba() {
    let g = Geometry::new(&[], &[Sphere::new(Vec3::ZERO, 1.0, 0)]);
    // (ray origin, direction, Mitsuba 3's uv at the hit).
    let cases = [
        (
            Vec3::new(5.0, 0.0, 0.3),
            -Vec3::X,
            Vec2::new(0.0, 0.403_013),
        ),
        (Vec3::new(0.0, 5.0, 0.0), -Vec3::Y, Vec2::new(0.25, 0.5)),
        (
            Vec3::new(-5.0, 0.001, 0.0),
            Vec3::X,
            Vec2::new(0.499_841, 0.5),
        ),
        (Vec3::new(0.0, 0.0, 5.0), -Vec3::Z, Vec2::new(0.0, 0.0)),
    ];
    for (o, d, want) in cases {
        let hit = g.intersect(&Ray::new(o, d)).unwrap();
        let uv = g.texture_uv(&hit);
        assert!(close(uv, want, 2e-4), "{o}: {uv} vs {want}");
    }
    // Below the equator on the -y side: phi in (pi, 2 pi), theta > pi / 2.
    let hit = g
        .intersect(&Ray::new(Vec3::new(0.0, -5.0, -0.5), Vec3::Y))
        .unwrap();
    let uv = g.texture_uv(&hit);
    let theta = (-0.5f32).acos();
    assert!(
        close(uv, Vec2::new(0.75, theta / std::f32::consts::PI), 1e-5),
        "{uv}"
    );
}
