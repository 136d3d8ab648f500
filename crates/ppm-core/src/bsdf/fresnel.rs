//! Fresnel reflectance of smooth dielectric and conductor interfaces.

use glam::Vec3;

/// Unpolarised Fresnel reflectance of a smooth dielectric interface (Born & Wolf, sec. 1.5).
///
/// `cos_i` is the cosine between the incident direction and the interface normal, signed: positive
/// when the direction lies on the normal's side. `eta` is the relative index of refraction of the
/// side opposite the normal over the normal's side (e.g. glass of index 1.5 below a normal that
/// points into vacuum: `eta = 1.5`). A negative `cos_i` means the light arrives from the other side,
/// and the interface is seen with `1 / eta`.
///
/// With `eta_i` the index on the incident side and `eta_t` on the transmitted side:
/// ```text
/// r_par  = (eta_t cos_i - eta_i cos_t) / (eta_t cos_i + eta_i cos_t)
/// r_perp = (eta_i cos_i - eta_t cos_t) / (eta_i cos_i + eta_t cos_t)
/// F      = (r_par^2 + r_perp^2) / 2
/// ```
/// where Snell's law gives `sin_t = sin_i eta_i / eta_t`. Total internal reflection
/// (`sin_t >= 1`) returns exactly 1. The result is always in [0, 1].
#[inline]
pub fn fresnel_dielectric(cos_i: f32, eta: f32) -> f32 {
    let (cos_i, eta) = if cos_i < 0.0 {
        (-cos_i, 1.0 / eta)
    } else {
        (cos_i, eta)
    };
    let cos_i = cos_i.min(1.0);
    // Snell's law in relative form: sin_t = sin_i / eta, with eta = eta_t / eta_i.
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    // Both denominators are positive here: eta > 0, cos_t > 0 (sin2_t < 1).
    let r_par = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    (0.5 * (r_par * r_par + r_perp * r_perp)).clamp(0.0, 1.0)
}

/// Unpolarised Fresnel reflectance of a conductor of complex relative index `eta + i k`, per
/// channel (Born & Wolf, sec. 14.2; the same Fresnel equations with a complex index).
///
/// `cos_i` is the cosine of the incident direction with the normal, on the outside; values
/// outside [0, 1] are clamped. With the complex index n = eta + i k and
/// w = sqrt(n^2 - sin_i^2) (principal root, Re w >= 0):
/// ```text
/// r_perp = (cos_i - w) / (cos_i + w)
/// r_par  = (n^2 cos_i - w) / (n^2 cos_i + w)
/// F      = (|r_perp|^2 + |r_par|^2) / 2
/// ```
/// For k = 0 this is the dielectric reflectance of [`fresnel_dielectric`], total internal
/// reflection (eta < 1) included. Computed in f64: the two terms cancel near grazing angles.
#[inline]
pub fn fresnel_conductor(cos_i: f32, eta: Vec3, k: Vec3) -> Vec3 {
    let cos = (cos_i as f64).clamp(0.0, 1.0);
    let sin2 = 1.0 - cos * cos;
    let channel = |eta: f32, k: f32| -> f32 {
        let n2 = Complex::new(eta as f64, k as f64).square();
        let w = (n2 - Complex::new(sin2, 0.0)).sqrt();
        let c = Complex::new(cos, 0.0);
        let r_perp = (c - w).norm_sqr() / (c + w).norm_sqr();
        let n2c = n2 * cos;
        let r_par = (n2c - w).norm_sqr() / (n2c + w).norm_sqr();
        let f = 0.5 * (r_perp + r_par);
        // 0 / 0 only when cos = 0 and n^2 = 0 (eta = k = 0): a grazing ray is reflected whole.
        if f.is_finite() {
            f.clamp(0.0, 1.0) as f32
        } else {
            1.0
        }
    };
    Vec3::new(
        channel(eta.x, k.x),
        channel(eta.y, k.y),
        channel(eta.z, k.z),
    )
}

/// Hemispherical average of the dielectric Fresnel reflectance, 2 \int_0^1 F(mu) mu dmu, of an
/// interface of relative index `eta` seen from the side of index 1, by the polynomial fits
/// Mitsuba 3 uses: Egan & Hilgeman (1973) for eta < 1, d'Eon & Irving (2011, eq. 5 of their
/// quantized-diffusion paper) for eta >= 1. Relative error below 0.6% for eta in [0.5, 2].
/// Used by the smooth plastic, whose light bounces inside the coating (see `plastic.rs`).
pub fn fresnel_diffuse_reflectance(eta: f32) -> f32 {
    let inv = 1.0 / eta;
    if eta < 1.0 {
        0.0636 * inv + eta * (eta * -1.4399 + 0.7099) + 0.6681
    } else {
        // Horner form of 0.919317 - 3.4793 x + 6.75335 x^2 - 7.80989 x^3 + 4.98554 x^4
        // - 1.36881 x^5 in x = 1 / eta.
        let c = [0.919317, -3.4793, 6.75335, -7.80989, 4.98554, -1.36881f32];
        c.iter().rev().fold(0.0, |acc, &ci| acc * inv + ci)
    }
}

/// The few complex operations the conductor Fresnel term needs, in f64.
#[derive(Clone, Copy, Debug)]
struct Complex {
    re: f64,
    im: f64,
}

impl Complex {
    fn new(re: f64, im: f64) -> Self {
        Complex { re, im }
    }
    fn square(self) -> Self {
        Complex::new(
            self.re * self.re - self.im * self.im,
            2.0 * self.re * self.im,
        )
    }
    fn norm_sqr(self) -> f64 {
        self.re * self.re + self.im * self.im
    }
    /// Principal square root (non-negative real part).
    fn sqrt(self) -> Self {
        let r = self.norm_sqr().sqrt();
        let re = (0.5 * (r + self.re)).max(0.0).sqrt();
        let im = (0.5 * (r - self.re)).max(0.0).sqrt().copysign(self.im);
        Complex::new(re, im)
    }
}

impl std::ops::Add for Complex {
    type Output = Complex;
    fn add(self, o: Complex) -> Complex {
        Complex::new(self.re + o.re, self.im + o.im)
    }
}

impl std::ops::Sub for Complex {
    type Output = Complex;
    fn sub(self, o: Complex) -> Complex {
        Complex::new(self.re - o.re, self.im - o.im)
    }
}

impl std::ops::Mul<f64> for Complex {
    type Output = Complex;
    fn mul(self, s: f64) -> Complex {
        Complex::new(self.re * s, self.im * s)
    }
}
