//! **The guide a pass draws from**: an SD-tree with what the pass before it learnt. A bounce
//! finds its cell by its point (`spatial.rs`) and draws a direction from that cell's
//! distribution for its facing (`quadtree.rs`); nothing in it changes while a pass renders, so every thread
//! reads it without a lock, and a sample's bounce depends only on the guide and its own
//! random numbers.
//!
//! Invariants: a guide is made only by `Learning::finish` (`learning.rs`), from integer sums,
//! so the same pass gives the same guide, bit for bit, whatever its schedule; it keeps each
//! cell's count of bounces and the samples per pixel it was learnt from, which the next
//! pass's cuts are decided by.

use crate::tracer::guiding::quadtree::Directions;
use crate::tracer::guiding::spatial::{FACINGS, SpatialTree};
use crate::tracer::math::real::Vec3;

/// A learnt SD-tree: per cell of its spatial tree and facing, a distribution of arriving
/// light.
#[derive(Clone, Debug, PartialEq)]
pub struct Guide {
    space: SpatialTree,
    /// Cell `c`'s distribution for facing `f` at `c × FACINGS + f`.
    distributions: Vec<Directions>,
    bounces: Vec<u64>,
    spp: u32,
}

impl Guide {
    /// The guide of `space` with `distributions` (cell `c`'s for facing `f` at
    /// `c × FACINGS + f`), learnt from `bounces` (per cell) in a pass of `spp` samples per
    /// pixel.
    ///
    /// # Panics
    /// If there is not one distribution per cell and facing, and one count per cell.
    pub fn new(space: SpatialTree, distributions: Vec<Directions>, bounces: Vec<u64>, spp: u32) -> Guide {
        let cells = space.cells();
        assert!(distributions.len() == cells * FACINGS && bounces.len() == cells, "one entry per cell");
        Guide { space, distributions, bounces, spp }
    }

    /// The distribution of light arriving at `point` on a surface of `facing`
    /// ([`facing`](crate::tracer::guiding::spatial::facing)).
    #[inline]
    pub fn directions(&self, point: Vec3, facing: usize) -> &Directions {
        &self.distributions[self.space.cell(point) * FACINGS + facing]
    }

    /// The spatial tree.
    pub fn space(&self) -> &SpatialTree {
        &self.space
    }

    /// Every distribution: cell `c`'s for facing `f` at `c × FACINGS + f`.
    pub fn distributions(&self) -> &[Directions] {
        &self.distributions
    }

    /// Every cell's count of bounces recorded, in cell order.
    pub fn bounces(&self) -> &[u64] {
        &self.bounces
    }

    /// Samples per pixel of the pass it was learnt from.
    pub fn spp(&self) -> u32 {
        self.spp
    }

    /// Bytes its trees take: each quadtree node's children and energies (48 bytes), each
    /// spatial node's and cell's few.
    pub fn bytes(&self) -> usize {
        let nodes: usize = self.distributions.iter().map(|d| d.shape().len()).sum();
        48 * nodes + 48 * self.distributions.len()
    }
}
