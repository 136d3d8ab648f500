//! Rays, hits and the scene's geometry: triangle meshes and analytic spheres under one BVH.
//!
//! Primitive ids are global: triangles first, in the order their meshes were added (each mesh's
//! triangles in index order, degenerate ones and exact duplicates of an earlier triangle
//! skipped), then spheres in the order they were added, then the triangles of each placement
//! of an instanced mesh (placement after placement, each mesh's local ids in order).

mod bvh;
mod mesh;
mod ray;
mod sphere;
mod triangle;
mod triangle_packet;

pub use bvh::{BvhStats, Geometry, MeshInstance};
pub use mesh::TriangleMesh;
pub use ray::Ray;
pub use sphere::Sphere;
pub use triangle::{intersect_triangle, Triangle};

use glam::{Vec2, Vec3};

/// A ray-surface intersection, everything the integrators need to shade it.
#[derive(Clone, Copy, Debug)]
pub struct Hit {
    /// Ray parameter of the hit (distance, as ray directions are unit length).
    pub t: f32,
    /// World-space position.
    pub p: Vec3,
    /// Unit geometric normal as the primitive defines it (triangle winding, sphere outward or
    /// inward), not flipped toward the ray: emission and glass sidedness depend on it.
    pub ng: Vec3,
    /// Unit shading normal (interpolated vertex normal, or `ng`), on the same side as `ng`.
    pub ns: Vec3,
    /// Barycentric coordinates (b1, b2) of a triangle hit; zero on spheres.
    pub uv: Vec2,
    /// Material index into the scene's material list.
    pub material: u32,
    /// Global primitive id (see the module docs).
    pub prim: u32,
}
