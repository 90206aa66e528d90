//! The sine and cosine of a fraction of a turn, for the two warps that draw an angle (a
//! direction on the sphere, a point in the lens's disk).
//!
//! Those warps draw a uniform `u` in `[0, 1)` and want `sin(2πu)` and `cos(2πu)`. Going
//! through radians (`(TAU * u).sin_cos()`) costs twice: `TAU` and the product `TAU * u` are
//! rounded, an angle error of up to 4·10⁻⁷ near a full turn, and libm's `sincosf` is a call
//! that reduces its argument by π/2 again, with branches on its size, and across which the
//! caller must save every vector register it still needs (the x86-64 ABI preserves none). In
//! turns the reduction is exact and nearly free: `2u` is exact, its nearest integer `q` counts
//! half turns, and `f = 2u − q` (exact, in `[−½, ½]`) is what is left, at most a quarter turn
//! either way. Two polynomials give `sin(πf)` and `cos(πf)` there, and a half turn only
//! negates both: `q`'s lowest bit goes into their sign bits, with no branch (which half of the
//! circle a random angle falls in is a coin toss that a branch predictor would lose half the
//! time).
//!
//! Invariants: for `u` in `[0, 1]`, each result is within 2.5·10⁻⁷ of the true value (about
//! two f32 spacings at 1): the test checks every `u` an f32 draw can take against f64's sine
//! and cosine of the exact angle (the worst is 2.39·10⁻⁷, where the polynomials' own roundings
//! add up near a quarter turn; the radians route's sine is off by up to 4.1·10⁻⁷). It is exact
//! at the half turns (0 and ±1 there), and `sin² + cos²` is within 5·10⁻⁷ of 1. The `f64`
//! build keeps libm's `sin_cos`: it is the comparison build, and f64's polynomials would be
//! twice as long.

use crate::tracer::math::real::Real;

/// `sin(2πu)` and `cos(2πu)` for `u` in `[0, 1]`.
///
/// ```
/// use raypool::tracer::math::turn::sin_cos_turn;
/// assert_eq!(sin_cos_turn(0.5), (0.0, -1.0));
/// let (sin, cos) = sin_cos_turn(0.125);
/// let diagonal = std::f32::consts::FRAC_1_SQRT_2; // an eighth of a turn
/// assert!((sin - diagonal).abs() < 2.5e-7 && (cos - diagonal).abs() < 2.5e-7);
/// ```
#[cfg(not(feature = "f64"))]
#[inline]
pub fn sin_cos_turn(u: Real) -> (Real, Real) {
    // Near-minimax on f in [-1/2, 1/2] as polynomials in y = f² (a Remez fit in f64 by
    // `benches/turn_fit.py`, rounded to f32; before that rounding, relative error 5.3e-9 for
    // sin and absolute 1e-9 for cos, well below f32's own, which dominates).
    // sin(πf) = f · P(y); cos(πf) = 1 + y · Q(y), so both are exact at f = 0. (The fit's
    // first coefficient rounds to π itself.)
    const P: [f32; 5] = [std::f32::consts::PI, -5.16771, 2.550_069_8, -0.598_242_1, 0.077_560_39];
    const Q: [f32; 5] = [-4.934_802, 4.058_711_5, -1.33524, 0.235_074_76, -0.024_627_9];
    // Adding 1.5·2²³ rounds to the nearest integer (f32's spacing there is 1) and leaves it in
    // the low bits; subtracting it again is exact. (`round` would be a libm call on baseline
    // x86-64, and a cast to an integer a saturating one.)
    const ROUND: f32 = 12_582_912.0;
    let halves = 2.0 * u;
    let rounded = halves + ROUND;
    let f = halves - (rounded - ROUND);
    let y = f * f;
    let sin = f * (P[0] + y * (P[1] + y * (P[2] + y * (P[3] + y * P[4]))));
    let cos = 1.0 + y * (Q[0] + y * (Q[1] + y * (Q[2] + y * (Q[3] + y * Q[4]))));
    // An odd number of half turns negates both.
    let sign = rounded.to_bits() << 31;
    (f32::from_bits(sin.to_bits() ^ sign), f32::from_bits(cos.to_bits() ^ sign))
}

/// `sin(2πu)` and `cos(2πu)` (libm's, in the `f64` build).
///
/// ```
/// use raypool::tracer::math::turn::sin_cos_turn;
/// let (sin, cos) = sin_cos_turn(0.25);
/// assert!((sin - 1.0).abs() < 1e-15 && cos.abs() < 1e-15);
/// ```
#[cfg(feature = "f64")]
#[inline]
pub fn sin_cos_turn(u: Real) -> (Real, Real) {
    (crate::tracer::math::real::consts::TAU * u).sin_cos()
}

#[cfg(all(test, not(feature = "f64")))]
mod tests {
    use super::sin_cos_turn;

    /// Every value an f32 draw takes (multiples of 2⁻²⁴ in [0, 1)) and 1 itself, against
    /// f64's sine and cosine of the exact angle.
    #[test]
    fn every_draw_is_within_two_spacings_of_the_true_sine_and_cosine() {
        let (mut worst, mut worst_norm, mut worst_libm) = (0.0f64, 0.0f64, 0.0f64);
        for k in 0..=(1u32 << 24) {
            let u = k as f32 / (1u32 << 24) as f32;
            let (sin, cos) = sin_cos_turn(u);
            let angle = std::f64::consts::TAU * f64::from(u);
            let error = (f64::from(sin) - angle.sin()).abs().max((f64::from(cos) - angle.cos()).abs());
            worst = worst.max(error);
            let norm = f64::from(sin).mul_add(f64::from(sin), f64::from(cos) * f64::from(cos));
            worst_norm = worst_norm.max((norm - 1.0).abs());
            let (libm_sin, _) = (std::f32::consts::TAU * u).sin_cos();
            worst_libm = worst_libm.max((f64::from(libm_sin) - angle.sin()).abs());
        }
        assert!(worst <= 2.5e-7, "worst error {worst:e}");
        assert!(worst_norm <= 5e-7, "sin² + cos² off 1 by {worst_norm:e}");
        // What the radians route loses to rounding TAU · u, for the record.
        assert!(worst_libm > 1.5 * worst, "libm's route {worst_libm:e}, this {worst:e}");
    }

    #[test]
    fn half_turns_are_exact() {
        assert_eq!(sin_cos_turn(0.0), (0.0, 1.0));
        assert_eq!(sin_cos_turn(0.5), (0.0, -1.0));
        assert_eq!(sin_cos_turn(1.0), (0.0, 1.0));
    }

    #[test]
    fn each_quadrant_has_its_signs() {
        // (u, sin > 0, cos > 0): two turns' fractions in each quarter of the circle.
        let quarters = [
            (0.1, true, true),
            (0.2, true, true),
            (0.3, true, false),
            (0.45, true, false),
            (0.55, false, false),
            (0.7, false, false),
            (0.8, false, true),
            (0.95, false, true),
        ];
        for (u, sin_positive, cos_positive) in quarters {
            let (sin, cos) = sin_cos_turn(u);
            assert_eq!((sin > 0.0, cos > 0.0), (sin_positive, cos_positive), "u = {u}");
        }
    }
}
