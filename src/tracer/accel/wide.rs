//! The four-wide hierarchy: the binary SAH tree of `bvh.rs`, collapsed so that each node has
//! up to four children whose boxes are stored as structure of arrays, and one pass of the
//! slab test checks all four at once.
//!
//! - **Collapse.** Starting from a binary node's two children, the inner child with the
//!   largest surface area is replaced by its own two children until there are four (or only
//!   leaves are left). A binary leaf (up to four spheres) becomes one leaf slot, which holds
//!   its spheres' range itself (so visiting it loads nothing before the spheres), and one
//!   [`Packet`] of them for the SIMD test; the rare larger leaf of spheres with one centre
//!   becomes a node of such leaves.
//! - **Traversal.** At a node the four child boxes are tested in the lanes of one register;
//!   the nearest child hit is visited at once and the others wait on a stack of
//!   `(child, entry distance)`, nearest on top, so the closest hit shrinks the search early.
//!   A waiting child whose entry distance is beyond the closest hit is skipped. A leaf's
//!   spheres are tested one by one ([`WideBvh::intersect_each`]: the default, because a
//!   scalar test stops at the first negative discriminant) or four at once in SIMD lanes
//!   ([`WideBvh::intersect`]: slower on `final` in most ablation runs, `results/perf.md`).
//! - **Exactness.** Ties go to the lower sphere index ([`Closest`]) and every box is padded
//!   by the sphere test's own rounding bound (`bvh.rs`), so the hierarchy finds exactly the
//!   hit that testing every sphere finds, whatever the order it visits them in.
//!
//! Invariant: unused child slots are `EMPTY` and have inverted boxes (lower corner +∞,
//! upper −∞), which the slab test never enters, so they are never pushed.

use std::ops::Range;

use arrayvec::ArrayVec;

use crate::tracer::accel::bvh::Bvh;
use crate::tracer::accel::packet::{LANES, Packet};
use crate::tracer::geometry::hit::Closest;
use crate::tracer::geometry::sphere::Sphere;
use crate::tracer::math::aabb::SLAB_ROUNDING;
use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::{Real, to_f32_at_most};

/// Children per node.
pub const WIDTH: usize = 4;

/// One value per child.
type Wide = [Real; WIDTH];

/// Stack entries the traversal needs at most: the tree is at most 64 levels deep (the binary
/// build bounds its depth, and collapsing only removes levels), and each level leaves at
/// most three siblings on the stack.
const STACK: usize = (WIDTH - 1) * 64 + 1;

/// A child slot holds an inner node's index, or with [`LEAF`] set a leaf's spheres (see
/// [`leaf_slot`]); an unused slot holds [`EMPTY`] (its box is inverted, so it is never
/// entered or pushed).
const LEAF: u32 = 1 << 31;
/// A leaf slot's low bits hold its sphere count less one (1 to [`LANES`] spheres).
const LEAF_COUNT_BITS: u32 = LANES.trailing_zeros();
const EMPTY: u32 = u32::MAX;
const ROOT: u32 = 0;

/// An inner node: four child boxes as structure of arrays.
#[derive(Clone, Copy, Debug)]
struct Node {
    /// `corner[0]` = lower corners, `corner[1]` = upper; then axis, then child.
    corner: [[Wide; 3]; 2],
    children: [u32; WIDTH],
}

/// The four-wide hierarchy over a scene's spheres.
#[derive(Clone, Debug)]
pub struct WideBvh {
    nodes: Vec<Node>,
    /// Every leaf's spheres as one packet (for [`WideBvh::intersect`] only).
    packets: Vec<Packet>,
    /// `packet_of[i - first]`: the packet whose first sphere is scene sphere `i`.
    packet_of: Vec<u32>,
    /// The scene index of the tree's first sphere.
    first: usize,
}

impl WideBvh {
    /// Collapses `binary`, built over `spheres` (which sit from index `first` of the scene's
    /// array on), into a four-wide hierarchy.
    ///
    /// ```
    /// use raypool::tracer::accel::{bvh::Bvh, wide::WideBvh};
    /// use raypool::tracer::geometry::{hit::Closest, sphere::Sphere};
    /// use raypool::tracer::math::{ray::Ray, real::{Real, Vec3}};
    /// let mut balls: Vec<Sphere> = (0..50)
    ///     .map(|k| Sphere { center: Vec3::new(k as Real * 3.0, 0.0, -10.0), radius: 1.0, material: 0 })
    ///     .collect();
    /// let wide = WideBvh::collapse(&Bvh::build(&mut balls), &balls, 0);
    /// let along_x = Ray::new(Vec3::new(-5.0, 0.0, -10.0), Vec3::X);
    /// let mut closest = Closest::none(Real::INFINITY);
    /// wide.intersect(&along_x, &mut closest);
    /// let (index, t) = closest.found().unwrap();
    /// assert_eq!((balls[index].center.x, t), (0.0, 4.0), "the first ball, 4 units away");
    /// ```
    pub fn collapse(binary: &Bvh, spheres: &[Sphere], first: usize) -> WideBvh {
        WideBvh::collapse_items(binary, spheres.len(), Some(spheres), first)
    }

    /// Collapses `binary`, built over `count` items of any kind (triangles, objects), into a
    /// four-wide hierarchy without sphere packets: searched with [`WideBvh::intersect_each`]
    /// or [`WideBvh::traverse`].
    pub fn collapse_plain(binary: &Bvh, count: usize) -> WideBvh {
        WideBvh::collapse_items(binary, count, None, 0)
    }

    fn collapse_items(binary: &Bvh, count: usize, spheres: Option<&[Sphere]>, first: usize) -> WideBvh {
        let packet_of = if spheres.is_some() { vec![0; count] } else { Vec::new() };
        let mut wide = WideBvh { nodes: Vec::new(), packets: Vec::new(), packet_of, first };
        if binary.node_count() > 0 {
            let root = wide.child(binary, spheres, first, 0);
            if root & LEAF != 0 {
                // A single leaf still needs a node above it.
                wide.nodes.push(Node { corner: EMPTY_CORNERS, children: [EMPTY; WIDTH] });
                wide.set_slot(0, 0, binary, 0, root);
            }
        }
        wide
    }

    /// The wide child for binary node `at`: a leaf slot for a leaf, a collapsed node otherwise.
    fn child(&mut self, binary: &Bvh, spheres: Option<&[Sphere]>, first: usize, at: usize) -> u32 {
        if let Some(range) = binary.leaf(at) {
            if range.len() <= LANES {
                return self.leaf(spheres, first, range);
            }
            // A leaf of coincident centres (the build cannot split them; at most 16): one
            // node whose children are packets of four, all with the leaf's box.
            assert!(range.len() <= LANES * WIDTH, "a binary leaf of {} spheres", range.len());
            let node = self.nodes.len();
            self.nodes.push(Node { corner: EMPTY_CORNERS, children: [EMPTY; WIDTH] });
            for (slot, start) in range.clone().step_by(LANES).enumerate() {
                let leaf = self.leaf(spheres, first, start..(start + LANES).min(range.end));
                self.set_slot(node, slot, binary, at, leaf);
            }
            return node as u32;
        }
        let open = binary.collapsed_children(at, WIDTH);
        let node = self.nodes.len();
        self.nodes.push(Node { corner: EMPTY_CORNERS, children: [EMPTY; WIDTH] });
        for (slot, &b) in open.iter().enumerate() {
            let child = self.child(binary, spheres, first, b);
            self.set_slot(node, slot, binary, b, child);
        }
        node as u32
    }

    /// The slot of a leaf of items `range` (1 to [`LANES`] of them), with its packet made
    /// when they are spheres.
    fn leaf(&mut self, spheres: Option<&[Sphere]>, first: usize, range: Range<usize>) -> u32 {
        if let Some(spheres) = spheres {
            self.packet_of[range.start] = self.packets.len() as u32;
            self.packets.push(Packet::new(&spheres[range.clone()], first + range.start));
        }
        leaf_slot(first + range.start, range.len())
    }

    fn set_slot(&mut self, node: usize, slot: usize, binary: &Bvh, b: usize, child: u32) {
        let (lower, upper) = binary.bounds(b);
        for axis in 0..3 {
            self.nodes[node].corner[0][axis][slot] = lower[axis];
            self.nodes[node].corner[1][axis][slot] = upper[axis];
        }
        self.nodes[node].children[slot] = child;
    }

    /// Offers every sphere the ray may hit before `closest.t` to `closest`, testing whole
    /// packets with [`Packet::intersect`] (a tree made by [`WideBvh::collapse`] only).
    #[inline]
    pub fn intersect(&self, ray: &Ray, closest: &mut Closest) {
        debug_assert!(!self.packet_of.is_empty(), "a tree of spheres");
        self.traverse(ray, closest, |leaf, closest| {
            let packet = self.packet_of[leaf.start - self.first] as usize;
            self.packets[packet].intersect(ray, closest);
        });
    }

    /// The same traversal with `test` (e.g. the book's sphere test, or a triangle's) applied
    /// to each item of a leaf in turn. Forced inline: left out of line, it was compiled once,
    /// for the baseline, and ran there whatever level the caller had chosen.
    #[inline(always)]
    pub fn intersect_each<T>(
        &self,
        spheres: &[T],
        ray: &Ray,
        closest: &mut Closest,
        test: impl Fn(&T, &Ray, Real) -> Option<Real>,
    ) {
        self.traverse(ray, closest, |leaf, closest| {
            for (i, sphere) in leaf.clone().zip(&spheres[leaf]) {
                if let Some(t) = test(sphere, ray, closest.bound()) {
                    closest.offer(t, i as u32);
                }
            }
        });
    }

    /// Visits, nearest first, every leaf whose box the ray enters before `closest.t`, handing
    /// `leaf` the range of items it holds; `leaf` offers its hits to `closest`, which prunes
    /// what is left.
    #[inline(always)]
    pub fn traverse(
        &self,
        ray: &Ray,
        closest: &mut Closest,
        mut leaf: impl FnMut(Range<usize>, &mut Closest),
    ) {
        if self.nodes.is_empty() {
            return;
        }
        let slab = Slab::new(ray);
        // Waiting children as one 8-byte word each (`Waiting`), written and read whole: a
        // `(child, entry)` pair was written field by field and read back whole, which defeats
        // the CPU's forwarding of stores to loads; two stacks of 4-byte values avoided that
        // but cost two pushes, two pops and two bounds checks. An ArrayVec, not an array:
        // zeroing the whole stack for every ray cost more than a short traversal
        // (`results/history/comment-figures.md`).
        let mut waiting: ArrayVec<Waiting, STACK> = ArrayVec::new();
        let mut child = ROOT;
        loop {
            if child & LEAF != 0 {
                leaf(leaf_spheres(child), closest);
            } else {
                let node = &self.nodes[child as usize];
                let (near, mask) = slab.enter(&node.corner, reach(closest));
                // Children hit, sorted farthest first (insertion sort of at most four). A
                // branch per lane: measured faster than a branch-free sorting network, than
                // looping over the mask's set bits and than special-casing a single hit
                // (`results/perf.md`): a predicted branch lets the CPU start on the next
                // node before this one's comparisons are done.
                let mut hit = [0u32; WIDTH];
                let mut at = [0.0 as Real; WIDTH];
                let mut count = 0;
                for (lane, (&entry, &lane_child)) in near.iter().zip(&node.children).enumerate() {
                    if mask & 1 << lane != 0 {
                        let mut j = count;
                        while j > 0 && at[j - 1] < entry {
                            (hit[j], at[j]) = (hit[j - 1], at[j - 1]);
                            j -= 1;
                        }
                        (hit[j], at[j]) = (lane_child, entry);
                        count += 1;
                    }
                }
                if count > 0 {
                    // The nearest is visited at once (its entry was just checked against
                    // the closest hit); the others wait on the stack, nearest on top.
                    for k in 0..count - 1 {
                        waiting.push(Waiting::new(hit[k], at[k]));
                    }
                    child = hit[count - 1];
                    continue;
                }
            }
            let Some(next) = next_waiting(&mut waiting, reach(closest)) else { return };
            child = next;
        }
    }
}

/// The slot of a leaf of `count` spheres (1 to [`LANES`]) from scene sphere `start` on: [`LEAF`],
/// then `start`, then `count - 1` in the low [`LEAF_COUNT_BITS`]. Visiting a leaf thus needs no
/// load before its spheres' own. The packet test, only the ablation's comparison, pays the
/// lookup of its packet instead (`results/history/comment-figures.md`).
fn leaf_slot(start: usize, count: usize) -> u32 {
    assert!((1..=LANES).contains(&count), "a leaf of {count} spheres");
    let start = u32::try_from(start).ok().filter(|&s| s < LEAF >> LEAF_COUNT_BITS);
    let start = start.expect("a scene of fewer than 2^29 spheres");
    LEAF | start << LEAF_COUNT_BITS | (count as u32 - 1)
}

/// The scene indices of the spheres of leaf slot `slot`.
#[inline(always)]
fn leaf_spheres(slot: u32) -> Range<usize> {
    let start = ((slot & !LEAF) >> LEAF_COUNT_BITS) as usize;
    start..start + (slot & (LANES as u32 - 1)) as usize + 1
}

/// Pops the nearest waiting child that a hit at `bound` does not rule out (one the ray enters
/// no later than `bound`), dropping those it does; `None` when none is left.
#[inline(always)]
pub(super) fn next_waiting<const N: usize>(waiting: &mut ArrayVec<Waiting, N>, bound: Real) -> Option<u32> {
    loop {
        let next = waiting.pop()?;
        if next.entry() <= bound {
            return Some(next.child());
        }
    }
}

/// A child waiting on the traversal's stack: its slot value in the low 32 bits, a lower bound
/// on its entry distance as f32 bits in the high 32, so that a push and a pop each move one
/// word. The bound is the entry distance itself in the default build; with the `f64` feature
/// it is rounded down to f32, which can only keep a child that the exact distance would have
/// skipped, never skip one it would have kept.
#[derive(Clone, Copy)]
pub(super) struct Waiting(u64);

impl Waiting {
    #[inline(always)]
    pub(super) fn new(child: u32, entry: Real) -> Waiting {
        Waiting(u64::from(to_f32_at_most(entry).to_bits()) << 32 | u64::from(child))
    }

    #[inline(always)]
    pub(super) fn entry(self) -> Real {
        Real::from(f32::from_bits((self.0 >> 32) as u32))
    }

    #[inline(always)]
    pub(super) fn child(self) -> u32 {
        self.0 as u32
    }
}

/// Child boxes of an empty node: inverted, so never entered.
const EMPTY_CORNERS: [[Wide; 3]; 2] = [[[Real::INFINITY; WIDTH]; 3], [[Real::NEG_INFINITY; WIDTH]; 3]];

/// A ray prepared for slab tests: its origin, inverse direction, and which corner of a box
/// it meets first on each axis.
pub(super) struct Slab {
    pub(super) origin: [Real; 3],
    pub(super) inv_dir: [Real; 3],
    /// `inv_dir` scaled by [`SLAB_ROUNDING`], for the exit distances: scaled once per ray
    /// instead of once per exit distance, which carries as many roundings as pbrt's (the
    /// reciprocal, this scaling, the subtraction, the product; pbrt scales last), so its
    /// bound still holds; one multiplication less per axis and node (`results/perf.md`).
    pub(super) inv_exit: [Real; 3],
    /// Per axis, 0 when the ray travels towards +axis (it enters at the lower corner), else 1.
    pub(super) near_corner: [usize; 3],
}

/// How far along the ray a box may be entered and still hold the closest hit so far, or a
/// hit tied with it that a lower index would win: a computed entry distance is at most
/// [`SLAB_ROUNDING`] times the exact one (three roundings: the reciprocal, the subtraction,
/// the product), so a box entered exactly at the hit's distance may read slightly beyond it.
#[inline(always)]
pub(super) fn reach(closest: &Closest) -> Real {
    closest.t * SLAB_ROUNDING
}

impl Slab {
    #[inline(always)]
    pub(super) fn new(ray: &Ray) -> Slab {
        let inv = ray.dir.recip();
        let inv_dir = [inv.x, inv.y, inv.z];
        Slab {
            origin: [ray.origin.x, ray.origin.y, ray.origin.z],
            inv_dir,
            inv_exit: inv_dir.map(|i| i * SLAB_ROUNDING),
            near_corner: inv_dir.map(|i| usize::from(i.is_sign_negative())),
        }
    }

    /// Per child, the distance at which the ray enters its box, and a mask with bit `k` set
    /// if it enters child `k`'s box before `t_max`. Comparisons are written
    /// `if a > b { a } else { b }` so they compile to `maxps`/`minps`, and the mask to one
    /// four-lane comparison, whose lanes the traversal's per-lane branches then test one by
    /// one (`pextrw`: the compiler folds the mask's bits into those branches); a NaN (a ray
    /// parallel to a face, starting on its plane) is ignored, which only widens the box.
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // one index runs over several arrays at once
    fn enter(&self, corner: &[[Wide; 3]; 2], t_max: Real) -> (Wide, u32) {
        let mut near: Wide = [0.0; WIDTH];
        let mut far: Wide = [t_max; WIDTH];
        for axis in 0..3 {
            let (o, inv, n) = (self.origin[axis], self.inv_dir[axis], self.near_corner[axis]);
            let inv_exit = self.inv_exit[axis];
            for lane in 0..WIDTH {
                let t_in = (corner[n][axis][lane] - o) * inv;
                let t_out = (corner[1 - n][axis][lane] - o) * inv_exit;
                near[lane] = if t_in > near[lane] { t_in } else { near[lane] };
                far[lane] = if t_out < far[lane] { t_out } else { far[lane] };
            }
        }
        let mask = (0..WIDTH).fold(0, |mask, lane| mask | u32::from(near[lane] <= far[lane]) << lane);
        (near, mask)
    }
}
