//! **The light arriving at one place, as a distribution over directions**: Müller, Gross and
//! Novák's directional quadtree ("Practical Path Guiding", 2017, §3.2). The sphere of
//! directions is laid flat on the unit square by an equal-area map (`cos θ` and `φ`, each
//! scaled to `[0, 1)`), so a piece of the square holds a share of the sphere's solid angle
//! equal to its share of the square's area; the square is cut into quadrants, and quadrants
//! into quadrants again, finely where much light arrives and coarsely where little does.
//!
//! A [`Quadtree`] is the cut alone (learning fills one in, `learning.rs`); [`Directions`] is a
//! cut with the energy learnt in each piece: what a guided bounce draws from.
//!
//! Invariants: node 0 is the root; every node has four slots, quadrant `q` = (right half) +
//! 2 × (upper half), each a leaf (child 0) or the index of a later node, so a pass over the
//! nodes from last to first sees every child before its parent. A slot's energy is the sum
//! of its subtree's leaves'. [`Directions::sample`] draws with exactly the density that
//! [`Directions::pdf`] states (up to the rounding of a direction on a leaf's border), which
//! `tests/guiding.rs` checks by a χ² test.

use crate::tracer::math::real::consts::{FRAC_1_PI, PI};
use crate::tracer::math::real::{Real, Vec3};
use crate::tracer::math::turn::sin_cos_turn;

/// The deepest a quadtree cuts: leaves of 2⁻²⁰ of the square's side (Müller et al.'s limit).
const MAX_DEPTH: u32 = 20;

/// The point of the unit square that the equal-area map sends the unit direction `dir` to:
/// `((cos θ + 1)/2, φ/2π)` about +z.
#[inline]
pub fn to_square(dir: Vec3) -> [Real; 2] {
    let u = ((dir.z.clamp(-1.0, 1.0) + 1.0) * 0.5).min(LAST_BELOW_ONE);
    let turns = atan2_turns(dir.y, dir.x);
    let v = if turns < 0.0 { turns + 1.0 } else { turns };
    [u, v.min(LAST_BELOW_ONE)]
}

/// `atan2(y, x)` in turns (`[−½, ½]`), to within 10⁻⁸ turn: Abramowitz and Stegun's
/// polynomial 4.4.49 for the arctangent of a ratio at most 1 (error 2·10⁻⁸ rad), folded to
/// the octant. Written out because `to_square` runs at every guided bounce, and libm's
/// `atan2f` took a fifth of the guide's time there.
#[inline]
fn atan2_turns(y: Real, x: Real) -> Real {
    const A: [Real; 8] = [
        -0.333_331_45,
        0.199_935_51,
        -0.142_089,
        0.106_562_64,
        -0.075_289_64,
        0.042_909_614,
        -0.016_165_737,
        0.002_866_225_7,
    ];
    let (ax, ay) = (x.abs(), y.abs());
    let (low, high) = if ay > ax { (ax, ay) } else { (ay, ax) };
    let a = if high > 0.0 { low / high } else { 0.0 };
    let s = a * a;
    let poly = A.iter().rev().fold(0.0, |acc, &c| acc * s + c);
    let mut turns = a * (1.0 + s * poly) * (0.5 * FRAC_1_PI);
    if ay > ax {
        turns = 0.25 - turns;
    }
    if x < 0.0 {
        turns = 0.5 - turns;
    }
    if y < 0.0 { -turns } else { turns }
}

/// The unit direction of the square's point `p`: [`to_square`]'s inverse.
#[inline]
pub fn to_sphere(p: [Real; 2]) -> Vec3 {
    let z = 2.0 * p[0] - 1.0;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let (sin, cos) = sin_cos_turn(p[1]);
    Vec3::new(r * cos, r * sin, z)
}

/// The largest number below 1: a coordinate is kept inside the square's half-open range.
const LAST_BELOW_ONE: Real = 1.0 - Real::EPSILON / 2.0;

/// How the unit square is cut: one entry per node, its four slots' children (0: a leaf).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Quadtree {
    nodes: Vec<[u32; 4]>,
}

impl Default for Quadtree {
    /// The root alone: four quadrants, each a leaf.
    fn default() -> Quadtree {
        Quadtree { nodes: vec![[0; 4]] }
    }
}

impl Quadtree {
    /// How many nodes (each of four slots).
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// Never: a quadtree always has its root.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// The leaf slot holding the square's point `p`: its node and quadrant.
    #[inline]
    pub fn leaf_of(&self, p: [Real; 2]) -> (usize, usize) {
        let [mut x, mut y] = p;
        let mut node = 0;
        loop {
            let (right, up) = (x >= 0.5, y >= 0.5);
            let q = usize::from(right) + 2 * usize::from(up);
            // Doubling and taking a half off are exact in binary floating point.
            (x, y) = (2.0 * x - Real::from(u8::from(right)), 2.0 * y - Real::from(u8::from(up)));
            match self.nodes[node][q] {
                0 => return (node, q),
                child => node = child as usize,
            }
        }
    }

    /// The cut the next pass learns into, from this one's `energy` (per node and slot): a
    /// slot is cut into four if it holds more than `threshold` of the total energy (Müller et
    /// al.'s ρ = 0.01), down to `MAX_DEPTH`; where this cut has a leaf, its energy is taken
    /// as spread evenly over the four quarters. Nothing learnt: the root alone.
    pub fn refined(&self, energy: &[[f64; 4]], threshold: f64) -> Quadtree {
        let total: f64 = energy[0].iter().sum();
        let mut nodes = vec![[0u32; 4]];
        if total <= 0.0 {
            return Quadtree { nodes };
        }
        // (the new node, the old node it copies if any, its slots' energies, its depth).
        let mut stack = vec![(0usize, Some(0usize), energy[0], 1u32)];
        while let Some((new, old, slots, depth)) = stack.pop() {
            for (q, &e) in slots.iter().enumerate() {
                if e <= threshold * total || depth >= MAX_DEPTH {
                    continue;
                }
                let old_child = old.map(|o| self.nodes[o][q] as usize).filter(|&c| c != 0);
                let quarters = old_child.map_or([e / 4.0; 4], |c| energy[c]);
                nodes[new][q] = nodes.len() as u32;
                nodes.push([0; 4]);
                stack.push((nodes.len() - 1, old_child, quarters, depth + 1));
            }
        }
        Quadtree { nodes }
    }

    /// Every slot's energy, from the leaves' `leaves` (per node and slot; an interior slot's
    /// own entry is ignored): each interior slot the sum of its child's four.
    pub fn summed(&self, mut leaves: Vec<[f64; 4]>) -> Vec<[f64; 4]> {
        for node in (0..self.nodes.len()).rev() {
            for q in 0..4 {
                let child = self.nodes[node][q] as usize;
                if child != 0 {
                    leaves[node][q] = leaves[child].iter().sum();
                }
            }
        }
        leaves
    }
}

/// A learnt distribution of arriving light over directions: a [`Quadtree`], the energy of
/// each of its slots, and, for drawing, each slot's share of its node's energy.
#[derive(Clone, Debug, PartialEq)]
pub struct Directions {
    shape: Quadtree,
    energy: Vec<[f64; 4]>,
    /// Per node, its slots' children and shares, together (32 bytes: half a cache line).
    nodes: Vec<Node>,
}

/// A node as drawing reads it.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Node {
    child: [u32; 4],
    /// Each slot's energy over the node's (all 0 if the node has none).
    share: [Real; 4],
}

impl Directions {
    /// The cut `shape` with the leaves' energies `leaves` (per node and slot), summed up.
    ///
    /// # Panics
    /// If `leaves` does not hold one entry per node.
    pub fn new(shape: Quadtree, leaves: Vec<[f64; 4]>) -> Directions {
        assert_eq!(leaves.len(), shape.len(), "one entry per node");
        let energy = shape.summed(leaves);
        let nodes = shape
            .nodes
            .iter()
            .zip(&energy)
            .map(|(&child, e)| {
                let sum: f64 = e.iter().sum();
                let share = e.map(|e| if sum > 0.0 { (e / sum) as Real } else { 0.0 });
                Node { child, share }
            })
            .collect();
        Directions { shape, energy, nodes }
    }

    /// The cut.
    pub fn shape(&self) -> &Quadtree {
        &self.shape
    }

    /// Every slot's energy (per node).
    pub fn energy(&self) -> &[[f64; 4]] {
        &self.energy
    }

    /// All the energy learnt: 0 where nothing was, and then nothing can be drawn.
    pub fn total(&self) -> f64 {
        self.energy[0].iter().sum()
    }

    /// A direction drawn in proportion to the energy, from two uniform numbers `u`, and its
    /// density (as [`Directions::pdf`] states it): at each node a quadrant chosen by its
    /// energy (a half by `u[0]`, then a quarter of it by `u[1]`, each number stretched back
    /// over `[0, 1)` for the next choice), then a point uniformly in the leaf. `None` if
    /// nothing was learnt.
    #[inline]
    pub fn sample(&self, u: [Real; 2]) -> Option<(Vec3, Real)> {
        if self.total() <= 0.0 {
            return None;
        }
        let [mut x, mut y] = u;
        let (mut corner, mut size, mut node, mut density) = ([0.0; 2], 1.0, 0usize, 1.0);
        loop {
            let Node { child, share } = self.nodes[node];
            // The shares sum to 1: `x` is uniform over the two halves' shares together.
            let right = choose(&mut x, share[0] + share[2], share[1] + share[3]);
            let h = usize::from(right);
            y *= share[h] + share[h + 2];
            let up = choose(&mut y, share[h], share[h + 2]);
            let q = h + 2 * usize::from(up);
            density *= 4.0 * share[q];
            size *= 0.5;
            let step = [right, up].map(|b| size * Real::from(u8::from(b)));
            corner = [corner[0] + step[0], corner[1] + step[1]];
            match child[q] {
                0 => {
                    let p = [corner[0] + size * x, corner[1] + size * y].map(|c| c.min(LAST_BELOW_ONE));
                    return Some((to_sphere(p), density * (0.25 / PI)));
                }
                next => node = next as usize,
            }
        }
    }

    /// The density (per unit solid angle) with which [`Directions::sample`] draws the unit
    /// direction `dir`: each quadrant's share of its node's energy times four, down to the
    /// leaf, over the sphere's 4π.
    #[inline]
    pub fn pdf(&self, dir: Vec3) -> Real {
        let [mut x, mut y] = to_square(dir);
        let (mut density, mut node): (Real, usize) = (1.0, 0);
        loop {
            let Node { child, share } = self.nodes[node];
            let (right, up) = (x >= 0.5, y >= 0.5);
            let q = usize::from(right) + 2 * usize::from(up);
            density *= 4.0 * share[q];
            (x, y) = (2.0 * x - Real::from(u8::from(right)), 2.0 * y - Real::from(u8::from(up)));
            match child[q] {
                _ if density == 0.0 => return 0.0,
                0 => return density * (0.25 / PI),
                next => node = next as usize,
            }
        }
    }
}

/// Chooses between two parts of shares `a` and `b` (not both 0) by `u`, uniform in
/// `[0, a + b)`: the second (`true`) if `u` falls past `a`, never a part of share 0; `u` is
/// stretched back over `[0, 1)` within the part chosen, so it can choose again. One division.
#[inline]
fn choose(u: &mut Real, a: Real, b: Real) -> bool {
    let second = b > 0.0 && (a == 0.0 || *u >= a);
    *u = if second { (*u - a) / b } else { *u / a };
    *u = u.clamp(0.0, LAST_BELOW_ONE);
    second
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_arctangent_in_turns_is_within_its_bound() {
        for k in 0..100_000 {
            let angle = std::f64::consts::TAU * (k as f64 / 100_000.0 - 0.5);
            let (y, x) = (angle.sin() * 3.0, angle.cos() * 3.0);
            let exact = y.atan2(x) / std::f64::consts::TAU;
            let ours = atan2_turns(y as Real, x as Real) as f64;
            assert!((ours - exact).abs() < 2e-7, "{angle}: {ours} against {exact}");
        }
    }

    #[test]
    fn the_map_and_its_inverse_agree() {
        for p in [[0.1, 0.2], [0.5, 0.5], [0.9, 0.95], [0.3, 0.01]] {
            let back = to_square(to_sphere(p));
            assert!((back[0] - p[0]).abs() < 1e-5 && (back[1] - p[1]).abs() < 1e-5, "{p:?} → {back:?}");
        }
    }

    #[test]
    fn energy_sums_up_and_refinement_follows_it() {
        // A cut with one interior node under the root's quadrant 3.
        let shape = Quadtree { nodes: vec![[0, 0, 0, 1], [0; 4]] };
        let directions = Directions::new(shape, vec![[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 9.0]]);
        assert_eq!(directions.energy()[0], [1.0, 0.0, 0.0, 9.0]);
        // 9/10 under quadrant 3, and 9/10 again in its own quadrant 3: cut there, and deeper.
        let refined = directions.shape().refined(directions.energy(), 0.2);
        assert!(refined.leaf_of([0.9, 0.9]).0 > 1);
        // A density over the sphere integrates to 1: its pieces' solid angles weigh it.
        let n = 200;
        let mut integral = 0.0;
        for i in 0..n {
            for j in 0..n {
                let p = [(i as Real + 0.5) / n as Real, (j as Real + 0.5) / n as Real];
                integral += directions.pdf(to_sphere(p)) as f64 * 4.0 * std::f64::consts::PI;
            }
        }
        assert!((integral / f64::from(n * n) - 1.0).abs() < 1e-3, "{integral}");
    }
}
