//! How a group's objects are searched ([`Runs`]): its surfaces in **runs** of up to eight, a
//! leaf of an eight-wide tree each or, for a small group, all in one, each run's quads in the
//! lanes of one [`QuadPacket`] and its other objects asked one by one; and its media asked
//! last, when the nearest surface bounds how far they must look (`object.rs`, which holds the
//! group, asks the objects themselves).
//!
//! The media stay out of the tree: a thin fog's box spans the whole world (the second book's
//! spans 10,000 units), and in a leaf it would send every ray through that leaf and the
//! surfaces that share it. The order in which objects are asked changes nothing: each reports
//! its nearest hit below the bound it is given, and the closest is the least
//! `(distance, index)` of them all ([`Closest`]), whatever the order it was offered in.

use std::ops::Range;

use crate::tracer::accel::bvh::Bvh;
use crate::tracer::accel::wide8::Bvh8;
use crate::tracer::geometry::hit::{Closest, Hit};
use crate::tracer::geometry::quad::Quad;
use crate::tracer::geometry::quads::{LANES, QuadPacket};
use crate::tracer::math::aabb::{Aabb, Bounded};
use crate::tracer::math::lanes::Lanes8;
use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::{Real, Vec3};

/// Groups of at most this many objects (one run) are searched without their tree (an
/// instance's only once the ray enters its box): a tree's traversal costs more than it saves
/// there.
pub const FLAT_MAX_OBJECTS: usize = LANES;

/// An eight-wide tree over a group's objects, and its leaves' ranges of them, by leaf number.
pub type Tree = (Bvh8, Vec<Range<usize>>);

/// Objects per leaf of a group's tree: four, as the spheres' trees have them, though a run
/// holds eight (a small group's whole search): leaves of eight quads made the second book's
/// ground of boxes slower (`results/books.md`), each leaf's box taking in more that a ray
/// does not hit.
const LEAF_OBJECTS: usize = LANES / 2;

/// Orders `objects` as the leaves of an eight-wide tree over their boxes (a leaf, one run, of
/// up to `LEAF_OBJECTS` each), and gives that tree if there are more than
/// [`FLAT_MAX_OBJECTS`] of them.
pub fn ordered<T: Bounded>(objects: &mut [T]) -> Option<Tree> {
    if objects.is_empty() {
        return None;
    }
    let tree = Bvh8::collapse(&Bvh::build_with_leaves(objects, LEAF_OBJECTS));
    (objects.len() > FLAT_MAX_OBJECTS).then_some(tree)
}

/// What the search needs to know of one of a group's objects.
pub struct Item<'a> {
    /// Its box.
    pub bounds: Aabb,
    /// The point a tree's build sorts it by.
    pub centroid: Vec3,
    /// What it is.
    pub kind: Kind<'a>,
}

/// The kinds the search treats apart.
pub enum Kind<'a> {
    /// A quad: tested in a packet's lane.
    Quad(&'a Quad),
    /// A sphere: tested on its own, its hit's record made only if it is the closest.
    Sphere,
    /// A medium: asked last.
    Medium,
    /// Anything else: asked on its own.
    Other,
}

/// Which of a group's objects holds the closest hit so far, and what its record will be made
/// from: only the closest hit's record is made, at the end of the search.
#[derive(Clone, Copy)]
pub enum Best {
    /// No hit yet.
    Nothing,
    /// A quad: the hit's coordinates (its distance is the closest one), and whether the ray
    /// meets its front.
    Quad {
        /// Along its first edge.
        alpha: Real,
        /// Along its second edge.
        beta: Real,
        /// `n · d < 0`.
        front: bool,
    },
    /// A sphere: the distance is all its record needs.
    Sphere,
    /// Any other object: its whole record.
    Other(Hit),
}

/// A group's search: its surfaces' runs (through a tree, or one after another) and its media.
#[derive(Clone, Debug)]
pub struct Runs {
    /// Over the surfaces; run `k` is its leaf `k`.
    tree: Option<Bvh8>,
    runs: Vec<Run>,
    media: Vec<u32>,
}

/// Up to [`LANES`] objects of a group, searched together.
#[derive(Clone, Debug)]
pub struct Run {
    /// Its objects' indices in the group (the first `count`).
    indices: [u32; LANES],
    /// Bit `k`: object `indices[k]` is a quad, tested in lane `k` of `quads`.
    quads_mask: u32,
    /// Bit `k`: object `indices[k]` is a sphere.
    spheres: u32,
    /// Bit `k`: object `indices[k]` is of another kind, asked on its own.
    others: u32,
    quads: QuadPacket,
}

/// A surface as the search's own tree sees it: its index in the group, its box.
struct Surface {
    index: u32,
    bounds: Aabb,
    centroid: Vec3,
}

impl Bounded for Surface {
    fn bounds(&self) -> Aabb {
        self.bounds
    }

    fn centroid(&self) -> Vec3 {
        self.centroid
    }
}

impl Runs {
    /// The search over `items`, a group's objects in its order: through `tree` (built over all
    /// of them, in that order) if there is one, or, if some of them are media, a tree of the
    /// other objects' boxes built here; without a tree, eight objects in a row.
    pub fn new(items: &[Item], tree: Option<Tree>) -> Runs {
        let media: Vec<u32> =
            (0..items.len() as u32).filter(|&i| matches!(items[i as usize].kind, Kind::Medium)).collect();
        let mut surfaces: Vec<Surface> = (0..items.len() as u32)
            .filter(|&i| !matches!(items[i as usize].kind, Kind::Medium))
            .map(|index| Surface {
                index,
                bounds: items[index as usize].bounds,
                centroid: items[index as usize].centroid,
            })
            .collect();
        let tree = match tree {
            Some(_) if !media.is_empty() && !surfaces.is_empty() => {
                Some(Bvh8::collapse(&Bvh::build_with_leaves(&mut surfaces, LEAF_OBJECTS)))
            }
            Some(_) if !media.is_empty() => None,
            tree => tree,
        };
        let (tree, ranges) = match tree {
            Some((tree, ranges)) => (Some(tree), ranges),
            None => {
                let runs = (0..surfaces.len()).step_by(LANES).map(|s| s..(s + LANES).min(surfaces.len()));
                (None, runs.collect())
            }
        };
        let runs = ranges
            .into_iter()
            .map(|range| {
                // Lanes in the order of the group's indices: a packet's nearest lane is the
                // lowest of equals, which must be the lowest index ([`Closest`]'s tie rule).
                let mut chosen: Vec<&Surface> = surfaces[range].iter().collect();
                chosen.sort_by_key(|s| s.index);
                let indices = std::array::from_fn(|k| chosen.get(k).map_or(u32::MAX, |s| s.index));
                let quad = |k: usize| match chosen.get(k).map(|s| &items[s.index as usize].kind) {
                    Some(Kind::Quad(quad)) => Some(*quad),
                    _ => None,
                };
                let quads: Vec<Option<&Quad>> = (0..chosen.len()).map(quad).collect();
                let kinds = |of: fn(&Kind) -> bool| {
                    (0..chosen.len())
                        .filter(|&k| of(&items[chosen[k].index as usize].kind))
                        .fold(0, |m, k| m | 1 << k)
                };
                let quads_mask = kinds(|kind| matches!(kind, Kind::Quad(_)));
                let spheres = kinds(|kind| matches!(kind, Kind::Sphere));
                let others = kinds(|kind| matches!(kind, Kind::Other));
                Run { indices, quads_mask, spheres, others, quads: QuadPacket::new(&quads) }
            })
            .collect();
        Runs { tree, runs, media }
    }

    /// Whether its surfaces are searched through a tree.
    pub fn has_tree(&self) -> bool {
        self.tree.is_some()
    }

    /// Visits every run the ray may find a hit in before `closest.t` (a tree's leaves nearest
    /// first, pruned by the closest hit so far); `visit` offers the run's hits to `closest`.
    #[inline(always)]
    pub fn search<L: Lanes8>(
        &self,
        lanes: L,
        ray: &Ray,
        closest: &mut Closest,
        mut visit: impl FnMut(&Run, &mut Closest),
    ) {
        // Loops and closures forced inline: code left out of line is compiled for the
        // baseline, whatever the level `lanes` stands for.
        match &self.tree {
            None => {
                for run in &self.runs {
                    visit(run, closest);
                }
            }
            Some(tree) => tree.traverse(
                lanes,
                ray,
                closest,
                #[inline(always)]
                |leaf: usize, closest: &mut Closest| visit(&self.runs[leaf], closest),
            ),
        }
    }

    /// The indices of the group's media.
    pub fn media(&self) -> impl Iterator<Item = usize> + '_ {
        self.media.iter().map(|&i| i as usize)
    }
}

impl Run {
    /// Offers its quads' nearest hit below `closest`'s bound to `closest`; if it became the
    /// closest, what its record is made from ([`Best::Quad`]).
    #[inline(always)]
    pub fn offer_quads<L: Lanes8>(&self, lanes: L, ray: &Ray, closest: &mut Closest) -> Option<Best> {
        if self.quads_mask == 0 {
            return None;
        }
        let hits = self.quads.intersect(lanes, ray, closest.bound());
        let k = hits.nearest()?;
        let i = self.indices[k];
        closest.offer(hits.t[k], i);
        let front = hits.front >> k & 1 != 0;
        (closest.index == i).then_some(Best::Quad { alpha: hits.alpha[k], beta: hits.beta[k], front })
    }

    /// Whether one of its quads is hit in `(0, t_max)`.
    #[inline(always)]
    pub fn quads_block<L: Lanes8>(&self, lanes: L, ray: &Ray, t_max: Real) -> bool {
        self.quads_mask != 0 && self.quads.intersect(lanes, ray, t_max).mask != 0
    }

    /// The group indices of its spheres.
    #[inline(always)]
    pub fn spheres(&self) -> impl Iterator<Item = usize> + use<> {
        bits(self.indices, self.spheres)
    }

    /// The group indices of its objects of other kinds.
    #[inline(always)]
    pub fn others(&self) -> impl Iterator<Item = usize> + use<> {
        bits(self.indices, self.others)
    }
}

/// `indices[k]` for every bit `k` set in `mask`, lowest first.
#[inline(always)]
fn bits(indices: [u32; LANES], mut mask: u32) -> impl Iterator<Item = usize> {
    std::iter::from_fn(move || {
        (mask != 0).then(|| {
            let k = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            indices[k] as usize
        })
    })
}
