//! Traversal of the 8-wide BVH: the robust slab test of a node's eight boxes at once, and a
//! stack walk nearest child first for closest-hit queries (any-hit ones: `any_hit.rs`).

use super::wide::{packet_index, sphere_record, Leaf, Node, SphereRecord, LEAF, PACKET, WIDTH};
use super::Geometry;
use crate::geometry::sphere::intersect_sphere;
use crate::geometry::triangle::{gamma, ShearedRay};
use crate::geometry::triangle_packet::{PacketRay, TrianglePacket};
use crate::geometry::{Hit, Ray};
use crate::simd::{F32x8, LANES};
use glam::{Vec2, Vec3, Vec3A};

/// Traversal stack size kept on the call stack; deeper trees (never seen in practice) use a
/// heap stack sized at build time.
pub(super) const STACK_SIZE: usize = 64;

/// Stack size for trees of depth up to 2 (WIDTH - 1 entries per level, plus one).
pub(super) const SMALL_STACK_SIZE: usize = 16;

/// Box exits are scaled by this (Ize 2013: three roundings in (bound - o) * inv_dir).
pub(super) const SLAB_SCALE: f32 = 1.0 + 2.0 * gamma(3);

/// Primitive tests get their bound widened by this: the final comparison is on the returned t
/// itself (`Closest::improves`, or `t < t_max` for shadow rays), so that exactly equal
/// distances are resolved the same way everywhere.
pub(super) const WIDEN: f32 = 1.0 + 4.0 * f32::EPSILON;

/// The closest candidate found so far: distance, global id, barycentrics, and for a
/// triangle found by the traversal its packet and lane (whose vertices the hit reads).
#[derive(Clone, Copy)]
pub(super) struct Closest<'a> {
    pub(super) t: f32,
    pub(super) id: u32,
    pub(super) uv: Vec2,
    pub(super) found: bool,
    pub(super) packet: Option<(&'a TrianglePacket, usize)>,
}

impl<'a> Closest<'a> {
    /// Nothing found yet within `t_max`.
    pub(super) fn new(t_max: f32) -> Self {
        Closest {
            t: t_max,
            id: 0,
            uv: Vec2::ZERO,
            found: false,
            packet: None,
        }
    }

    /// Nearer, or as near with a smaller id: the same answer in any traversal order.
    #[inline(always)]
    fn improves(&self, t: f32, id: u32) -> bool {
        t < self.t || (t == self.t && id < self.id)
    }

    /// Keeps the candidate if it improves on the closest so far.
    #[inline(always)]
    fn offer(&mut self, t: f32, id: u32, uv: Vec2, packet: Option<(&'a TrianglePacket, usize)>) {
        if self.improves(t, id) {
            *self = Closest {
                t,
                id,
                uv,
                found: true,
                packet,
            };
        }
    }
}

/// Per-ray constants of the traversal.
pub(super) struct TraversalRay {
    origin: Vec3A,
    /// 1 / dir per axis, finite (see `new`).
    inv_dir: Vec3A,
    shear: ShearedRay,
    packet: PacketRay,
    dir: Vec3,
}

impl TraversalRay {
    #[inline(always)]
    pub(super) fn new(ray: &Ray) -> Self {
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
    pub(super) fn slab(&self, node: &Node, t_max: f32) -> (u32, [f32; WIDTH]) {
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
    pub(super) fn sphere(&self, s: &SphereRecord, t_max: f32) -> Option<f32> {
        let bound = t_max * WIDEN;
        intersect_sphere(s.center, s.radius, self.origin.into(), self.dir, bound)
    }

    /// Tests a triangle packet against (0, bound], calling `hit(t)` for each lane met.
    #[inline(always)]
    pub(super) fn packet_test(
        &self,
        packet: &TrianglePacket,
        bound: f32,
        mut hit: impl FnMut(f32),
    ) {
        packet.intersect(&self.shear, &self.packet, bound, |_, t, _, _| hit(t));
    }
}

impl Geometry {
    /// Closest hit along the ray: the primitives of the flat level, then the instances (whose
    /// ids all come after the flat level's, so a flat hit wins a tie). Always inlined: the
    /// passes call it in their hot loops, and whether LLVM inlines it otherwise depends on
    /// how the crate is split into codegen units.
    #[inline(always)]
    pub fn intersect(&self, ray: &Ray) -> Option<Hit> {
        let hit = self.intersect_flat(ray);
        if self.instances.is_empty() {
            hit
        } else {
            self.instances.intersect(ray, hit)
        }
    }

    /// Closest hit among the primitives of this level's own BVH (instances left out).
    #[inline(always)]
    pub(super) fn intersect_flat(&self, ray: &Ray) -> Option<Hit> {
        let tr = TraversalRay::new(ray);
        let best = self.closest(&tr, ray.t_max);
        match (best.found, best.packet) {
            (false, _) => None,
            (true, Some((packet, lane))) => {
                Some(self.triangle_hit(best.t, best.id, best.uv, packet.vertices(lane)))
            }
            (true, None) => Some(self.sphere_hit(ray, best.t, best.id)),
        }
    }

    /// The closest candidate in (0, t_max) of this level's own BVH, before its hit record
    /// is made (an instance makes it in world space).
    #[inline(always)]
    pub(super) fn closest(&self, tr: &TraversalRay, t_max: f32) -> Closest<'_> {
        let mut best = Closest::new(t_max);
        self.traverse(tr, t_max, |packets, spheres, t_max| {
            for packet in packets {
                let bound = best.t * WIDEN;
                packet.intersect(&tr.shear, &tr.packet, bound, |lane, t, b1, b2| {
                    best.offer(t, packet.id[lane], Vec2::new(b1, b2), Some((packet, lane)));
                });
            }
            for s in spheres {
                if let Some(t) = tr.sphere(s, best.t) {
                    best.offer(t, s.id, Vec2::ZERO, None);
                }
            }
            *t_max = best.t;
            false
        });
        best
    }

    /// The triangle packets of a leaf.
    #[inline(always)]
    pub(super) fn leaf_packets(&self, leaf: &Leaf) -> &[TrianglePacket] {
        &self.packets[leaf.packets.0 as usize..leaf.packets.1 as usize]
    }

    /// The spheres of a leaf.
    #[inline(always)]
    pub(super) fn leaf_spheres(&self, leaf: &Leaf) -> &[SphereRecord] {
        &self.sphere_records[leaf.spheres.0 as usize..leaf.spheres.1 as usize]
    }

    /// Stack traversal, nearest child first. `leaf(packets, spheres, t_max)` tests the
    /// primitives of a leaf, may shrink `t_max`, and returns true to stop; so does `traverse`.
    #[inline(always)]
    fn traverse<'g>(
        &'g self,
        tr: &TraversalRay,
        t_max: f32,
        mut leaf: impl FnMut(&'g [TrianglePacket], &'g [SphereRecord], &mut f32) -> bool,
    ) -> bool {
        if self.nodes.is_empty() {
            return false;
        }
        // The stack array is zeroed on every call: a small tree gets a small one.
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
    fn traverse_with<'g>(
        &'g self,
        tr: &TraversalRay,
        mut t_max: f32,
        stack: &mut [(u32, f32)],
        leaf: &mut impl FnMut(&'g [TrianglePacket], &'g [SphereRecord], &mut f32) -> bool,
    ) -> bool {
        // Entries are (child reference, entry distance), the nearest on top.
        let mut sp = 0;
        let mut current = 0u32;
        loop {
            if current & LEAF != 0 {
                let (packets, spheres) = if current & PACKET != 0 {
                    let packet = &self.packets[packet_index(current)];
                    (std::slice::from_ref(packet), &[][..])
                } else {
                    let record = &self.leaves[(current & !LEAF) as usize];
                    (self.leaf_packets(record), self.leaf_spheres(record))
                };
                if leaf(packets, spheres, &mut t_max) {
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
                    self.prefetch(node.child[first]);
                    stack[sp] = (node.child[first], t_near[first]);
                    sp += 1;
                    while met != 0 {
                        let i = met.trailing_zeros() as usize;
                        met &= met - 1;
                        let entry = (node.child[i], t_near[i]);
                        self.prefetch(entry.0);
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

    /// Asks the cache for the lines of a child a node pushes (a node's four, a packet's three
    /// or four), so that the misses of the children deferred overlap the work on the nearer
    /// ones instead of stalling the loop when they are popped. Leaf records, rare on meshes,
    /// are not prefetched.
    #[inline(always)]
    pub(super) fn prefetch(&self, child: u32) {
        if child & LEAF == 0 {
            prefetch_lines(self.nodes.as_ptr().wrapping_add(child as usize));
        } else if child & PACKET != 0 {
            prefetch_lines(self.packets.as_ptr().wrapping_add(packet_index(child)));
        }
    }

    /// Closest hit by testing every primitive (the reference for tests).
    pub fn intersect_brute_force(&self, ray: &Ray) -> Option<Hit> {
        let tr = TraversalRay::new(ray);
        let mut best = Closest::new(ray.t_max);
        let n_tri = self.triangle_count();
        for id in 0..n_tri {
            let [v0, v1, v2] = self.packed_vertices(id as u32);
            let bound = best.t * WIDEN;
            if let Some((t, b1, b2)) = tr.shear.intersect(v0, v1, v2, bound) {
                best.offer(t, id as u32, Vec2::new(b1, b2), None);
            }
        }
        for (i, s) in self.spheres.iter().enumerate() {
            let id = n_tri + i;
            if let Some(t) = tr.sphere(&sphere_record(s, id), best.t) {
                best.offer(t, id as u32, Vec2::ZERO, None);
            }
        }
        let triangle = (best.id as usize) < n_tri;
        best.found.then(|| match triangle {
            true => {
                let v = self.packed_vertices(best.id);
                self.triangle_hit(best.t, best.id, best.uv, v)
            }
            false => self.sphere_hit(ray, best.t, best.id),
        })
    }
}

/// Prefetches the cache line of address `p` (into every level); a prefetch never faults.
#[inline(always)]
pub(super) fn prefetch_line(p: usize) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: a prefetch is a hint with no architectural effect; it never faults, whatever
    // the address.
    unsafe {
        std::arch::x86_64::_mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T0 }>(p as *const i8)
    };
    #[cfg(not(target_arch = "x86_64"))]
    let _ = p;
}

/// Prefetches the cache lines of the value at `p` (into every level). `p` is never
/// dereferenced: a prefetch does not fault, and nothing is read through the pointer.
#[inline(always)]
pub(super) fn prefetch_lines<T>(p: *const T) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        let start = p as usize & !63;
        let end = p as usize + size_of::<T>();
        let mut line = start;
        while line < end {
            // SAFETY: a prefetch is a hint with no architectural effect; it never faults,
            // whatever the address.
            unsafe { _mm_prefetch::<_MM_HINT_T0>(line as *const i8) };
            line += 64;
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = p;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Sphere, TriangleMesh};
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
    #[allow(clippy::needless_range_loop)] // a lane indexes the node and both results
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
