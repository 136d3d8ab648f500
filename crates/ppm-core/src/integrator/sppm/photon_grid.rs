//! The hash grid over one batch of SPPM's photons, looked up by every visible point.
//!
//! Each visible point gathers the photons inside its disc. Cells have edge 2 R_q, R_q the
//! [`CELL_QUANTILE`] quantile of the radii of the iteration's visible points, so most discs'
//! bounding boxes overlap at most 2 x 2 x 2 cells; a larger disc visits more cells. (Cells
//! for the largest radius would make every gather scan cells sized for it: radii shrink
//! where photons arrive, so after some iterations the dark pixels' radii, which barely
//! shrink, would set the cells of all.) Only the box of all discs is gridded: a photon
//! outside it lies in no disc and is dropped when the grid is built. The photons of a bucket are contiguous
//! (a counting sort), their positions in one array (the distance test reads 12 bytes per
//! candidate) and what a hit reads (direction, flux, bounce) in another.
//!
//! Buckets are laid out by rows along x: cell (x, y, z) takes bucket hash(y, z) + x, so the
//! two cells of a box along x are neighbours in memory. The visible points are gathered in
//! pixel order, neighbouring pixels see neighbouring points and read the same cells: the
//! grid's reads stay in cache.
//!
//! Why not ppm's [`crate::photon::HashGrid`]: that grid stores a whole iteration's photons for
//! gathers of one radius, sorts each bucket into a canonical order (its f32 sums must not
//! depend on thread scheduling) and keeps SIMD columns for its kernel sum. Here the photons
//! are a batch, the radii are per point and shrink apart, the sums are fixed-point (order-free,
//! so no sort is needed), and a photon outside the box of all discs is dropped at the build:
//! a box cull and quantile-sized cells instead of a sort and columns.

use super::photon::SppmPhoton;
use super::visible_point::SplatPoint;
use glam::Vec3;
use rayon::prelude::*;

/// Cells a disc of radius up to R_q overlaps, at most (cells of edge 2 R_q).
const SMALL_QUERY: usize = 8;

/// The quantile of the visible points' radii the cells are sized for.
pub const CELL_QUANTILE: f32 = 0.9;

/// Bytes per pixel: the scratch of squared radii.
pub const BYTES_PER_PIXEL: usize = std::mem::size_of::<f32>();

/// Bytes per photon of a batch: the append buffer's record, the grid's sorted position and
/// payload, the bucket of each photon (scratch) and at most two bucket bounds.
pub const BYTES_PER_PHOTON: usize = std::mem::size_of::<SppmPhoton>()
    + std::mem::size_of::<Vec3>()
    + std::mem::size_of::<Payload>()
    + 3 * std::mem::size_of::<u32>();

/// Marks a photon outside the box of all discs in the scratch array of buckets.
const OUTSIDE: u32 = u32::MAX;

/// What the estimate reads of a photon inside a disc.
#[derive(Clone, Copy, Debug, Default)]
pub struct Payload {
    /// Unit direction the photon arrived from (pointing away from the surface).
    pub wi: Vec3,
    /// Its flux.
    pub flux: Vec3,
    /// Its bounce.
    pub bounce: u32,
}

/// The photons of one batch, sorted into hashed cells of edge 2 R_max over the box of the
/// iteration's discs. Storage is reused from batch to batch and grows only with the batch.
#[derive(Debug, Default)]
pub struct PhotonGrid {
    /// Corner of the box of all visible points' discs.
    lower: Vec3,
    /// Its opposite corner.
    upper: Vec3,
    /// 1 / cell edge.
    inv_cell: f32,
    /// The number of buckets minus one (a power of two minus one).
    mask: usize,
    /// Bucket b holds photons `starts[b]..starts[b + 1]`.
    starts: Vec<u32>,
    positions: Vec<Vec3>,
    payloads: Vec<Payload>,
    /// Scratch: the bucket of each photon of the batch, [`OUTSIDE`] if it is outside the box.
    bucket_of: Vec<u32>,
    /// Scratch: the squared radii of the visible points, for their quantile.
    radii: Vec<f32>,
}

/// Cell coordinates of `p` relative to `lower` (non-negative inside the box).
#[inline]
fn cell_of(p: Vec3, lower: Vec3, inv_cell: f32) -> [u32; 3] {
    let c = (p - lower) * inv_cell;
    [c.x as u32, c.y as u32, c.z as u32]
}

/// The bucket of a cell: a hash of the row (y, z) (multiply, xor, fold: every bit of y and z
/// reaches the low bits), plus x, masked to the table size (a power of two).
#[inline]
fn bucket_of(cell: [u32; 3], mask: usize) -> usize {
    let h = (cell[1] as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15)
        ^ (cell[2] as u64).wrapping_mul(0xc2b2_ae3d_27d4_eb4f);
    let row = (h ^ (h >> 29) ^ (h >> 47)) as u32;
    row.wrapping_add(cell[0]) as usize & mask
}

impl PhotonGrid {
    /// An empty grid.
    pub fn new() -> Self {
        Self::default()
    }

    /// Sets the box and the cells for this iteration's visible points (those found; each
    /// disc is `(p, r2)`); every batch of the iteration is then built over them.
    pub fn cover(&mut self, points: &[SplatPoint]) {
        let (lower, upper, r_max) = points
            .par_iter()
            .filter_map(SplatPoint::disc)
            .map(|(p, r2)| {
                let r = r2.sqrt();
                (p - r, p + r, r)
            })
            .reduce(
                || (Vec3::INFINITY, Vec3::NEG_INFINITY, 0.0f32),
                |a, b| (a.0.min(b.0), a.1.max(b.1), a.2.max(b.2)),
            );
        self.lower = lower;
        self.upper = upper;
        self.radii.clear();
        self.radii
            .extend(points.iter().filter_map(|p| p.disc().map(|(_, r2)| r2)));
        let r_q = if self.radii.is_empty() {
            0.0
        } else {
            let k = ((self.radii.len() - 1) as f32 * CELL_QUANTILE) as usize;
            self.radii
                .select_nth_unstable_by(k, f32::total_cmp)
                .1
                .sqrt()
        };
        // Cells of edge 2 R_q, but at least R_max / 4 (the largest disc's box spans at most
        // 10 cells per axis) and never so small that the box spans more cells than a u32
        // counts.
        let extent = (upper - lower).max_element();
        let edge = (2.0 * r_q)
            .max(0.25 * r_max)
            .max(extent * 1e-6)
            .max(f32::MIN_POSITIVE);
        self.inv_cell = if r_max > 0.0 { 1.0 / edge } else { 0.0 };
    }

    /// Rebuilds the grid over `photons` in the box of [`Self::cover`]; photons outside it
    /// (in no disc) are left out.
    pub fn build(&mut self, photons: &[SppmPhoton]) {
        let (lower, upper, inv_cell) = (self.lower, self.upper, self.inv_cell);
        let buckets = photons.len().max(1).next_power_of_two();
        let mask = buckets - 1;
        self.mask = mask;
        // 1. The bucket of every photon.
        photons
            .par_iter()
            .with_min_len(1 << 12)
            .map(|photon| {
                let p = photon.position;
                if p.cmpge(lower).all() && p.cmple(upper).all() {
                    bucket_of(cell_of(p, lower, inv_cell), mask) as u32
                } else {
                    OUTSIDE
                }
            })
            .collect_into_vec(&mut self.bucket_of);
        // 2. Counting sort: count bucket b in starts[b + 1], prefix sums make starts[b] its
        //    first slot, and the scatter advances starts[b] to b's end; a shift restores it.
        self.starts.clear();
        self.starts.resize(buckets + 1, 0);
        for &b in &self.bucket_of {
            if b != OUTSIDE {
                self.starts[b as usize + 1] += 1;
            }
        }
        let mut total = 0;
        for s in &mut self.starts {
            total += *s;
            *s = total;
        }
        self.positions.resize(total as usize, Vec3::ZERO);
        self.payloads.resize(total as usize, Payload::default());
        for (photon, &b) in photons.iter().zip(&self.bucket_of) {
            if b == OUTSIDE {
                continue;
            }
            let slot = &mut self.starts[b as usize];
            self.positions[*slot as usize] = photon.position;
            self.payloads[*slot as usize] = Payload {
                wi: photon.wi,
                flux: photon.flux,
                bounce: photon.bounce,
            };
            *slot += 1;
        }
        self.starts.copy_within(0..buckets, 1);
        self.starts[0] = 0;
    }

    /// Calls `f(position, payload)` for every photon of the cells the bounding box of disc
    /// `(p, r2)` overlaps, each once: a superset of the photons inside the disc.
    ///
    /// A box of at most [`SMALL_QUERY`] cells (radius up to R_q) reads the distinct buckets of
    /// its cells (a bucket two cells share is read once). A larger box reads the bucket of
    /// each of its cells, and of each only the photons of that cell (their cell recomputed
    /// from their position): a bucket shared by several of its cells is read several times,
    /// each photon kept once.
    #[inline]
    pub fn for_each_candidate(&self, p: Vec3, r2: f32, mut f: impl FnMut(Vec3, &Payload)) {
        if self.payloads.is_empty() {
            return;
        }
        let r = r2.sqrt();
        let lo = cell_of(p - r, self.lower, self.inv_cell);
        let hi = cell_of(p + r, self.lower, self.inv_cell);
        let count = (0..3).fold(1u64, |n, a| n * (hi[a] - lo[a] + 1) as u64);
        if count <= SMALL_QUERY as u64 {
            let mut buckets = [0usize; SMALL_QUERY];
            let mut n = 0;
            for z in lo[2]..=hi[2] {
                for y in lo[1]..=hi[1] {
                    for x in lo[0]..=hi[0] {
                        let b = bucket_of([x, y, z], self.mask);
                        if !buckets[..n].contains(&b) {
                            buckets[n] = b;
                            n += 1;
                        }
                    }
                }
            }
            for &b in &buckets[..n] {
                let (positions, payloads) = self.bucket(b);
                for (&xp, photon) in positions.iter().zip(payloads) {
                    f(xp, photon);
                }
            }
            return;
        }
        for z in lo[2]..=hi[2] {
            for y in lo[1]..=hi[1] {
                for x in lo[0]..=hi[0] {
                    let (positions, payloads) = self.bucket(bucket_of([x, y, z], self.mask));
                    for (&xp, photon) in positions.iter().zip(payloads) {
                        if cell_of(xp, self.lower, self.inv_cell) == [x, y, z] {
                            f(xp, photon);
                        }
                    }
                }
            }
        }
    }

    /// The photons of `bucket`: their positions and payloads, index for index.
    #[inline]
    fn bucket(&self, bucket: usize) -> (&[Vec3], &[Payload]) {
        let range = self.starts[bucket] as usize..self.starts[bucket + 1] as usize;
        (&self.positions[range.clone()], &self.payloads[range])
    }

    /// Bytes held (bounded by the batch's photons).
    pub fn memory_bytes(&self) -> usize {
        (self.starts.capacity() + self.bucket_of.capacity()) * std::mem::size_of::<u32>()
            + self.positions.capacity() * std::mem::size_of::<Vec3>()
            + self.payloads.capacity() * std::mem::size_of::<Payload>()
            + self.radii.capacity() * std::mem::size_of::<f32>()
    }
}
