//! Textures: sources sampled at (u,v) with the pixel's footprint in texture space.

pub mod footprint;
pub mod image_texture;

pub use footprint::Footprint;
pub use image_texture::ImageTexture;

use glam::{Vec2, Vec3, Vec4};

/// Anything that can be looked up at (u,v). The footprint tells the lookup how large the pixel is,
/// so that a filter can integrate over it; filters plug in here without touching the shader.
pub trait Texture: Send + Sync {
    /// Linear-light RGBA at `uv` (one period is [0,1]; the source decides how it wraps).
    fn sample(&self, uv: Vec2, footprint: &Footprint) -> Vec4;

    /// The lookup at a surface point: solid textures read the object-space point (u = x, v = y, w = z);
    /// every other texture reads (u,v) as `sample` does.
    fn sample_at(&self, uv: Vec2, footprint: &Footprint, _solid: &SolidPoint) -> Vec4 {
        self.sample(uv, footprint)
    }
}

/// The object-space point of a surface sample and the size of its pixel there (the square root of the
/// area spanned by the screen steps dP/dx, dP/dy), for solid textures.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SolidPoint {
    pub p: Vec3,
    pub width: f32,
}

/// Wraps a coordinate into [0, 1) periodically.
#[inline]
pub fn wrap01(x: f32) -> f32 {
    let f = x - x.floor();
    // x slightly below an integer can round to exactly 1.0.
    if f >= 1.0 {
        0.0
    } else {
        f
    }
}

/// The two texels around `s` (one period per unit, texel centres at (i + 0.5) / n, periodic) and the
/// weight of the second: the bilinear taps along one axis. No division and no modulo: this runs per sample.
#[inline]
pub fn bilinear_taps(s: f32, n: usize) -> (usize, usize, f32) {
    let x = wrap01(s) * n as f32 + 0.5;
    // x is in [0.5, n + 0.5]: truncation is the floor, and x - 1 is the position in texel-centre units.
    let k = x as usize;
    let f = x - k as f32;
    let i0 = if k == 0 { n - 1 } else { k - 1 };
    let i1 = if k >= n { k - n } else { k };
    (i0.min(n - 1), i1.min(n - 1), f)
}
