//! A colour texture with a choice of filter: linear RGBA texels (decoded once from 8-bit, 16-bit or float
//! sources), wrap modes per axis, a border colour, a replication count, and one of the filters of
//! [`Filter`] for every lookup.

use super::filter::{Filter, FilterOptions, Filterable};
use super::mip::MipFilter;
use super::texel::Plane;
use super::wrap::Wrap;
use super::{Footprint, Texture};
use crate::image::Image;
use glam::{Vec2, Vec4};
use std::sync::Arc;

/// How a texture is prepared (once) and looked up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureOptions {
    pub wrap: [Wrap; 2],
    pub border: Vec4,
    pub mip_filter: MipFilter,
    /// Copies of the texture per unit of (u, v).
    pub repeat: Vec2,
    pub filter: FilterOptions,
}

impl Default for TextureOptions {
    fn default() -> Self {
        TextureOptions {
            wrap: [Wrap::Repeat; 2],
            border: Vec4::ZERO,
            mip_filter: MipFilter::Box,
            repeat: Vec2::ONE,
            filter: FilterOptions::default(),
        }
    }
}

pub struct FilteredTexture {
    data: Arc<Filterable<Plane<Vec4>>>,
    options: TextureOptions,
}

impl FilteredTexture {
    /// A texture from linear RGBA pixels (row 0 at the top, as images are stored).
    pub fn new(image: &Image<[f32; 4]>, options: TextureOptions) -> Self {
        let rows: Vec<Vec4> = image.pixels.iter().map(|&p| Vec4::from(p)).collect();
        let plane = Plane::from_top_rows(image.width, image.height, &rows);
        FilteredTexture { data: Arc::new(Filterable::new(plane, options.mip_filter, options.wrap)), options }
    }

    /// The same texture data looked up with other filter options (the pyramid is shared, not rebuilt).
    pub fn with_options(&self, filter: FilterOptions) -> FilteredTexture {
        FilteredTexture { data: Arc::clone(&self.data), options: TextureOptions { filter, ..self.options } }
    }

    /// The same texture data replicated `repeat` times per unit of (u, v).
    pub fn with_repeat(&self, repeat: Vec2) -> FilteredTexture {
        FilteredTexture { data: Arc::clone(&self.data), options: TextureOptions { repeat, ..self.options } }
    }

    pub fn data(&self) -> &Filterable<Plane<Vec4>> {
        &self.data
    }

    pub fn options(&self) -> &TextureOptions {
        &self.options
    }

    /// The filtered texture at (s, t) of one period, footprint in the same units.
    #[inline]
    pub fn lookup(&self, s: f32, t: f32, fp: &Footprint) -> Vec4 {
        self.data.sample(&self.options.filter, self.options.border, s, t, fp)
    }
}

impl Texture for FilteredTexture {
    #[inline]
    fn sample(&self, uv: Vec2, footprint: &Footprint) -> Vec4 {
        let st = uv * self.options.repeat;
        let fp = footprint.replicated(self.options.repeat.x, self.options.repeat.y);
        self.lookup(st.x, st.y, &fp)
    }

    fn with_filter(&self, filter: Filter) -> Option<Arc<dyn Texture>> {
        Some(Arc::new(self.with_options(FilterOptions { filter, ..self.options.filter })))
    }
}
