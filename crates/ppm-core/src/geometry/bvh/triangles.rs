//! The triangles a [`super::Geometry`] keeps from its meshes, with what a hit needs of each
//! ([`TriangleAttributes`]: the unit geometric normal, the material and the slot of its
//! shading normals).
//!
//! A face is skipped when a vertex index is out of range, a vertex is not finite, or its
//! cross product is zero or not finite (repeated or collinear vertices). The work is done in
//! parallel passes over the faces, each writing its array in face order (rayon's indexed
//! `par_extend` writes every element at its index), so the arrays are the same on any
//! number of threads and equal to a serial loop's.

use super::super::{Triangle, TriangleMesh};
use glam::{Vec2, Vec3};
use rayon::prelude::*;
use std::mem::take;

/// What a hit on a triangle needs beyond its vertices, in one record (one memory access
/// per hit).
#[derive(Clone, Copy, Debug)]
pub(super) struct TriangleAttributes {
    /// `cross(v1 - v0, v2 - v0)` normalised: the very expression a hit would evaluate.
    pub(super) ng: Vec3,
    pub(super) material: u32,
    /// Index into `Geometry::shading_normals`, u32::MAX when the mesh has no normals.
    pub(super) normals: u32,
}

/// The kept triangles by global id (faces of the meshes in order, skipped ones left out).
#[derive(Default)]
pub(super) struct Kept {
    pub(super) triangles: Vec<Triangle>,
    pub(super) attributes: Vec<TriangleAttributes>,
    pub(super) shading_normals: Vec<[Vec3; 3]>,
    /// Texture coordinates of each kept triangle's vertices, by global id; empty when no
    /// mesh has any (a mesh without them gives its triangles (0, 0), (1, 0), (0, 1), so
    /// interpolating them gives back the barycentrics).
    pub(super) tex_coords: Vec<[Vec2; 3]>,
    /// Faces skipped as degenerate.
    pub(super) skipped: usize,
}

/// The triangle of face `idx` of `mesh`; `None` if it is skipped (see the module docs).
#[inline(always)]
fn face(mesh: &TriangleMesh, idx: &[u32; 3]) -> Option<Triangle> {
    let vertex = |k: usize| mesh.positions.get(idx[k] as usize).copied();
    let tri = Triangle {
        v: [vertex(0)?, vertex(1)?, vertex(2)?],
    };
    let n = tri.cross();
    let finite = tri.v.iter().all(|v| v.is_finite());
    // A zero cross product covers repeated vertices and collinear ones.
    (finite && n.is_finite() && n.length_squared() != 0.0).then_some(tri)
}

impl Kept {
    /// Every face of `meshes` that is not skipped, in order.
    pub(super) fn gather(meshes: &[TriangleMesh]) -> Kept {
        let mut kept = Kept::default();
        let has_uvs = |m: &TriangleMesh| !m.uvs.is_empty() && m.uvs.len() == m.positions.len();
        let any_uvs = meshes.iter().any(has_uvs);
        for mesh in meshes {
            // The faces kept: all of them in the common case, else the list of their indices.
            let skipped = mesh
                .indices
                .par_iter()
                .filter(|idx| face(mesh, idx).is_none())
                .count();
            let list: Vec<u32> = if skipped == 0 {
                Vec::new()
            } else {
                (0..mesh.indices.len() as u32)
                    .into_par_iter()
                    .filter(|&i| face(mesh, &mesh.indices[i as usize]).is_some())
                    .collect()
            };
            let count = mesh.indices.len() - skipped;
            let face_of = |j: usize| if skipped == 0 { j } else { list[j] as usize };
            kept.skipped += skipped;
            let has_normals = mesh.normals.len() == mesh.positions.len();
            let base = kept.shading_normals.len();
            // Both arrays in one pass, each element written at its index.
            let mut both = (take(&mut kept.triangles), take(&mut kept.attributes));
            both.par_extend((0..count).into_par_iter().map(|j| {
                let i = face_of(j);
                let tri = face(mesh, &mesh.indices[i]).expect("a kept face is not skipped");
                let attributes = TriangleAttributes {
                    ng: tri.cross().normalize(),
                    material: mesh.materials.get(i).copied().unwrap_or(0),
                    normals: if has_normals {
                        (base + j) as u32
                    } else {
                        u32::MAX
                    },
                };
                (tri, attributes)
            }));
            (kept.triangles, kept.attributes) = both;
            if has_normals {
                kept.shading_normals.par_extend(
                    (0..count)
                        .into_par_iter()
                        .map(|j| mesh.indices[face_of(j)].map(|k| mesh.normals[k as usize])),
                );
            }
            if any_uvs {
                let uvs = has_uvs(mesh);
                kept.tex_coords
                    .par_extend((0..count).into_par_iter().map(|j| match uvs {
                        true => mesh.indices[face_of(j)].map(|k| mesh.uvs[k as usize]),
                        false => [Vec2::ZERO, Vec2::X, Vec2::Y],
                    }));
            }
        }
        kept
    }

    /// Drops the triangles `duplicate` marks (one flag per triangle), keeping the order.
    pub(super) fn drop(&mut self, duplicate: &[bool]) {
        let keep = |i: &mut usize| {
            let k = !duplicate[*i];
            *i += 1;
            k
        };
        let mut i = 0;
        self.triangles.retain(|_| keep(&mut i));
        i = 0;
        self.attributes.retain(|_| keep(&mut i));
        if !self.tex_coords.is_empty() {
            i = 0;
            self.tex_coords.retain(|_| keep(&mut i));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    /// The serial loop `gather` replaced, one face at a time.
    fn reference(meshes: &[TriangleMesh]) -> Kept {
        let mut kept = Kept::default();
        for mesh in meshes {
            let has_normals = mesh.normals.len() == mesh.positions.len();
            for (i, idx) in mesh.indices.iter().enumerate() {
                let Some(tri) = face(mesh, idx) else {
                    kept.skipped += 1;
                    continue;
                };
                kept.triangles.push(tri);
                let normals = match has_normals {
                    true => kept.shading_normals.len() as u32,
                    false => u32::MAX,
                };
                kept.attributes.push(TriangleAttributes {
                    ng: tri.cross().normalize(),
                    material: mesh.materials.get(i).copied().unwrap_or(0),
                    normals,
                });
                if has_normals {
                    kept.shading_normals
                        .push(idx.map(|k| mesh.normals[k as usize]));
                }
            }
        }
        kept
    }

    /// A mesh of `faces` random faces over `vertices` random vertices (a few repeated,
    /// collinear, non-finite or out of range), with normals when `normals`.
    fn mesh(rng: &mut Rng, faces: usize, normals: bool) -> TriangleMesh {
        let vertices = 300;
        let mut positions: Vec<Vec3> = (0..vertices)
            .map(|_| Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()))
            .collect();
        positions[7] = Vec3::new(f32::INFINITY, 0.0, 0.0);
        positions[8] = positions[9];
        let indices = (0..faces)
            .map(|_| {
                // About one face in 30 names a vertex out of range.
                [0; 3].map(|_| (rng.uniform() * (vertices as f32 + 10.0)) as u32)
            })
            .collect();
        let normals = if normals {
            (0..vertices)
                .map(|i| Vec3::new(i as f32, 1.0, 0.0).normalize())
                .collect()
        } else {
            Vec::new()
        };
        TriangleMesh {
            positions,
            normals,
            uvs: Vec::new(),
            indices,
            // Fewer materials than faces: the rest default to 0.
            materials: (0..faces as u32 / 2).collect(),
        }
    }

    /// The parallel passes give the serial loop's arrays exactly, over meshes with and
    /// without normals and with skipped faces, on one thread and on three; and a mesh
    /// without skipped faces takes the fast path.
    #[test]
    fn gather_equals_the_serial_loop() {
        let mut rng = Rng::new(11, 0, 0);
        let mut meshes = vec![
            mesh(&mut rng, 20_000, true),
            mesh(&mut rng, 5_000, false),
            mesh(&mut rng, 30_000, true),
        ];
        // A clean mesh (no face skipped).
        let mut clean = mesh(&mut rng, 1000, true);
        clean.positions[7] = Vec3::ZERO;
        clean.indices = (0..1000)
            .map(|i| [i % 100, 100 + i % 100, 200 + i % 97])
            .collect();
        meshes.push(clean);
        let want = reference(&meshes);
        assert!(want.skipped > 1000 && want.triangles.len() > 40_000);
        for threads in [1, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let got = pool.install(|| Kept::gather(&meshes));
            assert_eq!(got.skipped, want.skipped);
            let bits = |k: &Kept| {
                let v = |p: &Vec3| p.to_array().map(f32::to_bits);
                (
                    k.triangles
                        .iter()
                        .map(|t| t.v.map(|p| v(&p)))
                        .collect::<Vec<_>>(),
                    k.attributes
                        .iter()
                        .map(|a| (v(&a.ng), a.material, a.normals))
                        .collect::<Vec<_>>(),
                    k.shading_normals
                        .iter()
                        .map(|n| n.map(|p| v(&p)))
                        .collect::<Vec<_>>(),
                )
            };
            assert!(bits(&got) == bits(&want), "{threads} threads");
        }
    }
}
