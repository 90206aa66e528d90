//! **Shading**: what light does where a ray ends. A [`material`] scatters (or absorbs, or
//! emits) at a hit; a [`texture`] gives a surface its colour (the marble's from [`perlin`]
//! noise); the [`background`] is what a ray that escapes sees.

pub mod perlin;
pub mod texture;
pub mod material;
pub mod background;
