//! Textures: sources sampled at (u,v) with the pixel's footprint in texture space.

pub mod footprint;
pub mod image_texture;

pub use footprint::Footprint;
pub use image_texture::ImageTexture;

use glam::{Vec2, Vec4};

/// Anything that can be looked up at (u,v). The footprint tells the lookup how large the pixel is,
/// so that a filter can integrate over it; filters plug in here without touching the shader.
pub trait Texture: Send + Sync {
    /// Linear-light RGBA at `uv` (one period is [0,1]; the source decides how it wraps).
    fn sample(&self, uv: Vec2, footprint: &Footprint) -> Vec4;
}

/// Wraps a coordinate into [0, 1) periodically.
#[inline]
pub fn wrap01(x: f32) -> f32 {
    let f = x - x.floor();
    // x slightly below an integer can round to exactly 1.0.
    if f >= 1.0 { 0.0 } else { f }
}
