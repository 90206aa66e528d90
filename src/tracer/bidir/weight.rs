//! The multiple-importance weight of one connection: how much of a path's light the strategy
//! that made it keeps, against every other strategy that could have made the same path.
//!
//! A path of `k + 1` vertices `x₀ … x_k` (light end first, the camera last) is made by the
//! strategy `(s, t)`, `s + t = k + 1`, from the light path's first `s` vertices and the camera
//! path's first `t`. Its density is the product of the light walk's densities of `x₀ … x_{s−1}`
//! and the camera walk's of `x_s … x_k`, so the strategies' densities differ by one factor a
//! step: `p_{s+1} / p_s = p_light(x_s) / p_cam(x_s)`. The power heuristic's weight is
//! `p_s² / Σ p_{s'}²` over the strategies that are used and can make the path (light tracing's
//! `p` scaled by its share, [`Limits::light_tracing_share`]); this walks
//! those ratios out from `s` both ways, as pbrt does (`MISWeight`). A delta vertex (mirror,
//! glass) has density 0 on both sides, read as 1 (the delta cancels), and no connection may
//! end on it.
//!
//! Invariant: the weight is a function of the path alone (its vertices and [`Limits`]), not of
//! the strategy that found it, so a path's weights over its strategies sum to 1 and the image
//! is unbiased.

use crate::tracer::bidir::vertex::Vertex;
use crate::tracer::math::real::Real;

/// Which strategies are used: every camera path (`s = 0`) and shadow ray (`s = 1`); light
/// paths of at most `light_vertices` vertices, joined to the camera (`t = 1`) or to the camera
/// path's first `connect_vertices − 1` bounces; and the share at which light tracing (`t = 1`)
/// is weighed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits {
    /// The most vertices of a light path (its point on the light included).
    pub light_vertices: usize,
    /// The most camera-path vertices (the camera included) a light path's vertex is joined to.
    pub connect_vertices: usize,
    /// The factor light tracing's density is weighed by against the others'.
    pub light_tracing_share: Real,
}

impl Limits {
    /// Whether strategy `(s, t)` is used.
    #[inline]
    pub fn used(&self, s: usize, t: usize) -> bool {
        match (s, t) {
            (_, 0) => false,
            (0, _) => true,
            (1, t) => t >= 2,
            (s, t) => s <= self.light_vertices && (t == 1 || t <= self.connect_vertices),
        }
    }
}

/// The densities at a connection's two ends, which neither walk could know: the light side's
/// density of the camera path's last two vertices, and the camera side's of the light path's.
#[derive(Clone, Copy, Debug, Default)]
pub struct Ends {
    /// Density with which the light side draws `x_s` (the camera path's last vertex): from
    /// `x_{s−1}`, or, for `s = 0`, as a light path's starting point.
    pub camera_last: Real,
    /// Density with which the light side draws `x_{s+1}` from `x_s`.
    pub camera_next: Real,
    /// Density with which the camera side draws `x_{s−1}` (the light path's last vertex) from
    /// `x_s`.
    pub light_last: Real,
    /// Density with which the camera side draws `x_{s−2}` from `x_{s−1}`.
    pub light_next: Real,
}

/// The power heuristic's weight of the path joined from `light` (its `s` vertices) and
/// `camera` (its `t` vertices, the camera first), with the connection's `ends`.
pub fn weight(light: &[Vertex], camera: &[Vertex], ends: &Ends, limits: Limits) -> Real {
    let (s, t) = (light.len(), camera.len());
    let k = s + t - 1;
    let vertex = |i: usize| if i < s { &light[i] } else { &camera[k - i] };
    // x₀ is the light's point (for s = 0, the emitter the camera path met): always joinable.
    let delta = |i: usize| i != 0 && !vertex(i).connectable();
    let p_light = |i: usize| match i {
        _ if i < s => light[i].pdf_fwd,
        _ if i == s => ends.camera_last,
        _ if i == s + 1 => ends.camera_next,
        _ => camera[k - i].pdf_rev,
    };
    let p_camera = |i: usize| match i {
        _ if i >= s => camera[k - i].pdf_fwd,
        _ if i + 1 == s => ends.light_last,
        _ if i + 2 == s => ends.light_next,
        _ => light[i].pdf_rev,
    };
    let possible = |s2: usize| limits.used(s2, k + 1 - s2) && (s2 == 0 || (!delta(s2 - 1) && !delta(s2)));
    // Light tracing's density counted at its share (`Limits::light_tracing_share`).
    let share = |s2: usize| if s2 == k { limits.light_tracing_share } else { 1.0 };
    let own = share(s);
    let mut sum = 1.0;
    let mut ratio = 1.0;
    for s2 in s + 1..=k {
        ratio *= cancel_delta(p_light(s2 - 1)) / cancel_delta(p_camera(s2 - 1));
        if possible(s2) {
            sum += (ratio * share(s2) / own).powi(2);
        }
    }
    ratio = 1.0;
    for s2 in (0..s).rev() {
        ratio *= cancel_delta(p_camera(s2)) / cancel_delta(p_light(s2));
        if possible(s2) {
            sum += (ratio * share(s2) / own).powi(2);
        }
    }
    let w = 1.0 / sum;
    if w.is_finite() { w } else { 0.0 }
}

/// A delta vertex's density, 0, read as 1: it stands for the same delta on both sides.
#[inline]
fn cancel_delta(pdf: Real) -> Real {
    if pdf == 0.0 { 1.0 } else { pdf }
}
