//! **The world** the second book builds from shapes, each kind in a file: an [`object`] (any
//! one thing a scene holds), a [`group`] of objects with its own tree, triangle [`mesh`]es
//! (flat, indexed, with their own tree), [`instance`]s (a group placed by a rigid transform:
//! the ray moves, not the geometry) and participating [`medium`]s (fog and smoke inside any
//! closed object). It stands on `accel`'s trees, which it reuses for every kind.
//!
//! A scene of the first book's spheres and materials never touches this room: it keeps its
//! own sphere search, and its rays pay for nothing here (`scene.rs`, `render.rs`).

pub mod object;
pub mod group;
pub mod mesh;
pub mod instance;
pub mod medium;
