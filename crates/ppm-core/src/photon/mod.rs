//! Photons: the compact record, the lock-free append buffer, the hash grid and the kernel.
//!
//! One photon-mapping iteration uses them in this order:
//!
//! 1. rayon workers trace light paths and push photons through [`PhotonWriter`]s into a
//!    [`PhotonBuffer`] (allocated once, cleared every iteration, grown and redone on overflow);
//! 2. [`HashGrid::build`] sorts that iteration's photons into hashed cells of side `2 r`, in
//!    an order independent of thread scheduling;
//! 3. each gather point asks [`HashGrid::kernel_flux`] for the flux of the photons around it
//!    weighted by the normalised [`Kernel`] ([`HashGrid::for_each_in_radius`] hands out the
//!    photons themselves).

mod buffer;
mod gather;
mod grid;
mod kernel;
mod normals;
mod record;

pub use buffer::{PhotonBuffer, PhotonRecord, PhotonWriter, BATCH};
pub use grid::HashGrid;
pub use kernel::{epanechnikov, Kernel};
pub use normals::GatherNormals;
pub use record::{FluxRecord, Photon, BOUNCE_BITS, MAX_KEY_BOUNCE};
