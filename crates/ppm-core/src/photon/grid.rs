//! A hashed uniform grid over one iteration's photons, for fixed-radius gathers.
//!
//! Space is cut into cubic cells of side `2 r` (the gather diameter) and each cell is hashed
//! into one of about as many buckets as there are photons. [`HashGrid::build`] counting-sorts
//! the photons by bucket into one flat array, so a bucket's photons are contiguous, and a
//! query visits the buckets of the (usually 2 x 2 x 2) cells its sphere overlaps.
//!
//! # Determinism
//!
//! Photons arrive in a scheduling-dependent order (see [`super::PhotonBuffer`]). After the
//! counting sort, each bucket is sorted by [`Photon::order_key`]: the light-path index, then
//! the record's raw bits as a tie-break. Two photons with equal keys are identical, so the
//! stored order depends only on the set of photons, and so does the order in which a query
//! calls its closure: gathers sum in the same order at any thread count.

use super::Photon;
use glam::{IVec3, Vec3};
use rayon::prelude::*;

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
        (p * self.inv_cell).floor().as_ivec3()
    }

    /// The bucket of cell `c`: xor of per-axis products with large odd constants, a
    /// murmur-style finaliser to mix high bits into all bits, then a multiply-shift onto
    /// `0..buckets` (which uses the best-mixed, high bits).
    #[inline]
    fn bucket(&self, c: IVec3) -> usize {
        let mut h = (c.x as u32).wrapping_mul(0x9e37_79b1)
            ^ (c.y as u32).wrapping_mul(0x85eb_ca77)
            ^ (c.z as u32).wrapping_mul(0xc2b2_ae3d);
        h ^= h >> 15;
        h = h.wrapping_mul(0x2c1b_3c6d);
        h ^= h >> 12;
        ((h as u64 * self.buckets as u64) >> 32) as usize
    }
}

/// Photons sorted into hashed cells, rebuilt every iteration with its allocations reused.
#[derive(Clone, Debug)]
pub struct HashGrid {
    hash: CellHash,
    cell_size: f32,
    /// Photons grouped by bucket; within a bucket ordered by `Photon::order_key`.
    photons: Vec<Photon>,
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
            start: vec![0, 0],
            bucket_of: Vec::new(),
        }
    }

    /// Rebuilds the grid over `photons` for gathers of radius up to `radius` (> 0, finite):
    /// cells of side `2 radius`, and the next power of two `>= photons.len()` buckets.
    ///
    /// Larger query radii still work, visiting more cells.
    pub fn build(&mut self, photons: &[Photon], radius: f32) {
        self.build_with_buckets(photons, radius, photons.len());
    }

    /// [`HashGrid::build`] with about `buckets` buckets (rounded up to a power of two, at
    /// least 1); fewer buckets mean more cells share one. For tests and tuning.
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
    }

    /// Calls `f(photon, d²)` for every photon within distance `r` of `p` (`d² <= r²`),
    /// exactly once each, in a deterministic order.
    ///
    /// Visits the buckets of the cells overlapping the cube `p ± r`: 2 x 2 x 2 when `r` is at
    /// most the build radius. Each bucket is scanned once even if several of those cells
    /// share it. `r` may exceed the build radius (more cells are visited). Allocates nothing.
    #[inline]
    pub fn for_each_in_radius(&self, p: Vec3, r: f32, mut f: impl FnMut(&Photon, f32)) {
        let r2 = r * r;
        // Pad the cube so that rounding in `p ± r` or in d² never leaves out a photon with
        // computed d² <= r² (a few ulps of r and of |p| suffice; this is generous).
        let pad = r * (1.0 + 1e-6) + p.abs().max_element() * 1e-6;
        let (lo, hi) = (self.hash.cell(p - pad), self.hash.cell(p + pad));
        if !(lo.cmple(hi).all()) || self.photons.is_empty() {
            return; // r < 0 or NaN, or nothing stored
        }
        let extent = (hi.as_i64vec3() - lo.as_i64vec3()) + 1;
        let cells = extent.x.saturating_mul(extent.y).saturating_mul(extent.z);

        let mut scan = |photons: &[Photon], cell: Option<IVec3>| {
            for photon in photons {
                let d2 = photon.position.distance_squared(p);
                if d2 <= r2 && cell.is_none_or(|c| self.hash.cell(photon.position) == c) {
                    f(photon, d2);
                }
            }
        };

        if cells <= SMALL_QUERY as i64 {
            // Common case: dedupe the few buckets in a stack array.
            let mut seen = [0usize; SMALL_QUERY];
            let mut n_seen = 0;
            for z in lo.z..=hi.z {
                for y in lo.y..=hi.y {
                    for x in lo.x..=hi.x {
                        let b = self.hash.bucket(IVec3::new(x, y, z));
                        if !seen[..n_seen].contains(&b) {
                            seen[n_seen] = b;
                            n_seen += 1;
                            scan(self.bucket(b), None);
                        }
                    }
                }
            }
        } else if cells >= self.hash.buckets as i64 {
            // The sphere covers more cells than there are buckets: scan every photon once.
            scan(&self.photons, None);
        } else {
            // Many cells: instead of remembering buckets, accept a photon only when visiting
            // its own cell, which happens exactly once since cells are distinct.
            for z in lo.z..=hi.z {
                for y in lo.y..=hi.y {
                    for x in lo.x..=hi.x {
                        let c = IVec3::new(x, y, z);
                        scan(self.bucket(self.hash.bucket(c)), Some(c));
                    }
                }
            }
        }
    }

    /// The photons of bucket `b`.
    #[inline]
    fn bucket(&self, b: usize) -> &[Photon] {
        &self.photons[self.start[b] as usize..self.start[b + 1] as usize]
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
            + (self.start.capacity() + self.bucket_of.capacity()) * std::mem::size_of::<u32>()
    }
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
