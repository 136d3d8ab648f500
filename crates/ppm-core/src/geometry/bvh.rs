//! All primitives of a scene under one BVH: closest-hit and any-hit queries.
//!
//! obvhs builds a binary BVH (PLOC, then reinsertion and SAH leaf collapsing, at most 2
//! primitives per leaf); we collapse it into an 8-wide BVH (each node opens its children with
//! the largest surface area until it holds eight, as Embree's BVH8 does) and traverse that
//! with our own loop: one node tests the boxes of all eight children at once (one AVX
//! operation per step, or two 4-wide halves without AVX), and a leaf tests its triangles as
//! one 4-wide packet ([`TrianglePacket`]), lane for lane the scalar watertight test.
//!
//! The slab test is robust: the exit distance of every box is scaled by 1 + 2 gamma(3) (Ize
//! 2013, "Robust BVH Ray Traversal"), which covers the three roundings of (bound - o) / d, and a
//! zero direction component uses a finite huge inverse instead of infinity so no 0 * inf = NaN
//! can drop a box. Together with the watertight triangle test no ray slips between primitives
//! or past a box it touches.
//!
//! Why not obvhs's own traversals: its compressed wide BVH (CWBVH) clamps every box entry to
//! an absolute t >= 1e-4 (`cwbvh::node::EPSILON`), so a ray 1e-5 from a wall of a unit box
//! passes through the wall (measured: all of 30000 corner rays of the unit box escaped), and
//! its `Bvh2` traversal replaces direction components below f32::EPSILON by f32::EPSILON and has
//! no Ize correction. Our own loop also resolves equal distances by primitive id, so the BVH
//! answers exactly like `intersect_brute_force`.

use super::sphere::intersect_sphere;
use super::triangle::{gamma, ShearedRay};
use super::triangle_packet::{PacketRay, TrianglePacket};
use super::{Hit, Ray, Sphere, Triangle, TriangleMesh};
use crate::simd::{F32x8, LANES};
use glam::{DVec3, Vec2, Vec3, Vec3A};
use obvhs::aabb::Aabb;
use obvhs::bvh2::Bvh2;
use obvhs::BvhBuildParams;

/// A sphere in a leaf.
#[derive(Clone, Copy, Debug)]
struct SphereRecord {
    center: Vec3,
    radius: f32,
    id: u32,
}

/// A child reference with this bit set names a leaf (the rest is its index), else a node.
const LEAF: u32 = 1 << 31;

/// Children per node.
const WIDTH: usize = 8;

/// A node of the 8-wide BVH: the boxes of its children in structure-of-arrays form.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
struct Node {
    /// `min[axis]` / `max[axis]`: that coordinate of each child's box.
    min: [[f32; WIDTH]; 3],
    max: [[f32; WIDTH]; 3],
    child: [u32; WIDTH],
    /// Bitmask of the children in use.
    valid: u32,
}

/// A leaf: a run of triangle packets and a run of spheres.
#[derive(Clone, Copy, Debug)]
struct Leaf {
    packets: (u32, u32),
    spheres: (u32, u32),
}

/// Traversal stack size kept on the call stack; deeper trees (never seen in practice) use a
/// heap stack sized at build time.
const STACK_SIZE: usize = 64;

/// Stack size for trees of depth up to 2 (WIDTH - 1 entries per level, plus one).
const SMALL_STACK_SIZE: usize = 16;

/// Box exits are scaled by this (Ize 2013: three roundings in (bound - o) * inv_dir).
const SLAB_SCALE: f32 = 1.0 + 2.0 * gamma(3);

/// Primitive tests get their bound widened by this: the final comparison is on the returned t
/// itself (`Closest::improves`, or `t < t_max` for shadow rays), so that exactly equal
/// distances are resolved the same way everywhere.
const WIDEN: f32 = 1.0 + 4.0 * f32::EPSILON;

/// The scene's geometry and its acceleration structure. Immutable once built.
pub struct Geometry {
    /// The 8-wide BVH; the root is node 0 (no nodes without primitives).
    nodes: Vec<Node>,
    leaves: Vec<Leaf>,
    packets: Vec<TrianglePacket>,
    sphere_records: Vec<SphereRecord>,
    /// Triangles, their unit geometric normals, materials and shading-normal slots, by
    /// global id. The normals are computed once here, by the very expression a hit would
    /// evaluate, instead of per hit.
    triangles: Vec<Triangle>,
    tri_geometric_normals: Vec<Vec3>,
    tri_materials: Vec<u32>,
    /// Index into `shading_normals` per triangle, u32::MAX when the mesh has no normals.
    tri_normals: Vec<u32>,
    shading_normals: Vec<[Vec3; 3]>,
    spheres: Vec<Sphere>,
    skipped: usize,
    bounds: (Vec3, Vec3),
    /// The traversal stack never holds more entries (3 per level of the tree).
    stack_size: usize,
}

/// The closest candidate found so far: distance, global id and barycentrics.
#[derive(Clone, Copy)]
struct Closest {
    t: f32,
    id: u32,
    uv: Vec2,
    found: bool,
}

impl Closest {
    /// Nearer, or as near with a smaller id: the same answer in any traversal order.
    #[inline(always)]
    fn improves(&self, t: f32, id: u32) -> bool {
        t < self.t || (t == self.t && id < self.id)
    }

    /// Keeps the candidate if it improves on the closest so far.
    #[inline(always)]
    fn offer(&mut self, t: f32, id: u32, uv: Vec2) {
        if self.improves(t, id) {
            *self = Closest {
                t,
                id,
                uv,
                found: true,
            };
        }
    }
}

/// Per-ray constants of the traversal.
struct TraversalRay {
    origin: Vec3A,
    /// 1 / dir per axis, finite (see `new`).
    inv_dir: Vec3A,
    shear: ShearedRay,
    packet: PacketRay,
    dir: Vec3,
}

impl TraversalRay {
    #[inline(always)]
    fn new(ray: &Ray) -> Self {
        // 1/0 = inf would give 0 * inf = NaN for a ray in a box's face plane; a huge finite
        // inverse gives the same slab intervals (up to t ~ 1e30) without NaN.
        let inv = |d: f32| {
            let i = 1.0 / d;
            if i.is_finite() {
                i
            } else {
                f32::MAX.copysign(d)
            }
        };
        let shear = ShearedRay::new(ray.origin, ray.dir);
        TraversalRay {
            origin: ray.origin.into(),
            inv_dir: Vec3A::new(inv(ray.dir.x), inv(ray.dir.y), inv(ray.dir.z)),
            packet: PacketRay::new(&shear),
            shear,
            dir: ray.dir,
        }
    }

    /// The slab test of a node's child boxes against [0, t_max]: the bitmask of the children
    /// met and their entry distances. All eight children at once over [`F32x8`]; no NaN can
    /// occur (see `new`), so its min/max (`a < b ? a : b`) are the exact minimum and maximum.
    #[inline(always)]
    fn slab(&self, node: &Node, t_max: f32) -> (u32, [f32; WIDTH]) {
        const _: () = assert!(WIDTH == LANES, "one F32x8 holds a node's children");
        let axis = |a: usize| {
            let (o, inv) = (F32x8::splat(self.origin[a]), F32x8::splat(self.inv_dir[a]));
            let t0 = (F32x8::from_array(&node.min[a]) - o) * inv;
            let t1 = (F32x8::from_array(&node.max[a]) - o) * inv;
            (t0.min(t1), t0.max(t1))
        };
        let ((near_x, far_x), (near_y, far_y), (near_z, far_z)) = (axis(0), axis(1), axis(2));
        let t_near = near_x.max(near_y).max(near_z.max(F32x8::zero()));
        let t_far = far_x.min(far_y).min(far_z.min(F32x8::splat(t_max))) * F32x8::splat(SLAB_SCALE);
        (t_near.le(t_far).bits() & node.valid, t_near.to_array())
    }

    /// Intersects a sphere: t in (0, t_max].
    #[inline(always)]
    fn sphere(&self, s: &SphereRecord, t_max: f32) -> Option<f32> {
        let bound = t_max * WIDEN;
        intersect_sphere(s.center, s.radius, self.origin.into(), self.dir, bound)
    }
}

impl Geometry {
    /// Builds the BVH over all triangles of `meshes` and all `spheres`. Degenerate triangles
    /// (zero area or non-finite vertices) are skipped and counted in [`Geometry::skipped_triangles`].
    pub fn new(meshes: &[TriangleMesh], spheres: &[Sphere]) -> Self {
        let mut triangles = Vec::new();
        let mut tri_geometric_normals = Vec::new();
        let mut tri_materials = Vec::new();
        let mut tri_normals = Vec::new();
        let mut shading_normals = Vec::new();
        let mut skipped = 0;
        for mesh in meshes {
            let has_normals = mesh.normals.len() == mesh.positions.len();
            for (i, idx) in mesh.indices.iter().enumerate() {
                let vertex = |k: usize| mesh.positions.get(idx[k] as usize).copied();
                let (Some(v0), Some(v1), Some(v2)) = (vertex(0), vertex(1), vertex(2)) else {
                    skipped += 1;
                    continue;
                };
                let tri = Triangle { v: [v0, v1, v2] };
                let n = tri.cross();
                let finite = v0.is_finite() && v1.is_finite() && v2.is_finite();
                // A zero cross product covers repeated vertices and collinear ones.
                if !finite || !n.is_finite() || n.length_squared() == 0.0 {
                    skipped += 1;
                    continue;
                }
                triangles.push(tri);
                tri_geometric_normals.push(n.normalize());
                tri_materials.push(mesh.materials.get(i).copied().unwrap_or(0));
                if has_normals {
                    tri_normals.push(shading_normals.len() as u32);
                    shading_normals.push(idx.map(|k| mesh.normals[k as usize]));
                } else {
                    tri_normals.push(u32::MAX);
                }
            }
        }
        let spheres = spheres.to_vec();

        let mut aabbs: Vec<Aabb> = triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.v.map(Vec3A::from);
                Aabb::new(a.min(b).min(c), a.max(b).max(c))
            })
            .collect();
        aabbs.extend(spheres.iter().map(|s| {
            let r = s.radius.abs();
            if s.center.is_finite() && r.is_finite() {
                let c = Vec3A::from(s.center);
                Aabb::new(c - r, c + r)
            } else {
                // Never hit (see `intersect_sphere`); keep it out of the way of the build.
                Aabb::from_point(Vec3A::ZERO)
            }
        }));
        let bounds = aabbs.iter().fold(None, |acc: Option<Aabb>, b| {
            Some(acc.map_or(*b, |a| a.union(b)))
        });
        let bounds = bounds.map_or((Vec3::ZERO, Vec3::ZERO), |b| (b.min.into(), b.max.into()));

        let mut wide = WideBvh::default();
        if !aabbs.is_empty() {
            // At most 2 primitives per leaf (one quad: a half-filled packet). Callgrind, one
            // iteration (`--photons 65536 --width 256 --height 256 -n 1 --threads 1`), whole
            // program, leaves of at most 1 / 2 / 4 with 4-wide nodes: specular box
            // 531 / 484 / 584 M instructions, water 1349 / 1229 / 1222 M, diffuse box
            // 537 / 477 / 479 M; with 8-wide nodes, 2 / 4: specular 414 / 540 M, water
            // 1091 / 1088 M, diffuse 404 / 412 M. The box walls span the scene, so bigger
            // leaves cull less.
            let params = BvhBuildParams {
                max_prims_per_leaf: 2,
                ..BvhBuildParams::medium_build()
            };
            let bvh: Bvh2 =
                obvhs::bvh2::builder::build_bvh2(&aabbs, params, &mut Default::default());
            wide.build(&bvh, &triangles, &spheres);
        }
        Geometry {
            nodes: wide.nodes,
            leaves: wide.leaves,
            packets: wide.packets,
            sphere_records: wide.spheres,
            triangles,
            tri_geometric_normals,
            tri_materials,
            tri_normals,
            shading_normals,
            spheres,
            skipped,
            bounds,
            stack_size: (WIDTH - 1) * wide.depth + 1,
        }
    }

    /// Closest hit along the ray. Always inlined: the passes call it in their hot loops,
    /// and whether LLVM inlines it otherwise depends on how the crate is split into codegen
    /// units (outlined, an iteration took 2-3% more instructions).
    #[inline(always)]
    pub fn intersect(&self, ray: &Ray) -> Option<Hit> {
        let tr = TraversalRay::new(ray);
        let mut best = Closest {
            t: ray.t_max,
            id: 0,
            uv: Vec2::ZERO,
            found: false,
        };
        self.traverse(&tr, ray.t_max, |leaf, t_max| {
            for packet in self.leaf_packets(leaf) {
                let bound = best.t * WIDEN;
                packet.intersect(&tr.shear, &tr.packet, bound, |lane, t, b1, b2| {
                    best.offer(t, packet.id[lane], Vec2::new(b1, b2));
                });
            }
            for s in self.leaf_spheres(leaf) {
                if let Some(t) = tr.sphere(s, best.t) {
                    best.offer(t, s.id, Vec2::ZERO);
                }
            }
            *t_max = best.t;
            false
        });
        best.found.then(|| self.hit(ray, best.t, best.id, best.uv))
    }

    /// True if anything blocks the ray within (0, t_max).
    #[inline]
    pub fn occluded(&self, ray: &Ray) -> bool {
        let tr = TraversalRay::new(ray);
        let bound = ray.t_max * WIDEN;
        self.traverse(&tr, ray.t_max, |leaf, _| {
            let mut blocked = false;
            for packet in self.leaf_packets(leaf) {
                packet.intersect(&tr.shear, &tr.packet, bound, |_, t, _, _| {
                    blocked |= t < ray.t_max;
                });
                if blocked {
                    return true;
                }
            }
            self.leaf_spheres(leaf)
                .iter()
                .any(|s| tr.sphere(s, ray.t_max).is_some_and(|t| t < ray.t_max))
        })
    }

    /// The triangle packets of a leaf.
    #[inline(always)]
    fn leaf_packets(&self, leaf: &Leaf) -> &[TrianglePacket] {
        &self.packets[leaf.packets.0 as usize..leaf.packets.1 as usize]
    }

    /// The spheres of a leaf.
    #[inline(always)]
    fn leaf_spheres(&self, leaf: &Leaf) -> &[SphereRecord] {
        &self.sphere_records[leaf.spheres.0 as usize..leaf.spheres.1 as usize]
    }

    /// Stack traversal, nearest child first. `leaf(leaf, t_max)` tests the primitives of a
    /// leaf, may shrink `t_max`, and returns true to stop; so does `traverse`.
    #[inline(always)]
    fn traverse(
        &self,
        tr: &TraversalRay,
        t_max: f32,
        mut leaf: impl FnMut(&Leaf, &mut f32) -> bool,
    ) -> bool {
        if self.nodes.is_empty() {
            return false;
        }
        // The stack array is zeroed on every call: a small tree gets a small one (zeroing
        // the 64-entry array on every ray cost about 1% of an iteration's instructions).
        if self.stack_size <= SMALL_STACK_SIZE {
            let mut stack = [(0u32, 0.0f32); SMALL_STACK_SIZE];
            self.traverse_with(tr, t_max, &mut stack, &mut leaf)
        } else if self.stack_size <= STACK_SIZE {
            let mut stack = [(0u32, 0.0f32); STACK_SIZE];
            self.traverse_with(tr, t_max, &mut stack, &mut leaf)
        } else {
            let mut stack = vec![(0u32, 0.0f32); self.stack_size];
            self.traverse_with(tr, t_max, &mut stack, &mut leaf)
        }
    }

    #[inline(always)]
    fn traverse_with(
        &self,
        tr: &TraversalRay,
        mut t_max: f32,
        stack: &mut [(u32, f32)],
        leaf: &mut impl FnMut(&Leaf, &mut f32) -> bool,
    ) -> bool {
        // Entries are (child reference, entry distance), the nearest on top.
        let mut sp = 0;
        let mut current = 0u32;
        loop {
            if current & LEAF != 0 {
                if leaf(&self.leaves[(current & !LEAF) as usize], &mut t_max) {
                    return true;
                }
            } else {
                let node = &self.nodes[current as usize];
                let (mut met, t_near) = tr.slab(node, t_max);
                if met != 0 {
                    let first = met.trailing_zeros() as usize;
                    met &= met - 1;
                    if met == 0 {
                        current = node.child[first];
                        continue;
                    }
                    // Two or more children: push them all, sorted so the nearest is on top.
                    let base = sp;
                    stack[sp] = (node.child[first], t_near[first]);
                    sp += 1;
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
            }
            // The nearest deferred child still in reach: the slab test as it would be now.
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

    /// Closest hit by testing every primitive (the reference for tests).
    pub fn intersect_brute_force(&self, ray: &Ray) -> Option<Hit> {
        let tr = TraversalRay::new(ray);
        let mut best = Closest {
            t: ray.t_max,
            id: 0,
            uv: Vec2::ZERO,
            found: false,
        };
        for (id, tri) in self.triangles.iter().enumerate() {
            let [v0, v1, v2] = tri.v;
            let bound = best.t * WIDEN;
            if let Some((t, b1, b2)) = tr.shear.intersect(v0, v1, v2, bound) {
                best.offer(t, id as u32, Vec2::new(b1, b2));
            }
        }
        for (i, s) in self.spheres.iter().enumerate() {
            let id = self.triangles.len() + i;
            if let Some(t) = tr.sphere(&sphere_record(s, id), best.t) {
                best.offer(t, id as u32, Vec2::ZERO);
            }
        }
        best.found.then(|| self.hit(ray, best.t, best.id, best.uv))
    }

    /// Everything the integrators need about the hit on primitive `prim` at distance `t`.
    #[inline(always)]
    fn hit(&self, ray: &Ray, t: f32, prim: u32, uv: Vec2) -> Hit {
        let n_tri = self.triangles.len() as u32;
        if prim < n_tri {
            let i = prim as usize;
            let [v0, v1, v2] = self.triangles[i].v;
            // The point from barycentrics in double precision, rounded once: it lies on the
            // triangle's plane to within half an ulp of its own coordinates, whatever the size
            // of the triangle, which is what `offset_origin` assumes.
            let (b1, b2) = (uv.x as f64, uv.y as f64);
            let p = DVec3::from(v0) * (1.0 - b1 - b2) + DVec3::from(v1) * b1 + DVec3::from(v2) * b2;
            let ng = self.tri_geometric_normals[i];
            let ns = match self.tri_normals[i] {
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
                material: self.tri_materials[i],
                prim,
            }
        } else {
            let s = &self.spheres[(prim - n_tri) as usize];
            let (p, ng) = s.surface(ray.at(t));
            Hit {
                t,
                p,
                ng,
                ns: ng,
                uv,
                material: s.material,
                prim,
            }
        }
    }

    /// Number of triangles kept.
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// Number of spheres.
    pub fn sphere_count(&self) -> usize {
        self.spheres.len()
    }

    /// Triangles dropped as degenerate.
    pub fn skipped_triangles(&self) -> usize {
        self.skipped
    }

    /// The triangle with global id `prim` (< triangle_count) and its material.
    pub fn triangle(&self, prim: u32) -> (Triangle, u32) {
        (
            self.triangles[prim as usize],
            self.tri_materials[prim as usize],
        )
    }

    /// The sphere with global id `prim` (>= triangle_count).
    pub fn sphere(&self, prim: u32) -> &Sphere {
        &self.spheres[prim as usize - self.triangles.len()]
    }

    /// World-space bounds (min, max) of all primitives.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.bounds
    }
}

/// A sphere's leaf record; a sphere with a non-finite center is never hit (radius 0).
fn sphere_record(s: &Sphere, id: usize) -> SphereRecord {
    let (center, radius) = if s.center.is_finite() {
        (s.center, s.radius.abs())
    } else {
        (Vec3::ZERO, 0.0)
    };
    SphereRecord {
        center,
        radius,
        id: id as u32,
    }
}

/// The 8-wide BVH being collapsed from obvhs's binary one.
#[derive(Default)]
struct WideBvh {
    nodes: Vec<Node>,
    leaves: Vec<Leaf>,
    packets: Vec<TrianglePacket>,
    spheres: Vec<SphereRecord>,
    /// Nodes on the longest root-to-leaf path.
    depth: usize,
}

impl WideBvh {
    fn build(&mut self, bvh: &Bvh2, triangles: &[Triangle], spheres: &[Sphere]) {
        let root = &bvh.nodes[0];
        if root.is_leaf() {
            // A single leaf still hangs below a node: traversal starts at a node.
            let leaf = self.leaf(bvh, 0, triangles, spheres);
            let mut node = Node::EMPTY;
            node.set_child(0, &root.aabb, leaf);
            self.nodes.push(node);
            self.depth = 1;
        } else {
            self.node(bvh, 0, triangles, spheres, 1);
        }
    }

    /// Collapses the binary subtree under inner node `index`; returns the new node's index.
    fn node(
        &mut self,
        bvh: &Bvh2,
        index: usize,
        triangles: &[Triangle],
        spheres: &[Sphere],
        depth: usize,
    ) -> u32 {
        self.depth = self.depth.max(depth);
        let first = bvh.nodes[index].first_index as usize;
        let mut children = vec![first, first + 1];
        // Open the inner child with the largest surface area until there are WIDTH.
        while children.len() < WIDTH {
            let widest = (0..children.len())
                .filter(|&i| !bvh.nodes[children[i]].is_leaf())
                .max_by(|&a, &b| {
                    let area = |i: usize| bvh.nodes[children[i]].aabb.half_area();
                    area(a).total_cmp(&area(b))
                });
            let Some(i) = widest else { break };
            let pair = bvh.nodes[children[i]].first_index as usize;
            children.splice(i..=i, [pair, pair + 1]);
        }
        let slot = self.nodes.len();
        self.nodes.push(Node::EMPTY);
        let mut node = Node::EMPTY;
        for (i, &c) in children.iter().enumerate() {
            let child = if bvh.nodes[c].is_leaf() {
                self.leaf(bvh, c, triangles, spheres)
            } else {
                self.node(bvh, c, triangles, spheres, depth + 1)
            };
            node.set_child(i, &bvh.nodes[c].aabb, child);
        }
        self.nodes[slot] = node;
        slot as u32
    }

    /// Packs the primitives of binary leaf `index`; returns its child reference.
    fn leaf(
        &mut self,
        bvh: &Bvh2,
        index: usize,
        triangles: &[Triangle],
        spheres: &[Sphere],
    ) -> u32 {
        let n = &bvh.nodes[index];
        let prims = &bvh.primitive_indices[n.first_index as usize..][..n.prim_count as usize];
        let tris: Vec<([Vec3; 3], u32)> = prims
            .iter()
            .filter(|&&id| (id as usize) < triangles.len())
            .map(|&id| (triangles[id as usize].v, id))
            .collect();
        let packets = self.packets.len() as u32;
        self.packets.extend(tris.chunks(4).map(TrianglePacket::new));
        let first_sphere = self.spheres.len() as u32;
        self.spheres.extend(
            prims
                .iter()
                .filter(|&&id| id as usize >= triangles.len())
                .map(|&id| sphere_record(&spheres[id as usize - triangles.len()], id as usize)),
        );
        self.leaves.push(Leaf {
            packets: (packets, self.packets.len() as u32),
            spheres: (first_sphere, self.spheres.len() as u32),
        });
        LEAF | (self.leaves.len() as u32 - 1)
    }
}

impl Node {
    const EMPTY: Node = Node {
        min: [[0.0; WIDTH]; 3],
        max: [[0.0; WIDTH]; 3],
        child: [0; WIDTH],
        valid: 0,
    };

    fn set_child(&mut self, i: usize, aabb: &Aabb, child: u32) {
        for axis in 0..3 {
            self.min[axis][i] = aabb.min[axis];
            self.max[axis][i] = aabb.max[axis];
        }
        self.child[i] = child;
        self.valid |= 1 << i;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    /// Every traversal stack (the small and the large array, the heap) answers like the brute
    /// force on the same tree: `stack_size` only picks the stack, so a shallow tree can be
    /// sent down each of them.
    #[test]
    fn every_stack_tier_matches_brute_force() {
        let mut rng = Rng::new(7, 0, 0);
        let mut point =
            || (Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * 2.0 - 1.0) * 3.0;
        let n = 24u32;
        let positions: Vec<Vec3> = (0..3 * n).map(|_| point()).collect();
        let indices = (0..n).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]).collect();
        let spheres: Vec<Sphere> = (0..6).map(|_| Sphere::new(point(), 0.4, 0)).collect();
        let mut geometry = Geometry::new(&[TriangleMesh::new(positions, indices, 0)], &spheres);
        // Two levels of nodes: deep enough to push and pop, shallow enough for every stack.
        assert_eq!(geometry.stack_size, 2 * (WIDTH - 1) + 1);
        assert!(geometry.stack_size <= SMALL_STACK_SIZE);
        let rays: Vec<Ray> = (0..2000)
            .map(|_| Ray::new(point(), (point() - point()).normalize()))
            .collect();
        let expected: Vec<Option<f32>> = rays
            .iter()
            .map(|r| geometry.intersect_brute_force(r).map(|h| h.t))
            .collect();
        for tier in [SMALL_STACK_SIZE, STACK_SIZE, STACK_SIZE + 1] {
            geometry.stack_size = tier;
            let mut hits = 0;
            for (ray, want) in rays.iter().zip(&expected) {
                let got = geometry.intersect(ray).map(|h| h.t);
                assert_eq!(
                    got.map(f32::to_bits),
                    want.map(f32::to_bits),
                    "stack {tier}"
                );
                assert_eq!(geometry.occluded(ray), want.is_some(), "stack {tier}");
                hits += got.is_some() as usize;
            }
            assert!(hits > 200, "too few hits to test anything: {hits}");
        }
    }

    /// The slab test of one child box in scalar code, with the vector's min/max semantics
    /// (`a < b ? a : b`): the reference for [`TraversalRay::slab`].
    fn slab_scalar(ray: &TraversalRay, node: &Node, t_max: f32, i: usize) -> (bool, f32) {
        let min = |a: f32, b: f32| if a < b { a } else { b };
        let max = |a: f32, b: f32| if a > b { a } else { b };
        let mut near = [0.0; 3];
        let mut far = [0.0; 3];
        for a in 0..3 {
            let t0 = (node.min[a][i] - ray.origin[a]) * ray.inv_dir[a];
            let t1 = (node.max[a][i] - ray.origin[a]) * ray.inv_dir[a];
            (near[a], far[a]) = (min(t0, t1), max(t0, t1));
        }
        let t_near = max(max(near[0], near[1]), max(near[2], 0.0));
        let t_far = min(min(far[0], far[1]), min(far[2], t_max)) * SLAB_SCALE;
        (t_near <= t_far && node.valid >> i & 1 == 1, t_near)
    }

    /// The 8-wide slab test answers like the scalar one lane by lane, bit for bit: random
    /// boxes (also flat and inverted ones, unused lanes) against random rays (also with zero
    /// direction components and origins on a box face).
    #[test]
    fn slab_matches_scalar_reference() {
        let mut rng = Rng::new(11, 0, 0);
        let mut value = move || (rng.uniform() * 2.0 - 1.0) * 4.0;
        let (mut met, mut missed) = (0, 0);
        for case in 0..20_000 {
            let mut node = Node::EMPTY;
            for i in 0..WIDTH {
                for axis in 0..3 {
                    let (a, b) = (value(), value());
                    let flat = case % 5 == 0 && axis == 1;
                    node.min[axis][i] = a.min(b);
                    node.max[axis][i] = if flat { a.min(b) } else { a.max(b) };
                }
                node.child[i] = i as u32;
            }
            node.valid = (case as u32 * 37) & 0xff | 1;
            let mut origin = Vec3::new(value(), value(), value());
            if case % 7 == 0 {
                origin.x = node.min[0][case % WIDTH];
            }
            let mut dir = Vec3::new(value(), value(), value());
            if case % 3 == 0 {
                dir[case % 3] = 0.0;
            } else if case % 3 == 1 {
                // Through a box corner: entry and exit agree to a few ulps, where the
                // rounding allowance decides.
                let i = case % WIDTH;
                dir = Vec3::new(node.max[0][i], node.min[1][i], node.max[2][i]) - origin;
            }
            let ray = TraversalRay::new(&Ray::new(origin, dir.normalize_or(Vec3::Z)));
            let t_max = if case % 2 == 0 {
                f32::INFINITY
            } else {
                value().abs()
            };
            let (lanes_met, lanes_near) = ray.slab(&node, t_max);
            for i in 0..WIDTH {
                let (hit, near) = slab_scalar(&ray, &node, t_max, i);
                assert_eq!(lanes_met >> i & 1 == 1, hit, "case {case} lane {i}");
                assert_eq!(
                    lanes_near[i].to_bits(),
                    near.to_bits(),
                    "case {case} lane {i}"
                );
            }
            met += lanes_met.count_ones();
            missed += (node.valid & !lanes_met).count_ones();
        }
        assert!(
            met > 3000 && missed > 3000,
            "too few boxes met or missed to test anything: {met}, {missed}"
        );
    }
}
