//! Wavefront OBJ meshes, read with tobj behind a checking pass of our own.
//!
//! The pass ([`prepare`]) reads the file line by line, so that every error names its line;
//! it strips comments (also after values), resolves negative (relative) indices, drops what
//! ppm does not use (texture coordinates, lines, points, smoothing groups, free-form
//! geometry) and hands tobj a text it cannot choke on: tobj 4 panics on some malformed
//! input (index arithmetic overflow on far-out-of-range relative indices) and reports errors
//! without lines. tobj then triangulates polygons (as fans), splits the file by object and
//! material, and builds one index per position/normal pair. Last, [`clean`] drops degenerate
//! triangles and repairs unusable vertex normals, so that no NaN ever leaves this module.

use crate::error::LoadError;
use crate::mtl::{self, MtlMaterial};
use glam::Vec3;
use ppm_core::geometry::TriangleMesh;
use ppm_core::material::Material;
use std::collections::HashSet;
use std::fmt::Write;
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
#[derive(Debug, Default)]
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
    let text = read_text(path, "OBJ mesh")?;
    parse_obj(&text, path, materials, warnings)
}

/// Parses OBJ text; `path` names it in messages and locates its MTL libraries.
pub fn parse_obj(
    text: &str,
    path: &Path,
    materials: ObjMaterials,
    warnings: &mut Vec<String>,
) -> Result<ObjData, LoadError> {
    let prepared = prepare(text, path, warnings)?;

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
                Some(i) => *local[i].get_or_insert_with(|| {
                    data.materials
                        .push(mtl::mtl_to_material(all[i], path, warnings));
                    data.materials.len() as u32 - 1
                }),
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
            "not a regular file",
        )));
    }
    let bytes = std::fs::read(path).map_err(io)?;
    Ok(String::from_utf8_lossy(&bytes).into_owned())
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
        let text = read_text(&found, "MTL material library")?;
        materials.extend(mtl::parse_mtl(&text, &found, warnings)?);
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

/// The OBJ text rewritten for tobj, and what it needs to know about materials.
struct Prepared {
    text: String,
    /// Each `mtllib` statement: its line and its argument.
    mtllibs: Vec<(usize, String)>,
    /// Each `usemtl` statement: its line and the material name.
    usemtl: Vec<(usize, String)>,
    /// Faces dropped for having no area.
    degenerate: usize,
}

/// Checks and rewrites OBJ text line by line (see the module docs). The output has only
/// `mtllib` (first, as statement numbers), `v`, `vn`, `f` (absolute indices), `o`, `g` and
/// `usemtl` statements.
fn prepare(text: &str, path: &Path, warnings: &mut Vec<String>) -> Result<Prepared, LoadError> {
    let mut body = String::with_capacity(text.len());
    let mut out = Prepared {
        text: String::new(),
        mtllibs: Vec::new(),
        usemtl: Vec::new(),
        degenerate: 0,
    };
    let mut positions: Vec<Vec3> = Vec::new();
    // Output index of each `vn` of the file: flat normals we add shift the numbering.
    let mut normal_index: Vec<usize> = Vec::new();
    let mut emitted_normals = 0usize;
    // In a file with vertex normals, faces without them get their flat normal: tobj can
    // only give a mesh normals on all vertices or on none.
    let file_has_normals = text.lines().any(|l| l.trim_start().starts_with("vn"));
    let (mut short_faces, mut skipped_elements) = (0usize, 0usize);
    let mut unknown: Vec<String> = Vec::new();

    for (line_no, line) in logical_lines(text) {
        let err = |message: String| LoadError::parse(path, line_no, message);
        let line = line.split('#').next().unwrap_or("");
        let mut words = line.split_whitespace();
        let Some(keyword) = words.next() else {
            continue;
        };
        let args: Vec<&str> = words.collect();
        match keyword {
            "v" => {
                let p = numbers(&args, path, line_no, "v")?;
                let p = match p.len() {
                    // x y z, or x y z r g b (vertex colours, unused)
                    3 | 6 => Vec3::new(p[0], p[1], p[2]),
                    // x y z w: homogeneous
                    4 if p[3] != 0.0 => Vec3::new(p[0], p[1], p[2]) / p[3],
                    4 => return Err(err("`v`: w is 0".into())),
                    n => return Err(err(format!("`v` needs x y z [w], found {n} numbers"))),
                };
                let _ = writeln!(body, "v {} {} {}", p.x, p.y, p.z);
                positions.push(p);
            }
            "vn" => {
                let n = numbers(&args, path, line_no, "vn")?;
                if n.len() != 3 {
                    return Err(err(format!("`vn` needs x y z, found {} numbers", n.len())));
                }
                let _ = writeln!(body, "vn {} {} {}", n[0], n[1], n[2]);
                emitted_normals += 1;
                normal_index.push(emitted_normals);
            }
            "f" | "fo" => {
                let mut vertices = Vec::with_capacity(args.len());
                for token in &args {
                    let (v, n) =
                        face_vertex(token, positions.len(), normal_index.len(), path, line_no)?;
                    vertices.push((v, n.map(|n| normal_index[n - 1])));
                }
                if vertices.len() < 3 {
                    short_faces += 1;
                    continue;
                }
                let mut flat = None;
                if file_has_normals && vertices.iter().any(|(_, n)| n.is_none()) {
                    let newell = newell_normal(vertices.iter().map(|&(v, _)| positions[v - 1]));
                    let Some(n) = safe_normalize(newell) else {
                        out.degenerate += 1;
                        continue;
                    };
                    let _ = writeln!(body, "vn {} {} {}", n.x, n.y, n.z);
                    emitted_normals += 1;
                    flat = Some(emitted_normals);
                }
                body.push('f');
                for (v, n) in vertices {
                    match flat.or(n) {
                        Some(n) => write!(body, " {v}//{n}"),
                        None => write!(body, " {v}"),
                    }
                    .ok();
                }
                body.push('\n');
            }
            "o" | "g" => {
                let _ = writeln!(body, "{keyword} {}", args.join(" "));
            }
            "usemtl" => {
                let name = args.join(" ");
                if name.is_empty() {
                    warnings.push(format!(
                        "{}:{line_no}: `usemtl` without a name ignored",
                        path.display()
                    ));
                    continue;
                }
                let _ = writeln!(body, "usemtl {name}");
                out.usemtl.push((line_no, name));
            }
            "mtllib" => {
                if args.is_empty() {
                    return Err(err("`mtllib` needs a file name".into()));
                }
                // Listed first so that every `usemtl` sees every library.
                let _ = writeln!(out.text, "mtllib {}", out.mtllibs.len());
                out.mtllibs.push((line_no, args.join(" ")));
            }
            // Texture coordinates and smoothing groups: ppm has no textures and shades with
            // the given vertex normals (or flat).
            "vt" | "s" => {}
            "l" | "p" => skipped_elements += 1,
            other => {
                if !unknown.iter().any(|u| u == other) {
                    unknown.push(other.to_string());
                }
            }
        }
    }
    let file = path.display();
    if short_faces > 0 {
        warnings.push(format!(
            "{file}: skipped {short_faces} faces with fewer than 3 vertices"
        ));
    }
    if skipped_elements > 0 {
        warnings.push(format!(
            "{file}: ignored {skipped_elements} line and point elements (not surfaces)"
        ));
    }
    if !unknown.is_empty() {
        unknown.truncate(8);
        warnings.push(format!(
            "{file}: ignored unsupported statements: {}",
            unknown.join(", ")
        ));
    }
    out.text.push_str(&body);
    Ok(out)
}

/// Lines with their 1-based numbers, a trailing `\` joining a line with the next.
fn logical_lines(text: &str) -> impl Iterator<Item = (usize, String)> + '_ {
    let mut lines = text.lines().enumerate().peekable();
    std::iter::from_fn(move || {
        let (i, first) = lines.next()?;
        let mut line = first.to_string();
        while line.ends_with('\\') {
            line.pop();
            match lines.next() {
                Some((_, next)) => {
                    line.push(' ');
                    line.push_str(next);
                }
                None => break,
            }
        }
        Some((i + 1, line))
    })
}

fn numbers(
    args: &[&str],
    path: &Path,
    line_no: usize,
    keyword: &str,
) -> Result<Vec<f32>, LoadError> {
    args.iter()
        .map(|a| {
            a.parse::<f32>().map_err(|_| {
                LoadError::parse(path, line_no, format!("`{keyword}`: `{a}` is not a number"))
            })
        })
        .collect()
}

/// One `v`, `v/vt`, `v//vn` or `v/vt/vn` of a face, as absolute 1-based position and normal
/// indices. Negative indices count back from the last element defined so far (-1 = last).
fn face_vertex(
    token: &str,
    n_positions: usize,
    n_normals: usize,
    path: &Path,
    line_no: usize,
) -> Result<(usize, Option<usize>), LoadError> {
    let err = |message: String| LoadError::parse(path, line_no, message);
    let mut parts = token.split('/');
    let v = parts.next().unwrap_or("");
    let vt = parts.next().unwrap_or("");
    let vn = parts.next().unwrap_or("");
    if parts.next().is_some() {
        return Err(err(format!(
            "face vertex `{token}` has more than three parts (v/vt/vn)"
        )));
    }
    if !vt.is_empty() && vt.parse::<i64>().is_err() {
        return Err(err(format!(
            "face vertex `{token}`: `{vt}` is not a texture coordinate index"
        )));
    }
    let resolve = |s: &str, count: usize, what: &str, plural: &str| -> Result<usize, LoadError> {
        let count = count as i64;
        let i: i64 = s.parse().map_err(|_| {
            err(format!(
                "face vertex `{token}`: `{s}` is not a {what} index"
            ))
        })?;
        let absolute = if i < 0 { count + 1 + i } else { i };
        if i == 0 || absolute < 1 || absolute > count {
            return Err(err(format!(
                "face vertex `{token}`: {what} index {i} is out of range ({count} {plural} defined before this line; indices start at 1, negative ones count back from the last)"
            )));
        }
        Ok(absolute as usize)
    };
    let position = resolve(v, n_positions, "vertex", "vertices")?;
    let normal = if vn.is_empty() {
        None
    } else {
        Some(resolve(vn, n_normals, "normal", "normals")?)
    };
    Ok((position, normal))
}

/// Counts of what [`clean`] repaired, reported once per file.
#[derive(Default)]
struct CleanStats {
    degenerate: usize,
    bad_normals: usize,
    flipped: usize,
}

impl CleanStats {
    fn warn(&self, path: &Path, warnings: &mut Vec<String>) {
        let file = path.display();
        if self.degenerate > 0 {
            warnings.push(format!(
                "{file}: skipped {} degenerate triangles (repeated vertices, zero area or non-finite positions)",
                self.degenerate
            ));
        }
        if self.bad_normals > 0 {
            warnings.push(format!(
                "{file}: replaced {} unusable vertex normals (NaN, infinite or zero) by the area-weighted normal of the adjacent triangles",
                self.bad_normals
            ));
        }
        if self.flipped > 0 {
            warnings.push(format!(
                "{file}: {} triangles have vertex normals facing away from their counter-clockwise winding; the winding decides which side emits and which side is inside glass",
                self.flipped
            ));
        }
    }
}

/// A tobj mesh as a [`TriangleMesh`] without degenerate triangles and with unit vertex
/// normals; `None` if no triangle is left.
fn clean(
    mesh: &tobj::Mesh,
    name: &str,
    material: u32,
    path: &Path,
    stats: &mut CleanStats,
    warnings: &mut Vec<String>,
) -> Option<TriangleMesh> {
    let positions: Vec<Vec3> = mesh
        .positions
        .chunks_exact(3)
        .map(Vec3::from_slice)
        .collect();
    let mut normals: Vec<Vec3> = mesh.normals.chunks_exact(3).map(Vec3::from_slice).collect();
    if !normals.is_empty() && normals.len() != positions.len() {
        warnings.push(format!(
            "{}: object `{name}`: some faces have vertex normals and some do not; its vertex normals are ignored",
            path.display()
        ));
        normals.clear();
    }

    let mut indices = Vec::with_capacity(mesh.indices.len() / 3);
    // Area-weighted sum of the geometric normals around each vertex (to repair bad normals).
    let mut around = vec![
        Vec3::ZERO;
        if normals.is_empty() {
            0
        } else {
            positions.len()
        }
    ];
    for t in mesh.indices.chunks_exact(3) {
        let [a, b, c] = [t[0], t[1], t[2]];
        let (Some(&p0), Some(&p1), Some(&p2)) = (
            positions.get(a as usize),
            positions.get(b as usize),
            positions.get(c as usize),
        ) else {
            stats.degenerate += 1;
            continue;
        };
        let (e1, e2) = (p1 - p0, p2 - p0);
        let n = e1.cross(e2); // |n| = 2 * area
                              // Zero area, or so thin (sine of the angle below 1e-6) that f32 cannot orient it.
        let ok = a != b
            && b != c
            && a != c
            && (p0.is_finite() && p1.is_finite() && p2.is_finite())
            && n.is_finite()
            && n.length() > 1e-6 * e1.length() * e2.length();
        if !ok {
            stats.degenerate += 1;
            continue;
        }
        for &v in &[a, b, c] {
            if let Some(s) = around.get_mut(v as usize) {
                *s += n;
            }
        }
        indices.push([a, b, c]);
    }
    if indices.is_empty() {
        return None;
    }

    for (ns, sum) in normals.iter_mut().zip(&around) {
        let unit = safe_normalize(*ns);
        *ns = match unit {
            Some(u) => u,
            None => {
                stats.bad_normals += 1;
                safe_normalize(*sum).unwrap_or(Vec3::Y)
            }
        };
    }
    if !normals.is_empty() {
        for &[a, b, c] in &indices {
            let [p0, p1, p2] = [a, b, c].map(|i| positions[i as usize]);
            let ng = (p1 - p0).cross(p2 - p0);
            let sum = normals[a as usize] + normals[b as usize] + normals[c as usize];
            if sum.dot(ng) < 0.0 {
                stats.flipped += 1;
            }
        }
    }

    let materials = vec![material; indices.len()];
    Some(TriangleMesh {
        positions,
        normals,
        indices,
        materials,
    })
}

/// The normal of a polygon, |n| = 2 area, robust for non-planar ones (Newell's method).
fn newell_normal(points: impl Iterator<Item = Vec3> + Clone) -> Vec3 {
    let next = points.clone().cycle().skip(1);
    points
        .zip(next)
        .fold(Vec3::ZERO, |n, (a, b)| n + (a - b).cross(a + b) * 0.5)
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
