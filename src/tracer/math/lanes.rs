//! **Eight lanes, in the instructions of one level.** An eight-wide node's slab test, and the
//! watertight test of a mesh leaf's eight triangles (`geometry/triangle.rs`), are whole-register
//! steps (add, subtract, multiply, divide, min, max, compare). Written as loops
//! over arrays, the compiler turned them into two four-lane (`xmm`) steps each even in the
//! copy compiled for AVX2 (`results/simd.md`); written against [`Lanes8`], each step is the
//! one instruction the level has: an AVX `ymm` operation through `pulp`'s token (which keeps
//! the `unsafe` of calling it inside `pulp`), or two SSE steps through glam's `Vec4` at the
//! baseline ([`Baseline8`]; a loop over eight scalars, which the compiler left scalar in the
//! triangle test's comparisons, where there is no SSE or with the `f64` feature).
//!
//! Invariant: every implementation computes each lane with the same single IEEE operation, and
//! `max`/`min` return their *second* argument when the comparison is false (as `maxps` does),
//! so every level gives the same bits. With the `f64` feature every level runs [`Scalar8`].
//! The level is picked at run time by `accel/isa.rs`; the lanes live here, with the numbers,
//! because the shapes' tests below the trees use them too.

use crate::tracer::math::real::Real;

/// Eight lanes at one vector level: the operations the eight-lane slab and triangle tests need.
///
/// ```
/// use raypool::tracer::math::lanes::{Lanes8, Scalar8};
/// let lanes = Scalar8;
/// let a = lanes.load(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0]);
/// let b = lanes.splat(4.5);
/// assert_eq!(lanes.le_mask(a, b), 0b0000_1111, "lanes 0 to 3 are at most 4.5");
/// assert_eq!(lanes.store(lanes.max(a, b))[7], 8.0);
/// ```
pub trait Lanes8: Copy {
    /// Eight values in this level's register (or registers).
    type V: Copy;
    /// The eight values of `a`.
    fn load(self, a: &[Real; 8]) -> Self::V;
    /// `x` in every lane.
    fn splat(self, x: Real) -> Self::V;
    /// The lanes as an array.
    fn store(self, v: Self::V) -> [Real; 8];
    /// `a + b` per lane.
    fn add(self, a: Self::V, b: Self::V) -> Self::V;
    /// `a − b` per lane.
    fn sub(self, a: Self::V, b: Self::V) -> Self::V;
    /// `a × b` per lane.
    fn mul(self, a: Self::V, b: Self::V) -> Self::V;
    /// `a ÷ b` per lane.
    fn div(self, a: Self::V, b: Self::V) -> Self::V;
    /// `|a|` per lane (the sign bit cleared).
    fn abs(self, a: Self::V) -> Self::V;
    /// `if a > b { a } else { b }` per lane.
    fn max(self, a: Self::V, b: Self::V) -> Self::V;
    /// `if a < b { a } else { b }` per lane.
    fn min(self, a: Self::V, b: Self::V) -> Self::V;
    /// Bit `k` set where `a[k] <= b[k]` (false for a NaN).
    fn le_mask(self, a: Self::V, b: Self::V) -> u32;
    /// Bit `k` set where `a[k] < b[k]` (false for a NaN).
    fn lt_mask(self, a: Self::V, b: Self::V) -> u32;
    /// Bit `k` set where `a[k] == b[k]` (false for a NaN).
    fn eq_mask(self, a: Self::V, b: Self::V) -> u32;
}

/// Code to run with the eight-lane operations of some level ([`Isa::run_lanes`]): generic,
/// because a closure cannot be.
///
/// [`Isa::run_lanes`]: crate::tracer::accel::isa::Isa::run_lanes
pub trait WithLanes8 {
    /// What the code returns.
    type Output;
    /// Runs the code with `lanes`.
    fn run<L: Lanes8>(self, lanes: L) -> Self::Output;
}

/// Eight lanes as an array of scalars: every level with the `f64` feature, and the baseline
/// where there is no SSE.
#[derive(Clone, Copy, Debug, Default)]
pub struct Scalar8;

/// The lanes of the build's own instructions: [`Sse8`] on x86-64, else [`Scalar8`].
#[cfg(all(target_arch = "x86_64", not(feature = "f64")))]
pub type Baseline8 = Sse8;
/// The lanes of the build's own instructions: [`Sse8`] on x86-64, else [`Scalar8`].
#[cfg(not(all(target_arch = "x86_64", not(feature = "f64"))))]
pub type Baseline8 = Scalar8;

impl Scalar8 {
    #[inline(always)]
    fn each(a: [Real; 8], b: [Real; 8], op: impl Fn(Real, Real) -> Real) -> [Real; 8] {
        std::array::from_fn(|k| op(a[k], b[k]))
    }
}

impl Lanes8 for Scalar8 {
    type V = [Real; 8];
    #[inline(always)]
    fn load(self, a: &[Real; 8]) -> [Real; 8] {
        *a
    }
    #[inline(always)]
    fn splat(self, x: Real) -> [Real; 8] {
        [x; 8]
    }
    #[inline(always)]
    fn store(self, v: [Real; 8]) -> [Real; 8] {
        v
    }
    #[inline(always)]
    fn add(self, a: [Real; 8], b: [Real; 8]) -> [Real; 8] {
        Scalar8::each(a, b, |a, b| a + b)
    }
    #[inline(always)]
    fn sub(self, a: [Real; 8], b: [Real; 8]) -> [Real; 8] {
        Scalar8::each(a, b, |a, b| a - b)
    }
    #[inline(always)]
    fn mul(self, a: [Real; 8], b: [Real; 8]) -> [Real; 8] {
        Scalar8::each(a, b, |a, b| a * b)
    }
    #[inline(always)]
    fn div(self, a: [Real; 8], b: [Real; 8]) -> [Real; 8] {
        Scalar8::each(a, b, |a, b| a / b)
    }
    #[inline(always)]
    fn abs(self, a: [Real; 8]) -> [Real; 8] {
        a.map(Real::abs)
    }
    #[inline(always)]
    fn max(self, a: [Real; 8], b: [Real; 8]) -> [Real; 8] {
        Scalar8::each(a, b, |a, b| if a > b { a } else { b })
    }
    #[inline(always)]
    fn min(self, a: [Real; 8], b: [Real; 8]) -> [Real; 8] {
        Scalar8::each(a, b, |a, b| if a < b { a } else { b })
    }
    #[inline(always)]
    fn le_mask(self, a: [Real; 8], b: [Real; 8]) -> u32 {
        (0..8).fold(0, |mask, k| mask | u32::from(a[k] <= b[k]) << k)
    }
    #[inline(always)]
    fn lt_mask(self, a: [Real; 8], b: [Real; 8]) -> u32 {
        (0..8).fold(0, |mask, k| mask | u32::from(a[k] < b[k]) << k)
    }
    #[inline(always)]
    fn eq_mask(self, a: [Real; 8], b: [Real; 8]) -> u32 {
        (0..8).fold(0, |mask, k| mask | u32::from(a[k] == b[k]) << k)
    }
}

#[cfg(all(target_arch = "x86_64", not(feature = "f64")))]
pub use x86::{Avx8, Sse8};

#[cfg(all(target_arch = "x86_64", not(feature = "f64")))]
mod x86 {
    use std::arch::x86_64::{__m256, _CMP_EQ_OQ, _CMP_LE_OQ, _CMP_LT_OQ};

    use glam::Vec4;

    use super::Lanes8;

    /// Eight lanes in two SSE registers (glam's `Vec4`, whose `max` and `min` are `maxps` and
    /// `minps`): the baseline, which every x86-64 has.
    #[derive(Clone, Copy, Debug, Default)]
    pub struct Sse8;

    impl Sse8 {
        #[inline(always)]
        fn each(a: [Vec4; 2], b: [Vec4; 2], op: impl Fn(Vec4, Vec4) -> Vec4) -> [Vec4; 2] {
            [op(a[0], b[0]), op(a[1], b[1])]
        }
    }

    impl Lanes8 for Sse8 {
        type V = [Vec4; 2];
        #[inline(always)]
        fn load(self, a: &[f32; 8]) -> [Vec4; 2] {
            [Vec4::new(a[0], a[1], a[2], a[3]), Vec4::new(a[4], a[5], a[6], a[7])]
        }
        #[inline(always)]
        fn splat(self, x: f32) -> [Vec4; 2] {
            [Vec4::splat(x); 2]
        }
        #[inline(always)]
        fn store(self, v: [Vec4; 2]) -> [f32; 8] {
            let ([a, b, c, d], [e, f, g, h]) = (v[0].to_array(), v[1].to_array());
            [a, b, c, d, e, f, g, h]
        }
        #[inline(always)]
        fn add(self, a: [Vec4; 2], b: [Vec4; 2]) -> [Vec4; 2] {
            Sse8::each(a, b, |a, b| a + b)
        }
        #[inline(always)]
        fn sub(self, a: [Vec4; 2], b: [Vec4; 2]) -> [Vec4; 2] {
            Sse8::each(a, b, |a, b| a - b)
        }
        #[inline(always)]
        fn mul(self, a: [Vec4; 2], b: [Vec4; 2]) -> [Vec4; 2] {
            Sse8::each(a, b, |a, b| a * b)
        }
        #[inline(always)]
        fn div(self, a: [Vec4; 2], b: [Vec4; 2]) -> [Vec4; 2] {
            Sse8::each(a, b, |a, b| a / b)
        }
        #[inline(always)]
        fn abs(self, a: [Vec4; 2]) -> [Vec4; 2] {
            [a[0].abs(), a[1].abs()]
        }
        #[inline(always)]
        fn max(self, a: [Vec4; 2], b: [Vec4; 2]) -> [Vec4; 2] {
            Sse8::each(a, b, Vec4::max)
        }
        #[inline(always)]
        fn min(self, a: [Vec4; 2], b: [Vec4; 2]) -> [Vec4; 2] {
            Sse8::each(a, b, Vec4::min)
        }
        #[inline(always)]
        fn le_mask(self, a: [Vec4; 2], b: [Vec4; 2]) -> u32 {
            a[0].cmple(b[0]).bitmask() | a[1].cmple(b[1]).bitmask() << 4
        }
        #[inline(always)]
        fn lt_mask(self, a: [Vec4; 2], b: [Vec4; 2]) -> u32 {
            a[0].cmplt(b[0]).bitmask() | a[1].cmplt(b[1]).bitmask() << 4
        }
        #[inline(always)]
        fn eq_mask(self, a: [Vec4; 2], b: [Vec4; 2]) -> u32 {
            a[0].cmpeq(b[0]).bitmask() | a[1].cmpeq(b[1]).bitmask() << 4
        }
    }

    /// Eight lanes in one AVX register, through `pulp`'s proof that the CPU has AVX2.
    #[derive(Clone, Copy, Debug)]
    pub struct Avx8(pub pulp::x86::V3);

    impl Lanes8 for Avx8 {
        type V = __m256;
        #[inline(always)]
        fn load(self, a: &[f32; 8]) -> __m256 {
            pulp::cast(*a)
        }
        #[inline(always)]
        fn splat(self, x: f32) -> __m256 {
            self.0.avx._mm256_set1_ps(x)
        }
        #[inline(always)]
        fn store(self, v: __m256) -> [f32; 8] {
            pulp::cast(v)
        }
        #[inline(always)]
        fn add(self, a: __m256, b: __m256) -> __m256 {
            self.0.avx._mm256_add_ps(a, b)
        }
        #[inline(always)]
        fn sub(self, a: __m256, b: __m256) -> __m256 {
            self.0.avx._mm256_sub_ps(a, b)
        }
        #[inline(always)]
        fn mul(self, a: __m256, b: __m256) -> __m256 {
            self.0.avx._mm256_mul_ps(a, b)
        }
        #[inline(always)]
        fn div(self, a: __m256, b: __m256) -> __m256 {
            self.0.avx._mm256_div_ps(a, b)
        }
        #[inline(always)]
        fn abs(self, a: __m256) -> __m256 {
            self.0.avx._mm256_andnot_ps(self.splat(-0.0), a)
        }
        #[inline(always)]
        fn max(self, a: __m256, b: __m256) -> __m256 {
            self.0.avx._mm256_max_ps(a, b)
        }
        #[inline(always)]
        fn min(self, a: __m256, b: __m256) -> __m256 {
            self.0.avx._mm256_min_ps(a, b)
        }
        #[inline(always)]
        fn le_mask(self, a: __m256, b: __m256) -> u32 {
            self.0.avx._mm256_movemask_ps(self.0.avx._mm256_cmp_ps::<_CMP_LE_OQ>(a, b)) as u32
        }
        #[inline(always)]
        fn lt_mask(self, a: __m256, b: __m256) -> u32 {
            self.0.avx._mm256_movemask_ps(self.0.avx._mm256_cmp_ps::<_CMP_LT_OQ>(a, b)) as u32
        }
        #[inline(always)]
        fn eq_mask(self, a: __m256, b: __m256) -> u32 {
            self.0.avx._mm256_movemask_ps(self.0.avx._mm256_cmp_ps::<_CMP_EQ_OQ>(a, b)) as u32
        }
    }
}
