//! A colour texture from an 8-bit image: sRGB texels decoded to linear light, bilinear reconstruction,
//! periodic wrap and a replication count.

use super::{bilinear_taps, Footprint, Texture};
use crate::image::{color::srgb8_decode_table, Image};
use glam::{Vec2, Vec4};

pub struct ImageTexture {
    width: usize,
    height: usize,
    texels: Vec<[u8; 4]>,
    /// Decoding of the colour channels (sRGB or linear); alpha is always linear.
    decode: [f32; 256],
    repeat: Vec2,
}

impl ImageTexture {
    /// `srgb`: the colour channels are sRGB-encoded (the default for colour images).
    pub fn new(image: Image<[u8; 4]>, srgb: bool, repeat: Vec2) -> Self {
        let decode = if srgb { srgb8_decode_table() } else { std::array::from_fn(|i| i as f32 / 255.0) };
        ImageTexture { width: image.width, height: image.height, texels: image.pixels, decode, repeat }
    }

    #[inline]
    fn texel(&self, i: usize, j_from_bottom: usize) -> Vec4 {
        let t = self.texels[(self.height - 1 - j_from_bottom) * self.width + i];
        let d = &self.decode;
        Vec4::new(d[t[0] as usize], d[t[1] as usize], d[t[2] as usize], t[3] as f32 / 255.0)
    }

    /// Bilinear reconstruction at (s,t) in [0,1) of one period, texel centres at (i + 0.5) / W.
    pub fn bilinear(&self, s: f32, t: f32) -> Vec4 {
        let (i0, i1, fx) = bilinear_taps(s, self.width);
        let (j0, j1, fy) = bilinear_taps(t, self.height);
        let bottom = self.texel(i0, j0).lerp(self.texel(i1, j0), fx);
        let top = self.texel(i0, j1).lerp(self.texel(i1, j1), fx);
        bottom.lerp(top, fy)
    }
}

impl Texture for ImageTexture {
    fn sample(&self, uv: Vec2, _footprint: &Footprint) -> Vec4 {
        let st = uv * self.repeat;
        self.bilinear(st.x, st.y)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn two_by_two() -> ImageTexture {
        // Row 0 is the top: v near 1.
        let img = Image {
            width: 2,
            height: 2,
            pixels: vec![[0, 0, 0, 255], [255, 0, 0, 255], [0, 255, 0, 255], [0, 0, 255, 255]],
        };
        ImageTexture::new(img, false, Vec2::ONE)
    }

    #[test]
    fn texel_centres_and_orientation() {
        let t = two_by_two();
        let fp = Footprint::default();
        // Bottom-left texel (row 1, column 0) is green.
        assert!((t.sample(Vec2::new(0.25, 0.25), &fp) - Vec4::new(0.0, 1.0, 0.0, 1.0)).length() < 1e-6);
        // Top-right is red.
        assert!((t.sample(Vec2::new(0.75, 0.75), &fp) - Vec4::new(1.0, 0.0, 0.0, 1.0)).length() < 1e-6);
        // Half way between all four, with periodic wrap at the corner.
        assert!((t.sample(Vec2::new(0.0, 0.0), &fp) - Vec4::new(0.25, 0.25, 0.25, 1.0)).length() < 1e-6);
        assert!((t.sample(Vec2::new(0.5, 0.5), &fp) - Vec4::new(0.25, 0.25, 0.25, 1.0)).length() < 1e-6);
    }

    #[test]
    fn srgb_decoded_before_filtering() {
        let img = Image { width: 1, height: 1, pixels: vec![[128, 128, 128, 255]] };
        let t = ImageTexture::new(img, true, Vec2::ONE);
        let c = t.sample(Vec2::new(0.3, 0.9), &Footprint::default());
        assert!((c.x - 0.215_861).abs() < 1e-5);
    }
}
