//! The 8-wide BVH: obvhs's binary BVH collapsed into nodes of eight children (each node opens
//! its children with the largest surface area until it holds eight, as Embree's BVH8 does),
//! with the boxes stored as structure of arrays for the 8-lane slab test.

use super::super::triangle_packet::TrianglePacket;
use super::super::{Sphere, Triangle};
use glam::Vec3;
use obvhs::aabb::Aabb;
use obvhs::bvh2::Bvh2;

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

/// Children per node.
pub(super) const WIDTH: usize = 8;

/// A node of the 8-wide BVH: the boxes of its children in structure-of-arrays form.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
pub(super) struct Node {
    /// `min[axis]` / `max[axis]`: that coordinate of each child's box.
    pub(super) min: [[f32; WIDTH]; 3],
    pub(super) max: [[f32; WIDTH]; 3],
    pub(super) child: [u32; WIDTH],
    /// Bitmask of the children in use.
    pub(super) valid: u32,
}

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

/// The 8-wide BVH being collapsed from obvhs's binary one.
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
    pub(super) fn build(&mut self, bvh: &Bvh2, triangles: &[Triangle], spheres: &[Sphere]) {
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
        // A fixed array, not a Vec: the collapse visits every node of a million-triangle
        // tree, and allocation would be most of its time.
        let mut children = [0usize; WIDTH];
        (children[0], children[1]) = (first, first + 1);
        let mut count = 2;
        // Open the inner child with the largest surface area until there are WIDTH.
        while count < WIDTH {
            let widest = (0..count)
                .filter(|&i| !bvh.nodes[children[i]].is_leaf())
                .max_by(|&a, &b| {
                    let area = |i: usize| bvh.nodes[children[i]].aabb.half_area();
                    area(a).total_cmp(&area(b))
                });
            let Some(i) = widest else { break };
            let pair = bvh.nodes[children[i]].first_index as usize;
            children.copy_within(i + 1..count, i + 2);
            (children[i], children[i + 1]) = (pair, pair + 1);
            count += 1;
        }
        let children = &children[..count];
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
        let packets = self.packets.len() as u32;
        // Four triangles at a time into a packet, through a fixed array (no allocation).
        let mut lanes = [([Vec3::ZERO; 3], 0u32); 4];
        let mut filled = 0;
        for &id in prims.iter().filter(|&&id| (id as usize) < triangles.len()) {
            lanes[filled] = (triangles[id as usize].v, id);
            filled += 1;
            if filled == 4 {
                self.packets.push(TrianglePacket::new(&lanes));
                filled = 0;
            }
        }
        if filled > 0 {
            self.packets.push(TrianglePacket::new(&lanes[..filled]));
        }
        let first_sphere = self.spheres.len() as u32;
        let sphere_count = prims
            .iter()
            .filter(|&&id| id as usize >= triangles.len())
            .count();
        if sphere_count == 0 && self.packets.len() as u32 == packets + 1 && packets < PACKET {
            return LEAF | PACKET | packets;
        }
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
    pub(super) const EMPTY: Node = Node {
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
