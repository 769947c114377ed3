//! Procedural and solid textures (Perlin 1985, Peachey 1985, Perlin and Hoffert 1989): gradient noise,
//! fBm and turbulence band-limited to the pixel, the classic effects, bias and gain, and hypertexture.
//! Knows nothing of scenes or rasters.

pub mod bake;
pub mod bias_gain;
pub mod effects;
pub mod fbm;
pub mod hypertexture;
pub mod perlin;
#[cfg(all(target_arch = "x86_64", target_feature = "avx2"))]
mod simd;
#[cfg(target_arch = "x86_64")]
mod simd512;
pub mod solid;

pub use perlin::{NoiseD, Perlin, Variant};
