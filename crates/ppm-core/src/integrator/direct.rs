//! Next-event estimation: direct light at a surface point by sampling a light.

use super::shading::ShadingFrame;
use crate::bsdf::{Bsdf, TransportMode};
use crate::geometry::{Hit, Ray};
use crate::sampling::{power_heuristic, Rng};
use crate::scene::Scene;
use glam::Vec3;

/// One light sample of the direct light reflected toward `wo` at `hit`:
///
/// L_d = f(wo, wi) |cos wi| L_e T / (p_light * p_dir(wi)) * w,
///
/// with T the transmittance of the medium between the point and the light (1 in clear
/// media; [`Scene::transmittance_to`]), the light chosen in proportion to power (p_light), the point sampled uniformly by
/// area and converted to solid angle (p_dir = d^2 / (A cos_l)), and `w` the power-heuristic
/// weight against BSDF sampling when `mis` is set (1 for point lights, which BSDF sampling
/// cannot find). Returns the contribution (before the path throughput) and whether a shadow
/// ray was traced.
#[inline]
pub fn estimate_direct(
    scene: &Scene,
    hit: &Hit,
    sf: &ShadingFrame,
    wo: Vec3,
    bsdf: &Bsdf,
    rng: &mut Rng,
    mis: bool,
) -> (Vec3, bool) {
    let u_light = rng.uniform();
    let u = rng.uniform2();
    let Some((light, p_light)) = scene.choose_light(u_light) else {
        return (Vec3::ZERO, false);
    };
    let Some(ls) = light.sample_direct(hit.p, u) else {
        return (Vec3::ZERO, false);
    };
    let wi_local = sf.frame.to_local(ls.wi);
    if !sf.consistent(hit, wo, ls.wi, wi_local) {
        return (Vec3::ZERO, false);
    }
    let f = bsdf.eval(sf.wo, wi_local, TransportMode::Radiance);
    if f == Vec3::ZERO {
        return (Vec3::ZERO, false);
    }
    let shadow = Ray::spawn_to(hit.p, hit.ng, ls.p, ls.n);
    if scene.occluded(&shadow) {
        return (Vec3::ZERO, true);
    }
    let pdf_light = p_light * ls.pdf;
    let weight = if mis && !ls.is_delta {
        power_heuristic(pdf_light, bsdf.pdf(sf.wo, wi_local))
    } else {
        1.0
    };
    // The unoccluded segment lies in one medium: Beer-Lambert over its length (the MIS
    // weight is unaffected, nothing is sampled in the medium).
    let li = ls.li * scene.transmittance_to(hit, ls.p);
    (f * wi_local.z.abs() * li * (weight / pdf_light), true)
}

/// MIS weight of emission found by BSDF sampling from `prev_p` with solid-angle pdf
/// `bsdf_pdf`, hitting the emissive primitive of `hit`: the power heuristic against the pdf
/// with which [`estimate_direct`] would have sampled the same point.
#[inline]
pub fn emission_mis_weight(scene: &Scene, prev_p: Vec3, bsdf_pdf: f32, hit: &Hit) -> f32 {
    match scene.light_of_prim(hit.prim) {
        Some((light, p_light)) => {
            power_heuristic(bsdf_pdf, p_light * light.pdf_direct(prev_p, hit.p, hit.ng))
        }
        None => 1.0,
    }
}
