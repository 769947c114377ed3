//! A colour texture with a choice of filter: RGBA texels (8-bit sources kept in 8 bits and decoded per
//! fetch, 16-bit and float sources as linear f32), wrap modes per axis, a border colour, and one of the filters of
//! [`Filter`] for every lookup.

use super::aniso::{AnisoLookup, Prefetch};
use super::filter::{Filter, FilterOptions, Filterable};
use super::mip::{build_rgba_levels, pyramid_of, LevelRule, MipFilter};
use super::rgba8::Rgba8Plane;
use super::texel::{Plane, TexelSource};
use super::trilinear8::{trilinear8, trilinear_taps8, TrilinearTaps};
use super::wrap::Wrap;
use super::{aniso, lane_by_lane, Footprint, LookupContext, LookupContext8, Texture};
use crate::image::color::SrgbEncoder;
use crate::image::{Image, ImageRef};
use crate::lanes::F8;
use glam::{Vec2, Vec4};
use std::sync::Arc;

/// How a texture is prepared (once) and looked up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureOptions {
    pub wrap: [Wrap; 2],
    pub border: Vec4,
    pub mip_filter: MipFilter,
    pub filter: FilterOptions,
    /// Added to the level of detail, as OpenGL's `GL_TEXTURE_LOD_BIAS`: every footprint is scaled by
    /// 2^lod_bias before filtering, so a MIP filter reads lod_bias levels coarser (finer where negative).
    /// -0.5 suits supersampled frames: a tent over a level's texels (bilinear) has twice the variance of the
    /// box over the sample's cell it stands for (docs/filtering.md).
    pub lod_bias: f32,
}

impl Default for TextureOptions {
    fn default() -> Self {
        TextureOptions {
            wrap: [Wrap::Repeat; 2],
            border: Vec4::ZERO,
            mip_filter: MipFilter::Box,
            filter: FilterOptions::default(),
            lod_bias: 0.0,
        }
    }
}

pub struct FilteredTexture {
    data: Arc<Levels>,
    options: TextureOptions,
    path: Path,
    /// 2^lod_bias, by which every footprint is scaled.
    footprint_scale: f32,
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

/// How many trilinear and anisotropic lookups a batch works out at a time (`pipelined`): enough that the
/// first one's texels have arrived from memory when it is read, few enough that the last one's are still
/// in L1 (measured on Zen 4, BENCHMARKS.md).
const TRILINEAR_RUN: usize = 16;
const ANISO_RUN: usize = 4;

/// The lookups of a batch in runs of `RUN`: each run's lookups are all worked out (`place`, which asks
/// the cache for their texels) before any of them is read (`read`).
fn pipelined<const RUN: usize, P>(
    st: &[Vec2],
    footprints: &[Footprint],
    out: &mut [Vec4],
    place: impl Fn(Vec2, &Footprint) -> P,
    read: impl Fn(&P) -> Vec4,
) {
    // On the stack, not a vector per call: a batch of 16 lookups lasts a microsecond or two.
    let mut placed: [Option<P>; RUN] = std::array::from_fn(|_| None);
    for ((st, footprints), out) in st.chunks(RUN).zip(footprints.chunks(RUN)).zip(out.chunks_mut(RUN)) {
        for (slot, (&p, f)) in placed.iter_mut().zip(st.iter().zip(footprints)) {
            *slot = Some(place(p, f));
        }
        // The first out.len() slots were all just filled.
        for (o, p) in out.iter_mut().zip(placed.iter().flatten()) {
            *o = read(p);
        }
    }
}

/// The pyramid's storage: 8-bit texels for 8-bit sources, f32 for 16-bit and float ones.
enum Levels {
    Float(Filterable<Plane<Vec4>>),
    Bytes(Filterable<Rgba8Plane>),
}

impl FilteredTexture {
    /// A texture from linear RGBA pixels (row 0 at the top, as images are stored), an [`Image`] or a view
    /// of the caller's buffer.
    pub fn new<'a>(image: impl Into<ImageRef<'a, [f32; 4]>>, options: TextureOptions) -> Self {
        let image = image.into();
        let plane = Plane::from_top_rows_with(image.width(), image.height(), image.pixels(), Vec4::from);
        let levels = build_rgba_levels(plane, options.mip_filter, options.wrap);
        FilteredTexture::of(Levels::Float(Filterable::from_levels(levels, options.mip_filter, options.wrap)), options)
    }

    /// A texture from 8-bit RGBA bytes as stored (row 0 at the top); `srgb`: the colour channels are
    /// sRGB-encoded. The pyramid is built in linear light in f32 and stored in 8 bits; level 0 keeps the bytes.
    pub fn from_rgba8<'a>(image: impl Into<ImageRef<'a, [u8; 4]>>, srgb: bool, options: TextureOptions) -> Self {
        let image = image.into();
        let base = Rgba8Plane::from_top_rows(image.width(), image.height(), image.pixels(), srgb);
        let float = build_rgba_levels(base.decode(), options.mip_filter, options.wrap);
        let encoder = SrgbEncoder::new();
        let levels =
            std::iter::once(base).chain(float.iter().skip(1).map(|l| Rgba8Plane::encode(l, srgb, &encoder))).collect();
        FilteredTexture::from_byte_levels(levels, options)
    }

    /// A texture of 8-bit levels already built (level 0 first, each the next level down).
    pub(crate) fn from_byte_levels(levels: Vec<Rgba8Plane>, options: TextureOptions) -> Self {
        let data = Filterable::from_levels(levels, options.mip_filter, options.wrap);
        FilteredTexture::of(Levels::Bytes(data), options)
    }

    /// A texture whose coarser levels come with it (a MIP-mapped file, or a file per level as
    /// `glTexImage2D` takes them): `levels` are linear RGBA images (row 0 at the top), level 0 first, each
    /// half the one before; the pyramid is completed down to 1 x 1 from the last one given.
    pub fn from_levels(levels: &[Image<[f32; 4]>], options: TextureOptions) -> Self {
        let plane = |i: &Image<[f32; 4]>| Plane::from_top_rows_with(i.width, i.height, &i.pixels, Vec4::from);
        let mut planes: Vec<Plane<Vec4>> = levels[..levels.len() - 1].iter().map(plane).collect();
        planes.extend(build_rgba_levels(plane(&levels[levels.len() - 1]), options.mip_filter, options.wrap));
        FilteredTexture::of(Levels::Float(Filterable::from_levels(planes, options.mip_filter, options.wrap)), options)
    }

    /// The stored 8-bit levels (none for a float texture).
    pub(crate) fn byte_levels(&self) -> &[Rgba8Plane] {
        match &*self.data {
            Levels::Bytes(d) => d.levels(),
            Levels::Float(_) => &[],
        }
    }

    /// The stored 8-bit levels to change in place, where no other texture shares them.
    pub(crate) fn byte_levels_mut(&mut self) -> Option<&mut [Rgba8Plane]> {
        match Arc::get_mut(&mut self.data)? {
            Levels::Bytes(d) => Some(d.levels_mut()),
            Levels::Float(_) => None,
        }
    }

    fn of(data: Levels, options: TextureOptions) -> Self {
        let path = Path::of(&data, &options);
        FilteredTexture { data: Arc::new(data), options, path, footprint_scale: options.lod_bias.exp2() }
    }

    /// The same texture data looked up with other filter options (the pyramid is shared, not rebuilt).
    pub fn with_options(&self, filter: FilterOptions) -> FilteredTexture {
        self.with_lookup(filter, self.options.lod_bias)
    }

    /// The same texture data looked up with other filter options and level-of-detail bias; the wrap, border
    /// and MIP filter the data was prepared with stay.
    pub fn with_lookup(&self, filter: FilterOptions, lod_bias: f32) -> FilteredTexture {
        let options = TextureOptions { filter, lod_bias, ..self.options };
        FilteredTexture {
            data: Arc::clone(&self.data),
            options,
            path: Path::of(&self.data, &options),
            footprint_scale: options.lod_bias.exp2(),
        }
    }

    /// (width, height) of level 0 in texels.
    pub fn size(&self) -> (usize, usize) {
        match &*self.data {
            Levels::Float(d) => (d.levels()[0].width(), d.levels()[0].height()),
            Levels::Bytes(d) => (d.levels()[0].width(), d.levels()[0].height()),
        }
    }

    pub fn options(&self) -> &TextureOptions {
        &self.options
    }

    /// Texel (i, j) of level 0 (j counted from the bottom) in linear RGBA.
    pub fn texel(&self, i: usize, j: usize) -> Vec4 {
        match &*self.data {
            Levels::Float(d) => d.levels()[0].texel(i, j),
            Levels::Bytes(d) => d.levels()[0].texel(i, j),
        }
    }

    /// The filtered texture at (s, t) of one period, footprint in the same units.
    #[inline]
    pub fn lookup(&self, s: f32, t: f32, fp: &Footprint) -> Vec4 {
        // Scaling by 1 (no bias) changes no bit.
        let fp = &fp.scaled(self.footprint_scale);
        match (self.path, &*self.data) {
            (Path::Trilinear8, Levels::Bytes(d)) => trilinear_taps8(d.levels(), s, t, fp),
            (Path::Aniso8, Levels::Bytes(d)) => {
                aniso::sample_rgba8_repeating(d.levels(), s, t, fp, self.options.filter.max_aniso)
            }
            _ => self.lookup_generic(s, t, fp),
        }
    }

    /// `lookup` at every (s, t) of `st` with its footprint in `footprints`, into `out`: the same values. The
    /// 8-bit repeating paths work out a run of lookups, and ask the cache for their texels, before they read
    /// any of them (`pipelined`): on a texture larger than the caches, the misses of many lookups overlap.
    /// All three slices are of one length.
    pub fn lookup_batch(&self, st: &[Vec2], footprints: &[Footprint], out: &mut [Vec4]) {
        assert!(st.len() == footprints.len() && st.len() == out.len(), "lookup_batch: slices of different lengths");
        let scale = self.footprint_scale;
        match (self.path, &*self.data) {
            (Path::Trilinear8, Levels::Bytes(d)) => {
                let levels = d.levels();
                let place = |p: Vec2, f: &Footprint| {
                    let taps = TrilinearTaps::at(levels, p.x, p.y, &f.scaled(scale));
                    taps.prefetch();
                    taps
                };
                pipelined::<TRILINEAR_RUN, _>(st, footprints, out, place, TrilinearTaps::sum);
            }
            (Path::Aniso8, Levels::Bytes(d)) => {
                let (levels, max_aniso) = (d.levels(), self.options.filter.max_aniso);
                let place = |p: Vec2, f: &Footprint| {
                    let lookup = AnisoLookup::at(levels, p.x, p.y, &f.scaled(scale), max_aniso);
                    lookup.prefetch(levels);
                    lookup
                };
                pipelined::<ANISO_RUN, _>(st, footprints, out, place, |lookup| {
                    lookup.sum(levels, Prefetch::AlreadyAsked)
                });
            }
            _ => {
                for ((p, f), o) in st.iter().zip(footprints).zip(out) {
                    *o = self.lookup(p.x, p.y, f);
                }
            }
        }
    }

    /// The MIP pyramid in linear light, level 0 first, each an image (row 0 at the top): level 0 as given,
    /// the others filtered from it in f32 (for an 8-bit source, before their storage in 8 bits).
    pub fn pyramid(&self) -> Vec<Image<[f32; 4]>> {
        let base = match &*self.data {
            Levels::Float(d) => d.levels()[0].clone(),
            Levels::Bytes(d) => d.levels()[0].decode(),
        };
        pyramid_of(base, self.options.mip_filter, self.options.wrap)
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

    fn image(&self) -> Option<&FilteredTexture> {
        Some(self)
    }

    fn eval8(&self, ctx: &LookupContext8<'_>) -> [F8; 4] {
        match (self.path, &*self.data) {
            (Path::Trilinear8, Levels::Bytes(d)) => {
                trilinear8(d.levels(), ctx.u, ctx.v, &ctx.footprint.scaled(self.footprint_scale))
            }
            // Each lane's `lookup` scales its footprint.
            _ => lane_by_lane(self, ctx),
        }
    }

    fn with_lookup(&self, change: &dyn Fn(&mut TextureOptions)) -> Option<Arc<dyn Texture>> {
        let mut options = self.options;
        change(&mut options);
        Some(Arc::new(FilteredTexture::with_lookup(self, options.filter, options.lod_bias)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// NaN, infinite and huge coordinates and footprints, through every filter, wrap and storage, one lookup
    /// a call and in batches: each returns (whatever it returns) and none reads outside its texture.
    #[test]
    fn non_finite_lookups_return_without_a_panic() {
        let bytes: Vec<[u8; 4]> = (0..40 * 24).map(|k| [(k * 37 % 251) as u8, (k % 256) as u8, 9, 200]).collect();
        let image = Image { width: 40, height: 24, pixels: bytes };
        let floats =
            Image { width: 40, height: 24, pixels: image.pixels.iter().map(|p| p.map(|c| c as f32 / 255.0)).collect() };
        let odd = [f32::NAN, f32::INFINITY, f32::NEG_INFINITY, 1e30, -1e30, 3.0e9, -1e-12, 0.5];
        let sizes = [f32::NAN, f32::INFINITY, 0.0, 1e30, 1e-30, 0.03, 2.0, -0.5];
        let coords: Vec<Vec2> = (0..odd.len() * odd.len()).map(|k| Vec2::new(odd[k % 8], odd[k / 8])).collect();
        let footprints: Vec<Footprint> = (0..coords.len())
            .map(|k| {
                let (w, r) = (sizes[k % 8], sizes[(k / 8 + 5) % 8]);
                Footprint { dudx: w, dvdx: r * w, dudy: -r, dvdy: w }
            })
            .collect();
        for &(_, filter) in Filter::ALL.iter() {
            for wrap in [Wrap::Repeat, Wrap::Clamp, Wrap::Mirror, Wrap::Border] {
                let filter = FilterOptions { filter, max_aniso: 8.0, ..FilterOptions::default() };
                let options = TextureOptions { wrap: [wrap; 2], filter, ..TextureOptions::default() };
                for tex in [FilteredTexture::from_rgba8(&image, true, options), FilteredTexture::new(&floats, options)]
                {
                    let mut out = vec![Vec4::ZERO; coords.len()];
                    tex.lookup_batch(&coords, &footprints, &mut out);
                    for (p, f) in coords.iter().zip(&footprints) {
                        tex.lookup(p.x, p.y, f);
                    }
                }
            }
        }
    }
}
