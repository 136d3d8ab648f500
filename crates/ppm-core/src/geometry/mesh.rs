//! Indexed triangle meshes as loaded from files or built in code.

use glam::Vec3;

/// An indexed triangle mesh. Winding is counter-clockwise seen from the side the geometric
/// normal points to: `ng = normalize(cross(v1 - v0, v2 - v0))`.
#[derive(Clone, Debug, Default)]
pub struct TriangleMesh {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Per-vertex shading normals, indexed like `positions`; empty when the mesh has none.
    pub normals: Vec<Vec3>,
    /// Vertex indices, three per triangle.
    pub indices: Vec<[u32; 3]>,
    /// Material index per triangle (same length as `indices`).
    pub materials: Vec<u32>,
}

impl TriangleMesh {
    /// A mesh with one material for every triangle and no vertex normals.
    pub fn new(positions: Vec<Vec3>, indices: Vec<[u32; 3]>, material: u32) -> Self {
        let materials = vec![material; indices.len()];
        TriangleMesh {
            positions,
            normals: Vec::new(),
            indices,
            materials,
        }
    }

    /// The two triangles of the quad `corner + s * edge_u + t * edge_v`, s, t in [0, 1], whose
    /// normal is `normalize(cross(edge_u, edge_v))`.
    pub fn quad(corner: Vec3, edge_u: Vec3, edge_v: Vec3, material: u32) -> Self {
        let positions = vec![
            corner,
            corner + edge_u,
            corner + edge_u + edge_v,
            corner + edge_v,
        ];
        Self::new(positions, vec![[0, 1, 2], [0, 2, 3]], material)
    }
}
