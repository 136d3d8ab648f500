//! The sRGB transfer function (IEC 61966-2-1), for 8-bit images stored in sRGB.

/// The linear value of an sRGB-encoded value `c` in [0, 1] (IEC 61966-2-1):
/// `c / 12.92` for `c <= 0.04045`, else `((c + 0.055) / 1.055)^2.4`.
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Values by hand from the standard's formula; the two branches meet at 0.04045.
    #[test]
    fn srgb_decodes_by_the_standard() {
        assert_eq!(srgb_to_linear(0.0), 0.0);
        assert!((srgb_to_linear(1.0) - 1.0).abs() < 1e-6);
        // 0.5: ((0.5 + 0.055) / 1.055)^2.4 = 0.21404.
        assert!((srgb_to_linear(0.5) - 0.214_041).abs() < 1e-5);
        // 128 / 255 = 0.50196: 0.21586 (the value Mitsuba and every decoder give).
        assert!((srgb_to_linear(128.0 / 255.0) - 0.215_861).abs() < 1e-5);
        // 10 / 255 = 0.0392 is on the linear segment: 0.0030353.
        assert!((srgb_to_linear(10.0 / 255.0) - 0.003_035_3).abs() < 1e-7);
        let below = srgb_to_linear(0.04045);
        let above = srgb_to_linear(0.040_451);
        assert!((above - below).abs() < 1e-6, "{below} {above}");
    }
}
