//! **Path guiding**: bounces drawn towards where light came from, as learnt while rendering
//! (Müller, Gross and Novák 2017, "Practical Path Guiding"; Cycles guides its paths with
//! Intel's Open PGL). No light sample finds the light that reaches a place only after
//! bounces (a room lit from its ceiling's lamp by the walls); a guide learns it.
//!
//! A guided render (`--guiding on`) runs in passes: the first takes sample 0 of every
//! pixel, the next sample 1, then 2–3, 4–7, … (each doubling the samples taken), up to its
//! pilot; each pass learns a guide from its paths (an SD-tree: a binary tree over the scene,
//! [`spatial`], and in each of its cells a quadtree over directions, [`quadtree`]), which the
//! next pass draws its bounces from ([`bounce`]), and the last pass takes the rest of the
//! samples with the last guide. Every sample is an unbiased estimate whatever guide it drew
//! from, so all count in the image. The files, in the order a pass uses them:
//!
//! - [`guide`]: the SD-tree a pass draws from, fixed while it renders;
//! - [`bounce`]: the guided bounce, one-sample MIS of the guide and the material;
//! - [`trail`]: a path's bounces, turned into estimates of the light arriving when it ends;
//! - [`learning`]: those estimates summed in fixed point from every thread, so the next guide
//!   is the same bits under any schedule, and the cuts of the next SD-tree.
//!
//! How the passes are scheduled is `schedule/guided.rs`'s; the path's use of the guide,
//! `render/path.rs`'s.

pub mod quadtree;
pub mod spatial;
pub mod guide;
pub mod bounce;
pub mod learning;
pub mod trail;

use std::ops::Range;

use crate::tracer::math::aabb::{Aabb, Bounded};
use crate::tracer::scene::Scene;

/// Path guiding (`--guiding on`): its passes' samples.
///
/// ```
/// use raypool::tracer::guiding::Guiding;
/// let guiding = Guiding { pilot: 8 };
/// // Passes end at 1, 2, 4 and 8 samples, each learning the next one's guide; the last takes the rest.
/// assert_eq!(guiding.passes(32), vec![0..1, 1..2, 2..4, 4..8, 8..32]);
/// // Fewer samples than the pilot: the pilot is cut short.
/// assert_eq!(guiding.passes(6), vec![0..1, 1..2, 2..4, 4..6]);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Guiding {
    /// Samples per pixel of the learning passes together (rounded down to a power of two).
    pub pilot: u32,
}

impl Guiding {
    /// The default for a render of `spp`: a quarter of the samples learn.
    ///
    /// ```
    /// use raypool::tracer::guiding::Guiding;
    /// assert_eq!(Guiding::for_spp(64), Guiding { pilot: 16 });
    /// ```
    pub fn for_spp(spp: u32) -> Guiding {
        Guiding { pilot: spp / 4 }
    }

    /// The sample ranges of a guided render of `spp` samples per pixel, in order: passes
    /// ending at 1, 2, 4, … up to the pilot (or `spp`), then one to `spp`. Every pass but
    /// the last learns the guide of the next.
    pub fn passes(self, spp: u32) -> Vec<Range<u32>> {
        let (mut passes, mut start, mut end) = (Vec::new(), 0, 1);
        while end <= self.pilot.min(spp) && end < spp {
            passes.push(start..end);
            (start, end) = (end, 2 * end);
        }
        if start < spp {
            passes.push(start..spp);
        }
        passes
    }
}

/// Whether `scene` takes a guide: a second-book scene with lights. Elsewhere (the first
/// book's sky-lit scenes, `final` among them) a guided render is the unguided one.
pub fn takes(scene: &Scene) -> bool {
    !scene.is_first_book() && !scene.lights().is_empty()
}

/// The box the spatial tree cuts: every object's.
pub fn bounds(scene: &Scene) -> Aabb {
    scene.objects().iter().map(Bounded::bounds).fold(Aabb::EMPTY, Aabb::union)
}
