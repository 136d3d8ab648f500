//! Geometry built in code, shared by the geometry tests (geometry.rs, ray_robustness.rs):
//! a closed box, a seeded scene of triangles and spheres at any scale and offset, random
//! points, and the bit-exact comparison of two hits.
#![allow(dead_code)]

use glam::Vec3;
use ppm_core::geometry::{Hit, Sphere, TriangleMesh};
use ppm_core::sampling::{uniform_sphere, Rng};

/// The six inward-facing walls of the box [lo, hi], two triangles each.
pub fn closed_box(lo: Vec3, hi: Vec3, material: u32) -> Vec<TriangleMesh> {
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
pub fn test_scene(seed: u64, scale: f32, offset: Vec3) -> (Vec<TriangleMesh>, Vec<Sphere>) {
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

pub fn random_point(rng: &mut Rng, half: f32) -> Vec3 {
    (rng.uniform2().extend(rng.uniform()) * 2.0 - 1.0) * half
}

/// Same primitive at the bit-identical distance (or both misses).
pub fn same_hit(a: &Option<Hit>, b: &Option<Hit>) -> bool {
    match (a, b) {
        (None, None) => true,
        (Some(a), Some(b)) => a.prim == b.prim && a.t.to_bits() == b.t.to_bits(),
        _ => false,
    }
}
