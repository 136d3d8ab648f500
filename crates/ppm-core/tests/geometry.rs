//! Robustness of the geometry core: the BVH against brute force, watertightness on shared
//! edges and vertices, corner rays, self-intersection at several scales, degenerate input.

use glam::{DVec3, Vec3};
use ppm_core::geometry::{intersect_triangle, Geometry, Hit, Ray, Sphere, Triangle, TriangleMesh};
use ppm_core::sampling::{uniform_sphere, Frame, Rng};

/// The six inward-facing walls of the box [lo, hi], two triangles each.
fn closed_box(lo: Vec3, hi: Vec3, material: u32) -> Vec<TriangleMesh> {
    let d = hi - lo;
    let (x, y, z) = (Vec3::X * d.x, Vec3::Y * d.y, Vec3::Z * d.z);
    vec![
        TriangleMesh::quad(lo, z, x, material), // floor, +y
        TriangleMesh::quad(Vec3::new(lo.x, hi.y, lo.z), x, z, material), // ceiling, -y
        TriangleMesh::quad(lo, y, z, material), // left, +x
        TriangleMesh::quad(Vec3::new(hi.x, lo.y, lo.z), z, y, material), // right, -x
        TriangleMesh::quad(lo, x, y, material), // back, +z
        TriangleMesh::quad(Vec3::new(lo.x, lo.y, hi.z), y, x, material), // front, -z
    ]
}

/// A seeded test scene in [-4, 4]^3: a closed box, a soup of random triangles, outward spheres
/// and one large inward sphere, all mapped by p -> p * scale + offset.
fn test_scene(seed: u64, scale: f32, offset: Vec3) -> (Vec<TriangleMesh>, Vec<Sphere>) {
    let mut rng = Rng::new(seed, 0, 0);
    let mut meshes = closed_box(Vec3::splat(-4.0), Vec3::splat(4.0), 0);
    let mut positions = Vec::new();
    let mut indices = Vec::new();
    for i in 0..300u32 {
        let c = (rng.uniform2().extend(rng.uniform()) * 2.0 - 1.0) * 3.0;
        for _ in 0..3 {
            positions.push(c + uniform_sphere(rng.uniform2()) * (0.2 + rng.uniform()));
        }
        indices.push([3 * i, 3 * i + 1, 3 * i + 2]);
    }
    meshes.push(TriangleMesh::new(positions, indices, 1));
    let mut spheres: Vec<Sphere> = (0..12)
        .map(|_| {
            let c = (rng.uniform2().extend(rng.uniform()) * 2.0 - 1.0) * 3.0;
            Sphere::new(c, 0.2 + 0.6 * rng.uniform(), 2)
        })
        .collect();
    spheres.push(Sphere::new(Vec3::new(0.5, -0.5, 0.25), 2.0, 3).inward());
    for m in &mut meshes {
        for p in &mut m.positions {
            *p = *p * scale + offset;
        }
    }
    for s in &mut spheres {
        s.center = s.center * scale + offset;
        s.radius *= scale;
    }
    (meshes, spheres)
}

fn random_point(rng: &mut Rng, half: f32) -> Vec3 {
    (rng.uniform2().extend(rng.uniform()) * 2.0 - 1.0) * half
}

/// Same primitive at the bit-identical distance (or both misses).
fn same_hit(a: &Option<Hit>, b: &Option<Hit>) -> bool {
    match (a, b) {
        (None, None) => true,
        (Some(a), Some(b)) => a.prim == b.prim && a.t.to_bits() == b.t.to_bits(),
        _ => false,
    }
}

#[test]
fn bvh_closest_hit_matches_brute_force() {
    for (scale, offset) in [
        (1.0, Vec3::ZERO),
        (1.0e-3, Vec3::ZERO),
        (1.0, Vec3::new(1.0e5, -2.0e4, 3.0)),
    ] {
        let (meshes, spheres) = test_scene(1, scale, offset);
        let geometry = Geometry::new(&meshes, &spheres);
        assert_eq!(geometry.sphere_count(), 13);
        let mut rng = Rng::new(2, 0, 0);
        let (mut hits, mut spawned) = (0, 0);
        for i in 0..20_000 {
            let ray = Ray::new(
                random_point(&mut rng, 3.9) * scale + offset,
                uniform_sphere(rng.uniform2()),
            );
            let hit = geometry.intersect(&ray);
            let reference = geometry.intersect_brute_force(&ray);
            assert!(
                same_hit(&hit, &reference),
                "ray {i} {ray:?}: bvh {hit:?} vs brute force {reference:?}"
            );
            let Some(hit) = hit else { continue };
            hits += 1;
            // Rays leaving the surface, to either side.
            let ray = Ray::spawn(hit.p, hit.ng, uniform_sphere(rng.uniform2()));
            let a = geometry.intersect(&ray);
            assert!(
                same_hit(&a, &geometry.intersect_brute_force(&ray)),
                "spawned ray {i} {ray:?}"
            );
            spawned += a.is_some() as u32;
        }
        // Every ray starts inside the closed box.
        assert_eq!(hits, 20_000, "scale {scale} offset {offset}");
        // About half leave the closed box through its walls.
        assert!(spawned > 10_000, "{spawned}");
    }
}

#[test]
fn occluded_agrees_with_closest_hit() {
    let (meshes, spheres) = test_scene(3, 1.0, Vec3::ZERO);
    let geometry = Geometry::new(&meshes, &spheres);
    let mut rng = Rng::new(4, 0, 0);
    let (mut blocked, mut free) = (0, 0);
    for _ in 0..20_000 {
        let mut ray = Ray::new(random_point(&mut rng, 3.9), uniform_sphere(rng.uniform2()));
        let closest = geometry.intersect(&ray).map_or(f32::INFINITY, |h| h.t);
        ray.t_max = 3.0 * rng.uniform();
        // Sometimes exactly at the hit: (0, t_max) is open, so that hit does not count.
        if rng.uniform() < 0.1 && closest.is_finite() {
            ray.t_max = closest;
        }
        let occluded = geometry.occluded(&ray);
        assert_eq!(occluded, closest < ray.t_max, "{ray:?} closest {closest}");
        if occluded {
            blocked += 1;
        } else {
            free += 1;
        }
    }
    assert!(blocked > 1000 && free > 1000, "{blocked} {free}");
}

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
fn degenerate_triangles_are_skipped_and_counted() {
    let v = [
        Vec3::ZERO,
        Vec3::X,
        Vec3::Y,
        Vec3::new(2.0, 0.0, 0.0),
        Vec3::new(0.0, 0.0, f32::NAN),
        Vec3::ZERO,
    ];
    let a = TriangleMesh {
        positions: v.to_vec(),
        normals: Vec::new(),
        indices: vec![
            [0, 1, 2], // kept: prim 0
            [0, 1, 3], // collinear, zero area
            [0, 0, 2], // repeated index
            [5, 0, 1], // repeated position under two indices
            [0, 4, 1], // NaN vertex
            [0, 1, 9], // index out of range
            [1, 2, 0], // kept: prim 1
        ],
        materials: vec![7, 1, 1, 1, 1, 1, 8],
    };
    let b = TriangleMesh::new(
        vec![
            Vec3::Z,
            Vec3::Z + Vec3::X,
            Vec3::Z + Vec3::Y,
            Vec3::Z + Vec3::X,
        ],
        vec![[0, 1, 3], [0, 1, 2]],
        9,
    );
    let geometry = Geometry::new(&[a, b], &[Sphere::new(Vec3::new(0.0, 0.0, -3.0), 0.5, 4)]);
    assert_eq!(geometry.skipped_triangles(), 6);
    assert_eq!(geometry.triangle_count(), 3);
    assert_eq!(geometry.sphere_count(), 1);
    assert_eq!(geometry.triangle(1).1, 8);
    let (tri, material) = geometry.triangle(2);
    assert_eq!((tri.v[2], material), (Vec3::Z + Vec3::Y, 9));
    assert_eq!(geometry.sphere(3).material, 4);
    // Global ids: triangles in order, then spheres.
    let down = |x: f32, y: f32| geometry.intersect(&Ray::new(Vec3::new(x, y, 5.0), Vec3::NEG_Z));
    assert_eq!(down(0.2, 0.2).map(|h| (h.prim, h.material)), Some((2, 9)));
    let below = Ray::new(Vec3::new(0.2, 0.2, -0.5), Vec3::NEG_Z);
    assert_eq!(
        geometry.intersect(&below).map(|h| (h.prim, h.material)),
        Some((3, 4))
    );
    let up = Ray::new(Vec3::new(0.2, 0.2, -1.0), Vec3::Z);
    assert!(matches!(geometry.intersect(&up), Some(h) if h.prim <= 1 && h.t == 1.0));
    let (lo, hi) = geometry.bounds();
    assert_eq!(
        (lo, hi),
        (Vec3::new(-0.5, -0.5, -3.5), Vec3::new(1.0, 1.0, 1.0))
    );
}

#[test]
fn hits_report_point_normals_and_barycentrics() {
    // Vertex normals pointing away from ng (flipped), one NaN and one zero (fall back to ng).
    let tilted = Vec3::new(1.0, 0.0, -1.0).normalize();
    let positions = vec![
        Vec3::ZERO,
        Vec3::X,
        Vec3::Y,
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::Y,
    ];
    let normals = vec![
        Vec3::NEG_Z,
        Vec3::NEG_Z,
        Vec3::new(f32::NAN, 0.0, 1.0),
        Vec3::ZERO,
        tilted,
    ];
    let indices = vec![[0, 1, 4], [1, 3, 2]];
    let mesh = TriangleMesh {
        positions,
        normals,
        indices,
        materials: vec![0, 0],
    };
    let geometry = Geometry::new(&[mesh], &[]);
    let hit = geometry
        .intersect(&Ray::new(Vec3::new(0.3, 0.1, 1.0), Vec3::NEG_Z))
        .unwrap();
    let expected = -(Vec3::NEG_Z * 0.9 + tilted * 0.1).normalize();
    assert_eq!((hit.prim, hit.ng), (0, Vec3::Z));
    assert!((hit.ns - expected).length() < 1e-6, "{hit:?}");
    assert!((hit.p - Vec3::new(0.3, 0.1, 0.0)).length() < 1e-7 && (hit.t - 1.0).abs() < 1e-6);
    assert!((hit.uv - glam::Vec2::new(0.3, 0.1)).length() < 1e-6);
    // The NaN normal spoils the interpolation: ns falls back to ng.
    let hit = geometry
        .intersect(&Ray::new(Vec3::new(0.6, 0.6, -1.0), Vec3::Z))
        .unwrap();
    assert_eq!((hit.prim, hit.ng, hit.ns), (1, Vec3::Z, Vec3::Z));
    // A ray from behind sees the same ng: normals are not flipped toward the ray.
    let hit = geometry
        .intersect(&Ray::new(Vec3::new(0.1, 0.1, -1.0), Vec3::Z))
        .unwrap();
    assert_eq!(hit.ng, Vec3::Z);
}

#[test]
fn inward_sphere_normal_points_to_the_center() {
    let center = Vec3::new(1.0, 2.0, 3.0);
    let spheres = [
        Sphere::new(center, 2.0, 0).inward(),
        Sphere::new(center + Vec3::X * 10.0, -2.0, 0),
    ];
    let geometry = Geometry::new(&[], &spheres);
    let mut rng = Rng::new(10, 0, 0);
    for i in 0..1000 {
        let s = &spheres[i % 2];
        // From inside and from outside.
        let origin = if i % 4 < 2 {
            s.center + random_point(&mut rng, 1.0)
        } else {
            s.center + Vec3::splat(5.0)
        };
        let dir = if i % 4 < 2 {
            uniform_sphere(rng.uniform2())
        } else {
            (s.center - origin).normalize()
        };
        let hit = geometry.intersect(&Ray::new(origin, dir)).unwrap();
        let to_center = (s.center - hit.p).normalize();
        assert!(
            hit.ng.dot(to_center) > 0.9999 && (hit.ng.length() - 1.0).abs() < 1e-6,
            "{hit:?}"
        );
        assert_eq!(hit.ns, hit.ng);
        assert!(((hit.p - s.center).length() - 2.0).abs() < 1e-6);
    }
    // Outward spheres point away from the center.
    let geometry = Geometry::new(&[], &[Sphere::new(center, 2.0, 0)]);
    let hit = geometry
        .intersect(&Ray::new(center + Vec3::Z * 5.0, Vec3::NEG_Z))
        .unwrap();
    assert!((hit.ng - Vec3::Z).length() < 1e-6);
}

#[test]
fn empty_and_single_primitive_scenes() {
    let empty = Geometry::new(&[], &[]);
    let ray = Ray::new(Vec3::ZERO, Vec3::X);
    assert!(empty.intersect(&ray).is_none() && !empty.occluded(&ray));
    let one = Geometry::new(&[], &[Sphere::new(Vec3::X * 3.0, 1.0, 0)]);
    assert!((one.intersect(&ray).unwrap().t - 2.0).abs() < 1e-6);
    assert!(one.occluded(&ray));
    assert!(!one.occluded(&Ray { t_max: 1.9, ..ray }));
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
