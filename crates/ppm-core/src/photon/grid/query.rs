//! Gathers: the cells a query sphere overlaps, the distinct buckets they hash to (as runs of
//! stored photons), and the scans of those runs, 8 candidates at a time.

use super::distances::block_distances;
use super::HashGrid;
use crate::photon::gather::{ColumnsView, FluxQuery, FluxSum};
use crate::photon::{FluxRecord, GatherNormals, Kernel, Photon, MAX_KEY_BOUNCE};
use crate::simd::LANES;
use glam::{IVec3, Vec3};
use std::ops::Range;

/// Cells a query dedupes through a stack array: 3 x 3 x 3 covers any radius up to the cell
/// size (half the cell when the query radius equals the build radius, plus rounding slivers).
const SMALL_QUERY: usize = 27;

impl HashGrid {
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

    /// [`HashGrid::for_each_in_radius`] handing out the photon's index in
    /// [`HashGrid::photons`] (the grid's order) instead of the photon: for data kept beside
    /// the grid in that order.
    #[inline]
    pub fn for_each_index_in_radius(&self, p: Vec3, r: f32, f: impl FnMut(usize, f32)) {
        self.query(p, r, f);
    }

    /// [`HashGrid::for_each_in_radius`] handing out only what a density estimate reads, the
    /// flux and the incoming side ([`FluxRecord`]).
    #[inline]
    pub fn for_each_flux_in_radius(&self, p: Vec3, r: f32, mut f: impl FnMut(&FluxRecord, f32)) {
        self.query(p, r, |i, d2| f(&FluxRecord::from(&self.photons[i]), d2));
    }

    /// The kernel-weighted flux of the photons within `r` of `p` that arrived from the
    /// viewer's side of a surface with `normals`: sum over those photons of
    /// Phi_p k(d_p²) w(wi_p) (`kernel` of radius `r`, w the photon's weight for shading
    /// normals, [`GatherNormals::weight`], 1 when flat), the sum of a density estimate.
    ///
    /// The usual query (at most 27 cells) sums 8 candidates at once with no branch per
    /// photon; the sum is formed per lane, so it equals the sequential sum over
    /// [`HashGrid::for_each_flux_in_radius`] up to rounding.
    #[inline]
    pub fn kernel_flux(&self, p: Vec3, r: f32, normals: GatherNormals, kernel: &Kernel) -> Vec3 {
        self.kernel_flux_up_to(p, r, normals, kernel, u32::MAX)
    }

    /// [`HashGrid::kernel_flux`] over the photons of at most `max_bounce` bounces
    /// ([`Photon::bounce`]; exact up to [`MAX_KEY_BOUNCE`], above which every photon counts).
    #[inline]
    pub fn kernel_flux_up_to(
        &self,
        p: Vec3,
        r: f32,
        normals: GatherNormals,
        kernel: &Kernel,
        max_bounce: u32,
    ) -> Vec3 {
        let Some((lo, hi, cells)) = self.cell_range(p, r) else {
            return Vec3::ZERO;
        };
        let max_bounce = max_bounce.min(MAX_KEY_BOUNCE);
        if cells > SMALL_QUERY as i64 {
            let mut sum = Vec3::ZERO;
            self.query(p, r, |i, d2| {
                let photon = &self.photons[i];
                let w = normals.weight(photon.wi_unfolded());
                if w > 0.0 && photon.bounce() <= max_bounce {
                    sum += photon.flux * (kernel.weight(d2) * w);
                }
            });
            return sum;
        }
        let (norm, slope) = kernel.coefficients();
        let q = FluxQuery {
            p,
            n: normals.geometric,
            ns: normals.shading,
            r2: r * r,
            norm,
            slope,
            max_bounce: max_bounce as f32,
        };
        // Flat shading (every quad and sphere, meshes without vertex normals) keeps the
        // loop without the ratio.
        if normals.is_flat() {
            self.block_sum::<false>(lo, hi, &q)
        } else {
            self.block_sum::<true>(lo, hi, &q)
        }
    }

    /// The block sums of [`HashGrid::kernel_flux`] over the buckets of cells `lo..=hi`.
    #[inline(always)]
    fn block_sum<const SHADED: bool>(&self, lo: IVec3, hi: IVec3, q: &FluxQuery) -> Vec3 {
        let runs = self.bucket_runs(lo, hi);
        let columns = self.columns.view();
        let mut sum = FluxSum::new();
        // One loop over the blocks of all runs; stepping to the next run is a select rather
        // than a branch (which the varying run lengths would mispredict).
        let (mut run, (mut i, mut end)) = (0, runs.get(0));
        for _ in 0..runs.blocks {
            sum.add::<SHADED>(columns.block(i), end - i, q);
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
    /// Along x the cells of a row are consecutive buckets (`CellHash::bucket`), and
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
