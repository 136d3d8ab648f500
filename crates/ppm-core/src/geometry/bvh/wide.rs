//! The 8-wide BVH's layout: nodes of eight children with their boxes stored as structure of
//! arrays for the 8-lane slab test, leaves, and how a child reference names either; and the
//! packing of the built tree's leaves into triangle packets and sphere records.

use super::super::triangle_packet::TrianglePacket;
use super::super::{Sphere, Triangle};
use super::build::{build_tree, Aabb};
use super::traversal::prefetch_lines;
use glam::Vec3;
use rayon::prelude::*;

/// A sphere in a leaf.
#[derive(Clone, Copy, Debug)]
pub(super) struct SphereRecord {
    pub(super) center: Vec3,
    pub(super) radius: f32,
    pub(super) id: u32,
}

/// A child reference with this bit set names a leaf, else a node (the rest is its index).
pub(super) const LEAF: u32 = 1 << 31;

/// With [`LEAF`]: the leaf is one triangle packet and nothing else, and the rest of the
/// reference is the packet's index (most leaves of a triangle mesh). The traversal then
/// reads the packet directly, without first loading a [`Leaf`] record: one dependent load
/// less per leaf, as Embree encodes its leaves' primitives in the child reference.
/// Without it, the rest is the index of a [`Leaf`] record.
pub(super) const PACKET: u32 = 1 << 30;

/// The packet index a [`LEAF`] | [`PACKET`] reference names.
#[inline(always)]
pub(super) fn packet_index(child: u32) -> usize {
    (child & !(LEAF | PACKET)) as usize
}

/// How many packets ahead the leaf packing prefetches the triangles it gathers.
const GATHER_AHEAD: usize = 8;

/// Children per node.
pub(super) const WIDTH: usize = 8;

/// A node of the 8-wide BVH: the boxes of its children in structure-of-arrays form.
/// 256 bytes, aligned to a cache line: a node is read as exactly four lines. (Aligned to
/// 32 only, the allocator placed the array at 0 or 32 modulo 64 from run to run, and in the
/// second case every node straddled five lines.)
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
pub(super) struct Node {
    /// `min[axis]` / `max[axis]`: that coordinate of each child's box.
    pub(super) min: [[f32; WIDTH]; 3],
    pub(super) max: [[f32; WIDTH]; 3],
    pub(super) child: [u32; WIDTH],
    /// Bitmask of the children in use.
    pub(super) valid: u32,
}

const _: () = assert!(size_of::<Node>() == 256, "a node is four cache lines");

/// A leaf: a run of triangle packets and a run of spheres.
#[derive(Clone, Copy, Debug)]
pub(super) struct Leaf {
    pub(super) packets: (u32, u32),
    pub(super) spheres: (u32, u32),
}

/// A sphere's leaf record; a sphere with a non-finite center is never hit (radius 0).
pub(super) fn sphere_record(s: &Sphere, id: usize) -> SphereRecord {
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

/// The finished BVH: nodes, leaf records, triangle packets and sphere records.
#[derive(Default)]
pub(super) struct WideBvh {
    pub(super) nodes: Vec<Node>,
    pub(super) leaves: Vec<Leaf>,
    pub(super) packets: Vec<TrianglePacket>,
    pub(super) spheres: Vec<SphereRecord>,
    /// Nodes on the longest root-to-leaf path.
    pub(super) depth: usize,
}

impl WideBvh {
    /// Builds the BVH over `triangles` (ids 0..) and `spheres` (ids after the triangles),
    /// whose boxes are `bounds` in that order.
    ///
    /// The leaves of `build::build_tree`'s tree are packed in their order: each leaf's
    /// triangles four at a time into packets, in the order of the tree's references, then
    /// its spheres. A leaf of one packet and no sphere is named by its packet directly
    /// ([`PACKET`]); any other gets a [`Leaf`] record. The packets are filled in parallel,
    /// each at the index a serial prefix sum over the leaves' packet counts gave it, so the
    /// arrays are those of a serial loop over the leaves on any number of threads.
    pub(super) fn build(bounds: &[Aabb], triangles: &[Triangle], spheres: &[Sphere]) -> Self {
        if bounds.is_empty() {
            return WideBvh::default();
        }
        let n_tri = triangles.len();
        let mut tree = build_tree(bounds, n_tri);
        let refs = &tree.order;
        let leaf_refs =
            |(start, count): (u32, u32)| &refs[start as usize..(start + count) as usize];
        // Each leaf's packets and spheres.
        let counts: Vec<(u32, u32)> = tree
            .leaves
            .par_iter()
            .map(|&leaf| {
                let spheres = leaf_refs(leaf).iter().map(|r| r.sphere).sum::<u32>();
                ((leaf.1 - spheres).div_ceil(4), spheres)
            })
            .collect();
        let mut bvh = WideBvh {
            depth: tree.depth,
            ..WideBvh::default()
        };
        // The prefix sums, serially (a few operations per leaf): each leaf's child
        // reference, its records, and for each packet its leaf and its group of four.
        let mut references = Vec::with_capacity(tree.leaves.len());
        let mut packet_source: Vec<(u32, u32)> = Vec::new();
        for (l, (&leaf, &(packets, sphere_count))) in tree.leaves.iter().zip(&counts).enumerate() {
            let first_packet = packet_source.len() as u32;
            packet_source.extend((0..packets).map(|group| (l as u32, group)));
            let first_sphere = bvh.spheres.len() as u32;
            if sphere_count > 0 {
                bvh.spheres.extend(
                    leaf_refs(leaf)
                        .iter()
                        .filter(|r| r.sphere != 0)
                        .map(|r| sphere_record(&spheres[r.id as usize - n_tri], r.id as usize)),
                );
            }
            references.push(
                if sphere_count == 0 && packets == 1 && first_packet < PACKET {
                    LEAF | PACKET | first_packet
                } else {
                    bvh.leaves.push(Leaf {
                        packets: (first_packet, first_packet + packets),
                        spheres: (first_sphere, bvh.spheres.len() as u32),
                    });
                    LEAF | (bvh.leaves.len() as u32 - 1)
                },
            );
        }
        // Packet `group` of a leaf: its triangles 4 group .. 4 group + 4 (spheres skipped),
        // through a fixed array (no allocation).
        bvh.packets.par_extend(
            packet_source
                .par_iter()
                .enumerate()
                .map(|(p, &(l, group))| {
                    // The triangles are read by id, in no order: those of the packet
                    // GATHER_AHEAD places on are asked of the cache now.
                    if let Some(&(l, _)) = packet_source.get(p + GATHER_AHEAD) {
                        for r in leaf_refs(tree.leaves[l as usize]) {
                            prefetch_lines(triangles.as_ptr().wrapping_add(r.id as usize));
                        }
                    }
                    let mut lanes = [([Vec3::ZERO; 3], 0u32); 4];
                    let mut filled = 0;
                    let leaf = leaf_refs(tree.leaves[l as usize]);
                    for r in leaf
                        .iter()
                        .filter(|r| r.sphere == 0)
                        .skip(4 * group as usize)
                        .take(4)
                    {
                        lanes[filled] = (triangles[r.id as usize].v, r.id);
                        filled += 1;
                    }
                    TrianglePacket::new(&lanes[..filled])
                }),
        );
        tree.nodes.par_iter_mut().for_each(|node| {
            for i in 0..WIDTH {
                if node.valid >> i & 1 == 1 && node.child[i] & LEAF != 0 {
                    node.child[i] = references[(node.child[i] & !LEAF) as usize];
                }
            }
        });
        bvh.nodes = tree.nodes;
        bvh
    }
}

impl Node {
    pub(super) const EMPTY: Node = Node {
        min: [[0.0; WIDTH]; 3],
        max: [[0.0; WIDTH]; 3],
        child: [0; WIDTH],
        valid: 0,
    };

    pub(super) fn set_child(&mut self, i: usize, aabb: &Aabb, child: u32) {
        for axis in 0..3 {
            self.min[axis][i] = aabb.lo[axis];
            self.max[axis][i] = aabb.hi[axis];
        }
        self.child[i] = child;
        self.valid |= 1 << i;
    }
}
