//! **The book's tracer**, in the book's order: numbers (and angles as fractions of a turn),
//! rays, spheres, materials, the camera, the sky, the hierarchies that find hits fast (spheres
//! four at a time in `packet`, the binary tree in `bvh`, the four-wide tree collapsed from it
//! in `wide`), the scene that holds them, random numbers, tiles and shards (how an image is
//! cut up), and the one render loop that turns a tile of pixels into colours.
//!
//! This is the bottom layer. It may use only itself, [`crate::error`] and outside crates; it
//! knows nothing of files, scene formats, threads or measurement. Everything above uses it:
//! [`crate::scenes`] builds a [`scene::Scene`], [`crate::schedule`] calls
//! [`render::render_tile`] on many threads, [`crate::files`] stores its [`render::TileOutput`]s.

pub mod real;
pub mod turn;
pub mod ray;
pub mod sphere;
pub mod material;
pub mod camera;
pub mod background;
pub mod packet;
pub mod bvh;
pub mod wide;
pub mod scene;
pub mod sampler;
pub mod tile;
pub mod render;
