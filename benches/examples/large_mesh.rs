//! Builds the large-mesh scene (`ppm_benches::large_mesh`), writes its triangles and ray sets to
//! a file for an outside ray tracer, and times ppm on the very same rays.
//!
//! `cargo run --release -p ppm-benches --example large_mesh -- [--write FILE] [--threads N]
//! [--n SUBDIVISIONS] [--reps R] [--build-reps B] [--scene NAME] [--only SET]` prints the BVH
//! build time (B rebuilds, default R), the geometry's bytes per triangle, the tree's counts and
//! SAH cost (`Geometry::bvh_stats`) and, per ray set (camera, incoherent, shadow; or only SET),
//! the hits and the rays per second (best and median of R repetitions) on a pool of N threads.
//! `--scene cornell_box_water.yml` uses a shipped scene (without its spheres, which another ray
//! tracer would not share) instead of the large mesh.

use ppm_benches::large_mesh::{large_scene, ray_sets, write_ray_file, LARGE_N};
use ppm_core::geometry::Geometry;
use ppm_core::geometry::Ray;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

fn main() {
    let mut args = std::env::args().skip(1);
    let (mut write, mut threads, mut n, mut reps, mut scene_name) = (None, 1, LARGE_N, 5, None);
    let (mut only, mut build_reps): (Option<String>, Option<usize>) = (None, None);
    while let Some(a) = args.next() {
        let mut value = || args.next().expect("a value after the flag");
        match a.as_str() {
            "--write" => write = Some(value()),
            "--threads" => threads = value().parse().expect("--threads N"),
            "--n" => n = value().parse().expect("--n SUBDIVISIONS"),
            "--reps" => reps = value().parse().expect("--reps R"),
            "--scene" => scene_name = Some(value()),
            "--only" => only = Some(value()),
            "--build-reps" => build_reps = Some(value().parse().expect("--build-reps B")),
            other => panic!("unknown argument {other}"),
        }
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let scene = match scene_name {
        Some(name) => {
            let mut builder = ppm_tests::load_small(&name, 1024, 1024);
            builder.spheres.clear();
            builder.build().expect("the scene builds")
        }
        None => large_scene(n, 1024, 1024),
    };
    let sets = ray_sets(&scene);
    if let Some(path) = write {
        write_ray_file(std::path::Path::new(&path), &scene, &sets).unwrap();
        println!("wrote {path}");
    }
    // Rebuild the BVH alone over the scene's triangles, as the scene build did.
    let meshes = [triangles_as_mesh(&scene.geometry)];
    let mut builds = Vec::new();
    for _ in 0..build_reps.unwrap_or(reps) {
        let start = Instant::now();
        let g = pool.install(|| Geometry::new(&meshes, &[]));
        builds.push(start.elapsed().as_secs_f64());
        assert_eq!(g.triangle_count(), scene.geometry.triangle_count());
    }
    let bytes = scene.geometry.memory_bytes();
    let tris = scene.geometry.triangle_count();
    println!(
        "triangles {tris} threads {threads} build_ms min {:.1} median {:.1} geometry_bytes {bytes} ({:.1} B/tri)",
        min(&builds) * 1e3,
        if builds.is_empty() { f64::NAN } else { median(&mut builds) * 1e3 },
        bytes as f64 / tris as f64
    );
    let s = scene.geometry.bvh_stats();
    println!(
        "bvh nodes {} ({:.2} children each) leaves {} packets {} ({:.2} triangles each) depth {} sah nodes {:.3} leaves {:.3} total {:.3}",
        s.nodes,
        s.children as f64 / s.nodes as f64,
        s.leaves,
        s.packets,
        tris as f64 / s.packets as f64,
        s.depth,
        s.sah_nodes,
        s.sah_leaves,
        s.sah_nodes + s.sah_leaves
    );
    for (name, rays, any) in [
        ("camera", &sets.camera, false),
        ("incoherent", &sets.incoherent, false),
        ("shadow", &sets.shadow, true),
    ] {
        if only.as_ref().is_some_and(|o| o != name) {
            continue;
        }
        let mut times = Vec::new();
        let mut hits = 0;
        for _ in 0..reps {
            let start = Instant::now();
            hits = pool.install(|| trace(&scene.geometry, rays, any));
            times.push(start.elapsed().as_secs_f64());
        }
        println!(
            "{name:<10} rays {} hits {hits} Mrays/s best {:.2} median {:.2}",
            rays.len(),
            rays.len() as f64 / min(&times) / 1e6,
            rays.len() as f64 / median(&mut times) / 1e6
        );
    }
}

/// Hits (closest-hit) or blocked rays (any-hit) on every thread of the pool. The threads
/// take chunks of 4096 rays in order from one shared counter, as the Embree harness's
/// threads do (docs/performance.md), so that both trace neighbouring chunks at the same time.
/// (Rayon's `par_chunks` would hand each thread one half of the set to start with: rays of
/// distant parts of the image, and of the mesh, at the same time.)
fn trace(geometry: &Geometry, rays: &[Ray], any: bool) -> usize {
    const CHUNK: usize = 4096;
    let next = AtomicUsize::new(0);
    let hits = AtomicUsize::new(0);
    rayon::broadcast(|_| {
        let mut found = 0;
        loop {
            let start = next.fetch_add(CHUNK, Ordering::Relaxed);
            if start >= rays.len() {
                break;
            }
            found += rays[start..(start + CHUNK).min(rays.len())]
                .iter()
                .filter(|r| {
                    if any {
                        geometry.occluded(r)
                    } else {
                        geometry.intersect(r).is_some()
                    }
                })
                .count();
        }
        hits.fetch_add(found, Ordering::Relaxed);
    });
    hits.into_inner()
}

fn triangles_as_mesh(geometry: &Geometry) -> ppm_core::geometry::TriangleMesh {
    let count = geometry.triangle_count() as u32;
    let positions = (0..count).flat_map(|p| geometry.triangle(p).0.v).collect();
    let indices = (0..count).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]).collect();
    ppm_core::geometry::TriangleMesh::new(positions, indices, 0)
}

fn min(v: &[f64]) -> f64 {
    v.iter().copied().fold(f64::INFINITY, f64::min)
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}
