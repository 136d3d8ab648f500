//! Fresnel reflectance of a smooth dielectric interface.

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
