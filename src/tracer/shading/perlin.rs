//! The second book's Perlin noise: random unit vectors at the points of an integer lattice,
//! blended across each cell with a smoothed (Hermite) trilinear weight, and turbulence, a sum
//! of octaves of it. Made from a seed, never from a global generator, so a scene's marble is
//! the same on every run and every thread.

use rand::SeedableRng;
use rand::rngs::SmallRng;

use crate::tracer::math::real::{Real, Vec3};
use crate::tracer::sampling::warp::{random_unit_vector, uniform};

/// Lattice points per axis before the pattern repeats.
const POINTS: usize = 256;

/// A Perlin noise field.
#[derive(Clone, Debug, PartialEq)]
pub struct Perlin {
    gradients: Vec<Vec3>,
    permutation: [Vec<u8>; 3],
}

impl Perlin {
    /// The field of `seed` (the same seed, the same noise, on every machine).
    pub fn new(seed: u64) -> Perlin {
        let mut rng = SmallRng::seed_from_u64(seed);
        let gradients = (0..POINTS).map(|_| random_unit_vector(&mut rng)).collect();
        let permutation = std::array::from_fn(|_| {
            let mut p: Vec<u8> = (0..POINTS).map(|i| i as u8).collect();
            for i in (1..POINTS).rev() {
                let j = ((uniform(&mut rng) * (i + 1) as Real) as usize).min(i);
                p.swap(i, j);
            }
            p
        });
        Perlin { gradients, permutation }
    }

    /// Noise at `p`, in about `[−1, 1]`.
    pub fn noise(&self, p: Vec3) -> Real {
        let floor = p.floor();
        let f = p - floor;
        let smooth = f * f * (Vec3::splat(3.0) - 2.0 * f);
        let base = [floor.x as i64, floor.y as i64, floor.z as i64];
        let mut sum = 0.0;
        for corner in 0..8 {
            let (di, dj, dk) = (corner & 1, corner >> 1 & 1, corner >> 2 & 1);
            let index =
                |axis: usize, d: usize| self.permutation[axis][((base[axis] + d as i64) & 255) as usize];
            let gradient = self.gradients[(index(0, di) ^ index(1, dj) ^ index(2, dk)) as usize];
            let offset = f - Vec3::new(di as Real, dj as Real, dk as Real);
            let weight = |d: usize, s: Real| if d == 1 { s } else { 1.0 - s };
            sum += weight(di, smooth.x) * weight(dj, smooth.y) * weight(dk, smooth.z) * gradient.dot(offset);
        }
        sum
    }

    /// Turbulence: `Σ |noise(2ᵏ p)| / 2ᵏ` over `depth` octaves.
    pub fn turbulence(&self, p: Vec3, depth: u32) -> Real {
        let (mut sum, mut point, mut weight) = (0.0, p, 1.0);
        for _ in 0..depth {
            sum += weight * self.noise(point);
            weight *= 0.5;
            point *= 2.0;
        }
        sum.abs()
    }
}
