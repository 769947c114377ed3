//! Colour tables: a colour index texture (8-bit indices filtered by nearest index, then looked up in a
//! palette) and the lookup after filtering (an intensity filtered as usual, then mapped through a 1D LUT).
//! The slides' "Color Index Textures" and SGI's table lookups after the texture samples.

use super::wrap::Wrap;
use super::{LookupContext, Texture, TextureOptions};
use crate::image::Image;
use glam::Vec4;
use std::sync::Arc;

/// Indices into a palette of linear RGBA colours.
pub struct IndexedTexture {
    indices: Image<u8>,
    palette: Vec<Vec4>,
    wrap: [Wrap; 2],
    border: Vec4,
}

impl IndexedTexture {
    /// `palette` in linear RGBA; every index of the image must name one of its entries.
    pub fn new(indices: Image<u8>, palette: Vec<Vec4>, wrap: [Wrap; 2], border: Vec4) -> Result<Self, String> {
        match indices.pixels.iter().max() {
            Some(&top) if top as usize >= palette.len() => Err(format!(
                "index {top} is outside the palette's {} entries (0 to {})",
                palette.len(),
                palette.len().saturating_sub(1)
            )),
            _ => Ok(IndexedTexture { indices, palette, wrap, border }),
        }
    }

    /// The palette entry of the texel nearest (s, t): texel centres at (i + 0.5) / width, t up the image.
    #[inline]
    pub fn lookup(&self, s: f32, t: f32) -> Vec4 {
        let (w, h) = (self.indices.width, self.indices.height);
        let i = (self.wrap[0].reduce(s) * w as f32).floor() as isize;
        let j = (self.wrap[1].reduce(t) * h as f32).floor() as isize;
        match (self.wrap[0].resolve(i, w), self.wrap[1].resolve(j, h)) {
            (Some(x), Some(y)) => self.palette[self.indices.get(x, h - 1 - y) as usize],
            _ => self.border,
        }
    }
}

impl Texture for IndexedTexture {
    fn eval(&self, ctx: &LookupContext) -> Vec4 {
        self.lookup(ctx.uv.x, ctx.uv.y)
    }
}

/// A texture read as an intensity (the mean of R, G, B, clamped to [0, 1]) and mapped through a table:
/// 0 reads the first entry, 1 the last, linearly in between.
pub struct LutTexture {
    intensity: Arc<dyn Texture>,
    table: Arc<[Vec4]>,
}

impl LutTexture {
    /// `table` in linear RGBA, at least one entry.
    pub fn new(intensity: Arc<dyn Texture>, table: Vec<Vec4>) -> LutTexture {
        assert!(!table.is_empty(), "a colour table has entries");
        LutTexture { intensity, table: table.into() }
    }

    #[inline]
    pub fn map(&self, c: Vec4) -> Vec4 {
        let x = ((c.x + c.y + c.z) / 3.0).clamp(0.0, 1.0) * (self.table.len() - 1) as f32;
        let k = (x as usize).min(self.table.len() - 1);
        let next = (k + 1).min(self.table.len() - 1);
        self.table[k].lerp(self.table[next], x - k as f32)
    }
}

impl Texture for LutTexture {
    fn eval(&self, ctx: &LookupContext) -> Vec4 {
        self.map(self.intensity.eval(ctx))
    }

    /// The intensity's lookup changes; the table stays.
    fn with_lookup(&self, change: &dyn Fn(&mut TextureOptions)) -> Option<Arc<dyn Texture>> {
        let intensity = self.intensity.with_lookup(change)?;
        Some(Arc::new(LutTexture { intensity, table: self.table.clone() }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_index_and_table_lookups() {
        // 2x2 indices, row 0 at the top: [0 1; 2 3].
        let indices = Image { width: 2, height: 2, pixels: vec![0, 1, 2, 3] };
        let palette: Vec<Vec4> = (0..4).map(|k| Vec4::splat(k as f32 / 10.0)).collect();
        let t = IndexedTexture::new(indices.clone(), palette.clone(), [Wrap::Repeat; 2], Vec4::ZERO).unwrap();
        // Bottom left is row 1 of the image: index 2; top right index 1; a period over, the same.
        assert_eq!(t.lookup(0.2, 0.3), palette[2]);
        assert_eq!(t.lookup(0.7, 0.8), palette[1]);
        assert_eq!(t.lookup(1.7, -0.2), palette[1]);
        let bordered = IndexedTexture::new(indices.clone(), palette.clone(), [Wrap::Border; 2], Vec4::ONE).unwrap();
        assert_eq!(bordered.lookup(1.2, 0.5), Vec4::ONE);
        let short = IndexedTexture::new(indices, palette[..3].to_vec(), [Wrap::Repeat; 2], Vec4::ZERO);
        assert_eq!(short.err().unwrap(), "index 3 is outside the palette's 3 entries (0 to 2)");
        // The table: ends exact, halfway between two entries the mean.
        struct Grey(f32);
        impl Texture for Grey {
            fn eval(&self, _: &LookupContext) -> Vec4 {
                Vec4::new(self.0, self.0, self.0, 1.0)
            }
        }
        let table = vec![Vec4::new(1.0, 0.0, 0.0, 1.0), Vec4::new(0.0, 1.0, 0.0, 1.0), Vec4::new(0.0, 0.0, 1.0, 1.0)];
        let lut = LutTexture::new(Arc::new(Grey(0.0)), table.clone());
        assert_eq!(lut.map(Vec4::ZERO), table[0]);
        assert_eq!(lut.map(Vec4::ONE), table[2]);
        assert_eq!(lut.map(Vec4::splat(0.25)), Vec4::new(0.5, 0.5, 0.0, 1.0));
        assert_eq!(lut.map(Vec4::splat(7.0)), table[2]);
    }
}
