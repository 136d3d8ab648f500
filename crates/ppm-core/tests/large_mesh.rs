//! The BVH on a large mesh (a displaced sphere of 110,592 triangles, the shape of the
//! large-mesh benchmark at a debug-friendly size): closest hits equal a brute-force loop on a
//! sample of random rays, any-hit agrees with closest hit, the closed mesh is watertight along
//! its shared edges and vertices (cube seams included), and duplicate faces are dropped
//! without changing an answer.

use glam::Vec3;
use ppm_core::geometry::{Geometry, Ray, TriangleMesh};
use ppm_core::sampling::{uniform_sphere, Rng};

const CENTER: Vec3 = Vec3::new(0.2, -0.1, 0.3);

/// 12 * 96^2 = 110,592 triangles around CENTER, radius 1 with 10% bumps.
fn bumpy_sphere() -> TriangleMesh {
    TriangleMesh::displaced_sphere(CENTER, 1.0, 96, 0.1, 24.0, 0)
}

/// Rays from random points in [-2, 2]^3 around the sphere (outside and inside) in random
/// directions, every fourth one aimed at the center (so most rays meet the mesh), and every
/// third with a finite t_max.
fn random_rays(seed: u64, count: usize) -> Vec<Ray> {
    let mut rng = Rng::new(seed, 0, 0);
    (0..count)
        .map(|i| {
            let o = CENTER + (rng.uniform2().extend(rng.uniform()) * 2.0 - 1.0) * 2.0;
            let dir = if i % 4 == 0 {
                (CENTER - o).normalize_or(Vec3::X)
            } else {
                uniform_sphere(rng.uniform2())
            };
            let mut ray = Ray::new(o, dir);
            if i % 3 == 0 {
                ray.t_max = 3.0 * rng.uniform();
            }
            ray
        })
        .collect()
}

#[test]
fn closest_hit_equals_brute_force_on_a_large_mesh() {
    let geometry = Geometry::new(&[bumpy_sphere()], &[]);
    assert_eq!(geometry.triangle_count(), 110_592);
    let mut hits = 0;
    for (i, ray) in random_rays(3, 400).iter().enumerate() {
        let want = geometry.intersect_brute_force(ray);
        let got = geometry.intersect(ray);
        assert_eq!(
            got.map(|h| (h.t.to_bits(), h.prim)),
            want.map(|h| (h.t.to_bits(), h.prim)),
            "ray {i}: {ray:?}"
        );
        hits += got.is_some() as usize;
    }
    assert!(hits > 100, "too few hits to test anything: {hits}");
}

/// The whole hit equals the brute force's, bit for bit: point, geometric and shading normal,
/// barycentrics and material, which the traversal reads from the packet it found the
/// triangle in and from one per-triangle record, and the brute force from the triangle
/// array. The mesh gets a material per face and vertex normals so that each field is
/// exercised.
#[test]
fn the_whole_hit_equals_the_brute_force_hit() {
    let mut mesh = bumpy_sphere();
    mesh.materials = (0..mesh.indices.len() as u32).map(|i| i % 7).collect();
    mesh.normals = mesh
        .positions
        .iter()
        .map(|p| (*p - CENTER).normalize())
        .collect();
    let geometry = Geometry::new(&[mesh], &[]);
    let bits = |v: Vec3| v.to_array().map(f32::to_bits);
    let mut hits = 0;
    for (i, ray) in random_rays(11, 800).iter().enumerate() {
        let whole = |h: ppm_core::geometry::Hit| {
            (
                h.t.to_bits(),
                bits(h.p),
                bits(h.ng),
                bits(h.ns),
                h.uv.to_array().map(f32::to_bits),
                h.material,
                h.prim,
            )
        };
        let want = geometry.intersect_brute_force(ray).map(whole);
        let got = geometry.intersect(ray).map(whole);
        assert_eq!(got, want, "ray {i}: {ray:?}");
        hits += got.is_some() as usize;
    }
    assert!(hits > 100, "too few hits to test anything: {hits}");
}

/// `occluded` is true exactly when `intersect` finds a hit, for unbounded rays and for rays
/// cut just before and just after their closest hit.
#[test]
fn any_hit_agrees_with_closest_hit_on_a_large_mesh() {
    let geometry = Geometry::new(&[bumpy_sphere()], &[]);
    let (mut blocked, mut cut) = (0, 0);
    for (i, ray) in random_rays(5, 20_000).iter().enumerate() {
        let hit = geometry.intersect(ray);
        assert_eq!(geometry.occluded(ray), hit.is_some(), "ray {i}: {ray:?}");
        blocked += hit.is_some() as usize;
        if let Some(h) = hit {
            let before = Ray {
                t_max: h.t * 0.999,
                ..*ray
            };
            let after = Ray {
                t_max: h.t * 1.001,
                ..*ray
            };
            assert_eq!(
                geometry.occluded(&before),
                geometry.intersect(&before).is_some(),
                "ray {i} cut before its hit"
            );
            assert!(geometry.occluded(&after), "ray {i} cut after its hit");
            cut += 1;
        }
    }
    assert!(blocked > 5_000 && cut == blocked, "{blocked} {cut}");
}

/// From inside the closed mesh every ray must hit it: random directions, and rays aimed
/// exactly at its vertices (where six or three triangles meet, along the cube's seams too)
/// and at the midpoints of its edges.
#[test]
fn large_closed_mesh_is_watertight() {
    let mesh = bumpy_sphere();
    let geometry = Geometry::new(std::slice::from_ref(&mesh), &[]);
    let mut rng = Rng::new(9, 0, 0);
    let mut targets: Vec<Vec3> = mesh.positions.clone();
    for t in mesh.indices.iter().step_by(7) {
        targets.push((mesh.positions[t[0] as usize] + mesh.positions[t[1] as usize]) * 0.5);
    }
    let mut misses = 0;
    let mut total = 0;
    for origin in [CENTER, CENTER + Vec3::new(0.31, -0.2, 0.11)] {
        for target in &targets {
            let ray = Ray::new(origin, (*target - origin).normalize());
            misses += geometry.intersect(&ray).is_none() as usize;
            misses += !geometry.occluded(&ray) as usize;
            total += 2;
        }
        for _ in 0..20_000 {
            let ray = Ray::new(origin, uniform_sphere(rng.uniform2()));
            misses += geometry.intersect(&ray).is_none() as usize;
            total += 1;
        }
    }
    assert_eq!(
        misses, 0,
        "{misses} of {total} rays escaped the closed mesh"
    );
}

/// 20,000 copies of one triangle among other geometry: 19,999 dropped (a size-based check,
/// not a timer: the tree is built over the distinct triangles only), and every answer equals
/// the brute force over the same scene without the copies.
#[test]
fn duplicate_triangles_are_dropped_without_changing_answers() {
    let sphere = TriangleMesh::displaced_sphere(CENTER, 1.0, 8, 0.1, 24.0, 0);
    let tri = [
        Vec3::new(-1.5, -1.5, 0.0),
        Vec3::new(1.5, -1.5, 0.0),
        Vec3::new(0.0, 1.5, 0.0),
    ];
    let copies = 20_000u32;
    let positions: Vec<Vec3> = (0..copies).flat_map(|_| tri).collect();
    let indices = (0..copies).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]).collect();
    let with_copies = Geometry::new(
        &[TriangleMesh::new(positions, indices, 1), sphere.clone()],
        &[],
    );
    let single = TriangleMesh::new(tri.to_vec(), vec![[0, 1, 2]], 1);
    let reference = Geometry::new(&[single, sphere.clone()], &[]);
    assert_eq!(with_copies.duplicate_triangles(), copies as usize - 1);
    assert_eq!(with_copies.triangle_count(), reference.triangle_count());
    assert_eq!(reference.duplicate_triangles(), 0);
    let mut on_copy = 0;
    for (i, ray) in random_rays(13, 3000).iter().enumerate() {
        let got = with_copies.intersect(ray);
        let want = reference.intersect_brute_force(ray);
        assert_eq!(
            got.map(|h| (h.t.to_bits(), h.prim, h.material)),
            want.map(|h| (h.t.to_bits(), h.prim, h.material)),
            "ray {i}"
        );
        assert_eq!(with_copies.occluded(ray), want.is_some(), "ray {i}");
        on_copy += got.is_some_and(|h| h.prim == 0) as usize;
    }
    assert!(
        on_copy > 100,
        "too few hits on the copied triangle: {on_copy}"
    );
}
