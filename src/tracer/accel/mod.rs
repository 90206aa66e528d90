//! **Acceleration**: finding a ray's nearest hit without testing every shape. Spheres four at
//! a time in SIMD lanes ([`packet`]), the binary SAH tree ([`bvh`]), the four-wide tree
//! collapsed from it ([`wide`]) and the eight-wide one meshes keep ([`wide8`]), whose slab test
//! runs in eight lanes of the vector level the CPU offers ([`isa`], which picks
//! [`lanes`](crate::tracer::math::lanes) for it). Each answers with the same [`Closest`] hit, whichever
//! [`Accel`] the scene chose, so `--accel` changes the time, never the image. The choice itself
//! (the [`Accel`] enum, and the sphere counts from which each tree is the default) lives with
//! the scene that makes it, in `scene.rs`.
//!
//! [`Closest`]: crate::tracer::geometry::hit::Closest
//! [`Accel`]: crate::tracer::scene::Accel

pub mod packet;
pub mod bvh;
pub mod wide;
pub mod wide8;
pub mod isa;
