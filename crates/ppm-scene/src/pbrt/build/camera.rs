//! `Camera "perspective"` and `Film` to ppm's pinhole camera, and the world mirror that makes
//! pbrt's left-handed camera render unmirrored.
//!
//! # Handedness
//! pbrt-v4's raster x grows with camera-space +x (`cameras.h`, `NDCFromScreen` and
//! `rasterFromNDC`: x = res.x (s.x - min.x) / (max.x - min.x), y flipped), camera +y is up
//! and the camera looks down +z. So the image's right is world-from-camera applied to +x, and
//! `LookAt` makes that right = normalize(up x dir) (`transform.cpp`): for a right-handed
//! world, the mirror of what a right-handed camera (ppm's, Mitsuba's: right = dir x up)
//! shows. Scenes exported from right-handed tools therefore start with `Scale -1 1 1`.
//!
//! ppm's camera always has right = forward x up. When pbrt's image right agrees (world-from-
//! camera has a negative determinant, as after `Scale -1 1 1`) the camera maps directly;
//! otherwise the whole world is mirrored through the plane that holds the camera's position,
//! view direction and up vector, which leaves the camera in place and puts what pbrt shows
//! on the image's right on ppm's right: the same picture, pixel for pixel. The mirror is one
//! matrix left-multiplied into every transform of the scene (shapes, lights).

use super::super::params::ParamSet;
use super::super::scene::Description;
use super::super::Loc;
use crate::LoadError;
use glam::{DMat3, DMat4, DVec3};
use ppm_core::camera::{Camera, MAX_RESOLUTION};
use ppm_core::pixel_bounds::PixelBounds;
use std::path::Path;
use std::sync::Arc;

/// pbrt-v4's default film size.
const DEFAULT_FILM: (i64, i64) = (1280, 720);

/// ppm's camera for the scene, the world mirror (identity or a reflection) to apply to
/// every world-space transform, and the film's crop window.
pub fn camera(
    desc: &Description,
    path: &Path,
    warnings: &mut Vec<String>,
) -> Result<(Camera, DMat4, Option<PixelBounds>), LoadError> {
    let ((width, height), crop) = film(desc, warnings)?;
    let default_loc = Loc {
        file: Arc::from(path),
        line: 0,
        column: 0,
    };
    // No Camera directive: pbrt-v4's default perspective camera at the origin.
    let (params, camera_from_world) = match &desc.camera {
        Some((e, m)) => (
            ParamSet::new(
                format!("Camera \"{}\"", e.kind),
                e.loc.clone(),
                &e.params,
                &[],
            ),
            *m,
        ),
        None => (
            ParamSet::new("Camera".into(), default_loc, &[], &[]),
            DMat4::IDENTITY,
        ),
    };
    if let Some((e, _)) = &desc.camera {
        if e.kind != "perspective" {
            return Err(params.error("not supported yet (only perspective is)"));
        }
    }
    // The thin lens (pbrt-v4 `CameraBase`/`PerspectiveCamera::Create`): aperture radius
    // `lensradius` (default 0, the pinhole) focused at `focaldistance` (default 10^6), both
    // in camera space.
    let lens_radius = params.float("lensradius", 0.0)?;
    let focal_distance = params.float("focaldistance", 1e6)?;
    params.ignore(&["shutteropen", "shutterclose"]);
    if params.has("screenwindow") {
        params.get("screenwindow");
        return Err(params.error("screenwindow is not supported yet"));
    }
    let aspect = width as f64 / height as f64;
    if let Some(frame) = params.float_opt("frameaspectratio")? {
        if (frame - aspect).abs() > 1e-6 * aspect {
            return Err(params.error(format!(
                "frameaspectratio {frame} differs from the film's {aspect}: non-square pixels are not supported"
            )));
        }
    }
    let fov = params.float("fov", 90.0)?;
    if !(fov > 0.0 && fov < 180.0) {
        return Err(params.error(format!("fov {fov} is not in (0, 180) degrees")));
    }
    params.finish()?;
    // pbrt's screen window spans [-1, 1] along the shorter image axis, which `fov` covers
    // (`PerspectiveCamera::Create`): for a tall image the vertical extent is 1 / aspect.
    let vertical = if aspect > 1.0 {
        fov
    } else {
        2.0 * ((fov.to_radians() * 0.5).tan() / aspect)
            .atan()
            .to_degrees()
    };

    let world_from_camera = camera_from_world.inverse();
    let linear = DMat3::from_mat4(world_from_camera);
    let axes = [linear.x_axis, linear.y_axis, linear.z_axis];
    let s = axes[0].length();
    let similar = s > 0.0
        && s.is_finite()
        && axes.iter().all(|a| (a.length() - s).abs() <= 1e-6 * s)
        && axes[0].dot(axes[1]).abs() <= 1e-6 * s * s
        && axes[1].dot(axes[2]).abs() <= 1e-6 * s * s
        && axes[0].dot(axes[2]).abs() <= 1e-6 * s * s;
    if !similar {
        return Err(params.error(
            "the camera transform scales unevenly or shears (the image would be stretched); not supported",
        ));
    }
    let position = world_from_camera.transform_point3(DVec3::ZERO);
    let forward = axes[2].normalize();
    let up = axes[1].normalize();
    let pbrt_right = axes[0].normalize();
    let ppm_right = forward.cross(up);
    let mirror = if ppm_right.dot(pbrt_right) > 0.0 {
        DMat4::IDENTITY
    } else {
        reflection(position, ppm_right)
    };
    // pbrt generates the lens ray in camera space and maps it to the world, so a camera
    // transform of uniform scale s scales the aperture and the focus distance by s; the
    // world mirror keeps distances, so it changes neither.
    let camera = Camera::new(
        position.as_vec3(),
        (position + forward).as_vec3(),
        up.as_vec3(),
        vertical as f32,
        (width, height),
    )
    .and_then(|c| c.with_lens((lens_radius * s) as f32, (focal_distance * s) as f32))
    .map_err(|e| params.error(e))?;
    Ok((camera, mirror, crop))
}

/// The reflection through the plane containing `point` with unit normal `n`:
/// p -> p - 2 n (n . (p - point)).
fn reflection(point: DVec3, n: DVec3) -> DMat4 {
    let h = DMat3::IDENTITY - 2.0 * DMat3::from_cols(n * n.x, n * n.y, n * n.z);
    let t = 2.0 * n * n.dot(point);
    DMat4::from_cols(
        h.x_axis.extend(0.0),
        h.y_axis.extend(0.0),
        h.z_axis.extend(0.0),
        t.extend(1.0),
    )
}

/// The image size of the `Film` (`rgb`, `gbuffer` or `spectral`: ppm writes RGB) and its
/// crop window.
fn film(
    desc: &Description,
    warnings: &mut Vec<String>,
) -> Result<((u32, u32), Option<PixelBounds>), LoadError> {
    let Some(e) = &desc.film else {
        return Ok(((DEFAULT_FILM.0 as u32, DEFAULT_FILM.1 as u32), None));
    };
    let p = ParamSet::new(
        format!("Film \"{}\"", e.kind),
        e.loc.clone(),
        &e.params,
        &[],
    );
    if !matches!(e.kind.as_str(), "rgb" | "gbuffer" | "spectral") {
        return Err(p.error("not supported yet"));
    }
    let side = |name: &str, default: i64| -> Result<u32, LoadError> {
        let v = p.int(name, default)?;
        u32::try_from(v)
            .ok()
            .filter(|v| (1..=MAX_RESOLUTION).contains(v))
            .ok_or_else(|| p.error(format!("{name} {v} is not in [1, {MAX_RESOLUTION}]")))
    };
    let size = (
        side("xresolution", DEFAULT_FILM.0)?,
        side("yresolution", DEFAULT_FILM.1)?,
    );
    if let Some(name) = p.string_opt("filename")? {
        warnings.push(format!(
            "{}: Film: filename \"{name}\" is not used: ppm writes where -o says",
            e.loc
        ));
    }
    let crop = film_crop(&p, size, warnings)?;
    // The sensor's imaging ratio exposuretime * iso / 100 scales the image (pbrt-v4
    // `PixelSensor`); only the default 1 is supported.
    let iso = p.float("iso", 100.0)?;
    let exposure = p.float("exposuretime", 1.0)?;
    if (iso * exposure - 100.0).abs() > 1e-9 {
        return Err(p.error(format!(
            "iso {iso} x exposuretime {exposure} scales the image; only the default (iso 100, exposure 1) is supported"
        )));
    }
    if p.float("whitebalance", 0.0)? != 0.0 {
        return Err(p.error("whitebalance is not supported yet"));
    }
    if let Some(sensor) = p.string_opt("sensor")? {
        if sensor != "cie1931" {
            return Err(p.error(format!("sensor \"{sensor}\" is not supported yet")));
        }
    }
    if p.has("maxcomponentvalue") {
        p.get("maxcomponentvalue");
        warnings.push(format!(
            "{}: Film: maxcomponentvalue is not used: ppm never clamps samples",
            e.loc
        ));
    }
    p.ignore(&["savefp16", "diagonal", "writefp16"]);
    p.finish()?;
    Ok((size, crop))
}

/// The film's crop: `pixelbounds` (x0 x1 y0 y1, pixels) or `cropwindow` (x0 x1 y0 y1,
/// fractions rounded up to pixels), the `cropwindow` winning when both are given, as in
/// pbrt-v4 (`FilmBaseParameters`). pbrt clamps a window that leaves the image; ppm refuses it.
fn film_crop(
    p: &ParamSet,
    size: (u32, u32),
    warnings: &mut Vec<String>,
) -> Result<Option<PixelBounds>, LoadError> {
    let pixels = p.ints("pixelbounds")?;
    let fractions = p.floats("cropwindow")?;
    if let (Some(_), Some(_)) = (&pixels, fractions) {
        warnings.push(format!(
            "{}: Film: pixelbounds is not used: cropwindow is given too, and wins (as in pbrt-v4)",
            p.loc
        ));
    }
    if let Some(c) = fractions {
        let &[x0, x1, y0, y1] = c else {
            return Err(p.error(format!("cropwindow has {} values, expected 4", c.len())));
        };
        return crate::crop::fraction_window([x0, x1, y0, y1], size)
            .map(Some)
            .map_err(|m| p.error(format!("cropwindow {m}")));
    }
    if let Some(b) = pixels {
        let &[x0, x1, y0, y1] = b.as_slice() else {
            return Err(p.error(format!("pixelbounds has {} values, expected 4", b.len())));
        };
        let edge = |e: i64| u32::try_from(e).unwrap_or(u32::MAX);
        return crate::crop::window([edge(x0), edge(x1), edge(y0), edge(y1)], size)
            .map(Some)
            .map_err(|m| p.error(format!("pixelbounds {m}")));
    }
    Ok(None)
}
