//! Spectra to linear sRGB, as Mitsuba 3's RGB variants convert them when they load a scene.
//!
//! - A uniform value v is the grey (v, v, v) for a reflectance; for an emitter it is
//!   v * M (1, 1, 1), M the XYZ-to-sRGB matrix: the colour of the equal-energy spectrum
//!   under sRGB's D65 white (slightly purple), which is what Mitsuba's RGB variants do so that
//!   they match its spectral ones.
//! - (wavelength, value) samples are interpolated linearly (zero outside their range) and
//!   integrated against the CIE 1931 colour-matching functions: for a reflectance under the
//!   D65 illuminant, XYZ = ∫ s D65 (x̄, ȳ, z̄) dλ / ∫ D65 ȳ dλ, clamped to [0, 1] after the
//!   conversion; for an emitter without it, XYZ = ∫ s (x̄, ȳ, z̄) dλ / ∫ ȳ dλ, negative
//!   components clamped to 0. Then RGB = M XYZ.
//! - A black body (emitters only) is Planck's law B(λ, T) = 2 h c^2 / λ^5 / (exp(h c / (λ k T)) - 1)
//!   in W m^-2 sr^-1 nm^-1, integrated as an emitter's samples: the radiance a spectral
//!   Mitsuba would see. Mitsuba 3's RGB variants leave it unimplemented.
//!
//! Integrals use the trapezoid rule on a 1 nm grid over [360, 830] nm with the tables
//! below interpolated linearly.

use super::tree::Spectrum;
use glam::{DMat3, DVec3};

/// How a spectrum is used, which decides its conversion (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    /// A reflectance or transmittance: bounded to [0, 1], seen under D65.
    Reflectance,
    /// An emitter's radiance or intensity: unbounded, no illuminant.
    Emission,
    /// A conductor's `eta` or `k`: converted as a reflectance (under D65) but not clamped,
    /// as Mitsuba 3's RGB variants do (they warn about the out-of-gamut colour and keep it).
    Index,
}

/// First wavelength of the tables, nm.
const LAMBDA_MIN: f64 = 360.0;
/// Table spacing, nm.
const STEP: f64 = 10.0;
/// Last wavelength, nm.
const LAMBDA_MAX: f64 = 830.0;

/// CIE 1931 2° standard observer colour-matching functions x̄, ȳ, z̄ at 10 nm from 360 to
/// 830 nm (CIE 015:2004, Colorimetry, 3rd ed., table T.4; every other row of the 5 nm table).
#[rustfmt::skip]
const CIE_XYZ: [[f64; 3]; 48] = [
    [0.0001299, 0.000003917, 0.0006061], [0.0004149, 0.00001239, 0.001946],
    [0.001368, 0.000039, 0.00645], [0.004243, 0.00012, 0.02005],
    [0.01431, 0.000396, 0.06785], [0.04351, 0.00121, 0.2074],
    [0.13438, 0.004, 0.6456], [0.2839, 0.0116, 1.3856],
    [0.34828, 0.023, 1.74706], [0.3362, 0.038, 1.77211],
    [0.2908, 0.06, 1.6692], [0.19536, 0.09098, 1.28764],
    [0.09564, 0.13902, 0.81295], [0.03201, 0.20802, 0.46518],
    [0.0049, 0.323, 0.272], [0.0093, 0.503, 0.1582],
    [0.06327, 0.71, 0.07825], [0.1655, 0.862, 0.04216],
    [0.2904, 0.954, 0.0203], [0.4334499, 0.9949501, 0.00875],
    [0.5945, 0.995, 0.0039], [0.7621, 0.952, 0.0021],
    [0.9163, 0.87, 0.00165], [1.0263, 0.757, 0.0011],
    [1.0622, 0.631, 0.0008], [1.0026, 0.503, 0.00034],
    [0.8544499, 0.381, 0.00019], [0.6424, 0.265, 0.00005],
    [0.4479, 0.175, 0.00002], [0.2835, 0.107, 0.0],
    [0.1649, 0.061, 0.0], [0.0874, 0.032, 0.0],
    [0.04677, 0.017, 0.0], [0.0227, 0.00821, 0.0],
    [0.01135916, 0.004102, 0.0], [0.005790346, 0.002091, 0.0],
    [0.002899327, 0.001047, 0.0], [0.001439971, 0.00052, 0.0],
    [0.0006900786, 0.0002492, 0.0], [0.0003323011, 0.00012, 0.0],
    [0.0001661505, 0.00006, 0.0], [0.00008307527, 0.00003, 0.0],
    [0.00004150994, 0.00001499, 0.0], [0.00002067383, 0.0000074657, 0.0],
    [0.00001025398, 0.0000037029, 0.0], [0.000005085868, 0.0000018366, 0.0],
    [0.000002522525, 0.00000091093, 0.0], [0.000001251141, 0.00000045181, 0.0],
];

/// CIE standard illuminant D65, relative spectral power (100 at 560 nm), 10 nm from 360 to
/// 830 nm (CIE 015:2004, table T.1).
#[rustfmt::skip]
const D65: [f64; 48] = [
    46.6383, 52.0891, 49.9755, 54.6482, 82.7549, 91.486, 93.4318, 86.6823, 104.865, 117.008,
    117.812, 114.861, 115.923, 108.811, 109.354, 107.802, 104.79, 107.689, 104.405, 104.046,
    100.0, 96.3342, 95.788, 88.6856, 90.0062, 89.5991, 87.6987, 83.2886, 83.6992, 80.0268,
    80.2146, 82.2778, 78.2842, 69.7213, 71.6091, 74.349, 61.604, 69.8856, 75.087, 63.5927,
    46.4182, 66.8054, 63.3828, 64.304, 59.4519, 51.959, 57.4406, 60.3125,
];

/// CIE XYZ to linear sRGB (IEC 61966-2-1, D65 white), row by row.
#[rustfmt::skip]
pub const XYZ_TO_SRGB: [f64; 9] = [
     3.2404542, -1.5371385, -0.4985314,
    -0.9692660,  1.8760108,  0.0415560,
     0.0556434, -0.2040259,  1.0572252,
];

/// `XYZ_TO_SRGB * xyz`.
pub fn xyz_to_srgb(xyz: DVec3) -> DVec3 {
    DMat3::from_cols_array(&XYZ_TO_SRGB).transpose() * xyz
}

/// A table of 48 rows at 10 nm, linearly interpolated at `lambda` in [360, 830].
fn lerp_table<T: Copy>(table: &[T; 48], lambda: f64, mix: impl Fn(T, T, f64) -> T) -> T {
    let t = ((lambda - LAMBDA_MIN) / STEP).clamp(0.0, 47.0);
    let i = (t as usize).min(46);
    mix(table[i], table[i + 1], t - i as f64)
}

/// The colour-matching functions at `lambda` nm.
pub fn cie_xyz(lambda: f64) -> DVec3 {
    let v = lerp_table(&CIE_XYZ, lambda, |a, b, f| {
        [0, 1, 2].map(|c| a[c] + (b[c] - a[c]) * f)
    });
    DVec3::from_array(v)
}

/// D65's relative power at `lambda` nm.
fn d65(lambda: f64) -> f64 {
    lerp_table(&D65, lambda, |a, b, f| a + (b - a) * f)
}

/// Planck's law: a black body's spectral radiance at `lambda` nm and `temperature` K, in
/// W m^-2 sr^-1 nm^-1.
pub fn planck(lambda: f64, temperature: f64) -> f64 {
    const H: f64 = 6.626_070_15e-34; // J s
    const C: f64 = 2.997_924_58e8; // m / s
    const K: f64 = 1.380_649e-23; // J / K
    let l = lambda * 1e-9;
    let per_metre = 2.0 * H * C * C / l.powi(5) / ((H * C / (l * K * temperature)).exp_m1());
    per_metre * 1e-9
}

/// Trapezoid rule of `f` over [360, 830] nm at 1 nm.
fn integrate(f: impl Fn(f64) -> DVec3) -> DVec3 {
    let n = (LAMBDA_MAX - LAMBDA_MIN) as usize;
    let mut sum = DVec3::ZERO;
    for i in 0..=n {
        let w = if i == 0 || i == n { 0.5 } else { 1.0 };
        sum += w * f(LAMBDA_MIN + i as f64);
    }
    sum
}

/// Linear interpolation of increasing (wavelength, value) samples, zero outside their range.
fn sampled(samples: &[(f64, f64)], lambda: f64) -> f64 {
    let (first, last) = (samples[0], samples[samples.len() - 1]);
    if lambda < first.0 || lambda > last.0 {
        return 0.0;
    }
    // One sample is a single wavelength: the value there (and zero elsewhere).
    if samples.len() == 1 {
        return first.1;
    }
    let i = samples
        .partition_point(|s| s.0 <= lambda)
        .clamp(1, samples.len() - 1);
    let (a, b) = (samples[i - 1], samples[i]);
    if b.0 <= a.0 {
        return b.1;
    }
    a.1 + (b.1 - a.1) * (lambda - a.0) / (b.0 - a.0)
}

/// The XYZ of the spectrum `s(λ)` for `role` (normalised as the module says).
fn spectrum_xyz(s: impl Fn(f64) -> f64, role: Role) -> DVec3 {
    match role {
        Role::Reflectance | Role::Index => {
            let norm = integrate(|l| DVec3::splat(d65(l) * cie_xyz(l).y)).y;
            integrate(|l| s(l) * d65(l) * cie_xyz(l)) / norm
        }
        Role::Emission => {
            let norm = integrate(|l| DVec3::splat(cie_xyz(l).y)).y;
            integrate(|l| s(l) * cie_xyz(l)) / norm
        }
    }
}

/// Linear sRGB of a spectrum used as `role`; `Err` says why it cannot be converted.
pub fn to_rgb(spectrum: &Spectrum, role: Role) -> Result<DVec3, String> {
    let rgb = match (spectrum, role) {
        (Spectrum::Uniform(v), Role::Reflectance | Role::Index) => return Ok(DVec3::splat(*v)),
        (Spectrum::Uniform(v), Role::Emission) => return Ok(*v * xyz_to_srgb(DVec3::ONE)),
        (Spectrum::Samples(samples), role) => {
            if samples.is_empty() {
                return Err("a spectrum needs at least one wavelength:value pair".into());
            }
            xyz_to_srgb(spectrum_xyz(|l| sampled(samples, l), role))
        }
        (Spectrum::Blackbody { .. }, Role::Reflectance | Role::Index) => {
            return Err("a blackbody spectrum is an emission, not a reflectance".into())
        }
        (Spectrum::Blackbody { temperature, scale }, Role::Emission) => {
            *scale * xyz_to_srgb(spectrum_xyz(|l| planck(l, *temperature), role))
        }
    };
    Ok(match role {
        Role::Reflectance => rgb.clamp(DVec3::ZERO, DVec3::ONE),
        Role::Emission | Role::Index => rgb.max(DVec3::ZERO),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_flat_reflectance_spectrum_is_white() {
        let s = Spectrum::Samples(vec![(360.0, 0.5), (830.0, 0.5)]);
        let rgb = to_rgb(&s, Role::Reflectance).unwrap();
        assert!(rgb.abs_diff_eq(DVec3::splat(0.5), 2e-3), "{rgb}");
    }

    #[test]
    fn interpolation_is_zero_outside_the_samples() {
        let s = [(400.0, 1.0), (500.0, 3.0)];
        assert_eq!(sampled(&s, 399.0), 0.0);
        assert_eq!(sampled(&s, 450.0), 2.0);
        assert_eq!(sampled(&s, 500.0), 3.0);
        assert_eq!(sampled(&[(550.0, 2.0)], 550.0), 2.0);
    }
}
