//! Photon grid throughput on a realistic photon map, without a renderer.
//!
//! Photons come from a light on the ceiling of an open-front unit box (a Cornell box without
//! geometry inside): cosine-distributed emission, up to four diffuse bounces with Russian
//! roulette, so the density varies strongly between floor, walls and ceiling. Gather points
//! are uniform on the five walls.
//!
//! `cargo bench -p ppm-core --bench gather`

use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use ppm_core::photon::{HashGrid, Kernel, Photon};
use ppm_core::sampling::{cosine_hemisphere, Frame, Rng};
use ppm_core::Vec3;
use std::time::Duration;

const PHOTONS: usize = 200_000;
const QUERIES: usize = 20_000;
/// Gather radius: about 80 photons per disc on average over the 5 m² of walls.
const RADIUS: f32 = 0.025;

/// Where a ray from `o` (inside the unit box) along `d` leaves it, and the inward normal of
/// that wall; `None` if it leaves through the open front (z = 1).
fn exit_box(o: Vec3, d: Vec3) -> Option<(Vec3, Vec3)> {
    let mut t_min = f32::INFINITY;
    let mut normal = Vec3::ZERO;
    for axis in 0..3 {
        if d[axis] == 0.0 {
            continue;
        }
        let wall = if d[axis] > 0.0 { 1.0 } else { 0.0 };
        let t = (wall - o[axis]) / d[axis];
        if t < t_min {
            t_min = t;
            normal = Vec3::ZERO;
            normal[axis] = -d[axis].signum();
        }
    }
    let p = (o + d * t_min).clamp(Vec3::ZERO, Vec3::ONE);
    (normal.z != -1.0).then_some((p, normal))
}

/// Traces light paths until `count` photons are stored; photons of one path are consecutive.
fn photon_map(count: usize) -> Vec<Photon> {
    let light = Vec3::new(0.5, 0.999, 0.5);
    let mut photons = Vec::with_capacity(count);
    let mut path = 0u32;
    while photons.len() < count {
        let mut rng = Rng::new(11, 0, path as u64);
        let (mut o, mut d) = (
            light,
            Frame::new(-Vec3::Y).to_world(cosine_hemisphere(rng.uniform2())),
        );
        let mut flux = Vec3::splat(1e-5);
        for _bounce in 0..4 {
            let Some((p, n)) = exit_box(o, d) else { break };
            photons.push(Photon::new(p, -d, flux, path));
            if photons.len() == count || rng.uniform() >= 0.6 {
                break;
            }
            flux *= Vec3::new(0.7, 0.6, 0.5) / 0.6; // albedo / survival probability
            (o, d) = (
                p + n * 1e-4,
                Frame::new(n).to_world(cosine_hemisphere(rng.uniform2())),
            );
        }
        path += 1;
    }
    photons
}

/// A point on wall `wall` (0 floor, 1 ceiling, 2 back, 3 left, 4 right) at `(u, v)`.
fn on_wall(wall: usize, u: f32, v: f32) -> Vec3 {
    match wall {
        0 => Vec3::new(u, 0.0, v),
        1 => Vec3::new(u, 1.0, v),
        2 => Vec3::new(u, v, 0.0),
        3 => Vec3::new(0.0, u, v),
        _ => Vec3::new(1.0, u, v),
    }
}

/// Uniform points on the five walls, in random order (every query misses the cache).
fn random_points(count: usize) -> Vec<Vec3> {
    let mut rng = Rng::new(12, 0, 0);
    (0..count)
        .map(|_| on_wall((rng.uniform() * 5.0) as usize, rng.uniform(), rng.uniform()))
        .collect()
}

/// Jittered raster points wall after wall in scanline order, like the gather points of
/// consecutive pixels: neighbouring queries share cells.
fn coherent_points(count: usize) -> Vec<Vec3> {
    let side = ((count / 5) as f32).sqrt().ceil() as usize;
    let mut rng = Rng::new(13, 0, 0);
    let mut points = Vec::with_capacity(5 * side * side);
    for wall in 0..5 {
        for j in 0..side {
            for i in 0..side {
                let uv = (glam::Vec2::new(i as f32, j as f32) + rng.uniform2()) / side as f32;
                points.push(on_wall(wall, uv.x, uv.y));
            }
        }
    }
    points.truncate(count);
    points
}

/// Irradiance estimates E = Σ Φ_p k(d²) at every point, on one thread.
fn estimate_all(grid: &HashGrid, points: &[Vec3], kernel: Kernel) -> Vec3 {
    let mut total = Vec3::ZERO;
    for &x in points {
        let mut irradiance = Vec3::ZERO;
        grid.for_each_in_radius(black_box(x), RADIUS, |photon, d2| {
            irradiance += photon.flux * kernel.weight(d2);
        });
        total += irradiance;
    }
    total
}

fn gather(c: &mut Criterion) {
    let photons = photon_map(PHOTONS);
    let mut grid = HashGrid::new();
    grid.build(&photons, RADIUS);
    let kernel = Kernel::new(RADIUS);

    let mut group = c.benchmark_group("gather");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3));

    for (name, points) in [
        ("density_estimate_random", random_points(QUERIES)),
        ("density_estimate_coherent", coherent_points(QUERIES)),
    ] {
        let found: usize = points
            .iter()
            .map(|&x| {
                let mut n = 0;
                grid.for_each_in_radius(x, RADIUS, |_, _| n += 1);
                n
            })
            .sum();
        eprintln!(
            "{name}: {:.1} photons per estimate",
            found as f64 / points.len() as f64
        );
        group.throughput(Throughput::Elements(points.len() as u64));
        group.bench_function(name, |b| b.iter(|| estimate_all(&grid, &points, kernel)));
    }

    // Rebuilding the grid over the same photons (allocations reused, as in a render).
    group.throughput(Throughput::Elements(PHOTONS as u64));
    group.bench_function("build", |b| {
        b.iter(|| grid.build(black_box(&photons), RADIUS))
    });
    group.finish();
}

criterion_group!(benches, gather);
criterion_main!(benches);
