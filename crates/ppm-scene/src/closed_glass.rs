//! Glass meshes that are not closed.
//!
//! A dielectric interface (Bsdf::Glass, Bsdf::Dielectric) bends light in on one side and out
//! on the other: a path that enters through a mesh with a hole never meets the exit and
//! carries the inside's index of refraction into the room, so the mesh looks wrong with no
//! error anywhere. A closed (watertight) mesh uses every edge by exactly two triangles; an
//! edge used by one triangle is open. (Thin glass sheets, Bsdf::ThinDielectric, are meant to
//! be open and are not checked.)

use ppm_core::bsdf::Bsdf;
use ppm_core::scene::SceneBuilder;
use std::collections::HashMap;

/// A vertex by its position's bits: vertices split by the OBJ loader (one per
/// position/normal/texture combination) share their position.
type VertexKey = [u32; 3];

/// The glass materials whose triangles have open edges: (material index, open edges),
/// counted per mesh and summed per material, in material order. Linear in the triangles
/// (one hash map of edges per mesh).
pub fn open_glass_edges(builder: &SceneBuilder) -> Vec<(u32, usize)> {
    let is_glass: Vec<bool> = builder
        .materials
        .iter()
        .map(|m| matches!(m.bsdf, Bsdf::Glass(_) | Bsdf::Dielectric(_)))
        .collect();
    let mut open = vec![0usize; is_glass.len()];
    for mesh in &builder.meshes {
        let key = |i: u32| -> VertexKey {
            let p = mesh.positions[i as usize];
            [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()]
        };
        // Triangles using each edge (both orientations alike), per material.
        let mut uses: HashMap<(u32, VertexKey, VertexKey), u32> = HashMap::new();
        for (triangle, &material) in mesh.indices.iter().zip(&mesh.materials) {
            if is_glass.get(material as usize) != Some(&true) {
                continue;
            }
            for k in 0..3 {
                let (a, b) = (key(triangle[k]), key(triangle[(k + 1) % 3]));
                let edge = if a <= b {
                    (material, a, b)
                } else {
                    (material, b, a)
                };
                *uses.entry(edge).or_insert(0) += 1;
            }
        }
        for ((material, _, _), n) in uses {
            if n == 1 {
                open[material as usize] += 1;
            }
        }
    }
    open.into_iter()
        .enumerate()
        .filter(|&(_, n)| n > 0)
        .map(|(material, n)| (material as u32, n))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use ppm_core::prelude::*;

    /// A unit cube of `material` (12 triangles, closed), without its top face if `open`.
    fn cube(material: u32, open: bool) -> TriangleMesh {
        let positions = (0..8)
            .map(|i| Vec3::new((i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32))
            .collect();
        let mut indices = vec![
            [0, 2, 1],
            [1, 2, 3], // z = 0
            [4, 5, 6],
            [5, 7, 6], // z = 1
            [0, 1, 4],
            [1, 5, 4], // y = 0
            [0, 4, 2],
            [2, 4, 6], // x = 0
            [1, 3, 5],
            [3, 7, 5], // x = 1
        ];
        if !open {
            indices.extend([[2, 6, 3], [3, 6, 7]]); // y = 1
        }
        TriangleMesh::new(positions, indices, material)
    }

    fn builder(meshes: Vec<TriangleMesh>) -> SceneBuilder {
        let camera = Camera::new(
            Vec3::new(0.5, 0.5, 5.0),
            Vec3::splat(0.5),
            Vec3::Y,
            40.0,
            (8, 8),
        )
        .unwrap();
        let mut b = SceneBuilder::new(camera);
        b.add_material(Material::new(Bsdf::diffuse(Vec3::splat(0.5)), Vec3::ZERO));
        b.add_material(Material::new(Bsdf::glass(1.5, Vec3::ONE), Vec3::ZERO));
        for mesh in meshes {
            b.add_mesh(mesh);
        }
        b
    }

    /// A closed glass cube has no open edge; without its top, the top's 4 outer edges are
    /// open (its diagonal went with it); an open diffuse box is not glass.
    #[test]
    fn open_edges_of_glass_meshes_are_counted() {
        assert!(open_glass_edges(&builder(vec![cube(1, false)])).is_empty());
        assert_eq!(open_glass_edges(&builder(vec![cube(1, true)])), [(1, 4)]);
        assert!(open_glass_edges(&builder(vec![cube(0, true)])).is_empty());
        // Two open cubes of the same glass: counted per mesh, summed per material.
        assert_eq!(
            open_glass_edges(&builder(vec![cube(1, true), cube(1, true)])),
            [(1, 8)]
        );
    }

    /// Vertices split by the OBJ loader (the same position twice) still join their edges.
    #[test]
    fn split_vertices_still_close_a_mesh() {
        let mut mesh = cube(1, false);
        let copy = mesh.positions[6];
        mesh.positions.push(copy);
        mesh.indices[11] = [3, 8, 7];
        assert!(open_glass_edges(&builder(vec![mesh])).is_empty());
    }
}
