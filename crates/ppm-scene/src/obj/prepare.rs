//! The checking pass in front of tobj: OBJ text in, errors with line numbers out, or a
//! rewritten text tobj cannot choke on (see the module docs of `obj`).

use super::safe_normalize;
use crate::error::LoadError;
use glam::{DVec3, Vec3};
use std::fmt::Write;
use std::path::Path;

/// The OBJ text rewritten for tobj, and what it needs to know about materials.
pub(super) struct Prepared {
    pub text: String,
    /// Each `mtllib` statement: its line and its argument.
    pub mtllibs: Vec<(usize, String)>,
    /// Each `usemtl` statement: its line and the material name.
    pub usemtl: Vec<(usize, String)>,
    /// Faces dropped for having no area.
    pub degenerate: usize,
}

/// Checks and rewrites OBJ text line by line (see the module docs). The output has only
/// `mtllib` (first, as statement numbers), `v` (minus `origin`, in double precision), `vn`,
/// `vt`, `f` (absolute indices), `o`, `g` and `usemtl` statements.
pub(super) fn prepare(
    text: &str,
    path: &Path,
    origin: DVec3,
    warnings: &mut Vec<String>,
) -> Result<Prepared, LoadError> {
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
    // Counts of what is skipped or ignored, with the line of the first occurrence.
    let mut short_faces = Tally::default();
    let mut bad_texcoords = Tally::default();
    let mut skipped_elements = Tally::default();
    let mut texcoords = 0usize;
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
                // At the world origin the numbers are read as f32 directly (no double
                // rounding through f64), exactly as ppm always read them.
                let p = if origin == DVec3::ZERO {
                    vertex(numbers::<f32>(&args, path, line_no, "v")?, path, line_no)?
                } else {
                    let p = vertex(numbers::<f64>(&args, path, line_no, "v")?, path, line_no)?;
                    (p - origin).as_vec3()
                };
                let _ = writeln!(body, "v {} {} {}", p.x, p.y, p.z);
                positions.push(p);
            }
            "vn" => {
                let n = numbers::<f32>(&args, path, line_no, "vn")?;
                if n.len() != 3 {
                    return Err(err(format!("`vn` needs x y z, found {} numbers", n.len())));
                }
                let _ = writeln!(body, "vn {} {} {}", n[0], n[1], n[2]);
                emitted_normals += 1;
                normal_index.push(emitted_normals);
            }
            "f" | "fo" => {
                let mut vertices = Vec::with_capacity(args.len());
                let mut uvs = Vec::with_capacity(args.len());
                let mut texcoord_ok = true;
                for token in &args {
                    let counts = (positions.len(), texcoords, normal_index.len());
                    let (v, vt, n) = face_vertex(token, counts, path, line_no)?;
                    texcoord_ok &= vt != Some(None);
                    uvs.push(vt.flatten());
                    vertices.push((v, n.map(|n| normal_index[n - 1])));
                }
                // A face's texture coordinates are kept when all its vertices have them.
                let uvs: Vec<usize> = uvs.iter().map_while(|t| *t).collect();
                let uvs = (uvs.len() == vertices.len()).then_some(uvs);
                if !texcoord_ok {
                    bad_texcoords.add(line_no);
                }
                if vertices.len() < 3 {
                    short_faces.add(line_no);
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
                for (k, (v, n)) in vertices.into_iter().enumerate() {
                    let _ = write!(body, " {v}");
                    match (uvs.as_ref().map(|t| t[k]), flat.or(n)) {
                        (Some(t), Some(n)) => write!(body, "/{t}/{n}"),
                        (Some(t), None) => write!(body, "/{t}"),
                        (None, Some(n)) => write!(body, "//{n}"),
                        (None, None) => Ok(()),
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
            // Texture coordinates: u v (a w is ignored). Smoothing groups: ppm shades with
            // the given vertex normals (or flat).
            "vt" => {
                let t = numbers::<f32>(&args, path, line_no, "vt")?;
                if !(1..=3).contains(&t.len()) {
                    return Err(err(format!(
                        "`vt` needs u [v [w]], found {} numbers",
                        t.len()
                    )));
                }
                let _ = writeln!(body, "vt {} {}", t[0], t.get(1).copied().unwrap_or(0.0));
                texcoords += 1;
            }
            "s" => {}
            "l" | "p" => skipped_elements.add(line_no),
            other => {
                if !unknown.iter().any(|u| u == other) {
                    unknown.push(other.to_string());
                }
            }
        }
    }
    let file = path.display();
    if let Some(first) = short_faces.first {
        warnings.push(format!(
            "{file}:{first}: skipped {} with fewer than 3 vertices{}",
            plural(short_faces.count, "face", "faces"),
            short_faces.more()
        ));
    }
    if let Some(first) = bad_texcoords.first {
        warnings.push(format!(
            "{file}:{first}: {} a texture coordinate index out of range{}; its texture coordinates are ignored",
            plural(bad_texcoords.count, "face has", "faces have"),
            bad_texcoords.more()
        ));
    }
    if let Some(first) = skipped_elements.first {
        warnings.push(format!(
            "{file}:{first}: ignored {} (not surfaces){}",
            plural(
                skipped_elements.count,
                "line or point element",
                "line and point elements"
            ),
            skipped_elements.more()
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

/// A `v` statement's position from its numbers: `x y z`, `x y z r g b` (vertex colours,
/// unused) or `x y z w` (homogeneous, divided by w).
fn vertex<T>(p: Vec<T>, path: &Path, line_no: usize) -> Result<T::Point, LoadError>
where
    T: Coordinate,
{
    match p.len() {
        3 | 6 => Ok(T::point(p[0], p[1], p[2])),
        4 if p[3] != T::ZERO => Ok(T::point(p[0] / p[3], p[1] / p[3], p[2] / p[3])),
        4 => Err(LoadError::parse(path, line_no, String::from("`v`: w is 0"))),
        n => Err(LoadError::parse(
            path,
            line_no,
            format!("`v` needs x y z [w], found {n} numbers"),
        )),
    }
}

/// f32 or f64 coordinates for [`vertex`].
trait Coordinate: Copy + PartialEq + std::ops::Div<Output = Self> {
    type Point;
    const ZERO: Self;
    fn point(x: Self, y: Self, z: Self) -> Self::Point;
}

impl Coordinate for f32 {
    type Point = Vec3;
    const ZERO: Self = 0.0;
    fn point(x: f32, y: f32, z: f32) -> Vec3 {
        Vec3::new(x, y, z)
    }
}

impl Coordinate for f64 {
    type Point = DVec3;
    const ZERO: Self = 0.0;
    fn point(x: f64, y: f64, z: f64) -> DVec3 {
        DVec3::new(x, y, z)
    }
}

/// How often something happened, and on which line first.
#[derive(Default)]
struct Tally {
    count: usize,
    first: Option<usize>,
}

impl Tally {
    fn add(&mut self, line_no: usize) {
        self.count += 1;
        self.first.get_or_insert(line_no);
    }

    /// Said after a count of several, so that the line number is read correctly.
    fn more(&self) -> &'static str {
        if self.count > 1 {
            " (the first on this line)"
        } else {
            ""
        }
    }
}

/// "1 face", "3 faces".
fn plural(n: usize, one: &str, many: &str) -> String {
    if n == 1 {
        format!("1 {one}")
    } else {
        format!("{n} {many}")
    }
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

fn numbers<T: std::str::FromStr>(
    args: &[&str],
    path: &Path,
    line_no: usize,
    keyword: &str,
) -> Result<Vec<T>, LoadError> {
    args.iter()
        .map(|a| {
            a.parse::<T>().map_err(|_| {
                LoadError::parse(path, line_no, format!("`{keyword}`: `{a}` is not a number"))
            })
        })
        .collect()
}

/// One `v`, `v/vt`, `v//vn` or `v/vt/vn` of a face, as absolute 1-based position and normal
/// indices, and whether its texture coordinate index (if any) names a `vt` defined so far;
/// `counts` are the positions, texture coordinates and normals defined before this line.
/// Negative indices count back from the last element defined so far (-1 = last).
fn face_vertex(
    token: &str,
    counts: (usize, usize, usize),
    path: &Path,
    line_no: usize,
) -> Result<(usize, TexcoordIndex, Option<usize>), LoadError> {
    let (n_positions, n_texcoords, n_normals) = counts;
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
    // None: no index; Some(None): an index out of range; Some(Some(i)): absolute index i.
    let texcoord = match vt {
        "" => None,
        vt => match vt.parse::<i64>() {
            Ok(i) if i != 0 && i.unsigned_abs() <= n_texcoords as u64 => {
                Some(Some(
                    if i < 0 { n_texcoords as i64 + 1 + i } else { i } as usize
                ))
            }
            Ok(_) => Some(None),
            Err(_) => {
                return Err(err(format!(
                    "face vertex `{token}`: `{vt}` is not a texture coordinate index"
                )))
            }
        },
    };
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
    Ok((position, texcoord, normal))
}

/// A face vertex's texture coordinate: `None` without one, `Some(None)` for an index out of
/// range, `Some(Some(i))` for the absolute index i.
type TexcoordIndex = Option<Option<usize>>;

/// The normal of a polygon, |n| = 2 area, robust for non-planar ones (Newell's method).
fn newell_normal(points: impl Iterator<Item = Vec3> + Clone) -> Vec3 {
    let next = points.clone().cycle().skip(1);
    points
        .zip(next)
        .fold(Vec3::ZERO, |n, (a, b)| n + (a - b).cross(a + b) * 0.5)
}
