//! The recursive MIS quantities of vertex connection and merging.
//!
//! Georgiev, Krivanek, Davidovic, Slusallek 2012, "Light transport simulation with vertex
//! connection and merging" (SIGGRAPH Asia), and its technical report "Implementing vertex
//! connection and merging" (Georgiev 2012, "TR" below, with its equation numbers), as SmallVCM
//! implements them (its comments cite the same equations). Every sampling technique of a full
//! path x_0..x_k (light tracing, the camera path hitting a light, connections of any light and
//! camera vertex, merging at any non-delta vertex) gets the weight
//! w = 1 / (sum over techniques of (p_t / p_this)^beta) (TR eq. 37: w = 1 / (w_light + 1 +
//! w_camera), the two partial sums of the subpaths); each subpath carries three partial sums
//! that make that weight a constant amount of work per technique:
//!
//! - dVCM: the ratio for the technique that ends this subpath at its last vertex,
//! - dVC: the sum of the ratios of the connection techniques further down the subpath,
//! - dVM: the same for the merging techniques.
//!
//! pdfs are solid-angle (`W`) or area (`A`); p_forward is the pdf with which the subpath
//! sampled its last direction, p_reverse the pdf of the opposite direction at the same vertex.
//! Merging and connection are related by eta_VCM = pi r^2 N_light (TR eq. 20, with n_VC = 1
//! and n_VM = N_light): merging's pdf is that of connecting, times the probability pi r^2 p_A
//! that a light vertex lands in the disc, times the N_light light paths of an iteration.
//!
//! Technique sets ([`Techniques`], SmallVCM's algorithms): a set without merging weighs it at
//! zero, mis(eta_VCM) -> 0 (the merge term of every connection-side sum: dVC and the
//! connection weights); a set without connections weighs them at zero, mis(1/eta_VCM) -> 0 (the
//! connection terms of every merge-side sum: dVM and the merge weights, the emission included,
//! whose ratio the light subpath carries in dVC and hands to dVM through the same factor).
//! The recursions are otherwise unchanged, so each weight is the power heuristic over exactly
//! the set's techniques. Two cases have no recursive form and are set explicitly: without
//! connections, the emission a camera subpath finds is weighted 1 while every vertex before
//! it was a delta lobe (nothing else samples it) and 0 otherwise (merging or light tracing
//! does), and light tracing without connections is the only technique of its paths (weight 1).
//!
//! Russian roulette and the path-length bound are left out of the pdfs: any weights that sum
//! to one over the techniques which can produce a path keep the estimator unbiased, and the
//! length bound removes no technique from a path of at most `max_depth + 1` edges (each
//! subpath may grow to that length).

use super::techniques::Techniques;

/// The power heuristic's exponent, beta = 2 (Veach 1997, sec. 9.2.4). SmallVCM's `Mis` returns
/// the pdf itself, the balance heuristic (beta = 1); on SmallVCM's glass-sphere box the two
/// give the same variance per iteration in either renderer (docs/vcm.md, "Against SmallVCM").
const BETA: i32 = 2;

/// p^beta: the heuristic applied to one pdf or pdf ratio ("Mis" in SmallVCM).
#[inline]
pub(super) fn mis(x: f32) -> f32 {
    x.powi(BETA)
}

/// The per-iteration constants: eta_VCM, the estimator's normalisation and the technique set.
#[derive(Clone, Copy, Debug)]
pub(super) struct MisConstants {
    /// mis(eta_VCM), eta_VCM = pi r^2 N_light: how merging weighs against connecting (0
    /// without merging: SmallVCM's mMisVmWeightFactor).
    pub vm_weight: f32,
    /// mis(1 / eta_VCM): how connecting weighs against merging (0 without connections or
    /// without merging, where no merge-side sum is read: mMisVcWeightFactor).
    pub vc_weight: f32,
    /// 1 / (pi r^2 N_light): the density estimate's normalisation (uniform kernel over the disc
    /// of radius r, averaged over the N_light light paths); 0 without merging.
    pub vm_normalization: f32,
    /// N_light, light subpaths per iteration.
    pub light_paths: f32,
    pub techniques: Techniques,
}

impl MisConstants {
    /// The constants of `techniques` for merge radius `radius` (> 0; read only with merging)
    /// and `light_paths` light subpaths.
    pub fn new(techniques: Techniques, radius: f32, light_paths: u32) -> Self {
        let n = light_paths as f32;
        let (vm_weight, vc_weight, vm_normalization) = if techniques.merging() {
            let eta = std::f32::consts::PI * radius * radius * n;
            let vc_weight = if techniques.connection() {
                mis(1.0 / eta)
            } else {
                0.0
            };
            (mis(eta), vc_weight, 1.0 / eta)
        } else {
            (0.0, 0.0, 0.0)
        };
        MisConstants {
            vm_weight,
            vc_weight,
            vm_normalization,
            light_paths: n,
            techniques,
        }
    }
}

/// The three partial sums a subpath carries (SmallVCM's dVCM, dVC, dVM; TR eqs. 31-36).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct SubpathMis {
    pub dvcm: f32,
    pub dvc: f32,
    pub dvm: f32,
}

impl SubpathMis {
    /// A light subpath leaving a light (TR eqs. 31-33, delta lights eqs. 48-50): with p_0 the
    /// area pdf of the origin (times the light's choice) and p_e = p_0 p_W(dir) the emission
    /// pdf,
    /// dVCM = mis(p_0 / p_e) = mis(1 / p_W), dVC = mis(cos_0 / p_e) (0 for a delta light,
    /// which no camera subpath can hit), dVM = dVC mis(1/eta_VCM).
    pub fn light_start(
        pdf_pos: f32,
        pdf_dir: f32,
        cos: f32,
        delta: bool,
        c: &MisConstants,
    ) -> Self {
        let dvc = if delta {
            0.0
        } else {
            mis(cos / (pdf_pos * pdf_dir))
        };
        SubpathMis {
            dvcm: mis(1.0 / pdf_dir),
            dvc,
            dvm: dvc * c.vc_weight,
        }
    }

    /// A light subpath leaving a light at infinity (TR sec. 5.1 and eqs. 48-50; SmallVCM's
    /// `DirectionalLight` and `BackgroundLight`): next-event estimation picks the direction
    /// with solid-angle density p_d (times the light's choice; 1 for a directional light) and
    /// the subpath leaves a disk with area density `pdf_pos` (1/(pi R^2)), so the emission
    /// pdf is p_e = p_d pdf_pos with p_d = `pdf_dir` (p_light p(w)) and the cosine at the
    /// light is 1: dVCM = mis(p_d / p_e) = mis(1 / pdf_pos), dVC = mis(1 / p_e) (0 for a
    /// directional light, a delta no camera subpath hits), dVM = dVC mis(1/eta_VCM).
    /// The first [`SubpathMis::arrive`] must then get distance^2 1: parallel rays reach the
    /// first vertex with area density p_e |cos|, whatever the distance to the disk.
    pub fn light_start_at_infinity(
        pdf_pos: f32,
        pdf_dir: f32,
        delta: bool,
        c: &MisConstants,
    ) -> Self {
        let dvc = if delta {
            0.0
        } else {
            mis(1.0 / (pdf_pos * pdf_dir))
        };
        SubpathMis {
            dvcm: mis(1.0 / pdf_pos),
            dvc,
            dvm: dvc * c.vc_weight,
        }
    }

    /// A camera subpath leaving the pinhole along a ray of per-pixel solid-angle pdf
    /// `camera_pdf` (TR eqs. 31-33 for the camera: the light-tracing technique reaches the
    /// first vertex with pdf p_camera / N_light in the same units): dVCM = mis(N_light /
    /// p_camera), dVC = dVM = 0 (the camera cannot be hit, nor merged at).
    pub fn camera_start(camera_pdf: f32, c: &MisConstants) -> Self {
        SubpathMis {
            dvcm: mis(c.light_paths / camera_pdf),
            dvc: 0.0,
            dvm: 0.0,
        }
    }

    /// At the next vertex, found at distance^2 `dist2` with |cos| `cos` between the incoming
    /// direction and the normal, completing TR eqs. 31-33 (first vertex) or 34-36: the
    /// solid-angle pdfs of the last step become area pdfs, dVCM *= mis(d^2), and every sum
    /// /= mis(|cos|). Returns false (the subpath
    /// ends) for a direction in the surface's plane, which carries nothing and would make the
    /// sums infinite.
    #[inline]
    #[must_use]
    pub fn arrive(&mut self, dist2: f32, cos: f32) -> bool {
        if cos.is_nan() || cos <= 0.0 {
            return false;
        }
        let inv = 1.0 / mis(cos);
        self.dvcm *= mis(dist2) * inv;
        self.dvc *= inv;
        self.dvm *= inv;
        true
    }

    /// The sum this subpath adds to a connection's weight (TR eqs. 40-41, 44-47): the
    /// techniques that would have sampled the connection's other vertex as this subpath's
    /// next one, reached from this subpath's last vertex with area pdf `pdf_area`, and
    /// `pdf_reverse` the last vertex's pdf of the direction back along this subpath given the
    /// connection: mis(p_A) (mis(eta_VCM) + dVCM + dVC mis(p_rev)).
    #[inline]
    pub fn connected(&self, pdf_area: f32, pdf_reverse: f32, c: &MisConstants) -> f32 {
        mis(pdf_area) * (c.vm_weight + self.dvcm + self.dvc * mis(pdf_reverse))
    }

    /// After sampling the next direction at a vertex (TR eqs. 35-37): `cos_out` is |cos| of the
    /// sampled direction, `pdf` its solid-angle pdf, `pdf_reverse` the pdf of the opposite
    /// direction (the one the path arrived from) given the sampled one (TR eqs. 34-36).
    ///
    /// Non-delta: dVC = mis(cos_out / pdf) (dVC mis(p_rev) + dVCM + mis(eta_VCM)),
    /// dVM = mis(cos_out / pdf) (dVM mis(p_rev) + dVCM mis(1/eta_VCM) + 1), dVCM = mis(1/pdf).
    /// Delta (TR eqs. 53-55; no connection or merge can end at this vertex, and the discrete
    /// probabilities of the lobe, forward and reverse, are equal and cancel): dVCM = 0,
    /// dVC *= mis(cos_out), dVM *= mis(cos_out).
    #[inline]
    pub fn scatter(
        &mut self,
        specular: bool,
        cos_out: f32,
        pdf: f32,
        pdf_reverse: f32,
        c: &MisConstants,
    ) {
        if specular {
            self.dvcm = 0.0;
            self.dvc *= mis(cos_out);
            self.dvm *= mis(cos_out);
        } else {
            let g = mis(cos_out / pdf);
            let rev = mis(pdf_reverse);
            self.dvc = g * (self.dvc * rev + self.dvcm + c.vm_weight);
            self.dvm = g * (self.dvm * rev + self.dvcm * c.vc_weight + 1.0);
            self.dvcm = mis(1.0 / pdf);
        }
    }
}

/// The weight of emission the camera subpath finds at a light vertex x_0 it did not start at
/// (TR eqs. 42-43), with `direct_pdf_area` the area pdf with which next-event estimation and
/// the light subpaths choose x_0 (p_light p_A) and `emission_pdf_dir` the light's pdf of
/// emitting toward the camera subpath's previous vertex: w_camera = mis(p_A) dVCM +
/// mis(p_A p_W) dVC, w = 1 / (1 + w_camera).
///
/// Without connections (`bpm`, `lt`): 1 if every camera vertex before x_0 was a delta lobe
/// (`specular_path`: no merge or light-tracing technique can end at such a vertex), else 0
/// (the set's other techniques sample the path; SmallVCM's GetLightRadiance does the same).
#[inline]
pub(super) fn emission_weight(
    camera: &SubpathMis,
    direct_pdf_area: f32,
    emission_pdf_dir: f32,
    specular_path: bool,
    c: &MisConstants,
) -> f32 {
    if !c.techniques.connection() {
        return if specular_path { 1.0 } else { 0.0 };
    }
    let w_camera =
        mis(direct_pdf_area) * camera.dvcm + mis(direct_pdf_area * emission_pdf_dir) * camera.dvc;
    1.0 / (1.0 + w_camera)
}

/// The weight of next-event estimation at a camera vertex (TR eqs. 44-45): `light_pdf` the
/// solid-angle pdf of the sampled light point (p_light p_W), `bsdf_pdf` the vertex's pdf of
/// sampling that direction, `emission_pdf_area` the light's emission pdf toward the vertex
/// as an area density there (p_e |cos| / d^2) and `bsdf_pdf_reverse` the vertex's pdf of the
/// direction back along the camera subpath. w_light = mis(p_bsdf / p_light) (0 for a delta
/// light, which no camera subpath hits), w_camera = mis(p_e |cos| / d^2) (mis(eta_VCM) + dVCM
/// + dVC mis(p_rev)), w = 1 / (w_light + 1 + w_camera).
#[inline]
pub(super) fn direct_weight(
    camera: &SubpathMis,
    light_pdf: f32,
    delta_light: bool,
    bsdf_pdf: f32,
    emission_pdf_area: f32,
    bsdf_pdf_reverse: f32,
    c: &MisConstants,
) -> f32 {
    let w_light = if delta_light {
        0.0
    } else {
        mis(bsdf_pdf / light_pdf)
    };
    let w_camera = camera.connected(emission_pdf_area, bsdf_pdf_reverse, c);
    1.0 / (w_light + 1.0 + w_camera)
}

/// The weight of connecting light vertex y to camera vertex x (TR eqs. 40-41): each subpath
/// extended to the other's vertex, in area measure (`camera_pdf_area` = p_x(-> y) |cos_y| /
/// d^2, `light_pdf_area` = p_y(-> x) |cos_x| / d^2), and each vertex's pdf of the direction
/// back along its own subpath given the connection (`light_pdf_reverse` at y,
/// `camera_pdf_reverse` at x): w_light = mis(camera_pdf_area) (mis(eta_VCM) + dVCM_y + dVC_y
/// mis(p_y,rev)), w_camera likewise, w = 1 / (w_light + 1 + w_camera).
#[inline]
pub(super) fn connection_weight(
    light: &SubpathMis,
    camera: &SubpathMis,
    camera_pdf_area: f32,
    light_pdf_area: f32,
    light_pdf_reverse: f32,
    camera_pdf_reverse: f32,
    c: &MisConstants,
) -> f32 {
    let w_light = light.connected(camera_pdf_area, light_pdf_reverse, c);
    let w_camera = camera.connected(light_pdf_area, camera_pdf_reverse, c);
    1.0 / (w_light + 1.0 + w_camera)
}

/// The weight of merging light vertex y at camera vertex x (TR eqs. 38-39): `pdf_forward` is
/// x's pdf of the direction y arrived along (the light subpath's next step, sampled at x),
/// `pdf_reverse` x's pdf of the camera subpath's direction given that one. w_light = dVCM_y
/// mis(1/eta_VCM) + dVM_y mis(p_forward), w_camera = dVCM_x mis(1/eta_VCM) + dVM_x
/// mis(p_reverse), w = 1 / (w_light + 1 + w_camera).
#[inline]
pub(super) fn merge_weight(
    light: &SubpathMis,
    camera: &SubpathMis,
    pdf_forward: f32,
    pdf_reverse: f32,
    c: &MisConstants,
) -> f32 {
    let w_light = light.dvcm * c.vc_weight + light.dvm * mis(pdf_forward);
    let w_camera = camera.dvcm * c.vc_weight + camera.dvm * mis(pdf_reverse);
    1.0 / (w_light + 1.0 + w_camera)
}

/// The weight of connecting light vertex y to the pinhole (TR eqs. 46-47): the camera subpath
/// finds y with area pdf `camera_pdf_area` (p_cam |cos_y| / d^2) out of N_light tries, and
/// `pdf_reverse` is y's pdf of the direction back along the light subpath given the camera's.
/// w_light = mis(p_cam |cos_y| / (d^2 N_light)) (mis(eta_VCM) + dVCM + dVC mis(p_rev)); the
/// camera subpath has no other vertex, w = 1 / (w_light + 1). Without connections (`lt`) the
/// path has no other technique: w = 1.
#[inline]
pub(super) fn light_tracing_weight(
    light: &SubpathMis,
    camera_pdf_area: f32,
    pdf_reverse: f32,
    c: &MisConstants,
) -> f32 {
    if !c.techniques.connection() {
        return 1.0;
    }
    let w_light = light.connected(camera_pdf_area / c.light_paths, pdf_reverse, c);
    1.0 / (w_light + 1.0)
}

#[cfg(test)]
mod tests;
