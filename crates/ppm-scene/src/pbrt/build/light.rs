//! `LightSource` (point, spot, distant, infinite with a constant `L` or an equal-area image) and `AreaLightSource "diffuse"` to ppm's lights and
//! emission. Colours follow pbrt-v4's photometric normalisation (`spectrum.rs`): an `rgb`
//! emission renders as that RGB, times `scale`; `power` (point, spot, area) and
//! `illuminance` (distant) rescale as pbrt-v4's `*Light::Create` do, by the normalised
//! spectrum's luminance-free k_e (so an RGB's own luminance is not divided out, as in
//! pbrt-v4).

use super::super::params::ParamSet;
use super::super::parse::resolve;
use super::super::scene::{Entity, LightEntity};
use super::super::spectrum;
use crate::LoadError;
use glam::{DMat3, DMat4, DVec3};
use ppm_core::light::{EnvironmentLight, EnvironmentMap, Light, PointLight};
use ppm_core::scene::SceneBuilder;
use std::f64::consts::PI;
use std::path::Path;
use std::sync::Arc;

/// The emission `name` of a light (default: the colour space's white, sRGB (1, 1, 1)),
/// times `scale`.
fn emission(p: &ParamSet, name: &str) -> Result<DVec3, LoadError> {
    let rgb = match p.spectrum(name)? {
        None => DVec3::ONE,
        Some((v, param)) => spectrum::illuminant_rgb(&v).map_err(|e| p.error_at(param, e))?,
    };
    let scale = p.float("scale", 1.0)?;
    if !(scale >= 0.0 && scale.is_finite()) {
        return Err(p.error(format!("scale {scale} is negative")));
    }
    Ok(rgb * scale)
}

/// A positive `power`-like parameter, if given (pbrt-v4 ignores values <= 0).
fn target(p: &ParamSet, name: &str) -> Result<Option<f64>, LoadError> {
    Ok(p.float_opt(name)?.filter(|&v| v > 0.0))
}

fn finite(p: &ParamSet, c: DVec3) -> Result<glam::Vec3, LoadError> {
    let c32 = c.as_vec3();
    if !c32.is_finite() {
        return Err(p.error("the emission is out of single-precision range"));
    }
    Ok(c32)
}

/// A light's world-space point, finite in single precision.
fn place(p: &ParamSet, m: DMat4, name: &str, default: DVec3) -> Result<DVec3, LoadError> {
    let x = m.transform_point3(p.point3(name, default)?);
    if !x.as_vec3().is_finite() {
        return Err(p.error(format!(
            "`{name}` is out of single-precision range in the world"
        )));
    }
    Ok(x)
}

/// Adds one `LightSource`; `mirror` is the world mirror of `camera.rs`; image files are
/// looked up beside the file that names them, else in `main_folder`.
pub fn add_light(
    light: &LightEntity,
    mirror: DMat4,
    main_folder: &Path,
    builder: &mut SceneBuilder,
) -> Result<(), LoadError> {
    let e = &light.entity;
    let p = ParamSet::new(
        format!("LightSource \"{}\"", e.kind),
        e.loc.clone(),
        &e.params,
        &light.defaults,
    );
    let m = mirror * light.ctm;
    match e.kind.as_str() {
        // Intensity I (W/sr) at `from`; power P gives I = P / (4 pi) per unit spectrum.
        "point" => {
            let mut intensity = emission(&p, "I")?;
            if let Some(power) = target(&p, "power")? {
                intensity *= power / (4.0 * PI);
            }
            let position = place(&p, m, "from", DVec3::ZERO)?;
            p.finish()?;
            builder.add_point_light(PointLight {
                position: position.as_vec3(),
                intensity: finite(&p, intensity)?,
            });
        }
        // pbrt-v4's spot: intensity I on the axis `from` -> `to`, smoothstep falloff from
        // coneangle - conedeltaangle to coneangle; power P gives I = P / k_e with
        // k_e = 2 pi ((1 - cos start) + (cos start - cos end) / 2).
        "spot" => {
            let mut intensity = emission(&p, "I")?;
            let cone = p.float("coneangle", 30.0)?;
            let delta = p.float("conedeltaangle", 5.0)?;
            if !(cone > 0.0 && cone <= 180.0 && delta >= 0.0 && delta <= cone) {
                return Err(p.error(format!(
                    "coneangle {cone} and conedeltaangle {delta}: expected 0 < coneangle <= 180 and 0 <= conedeltaangle <= coneangle"
                )));
            }
            let (end, start) = (cone.to_radians(), (cone - delta).to_radians());
            if let Some(power) = target(&p, "power")? {
                let k_e = 2.0 * PI * ((1.0 - start.cos()) + (start.cos() - end.cos()) / 2.0);
                intensity *= power / k_e;
            }
            let from = place(&p, m, "from", DVec3::ZERO)?;
            let to = place(&p, m, "to", DVec3::Z)?;
            p.finish()?;
            let light = Light::spot(
                from.as_vec3(),
                (to - from).as_vec3(),
                finite(&p, intensity)?,
                end as f32,
                start as f32,
            )
            .ok_or_else(|| p.error("from equals to"))?;
            builder.add_light(light);
        }
        // Radiance L arriving from `from` - `to` (light travels from -> to): irradiance
        // scale L on a surface facing it; `illuminance` E multiplies it by E.
        "distant" => {
            let mut irradiance = emission(&p, "L")?;
            if let Some(e_v) = target(&p, "illuminance")? {
                irradiance *= e_v / PI;
            }
            let from = place(&p, m, "from", DVec3::ZERO)?;
            let to = place(&p, m, "to", DVec3::Z)?;
            p.finish()?;
            let light = Light::directional((to - from).as_vec3(), finite(&p, irradiance)?)
                .ok_or_else(|| p.error("from equals to"))?;
            builder.add_light(light);
        }
        // A constant environment: radiance L from every direction, times `scale`; pbrt-v4
        // (`UniformInfiniteLight`, `Light::Create`) rescales it by E / k_e for an
        // `illuminance` E, with k_e = pi the irradiance unit radiance gives an upward
        // surface (the integral of cos theta over the hemisphere).
        //
        // With a `filename`: pbrt-v4's `ImageInfiniteLight`, an equal-area octahedral image
        // (`equal_area.rs` in ppm-core) whose texels are RGB radiance times `scale`, looked
        // up by the light-space direction toward the light (the light's transform, with the
        // world mirror, turns it into the world).
        "infinite" if p.has("filename") => {
            let name = p.string_opt("filename")?.unwrap_or_default();
            if p.has("L") {
                return Err(p.error("L and filename together: pbrt-v4 takes one or the other"));
            }
            if p.has("portal") {
                p.get("portal");
                return Err(p.error("portal is not supported yet"));
            }
            if p.has("illuminance") {
                p.get("illuminance");
                return Err(
                    p.error("illuminance with an image map is not supported yet (scale is)")
                );
            }
            let scale = p.float("scale", 1.0)?;
            if !(scale >= 0.0 && scale.is_finite()) {
                return Err(p.error(format!("scale {scale} is negative")));
            }
            let path = resolve(name, &e.loc, main_folder);
            p.finish()?;
            let map = crate::radiance_map::read_equal_area_map(&path)
                .map_err(|why| p.error(format!("filename \"{}\": {why}", path.display())))?;
            let to_world = DMat3::from_mat4(m);
            let orthonormal = (to_world.transpose() * to_world).abs_diff_eq(DMat3::IDENTITY, 1e-6);
            if !orthonormal {
                return Err(p.error(
                    "the light's transform scales or shears: an environment can only be turned (or mirrored)",
                ));
            }
            let light = EnvironmentLight::new(
                EnvironmentMap::EqualArea(Arc::new(map)),
                scale as f32,
                to_world.as_mat3(),
            )
            .ok_or_else(|| p.error("not a valid environment light"))?;
            builder.add_light(Light::Environment(light));
        }
        "infinite" => {
            if p.has("portal") {
                p.get("portal");
                return Err(p.error("portal is not supported yet"));
            }
            let mut radiance = emission(&p, "L")?;
            if let Some(e_v) = target(&p, "illuminance")? {
                radiance *= e_v / PI;
            }
            p.finish()?;
            let light = EnvironmentLight::new(
                EnvironmentMap::Constant(finite(&p, radiance)?),
                1.0,
                glam::Mat3::IDENTITY,
            )
            .ok_or_else(|| p.error("not a valid environment light"))?;
            builder.add_light(Light::Environment(light));
        }
        _ => {
            return Err(p.error(
                "light type not supported yet (point, spot, distant, infinite and area lights are)",
            ))
        }
    }
    Ok(())
}

/// The radiance of an `AreaLightSource "diffuse"` on a shape of world-space `area`:
/// L times `scale`, or scaled to `power` P as pbrt-v4 does, L P / (pi area). One-sided, on
/// the side the shape's normal faces, as pbrt-v4's default.
pub fn area_radiance(e: &Entity, area: f64) -> Result<glam::Vec3, LoadError> {
    let p = ParamSet::new(
        format!("AreaLightSource \"{}\"", e.kind),
        e.loc.clone(),
        &e.params,
        &[],
    );
    if e.kind != "diffuse" {
        return Err(p.error("not supported yet (only diffuse is)"));
    }
    if p.bool("twosided", false)? {
        return Err(p.error(
            "twosided area lights are not supported yet (ppm's area lights emit on the side the normal faces)",
        ));
    }
    if p.string_opt("filename")?.is_some() {
        return Err(p.error("image area lights (filename) are not supported yet"));
    }
    let mut le = emission(&p, "L")?;
    if let Some(power) = target(&p, "power")? {
        if area.is_nan() || area <= 0.0 {
            return Err(p.error("power given for a shape of no area"));
        }
        le *= power / (PI * area);
    }
    p.finish()?;
    finite(&p, le)
}
