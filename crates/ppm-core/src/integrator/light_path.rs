//! Light paths that leave photons on non-specular surfaces: the walk
//! the photon passes of `ppm` and `sppm` share, generic over where the photons go
//! ([`PhotonSink`]).

use crate::bsdf::{shading_normal_correction, Bsdf, BsdfFlags, TransportMode};
use crate::geometry::Ray;
use crate::integrator::shading::ShadingFrame;
use crate::integrator::{DirectMode, PhotonSink, RenderSettings};
use crate::light::Light;
use crate::photon::BOUNCE_BITS;
use crate::sampling::Rng;
use crate::scene::Scene;

/// Random streams of light paths are kept apart from the eye paths' by this salt.
pub const PHOTON_STREAM: u64 = 0x7068_6f74_6f6e_7321;

/// Most light paths one iteration can trace (the ordering key, [`crate::photon::Photon::key`], must fit in
/// 32 bits).
pub const MAX_LIGHT_PATHS: u32 = 1 << (32 - BOUNCE_BITS);

/// Rays traced by one worker.
#[derive(Clone, Copy, Debug, Default)]
pub struct PhotonCounters {
    pub rays: u64,
    pub photons: u64,
}

/// True where photons are stored: surfaces whose BSDF has a diffuse part, which the eye pass
/// density-estimates. Never where every lobe is glossy or specular: those lobes are traced
/// (6.4), and photons there would be counted by no estimate.
#[inline]
pub fn stores_photons(bsdf: &Bsdf) -> bool {
    bsdf.flags().contains(BsdfFlags::DIFFUSE)
}

/// Traces light path `path` of iteration `iteration` and deposits its photons in `out`.
///
/// The path starts with a light chosen in proportion to power, a point uniform on it and a
/// cosine-weighted direction, so its flux is Phi = Le cos / (p_light p_area p_dir)
/// ([`Scene::sample_emission`]); the N paths of an iteration together carry the lights' power
/// (the gather divides by N). At every non-specular hit a photon (position, incoming
/// direction, flux) is stored: from the first hit on with `--direct photons`, from the second
/// with `--direct sampled` (the eye pass then samples direct light itself). The path scatters
/// by BSDF sampling in importance mode: flux *= f |cos| / pdf times Veach's shading-normal
/// correction; along each segment the flux is multiplied by the transmittance of the medium
/// it crossed ([`Scene::transmittance`], Beer-Lambert). Russian roulette keeps photons of
/// about equal power: the survival probability is q = min(1, max(flux after) / max(flux
/// before)) (the transmittance of the segment times the reflectivity of the bounce along the
/// sampled direction), and survivors are divided by q.
/// Always inlined into the pass's loop over paths, so that the loop's invariants are derived
/// once and the ray counters stay in registers (docs/performance.md, "Inlining").
#[inline(always)]
pub fn trace_light_path<S: PhotonSink>(
    scene: &Scene,
    settings: &RenderSettings,
    iteration: u64,
    path: u32,
    out: &mut S,
    counters: &mut PhotonCounters,
) {
    let mut rng = Rng::new(settings.seed ^ PHOTON_STREAM, iteration, path as u64);
    let (u_light, u_pos, u_dir) = (rng.uniform(), rng.uniform2(), rng.uniform2());
    let Some(emission) = scene.sample_emission(u_light, u_pos, u_dir) else {
        return;
    };
    let mut flux = emission.flux;
    if flux.max_element() <= 0.0 || !flux.is_finite() {
        return;
    }
    let mut ray = Light::emission_ray(&emission);
    let first_stored_bounce = match settings.direct {
        DirectMode::Photons => 0,
        DirectMode::Sampled => 1,
    };
    for bounce in 0..settings.max_depth {
        counters.rays += 1;
        let Some(hit) = scene.intersect(&ray) else {
            return;
        };
        let bsdf = &scene.bsdf(&hit);
        // The photon arrived along ray.dir: its incoming direction points back along the ray.
        let wo = -ray.dir;
        // The flux leaving the last vertex, before the medium the segment crossed absorbed
        // part of it: Russian roulette below compares with it, so that absorption, like
        // the BSDF, thins photons out instead of dimming them.
        let emitted = flux;
        flux *= scene.transmittance(&hit, wo, hit.t);
        if bounce >= first_stored_bounce && stores_photons(bsdf) {
            out.deposit(hit.p, wo, flux, path, bounce);
            counters.photons += 1;
        }
        let sf = ShadingFrame::new(&hit, wo);
        let (u_lobe, u) = (rng.uniform(), rng.uniform2());
        let Some(s) = bsdf.sample(sf.wo, u_lobe, u, TransportMode::Importance) else {
            return;
        };
        let wi = sf.frame.to_world(s.wi);
        if !sf.consistent(&hit, wo, wi, s.wi) {
            return;
        }
        let correction =
            shading_normal_correction(TransportMode::Importance, wo, wi, hit.ng, sf.frame.z);
        let scattered = flux * s.weight * correction;
        let survive = (scattered.max_element() / emitted.max_element()).min(1.0);
        if survive.is_nan() || rng.uniform() >= survive {
            return;
        }
        flux = scattered / survive;
        ray = Ray::spawn(hit.p, hit.ng, wi);
    }
}
