//! Throughput on the four shipped scenes at their full resolution: closest-hit and shadow rays,
//! photon tracing, hash-grid build and the photon gather (density estimates on the water and
//! specular scenes' real photon maps at the eye pass's gather points); and one iteration of
//! each integrator on the water box at 64 x 64 pixels, on one thread.
//!
//! `cargo bench -p ppm-benches` (add `-- gather` etc. to filter). Single-threaded: these are
//! kernel throughputs; the parallel scaling is measured by `scripts/scaling.py`.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use ppm_benches::{camera_rays, gather_points, photons, shadow_rays};
use ppm_core::integrator::{density_estimate, trace_light_path, GatherContext, ShadingFrame};
use ppm_core::photon::{HashGrid, Kernel, PhotonBuffer};
use ppm_core::prelude::*;
use ppm_tests::{load_small, SCENES};
use std::hint::black_box;
use std::time::Duration;

fn load(name: &str) -> Scene {
    let b = ppm_scene::load_scene_builder(&ppm_tests::scene_path(name))
        .unwrap()
        .0;
    let (w, h) = (b.camera.width, b.camera.height);
    load_small(name, w, h).build().unwrap()
}

type Group<'a> = criterion::BenchmarkGroup<'a, criterion::measurement::WallTime>;

fn config<'a>(c: &'a mut Criterion, name: &str) -> Group<'a> {
    let mut g = c.benchmark_group(name);
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    g
}

fn rays(c: &mut Criterion) {
    let mut g = config(c, "rays");
    for name in SCENES {
        let scene = load(name);
        let primary = camera_rays(&scene, 100_000);
        g.throughput(Throughput::Elements(primary.len() as u64));
        g.bench_with_input(
            BenchmarkId::new("closest_hit", name),
            &primary,
            |b, rays| b.iter(|| rays.iter().filter(|r| scene.intersect(r).is_some()).count()),
        );
        let shadow = shadow_rays(&scene, 100_000);
        g.throughput(Throughput::Elements(shadow.len() as u64));
        g.bench_with_input(BenchmarkId::new("shadow", name), &shadow, |b, rays| {
            b.iter(|| rays.iter().filter(|r| scene.occluded(r)).count())
        });
    }
}

fn photon_tracing(c: &mut Criterion) {
    let mut g = config(c, "photon_tracing");
    let paths = 20_000u32;
    for name in SCENES {
        let scene = load(name);
        let settings = RenderSettings::new(&scene);
        let stored = photons(&scene, &settings, paths).len();
        g.throughput(Throughput::Elements(stored as u64));
        let mut buffer = PhotonBuffer::with_capacity(stored * 2);
        g.bench_function(BenchmarkId::new("photons", name), |b| {
            b.iter(|| {
                buffer.clear();
                let mut writer = buffer.writer();
                let mut counters = Default::default();
                for path in 0..paths {
                    trace_light_path(&scene, &settings, 0, path, &mut writer, &mut counters);
                }
            })
        });
    }
}

/// Grid build and gather on one iteration's real photon map: the water scene at its 200,000
/// light paths, and the specular scene at 262,144 (the speed benchmark render of
/// docs/performance.md).
fn photon_map(c: &mut Criterion) {
    for (group, name, paths) in [
        ("photon_map_water", "cornell_box_water.yml", 200_000),
        ("photon_map_specular", "cornell_box_specular.yml", 262_144),
    ] {
        let scene = load(name);
        let settings = RenderSettings::new(&scene);
        let Some(Radius::World(radius0)) = scene.defaults.radius else {
            panic!("the shipped scenes give a world radius")
        };
        let photons = photons(&scene, &settings, paths);
        let points = gather_points(&scene, 50_000);
        let mut g = config(c, group);
        g.throughput(Throughput::Elements(photons.len() as u64));
        let mut grid = HashGrid::new();
        g.bench_function("grid_build", |b| {
            b.iter(|| grid.build(black_box(&photons), radius0))
        });
        for radius in [radius0, radius0 * 0.5] {
            grid.build(&photons, radius);
            let ctx = GatherContext {
                grid: &grid,
                kernel: Kernel::new(radius),
                radius,
                inv_paths: 1.0 / paths as f32,
            };
            g.throughput(Throughput::Elements(points.len() as u64));
            g.bench_with_input(
                BenchmarkId::new("gather", format!("r={radius}")),
                &points,
                |b, points| {
                    b.iter(|| {
                        let mut sum = Vec3::ZERO;
                        for (hit, wo) in points {
                            let albedo = scene
                                .material(hit)
                                .bsdf
                                .diffuse_part()
                                .expect("gather points store photons")
                                .albedo;
                            let normals = ShadingFrame::new(hit, *wo).gather_normals(hit, *wo);
                            sum += density_estimate(&ctx, hit.p, normals, albedo, u32::MAX);
                        }
                        sum
                    })
                },
            );
        }
    }
}

/// One iteration of each integrator (`pt`, `ppm`, `sppm`, `vcm`) with the scene's settings, on
/// a pool of one thread; throughput in pixels. The render state carries over from sample to
/// sample (a photon mapper's radius keeps shrinking), as in a render.
fn iteration(c: &mut Criterion) {
    let mut g = config(c, "iteration");
    let name = "cornell_box_water.yml";
    let scene = load_small(name, 64, 64).build().unwrap();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    g.throughput(Throughput::Elements(64 * 64));
    for algorithm in Algorithm::ALL {
        let settings = RenderSettings::for_algorithm(&scene, algorithm);
        let mut renderer = Renderer::new(&scene, &settings);
        g.bench_function(BenchmarkId::new(algorithm.name(), name), |b| {
            b.iter(|| pool.install(|| renderer.iterate(&scene)).rays)
        });
    }
}

criterion_group!(benches, rays, photon_tracing, photon_map, iteration);
criterion_main!(benches);
