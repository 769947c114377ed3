//! What a filter needs of a texel (weighted sums, in f32 and, for summed-area tables, in f64) and the plane of
//! texels one MIP level holds. Colour textures use `Vec4` (linear RGBA), bump tables `f32` heights and, with
//! their central differences, `Vec3` (T, dT/ds, dT/dt): the filters are written once for all of them.

use crate::image::Image;
use glam::{DVec3, DVec4, Vec3, Vec4};
use rayon::prelude::*;
use std::ops::{Add, Mul, Sub};

/// A texel value: filters only add, subtract and scale them.
pub trait Texel:
    Copy + Default + Send + Sync + 'static + Add<Output = Self> + Sub<Output = Self> + Mul<f32, Output = Self>
{
    /// The same value in f64, for sums over millions of texels.
    type Wide: Copy
        + Default
        + Send
        + Sync
        + Add<Output = Self::Wide>
        + Sub<Output = Self::Wide>
        + Mul<f64, Output = Self::Wide>;
    fn widen(self) -> Self::Wide;
    fn narrow(w: Self::Wide) -> Self;
}

impl Texel for f32 {
    type Wide = f64;
    fn widen(self) -> f64 {
        self as f64
    }
    fn narrow(w: f64) -> f32 {
        w as f32
    }
}

impl Texel for Vec3 {
    type Wide = DVec3;
    fn widen(self) -> DVec3 {
        self.as_dvec3()
    }
    fn narrow(w: DVec3) -> Vec3 {
        w.as_vec3()
    }
}

impl Texel for Vec4 {
    type Wide = DVec4;
    fn widen(self) -> DVec4 {
        self.as_dvec4()
    }
    fn narrow(w: DVec4) -> Vec4 {
        w.as_vec4()
    }
}

/// Where a filter reads texels from: a `width` x `height` grid, (i, j) with j counted from the bottom
/// (t near 0). Indices are always in range; wrap modes are resolved before.
pub trait TexelSource: Sync {
    type Texel: Texel;
    fn width(&self) -> usize;
    fn height(&self) -> usize;
    fn texel(&self, i: usize, j: usize) -> Self::Texel;

    /// A hint that texel (i, j) will be read soon: sources in memory larger than the caches start loading
    /// it, so that a filter reading many texels has their misses overlap. Nothing by default.
    #[inline]
    fn prefetch(&self, _i: usize, _j: usize) {}

    /// The four texels of a bilinear footprint: (i[0], j[0]), (i[1], j[0]), (i[0], j[1]), (i[1], j[1]).
    /// Sources whose index is costly to compute share its parts between the four.
    #[inline]
    fn quad(&self, i: [usize; 2], j: [usize; 2]) -> [Self::Texel; 4] {
        [self.texel(i[0], j[0]), self.texel(i[1], j[0]), self.texel(i[0], j[1]), self.texel(i[1], j[1])]
    }

    /// Adds row `j` times `weight` to `sum` (one texel per column): what resampling a level reads.
    #[inline]
    fn add_row(&self, j: usize, weight: f32, sum: &mut [Self::Texel]) {
        for (i, s) in sum.iter_mut().enumerate() {
            *s = *s + self.texel(i, j) * weight;
        }
    }
}

/// One image of texels, row 0 at the bottom.
#[derive(Clone, Debug, PartialEq)]
pub struct Plane<T> {
    pub width: usize,
    pub height: usize,
    pub texels: Vec<T>,
}

impl<T: Texel> Plane<T> {
    /// `rows_from_top` as images store them (row 0 at the top), flipped so that row 0 is the bottom.
    pub fn from_top_rows(width: usize, height: usize, rows_from_top: &[T]) -> Self {
        Self::from_top_rows_with(width, height, rows_from_top, |t| t)
    }

    /// [`Plane::from_top_rows`] converting each pixel on the way (no intermediate copy of the image), rows on
    /// every worker: a large texture is memory-bound here.
    pub fn from_top_rows_with<S: Copy + Sync>(
        width: usize,
        height: usize,
        rows_from_top: &[S],
        f: impl Fn(S) -> T + Sync,
    ) -> Self {
        let mut texels = vec![T::default(); width * height];
        texels.par_chunks_mut(width.max(1)).enumerate().for_each(|(j, row)| {
            let from = height - 1 - j;
            for (t, &s) in row.iter_mut().zip(&rows_from_top[from * width..(from + 1) * width]) {
                *t = f(s);
            }
        });
        Plane { width, height, texels }
    }

    #[inline]
    pub fn row(&self, j: usize) -> &[T] {
        &self.texels[j * self.width..(j + 1) * self.width]
    }
}

impl Plane<Vec4> {
    /// The texels as an image of RGBA pixels, flipped back so that row 0 is the top.
    pub fn to_image(&self) -> Image<[f32; 4]> {
        let mut pixels = vec![[0.0; 4]; self.width * self.height];
        pixels.par_chunks_mut(self.width.max(1)).enumerate().for_each(|(y, row)| {
            for (p, t) in row.iter_mut().zip(self.row(self.height - 1 - y)) {
                *p = t.to_array();
            }
        });
        Image { width: self.width, height: self.height, pixels }
    }
}

impl<T: Texel> TexelSource for Plane<T> {
    type Texel = T;
    #[inline]
    fn width(&self) -> usize {
        self.width
    }
    #[inline]
    fn height(&self) -> usize {
        self.height
    }
    #[inline]
    fn texel(&self, i: usize, j: usize) -> T {
        self.texels[j * self.width + i]
    }

    #[inline]
    fn add_row(&self, j: usize, weight: f32, sum: &mut [T]) {
        for (s, &t) in sum.iter_mut().zip(self.row(j)) {
            *s = *s + t * weight;
        }
    }
}
