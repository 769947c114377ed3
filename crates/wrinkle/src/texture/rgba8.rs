//! Levels of 8-bit RGBA texels, decoded per fetch through a 256-entry table (sRGB or linear colour, linear
//! alpha): a quarter of the memory of f32 texels, so four times as much of a pyramid stays in cache. Used
//! for 8-bit sources: level 0 keeps the source bytes exactly; coarser levels are built in linear light in
//! f32 and then encoded (within one code of the exact encoding).

use super::mip::{MipFilter, Resample};
use super::texel::{Plane, TexelSource};
use super::wrap::Wrap;
use crate::image::color::{srgb8_decode_table, SrgbEncoder};
use glam::Vec4;
use rayon::prelude::*;
use std::sync::OnceLock;

#[derive(Clone, Debug)]
pub struct Rgba8Plane {
    pub width: usize,
    pub height: usize,
    /// Row 0 at the bottom.
    pub texels: Vec<[u8; 4]>,
    srgb: bool,
    decode: &'static [f32; 256],
}

fn table(srgb: bool) -> &'static [f32; 256] {
    static SRGB: OnceLock<[f32; 256]> = OnceLock::new();
    static LINEAR: OnceLock<[f32; 256]> = OnceLock::new();
    if srgb {
        SRGB.get_or_init(srgb8_decode_table)
    } else {
        LINEAR.get_or_init(|| std::array::from_fn(|i| i as f32 / 255.0))
    }
}

impl Rgba8Plane {
    /// Bytes as stored in an image (row 0 at the top); `srgb`: the colour channels are sRGB-encoded.
    pub fn from_top_rows(width: usize, height: usize, rows: &[[u8; 4]], srgb: bool) -> Self {
        let mut texels = Vec::with_capacity(width * height);
        for j in 0..height {
            let row = height - 1 - j;
            texels.extend_from_slice(&rows[row * width..(row + 1) * width]);
        }
        Rgba8Plane { width, height, texels, srgb, decode: table(srgb) }
    }

    /// Linear texels encoded to 8 bits.
    pub fn encode(plane: &Plane<Vec4>, srgb: bool, encoder: &SrgbEncoder) -> Self {
        let unorm = |x: f32| (x.clamp(0.0, 1.0) * 255.0 + 0.5) as u8;
        let colour = |x: f32| if srgb { encoder.encode(x) } else { unorm(x) };
        let texels = plane.texels.par_iter().map(|v| [colour(v.x), colour(v.y), colour(v.z), unorm(v.w)]).collect();
        Rgba8Plane { width: plane.width, height: plane.height, texels, srgb, decode: table(srgb) }
    }

    /// The texels in linear light.
    pub fn decode(&self) -> Plane<Vec4> {
        let texels =
            (0..self.width * self.height).into_par_iter().map(|k| self.texel(k % self.width, k / self.width)).collect();
        Plane { width: self.width, height: self.height, texels }
    }
}

impl TexelSource for Rgba8Plane {
    type Texel = Vec4;
    #[inline]
    fn width(&self) -> usize {
        self.width
    }
    #[inline]
    fn height(&self) -> usize {
        self.height
    }
    #[inline]
    fn texel(&self, i: usize, j: usize) -> Vec4 {
        let t = self.texels[j * self.width + i];
        let d = self.decode;
        Vec4::new(d[t[0] as usize], d[t[1] as usize], d[t[2] as usize], t[3] as f32 * (1.0 / 255.0))
    }
}

impl Resample for Rgba8Plane {
    fn downsample(&self, nw: usize, nh: usize, filter: MipFilter, wrap: [Wrap; 2]) -> Self {
        Rgba8Plane::encode(&self.decode().downsample(nw, nh, filter, wrap), self.srgb, &SrgbEncoder::new())
    }
}
