//! The SAH split's binning, partition and plane choice against straightforward reference
//! implementations (the ones they replaced, written for clarity rather than speed), on
//! random sets with coincident centroids, flat axes, equal costs and spheres, and on
//! non-finite positions: the tree must stay the same, node for node.

use super::*;
use crate::sampling::Rng;

/// The reference bin of `r` along each axis: the position converted by Rust's saturating
/// `as usize` (NaN to 0, negative to 0) and clamped to the last bin.
fn reference_bins(binner: &Binner, r: &PrimRef) -> [usize; 3] {
    let last = binner.last as usize;
    let centroid2 = Vec3A::from_array(r.lo) + Vec3A::from_array(r.hi);
    let position = (centroid2 - binner.origin) * binner.scale;
    position.to_array().map(|x| (x as usize).min(last))
}

/// The reference `SetInfo::add`: one branch per primitive kind.
fn reference_add(info: &mut SetInfo, r: &PrimRef) {
    info.prims.bounds.grow(&r.bounds());
    info.centroids.grow_point(r.centroid2());
    if r.sphere != 0 {
        info.prims.spheres += 1;
    } else {
        info.prims.triangles += 1;
    }
}

/// The reference partition: the two-finger partition with the reference bins.
fn reference_partition(
    refs: &mut [PrimRef],
    info: &SetInfo,
    split: &Split,
) -> (usize, SetInfo, SetInfo) {
    let Split::Plane { axis, bin, bins } = *split else {
        unreachable!("only planes are binned")
    };
    let binner = Binner::new(&info.centroids, bins);
    let goes_left = |r: &PrimRef| reference_bins(&binner, r)[axis] < bin;
    let (mut left, mut right) = (SetInfo::EMPTY, SetInfo::EMPTY);
    let (mut i, mut j) = (0, refs.len());
    loop {
        while i < j && goes_left(&refs[i]) {
            reference_add(&mut left, &refs[i]);
            i += 1;
        }
        while i < j && !goes_left(&refs[j - 1]) {
            reference_add(&mut right, &refs[j - 1]);
            j -= 1;
        }
        if i >= j {
            break;
        }
        refs.swap(i, j - 1);
        reference_add(&mut left, &refs[i]);
        reference_add(&mut right, &refs[j - 1]);
        i += 1;
        j -= 1;
    }
    (i, left, right)
}

/// The reference plane choice: bin every primitive on every axis into `N` bins, then per
/// axis sweep the bins from the right (the right sides' costs) and from the left, keeping
/// the first cheapest plane with primitives on both sides.
fn reference_best_plane<const N: usize>(refs: &[PrimRef], info: &SetInfo) -> Option<(f32, Split)> {
    let binner = Binner::new(&info.centroids, N);
    let mut bins = [[Bin::EMPTY; N]; 3];
    for r in refs {
        let b = reference_bins(&binner, r);
        for axis in 0..3 {
            bins[axis][b[axis]].add_of::<true>(r);
        }
    }
    let extent = info.centroids.hi - info.centroids.lo;
    let mut best: Option<(f32, Split)> = None;
    for (axis, bins) in bins.iter().enumerate() {
        if extent[axis] <= 0.0 {
            continue;
        }
        let (mut right_cost, mut right_count) = ([0.0f32; N], [0u32; N]);
        let mut right = Bin::EMPTY;
        for i in (1..N).rev() {
            right.merge(&bins[i]);
            right_cost[i] = right.bounds.half_area() * leaf_cost(right.triangles, right.spheres);
            right_count[i] = right.triangles + right.spheres;
        }
        let mut left = Bin::EMPTY;
        for i in 1..N {
            left.merge(&bins[i - 1]);
            if left.triangles + left.spheres == 0 || right_count[i] == 0 {
                continue;
            }
            let cost =
                left.bounds.half_area() * leaf_cost(left.triangles, left.spheres) + right_cost[i];
            if best.is_none_or(|(c, _)| cost < c) {
                best = Some((
                    cost,
                    Split::Plane {
                        axis,
                        bin: i,
                        bins: N,
                    },
                ));
            }
        }
    }
    best
}

/// `n` random boxes in the unit cube. `grid`: corners and sizes on a grid of quarters, so
/// that many centroids coincide and many planes cost the same. `flat`: every box has x = 0.5
/// (no extent along x). About a third are spheres when `spheres`.
fn random_set(rng: &mut Rng, n: usize, grid: bool, flat: bool, spheres: bool) -> Vec<PrimRef> {
    let coordinate = |rng: &mut Rng| {
        let u = rng.uniform();
        if grid {
            (u * 4.0).floor() / 4.0
        } else {
            u
        }
    };
    (0..n)
        .map(|i| {
            let lo = Vec3A::new(coordinate(rng), coordinate(rng), coordinate(rng));
            let size = Vec3A::new(coordinate(rng), coordinate(rng), coordinate(rng)) * 0.25;
            let mut bounds = Aabb { lo, hi: lo + size };
            if flat {
                bounds.lo.x = 0.5;
                bounds.hi.x = 0.5;
            }
            let sphere = spheres && rng.uniform() < 0.3;
            PrimRef::new(bounds, i as u32, sphere)
        })
        .collect()
}

/// Every combination of the random sets' options, `count` sets of each, sizes from `sizes`.
fn random_sets(
    seed: u64,
    count: usize,
    sizes: std::ops::RangeInclusive<usize>,
) -> Vec<Vec<PrimRef>> {
    let mut rng = Rng::new(seed, 0, 0);
    let span = (sizes.end() - sizes.start() + 1) as f32;
    let mut sets = Vec::new();
    for options in 0..8 {
        let (grid, flat, spheres) = (options & 1 != 0, options & 2 != 0, options & 4 != 0);
        for _ in 0..count {
            let n =
                sizes.start() + ((rng.uniform() * span) as usize).min(sizes.end() - sizes.start());
            sets.push(random_set(&mut rng, n, grid, flat, spheres));
        }
    }
    sets
}

fn aabb_bits(a: &Aabb) -> [u32; 6] {
    let (lo, hi) = (a.lo.to_array(), a.hi.to_array());
    [lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]].map(f32::to_bits)
}

fn info_bits(info: &SetInfo) -> ([u32; 6], [u32; 6], u32, u32) {
    (
        aabb_bits(&info.prims.bounds),
        aabb_bits(&info.centroids),
        info.prims.triangles,
        info.prims.spheres,
    )
}

fn plane_bits(choice: Option<(f32, Split)>) -> Option<(u32, usize, usize, usize)> {
    choice.map(|(cost, split)| match split {
        Split::Plane { axis, bin, bins } => (cost.to_bits(), axis, bin, bins),
        Split::Halves => unreachable!("a plane choice"),
    })
}

/// The bin and the below-the-plane test agree with the saturating conversion on random sets
/// and on the positions where a fast conversion could differ: bin borders, just below
/// the last bin's end, beyond it, negative, signed zero, infinities and NaN.
#[test]
fn bins_and_below_agree_with_the_saturating_conversion() {
    let check = |binner: &Binner, refs: &[PrimRef]| {
        let count = binner.last as usize + 1;
        for r in refs {
            let expected = reference_bins(binner, r);
            assert_eq!(binner.bins(r), expected, "{r:?}");
            for (axis, &bin) in expected.iter().enumerate() {
                for plane in 1..count {
                    let below = Binner::below(r, axis, binner.axis(axis), plane as f32);
                    assert_eq!(below, bin < plane, "{r:?} axis {axis} plane {plane}");
                }
            }
        }
    };
    for refs in random_sets(11, 20, 2..=100) {
        let info = SetInfo::of(&refs);
        for count in [8, 16, BINS] {
            check(&Binner::new(&info.centroids, count), &refs);
        }
    }
    let special = [
        0.0,
        -0.0,
        0.5,
        1.0,
        1.0 - f32::EPSILON / 2.0,
        6.0,
        7.0 - 7.0 * f32::EPSILON,
        7.0,
        7.5,
        8.0,
        31.999998,
        32.0,
        1e9,
        1e30,
        f32::MAX,
        f32::INFINITY,
        -1.0,
        -f32::MAX,
        f32::NEG_INFINITY,
        f32::NAN,
    ];
    // Position = centroid2 exactly: lo = x, hi = 0, origin 0, scale 1.
    let refs: Vec<PrimRef> = special
        .iter()
        .map(|&x| {
            PrimRef::new(
                Aabb {
                    lo: Vec3A::new(x, -x, x * 0.5),
                    hi: Vec3A::ZERO,
                },
                0,
                false,
            )
        })
        .collect();
    for count in [8, 16, BINS] {
        let binner = Binner {
            origin: Vec3A::ZERO,
            scale: Vec3A::ONE,
            last: (count - 1) as f32,
        };
        check(&binner, &refs);
    }
}

/// The partition puts the same primitives in the same order on each side, with the same
/// sets (boxes to the bit, counts), as the reference, for every axis and plane.
#[test]
fn partition_agrees_with_the_reference() {
    for refs in random_sets(12, 12, 2..=120) {
        let info = SetInfo::of(&refs);
        for bins in [8, 16, BINS] {
            for axis in 0..3 {
                for bin in 1..bins {
                    let split = Split::Plane { axis, bin, bins };
                    let (mut ours, mut theirs) = (refs.clone(), refs.clone());
                    let (mid, left, right) = partition(&mut ours, &info, &split);
                    let (ref_mid, ref_left, ref_right) =
                        reference_partition(&mut theirs, &info, &split);
                    assert_eq!(mid, ref_mid, "{split:?}");
                    let ids = |v: &[PrimRef]| v.iter().map(|r| r.id).collect::<Vec<_>>();
                    assert_eq!(ids(&ours), ids(&theirs), "{split:?}");
                    assert_eq!(info_bits(&left), info_bits(&ref_left));
                    assert_eq!(info_bits(&right), info_bits(&ref_right));
                }
            }
        }
    }
}

/// Small sets: the sort-and-sweep choice is the reference's binned choice, to the bit
/// (cost, axis, plane), including the first of equal costs on the grid sets.
#[test]
fn the_sorted_sweep_chooses_the_binned_plane() {
    let mut ties = 0;
    for refs in random_sets(13, 400, 2..=SMALL) {
        let info = SetInfo::of(&refs);
        let ours = match refs.len() {
            0..=8 => best_plane_sorted::<8>(&refs, &info),
            9..=16 => best_plane_sorted::<16>(&refs, &info),
            _ => best_plane_sorted::<BINS>(&refs, &info),
        };
        let theirs = match refs.len() {
            0..=8 => reference_best_plane::<8>(&refs, &info),
            9..=16 => reference_best_plane::<16>(&refs, &info),
            _ => reference_best_plane::<BINS>(&refs, &info),
        };
        assert_eq!(
            plane_bits(ours),
            plane_bits(theirs),
            "{} primitives",
            refs.len()
        );
        ties += count_ties::<16>(&refs, &info);
    }
    assert!(
        ties > 100,
        "only {ties} sets with equal-cost planes: the tie rule is untested"
    );
}

/// Whether two different planes of the reference's sweep cost the same as its best (1 or 0).
fn count_ties<const N: usize>(refs: &[PrimRef], info: &SetInfo) -> usize {
    let Some((best, _)) = reference_best_plane::<N>(refs, info) else {
        return 0;
    };
    let binner = Binner::new(&info.centroids, N);
    let mut equal = 0;
    for axis in 0..3 {
        let mut sides = std::collections::BTreeSet::new();
        for plane in 1..N {
            let left: Vec<u32> = refs
                .iter()
                .filter(|r| reference_bins(&binner, r)[axis] < plane)
                .map(|r| r.id)
                .collect();
            if left.is_empty() || left.len() == refs.len() || !sides.insert(left.clone()) {
                continue;
            }
            let (mut l, mut r) = (Bin::EMPTY, Bin::EMPTY);
            for p in refs {
                if left.contains(&p.id) {
                    l.add_of::<true>(p)
                } else {
                    r.add_of::<true>(p)
                }
            }
            let cost = l.bounds.half_area() * leaf_cost(l.triangles, l.spheres)
                + r.bounds.half_area() * leaf_cost(r.triangles, r.spheres);
            equal += (cost == best) as usize;
        }
    }
    (equal >= 2) as usize
}

/// Larger sets: the binned choice (with and without spheres, serial and in parallel
/// chunks) is the reference's, to the bit.
#[test]
fn the_binned_sweep_chooses_the_reference_plane() {
    let mut sets = random_sets(14, 40, SMALL + 1..=400);
    sets.extend(random_sets(15, 1, PARALLEL_MIN..=PARALLEL_MIN * 2));
    for refs in sets {
        let info = SetInfo::of(&refs);
        let ours = best_plane::<BINS>(&refs, &info);
        let theirs = reference_best_plane::<BINS>(&refs, &info);
        assert_eq!(
            plane_bits(ours),
            plane_bits(theirs),
            "{} primitives",
            refs.len()
        );
    }
}
