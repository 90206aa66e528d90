//! **What a learning path leaves behind**: its guided bounces, kept until the path ends,
//! then each turned into an estimate of the light that arrived along it and handed to the
//! pass's statistics (`learning.rs`). Light reaches a bounce from everything the path meets
//! after it, so an estimate can only be made once the path is over (Müller et al.'s
//! "vertices" of a path, recorded backwards).
//!
//! The estimate: the light the path gathered after the bounce (its radiance at the end less
//! its radiance then), divided by the path's throughput after the bounce, is the radiance
//! that arrived along the bounce's direction (an unbiased estimate of it; Russian roulette
//! and chances taken later are inside both). Its grey mean, at a surface times the cosine
//! to the normal (the diffuse bounce's integrand is the arriving light times the cosine: the
//! guide learns the product, not the light alone, which measured better on `cornell`), over
//! the density the direction was drawn with, estimates the leaf's light per unit of the
//! sphere (Müller et al., §3.3). Light sampled towards the lights at the bounce itself is not
//! in it: it arrived along other directions. What arrives by the bounce is weighed as the
//! path weighed it (against the light samples, by MIS), which is what the bounce has left to
//! find.
//!
//! Invariant: a trail is emptied by [`Trail::learn`] after every path, so one trail serves a
//! tile's paths one after another, allocated once.

use crate::tracer::geometry::hit::Hit;
use crate::tracer::guiding::learning::Learning;
use crate::tracer::guiding::spatial::facing;
use crate::tracer::math::real::{Real, Vec3};
use crate::tracer::shading::material::Lobe;

/// One guided bounce of a path that is learnt from.
#[derive(Clone, Copy, Debug)]
struct Bounce {
    /// Where it left.
    point: Vec3,
    /// Which way its surface faces ([`facing`]).
    facing: usize,
    /// Its unit direction.
    dir: Vec3,
    /// What its light is weighed by besides: the cosine to the surface's normal, 1 in a
    /// medium.
    cosine: Real,
    /// The density it was drawn with.
    pdf: Real,
    /// The path's throughput after it (its attenuation included).
    throughput: Vec3,
    /// The path's radiance when it left (the light samples at its hit included).
    radiance: Vec3,
}

/// A path's guided bounces, in order, until it ends.
#[derive(Clone, Debug, Default)]
pub struct Trail {
    bounces: Vec<Bounce>,
}

impl Trail {
    /// Notes a bounce from `hit` (of a material that scatters by `lobe`) along the unit `dir`,
    /// drawn with density `pdf`, leaving the path with `throughput` and `radiance` gathered
    /// so far.
    #[inline]
    pub fn push(&mut self, hit: &Hit, lobe: Lobe, dir: Vec3, pdf: Real, throughput: Vec3, radiance: Vec3) {
        let normal = (lobe == Lobe::Cosine).then_some(hit.normal);
        let cosine = normal.map_or(1.0, |n| n.dot(dir).abs());
        let point = hit.departure();
        self.bounces.push(Bounce { point, facing: facing(normal), dir, cosine, pdf, throughput, radiance });
    }

    /// The path is over with `radiance` gathered: every bounce's estimate to `learning`, and
    /// the trail emptied.
    #[inline]
    pub fn learn(&mut self, learning: &Learning, radiance: Vec3) {
        for bounce in self.bounces.drain(..) {
            let later = radiance - bounce.radiance;
            let carried = bounce.throughput.cmpgt(Vec3::ZERO);
            let arrived = Vec3::select(carried, later / bounce.throughput, Vec3::ZERO);
            let grey = (arrived.x + arrived.y + arrived.z) / 3.0;
            let estimate = if bounce.pdf > 0.0 { grey * bounce.cosine / bounce.pdf } else { 0.0 };
            learning.record(bounce.point, bounce.facing, bounce.dir, estimate);
        }
    }
}
