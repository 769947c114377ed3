//! A colour texture with a choice of filter: RGBA texels (8-bit sources kept in 8 bits and decoded per
//! fetch, 16-bit and float sources as linear f32), wrap modes per axis, a border colour, and one of the filters of
//! [`Filter`] for every lookup.

use super::filter::{Filter, FilterOptions, Filterable};
use super::mip::{build_levels, LevelRule, MipFilter};
use super::rgba8::Rgba8Plane;
use super::texel::Plane;
use super::trilinear8::{trilinear8, trilinear_taps8};
use super::wrap::Wrap;
use super::{aniso, lane_by_lane, Footprint, LookupContext, LookupContext8, Texture};
use crate::image::color::SrgbEncoder;
use crate::image::Image;
use crate::lanes::F8;
use glam::Vec4;
use std::sync::Arc;

/// How a texture is prepared (once) and looked up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureOptions {
    pub wrap: [Wrap; 2],
    pub border: Vec4,
    pub mip_filter: MipFilter,
    pub filter: FilterOptions,
}

impl Default for TextureOptions {
    fn default() -> Self {
        TextureOptions {
            wrap: [Wrap::Repeat; 2],
            border: Vec4::ZERO,
            mip_filter: MipFilter::Box,
            filter: FilterOptions::default(),
        }
    }
}

pub struct FilteredTexture {
    data: Arc<Levels>,
    options: TextureOptions,
    path: Path,
}

/// Which code serves a lookup, decided once from the data and the options: the common cases of 8-bit
/// repeating textures have their own lane forms.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Path {
    /// Trilinear, longest-axis level: `trilinear_taps8` (one lookup) and `trilinear8` (eight).
    Trilinear8,
    /// Anisotropic: `aniso::sample_rgba8_repeating`.
    Aniso8,
    /// Everything else: the generic filters.
    General,
}

impl Path {
    fn of(data: &Levels, options: &TextureOptions) -> Path {
        let Levels::Bytes(d) = data else { return Path::General };
        if d.wrap() != [Wrap::Repeat; 2] {
            return Path::General;
        }
        let f = &options.filter;
        match f.filter {
            Filter::Trilinear if f.level_rule == LevelRule::Longest => Path::Trilinear8,
            Filter::Aniso => Path::Aniso8,
            _ => Path::General,
        }
    }
}

/// The pyramid's storage: 8-bit texels for 8-bit sources, f32 for 16-bit and float ones.
enum Levels {
    Float(Filterable<Plane<Vec4>>),
    Bytes(Filterable<Rgba8Plane>),
}

impl FilteredTexture {
    /// A texture from linear RGBA pixels (row 0 at the top, as images are stored).
    pub fn new(image: &Image<[f32; 4]>, options: TextureOptions) -> Self {
        let plane = Plane::from_top_rows_with(image.width, image.height, &image.pixels, Vec4::from);
        FilteredTexture::of(Levels::Float(Filterable::new(plane, options.mip_filter, options.wrap)), options)
    }

    /// A texture from 8-bit RGBA bytes as stored (row 0 at the top); `srgb`: the colour channels are
    /// sRGB-encoded. The pyramid is built in linear light in f32 and stored in 8 bits; level 0 keeps the bytes.
    pub fn from_rgba8(image: &Image<[u8; 4]>, srgb: bool, options: TextureOptions) -> Self {
        let base = Rgba8Plane::from_top_rows(image.width, image.height, &image.pixels, srgb);
        let float = build_levels(base.decode(), options.mip_filter, options.wrap);
        let encoder = SrgbEncoder::new();
        let levels =
            std::iter::once(base).chain(float.iter().skip(1).map(|l| Rgba8Plane::encode(l, srgb, &encoder))).collect();
        let data = Filterable::from_levels(levels, options.mip_filter, options.wrap);
        FilteredTexture::of(Levels::Bytes(data), options)
    }

    fn of(data: Levels, options: TextureOptions) -> Self {
        let path = Path::of(&data, &options);
        FilteredTexture { data: Arc::new(data), options, path }
    }

    /// The same texture data looked up with other filter options (the pyramid is shared, not rebuilt).
    pub fn with_options(&self, filter: FilterOptions) -> FilteredTexture {
        let options = TextureOptions { filter, ..self.options };
        FilteredTexture { data: Arc::clone(&self.data), options, path: Path::of(&self.data, &options) }
    }

    pub fn options(&self) -> &TextureOptions {
        &self.options
    }

    /// The filtered texture at (s, t) of one period, footprint in the same units.
    #[inline]
    pub fn lookup(&self, s: f32, t: f32, fp: &Footprint) -> Vec4 {
        match (self.path, &*self.data) {
            (Path::Trilinear8, Levels::Bytes(d)) => trilinear_taps8(d.levels(), s, t, fp),
            (Path::Aniso8, Levels::Bytes(d)) => {
                aniso::sample_rgba8_repeating(d.levels(), s, t, fp, self.options.filter.max_aniso)
            }
            _ => self.lookup_generic(s, t, fp),
        }
    }

    /// `lookup` through the generic filters (kept out of line, so that `lookup` itself stays small).
    #[inline(never)]
    fn lookup_generic(&self, s: f32, t: f32, fp: &Footprint) -> Vec4 {
        let (opts, border) = (&self.options.filter, self.options.border);
        match &*self.data {
            Levels::Float(d) => d.sample(opts, border, s, t, fp),
            Levels::Bytes(d) => d.sample(opts, border, s, t, fp),
        }
    }
}

impl Texture for FilteredTexture {
    #[inline]
    fn eval(&self, ctx: &LookupContext) -> Vec4 {
        self.lookup(ctx.uv.x, ctx.uv.y, &ctx.footprint)
    }

    fn eval8(&self, ctx: &LookupContext8<'_>) -> [F8; 4] {
        match (self.path, &*self.data) {
            (Path::Trilinear8, Levels::Bytes(d)) => trilinear8(d.levels(), ctx.u, ctx.v, &ctx.footprint),
            _ => lane_by_lane(self, ctx),
        }
    }

    fn with_filter(&self, filter: Filter) -> Option<Arc<dyn Texture>> {
        Some(Arc::new(self.with_options(FilterOptions { filter, ..self.options.filter })))
    }
}
