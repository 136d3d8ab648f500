//! The split of one set of primitives by the surface area heuristic (MacDonald and Booth
//! 1990), which predicts the cheapest traversal of a random ray that meets the set's box:
//!
//! ```text
//! cost(split) = C_TRAVERSE + (A_L / A) cost(L) + (A_R / A) cost(R)
//! cost(leaf)  = C_PACKET ceil(triangles / 4) + C_SPHERE spheres
//! ```
//!
//! where A, A_L and A_R are the surface areas of the set's box and of its two halves' boxes
//! (the ratio is the probability that a ray meeting the set's box also meets the half's) and
//! the children are priced as leaves (the greedy top-down SAH). A leaf's triangles are
//! tested four at a time (`TrianglePacket`), so its cost counts packets, not triangles. A
//! set becomes a leaf when it holds at most [`MAX_LEAF`] primitives and no split is cheaper.
//!
//! Candidate splits are the planes between [`BINS`] equal bins of the centroids' extent along
//! each axis (Wald 2007, "On fast construction of SAH-based bounding volume hierarchies"):
//! one pass bins the primitives, one sweep per axis prices every plane. Sets of up to 32
//! primitives get the same choice from a sweep of their bins' members (`small.rs`). A set
//! whose centroids all coincide cannot be binned and is halved by count.

use glam::Vec3A;
use rayon::prelude::*;
/// Centroid bins per axis.
const BINS: usize = 32;

/// Most primitives in one leaf: two triangle packets. The SAH decides below that.
pub(super) const MAX_LEAF: usize = 8;

/// SAH cost of descending one binary level, relative to one packet test. A wide node's slab
/// test costs about one packet test and resolves about three binary levels (log2 8), which
/// would give 1/3; rays that start inside an enclosure (every ray of an interior scene)
/// enter every box around their origin whatever its area, which the area ratio does not
/// see and which favours smaller leaves. 0.2 is what the shipped scenes and the large mesh
/// measured best (docs/performance.md).
const C_TRAVERSE: f32 = 0.2;

/// SAH cost of testing one packet of up to four triangles.
const C_PACKET: f32 = 1.0;

/// SAH cost of testing one sphere.
const C_SPHERE: f32 = 1.0;

/// Sets at least this large are binned in parallel chunks and built as parallel tasks.
pub(super) const PARALLEL_MIN: usize = 16 * 1024;

/// A primitive during the build: its box and its global id (triangles first, then spheres).
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
pub(crate) struct PrimRef {
    lo: [f32; 3],
    pub(crate) id: u32,
    hi: [f32; 3],
    /// 1 for a sphere, 0 for a triangle.
    pub(crate) sphere: u32,
}

impl PrimRef {
    /// A reference to primitive `id` with box `bounds`; `sphere` when the id names a sphere.
    pub(crate) fn new(bounds: Aabb, id: u32, sphere: bool) -> Self {
        PrimRef {
            lo: bounds.lo.to_array(),
            id,
            hi: bounds.hi.to_array(),
            sphere: sphere as u32,
        }
    }

    #[inline(always)]
    fn bounds(&self) -> Aabb {
        Aabb {
            lo: Vec3A::from_array(self.lo),
            hi: Vec3A::from_array(self.hi),
        }
    }

    /// Twice the centroid (lo + hi): binning only compares centroids, so the halving is left out.
    #[inline(always)]
    fn centroid2(&self) -> Vec3A {
        Vec3A::from_array(self.lo) + Vec3A::from_array(self.hi)
    }
}

/// An axis-aligned box; the empty box has lo = +inf and hi = -inf.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Aabb {
    pub(crate) lo: Vec3A,
    pub(crate) hi: Vec3A,
}

impl Aabb {
    pub(crate) const EMPTY: Aabb = Aabb {
        lo: Vec3A::INFINITY,
        hi: Vec3A::NEG_INFINITY,
    };

    #[inline(always)]
    pub(crate) fn grow(&mut self, b: &Aabb) {
        self.lo = self.lo.min(b.lo);
        self.hi = self.hi.max(b.hi);
    }

    #[inline(always)]
    fn grow_point(&mut self, p: Vec3A) {
        self.lo = self.lo.min(p);
        self.hi = self.hi.max(p);
    }

    /// Half the surface area (the SAH only uses ratios); 0 for the empty box.
    #[inline(always)]
    pub(super) fn half_area(&self) -> f32 {
        let d = (self.hi - self.lo).max(Vec3A::ZERO);
        d.x * d.y + d.y * d.z + d.z * d.x
    }
}

/// A set of primitives: its box and counts (a [`Bin`]'s, added and merged as a bin's) and
/// its centroids' box (of twice the centroids), which a bin does not need.
#[derive(Clone, Copy, Debug)]
pub(super) struct SetInfo {
    prims: Bin,
    pub(super) centroids: Aabb,
}

impl SetInfo {
    pub(super) const EMPTY: SetInfo = SetInfo {
        prims: Bin::EMPTY,
        centroids: Aabb::EMPTY,
    };

    #[inline(always)]
    pub(super) fn add(&mut self, r: &PrimRef) {
        self.add_of::<true>(r);
    }

    /// [`SetInfo::add`], for a primitive known to be a triangle unless `SPHERES`.
    #[inline(always)]
    fn add_of<const SPHERES: bool>(&mut self, r: &PrimRef) {
        self.prims.add_of::<SPHERES>(r);
        self.centroids.grow_point(r.centroid2());
    }

    pub(super) fn merge(mut self, o: &SetInfo) -> SetInfo {
        self.prims.merge(&o.prims);
        self.centroids.grow(&o.centroids);
        self
    }

    /// The box of the set's primitives.
    pub(super) fn bounds(&self) -> &Aabb {
        &self.prims.bounds
    }

    pub(super) fn count(&self) -> usize {
        (self.prims.triangles + self.prims.spheres) as usize
    }

    /// The SAH cost of testing this set as one leaf.
    fn leaf_cost(&self) -> f32 {
        leaf_cost(self.prims.triangles, self.prims.spheres)
    }

    /// Over a slice of references, in parallel chunks for large slices (min, max and counts
    /// do not depend on the order of reduction).
    pub(super) fn of(refs: &[PrimRef]) -> SetInfo {
        let serial = |refs: &[PrimRef]| {
            let mut info = SetInfo::EMPTY;
            refs.iter().for_each(|r| info.add(r));
            info
        };
        if refs.len() < PARALLEL_MIN {
            serial(refs)
        } else {
            refs.par_chunks(PARALLEL_MIN / 2)
                .map(serial)
                .reduce(|| SetInfo::EMPTY, |a, b| a.merge(&b))
        }
    }
}

/// How a set is to be divided.
#[derive(Clone, Copy, Debug)]
pub(super) enum Split {
    /// Primitives whose centroid falls in a bin below `bin` of `bins` along `axis` go left.
    Plane {
        axis: usize,
        bin: usize,
        bins: usize,
    },
    /// All centroids coincide: the first half by count goes left.
    Halves,
}

/// Binning of a set's centroids along each axis to `count` bins.
///
/// A primitive's position along an axis is `(2 centroid - origin) * scale`, in bin units;
/// its bin is `floor(position)` clamped to `0..count` (a NaN position, from a centroid at
/// infinity, is bin 0). Binning and partition both go through [`Binner::position`], so a
/// primitive is put on the side of the plane that the SAH priced it on.
#[derive(Clone, Copy)]
pub(super) struct Binner {
    origin: Vec3A,
    scale: Vec3A,
    /// The last bin, `count - 1`, as a float.
    last: f32,
}

/// 2^23: a float in [2^23, 2^24) has no fraction bits, so adding it to an integer-valued
/// float below 2^23 is exact and leaves the integer in the low bits of the mantissa.
const TWO_POW_23: f32 = 8_388_608.0;

impl Binner {
    pub(super) fn new(centroids: &Aabb, count: usize) -> Self {
        debug_assert!(count >= 1 && (count as f32) < TWO_POW_23);
        let extent = centroids.hi - centroids.lo;
        // Just under `count` per extent, so the largest centroid lands in the last bin.
        let k = count as f32 * (1.0 - 1e-5);
        let scale = Vec3A::select(extent.cmpgt(Vec3A::ZERO), k / extent, Vec3A::ZERO);
        Binner {
            origin: centroids.lo,
            scale,
            last: (count - 1) as f32,
        }
    }

    /// The primitive's position along each axis, in bins.
    #[inline(always)]
    fn position(&self, r: &PrimRef) -> Vec3A {
        (r.centroid2() - self.origin) * self.scale
    }

    /// The primitive's bin along each axis: `floor(position)` clamped to `0..=last`, NaN to
    /// 0, which is what `(position as usize).min(last)` gives, without the saturating
    /// conversion's fix-up code per lane. The clamps are done first, on all three lanes at
    /// once: `max(x, 0)` is `maxps(x, 0)`, which returns its second operand, 0, for a NaN x
    /// (and +0 for -0, the same bin); `min(x, last)` is `minps`. The floor is then an integer
    /// in `0..=last` and the 2^23 trick converts it exactly.
    #[inline(always)]
    pub(super) fn bins(&self, r: &PrimRef) -> [usize; 3] {
        let x = self
            .position(r)
            .max(Vec3A::ZERO)
            .min(Vec3A::splat(self.last));
        (x.floor() + Vec3A::splat(TWO_POW_23))
            .to_array()
            .map(|x| (x.to_bits() - TWO_POW_23.to_bits()) as usize)
    }

    /// Whether the primitive's bin along `axis` is below `plane` (`1..=last`), from that
    /// axis alone: for `0 <= plane <= last` an integer, `min(floor(x), last) < plane`
    /// exactly when `x < plane`, and a NaN position (bin 0) is below too. `origin` and
    /// `scale` are this binner's along `axis`, hoisted out of the partition's loop by
    /// [`Binner::axis`].
    #[inline(always)]
    pub(super) fn below(r: &PrimRef, axis: usize, (origin, scale): (f32, f32), plane: f32) -> bool {
        // The same float operations as `position`'s lane `axis`: (lo + hi - origin) * scale.
        let x = (r.lo[axis] + r.hi[axis] - origin) * scale;
        x < plane || x.is_nan()
    }

    /// The origin and scale along `axis`.
    pub(super) fn axis(&self, axis: usize) -> (f32, f32) {
        (self.origin[axis], self.scale[axis])
    }
}

/// What the SAH needs of a bin (and of a set, in [`SetInfo`]): the box of its primitives
/// and their counts.
#[derive(Clone, Copy, Debug)]
struct Bin {
    bounds: Aabb,
    triangles: u32,
    spheres: u32,
}

impl Bin {
    const EMPTY: Bin = Bin {
        bounds: Aabb::EMPTY,
        triangles: 0,
        spheres: 0,
    };

    /// Adds a primitive, known to be a triangle unless `SPHERES` (the sets of a mesh hold
    /// none, and the build then skips reading and counting the kind).
    #[inline(always)]
    fn add_of<const SPHERES: bool>(&mut self, r: &PrimRef) {
        self.bounds.grow(&r.bounds());
        if SPHERES {
            self.triangles += 1 - r.sphere;
            self.spheres += r.sphere;
        } else {
            self.triangles += 1;
        }
    }

    #[inline(always)]
    fn is_empty(&self) -> bool {
        self.triangles + self.spheres == 0
    }

    #[inline(always)]
    fn merge(&mut self, o: &Bin) {
        self.bounds.grow(&o.bounds);
        self.triangles += o.triangles;
        self.spheres += o.spheres;
    }
}

/// `N` bins on each axis.
type Bins<const N: usize> = [[Bin; N]; 3];

/// Each primitive added to its bin on each axis, into `bins` (empty on entry): serially, or
/// for large sets in parallel chunks merged after (the result does not depend on the order
/// of merging). `spheres`: whether the set holds any sphere; without, the sphere counts are
/// left at 0 and only the triangle counts kept.
fn bin_refs<const N: usize>(binner: &Binner, refs: &[PrimRef], spheres: bool, bins: &mut Bins<N>) {
    let serial = |refs: &[PrimRef], bins: &mut Bins<N>| {
        if spheres {
            bin_serial::<N, true>(binner, refs, bins)
        } else {
            bin_serial::<N, false>(binner, refs, bins)
        }
    };
    if refs.len() < PARALLEL_MIN {
        return serial(refs, bins);
    }
    *bins = refs
        .par_chunks(PARALLEL_MIN / 2)
        .map(|chunk| {
            let mut bins = [[Bin::EMPTY; N]; 3];
            serial(chunk, &mut bins);
            bins
        })
        .reduce(
            || [[Bin::EMPTY; N]; 3],
            |mut a, b| {
                for axis in 0..3 {
                    for i in 0..N {
                        a[axis][i].merge(&b[axis][i]);
                    }
                }
                a
            },
        );
}

/// Runs at least this long are binned as two interleaved halves (see [`bin_serial`]).
const TWO_WAY_MIN: usize = 256;

/// The binning loop over one run of primitives; `SPHERES` as `bin_refs`'s `spheres`.
///
/// Neighbouring primitives of a mesh mostly fall in the same bins, so each update of a bin
/// waits for the previous one's store. Long runs are therefore binned as two halves into two
/// sets of bins in one interleaved loop (two independent chains of updates), merged after:
/// the same bins, as a box union by min and max and a sum do not depend on the order.
#[inline(always)]
fn bin_serial<const N: usize, const SPHERES: bool>(
    binner: &Binner,
    refs: &[PrimRef],
    bins: &mut Bins<N>,
) {
    const { assert!(N.is_power_of_two()) };
    if refs.len() < TWO_WAY_MIN {
        refs.iter()
            .for_each(|r| bin_one::<N, SPHERES>(binner, r, bins));
        return;
    }
    let mut other = [[Bin::EMPTY; N]; 3];
    let (first, second) = refs.split_at(refs.len() / 2);
    for (a, b) in first.iter().zip(second) {
        bin_one::<N, SPHERES>(binner, a, bins);
        bin_one::<N, SPHERES>(binner, b, &mut other);
    }
    if let Some(last) = second.get(first.len()) {
        bin_one::<N, SPHERES>(binner, last, &mut other);
    }
    for axis in 0..3 {
        for i in 0..N {
            bins[axis][i].merge(&other[axis][i]);
        }
    }
}

/// One primitive added to its bin on each axis.
#[inline(always)]
fn bin_one<const N: usize, const SPHERES: bool>(binner: &Binner, r: &PrimRef, bins: &mut Bins<N>) {
    let b = binner.bins(r);
    let bounds = r.bounds();
    for axis in 0..3 {
        // The bin is at most N - 1 already; the mask only lets the compiler see it.
        let bin = &mut bins[axis][b[axis] & (N - 1)];
        bin.bounds.grow(&bounds);
        if SPHERES {
            bin.triangles += 1 - r.sphere;
            bin.spheres += r.sphere;
        } else {
            bin.triangles += 1;
        }
    }
}

/// The SAH cost of a leaf of `triangles` and `spheres`.
#[inline(always)]
fn leaf_cost(triangles: u32, spheres: u32) -> f32 {
    C_PACKET * triangles.div_ceil(4) as f32 + C_SPHERE * spheres as f32
}

/// The SAH's choice for a set: `None` makes it a leaf.
pub(super) fn choose_split(refs: &[PrimRef], info: &SetInfo) -> Option<Split> {
    let n = info.count();
    if n <= 1 {
        return None;
    }
    let extent = info.centroids.hi - info.centroids.lo;
    if extent.max_element() <= 0.0 {
        // Coincident centroids: nothing to bin; halve by count if the set is too big.
        return (n > MAX_LEAF).then_some(Split::Halves);
    }
    // Fewer bins for small sets: sweeping 32 bins costs more than it finds among a few.
    // Small sets are not binned into boxes but swept by their bins' members
    // (`best_plane_sorted`, the same choice).
    let (cost, split) = match n {
        0..=8 => best_plane_sorted::<8>(refs, info),
        9..=16 => best_plane_sorted::<16>(refs, info),
        17..=SMALL => best_plane_sorted::<BINS>(refs, info),
        _ => best_plane::<BINS>(refs, info),
    }?;
    let area = info.bounds().half_area();
    let split_cost = C_TRAVERSE + if area > 0.0 { cost / area } else { 0.0 };
    if n <= MAX_LEAF && split_cost >= info.leaf_cost() {
        return None;
    }
    Some(split)
}

/// The cheapest plane between `N` bins along any axis, with its SAH term A_L cost(L) +
/// A_R cost(R); `None` if no plane has primitives on both sides.
fn best_plane<const N: usize>(refs: &[PrimRef], info: &SetInfo) -> Option<(f32, Split)> {
    let binner = Binner::new(&info.centroids, N);
    let mut bins = [[Bin::EMPTY; N]; 3];
    bin_refs::<N>(&binner, refs, info.prims.spheres > 0, &mut bins);
    let extent = info.centroids.hi - info.centroids.lo;
    let mut best: Option<(f32, Split)> = None;
    for (axis, bins) in bins.iter().enumerate() {
        if extent[axis] <= 0.0 {
            continue;
        }
        // right_cost[i], right_count[i]: bins i.. as one side, swept from the right. Merging
        // an empty bin changes nothing, so its cost is carried over, not recomputed.
        let (mut right_cost, mut right_count) = ([0.0f32; N], [0u32; N]);
        let (mut right, mut cost) = (Bin::EMPTY, 0.0);
        for i in (1..N).rev() {
            if !bins[i].is_empty() {
                right.merge(&bins[i]);
                cost = right.bounds.half_area() * leaf_cost(right.triangles, right.spheres);
            }
            right_cost[i] = cost;
            right_count[i] = right.triangles + right.spheres;
        }
        let mut left = Bin::EMPTY;
        for i in 1..N {
            // With bin i - 1 empty, plane i divides as plane i - 1 did, at the same cost,
            // which is not strictly cheaper: only planes above a full bin are priced.
            if bins[i - 1].is_empty() {
                continue;
            }
            left.merge(&bins[i - 1]);
            if right_count[i] == 0 {
                continue;
            }
            let cost =
                left.bounds.half_area() * leaf_cost(left.triangles, left.spheres) + right_cost[i];
            if best.is_none_or(|(c, _)| cost < c) {
                let split = Split::Plane {
                    axis,
                    bin: i,
                    bins: N,
                };
                best = Some((cost, split));
            }
        }
    }
    best
}

/// Divides `refs` as `split` says; returns the left count and both halves' sets.
pub(super) fn partition(
    refs: &mut [PrimRef],
    info: &SetInfo,
    split: &Split,
) -> (usize, SetInfo, SetInfo) {
    match *split {
        Split::Plane { axis, bin, bins } if info.prims.spheres > 0 => {
            partition_plane::<true>(refs, info, axis, bin, bins)
        }
        Split::Plane { axis, bin, bins } => partition_plane::<false>(refs, info, axis, bin, bins),
        Split::Halves => {
            let mid = refs.len() / 2;
            let (l, r) = refs.split_at(mid);
            (mid, SetInfo::of(l), SetInfo::of(r))
        }
    }
}

/// [`partition`] by the plane below bin `bin` of `bins` along `axis`, for a set that holds
/// spheres only if `SPHERES`.
#[inline(always)]
fn partition_plane<const SPHERES: bool>(
    refs: &mut [PrimRef],
    info: &SetInfo,
    axis: usize,
    bin: usize,
    bins: usize,
) -> (usize, SetInfo, SetInfo) {
    let along = Binner::new(&info.centroids, bins).axis(axis);
    let plane = bin as f32;
    let goes_left = |r: &PrimRef| Binner::below(r, axis, along, plane);
    // Two-finger partition, deterministic and in place; each primitive is added to its
    // side's set as the fingers pass it.
    let (mut left, mut right) = (SetInfo::EMPTY, SetInfo::EMPTY);
    let (mut i, mut j) = (0, refs.len());
    loop {
        while i < j && goes_left(&refs[i]) {
            left.add_of::<SPHERES>(&refs[i]);
            i += 1;
        }
        while i < j && !goes_left(&refs[j - 1]) {
            right.add_of::<SPHERES>(&refs[j - 1]);
            j -= 1;
        }
        if i >= j {
            break;
        }
        refs.swap(i, j - 1);
        left.add_of::<SPHERES>(&refs[i]);
        right.add_of::<SPHERES>(&refs[j - 1]);
        i += 1;
        j -= 1;
    }
    (i, left, right)
}

mod small;
use small::{best_plane_sorted, SMALL};

#[cfg(test)]
mod reference_tests;
