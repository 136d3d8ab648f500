//! `{ type: mesh, file: x.ply }` in scene format v1: a PLY mesh (ASCII or binary, as the
//! Mitsuba importer reads it) with the object's material everywhere.
//!
//! Vertex normals within 1e-6 of unit length are kept as stored, bit for bit, so a mesh that
//! `ppm convert` wrote loads back exactly as it was in memory; others are normalised (zero
//! ones stay zero: the face normal is used there). Texture coordinates are kept as stored.

use crate::error::LoadError;
use crate::obj::ObjData;
use glam::DVec3;
use std::path::Path;

/// The PLY mesh at `path`, its points made relative to `origin` (in double precision, as OBJ
/// meshes are), every triangle of material 0.
pub(crate) fn load_ply_object(path: &Path, origin: DVec3) -> Result<ObjData, LoadError> {
    let data = crate::ply::load_ply(path)?;
    let positions = if origin == DVec3::ZERO {
        data.positions
    } else {
        data.positions
            .iter()
            .map(|p| (p.as_dvec3() - origin).as_vec3())
            .collect()
    };
    let mut mesh = ppm_core::geometry::TriangleMesh::new(positions, data.indices, 0);
    mesh.normals = data
        .normals
        .iter()
        .map(|n| {
            if (n.length_squared() - 1.0).abs() <= 1e-6 {
                *n
            } else {
                n.normalize_or_zero()
            }
        })
        .collect();
    if data.uvs.len() == mesh.positions.len() {
        mesh.uvs = data.uvs;
    }
    Ok(ObjData {
        meshes: vec![mesh],
        materials: Vec::new(),
    })
}
