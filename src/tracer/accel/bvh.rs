//! A bounding volume hierarchy over the spheres: test only the boxes and spheres along a
//! ray's path instead of all ~480 of the book's final scene (`results/perf.md`).
//!
//! - **Build**: binned surface-area heuristic (SAH). At each node the sphere centres are
//!   sorted into 32 bins along each axis; the split between bins, on any axis, that minimises
//!   `area(left)·count(left) + area(right)·count(right)` wins, unless a leaf is cheaper.
//!   A ray's chance of hitting a box is roughly proportional to its surface area, so this
//!   minimises the expected number of sphere tests.
//! - **Layout**: nodes are flattened depth-first into one array; an interior node's left
//!   child is the next node, its right child is stored as an index. Spheres are reordered so
//!   every leaf covers a contiguous range of them.
//! - **Traversal**: a small stack; boxes tested with the ray's precomputed inverse direction
//!   (the slab test); the child on the side the ray comes from is visited first, and any box
//!   farther than the closest hit found so far is skipped.
//!
//! The hierarchy changes which spheres are tested, not which is closest: boxes are padded by
//! the sphere test's rounding bound, and of two spheres hit at exactly the same distance the
//! lower index wins, so it reports exactly what testing every sphere in order reports
//! (`tests/bvh.rs` compares whole images). The renderer traverses the four-wide tree that
//! `wide.rs` collapses from this one; the binary traversal stays for comparison.

use crate::tracer::geometry::hit::Closest;
use crate::tracer::math::aabb::{Aabb, Bounded};
use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::{Real, Vec3};

/// Leaves hold at most this many spheres when splitting stops paying off (or as many as the
/// build asks for, if more).
const MAX_LEAF: usize = 4;
/// The most items per leaf a build may ask for: a mesh's eight-lane leaf test.
const LARGEST_LEAF: usize = 8;
/// Below this depth nodes split at the median instead of by SAH, so that no scene can build
/// a tree deeper than `SAH_DEPTH + log2(spheres)`, which the traversal stack always holds.
const SAH_DEPTH: usize = 32;
/// Traversal stack entries: one per level at most.
const STACK: usize = 64;
const BINS: usize = 32;

/// Half the surface area of the box around `items` (each box padded as its shape pads it):
/// how likely a ray is to enter it. The scene uses it to find huge spheres.
pub(crate) fn half_area_around<T: Bounded>(items: &[T]) -> Real {
    items.iter().map(Bounded::bounds).fold(Aabb::EMPTY, Aabb::union).half_area()
}

/// One node of the flattened tree.
#[derive(Clone, Copy, Debug)]
struct Node {
    bounds: Aabb,
    /// Leaf: index of the first sphere. Interior: index of the right child.
    index: u32,
    /// Leaf: number of spheres (> 0). Interior: 0.
    count: u16,
    /// Interior: the split axis (0, 1, 2), for front-to-back order.
    axis: u8,
}

/// The hierarchy: nodes only; the spheres it indexes live in the [`Scene`](crate::tracer::scene::Scene).
#[derive(Clone, Debug)]
pub struct Bvh {
    nodes: Vec<Node>,
}

impl Bvh {
    /// Builds the hierarchy, reordering `spheres` (or any [`Bounded`] items: triangles,
    /// objects) so that each leaf's items are contiguous.
    pub fn build<T: Bounded>(spheres: &mut [T]) -> Bvh {
        Bvh::build_with_leaves(spheres, 1)
    }

    /// Builds the hierarchy with every group of at most `leaf` spheres (1 to 8) kept in one
    /// leaf: for the four-wide tree, whose leaves test four spheres in one go, a leaf of four
    /// costs about what a leaf of one does (and for a mesh's tree, eight triangles what one).
    pub fn build_with_leaves<T: Bounded>(spheres: &mut [T], leaf: usize) -> Bvh {
        assert!((1..=LARGEST_LEAF).contains(&leaf), "leaves of 1 to {LARGEST_LEAF} spheres");
        let mut nodes = Vec::with_capacity(2 * spheres.len() / leaf + 1);
        if !spheres.is_empty() {
            build_node(spheres, 0, 0, leaf, &mut nodes);
        }
        Bvh { nodes }
    }

    /// Number of nodes (for tests and statistics).
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Levels from the root to the deepest leaf (1 for a single leaf; 0 when empty).
    pub fn depth(&self) -> usize {
        fn below(nodes: &[Node], at: usize) -> usize {
            match nodes[at].count {
                0 => 1 + below(nodes, at + 1).max(below(nodes, nodes[at].index as usize)),
                _ => 1,
            }
        }
        if self.nodes.is_empty() { 0 } else { below(&self.nodes, 0) }
    }

    /// Spheres of node `at` if it is a leaf (a range of the array the tree was built over).
    pub(crate) fn leaf(&self, at: usize) -> Option<std::ops::Range<usize>> {
        let n = &self.nodes[at];
        (n.count > 0).then(|| n.index as usize..n.index as usize + n.count as usize)
    }

    /// The two children of node `at` if it is an inner node.
    pub(crate) fn children(&self, at: usize) -> Option<(usize, usize)> {
        (self.nodes[at].count == 0).then(|| (at + 1, self.nodes[at].index as usize))
    }

    /// Lower and upper corners of node `at`'s box.
    pub(crate) fn bounds(&self, at: usize) -> (Vec3, Vec3) {
        (self.nodes[at].bounds.min, self.nodes[at].bounds.max)
    }

    /// Half the surface area of node `at`'s box (proportional to a ray's chance of hitting it).
    pub(crate) fn half_area(&self, at: usize) -> Real {
        self.nodes[at].bounds.half_area()
    }

    /// The nodes that become the children of a node `width` wide collapsed from inner node
    /// `at`: its two children, then, while there are fewer than `width`, the inner one of
    /// largest surface area (the likeliest to be entered) opened into its own two, until only
    /// leaves are left. The wide trees (`wide.rs`, `wide8.rs`) are collapsed so.
    pub(crate) fn collapsed_children(&self, at: usize, width: usize) -> Vec<usize> {
        let (left, right) = self.children(at).expect("an inner node");
        let mut open = vec![left, right];
        while open.len() < width {
            let widest = (0..open.len())
                .filter(|&k| self.leaf(open[k]).is_none())
                .max_by(|&a, &b| self.half_area(open[a]).total_cmp(&self.half_area(open[b])));
            let Some(k) = widest else { break };
            let (left, right) = self.children(open[k]).expect("an inner node");
            open[k] = left;
            open.push(right);
        }
        open
    }

    /// The closest sphere hit before `t_max`, as found by `test` (normally
    /// [`Sphere::intersect`](crate::tracer::geometry::sphere::Sphere::intersect)): `(index into spheres, t)`. Of two spheres hit at exactly the
    /// same distance, the one with the lower index is reported, as testing every sphere in
    /// order would.
    #[inline]
    pub fn hit<T>(
        &self,
        spheres: &[T],
        ray: &Ray,
        t_max: Real,
        test: impl Fn(&T, &Ray, Real) -> Option<Real>,
    ) -> Option<(usize, Real)> {
        let inv_dir = ray.dir.recip();
        let from_negative = [ray.dir.x < 0.0, ray.dir.y < 0.0, ray.dir.z < 0.0];
        let mut closest = Closest::none(t_max);
        let mut stack = [0u32; STACK];
        let mut depth = 0;
        let mut node = 0usize;
        loop {
            let n = &self.nodes[node];
            if n.bounds.hit(ray.origin, inv_dir, closest.bound()) {
                if n.count > 0 {
                    let first = n.index as usize;
                    for (k, sphere) in spheres[first..first + n.count as usize].iter().enumerate() {
                        if let Some(t) = test(sphere, ray, closest.bound()) {
                            closest.offer(t, (first + k) as u32);
                        }
                    }
                } else {
                    // Visit the child on the ray's near side first; remember the other.
                    let (near, far) = if from_negative[n.axis as usize] {
                        (n.index as usize, node + 1)
                    } else {
                        (node + 1, n.index as usize)
                    };
                    stack[depth] = far as u32;
                    depth += 1;
                    node = near;
                    continue;
                }
            }
            if depth == 0 {
                return closest.found();
            }
            depth -= 1;
            node = stack[depth] as usize;
        }
    }
}

/// Builds the subtree over `spheres` (which start at index `first` of the scene's array) at
/// `depth`, appending its nodes depth-first: the subtree's root is the first node appended.
fn build_node<T: Bounded>(spheres: &mut [T], first: usize, depth: usize, leaf: usize, nodes: &mut Vec<Node>) {
    let bounds = spheres.iter().map(Bounded::bounds).fold(Aabb::EMPTY, Aabb::union);
    let at = nodes.len();
    nodes.push(Node { bounds, index: first as u32, count: spheres.len() as u16, axis: 0 });
    let split = if depth < SAH_DEPTH { choose_split(spheres, &bounds, leaf) } else { median_split(spheres) };
    let Some((axis, mid)) = split else { return };
    nodes[at].axis = axis as u8;
    nodes[at].count = 0;
    let (left, right) = spheres.split_at_mut(mid);
    build_node(left, first, depth + 1, leaf, nodes);
    nodes[at].index = nodes.len() as u32;
    build_node(right, first + mid, depth + 1, leaf, nodes);
}

/// Halves `spheres` at the median centre along their widest axis; `None` for a leaf.
fn median_split<T: Bounded>(spheres: &mut [T]) -> Option<(usize, usize)> {
    if spheres.len() <= MAX_LEAF {
        return None;
    }
    let centroids = spheres.iter().fold(Aabb::EMPTY, |b, s| b.grow(s.centroid()));
    let axis = (centroids.max - centroids.min).max_position();
    let mid = spheres.len() / 2;
    spheres.select_nth_unstable_by(mid, |a, b| a.centroid()[axis].total_cmp(&b.centroid()[axis]));
    Some((axis, mid))
}

/// The best SAH split as `(axis, number of spheres on the left)`, having partitioned
/// `spheres` accordingly; `None` when a leaf is the better choice.
fn choose_split<T: Bounded>(spheres: &mut [T], bounds: &Aabb, leaf: usize) -> Option<(usize, usize)> {
    let n = spheres.len();
    if n <= 1 {
        return None;
    }
    let centroids = spheres.iter().fold(Aabb::EMPTY, |b, s| b.grow(s.centroid()));
    let extent = centroids.max - centroids.min;
    if extent.max_element() <= 0.0 {
        // Every centre coincides: nothing separates them. Fine unless the leaf is huge.
        return (n > MAX_LEAF * 4).then_some((0, n / 2));
    }
    let bin_of = |axis: usize, s: &T| {
        (((s.centroid()[axis] - centroids.min[axis]) / extent[axis] * BINS as Real) as usize).min(BINS - 1)
    };
    // (cost, axis, last bin on the left), over every axis the centres spread along.
    let mut best = (Real::INFINITY, 0, 0);
    for axis in (0..3).filter(|&axis| extent[axis] > 0.0) {
        let mut bins = [(Aabb::EMPTY, 0usize); BINS];
        for s in spheres.iter() {
            let b = &mut bins[bin_of(axis, s)];
            *b = (b.0.union(s.bounds()), b.1 + 1);
        }
        // Cost of splitting after bin i, from a right-to-left then a left-to-right sweep.
        let mut right_cost = [0.0; BINS];
        let (mut acc, mut count) = (Aabb::EMPTY, 0);
        for i in (1..BINS).rev() {
            acc = acc.union(bins[i].0);
            count += bins[i].1;
            right_cost[i - 1] = acc.half_area() * count as Real;
        }
        let (mut acc, mut count) = (Aabb::EMPTY, 0);
        for i in 0..BINS - 1 {
            acc = acc.union(bins[i].0);
            count += bins[i].1;
            let cost = acc.half_area() * count as Real + right_cost[i];
            if count > 0 && count < n && cost < best.0 {
                best = (cost, axis, i);
            }
        }
    }
    // Relative to testing all n spheres in a leaf, with a box test costing about one sphere.
    let split_cost = 1.0 + best.0 / bounds.half_area().max(Real::MIN_POSITIVE);
    // Up to `leaf` spheres stay together unless splitting more than halves the expected
    // work: in the four-wide tree, paper2's ground (radius 10⁴) grouped with three small
    // spheres made every ray that enters the ground's box test all four (slower,
    // `results/perf.md`).
    // Up to MAX_LEAF (or `leaf`, if more), they stay together unless splitting saves anything.
    let leaf_cost = if n <= leaf { 0.5 * n as Real } else { n as Real };
    if best.0.is_infinite() || (split_cost >= leaf_cost && n <= MAX_LEAF.max(leaf)) {
        return None;
    }
    let (_, axis, last) = best;
    let mid = partition(spheres, |s| bin_of(axis, s) <= last);
    Some((axis, mid))
}

/// Moves the spheres satisfying `left` to the front; returns how many there are.
fn partition<T>(spheres: &mut [T], left: impl Fn(&T) -> bool) -> usize {
    let mut mid = 0;
    for i in 0..spheres.len() {
        if left(&spheres[i]) {
            spheres.swap(i, mid);
            mid += 1;
        }
    }
    mid
}
