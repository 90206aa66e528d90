//! **The book's tracer**, in rooms that each hold one family, read in this order:
//!
//! | room | what it holds |
//! |---|---|
//! | [`math`] | the scalar and vector types, angles as fractions of a turn, rays |
//! | [`sampling`] | a pixel sample's random numbers: the sampler interface, independent and Sobol streams, warps |
//! | [`geometry`] | the shapes rays meet (spheres, moving spheres, quads, triangles) and what a hit reports |
//! | [`shading`] | materials (lights and fog's phase function among them), textures and the background |
//! | [`accel`] | finding the nearest hit fast: SIMD packets, the binary tree, the four-wide tree |
//! | [`world`] | what the second book builds from shapes: groups, meshes, instances, media |
//! | [`lights`] | what the lights are: one `Light` per emitting shape, chosen by power, their densities, where light paths start, and the glass balls light is aimed through |
//! | [`camera`] | rays from pixels through a thin lens |
//! | [`scene`] | the scene that holds them all, and the one hit search that dispatches to the chosen tree |
//! | [`lighting`] | how a path finds the lights: a material's bounce, the mixture, multiple importance sampling, manifold samples, the lights' edges |
//! | [`guiding`] | path guiding: where light came from, learnt pass by pass in an SD-tree, and bounces drawn from it |
//! | [`splats`] | light that lands in another pixel than the sample that carried it, summed in fixed point so any order of tiles adds to the same bits |
//! | [`bidir`] | bidirectional path tracing: camera and light paths joined, weighted over every strategy |
//! | [`tile`] | how an image is cut into tiles, and tiles into shards; a tile's running pixel sums |
//! | [`render`] | the one render loop that turns a tile of pixels into colours |
//!
//! A room uses only the rooms listed before it in this table (`tests/layers.rs` checks it, and
//! that they are declared in this order), so a new shape, texture or light lands in its own
//! room without reaching into a later one.
//!
//! This is the lowest layer. It may use only itself, [`crate::error`] and outside crates; it
//! knows nothing of files, scene formats, threads or measurement. Everything above uses it:
//! [`crate::scenes`] builds a [`scene::Scene`], [`crate::schedule`] calls
//! [`render::render_tile`] on many threads, [`crate::files`] stores its [`render::TileOutput`]s.

pub mod math;
pub mod sampling;
pub mod geometry;
pub mod shading;
pub mod accel;
pub mod world;
pub mod lights;
pub mod camera;
pub mod scene;
pub mod lighting;
pub mod guiding;
pub mod splats;
pub mod bidir;
pub mod tile;
pub mod render;
