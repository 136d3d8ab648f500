//! Photons: the compact record, the lock-free append buffer, the hash grid and the kernel.
//!
//! One photon-mapping iteration uses them in this order:
//!
//! 1. rayon workers trace light paths and push photons through [`PhotonWriter`]s into a
//!    [`PhotonBuffer`] (allocated once, cleared every iteration, grown and redone on overflow);
//! 2. [`HashGrid::build`] sorts that iteration's photons into hashed cells of side `2 r`, in
//!    an order independent of thread scheduling;
//! 3. each gather point calls [`HashGrid::for_each_in_radius`] and weights photons with the
//!    normalised [`Kernel`].

mod buffer;
mod grid;
mod kernel;
mod record;

pub use buffer::{PhotonBuffer, PhotonWriter, BATCH};
pub use grid::HashGrid;
pub use kernel::{epanechnikov, Kernel};
pub use record::{FluxRecord, Photon};
