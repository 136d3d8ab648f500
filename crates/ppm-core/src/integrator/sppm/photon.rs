//! The photon SPPM keeps between its light paths and its gather: what the density estimate
//! at a visible point reads, exactly as the light path left it.

use crate::integrator::PhotonSink;
use crate::photon::{PhotonRecord, PhotonWriter};
use glam::Vec3;

/// A photon of the current batch of light paths ([`super::photon_grid`]).
///
/// Unlike ppm's 32-byte [`crate::photon::Photon`], the incoming direction is kept as three
/// `f32` (not octahedral-encoded) and the bounce in full: the estimate weighs each photon by
/// [`crate::photon::GatherNormals::weight`] of this exact direction, so the order in which
/// photons meet visible points (splat or gather) cannot change a single bit of a sum.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SppmPhoton {
    /// Where the photon landed (world space).
    pub position: Vec3,
    /// Unit direction it arrived from, pointing away from the surface.
    pub wi: Vec3,
    /// Flux Phi_p it carries (importance transport, RGB).
    pub flux: Vec3,
    /// Its bounce: 0 at the first surface the light reached.
    pub bounce: u32,
}

impl PhotonRecord for SppmPhoton {
    const ZERO: SppmPhoton = SppmPhoton {
        position: Vec3::ZERO,
        wi: Vec3::ZERO,
        flux: Vec3::ZERO,
        bounce: 0,
    };
}

impl PhotonSink for PhotonWriter<'_, SppmPhoton> {
    #[inline]
    fn deposit(&mut self, position: Vec3, wi: Vec3, flux: Vec3, _path: u32, bounce: u32) {
        self.push(SppmPhoton {
            position,
            wi,
            flux,
            bounce,
        });
    }
}
