//! The checks every part of a scene file shares: a condition with its message, a colour, a
//! finite point. Lowest in `scenes/`: the format, its looks, its shapes and its files use them.

/// `Ok` if `ok`, else the message.
pub fn check(ok: bool, message: impl FnOnce() -> String) -> Result<(), String> {
    if ok { Ok(()) } else { Err(message()) }
}

/// A colour: finite and ≥ 0 in every channel.
pub fn colour(v: [f64; 3]) -> Result<(), String> {
    check(v.iter().all(|x| x.is_finite() && *x >= 0.0), || format!("must be finite and ≥ 0, got {v:?}"))
}

/// A finite `[x, y, z]`.
pub fn finite3(v: [f64; 3]) -> bool {
    v.iter().all(|x| x.is_finite())
}
