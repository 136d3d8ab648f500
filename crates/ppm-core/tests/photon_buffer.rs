//! Concurrency stress test of the lock-free photon append buffer: every thread count from 1 to
//! 16, many small batches (partial writer batches, direct `push_batch` calls of every size up
//! to twice [`BATCH`]), passes that overflow the buffer, then grow it and are redone. After
//! each pass the stored photons are checked one by one: when nothing overflowed, every pushed
//! photon is stored exactly once; when the buffer overflowed, it holds exactly `capacity`
//! distinct pushed photons and counts the rest as dropped.

use glam::Vec3;
use ppm_core::photon::{Photon, PhotonBuffer, BATCH};
use rayon::prelude::*;

/// A photon that names itself: (path, bounce) in its position (exact in f32 below 2^24).
fn tagged(path: u32, bounce: u32) -> Photon {
    Photon::new(
        Vec3::new(path as f32, bounce as f32, 0.0),
        Vec3::Z,
        Vec3::ONE,
        path,
    )
}

/// Photons path `path` pushes in the pass seeded by `salt`: 0 to 12, scrambled.
fn bounces(path: u32, salt: u32) -> u32 {
    let h = (path ^ salt.wrapping_mul(0x9e37_79b9)).wrapping_mul(0x85eb_ca6b);
    (h ^ (h >> 15)) % 13
}

/// How the workers hand their photons to the buffer.
#[derive(Clone, Copy, Debug)]
enum Pushing {
    /// A `PhotonWriter` per rayon job of at most `jobs` paths (flushed when full and on drop).
    Writers { jobs: usize },
    /// One `push_batch` per path, batches of 1 to 2 * BATCH photons.
    Batches,
}

/// One pass on a pool of `threads` threads; returns the photons pushed, sorted.
fn pass(
    buffer: &mut PhotonBuffer,
    threads: usize,
    paths: u32,
    salt: u32,
    how: Pushing,
) -> Vec<(u32, u32)> {
    buffer.clear();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let shared = &*buffer;
    pool.install(|| match how {
        Pushing::Writers { jobs } => (0..paths).into_par_iter().with_max_len(jobs).for_each_init(
            || shared.writer(),
            |writer, path| {
                for bounce in 0..bounces(path, salt) {
                    writer.push(tagged(path, bounce));
                }
            },
        ),
        Pushing::Batches => (0..paths).into_par_iter().with_max_len(1).for_each(|path| {
            let n = (path as usize * 7 + salt as usize) % (2 * BATCH) + 1;
            let batch: Vec<Photon> = (0..n as u32).map(|b| tagged(path, b)).collect();
            let stored = shared.push_batch(&batch);
            assert!(stored <= n);
        }),
    });
    let mut pushed: Vec<(u32, u32)> = match how {
        Pushing::Writers { .. } => (0..paths)
            .flat_map(|path| (0..bounces(path, salt)).map(move |b| (path, b)))
            .collect(),
        Pushing::Batches => (0..paths)
            .flat_map(|path| {
                let n = (path as usize * 7 + salt as usize) % (2 * BATCH) + 1;
                (0..n as u32).map(move |b| (path, b))
            })
            .collect(),
    };
    pushed.sort_unstable();
    pushed
}

/// The stored photons' tags, sorted; each photon must be one `tagged` made.
fn stored(buffer: &mut PhotonBuffer) -> Vec<(u32, u32)> {
    let mut tags: Vec<(u32, u32)> = buffer
        .as_slice()
        .iter()
        .map(|p| {
            let (path, bounce) = (p.position.x as u32, p.position.y as u32);
            assert_eq!(*p, tagged(path, bounce), "a torn or foreign photon");
            (path, bounce)
        })
        .collect();
    tags.sort_unstable();
    tags
}

#[test]
fn every_pushed_photon_is_stored_exactly_once_at_any_thread_count() {
    let paths = 2000;
    let mut buffer = PhotonBuffer::with_capacity(1000);
    for threads in 1..=16 {
        for (k, how) in [
            Pushing::Writers { jobs: 1 },
            Pushing::Writers { jobs: 37 },
            Pushing::Batches,
        ]
        .into_iter()
        .enumerate()
        {
            let salt = (threads * 3 + k) as u32;
            // Overflowing pass: exactly `capacity` distinct pushed photons, the rest counted.
            let capacity = buffer.capacity();
            let pushed = pass(&mut buffer, threads, paths, salt, how);
            assert!(pushed.len() > capacity, "the pass must overflow");
            assert!(buffer.overflowed(), "{threads} threads, {how:?}");
            assert_eq!(
                (buffer.len(), buffer.pushed(), buffer.dropped()),
                (capacity, pushed.len(), pushed.len() - capacity),
                "{threads} threads, {how:?}"
            );
            let kept = stored(&mut buffer);
            assert!(
                kept.windows(2).all(|w| w[0] < w[1]),
                "a photon stored twice"
            );
            assert!(kept.iter().all(|t| pushed.binary_search(t).is_ok()));

            // Grown to what the pass needed, the redone pass keeps every photon once.
            buffer.grow(buffer.pushed());
            let again = pass(&mut buffer, threads, paths, salt, how);
            assert!(!buffer.overflowed(), "{threads} threads, {how:?}");
            assert_eq!(stored(&mut buffer), again, "{threads} threads, {how:?}");

            // Back to a small buffer for the next overflow (a fresh allocation).
            buffer = PhotonBuffer::with_capacity(1000 + threads);
        }
    }
}
