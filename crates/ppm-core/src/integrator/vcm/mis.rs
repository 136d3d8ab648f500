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
//! Russian roulette and the path-length bound are left out of the pdfs: any weights that sum
//! to one over the techniques which can produce a path keep the estimator unbiased, and the
//! length bound removes no technique from a path of at most `max_depth + 1` edges (each
//! subpath may grow to that length).

/// The power heuristic's exponent (beta = 2), as SmallVCM uses by default.
const BETA: i32 = 2;

/// p^beta: the heuristic applied to one pdf or pdf ratio ("Mis" in SmallVCM).
#[inline]
pub(super) fn mis(x: f32) -> f32 {
    x.powi(BETA)
}

/// The per-iteration constants: eta_VCM and the estimator's normalisation.
#[derive(Clone, Copy, Debug)]
pub(super) struct MisConstants {
    /// mis(eta_VCM), eta_VCM = pi r^2 N_light: how merging weighs against connecting.
    pub vm_weight: f32,
    /// mis(1 / eta_VCM).
    pub vc_weight: f32,
    /// 1 / (pi r^2 N_light): the density estimate's normalisation (uniform kernel over the disc
    /// of radius r, averaged over the N_light light paths).
    pub vm_normalization: f32,
    /// N_light, light subpaths per iteration.
    pub light_paths: f32,
}

impl MisConstants {
    /// The constants for merge radius `radius` (> 0) and `light_paths` light subpaths.
    pub fn new(radius: f32, light_paths: u32) -> Self {
        let n = light_paths as f32;
        let eta = std::f32::consts::PI * radius * radius * n;
        MisConstants {
            vm_weight: mis(eta),
            vc_weight: mis(1.0 / eta),
            vm_normalization: 1.0 / eta,
            light_paths: n,
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
