//! Ray throughput of the geometry core: closest-hit and shadow rays per second on a
//! Cornell-like box (quads, two spheres and a 4096-triangle torus).
//!
//! `cargo bench -p ppm-core --bench rays`. For scale, the same rays are also traced through
//! obvhs's compressed wide BVH (CWBVH) with the same primitive tests, the fast structure we do
//! not use because its traversal misses rays that start next to a corner.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use glam::{Vec3, Vec3A};
use obvhs::aabb::Aabb;
use obvhs::ray::{Ray as ObvhsRay, RayHit};
use obvhs::BvhBuildParams;
use ppm_core::geometry::{intersect_triangle, Geometry, Ray, Sphere, TriangleMesh};
use ppm_core::sampling::{cosine_hemisphere, uniform_triangle, Frame, Rng};
use std::hint::black_box;

/// Rays per batch.
const N: usize = 1 << 16;

/// A closed unit box with a ceiling light quad, two blocks, two spheres and a torus.
fn scene() -> (Vec<TriangleMesh>, Vec<Sphere>) {
    let (x, y, z) = (Vec3::X, Vec3::Y, Vec3::Z);
    let mut meshes = vec![
        TriangleMesh::quad(Vec3::ZERO, z, x, 0),
        TriangleMesh::quad(y, x, z, 0),
        TriangleMesh::quad(Vec3::ZERO, y, z, 1),
        TriangleMesh::quad(x, z, y, 2),
        TriangleMesh::quad(Vec3::ZERO, x, y, 0),
        TriangleMesh::quad(z, y, x, 0),
        TriangleMesh::quad(Vec3::new(0.35, 0.999, 0.35), 0.3 * x, 0.3 * z, 3),
    ];
    // Two axis-aligned blocks, five quads each.
    for (lo, size) in [
        (Vec3::new(0.15, 0.0, 0.2), Vec3::new(0.25, 0.6, 0.25)),
        (Vec3::new(0.6, 0.0, 0.55), Vec3::splat(0.25)),
    ] {
        let (sx, sy, sz) = (x * size.x, y * size.y, z * size.z);
        meshes.push(TriangleMesh::quad(lo + sy, sz, sx, 0));
        meshes.push(TriangleMesh::quad(lo, sx, sy, 0));
        meshes.push(TriangleMesh::quad(lo + sz, sy, sx, 0));
        meshes.push(TriangleMesh::quad(lo, sy, sz, 0));
        meshes.push(TriangleMesh::quad(lo + sx, sz, sy, 0));
    }
    // A torus of 64 x 32 quads (4096 triangles) with shared vertices.
    let (ring, tube) = (64u32, 32u32);
    let center = Vec3::new(0.5, 0.75, 0.5);
    let mut positions = Vec::new();
    for i in 0..ring {
        let a = i as f32 / ring as f32 * std::f32::consts::TAU;
        for j in 0..tube {
            let b = j as f32 / tube as f32 * std::f32::consts::TAU;
            let r = 0.15 + 0.05 * b.cos();
            positions.push(center + Vec3::new(r * a.cos(), 0.05 * b.sin(), r * a.sin()));
        }
    }
    let mut indices = Vec::new();
    for i in 0..ring {
        for j in 0..tube {
            let v = |i: u32, j: u32| (i % ring) * tube + j % tube;
            indices.push([v(i, j), v(i + 1, j), v(i + 1, j + 1)]);
            indices.push([v(i, j), v(i + 1, j + 1), v(i, j + 1)]);
        }
    }
    meshes.push(TriangleMesh::new(positions, indices, 0));
    let spheres = vec![
        Sphere::new(Vec3::new(0.3, 0.75, 0.3), 0.1, 4),
        Sphere::new(Vec3::new(0.75, 0.4, 0.3), 0.12, 5),
    ];
    (meshes, spheres)
}

/// Camera rays from inside the front wall, diffuse bounce rays and shadow rays to the light.
fn rays(geometry: &Geometry) -> (Vec<Ray>, Vec<Ray>, Vec<Ray>) {
    let mut rng = Rng::new(1, 0, 0);
    let eye = Vec3::new(0.5, 0.5, 0.99);
    let camera: Vec<Ray> = (0..N)
        .map(|_| {
            let u = rng.uniform2() * 2.0 - 1.0;
            Ray::new(eye, Vec3::new(0.6 * u.x, 0.6 * u.y, -1.0).normalize())
        })
        .collect();
    let light = [
        Vec3::new(0.35, 0.999, 0.35),
        Vec3::new(0.65, 0.999, 0.35),
        Vec3::new(0.65, 0.999, 0.65),
    ];
    let (mut bounce, mut shadow) = (Vec::with_capacity(N), Vec::with_capacity(N));
    for ray in &camera {
        let hit = geometry.intersect(ray).expect("closed box");
        let n = if hit.ng.dot(ray.dir) < 0.0 {
            hit.ng
        } else {
            -hit.ng
        };
        let dir = Frame::new(n).to_world(cosine_hemisphere(rng.uniform2()));
        bounce.push(Ray::spawn(hit.p, hit.ng, dir));
        let b = uniform_triangle(rng.uniform2());
        let target = light[0] * (1.0 - b.x - b.y) + light[1] * b.x + light[2] * b.y;
        shadow.push(Ray::spawn_to(hit.p, hit.ng, target, Vec3::NEG_Y));
    }
    (camera, bounce, shadow)
}

fn bench(c: &mut Criterion) {
    let (meshes, spheres) = scene();
    let geometry = Geometry::new(&meshes, &spheres);
    let (camera, bounce, shadow) = rays(&geometry);

    // The same primitives under obvhs's CWBVH, for comparison only.
    let n_tri = geometry.triangle_count() as u32;
    let n_prim = n_tri + geometry.sphere_count() as u32;
    let aabbs: Vec<Aabb> = (0..n_prim)
        .map(|p| {
            if p < n_tri {
                let v = geometry.triangle(p).0.v.map(Vec3A::from);
                Aabb::new(v[0].min(v[1]).min(v[2]), v[0].max(v[1]).max(v[2]))
            } else {
                let s = geometry.sphere(p);
                Aabb::new(
                    Vec3A::from(s.center) - s.radius,
                    Vec3A::from(s.center) + s.radius,
                )
            }
        })
        .collect();
    let cwbvh = obvhs::cwbvh::builder::build_cwbvh(
        &aabbs,
        BvhBuildParams::medium_build(),
        &mut Default::default(),
    );
    let cwbvh_closest = |ray: &Ray| {
        let mut hit = RayHit::none();
        let oray = ObvhsRay::new(ray.origin.into(), ray.dir.into(), 0.0, ray.t_max);
        cwbvh.ray_traverse(oray, &mut hit, |r, id| {
            let p = cwbvh.primitive_indices[id];
            let (o, d) = (Vec3::from(r.origin), Vec3::from(r.direction));
            let t = if p < n_tri {
                intersect_triangle(&geometry.triangle(p).0, o, d, r.tmax).map(|h| h.0)
            } else {
                geometry.sphere(p).intersect(o, d, r.tmax)
            };
            t.unwrap_or(f32::INFINITY)
        })
    };

    let mut group = c.benchmark_group("rays");
    group.throughput(Throughput::Elements(N as u64));
    group.sample_size(20);
    for (name, batch) in [("camera", &camera), ("bounce", &bounce)] {
        group.bench_function(format!("closest_{name}"), |b| {
            b.iter(|| {
                batch
                    .iter()
                    .filter(|r| geometry.intersect(r).is_some())
                    .count()
            })
        });
        group.bench_function(format!("obvhs_cwbvh_closest_{name}"), |b| {
            b.iter(|| batch.iter().filter(|r| cwbvh_closest(r)).count())
        });
    }
    group.bench_function("shadow", |b| {
        b.iter(|| shadow.iter().filter(|r| geometry.occluded(r)).count())
    });
    group.finish();
    black_box(&geometry);
}

criterion_group!(benches, bench);
criterion_main!(benches);
