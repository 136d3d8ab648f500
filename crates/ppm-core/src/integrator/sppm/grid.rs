//! The hash grid over one iteration's visible points, looked up by every photon.
//!
//! SPPM inverts photon mapping's search: the visible points are few (one per pixel) and
//! known before the photons, so they go into the grid and each photon finds the visible
//! points whose disc contains it. A visible point of radius R is inserted into every cell its
//! bounding box overlaps; with cells of edge 2 R_max that is at most 2 x 2 x 2 cells, so the
//! grid holds at most 8 entries per pixel whatever the number of photons. A photon then reads
//! one bucket: the visible points of its own cell (and of cells sharing the bucket's hash),
//! and tests each against the disc copied into the grid.
//!
//! A lookup is a chain of dependent reads in memory the photon pass visits in no order (the
//! bucket's start, its entries, their discs): [`VisiblePointGrid::prefetch_bucket`] and
//! [`VisiblePointGrid::prefetch_entries`] let the caller start each read well before it
//! needs it ([`super::splat`]).

use glam::{Vec3, Vec4};
use rayon::prelude::*;
use std::sync::atomic::{AtomicU32, Ordering};

/// Cells overlapped by one visible point, at most.
pub const MAX_CELLS: usize = 8;

/// Buckets of pixel indices, in compressed-row form: the pixels of bucket b are
/// `entries[starts[b]..starts[b + 1]]`. Within a bucket the order depends on the thread
/// schedule; nothing reads it in order (splats are integer sums), so images do not.
#[derive(Debug, Default)]
pub struct VisiblePointGrid {
    /// Corner of the box of all visible points' discs.
    lower: Vec3,
    /// Its opposite corner.
    upper: Vec3,
    /// 1 / cell edge.
    inv_cell: f32,
    /// The number of buckets minus one (a power of two minus one: a mask, not a division).
    mask: usize,
    starts: Vec<AtomicU32>,
    entries: Vec<AtomicU32>,
    /// Each pixel's disc as (x, y, z, r^2), r^2 < 0 without a visible point: the distance test
    /// reads 16 bytes, four neighbouring pixels to a cache line, instead of the whole point.
    discs: Vec<Vec4>,
}

/// Cell coordinates of `p` (saturating at the i32 range: far-out points share edge cells).
#[inline]
fn cell_of(p: Vec3, lower: Vec3, inv_cell: f32) -> [i32; 3] {
    let c = (p - lower) * inv_cell;
    [c.x.floor() as i32, c.y.floor() as i32, c.z.floor() as i32]
}

/// Bucket of a cell: the spatial hash of Teschner et al. 2003, masked to the table size (a
/// power of two).
#[inline]
fn bucket_of(cell: [i32; 3], mask: usize) -> usize {
    let h = (cell[0] as u32).wrapping_mul(73_856_093)
        ^ (cell[1] as u32).wrapping_mul(19_349_663)
        ^ (cell[2] as u32).wrapping_mul(83_492_791);
    h as usize & mask
}

impl VisiblePointGrid {
    /// An empty grid.
    pub fn new() -> Self {
        Self::default()
    }

    /// Rebuilds the grid over the discs of `pixels` pixels: `disc(pixel)` is the visible
    /// point's `(position, r^2)`, `None` where the pixel has none this iteration. Storage is
    /// reused between iterations; it grows only with the number of pixels.
    pub fn build<F>(&mut self, pixels: usize, disc: F)
    where
        F: Fn(usize) -> Option<(Vec3, f32)> + Sync,
    {
        let (lower, upper, r_max) = (0..pixels)
            .into_par_iter()
            .filter_map(&disc)
            .map(|(p, r2)| {
                let r = r2.sqrt();
                (p - r, p + r, r)
            })
            .reduce(
                || (Vec3::INFINITY, Vec3::NEG_INFINITY, 0.0f32),
                |a, b| (a.0.min(b.0), a.1.max(b.1), a.2.max(b.2)),
            );
        let buckets = pixels.max(1).next_power_of_two();
        let mask = buckets - 1;
        self.lower = lower;
        self.upper = upper;
        self.mask = mask;
        // Cells of edge 2 R_max (a point overlaps at most two cells per axis), never so small
        // that the box spans more cells than an i32 holds.
        let extent = (upper - lower).max_element();
        let edge = (2.0 * r_max).max(extent * 1e-6).max(f32::MIN_POSITIVE);
        self.inv_cell = if r_max > 0.0 { 1.0 / edge } else { 0.0 };
        self.discs.resize(pixels, Vec4::ZERO);
        self.discs
            .par_iter_mut()
            .enumerate()
            .for_each(|(pixel, d)| {
                *d = match disc(pixel) {
                    Some((p, r2)) => p.extend(r2),
                    None => Vec4::new(0.0, 0.0, 0.0, -1.0),
                }
            });
        self.starts.resize_with(buckets + 1, AtomicU32::default);
        self.starts.par_iter_mut().for_each(|s| *s.get_mut() = 0);

        // Pass 1: count the entries of every bucket (starts[b + 1] counts bucket b).
        (0..pixels).into_par_iter().for_each(|pixel| {
            let mut cells = [0usize; MAX_CELLS];
            for &b in self.buckets_of(disc(pixel), &mut cells) {
                self.starts[b + 1].fetch_add(1, Ordering::Relaxed);
            }
        });
        // Prefix sum: starts[b] becomes the first entry of bucket b.
        let mut total = 0u32;
        for s in &mut self.starts {
            total += *s.get_mut();
            *s.get_mut() = total;
        }
        self.entries.resize_with(total as usize, AtomicU32::default);
        // Pass 2: place the entries; starts[b] advances to the end of bucket b, which is
        // starts[b + 1] of pass 1, so afterwards starts[b] is the *end* of bucket b.
        (0..pixels).into_par_iter().for_each(|pixel| {
            let mut cells = [0usize; MAX_CELLS];
            for &b in self.buckets_of(disc(pixel), &mut cells) {
                let slot = self.starts[b].fetch_add(1, Ordering::Relaxed);
                self.entries[slot as usize].store(pixel as u32, Ordering::Relaxed);
            }
        });
        // Shift back: bucket b spans starts[b]..starts[b + 1].
        for b in (1..=buckets).rev() {
            let prev = *self.starts[b - 1].get_mut();
            *self.starts[b].get_mut() = prev;
        }
        *self.starts[0].get_mut() = 0;
    }

    /// The distinct buckets of the cells `point`'s disc overlaps, written into `cells`.
    #[inline]
    fn buckets_of<'c>(
        &self,
        point: Option<(Vec3, f32)>,
        cells: &'c mut [usize; MAX_CELLS],
    ) -> &'c [usize] {
        let Some((p, r2)) = point else {
            return &cells[..0];
        };
        let r = r2.sqrt();
        let lo = cell_of(p - r, self.lower, self.inv_cell);
        let hi = cell_of(p + r, self.lower, self.inv_cell);
        let mut n = 0;
        for x in lo[0]..=hi[0] {
            for y in lo[1]..=hi[1] {
                for z in lo[2]..=hi[2] {
                    let b = bucket_of([x, y, z], self.mask);
                    // Two cells may hash to one bucket: insert the point once, or a photon
                    // would be splatted into it twice.
                    if n < MAX_CELLS && !cells[..n].contains(&b) {
                        cells[n] = b;
                        n += 1;
                    }
                }
            }
        }
        &cells[..n]
    }

    /// The bucket of `p`'s cell; `None` outside the box of all discs (no disc contains `p`).
    #[inline]
    pub fn bucket(&self, p: Vec3) -> Option<usize> {
        let inside =
            !self.starts.is_empty() && p.cmpge(self.lower).all() && p.cmple(self.upper).all();
        inside.then(|| bucket_of(cell_of(p, self.lower, self.inv_cell), self.mask))
    }

    /// Starts loading where `bucket`'s entries begin and end.
    #[inline]
    pub fn prefetch_bucket(&self, bucket: Option<usize>) {
        if let Some(b) = bucket {
            prefetch(&self.starts[b]);
            prefetch(&self.starts[b + 1]);
        }
    }

    /// The range of `bucket`'s entries.
    #[inline]
    fn range(&self, bucket: Option<usize>) -> std::ops::Range<usize> {
        match bucket {
            Some(b) => {
                self.starts[b].load(Ordering::Relaxed) as usize
                    ..self.starts[b + 1].load(Ordering::Relaxed) as usize
            }
            None => 0..0,
        }
    }

    /// Starts loading `bucket`'s entries (the bucket's start should be in cache:
    /// [`Self::prefetch_bucket`]).
    #[inline]
    pub fn prefetch_entries(&self, bucket: Option<usize>) {
        let entries = &self.entries[self.range(bucket)];
        // One prefetch per cache line (16 entries of 4 bytes), and the last entry's line.
        for e in entries.iter().step_by(16).chain(entries.last()) {
            prefetch(e);
        }
    }

    /// The pixels of `bucket`: those whose disc may contain a point of the bucket's cells (a
    /// superset: see [`Self::contains`]).
    #[inline]
    pub fn candidates_in(&self, bucket: Option<usize>) -> impl Iterator<Item = usize> + '_ {
        self.entries[self.range(bucket)]
            .iter()
            .map(|e| e.load(Ordering::Relaxed) as usize)
    }

    /// The pixels whose visible points may have `p` inside their disc (a superset: see
    /// [`Self::contains`]).
    #[cfg(test)]
    pub fn candidates(&self, p: Vec3) -> impl Iterator<Item = usize> + '_ {
        self.candidates_in(self.bucket(p))
    }

    /// Starts loading `pixel`'s disc.
    #[inline]
    pub fn prefetch_disc(&self, pixel: usize) {
        prefetch(&self.discs[pixel]);
    }

    /// True if `pixel`'s disc contains `p` (|x - p| <= R).
    #[inline]
    pub fn contains(&self, pixel: usize, p: Vec3) -> bool {
        let d = self.discs[pixel];
        d.truncate().distance_squared(p) <= d.w
    }

    /// The pixels whose disc contains `p`, each once.
    #[cfg(test)]
    pub fn within(&self, p: Vec3) -> impl Iterator<Item = usize> + '_ {
        self.candidates(p)
            .filter(move |&pixel| self.contains(pixel, p))
    }

    /// Bytes held (bounded by the number of pixels: at most 8 entries, one disc and two
    /// buckets per pixel).
    pub fn memory_bytes(&self) -> usize {
        (self.starts.capacity() + self.entries.capacity()) * std::mem::size_of::<AtomicU32>()
            + self.discs.capacity() * std::mem::size_of::<Vec4>()
    }
}

/// Starts loading the cache line holding `x` (a hint: nothing waits for it). Elsewhere than
/// on x86-64, nothing.
#[inline(always)]
pub(super) fn prefetch<T>(x: &T) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: a prefetch never faults and changes nothing the program can observe; the
    // pointer comes from a reference.
    unsafe {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        _mm_prefetch::<_MM_HINT_T0>((x as *const T).cast::<i8>());
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = x;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    /// Every (photon, visible point) pair within the radius is found exactly once, against a
    /// brute-force scan, for radii of very different sizes.
    #[test]
    fn finds_every_point_within_its_radius_once() {
        let mut rng = Rng::new(7, 0, 0);
        let points: Vec<Option<(Vec3, f32)>> = (0..500)
            .map(|i| {
                if i % 7 == 3 {
                    return None;
                }
                let p = Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * 2.0;
                let r = if i % 5 == 0 {
                    0.3
                } else {
                    0.02 + 0.05 * rng.uniform()
                };
                Some((p, r * r))
            })
            .collect();
        let mut grid = VisiblePointGrid::new();
        grid.build(points.len(), |i| points[i]);
        let mut found = 0;
        for _ in 0..5000 {
            let q = Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * 2.4 - 0.2;
            let mut got: Vec<usize> = grid
                .candidates(q)
                .filter(|&i| points[i].is_some_and(|(p, r2)| p.distance_squared(q) <= r2))
                .collect();
            let n = got.len();
            got.sort_unstable();
            got.dedup();
            assert_eq!(got.len(), n, "a point was listed twice");
            let want: Vec<usize> = (0..points.len())
                .filter(|&i| points[i].is_some_and(|(p, r2)| p.distance_squared(q) <= r2))
                .collect();
            assert_eq!(got, want, "query {q}");
            found += n;
        }
        assert!(found > 1000, "the test must exercise hits: {found}");
        assert!(grid.entries.len() <= MAX_CELLS * points.len());
        // `within` is the same as the candidates with the distance test.
        for _ in 0..500 {
            let q = Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * 2.4 - 0.2;
            let mut got: Vec<usize> = grid.within(q).collect();
            got.sort_unstable();
            let want: Vec<usize> = (0..points.len())
                .filter(|&i| points[i].is_some_and(|(p, r2)| p.distance_squared(q) <= r2))
                .collect();
            assert_eq!(got, want, "query {q}");
        }
    }

    #[test]
    fn empty_and_pointless_grids_find_nothing() {
        let mut grid = VisiblePointGrid::new();
        grid.build(0, |_| None);
        assert_eq!(grid.candidates(Vec3::ZERO).count(), 0);
        grid.build(2, |_| None);
        assert_eq!(grid.candidates(Vec3::ZERO).count(), 0);
        // A single point of radius zero still finds a photon exactly on it.
        grid.build(1, |_| Some((Vec3::ONE, 0.0)));
        assert_eq!(grid.candidates(Vec3::ONE).collect::<Vec<_>>(), [0]);
    }
}
