//! Times iterations of an integrator on the large-mesh scene (`ppm_benches::large_mesh`): how
//! a whole render, not one ray set, runs on a scene larger than the caches.
//!
//! `cargo run --release -p ppm-benches --example large_mesh_render -- [--threads N]
//! [--algorithm pt|ppm|sppm|vcm] [--iterations I] [--size PIXELS]` renders one iteration to
//! warm up, then I iterations (default 3) at PIXELS x PIXELS (default 512) with the
//! algorithm's default settings on a pool of N threads (default 1), and prints their time and
//! the closest-hit rays per second.

use ppm_benches::large_mesh::{large_scene, LARGE_N};
use ppm_core::integrator::{Algorithm, RenderSettings, Renderer};
use std::time::Instant;

fn main() {
    let mut args = std::env::args().skip(1);
    let (mut threads, mut algorithm, mut iterations, mut size) = (1, Algorithm::Path, 3, 512);
    while let Some(a) = args.next() {
        let mut value = || args.next().expect("a value after the flag");
        match a.as_str() {
            "--threads" => threads = value().parse().expect("--threads N"),
            "--iterations" => iterations = value().parse().expect("--iterations I"),
            "--size" => size = value().parse().expect("--size PIXELS"),
            "--algorithm" => {
                algorithm = value()
                    .parse()
                    .unwrap_or_else(|e| panic!("--algorithm: {e}"))
            }
            other => panic!("unknown argument {other}"),
        }
    }
    let scene = large_scene(LARGE_N, size, size);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let settings = RenderSettings::for_algorithm(&scene, algorithm);
    let mut renderer = Renderer::new(&scene, &settings);
    pool.install(|| renderer.iterate(&scene));
    let start = Instant::now();
    let rays: u64 = (0..iterations)
        .map(|_| pool.install(|| renderer.iterate(&scene)).rays)
        .sum();
    let seconds = start.elapsed().as_secs_f64();
    println!(
        "{algorithm:?} threads {threads} iterations {iterations} time_s {seconds:.3} Mrays/s {:.3}",
        rays as f64 / seconds / 1e6
    );
}
