//! Exact duplicate triangles: faces whose three vertices equal, bit for bit and in the same
//! order, those of an earlier face. Real exports contain them, and thousands of coincident
//! primitives make any BVH build and traversal pay for primitives that can never be seen.
//!
//! Dropping them changes no answer: the watertight test of the same three vertices in the
//! same order returns the same t to the bit, and the traversal resolves equal distances by
//! the smaller primitive id, so a later duplicate never wins a closest hit, and any-hit is
//! blocked by the first copy exactly when by the second.

use super::super::Triangle;
use rayon::prelude::*;

/// 64-bit hash of a triangle's vertex bit patterns (FNV-1a over the nine words, then a
/// final avalanche); equal triangles have equal hashes, and equal hashes are checked.
fn key(t: &Triangle) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for v in t.v {
        for c in v.to_array() {
            h = (h ^ c.to_bits() as u64).wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    h ^= h >> 33;
    h = h.wrapping_mul(0xff51_afd7_ed55_8ccd);
    h ^ (h >> 33)
}

fn same(a: &Triangle, b: &Triangle) -> bool {
    a.v.iter()
        .zip(&b.v)
        .all(|(p, q)| p.to_array().map(f32::to_bits) == q.to_array().map(f32::to_bits))
}

/// Sorted keys per piece of the parallel scan, about.
const PIECE: usize = 8192;

/// For each triangle, true if it duplicates an earlier one (the first copy is kept).
/// A parallel sort by (hash, index), then a scan of each run of equal hashes: linear in
/// the number of triangles however many copies there are. The runs are scanned in
/// parallel, in pieces of about [`PIECE`] sorted keys whose starts are moved forward to the
/// start of a run (no run is cut), each piece listing the duplicates it finds: the mask is
/// the serial scan's on any number of threads.
pub(super) fn duplicate_mask(triangles: &[Triangle]) -> Vec<bool> {
    let mut keys: Vec<(u64, u32)> = triangles
        .par_iter()
        .enumerate()
        .map(|(i, t)| (key(t), i as u32))
        .collect();
    keys.par_sort_unstable();
    let mut starts: Vec<usize> = (0..keys.len())
        .step_by(PIECE)
        .map(|mut start| {
            while start > 0 && start < keys.len() && keys[start].0 == keys[start - 1].0 {
                start += 1;
            }
            start
        })
        .collect();
    starts.push(keys.len());
    starts.dedup();
    let found: Vec<Vec<u32>> = starts
        .par_windows(2)
        .map(|piece| duplicates_in(&keys[piece[0]..piece[1]], triangles))
        .collect();
    let mut duplicate = vec![false; triangles.len()];
    for &i in found.iter().flatten() {
        duplicate[i as usize] = true;
    }
    duplicate
}

/// The duplicates among sorted `keys` that hold whole runs of equal hashes.
fn duplicates_in(keys: &[(u64, u32)], triangles: &[Triangle]) -> Vec<u32> {
    let mut duplicates = Vec::new();
    let mut kept: Vec<u32> = Vec::new();
    let mut start = 0;
    while start < keys.len() {
        let hash = keys[start].0;
        let end = start + keys[start..].iter().take_while(|k| k.0 == hash).count();
        // Sorted by index within the run: each one is compared with the distinct triangles
        // kept before it (one in practice; more only on a hash collision).
        kept.clear();
        for &(_, i) in &keys[start..end] {
            let t = &triangles[i as usize];
            if kept.iter().any(|&k| same(&triangles[k as usize], t)) {
                duplicates.push(i);
            } else {
                kept.push(i);
            }
        }
        start = end;
    }
    duplicates
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;
    use glam::Vec3;
    use std::collections::HashMap;

    /// The mask by a hash map from the vertices' bits to the first copy: no sort, no pieces.
    fn reference(triangles: &[Triangle]) -> Vec<bool> {
        let mut first = HashMap::new();
        triangles
            .iter()
            .enumerate()
            .map(|(i, t)| {
                let bits = t.v.map(|p| p.to_array().map(f32::to_bits));
                *first.entry(bits).or_insert(i) != i
            })
            .collect()
    }

    /// Random triangles with copies: one triangle 20,000 times (a run of equal hashes
    /// longer than a piece, so the pieces' starts must move past it), 500 copies of random
    /// earlier ones, and near-copies that differ in one bit or in the order of the vertices
    /// (not duplicates); on one thread and on three.
    #[test]
    fn the_parallel_scan_marks_what_a_hash_map_marks() {
        let mut rng = Rng::new(23, 0, 0);
        let mut point = || Vec3::new(rng.uniform(), rng.uniform(), rng.uniform());
        let mut triangles: Vec<Triangle> = (0..30_000)
            .map(|_| Triangle {
                v: [point(), point(), point()],
            })
            .collect();
        let copied = triangles[17];
        triangles.splice(9_000..9_000, std::iter::repeat_n(copied, 20_000));
        let mut rng = Rng::new(24, 0, 0);
        for _ in 0..500 {
            let from = (rng.uniform() * triangles.len() as f32) as usize;
            let at = (rng.uniform() * triangles.len() as f32) as usize;
            let mut t = triangles[from];
            match (rng.uniform() * 3.0) as u32 {
                0 => {}
                1 => t.v[1].y = f32::from_bits(t.v[1].y.to_bits() ^ 1),
                _ => t.v.rotate_left(1),
            }
            triangles.insert(at, t);
        }
        let want = reference(&triangles);
        assert!(want.iter().filter(|&&d| d).count() > 20_000);
        for threads in [1, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let got = pool.install(|| duplicate_mask(&triangles));
            assert!(got == want, "{threads} threads");
        }
    }
}
