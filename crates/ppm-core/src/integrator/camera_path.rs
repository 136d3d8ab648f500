//! Where a camera path starts, what it carries from vertex to vertex, and its BSDF-sampled
//! continuation.

use super::direct::emission_mis_weight;
use super::shading::ShadingFrame;
use super::LightStrategy;
use crate::bsdf::{Bsdf, Lobe, TransportMode};
use crate::geometry::{Hit, Ray};
use crate::sampling::{power_heuristic, Rng};
use crate::scene::Scene;
use glam::{Vec2, Vec3};

/// The start of pixel `pixel`'s camera path in `iteration` (pixels row-major, `width` to a
/// row): the path's random stream and its first ray.
///
/// The stream is keyed by (`seed`, `iteration`, `pixel`), never by thread, so the image is
/// the same at any thread count; each camera pass passes its own salted `seed`, which keeps
/// its stream apart from the others'. The ray goes through a film position drawn uniformly in
/// the pixel's square [x, x+1) x [y, y+1), pdf 1 per unit pixel area: the pixel estimates the
/// mean radiance over its area (a box filter), and the sample weight is 1. A thin lens then
/// draws the ray's lens point from the same stream ([`crate::camera::Camera::sample_ray`]);
/// the lens's importance over its density is 1 too (the lens module's docs).
/// Always inlined: it opens the per-pixel loop of every camera pass.
#[inline(always)]
pub fn start_pixel_path(
    scene: &Scene,
    seed: u64,
    iteration: u64,
    pixel: usize,
    width: usize,
) -> (Rng, Ray) {
    let mut rng = Rng::new(seed, iteration, pixel as u64);
    let film = Vec2::new((pixel % width) as f32, (pixel / width) as f32) + rng.uniform2();
    let ray = scene.camera.sample_ray(film, &mut rng);
    (rng, ray)
}

/// The throughput of a camera path and what MIS needs to know of its previous vertex.
#[derive(Clone, Copy, Debug)]
pub struct CameraPath {
    /// Product of f |cos| / pdf (and Russian-roulette survival) along the path.
    pub throughput: Vec3,
    /// True at the camera and after a delta bounce: emission found next counts fully.
    pub prev_specular: bool,
    /// Solid-angle pdf of the last BSDF sample, for the MIS weight of emission it finds.
    pub prev_pdf: f32,
    /// The last vertex.
    pub prev_p: Vec3,
    /// The product of eta^2 over the refractions so far ([`refraction_scale`]): Russian
    /// roulette reads the throughput times it.
    pub eta_scale: f32,
}

/// The factor eta^2 by which the radiance-mode weight `radiance` of a transmission sample
/// drawn from `bsdf` (local `wo`, random numbers `u_lobe`, `u`) is smaller than its
/// importance-mode weight: the 1/eta^2 of [`TransportMode::Radiance`] (see `bsdf::Glass`).
/// The same sample drawn again in importance mode (the mode changes only the weight's scale,
/// not the direction), the ratio of the two weights' largest channels; 1 if either is zero.
/// Russian roulette on a camera path multiplies the throughput by the product of these
/// factors (pbrt-v4's etaScale): the radiance carried into a dielectric is divided by eta^2
/// and multiplied back on leaving it, so roulette on the throughput alone would kill paths
/// inside glass with probability 1 - 1/eta^2 (61% at eta 1.6) and the survivors would leave it
/// carrying eta^2 times the radiance: rare bright paths where glass shows a light. Any survival
/// probability keeps the estimator unbiased; this one follows what the path can still bring.
#[inline]
pub fn refraction_scale(bsdf: &Bsdf, wo: Vec3, u_lobe: f32, u: Vec2, radiance: Vec3) -> f32 {
    let Some(importance) = bsdf.sample(wo, u_lobe, u, TransportMode::Importance) else {
        return 1.0;
    };
    let (r, i) = (radiance.max_element(), importance.weight.max_element());
    if r > 0.0 && i > 0.0 && r.is_finite() && i.is_finite() {
        i / r
    } else {
        1.0
    }
}

impl CameraPath {
    /// A path leaving the camera at `origin`.
    pub fn new(origin: Vec3) -> Self {
        CameraPath {
            throughput: Vec3::ONE,
            prev_specular: true,
            prev_pdf: 0.0,
            prev_p: origin,
            eta_scale: 1.0,
        }
    }

    /// The emitted radiance the path picks up at `hit` (seen along `wo`), before the
    /// throughput: emission is one-sided (toward the geometric normal) and counts fully at the
    /// camera and after a delta bounce; after a non-specular bounce it is weighted against
    /// light sampling by `strategy` (the power heuristic for MIS, 0 when only light sampling
    /// finds emitters, 1 when only BSDF sampling does).
    /// Always inlined into the walk, as `scatter` is (docs/performance.md, "Inlining").
    #[inline(always)]
    pub fn emission(&self, scene: &Scene, hit: &Hit, wo: Vec3, strategy: LightStrategy) -> Vec3 {
        let material = scene.material(hit);
        if !material.is_emissive() || wo.dot(hit.ng) <= 0.0 {
            return Vec3::ZERO;
        }
        let weight = if self.prev_specular {
            1.0
        } else {
            match strategy {
                LightStrategy::Mis => emission_mis_weight(scene, self.prev_p, self.prev_pdf, hit),
                LightStrategy::LightOnly => 0.0,
                LightStrategy::BsdfOnly => 1.0,
            }
        };
        material.emission * weight
    }

    /// The radiance the path picks up when it leaves the scene along `dir` (unit), before the
    /// throughput: the environment's L(dir) (zero without one), counted fully at the camera
    /// and after a delta bounce; after a non-specular bounce weighted as emission is, the
    /// power heuristic between the BSDF's pdf and the light's p_light p(dir) (Veach 1997,
    /// sec. 9.2; pbrt-v4's `PathIntegrator` on an escaped ray).
    #[inline(always)]
    pub fn escaped(&self, scene: &Scene, dir: Vec3, strategy: LightStrategy) -> Vec3 {
        let Some((light, p_light)) = scene.environment() else {
            return Vec3::ZERO;
        };
        let weight = if self.prev_specular {
            1.0
        } else {
            match strategy {
                LightStrategy::Mis => {
                    power_heuristic(self.prev_pdf, p_light * light.pdf_infinite(dir))
                }
                LightStrategy::LightOnly => 0.0,
                LightStrategy::BsdfOnly => 1.0,
            }
        };
        light.le_infinite(dir) * weight
    }

    /// Continues the path at `hit` by sampling `bsdf` (radiance mode): throughput *= f |cos| /
    /// pdf. Returns the next ray, or `None` when the path ends: no sample, a direction whose
    /// geometric side contradicts its lobe (it would leak through the surface), or Russian
    /// roulette after `rr_depth` bounces, which survives with probability min(1, max channel
    /// of the throughput times `eta_scale`, [`refraction_scale`]) and divides the survivors
    /// by it.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub fn scatter(
        &mut self,
        bsdf: &Bsdf,
        sf: &ShadingFrame,
        hit: &Hit,
        wo: Vec3,
        rng: &mut Rng,
        depth: u32,
        rr_depth: u32,
    ) -> Option<Ray> {
        let (u_lobe, u) = (rng.uniform(), rng.uniform2());
        let s = bsdf.sample(sf.wo, u_lobe, u, TransportMode::Radiance)?;
        let wi = sf.frame.to_world(s.wi);
        if !sf.consistent(hit, wo, wi, s.wi) {
            return None;
        }
        if s.wi.z * sf.wo.z < 0.0 {
            self.eta_scale *= refraction_scale(bsdf, sf.wo, u_lobe, u, s.weight);
        }
        self.throughput *= s.weight;
        self.prev_specular = s.lobe == Lobe::Specular;
        self.prev_pdf = s.pdf;
        self.prev_p = hit.p;
        if depth + 1 >= rr_depth {
            let survive = (self.throughput * self.eta_scale).max_element().min(1.0);
            if survive.is_nan() || rng.uniform() >= survive {
                return None;
            }
            self.throughput /= survive;
        }
        Some(Ray::spawn(hit.p, hit.ng, wi))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A hit on a glass surface at the origin with normal +z, seen from above.
    fn glass_hit() -> Hit {
        Hit {
            t: 1.0,
            p: Vec3::ZERO,
            ng: Vec3::Z,
            ns: Vec3::Z,
            uv: Vec2::ZERO,
            material: 0,
            prim: 0,
        }
    }

    /// Scatters `n` camera paths of throughput 1 at a glass surface (index 1.6) from the side
    /// `from` (+z outside, -z inside), past the roulette depth, and returns how many refracted
    /// and how many of those survived, with their mean throughput times eta_scale.
    fn refract_and_roulette(from: f32, n: u64) -> (u32, u32, f32) {
        let hit = glass_hit();
        let bsdf = Bsdf::glass(1.6, Vec3::ONE);
        let wo = Vec3::new(0.3, 0.0, from).normalize();
        let sf = ShadingFrame::new(&hit, wo);
        let (mut refracted, mut survived, mut carried) = (0, 0, 0.0);
        for i in 0..n {
            let mut rng = Rng::new(7, 0, i);
            let mut path = CameraPath::new(Vec3::new(0.0, 0.0, from));
            let ray = path.scatter(&bsdf, &sf, &hit, wo, &mut rng, 5, 3);
            let crossed = path.eta_scale != 1.0;
            refracted += crossed as u32;
            if crossed && ray.is_some() {
                survived += 1;
                carried += (path.throughput * path.eta_scale).x;
            }
        }
        (refracted, survived, carried / survived.max(1) as f32)
    }

    /// Entering glass, the radiance weight is 1/eta^2 (0.39) and eta_scale eta^2 (2.56):
    /// roulette on their product keeps every refracted path (on the throughput alone it kept
    /// 39%, each survivor carrying 2.56 times too much once it left the glass). Leaving,
    /// eta_scale comes back to 1 times the weights' product.
    #[test]
    fn roulette_keeps_paths_that_refract_into_glass() {
        let (refracted, survived, carried) = refract_and_roulette(1.0, 2000);
        assert!(refracted > 1500, "{refracted} of 2000 refracted");
        assert_eq!(survived, refracted, "roulette killed paths entering glass");
        assert!(
            (carried - 1.0).abs() < 1e-5,
            "throughput x eta_scale {carried}"
        );
        let bsdf = Bsdf::glass(1.6, Vec3::ONE);
        let wo = Vec3::new(0.3, 0.0, 1.0).normalize();
        let s = bsdf
            .sample(wo, 0.9, Vec2::ZERO, TransportMode::Radiance)
            .unwrap();
        let scale = refraction_scale(&bsdf, wo, 0.9, Vec2::ZERO, s.weight);
        assert!((scale - 2.56).abs() < 1e-5, "entering: {scale}");
        // The way back: wo inside is the refracted direction itself (pointing away from the
        // surface, below it).
        let inside = s.wi;
        let s2 = bsdf
            .sample(inside, 0.9, Vec2::ZERO, TransportMode::Radiance)
            .unwrap();
        let back = refraction_scale(&bsdf, inside, 0.9, Vec2::ZERO, s2.weight);
        assert!(
            (scale * back - 1.0).abs() < 1e-5,
            "entering then leaving: {}",
            scale * back
        );
    }
}
