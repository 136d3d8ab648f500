//! The camera subpaths of VCM and the estimators evaluated at their vertices: emission found
//! by the path, next-event estimation, connection to the light subpath paired with the pixel,
//! and merging with the light vertices within the radius.

use super::mis::{
    connection_weight, direct_weight, emission_weight, merge_weight, MisConstants, SubpathMis,
};
use super::vertex::{LightVertex, MergeVertex, SurfaceVertex};
use crate::bsdf::{Lobe, TransportMode};
use crate::geometry::Ray;
use crate::integrator::camera_path::{refraction_scale, start_pixel_path};
use crate::integrator::camera_walk::RayCounters;
use crate::integrator::runner::Poll;
use crate::photon::HashGrid;
use crate::sampling::Rng;
use crate::scene::Scene;
use glam::Vec3;

/// Random streams of VCM's camera subpaths, apart from every other pass's.
pub(super) const CAMERA_STREAM: u64 = 0x7663_6d5f_6361_6d65;

/// Everything a camera subpath reads: the iteration's light vertices and their grid.
pub(super) struct CameraPass<'a> {
    pub scene: &'a Scene,
    pub seed: u64,
    pub iteration: u64,
    /// Most edges of a full path (max_depth + 1).
    pub max_edges: u32,
    pub rr_depth: u32,
    pub mis: MisConstants,
    pub radius: f32,
    pub grid: &'a HashGrid,
    /// Every light subpath's stored vertices, path after path, in order of their edges.
    pub vertices: &'a [LightVertex],
    /// Light path i's vertices are `vertices[path_start[i]..path_start[i + 1]]`.
    pub path_start: &'a [u32],
    /// What merging reads of the light vertices, in the grid's order.
    pub merge_vertices: &'a [MergeVertex],
    /// The pass's stop request, asked at every camera vertex: in a deep closed scene one
    /// pixel is up to max_depth vertices, each connected to up to max_depth light vertices.
    pub poll: &'a Poll<'a>,
}

/// The camera vertex and the subpath state the estimators at it read.
struct CameraVertex<'v> {
    v: &'v SurfaceVertex,
    state: &'v SubpathMis,
    /// Edges from the camera to this vertex (1 at the first hit).
    edges: u32,
    /// Every vertex before this one was a delta lobe.
    specular_path: bool,
}

impl CameraPass<'_> {
    /// The estimate of pixel `pixel` (row-major in the full image) in this iteration: the
    /// camera subpath through a uniform point of the pixel, paired with light subpath
    /// `pixel`. Camera subpaths scatter by BSDF sampling in radiance mode with the path
    /// tracer's Russian roulette (after `rr_depth` bounces, survival min(1, max channel of the
    /// throughput)). The technique set decides what runs at each vertex; light tracing alone
    /// ends the subpath at its first non-delta vertex. Cut short (and meaningless) once the
    /// pass's [`Poll`] says stop.
    pub fn pixel(&self, pixel: usize, counters: &mut RayCounters) -> Vec3 {
        let scene = self.scene;
        let camera = &scene.camera;
        let width = camera.width as usize;
        let (mut rng, mut ray) = start_pixel_path(
            scene,
            self.seed ^ CAMERA_STREAM,
            self.iteration,
            pixel,
            width,
        );
        let c = &self.mis;
        let cos = ray.dir.dot(camera.forward());
        let mut state = SubpathMis::camera_start(camera.pixel_direction_pdf(cos), c);
        let mut throughput = Vec3::ONE;
        // The product of the importance-mode over radiance-mode weights of the refractions so
        // far (eta^2 each, [`refraction_scale`]): Russian roulette reads the throughput
        // times it.
        let mut eta_scale = 1.0f32;
        let mut result = Vec3::ZERO;
        let mut edges = 0;
        // Every vertex so far was a delta lobe (see `mis::emission_weight`).
        let mut specular_path = true;
        let techniques = c.techniques;
        while edges < self.max_edges {
            if self.poll.stopped() {
                // The pass is abandoned: this estimate is discarded.
                break;
            }
            counters.rays += 1;
            let Some(hit) = scene.intersect(&ray) else {
                let escaped = self.escaped(ray.dir, edges, &state, specular_path);
                if escaped != Vec3::ZERO {
                    result += throughput * escaped;
                }
                break;
            };
            edges += 1;
            // Beer-Lambert along the segment (1 in clear media).
            throughput *= scene.transmittance(&hit, -ray.dir, hit.t);
            let material = scene.material(&hit);
            let v = SurfaceVertex::new(hit, scene.bsdf(&hit), -ray.dir);
            if !state.arrive(hit.t * hit.t, v.cos_wo()) {
                break;
            }
            let x = CameraVertex {
                v: &v,
                state: &state,
                edges,
                specular_path,
            };
            if material.is_emissive() && v.wo.dot(hit.ng) > 0.0 {
                result += throughput * material.emission * self.emission_weight(&x);
            }
            if !v.bsdf.is_delta() {
                if !techniques.extends_camera_paths() {
                    // Light tracing alone: the light subpaths carry every path from here on.
                    break;
                }
                if techniques.connection() {
                    result += throughput * self.direct(&x, &mut rng, counters);
                    result += throughput * self.connect(&x, pixel, counters);
                }
                if techniques.merging() {
                    result += throughput * self.merge(&x);
                }
            }
            if edges + 1 > self.max_edges {
                break;
            }
            let (u_lobe, u) = (rng.uniform(), rng.uniform2());
            let Some(s) = v.bsdf.sample(v.sf.wo, u_lobe, u, TransportMode::Radiance) else {
                break;
            };
            let wi = v.sf.frame.to_world(s.wi);
            if !v.sf.consistent(&hit, v.wo, wi, s.wi) {
                break;
            }
            let specular = s.lobe == Lobe::Specular;
            let pdf_reverse = if specular {
                s.pdf
            } else {
                v.bsdf.pdf(s.wi, v.sf.wo)
            };
            state.scatter(specular, s.wi.z.abs(), s.pdf, pdf_reverse, c);
            specular_path &= specular;
            if s.wi.z * v.sf.wo.z < 0.0 {
                eta_scale *= refraction_scale(&v.bsdf, v.sf.wo, u_lobe, u, s.weight);
            }
            throughput *= s.weight;
            if edges >= self.rr_depth {
                // Survival min(1, max channel of throughput eta_scale), as the path tracer's
                // (`CameraPath::scatter`; why: [`refraction_scale`]). The MIS weights leave
                // roulette out, so any survival probability keeps the estimator unbiased.
                let survive = (throughput * eta_scale).max_element().min(1.0);
                if survive.is_nan() || rng.uniform() >= survive {
                    break;
                }
                throughput /= survive;
            }
            ray = Ray::spawn(hit.p, hit.ng, wi);
        }
        result
    }

    /// The MIS weight of emission the camera subpath hits at `x` (TR eqs. 42-43): 1 when seen
    /// directly (no other technique sees it); otherwise the light subpath could have
    /// produced the emitting vertex x_k by choosing the light and its point (area pdf
    /// p_A = p_light / A: next-event estimation) or by emitting toward x_{k-1} (p_A p_W with
    /// p_W = cos/pi), so w_camera = mis(p_A) dVCM + mis(p_A p_W) dVC, weight 1 / (1 + w_camera).
    /// Without connections, 1 on a purely specular camera subpath and 0 otherwise.
    #[inline]
    fn emission_weight(&self, x: &CameraVertex) -> f32 {
        if x.edges == 1 {
            return 1.0;
        }
        let hit = &x.v.hit;
        let Some((light, p_light)) = self.scene.light_of_prim(hit.prim) else {
            return 1.0;
        };
        let (pdf_pos, pdf_dir) = light.pdf_emission(hit.ng, x.v.wo);
        emission_weight(
            x.state,
            p_light * pdf_pos,
            pdf_dir,
            x.specular_path,
            &self.mis,
        )
    }

    /// The environment a camera subpath finds when it leaves the scene along `dir` after
    /// `edges` vertices (SmallVCM's GetLightRadiance for its `BackgroundLight`; TR eqs.
    /// 42-43 with the light at infinity): 1 when seen directly; otherwise next-event
    /// estimation picks the direction with solid-angle density p_d = p_light p(dir) (no
    /// distance, and the camera state is not advanced by `arrive`) and a light subpath emits
    /// it with p_d / (pi R^2), so w_camera = mis(p_d) dVCM + mis(p_d / (pi R^2)) dVC.
    #[inline]
    fn escaped(&self, dir: Vec3, edges: u32, state: &SubpathMis, specular_path: bool) -> Vec3 {
        let Some((light, p_light)) = self.scene.environment() else {
            return Vec3::ZERO;
        };
        let le = light.le_infinite(dir);
        if edges == 0 || le == Vec3::ZERO {
            return le;
        }
        let (pdf_pos, _) = light.pdf_emission(Vec3::ZERO, -dir);
        let weight = emission_weight(
            state,
            p_light * light.pdf_infinite(dir),
            pdf_pos,
            specular_path,
            &self.mis,
        );
        le * weight
    }

    /// Next-event estimation, a vertex connection to a light (TR eqs. 44-45): one light
    /// chosen in proportion to power (p_light), a point on it with solid-angle pdf p_W
    /// (`DirectSample::pdf`; a delta of weight I/d^2 for point lights):
    ///
    /// L = f(wo, wi) |cos wi| L_e Tr / (p_light p_W) w (Tr the transmittance to the light),
    ///
    /// w_light = mis(p_bsdf(wi) / (p_light p_W)) (0 for point lights, which the camera
    /// subpath cannot hit), w_camera = mis(p_e(-wi) |cos wi| / d^2) (mis(eta_VCM) + dVCM +
    /// dVC mis(p_rev)), with p_e the light's emission direction pdf toward the vertex (the
    /// light subpath reaching the vertex, as an area density there: `Light::pdf_emission_at`,
    /// |cos wi| / (pi R^2) for a directional light) and p_rev the pdf at the
    /// vertex of the direction back along the camera subpath given wi.
    #[inline]
    fn direct(&self, x: &CameraVertex, rng: &mut Rng, counters: &mut RayCounters) -> Vec3 {
        let (u_light, u) = (rng.uniform(), rng.uniform2());
        if x.edges + 1 > self.max_edges {
            return Vec3::ZERO;
        }
        let scene = self.scene;
        let Some((light, p_light)) = scene.choose_light(u_light) else {
            return Vec3::ZERO;
        };
        let hit = &x.v.hit;
        let Some(ls) = light.sample_direct(hit.p, u) else {
            return Vec3::ZERO;
        };
        let Some(e) = x.v.eval(ls.wi, TransportMode::Radiance) else {
            return Vec3::ZERO;
        };
        let pdf_light = p_light * ls.pdf;
        let weight = direct_weight(
            x.state,
            pdf_light,
            ls.is_delta,
            e.pdf_forward,
            light.pdf_emission_at(&ls, e.cos),
            e.pdf_reverse,
            &self.mis,
        );
        counters.shadow_rays += 1;
        if scene.occluded(&Ray::spawn_to(hit.p, hit.ng, ls.p, ls.n)) {
            return Vec3::ZERO;
        }
        e.f_cos * ls.li * scene.transmittance_to(hit, ls.p) * (weight / pdf_light)
    }

    /// Vertex connection of `x` to each stored vertex y of light subpath `path` (TR eqs.
    /// 40-41), as long as the full path has at most `max_edges` edges:
    ///
    /// C = T_y f_y(-> x) f_x(-> y) G(x, y) Tr(x, y) w, G = |cos_x| |cos_y| / d^2,
    ///
    /// Tr the Beer-Lambert transmittance of the segment's medium ([`Scene::transmittance_to`];
    /// a factor of the contribution only, absorption is not sampled),
    ///
    /// w_light = mis(p_x(-> y) |cos_y| / d^2) (mis(eta_VCM) + dVCM_y + dVC_y mis(p_y,rev)),
    /// w_camera = mis(p_y(-> x) |cos_x| / d^2) (mis(eta_VCM) + dVCM_x + dVC_x mis(p_x,rev)):
    /// the camera subpath extended to y and the light subpath extended to x, in area measure.
    #[inline]
    fn connect(&self, x: &CameraVertex, path: usize, counters: &mut RayCounters) -> Vec3 {
        let range = self.path_start[path] as usize..self.path_start[path + 1] as usize;
        let c = &self.mis;
        let hit = &x.v.hit;
        let mut sum = Vec3::ZERO;
        for y in &self.vertices[range] {
            if x.edges + y.edges + 1 > self.max_edges {
                break;
            }
            let to_y = y.vertex.hit.p - hit.p;
            let dist2 = to_y.length_squared();
            if dist2.is_nan() || dist2 <= 0.0 {
                continue;
            }
            let w = to_y / dist2.sqrt();
            let Some(ex) = x.v.eval(w, TransportMode::Radiance) else {
                continue;
            };
            let Some(ey) = y.vertex.eval(-w, TransportMode::Importance) else {
                continue;
            };
            let camera_pdf_area = ex.pdf_forward * ey.cos / dist2;
            let light_pdf_area = ey.pdf_forward * ex.cos / dist2;
            let weight = connection_weight(
                &y.mis,
                x.state,
                camera_pdf_area,
                light_pdf_area,
                ey.pdf_reverse,
                ex.pdf_reverse,
                c,
            );
            counters.shadow_rays += 1;
            let shadow = Ray::spawn_to(hit.p, hit.ng, y.vertex.hit.p, y.vertex.hit.ng);
            if self.scene.occluded(&shadow) {
                continue;
            }
            let tr = self.scene.transmittance_to(hit, y.vertex.hit.p);
            sum += y.throughput * ex.f_cos * ey.f_cos * tr * (weight / dist2);
        }
        sum
    }

    /// Vertex merging of `x` with every light vertex y within the radius r (TR eqs. 38-39),
    /// as long as the full path has at most `max_edges` edges: the density estimate with a
    /// uniform kernel over the disc, averaged over the N_light light subpaths,
    ///
    /// M = 1 / (pi r^2 N_light) sum_y f_x(wo, wi_y) T_y (|wi_y . ns| / |wi_y . ng|) w_y,
    ///
    /// the cosine ratio turning the light vertices' density per unit of geometric area (an
    /// irradiance with the geometric cosine, from either side of the surface) into the
    /// shading cosine the reflected or transmitted radiance takes at x
    /// ([`crate::photon::GatherNormals::weight_either_side`]; ppm's and sppm's photons,
    /// gathered on diffuse surfaces only, take the one-sided weight; 1 when flat), and
    ///
    /// w_light = dVCM_y mis(1/eta_VCM) + dVM_y mis(p_x(wo -> wi_y)),
    /// w_camera = dVCM_x mis(1/eta_VCM) + dVM_x mis(p_x(wi_y -> wo)).
    #[inline]
    fn merge(&self, x: &CameraVertex) -> Vec3 {
        let c = &self.mis;
        let mut sum = Vec3::ZERO;
        let normals = x.v.sf.gather_normals(&x.v.hit, x.v.wo);
        self.grid
            .for_each_index_in_radius(x.v.hit.p, self.radius, |i, _| {
                let y = &self.merge_vertices[i];
                if x.edges + y.edges > self.max_edges {
                    return;
                }
                // Light vertices on either side: at a rough dielectric the far side's light
                // is transmitted toward the camera (f_x evaluates to zero where it cannot be).
                let ratio = normals.weight_either_side(y.wo);
                if ratio <= 0.0 {
                    return;
                }
                let Some(e) = x.v.eval(y.wo, TransportMode::Radiance) else {
                    return;
                };
                sum += e.f
                    * y.throughput
                    * (ratio * merge_weight(&y.mis, x.state, e.pdf_forward, e.pdf_reverse, c));
            });
        sum * c.vm_normalization
    }
}
