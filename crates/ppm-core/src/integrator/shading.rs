//! The local shading frame at a hit, shared by every tracer.

use crate::geometry::Hit;
use crate::photon::GatherNormals;
use crate::sampling::Frame;
use glam::Vec3;

/// The shading frame at a hit as seen from `wo` (world space, pointing away from the surface).
///
/// The frame's z axis is the shading normal, which lies on the geometric normal's side. If
/// the shading and geometric normals disagree about which side `wo` is on (interpolated
/// normals near a silhouette), the geometric frame is used instead, so that the side a BSDF
/// sees (outside/inside for glass, front/back for the others) is always the geometric one.
#[derive(Clone, Copy, Debug)]
pub struct ShadingFrame {
    pub frame: Frame,
    /// `wo` in the local frame.
    pub wo: Vec3,
}

impl ShadingFrame {
    /// The frame at `hit` for outgoing direction `wo`.
    #[inline]
    pub fn new(hit: &Hit, wo: Vec3) -> Self {
        let frame = Frame::new(hit.ns);
        let wo_local = frame.to_local(wo);
        if wo_local.z * wo.dot(hit.ng) > 0.0 {
            ShadingFrame {
                frame,
                wo: wo_local,
            }
        } else {
            let frame = Frame::new(hit.ng);
            ShadingFrame {
                frame,
                wo: frame.to_local(wo),
            }
        }
    }

    /// True if the world-space direction `wi` leaves on the geometric side that the local
    /// direction `wi_local` claims (same side as `wo` for reflection, the other for
    /// transmission). Directions that disagree would leak light through the surface.
    #[inline]
    pub fn consistent(&self, hit: &Hit, wo: Vec3, wi: Vec3, wi_local: Vec3) -> bool {
        let reflect_local = wi_local.z * self.wo.z > 0.0;
        let reflect_geometric = wi.dot(hit.ng) * wo.dot(hit.ng) > 0.0;
        reflect_local == reflect_geometric
    }

    /// The normals a density estimate at this hit weighs photons with
    /// ([`GatherNormals::weight`]): the geometric normal and this frame's shading normal,
    /// each turned toward `wo`. Flat when the frame is the geometric one.
    #[inline]
    pub fn gather_normals(&self, hit: &Hit, wo: Vec3) -> GatherNormals {
        let geometric = if wo.dot(hit.ng) >= 0.0 {
            hit.ng
        } else {
            -hit.ng
        };
        let shading = if self.wo.z >= 0.0 {
            self.frame.z
        } else {
            -self.frame.z
        };
        GatherNormals { geometric, shading }
    }
}
