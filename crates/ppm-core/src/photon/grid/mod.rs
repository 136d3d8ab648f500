//! A hashed uniform grid over one iteration's photons, for fixed-radius gathers.
//!
//! Space is cut into cubic cells of side `2 r` (the gather diameter) and each cell is hashed
//! into one of about as many buckets as there are photons. [`HashGrid::build`] counting-sorts
//! the photons by bucket into one flat array, so a bucket's photons are contiguous, and a
//! query visits the buckets of the (usually 2 x 2 x 2) cells its sphere overlaps. Cells that
//! follow each other along x take consecutive buckets, so those 8 cells are 4 runs of memory.
//!
//! The photons are also kept as columns in the same order (position, flux, incoming
//! direction, one array per coordinate, and the bounce of the photon's key): a query tests about five candidates for every photon
//! inside its sphere (the cube of 2 x 2 cells on a surface has 16 r² of area, the disc
//! pi r²), so it works on [`LANES`] candidates at once (an 8-lane `F32x8` per coordinate).
//! [`HashGrid::for_each_in_radius`] computes their distances into a bit mask and calls back
//! for the set bits only; [`HashGrid::kernel_flux`], the density estimate's sum, weights and
//! masks all lanes and has no branch per photon at all (see `photon/gather.rs`).
//!
//! - `mod.rs` (this file): the grid and its build (bucket of every photon, counting sort,
//!   canonical order, columns);
//! - `hash.rs`: the map from points to cells and from cells to buckets;
//! - `query.rs`: the gathers (which buckets a sphere overlaps, and the scans over them);
//! - `distances.rs`: the 8-lane squared-distance kernel of the scans.
//!
//! # Determinism
//!
//! Photons arrive in a scheduling-dependent order (see [`crate::photon::PhotonBuffer`]).
//! After the counting sort, each bucket is sorted by [`Photon::order_key`]: the light-path
//! index, then the record's raw bits as a tie-break. Two photons with equal keys are
//! identical, so the stored order depends only on the set of photons, and so does the order
//! in which a query calls its closure: gathers sum in the same order at any thread count.

mod distances;
mod hash;
mod query;

use super::gather::Columns;
use super::Photon;
use crate::simd::LANES;
use hash::CellHash;
use rayon::prelude::*;

/// Photon count below which a build step runs serially (parallel overhead dominates).
const PARALLEL_MIN: usize = 1 << 14;

/// Photons sorted into hashed cells, rebuilt every iteration with its allocations reused.
#[derive(Clone, Debug)]
pub struct HashGrid {
    hash: CellHash,
    cell_size: f32,
    /// Photons grouped by bucket; within a bucket ordered by `Photon::order_key`.
    photons: Vec<Photon>,
    /// `photons` as columns (position, flux, incoming direction, bounce), for the scan of
    /// the candidates and the density estimate.
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
            bounce,
        } = &mut self.columns;
        let mut columns = [x, y, z, r, g, b, u, v, w, bounce];
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
                out[9][i] = photon.bounce() as f32;
            }
        });
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
