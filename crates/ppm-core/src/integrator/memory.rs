//! What a render will allocate, stated by each integrator before it allocates anything.
//!
//! A front end compares [`MemoryEstimate::total`] with the memory it has and refuses a render
//! that cannot fit, instead of letting the allocator abort the process half-way. Each
//! integrator owns its estimate ([`super::Integrator::memory_estimate`]), next to the code
//! that allocates, so a new integrator states its own; [`super::Algorithm::memory_estimate`]
//! and [`super::Renderer::memory_estimate`] dispatch on the algorithm.
//!
//! The estimate counts the render state's large buffers and one copy of the image (what
//! `Renderer::image` returns). It is a lower bound where a buffer grows on demand: the photon
//! buffer starts at [`PHOTONS_PER_PATH`] photons per light path and grows if a scene stores
//! more.

use crate::photon::Photon;
use glam::Vec3;

/// Photon slots allocated per light path at the start of a render (about 3 photons per path in
/// a closed box of albedo 0.7; the buffer grows when an iteration stores more).
pub const PHOTONS_PER_PATH: usize = 4;

/// Which setting a part of the memory grows with, so a refusal can name it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MemoryPart {
    /// Per-pixel buffers: grows with the resolution (width x height).
    Image,
    /// Photon buffer and hash grid: grows with the light paths per iteration.
    Photons,
    /// The `photons` radius's pilot photon map, a fixed size, held during the first
    /// iteration only; a world radius or `footprint` needs none.
    Pilot,
}

/// Bytes of one part of a render's memory.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MemoryItem {
    pub part: MemoryPart,
    pub bytes: u64,
}

/// The memory a render will allocate, part by part.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct MemoryEstimate {
    pub items: Vec<MemoryItem>,
}

impl MemoryEstimate {
    /// All parts together (saturating: an absurd request stays absurd, never wraps).
    pub fn total(&self) -> u64 {
        self.items
            .iter()
            .fold(0u64, |sum, item| sum.saturating_add(item.bytes))
    }

    /// The largest part: the setting to lower first.
    pub fn largest(&self) -> Option<MemoryItem> {
        self.items.iter().copied().max_by_key(|item| item.bytes)
    }

    /// Adds a part.
    pub fn add(&mut self, part: MemoryPart, bytes: u64) {
        self.items.push(MemoryItem { part, bytes });
    }
}

/// Bytes per pixel common to every integrator: the iteration's estimate (f32 RGB), the film's
/// exact fixed-point RGB sum (u128 per channel, see [`crate::film::Film`]) and one f32 RGB
/// image returned by `image()`.
pub const BYTES_PER_PIXEL: u64 =
    (2 * std::mem::size_of::<Vec3>() + 3 * std::mem::size_of::<u128>()) as u64;

/// Bytes per photon slot of photon mapping: the append buffer's photon, the hash grid's
/// sorted copy, its columns (position, flux, direction and bounce, 10 f32), the bucket of each photon
/// (u32) and the bucket table (at most 2 u32 per photon: the bucket count is the photon count
/// rounded up to a power of two).
pub const BYTES_PER_PHOTON: u64 = (2 * std::mem::size_of::<Photon>()
    + 10 * std::mem::size_of::<f32>()
    + std::mem::size_of::<u32>()
    + 2 * std::mem::size_of::<u32>()) as u64;

/// The per-pixel part for a `width` x `height` image.
pub fn image_bytes(width: u32, height: u32) -> u64 {
    (width as u64 * height as u64).saturating_mul(BYTES_PER_PIXEL)
}
