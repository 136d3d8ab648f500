//! The BVH build: top-down binned SAH, straight to 8-wide nodes, in parallel.
//!
//! Each set of primitives is split where the surface area heuristic (MacDonald and Booth
//! 1990) predicts the cheapest traversal of a random ray that meets the set's box:
//!
//! ```text
//! cost(split) = C_TRAVERSE + (A_L / A) cost(L) + (A_R / A) cost(R)
//! cost(leaf)  = C_PACKET ceil(triangles / 4) + C_SPHERE spheres
//! ```
//!
//! where A, A_L and A_R are the surface areas of the set's box and of its two halves' boxes
//! (the ratio is the probability that a ray meeting the set's box also meets the half's) and
//! the children are priced as leaves (the greedy top-down SAH). A leaf's triangles are
//! tested four at a time (`TrianglePacket`), so its cost counts packets, not triangles. A
//! set becomes a leaf when it holds at most [`MAX_LEAF`] primitives and no split is cheaper.
//!
//! Candidate splits are the planes between [`BINS`] equal bins of the centroids' extent along
//! each axis (Wald 2007, "On fast construction of SAH-based bounding volume hierarchies"):
//! one pass bins the primitives, one sweep per axis prices every plane. A set whose
//! centroids all coincide cannot be binned and is halved by count.
//!
//! An 8-wide node is formed as Embree's BVH8 builder forms one: starting from its set, the
//! child with the largest surface area that the SAH would split is split, until there are
//! eight children or no child should be split. Large children are built as parallel tasks
//! on the current rayon pool, each into a subtree of its own, appended in child order: the
//! tree, its memory layout and so every answer are the same on any number of threads.

use super::wide::{Node, LEAF, WIDTH};
use glam::Vec3A;
use rayon::prelude::*;

/// Centroid bins per axis.
const BINS: usize = 32;

/// Most primitives in one leaf: two triangle packets. The SAH decides below that.
const MAX_LEAF: usize = 8;

/// SAH cost of descending one binary level, relative to one packet test. A wide node's slab
/// test costs about one packet test and resolves about three binary levels (log2 8), which
/// would give 1/3; rays that start inside an enclosure (every ray of an interior scene)
/// enter every box around their origin whatever its area, which the area ratio does not
/// see and which favours smaller leaves. 0.2 is what the shipped scenes and the large mesh
/// measured best (docs/performance.md).
const C_TRAVERSE: f32 = 0.2;

/// SAH cost of testing one packet of up to four triangles.
const C_PACKET: f32 = 1.0;

/// SAH cost of testing one sphere.
const C_SPHERE: f32 = 1.0;

/// Sets at least this large are binned in parallel chunks and built as parallel tasks.
const PARALLEL_MIN: usize = 16 * 1024;

/// A primitive during the build: its box and its global id (triangles first, then spheres).
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
pub(super) struct PrimRef {
    lo: [f32; 3],
    pub(super) id: u32,
    hi: [f32; 3],
    /// 1 for a sphere, 0 for a triangle.
    pub(super) sphere: u32,
}

impl PrimRef {
    /// A reference to primitive `id` with box `bounds`; `sphere` when the id names a sphere.
    pub(super) fn new(bounds: Aabb, id: u32, sphere: bool) -> Self {
        PrimRef {
            lo: bounds.lo.to_array(),
            id,
            hi: bounds.hi.to_array(),
            sphere: sphere as u32,
        }
    }

    #[inline(always)]
    fn bounds(&self) -> Aabb {
        Aabb {
            lo: Vec3A::from_array(self.lo),
            hi: Vec3A::from_array(self.hi),
        }
    }

    /// Twice the centroid (lo + hi): binning only compares centroids, so the halving is left out.
    #[inline(always)]
    fn centroid2(&self) -> Vec3A {
        Vec3A::from_array(self.lo) + Vec3A::from_array(self.hi)
    }
}

/// An axis-aligned box; the empty box has lo = +inf and hi = -inf.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Aabb {
    pub(super) lo: Vec3A,
    pub(super) hi: Vec3A,
}

impl Aabb {
    pub(super) const EMPTY: Aabb = Aabb {
        lo: Vec3A::INFINITY,
        hi: Vec3A::NEG_INFINITY,
    };

    #[inline(always)]
    fn grow(&mut self, b: &Aabb) {
        self.lo = self.lo.min(b.lo);
        self.hi = self.hi.max(b.hi);
    }

    #[inline(always)]
    fn grow_point(&mut self, p: Vec3A) {
        self.lo = self.lo.min(p);
        self.hi = self.hi.max(p);
    }

    /// Half the surface area (the SAH only uses ratios); 0 for the empty box.
    #[inline(always)]
    fn half_area(&self) -> f32 {
        let d = (self.hi - self.lo).max(Vec3A::ZERO);
        d.x * d.y + d.y * d.z + d.z * d.x
    }
}

/// A set of primitives: its box, its centroids' box (of twice the centroids) and counts.
#[derive(Clone, Copy, Debug)]
struct SetInfo {
    bounds: Aabb,
    centroids: Aabb,
    triangles: u32,
    spheres: u32,
}

impl SetInfo {
    const EMPTY: SetInfo = SetInfo {
        bounds: Aabb::EMPTY,
        centroids: Aabb::EMPTY,
        triangles: 0,
        spheres: 0,
    };

    #[inline(always)]
    fn add(&mut self, r: &PrimRef) {
        self.bounds.grow(&r.bounds());
        self.centroids.grow_point(r.centroid2());
        if r.sphere != 0 {
            self.spheres += 1;
        } else {
            self.triangles += 1;
        }
    }

    fn merge(mut self, o: &SetInfo) -> SetInfo {
        self.bounds.grow(&o.bounds);
        self.centroids.grow(&o.centroids);
        self.triangles += o.triangles;
        self.spheres += o.spheres;
        self
    }

    fn count(&self) -> usize {
        (self.triangles + self.spheres) as usize
    }

    /// The SAH cost of testing this set as one leaf.
    fn leaf_cost(&self) -> f32 {
        leaf_cost(self.triangles, self.spheres)
    }

    /// Over a slice of references, in parallel chunks for large slices (min, max and counts
    /// do not depend on the order of reduction).
    fn of(refs: &[PrimRef]) -> SetInfo {
        let serial = |refs: &[PrimRef]| {
            let mut info = SetInfo::EMPTY;
            refs.iter().for_each(|r| info.add(r));
            info
        };
        if refs.len() < PARALLEL_MIN {
            serial(refs)
        } else {
            refs.par_chunks(PARALLEL_MIN / 2)
                .map(serial)
                .reduce(|| SetInfo::EMPTY, |a, b| a.merge(&b))
        }
    }
}

/// How a set is to be divided.
#[derive(Clone, Copy, Debug)]
enum Split {
    /// Primitives whose centroid falls in a bin below `bin` of `bins` along `axis` go left.
    Plane {
        axis: usize,
        bin: usize,
        bins: usize,
    },
    /// All centroids coincide: the first half by count goes left.
    Halves,
}

/// Binning of a set's centroids along each axis to `count` bins.
#[derive(Clone, Copy)]
struct Binner {
    origin: Vec3A,
    scale: Vec3A,
    count: usize,
}

impl Binner {
    fn new(centroids: &Aabb, count: usize) -> Self {
        let extent = centroids.hi - centroids.lo;
        // Just under `count` per extent, so the largest centroid lands in the last bin.
        let k = count as f32 * (1.0 - 1e-5);
        let scale = Vec3A::select(extent.cmpgt(Vec3A::ZERO), k / extent, Vec3A::ZERO);
        Binner {
            origin: centroids.lo,
            scale,
            count,
        }
    }

    #[inline(always)]
    fn bins(&self, r: &PrimRef) -> [usize; 3] {
        let b = ((r.centroid2() - self.origin) * self.scale).to_array();
        b.map(|x| (x as usize).min(self.count - 1))
    }
}

/// What the SAH needs of a bin: the box of its primitives and their counts.
#[derive(Clone, Copy, Debug)]
struct Bin {
    bounds: Aabb,
    triangles: u32,
    spheres: u32,
}

impl Bin {
    const EMPTY: Bin = Bin {
        bounds: Aabb::EMPTY,
        triangles: 0,
        spheres: 0,
    };

    #[inline(always)]
    fn add(&mut self, r: &PrimRef) {
        self.bounds.grow(&r.bounds());
        self.triangles += 1 - r.sphere;
        self.spheres += r.sphere;
    }

    #[inline(always)]
    fn merge(&mut self, o: &Bin) {
        self.bounds.grow(&o.bounds);
        self.triangles += o.triangles;
        self.spheres += o.spheres;
    }
}

/// `N` bins on each axis.
type Bins<const N: usize> = [[Bin; N]; 3];

/// Each primitive added to its bin on each axis: serially, or for large sets in parallel
/// chunks merged after (the result does not depend on the order of merging).
fn bin_refs<const N: usize>(binner: &Binner, refs: &[PrimRef]) -> Bins<N> {
    let serial = |refs: &[PrimRef]| {
        let mut bins = [[Bin::EMPTY; N]; 3];
        for r in refs {
            let b = binner.bins(r);
            for axis in 0..3 {
                bins[axis][b[axis]].add(r);
            }
        }
        bins
    };
    if refs.len() < PARALLEL_MIN {
        return serial(refs);
    }
    refs.par_chunks(PARALLEL_MIN / 2).map(serial).reduce(
        || [[Bin::EMPTY; N]; 3],
        |mut a, b| {
            for axis in 0..3 {
                for i in 0..N {
                    a[axis][i].merge(&b[axis][i]);
                }
            }
            a
        },
    )
}

/// The SAH cost of a leaf of `triangles` and `spheres`.
#[inline(always)]
fn leaf_cost(triangles: u32, spheres: u32) -> f32 {
    C_PACKET * triangles.div_ceil(4) as f32 + C_SPHERE * spheres as f32
}

/// The SAH's choice for a set: `None` makes it a leaf.
fn choose_split(refs: &[PrimRef], info: &SetInfo) -> Option<Split> {
    let n = info.count();
    if n <= 1 {
        return None;
    }
    let extent = info.centroids.hi - info.centroids.lo;
    if extent.max_element() <= 0.0 {
        // Coincident centroids: nothing to bin; halve by count if the set is too big.
        return (n > MAX_LEAF).then_some(Split::Halves);
    }
    // Fewer bins for small sets: sweeping 32 bins costs more than it finds among a few.
    let (cost, split) = match n {
        0..=8 => best_plane::<8>(refs, info),
        9..=16 => best_plane::<16>(refs, info),
        _ => best_plane::<BINS>(refs, info),
    }?;
    let area = info.bounds.half_area();
    let split_cost = C_TRAVERSE + if area > 0.0 { cost / area } else { 0.0 };
    if n <= MAX_LEAF && split_cost >= info.leaf_cost() {
        return None;
    }
    Some(split)
}

/// The cheapest plane between `N` bins along any axis, with its SAH term A_L cost(L) +
/// A_R cost(R); `None` if no plane has primitives on both sides.
fn best_plane<const N: usize>(refs: &[PrimRef], info: &SetInfo) -> Option<(f32, Split)> {
    let binner = Binner::new(&info.centroids, N);
    let bins = bin_refs::<N>(&binner, refs);
    let extent = info.centroids.hi - info.centroids.lo;
    let mut best: Option<(f32, Split)> = None;
    for (axis, bins) in bins.iter().enumerate() {
        if extent[axis] <= 0.0 {
            continue;
        }
        // right_cost[i], right_count[i]: bins i.. as one side, swept from the right.
        let (mut right_cost, mut right_count) = ([0.0f32; N], [0u32; N]);
        let mut right = Bin::EMPTY;
        for i in (1..N).rev() {
            right.merge(&bins[i]);
            right_cost[i] = right.bounds.half_area() * leaf_cost(right.triangles, right.spheres);
            right_count[i] = right.triangles + right.spheres;
        }
        let mut left = Bin::EMPTY;
        for i in 1..N {
            left.merge(&bins[i - 1]);
            if left.triangles + left.spheres == 0 || right_count[i] == 0 {
                continue;
            }
            let cost =
                left.bounds.half_area() * leaf_cost(left.triangles, left.spheres) + right_cost[i];
            if best.is_none_or(|(c, _)| cost < c) {
                let split = Split::Plane {
                    axis,
                    bin: i,
                    bins: N,
                };
                best = Some((cost, split));
            }
        }
    }
    best
}

/// Divides `refs` as `split` says; returns the left count and both halves' sets.
fn partition(refs: &mut [PrimRef], info: &SetInfo, split: &Split) -> (usize, SetInfo, SetInfo) {
    match *split {
        Split::Plane { axis, bin, bins } => {
            let binner = Binner::new(&info.centroids, bins);
            let goes_left = |r: &PrimRef| binner.bins(r)[axis] < bin;
            // Two-finger partition, deterministic and in place; each primitive is added to
            // its side's set as the fingers pass it.
            let (mut left, mut right) = (SetInfo::EMPTY, SetInfo::EMPTY);
            let (mut i, mut j) = (0, refs.len());
            loop {
                while i < j && goes_left(&refs[i]) {
                    left.add(&refs[i]);
                    i += 1;
                }
                while i < j && !goes_left(&refs[j - 1]) {
                    right.add(&refs[j - 1]);
                    j -= 1;
                }
                if i >= j {
                    break;
                }
                refs.swap(i, j - 1);
                left.add(&refs[i]);
                right.add(&refs[j - 1]);
                i += 1;
                j -= 1;
            }
            (i, left, right)
        }
        Split::Halves => {
            let mid = refs.len() / 2;
            let (l, r) = refs.split_at(mid);
            (mid, SetInfo::of(l), SetInfo::of(r))
        }
    }
}

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
            .filter(|&i| children[i].split.is_some())
            .max_by(|&a, &b| {
                let area = |i: usize| children[i].info.bounds.half_area();
                area(a).total_cmp(&area(b))
            });
        let Some(i) = widest else { break };
        let c = children[i];
        let Some(split) = c.split else { break };
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
                tasks.push((i, slice, offset + c.start, c.info, split));
                continue;
            }
            Some(split) => build_node(slice, offset + c.start, c.info, split, out, depth + 1),
        };
        node.set_child(i, &c.info.bounds, child);
    }
    let subtrees: Vec<(usize, Subtree)> = tasks
        .into_par_iter()
        .map(|(i, slice, start, info, split)| {
            let mut sub = Subtree::default();
            build_node(slice, start, info, split, &mut sub, 1);
            (i, sub)
        })
        .collect();
    for (i, sub) in subtrees {
        let root = out.append(sub, depth);
        node.set_child(i, &children[i].info.bounds, root);
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
            node.set_child(0, &info.bounds, LEAF);
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
