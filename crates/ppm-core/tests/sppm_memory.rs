//! SPPM's memory is bounded by the pixels: the peak heap of a render at 10^6 and at 10^7
//! photons per iteration differs by less than 10%. A test binary of its own, because it
//! counts every allocation of the process with a global allocator.

use ppm_core::integrator::MemoryPart;
use ppm_core::prelude::*;
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

struct Counting;

static CURRENT: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = System.alloc(layout);
        if !p.is_null() {
            let now = CURRENT.fetch_add(layout.size(), Ordering::Relaxed) + layout.size();
            PEAK.fetch_max(now, Ordering::Relaxed);
        }
        p
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout);
        CURRENT.fetch_sub(layout.size(), Ordering::Relaxed);
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// A closed diffuse box seen at 16 x 16 pixels, with a light under the ceiling.
fn scene() -> Scene {
    let camera = Camera::new(
        Vec3::new(0.0, 1.0, 0.9),
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::Y,
        70.0,
        (16, 16),
    )
    .unwrap();
    let mut b = SceneBuilder::new(camera);
    let white = b.add_material(Material::new(Bsdf::diffuse(Vec3::splat(0.7)), Vec3::ZERO));
    let lamp = b.add_material(Material::new(Bsdf::diffuse(Vec3::ZERO), Vec3::splat(10.0)));
    let q = |c: [f32; 3], u: [f32; 3], v: [f32; 3], m| {
        TriangleMesh::quad(Vec3::from(c), Vec3::from(u), Vec3::from(v), m)
    };
    b.add_mesh(q(
        [-1.0, 0.0, -1.0],
        [0.0, 0.0, 2.0],
        [2.0, 0.0, 0.0],
        white,
    ));
    b.add_mesh(q(
        [-1.0, 2.0, -1.0],
        [2.0, 0.0, 0.0],
        [0.0, 0.0, 2.0],
        white,
    ));
    b.add_mesh(q(
        [-1.0, 0.0, -1.0],
        [2.0, 0.0, 0.0],
        [0.0, 2.0, 0.0],
        white,
    ));
    b.add_mesh(q([-1.0, 0.0, 1.0], [0.0, 2.0, 0.0], [2.0, 0.0, 0.0], white));
    b.add_mesh(q(
        [-1.0, 0.0, -1.0],
        [0.0, 2.0, 0.0],
        [0.0, 0.0, 2.0],
        white,
    ));
    b.add_mesh(q([1.0, 0.0, -1.0], [0.0, 0.0, 2.0], [0.0, 2.0, 0.0], white));
    b.add_mesh(q(
        [-0.25, 1.98, -0.25],
        [0.5, 0.0, 0.0],
        [0.0, 0.0, 0.5],
        lamp,
    ));
    b.build().unwrap()
}

/// Peak heap bytes (above what was live before) of creating a render and running one
/// iteration with `photons` light paths, and the render state's own count of its bytes.
/// A world radius: the default radius's pilot photon map has a fixed size of its own.
fn peak_bytes(scene: &Scene, algorithm: Algorithm, photons: u32) -> (usize, usize) {
    peak_bytes_with(scene, algorithm, photons, Radius::World(0.05))
}

/// [`peak_bytes`] with the initial radius `radius`.
fn peak_bytes_with(
    scene: &Scene,
    algorithm: Algorithm,
    photons: u32,
    radius: Radius,
) -> (usize, usize) {
    let settings = RenderSettings {
        photons,
        radius,
        max_depth: 2, // short light paths: the test is about storage, not transport
        ..RenderSettings::for_algorithm(scene, algorithm)
    };
    // One worker: rayon's per-thread buffers stay out of the comparison.
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    pool.install(|| {
        let base = CURRENT.load(Ordering::Relaxed);
        PEAK.store(base, Ordering::Relaxed);
        let mut r = Renderer::new(scene, &settings);
        let stats = r.iterate(scene);
        assert!(stats.photons as f64 > 0.3 * photons as f64, "{stats:?}");
        let declared = r.memory_bytes();
        drop(r);
        (PEAK.load(Ordering::Relaxed) - base, declared)
    })
}

#[test]
fn sppm_memory_does_not_grow_with_the_photons() {
    let scene = scene();
    let (peak6, declared6) = peak_bytes(&scene, Algorithm::Sppm, 1_000_000);
    let (peak7, declared7) = peak_bytes(&scene, Algorithm::Sppm, 10_000_000);
    assert!(
        (peak7 as f64) < 1.1 * peak6 as f64,
        "peak heap: {peak6} bytes at 10^6 photons, {peak7} at 10^7"
    );
    assert!((declared7 as f64) < 1.1 * declared6 as f64);
    // The measurement can see photon storage: ppm, which stores its photons, grows.
    let (ppm6, _) = peak_bytes(&scene, Algorithm::Ppm, 100_000);
    let (ppm7, _) = peak_bytes(&scene, Algorithm::Ppm, 1_000_000);
    assert!(ppm7 as f64 > 5.0 * ppm6 as f64, "ppm: {ppm6} vs {ppm7}");
}

/// The memory estimate's pilot part covers what the `photons` radius's pilot allocates beyond
/// a world radius's render, without exceeding it many times over (vcm's pilot is the same
/// code; its light paths do not follow `photons`, which `peak_bytes_with` checks).
#[test]
fn the_pilot_estimate_covers_the_pilot_photon_map() {
    let scene = scene();
    for algorithm in [Algorithm::Ppm, Algorithm::Sppm] {
        let (world, _) = peak_bytes_with(&scene, algorithm, 10_000, Radius::World(0.05));
        let (photons, _) = peak_bytes_with(&scene, algorithm, 10_000, Radius::Photons);
        let settings = RenderSettings {
            photons: 10_000,
            radius: Radius::Photons,
            ..RenderSettings::for_algorithm(&scene, algorithm)
        };
        let pilot: u64 = Renderer::memory_estimate(&scene, &settings)
            .items
            .iter()
            .filter(|i| i.part == MemoryPart::Pilot)
            .map(|i| i.bytes)
            .sum();
        let extra = photons.saturating_sub(world) as u64;
        assert!(
            extra <= pilot && extra > pilot / 8,
            "{algorithm:?}: the pilot allocates {extra} bytes, estimated {pilot}"
        );
    }
}
