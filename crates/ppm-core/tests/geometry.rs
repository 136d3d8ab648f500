//! The geometry core against brute force and closed forms: the BVH's closest hit and any-hit
//! queries against a linear scan, degenerate input skipped and counted, and what a hit
//! reports (point, normals, barycentrics, primitive ids). Rays that must not slip through or
//! re-hit a surface are tested in ray_robustness.rs.

mod geometry_common;

use geometry_common::{random_point, same_hit, test_scene};
use glam::Vec3;
use ppm_core::geometry::{Geometry, Ray, Sphere, TriangleMesh};
use ppm_core::sampling::{uniform_sphere, Rng};

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
        uvs: Vec::new(),
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
        uvs: Vec::new(),
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
