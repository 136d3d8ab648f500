//! The sensor (`perspective`, `thinlens`), its film (`hdrfilm`) and sampler, and the
//! integrator (`path`, `volpath`), mapped to ppm's camera and render defaults.

use super::unsupported;
use crate::fov::{focal_length_fov, vertical_fov, FovAxis};
use crate::mitsuba::props::Props;
use crate::mitsuba::tree::SceneTree;
use crate::LoadError;
use glam::DVec3;
use ppm_core::camera::Camera;
use ppm_core::integrator::MAX_DEPTH;
use ppm_core::pixel_bounds::PixelBounds;

/// Mitsuba's default film size.
const DEFAULT_FILM: (i64, i64) = (768, 576);

/// ppm's camera from a `<sensor type="perspective">` or `<sensor type="thinlens">`: the
/// position, view direction and up vector its `to_world` gives the camera's origin and +z and
/// +y axes, and the vertical field of view its `fov` and `fov_axis` (or `focal_length`) give
/// for the film's aspect ratio. A `thinlens` adds its `aperture_radius` (required, as in
/// Mitsuba) and `focus_distance` (Mitsuba's default: `far_clip`, itself 10^4 by default).
/// With it, the film's crop window ([`film_crop`]).
pub fn camera(
    tree: &SceneTree,
    index: usize,
    warnings: &mut Vec<String>,
) -> Result<(Camera, Option<PixelBounds>), LoadError> {
    let p = Props::new(tree, index);
    let thin_lens = match p.object.plugin.as_str() {
        "perspective" => false,
        "thinlens" => true,
        _ => return Err(unsupported(&tree.objects[index])),
    };
    let films = p.objects("film");
    let ((width, height), crop) = match films.first() {
        Some(&film) => film_size(tree, film, warnings)?,
        None => ((DEFAULT_FILM.0 as u32, DEFAULT_FILM.1 as u32), None),
    };
    for sampler in p.objects("sampler") {
        let s = Props::new(tree, sampler);
        s.ignore(&["seed"]);
        if let Some(n) = s.integer_opt("sample_count")? {
            warnings.push(format!(
                "{}: sampler `{}`: sample_count {n} is not used: ppm's -n sets the iterations, and its sampling is its own",
                s.location(),
                s.object.plugin
            ));
        }
        s.finish()?;
    }
    let aspect = width as f64 / height as f64;
    let vertical = sensor_vertical_fov(&p, aspect)?;
    let m = p.transform("to_world")?;
    let lens = if thin_lens {
        let radius = p
            .float_opt("aperture_radius")?
            .ok_or_else(|| p.error("sensor: thinlens needs `aperture_radius`"))?;
        let far_clip = p.float("far_clip", 1e4)?;
        let focus = p.float("focus_distance", far_clip)?;
        Some((radius, focus))
    } else {
        // Mitsuba 3's projective cameras all read `focus_distance` (default `far_clip`);
        // a pinhole has no lens to focus, so it changes nothing (many files of the field,
        // Mitsuba's own Cornell box among them, write it on a `perspective`).
        p.ignore(&["focus_distance"]);
        None
    };
    if p.get("near_clip").is_some() | p.get("far_clip").is_some() {
        warnings.push(format!(
            "{}: sensor: near_clip and far_clip are not used: ppm's camera does not clip",
            p.location()
        ));
    }
    p.ignore(&["shutter_open", "shutter_close", "srf"]);
    p.finish()?;
    let position = m.transform_point3(DVec3::ZERO);
    let forward = m.transform_vector3(DVec3::Z);
    let up = m.transform_vector3(DVec3::Y);
    let linear = glam::DMat3::from_mat4(m);
    if linear.determinant() <= 0.0 {
        return Err(tree.objects[index].location.error(
            "sensor: its to_world mirrors the image (negative determinant); ppm's camera cannot, rewrite it with a <lookat>",
        ));
    }
    let camera = Camera::new(
        position.as_vec3(),
        (position + forward).as_vec3(),
        up.as_vec3(),
        vertical as f32,
        (width, height),
    );
    // to_world's scale does not scale the lens: Mitsuba's thin lens takes its radius and
    // focus distance in world units.
    let camera = match (camera, lens) {
        (Ok(c), Some((radius, focus))) => c.with_lens(radius as f32, focus as f32),
        (camera, _) => camera,
    };
    camera
        .map(|c| (c, crop))
        .map_err(|e| tree.objects[index].location.error(format!("sensor: {e}")))
}

/// The vertical field of view, degrees, from `fov` + `fov_axis` (x, y, diagonal, smaller,
/// larger; default x) or `focal_length` (`50mm`: a 36 x 24 mm film's diagonal, Mitsuba's
/// default). With a = width / height and t = tan(fov / 2), tan(vertical / 2) is t / a (x),
/// t (y), t / sqrt(1 + a^2) (diagonal).
fn sensor_vertical_fov(p: &Props, aspect: f64) -> Result<f64, LoadError> {
    let fov = p.float_opt("fov")?;
    let focal = p.string_opt("focal_length")?;
    let axis_name = p.string_opt("fov_axis")?;
    let (fov, axis) = match (fov, focal) {
        (Some(_), Some(_)) => {
            return Err(p.error("sensor: give either `fov` or `focal_length`, not both"))
        }
        (Some(fov), None) => (fov, axis_name.unwrap_or("x").to_ascii_lowercase()),
        (None, focal) => {
            let f = focal.unwrap_or("50mm");
            let mm = f
                .trim()
                .trim_end_matches("mm")
                .parse::<f64>()
                .ok()
                .filter(|v| *v > 0.0 && v.is_finite())
                .ok_or_else(|| p.error(format!("sensor: focal_length `{f}` is not like `50mm`")))?;
            (focal_length_fov(mm), "diagonal".to_string())
        }
    };
    if !(fov > 0.0 && fov < 180.0) {
        return Err(p.error(format!("sensor: fov {fov} is not in (0, 180) degrees")));
    }
    let axis = match axis.as_str() {
        "smaller" if aspect > 1.0 => FovAxis::Y,
        "smaller" => FovAxis::X,
        "larger" if aspect > 1.0 => FovAxis::X,
        "larger" => FovAxis::Y,
        "x" => FovAxis::X,
        "y" => FovAxis::Y,
        "diagonal" => FovAxis::Diagonal,
        other => {
            return Err(p.error(format!(
                "sensor: fov_axis `{other}` is not x, y, diagonal, smaller or larger"
            )))
        }
    };
    Ok(vertical_fov(fov, axis, aspect))
}

/// The image size of an `hdrfilm` and its crop window; a reconstruction filter other than
/// `box` is a warning (ppm averages over each pixel).
fn film_size(
    tree: &SceneTree,
    index: usize,
    warnings: &mut Vec<String>,
) -> Result<((u32, u32), Option<PixelBounds>), LoadError> {
    let p = Props::new(tree, index);
    if p.object.plugin != "hdrfilm" {
        return Err(unsupported(&tree.objects[index]));
    }
    let width = p.integer("width", DEFAULT_FILM.0)?;
    let height = p.integer("height", DEFAULT_FILM.1)?;
    let side = |v: i64, name: &str| -> Result<u32, LoadError> {
        u32::try_from(v)
            .ok()
            .filter(|v| (1..=ppm_core::camera::MAX_RESOLUTION).contains(v))
            .ok_or_else(|| {
                p.error(format!(
                    "film: {name} {v} is not in [1, {}]",
                    ppm_core::camera::MAX_RESOLUTION
                ))
            })
    };
    let size = (side(width, "width")?, side(height, "height")?);
    let crop = film_crop(&p, size)?;
    for filter in p.objects("rfilter") {
        let f = Props::new(tree, filter);
        if f.object.plugin != "box" {
            warnings.push(format!(
                "{}: rfilter `{}` is not used: ppm averages each pixel's samples (a box filter)",
                f.location(),
                f.object.plugin
            ));
        }
        f.ignore(&["radius", "stddev", "lobes", "b", "c"]);
        f.finish()?;
    }
    p.ignore(&[
        "file_format",
        "pixel_format",
        "component_format",
        "banner",
        "high_quality_edges",
        "attach_log",
        "sample_border",
        "compensate",
    ]);
    p.finish()?;
    Ok((size, crop))
}

/// The film's crop window, as Mitsuba 3's `Film` reads it: `crop_offset_x`/`_y` (default 0)
/// and `crop_width`/`crop_height` (default the film's width and height, whatever the
/// offset), which must fit in the film (Mitsuba throws otherwise). Mitsuba's image is then
/// the crop's size, its pixels the full image's in the window; `None` without a crop.
fn film_crop(p: &Props, (width, height): (u32, u32)) -> Result<Option<PixelBounds>, LoadError> {
    let names = [
        "crop_offset_x",
        "crop_offset_y",
        "crop_width",
        "crop_height",
    ];
    let mut values = [None; 4];
    for (v, name) in values.iter_mut().zip(names) {
        *v = p.integer_opt(name)?;
        if let Some(x) = *v {
            if !(0..=i64::from(ppm_core::camera::MAX_RESOLUTION)).contains(&x) {
                return Err(p.error(format!("film: {name} {x} is not a number of pixels")));
            }
        }
    }
    if values.iter().all(Option::is_none) {
        return Ok(None);
    }
    let [x, y, w, h] = values;
    let (x, y) = (x.unwrap_or(0), y.unwrap_or(0));
    let (w, h) = (w.unwrap_or(width.into()), h.unwrap_or(height.into()));
    if w == 0 || h == 0 || x + w > i64::from(width) || y + h > i64::from(height) {
        return Err(p.error(format!(
            "film: the crop window (offset {x}, {y}, size {w} x {h}) is not inside the {width} x {height} film (Mitsuba: crop_offset + crop_size must not exceed the size, and crop_width/crop_height default to the film's width/height)"
        )));
    }
    crate::crop::window(
        [x as u32, (x + w) as u32, y as u32, (y + h) as u32],
        (width, height),
    )
    .map(Some)
    .map_err(|m| p.error(format!("film: crop window {m}")))
}

/// ppm's `max_depth` from the scene's integrator: Mitsuba counts the segments of a path
/// including the one that leaves the camera, so its `max_depth` is ppm's plus one; -1
/// (unbounded, the default) is ppm's largest depth.
///
/// The integrators whose converged image is that of `path` (in the scenes ppm loads, which
/// have no media) are read silently: `path`, `volpath`, `volpathmis`, `prb`, `ptracer` and
/// 0.6's `bdpt`; ppm's algorithm is chosen with `-a`. `direct` (emission and one bounce) is
/// `max_depth` 2. 0.6's photon mappers (`photonmapper`, `ppm`, `sppm`) give their depth with
/// a warning that their photon counts and radii are ppm's own settings. The others (`aov`,
/// `depth`, `moment`, ...) render something else: an error.
pub fn max_depth(
    tree: &SceneTree,
    index: usize,
    warnings: &mut Vec<String>,
) -> Result<u32, LoadError> {
    let p = Props::new(tree, index);
    let depth = match p.object.plugin.as_str() {
        "path" | "volpath" | "volpathmis" | "prb" | "ptracer" | "bdpt" => {
            p.ignore(&["light_image", "sample_direct"]);
            p.integer("max_depth", -1)?
        }
        "direct" => {
            p.ignore(&["emitter_samples", "bsdf_samples", "shading_samples"]);
            2
        }
        "photonmapper" | "ppm" | "sppm" => {
            const SETTINGS: [&str; 10] = [
                "photon_count",
                "initial_radius",
                "alpha",
                "granularity",
                "global_photons",
                "caustic_photons",
                "volume_photons",
                "global_lookup_radius",
                "caustic_lookup_radius",
                "lookup_size",
            ];
            if SETTINGS.iter().any(|n| p.get(n).is_some()) {
                warnings.push(format!(
                    "{}: integrator `{}`: its photon counts and radii are not used: ppm's are set by -a, --photons and --radius",
                    p.location(),
                    p.object.plugin
                ));
            }
            p.ignore(&SETTINGS);
            p.integer("max_depth", -1)?
        }
        _ => return Err(unsupported(&tree.objects[index])),
    };
    if p.integer_opt("rr_depth")?.is_some() {
        warnings.push(format!(
            "{}: integrator: rr_depth is not used: ppm's Russian roulette is its own",
            p.location()
        ));
    }
    if p.boolean("hide_emitters", false)? {
        return Err(p.error("integrator: hide_emitters is not supported yet"));
    }
    p.ignore(&["samples_per_pass", "timeout"]);
    let location = p.location().clone();
    p.finish()?;
    match depth {
        -1 => Ok(MAX_DEPTH),
        d if d < 1 => Err(location.error(format!(
            "integrator: max_depth {d} renders nothing (use -1 for unbounded, or 1 for the lights alone)"
        ))),
        d => {
            let ppm = (d - 1) as u64;
            if ppm > MAX_DEPTH as u64 {
                warnings.push(format!(
                    "{location}: integrator: max_depth {d} is above the supported {} bounces; using {MAX_DEPTH}",
                    MAX_DEPTH + 1
                ));
            }
            Ok(ppm.min(MAX_DEPTH as u64) as u32)
        }
    }
}
