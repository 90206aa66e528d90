//! **Geometry**: the shapes rays meet, each in a file of its own with its robust ray test, and
//! [`hit`], what every test reports: [`sphere`]s, [`moving`] spheres (motion blur), the second
//! book's [`quad`]s (and boxes of six; [`quads`] tests eight at once), pbrt's [`disc`]s, and
//! [`triangle`]s (the watertight test meshes use); and the [`cone`] a sphere fills seen from a
//! point, by which a sphere light is aimed at.
//! What is built from them (meshes, instances, media) is the `world` room's.

pub mod hit;
pub mod sphere;
pub mod moving;
pub mod quad;
pub mod quads;
pub mod disc;
pub mod triangle;
pub mod cone;
