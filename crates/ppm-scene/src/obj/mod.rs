//! Wavefront OBJ meshes, read with tobj behind a checking pass of our own.
//!
//! The pass (`prepare.rs`) reads the file line by line, so that every error names its line;
//! it strips comments (also after values), resolves negative (relative) indices, drops what
//! ppm does not use (texture coordinates, lines, points, smoothing groups, free-form
//! geometry) and hands tobj a text it cannot choke on: tobj 4.0 overflows (a panic in debug
//! builds) on a relative normal index reaching before the first normal, and reports errors
//! without lines. tobj then triangulates polygons (as fans), splits the file by object and
//! material, and builds one index per position/normal pair. Last, `clean.rs` drops degenerate
//! triangles and repairs unusable vertex normals, so that no NaN ever leaves this module.

mod clean;
mod prepare;

use crate::error::LoadError;
use crate::mtl::{self, MtlMaterial};
use clean::{clean, CleanStats};
use glam::{DVec3, Vec3};
use ppm_core::geometry::TriangleMesh;
use ppm_core::material::Material;
use prepare::prepare;
use std::collections::HashSet;
use std::path::{Path, PathBuf};

/// Where the materials of an OBJ's faces come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ObjMaterials {
    /// From the MTL libraries the OBJ names (`mtllib`, `usemtl`).
    FromMtl,
    /// None: the caller assigns one material to everything (MTL files are not read).
    Ignore,
}

/// The meshes of one OBJ file and the materials they use.
#[derive(Clone, Debug, Default)]
pub struct ObjData {
    /// One mesh per object and material; `TriangleMesh::materials` index into `materials`.
    pub meshes: Vec<TriangleMesh>,
    /// The materials the meshes use (MTL materials, and the default grey diffuse of
    /// [`mtl::default_material`] for faces without a usable material). Empty with
    /// [`ObjMaterials::Ignore`], where every triangle has material 0.
    pub materials: Vec<Material>,
}

impl ObjData {
    /// Number of triangles in all meshes.
    pub fn triangle_count(&self) -> usize {
        self.meshes.iter().map(|m| m.indices.len()).sum()
    }
}

/// Reads an OBJ file (and its MTL libraries when `materials` says so).
pub fn load_obj(
    path: &Path,
    materials: ObjMaterials,
    warnings: &mut Vec<String>,
) -> Result<ObjData, LoadError> {
    load_obj_relative(path, materials, DVec3::ZERO, warnings)
}

/// [`load_obj`] with every vertex position minus `origin`, subtracted in double precision
/// before rounding to `f32` (the scene loader passes the camera position, so that a mesh far
/// from the world origin keeps its detail).
pub fn load_obj_relative(
    path: &Path,
    materials: ObjMaterials,
    origin: DVec3,
    warnings: &mut Vec<String>,
) -> Result<ObjData, LoadError> {
    // Read and parsed once per load however many objects name it (`file_cache`).
    let variant = format!("{materials:?} {:?}", origin.to_array());
    crate::file_cache::parsed("obj", path, variant, || {
        let text = read_text(path, "OBJ mesh")?;
        parse_obj_relative(&text, path, materials, origin, warnings)
    })
}

/// Parses OBJ text; `path` names it in messages and locates its MTL libraries.
pub fn parse_obj(
    text: &str,
    path: &Path,
    materials: ObjMaterials,
    warnings: &mut Vec<String>,
) -> Result<ObjData, LoadError> {
    parse_obj_relative(text, path, materials, DVec3::ZERO, warnings)
}

/// [`parse_obj`] with every vertex position minus `origin` (see [`load_obj_relative`]).
pub fn parse_obj_relative(
    text: &str,
    path: &Path,
    materials: ObjMaterials,
    origin: DVec3,
    warnings: &mut Vec<String>,
) -> Result<ObjData, LoadError> {
    let prepared = prepare(text, path, origin, warnings)?;

    // Each `mtllib` statement becomes a list of MTL materials; tobj sees only their names.
    let mut libraries: Vec<Vec<MtlMaterial>> = Vec::new();
    if materials == ObjMaterials::FromMtl {
        for (line, files) in &prepared.mtllibs {
            libraries.push(load_libraries(path, *line, files, warnings)?);
        }
    }
    let options = tobj::LoadOptions {
        single_index: true,
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
    };
    let mut reader = std::io::Cursor::new(prepared.text.as_bytes());
    let (models, _) = tobj::load_obj_buf(&mut reader, &options, |p| {
        // `prepare` wrote each `mtllib` as its statement number.
        let i: usize = p
            .to_str()
            .and_then(|s| s.parse().ok())
            .unwrap_or(usize::MAX);
        let names: Vec<&MtlMaterial> = libraries
            .get(i)
            .map(|l| l.iter().collect())
            .unwrap_or_default();
        let mats = names
            .iter()
            .map(|m| tobj::Material {
                name: m.name.clone(),
                ..Default::default()
            })
            .collect();
        let map = names
            .iter()
            .enumerate()
            .map(|(k, m)| (m.name.clone(), k))
            .collect();
        Ok((mats, map))
    })
    .map_err(|e| LoadError::parse(path, 0, format!("OBJ error: {e}")))?;

    // tobj numbers materials across all libraries in statement order, as we do.
    let all: Vec<&MtlMaterial> = libraries.iter().flatten().collect();
    if materials == ObjMaterials::FromMtl {
        let known: HashSet<&str> = all.iter().map(|m| m.name.as_str()).collect();
        for (line, name) in &prepared.usemtl {
            if !known.contains(name.as_str()) {
                warnings.push(format!(
                    "{}:{line}: usemtl `{name}`: no such material in the MTL libraries; its faces use the default grey diffuse (albedo {})",
                    path.display(),
                    mtl::DEFAULT_ALBEDO
                ));
            }
        }
    }

    let mut data = ObjData::default();
    // Local index of each MTL material, created on first use (so unused ones are left out).
    let mut local: Vec<Option<u32>> = vec![None; all.len()];
    let mut default_index = None;
    let mut stats = CleanStats {
        degenerate: prepared.degenerate,
        ..Default::default()
    };
    for model in &models {
        let material = match materials {
            ObjMaterials::Ignore => 0,
            ObjMaterials::FromMtl => match model.mesh.material_id.filter(|&i| i < all.len()) {
                Some(i) => match local[i] {
                    Some(l) => l,
                    None => {
                        let m = mtl::mtl_to_material(all[i], path, warnings);
                        let m = crate::mtl_texture::textured(m, all[i], warnings)?;
                        data.materials.push(m);
                        *local[i].insert(data.materials.len() as u32 - 1)
                    }
                },
                None => *default_index.get_or_insert_with(|| {
                    data.materials.push(mtl::default_material());
                    data.materials.len() as u32 - 1
                }),
            },
        };
        if let Some(mesh) = clean(
            &model.mesh,
            &model.name,
            material,
            path,
            &mut stats,
            warnings,
        ) {
            data.meshes.push(mesh);
        }
    }
    stats.warn(path, warnings);
    if data.meshes.is_empty() {
        warnings.push(format!("{}: contains no triangles", path.display()));
    } else if materials == ObjMaterials::FromMtl
        && default_index.is_some()
        && prepared.mtllibs.is_empty()
    {
        warnings.push(format!(
            "{}: names no material library (mtllib); using a grey diffuse (albedo {})",
            path.display(),
            mtl::DEFAULT_ALBEDO
        ));
    }
    Ok(data)
}

/// Reads a whole text file; not-UTF-8 bytes become U+FFFD. Only regular files are read
/// (never a device such as /dev/zero).
pub(crate) fn read_text(path: &Path, what: &str) -> Result<String, LoadError> {
    let io = |source| LoadError::Io {
        path: path.to_path_buf(),
        what: what.to_string(),
        source,
    };
    let meta = std::fs::metadata(path).map_err(io)?;
    if !meta.is_file() {
        return Err(io(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!("it is {}, not a regular file", file_kind(&meta.file_type())),
        )));
    }
    crate::file_cache::note_read();
    let bytes = std::fs::read(path).map_err(io)?;
    // A UTF-8 byte order mark (written by some Windows editors and exporters) is not part of
    // the text: left in, it would glue itself to the first statement (an OBJ's first `v`).
    let bytes = bytes.strip_prefix("\u{feff}".as_bytes()).unwrap_or(&bytes);
    Ok(String::from_utf8_lossy(bytes).into_owned())
}

/// What a non-regular file is, for messages: "a folder", "a FIFO (named pipe)"...
pub fn file_kind(kind: &std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if kind.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if kind.is_char_device() {
            return "a character device";
        }
        if kind.is_block_device() {
            return "a block device";
        }
        if kind.is_socket() {
            return "a socket";
        }
    }
    if kind.is_dir() {
        "a folder"
    } else if kind.is_symlink() {
        "a symbolic link"
    } else {
        "a special file"
    }
}

/// Loads the MTL files of one `mtllib` statement. A missing file is a warning (its materials
/// fall back to the default); a malformed one is an error.
fn load_libraries(
    obj: &Path,
    line: usize,
    files: &str,
    warnings: &mut Vec<String>,
) -> Result<Vec<MtlMaterial>, LoadError> {
    let dir = obj.parent().unwrap_or(Path::new(""));
    // `mtllib a.mtl b.mtl` names two files, unless a file with the whole name exists.
    let names: Vec<&str> = if dir.join(files).is_file() {
        vec![files]
    } else {
        files.split_whitespace().collect()
    };
    let mut materials = Vec::new();
    for name in names {
        let Some(found) = find_library(dir, name) else {
            let tried = candidates(dir, name)
                .iter()
                .map(|p| p.display().to_string())
                .collect::<Vec<_>>()
                .join(" and ");
            warnings.push(format!(
                "{}:{line}: material library `{name}` not found (tried {tried}); its materials become a grey diffuse (albedo {})",
                obj.display(),
                mtl::DEFAULT_ALBEDO
            ));
            continue;
        };
        if found != dir.join(name) {
            warnings.push(format!(
                "{}:{line}: material library `{name}` not found as written; using {}",
                obj.display(),
                found.display()
            ));
        }
        let library = crate::file_cache::parsed("mtl", &found, String::new(), || {
            let text = read_text(&found, "MTL material library")?;
            mtl::parse_mtl(&text, &found, warnings)
        })?;
        materials.extend(library);
    }
    Ok(materials)
}

/// The paths tried for an `mtllib` name: as written relative to the OBJ's folder, then its
/// bare file name (after the last `/` or `\`) in that folder.
fn candidates(dir: &Path, name: &str) -> Vec<PathBuf> {
    let as_written = dir.join(name);
    let bare = name.rsplit(['/', '\\']).next().unwrap_or(name);
    let mut v = vec![as_written];
    if !bare.is_empty() && dir.join(bare) != v[0] {
        v.push(dir.join(bare));
    }
    v
}

fn find_library(dir: &Path, name: &str) -> Option<PathBuf> {
    candidates(dir, name).into_iter().find(|p| p.is_file())
}

/// `v / |v|` when that is a finite unit vector, even for components near the f32 limits.
fn safe_normalize(v: Vec3) -> Option<Vec3> {
    let scale = v.abs().max_element();
    if !(scale.is_finite() && scale > 0.0) {
        return None;
    }
    let u = (v / scale).normalize();
    u.is_finite().then_some(u)
}
