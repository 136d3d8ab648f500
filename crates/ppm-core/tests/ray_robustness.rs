//! Rays that must not slip through or re-hit a surface: watertightness on shared edges and
//! vertices, rays leaving the corners of a closed box, and self-intersection of spawned rays
//! at several scales and far from the origin.

mod geometry_common;

use geometry_common::{closed_box, random_point, same_hit, test_scene};
use glam::{DVec3, Vec3};
use ppm_core::geometry::{intersect_triangle, Geometry, Ray, Sphere, Triangle, TriangleMesh};
use ppm_core::sampling::{uniform_sphere, Frame, Rng};

/// A 3 x 3 grid of quads in the unit square (16 vertices shared by index), mapped by a random
/// rotation, scale and translation.
fn quad_grid(rng: &mut Rng) -> (TriangleMesh, Vec<Vec3>) {
    let frame = Frame::new(uniform_sphere(rng.uniform2()));
    let scale = 0.1 + 10.0 * rng.uniform();
    let offset = random_point(rng, 20.0);
    let map = |x: f32, y: f32| offset + scale * (frame.x * x + frame.y * y);
    let mut positions = Vec::new();
    for j in 0..4 {
        for i in 0..4 {
            positions.push(map(i as f32 / 3.0, j as f32 / 3.0));
        }
    }
    let mut indices = Vec::new();
    for j in 0..3u32 {
        for i in 0..3u32 {
            let (a, b, c, d) = (4 * j + i, 4 * j + i + 1, 4 * j + i + 5, 4 * j + i + 4);
            // Alternate the diagonal so both orientations are shared.
            if (i + j) % 2 == 0 {
                indices.extend([[a, b, c], [a, c, d]]);
            } else {
                indices.extend([[a, b, d], [b, c, d]]);
            }
        }
    }
    (TriangleMesh::new(positions.clone(), indices, 0), positions)
}

/// A point exactly (to float precision) on an inner edge, diagonal or vertex of the grid.
fn grid_target(rng: &mut Rng, p: &[Vec3]) -> Vec3 {
    let s = 0.01 + 0.98 * rng.uniform();
    let (i, j) = (
        (rng.uniform() * 3.0) as usize,
        (rng.uniform() * 3.0) as usize,
    );
    let v = |i: usize, j: usize| p[4 * j + i];
    match (rng.uniform() * 4.0) as u32 {
        // Inner vertical and horizontal edges (shared by two quads).
        0 => v(1 + i % 2, j).lerp(v(1 + i % 2, j + 1), s),
        1 => v(i, 1 + j % 2).lerp(v(i + 1, 1 + j % 2), s),
        // Diagonals (shared by the two triangles of a quad).
        2 if (i + j) % 2 == 0 => v(i, j).lerp(v(i + 1, j + 1), s),
        2 => v(i + 1, j).lerp(v(i, j + 1), s),
        // Inner vertices (shared by up to six triangles).
        _ => v(1 + i % 2, 1 + j % 2),
    }
}

/// A ray from a random direction (either side, at least 1 degree off the plane) through `target`.
fn ray_through(rng: &mut Rng, target: Vec3, normal: Vec3, distance: f32) -> Ray {
    let mut w = uniform_sphere(rng.uniform2());
    while w.dot(normal).abs() < 0.02 {
        w = uniform_sphere(rng.uniform2());
    }
    let origin = target + w * distance;
    Ray::new(origin, (target - origin).normalize())
}

/// Möller-Trumbore without epsilons: not watertight, a control showing the rays are hard.
fn moller_trumbore(tri: &Triangle, o: Vec3, d: Vec3) -> bool {
    let (e1, e2) = (tri.v[1] - tri.v[0], tri.v[2] - tri.v[0]);
    let p = d.cross(e2);
    let det = e1.dot(p);
    if det == 0.0 {
        return false;
    }
    let s = o - tri.v[0];
    let u = s.dot(p) / det;
    let q = s.cross(e1);
    let v = d.dot(q) / det;
    u >= 0.0 && v >= 0.0 && u + v <= 1.0 && e2.dot(q) / det > 0.0
}

#[test]
fn shared_edges_diagonals_and_vertices_are_watertight() {
    let mut rng = Rng::new(5, 0, 0);
    let (mut rays, mut leaks, mut control_leaks) = (0u64, 0u64, 0u64);
    for _ in 0..100 {
        let (mesh, p) = quad_grid(&mut rng);
        let normal = (p[1] - p[0]).cross(p[4] - p[0]).normalize();
        let tris: Vec<Triangle> = mesh
            .indices
            .iter()
            .map(|i| Triangle {
                v: i.map(|k| p[k as usize]),
            })
            .collect();
        let scale = (p[15] - p[0]).length();
        let geometry = Geometry::new(&[mesh], &[]);
        for k in 0..12_000 {
            let target = grid_target(&mut rng, &p);
            let distance = scale * (0.5 + 4.0 * rng.uniform());
            let ray = ray_through(&mut rng, target, normal, distance);
            rays += 1;
            let hit = tris
                .iter()
                .any(|t| intersect_triangle(t, ray.origin, ray.dir, f32::INFINITY).is_some());
            // The BVH on every fourth ray (its triangle test is the same code).
            let bvh_hit = k % 4 != 0 || geometry.intersect(&ray).is_some();
            leaks += (!hit || !bvh_hit) as u64;
            control_leaks += !tris.iter().any(|t| moller_trumbore(t, ray.origin, ray.dir)) as u64;
        }
    }
    assert_eq!(
        leaks, 0,
        "{leaks} of {rays} rays slipped through a shared edge"
    );
    // The same rays do leak through a test that is not watertight.
    assert!(control_leaks > 0, "control: {control_leaks} of {rays}");
    println!("rays {rays}, Moller-Trumbore leaks {control_leaks}");
}

#[test]
fn fan_center_vertex_and_spokes_are_watertight() {
    let mut rng = Rng::new(6, 0, 0);
    let (mut rays, mut leaks) = (0u64, 0u64);
    for _ in 0..100 {
        let frame = Frame::new(uniform_sphere(rng.uniform2()));
        let center = random_point(&mut rng, 50.0);
        // At least 5 spokes with jittered angles: every gap stays below 180 degrees.
        let n = 5 + (rng.uniform() * 10.0) as u32;
        let radius = 0.01 + 5.0 * rng.uniform();
        // Irregular angles, so the spokes are not symmetric.
        let mut angles: Vec<f32> = (0..n)
            .map(|i| (i as f32 + 0.5 * rng.uniform()) / n as f32)
            .collect();
        angles.sort_by(f32::total_cmp);
        let mut positions = vec![center];
        for a in &angles {
            let phi = a * std::f32::consts::TAU;
            positions.push(center + radius * (frame.x * phi.cos() + frame.y * phi.sin()));
        }
        let indices: Vec<[u32; 3]> = (0..n).map(|i| [0, 1 + i, 1 + (i + 1) % n]).collect();
        let tris: Vec<Triangle> = indices
            .iter()
            .map(|i| Triangle {
                v: i.map(|k| positions[k as usize]),
            })
            .collect();
        for k in 0..4_000 {
            let target = if k % 2 == 0 {
                center
            } else {
                let spoke = 1 + (rng.uniform() * n as f32) as usize;
                center.lerp(positions[spoke], 0.01 + 0.98 * rng.uniform())
            };
            let distance = radius * (0.2 + 4.0 * rng.uniform());
            let ray = ray_through(&mut rng, target, frame.z, distance);
            rays += 1;
            leaks += !tris
                .iter()
                .any(|t| intersect_triangle(t, ray.origin, ray.dir, f32::INFINITY).is_some())
                as u64;
        }
    }
    assert_eq!(leaks, 0, "{leaks} of {rays} rays slipped through the fan");
}

#[test]
fn rays_leaving_corners_never_escape_the_box() {
    for size in [1.0f32, 555.0] {
        let meshes = closed_box(Vec3::ZERO, Vec3::splat(size), 0);
        let sphere = [Sphere::new(Vec3::splat(0.5 * size), 0.2 * size, 1)];
        let geometry = Geometry::new(&meshes, &sphere);
        let mut rng = Rng::new(7, 0, 0);
        for i in 0..200_000 {
            // A point on one wall very near an edge it shares with a neighbour, or near a
            // corner, leaving toward the neighbour.
            // Mostly 1e-5..3e-5 of the box size; every fourth ray 1e-7..3e-7, below the rounding
            // error of t in single precision.
            let scale = if i % 4 == 3 { 1.0e-7 } else { 1.0e-5 };
            let delta = |rng: &mut Rng| size * scale * (1.0 + 2.0 * rng.uniform());
            let along = size * (0.05 + 0.9 * rng.uniform());
            let (p, ng, toward) = match i % 3 {
                // Floor near the left wall.
                0 => (Vec3::new(delta(&mut rng), 0.0, along), Vec3::Y, Vec3::NEG_X),
                // Left wall near the floor.
                1 => (Vec3::new(0.0, delta(&mut rng), along), Vec3::X, Vec3::NEG_Y),
                // Back wall near the corner with floor and left wall.
                _ => (
                    Vec3::new(delta(&mut rng), delta(&mut rng), 0.0),
                    Vec3::Z,
                    Vec3::NEG_X,
                ),
            };
            // Mostly toward the neighbour, grazing along the surface, some at random.
            let tangent = (toward + ng.cross(toward) * (2.0 * rng.uniform() - 1.0)).normalize();
            let lift = [1e-6, 1e-4, 1e-2, 0.3, 2.0][(rng.uniform() * 5.0) as usize];
            let dir = (tangent + ng * lift).normalize();
            let ray = Ray::spawn(p, ng, dir);
            let hit = geometry.intersect(&ray);
            let reference = geometry.intersect_brute_force(&ray);
            assert!(
                same_hit(&hit, &reference),
                "ray {i} {ray:?}: {hit:?} vs {reference:?}"
            );
            let hit = hit.unwrap_or_else(|| panic!("ray {i} from {p} escaped: {ray:?}"));
            let tol = 1e-4 * size;
            assert!(
                hit.p.cmpge(Vec3::splat(-tol)).all() && hit.p.cmple(Vec3::splat(size + tol)).all(),
                "ray {i} left the box: {hit:?}"
            );
        }
    }
}

/// The smallest positive root of the ray with the sphere, in double precision.
fn sphere_root(s: &Sphere, o: Vec3, d: Vec3) -> Option<f64> {
    let (o, d, c) = (DVec3::from(o), DVec3::from(d), DVec3::from(s.center));
    let f = o - c;
    let (a, b, cc) = (d.dot(d), f.dot(d), f.dot(f) - (s.radius as f64).powi(2));
    let disc = b * b - a * cc;
    if disc < 0.0 {
        return None;
    }
    [(-b - disc.sqrt()) / a, (-b + disc.sqrt()) / a]
        .into_iter()
        .find(|&t| t > 0.0)
}

#[test]
fn spawned_rays_never_rehit_their_own_surface() {
    for (scale, offset) in [
        (1.0, Vec3::ZERO),
        (1.0, Vec3::new(1.0e5, 1.0e5, -1.0e5)),
        (1.0e-3, Vec3::ZERO),
    ] {
        let (meshes, spheres) = test_scene(8, scale, offset);
        let geometry = Geometry::new(&meshes, &spheres);
        let n_tri = geometry.triangle_count() as u32;
        let mut rng = Rng::new(9, 0, 0);
        let mut tested = 0;
        for i in 0..20_000 {
            let ray = Ray::new(
                random_point(&mut rng, 3.9) * scale + offset,
                uniform_sphere(rng.uniform2()),
            );
            let Some(hit) = geometry.intersect(&ray) else {
                continue;
            };
            let frame = Frame::new(hit.ng);
            for k in 0..8 {
                // Both sides; grazing (down to 1e-6 rad off the surface) and random directions.
                let side = if k % 2 == 0 { 1.0 } else { -1.0 };
                let elevation = [1e-6f32, 1e-4, 1e-2, rng.uniform()][k / 2];
                let phi = std::f32::consts::TAU * rng.uniform();
                let local = Vec3::new(phi.cos(), phi.sin(), side * elevation).normalize();
                let dir = frame.to_world(local);
                let spawned = Ray::spawn(hit.p, hit.ng, dir);
                tested += 1;
                let off = (spawned.origin - hit.p).dot(hit.ng);
                assert!(
                    off * side > 0.0,
                    "origin on the wrong side: {hit:?} {spawned:?}"
                );
                let Some(again) = geometry.intersect(&spawned) else {
                    continue;
                };
                if again.prim != hit.prim {
                    continue;
                }
                // A triangle cannot be met again; a sphere only across its inside, at the chord.
                let ok = hit.prim >= n_tri && {
                    let s = geometry.sphere(hit.prim);
                    let expected = sphere_root(s, spawned.origin, spawned.dir).unwrap_or(0.0);
                    again.t as f64 > 0.5 * expected && expected > 0.0
                };
                assert!(
                    ok,
                    "scale {scale} offset {offset}: ray {i}/{k} re-hit prim {} at t {} ({hit:?} -> {spawned:?})",
                    hit.prim, again.t
                );
            }
        }
        assert!(tested > 100_000, "{tested}");
    }
}

#[test]
fn large_triangles_through_the_world_origin_do_not_self_intersect() {
    // Hit points near (0, 0, 0) on triangles a thousand times larger: the offset, which scales
    // with |p|, is far below the rounding error of the triangle test, which scales with the
    // vertices; the test itself must not report the triangle a ray leaves.
    let mut rng = Rng::new(11, 0, 0);
    let mut tested = 0;
    for _ in 0..200 {
        let frame = Frame::new(uniform_sphere(rng.uniform2()));
        let size = 1.0 + 100.0 * rng.uniform();
        let (u, v) = (frame.x * size, frame.y * size);
        let geometry = Geometry::new(&[TriangleMesh::quad(-0.5 * (u + v), u, v, 0)], &[]);
        for k in 0..200 {
            let target = (frame.x * (2.0 * rng.uniform() - 1.0)
                + frame.y * (2.0 * rng.uniform() - 1.0))
                * size
                * 1e-3;
            let ray = ray_through(&mut rng, target, frame.z, 1.0);
            let hit = geometry.intersect(&ray).expect("aimed at the quad");
            let side = if k % 2 == 0 { 1.0 } else { -1.0 };
            let elevation = [1e-6f32, 1e-3, 0.1, 1.0, 10.0][k % 5];
            let phi = std::f32::consts::TAU * rng.uniform();
            let dir = Frame::new(hit.ng)
                .to_world(Vec3::new(phi.cos(), phi.sin(), side * elevation).normalize());
            let spawned = Ray::spawn(hit.p, hit.ng, dir);
            tested += 1;
            assert!(
                geometry.intersect(&spawned).is_none(),
                "{hit:?} -> {spawned:?}"
            );
            assert!(!geometry.occluded(&spawned));
        }
    }
    assert_eq!(tested, 40_000);
}
