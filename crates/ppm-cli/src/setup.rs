//! From command-line arguments to a scene and render settings: finding and loading the scene
//! file, the resolution, setting overrides and the thread pool.

use crate::args::SettingsArgs;
use anyhow::{bail, Context, Result};
use ppm_core::integrator::{
    bounded_depth, smallest_radius, Algorithm, Radius, RenderSettings, Setting, MAX_DEPTH,
};
use ppm_core::scene::Scene;
use std::path::{Path, PathBuf};

/// The scene file a command-line argument names (searched as described in
/// [`crate::scene_search`]), or an error naming every path tried. A path that exists but is
/// no regular file (a FIFO, /dev/zero, a symbolic-link loop) is reported as what it is, not
/// as "not found".
pub fn locate_scene(arg: &Path) -> Result<PathBuf> {
    locate_scene_found(arg).map(|(path, _)| path)
}

/// [`locate_scene`] with the rule that found the scene, in words (`as given`, `in
/// $PPM_SCENES`), for `-v`.
pub fn locate_scene_found(arg: &Path) -> Result<(PathBuf, &'static str)> {
    if std::fs::symlink_metadata(arg).is_ok() {
        match std::fs::metadata(arg) {
            Err(e) => bail!("cannot read scene file {}: {e}", arg.display()),
            Ok(meta) if !meta.is_file() && !meta.is_dir() => bail!(
                "scene file {} is {}, not a regular file",
                arg.display(),
                ppm_scene::obj::file_kind(&meta.file_type())
            ),
            Ok(_) => {}
        }
    }
    let folders = crate::scene_search::default_search_folders();
    if let Some((path, rule)) = crate::scene_search::find(arg, &folders) {
        if crate::bare_obj::is_obj(&path) {
            bail!("{}", crate::bare_obj::refusal(&path));
        }
        return Ok((path, rule));
    }
    if arg.is_dir() {
        bail!("scene {} is a folder, not a scene file", arg.display());
    }
    let tried: Vec<String> = crate::scene_search::candidates(arg, &folders)
        .iter()
        .map(|(p, _)| p.display().to_string())
        .collect();
    bail!(
        "scene file {} not found (tried {}; PPM_SCENES can name more folders)",
        arg.display(),
        tried.join(", ")
    )
}

/// Loads a scene file with the parameters of `-D` (Mitsuba XML scenes), printing the
/// loader's warnings to stderr.
pub fn load_scene(path: &Path, defines: &[(String, String)]) -> Result<Scene> {
    load_scene_hashed(path, defines).map(|(scene, _)| scene)
}

/// Like [`load_scene`], with the scene's content hash (recorded in the images' provenance).
pub fn load_scene_hashed(path: &Path, defines: &[(String, String)]) -> Result<(Scene, u64)> {
    let loaded = ppm_scene::load_scene_with_defines(path, defines)
        .with_context(|| format!("cannot load scene {}", path.display()))?;
    for warning in &loaded.warnings {
        status!("warning: {warning}");
    }
    Ok((loaded.scene, loaded.content_hash))
}

/// The image size of a render: `--width`/`--height` if given (one alone keeps the scene's
/// aspect ratio), else the reference's size if there is one, else the scene's. With a
/// reference the result must match it.
pub fn resolve_resolution(
    scene: (u32, u32),
    width: Option<u32>,
    height: Option<u32>,
    reference: Option<(u32, u32)>,
) -> Result<(u32, u32)> {
    let (sw, sh) = (scene.0 as f64, scene.1 as f64);
    let size = match (width, height, reference) {
        (Some(w), Some(h), _) => (w, h),
        (Some(w), None, _) => (w, ((w as f64 * sh / sw).round() as u32).max(1)),
        (None, Some(h), _) => (((h as f64 * sw / sh).round() as u32).max(1), h),
        (None, None, Some(r)) => r,
        (None, None, None) => scene,
    };
    if let Some(r) = reference {
        if r != size {
            bail!(
                "the reference image is {}x{} but the render would be {}x{}: render at the reference's size \
                 (drop --width/--height)",
                r.0,
                r.1,
                size.0,
                size.1
            );
        }
    }
    Ok(size)
}

/// Sets the camera resolution (see [`resolve_resolution`]).
pub fn apply_resolution(
    scene: &mut Scene,
    settings: &SettingsArgs,
    reference: Option<(u32, u32)>,
) -> Result<()> {
    let camera = &mut scene.camera;
    let from = (camera.width, camera.height);
    let (w, h) = resolve_resolution(from, settings.width, settings.height, reference)?;
    camera
        .set_resolution(w, h)
        .context("invalid --width/--height")?;
    // The scene's crop window keeps its place in the resized image.
    if let Some(crop) = scene.defaults.crop {
        scene.defaults.crop = Some(crop.resized(from, (w, h)).with_context(|| {
            format!(
                "the scene's crop window (pixels {} {} {} {} of {}x{}) covers no pixel of the {w}x{h} image",
                crop.x0, crop.x1, crop.y0, crop.y1, from.0, from.1
            )
        })?);
    }
    Ok(())
}

/// The scene's render defaults with the command line's overrides.
pub fn render_settings(scene: &Scene, algorithm: Algorithm, args: &SettingsArgs) -> RenderSettings {
    let mut settings = RenderSettings::for_algorithm(scene, algorithm);
    apply_overrides(&mut settings, algorithm, args);
    settings
}

/// Overrides the settings the command line sets, then normalises them
/// ([`RenderSettings::normalised`]: what the render uses is what the saved render records),
/// with a warning when a depth above the bound was asked for.
pub fn apply_overrides(settings: &mut RenderSettings, algorithm: Algorithm, args: &SettingsArgs) {
    settings.algorithm = algorithm;
    settings.seed = args.seed.unwrap_or(0);
    if let Some(v) = args.max_depth {
        settings.max_depth = v;
    }
    if bounded_depth(settings.max_depth) != settings.max_depth {
        status!(
            "warning: max_depth {} is above the supported {MAX_DEPTH} bounces; using {MAX_DEPTH}",
            settings.max_depth
        );
    }
    if let Some(v) = args.photons {
        settings.photons = v;
    }
    if let Some(v) = args.radius {
        settings.radius = v;
    }
    if let Some(v) = args.alpha {
        settings.alpha = v;
    }
    if let Some(v) = args.direct {
        settings.direct = v.into();
    }
    if let Some(v) = args.light_strategy {
        settings.light_strategy = v.into();
    }
    *settings = settings.normalised();
}

/// Refuses an initial merge radius below [`smallest_radius`] for the scene (the disc area
/// underflows in f32, or the disc is finer than f32 resolves positions at the scene's extent):
/// such a render finds no photon and comes out black or without its indirect light. A
/// `--radius` is a usage error (exit 2); the scene's `render.radius` an error naming it.
pub fn check_radius(
    scene: &Scene,
    settings: &RenderSettings,
    args: &SettingsArgs,
    scene_path: &Path,
) -> Result<()> {
    let Radius::World(r) = settings.radius else {
        return Ok(());
    };
    if !settings.algorithm.reads(Setting::Radius) {
        return Ok(());
    }
    let diagonal = scene.diagonal();
    let smallest = smallest_radius(diagonal);
    if r >= smallest {
        return Ok(());
    }
    let why = if smallest > smallest_radius(0.0) {
        format!(
            "2^-24 of the scene's extent {diagonal}: single precision resolves positions \
             only to about that, so a smaller merge disc finds no photon"
        )
    } else {
        "below it the merge disc's area pi r^2 underflows in single precision".to_string()
    };
    let fix = "raise it, or use `auto` (a few pixel footprints)";
    if args.radius.is_some() {
        usage_bail!(
            "--radius {r:e} is too small for {}: the smallest merge radius is {smallest:.3e} \
             ({why}); {fix}",
            scene_path.display()
        );
    }
    bail!(
        "{}: render.radius {r:e} is too small: the smallest merge radius is {smallest:.3e} \
         ({why}); {fix}, or override it with --radius",
        scene_path.display()
    )
}

/// The flag that sets `setting`, and whether the command line gave it.
fn flag(args: &SettingsArgs, setting: Setting) -> (&'static str, bool) {
    match setting {
        Setting::Photons => ("--photons", args.photons.is_some()),
        Setting::Radius => ("--radius", args.radius.is_some()),
        Setting::Alpha => ("--alpha", args.alpha.is_some()),
        Setting::Direct => ("--direct", args.direct.is_some()),
        Setting::LightStrategy => ("--light-strategy", args.light_strategy.is_some()),
    }
}

/// Warns about each flag given that none of `algorithms` reads ([`Algorithm::reads`]): it
/// changes nothing in the image, which a user who gave it would not expect. A warning, not an
/// error: scripts that pass one set of flags to every algorithm keep working.
pub fn warn_unread_flags(args: &SettingsArgs, algorithms: &[Algorithm]) {
    for setting in Setting::ALL {
        let (name, given) = flag(args, setting);
        if !given || algorithms.iter().any(|a| a.reads(setting)) {
            continue;
        }
        let readers = Algorithm::ALL.into_iter().filter(|a| a.reads(setting));
        status!(
            "warning: {name} has no effect with -a {} and is ignored (it is read by {})",
            names(algorithms.iter().copied()),
            names(readers)
        );
    }
}

/// The algorithms' command-line names, comma-separated.
fn names(algorithms: impl Iterator<Item = Algorithm>) -> String {
    algorithms.map(|a| a.name()).collect::<Vec<_>>().join(", ")
}

/// Warns when an integrator that cannot sample delta-light (point, spot or directional) paths through a
/// mirror or glass surface ([`ppm_core::integrator::Features::delta_light_caustics`]: the path
/// tracer) renders a scene that has them (it is offered as the reference, so the missing light
/// would otherwise pass for the truth).
pub fn warn_missing_light(scene: &Scene, algorithm: Algorithm, scene_path: &Path) {
    if !algorithm.features().delta_light_caustics && scene.has_delta_light_behind_specular() {
        status!(
            "warning: {} has a point, spot or directional light and a mirror or glass surface: the \
             path tracer cannot render point-light light that passes a mirror or glass before a \
             diffuse surface (its caustics, its reflection); that light is missing from this \
             image. -a ppm, sppm or vcm render it",
            scene_path.display()
        );
    }
}

/// The most worker threads `--threads` starts: 16 per core (at least 64). More add only the
/// cost of starting and feeding them (4096 threads on 2 cores made a 32 x 32 iteration some
/// 400 times slower than 64), and the image does not depend on the thread count.
pub fn max_threads() -> u64 {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get()) as u64;
    (16 * cores).max(64)
}

/// Warns once when `--threads` asks for more than [`max_threads`], which [`with_threads`]
/// then starts instead.
pub fn warn_if_threads_capped(threads: Option<u64>) {
    let max = max_threads();
    if let Some(n) = threads.filter(|&n| n > max) {
        status!(
            "warning: --threads {n} is more than this machine can use; using {max} (16 per \
             core): the image is the same at any thread count"
        );
    }
}

/// Runs `f` on a pool of `threads` workers (at most [`max_threads`]), or on rayon's global
/// pool (all cores) if `None`.
pub fn with_threads<T: Send>(threads: Option<u64>, f: impl FnOnce() -> T + Send) -> Result<T> {
    match threads {
        None => Ok(f()),
        Some(n) => {
            let n = n.min(max_threads());
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(n as usize)
                .build()
                .with_context(|| format!("cannot start {n} threads (--threads)"))?;
            Ok(pool.install(f))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::args::{DirectArg, LightStrategyArg};
    use ppm_core::integrator::{Algorithm, DirectMode, LightStrategy, Radius};

    #[test]
    fn resolution_rules() {
        let scene = (512, 412);
        assert_eq!(
            resolve_resolution(scene, None, None, None).unwrap(),
            (512, 412)
        );
        assert_eq!(
            resolve_resolution(scene, Some(64), Some(32), None).unwrap(),
            (64, 32)
        );
        // One side alone keeps the aspect ratio: 256 * 412 / 512 = 206.
        assert_eq!(
            resolve_resolution(scene, Some(256), None, None).unwrap(),
            (256, 206)
        );
        assert_eq!(
            resolve_resolution(scene, None, Some(206), None).unwrap(),
            (256, 206)
        );
        assert_eq!(
            resolve_resolution(scene, Some(1), None, None).unwrap(),
            (1, 1)
        );
        // A reference sets the default size and must match an explicit one.
        assert_eq!(
            resolve_resolution(scene, None, None, Some((64, 48))).unwrap(),
            (64, 48)
        );
        assert_eq!(
            resolve_resolution(scene, Some(64), Some(48), Some((64, 48))).unwrap(),
            (64, 48)
        );
        let err = resolve_resolution(scene, Some(64), None, Some((64, 48)))
            .unwrap_err()
            .to_string();
        assert!(err.contains("64x48") && err.contains("64x52"), "{err}");
    }

    #[test]
    fn unknown_scene_names_the_paths_tried() {
        let err = locate_scene(Path::new("no_such_scene.yml"))
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("no_such_scene.yml") && err.contains("scenes/no_such_scene.yml"),
            "{err}"
        );
        let dir = tempfile::tempdir().unwrap();
        let err = locate_scene(dir.path()).unwrap_err().to_string();
        assert!(err.contains("folder"), "{err}");
        let file = dir.path().join("s.yml");
        std::fs::write(&file, "").unwrap();
        assert_eq!(locate_scene(&file).unwrap(), file);
    }

    #[test]
    fn overrides_replace_only_what_is_given() {
        // Built by hand: a Scene needs the BVH, and these rules do not.
        let defaults = RenderSettings {
            algorithm: Algorithm::Ppm,
            seed: 0,
            max_depth: 32,
            rr_depth: 3,
            light_strategy: LightStrategy::Mis,
            photons: 1000,
            radius: Radius::World(0.01),
            alpha: 0.7,
            direct: DirectMode::Photons,
        };
        let mut s = defaults.clone();
        apply_overrides(&mut s, Algorithm::Path, &SettingsArgs::default());
        assert_eq!(s.algorithm, Algorithm::Path);
        assert_eq!(
            (s.photons, s.radius, s.alpha, s.max_depth),
            (
                defaults.photons,
                defaults.radius,
                defaults.alpha,
                defaults.max_depth
            )
        );
        let args = SettingsArgs {
            seed: Some(9),
            photons: Some(123),
            radius: Some(Radius::World(0.5)),
            alpha: Some(0.9),
            max_depth: Some(4),
            direct: Some(DirectArg::Sampled),
            light_strategy: Some(LightStrategyArg::Bsdf),
            ..SettingsArgs::default()
        };
        apply_overrides(&mut s, Algorithm::Ppm, &args);
        assert_eq!(s.algorithm, Algorithm::Ppm);
        assert_eq!(
            (s.seed, s.photons, s.radius, s.alpha, s.max_depth),
            (9, 123, Radius::World(0.5), 0.9, 4)
        );
        assert_eq!(s.direct, DirectMode::Sampled);
        assert_eq!(s.light_strategy, LightStrategy::BsdfOnly);
    }

    #[test]
    fn a_thread_count_beyond_the_machine_is_capped() {
        let max = max_threads();
        assert!(max >= 64);
        assert_eq!(
            with_threads(Some(4 * max), rayon::current_num_threads).unwrap() as u64,
            max
        );
        assert_eq!(
            with_threads(Some(max), rayon::current_num_threads).unwrap() as u64,
            max
        );
    }

    #[test]
    fn thread_pool_has_the_asked_size() {
        assert_eq!(
            with_threads(Some(3), rayon::current_num_threads).unwrap(),
            3
        );
        assert_eq!(
            with_threads(None, rayon::current_num_threads).unwrap(),
            rayon::current_num_threads()
        );
    }
}
