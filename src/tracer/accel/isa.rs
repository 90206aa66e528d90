//! **Wide vectors, chosen at run time.** raypool is built for baseline x86-64 (SSE2: four f32
//! lanes), so the binary runs on any x86-64; a search that [`Isa::run`]s its code on a CPU
//! with AVX2 or AVX-512 gets that code compiled again with those instructions enabled, where
//! an eight-lane [`Lanes8`](crate::tracer::math::lanes::Lanes8) operation is one instruction
//! instead of two. Calling code compiled for instructions the CPU may lack needs `unsafe`
//! (`#[target_feature]`); the `pulp` crate (faer's; already built for `image`'s EXR reader)
//! keeps that `unsafe` inside itself behind a token that exists only once the CPU has been
//! asked, so our crates stay `#![forbid(unsafe_code)]`.
//!
//! Invariant: the level changes instructions, never numbers. The code run is the same Rust at
//! every level, each lane's arithmetic one IEEE operation with nothing fused, so every search
//! finds the same hit bit for bit and an image is the same whatever the level
//! (`tests/isa.rs`).

use std::fmt;

use crate::tracer::math::lanes::{Baseline8, WithLanes8};

/// The widest vector instructions a search may use: [`Isa::best`] by default, or another
/// level asked for by name (`RAYPOOL_ISA`, for tests and benchmarks).
///
/// ```
/// use raypool::tracer::accel::isa::Isa;
/// let best = Isa::best();
/// assert_eq!(best.run(|| 6 * 7), 42, "the same answer at every level");
/// assert_eq!(Isa::named("sse2"), Ok(Isa::BASELINE));
/// assert!(Isa::named("avx3").unwrap_err().contains("sse2, avx2 or avx512"));
/// ```
#[derive(Clone, Copy)]
pub struct Isa(Level);

#[derive(Clone, Copy)]
enum Level {
    /// What every x86-64 has (or, elsewhere, what the build targets).
    Baseline,
    #[cfg(target_arch = "x86_64")]
    Avx2(pulp::x86::V3),
    #[cfg(target_arch = "x86_64")]
    Avx512(pulp::x86::V4),
}

impl Isa {
    /// The build's own instructions (SSE2 on x86-64).
    pub const BASELINE: Isa = Isa(Level::Baseline);

    /// The names [`Isa::named`] takes, lowest first.
    pub const NAMES: [&'static str; 3] = ["sse2", "avx2", "avx512"];

    /// The level a search uses unless told otherwise: the widest the CPU has. A mesh's
    /// eight-wide search gains from AVX-512's thirty-two registers even in eight lanes; the
    /// four-wide sphere tree neither gains nor loses (`results/simd.md`, `results/embree.md`).
    pub fn best() -> Isa {
        Isa::available().pop().unwrap_or(Isa::BASELINE)
    }

    /// Every level this CPU offers, lowest first (the baseline always).
    pub fn available() -> Vec<Isa> {
        Isa::NAMES.iter().filter_map(|name| Isa::named(name).ok()).collect()
    }

    /// The level called `name` (`sse2`, `avx2` or `avx512`), if this CPU has it.
    pub fn named(name: &str) -> Result<Isa, String> {
        let missing = |what: &str| Err(format!("this CPU has no {what}, so the ISA `{name}` cannot run"));
        match name {
            "sse2" => Ok(Isa::BASELINE),
            #[cfg(target_arch = "x86_64")]
            "avx2" => pulp::x86::V3::try_new()
                .map_or_else(|| missing("AVX2 and FMA"), |v3| Ok(Isa(Level::Avx2(v3)))),
            #[cfg(target_arch = "x86_64")]
            "avx512" => {
                pulp::x86::V4::try_new().map_or_else(|| missing("AVX-512"), |v4| Ok(Isa(Level::Avx512(v4))))
            }
            _ => Err(format!("unknown ISA `{name}`: it is sse2, avx2 or avx512")),
        }
    }

    /// Its name, as [`Isa::named`] takes it.
    pub fn name(self) -> &'static str {
        match self.0 {
            Level::Baseline => "sse2",
            #[cfg(target_arch = "x86_64")]
            Level::Avx2(_) => "avx2",
            #[cfg(target_arch = "x86_64")]
            Level::Avx512(_) => "avx512",
        }
    }

    /// Runs `op` compiled for this level: `op` (and what it inlines) is compiled once per
    /// level, and this picks the copy. Only code inlined into `op` gains: mark the search's
    /// functions `#[inline(always)]`.
    #[inline(always)]
    pub fn run<R>(self, op: impl FnOnce() -> R) -> R {
        match self.0 {
            Level::Baseline => op(),
            #[cfg(target_arch = "x86_64")]
            Level::Avx2(v3) => v3.vectorize(op),
            #[cfg(target_arch = "x86_64")]
            Level::Avx512(v4) => v4.vectorize(op),
        }
    }

    /// Runs `op` compiled for this level, with this level's eight-lane operations
    /// ([`Lanes8`](crate::tracer::math::lanes::Lanes8)): AVX registers at avx2 and avx512
    /// (eight lanes are what an eight-wide node needs), two SSE registers at the baseline, and
    /// eight scalars at every level in the `f64` build
    /// ([`Baseline8`] both).
    ///
    /// ```
    /// use raypool::tracer::accel::isa::Isa;
    /// use raypool::tracer::math::lanes::{Lanes8, WithLanes8};
    /// use raypool::tracer::math::real::Real;
    /// struct CountBelow(Real);
    /// impl WithLanes8 for CountBelow {
    ///     type Output = u32;
    ///     fn run<L: Lanes8>(self, lanes: L) -> u32 {
    ///         let a = lanes.load(&[0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0]);
    ///         lanes.le_mask(a, lanes.splat(self.0)).count_ones()
    ///     }
    /// }
    /// for isa in Isa::available() {
    ///     assert_eq!(isa.run_lanes(CountBelow(2.5)), 3, "the same at {isa:?}");
    /// }
    /// ```
    #[inline(always)]
    pub fn run_lanes<W: WithLanes8>(self, op: W) -> W::Output {
        match self.0 {
            Level::Baseline => op.run(Baseline8::default()),
            #[cfg(all(target_arch = "x86_64", not(feature = "f64")))]
            Level::Avx2(v3) => v3.vectorize(
                #[inline(always)]
                || op.run(crate::tracer::math::lanes::Avx8(v3)),
            ),
            #[cfg(all(target_arch = "x86_64", not(feature = "f64")))]
            Level::Avx512(v4) => v4.vectorize(
                #[inline(always)]
                || op.run(crate::tracer::math::lanes::Avx8(*v4)),
            ),
            #[cfg(all(target_arch = "x86_64", feature = "f64"))]
            Level::Avx2(v3) => v3.vectorize(
                #[inline(always)]
                || op.run(Baseline8::default()),
            ),
            #[cfg(all(target_arch = "x86_64", feature = "f64"))]
            Level::Avx512(v4) => v4.vectorize(
                #[inline(always)]
                || op.run(Baseline8::default()),
            ),
        }
    }
}

impl PartialEq for Isa {
    fn eq(&self, other: &Isa) -> bool {
        self.name() == other.name()
    }
}

impl Eq for Isa {}

impl Default for Isa {
    /// [`Isa::best`].
    fn default() -> Isa {
        Isa::best()
    }
}

impl fmt::Debug for Isa {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}
