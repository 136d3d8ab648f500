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

/// Triangles per bucket of the hash's range, on average: a bucket is sorted in cache.
const BUCKET: usize = 1024;

/// For each triangle, true if it duplicates an earlier one (the first copy is kept).
///
/// Equal triangles have equal hashes, so only triangles of equal hash are compared. The
/// (hash, index) pairs are distributed by hash into about n / [`BUCKET`] buckets (one
/// counting pass and one scattering pass, serial and sequential in the triangles), and each
/// bucket is sorted by (hash, index) and scanned for runs of equal hashes, the buckets in
/// parallel: a few passes over the triangles and small sorts in cache, where one parallel
/// sort of all the pairs moved each of them log n times. Within a run the indices increase,
/// so the first copy is the one kept; the mask does not depend on the number of threads, nor
/// on how many copies there are (20,000 copies are one run of one bucket).
pub(super) fn duplicate_mask(triangles: &[Triangle]) -> Vec<bool> {
    let hashes: Vec<u64> = triangles.par_iter().map(key).collect();
    let buckets = (triangles.len() / BUCKET).max(1);
    // The bucket of a hash: its position in [0, 2^64) scaled to the bucket count (the high
    // word of a 64 x 64-bit product), so the hash's high bits pick it.
    let bucket = |h: u64| ((h as u128 * buckets as u128) >> 64) as usize;
    let mut start = vec![0usize; buckets + 1];
    for &h in &hashes {
        start[bucket(h) + 1] += 1;
    }
    for b in 0..buckets {
        start[b + 1] += start[b];
    }
    let mut fill = start.clone();
    let mut pairs = vec![(0u64, 0u32); triangles.len()];
    for (i, &h) in hashes.iter().enumerate() {
        let b = bucket(h);
        pairs[fill[b]] = (h, i as u32);
        fill[b] += 1;
    }
    drop(hashes);
    let mut slices = Vec::with_capacity(buckets);
    let mut rest = pairs.as_mut_slice();
    for b in 0..buckets {
        let (slice, tail) = std::mem::take(&mut rest).split_at_mut(start[b + 1] - start[b]);
        slices.push(slice);
        rest = tail;
    }
    let found: Vec<Vec<u32>> = slices
        .into_par_iter()
        .map(|slice| {
            slice.sort_unstable();
            duplicates_in(slice, triangles)
        })
        .filter(|found| !found.is_empty())
        .collect();
    let mut duplicate = vec![false; triangles.len()];
    for &i in found.iter().flatten() {
        duplicate[i as usize] = true;
    }
    duplicate
}

/// The duplicates among `pairs` of (hash, index), sorted.
fn duplicates_in(pairs: &[(u64, u32)], triangles: &[Triangle]) -> Vec<u32> {
    let mut duplicates = Vec::new();
    let mut kept: Vec<u32> = Vec::new();
    let mut start = 0;
    while start < pairs.len() {
        let hash = pairs[start].0;
        let end = start + pairs[start..].iter().take_while(|k| k.0 == hash).count();
        if end - start > 1 {
            // Each one is compared with the distinct triangles kept before it (one in
            // practice; more only on a hash collision).
            kept.clear();
            for &(_, i) in &pairs[start..end] {
                let t = &triangles[i as usize];
                if kept.iter().any(|&k| same(&triangles[k as usize], t)) {
                    duplicates.push(i);
                } else {
                    kept.push(i);
                }
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

    /// Random triangles with copies: one triangle 20,000 times (a bucket of one long run,
    /// whose first copy is the one kept), 500 copies of random earlier ones, and near-copies
    /// that differ in one bit or in the order of the vertices (not duplicates); on one
    /// thread and on three.
    #[test]
    fn the_bucketed_scan_marks_what_a_hash_map_marks() {
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
