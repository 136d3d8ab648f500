//! A surface vertex of a subpath and what the estimators ask of its BSDF: the value toward
//! another vertex with its cosine, and the forward and reverse pdfs MIS needs.

use super::mis::SubpathMis;
use crate::bsdf::{shading_normal_correction, Bsdf, TransportMode};
use crate::geometry::Hit;
use crate::integrator::shading::ShadingFrame;
use glam::Vec3;

/// A subpath's vertex on a surface.
#[derive(Clone, Copy, Debug)]
pub(super) struct SurfaceVertex {
    pub hit: Hit,
    pub bsdf: Bsdf,
    /// Unit direction back along the subpath (toward the camera for camera subpaths, toward
    /// the light for light subpaths), world space.
    pub wo: Vec3,
    pub sf: ShadingFrame,
}

/// The BSDF of a vertex evaluated toward a direction.
#[derive(Clone, Copy, Debug)]
pub(super) struct Evaluation {
    /// f(wo, w) |cos(w)| with Veach's shading-normal correction on light subpaths.
    pub f_cos: Vec3,
    /// f(wo, w), without the cosine (for merging's density estimate).
    pub f: Vec3,
    /// |cos| between `w` and the shading normal.
    pub cos: f32,
    /// Solid-angle pdf of sampling `w` given `wo` (the subpath continuing toward `w`).
    pub pdf_forward: f32,
    /// Solid-angle pdf of sampling `wo` given `w` (the other subpath continuing through here).
    pub pdf_reverse: f32,
}

impl SurfaceVertex {
    /// The vertex at `hit` reached along `-wo`.
    #[inline]
    pub fn new(hit: Hit, bsdf: Bsdf, wo: Vec3) -> Self {
        SurfaceVertex {
            hit,
            bsdf,
            wo,
            sf: ShadingFrame::new(&hit, wo),
        }
    }

    /// The BSDF toward the unit world direction `w` in transport `mode`; `None` when `w`
    /// leaves on the geometric side that contradicts its local side (it would leak through the
    /// surface) or the BSDF is zero there. Delta lobes evaluate to zero (they are never
    /// connected or merged).
    #[inline]
    pub fn eval(&self, w: Vec3, mode: TransportMode) -> Option<Evaluation> {
        let local = self.sf.frame.to_local(w);
        if !self.sf.consistent(&self.hit, self.wo, w, local) {
            return None;
        }
        let f = self.bsdf.eval(self.sf.wo, local, mode);
        if f == Vec3::ZERO {
            return None;
        }
        let cos = local.z.abs();
        let correction = shading_normal_correction(mode, self.wo, w, self.hit.ng, self.sf.frame.z);
        Some(Evaluation {
            f_cos: f * (cos * correction),
            f,
            cos,
            pdf_forward: self.bsdf.pdf(self.sf.wo, local),
            pdf_reverse: self.bsdf.pdf(local, self.sf.wo),
        })
    }

    /// |cos| of `wo` with the shading normal.
    #[inline]
    pub fn cos_wo(&self) -> f32 {
        self.sf.wo.z.abs()
    }
}

/// A stored light-subpath vertex (non-delta surfaces only), for connections and merging.
#[derive(Clone, Copy, Debug)]
pub(super) struct LightVertex {
    pub vertex: SurfaceVertex,
    /// The light subpath's throughput arriving here: Le cos / (p_light p_A p_W) times
    /// f |cos| / pdf (and Russian roulette) per bounce: a flux, as a photon's.
    pub throughput: Vec3,
    pub mis: SubpathMis,
    /// Edges from the light to this vertex (1 at the first hit).
    pub edges: u32,
}

/// What merging reads of a light vertex: kept beside the hash grid in its order
/// (`VcmRenderer::merge_vertices`), so that the light vertices a query finds, which lie in
/// the same cells, are read from consecutive memory rather than one by one from the paths'
/// storage (three cache lines each, in path order).
#[derive(Clone, Copy, Debug)]
pub(super) struct MergeVertex {
    /// The light vertex's `wo`: the direction back toward the light.
    pub wo: Vec3,
    pub throughput: Vec3,
    pub mis: SubpathMis,
    pub edges: u32,
}

impl MergeVertex {
    /// The part of `y` merging reads.
    #[inline]
    pub fn of(y: &LightVertex) -> Self {
        MergeVertex {
            wo: y.vertex.wo,
            throughput: y.throughput,
            mis: y.mis,
            edges: y.edges,
        }
    }
}
