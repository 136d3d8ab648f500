//! The light subpaths of VCM: traced from the lights, their non-delta vertices stored for
//! connections and merging, and each of those connected to the camera (light tracing).

use super::mis::{light_tracing_weight, MisConstants, SubpathMis};
use super::vertex::{LightVertex, SurfaceVertex};
use crate::bsdf::{shading_normal_correction, Lobe, TransportMode};
use crate::geometry::Ray;
use crate::integrator::camera_walk::RayCounters;
use crate::light::Light;
use crate::pixel_bounds::PixelBounds;
use crate::sampling::Rng;
use crate::scene::Scene;
use glam::Vec3;

/// Random streams of VCM's light subpaths, apart from every other pass's.
pub(super) const LIGHT_STREAM: u64 = 0x7663_6d5f_6c69_6768;

/// A light-tracing contribution to the pixel `pixel` (row-major index within the render's
/// bounds): the pass collects them in path order and sums them exactly.
#[derive(Clone, Copy, Debug)]
pub(super) struct Splat {
    pub pixel: u32,
    pub value: Vec3,
}

/// What a light subpath needs besides the scene.
#[derive(Clone, Copy, Debug)]
pub(super) struct LightPathParams {
    pub seed: u64,
    pub iteration: u64,
    /// Most edges of a full path (max_depth + 1).
    pub max_edges: u32,
    pub mis: MisConstants,
    pub bounds: PixelBounds,
}

/// Traces light subpath `path`: appends its stored vertices to `vertices` (if the technique
/// set connects or merges) and its connections to the camera to `splats` (if it traces light).
///
/// The subpath starts as the photon pass's does (a light chosen in proportion to power, a
/// point uniform on it, a cosine-weighted direction; a uniform one for point lights): the
/// throughput Le cos / (p_light p_A p_W), times the transmittance of each segment's medium
/// ([`Scene::transmittance`]; absorption is not sampled, so no pdf and no MIS weight
/// changes). At each hit the MIS quantities are completed
/// ([`SubpathMis::arrive`]); at a vertex with a non-delta lobe the vertex is stored and
/// connected to the camera; the subpath then scatters by BSDF sampling in importance mode
/// (throughput *= f |cos| / pdf times Veach's shading-normal correction), with Russian
/// roulette as the photon pass (survival min(1, max(throughput after) / max(throughput
/// before))). A vertex with l edges can end full paths of l + 1 edges (to the camera), so the
/// subpath stops when that would exceed `max_edges`.
#[allow(clippy::too_many_arguments)]
pub(super) fn trace_light_subpath(
    scene: &Scene,
    params: &LightPathParams,
    path: u32,
    vertices: &mut Vec<LightVertex>,
    splats: &mut Vec<Splat>,
    counters: &mut RayCounters,
) {
    let c = &params.mis;
    let mut rng = Rng::new(params.seed ^ LIGHT_STREAM, params.iteration, path as u64);
    let (u_light, u_pos, u_dir) = (rng.uniform(), rng.uniform2(), rng.uniform2());
    let Some((light, p_light)) = scene.choose_light(u_light) else {
        return;
    };
    let emission = light.sample_emission(u_pos, u_dir);
    let mut throughput = emission.flux / p_light;
    if !(throughput.is_finite() && throughput.max_element() > 0.0 && emission.pdf_dir > 0.0) {
        return;
    }
    let delta = light.is_delta();
    let cos_light = if delta {
        1.0
    } else {
        emission.n.dot(emission.dir)
    };
    // A light at infinity (directional, environment) starts the sums from its disk's density
    // and its first edge has no distance term (`SubpathMis::light_start_at_infinity`).
    let at_infinity = light.kind().is_infinite();
    let mut state = if at_infinity {
        SubpathMis::light_start_at_infinity(emission.pdf_pos, p_light * emission.pdf_dir, delta, c)
    } else {
        SubpathMis::light_start(
            p_light * emission.pdf_pos,
            emission.pdf_dir,
            cos_light,
            delta,
            c,
        )
    };
    let mut ray = Light::emission_ray(&emission);
    let mut edges = 0;
    loop {
        // The next vertex (edges + 1) ends full paths of edges + 2 edges at the camera.
        if edges + 2 > params.max_edges {
            return;
        }
        counters.rays += 1;
        let Some(hit) = scene.intersect(&ray) else {
            return;
        };
        edges += 1;
        // Beer-Lambert along the segment (1 in clear media); as in the photon pass, Russian
        // roulette below compares with the throughput before it.
        let emitted = throughput;
        throughput *= scene.transmittance(&hit, -ray.dir, hit.t);
        let bsdf = scene.bsdf(&hit);
        let v = SurfaceVertex::new(hit, bsdf, -ray.dir);
        let dist2 = if at_infinity && edges == 1 {
            1.0
        } else {
            hit.t * hit.t
        };
        if !state.arrive(dist2, v.cos_wo()) {
            return;
        }
        if !bsdf.is_delta() {
            let stored = LightVertex {
                vertex: v,
                throughput,
                mis: state,
                edges,
            };
            if c.techniques.stores_light_vertices() {
                vertices.push(stored);
            }
            if c.techniques.light_tracing() {
                connect_to_camera(scene, params, &stored, &mut rng, splats, counters);
            }
        }
        let (u_lobe, u) = (rng.uniform(), rng.uniform2());
        let Some(s) = bsdf.sample(v.sf.wo, u_lobe, u, TransportMode::Importance) else {
            return;
        };
        let wi = v.sf.frame.to_world(s.wi);
        if !v.sf.consistent(&hit, v.wo, wi, s.wi) {
            return;
        }
        let specular = s.lobe == Lobe::Specular;
        let pdf_reverse = if specular {
            s.pdf
        } else {
            bsdf.pdf(s.wi, v.sf.wo)
        };
        state.scatter(specular, s.wi.z.abs(), s.pdf, pdf_reverse, c);
        let correction =
            shading_normal_correction(TransportMode::Importance, v.wo, wi, hit.ng, v.sf.frame.z);
        let scattered = throughput * s.weight * correction;
        let survive = (scattered.max_element() / emitted.max_element()).min(1.0);
        if survive.is_nan() || rng.uniform() >= survive {
            return;
        }
        throughput = scattered / survive;
        ray = Ray::spawn(hit.p, hit.ng, wi);
    }
}

/// Light tracing: the vertex `y` connected to the pinhole (TR eqs. 46-47; the camera is the
/// last vertex, so the camera subpath's partial weight is 0).
///
/// The pixel j that the direction to the camera falls in receives, from each of the N_light
/// light subpaths, T f(y; wo -> camera) |cos_y| / d^2 p_cam(theta) / N_light, where
/// p_cam = d_img^2 / cos^3 theta is the per-pixel solid-angle density of the camera's rays
/// ([`crate::camera::Camera::pixel_direction_pdf`]): the pixel's measurement is the mean of
/// the radiance over its unit area on the image plane at d_img pixels from the pinhole, and
/// changing variables from image area to the solid angle at the pinhole and then to area at
/// y gives the importance W = p_cam |cos_y| / d^2 per unit area at y. MIS: the camera subpath
/// would find y with area pdf p_cam |cos_y| / d^2 out of N_light tries (one per light path,
/// the count of the light-tracing technique), so
/// w_light = mis(p_cam |cos_y| / (d^2 N_light)) (mis(eta_VCM) + dVCM + dVC mis(p_rev)) with
/// p_rev the pdf at y of the direction back to the light given the camera's.
///
/// A thin lens: the camera vertex is a point x_lens drawn uniformly on the lens from `rng`
/// (area density 1 / A_lens), the pixel is the one whose lens ray from x_lens passes through y,
/// and the importance W_e = 1 / (A_lens A cos^4 theta) divided by that density leaves the same
/// per-pixel factor p_cam / d^2, with theta and d measured from x_lens (crate::camera's lens
/// module). The camera subpath draws its lens point with the same density, so the MIS weight
/// is the pinhole's formula at x_lens. A pinhole draws nothing from `rng`.
#[inline]
fn connect_to_camera(
    scene: &Scene,
    params: &LightPathParams,
    y: &LightVertex,
    rng: &mut Rng,
    splats: &mut Vec<Splat>,
    counters: &mut RayCounters,
) {
    let camera = &scene.camera;
    let p = y.vertex.hit.p;
    let (lens, film) = if camera.is_pinhole() {
        (camera.position, camera.raster_position(p))
    } else {
        let lens = camera.lens_point(rng.uniform2());
        (lens, camera.lens_raster_position(lens, p))
    };
    let Some(film) = film else {
        return;
    };
    let (px, py) = (film.x as u32, film.y as u32);
    let b = &params.bounds;
    if px < b.x0 || px >= b.x1 || py < b.y0 || py >= b.y1 {
        return;
    }
    let to_camera = lens - p;
    let dist2 = to_camera.length_squared();
    let dist = dist2.sqrt();
    let w = to_camera / dist;
    let cos_camera = -w.dot(camera.forward());
    if !(dist2 > 0.0 && cos_camera > 0.0) {
        return;
    }
    let Some(e) = y.vertex.eval(w, TransportMode::Importance) else {
        return;
    };
    let camera_pdf = camera.pixel_direction_pdf(cos_camera);
    let camera_pdf_area = camera_pdf * e.cos / dist2;
    let c = &params.mis;
    let weight = light_tracing_weight(&y.mis, camera_pdf_area, e.pdf_reverse, c);
    counters.shadow_rays += 1;
    let shadow = Ray::spawn_to(p, y.vertex.hit.ng, lens, Vec3::ZERO);
    if scene.occluded(&shadow) {
        return;
    }
    // f |cos_y| carries the cosine at y; the importance's other factors: p_cam / d^2; the
    // medium between y and the pinhole its transmittance.
    let value = y.throughput
        * e.f_cos
        * scene.transmittance(&y.vertex.hit, w, dist)
        * (weight * camera_pdf / (dist2 * c.light_paths));
    let pixel = (py - b.y0) * b.width() + (px - b.x0);
    splats.push(Splat { pixel, value });
}
