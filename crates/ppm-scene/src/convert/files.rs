//! The files `ppm convert` writes beside the YAML: meshes as binary PLY, textures and
//! environment maps as 32-bit float OpenEXR (linear, exactly the values held in memory).

use crate::error::LoadError;
use glam::Vec3;
use ppm_core::geometry::TriangleMesh;
use std::io::Write;
use std::path::Path;

/// An I/O error writing `path`.
fn write_error(path: &Path, what: &str, source: std::io::Error) -> LoadError {
    LoadError::Io {
        path: path.to_path_buf(),
        what: format!("{what} (writing)"),
        source,
    }
}

/// Writes the triangles of `mesh` whose material is `material` as a binary little-endian PLY:
/// positions, the normals and uvs if the mesh has them, and the triangles, with the mesh's
/// vertices (all of them, so indices keep their values).
pub(crate) fn write_ply(path: &Path, mesh: &TriangleMesh, material: u32) -> Result<(), LoadError> {
    let triangles: Vec<[u32; 3]> = mesh
        .indices
        .iter()
        .zip(&mesh.materials)
        .filter(|(_, &m)| m == material)
        .map(|(t, _)| *t)
        .collect();
    let normals = mesh.normals.len() == mesh.positions.len();
    let uvs = mesh.uvs.len() == mesh.positions.len();
    let mut header =
        String::from("ply\nformat binary_little_endian 1.0\ncomment written by ppm convert\n");
    header.push_str(&format!("element vertex {}\n", mesh.positions.len()));
    header.push_str("property float x\nproperty float y\nproperty float z\n");
    if normals {
        header.push_str("property float nx\nproperty float ny\nproperty float nz\n");
    }
    if uvs {
        header.push_str("property float u\nproperty float v\n");
    }
    header.push_str(&format!("element face {}\n", triangles.len()));
    header.push_str("property list uchar uint vertex_indices\nend_header\n");
    let mut bytes = header.into_bytes();
    let mut put = |x: f32| bytes.extend_from_slice(&x.to_le_bytes());
    for (i, p) in mesh.positions.iter().enumerate() {
        p.to_array().into_iter().for_each(&mut put);
        if normals {
            mesh.normals[i].to_array().into_iter().for_each(&mut put);
        }
        if uvs {
            mesh.uvs[i].to_array().into_iter().for_each(&mut put);
        }
    }
    for t in &triangles {
        bytes.push(3);
        for i in t {
            bytes.extend_from_slice(&i.to_le_bytes());
        }
    }
    let mut file = std::fs::File::create(path).map_err(|e| write_error(path, "mesh", e))?;
    file.write_all(&bytes)
        .map_err(|e| write_error(path, "mesh", e))
}

/// Writes `width` x `height` linear RGB `texels` (row-major from the top row) as a 32-bit
/// float OpenEXR.
pub(crate) fn write_exr(
    path: &Path,
    width: usize,
    height: usize,
    texels: &[Vec3],
    what: &str,
) -> Result<(), LoadError> {
    use exr::prelude::{Image, SpecificChannels, WritableImage};
    let channels = SpecificChannels::rgb(|exr::math::Vec2(x, y)| {
        let t: Vec3 = texels[y * width + x];
        (t.x, t.y, t.z)
    });
    Image::from_channels((width, height), channels)
        .write()
        .to_file(path)
        .map_err(|e| write_error(path, what, std::io::Error::other(e.to_string())))
}
