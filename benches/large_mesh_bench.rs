//! The large-mesh benchmark of docs/performance.md: BVH build, closest hit on camera and on
//! incoherent rays, and any-hit shadow rays, on the displaced sphere of 995,328 triangles in
//! the Cornell box (`ppm_benches::large_mesh`), the same seeded rays for every build.
//!
//! `cargo bench -p ppm-benches --bench large_mesh`. Single-threaded like the other kernel
//! benchmarks (the build on a one-thread pool); the rays are a 1/8 sample of each set, to
//! keep one sample short. `examples/large_mesh.rs` runs the full sets at any thread count.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use ppm_benches::large_mesh::{large_scene, ray_sets, LARGE_N};
use ppm_core::geometry::{Geometry, Ray, TriangleMesh};
use std::hint::black_box;
use std::time::Duration;

fn large_mesh(c: &mut Criterion) {
    let scene = large_scene(LARGE_N, 1024, 1024);
    let sets = ray_sets(&scene);
    let sample = |rays: &[Ray]| -> Vec<Ray> { rays.iter().step_by(8).copied().collect() };
    let mut g = c.benchmark_group("large_mesh");
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));

    let count = scene.geometry.triangle_count() as u32;
    let mesh = TriangleMesh::new(
        (0..count)
            .flat_map(|p| scene.geometry.triangle(p).0.v)
            .collect(),
        (0..count).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]).collect(),
        0,
    );
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    g.throughput(Throughput::Elements(count as u64));
    g.bench_function("build", |b| {
        b.iter(|| pool.install(|| Geometry::new(black_box(std::slice::from_ref(&mesh)), &[])))
    });

    for (name, rays) in [("camera", &sets.camera), ("incoherent", &sets.incoherent)] {
        let rays = sample(rays);
        g.throughput(Throughput::Elements(rays.len() as u64));
        g.bench_with_input(BenchmarkId::new("closest_hit", name), &rays, |b, rays| {
            b.iter(|| rays.iter().filter(|r| scene.intersect(r).is_some()).count())
        });
    }
    let shadow = sample(&sets.shadow);
    g.throughput(Throughput::Elements(shadow.len() as u64));
    g.bench_with_input(BenchmarkId::new("any_hit", "shadow"), &shadow, |b, rays| {
        b.iter(|| rays.iter().filter(|r| scene.occluded(r)).count())
    });
}

criterion_group!(benches, large_mesh);
criterion_main!(benches);
