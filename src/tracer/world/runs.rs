//! A group's objects searched in **runs** of up to four: a leaf of the group's tree each, or,
//! without a tree, four in a row. A run's quads sit in the lanes of one [`QuadPacket`] and are
//! tested together; its other objects are asked one by one (`object.rs`, which holds the
//! group).
//!
//! The order in which a run asks its objects changes nothing: each object reports its nearest
//! hit below the bound it is given, and the closest is the least `(distance, index)` of them
//! all ([`Closest`]), whatever the order they were offered in.

use std::ops::Range;

use crate::tracer::geometry::hit::Closest;
use crate::tracer::geometry::quad::Quad;
use crate::tracer::geometry::quads::{LANES, QuadPacket};
use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::Real;

/// Up to [`LANES`] objects of a group, searched together.
#[derive(Clone, Debug)]
pub struct Run {
    /// The index of its first object in the group.
    start: u32,
    /// Bit `k`: object `start + k` is a quad, tested in lane `k` of `quads`.
    quads_mask: u32,
    /// Bit `k`: object `start + k` is of another kind, asked on its own.
    others: u32,
    quads: QuadPacket,
}

impl Run {
    /// The run of the group's objects `range`, where `quad(i)` is object `i` if that is a
    /// quad.
    pub fn new<'a>(range: Range<usize>, quad: impl Fn(usize) -> Option<&'a Quad>) -> Run {
        assert!(range.len() <= LANES, "a run of {} objects", range.len());
        let quads: [Option<&Quad>; LANES] =
            std::array::from_fn(|k| (k < range.len()).then(|| quad(range.start + k)).flatten());
        let quads_mask = (0..range.len()).filter(|&k| quads[k].is_some()).fold(0, |m, k| m | 1 << k);
        let others = (0..range.len()).filter(|&k| quads[k].is_none()).fold(0, |m, k| m | 1 << k);
        Run { start: range.start as u32, quads_mask, others, quads: QuadPacket::new(quads) }
    }

    /// Offers its quads' nearest hit below `closest`'s bound to `closest`; if it became the
    /// closest, its `(α, β)`.
    #[inline(always)]
    pub fn offer_quads(&self, ray: &Ray, closest: &mut Closest) -> Option<(Real, Real)> {
        if self.quads_mask == 0 {
            return None;
        }
        let hits = self.quads.intersect(ray, closest.bound());
        let k = hits.nearest()?;
        let i = self.start + k as u32;
        // Lanes by array index: a vector's own `[k]` is a jump table.
        closest.offer(hits.t.to_array()[k], i);
        (closest.index == i).then(|| (hits.alpha.to_array()[k], hits.beta.to_array()[k]))
    }

    /// Whether one of its quads is hit in `(0, t_max)`.
    #[inline(always)]
    pub fn quads_block(&self, ray: &Ray, t_max: Real) -> bool {
        self.quads_mask != 0 && self.quads.intersect(ray, t_max).mask != 0
    }

    /// The group indices of its objects that are not quads.
    #[inline(always)]
    pub fn others(&self) -> impl Iterator<Item = usize> + use<> {
        let start = self.start as usize;
        lanes(self.others).map(move |k| start + k)
    }
}

/// The lanes whose bits are set in `mask`, lowest first.
#[inline(always)]
fn lanes(mut mask: u32) -> impl Iterator<Item = usize> {
    std::iter::from_fn(move || {
        (mask != 0).then(|| {
            let k = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            k
        })
    })
}

/// Up to four objects' indices kept to be asked later (a group's media, asked once the nearest
/// surface bounds how far they must look); a fifth is asked at once.
#[derive(Default)]
pub struct Deferred {
    indices: [u32; 4],
    len: usize,
}

impl Deferred {
    /// Keeps `i` for later; `false` when full.
    pub fn defer(&mut self, i: usize) -> bool {
        let kept = self.len < self.indices.len();
        if kept {
            self.indices[self.len] = i as u32;
            self.len += 1;
        }
        kept
    }

    /// Calls `each` with every kept index, in the order kept.
    pub fn each(&self, mut each: impl FnMut(usize)) {
        self.indices[..self.len].iter().for_each(|&i| each(i as usize));
    }
}
