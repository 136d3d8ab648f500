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

/// For each triangle, true if it duplicates an earlier one (the first copy is kept).
/// A parallel sort by (hash, index), then a scan of each run of equal hashes: linear in
/// the number of triangles however many copies there are.
pub(super) fn duplicate_mask(triangles: &[Triangle]) -> Vec<bool> {
    let mut keys: Vec<(u64, u32)> = triangles
        .par_iter()
        .enumerate()
        .map(|(i, t)| (key(t), i as u32))
        .collect();
    keys.par_sort_unstable();
    let mut duplicate = vec![false; triangles.len()];
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
                duplicate[i as usize] = true;
            } else {
                kept.push(i);
            }
        }
        start = end;
    }
    duplicate
}
