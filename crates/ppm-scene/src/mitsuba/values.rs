//! The text of attribute values: numbers, colours and spectra as Mitsuba writes them.

use super::tree::Spectrum;
use glam::DVec3;

/// A finite number.
pub fn parse_number(s: &str) -> Option<f64> {
    s.trim().parse::<f64>().ok().filter(|v| v.is_finite())
}

/// Numbers separated by commas and/or white space.
pub fn parse_numbers(s: &str) -> Option<Vec<f64>> {
    s.split(|c: char| c == ',' || c.is_whitespace())
        .filter(|t| !t.is_empty())
        .map(parse_number)
        .collect()
}

/// Three numbers, or one for all three.
pub fn parse_triple(s: &str) -> Option<DVec3> {
    match parse_numbers(s)?.as_slice() {
        [v] => Some(DVec3::splat(*v)),
        [x, y, z] => Some(DVec3::new(*x, *y, *z)),
        _ => None,
    }
}

/// `#rrggbb` as three values in [0, 1] (still sRGB-encoded).
pub fn parse_hex_colour(s: &str) -> Option<DVec3> {
    let hex = s.trim().strip_prefix('#')?;
    if hex.len() != 6 || !hex.is_ascii() {
        return None;
    }
    let channel = |i: usize| u8::from_str_radix(&hex[2 * i..2 * i + 2], 16).ok();
    Some(DVec3::new(channel(0)? as f64, channel(1)? as f64, channel(2)? as f64) / 255.0)
}

/// The sRGB transfer function's inverse (IEC 61966-2-1).
pub fn srgb_to_linear(v: f64) -> f64 {
    if v <= 0.04045 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

/// `0.5` (uniform) or `400:0.1, 500:0.5, ...` (wavelengths increasing, in nm).
pub fn parse_spectrum(s: &str) -> Result<Spectrum, String> {
    if !s.contains(':') {
        return match parse_numbers(s).as_deref() {
            Some([v]) => Ok(Spectrum::Uniform(*v)),
            _ => Err("expected one value or wavelength:value pairs".into()),
        };
    }
    let mut samples = Vec::new();
    for pair in s.split(',').map(str::trim).filter(|p| !p.is_empty()) {
        let (l, v) = pair
            .split_once(':')
            .ok_or_else(|| format!("`{pair}` is not wavelength:value"))?;
        let (l, v) = parse_number(l)
            .zip(parse_number(v))
            .ok_or_else(|| format!("`{pair}` is not two numbers"))?;
        if samples
            .last()
            .is_some_and(|&(last, _): &(f64, f64)| l <= last)
        {
            return Err(format!("wavelength {l} does not increase"));
        }
        samples.push((l, v));
    }
    if samples.is_empty() {
        return Err("no wavelength:value pairs".into());
    }
    Ok(Spectrum::Samples(samples))
}
