//! Mitsuba's `.serialized` meshes, format versions 3 and 4 (what Mitsuba 0.5/0.6 and the
//! exporters write). A file is a sequence of meshes, each:
//! - `u16` magic 0x041C, `u16` version (3 or 4), little endian;
//! - a zlib stream holding: `u32` flags (0x0001 vertex normals, 0x0002 texture coordinates,
//!   0x0008 vertex colours, 0x0010 use face normals, 0x1000 single / 0x2000 double precision),
//!   in version 4 the mesh's name (UTF-8, NUL-terminated), `u64` vertex count V, `u64`
//!   triangle count F, then 3V positions, 3V normals, 2V texture coordinates, 3V colours
//!   (each if flagged; `f32`, or `f64` with 0x2000) and 3F `u32` vertex indices.
//!
//! The file ends with a table to find mesh i: the meshes' byte offsets (`u64` in version 4,
//! `u32` in version 3) and then a `u32` mesh count.

use crate::ply::{read_bytes, MeshData};
use crate::LoadError;
use flate2::read::ZlibDecoder;
use glam::{Vec2, Vec3};
use std::io::Read;
use std::path::Path;

const MAGIC: u16 = 0x041C;
const HAS_NORMALS: u32 = 0x0001;
const HAS_TEXCOORDS: u32 = 0x0002;
const HAS_COLORS: u32 = 0x0008;
const FACE_NORMALS: u32 = 0x0010;
const DOUBLE_PRECISION: u32 = 0x2000;

/// Largest file read, in bytes.
pub const MAX_FILE_BYTES: u64 = 4 << 30;
/// Most vertices or triangles in one mesh.
pub const MAX_COUNT: u64 = 1 << 28;
/// Longest mesh name read (version 4).
const MAX_NAME: usize = 4096;

/// Reads mesh `shape_index` of the file at `path`.
pub fn load_serialized(path: &Path, shape_index: u32) -> Result<MeshData, LoadError> {
    // The file is read once per load, each of its meshes parsed once (`file_cache`).
    crate::file_cache::parsed("serialized", path, shape_index.to_string(), || {
        let bytes = crate::file_cache::parsed("serialized file", path, String::new(), || {
            read_bytes(path, "serialized mesh file", MAX_FILE_BYTES).map(std::rc::Rc::new)
        })?;
        parse_serialized(&bytes, path, shape_index)
    })
}

fn u16_at(b: &[u8], at: usize) -> Option<u16> {
    Some(u16::from_le_bytes(b.get(at..at + 2)?.try_into().ok()?))
}
fn u32_at(b: &[u8], at: usize) -> Option<u32> {
    Some(u32::from_le_bytes(b.get(at..at + 4)?.try_into().ok()?))
}
fn u64_at(b: &[u8], at: usize) -> Option<u64> {
    Some(u64::from_le_bytes(b.get(at..at + 8)?.try_into().ok()?))
}

/// Parses mesh `shape_index` from the bytes of a serialized file; `path` names it.
pub fn parse_serialized(
    bytes: &[u8],
    path: &Path,
    shape_index: u32,
) -> Result<MeshData, LoadError> {
    let fail = |m: String| LoadError::parse(path, 0, format!("mesh {shape_index}: {m}"));
    let version = header(bytes, 0).map_err(|m| LoadError::parse(path, 0, m))?;
    let offset = if shape_index == 0 {
        0
    } else {
        let count = bytes
            .len()
            .checked_sub(4)
            .and_then(|at| u32_at(bytes, at))
            .ok_or_else(|| fail("the file is too short for its table of meshes".into()))?;
        if shape_index >= count {
            return Err(fail(format!(
                "the file has {count} meshes (shape_index 0 to {})",
                count.max(1) - 1
            )));
        }
        let from_end = (count - shape_index) as usize;
        let at = if version == 4 {
            bytes
                .len()
                .checked_sub(8 * from_end + 4)
                .and_then(|at| u64_at(bytes, at))
        } else {
            bytes
                .len()
                .checked_sub(4 * (from_end + 1))
                .and_then(|at| u32_at(bytes, at).map(u64::from))
        };
        at.and_then(|o| usize::try_from(o).ok())
            .filter(|&o| o < bytes.len())
            .ok_or_else(|| fail("its offset in the table is outside the file".into()))?
    };
    let version = header(bytes, offset).map_err(fail)?;
    let mut z = ZlibDecoder::new(&bytes[offset + 4..]);
    read_mesh(&mut z, version).map_err(fail)
}

/// The format version of the mesh at `at`, after checking its magic number.
fn header(bytes: &[u8], at: usize) -> Result<u16, String> {
    let magic = u16_at(bytes, at).ok_or("the file is too short for a header")?;
    if magic != MAGIC {
        return Err(format!(
            "not a Mitsuba serialized mesh (magic {magic:#06x}, expected 0x041c)"
        ));
    }
    match u16_at(bytes, at + 2) {
        Some(v @ (3 | 4)) => Ok(v),
        Some(v) => Err(format!(
            "format version {v} is not supported (ppm reads versions 3 and 4)"
        )),
        None => Err("the file is too short for a header".into()),
    }
}

/// Exactly `n` bytes of the stream; reading stops at what the stream has, so a lying count
/// costs no more memory than the data.
fn take(z: &mut impl Read, n: u64, what: &str) -> Result<Vec<u8>, String> {
    let mut buf = Vec::new();
    z.take(n)
        .read_to_end(&mut buf)
        .map_err(|e| format!("{what}: {e}"))?;
    if (buf.len() as u64) < n {
        return Err(format!("{what}: the data ends early"));
    }
    Ok(buf)
}

/// `n` vectors of `dim` reals (f32, or f64 when `double`).
fn reals(
    z: &mut impl Read,
    n: u64,
    dim: usize,
    double: bool,
    what: &str,
) -> Result<Vec<f32>, String> {
    let size = if double { 8 } else { 4 };
    let bytes = take(z, n * dim as u64 * size, what)?;
    Ok(if double {
        bytes
            .chunks_exact(8)
            .map(|c| f64::from_le_bytes(c.try_into().unwrap()) as f32)
            .collect()
    } else {
        bytes
            .chunks_exact(4)
            .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
            .collect()
    })
}

fn read_mesh(z: &mut impl Read, version: u16) -> Result<MeshData, String> {
    let word = |z: &mut dyn Read, n: usize| -> Result<Vec<u8>, String> {
        let mut b = vec![0; n];
        z.read_exact(&mut b)
            .map_err(|e| format!("the header: {e}"))?;
        Ok(b)
    };
    let flags = u32::from_le_bytes(word(z, 4)?.try_into().unwrap());
    if version == 4 {
        // The name: bytes up to a NUL.
        let mut len = 0;
        loop {
            if word(z, 1)?[0] == 0 {
                break;
            }
            len += 1;
            if len > MAX_NAME {
                return Err(format!("the mesh name is longer than {MAX_NAME} bytes"));
            }
        }
    }
    let vertices = u64::from_le_bytes(word(z, 8)?.try_into().unwrap());
    let triangles = u64::from_le_bytes(word(z, 8)?.try_into().unwrap());
    if vertices > MAX_COUNT || triangles > MAX_COUNT {
        return Err(format!(
            "{vertices} vertices and {triangles} triangles: more than the {MAX_COUNT} read"
        ));
    }
    let double = flags & DOUBLE_PRECISION != 0;
    let p = reals(z, vertices, 3, double, "positions")?;
    let mut mesh = MeshData {
        positions: p.chunks_exact(3).map(Vec3::from_slice).collect(),
        ..MeshData::default()
    };
    if let Some(bad) = mesh.positions.iter().position(|p| !p.is_finite()) {
        return Err(format!("vertex {bad}: its position is not finite"));
    }
    if flags & HAS_NORMALS != 0 {
        let n = reals(z, vertices, 3, double, "normals")?;
        if flags & FACE_NORMALS == 0 {
            mesh.normals = n.chunks_exact(3).map(Vec3::from_slice).collect();
        }
    }
    if flags & HAS_TEXCOORDS != 0 {
        let uv = reals(z, vertices, 2, double, "texture coordinates")?;
        mesh.uvs = uv.chunks_exact(2).map(Vec2::from_slice).collect();
    }
    if flags & HAS_COLORS != 0 {
        reals(z, vertices, 3, double, "vertex colours")?;
    }
    let idx = take(z, triangles * 12, "triangles")?;
    for (t, c) in idx.chunks_exact(12).enumerate() {
        let tri = [0, 1, 2].map(|k| u32::from_le_bytes(c[4 * k..4 * k + 4].try_into().unwrap()));
        if let Some(&bad) = tri.iter().find(|&&i| i as u64 >= vertices) {
            return Err(format!(
                "triangle {t}: vertex index {bad} is out of range ({vertices} vertices)"
            ));
        }
        mesh.indices.push(tri);
    }
    Ok(mesh)
}
