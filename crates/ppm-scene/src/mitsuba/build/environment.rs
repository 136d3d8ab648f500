//! Mitsuba 3's environment emitters: `constant` (`radiance`, default 1) and `envmap`
//! (`filename`, `scale`, `to_world`), as ppm's environment light.
//!
//! # Mitsuba's lat-long map
//! Mitsuba 3 (`emitters/envmap.cpp`, checked against Mitsuba 3.9 itself with an asymmetric
//! map) looks a world direction d up as v = R^-1 d (R its `to_world`), u = atan2(v.x, -v.z)
//! / 2 pi (wrapped to [0, 1)), v = acos(v.y) / pi: the top row is +y, u = 0 looks along -z
//! and u = 1/4 along +x. That is ppm's frame (`envmap.rs` in ppm-core), so R carries over.
//! Mitsuba interpolates bilinearly: column j's centre is at u = (j + 1/2) / W (wrapping
//! around at u = 0), row i lies at v = i / (H - 1) (the first and last rows on the poles).
//! ppm's map is piecewise constant (texel i covers v in [i/H, (i+1)/H]), so the importer
//! resamples Mitsuba's interpolated function onto a map k times finer in each direction
//! (k = 4 for maps of up to 64 K texels, 2 up to 1 M, else 1), each texel the function at
//! its centre: the exact mean of a bilinear patch over a texel inside it, and with k even
//! the texel edges fall on Mitsuba's column centres, where its interpolation has kinks.
//! Its rows do not align (an O(texel^2) difference); a warning says so.

use super::super::props::Props;
use super::super::tree::SceneTree;
use super::emitter::emission;
use crate::radiance_map::{read_rgb, RgbImage};
use crate::LoadError;
use glam::{DMat3, DVec3, Mat3, Vec3};
use ppm_core::light::{EnvironmentLight, EnvironmentMap, LatLongMap, Light};
use ppm_core::scene::SceneBuilder;
use std::sync::Arc;

/// Adds the `constant` or `envmap` emitter at `index`.
pub(super) fn add(
    tree: &SceneTree,
    index: usize,
    builder: &mut SceneBuilder,
    warnings: &mut Vec<String>,
) -> Result<(), LoadError> {
    let p = Props::new(tree, index);
    let (map, scale, rotation) = match p.object.plugin.as_str() {
        "constant" => {
            let radiance = emission(&p, "radiance", Some(DVec3::ONE))?;
            (EnvironmentMap::Constant(radiance), 1.0, Mat3::IDENTITY)
        }
        _ => {
            let name = p
                .string_opt("filename")?
                .ok_or_else(|| p.error("emitter `envmap` needs a string `filename`"))?;
            let path = p.tree.resolve(&p.location().file, name);
            let image = read_rgb(&path)
                .map_err(|e| p.error(format!("emitter `envmap`: {}: {e}", path.display())))?;
            let scale = p.float("scale", 1.0)?;
            if !(scale.is_finite() && scale >= 0.0) {
                return Err(p.error(format!("emitter `envmap`: `scale` {scale} is negative")));
            }
            let rotation = rotation_of(&p)?;
            let (map, k) = resample(&image)
                .map_err(|e| p.error(format!("emitter `envmap`: {}: {e}", path.display())))?;
            let (w, h) = map.size();
            warnings.push(format!(
                "{}: emitter `envmap`: Mitsuba interpolates the {}x{} map bilinearly; ppm \
                 renders it resampled to {w}x{h} constant texels ({k}x{k} per texel)",
                p.location(),
                image.width,
                image.height
            ));
            (EnvironmentMap::Image(Arc::new(map)), scale as f32, rotation)
        }
    };
    p.finish()?;
    let light = EnvironmentLight::new(map, scale, rotation).ok_or_else(|| {
        tree.objects[index]
            .location
            .error("not a valid environment emitter")
    })?;
    builder.add_light(Light::Environment(light));
    Ok(())
}

/// The rotation of `to_world`: its linear part, which must be a rotation (times a positive
/// uniform scale, which directions ignore); a translation is ignored (the light is at
/// infinity).
fn rotation_of(p: &Props) -> Result<Mat3, LoadError> {
    let m = p.transform("to_world")?;
    let linear = DMat3::from_mat4(m);
    let s = linear.determinant().cbrt();
    let r = linear * (1.0 / s);
    if !(s > 0.0 && (r.transpose() * r).abs_diff_eq(DMat3::IDENTITY, 1e-6)) {
        return Err(p.error(
            "emitter `envmap`: `to_world` must be a rotation (a shear, mirror or unequal \
             scale turns an environment into no rotation ppm has)",
        ));
    }
    Ok(r.as_mat3())
}

/// Mitsuba's bilinear lookup of `image` at (u, v) (see the module documentation).
fn bilinear(image: &RgbImage, u: f64, v: f64) -> Vec3 {
    let (w, h) = (image.width, image.height);
    let x = u * w as f64 - 0.5;
    let y = if h > 1 { v * (h - 1) as f64 } else { 0.0 };
    let (x0, y0) = (x.floor(), y.floor().min((h.max(2) - 2) as f64).max(0.0));
    let (fx, fy) = ((x - x0) as f32, ((y - y0) as f32).clamp(0.0, 1.0));
    let col = |i: f64| (i as i64).rem_euclid(w as i64) as usize;
    let row = |i: f64| (i as usize).min(h - 1);
    let t = |r: usize, c: usize| image.texels[r * w + c];
    let (c0, c1, r0, r1) = (col(x0), col(x0 + 1.0), row(y0), row(y0 + 1.0));
    let top = t(r0, c0) * (1.0 - fx) + t(r0, c1) * fx;
    let bottom = t(r1, c0) * (1.0 - fx) + t(r1, c1) * fx;
    top * (1.0 - fy) + bottom * fy
}

/// The map resampled k times finer (see the module documentation), and k.
fn resample(image: &RgbImage) -> Result<(LatLongMap, usize), String> {
    let texels = image.width * image.height;
    if texels == 0 {
        return Err("the image is empty".into());
    }
    if let Some(t) = image
        .texels
        .iter()
        .find(|t| !t.is_finite() || t.min_element() < 0.0)
    {
        return Err(format!(
            "a texel is {t}: radiance must be finite and non-negative"
        ));
    }
    let k = if texels <= 1 << 16 {
        4
    } else if texels <= 1 << 20 {
        2
    } else {
        1
    };
    let (w, h) = (image.width * k, image.height * k);
    let out = (0..w * h)
        .map(|n| {
            let (j, i) = (n % w, n / w);
            bilinear(
                image,
                (j as f64 + 0.5) / w as f64,
                (i as f64 + 0.5) / h as f64,
            )
        })
        .collect();
    Ok((LatLongMap::new(w, h, out).map_err(|e| e.to_string())?, k))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Mitsuba 3.9's `envmap` evaluated on an 8 x 4 map whose texel (row i, column j) is
    /// (1 + j, 1 + i, 1), at these (u, v) (the values printed by Mitsuba itself).
    #[test]
    fn the_lookup_is_mitsubas() {
        let image = RgbImage {
            width: 8,
            height: 4,
            texels: (0..32)
                .map(|n| Vec3::new(1.0 + (n % 8) as f32, 1.0 + (n / 8) as f32, 1.0))
                .collect(),
        };
        for (u, v, r, g) in [
            (0.0, 0.5, 4.5, 2.5),
            (0.01, 0.5, 3.94, 2.5),
            (0.0625, 0.5, 1.0, 2.5),
            (0.125, 0.5, 1.5, 2.5),
            (0.3, 1.0, 2.9, 4.0),
            (0.3, 0.1, 2.9, 1.3),
            (0.3, 0.9, 2.9, 3.7),
            (0.0625, 0.125, 1.0, 1.375),
        ] {
            let c = bilinear(&image, u, v);
            assert!(
                (c.x - r).abs() < 1e-4 && (c.y - g).abs() < 1e-4,
                "({u}, {v}): {c} vs Mitsuba's ({r}, {g})"
            );
        }
    }
}
