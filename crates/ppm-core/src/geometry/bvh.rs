//! All primitives of a scene under one obvhs BVH: closest-hit and any-hit queries.

use super::{Hit, Ray, Sphere, Triangle, TriangleMesh};

/// The scene's geometry and its acceleration structure. Immutable once built.
pub struct Geometry {
    // TODO(geometry helper)
}

impl Geometry {
    /// Builds the BVH over all triangles of `meshes` and all `spheres`. Degenerate triangles
    /// (zero area or non-finite vertices) are skipped and counted in [`Geometry::skipped_triangles`].
    pub fn new(_meshes: &[TriangleMesh], _spheres: &[Sphere]) -> Self {
        todo!()
    }
    /// Closest hit along the ray.
    pub fn intersect(&self, _ray: &Ray) -> Option<Hit> {
        todo!()
    }
    /// True if anything blocks the ray within (0, t_max).
    pub fn occluded(&self, _ray: &Ray) -> bool {
        todo!()
    }
    /// Closest hit by testing every primitive (the reference for tests).
    pub fn intersect_brute_force(&self, _ray: &Ray) -> Option<Hit> {
        todo!()
    }
    /// Number of triangles kept.
    pub fn triangle_count(&self) -> usize {
        todo!()
    }
    /// Number of spheres.
    pub fn sphere_count(&self) -> usize {
        todo!()
    }
    /// Triangles dropped as degenerate.
    pub fn skipped_triangles(&self) -> usize {
        todo!()
    }
    /// The triangle with global id `prim` (< triangle_count) and its material.
    pub fn triangle(&self, _prim: u32) -> (Triangle, u32) {
        todo!()
    }
    /// The sphere with global id `prim` (>= triangle_count).
    pub fn sphere(&self, _prim: u32) -> &Sphere {
        todo!()
    }
    /// World-space bounds (min, max) of all primitives.
    pub fn bounds(&self) -> (glam::Vec3, glam::Vec3) {
        todo!()
    }
}
