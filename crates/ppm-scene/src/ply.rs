//! Stanford PLY meshes: ASCII, binary little endian and binary big endian; triangles and
//! polygons (split into fans, so a quad gives two triangles); vertex normals (`nx ny nz`) and
//! texture coordinates (`u v`, `s t`, `texture_u texture_v` or `texture_s texture_t`).
//! Other elements and properties are read past.
//!
//! A reader of our own rather than `ply-rs` (unmaintained since 2018) or its fork `ply-rs-bw`
//! (which needs Rust 1.87, above this workspace's 1.86): both build a hash map per vertex and
//! per face, and neither bounds what a lying header makes them allocate. This one checks every
//! count against the bytes left before allocating and names the file, element and instance
//! (and the line, in the header and in ASCII bodies) in its errors.

use crate::LoadError;
use glam::{Vec2, Vec3};
use ppm_core::geometry::TriangleMesh;
use std::path::Path;

/// A triangle mesh read from a file, before ppm's material and placement.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshData {
    pub positions: Vec<Vec3>,
    /// Per-vertex normals as stored (not normalised), or empty.
    pub normals: Vec<Vec3>,
    /// Per-vertex texture coordinates as stored, or empty.
    pub uvs: Vec<Vec2>,
    pub indices: Vec<[u32; 3]>,
}

impl MeshData {
    /// ppm's mesh with `material` everywhere; normals normalised; texture coordinates as
    /// stored (Mitsuba 3 reads PLY and serialized uvs unflipped).
    pub fn into_triangle_mesh(self, material: u32) -> TriangleMesh {
        let mut mesh = TriangleMesh::new(self.positions, self.indices, material);
        mesh.normals = self.normals.iter().map(|n| n.normalize_or_zero()).collect();
        if self.uvs.len() == mesh.positions.len() {
            mesh.uvs = self.uvs;
        }
        mesh
    }
}

/// Largest PLY file read, in bytes.
pub const MAX_FILE_BYTES: u64 = 4 << 30;

/// Reads the PLY file at `path`.
pub fn load_ply(path: &Path) -> Result<MeshData, LoadError> {
    // Read and parsed once per load however many shapes name it (`file_cache`).
    crate::file_cache::parsed("ply", path, String::new(), || {
        let bytes = read_bytes(path, "PLY file", MAX_FILE_BYTES)?;
        parse_ply(&bytes, path)
    })
}

/// A regular file's bytes, at most `max`.
pub(crate) fn read_bytes(path: &Path, what: &str, max: u64) -> Result<Vec<u8>, LoadError> {
    let io = |source| LoadError::Io {
        path: path.to_path_buf(),
        what: what.to_string(),
        source,
    };
    let meta = std::fs::metadata(path).map_err(io)?;
    if !meta.is_file() {
        return Err(io(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!(
                "it is {}, not a regular file",
                crate::obj::file_kind(&meta.file_type())
            ),
        )));
    }
    if meta.len() > max {
        return Err(LoadError::parse(
            path,
            0,
            format!("the file is {} bytes, more than the {max} read", meta.len()),
        ));
    }
    crate::file_cache::note_read();
    std::fs::read(path).map_err(io)
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(name: &str) -> Option<Self> {
        Some(match name {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }
}

#[derive(Debug)]
enum Property {
    Scalar(String, Scalar),
    /// name, count type, item type.
    List(String, Scalar, Scalar),
}

impl Property {
    fn name(&self) -> &str {
        match self {
            Property::Scalar(n, _) | Property::List(n, _, _) => n,
        }
    }

    /// Fewest bytes one value takes in a binary file.
    fn min_size(&self) -> usize {
        match self {
            Property::Scalar(_, t) => t.size(),
            Property::List(_, c, _) => c.size(),
        }
    }
}

#[derive(Debug)]
struct Element {
    name: String,
    count: u64,
    properties: Vec<Property>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Format {
    Ascii,
    LittleEndian,
    BigEndian,
}

/// The body's values, read one at a time as f64 (exact for every PLY integer type).
enum Body<'a> {
    /// Tokens with their 1-based line numbers.
    Ascii {
        text: &'a [u8],
        pos: usize,
        line: usize,
    },
    Binary {
        data: &'a [u8],
        pos: usize,
        big_endian: bool,
    },
}

impl Body<'_> {
    fn remaining(&self) -> usize {
        match self {
            Body::Ascii { text, pos, .. } => text.len() - pos,
            Body::Binary { data, pos, .. } => data.len() - pos,
        }
    }

    fn read(&mut self, ty: Scalar) -> Result<f64, String> {
        match self {
            Body::Ascii { text, pos, line } => {
                while *pos < text.len() && text[*pos].is_ascii_whitespace() {
                    if text[*pos] == b'\n' {
                        *line += 1;
                    }
                    *pos += 1;
                }
                let start = *pos;
                while *pos < text.len() && !text[*pos].is_ascii_whitespace() {
                    *pos += 1;
                }
                if start == *pos {
                    return Err("the file ends early".into());
                }
                let token = String::from_utf8_lossy(&text[start..*pos]);
                let v: f64 = token
                    .parse()
                    .map_err(|_| format!("line {line}: `{token}` is not a number"))?;
                let integral = !matches!(ty, Scalar::F32 | Scalar::F64);
                if integral && v.fract() != 0.0 {
                    return Err(format!("line {line}: `{token}` is not an integer"));
                }
                Ok(v)
            }
            Body::Binary {
                data,
                pos,
                big_endian,
            } => {
                let n = ty.size();
                if data.len() - *pos < n {
                    return Err("the file ends early".into());
                }
                let mut b = [0u8; 8];
                b[..n].copy_from_slice(&data[*pos..*pos + n]);
                if *big_endian {
                    b[..n].reverse();
                }
                *pos += n;
                Ok(match ty {
                    Scalar::I8 => b[0] as i8 as f64,
                    Scalar::U8 => b[0] as f64,
                    Scalar::I16 => i16::from_le_bytes([b[0], b[1]]) as f64,
                    Scalar::U16 => u16::from_le_bytes([b[0], b[1]]) as f64,
                    Scalar::I32 => i32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
                    Scalar::U32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
                    Scalar::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
                    Scalar::F64 => f64::from_le_bytes(b),
                })
            }
        }
    }
}

/// The header: format, elements, and where the body starts.
fn parse_header(bytes: &[u8], path: &Path) -> Result<(Format, Vec<Element>, usize), LoadError> {
    let err = |line: usize, m: String| LoadError::parse(path, line, m);
    if !bytes.starts_with(b"ply") {
        return Err(err(
            1,
            "not a PLY file (it does not start with `ply`)".into(),
        ));
    }
    let mut format = None;
    let mut elements: Vec<Element> = Vec::new();
    let mut pos = 0;
    let mut line_no = 0;
    loop {
        let end = bytes[pos..]
            .iter()
            .position(|&b| b == b'\n')
            .ok_or_else(|| err(line_no + 1, "the header has no `end_header`".into()))?;
        let line = String::from_utf8_lossy(&bytes[pos..pos + end]);
        pos += end + 1;
        line_no += 1;
        let words: Vec<&str> = line.split_whitespace().collect();
        match words.as_slice() {
            ["ply"] if line_no == 1 => {}
            [] | ["comment", ..] | ["obj_info", ..] => {}
            ["format", f, _version] => {
                format = Some(match *f {
                    "ascii" => Format::Ascii,
                    "binary_little_endian" => Format::LittleEndian,
                    "binary_big_endian" => Format::BigEndian,
                    _ => return Err(err(line_no, format!("unknown format `{f}`"))),
                })
            }
            ["element", name, count] => elements.push(Element {
                name: name.to_string(),
                count: count.parse().map_err(|_| {
                    err(
                        line_no,
                        format!("element `{name}`: count `{count}` is not a number"),
                    )
                })?,
                properties: Vec::new(),
            }),
            ["property", "list", c, t, name] => {
                let ty = |s: &str| {
                    Scalar::parse(s).ok_or_else(|| err(line_no, format!("unknown type `{s}`")))
                };
                let (c, t) = (ty(c)?, ty(t)?);
                if matches!(c, Scalar::F32 | Scalar::F64) {
                    return Err(err(
                        line_no,
                        "a list's count must be an integer type".into(),
                    ));
                }
                elements
                    .last_mut()
                    .ok_or_else(|| err(line_no, "a property before any element".into()))?
                    .properties
                    .push(Property::List(name.to_string(), c, t));
            }
            ["property", t, name] => {
                let t =
                    Scalar::parse(t).ok_or_else(|| err(line_no, format!("unknown type `{t}`")))?;
                elements
                    .last_mut()
                    .ok_or_else(|| err(line_no, "a property before any element".into()))?
                    .properties
                    .push(Property::Scalar(name.to_string(), t));
            }
            ["end_header"] => break,
            _ => {
                return Err(err(
                    line_no,
                    format!("unexpected header line `{}`", line.trim()),
                ))
            }
        }
    }
    let format = format.ok_or_else(|| err(line_no, "the header has no `format` line".into()))?;
    Ok((format, elements, pos))
}

/// Where the vertex properties ppm reads are in the element's property list.
struct VertexLayout {
    position: [usize; 3],
    normal: Option<[usize; 3]>,
    uv: Option<[usize; 2]>,
}

fn vertex_layout(e: &Element) -> Result<VertexLayout, String> {
    let find = |n: &str| {
        e.properties
            .iter()
            .position(|p| p.name() == n && matches!(p, Property::Scalar(..)))
    };
    let all3 = |names: [&str; 3]| -> Option<[usize; 3]> {
        Some([find(names[0])?, find(names[1])?, find(names[2])?])
    };
    let position = all3(["x", "y", "z"]).ok_or("element `vertex` needs properties x, y and z")?;
    let uv = [
        ("u", "v"),
        ("s", "t"),
        ("texture_u", "texture_v"),
        ("texture_s", "texture_t"),
    ]
    .iter()
    .find_map(|(u, v)| Some([find(u)?, find(v)?]));
    Ok(VertexLayout {
        position,
        normal: all3(["nx", "ny", "nz"]),
        uv,
    })
}

/// Parses PLY bytes; `path` names the file in messages.
pub fn parse_ply(bytes: &[u8], path: &Path) -> Result<MeshData, LoadError> {
    let (format, elements, start) = parse_header(bytes, path)?;
    let mut body = match format {
        Format::Ascii => Body::Ascii {
            text: &bytes[start..],
            pos: 0,
            line: 1 + bytes[..start].iter().filter(|&&b| b == b'\n').count(),
        },
        Format::LittleEndian | Format::BigEndian => Body::Binary {
            data: &bytes[start..],
            pos: 0,
            big_endian: format == Format::BigEndian,
        },
    };
    let mut mesh = MeshData::default();
    let mut vertex_count: Option<u64> = None;
    let mut values = Vec::new();
    for e in &elements {
        let fail =
            |i: u64, m: String| LoadError::parse(path, 0, format!("element `{}` {i}: {m}", e.name));
        if e.properties.is_empty() {
            continue;
        }
        // Each instance takes at least this many bytes (in ASCII, a digit and a separator
        // per value).
        let min: usize = match format {
            Format::Ascii => 2 * e.properties.len(),
            _ => e.properties.iter().map(Property::min_size).sum(),
        };
        // (The last ASCII value may lack its separator: one byte of slack.)
        if e.count.saturating_mul(min as u64) > body.remaining() as u64 + 1 {
            return Err(LoadError::parse(
                path,
                0,
                format!(
                    "element `{}` declares {} instances, more than the {} bytes left can hold",
                    e.name,
                    e.count,
                    body.remaining()
                ),
            ));
        }
        let layout = if e.name == "vertex" {
            if vertex_count.is_some() {
                return Err(fail(0, "a second `vertex` element".into()));
            }
            vertex_count = Some(e.count);
            let l = vertex_layout(e).map_err(|m| LoadError::parse(path, 0, m))?;
            mesh.positions.reserve(e.count as usize);
            Some(l)
        } else {
            None
        };
        let face_list = (e.name == "face").then(|| {
            e.properties
                .iter()
                .position(|p| matches!(p, Property::List(n, ..) if n == "vertex_indices" || n == "vertex_index"))
        });
        let face_list = match face_list {
            Some(None) => {
                return Err(fail(
                    0,
                    "element `face` has no list `vertex_indices`".into(),
                ))
            }
            Some(Some(i)) => Some(i),
            None => None,
        };
        for i in 0..e.count {
            values.clear();
            let mut face: Vec<u32> = Vec::new();
            for (k, p) in e.properties.iter().enumerate() {
                match p {
                    Property::Scalar(_, t) => values.push(body.read(*t).map_err(|m| fail(i, m))?),
                    Property::List(name, c, t) => {
                        let n = body.read(*c).map_err(|m| fail(i, m))?;
                        // Each item takes its size in binary, a digit at least in ASCII.
                        let item = if format == Format::Ascii { 1 } else { t.size() };
                        if n < 0.0 || n * item as f64 > body.remaining() as f64 {
                            return Err(fail(i, format!("list `{name}` has a bad length {n}")));
                        }
                        values.push(f64::NAN);
                        for _ in 0..n as u64 {
                            let v = body.read(*t).map_err(|m| fail(i, m))?;
                            if face_list == Some(k) {
                                let nv = vertex_count.unwrap_or(0);
                                if !(v >= 0.0 && v < nv as f64) {
                                    return Err(fail(
                                        i,
                                        format!("vertex index {v} is out of range ({nv} vertices)"),
                                    ));
                                }
                                face.push(v as u32);
                            }
                        }
                    }
                }
            }
            if let Some(l) = &layout {
                let v3 = |idx: [usize; 3]| {
                    Vec3::new(
                        values[idx[0]] as f32,
                        values[idx[1]] as f32,
                        values[idx[2]] as f32,
                    )
                };
                let p = v3(l.position);
                if !p.is_finite() {
                    return Err(fail(i, format!("position {p} is not finite")));
                }
                mesh.positions.push(p);
                if let Some(n) = l.normal {
                    mesh.normals.push(v3(n));
                }
                if let Some([u, v]) = l.uv {
                    mesh.uvs.push(Vec2::new(values[u] as f32, values[v] as f32));
                }
            }
            // A polygon as a fan around its first vertex; fewer than 3 vertices is nothing.
            for k in 1..face.len().saturating_sub(1) {
                mesh.indices.push([face[0], face[k], face[k + 1]]);
            }
        }
    }
    if vertex_count.is_none() {
        return Err(LoadError::parse(path, 0, "no `vertex` element"));
    }
    Ok(mesh)
}
