//! The sRGB transfer curve (IEC 61966-2-1) and the 8-bit encoding of linear values: how the
//! PNG of a render is made from its linear image, and how a PNG is read back as linear.

use ppm_core::film::Image;

/// The sRGB opto-electronic transfer function (IEC 61966-2-1): linear [0, 1] to encoded [0, 1].
pub fn srgb_oetf(linear: f32) -> f32 {
    if linear <= 0.003_130_8 {
        12.92 * linear
    } else {
        1.055 * linear.powf(1.0 / 2.4) - 0.055
    }
}

/// The inverse of [`srgb_oetf`]: encoded [0, 1] to linear.
pub fn srgb_eotf(encoded: f32) -> f32 {
    if encoded <= 0.040_45 {
        encoded / 12.92
    } else {
        ((encoded + 0.055) / 1.055).powf(2.4)
    }
}

/// A linear value as an 8-bit sRGB code: clamped to [0, 1] (NaN to 0), encoded, rounded.
pub fn encode_srgb8(linear: f32) -> u8 {
    let v = if linear.is_nan() {
        0.0
    } else {
        linear.clamp(0.0, 1.0)
    };
    (srgb_oetf(v) * 255.0 + 0.5) as u8
}

/// An image as interleaved 8-bit sRGB.
pub fn to_srgb8(image: &Image) -> Vec<u8> {
    image
        .pixels
        .iter()
        .flat_map(|p| p.to_array().map(encode_srgb8))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_encoding_values() {
        assert_eq!(encode_srgb8(0.0), 0);
        // The linear segment ends at 0.0031308 -> 0.040450 -> 10.31 of 255.
        assert!((srgb_oetf(0.003_130_8) - 0.040_45).abs() < 1e-6);
        assert_eq!(encode_srgb8(0.003_130_8), 10);
        // 1.055 * 0.5^(1/2.4) - 0.055 = 0.735357 -> 187.52 of 255.
        assert!((srgb_oetf(0.5) - 0.735_357).abs() < 1e-5);
        assert_eq!(encode_srgb8(0.5), 188);
        assert_eq!(encode_srgb8(1.0), 255);
        assert_eq!(encode_srgb8(7.5), 255);
        assert_eq!(encode_srgb8(-1.0), 0);
        assert_eq!(encode_srgb8(f32::NAN), 0);
        assert_eq!(encode_srgb8(f32::INFINITY), 255);
        // The two pieces meet: the curve is continuous at the break point.
        let below = srgb_oetf(0.003_130_8 - 1e-7);
        let above = srgb_oetf(0.003_130_8 + 1e-7);
        assert!((above - below).abs() < 1e-5);
        for code in 0..=255u8 {
            let linear = srgb_eotf(code as f32 / 255.0);
            assert_eq!(
                encode_srgb8(linear),
                code,
                "sRGB code {code} does not round-trip"
            );
        }
    }
}
