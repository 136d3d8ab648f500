//! `ppm convert SCENE -o OUT.yml`: writes a scene (scene format v1, Mitsuba XML or pbrt-v4)
//! as scene format v1, what ppm understood of it (`ppm_scene::convert`).

use crate::args::ConvertArgs;
use anyhow::{Context, Result};

/// Runs `ppm convert`.
pub fn run(args: &ConvertArgs) -> Result<()> {
    let yaml = args
        .output
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("yml") || e.eq_ignore_ascii_case("yaml"));
    if !yaml {
        usage_bail!(
            "-o {}: the converted scene is YAML; name it .yml or .yaml",
            args.output.display()
        );
    }
    let (scene, _) = crate::setup::locate_scene_found(&args.scene)?;
    let same = |a: &std::path::Path, b: &std::path::Path| match (a.canonicalize(), b.canonicalize())
    {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    };
    if same(&scene, &args.output) {
        usage_bail!(
            "-o {}: ppm would overwrite its own input; choose another output name",
            args.output.display()
        );
    }
    if let Some(folder) = args.output.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(folder)
            .with_context(|| format!("cannot create folder {}", folder.display()))?;
    }
    let done = ppm_scene::convert::convert_scene(&scene, &args.output, &args.define)
        .with_context(|| format!("cannot convert {}", scene.display()))?;
    for w in &done.warnings {
        status!("warning: {w}");
    }
    for n in &done.notes {
        status!("note: not written exactly as loaded: {n}");
    }
    status!(
        "wrote {} ({} files beside it)",
        args.output.display(),
        done.files.len()
    );
    Ok(())
}
