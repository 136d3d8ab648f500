//! The render state a render needs to continue exactly where it stopped, or to be joined with
//! renders of other iterations: what `--resume`, `--shard` and `ppm merge` save and read.
//!
//! Each integrator owns what it saves ([`super::Integrator::snapshot`] and
//! [`super::Integrator::from_snapshot`]; by default the film, [`super::RenderStart::resumed`]):
//! - the path tracer and progressive photon mapping save the film only: every iteration is an
//!   independent estimate given (seed, iteration), and the photon-mapping radius of iteration
//!   i is a function of i alone ([`super::RadiusSchedule::at_iteration`]). Their snapshots
//!   of consecutive slices of iterations join exactly ([`Snapshot::append`]);
//! - an integrator that carries per-pixel statistics from one iteration to the next
//!   (stochastic PPM: each pixel's radius, photon count and unnormalised flux) saves them as
//!   [`PixelChannel`]s. Such a state can be resumed, but slices cannot be merged: iteration
//!   k's statistics depend on every iteration before it, so a slice that starts at k > 0
//!   without them is not a slice of the same render.

use crate::film::Film;
use crate::integrator::Algorithm;
use crate::StateError;

/// One value per pixel (row-major) that an integrator carries between iterations, stored as
/// u32 words (an f32 is saved by its bits).
#[derive(Clone, Debug, PartialEq)]
pub struct PixelChannel {
    /// A short name, unique within the snapshot (e.g. `radius2`).
    pub name: String,
    pub values: Vec<u32>,
}

/// The state of a render after its last finished iteration.
#[derive(Clone, Debug, PartialEq)]
pub struct Snapshot {
    /// Exact sums of the iterations `film.first_iteration()..film.next_iteration()`.
    pub film: Film,
    /// Per-pixel state beyond the film (empty for the path tracer and PPM).
    pub pixels: Vec<PixelChannel>,
}

impl Snapshot {
    /// The state before the first of the iterations `first_iteration..`: an empty film, no
    /// per-pixel state. A shard of a render starts here.
    pub fn starting_at(width: u32, height: u32, first_iteration: u64) -> Self {
        Snapshot {
            film: Film::starting_at(width, height, first_iteration),
            pixels: Vec::new(),
        }
    }

    /// Joins the snapshot of the iterations that follow this one's: the result equals, bit for
    /// bit, the snapshot of one render of both slices. Refused when either carries per-pixel
    /// state (see the module documentation) or when the slices do not follow each other.
    pub fn append(&mut self, later: &Snapshot) -> Result<(), StateError> {
        if !self.pixels.is_empty() || !later.pixels.is_empty() {
            return Err(StateError::Unsupported(
                "this algorithm carries per-pixel state from one iteration to the next: \
                 its renders can be resumed but slices of them cannot be merged"
                    .into(),
            ));
        }
        self.film.append(&later.film)
    }

    /// Bytes of the snapshot of a `width` x `height` render by `algorithm`
    /// ([`crate::integrator::Renderer::snapshot`]): the film's exact sums and the per-pixel
    /// channels ([`super::Features::snapshot_channels`]: SPPM's statistics). A render's end
    /// holds it beside the renderer, and writing it copies it once more, so the memory check
    /// counts it before the render starts.
    pub fn estimate_bytes(width: u32, height: u32, algorithm: Algorithm) -> u64 {
        let channels = algorithm.features().snapshot_channels;
        let per_pixel = std::mem::size_of::<[u128; 3]>() + channels * std::mem::size_of::<u32>();
        (width as u64 * height as u64).saturating_mul(per_pixel as u64)
    }

    /// Bytes held: the film's sums and the per-pixel channels.
    pub fn memory_bytes(&self) -> usize {
        self.film.memory_bytes()
            + self
                .pixels
                .iter()
                .map(|c| c.values.len() * std::mem::size_of::<u32>())
                .sum::<usize>()
    }

    /// The state of an integrator that carries nothing but its film between iterations (the
    /// path tracer, PPM and VCM).
    pub(crate) fn of_film(film: &Film) -> Self {
        Snapshot {
            film: film.clone(),
            pixels: Vec::new(),
        }
    }

    /// The film of a snapshot that fits a `width` x `height` render with no per-pixel state
    /// (what [`Snapshot::of_film`] saves); an error otherwise.
    pub(crate) fn into_film(self, width: u32, height: u32) -> Result<Film, StateError> {
        self.check_size(width, height)?;
        if let Some(c) = self.pixels.first() {
            return Err(StateError::Unsupported(format!(
                "the saved state has a per-pixel channel '{}' this algorithm does not use \
                 (was it saved by another algorithm?)",
                c.name
            )));
        }
        Ok(self.film)
    }

    /// Checks the film is `width` x `height`.
    pub fn check_size(&self, width: u32, height: u32) -> Result<(), StateError> {
        if (self.film.width, self.film.height) != (width, height) {
            return Err(StateError::Size {
                saved_width: self.film.width,
                saved_height: self.film.height,
                width,
                height,
            });
        }
        Ok(())
    }
}
