//! An 8-bit texture that changes a little at a time (a paint stroke): its linear pyramid is kept beside the
//! stored one, so a change recomputes, level by level, only the texels whose filter taps read changed ones,
//! with the same arithmetic in the same order as a whole build. The result equals
//! `FilteredTexture::from_rgba8` of the whole changed image bit for bit, at a cost that follows the change.

use super::filtered::{FilteredTexture, TextureOptions};
use super::mip::{build_levels, resample_changed, Span, Taps};
use super::rgba8::{encode_texel, Rgba8Plane};
use super::texel::{Plane, TexelSource};
use crate::image::color::SrgbEncoder;
use crate::image::ImageRef;
use crate::{Error, Result};
use glam::Vec4;

pub struct EditableTexture {
    /// Level 0 decoded, then each coarser level in linear light, as `from_rgba8` builds them.
    linear: Vec<Plane<Vec4>>,
    /// The texture as stored (level 0 the bytes given); changed in place while no other texture shares its
    /// levels, else copied first.
    stored: FilteredTexture,
    /// Each coarser level's taps: (columns, rows) of the level before.
    taps: Vec<Taps>,
    srgb: bool,
    options: TextureOptions,
    encoder: SrgbEncoder,
}

impl EditableTexture {
    /// An opaque texture of 8-bit RGBA bytes as stored (row 0 at the top); `srgb` as for `from_rgba8`.
    pub fn new<'a>(image: impl Into<ImageRef<'a, [u8; 4]>>, srgb: bool, options: TextureOptions) -> Result<Self> {
        let image = image.into();
        if image.pixels().iter().any(|t| t[3] != 255) {
            return Err(Error::Invalid("an editable texture is opaque: every alpha must be 255".into()));
        }
        let base = Rgba8Plane::from_top_rows(image.width(), image.height(), image.pixels(), srgb);
        let linear = build_levels(base.decode(), options.mip_filter, options.wrap);
        let encoder = SrgbEncoder::new();
        let levels =
            std::iter::once(base).chain(linear.iter().skip(1).map(|l| Rgba8Plane::encode(l, srgb, &encoder))).collect();
        let stored = FilteredTexture::from_byte_levels(levels, options);
        let taps =
            linear.windows(2).map(|pair| Taps::between(&pair[0], &pair[1], options.mip_filter, options.wrap)).collect();
        Ok(EditableTexture { linear, stored, taps, srgb, options, encoder })
    }

    /// Replaces level 0's texels in columns `x0..x1` and rows `y0..y1` (row 0 at the top) with `texel(i, row)`
    /// and brings every coarser level up to date.
    pub fn update(&mut self, (x0, y0, x1, y1): (usize, usize, usize, usize), texel: impl Fn(usize, usize) -> [u8; 4]) {
        let (w, h) = (self.linear[0].width, self.linear[0].height);
        let (x1, y1) = (x1.min(w), y1.min(h));
        if x0 >= x1 || y0 >= y1 {
            return;
        }
        if self.stored.byte_levels_mut().is_none() {
            self.stored = FilteredTexture::from_byte_levels(self.stored.byte_levels().to_vec(), self.options);
        }
        let stored = self.stored.byte_levels_mut().expect("the levels are this texture's own");
        for row in y0..y1 {
            let j = h - 1 - row;
            for i in x0..x1 {
                let t = texel(i, row);
                assert_eq!(t[3], 255, "an editable texture stays opaque");
                stored[0].set(i, j, t);
                self.linear[0].texels[j * w + i] = stored[0].texel(i, j);
            }
        }
        let mut span = Span { x: (x0, x1), y: (h - y1, h - y0) };
        for level in 1..self.linear.len() {
            let (before, after) = self.linear.split_at_mut(level);
            let (srgb, encoder, stored) = (self.srgb, &self.encoder, &mut stored[level]);
            span = resample_changed(&before[level - 1], &mut after[0], &self.taps[level - 1], span, |x, y, v| {
                stored.set(x, y, encode_texel(v, srgb, encoder))
            });
        }
    }

    /// The texture as it stands, sharing its levels: while it is held, the next update copies them first;
    /// once it is dropped, updates change them in place.
    pub fn texture(&self) -> FilteredTexture {
        self.stored.with_options(self.options.filter)
    }

    /// (width, height) of level 0.
    pub fn size(&self) -> (usize, usize) {
        (self.linear[0].width, self.linear[0].height)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::Image;
    use crate::texture::{MipFilter, Wrap};

    fn pseudo_random(k: usize) -> u8 {
        ((k as u64).wrapping_mul(2654435761) >> 13) as u8
    }

    /// Random edits of odd-sized images, under each filter and wrap: every level equals the whole build.
    #[test]
    fn updates_equal_a_whole_build_bit_for_bit() {
        for (filter, wrap) in
            [(MipFilter::Box, Wrap::Repeat), (MipFilter::Kaiser, Wrap::Repeat), (MipFilter::Box, Wrap::Clamp)]
        {
            let (w, h) = (203, 130);
            let mut pixels: Vec<[u8; 4]> =
                (0..w * h).map(|k| [pseudo_random(k), pseudo_random(3 * k), pseudo_random(7 * k), 255]).collect();
            let options = TextureOptions { mip_filter: filter, wrap: [wrap; 2], ..TextureOptions::default() };
            let mut editable =
                EditableTexture::new(&Image { width: w, height: h, pixels: pixels.clone() }, true, options).unwrap();
            // The texture handed out after an even edit is held through the next update (which must copy
            // the levels); after an odd one it is dropped (the update changes them in place). Both must give
            // the whole build.
            let mut held = None;
            for (n, region) in
                [(0, 0, 5, 7), (198, 120, 203, 130), (40, 33, 90, 61), (100, 0, 101, 130)].into_iter().enumerate()
            {
                let (x0, y0, x1, y1) = region;
                for row in y0..y1 {
                    for i in x0..x1 {
                        pixels[row * w + i] = [pseudo_random(i + n), 200, pseudo_random(row * 5 + n), 255];
                    }
                }
                // Alive through this update, which must then leave it as it was.
                let kept: Option<FilteredTexture> = held.take();
                let kept_texel = kept.as_ref().map(|t| t.texel(x0, h - y1));
                editable.update(region, |i, row| pixels[row * w + i]);
                if let (Some(t), Some(texel)) = (&kept, kept_texel) {
                    assert_eq!(t.texel(x0, h - y1), texel, "a texture handed out changed under its holder");
                    assert_ne!(editable.texture().texel(x0, h - y1), texel, "the edit changes the texel");
                }
                drop(kept);
                let whole =
                    FilteredTexture::from_rgba8(&Image { width: w, height: h, pixels: pixels.clone() }, true, options);
                let ours = editable.texture();
                assert_eq!(ours.byte_levels().len(), whole.byte_levels().len());
                for (l, (a, b)) in ours.byte_levels().iter().zip(whole.byte_levels()).enumerate() {
                    // Decoding is one-to-one on bytes: equal decodings are equal bytes.
                    assert!(a.decode() == b.decode(), "{filter:?} {wrap:?} after edit {n}: stored level {l} differs");
                }
                let rebuilt = build_levels(ours.byte_levels()[0].decode(), filter, [wrap; 2]);
                assert!(editable.linear == rebuilt, "{filter:?} {wrap:?} after edit {n}: the linear levels differ");
                if n % 2 == 0 {
                    held = Some(ours);
                }
            }
        }
    }

    #[test]
    fn textures_with_alpha_are_refused() {
        let image = Image { width: 2, height: 1, pixels: vec![[0, 0, 0, 255], [0, 0, 0, 100]] };
        assert!(EditableTexture::new(&image, false, TextureOptions::default()).is_err());
    }
}
