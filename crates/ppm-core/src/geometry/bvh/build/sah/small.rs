//! The SAH's plane choice for small sets (up to [`SMALL`] primitives) without bins of boxes:
//! each bin records only which primitives it holds, and the occupied bins are swept in
//! order. It chooses what [`super::best_plane`] would, in time linear in the set.

use super::{leaf_cost, Bin, Binner, PrimRef, SetInfo, Split};

/// Sets up to this size are priced by [`best_plane_sorted`] instead of bins (at most 32:
/// a set's members are a `u32` mask).
pub(super) const SMALL: usize = 32;

/// The choice of `best_plane::<N>` for a set of at most [`SMALL`] primitives, found without
/// filling and sweeping `3 N` bins of boxes: along each axis each bin records only which
/// primitives it holds (a bitmask), and the occupied bins are swept in order, each adding
/// its primitives' boxes to the side being grown. The plane between bins i - 1 and i only
/// depends on which primitives lie below it, so of the planes that leave the same
/// primitives on each side, all priced the same, `best_plane` keeps the first, the one just
/// above the left side's highest bin; this sweep prices exactly those planes (one above each
/// occupied bin but the last), in the same order, with the same float operations (boxes are
/// unions by min and max, whose result does not depend on the order), and keeps the first
/// cheapest as `best_plane` does. Its work is linear in the set, where an insertion sort by
/// bin was quadratic and a binned sweep pays for all `N` bins.
pub(super) fn best_plane_sorted<const N: usize>(
    refs: &[PrimRef],
    info: &SetInfo,
) -> Option<(f32, Split)> {
    if info.prims.spheres > 0 {
        best_plane_sorted_of::<N, true>(refs, info)
    } else {
        best_plane_sorted_of::<N, false>(refs, info)
    }
}

/// [`best_plane_sorted`] for a set that holds spheres only if `SPHERES`.
#[inline(always)]
fn best_plane_sorted_of<const N: usize, const SPHERES: bool>(
    refs: &[PrimRef],
    info: &SetInfo,
) -> Option<(f32, Split)> {
    const { assert!(N.is_power_of_two() && N <= 32) };
    let n = refs.len();
    debug_assert!((2..=SMALL).contains(&n));
    let binner = Binner::new(&info.centroids, N);
    // members[axis][bin]: the primitives in that bin; occupied[axis]: the bins holding any.
    let mut members = [[0u32; N]; 3];
    let mut occupied = [0u32; 3];
    for (j, r) in refs.iter().enumerate() {
        let bins = binner.bins(r);
        for axis in 0..3 {
            let bin = bins[axis] & (N - 1);
            members[axis][bin] |= 1 << j;
            occupied[axis] |= 1 << bin;
        }
    }
    let add_members = |side: &mut Bin, mut members: u32| {
        while members != 0 {
            side.add_of::<SPHERES>(&refs[members.trailing_zeros() as usize]);
            members &= members - 1;
        }
    };
    let extent = info.centroids.hi - info.centroids.lo;
    let mut best: Option<(f32, Split)> = None;
    for axis in 0..3 {
        if extent[axis] <= 0.0 {
            continue;
        }
        let (members, occupied) = (&members[axis], occupied[axis]);
        // right_cost[b]: A_R cost(R) of the primitives in bins b.. as one side, for every
        // occupied bin b above the lowest (the right side of a plane starts at one of them).
        let mut right_cost = [0.0f32; N];
        let mut right = Bin::EMPTY;
        let mut above_lowest = occupied & (occupied - 1);
        while above_lowest != 0 {
            let bin = 31 - above_lowest.leading_zeros() as usize;
            above_lowest &= !(1 << bin);
            add_members(&mut right, members[bin & (N - 1)]);
            right_cost[bin & (N - 1)] =
                right.bounds.half_area() * leaf_cost(right.triangles, right.spheres);
        }
        // The left side grows bin by bin; the plane above bin `below` has the next occupied
        // bin, `above`, as the lowest of its right side.
        let mut left = Bin::EMPTY;
        let mut rest = occupied;
        while rest != 0 {
            let below = rest.trailing_zeros() as usize;
            rest &= rest - 1;
            if rest == 0 {
                break;
            }
            add_members(&mut left, members[below & (N - 1)]);
            let above = rest.trailing_zeros() as usize;
            let cost = left.bounds.half_area() * leaf_cost(left.triangles, left.spheres)
                + right_cost[above & (N - 1)];
            if best.is_none_or(|(c, _)| cost < c) {
                let split = Split::Plane {
                    axis,
                    bin: below + 1,
                    bins: N,
                };
                best = Some((cost, split));
            }
        }
    }
    best
}
