//! Instances: one mesh placed many times without copying its triangles, as Embree's
//! instances are. A two-level BVH: each shared mesh has its own BVH (a [`Geometry`] of
//! triangles only, in the mesh's object space, built once), and a top-level BVH over the
//! world-space boxes of its placements. A ray that meets an instance's box is moved into
//! object space (`o' = M^-1 o`, `d' = M^-1 d`, not renormalised, so the ray parameter t is
//! the same in both spaces) and traced through the shared BVH; the hit found is moved back:
//! the point by M (in double precision, from the barycentrics, rounded once), the geometric
//! normal and the vertex normals (before they are interpolated) by the inverse transpose M^-T (a normal stays perpendicular to every
//! transformed tangent: (M^-T n) . (M t) = n . t = 0; pbrt-v4 `Transform::ApplyInverse` on
//! normals, Embree's `instance` geometry).
//!
//! Handedness: M^-T n is the transformed normal whatever the sign of det M, so a mirroring
//! placement keeps a closed mesh's outside outside and its emitting side the one the mesh
//! had; this is what the flattened copy gets when its winding is reversed for a mirroring
//! transform (cross(M a, M b) = det(M) M^-T (a x b), `ppm_scene::placement::place_mesh`).
//!
//! An instance whose transform is exactly the identity traces the world ray itself and
//! returns the shared BVH's hit as it is (only its id moved), so its hits are bit for bit
//! those of the same mesh in the flat level.
//!
//! Ids: the triangles of instance k get the global ids `first_prim(k) + local id`, after the
//! flat level's triangles and spheres, instance after instance.

use super::build::{build_tree, Aabb};
use super::traversal::{Closest, TraversalRay, SLAB_SCALE, STACK_SIZE};
use super::wide::{Node, LEAF, WIDTH};
use super::Geometry;
use crate::geometry::{Hit, Ray, TriangleMesh};
use crate::SceneError;
use glam::{Affine3A, DAffine3, DMat4, DVec3, Mat3A, Vec2, Vec3, Vec3A};

/// One placement of a shared mesh, as the scene builder hands it over.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshInstance {
    /// Index of the shared mesh (in the list given with the placements).
    pub mesh: u32,
    /// Object-to-world transform; affine (the last row is taken as 0 0 0 1).
    pub to_world: DMat4,
}

/// A placement as the traversal reads it.
#[derive(Clone, Copy, Debug)]
struct Instance {
    /// World to object, in f32: what each ray is moved by.
    to_object: Affine3A,
    /// Object to world, in f64: what a hit point is moved by.
    to_world: DAffine3,
    /// The inverse transpose of `to_world`'s linear part: what normals are moved by.
    normal_to_world: Mat3A,
    /// Exactly the identity: the ray and the hit are not moved at all.
    identity: bool,
    mesh: u32,
    first_prim: u32,
}

impl Instance {
    /// The ray in the instance's object space; the same parameter t in both spaces.
    #[inline(always)]
    fn object_ray(&self, ray: &Ray) -> Ray {
        if self.identity {
            return *ray;
        }
        Ray {
            origin: self.to_object.transform_point3(ray.origin),
            dir: self.to_object.transform_vector3(ray.dir),
            t_max: ray.t_max,
        }
    }
}

/// The instances of a scene: the shared meshes' BVHs, the placements and the top-level BVH.
#[derive(Default)]
pub(super) struct Instances {
    meshes: Vec<Geometry>,
    instances: Vec<Instance>,
    /// The top-level BVH; a leaf child names a range of `order` (as `build_tree` makes it).
    nodes: Vec<Node>,
    leaves: Vec<(u32, u32)>,
    /// Instance indices in the tree's leaf order.
    order: Vec<u32>,
    stack_size: usize,
    /// World-space bounds of all placements; `None` without any.
    bounds: Option<(Vec3, Vec3)>,
    /// The materials of the meshes that are placed, each once, ascending.
    materials: Vec<u32>,
    /// Triangles over all placements (what the flattened scene would hold).
    placed_triangles: u64,
}

/// An error about placement `i`.
fn invalid(i: usize, value: String, why: &str) -> SceneError {
    SceneError::InvalidValue {
        field: format!("instance {i}"),
        value,
        why: why.into(),
    }
}

impl Instances {
    /// Builds the shared meshes' BVHs and the top-level BVH over `placements`, whose ids
    /// start at `first_prim`. A transform that is singular or not finite, a mesh index out of
    /// range, or more than 2^32 primitive ids, is an error naming the placement.
    pub(super) fn new(
        meshes: &[TriangleMesh],
        placements: &[MeshInstance],
        first_prim: u32,
    ) -> Result<Self, SceneError> {
        if placements.is_empty() {
            return Ok(Instances::default());
        }
        let mut used = vec![false; meshes.len()];
        for (i, p) in placements.iter().enumerate() {
            match used.get_mut(p.mesh as usize) {
                Some(u) => *u = true,
                None => {
                    return Err(invalid(
                        i,
                        p.mesh.to_string(),
                        &format!("there are {} shared meshes", meshes.len()),
                    ))
                }
            }
        }
        // A mesh nobody places gets an empty BVH: the indices stay those of the caller.
        let shared: Vec<Geometry> = meshes
            .iter()
            .zip(&used)
            .map(|(m, &u)| match u {
                true => Geometry::new(std::slice::from_ref(m), &[]),
                false => Geometry::new(&[], &[]),
            })
            .collect();
        let mut materials: Vec<u32> = (meshes.iter().zip(&used))
            .filter(|(_, &u)| u)
            .flat_map(|(m, _)| m.materials.iter().copied())
            .collect();
        materials.sort_unstable();
        materials.dedup();

        let mut instances = Vec::with_capacity(placements.len());
        let mut boxes = Vec::with_capacity(placements.len());
        let mut in_tree = Vec::with_capacity(placements.len());
        let mut next = first_prim as u64;
        let mut placed_triangles = 0u64;
        for (i, p) in placements.iter().enumerate() {
            let to_world = DAffine3::from_mat4(p.to_world);
            let linear = to_world.matrix3;
            let det = linear.determinant();
            if !(det.is_finite() && det != 0.0 && to_world.translation.is_finite()) {
                return Err(invalid(
                    i,
                    format!("{:?}", p.to_world),
                    "the transform is singular or not finite",
                ));
            }
            let to_object = to_world.inverse();
            let normal = linear.inverse().transpose();
            let blas = &shared[p.mesh as usize];
            let count = blas.triangle_count() as u64;
            if next + count > u32::MAX as u64 {
                return Err(invalid(
                    i,
                    format!("{} triangles", next + count),
                    "more than 2^32 primitives over all placements",
                ));
            }
            let identity = p.to_world == DMat4::IDENTITY;
            instances.push(Instance {
                to_object: Affine3A::from_mat4(DMat4::from(to_object).as_mat4()),
                to_world,
                normal_to_world: Mat3A::from(normal.as_mat3()),
                identity,
                mesh: p.mesh,
                first_prim: next as u32,
            });
            next += count;
            placed_triangles += count;
            if count > 0 {
                let b = world_box(blas.bounds(), &to_world, identity);
                if !(b.lo.is_finite() && b.hi.is_finite()) {
                    return Err(invalid(
                        i,
                        format!("{:?}", p.to_world),
                        "the transform takes the mesh out of single-precision range",
                    ));
                }
                boxes.push(b);
                in_tree.push(i as u32);
            }
        }
        let mut out = Instances {
            meshes: shared,
            instances,
            materials,
            placed_triangles,
            ..Instances::default()
        };
        if boxes.is_empty() {
            return Ok(out);
        }
        let tree = build_tree(&boxes, 0);
        out.order = tree.order.iter().map(|r| in_tree[r.id as usize]).collect();
        out.nodes = tree.nodes;
        out.leaves = tree.leaves;
        out.stack_size = (WIDTH - 1) * tree.depth + 1;
        let mut all = Aabb::EMPTY;
        for b in &boxes {
            all.grow(b);
        }
        out.bounds = Some((all.lo.into(), all.hi.into()));
        Ok(out)
    }

    /// True without placements (the traversal then never looks at the instances).
    #[inline(always)]
    pub(super) fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// The nearer of `flat` (the flat level's hit) and the nearest instance hit.
    #[inline]
    pub(super) fn intersect(&self, ray: &Ray, flat: Option<Hit>) -> Option<Hit> {
        let tr = TraversalRay::new(ray);
        let t_max = flat.map_or(ray.t_max, |h| h.t);
        let mut found: Option<(u32, Closest<'_>)> = None;
        self.walk(&tr, t_max, |i, t_max| {
            let inst = &self.instances[i as usize];
            let local = inst.object_ray(ray);
            let blas = &self.meshes[inst.mesh as usize];
            // Strictly nearer than `t_max` only: a flat hit (smaller ids) keeps a tie.
            let c = blas.closest(&TraversalRay::new(&local), *t_max);
            if c.found {
                *t_max = c.t;
                found = Some((i, c));
            }
            false
        });
        match found {
            Some((i, c)) => self.hit(i, &c).or(flat),
            None => flat,
        }
    }

    /// True if an instance blocks the ray within (0, t_max).
    #[inline]
    pub(super) fn occluded(&self, ray: &Ray) -> bool {
        let tr = TraversalRay::new(ray);
        self.walk(&tr, ray.t_max, |i, _| {
            let inst = &self.instances[i as usize];
            self.meshes[inst.mesh as usize].occluded_flat(&inst.object_ray(ray))
        })
    }

    /// The world-space hit of candidate `c` of instance `i`.
    #[inline(always)]
    fn hit(&self, i: u32, c: &Closest<'_>) -> Option<Hit> {
        let inst = &self.instances[i as usize];
        let (packet, lane) = c.packet?;
        let v = packet.vertices(lane);
        let local = self.meshes[inst.mesh as usize].triangle_hit(c.t, c.id, c.uv, v);
        let prim = inst.first_prim + c.id;
        if inst.identity {
            return Some(Hit { prim, ..local });
        }
        // The point from the barycentrics and the transform in double precision, rounded
        // once: within half an ulp of the transformed triangle, as `triangle_hit`'s is.
        let (b1, b2) = (c.uv.x as f64, c.uv.y as f64);
        let p =
            DVec3::from(v[0]) * (1.0 - b1 - b2) + DVec3::from(v[1]) * b1 + DVec3::from(v[2]) * b2;
        let p = inst.to_world.transform_point3(p).as_vec3();
        let n = inst.normal_to_world;
        let ng = Vec3::from(n * Vec3A::from(local.ng)).normalize_or_zero();
        if ng == Vec3::ZERO {
            return None;
        }
        // Vertex normals moved by M^-T and normalised at the vertices, then interpolated, as
        // the flattened copy's are (normalising before or after a non-uniform scale differs).
        let blas = &self.meshes[inst.mesh as usize];
        let ns = match blas.vertex_normals(c.id) {
            None => ng,
            Some(normals) => {
                let [n0, n1, n2] =
                    normals.map(|v| Vec3::from(n * Vec3A::from(v)).normalize_or_zero());
                let (u, w) = (c.uv.x, c.uv.y);
                match (n0 * (1.0 - u - w) + n1 * u + n2 * w).normalize_or_zero() {
                    s if s == Vec3::ZERO => ng,
                    s if s.dot(ng) < 0.0 => -s,
                    s => s,
                }
            }
        };
        Some(Hit {
            t: c.t,
            p,
            ng,
            ns,
            uv: c.uv,
            material: local.material,
            prim,
        })
    }

    /// The top-level walk, nearest box first: `visit(instance, t_max)` traces one
    /// instance, may shrink `t_max`, and returns true to stop (so does `walk`).
    #[inline(always)]
    fn walk(
        &self,
        tr: &TraversalRay,
        t_max: f32,
        mut visit: impl FnMut(u32, &mut f32) -> bool,
    ) -> bool {
        if self.stack_size <= STACK_SIZE {
            let mut stack = [(0u32, 0.0f32); STACK_SIZE];
            self.walk_with(tr, t_max, &mut stack, &mut visit)
        } else {
            let mut stack = vec![(0u32, 0.0f32); self.stack_size];
            self.walk_with(tr, t_max, &mut stack, &mut visit)
        }
    }

    #[inline(always)]
    fn walk_with(
        &self,
        tr: &TraversalRay,
        mut t_max: f32,
        stack: &mut [(u32, f32)],
        visit: &mut impl FnMut(u32, &mut f32) -> bool,
    ) -> bool {
        let mut sp = 0;
        let mut current = 0u32;
        loop {
            if current & LEAF != 0 {
                let (start, count) = self.leaves[(current & !LEAF) as usize];
                for &i in &self.order[start as usize..(start + count) as usize] {
                    if visit(i, &mut t_max) {
                        return true;
                    }
                }
            } else {
                let node = &self.nodes[current as usize];
                let (mut met, t_near) = tr.slab(node, t_max);
                // Every child met, sorted so the nearest is on top.
                let base = sp;
                while met != 0 {
                    let i = met.trailing_zeros() as usize;
                    met &= met - 1;
                    let entry = (node.child[i], t_near[i]);
                    let mut j = sp;
                    while j > base && stack[j - 1].1 < entry.1 {
                        stack[j] = stack[j - 1];
                        j -= 1;
                    }
                    stack[j] = entry;
                    sp += 1;
                }
            }
            loop {
                if sp == 0 {
                    return false;
                }
                sp -= 1;
                let (child, t_near) = stack[sp];
                if t_near <= t_max * SLAB_SCALE {
                    current = child;
                    break;
                }
            }
        }
    }

    /// The texture coordinates at `hit` on an instance (its id past the flat level's).
    pub(super) fn texture_uv(&self, hit: &Hit) -> Vec2 {
        let k = self.instances.partition_point(|i| i.first_prim <= hit.prim);
        let Some(inst) = k.checked_sub(1).map(|k| &self.instances[k]) else {
            return hit.uv;
        };
        let local = Hit {
            prim: hit.prim - inst.first_prim,
            ..*hit
        };
        self.meshes[inst.mesh as usize].texture_uv(&local)
    }

    /// World bounds of all placements.
    pub(super) fn bounds(&self) -> Option<(Vec3, Vec3)> {
        self.bounds
    }

    /// The materials of the placed meshes, each once.
    pub(super) fn materials(&self) -> &[u32] {
        &self.materials
    }

    /// Number of placements.
    pub(super) fn count(&self) -> usize {
        self.instances.len()
    }

    /// Triangles over all placements: what the flattened scene would hold.
    pub(super) fn placed_triangles(&self) -> u64 {
        self.placed_triangles
    }

    /// Bytes held: each shared mesh's geometry and BVH once, plus per placement its record
    /// and its share of the top-level BVH.
    pub(super) fn memory_bytes(&self) -> usize {
        self.meshes
            .iter()
            .map(Geometry::memory_bytes)
            .sum::<usize>()
            + self.meshes.capacity() * size_of::<Geometry>()
            + self.instances.capacity() * size_of::<Instance>()
            + self.nodes.capacity() * size_of::<Node>()
            + self.leaves.capacity() * size_of::<(u32, u32)>()
            + self.order.capacity() * size_of::<u32>()
            + self.materials.capacity() * size_of::<u32>()
    }
}

/// The world-space box of a mesh with object-space bounds `(lo, hi)` placed by `to_world`:
/// its eight corners moved in double precision, then widened by 2^-20 of its largest
/// coordinate (plus the smallest normal float) so that the rounding of the f32 object-space
/// ray never lets a ray that meets the triangles miss the box. The identity keeps the box.
fn world_box((lo, hi): (Vec3, Vec3), to_world: &DAffine3, identity: bool) -> Aabb {
    if identity {
        return Aabb {
            lo: lo.into(),
            hi: hi.into(),
        };
    }
    let (lo, hi) = (lo.as_dvec3(), hi.as_dvec3());
    let mut min = DVec3::INFINITY;
    let mut max = DVec3::NEG_INFINITY;
    for k in 0..8 {
        let corner = DVec3::new(
            if k & 1 == 0 { lo.x } else { hi.x },
            if k & 2 == 0 { lo.y } else { hi.y },
            if k & 4 == 0 { lo.z } else { hi.z },
        );
        let p = to_world.transform_point3(corner);
        min = min.min(p);
        max = max.max(p);
    }
    let pad = min.abs().max(max.abs()).max_element() * (1.0 / (1 << 20) as f64)
        + f32::MIN_POSITIVE as f64;
    Aabb {
        lo: (min - pad).as_vec3().into(),
        hi: (max + pad).as_vec3().into(),
    }
}
