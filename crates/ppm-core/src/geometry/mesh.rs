//! Indexed triangle meshes as loaded from files or built in code.

use glam::{Vec2, Vec3};

/// An indexed triangle mesh. Winding is counter-clockwise seen from the side the geometric
/// normal points to: `ng = normalize(cross(v1 - v0, v2 - v0))`.
#[derive(Clone, Debug, Default)]
pub struct TriangleMesh {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Per-vertex shading normals, indexed like `positions`; empty when the mesh has none.
    pub normals: Vec<Vec3>,
    /// Per-vertex texture coordinates, indexed like `positions`; empty when the mesh has
    /// none (a hit then takes its barycentrics (b1, b2) as uv, as Mitsuba 3 does).
    pub uvs: Vec<Vec2>,
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
            uvs: Vec::new(),
            indices,
            materials,
        }
    }

    /// The two triangles of the quad `corner + s * edge_u + t * edge_v`, s, t in [0, 1], whose
    /// normal is `normalize(cross(edge_u, edge_v))`. Its uv is (s, t): Mitsuba 3's
    /// `rectangle` convention for the rectangle's corner (-1, -1, 0) and edges 2x, 2y.
    pub fn quad(corner: Vec3, edge_u: Vec3, edge_v: Vec3, material: u32) -> Self {
        let positions = vec![
            corner,
            corner + edge_u,
            corner + edge_u + edge_v,
            corner + edge_v,
        ];
        let mut mesh = Self::new(positions, vec![[0, 1, 2], [0, 2, 3]], material);
        mesh.uvs = vec![Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y];
        mesh
    }

    /// A closed, bumpy sphere for benchmarks and tests of large meshes: each face of a cube
    /// cut into `n` x `n` quads (12 n^2 triangles), its points pushed onto the sphere of
    /// `radius` around `center` and displaced along the radius by
    /// `amplitude * sin(f x) sin(f y) sin(f z)` of the unit direction (f = `frequency`).
    /// Points on a cube edge are computed from the same cube coordinates by every face that
    /// shares them, so they are bitwise equal and the mesh is watertight. Outward normals.
    pub fn displaced_sphere(
        center: Vec3,
        radius: f32,
        n: u32,
        amplitude: f32,
        frequency: f32,
        material: u32,
    ) -> Self {
        let side = n + 1;
        let grid = |i: u32| 2.0 * i as f32 / n as f32 - 1.0;
        let mut positions = Vec::with_capacity(6 * (side * side) as usize);
        let mut indices = Vec::with_capacity(12 * (n * n) as usize);
        // (normal axis, sign): the face's cube points are `sign` on that axis.
        for (axis, sign) in [
            (0, 1.0),
            (0, -1.0),
            (1, 1.0),
            (1, -1.0),
            (2, 1.0),
            (2, -1.0),
        ] {
            let base = positions.len() as u32;
            for i in 0..side {
                for j in 0..side {
                    let mut c = [0.0f32; 3];
                    c[axis] = sign;
                    c[(axis + 1) % 3] = grid(i);
                    c[(axis + 2) % 3] = grid(j);
                    let d = Vec3::from_array(c).normalize();
                    let bump =
                        (frequency * d.x).sin() * (frequency * d.y).sin() * (frequency * d.z).sin();
                    positions.push(center + d * (radius * (1.0 + amplitude * bump)));
                }
            }
            let v = |i: u32, j: u32| base + i * side + j;
            for i in 0..n {
                for j in 0..n {
                    // cross(e_u, e_v) points along +axis; flip the winding on the -axis face.
                    let (a, b, c, d) = (v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j + 1));
                    if sign > 0.0 {
                        indices.push([a, b, c]);
                        indices.push([a, c, d]);
                    } else {
                        indices.push([a, c, b]);
                        indices.push([a, d, c]);
                    }
                }
            }
        }
        Self::new(positions, indices, material)
    }
}
