//! Trace time of instances against the same meshes flattened: 100 placements of a
//! 10,092-triangle mesh (each turned differently, on a 5 x 5 x 4 grid) as a two-level BVH,
//! and as one BVH over the 1,009,200 copied triangles; 2^16 closest-hit and shadow rays.
//!
//! `cargo bench -p ppm-core --bench instances`. (1,000 placements of a 100k-triangle mesh
//! flattened would be 10^8 triangles, about 15 GB: more than a shared machine has.)

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use glam::{DMat3, DMat4, DVec3, Vec3};
use ppm_core::geometry::{Geometry, MeshInstance, Ray, TriangleMesh};
use ppm_core::sampling::{uniform_sphere, Rng};
use std::hint::black_box;

/// The mesh moved by `m` as a flattened copy: points by M, the winding reversed if it mirrors.
fn flatten(mesh: &TriangleMesh, m: DMat4) -> TriangleMesh {
    let mut out = mesh.clone();
    for p in &mut out.positions {
        *p = m.transform_point3(p.as_dvec3()).as_vec3();
    }
    if DMat3::from_mat4(m).determinant() < 0.0 {
        out.indices.iter_mut().for_each(|t| t.swap(1, 2));
    }
    out
}

fn bench(c: &mut Criterion) {
    let mesh = TriangleMesh::displaced_sphere(Vec3::ZERO, 1.0, 29, 0.1, 9.0, 0);
    let placements: Vec<MeshInstance> = (0..100)
        .map(|i| MeshInstance {
            mesh: 0,
            to_world: DMat4::from_translation(DVec3::new(
                (i % 5) as f64 * 2.5,
                (i / 5 % 5) as f64 * 2.5,
                (i / 25) as f64 * 2.5,
            )) * DMat4::from_axis_angle(
                DVec3::new(1.0, 1.0, 0.0).normalize(),
                i as f64 * 0.3,
            ),
        })
        .collect();
    let copies: Vec<TriangleMesh> = placements
        .iter()
        .map(|p| flatten(&mesh, p.to_world))
        .collect();
    let flat = Geometry::new(&copies, &[]);
    let instanced = Geometry::with_instances(&[], &[], &[mesh], &placements).unwrap();
    let mut rng = Rng::new(4, 0, 0);
    let center = Vec3::new(5.0, 5.0, 3.75);
    let rays: Vec<Ray> = (0..1 << 16)
        .map(|_| {
            let o = center + uniform_sphere(rng.uniform2()) * 15.0;
            let target = center + (rng.uniform2().extend(rng.uniform()) * 2.0 - 1.0) * 5.0;
            Ray::new(o, (target - o).normalize())
        })
        .collect();
    let mut group = c.benchmark_group("instances");
    group.throughput(Throughput::Elements(rays.len() as u64));
    for (name, g) in [("instanced", &instanced), ("flattened", &flat)] {
        group.bench_function(format!("closest/{name}"), |b| {
            b.iter(|| {
                rays.iter()
                    .filter(|r| black_box(g.intersect(r)).is_some())
                    .count()
            })
        });
        group.bench_function(format!("shadow/{name}"), |b| {
            b.iter(|| {
                rays.iter()
                    .filter(|r| g.occluded(&Ray { t_max: 10.0, ..**r }))
                    .count()
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
