//! What a built BVH looks like: node and leaf counts, how full the nodes are, and its SAH
//! cost, in the terms Embree's verbose build statistics use, so two trees over the same
//! triangles can be compared without tracing a ray.

use super::wide::{Node, LEAF, PACKET, WIDTH};
use super::Geometry;

/// Counts and SAH cost of a built BVH ([`Geometry::bvh_stats`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BvhStats {
    /// Inner nodes.
    pub nodes: usize,
    /// Leaves (each a run of triangle packets and spheres).
    pub leaves: usize,
    /// Triangle packets of up to four triangles, over all leaves.
    pub packets: usize,
    /// Children in use over all nodes (`children / nodes` is the mean fill, at most 8).
    pub children: usize,
    /// Nodes on the longest root-to-leaf path.
    pub depth: usize,
    /// SAH cost of the inner nodes: the sum of their boxes' surface areas over the root's
    /// (the expected number of nodes a ray meeting the root's box visits, if a node test
    /// costs 1).
    pub sah_nodes: f64,
    /// SAH cost of the leaves: the sum of each leaf's surface area over the root's times its
    /// packets and spheres (the expected number of packet tests, at cost 1 each).
    pub sah_leaves: f64,
}

impl Geometry {
    /// Counts and SAH cost of the BVH (a diagnostic for comparing builds; walks every node).
    pub fn bvh_stats(&self) -> BvhStats {
        let mut stats = BvhStats::default();
        if self.nodes.is_empty() {
            return stats;
        }
        let half_area = |node: &Node, i: usize| {
            let d = |a: usize| (node.max[a][i] - node.min[a][i]).max(0.0) as f64;
            d(0) * d(1) + d(1) * d(2) + d(2) * d(0)
        };
        // The root's box is the union of its children's.
        let root = &self.nodes[0];
        let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
        for i in (0..WIDTH).filter(|i| root.valid >> i & 1 == 1) {
            for a in 0..3 {
                lo[a] = lo[a].min(root.min[a][i]);
                hi[a] = hi[a].max(root.max[a][i]);
            }
        }
        let d = |a: usize| (hi[a] - lo[a]).max(0.0) as f64;
        let root_area = (d(0) * d(1) + d(1) * d(2) + d(2) * d(0)).max(f64::MIN_POSITIVE);
        stats.sah_nodes = 1.0;
        // Depth-first from the root, with each node's depth.
        let mut stack = vec![(0u32, 1usize)];
        while let Some((index, depth)) = stack.pop() {
            let node = &self.nodes[index as usize];
            stats.nodes += 1;
            stats.depth = stats.depth.max(depth);
            for i in (0..WIDTH).filter(|i| node.valid >> i & 1 == 1) {
                stats.children += 1;
                let child = node.child[i];
                let area = half_area(node, i) / root_area;
                if child & LEAF == 0 {
                    stats.sah_nodes += area;
                    stack.push((child, depth + 1));
                    continue;
                }
                stats.leaves += 1;
                let (packets, spheres) = if child & PACKET != 0 {
                    (1, 0)
                } else {
                    let leaf = &self.leaves[(child & !LEAF) as usize];
                    (
                        leaf.packets.1 - leaf.packets.0,
                        leaf.spheres.1 - leaf.spheres.0,
                    )
                };
                stats.packets += packets as usize;
                let tests = packets + spheres;
                stats.sah_leaves += area * tests as f64;
            }
        }
        stats
    }
}

#[cfg(test)]
mod tests {
    use crate::geometry::{Geometry, TriangleMesh};
    use crate::sampling::Rng;
    use glam::Vec3;

    /// One triangle: one node whose one child is a one-packet leaf with the root's box, so
    /// both SAH terms are exactly 1.
    #[test]
    fn one_triangle_is_one_node_over_one_leaf() {
        let mesh = TriangleMesh::new(vec![Vec3::ZERO, Vec3::X, Vec3::Y], vec![[0, 1, 2]], 0);
        let s = Geometry::new(&[mesh], &[]).bvh_stats();
        assert_eq!(
            (s.nodes, s.leaves, s.packets, s.children, s.depth),
            (1, 1, 1, 1, 1)
        );
        assert_eq!((s.sah_nodes, s.sah_leaves), (1.0, 1.0));
    }

    /// Eight large triangles overlapping around the origin: no split is cheaper than one leaf,
    /// which holds two packets.
    #[test]
    fn eight_overlapping_triangles_are_one_leaf_of_two_packets() {
        let mut positions = Vec::new();
        for k in 0..8 {
            let a = k as f32 * 0.7;
            let (u, v) = (
                Vec3::new(a.cos(), a.sin(), 0.0),
                Vec3::new(0.0, 0.0, 1.0 + a),
            );
            positions.extend([u, v - u, -v]);
        }
        let indices = (0..8).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]).collect();
        let s = Geometry::new(&[TriangleMesh::new(positions, indices, 0)], &[]).bvh_stats();
        assert_eq!((s.nodes, s.leaves, s.packets), (1, 1, 2));
        assert_eq!(s.sah_leaves, 2.0);
    }

    /// Random triangles: every node but the root is some node's child, the packets hold
    /// every triangle (at most four each), and a node's or leaf's box never exceeds the root's.
    #[test]
    fn counts_are_consistent() {
        let mut rng = Rng::new(3, 0, 0);
        let n = 5000u32;
        let positions: Vec<Vec3> = (0..3 * n)
            .map(|i| {
                let centre = (i / 3) as f32;
                Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * 0.1
                    + Vec3::new(centre.sin(), centre.cos(), (centre * 0.37).sin()) * 4.0
            })
            .collect();
        let indices = (0..n).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]).collect();
        let g = Geometry::new(&[TriangleMesh::new(positions, indices, 0)], &[]);
        let s = g.bvh_stats();
        assert_eq!(s.children, s.nodes - 1 + s.leaves);
        assert!(s.packets * 4 >= g.triangle_count() && s.packets >= s.leaves);
        assert!(s.depth >= 3 && s.children <= 8 * s.nodes);
        assert!(s.sah_nodes < s.nodes as f64 && s.sah_leaves < s.packets as f64);
        assert!(s.sah_nodes > 1.0 && s.sah_leaves > 0.0);
    }
}
