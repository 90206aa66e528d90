//! **Numbers and rays**, the floor every other room stands on: the scalar and vector types
//! ([`real`], f32 by default, f64 with the `f64` feature; [`lanes`], eight of them in the
//! instructions of one vector level, for the tests that run eight at once), angles as fractions of a turn
//! ([`turn`]), the [`ray`], axis-aligned boxes ([`aabb`]) and rigid placements
//! ([`transform`]).

pub mod real;
pub mod lanes;
pub mod turn;
pub mod ray;
pub mod aabb;
pub mod transform;
