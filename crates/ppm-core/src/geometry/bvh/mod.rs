//! All primitives of a scene under one BVH: closest-hit and any-hit queries.
//!
//! Exact duplicate triangles are dropped first (`duplicates.rs`). The BVH is built top-down
//! by binned SAH straight into nodes of eight children, in parallel (`build/`), and
//! traversed by our own loop: one node tests the boxes of all eight children at once (one 8-lane
//! [`crate::simd::F32x8`] operation per step), and a leaf tests its triangles as one 4-wide
//! packet ([`TrianglePacket`]), lane for lane the scalar watertight test.
//!
//! - `mod.rs` (this file): the primitive storage ([`Geometry`]) and what a hit returns;
//! - `triangles.rs`: the triangles kept from the meshes, with the record a hit reads;
//! - `duplicates.rs`: finding exact duplicate triangles in linear time;
//! - `build/`: the binned SAH build of the 8-wide tree;
//! - `wide.rs`: the layout of the 8-wide nodes and leaves;
//! - `traversal.rs`: the robust slab test and the stack traversal (closest hit);
//! - `any_hit.rs`: the any-hit traversal, with a stack of bare references;
//! - `instances.rs`: meshes placed many times by transforms, a second level of BVHs.
//!
//! The slab test is robust: the exit distance of every box is scaled by 1 + 2 gamma(3) (Ize
//! 2013, "Robust BVH Ray Traversal"), which covers the three roundings of (bound - o) / d, and a
//! zero direction component uses a finite huge inverse instead of infinity so no 0 * inf = NaN
//! can drop a box. Together with the watertight triangle test no ray slips between primitives
//! or past a box it touches.
//!
//! The traversal resolves equal distances by primitive id, so the BVH answers exactly like
//! `intersect_brute_force` whatever the tree's shape. (Why not obvhs's traversals, which
//! `benches/rays.rs` still measures: its compressed wide BVH clamps every box entry to an
//! absolute t >= 1e-4, so a ray 1e-5 from a wall of a unit box passes through the wall, and
//! its binary traversal replaces direction components below f32::EPSILON by f32::EPSILON
//! without Ize's correction.)

mod any_hit;
mod build;
mod duplicates;
mod instances;
mod stats;
mod traversal;
mod triangles;
mod wide;

use super::triangle_packet::TrianglePacket;
use super::{Hit, Ray, Sphere, Triangle, TriangleMesh};
use build::Aabb;
use glam::{DVec3, Vec2, Vec3, Vec3A};
use instances::Instances;
pub use instances::MeshInstance;
use rayon::prelude::*;
pub use stats::BvhStats;
use triangles::TriangleAttributes;
use wide::{Leaf, Node, SphereRecord, WideBvh, WIDTH};

/// The scene's geometry and its acceleration structure. Immutable once built.
pub struct Geometry {
    /// The 8-wide BVH; the root is node 0 (no nodes without primitives).
    nodes: Vec<Node>,
    leaves: Vec<Leaf>,
    packets: Vec<TrianglePacket>,
    sphere_records: Vec<SphereRecord>,
    /// Where each triangle (by global id) is packed: packet index * 4 + lane. Its vertices
    /// are kept only there (`Geometry::triangle`, the brute force; a hit reads them from the
    /// packet the traversal found it in, already in cache).
    packed_at: Vec<u32>,
    /// Geometric normal, material and shading-normal slot by global id: one record, so a
    /// hit costs one memory access beyond the BVH's.
    tri_attributes: Vec<TriangleAttributes>,
    shading_normals: Vec<[Vec3; 3]>,
    /// Texture coordinates of each triangle's vertices by global id, read only when a
    /// textured material is shaded ([`Geometry::texture_uv`]); empty without any.
    tex_coords: Vec<[Vec2; 3]>,
    spheres: Vec<Sphere>,
    skipped: usize,
    duplicates: usize,
    bounds: (Vec3, Vec3),
    /// The traversal stack never holds more entries: WIDTH - 1 per level of the tree (a node
    /// pushes all its children met but the one it descends into), plus one.
    stack_size: usize,
    /// Meshes placed by transforms, traced after the primitives above (empty if none).
    instances: Instances,
}

impl Geometry {
    /// Builds the BVH over all triangles of `meshes` and all `spheres`. Degenerate triangles
    /// (zero area or non-finite vertices) are skipped and counted in [`Geometry::skipped_triangles`];
    /// exact duplicates of an earlier triangle are dropped and counted in
    /// [`Geometry::duplicate_triangles`]. The build runs on the current rayon thread pool.
    pub fn new(meshes: &[TriangleMesh], spheres: &[Sphere]) -> Self {
        let mut kept = triangles::Kept::gather(meshes);
        let duplicate = duplicates::duplicate_mask(&kept.triangles);
        let duplicates = duplicate.iter().filter(|&&d| d).count();
        if duplicates > 0 {
            kept.drop(&duplicate);
        }
        let triangles::Kept {
            triangles,
            attributes: tri_attributes,
            shading_normals,
            tex_coords,
            skipped,
        } = kept;
        let spheres = spheres.to_vec();

        let mut aabbs: Vec<Aabb> = triangles
            .par_iter()
            .map(|t| {
                let [a, b, c] = t.v.map(Vec3A::from);
                Aabb {
                    lo: a.min(b).min(c),
                    hi: a.max(b).max(c),
                }
            })
            .collect();
        aabbs.extend(spheres.iter().map(|s| {
            let r = s.radius.abs();
            if s.center.is_finite() && r.is_finite() {
                let c = Vec3A::from(s.center);
                Aabb {
                    lo: c - r,
                    hi: c + r,
                }
            } else {
                // Never hit (see `intersect_sphere`); keep it out of the way of the build.
                Aabb {
                    lo: Vec3A::ZERO,
                    hi: Vec3A::ZERO,
                }
            }
        }));
        // Min and max: the same box whatever the order of reduction.
        let all = aabbs.par_iter().copied().reduce(
            || Aabb::EMPTY,
            |mut acc, b| {
                acc.grow(&b);
                acc
            },
        );
        let bounds = if aabbs.is_empty() {
            (Vec3::ZERO, Vec3::ZERO)
        } else {
            (all.lo.into(), all.hi.into())
        };
        let wide = WideBvh::build(&aabbs, &triangles, &spheres);
        // Every triangle is in exactly one packet lane (the leaves partition the ids).
        let mut packed_at = vec![u32::MAX; triangles.len()];
        for (p, packet) in wide.packets.iter().enumerate() {
            for lane in 0..packet.count() {
                let at = u32::try_from(4 * p + lane).expect("fewer than 2^30 triangle packets");
                packed_at[packet.id[lane] as usize] = at;
            }
        }
        debug_assert!(packed_at.iter().all(|&at| at != u32::MAX));
        drop(triangles);
        Geometry {
            nodes: wide.nodes,
            leaves: wide.leaves,
            packets: wide.packets,
            sphere_records: wide.spheres,
            packed_at,
            tri_attributes,
            shading_normals,
            tex_coords,
            spheres,
            skipped,
            duplicates,
            bounds,
            stack_size: (WIDTH - 1) * wide.depth + 1,
            instances: Instances::default(),
        }
    }

    /// [`Geometry::new`] and, in a second level, the shared `instanced` meshes placed by
    /// `placements` without copying their triangles (see `instances.rs`). Their ids follow
    /// the flat level's triangles and spheres, placement after placement. A placement with a
    /// singular or non-finite transform, or a mesh index out of range, is an error naming it.
    pub fn with_instances(
        meshes: &[TriangleMesh],
        spheres: &[Sphere],
        instanced: &[TriangleMesh],
        placements: &[MeshInstance],
    ) -> Result<Self, crate::SceneError> {
        let mut geometry = Geometry::new(meshes, spheres);
        let first = geometry.packed_at.len() + geometry.spheres.len();
        let first = u32::try_from(first).map_err(|_| crate::SceneError::InvalidValue {
            field: "geometry".into(),
            value: first.to_string(),
            why: "more than 2^32 primitives".into(),
        })?;
        geometry.instances = Instances::new(instanced, placements, first)?;
        if let Some((lo, hi)) = geometry.instances.bounds() {
            geometry.bounds = if geometry.nodes.is_empty() {
                (lo, hi)
            } else {
                (geometry.bounds.0.min(lo), geometry.bounds.1.max(hi))
            };
        }
        Ok(geometry)
    }

    /// Everything the integrators need about the hit at distance `t` on triangle `prim`,
    /// whose vertices are `v` (read from the packet the traversal found it in).
    #[inline(always)]
    pub(super) fn triangle_hit(&self, t: f32, prim: u32, uv: Vec2, v: [Vec3; 3]) -> Hit {
        let [v0, v1, v2] = v;
        // The point from barycentrics in double precision, rounded once: it lies on the
        // triangle's plane to within half an ulp of its own coordinates, whatever the size
        // of the triangle, which is what `offset_origin` assumes.
        let (b1, b2) = (uv.x as f64, uv.y as f64);
        let p = DVec3::from(v0) * (1.0 - b1 - b2) + DVec3::from(v1) * b1 + DVec3::from(v2) * b2;
        let attributes = self.tri_attributes[prim as usize];
        let ng = attributes.ng;
        let ns = match attributes.normals {
            u32::MAX => ng,
            k => {
                let [n0, n1, n2] = self.shading_normals[k as usize];
                let n = (n0 * (1.0 - uv.x - uv.y) + n1 * uv.x + n2 * uv.y).normalize_or_zero();
                if n == Vec3::ZERO {
                    ng
                } else if n.dot(ng) < 0.0 {
                    -n
                } else {
                    n
                }
            }
        };
        Hit {
            t,
            p: p.as_vec3(),
            ng,
            ns,
            uv,
            material: attributes.material,
            prim,
        }
    }

    /// The vertex normals of triangle `prim`, if its mesh has them.
    #[inline(always)]
    pub(super) fn vertex_normals(&self, prim: u32) -> Option<[Vec3; 3]> {
        match self.tri_attributes[prim as usize].normals {
            u32::MAX => None,
            k => Some(self.shading_normals[k as usize]),
        }
    }

    /// Everything the integrators need about the hit at distance `t` on sphere `prim`.
    #[inline(always)]
    pub(super) fn sphere_hit(&self, ray: &Ray, t: f32, prim: u32) -> Hit {
        let s = &self.spheres[prim as usize - self.packed_at.len()];
        let (p, ng) = s.surface(ray.at(t));
        Hit {
            t,
            p,
            ng,
            ns: ng,
            uv: Vec2::ZERO,
            material: s.material,
            prim,
        }
    }

    /// The texture coordinates (u, v) at `hit`, computed after the nearest hit is known
    /// (the traversal never reads them), as Mitsuba 3 defines them:
    /// - a triangle: its vertices' uvs interpolated by the barycentrics,
    ///   `(1 - b1 - b2) uv0 + b1 uv1 + b2 uv2`; without uvs, (b1, b2) itself;
    /// - a sphere: `(phi / 2 pi, theta / pi)` of the direction `d` from its centre, with
    ///   `phi = atan2(d.y, d.x)` in [0, 2 pi) and `theta = acos(d.z)` (Mitsuba's `sphere`
    ///   in its object frame; ppm's spheres are not rotated).
    pub fn texture_uv(&self, hit: &Hit) -> Vec2 {
        let prim = hit.prim as usize;
        let (b1, b2) = (hit.uv.x, hit.uv.y);
        if prim >= self.packed_at.len() + self.spheres.len() {
            return self.instances.texture_uv(hit);
        }
        if prim < self.packed_at.len() {
            match self.tex_coords.get(prim) {
                Some([t0, t1, t2]) => *t0 * (1.0 - b1 - b2) + *t1 * b1 + *t2 * b2,
                None => hit.uv,
            }
        } else {
            let s = self.sphere(hit.prim);
            let d = ((hit.p - s.center) / s.radius).clamp(Vec3::splat(-1.0), Vec3::ONE);
            let mut phi = d.y.atan2(d.x);
            if phi < 0.0 {
                phi += std::f32::consts::TAU;
            }
            let theta = d.z.acos();
            Vec2::new(
                phi * std::f32::consts::FRAC_1_PI * 0.5,
                theta * std::f32::consts::FRAC_1_PI,
            )
        }
    }

    /// Number of placements of instanced meshes.
    pub fn instance_count(&self) -> usize {
        self.instances.count()
    }

    /// Triangles over all placements of instanced meshes: what flattening them would store.
    pub fn instanced_triangle_count(&self) -> u64 {
        self.instances.placed_triangles()
    }

    /// The materials of the instanced meshes, each once (ascending).
    pub fn instance_materials(&self) -> &[u32] {
        self.instances.materials()
    }

    /// Number of triangles kept in the flat level (instances not counted; their ids follow
    /// the spheres').
    pub fn triangle_count(&self) -> usize {
        self.packed_at.len()
    }

    /// Number of spheres.
    pub fn sphere_count(&self) -> usize {
        self.spheres.len()
    }

    /// Triangles dropped as degenerate.
    pub fn skipped_triangles(&self) -> usize {
        self.skipped
    }

    /// Bytes held by the geometry and its BVH (nodes, leaves, triangle packets, and the
    /// per-triangle packet lanes, normals, materials and shading-normal slots), by capacity;
    /// instanced meshes once each, plus their placements and the top-level BVH.
    pub fn memory_bytes(&self) -> usize {
        let bytes = |len: usize, one: usize| len * one;
        bytes(self.nodes.capacity(), size_of::<Node>())
            + bytes(self.leaves.capacity(), size_of::<Leaf>())
            + bytes(self.packets.capacity(), size_of::<TrianglePacket>())
            + bytes(self.sphere_records.capacity(), size_of::<SphereRecord>())
            + bytes(self.packed_at.capacity(), size_of::<u32>())
            + bytes(
                self.tri_attributes.capacity(),
                size_of::<TriangleAttributes>(),
            )
            + bytes(self.shading_normals.capacity(), size_of::<[Vec3; 3]>())
            + bytes(self.tex_coords.capacity(), size_of::<[Vec2; 3]>())
            + bytes(self.spheres.capacity(), size_of::<Sphere>())
            + self.instances.memory_bytes()
    }

    /// Triangles dropped as exact duplicates of an earlier one (same three vertices, bit for
    /// bit, in the same order): they could never be hit (see `duplicates.rs`).
    pub fn duplicate_triangles(&self) -> usize {
        self.duplicates
    }

    /// The triangle with global id `prim` (< triangle_count) and its material.
    pub fn triangle(&self, prim: u32) -> (Triangle, u32) {
        let v = self.packed_vertices(prim);
        (Triangle { v }, self.tri_attributes[prim as usize].material)
    }

    /// The vertices of triangle `prim` (< triangle_count), from its packet lane.
    pub(super) fn packed_vertices(&self, prim: u32) -> [Vec3; 3] {
        let at = self.packed_at[prim as usize] as usize;
        self.packets[at / 4].vertices(at % 4)
    }

    /// The sphere with global id `prim` (>= triangle_count).
    pub fn sphere(&self, prim: u32) -> &Sphere {
        &self.spheres[prim as usize - self.packed_at.len()]
    }

    /// World-space bounds (min, max) of all primitives, instances included.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.bounds
    }
}
