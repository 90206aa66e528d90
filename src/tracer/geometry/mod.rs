//! **Geometry**: the shapes rays meet, each in a file of its own with its robust ray test, and
//! [`hit`], what every test reports. Spheres now; quads, triangles, meshes, instances and
//! media will each be a new file here.

pub mod hit;
pub mod sphere;
