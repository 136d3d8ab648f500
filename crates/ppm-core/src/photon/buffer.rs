//! A fixed-capacity, lock-free append buffer that rayon workers fill with photons.
//!
//! Each worker collects photons in a small [`PhotonWriter`] batch on its stack and flushes the
//! whole batch with a single `fetch_add` on the shared slot counter, then copies the batch
//! into the slots it claimed. There is no mutex and no atomic per photon.
//!
//! The order of photons in the buffer depends on thread scheduling; [`super::HashGrid::build`]
//! restores a deterministic order. When the buffer is full, photons are dropped and counted
//! exactly; the integrator then grows the buffer and redoes the pass, because *which* photons
//! were kept also depends on scheduling.
//!
//! ```
//! use ppm_core::photon::{Photon, PhotonBuffer};
//! use ppm_core::Vec3;
//! use rayon::prelude::*;
//!
//! let mut buffer = PhotonBuffer::with_capacity(1000);
//! loop {
//!     buffer.clear();
//!     (0..600u32).into_par_iter().for_each_init(
//!         || buffer.writer(), // flushed when rayon drops it
//!         |writer, path| {
//!             for bounce in 0..2 {
//!                 let p = Vec3::new(path as f32, bounce as f32, 0.0);
//!                 writer.push(Photon::new(p, Vec3::Z, Vec3::ONE, path));
//!             }
//!         },
//!     );
//!     if !buffer.overflowed() {
//!         break;
//!     }
//!     let needed = buffer.pushed();
//!     buffer.grow(needed); // and redo the pass
//! }
//! assert_eq!(buffer.as_slice().len(), 1200);
//! ```

use super::Photon;
use std::cell::UnsafeCell;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Photons a [`PhotonWriter`] collects before claiming slots in the shared buffer.
pub const BATCH: usize = 64;

/// A record a [`PhotonBuffer`] stores: plain data with a value that fills unused slots.
pub trait PhotonRecord: Copy + Send + Sync {
    /// The value of a slot nothing was written to.
    const ZERO: Self;
}

impl PhotonRecord for Photon {
    const ZERO: Photon = Photon::ZERO;
}

/// A fixed-capacity photon store that many threads append to through `&self`: ppm's
/// [`Photon`]s by default, or another [`PhotonRecord`] (SPPM keeps exact directions).
pub struct PhotonBuffer<T: PhotonRecord = Photon> {
    /// The photon storage, always fully initialised (to [`PhotonRecord::ZERO`] when allocated).
    slots: Box<[UnsafeCell<T>]>,
    /// Slots claimed since the last `clear`, *including* claims beyond the capacity: the
    /// photons stored are `min(claimed, capacity)` and those dropped `claimed - capacity`.
    claimed: AtomicUsize,
}

// SAFETY: the only shared-reference access to `slots` is the write in `push_batch`, and
// `fetch_add` on `claimed` hands every caller a range of slot indices disjoint from all other
// ranges since the last `clear` (an atomic read-modify-write always reads the latest value in
// the counter's modification order). Two threads never write the same slot, and no method
// taking `&self` reads a slot. Reads (`as_slice`) and resets (`clear`, `grow`) take `&mut self`,
// which cannot coexist with a `&self` used by a writer; the end of the borrow (e.g. the end of
// a rayon `join`/`scope`/parallel iterator, which synchronise with the caller) also orders
// every slot write before those reads.
unsafe impl<T: PhotonRecord> Sync for PhotonBuffer<T> {}

impl PhotonBuffer {
    /// An empty buffer with room for `capacity` photons, allocated once.
    pub fn with_capacity(capacity: usize) -> Self {
        Self::of_records(capacity)
    }
}

impl<T: PhotonRecord> PhotonBuffer<T> {
    /// An empty buffer with room for `capacity` records of type `T`, allocated once.
    pub fn of_records(capacity: usize) -> Self {
        PhotonBuffer {
            slots: (0..capacity).map(|_| UnsafeCell::new(T::ZERO)).collect(),
            claimed: AtomicUsize::new(0),
        }
    }

    /// How many photons fit.
    pub fn capacity(&self) -> usize {
        self.slots.len()
    }

    /// Forgets the stored photons, keeping the allocation.
    pub fn clear(&mut self) {
        *self.claimed.get_mut() = 0;
    }

    /// Clears the buffer and makes room for at least `capacity` photons.
    ///
    /// The contents are discarded rather than kept: after an overflow the stored subset
    /// depends on scheduling, so the pass must be redone anyway. Reallocates only if the
    /// buffer is too small. The photon count varies between iterations, so grow with some
    /// headroom (e.g. `pushed() * 5 / 4`) to avoid redoing the next iteration too.
    pub fn grow(&mut self, capacity: usize) {
        self.clear();
        if capacity > self.capacity() {
            self.slots = Box::new([]); // free the old storage before allocating the new
            self.slots = (0..capacity).map(|_| UnsafeCell::new(T::ZERO)).collect();
        }
    }

    /// Photons stored since the last `clear` (a snapshot if writers are still running).
    pub fn len(&self) -> usize {
        self.pushed().min(self.capacity())
    }

    /// Whether no photon is stored.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Photons pushed since the last `clear`, stored or dropped: the capacity a redone pass
    /// needs (assuming the same photons are pushed again).
    pub fn pushed(&self) -> usize {
        self.claimed.load(Ordering::Relaxed)
    }

    /// Photons dropped because the buffer was full.
    pub fn dropped(&self) -> usize {
        self.pushed().saturating_sub(self.capacity())
    }

    /// Whether any photon was dropped since the last `clear`.
    pub fn overflowed(&self) -> bool {
        self.pushed() > self.capacity()
    }

    /// A batching writer for one worker; it flushes when full and when dropped.
    pub fn writer(&self) -> PhotonWriter<'_, T> {
        PhotonWriter {
            buffer: self,
            batch: [T::ZERO; BATCH],
            len: 0,
        }
    }

    /// Appends `photons` with one atomic claim and returns how many were stored; the rest
    /// (the tail of the slice) were dropped because the buffer is full.
    ///
    /// `PhotonWriter` calls this once per batch; prefer it over calling this per photon.
    pub fn push_batch(&self, photons: &[T]) -> usize {
        if photons.is_empty() {
            return 0;
        }
        // Relaxed is enough: the counter only has to hand out disjoint ranges; visibility of
        // the slot writes to the reader comes from the `&mut self` borrow (see `Sync`).
        // (A `usize` cannot realistically wrap: that needs 2^64 photons pushed in one pass.)
        let start = self.claimed.fetch_add(photons.len(), Ordering::Relaxed);
        let stored = self.capacity().saturating_sub(start).min(photons.len());
        if stored > 0 {
            // SAFETY: slots `start..start + stored` are in bounds (`stored <= capacity - start`)
            // and were claimed by this call alone, so no other thread accesses them until the
            // buffer is borrowed mutably. `UnsafeCell<T>` has the layout of `T`.
            unsafe {
                let dst = UnsafeCell::raw_get(self.slots.as_ptr().add(start));
                std::ptr::copy_nonoverlapping(photons.as_ptr(), dst, stored);
            }
        }
        stored
    }

    /// The stored photons, in scheduling-dependent order.
    ///
    /// Takes `&mut self` so that no writer can still be running: the exclusive borrow proves
    /// that every `push_batch` has returned and its writes are visible here.
    pub fn as_slice(&mut self) -> &[T] {
        let len = self.len();
        // SAFETY: `UnsafeCell<T>` is `repr(transparent)` over `T`; every slot is
        // initialised; `&mut self` excludes concurrent writers for the returned lifetime.
        unsafe { std::slice::from_raw_parts(self.slots.as_ptr().cast::<T>(), len) }
    }

    /// Bytes of photon storage.
    pub fn memory_bytes(&self) -> usize {
        self.capacity() * std::mem::size_of::<T>()
    }
}

impl<T: PhotonRecord> std::fmt::Debug for PhotonBuffer<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PhotonBuffer")
            .field("capacity", &self.capacity())
            .field("pushed", &self.pushed())
            .finish()
    }
}

/// A worker's local batch of up to [`BATCH`] photons on its stack, flushed into the shared
/// [`PhotonBuffer`] with one atomic claim when full, on [`PhotonWriter::flush`] and on drop.
pub struct PhotonWriter<'a, T: PhotonRecord = Photon> {
    buffer: &'a PhotonBuffer<T>,
    batch: [T; BATCH],
    len: usize,
}

impl<T: PhotonRecord> PhotonWriter<'_, T> {
    /// Adds one photon (flushing the batch first if it is full).
    #[inline]
    pub fn push(&mut self, photon: T) {
        if self.len == BATCH {
            self.flush();
        }
        self.batch[self.len] = photon;
        self.len += 1;
    }

    /// Moves the batched photons into the buffer; overflow is recorded by the buffer.
    pub fn flush(&mut self) {
        self.buffer.push_batch(&self.batch[..self.len]);
        self.len = 0;
    }
}

impl<T: PhotonRecord> Drop for PhotonWriter<'_, T> {
    fn drop(&mut self) {
        self.flush();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;
    use rayon::prelude::*;

    /// A photon that encodes `(path, bounce)` in its position, so it can be identified.
    fn tagged(path: u32, bounce: u32) -> Photon {
        Photon::new(
            Vec3::new(path as f32, bounce as f32, 0.0),
            Vec3::Z,
            Vec3::ONE,
            path,
        )
    }

    /// Fills `buffer` from a 4-thread pool: path `i` pushes `i % 7` photons.
    fn fill(buffer: &mut PhotonBuffer, paths: u32) -> usize {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(4)
            .build()
            .unwrap();
        buffer.clear();
        pool.install(|| {
            (0..paths)
                .into_par_iter()
                .with_max_len(97) // many small jobs, so writers flush partial batches
                .for_each_init(
                    || buffer.writer(),
                    |writer, path| {
                        for bounce in 0..path % 7 {
                            writer.push(tagged(path, bounce));
                        }
                    },
                );
        });
        (0..paths).map(|p| (p % 7) as usize).sum()
    }

    /// Sorted (path, bounce) tags of the stored photons.
    fn tags(buffer: &mut PhotonBuffer) -> Vec<(u32, u32)> {
        let mut tags: Vec<_> = buffer
            .as_slice()
            .iter()
            .map(|p| {
                assert_eq!(p.position.x as u32, p.path);
                (p.path, p.position.y as u32)
            })
            .collect();
        tags.sort_unstable();
        tags
    }

    #[test]
    fn every_photon_stored_exactly_once() {
        let mut buffer = PhotonBuffer::with_capacity(100_000);
        let total = fill(&mut buffer, 20_000);
        assert!(!buffer.overflowed());
        assert_eq!(
            (buffer.len(), buffer.pushed(), buffer.dropped()),
            (total, total, 0)
        );
        let expected: Vec<_> = (0..20_000u32)
            .flat_map(|path| (0..path % 7).map(move |b| (path, b)))
            .collect();
        assert_eq!(tags(&mut buffer), expected);
    }

    #[test]
    fn overflow_is_detected_and_counted_exactly() {
        let mut buffer = PhotonBuffer::with_capacity(10_007);
        let total = fill(&mut buffer, 20_000);
        assert!(buffer.overflowed());
        assert_eq!(buffer.len(), 10_007);
        assert_eq!(buffer.pushed(), total);
        assert_eq!(buffer.dropped(), total - 10_007);
        // The stored photons are distinct photons that were pushed.
        let stored = tags(&mut buffer);
        assert!(
            stored.windows(2).all(|w| w[0] != w[1]),
            "a photon stored twice"
        );
        assert!(stored
            .iter()
            .all(|&(path, bounce)| path < 20_000 && bounce < path % 7));

        // Growing to the reported need lets the redone pass fit, exactly.
        buffer.grow(buffer.pushed());
        assert!(buffer.is_empty());
        let again = fill(&mut buffer, 20_000);
        assert_eq!(
            (buffer.len(), buffer.dropped(), buffer.capacity()),
            (again, 0, again)
        );
    }

    #[test]
    fn clear_keeps_capacity_and_allocation() {
        let mut buffer = PhotonBuffer::with_capacity(5000);
        fill(&mut buffer, 1000);
        let ptr = buffer.as_slice().as_ptr();
        buffer.clear();
        assert!(buffer.is_empty() && buffer.as_slice().is_empty());
        buffer.grow(100); // smaller: no reallocation
        assert_eq!(buffer.capacity(), 5000);
        fill(&mut buffer, 1000);
        assert_eq!(buffer.as_slice().as_ptr(), ptr);
    }

    #[test]
    fn single_batch_straddling_the_end_is_split() {
        let buffer = PhotonBuffer::with_capacity(5);
        let batch: Vec<_> = (0..3).map(|i| tagged(i, 0)).collect();
        assert_eq!(buffer.push_batch(&batch), 3);
        assert_eq!(buffer.push_batch(&batch), 2);
        assert_eq!(buffer.push_batch(&batch), 0);
        assert_eq!(buffer.push_batch(&[]), 0);
        assert_eq!((buffer.len(), buffer.dropped()), (5, 4));
        let mut buffer = buffer;
        let paths: Vec<_> = buffer.as_slice().iter().map(|p| p.path).collect();
        assert_eq!(paths, [0, 1, 2, 0, 1]);
    }

    #[test]
    fn zero_capacity_drops_everything() {
        let mut buffer = PhotonBuffer::with_capacity(0);
        let n = fill(&mut buffer, 100);
        assert_eq!((buffer.len(), buffer.dropped()), (0, n));
    }
}
