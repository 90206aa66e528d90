//! The density of reaching a vertex through mirrors and glass: a walk that leaves vertex `a`
//! in direction `ω` and passes a chain of specular vertices lands on vertex `b` at a point
//! that depends on `ω` alone, so its density per unit area at `b` is `p(ω) / J`, where
//! `J = dA_b / dω` is the chain's Jacobian (Veach's generalized geometry term; `d² / cos θ`
//! with no chain between). A glass ball that focuses a lamp's light makes `J` small: the walk
//! from the lamp lands densely there, the walk from the floor rarely finds the lamp.
//!
//! Without it, the weights would count a specular chain as 1 on both sides (pbrt's convention
//! for delta vertices), ignoring the focusing, and give the caustic next to a glass ball's foot
//! to the camera's path, whose short floor-to-glass step looks dense (`results/bdpt.md`).
//!
//! `J` is measured by forward differences: the chain is followed again (same surfaces, each
//! vertex reflecting or refracting as the path did) from two directions `10⁻³` radians off
//! `ω`, and their landing points on `b`'s tangent plane, less `b` itself, give
//! `|∂p/∂u × ∂p/∂v|` (central differences, twice the traces, measured no better on `cornell`). A trace that
//! meets another surface, or cannot refract, gives no density (0: the convention above), so a
//! path's weights stay a function of the path alone.

use crate::tracer::bidir::vertex::{Kind, Vertex};
use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::{Real, Vec3};
use crate::tracer::scene::Scene;
use crate::tracer::shading::material::{Material, reflect, refract};
use crate::tracer::world::object::Probe;

/// The angle by which the chain's start direction is moved to measure its Jacobian.
const STEP: Real = 1e-3;

/// The specular vertices between two vertices of a path, walked in the path's order or
/// backwards (the other walk's way), without copying them.
#[derive(Clone, Copy, Debug)]
pub struct Chain<'a> {
    /// The vertices, in the order the path met them.
    pub vertices: &'a [Vertex],
    /// Whether they are walked from the last to the first.
    pub backwards: bool,
}

impl Chain<'_> {
    /// The `k`-th vertex met on this walk.
    fn at(&self, k: usize) -> &Vertex {
        if self.backwards { &self.vertices[self.vertices.len() - 1 - k] } else { &self.vertices[k] }
    }
}

/// A direction a walk leaves a vertex in, and the density per unit solid angle with which it
/// was drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Leaving {
    /// The unit direction.
    pub dir: Vec3,
    /// Its density.
    pub pdf: Real,
}

/// The density per unit area at `end` of a walk that leaves `start` as `leaving` says and
/// passes the specular vertices of `chain` (`probe`: the path's time; media play no part). 0
/// where it cannot be measured. The rays it casts count in `rays`.
pub fn density_through(
    scene: &Scene,
    start: &Vertex,
    leaving: Leaving,
    chain: Chain,
    end: &Vertex,
    probe: Probe,
    rays: &mut u64,
) -> Real {
    let Leaving { dir, pdf } = leaving;
    if end.kind == Kind::Medium || pdf <= 0.0 {
        return 0.0;
    }
    let (u, v) = dir.any_orthonormal_pair();
    let mut land =
        |a: Real, b: Real| follow(scene, start, (dir + a * u + b * v).normalize(), chain, end, probe, rays);
    // The chain followed along `dir` itself lands on `end`: forward differences need two.
    let (Some(along_u), Some(along_v)) = (land(STEP, 0.0), land(0.0, STEP)) else { return 0.0 };
    let jacobian = ((along_u - end.point).cross(along_v - end.point) / (STEP * STEP)).length();
    let density = pdf / jacobian;
    if density.is_finite() { density } else { 0.0 }
}

/// Where a ray leaving `start` along `dir` lands on `end`'s tangent plane after reflecting or
/// refracting at each vertex of `chain` as the path did; `None` if it meets anything else.
fn follow(
    scene: &Scene,
    start: &Vertex,
    dir: Vec3,
    chain: Chain,
    end: &Vertex,
    probe: Probe,
    rays: &mut u64,
) -> Option<Vec3> {
    let mut ray = match &start.hit {
        Some(hit) => hit.spawn(dir),
        // The camera's point, or a light's, raised off the light as a light path leaves it.
        None => Ray {
            origin: start.point + (64.0 * Real::EPSILON * start.point.abs().max_element()) * start.normal,
            dir,
        },
    };
    let n = chain.vertices.len();
    for k in 0..n {
        let vertex = chain.at(k);
        *rays += 1;
        let hit = scene.hit_world(&ray, &probe)?;
        if hit.material != vertex.hit?.material {
            return None;
        }
        let before = if k == 0 { start.point } else { chain.at(k - 1).point };
        let after = if k + 1 == n { end.point } else { chain.at(k + 1).point };
        // The path refracted here if its two sides lie on opposite sides of the surface (in
        // either direction of travel).
        let side = |p: Vec3| (p - vertex.point).dot(vertex.normal) > 0.0;
        let refracted = side(before) != side(after);
        let out = match *scene.material(&hit) {
            Material::Dielectric { ior, .. } if refracted => {
                refract(ray.dir, hit.normal, if hit.front_face { 1.0 / ior } else { ior })?
            }
            Material::Dielectric { .. } | Material::Metal { .. } => reflect(ray.dir, hit.normal).normalize(),
            _ => return None,
        };
        ray = hit.spawn(out);
    }
    let facing = ray.dir.dot(end.normal);
    let t = (end.point - ray.origin).dot(end.normal) / facing;
    (t > 0.0 && t.is_finite()).then(|| ray.at(t))
}
