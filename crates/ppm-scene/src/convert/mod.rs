//! `ppm convert`: a loaded scene (scene format v1, Mitsuba XML or pbrt-v4) written back as
//! scene format v1, so a user can read and edit what ppm understood of it.
//!
//! What is written is the scene as ppm holds it after import ([`SceneBuilder`]), not the
//! source's syntax: every material is the YAML type that builds the same BSDF with the same
//! values (`material.rs`), lights and the camera with the values they hold, and meshes, in
//! world space, as binary PLY files (with their normals and uvs) in a folder beside the YAML,
//! `<name>_files/`, which also holds bitmap textures and environment maps as float EXR.
//! Numbers are written so they read back to the same `f32`, so loading the written file
//! gives the same scene content fingerprint ([`crate::content_hash`]) as the import, except
//! where a note at the top of the file says what differs. The import's warnings are repeated
//! as comments at the top. A feature scene format v1 cannot express is an error naming it.

mod files;
mod material;
mod text;

use crate::error::LoadError;
use glam::{Mat3, Vec3};
use ppm_core::light::{EnvironmentMap, Light};
use ppm_core::scene::SceneBuilder;
use std::collections::HashSet;
use std::path::{Path, PathBuf};
use text::{list, num, quoted, triple, Yaml};

/// The first line of every file `ppm convert` writes; a YAML input that starts with it keeps
/// its comment block, so converting a converted file again gives the same text.
pub const HEADER: &str =
    "# Scene format v1 written by `ppm convert`: what ppm understood of the scene.";

/// What [`convert_scene`] did.
pub struct Conversion {
    /// The warnings of loading the input.
    pub warnings: Vec<String>,
    /// What the written file does not hold exactly as loaded (also comments in the file).
    pub notes: Vec<String>,
    /// The files written besides the YAML (meshes, textures, environment maps).
    pub files: Vec<PathBuf>,
}

/// Loads the scene `input` (any format [`crate::load_scene_builder_with_defines`] reads)
/// and writes it as scene format v1 to `output`, its meshes and images in
/// `<output stem>_files/` beside it.
pub fn convert_scene(
    input: &Path,
    output: &Path,
    defines: &[(String, String)],
) -> Result<Conversion, LoadError> {
    let (mut builder, warnings) = crate::load_scene_builder_with_defines(input, defines)?;
    // A file ppm convert wrote keeps its comments (the warnings of the original import).
    let kept_header = std::fs::read_to_string(input).ok().and_then(|text| {
        text.starts_with(HEADER).then(|| {
            text.lines()
                .take_while(|l| l.starts_with('#'))
                .map(|l| format!("{l}\n"))
                .collect::<String>()
        })
    });
    let mut ctx = Context::new(input, output);
    // Instances are written as the copies they stand for: scene format v1's `instances:`
    // takes its steps in single precision, and an imported placement is a double-precision
    // matrix that would not come back the same.
    if !builder.instances.is_empty() {
        ctx.notes.push(format!(
            "{} placements of {} instanced meshes are written as copies",
            builder.instances.len(),
            builder.instanced_meshes.len()
        ));
        builder
            .flatten_instances()
            .map_err(|e| LoadError::invalid(input, "instances", e.to_string()))?;
        builder.instanced_meshes.clear();
    }
    let body = write_body(&builder, &mut ctx)?;
    let header = match kept_header {
        Some(h) => h,
        None => header(&warnings, &ctx.notes, builder.world_offset),
    };
    let text = format!("{header}{body}");
    std::fs::write(output, text).map_err(|source| LoadError::Io {
        path: output.to_path_buf(),
        what: "converted scene (writing)".into(),
        source,
    })?;
    Ok(Conversion {
        warnings,
        notes: ctx.notes,
        files: ctx.files,
    })
}

/// Where the written files go, and what the conversion noted.
pub(crate) struct Context {
    /// The input, named in errors.
    pub source: PathBuf,
    /// The folder of the output file.
    dir: PathBuf,
    /// `<output stem>_files`, relative to `dir`.
    files_dir: String,
    pub notes: Vec<String>,
    pub files: Vec<PathBuf>,
}

impl Context {
    fn new(input: &Path, output: &Path) -> Self {
        let stem = output
            .file_stem()
            .map_or("scene".into(), |s| s.to_string_lossy().into_owned());
        Context {
            source: input.to_path_buf(),
            dir: output.parent().unwrap_or(Path::new("")).to_path_buf(),
            files_dir: format!("{stem}_files"),
            notes: Vec::new(),
            files: Vec::new(),
        }
    }

    /// A new file `name` in the files folder (made on first use): its path, and its name
    /// relative to the output file as the YAML refers to it.
    pub fn side_file(&mut self, name: &str) -> Result<(PathBuf, String), LoadError> {
        let folder = self.dir.join(&self.files_dir);
        std::fs::create_dir_all(&folder).map_err(|source| LoadError::Io {
            path: folder.clone(),
            what: "folder for the converted scene's meshes and images".into(),
            source,
        })?;
        let path = folder.join(name);
        self.files.push(path.clone());
        Ok((path, format!("{}/{name}", self.files_dir)))
    }
}

/// The comment block: the header line, the import's warnings, the conversion's notes.
fn header(warnings: &[String], notes: &[String], world_offset: Vec3) -> String {
    let mut y = Yaml::default();
    y.text.push_str(HEADER);
    y.text.push('\n');
    if world_offset != Vec3::ZERO {
        y.comment(&format!(
            "Coordinates are relative to the camera's position in the source, {} (the scene is far from the origin).",
            triple(world_offset)
        ));
    }
    if !warnings.is_empty() {
        y.comment("Warnings of the import:");
        for w in warnings {
            y.comment(&format!("  {w}"));
        }
    }
    if !notes.is_empty() {
        y.comment("Not written exactly as loaded:");
        for n in notes {
            y.comment(&format!("  {n}"));
        }
    }
    y.text
}

/// Everything but the comments.
fn write_body(b: &SceneBuilder, ctx: &mut Context) -> Result<String, LoadError> {
    let mut y = Yaml::default();
    write_camera(&mut y, b);
    let d = &b.defaults;
    y.line(0, "render:");
    y.field(1, "max_depth", &d.max_depth.to_string());
    if let Some(p) = d.photons {
        y.field(1, "photons", &p.to_string());
    }
    if let Some(r) = d.radius {
        let r = match r {
            ppm_core::integrator::Radius::World(r) => num(r),
            rule => rule.to_string(),
        };
        y.field(1, "radius", &r);
    }
    y.field(1, "alpha", &num(d.alpha));
    if let Some(a) = d.algorithm {
        y.field(1, "algorithm", a.name());
    }
    if let Some(c) = d.crop {
        y.field(
            1,
            "pixel_bounds",
            &format!("[{}, {}, {}, {}]", c.x0, c.x1, c.y0, c.y1),
        );
    }

    // Names must be unique keys; a repeated one gets a suffix (and a note: names count in
    // the fingerprint).
    let mut seen = HashSet::new();
    let mut names = Vec::with_capacity(b.materials.len());
    for m in &b.materials {
        let mut name = m.name.clone();
        let mut n = 2;
        while !seen.insert(name.clone()) {
            name = format!("{} ({n})", m.name);
            n += 1;
        }
        if name != m.name {
            ctx.notes.push(format!(
                "a second material named `{}` is written as `{name}`",
                m.name
            ));
        }
        names.push(name);
    }
    if !b.materials.is_empty() {
        y.line(0, "materials:");
        for (i, m) in b.materials.iter().enumerate() {
            let renamed;
            let m = if names[i] != m.name {
                renamed = m.clone().named(names[i].clone());
                &renamed
            } else {
                m
            };
            material::write_material(&mut y, ctx, m, i)?;
        }
    }

    if !b.meshes.is_empty() || !b.spheres.is_empty() {
        y.line(0, "objects:");
    }
    for (i, mesh) in b.meshes.iter().enumerate() {
        let mut used: Vec<u32> = Vec::new();
        for &m in &mesh.materials {
            if !used.contains(&m) {
                used.push(m);
            }
        }
        if used.len() > 1 {
            ctx.notes.push(format!(
                "mesh {i} has {} materials: written as one PLY file per material",
                used.len()
            ));
        }
        let split = used.len() > 1;
        for m in used {
            let file = if split {
                format!("mesh{i}_material{m}.ply")
            } else {
                format!("mesh{i}.ply")
            };
            let (path, relative) = ctx.side_file(&file)?;
            files::write_ply(&path, mesh, m)?;
            y.line(1, "- type: mesh");
            y.field(2, "file", &quoted(&relative));
            y.field(2, "material", &quoted(&names[m as usize]));
        }
    }
    for s in &b.spheres {
        y.line(1, "- type: sphere");
        y.field(2, "center", &triple(s.center));
        y.field(2, "radius", &num(s.radius));
        y.field(2, "material", &quoted(&names[s.material as usize]));
        if s.inward {
            y.field(2, "inward", "true");
        }
    }

    if !b.lights.is_empty() {
        y.line(0, "lights:");
    }
    for (i, l) in b.lights.iter().enumerate() {
        write_light(&mut y, ctx, l, i)?;
    }
    Ok(y.text)
}

/// `camera:` and `resolution:`, from the values the camera was made of, so that it is made
/// again bit for bit.
fn write_camera(y: &mut Yaml, b: &SceneBuilder) {
    let c = &b.camera;
    let (look_at, up, fov) = c.placement();
    y.line(0, "camera:");
    y.field(1, "position", &triple(c.position));
    y.field(1, "look_at", &triple(look_at));
    y.field(1, "up", &triple(up));
    y.field(1, "fov", &num(fov));
    if !c.is_pinhole() {
        y.field(1, "aperture_radius", &num(c.lens_radius()));
        y.field(1, "focus_distance", &num(c.focus_distance()));
    }
    y.field(0, "resolution", &format!("[{}, {}]", c.width, c.height));
}

/// An angle in degrees that the loader's `to_radians` turns into `radians` exactly, if one
/// is near `radians.to_degrees()`.
fn exact_degrees(radians: f32) -> Option<f32> {
    let d = radians.to_degrees();
    let mut below = d;
    let mut above = d;
    for _ in 0..16 {
        for x in [below, above] {
            if x.to_radians() == radians {
                return Some(x);
            }
        }
        below = below.next_down();
        above = above.next_up();
    }
    None
}

/// A direction that the loader's normalising turns into the unit vector `v` exactly: `v`
/// itself when normalising it again gives it back, else the nearest vector (a few ulps per
/// component away) that does; noted if there is none.
fn direction(v: Vec3, what: &str, ctx: &mut Context) -> String {
    let step = |x: f32, k: i32| -> f32 {
        let mut y = x;
        for _ in 0..k.abs() {
            y = if k > 0 { y.next_up() } else { y.next_down() };
        }
        y
    };
    const R: i32 = 3;
    let mut candidates: Vec<(i32, Vec3)> = Vec::new();
    for i in -R..=R {
        for j in -R..=R {
            for k in -R..=R {
                let w = Vec3::new(step(v.x, i), step(v.y, j), step(v.z, k));
                candidates.push((i.abs() + j.abs() + k.abs(), w));
            }
        }
    }
    candidates.sort_by_key(|(cost, _)| *cost);
    match candidates
        .into_iter()
        .find(|(_, w)| w.try_normalize() == Some(v))
    {
        Some((_, w)) => triple(w),
        None => {
            ctx.notes.push(format!(
                "{what}: no direction near it normalises to it exactly"
            ));
            triple(v)
        }
    }
}

/// An angle field: degrees when a number of degrees converts to `radians` exactly, else
/// `{ radians: x }`.
fn angle(radians: f32) -> String {
    match exact_degrees(radians) {
        Some(d) => num(d),
        None => format!("{{ radians: {} }}", num(radians)),
    }
}

/// One entry of `lights:`.
fn write_light(y: &mut Yaml, ctx: &mut Context, l: &Light, i: usize) -> Result<(), LoadError> {
    match l {
        Light::Point(p) => {
            y.line(1, "- type: point");
            y.field(2, "position", &triple(p.position));
            y.field(2, "intensity", &triple(p.intensity));
        }
        Light::Spot(s) => {
            y.line(1, "- type: spot");
            y.field(2, "position", &triple(s.position));
            let axis = direction(s.direction(), &format!("lights[{i}].direction"), ctx);
            y.field(2, "direction", &axis);
            y.field(2, "intensity", &triple(s.intensity));
            y.field(2, "cone_angle", &angle(s.cone_angle()));
            y.field(2, "falloff_start", &angle(s.falloff_start()));
        }
        Light::Directional(d) => {
            y.line(1, "- type: directional");
            let w = direction(d.direction(), &format!("lights[{i}].direction"), ctx);
            y.field(2, "direction", &w);
            y.field(2, "irradiance", &triple(d.irradiance));
        }
        Light::Environment(e) => {
            let (map, scale, to_world) = e.parts();
            y.line(1, "- type: environment");
            match map {
                EnvironmentMap::Constant(c) => y.field(2, "color", &triple(*c)),
                EnvironmentMap::Image(m) => {
                    let (width, height) = m.size();
                    let (path, relative) = ctx.side_file(&format!("environment{i}.exr"))?;
                    files::write_exr(&path, width, height, m.texels(), "environment map")?;
                    y.field(2, "file", &quoted(&relative));
                }
                EnvironmentMap::EqualArea(m) => {
                    let n = m.size();
                    let (path, relative) = ctx.side_file(&format!("environment{i}.exr"))?;
                    files::write_exr(&path, n, n, m.texels(), "environment map")?;
                    y.field(2, "file", &quoted(&relative));
                    y.field(2, "mapping", "equal_area");
                }
            }
            if scale != 1.0 {
                y.field(2, "scale", &num(scale));
            }
            if to_world != Mat3::IDENTITY {
                y.field(2, "to_world", &list(&to_world.transpose().to_cols_array()));
            }
        }
        Light::Triangle(_) | Light::Sphere(_) => {
            return Err(LoadError::invalid(
                &ctx.source,
                format!("lights[{i}]"),
                "an area light outside the materials' emission; scene format v1 makes area lights only from emissive materials",
            ))
        }
    }
    Ok(())
}
