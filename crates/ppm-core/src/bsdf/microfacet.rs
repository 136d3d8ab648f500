//! The microfacet distributions of the rough conductor, dielectric and plastic: GGX
//! (Trowbridge-Reitz, here, with sampling of the visible normals) and Beckmann
//! ([`super::beckmann`]), behind the closed enum [`Microfacet`] the BSDFs call.

use super::beckmann::Beckmann;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// GGX distribution of microfacet normals with roughness `alpha_x` along the local x axis and
/// `alpha_y` along y (isotropic when equal). All directions are in the local frame, `z` the
/// macro normal; microfacet normals `m` lie in the upper hemisphere.
///
/// - Normal density (Walter et al. 2007, eq. 33; anisotropic form Heitz 2014, "Understanding
///   the masking-shadowing function", eq. 85):
///   `D(m) = 1 / (pi ax ay ((mx/ax)^2 + (my/ay)^2 + mz^2)^2)` for `mz > 0`, so that
///   `integral D(m) mz dm = 1`.
/// - Smith's Lambda (Heitz 2014, eq. 86): `Lambda(w) = (-1 + sqrt(1 + a^2 tan^2 theta)) / 2`
///   with `a^2 tan^2 theta = (ax^2 wx^2 + ay^2 wy^2) / wz^2`, and the masking of one direction
///   `G1(w, m) = chi+((w . m) / (w . n)) / (1 + Lambda(w))` (Walter et al. 2007, eq. 34).
/// - Masking-shadowing: the **separable** form `G(wo, wi, m) = G1(wo, m) G1(wi, m)` (Walter et
///   al. 2007, eq. 23; Heitz 2014, eq. 98), which is what Mitsuba 3's `MicrofacetDistribution::G`
///   computes, so that values agree with it. (The height-correlated form, Heitz 2014 eq. 99,
///   is slightly brighter at grazing angles.)
/// - Sampling: the distribution of normals visible from `w` (Heitz 2014, eq. 38),
///   `D_w(m) = G1(w, m) max(0, w . m) D(m) / wz`, sampled exactly by Heitz 2018, "Sampling the
///   GGX Distribution of Visible Normals" (JCGT 7(4)): stretch `w` to the configuration of
///   roughness 1, sample a point on the projected hemisphere, unstretch.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ggx {
    pub alpha_x: f32,
    pub alpha_y: f32,
}

impl Ggx {
    /// The smallest roughness used; smaller ones are raised to it. At 1e-4 the density's peak,
    /// 1 / (pi alpha^2) = 3e7, and its square (what vcm's MIS multiplies) stay well inside f32.
    pub const MIN_ALPHA: f32 = 1e-4;

    /// A distribution of roughness `alpha_x` along x and `alpha_y` along y, each clamped to
    /// [`Ggx::MIN_ALPHA`, 1e3] (the caller rejects non-finite or negative values).
    pub fn new(alpha_x: f32, alpha_y: f32) -> Self {
        Ggx {
            alpha_x: alpha_x.clamp(Self::MIN_ALPHA, 1e3),
            alpha_y: alpha_y.clamp(Self::MIN_ALPHA, 1e3),
        }
    }

    /// An isotropic distribution of roughness `alpha`.
    pub fn isotropic(alpha: f32) -> Self {
        Self::new(alpha, alpha)
    }

    /// The normal density D(m); zero for `m` in the lower hemisphere.
    #[inline]
    pub fn d(&self, m: Vec3) -> f32 {
        if m.z <= 0.0 {
            return 0.0;
        }
        let (x, y) = (m.x / self.alpha_x, m.y / self.alpha_y);
        let s = x * x + y * y + m.z * m.z;
        let d = 1.0 / (PI * self.alpha_x * self.alpha_y * s * s);
        if d.is_finite() {
            d
        } else {
            0.0
        }
    }

    /// Smith's Lambda(w), the same for `w` and `-w`.
    #[inline]
    pub fn lambda(&self, w: Vec3) -> f32 {
        let (x, y) = (self.alpha_x * w.x, self.alpha_y * w.y);
        let xy2 = x * x + y * y;
        if xy2 == 0.0 {
            return 0.0;
        }
        let a2_tan2 = xy2 / (w.z * w.z);
        // (-1 + sqrt(1 + t)) / 2 = t / (2 (1 + sqrt(1 + t))), exact where t is tiny.
        let l = 0.5 * a2_tan2 / (1.0 + (1.0 + a2_tan2).sqrt());
        if l.is_finite() {
            l
        } else {
            f32::INFINITY
        }
    }

    /// Masking of one direction by microfacets of normal `m`: 1 / (1 + Lambda(w)) where `w`
    /// sees the front of `m` from the side of the macro surface it is on, else 0.
    #[inline]
    pub fn g1(&self, w: Vec3, m: Vec3) -> f32 {
        if w.dot(m) * w.z <= 0.0 {
            return 0.0;
        }
        1.0 / (1.0 + self.lambda(w))
    }

    /// Separable masking-shadowing G1(wo, m) G1(wi, m).
    #[inline]
    pub fn g(&self, wo: Vec3, wi: Vec3, m: Vec3) -> f32 {
        self.g1(wo, m) * self.g1(wi, m)
    }

    /// Density of [`Ggx::sample_visible`] over the normals `m` (solid angle):
    /// `D_w(m) = G1(w, m) |w . m| D(m) / |wz|`, for `w` on either side (it is mirrored up).
    #[inline]
    pub fn pdf_visible(&self, w: Vec3, m: Vec3) -> f32 {
        if w.z == 0.0 {
            return 0.0;
        }
        let w = if w.z < 0.0 { -w } else { w };
        self.g1(w, m) * w.dot(m).max(0.0) * self.d(m) / w.z
    }

    /// A normal from the distribution of normals visible from `w` (mirrored to the upper
    /// hemisphere if below), Heitz 2018: in the stretched space where the roughness is 1, the
    /// visible normals are the points of a hemisphere seen from `w_h`, uniform over its
    /// projection (a disc, of which the half hidden behind the horizon is folded by `s`).
    #[inline]
    pub fn sample_visible(&self, w: Vec3, u: Vec2) -> Vec3 {
        let w = if w.z < 0.0 { -w } else { w };
        // The view direction in the stretched configuration.
        let wh = Vec3::new(self.alpha_x * w.x, self.alpha_y * w.y, w.z).normalize();
        // An orthonormal basis (t1, t2, wh) around it, t1 horizontal.
        let len2 = wh.x * wh.x + wh.y * wh.y;
        let t1 = if len2 > 0.0 {
            Vec3::new(-wh.y, wh.x, 0.0) / len2.sqrt()
        } else {
            Vec3::X
        };
        let t2 = wh.cross(t1);
        // A uniform point of the unit disc, its t2 coordinate squeezed into the visible part
        // of the projected hemisphere: of height (1 + wh.z) / 2 of the disc's upper half.
        let r = u.x.sqrt();
        let (sin_phi, cos_phi) = (2.0 * PI * u.y).sin_cos();
        let p1 = r * cos_phi;
        let s = 0.5 * (1.0 + wh.z);
        let p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * r * sin_phi;
        // Lift to the hemisphere and unstretch the normal.
        let pz = (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt();
        let nh = p1 * t1 + p2 * t2 + pz * wh;
        Vec3::new(self.alpha_x * nh.x, self.alpha_y * nh.y, nh.z.max(1e-6)).normalize()
    }
}

/// A microfacet distribution: the BSDFs call its `d`, `g1`, `g`, `sample_m` and `pdf_m`,
/// which dispatch statically to the model. The two samplers differ: GGX draws the normals
/// visible from the view direction (density `D_w(m)`), Beckmann draws `D(m) mz`; `pdf_m` is
/// the density of `sample_m` either way.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Microfacet {
    /// Trowbridge-Reitz.
    Ggx(Ggx),
    /// Beckmann (Gaussian slopes).
    Beckmann(Beckmann),
}

impl From<Ggx> for Microfacet {
    fn from(g: Ggx) -> Self {
        Microfacet::Ggx(g)
    }
}

impl From<Beckmann> for Microfacet {
    fn from(b: Beckmann) -> Self {
        Microfacet::Beckmann(b)
    }
}

impl Microfacet {
    /// The same distribution (GGX or Beckmann) with isotropic roughness `alpha`, clamped as
    /// its constructor clamps: what a roughness texture sets at a hit.
    #[inline]
    pub fn with_alpha(&self, alpha: f32) -> Microfacet {
        match self {
            Microfacet::Ggx(_) => Ggx::new(alpha, alpha).into(),
            Microfacet::Beckmann(_) => Beckmann::new(alpha, alpha).into(),
        }
    }

    /// Roughness along the local x axis.
    #[inline]
    pub fn alpha_x(&self) -> f32 {
        match self {
            Microfacet::Ggx(g) => g.alpha_x,
            Microfacet::Beckmann(b) => b.alpha_x,
        }
    }

    /// Roughness along the local y axis.
    #[inline]
    pub fn alpha_y(&self) -> f32 {
        match self {
            Microfacet::Ggx(g) => g.alpha_y,
            Microfacet::Beckmann(b) => b.alpha_y,
        }
    }

    /// The normal density D(m); zero for `m` in the lower hemisphere.
    #[inline]
    pub fn d(&self, m: Vec3) -> f32 {
        match self {
            Microfacet::Ggx(g) => g.d(m),
            Microfacet::Beckmann(b) => b.d(m),
        }
    }

    /// Smith masking of `w` by microfacets of normal `m`, 1 / (1 + Lambda(w)) or 0.
    #[inline]
    pub fn g1(&self, w: Vec3, m: Vec3) -> f32 {
        match self {
            Microfacet::Ggx(g) => g.g1(w, m),
            Microfacet::Beckmann(b) => b.g1(w, m),
        }
    }

    /// Separable masking-shadowing G1(wo, m) G1(wi, m).
    #[inline]
    pub fn g(&self, wo: Vec3, wi: Vec3, m: Vec3) -> f32 {
        self.g1(wo, m) * self.g1(wi, m)
    }

    /// A normal in the upper hemisphere for the view direction `w` (either side: mirrored up).
    #[inline]
    pub fn sample_m(&self, w: Vec3, u: Vec2) -> Vec3 {
        match self {
            Microfacet::Ggx(g) => g.sample_visible(w, u),
            Microfacet::Beckmann(b) => b.sample(u),
        }
    }

    /// Density of [`Microfacet::sample_m`] at the upper-hemisphere normal `m` (solid angle):
    /// `D_w(m)` for GGX, `D(m) mz` for Beckmann.
    #[inline]
    pub fn pdf_m(&self, w: Vec3, m: Vec3) -> f32 {
        match self {
            Microfacet::Ggx(g) => g.pdf_visible(w, m),
            Microfacet::Beckmann(b) => b.pdf(m),
        }
    }

    /// Density at `wi` of reflecting `wo` about `h = normalize(wo + wi)` drawn by `sample_m`,
    /// both above the surface: `pdf_m(wo, h) / (4 |wo . h|)` (Walter et al. 2007, eq. 14).
    /// For GGX written `G1(wo, h) D(h) / (4 cos_o)`, the `wo . h` cancelled.
    #[inline]
    pub fn reflection_pdf_h(&self, wo: Vec3, h: Vec3) -> f32 {
        match self {
            Microfacet::Ggx(g) => g.g1(wo, h) * g.d(h) / (4.0 * wo.z),
            Microfacet::Beckmann(b) => b.pdf(h) / (4.0 * wo.dot(h).abs()),
        }
    }

    /// `D_w(m) / pdf_m(w, m)` for `w` above the surface: the factor that turns an average over
    /// `sample_m` into one over the visible normals. Exactly 1 for GGX; for Beckmann
    /// `G1(w, m) max(0, w . m) / (wz mz)`.
    #[inline]
    pub fn visible_weight(&self, w: Vec3, m: Vec3) -> f32 {
        match self {
            Microfacet::Ggx(_) => 1.0,
            Microfacet::Beckmann(b) => {
                let v = b.g1(w, m) * w.dot(m).max(0.0) / (w.z * m.z);
                if v.is_finite() {
                    v
                } else {
                    0.0
                }
            }
        }
    }
}

/// Directional albedo of the rough dielectric interface's reflection and transmission, for
/// `wo` at `cos_o` in the upper hemisphere of an interface of relative index `eta` (lower over
/// upper side): the integrals over `wi` of `f cos(wi)` of each lobe (Walter et al. 2007,
/// eqs. 20 and 21, with the radiance scaling of refraction left out).
///
/// Computed, as Mitsuba 3 does for its rough plastic, by quadrature over the visible normals:
/// with `m ~ D_wo`, reflection contributes `F(wo . m) G1(wi_r, m)` and transmission
/// `(1 - F) G1(wi_t, m)` (the rest of each integrand is the density `D_wo` and the Jacobian),
/// on an `n x n` Gauss-Legendre grid of the sampler's unit square. With a sampler of another
/// density (Beckmann's), each term is multiplied by [`Microfacet::visible_weight`].
pub fn rough_dielectric_albedo(dist: &Microfacet, cos_o: f32, eta: f32, n: usize) -> (f32, f32) {
    let cos_o = cos_o.clamp(1e-6, 1.0);
    let wo = Vec3::new((1.0 - cos_o * cos_o).max(0.0).sqrt(), 0.0, cos_o);
    let rule = gauss_legendre_unit(n);
    let (mut reflected, mut transmitted) = (0.0f64, 0.0f64);
    for &(x, wx) in &rule {
        for &(y, wy) in &rule {
            let m = dist.sample_m(wo, Vec2::new(x as f32, y as f32));
            let v = dist.visible_weight(wo, m);
            let cos_m = wo.dot(m);
            let f = super::fresnel_dielectric(cos_m, eta);
            let wi_r = 2.0 * cos_m * m - wo;
            if wi_r.z > 0.0 {
                reflected += wx * wy * (f * dist.g1(wi_r, m) * v) as f64;
            }
            if let Some(wi_t) = super::refract_about(wo, m, eta) {
                if wi_t.z < 0.0 {
                    transmitted += wx * wy * ((1.0 - f) * dist.g1(wi_t, m) * v) as f64;
                }
            }
        }
    }
    (reflected as f32, transmitted as f32)
}

/// Gauss-Legendre nodes and weights on [0, 1] (weights summing to 1), by Newton's iteration on
/// the Legendre polynomial P_n from the Chebyshev guess.
pub fn gauss_legendre_unit(n: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| {
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut dp = 1.0;
            for _ in 0..100 {
                // P_n(x) and its derivative by the three-term recurrence.
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=n {
                    let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                    p0 = p1;
                    p1 = p2;
                }
                let p = if n == 0 { 1.0 } else { p1 };
                let p_prev = if n == 1 { 1.0 } else { p0 };
                dp = n as f64 * (x * p - p_prev) / (x * x - 1.0);
                let dx = p / dp;
                x -= dx;
                if dx.abs() < 1e-15 {
                    break;
                }
            }
            let w = 2.0 / ((1.0 - x * x) * dp * dp);
            (0.5 * (x + 1.0), 0.5 * w)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::{uniform_sphere, Rng};

    #[test]
    fn gauss_legendre_integrates_polynomials_exactly() {
        let rule = gauss_legendre_unit(8);
        for k in 0..16 {
            let sum: f64 = rule.iter().map(|&(x, w)| w * x.powi(k)).sum();
            assert!((sum - 1.0 / (k as f64 + 1.0)).abs() < 1e-12, "x^{k}: {sum}");
        }
    }

    /// D is normalised, integral of D(m) m.z dm = 1, and the visible microfacets project to
    /// the macro surface's area seen from any direction, integral of
    /// G1(w, m) max(0, w . m) D(m) dm = w.z (Heitz 2014, eq. 7), by uniform sphere sampling.
    #[test]
    fn normals_are_normalised_and_visible_projected_area_is_the_surface() {
        for (ax, ay) in [(0.1, 0.1), (0.5, 0.5), (1.0, 1.0), (0.2, 0.6)] {
            let ggx = Ggx::new(ax, ay);
            let mut rng = Rng::new(7, 0, 0);
            let w = Vec3::new(0.6, 0.3, 0.5).normalize();
            let n = 2_000_000;
            let (mut norm, mut visible) = (0.0f64, 0.0f64);
            for _ in 0..n {
                let m = uniform_sphere(rng.uniform2());
                norm += (ggx.d(m) * m.z.max(0.0)) as f64;
                visible += (ggx.g1(w, m) * w.dot(m).max(0.0) * ggx.d(m)) as f64;
            }
            let scale = 4.0 * std::f64::consts::PI / n as f64;
            let (norm, visible) = (norm * scale, visible * scale);
            let tol = if ax < 0.2 { 0.05 } else { 0.01 };
            assert!(
                (norm - 1.0).abs() < tol,
                "{ax} {ay}: integral D cos = {norm}"
            );
            assert!(
                (visible - w.z as f64).abs() < tol * w.z as f64,
                "{ax} {ay}: visible projected area {visible} != {}",
                w.z
            );
        }
    }
}
