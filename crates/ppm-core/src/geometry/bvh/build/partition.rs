//! Dividing a set of references as the SAH's split says (`sah.rs` chooses the split).
//!
//! A plane split puts on the left every primitive whose centroid lies in a bin below the
//! plane ([`Binner::below`], the very test the binning priced), and returns both sides'
//! sets (boxes, centroid boxes, counts), accumulated as the references are visited.
//!
//! Sets below [`PARALLEL_PARTITION_MIN`] references are divided in place by the two-finger
//! partition. Larger ones (the top of the tree, where one thread would otherwise divide a
//! million references while the others wait) are divided in parallel, in blocks of
//! [`BLOCK`] references, a size fixed independently of the number of threads:
//!
//! 1. each block is divided in place by the two-finger partition, giving the block's left
//!    count and the sets of its two sides;
//! 2. a prefix sum over the blocks' left counts gives each block's two destination ranges
//!    (its left references after the lefts of the blocks before it, its right ones after
//!    the `mid` lefts and the rights before it), disjoint slices of the set;
//! 3. each block copies its two runs to their ranges of a scratch array, which is copied
//!    back.
//!
//! The sides' sets are the blocks' sets merged in block order; a set is a union of boxes
//! (min and max) and integer counts, whose result does not depend on the order, so they
//! equal the serial partition's bit for bit. Each side holds the same references as the
//! serial partition's, in another order: the blocks' runs in block order. Nothing in the
//! build depends on the order within a side except a set whose centroids all coincide
//! (halved by count) and the lanes of a leaf's packets; both are the same on any number of
//! threads, since the blocks are.

use super::sah::{Binner, PrimRef, SetInfo, Split, PARALLEL_MIN};
use rayon::prelude::*;

/// References per block of the parallel partition.
const BLOCK: usize = PARALLEL_MIN / 2;

/// Sets at least this large are partitioned in parallel. The parallel partition moves every
/// reference twice more than the serial one (to the scratch array and back), which pays
/// where threads would idle: the few partitions at the top of the tree, before the subtrees
/// become parallel tasks (`PARALLEL_MIN` and up) that keep every thread busy.
pub(super) const PARALLEL_PARTITION_MIN: usize = 8 * PARALLEL_MIN;

/// Divides `refs` as `split` says; returns the left count and both halves' sets.
/// `scratch` is as long as `refs`; its contents on entry and exit mean nothing.
pub(super) fn partition(
    refs: &mut [PrimRef],
    scratch: &mut [PrimRef],
    info: &SetInfo,
    split: &Split,
) -> (usize, SetInfo, SetInfo) {
    debug_assert_eq!(refs.len(), scratch.len());
    match *split {
        Split::Plane { axis, bin, bins } => {
            let along = Binner::new(&info.centroids, bins).axis(axis);
            let plane = bin as f32;
            let goes_left = |r: &PrimRef| Binner::below(r, axis, along, plane);
            if refs.len() >= PARALLEL_PARTITION_MIN {
                in_blocks(refs, scratch, goes_left)
            } else {
                two_finger(refs, goes_left)
            }
        }
        Split::Halves => {
            let mid = refs.len() / 2;
            let (l, r) = refs.split_at(mid);
            (mid, SetInfo::of(l), SetInfo::of(r))
        }
    }
}

/// The two-finger partition, serial and in place: each reference is added to its side's
/// set as the fingers pass it.
fn two_finger(
    refs: &mut [PrimRef],
    goes_left: impl Fn(&PrimRef) -> bool,
) -> (usize, SetInfo, SetInfo) {
    let (mut left, mut right) = (SetInfo::EMPTY, SetInfo::EMPTY);
    let (mut i, mut j) = (0, refs.len());
    loop {
        while i < j && goes_left(&refs[i]) {
            left.add(&refs[i]);
            i += 1;
        }
        while i < j && !goes_left(&refs[j - 1]) {
            right.add(&refs[j - 1]);
            j -= 1;
        }
        if i >= j {
            break;
        }
        refs.swap(i, j - 1);
        left.add(&refs[i]);
        right.add(&refs[j - 1]);
        i += 1;
        j -= 1;
    }
    (i, left, right)
}

/// The parallel partition in blocks (see the module docs).
fn in_blocks(
    refs: &mut [PrimRef],
    scratch: &mut [PrimRef],
    goes_left: impl Fn(&PrimRef) -> bool + Sync,
) -> (usize, SetInfo, SetInfo) {
    // 1. Each block divided in place.
    let blocks: Vec<(usize, SetInfo, SetInfo)> = refs
        .par_chunks_mut(BLOCK)
        .map(|block| two_finger(block, &goes_left))
        .collect();
    // 2. The sides' sets, and each block's destination ranges (the prefix sums, as
    // successive splits of the two sides).
    let mid = blocks.iter().map(|b| b.0).sum();
    let (left, right) = blocks
        .iter()
        .fold((SetInfo::EMPTY, SetInfo::EMPTY), |(l, r), b| {
            (l.merge(&b.1), r.merge(&b.2))
        });
    let (mut lefts, mut rights) = scratch.split_at_mut(mid);
    let mut moves = Vec::with_capacity(blocks.len());
    for (block, &(to_left, ..)) in refs.chunks(BLOCK).zip(&blocks) {
        let (l, rest) = std::mem::take(&mut lefts).split_at_mut(to_left);
        lefts = rest;
        let (r, rest) = std::mem::take(&mut rights).split_at_mut(block.len() - to_left);
        rights = rest;
        moves.push((block, l, r));
    }
    // 3. Each block's two runs copied to their ranges of the scratch array, and back.
    moves.into_par_iter().for_each(|(block, l, r)| {
        let (from_left, from_right) = block.split_at(l.len());
        l.copy_from_slice(from_left);
        r.copy_from_slice(from_right);
    });
    refs.par_chunks_mut(BLOCK)
        .zip(scratch.par_chunks(BLOCK))
        .for_each(|(to, from)| to.copy_from_slice(from));
    (mid, left, right)
}

#[cfg(test)]
mod tests {
    use super::super::sah::Aabb;
    use super::*;
    use crate::sampling::Rng;
    use glam::Vec3A;

    /// `n` boxes: `grid` puts corners and sizes on a grid of quarters (many coincident
    /// centroids, and many on the planes' borders); about a third are spheres when
    /// `spheres`.
    fn boxes(rng: &mut Rng, n: usize, grid: bool, spheres: bool) -> Vec<PrimRef> {
        let mut coordinate = || {
            let u = rng.uniform();
            if grid {
                (u * 4.0).floor() / 4.0
            } else {
                u
            }
        };
        (0..n)
            .map(|i| {
                let lo = Vec3A::new(coordinate(), coordinate(), coordinate());
                let size = Vec3A::new(coordinate(), coordinate(), coordinate()) * 0.25;
                let sphere = spheres && coordinate() < 0.3;
                PrimRef::new(Aabb { lo, hi: lo + size }, i as u32, sphere)
            })
            .collect()
    }

    /// The parallel partition against the two-finger one on sets just below, at and above
    /// the threshold and of several blocks with a partial last one, with coincident
    /// centroids and spheres, for planes on every axis: the same left count, the same
    /// primitives on each side, the same sets bit for bit; above the threshold each block's
    /// runs in block order; and the same answer on one thread and on three.
    #[test]
    fn the_parallel_partition_agrees_with_the_two_finger_one() {
        let mut rng = Rng::new(19, 0, 0);
        let sizes = [
            PARALLEL_PARTITION_MIN - 1,
            PARALLEL_PARTITION_MIN,
            PARALLEL_PARTITION_MIN + 1,
            PARALLEL_PARTITION_MIN + 3 * BLOCK + 777,
        ];
        let pool = |threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
        };
        let (one, three) = (pool(1), pool(3));
        let mut parallel_runs = 0;
        for (k, &n) in sizes.iter().enumerate() {
            for (grid, spheres) in [(false, false), (true, false), (true, true), (false, true)] {
                let refs = boxes(&mut rng, n, grid, spheres);
                let info = SetInfo::of(&refs);
                for (axis, bin) in [(0, 1), (1, 16), (2, 31), (k % 3, 8)] {
                    let split = Split::Plane {
                        axis,
                        bin,
                        bins: 32,
                    };
                    let mut serial = refs.clone();
                    let want = {
                        let along = Binner::new(&info.centroids, 32).axis(axis);
                        two_finger(&mut serial, |r| Binner::below(r, axis, along, bin as f32))
                    };
                    let run = |pool: &rayon::ThreadPool| {
                        let (mut ours, mut scratch) = (refs.clone(), refs.clone());
                        let got =
                            pool.install(|| partition(&mut ours, &mut scratch, &info, &split));
                        (got, ours)
                    };
                    let ((mid, left, right), ours) = run(&one);
                    assert_eq!(mid, want.0, "n {n} {split:?}");
                    assert!(0 < mid && mid < n, "a plane with both sides full");
                    let sorted = |v: &[PrimRef]| {
                        let mut ids: Vec<u32> = v.iter().map(|r| r.id).collect();
                        ids.sort_unstable();
                        ids
                    };
                    assert_eq!(sorted(&ours[..mid]), sorted(&serial[..mid]));
                    assert_eq!(sorted(&ours[mid..]), sorted(&serial[mid..]));
                    let bits = |s: &SetInfo| format!("{s:?}");
                    assert_eq!(bits(&left), bits(&want.1), "n {n} {split:?}");
                    assert_eq!(bits(&right), bits(&want.2), "n {n} {split:?}");
                    let ids = |v: &[PrimRef]| v.iter().map(|r| r.id).collect::<Vec<u32>>();
                    if n >= PARALLEL_PARTITION_MIN {
                        parallel_runs += 1;
                        let along = Binner::new(&info.centroids, 32).axis(axis);
                        let (mut blocks, mut rights) = (refs.clone(), Vec::new());
                        let mut order = Vec::new();
                        for block in blocks.chunks_mut(BLOCK) {
                            let (m, ..) =
                                two_finger(block, |r| Binner::below(r, axis, along, bin as f32));
                            order.extend_from_slice(&block[..m]);
                            rights.extend_from_slice(&block[m..]);
                        }
                        order.extend(rights);
                        assert_eq!(ids(&ours), ids(&order), "the blocks' runs in block order");
                    } else {
                        assert_eq!(ids(&ours), ids(&serial), "below the threshold: two-finger");
                    }
                    let (_, ours3) = run(&three);
                    assert_eq!(ids(&ours), ids(&ours3), "one thread against three");
                }
            }
        }
        assert_eq!(parallel_runs, 3 * 4 * 4);
    }
}
