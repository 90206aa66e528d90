//! The eight-wide hierarchy, as Embree keeps meshes' trees on CPUs with AVX: the binary SAH
//! tree of `bvh.rs` collapsed so that each node has up to eight children, whose boxes one
//! slab test checks in eight lanes ([`Lanes8`]: one AVX register, or two SSE steps at the
//! baseline).
//!
//! - **Collapse.** As for the four-wide tree (`wide.rs`): the inner child with the largest
//!   surface area is opened until there are eight children or only leaves. A binary leaf (up
//!   to eight items) is one leaf slot; the rare larger one (items whose centres coincide) a
//!   node of leaves of eight. Leaves are numbered in the order they are made, and a leaf slot
//!   holds its number, so the caller keeps each leaf's items in a block of their own, found
//!   with no lookup (a mesh's [`Triangles8`](crate::tracer::geometry::triangle::Triangles8)).
//! - **Traversal.** A node's hit children are found as a bit mask. Most nodes a ray enters
//!   have one or two hit children (Embree's observation, which its `BVH8` traversal is built
//!   on): one is visited at once, two in order of entry, and only more than two are sorted
//!   (by insertion, nearest on top of the stack). Waiting children beyond the closest hit are
//!   skipped when popped.
//! - **Exactness.** Boxes are padded by their items' test's rounding bound, and the closest
//!   hit breaks ties by index ([`Closest`]), so the hit found is the one testing every item
//!   finds, whatever the level, order or width (`tests/isa.rs`).
//!
//! Invariant: unused child slots are `EMPTY` with inverted boxes (lower +∞, upper −∞), which
//! the slab test never enters.

use std::ops::Range;

use arrayvec::ArrayVec;

use crate::tracer::accel::bvh::Bvh;
use crate::tracer::accel::wide::{Slab, Waiting, next_waiting, reach};
use crate::tracer::geometry::hit::Closest;
use crate::tracer::math::lanes::Lanes8;
use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::{Real, Vec3};

/// Children per node.
const WIDTH: usize = 8;
/// Items per leaf at most (what one eight-lane leaf test holds).
const LEAF_ITEMS: usize = 8;
/// At most 64 levels (the binary build's bound), each leaving at most seven siblings waiting.
const STACK: usize = (WIDTH - 1) * 64 + 1;
/// A child slot with this bit set holds a leaf's number.
const LEAF: u32 = 1 << 31;
const EMPTY: u32 = u32::MAX;

/// An inner node: eight child boxes as structure of arrays, 32-byte aligned for AVX loads.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
struct Node {
    /// `corner[0]` = lower corners, `corner[1]` = upper; then axis, then child.
    corner: [[[Real; WIDTH]; 3]; 2],
    children: [u32; WIDTH],
}

const EMPTY_NODE: Node = Node {
    corner: [[[Real::INFINITY; WIDTH]; 3], [[Real::NEG_INFINITY; WIDTH]; 3]],
    children: [EMPTY; WIDTH],
};

/// The eight-wide hierarchy over a list of items (a mesh's triangles).
#[derive(Clone, Debug)]
pub struct Bvh8 {
    nodes: Vec<Node>,
}

impl Bvh8 {
    /// Collapses `binary` (built with leaves of at most eight) into an eight-wide hierarchy;
    /// returns it with each leaf's range of items, by leaf number.
    ///
    /// ```
    /// use raypool::tracer::accel::{bvh::Bvh, isa::Isa, wide8::Bvh8};
    /// use raypool::tracer::math::lanes::{Lanes8, WithLanes8};
    /// use raypool::tracer::geometry::{hit::Closest, sphere::Sphere};
    /// use raypool::tracer::math::{ray::Ray, real::{Real, Vec3}};
    /// let mut balls: Vec<Sphere> = (0..100)
    ///     .map(|k| Sphere { center: Vec3::new(k as Real * 3.0, 0.0, -10.0), radius: 1.0, material: 0 })
    ///     .collect();
    /// let (tree, leaves) = Bvh8::collapse(&Bvh::build_with_leaves(&mut balls, 4));
    /// struct Search<'a>(&'a Bvh8, &'a [std::ops::Range<usize>], &'a [Sphere], Ray);
    /// impl WithLanes8 for Search<'_> {
    ///     type Output = Option<(usize, Real)>;
    ///     fn run<L: Lanes8>(self, lanes: L) -> Self::Output {
    ///         let mut closest = Closest::none(Real::INFINITY);
    ///         self.0.traverse(lanes, &self.3, &mut closest, |leaf, closest| {
    ///             for i in self.1[leaf].clone() {
    ///                 if let Some(t) = self.2[i].intersect(&self.3, closest.bound()) {
    ///                     closest.offer(t, i as u32);
    ///                 }
    ///             }
    ///         });
    ///         closest.found()
    ///     }
    /// }
    /// let along_x = Ray::new(Vec3::new(-5.0, 0.0, -10.0), Vec3::X);
    /// let (index, t) = Isa::best().run_lanes(Search(&tree, &leaves, &balls, along_x)).unwrap();
    /// assert_eq!((balls[index].center.x, t), (0.0, 4.0), "the first ball, 4 units away");
    /// ```
    pub fn collapse(binary: &Bvh) -> (Bvh8, Vec<Range<usize>>) {
        let mut tree = Bvh8 { nodes: Vec::new() };
        let mut leaves = Vec::new();
        if binary.node_count() > 0 {
            let root = tree.child(binary, 0, &mut leaves);
            if root & LEAF != 0 {
                // A single leaf still needs a node above it.
                tree.nodes.push(EMPTY_NODE);
                tree.set_slot(0, 0, binary.bounds(0), root);
            }
        }
        (tree, leaves)
    }

    /// The child slot for binary node `at`: a leaf's number, or a collapsed node's index.
    fn child(&mut self, binary: &Bvh, at: usize, leaves: &mut Vec<Range<usize>>) -> u32 {
        if let Some(range) = binary.leaf(at) {
            let mut leaf = |range: Range<usize>| {
                leaves.push(range);
                LEAF | (leaves.len() - 1) as u32
            };
            if range.len() <= LEAF_ITEMS {
                return leaf(range);
            }
            // Items the build could not split (coincident centres): a node of leaves of eight.
            assert!(range.len() <= LEAF_ITEMS * WIDTH, "a binary leaf of {} items", range.len());
            let node = self.push_node();
            for (slot, start) in range.clone().step_by(LEAF_ITEMS).enumerate() {
                let slot_leaf = leaf(start..(start + LEAF_ITEMS).min(range.end));
                self.set_slot(node, slot, binary.bounds(at), slot_leaf);
            }
            return node as u32;
        }
        let open = binary.collapsed_children(at, WIDTH);
        let node = self.push_node();
        for (slot, &b) in open.iter().enumerate() {
            let child = self.child(binary, b, leaves);
            self.set_slot(node, slot, binary.bounds(b), child);
        }
        node as u32
    }

    fn push_node(&mut self) -> usize {
        self.nodes.push(EMPTY_NODE);
        self.nodes.len() - 1
    }

    fn set_slot(&mut self, node: usize, slot: usize, (lower, upper): (Vec3, Vec3), child: u32) {
        for axis in 0..3 {
            self.nodes[node].corner[0][axis][slot] = lower[axis];
            self.nodes[node].corner[1][axis][slot] = upper[axis];
        }
        self.nodes[node].children[slot] = child;
    }

    /// Visits, nearest first, every leaf whose box the ray enters before `closest.t`, handing
    /// `leaf` the leaf's number; `leaf` offers its hits to `closest`, which prunes the rest.
    #[inline(always)]
    pub fn traverse<L: Lanes8>(
        &self,
        lanes: L,
        ray: &Ray,
        closest: &mut Closest,
        mut leaf: impl FnMut(usize, &mut Closest),
    ) {
        if self.nodes.is_empty() {
            return;
        }
        let slab = NodeSlab::new(lanes, ray);
        let mut waiting: ArrayVec<Waiting, STACK> = ArrayVec::new();
        let mut child = 0;
        loop {
            if child & LEAF != 0 {
                leaf((child & !LEAF) as usize, closest);
            } else {
                let node = &self.nodes[child as usize];
                let (near, mut mask) = slab.enter(lanes, node, reach(closest));
                if mask != 0 {
                    let first = mask.trailing_zeros() as usize;
                    mask &= mask - 1;
                    if mask == 0 {
                        child = node.children[first];
                        continue;
                    }
                    let second = mask.trailing_zeros() as usize;
                    mask &= mask - 1;
                    let (near_one, far_one) =
                        if near[second] < near[first] { (second, first) } else { (first, second) };
                    if mask == 0 {
                        waiting.push(Waiting::new(node.children[far_one], near[far_one]));
                        child = node.children[near_one];
                        continue;
                    }
                    child = sort_onto(&mut waiting, node, &near, [near_one, far_one], mask);
                    continue;
                }
            }
            let Some(next) = next_waiting(&mut waiting, reach(closest)) else { return };
            child = next;
        }
    }
}

/// Three or more hit children: pushes all but the nearest onto `waiting`, nearest on top, and
/// returns the nearest. `pair` holds the first two (nearer first), `mask` the rest.
#[inline(always)]
fn sort_onto(
    waiting: &mut ArrayVec<Waiting, STACK>,
    node: &Node,
    near: &[Real; WIDTH],
    pair: [usize; 2],
    mut mask: u32,
) -> u32 {
    // Entries sorted farthest first: an insertion sort of at most eight.
    let mut order: ArrayVec<(Real, u32), WIDTH> = ArrayVec::new();
    order.push((near[pair[1]], node.children[pair[1]]));
    order.push((near[pair[0]], node.children[pair[0]]));
    while mask != 0 {
        let lane = mask.trailing_zeros() as usize;
        mask &= mask - 1;
        let entry = (near[lane], node.children[lane]);
        let mut j = order.len();
        order.push(entry);
        while j > 0 && order[j - 1].0 < entry.0 {
            order[j] = order[j - 1];
            j -= 1;
        }
        order[j] = entry;
    }
    let (_, nearest) = order.pop().expect("three children");
    for &(entry, child) in &order {
        waiting.push(Waiting::new(child, entry));
    }
    nearest
}

/// A ray prepared for eight-lane slab tests ([`Slab`], with its values in every lane).
struct NodeSlab<V> {
    origin: [V; 3],
    inv_dir: [V; 3],
    inv_exit: [V; 3],
    near_corner: [usize; 3],
}

impl<V: Copy> NodeSlab<V> {
    #[inline(always)]
    fn new<L: Lanes8<V = V>>(lanes: L, ray: &Ray) -> NodeSlab<V> {
        let slab = Slab::new(ray);
        NodeSlab {
            origin: slab.origin.map(|x| lanes.splat(x)),
            inv_dir: slab.inv_dir.map(|x| lanes.splat(x)),
            inv_exit: slab.inv_exit.map(|x| lanes.splat(x)),
            near_corner: slab.near_corner,
        }
    }

    /// Per child, the distance at which the ray enters its box, and a mask with bit `k` set
    /// if it enters child `k`'s box before `t_max`: the four-wide tree's test
    /// (`wide.rs`'s `Slab::enter`), each step on all eight lanes.
    #[inline(always)]
    fn enter<L: Lanes8<V = V>>(&self, lanes: L, node: &Node, t_max: Real) -> ([Real; WIDTH], u32) {
        let mut near = lanes.splat(0.0);
        let mut far = lanes.splat(t_max);
        for axis in 0..3 {
            let n = self.near_corner[axis];
            let lower = lanes.load(&node.corner[n][axis]);
            let upper = lanes.load(&node.corner[1 - n][axis]);
            let t_in = lanes.mul(lanes.sub(lower, self.origin[axis]), self.inv_dir[axis]);
            let t_out = lanes.mul(lanes.sub(upper, self.origin[axis]), self.inv_exit[axis]);
            near = lanes.max(t_in, near);
            far = lanes.min(t_out, far);
        }
        (lanes.store(near), lanes.le_mask(near, far))
    }
}
