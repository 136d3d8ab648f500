//! The BVH build: top-down binned SAH (`sah.rs`: how one set is split), straight to 8-wide
//! nodes, in parallel (this file: how the nodes are formed).
//!
//! An 8-wide node is formed as Embree's BVH8 builder forms one: starting from its set, the
//! child with the largest surface area that the SAH would split is split, until there are
//! eight children or no child should be split; the children take the node's slots by size.
//! Large children are built as parallel tasks on the current rayon pool, each into a subtree
//! of its own, appended in child order: the tree, its memory layout and so every answer are
//! the same on any number of threads.

mod sah;

#[cfg(test)]
use sah::MAX_LEAF;
use sah::{choose_split, partition, SetInfo, Split, PARALLEL_MIN};
pub(super) use sah::{Aabb, PrimRef};

use super::wide::{Node, LEAF, WIDTH};
use rayon::prelude::*;

/// A child being formed: its range in the node's slice of references, its set and the
/// SAH's decision for it.
#[derive(Clone, Copy)]
struct Child {
    start: usize,
    end: usize,
    info: SetInfo,
    split: Option<Split>,
}

/// A subtree in the making: nodes (its root first) whose leaf children name entries of
/// `leaves`, ranges of the final reference order.
#[derive(Default)]
struct Subtree {
    nodes: Vec<Node>,
    leaves: Vec<(u32, u32)>,
    depth: usize,
}

impl Subtree {
    /// Appends `other` (built apart), renumbering its references; returns its root's index.
    fn append(&mut self, other: Subtree, depth: usize) -> u32 {
        let (node_base, leaf_base) = (self.nodes.len() as u32, self.leaves.len() as u32);
        self.nodes.extend(other.nodes.into_iter().map(|mut node| {
            for i in 0..WIDTH {
                if node.valid >> i & 1 == 1 {
                    let c = node.child[i];
                    node.child[i] = if c & LEAF != 0 {
                        LEAF | ((c & !LEAF) + leaf_base)
                    } else {
                        c + node_base
                    };
                }
            }
            node
        }));
        self.leaves.extend(other.leaves);
        self.depth = self.depth.max(depth + other.depth);
        node_base
    }
}

/// Builds the node over `refs` (which starts at `offset` in the whole array) into `out`,
/// whose set is `info` and which the SAH splits by `split`; returns the node's index.
fn build_node(
    refs: &mut [PrimRef],
    offset: usize,
    info: SetInfo,
    split: Split,
    out: &mut Subtree,
    depth: usize,
) -> u32 {
    out.depth = out.depth.max(depth);
    let mut children = [Child {
        start: 0,
        end: refs.len(),
        info,
        split: Some(split),
    }; WIDTH];
    let mut count = 1;
    // Split the widest child the SAH would split, until there are eight.
    while count < WIDTH {
        let widest = (0..count)
            .filter_map(|i| children[i].split.map(|split| (i, split)))
            .max_by(|(a, _), (b, _)| {
                let area = |i: usize| children[i].info.bounds().half_area();
                area(*a).total_cmp(&area(*b))
            });
        let Some((i, split)) = widest else { break };
        let c = children[i];
        let slice = &mut refs[c.start..c.end];
        let (mid, left, right) = partition(slice, &c.info, &split);
        let (l, r) = slice.split_at(mid);
        let (left_split, right_split) = if slice.len() >= 2 * PARALLEL_MIN {
            rayon::join(|| choose_split(l, &left), || choose_split(r, &right))
        } else {
            (choose_split(l, &left), choose_split(r, &right))
        };
        children.copy_within(i + 1..count, i + 2);
        children[i] = Child {
            start: c.start,
            end: c.start + mid,
            info: left,
            split: left_split,
        };
        children[i + 1] = Child {
            start: c.start + mid,
            end: c.end,
            info: right,
            split: right_split,
        };
        count += 1;
    }
    // The node's slots hold the children by size, the most primitives first, ties in range
    // order (a stable sort), as Embree's builder orders them: the any-hit traversal visits
    // the highest slot first (`any_hit.rs`). The children's ranges keep their order.
    let mut by_size: [usize; WIDTH] = std::array::from_fn(|i| i);
    by_size[..count].sort_by_key(|&i| std::cmp::Reverse(children[i].end - children[i].start));
    let mut slot_of = [0usize; WIDTH];
    for (slot, &i) in by_size[..count].iter().enumerate() {
        slot_of[i] = slot;
    }
    let slot = out.nodes.len();
    out.nodes.push(Node::EMPTY);
    let mut node = Node::EMPTY;
    // Children small enough are built here, the others as tasks into subtrees of their own.
    let mut tasks: Vec<(usize, &mut [PrimRef], usize, SetInfo, Split)> = Vec::new();
    let mut rest = refs;
    let mut consumed = 0;
    for (i, c) in children[..count].iter().enumerate() {
        let (slice, tail) = std::mem::take(&mut rest).split_at_mut(c.end - consumed);
        rest = tail;
        consumed = c.end;
        let child = match c.split {
            None => {
                out.leaves
                    .push(((offset + c.start) as u32, (c.end - c.start) as u32));
                LEAF | (out.leaves.len() as u32 - 1)
            }
            Some(split) if slice.len() >= PARALLEL_MIN => {
                tasks.push((slot_of[i], slice, offset + c.start, c.info, split));
                continue;
            }
            Some(split) => build_node(slice, offset + c.start, c.info, split, out, depth + 1),
        };
        node.set_child(slot_of[i], c.info.bounds(), child);
    }
    let subtrees: Vec<(usize, Subtree)> = tasks
        .into_par_iter()
        .map(|(i, slice, start, info, split)| {
            let mut sub = Subtree::default();
            build_node(slice, start, info, split, &mut sub, 1);
            (i, sub)
        })
        .collect();
    for (child_slot, sub) in subtrees {
        let root = out.append(sub, depth);
        node.set_child(
            child_slot,
            children[by_size[child_slot]].info.bounds(),
            root,
        );
    }
    out.nodes[slot] = node;
    slot as u32
}

/// The tree the build produces: nodes whose leaf children name entries of `leaves`, each a
/// range of `order`, the primitive ids in their final order.
pub(super) struct Tree {
    pub(super) nodes: Vec<Node>,
    pub(super) leaves: Vec<(u32, u32)>,
    pub(super) order: Vec<PrimRef>,
    /// Nodes on the longest root-to-leaf path.
    pub(super) depth: usize,
}

/// Builds the tree over primitives whose boxes are `bounds`: ids 0..triangles name
/// triangles, the rest spheres. At least one primitive.
pub(super) fn build_tree(bounds: &[Aabb], triangles: usize) -> Tree {
    let mut refs: Vec<PrimRef> = bounds
        .par_iter()
        .enumerate()
        .map(|(i, b)| PrimRef::new(*b, i as u32, i >= triangles))
        .collect();
    let info = SetInfo::of(&refs);
    let mut tree = Subtree::default();
    match choose_split(&refs, &info) {
        Some(split) => {
            build_node(&mut refs, 0, info, split, &mut tree, 1);
        }
        None => {
            // A single leaf still hangs below a node: traversal starts at a node.
            let mut node = Node::EMPTY;
            node.set_child(0, info.bounds(), LEAF);
            tree.nodes.push(node);
            tree.leaves.push((0, refs.len() as u32));
            tree.depth = 1;
        }
    }
    Tree {
        nodes: tree.nodes,
        leaves: tree.leaves,
        order: refs,
        depth: tree.depth,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;
    use glam::Vec3A;

    /// Boxes of small random triangles in a unit cube, then `coincident` boxes of different
    /// sizes around one centre (distinct primitives whose centroids cannot be binned apart).
    fn boxes(n: usize, coincident: usize, seed: u64) -> Vec<Aabb> {
        let mut rng = Rng::new(seed, 0, 0);
        let mut point = || Vec3A::new(rng.uniform(), rng.uniform(), rng.uniform());
        let mut out: Vec<Aabb> = (0..n)
            .map(|_| {
                let p = point();
                let (a, b) = (p + (point() - 0.5) * 0.02, p + (point() - 0.5) * 0.02);
                Aabb {
                    lo: p.min(a).min(b),
                    hi: p.max(a).max(b),
                }
            })
            .collect();
        let centre = Vec3A::splat(0.5);
        out.extend((0..coincident).map(|i| {
            let r = 0.001 * (1 + i) as f32;
            Aabb {
                lo: centre - r,
                hi: centre + r,
            }
        }));
        out
    }

    fn contains(outer: (Vec3A, Vec3A), inner: &Aabb) -> bool {
        outer.0.cmple(inner.lo).all() && inner.hi.cmple(outer.1).all()
    }

    /// Every primitive sits in exactly one leaf, inside the box its parent stores for that
    /// leaf, and no leaf holds more than MAX_LEAF: also for 300 distinct boxes sharing one
    /// centroid, and with spheres among the triangles.
    #[test]
    fn leaves_partition_the_primitives_inside_their_boxes() {
        let bounds = boxes(5000, 300, 3);
        let triangles = 4000;
        let tree = build_tree(&bounds, triangles);
        let mut seen = vec![0u32; bounds.len()];
        let mut spheres_seen = 0;
        for node in &tree.nodes {
            for i in 0..WIDTH {
                if node.valid >> i & 1 == 0 || node.child[i] & LEAF == 0 {
                    continue;
                }
                let child_box = (
                    Vec3A::new(node.min[0][i], node.min[1][i], node.min[2][i]),
                    Vec3A::new(node.max[0][i], node.max[1][i], node.max[2][i]),
                );
                let (start, count) = tree.leaves[(node.child[i] & !LEAF) as usize];
                assert!(count as usize <= MAX_LEAF, "a leaf of {count}");
                for r in &tree.order[start as usize..(start + count) as usize] {
                    assert!(contains(child_box, &bounds[r.id as usize]), "prim {}", r.id);
                    assert_eq!(r.sphere == 1, r.id as usize >= triangles);
                    seen[r.id as usize] += 1;
                    spheres_seen += r.sphere;
                }
            }
        }
        assert!(
            seen.iter().all(|&k| k == 1),
            "a primitive in no leaf or in two"
        );
        assert_eq!(spheres_seen as usize, bounds.len() - triangles);
        assert!(tree.depth >= 3, "depth {}", tree.depth);
    }

    /// The same tree, node for node and bit for bit, on one thread and on three: the
    /// parallel binning reduces by min, max and integer sums, and subtrees built as tasks
    /// are appended in child order. Enough primitives for both parallel paths.
    #[test]
    fn the_tree_is_the_same_on_any_number_of_threads() {
        // The root's eight children are each above PARALLEL_MIN: built as tasks.
        let bounds = boxes(20 * PARALLEL_MIN, 0, 5);
        let build = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| build_tree(&bounds, bounds.len()))
        };
        let (one, three) = (build(1), build(3));
        assert_eq!(one.nodes.len(), three.nodes.len());
        for (a, b) in one.nodes.iter().zip(&three.nodes) {
            let bits = |n: &Node| {
                let boxes: Vec<u32> = n
                    .min
                    .iter()
                    .chain(&n.max)
                    .flatten()
                    .map(|x| x.to_bits())
                    .collect();
                (boxes, n.child, n.valid)
            };
            assert_eq!(bits(a), bits(b));
        }
        assert_eq!(one.leaves, three.leaves);
        let ids = |t: &Tree| t.order.iter().map(|r| r.id).collect::<Vec<_>>();
        assert_eq!(ids(&one), ids(&three));
        assert!(one.nodes.len() > 1000, "{} nodes", one.nodes.len());
    }
}
