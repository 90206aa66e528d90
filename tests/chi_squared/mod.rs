//! The χ² goodness-of-fit machinery of the sampling tests (`sampling.rs`, `sampling_paths.rs`),
//! as pbrt's and Mitsuba's: bins of equal solid angle over the sphere or a cone of it, the
//! counts a stated density predicts in each (integrated over the bin), Pearson's χ² with the
//! sparse bins pooled, and its upper-tail probability.
#![allow(dead_code)]

use glam::DVec3;
use rand::SeedableRng;
use rand::rngs::SmallRng;
use raypool::tracer::geometry::hit::Hit;
use raypool::tracer::math::real::{Real, Vec3};

const TAU: f64 = std::f64::consts::TAU;

/// Bins of equal solid angle in the cone of directions within `acos(cos_min)` of `axis`:
/// `bands` bands evenly in `cos θ` about it, each cut into `sectors` evenly in `φ` (measured
/// from `u` towards `v`; `axis`, `u`, `v` orthonormal).
pub struct Cone {
    axis: DVec3,
    u: DVec3,
    v: DVec3,
    cos_min: f64,
    bands: usize,
    sectors: usize,
}

impl Cone {
    /// The whole sphere, about +z, `φ` from +x.
    pub fn sphere(bands: usize, sectors: usize) -> Cone {
        Cone { axis: DVec3::Z, u: DVec3::X, v: DVec3::Y, cos_min: -1.0, bands, sectors }
    }

    /// The directions within `half_angle` (radians) of the unit `axis`.
    pub fn about(axis: Vec3, half_angle: f64, bands: usize, sectors: usize) -> Cone {
        let axis = wide(axis).normalize();
        let (u, v) = axis.any_orthonormal_pair();
        Cone { axis, u, v, cos_min: half_angle.cos(), bands, sectors }
    }

    /// How many bins.
    pub fn len(&self) -> usize {
        self.bands * self.sectors
    }

    /// The bin of a unit direction; `None` outside the cone.
    pub fn bin(&self, d: Vec3) -> Option<usize> {
        let d = wide(d);
        let cos = d.dot(self.axis);
        if self.cos_min > -1.0 && cos < self.cos_min - 1e-9 {
            return None;
        }
        let bands = self.bands as f64;
        let band = ((cos - self.cos_min) / (1.0 - self.cos_min) * bands).clamp(0.0, bands - 1.0) as usize;
        let phi = d.dot(self.v).atan2(d.dot(self.u)).rem_euclid(TAU) / TAU * self.sectors as f64;
        Some(band * self.sectors + (phi as usize).min(self.sectors - 1))
    }

    /// Which side of the cone `d` lies on (the sign of its component along `u`): a tilt of a
    /// density by ±5% across it is what each test must reject.
    pub fn side(&self, d: Vec3) -> f64 {
        wide(d).dot(self.u).signum()
    }

    /// The expected count in every bin of `n` directions of density `pdf` (per solid angle),
    /// by the midpoint rule on `sub` × `sub` points of each bin ([`Cone::points`]).
    pub fn expected(&self, pdf: &dyn Fn(Vec3) -> f64, n: usize, sub: usize) -> Vec<f64> {
        let mut counts = vec![0.0; self.len()];
        self.points(sub, |b, d, solid_angle| counts[b] += pdf(d) * solid_angle * n as f64);
        counts
    }

    /// Calls `each` with every bin, the midpoint of each of `sub` × `sub` pieces of it, and the
    /// piece's solid angle; the pieces are spaced evenly in angle (even in `cos θ`, they would
    /// leave a small light near a pole between them).
    pub fn points(&self, sub: usize, mut each: impl FnMut(usize, Vec3, f64)) {
        let dphi = TAU / self.sectors as f64;
        for b in 0..self.len() {
            let (zi, pi) = (b / self.sectors, b % self.sectors);
            let edge = |z: usize| {
                (self.cos_min + (1.0 - self.cos_min) * z as f64 / self.bands as f64).clamp(-1.0, 1.0).acos()
            };
            let (from, to) = (edge(zi + 1), edge(zi));
            let dtheta = (to - from) / sub as f64;
            for (i, j) in (0..sub * sub).map(|k| (k / sub, k % sub)) {
                let theta = from + dtheta * (i as f64 + 0.5);
                let phi = dphi * (pi as f64 + (j as f64 + 0.5) / sub as f64);
                let (sin, z) = theta.sin_cos();
                let (x, y) = (sin * phi.cos(), sin * phi.sin());
                let d = |k: usize| (self.u[k] * x + self.v[k] * y + self.axis[k] * z) as Real;
                each(b, Vec3::new(d(0), d(1), d(2)), sin * dtheta * dphi / sub as f64);
            }
        }
    }
}

/// A vector in double precision.
pub fn wide(v: Vec3) -> DVec3 {
    DVec3::new(v.x.into(), v.y.into(), v.z.into())
}

/// A vector in the tracer's precision.
pub fn narrow(v: DVec3) -> Vec3 {
    Vec3::new(v.x as Real, v.y as Real, v.z as Real)
}

/// Pearson's χ² of `observed` against `expected`, bins expecting fewer than 5 pooled into
/// one, and the upper-tail probability of it (Wilson–Hilferty's normal approximation), with
/// `fitted` degrees of freedom taken by the expectation (1 where it was scaled to the total
/// observed, 0 where it is absolute). Counts that the density says cannot occur (a pool
/// expecting under 5 that holds more than a few) fail at once.
pub fn chi_squared_p(observed: &[usize], expected: &[f64], fitted: usize) -> f64 {
    let (mut chi2, mut dof, mut pooled) = (0.0, 0usize, (0.0, 0.0));
    for (&o, &e) in observed.iter().zip(expected) {
        if e < 5.0 {
            pooled = (pooled.0 + o as f64, pooled.1 + e);
        } else {
            chi2 += (o as f64 - e).powi(2) / e;
            dof += 1;
        }
    }
    if pooled.1 >= 5.0 {
        chi2 += (pooled.0 - pooled.1).powi(2) / pooled.1;
        dof += 1;
    } else if pooled.0 > pooled.1 + 5.0 * (pooled.1 + 1.0).sqrt() {
        return 0.0;
    }
    let k = (dof - fitted) as f64;
    let z = ((chi2 / k).cbrt() - (1.0 - 2.0 / (9.0 * k))) / (2.0 / (9.0 * k)).sqrt();
    0.5 * erfc(z / std::f64::consts::SQRT_2)
}

/// Asserts that `observed` fits `expected` (p above `alpha`) and not `tilted` (the density
/// tilted by ±5% across the bins, deliberately wrong: p below `alpha`, the power the test
/// states). Prints both p and the smallest tilt, in steps of 0.25%, that the counts reject.
pub fn assert_fits(
    name: &str,
    observed: &[usize],
    (expected, tilted): (&[f64], &[f64]),
    fitted: usize,
    alpha: f64,
) {
    let p = chi_squared_p(observed, expected, fitted);
    let p_wrong = chi_squared_p(observed, tilted, fitted);
    let by =
        |t: f64| -> Vec<f64> { expected.iter().zip(tilted).map(|(e, w)| e + (w - e) * t / 0.05).collect() };
    let smallest =
        (1..=20).map(|k| 0.0025 * k as f64).find(|&t| chi_squared_p(observed, &by(t), fitted) < alpha);
    let smallest = smallest.map_or("none".into(), |t| format!("±{:.2}%", 100.0 * t));
    eprintln!("{name}: p = {p:.3}; tilted by ±5%: p = {p_wrong:.1e}; smallest tilt rejected: {smallest}");
    assert!(p > alpha, "{name}: the draws do not follow the stated density (p = {p:.2e})");
    assert!(p_wrong < alpha, "{name}: a density 5% off in half the bins would pass too (p = {p_wrong:.2e})");
}

/// The complementary error function (Numerical Recipes' Chebyshev fit, |error| < 1.2e-7).
fn erfc(x: f64) -> f64 {
    let t = 1.0 / (1.0 + 0.5 * x.abs());
    let poly = [
        -1.26551223,
        1.00002368,
        0.37409196,
        0.09678418,
        -0.18628806,
        0.27886807,
        -1.13520398,
        1.48851587,
        -0.82215223,
        0.17087277,
    ];
    let sum = poly.iter().rev().fold(0.0, |acc, c| acc * t + c);
    let r = t * (-x * x + sum).exp();
    if x >= 0.0 { r } else { 2.0 - r }
}

/// A hit on the front of a surface at `point`, facing `normal`: where a bounce is drawn from.
pub fn front_hit(point: Vec3, normal: Vec3) -> Hit {
    Hit { t: 1.0, point, normal, front_face: true, material: 0, offset: 0.0, lift: 0.0, u: 0.0, v: 0.0 }
}

/// Bins of [`assert_draws_follow`] in `cos θ` (about +z) and in `φ`: equal solid angle each.
const Z_BINS: usize = 16;
const PHI_BINS: usize = 32;
/// Directions [`assert_draws_follow`] draws.
const DRAWS: usize = 200_000;

/// Draws `DRAWS` directions from `draw` (seeded from `name`) and checks their counts in
/// 16 × 32 bins of the sphere against `pdf`, and that the same counts reject `pdf` tilted by
/// ±5% along x, each at significance `alpha` ([`assert_fits`]).
pub fn assert_draws_follow(
    name: &str,
    mut draw: impl FnMut(&mut SmallRng) -> Option<Vec3>,
    pdf: &dyn Fn(Vec3) -> f64,
    alpha: f64,
) {
    let mut rng = SmallRng::seed_from_u64(name.len() as u64 * 7919);
    let sphere = Cone::sphere(Z_BINS, PHI_BINS);
    let mut observed = vec![0usize; sphere.len()];
    for _ in 0..DRAWS {
        if let Some(d) = draw(&mut rng) {
            observed[sphere.bin(d).expect("the whole sphere")] += 1;
        }
    }
    // Shape, not total: the counts are compared with the density scaled to the draws made
    // (that `Lights::pdf` integrates to 1 is `tests/lights.rs`'s).
    let drawn = observed.iter().sum::<usize>() as f64;
    let scaled = |counts: Vec<f64>| {
        let total = counts.iter().sum::<f64>();
        counts.into_iter().map(|c| c * drawn / total).collect::<Vec<_>>()
    };
    let tilted = |d: Vec3| pdf(d) * (1.0 + 0.05 * sphere.side(d));
    let expected = scaled(sphere.expected(pdf, DRAWS, 64));
    let wrong = scaled(sphere.expected(&tilted, DRAWS, 64));
    assert_fits(name, &observed, (&expected, &wrong), 1, alpha);
}
