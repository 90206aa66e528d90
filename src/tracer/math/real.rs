//! The renderer's scalar and vector types.
//!
//! Everything numeric in the renderer is written against [`Real`] and [`Vec3`], so one cargo
//! feature (`f64`) switches the whole tracer between single and double precision for accuracy
//! comparisons. f32 is the default: it is twice as dense in cache and SIMD registers, and the
//! robust intersection code (see `geometry/sphere.rs`) makes it accurate enough for every
//! built-in scene.

#[cfg(not(feature = "f64"))]
mod precision {
    /// The renderer's scalar type (`f32`; `f64` with the `f64` feature).
    pub type Real = f32;
    /// The renderer's 3-vector: points, directions and linear RGB colours.
    pub type Vec3 = glam::Vec3A;
    /// Four scalars in one SIMD register (SSE on x86-64): four shapes tested at once.
    pub type Real4 = glam::Vec4;
    pub use std::f32::consts;
}

#[cfg(feature = "f64")]
mod precision {
    /// The renderer's scalar type (`f64` with the `f64` feature).
    pub type Real = f64;
    /// The renderer's 3-vector: points, directions and linear RGB colours.
    pub type Vec3 = glam::DVec3;
    /// Four scalars tested at once (scalar code with the `f64` feature).
    pub type Real4 = glam::DVec4;
    pub use std::f64::consts;
}

pub use precision::{Real, Real4, Vec3, consts};

/// Converts a scene file's `[x, y, z]` (always f64 on disk) to a [`Vec3`].
pub fn vec3(v: [f64; 3]) -> Vec3 {
    Vec3::new(v[0] as Real, v[1] as Real, v[2] as Real)
}

/// `x` as f32 (a no-op in the default build; rounds with the `f64` feature).
#[allow(clippy::unnecessary_cast)]
pub fn to_f32(x: Real) -> f32 {
    x as f32
}

/// `x` rounded down to f32: `x` itself in the default build; with the `f64` feature the
/// largest f32 not above `x`, for a bound that may err low but never high.
///
/// ```
/// use raypool::tracer::math::real::{Real, to_f32_at_most};
/// let third: Real = 1.0 / 3.0; // in f64, the nearest f32 lies above it
/// assert!(Real::from(to_f32_at_most(third)) <= third);
/// assert_eq!(to_f32_at_most(0.5), 0.5);
/// ```
pub fn to_f32_at_most(x: Real) -> f32 {
    let nearest = to_f32(x);
    // Folds away in the default build (a number is never above itself).
    if Real::from(nearest) > x { nearest.next_down() } else { nearest }
}

/// `x` as f64 (exact in both builds).
#[allow(clippy::unnecessary_cast)]
pub fn to_f64(x: Real) -> f64 {
    x as f64
}

/// `v` in f64 (exact in both builds).
#[allow(clippy::unnecessary_cast)]
pub fn to_dvec3(v: Vec3) -> glam::DVec3 {
    glam::DVec3::new(v.x as f64, v.y as f64, v.z as f64)
}

/// `v` rounded to [`Vec3`] (a no-op with the `f64` feature).
#[allow(clippy::unnecessary_cast)]
pub fn from_dvec3(v: glam::DVec3) -> Vec3 {
    Vec3::new(v.x as Real, v.y as Real, v.z as Real)
}
