//! **The world** the second book builds from shapes: an [`object`] (any one thing a scene
//! holds: a shape, a triangle [`mesh`], a group of objects with its own tree, an instance that
//! places a group by a rigid transform — the ray moves, not the geometry — or a participating
//! medium inside any closed group). It stands on `accel`'s trees, which it reuses for every
//! kind, and searches a group's objects in [`runs`], its quads eight at once. Meshes
//! are flat and indexed, with their own tree. Which of these objects emit, and
//! how they are aimed at, is the next room's, `lights`.
//!
//! A scene of the first book's spheres and materials never touches this room: it keeps its
//! own sphere search, and its rays pay for nothing here (`scene.rs`, `render.rs`).

mod bounds;
pub mod mesh;
pub mod object;
pub mod probe;
pub mod runs;
