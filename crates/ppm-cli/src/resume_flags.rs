//! `--resume FILE` without repeating the flags: every setting the command line leaves unset
//! is taken from the file, which records them all ([`Provenance`]), so `ppm --resume out.exr
//! -n 200` continues with the recorded scene, algorithm, seed, size, depth, photons, radius,
//! alpha and light modes. A flag given explicitly is kept, and must agree with the file or
//! the resume is refused (naming the difference) as before.

use crate::args::{gather_radius, DirectArg, LightStrategyArg, RenderArgs};
use crate::provenance::Provenance;
use anyhow::{bail, Result};
use ppm_core::integrator::{Algorithm, Setting};
use std::path::PathBuf;

/// `args` with the settings it does not give filled in from `saved`, the provenance of the
/// file to resume. Settings the recorded algorithm does not read (photons for `pt`) are left
/// unset, as such a render's own flags would be.
pub fn with_recorded_settings(args: &RenderArgs, saved: &Provenance) -> Result<RenderArgs> {
    let mut args = args.clone();
    let recorded = |what: &str, value: &str| {
        anyhow::anyhow!("the --resume file records {what} `{value}`, which this ppm does not read")
    };
    let Ok(file_algorithm) = saved.algorithm.parse::<Algorithm>() else {
        bail!(recorded("the algorithm", &saved.algorithm));
    };
    let algorithm = *args.algorithm.get_or_insert(file_algorithm);
    if args.scene.is_none() {
        args.scene = Some(PathBuf::from(&saved.scene));
    }
    let s = &mut args.settings;
    if s.width.is_none() && s.height.is_none() && args.reference.is_none() {
        (s.width, s.height) = (Some(saved.width), Some(saved.height));
    }
    s.seed.get_or_insert(saved.seed);
    s.max_depth.get_or_insert(saved.max_depth);
    if algorithm.reads(Setting::Photons) {
        s.photons.get_or_insert(saved.photons);
    }
    if algorithm.reads(Setting::Radius) && s.radius.is_none() {
        s.radius =
            Some(gather_radius(&saved.radius).map_err(|_| recorded("the radius", &saved.radius))?);
    }
    if algorithm.reads(Setting::Alpha) {
        s.alpha.get_or_insert(saved.alpha);
    }
    if algorithm.reads(Setting::Direct) && s.direct.is_none() {
        s.direct = Some(match saved.direct.as_str() {
            "photons" => DirectArg::Photons,
            "sampled" => DirectArg::Sampled,
            other => bail!(recorded("the direct light mode", other)),
        });
    }
    if algorithm.reads(Setting::LightStrategy) && s.light_strategy.is_none() {
        s.light_strategy = Some(match saved.light_strategy.as_str() {
            "mis" => LightStrategyArg::Mis,
            "light" => LightStrategyArg::Light,
            "bsdf" => LightStrategyArg::Bsdf,
            other => bail!(recorded("the light strategy", other)),
        });
    }
    Ok(args)
}
