//! What the user asked for: the render settings, separate from the scene and the render state.

use crate::scene::Scene;

/// Which integrator renders the image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Algorithm {
    /// Unidirectional path tracing with next-event estimation and MIS (`-a pt`).
    Path,
    /// Progressive photon mapping (`-a ppm`, the default).
    Ppm,
}

/// How the path tracer finds light at non-specular vertices (all three converge to the same
/// image; only MIS is meant for production, the others exist to cross-check it).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LightStrategy {
    /// Light sampling and BSDF sampling combined by the power heuristic.
    Mis,
    /// Light sampling only (emission found by BSDF sampling is ignored after the first vertex).
    LightOnly,
    /// BSDF sampling only (no shadow rays; point lights are then invisible).
    BsdfOnly,
}

/// How photon mapping computes direct light at diffuse gather points.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DirectMode {
    /// Photons of every bounce are stored and density-estimated (the assignment's method).
    Photons,
    /// Direct light by light sampling at the gather point; photons are stored from their
    /// second bounce on.
    Sampled,
}

/// Everything the user can set for one render.
#[derive(Clone, Debug)]
pub struct RenderSettings {
    pub algorithm: Algorithm,
    /// Seed of every random stream.
    pub seed: u64,
    /// Longest eye or light path, in bounces.
    pub max_depth: u32,
    /// Russian roulette starts after this many bounces.
    pub rr_depth: u32,
    /// Path tracer: how light is found.
    pub light_strategy: LightStrategy,
    /// Photon mapping: light paths per iteration.
    pub photons: u32,
    /// Photon mapping: initial gather radius (scene units).
    pub radius: f32,
    /// Photon mapping: radius reduction r_{i+1}^2 = r_i^2 (i + alpha) / (i + 1).
    pub alpha: f32,
    /// Photon mapping: direct light from photons or from light sampling.
    pub direct: DirectMode,
}

impl RenderSettings {
    /// Defaults, taking what the scene file says where it says anything. Without a radius in
    /// the scene the initial radius is 0.25% of the scene's diagonal (about 1.4 mm... 1 cm in a
    /// 2-unit Cornell box, a few pixels wide at 512x512).
    pub fn new(scene: &Scene) -> Self {
        let d = scene.defaults;
        RenderSettings {
            algorithm: Algorithm::Ppm,
            seed: 0,
            max_depth: d.max_depth,
            rr_depth: 3,
            light_strategy: LightStrategy::Mis,
            photons: d.photons,
            radius: d.radius.unwrap_or(0.005 * scene.diagonal()),
            alpha: d.alpha,
            direct: DirectMode::Photons,
        }
    }
}
