//! **What one pass learns, joined from every thread in fixed point**: the statistics of an
//! SD-tree being filled. Every bounce of a learning pass adds, in its cell, to the quadtree of
//! its facing (`spatial.rs`), in the leaf its direction falls in, an estimate of the light
//! arriving along it (`trail.rs`), and counts one bounce in the cell.
//!
//! Many threads add to the same sums at once, in an order no one controls. Floating-point
//! addition is not associative (`(a + b) + c` may differ from `a + (b + c)` in the last
//! bit), so float sums would depend on the schedule, and with them the guide and every
//! later pixel. So each estimate is rounded *once*, when it is made, to a whole number of
//! 2⁻²⁰ units, and the sums are integers (`AtomicU64::fetch_add`): integer addition gives the
//! same bits in any order, as the image's splats do (`splats.rs`). The threads never wait on
//! one another, and the guide a pass leaves is the same under every scheduler, thread count
//! and tile size.
//!
//! Invariants: an estimate is rounded by [`to_units`] alone, a function of the estimate;
//! sums wrap modulo 2⁶⁴ (which also adds the same in any order): only a leaf receiving 2²⁰
//! estimates at the cap, each [`CAP`] units of light, could wrap, which would change the
//! guide, never make it depend on the schedule or the image biased. [`Learning::finish`]
//! reads the sums after the pass's threads are joined (the scheduler returns only then).

use std::sync::atomic::{AtomicU64, Ordering};

use crate::tracer::guiding::guide::Guide;
use crate::tracer::guiding::quadtree::{Directions, Quadtree, to_square};
use crate::tracer::guiding::spatial::{FACINGS, SpatialTree};
use crate::tracer::math::aabb::Aabb;
use crate::tracer::math::real::{Real, Vec3, to_f64};

/// A cell is cut in two once it records this many bounces times the square root of its
/// pass's samples per pixel (Müller et al.'s `c`).
pub const SPLIT_BOUNCES: f64 = 12_000.0;
/// A quadrant is cut in four once it holds this share of its distribution's light (their
/// `ρ`).
pub const SPLIT_SHARE: f64 = 0.01;

/// One unit of an estimate is this many counts: 2²⁰.
const SCALE: f64 = 1_048_576.0;
/// The largest estimate added, in units of light: 2²⁴.
pub const CAP: f64 = 16_777_216.0;

/// `estimate` in fixed point: a whole number of 2⁻²⁰ units, at most [`CAP`]; 0 for a
/// negative or NaN estimate.
///
/// ```
/// use raypool::tracer::guiding::learning::to_units;
/// assert_eq!(to_units(1.0), 1 << 20);
/// assert_eq!(to_units(-3.0), 0);
/// assert_eq!(to_units(f32::NAN as _), 0);
/// ```
pub fn to_units(estimate: Real) -> u64 {
    // Tested first: `NaN.min(CAP)` would be `CAP`.
    if estimate > 0.0 { (to_f64(estimate).min(CAP) * SCALE) as u64 } else { 0 }
}

/// One distribution's statistics: its quadtree's cut and a sum per slot (only leaf slots
/// receive).
#[derive(Debug)]
struct Sums {
    shape: Quadtree,
    sums: Vec<[AtomicU64; 4]>,
}

impl Sums {
    fn new(shape: Quadtree) -> Sums {
        let sums = (0..shape.len()).map(|_| Default::default()).collect();
        Sums { shape, sums }
    }
}

/// The statistics one learning pass fills: a spatial tree and, per cell and facing, a
/// quadtree's sums; per cell, its bounces.
#[derive(Debug)]
pub struct Learning {
    space: SpatialTree,
    /// Cell `c`'s distribution for facing `f` at `c × FACINGS + f`.
    distributions: Vec<Sums>,
    bounces: Vec<AtomicU64>,
    /// Samples per pixel of the pass that fills it.
    spp: u32,
}

impl Learning {
    /// The first pass's: one cell over `bounds`, its quadtrees the root alone, filled by a
    /// pass of `spp` samples per pixel.
    pub fn new(bounds: Aabb, spp: u32) -> Learning {
        Learning::from_parts(SpatialTree::new(bounds), vec![Quadtree::default(); FACINGS], spp)
    }

    /// The statistics the pass after the one that learnt `guide` fills, with `spp` samples
    /// per pixel: the guide's cells cut where they recorded more than
    /// [`SPLIT_BOUNCES`]` × √(its pass's spp)` bounces (Müller et al.'s `c·√(2ᵏ)`), and each
    /// quadtree cut where its directions hold more than [`SPLIT_SHARE`] of its light.
    pub fn after(guide: &Guide, spp: u32) -> Learning {
        let threshold = SPLIT_BOUNCES * f64::from(guide.spp()).sqrt();
        let (space, origins) = guide.space().refined(guide.bounces(), threshold);
        let shapes = origins
            .into_iter()
            .flat_map(|cell| &guide.distributions()[cell * FACINGS..(cell + 1) * FACINGS])
            .map(|directions| directions.shape().refined(directions.energy(), SPLIT_SHARE))
            .collect();
        Learning::from_parts(space, shapes, spp)
    }

    /// Statistics over the cells of `space`, cell `c`'s distribution for facing `f` cut as
    /// `shapes[c × FACINGS + f]`, for a pass of `spp` samples per pixel.
    ///
    /// # Panics
    /// If `shapes` does not hold one cut per cell and facing.
    pub fn from_parts(space: SpatialTree, shapes: Vec<Quadtree>, spp: u32) -> Learning {
        assert_eq!(shapes.len(), space.cells() * FACINGS, "a cut per cell and facing");
        let bounces = (0..space.cells()).map(|_| AtomicU64::new(0)).collect();
        Learning { space, distributions: shapes.into_iter().map(Sums::new).collect(), bounces, spp }
    }

    /// Adds `estimate` (light arriving along the unit `dir` at `point`, on a surface of
    /// `facing`, over the density of drawing `dir`) to its leaf, and counts the bounce in its
    /// cell: from any thread.
    #[inline]
    pub fn record(&self, point: Vec3, facing: usize, dir: Vec3, estimate: Real) {
        let cell = self.space.cell(point);
        self.bounces[cell].fetch_add(1, Ordering::Relaxed);
        let units = to_units(estimate);
        if units > 0 {
            let distribution = &self.distributions[cell * FACINGS + facing];
            let (node, q) = distribution.shape.leaf_of(to_square(dir));
            distribution.sums[node][q].fetch_add(units, Ordering::Relaxed);
        }
    }

    /// The guide the statistics make: per cell and facing, its cut with each leaf's sum
    /// (back in units of light) summed up the quadtree; per cell, its count of bounces.
    /// Called once the pass's threads are joined.
    pub fn finish(&self) -> Guide {
        let load = |sum: &AtomicU64| sum.load(Ordering::Relaxed) as f64 / SCALE;
        let distributions = self
            .distributions
            .iter()
            .map(|d| {
                Directions::new(d.shape.clone(), d.sums.iter().map(|s| s.each_ref().map(load)).collect())
            })
            .collect();
        let bounces = self.bounces.iter().map(|b| b.load(Ordering::Relaxed)).collect();
        Guide::new(self.space.clone(), distributions, bounces, self.spp)
    }
}
