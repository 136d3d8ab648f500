//! A hashed uniform grid over one iteration's photons, for fixed-radius gathers.
//!
//! Space is cut into cubic cells of side `2 r` (the gather diameter) and each cell is hashed
//! into one of about as many buckets as there are photons. [`HashGrid::build`] counting-sorts
//! the photons by bucket into one flat array, so a bucket's photons are contiguous, and a
//! query visits the buckets of the (usually 2 x 2 x 2) cells its sphere overlaps. Cells that
//! follow each other along x take consecutive buckets, so those 8 cells are 4 runs of memory.
//!
//! The photons are also kept as columns in the same order (position, flux and incoming
//! direction, one array per coordinate): a query tests about five candidates for every photon
//! inside its sphere (the cube of 2 x 2 cells on a surface has 16 r² of area, the disc
//! pi r²), so it works on [`LANES`] candidates at once (8-wide AVX where the build has AVX).
//! [`HashGrid::for_each_in_radius`] computes their distances into a bit mask and calls back
//! for the set bits only; [`HashGrid::kernel_flux`], the density estimate's sum, weights and
//! masks all lanes and has no branch per photon at all (see [`super::gather`]).
//!
//! # Determinism
//!
//! Photons arrive in a scheduling-dependent order (see [`super::PhotonBuffer`]). After the
//! counting sort, each bucket is sorted by [`Photon::order_key`]: the light-path index, then
//! the record's raw bits as a tie-break. Two photons with equal keys are identical, so the
//! stored order depends only on the set of photons, and so does the order in which a query
//! calls its closure: gathers sum in the same order at any thread count.

use super::gather::{Columns, ColumnsView, FluxQuery, FluxSum};
use super::{FluxRecord, Kernel, Photon};
use crate::simd::{F32x8, LANES};
use glam::{IVec3, Vec3};
use rayon::prelude::*;
use std::ops::Range;

/// Photon count below which a build step runs serially (parallel overhead dominates).
const PARALLEL_MIN: usize = 1 << 14;

/// Cells a query dedupes through a stack array: 3 x 3 x 3 covers any radius up to the cell
/// size (half the cell when the query radius equals the build radius, plus rounding slivers).
const SMALL_QUERY: usize = 27;

/// The cell-to-bucket map, copied out of the grid so that parallel closures can borrow it.
#[derive(Clone, Copy, Debug)]
struct CellHash {
    inv_cell: f32,
    buckets: u32,
}

impl CellHash {
    /// Integer coordinates of the cell containing `p`: floor, so that -0.5 is in cell -1.
    /// Coordinates beyond the `i32` range saturate, which keeps the map monotonic.
    #[inline]
    fn cell(&self, p: Vec3) -> IVec3 {
        let q = p * self.inv_cell;
        IVec3::new(floor_i32(q.x), floor_i32(q.y), floor_i32(q.z))
    }

    /// The bucket of cell `c`: the row of cells along x through `c` starts at a hashed
    /// bucket, and the row's cells take the buckets after it (modulo the table size), so
    /// neighbours along x are neighbours in memory and a query reads a 2 x 2 x 2 block of
    /// cells as 4 runs instead of 8 scattered buckets ([`HashGrid::bucket_runs`]).
    ///
    /// The row's bucket: a linear combination of (y, z) with large odd 64-bit constants
    /// (injective on any realistic block of cells), the SplitMix64 finaliser (full
    /// avalanche), then the top 32 bits mapped onto `0..buckets` by a multiply-shift.
    /// The classic `x p1 ^ y p2 ^ z p3` (Teschner et al. 2003) is avoided: with sign-extended
    /// negative coordinates the xor collides often (a 16³ block around the origin has only
    /// 2518 distinct values out of 4096).
    #[inline]
    fn bucket(&self, c: IVec3) -> usize {
        let mut h = (c.y as u64)
            .wrapping_mul(0xc2b2_ae3d_27d4_eb4f)
            .wrapping_add((c.z as u64).wrapping_mul(0x1656_67b1_9e37_79f9));
        h = (h ^ (h >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        h = (h ^ (h >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        h ^= h >> 31;
        let row = ((h >> 32) * self.buckets as u64) >> 32;
        // `buckets` is a power of two: the mask is the modulo, also for negative x.
        (row as u32).wrapping_add(c.x as u32) as usize & (self.buckets as usize - 1)
    }
}

/// `floor(x)` as an `i32`, saturating (NaN gives 0), monotonic in `x`.
///
/// `f32::floor` is a libm call on x86-64 without SSE4.1 (16% of the build time); truncate
/// instead and step down when truncation rounded a negative value up. For |x| >= 2^24 every
/// float is an integer, so the comparison is exact wherever it matters.
#[inline]
fn floor_i32(x: f32) -> i32 {
    let t = x as i32;
    t.saturating_sub((t as f32 > x) as i32)
}

/// Photons sorted into hashed cells, rebuilt every iteration with its allocations reused.
#[derive(Clone, Debug)]
pub struct HashGrid {
    hash: CellHash,
    cell_size: f32,
    /// Photons grouped by bucket; within a bucket ordered by `Photon::order_key`.
    photons: Vec<Photon>,
    /// `photons` as columns (position, flux, incoming direction), for the scan of the
    /// candidates and the density estimate.
    columns: Columns,
    /// Bucket `b` holds `photons[start[b]..start[b + 1]]`; `buckets + 1` entries.
    start: Vec<u32>,
    /// Scratch: the bucket of each input photon.
    bucket_of: Vec<u32>,
}

impl Default for HashGrid {
    fn default() -> Self {
        HashGrid::new()
    }
}

impl HashGrid {
    /// An empty grid; every query finds nothing until [`HashGrid::build`].
    pub fn new() -> Self {
        HashGrid {
            hash: CellHash {
                inv_cell: 1.0,
                buckets: 1,
            },
            cell_size: 1.0,
            photons: Vec::new(),
            columns: Columns::default(),
            start: vec![0, 0],
            bucket_of: Vec::new(),
        }
    }

    /// Rebuilds the grid over `photons` for gathers of radius up to `radius` (> 0, finite):
    /// cells of side `2 radius`, and the next power of two `>= photons.len()` buckets.
    ///
    /// Larger query radii still work, visiting more cells.
    ///
    /// # Panics
    ///
    /// If `radius` is not positive and finite, or there are `u32::MAX` photons or more.
    pub fn build(&mut self, photons: &[Photon], radius: f32) {
        self.build_with_buckets(photons, radius, photons.len());
    }

    /// [`HashGrid::build`] with about `buckets` buckets (rounded up to a power of two, at
    /// least 1); fewer buckets mean more cells share one. For tests and tuning.
    ///
    /// # Panics
    ///
    /// As [`HashGrid::build`], or with `2^31` buckets or more.
    pub fn build_with_buckets(&mut self, photons: &[Photon], radius: f32, buckets: usize) {
        assert!(
            radius > 0.0 && radius.is_finite(),
            "HashGrid::build: radius must be positive and finite, got {radius}"
        );
        assert!(
            photons.len() < u32::MAX as usize && buckets < 1 << 31,
            "HashGrid::build: at most 2^32 - 2 photons and 2^31 buckets"
        );
        let buckets = buckets.max(1).next_power_of_two();
        self.cell_size = 2.0 * radius;
        self.hash = CellHash {
            inv_cell: 1.0 / self.cell_size,
            buckets: buckets as u32,
        };
        let hash = self.hash;

        // 1. The bucket of every photon (independent, so parallel).
        photons
            .par_iter()
            .with_min_len(PARALLEL_MIN)
            .map(|p| hash.bucket(hash.cell(p.position)) as u32)
            .collect_into_vec(&mut self.bucket_of);

        // 2. Counting sort. `start[b]` first counts bucket b, then the exclusive prefix sum
        //    makes it b's first slot, the scatter advances it to b's end (= b + 1's first
        //    slot), and a shift by one entry restores the starts.
        let start = &mut self.start;
        start.clear();
        start.resize(buckets + 1, 0);
        for &b in &self.bucket_of {
            start[b as usize] += 1;
        }
        let mut sum = 0;
        for s in start.iter_mut() {
            (*s, sum) = (sum, sum + *s);
        }
        self.photons.resize(photons.len(), Photon::ZERO);
        for (photon, &b) in photons.iter().zip(&self.bucket_of) {
            let slot = &mut start[b as usize];
            self.photons[*slot as usize] = *photon;
            *slot += 1;
        }
        start.copy_within(0..buckets, 1);
        start[0] = 0;

        // 3. Canonical order inside each bucket (see the module documentation).
        sort_buckets(&mut self.photons, &self.start);

        // 4. The columns, in one parallel pass over chunks of the photons.
        let n = self.photons.len();
        let Columns {
            position: [x, y, z],
            flux: [r, g, b],
            wi: [u, v, w],
        } = &mut self.columns;
        let mut columns = [x, y, z, r, g, b, u, v, w];
        for (k, column) in columns.iter_mut().enumerate() {
            // Only growth writes here (the vectors are reused); the pass overwrites 0..n.
            column.resize(n + LANES, 0.0);
            let padding = if k < 3 { f32::INFINITY } else { 0.0 };
            column[n..].fill(padding);
        }
        const CHUNK: usize = 1 << 12;
        let mut chunks = columns.map(|c| c[..n].chunks_mut(CHUNK));
        let tasks: Vec<_> = self
            .photons
            .chunks(CHUNK)
            .map(|photons| (photons, chunks.each_mut().map(|c| c.next().unwrap())))
            .collect();
        tasks.into_par_iter().for_each(|(photons, out)| {
            for (i, photon) in photons.iter().enumerate() {
                let values = [photon.position, photon.flux, photon.wi_unfolded()];
                for (k, value) in values.iter().flat_map(|v| v.to_array()).enumerate() {
                    out[k][i] = value;
                }
            }
        });
    }

    /// Calls `f(photon, d²)` for every photon within distance `r` of `p` (`d² <= r²`),
    /// exactly once each, in a deterministic order.
    ///
    /// Visits the buckets of the cells overlapping the cube `p ± r`: 2 x 2 x 2 when `r` is at
    /// most the build radius. Each bucket is scanned once even if several of those cells
    /// share it. `r` may exceed the build radius (more cells are visited). Allocates nothing.
    #[inline]
    pub fn for_each_in_radius(&self, p: Vec3, r: f32, mut f: impl FnMut(&Photon, f32)) {
        self.query(p, r, |i, d2| f(&self.photons[i], d2));
    }

    /// [`HashGrid::for_each_in_radius`] handing out only what a density estimate reads, the
    /// flux and the incoming side ([`FluxRecord`]).
    #[inline]
    pub fn for_each_flux_in_radius(&self, p: Vec3, r: f32, mut f: impl FnMut(&FluxRecord, f32)) {
        self.query(p, r, |i, d2| f(&FluxRecord::from(&self.photons[i]), d2));
    }

    /// The kernel-weighted flux of the photons within `r` of `p` that arrived from the side
    /// `n` points to: sum over those photons of Phi_p k(d_p²) (`kernel` of radius `r`), the
    /// sum of a density estimate. Photons with `wi . n <= 0` are left out
    /// ([`FluxRecord::arrived_from`]).
    ///
    /// The usual query (at most 27 cells) sums 8 candidates at once with no branch per
    /// photon; the sum is formed per lane, so it equals the sequential sum over
    /// [`HashGrid::for_each_flux_in_radius`] up to rounding.
    #[inline]
    pub fn kernel_flux(&self, p: Vec3, r: f32, n: Vec3, kernel: &Kernel) -> Vec3 {
        let Some((lo, hi, cells)) = self.cell_range(p, r) else {
            return Vec3::ZERO;
        };
        if cells > SMALL_QUERY as i64 {
            let mut sum = Vec3::ZERO;
            self.for_each_flux_in_radius(p, r, |photon, d2| {
                if photon.arrived_from(n) {
                    sum += photon.flux * kernel.weight(d2);
                }
            });
            return sum;
        }
        let (norm, slope) = kernel.coefficients();
        let q = FluxQuery {
            p,
            n,
            r2: r * r,
            norm,
            slope,
        };
        let runs = self.bucket_runs(lo, hi);
        let columns = self.columns.view();
        let mut sum = FluxSum::new();
        // One loop over the blocks of all runs; stepping to the next run is a select rather
        // than a branch (which the varying run lengths would mispredict).
        let (mut run, (mut i, mut end)) = (0, runs.get(0));
        for _ in 0..runs.blocks {
            sum.add(columns.block(i), end - i, &q);
            i += LANES;
            let next = (i >= end) as usize;
            run += next;
            let (next_start, next_end) = runs.get(run);
            // All ones when moving on (branch-free, so no misprediction per run).
            let take = next.wrapping_neg();
            i = (next_start & take) | (i & !take);
            end = (next_end & take) | (end & !take);
        }
        sum.total()
    }

    /// Calls `f(i, d²)` for the stored index `i` of every photon within `r` of `p`.
    #[inline(always)]
    fn query(&self, p: Vec3, r: f32, mut f: impl FnMut(usize, f32)) {
        let r2 = r * r;
        let Some((lo, hi, cells)) = self.cell_range(p, r) else {
            return;
        };

        if cells <= SMALL_QUERY as i64 {
            let columns = self.columns.view();
            for range in self.bucket_runs(lo, hi).iter() {
                Self::scan(&columns, range, p, r2, &mut f);
            }
        } else if cells >= self.hash.buckets as i64 {
            // The sphere covers more cells than there are buckets: scan every photon once.
            Self::scan(&self.columns.view(), 0..self.photons.len(), p, r2, &mut f);
        } else {
            // Many cells: instead of remembering buckets, accept a photon only when visiting
            // its own cell, which happens exactly once since cells are distinct.
            for z in lo.z..=hi.z {
                for y in lo.y..=hi.y {
                    for x in lo.x..=hi.x {
                        let c = IVec3::new(x, y, z);
                        for i in self.bucket(self.hash.bucket(c)) {
                            let position = self.photons[i].position;
                            let d2 = position.distance_squared(p);
                            if d2 <= r2 && self.hash.cell(position) == c {
                                f(i, d2);
                            }
                        }
                    }
                }
            }
        }
    }

    /// Calls `f(i, d²)` for the photons `i` of the stored `range` (read through `columns`, the
    /// grid's column view, made once per query) with `d² <= r2`, in order.
    ///
    /// Blocks of [`LANES`] candidates: the squared distances (computed as
    /// `Vec3::distance_squared` does, so bit-identical to it) and a mask of those inside;
    /// lanes past the end of the range are masked off (they read the padding or the next
    /// bucket).
    #[inline(always)]
    fn scan(
        columns: &ColumnsView<'_>,
        range: Range<usize>,
        p: Vec3,
        r2: f32,
        f: &mut impl FnMut(usize, f32),
    ) {
        let mut i = range.start;
        while i < range.end {
            let (mut inside, d2) = block_distances(columns.block(i).position, p, r2);
            let valid = (range.end - i).min(LANES);
            inside &= ((1u64 << valid) - 1) as u32;
            while inside != 0 {
                let k = inside.trailing_zeros() as usize;
                f(i + k, d2[k]);
                inside &= inside - 1;
            }
            i += LANES;
        }
    }

    /// The stored ranges of the distinct buckets of the cells `lo..=hi` (at most
    /// [`SMALL_QUERY`] cells), in the order of the cells: several cells may hash to one
    /// bucket, which is visited once (the few buckets seen are remembered in a stack array).
    ///
    /// Along x the cells of a row are consecutive buckets ([`CellHash::bucket`]), and
    /// consecutive buckets are consecutive in the photon array, so a run of new buckets is
    /// one range: the photons are the same, in the same order, with fewer bucket lookups and
    /// partial blocks. Returned in a stack array rather than through a callback, so that the
    /// caller's scan stays one inlined loop.
    #[inline(always)]
    fn bucket_runs(&self, lo: IVec3, hi: IVec3) -> Runs {
        let mut runs = Runs::default();
        // Usually the rows' runs of buckets are disjoint and none wraps around the end of
        // the table: then each row is one run, with no per-bucket bookkeeping (and no
        // unpredictable branch). This is what the general walk below gives in that case.
        let buckets = self.hash.buckets as usize;
        let len = (hi.x - lo.x) as usize + 1;
        let mut rows = [0usize; SMALL_QUERY];
        let mut n_rows = 0;
        for z in lo.z..=hi.z {
            for y in lo.y..=hi.y {
                rows[n_rows] = self.hash.bucket(IVec3::new(lo.x, y, z));
                n_rows += 1;
            }
        }
        let rows = &rows[..n_rows];
        let mut clash = false;
        for (i, &a) in rows.iter().enumerate() {
            clash |= a + len > buckets;
            for &b in &rows[..i] {
                clash |= (a < b + len) & (b < a + len);
            }
        }
        if !clash {
            for &row in rows {
                runs.push(self.buckets(row..row + len));
            }
            return runs;
        }

        let mut seen = [0usize; SMALL_QUERY];
        let mut n_seen = 0;
        let mask = self.hash.buckets as usize - 1;
        for &first in rows {
            // The pending run of new, consecutive buckets, [start, end).
            let mut run: Option<(usize, usize)> = None;
            for dx in 0..len {
                let b = (first + dx) & mask;
                let new = !seen[..n_seen].contains(&b);
                if new {
                    seen[n_seen] = b;
                    n_seen += 1;
                }
                run = match run {
                    // b == end also excludes the wrap from the last bucket to bucket 0.
                    Some((start, end)) if new && b == end => Some((start, b + 1)),
                    pending => {
                        if let Some((start, end)) = pending {
                            runs.push(self.buckets(start..end));
                        }
                        new.then_some((b, b + 1))
                    }
                };
            }
            if let Some((start, end)) = run {
                runs.push(self.buckets(start..end));
            }
        }
        runs
    }

    /// The cells (lowest, highest, count) that the sphere of radius `r` around `p` overlaps;
    /// `None` when nothing can be found (r < 0 or NaN, or no photon stored). The cube is
    /// padded so that rounding in `p ± r` or in d² never leaves out a photon with computed
    /// d² <= r² (a few ulps of r and of |p| suffice; this is generous).
    #[inline(always)]
    fn cell_range(&self, p: Vec3, r: f32) -> Option<(IVec3, IVec3, i64)> {
        let pad = r * (1.0 + 1e-6) + p.abs().max_element() * 1e-6;
        let (lo, hi) = (self.hash.cell(p - pad), self.hash.cell(p + pad));
        if !(lo.cmple(hi).all()) || self.photons.is_empty() {
            return None;
        }
        let extent = (hi.as_i64vec3() - lo.as_i64vec3()) + 1;
        Some((
            lo,
            hi,
            extent.x.saturating_mul(extent.y).saturating_mul(extent.z),
        ))
    }

    /// The stored range of bucket `b`.
    #[inline]
    fn bucket(&self, b: usize) -> Range<usize> {
        self.buckets(b..b + 1)
    }

    /// The stored range of the consecutive buckets `run` (one range: bucket `b + 1` is
    /// stored right after bucket `b`).
    #[inline]
    fn buckets(&self, run: Range<usize>) -> Range<usize> {
        self.start[run.start] as usize..self.start[run.end] as usize
    }

    /// All stored photons, grouped by bucket in the canonical order.
    pub fn photons(&self) -> &[Photon] {
        &self.photons
    }

    /// Photons stored.
    pub fn len(&self) -> usize {
        self.photons.len()
    }

    /// Whether no photon is stored.
    pub fn is_empty(&self) -> bool {
        self.photons.is_empty()
    }

    /// Side of a cell (twice the build radius).
    pub fn cell_size(&self) -> f32 {
        self.cell_size
    }

    /// Number of hash buckets.
    pub fn bucket_count(&self) -> usize {
        self.hash.buckets as usize
    }

    /// Bytes allocated by the grid.
    pub fn memory_bytes(&self) -> usize {
        self.photons.capacity() * std::mem::size_of::<Photon>()
            + self.columns.memory_bytes()
            + (self.start.capacity() + self.bucket_of.capacity()) * std::mem::size_of::<u32>()
    }
}

/// Up to [`SMALL_QUERY`] non-empty ranges of stored photons, on the stack.
#[derive(Clone, Copy, Debug, Default)]
struct Runs {
    /// One more than can be used: `get(len)` reads an empty range.
    ranges: [(u32, u32); SMALL_QUERY + 1],
    len: usize,
    /// Blocks of [`LANES`] candidates that cover all ranges, each range on its own.
    blocks: usize,
}

impl Runs {
    /// Appends a range unless it is empty (the grid stores fewer than `u32::MAX` photons).
    #[inline]
    fn push(&mut self, range: Range<usize>) {
        self.ranges[self.len] = (range.start as u32, range.end as u32);
        self.len += !range.is_empty() as usize;
        self.blocks += range.len().div_ceil(LANES);
    }

    /// Range `k` as (start, end); empty for `k == len`.
    #[inline(always)]
    fn get(&self, k: usize) -> (usize, usize) {
        let (start, end) = self.ranges[k.min(SMALL_QUERY)];
        (start as usize, end as usize)
    }

    #[inline]
    fn iter(&self) -> impl Iterator<Item = Range<usize>> + '_ {
        self.ranges[..self.len]
            .iter()
            .map(|&(start, end)| start as usize..end as usize)
    }
}

/// The coordinates of [`LANES`] consecutive candidates, one array per axis.
type Positions<'a> = [&'a [f32; LANES]; 3];

/// The squared distances from `p` of the [`LANES`] candidates `(xs[k], ys[k], zs[k])`, and the
/// mask of those with `d² <= r2` (bit k for candidate k).
///
/// `d² = (dx² + dy²) + dz²` in this order and without fused multiply-adds, as
/// `Vec3::distance_squared` computes it, so each lane equals that scalar expression bit for
/// bit (tested) and results do not depend on how the crate was compiled.
#[inline(always)]
fn block_distances(position: Positions<'_>, p: Vec3, r2: f32) -> (u32, [f32; LANES]) {
    let [xs, ys, zs] = position;
    let dx = F32x8::from_array(xs) - F32x8::splat(p.x);
    let dy = F32x8::from_array(ys) - F32x8::splat(p.y);
    let dz = F32x8::from_array(zs) - F32x8::splat(p.z);
    let d2 = (dx * dx + dy * dy) + dz * dz;
    // Ordered <=: false for NaN, like the scalar comparison.
    (d2.le(F32x8::splat(r2)).bits(), d2.to_array())
}

/// Sorts every bucket of `photons` (bucket `b` is `start[b] - start[0]..start[b + 1] -
/// start[0]`) by `Photon::order_key`, splitting the bucket range in halves across threads.
fn sort_buckets(photons: &mut [Photon], start: &[u32]) {
    let base = start[0];
    if start.len() > 2 && photons.len() >= PARALLEL_MIN {
        let mid = start.len() / 2;
        let (left, right) = photons.split_at_mut((start[mid] - base) as usize);
        rayon::join(
            || sort_buckets(left, &start[..=mid]),
            || sort_buckets(right, &start[mid..]),
        );
    } else if start.len() == 2 && photons.len() >= PARALLEL_MIN {
        photons.par_sort_unstable_by_key(Photon::order_key); // one huge bucket
    } else {
        for w in start.windows(2) {
            let bucket = &mut photons[(w[0] - base) as usize..(w[1] - base) as usize];
            if bucket.len() > 1 {
                bucket.sort_unstable_by_key(Photon::order_key);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cells_use_floor_for_negative_coordinates() {
        let hash = CellHash {
            inv_cell: 2.0,
            buckets: 8,
        };
        // Truncation toward zero would merge cells -1 and 0 into one twice as wide.
        assert_eq!(
            hash.cell(Vec3::new(-0.25, -0.5, 0.25)),
            IVec3::new(-1, -1, 0)
        );
        assert_eq!(hash.cell(Vec3::new(-0.0, 0.5, -0.51)), IVec3::new(0, 1, -2));
        assert_eq!(hash.cell(Vec3::splat(-1e-30)), IVec3::splat(-1));
    }

    #[test]
    fn floor_i32_matches_floor() {
        // Magnitudes from 1e-3 to 3e9 (past the i32 range), both signs, with fractions.
        let mut m = 1e-3f32;
        while m < 3e9 {
            let (above, below) = (
                f32::from_bits(m.to_bits() + 1),
                -f32::from_bits(m.to_bits() + 1),
            );
            for v in [m, -m, m + 0.5, -m - 0.5, above, below] {
                let expected = v.floor().clamp(i32::MIN as f32, i32::MAX as f32) as i32;
                assert_eq!(floor_i32(v), expected, "{v}");
            }
            m *= 1.01;
        }
        for v in [
            0.0,
            -0.0,
            -1.0,
            1.0,
            -0.5,
            0.5,
            -1e-30,
            16777217.0,
            -16777216.0,
        ] {
            assert_eq!(floor_i32(v), v.floor() as i32, "{v}");
        }
        assert_eq!(floor_i32(f32::NAN), 0);
        assert_eq!(floor_i32(f32::NEG_INFINITY), i32::MIN);
        assert_eq!(floor_i32(f32::INFINITY), i32::MAX);
    }

    #[test]
    fn buckets_are_in_range_and_well_spread() {
        for buckets in [1u32, 2, 64, 4096] {
            let hash = CellHash {
                inv_cell: 1.0,
                buckets,
            };
            let mut used = vec![false; buckets as usize];
            // A 16^3 block of cells around the origin, as many cells as the largest table.
            for z in -8..8 {
                for y in -8..8 {
                    for x in -8..8 {
                        used[hash.bucket(IVec3::new(x, y, z))] = true;
                    }
                }
            }
            // A random map of 4096 cells into n buckets fills n (1 - e^(-4096/n)) of them
            // on average: 63% for n = 4096 and ~100% for the smaller tables.
            let filled = used.iter().filter(|&&u| u).count() as f32 / buckets as f32;
            let expected = 1.0 - (-4096.0 / buckets as f32).exp();
            assert!(
                filled > 0.95 * expected,
                "{buckets} buckets: {filled} filled"
            );
        }
    }

    #[test]
    fn block_distances_match_scalar_distance_squared_bit_for_bit() {
        let mut rng = crate::sampling::Rng::new(7, 0, 0);
        let mut coordinate = |scale: f32| (rng.uniform() - 0.5) * scale;
        for trial in 0..20_000 {
            let scale = [1e-3, 1.0, 3.0, 1e5][trial % 4];
            let p = Vec3::new(coordinate(scale), coordinate(scale), coordinate(scale));
            let mut xyz = [[0.0f32; LANES]; 3];
            for k in 0..LANES {
                for axis in xyz.iter_mut() {
                    axis[k] = coordinate(scale);
                }
            }
            // Padding lanes, a candidate at p (d² = 0) and one exactly on the radius.
            xyz[0][7] = f32::INFINITY;
            xyz[1][6] = f32::NAN;
            (xyz[0][5], xyz[1][5], xyz[2][5]) = (p.x, p.y, p.z);
            let q = Vec3::new(xyz[0][4], xyz[1][4], xyz[2][4]);
            let r2 = if trial % 2 == 0 {
                q.distance_squared(p)
            } else {
                0.1 * scale * scale
            };
            let position = xyz.each_ref();
            let (mask, d2) = block_distances(position, p, r2);
            for k in 0..LANES {
                let expected = Vec3::new(xyz[0][k], xyz[1][k], xyz[2][k]).distance_squared(p);
                assert_eq!(
                    d2[k].to_bits(),
                    expected.to_bits(),
                    "trial {trial}, lane {k}"
                );
                assert_eq!(
                    mask >> k & 1 == 1,
                    expected <= r2,
                    "trial {trial}, lane {k}"
                );
            }
            // The candidate at p is in, padding and NaN are out, the one on the radius is in.
            assert_eq!(mask & 0b1110_0000, 0b0010_0000, "trial {trial}");
            assert!(trial % 2 == 1 || mask & 0b1_0000 != 0, "trial {trial}");
        }
    }

    #[test]
    fn cells_along_x_take_consecutive_buckets() {
        for buckets in [1u32, 16, 1 << 18] {
            let hash = CellHash {
                inv_cell: 1.0,
                buckets,
            };
            for (y, z) in [(0, 0), (-3, 7), (i32::MAX, i32::MIN), (12345, -54321)] {
                for x in [-2, -1, 0, 1, 1000, i32::MAX - 1] {
                    let b = hash.bucket(IVec3::new(x, y, z));
                    let next = hash.bucket(IVec3::new(x + 1, y, z));
                    assert_eq!(next, (b + 1) % buckets as usize, "{x} {y} {z}");
                }
            }
        }
    }
}
