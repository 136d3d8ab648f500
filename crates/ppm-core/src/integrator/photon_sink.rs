//! Where a light path's photons go: the one interface between the light-path walk
//! ([`super::trace_light_path`]) and the passes that use it.

use crate::photon::{Photon, PhotonWriter};
use glam::Vec3;

/// Where a light path's photons go: a photon buffer of [`crate::photon::Photon`]s (`ppm`) or
/// of exact records, one batch of light paths at a time (`sppm`). Generic, so
/// the light-path walk is written once and dispatched statically.
pub trait PhotonSink {
    /// A photon at `position` that arrived from `wi` (unit, pointing away from the surface)
    /// carrying `flux`, left by light path `path` at its hit number `bounce + 1` (bounce 0: the
    /// first surface the light reached). The bounce bounds the camera vertices that may
    /// gather it: no path may have more than max_depth bounces (see [`super::density_estimate`]).
    fn deposit(&mut self, position: Vec3, wi: Vec3, flux: Vec3, path: u32, bounce: u32);
}

impl PhotonSink for PhotonWriter<'_> {
    #[inline]
    fn deposit(&mut self, position: Vec3, wi: Vec3, flux: Vec3, path: u32, bounce: u32) {
        self.push(Photon::new(position, wi, flux, Photon::key(path, bounce)));
    }
}
