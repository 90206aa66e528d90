//! **Shading**: what light does where a ray ends. A [`material`] scatters (or absorbs) a ray
//! at a hit; the [`background`] is what a ray that escapes sees. Textures and lights will be
//! files here.

pub mod material;
pub mod background;
