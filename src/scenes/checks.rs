//! The checks every part of a scene file shares: a condition with its message, a colour, a
//! finite point. Lowest in `scenes/`: the format, its looks, its shapes and its files use them.

use crate::tracer::math::real::Real;

/// `Ok` if `ok`, else the message.
pub fn check(ok: bool, message: impl FnOnce() -> String) -> Result<(), String> {
    if ok { Ok(()) } else { Err(message()) }
}

/// A colour: finite and ≥ 0 in every channel, finite also in the tracer's precision (`1e39`
/// is an `f64` but would be infinite in `f32`).
pub fn colour(v: [f64; 3]) -> Result<(), String> {
    check(v.iter().all(|&x| representable(x) && x >= 0.0), || {
        format!(
            "must be finite (also as the renderer's {}) and ≥ 0, got {v:?}",
            std::any::type_name::<Real>()
        )
    })
}

/// A finite `[x, y, z]`, finite also in the tracer's precision.
pub fn finite3(v: [f64; 3]) -> bool {
    v.iter().all(|&x| representable(x))
}

/// The tracer's precision, as messages name it.
pub const REAL: &str = if cfg!(feature = "f64") { "f64" } else { "f32" };

/// Whether `x` is finite as the tracer's [`Real`] (`1e39` is a finite `f64` but an infinite
/// `f32`): every number of a scene file is checked so.
pub fn representable(x: f64) -> bool {
    (x as Real).is_finite()
}
