//! The MIP pyramid (Williams 1983): each level half the size of the one before, built in linear light by a
//! box or a better low-pass filter, for any size (odd and non-power-of-two sides are resampled with
//! fractional weights, not truncated); lookups on the nearest level or trilinear between two.

use super::reconstruct::{bilinear, lerp, sinc, Addressing};
use super::texel::{Plane, Texel, TexelSource};
use super::wrap::Wrap;
use super::Footprint;
use crate::image::{Image, ImageRef};
use glam::Vec4;
use rayon::prelude::*;

/// The low-pass filter that makes each level from the one before.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum MipFilter {
    /// The average of the texels each new texel covers (fractional at its borders): fast, slightly soft
    /// and slightly aliased.
    #[default]
    Box,
    /// Kaiser-windowed sinc (radius 3 new texels, alpha 4): sharper levels with little ringing.
    Kaiser,
    /// Lanczos-3 windowed sinc: the sharpest, with some ringing at hard edges.
    Lanczos,
}

impl MipFilter {
    pub const NAMES: [(&'static str, MipFilter); 3] =
        [("box", MipFilter::Box), ("kaiser", MipFilter::Kaiser), ("lanczos", MipFilter::Lanczos)];

    pub fn parse(name: &str) -> Option<MipFilter> {
        MipFilter::NAMES.iter().find(|(n, _)| *n == name).map(|&(_, f)| f)
    }

    /// Weight at distance `x` measured in new (coarser) texels.
    fn weight(self, x: f32) -> f32 {
        let x = x.abs();
        match self {
            MipFilter::Box => unreachable!("the box is integrated exactly, not sampled"),
            MipFilter::Kaiser => {
                if x >= KAISER_RADIUS {
                    return 0.0;
                }
                let r = x / KAISER_RADIUS;
                sinc(x) * bessel_i0(KAISER_ALPHA * (1.0 - r * r).sqrt()) / bessel_i0(KAISER_ALPHA)
            }
            MipFilter::Lanczos => {
                if x >= 3.0 {
                    0.0
                } else {
                    sinc(x) * sinc(x / 3.0)
                }
            }
        }
    }

    fn radius(self) -> f32 {
        match self {
            MipFilter::Box => 0.5,
            MipFilter::Kaiser => KAISER_RADIUS,
            MipFilter::Lanczos => 3.0,
        }
    }
}

const KAISER_RADIUS: f32 = 3.0;
const KAISER_ALPHA: f32 = 4.0;

/// The modified Bessel function of the first kind, order 0 (its power series converges fast for x < 10).
fn bessel_i0(x: f32) -> f32 {
    let (mut sum, mut term, q) = (1.0f64, 1.0f64, (x as f64 * 0.5).powi(2));
    for k in 1..30 {
        term *= q / (k * k) as f64;
        sum += term;
    }
    sum as f32
}

/// The source taps (index, weight) of every texel of an axis resampled from `n` to `nn` texels.
fn axis_taps(n: usize, nn: usize, filter: MipFilter, wrap: Wrap) -> Vec<Vec<(usize, f32)>> {
    if n == nn {
        return (0..n).map(|i| vec![(i, 1.0)]).collect();
    }
    let ratio = n as f64 / nn as f64;
    // The border colour is not part of the texture: the pyramid extends the edge texels instead.
    let wrap = if wrap == Wrap::Border { Wrap::Clamp } else { wrap };
    (0..nn)
        .map(|k| {
            let mut taps: Vec<(usize, f32)> = Vec::new();
            let (lo, hi) = (k as f64 * ratio, (k + 1) as f64 * ratio);
            if filter == MipFilter::Box {
                let mut x = lo.floor();
                while x < hi {
                    let cover = (hi.min(x + 1.0) - lo.max(x)) / ratio;
                    if cover > 1e-9 {
                        taps.push((x as usize, cover as f32));
                    }
                    x += 1.0;
                }
            } else {
                let centre = 0.5 * (lo + hi);
                let reach = filter.radius() as f64 * ratio;
                let first = (centre - reach - 0.5).floor() as isize;
                let last = (centre + reach - 0.5).ceil() as isize;
                let mut sum = 0.0;
                for i in first..=last {
                    let w = filter.weight(((i as f64 + 0.5 - centre) / ratio) as f32);
                    if w != 0.0 {
                        let idx = wrap.resolve(i, n).expect("border is clamped above");
                        match taps.iter_mut().find(|(j, _)| *j == idx) {
                            Some(t) => t.1 += w,
                            None => taps.push((idx, w)),
                        }
                        sum += w;
                    }
                }
                for t in &mut taps {
                    t.1 /= sum;
                }
            }
            taps
        })
        .collect()
}

/// Something a pyramid can be built of: resampled to a smaller size with a low-pass filter.
pub trait Resample: TexelSource + Sized + Send + Clone {
    fn downsample(&self, nw: usize, nh: usize, filter: MipFilter, wrap: [Wrap; 2]) -> Self;
}

impl<T: Texel> Resample for Plane<T> {
    fn downsample(&self, nw: usize, nh: usize, filter: MipFilter, wrap: [Wrap; 2]) -> Self {
        resample(self, nw, nh, filter, wrap)
    }
}

/// Resamples `src` to `nw` x `nh` in one pass over the output rows (in parallel): each output row first
/// combines its source rows, then its columns, so the source is streamed once.
pub fn resample<S: TexelSource>(src: &S, nw: usize, nh: usize, filter: MipFilter, wrap: [Wrap; 2]) -> Plane<S::Texel> {
    let (w, h) = (src.width(), src.height());
    let cols = axis_taps(w, nw, filter, wrap[0]);
    let rows = axis_taps(h, nh, filter, wrap[1]);
    let mut texels = vec![S::Texel::default(); nw * nh];
    // Rows per parallel task: enough work to amortise the task, small enough to share among threads.
    let band = (65536 / nw.max(1)).clamp(1, 64);
    texels.par_chunks_mut(nw * band).enumerate().for_each(|(b, out)| {
        let mut combined = vec![S::Texel::default(); w];
        for (r, out_row) in out.chunks_mut(nw).enumerate() {
            let y = b * band + r;
            let taps = &rows[y];
            combined.fill(S::Texel::default());
            for &(j, wj) in taps {
                src.add_row(j, wj, &mut combined);
            }
            for (o, taps) in out_row.iter_mut().zip(&cols) {
                *o = sum_taps(&combined, taps);
            }
        }
    });
    Plane { width: nw, height: nh, texels }
}

/// One output texel from its row's combined source columns: the weighted sum over `taps`, in their order
/// (a whole resample and an update of changed texels must add alike to agree bit for bit).
#[inline]
fn sum_taps<T: Texel>(combined: &[T], taps: &[(usize, f32)]) -> T {
    let mut sum = combined[taps[0].0] * taps[0].1;
    for &(i, wi) in &taps[1..] {
        sum = sum + combined[i] * wi;
    }
    sum
}

/// A level's filter taps on the level before: (index, weight) for each of its columns, then of its rows.
pub(crate) struct Taps {
    columns: Vec<Vec<(usize, f32)>>,
    rows: Vec<Vec<(usize, f32)>>,
}

impl Taps {
    pub(crate) fn between<T>(from: &Plane<T>, to: &Plane<T>, filter: MipFilter, wrap: [Wrap; 2]) -> Taps {
        Taps {
            columns: axis_taps(from.width, to.width, filter, wrap[0]),
            rows: axis_taps(from.height, to.height, filter, wrap[1]),
        }
    }
}

/// Columns `x.0..x.1` by rows `y.0..y.1` of one level, row 0 at the bottom.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Span {
    pub x: (usize, usize),
    pub y: (usize, usize),
}

/// Recomputes the texels of `dst` (the level after `src`, by `taps`) that read the `changed` texels of
/// `src`, bit for bit as `resample` computes them (each sum in the same order), calling `changed_texel` on
/// each: the span of those texels. What keeps a pyramid up to date as its base is painted.
pub(crate) fn resample_changed<T: Texel>(
    src: &Plane<T>,
    dst: &mut Plane<T>,
    taps: &Taps,
    changed: Span,
    mut changed_texel: impl FnMut(usize, usize, T),
) -> Span {
    let reads = |taps: &[(usize, f32)], (lo, hi): (usize, usize)| taps.iter().any(|&(k, _)| k >= lo && k < hi);
    let xs: Vec<usize> = (0..taps.columns.len()).filter(|&x| reads(&taps.columns[x], changed.x)).collect();
    let ys: Vec<usize> = (0..taps.rows.len()).filter(|&y| reads(&taps.rows[y], changed.y)).collect();
    let (Some(&x_lo), Some(&x_hi), Some(&y_lo), Some(&y_hi)) = (xs.first(), xs.last(), ys.first(), ys.last()) else {
        return Span { x: (0, 0), y: (0, 0) };
    };
    // Only the columns the changed texels read (neighbours share some).
    let mut read: Vec<usize> = xs.iter().flat_map(|&x| taps.columns[x].iter().map(|t| t.0)).collect();
    read.sort_unstable();
    read.dedup();
    let mut combined = vec![T::default(); src.width];
    for &y in &ys {
        for &i in &read {
            combined[i] = T::default();
        }
        for &(j, wj) in &taps.rows[y] {
            let row = src.row(j);
            for &i in &read {
                combined[i] = combined[i] + row[i] * wj;
            }
        }
        for &x in &xs {
            let sum = sum_taps(&combined, &taps.columns[x]);
            dst.texels[y * dst.width + x] = sum;
            changed_texel(x, y, sum);
        }
    }
    Span { x: (x_lo, x_hi + 1), y: (y_lo, y_hi + 1) }
}

/// The size of the level after one of `n` texels: half, rounded down, at least one.
#[inline]
pub fn half(n: usize) -> usize {
    (n / 2).max(1)
}

/// Every level from `base` down to 1 x 1.
pub fn build_levels<S: Resample>(base: S, filter: MipFilter, wrap: [Wrap; 2]) -> Vec<S> {
    let mut levels = vec![base];
    loop {
        let last = &levels[levels.len() - 1];
        let (w, h) = (last.width(), last.height());
        if w == 1 && h == 1 {
            return levels;
        }
        let next = last.downsample(half(w), half(h), filter, wrap);
        levels.push(next);
    }
}

/// Every level of an RGBA texture, built from its colour premultiplied by alpha (so a transparent texel's
/// colour does not darken its opaque neighbours' average: no dark fringe at a cut-out's border), then stored
/// straight again; where nothing is there (alpha 0) the level keeps the plain average of the stored colours,
/// as level 0 keeps the file's. Level 0 is `base` itself; opaque textures are built directly.
pub fn build_rgba_levels(base: Plane<Vec4>, filter: MipFilter, wrap: [Wrap; 2]) -> Vec<Plane<Vec4>> {
    if base.texels.par_iter().all(|t| t.w == 1.0) {
        return build_levels(base, filter, wrap);
    }
    let premultiplied = base.texels.par_iter().map(|t| (t.truncate() * t.w).extend(t.w)).collect();
    let weighted = build_levels(Plane { texels: premultiplied, ..base }, filter, wrap);
    let mut levels = build_levels(base, filter, wrap);
    for (level, weighted) in levels[1..].iter_mut().zip(&weighted[1..]) {
        level.texels.par_iter_mut().zip(&weighted.texels).for_each(|(t, w)| {
            // A sharpening kernel can take alpha to 0 or below: nothing to divide, the plain average stays.
            if w.w > 0.0 {
                *t = (w.truncate() / w.w).extend(w.w);
            }
        });
    }
    levels
}

/// The MIP pyramid of linear RGBA pixels (an [`Image`] or a view of the caller's buffer, row 0 at the top),
/// level 0 first and each level an image the same way up.
pub fn pyramid<'a>(
    image: impl Into<ImageRef<'a, [f32; 4]>>,
    filter: MipFilter,
    wrap: [Wrap; 2],
) -> Vec<Image<[f32; 4]>> {
    let image = image.into();
    pyramid_of(Plane::from_top_rows_with(image.width(), image.height(), image.pixels(), Vec4::from), filter, wrap)
}

/// [`pyramid`] from texels already in a plane.
pub(crate) fn pyramid_of(base: Plane<Vec4>, filter: MipFilter, wrap: [Wrap; 2]) -> Vec<Image<[f32; 4]>> {
    // Each plane goes as soon as its image is made: the pyramid is held about once, not twice.
    build_rgba_levels(base, filter, wrap).into_iter().map(|level| level.to_image()).collect()
}

/// How the level is chosen from the footprint.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum LevelRule {
    /// log2 of the longer of the pixel's two axes in texels (Williams): never aliases, blurs at grazing
    /// angles.
    #[default]
    Longest,
    /// log2 of the square root of the pixel's area in texels (the slides' alternative): sharper at grazing
    /// angles, aliases along the long axis.
    Area,
}

impl LevelRule {
    /// The fractional level for a footprint (in one-period units) on a `w` x `h` base level.
    #[inline]
    pub fn level(self, fp: &Footprint, w: usize, h: usize) -> f32 {
        match self {
            LevelRule::Longest => fp.mip_level(w, h),
            LevelRule::Area => fp.mip_level_area(w, h),
        }
    }
}

/// Bilinear on the level nearest to `level`.
#[inline]
pub fn nearest_level<S: TexelSource>(
    levels: &[S],
    addr: &Addressing<S::Texel>,
    s: f32,
    t: f32,
    level: f32,
) -> S::Texel {
    let l = (level.max(0.0).round() as usize).min(levels.len() - 1);
    bilinear(&levels[l], addr, s, t)
}

/// The two levels around the fractional `level` of a pyramid of `count` levels, and the coarser one's
/// weight: (fine, coarse, frac), `level` clamped into the pyramid (at the last level coarse = fine, frac 0).
#[inline]
pub fn level_pair(level: f32, count: usize) -> (usize, usize, f32) {
    let last = count - 1;
    // `max` first turns NaN into 0 (`clamp` would keep it).
    let level = level.max(0.0).min(last as f32);
    // SAFETY: `level` is a number in [0, last], and a pyramid has far fewer than 2^32 levels; the unchecked
    // conversion is one instruction, a checked one seven.
    let fine = unsafe { level.to_int_unchecked::<u32>() } as usize;
    (fine, (fine + 1).min(last), level - fine as f32)
}

/// Bilinear on the two levels around `level`, blended linearly (trilinear).
#[inline]
pub fn trilinear<S: TexelSource>(levels: &[S], addr: &Addressing<S::Texel>, s: f32, t: f32, level: f32) -> S::Texel {
    let (fine, coarse, frac) = level_pair(level, levels.len());
    let a = bilinear(&levels[fine], addr, s, t);
    if frac > 0.0 && coarse > fine {
        lerp(a, bilinear(&levels[coarse], addr, s, t), frac)
    } else {
        a
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::color::srgb_to_linear;
    use glam::Vec4;

    #[test]
    fn sizes_halve_down_to_one_for_odd_sides() {
        let base = Plane { width: 13, height: 6, texels: vec![1.0f32; 78] };
        let sizes: Vec<(usize, usize)> =
            build_levels(base, MipFilter::Box, [Wrap::Repeat; 2]).iter().map(|l| (l.width, l.height)).collect();
        assert_eq!(sizes, vec![(13, 6), (6, 3), (3, 1), (1, 1)]);
    }

    /// An sRGB checkerboard of black and white converges to 0.5 in linear light, not to the 0.214 that
    /// averaging the encoded values (0.5 in sRGB) would give, under every pyramid filter and odd sizes.
    #[test]
    fn checkerboard_pyramid_converges_to_linear_mean_grey() {
        for (w, h) in [(64, 64), (45, 27)] {
            let encoded = |x: usize, y: usize| if (x + y).is_multiple_of(2) { 0.0 } else { 1.0 };
            let texels = (0..w * h).map(|k| Vec4::splat(srgb_to_linear(encoded(k % w, k / w)))).collect();
            let plane = Plane { width: w, height: h, texels };
            let mean = plane.texels.iter().map(|t| t.x as f64).sum::<f64>() / (w * h) as f64;
            for filter in [MipFilter::Box, MipFilter::Kaiser, MipFilter::Lanczos] {
                let levels = build_levels(plane.clone(), filter, [Wrap::Repeat; 2]);
                let top = levels.last().unwrap().texels[0];
                assert!((top.x as f64 - mean).abs() < 2e-3, "{filter:?} {w}x{h}: {} vs {mean}", top.x);
                assert!((top.x - 0.5).abs() < 0.02, "{filter:?}: {}", top.x);
                // Two levels down the checks are already grey.
                for t in &levels[2].texels {
                    assert!((t.x - 0.5).abs() < 0.05, "{filter:?} {w}x{h} level 2: {}", t.x);
                }
            }
        }
    }

    /// A red cut-out on transparent black: straight averaging darkens the border's colour towards black;
    /// built premultiplied, every level keeps the red of the texels that are there, alpha their coverage.
    #[test]
    fn transparent_texels_do_not_darken_a_cut_outs_levels() {
        let texels = (0..64).map(|i| if (i % 8) < 3 { Vec4::new(1.0, 0.2, 0.1, 1.0) } else { Vec4::ZERO }).collect();
        let base = Plane { width: 8, height: 8, texels };
        let levels = build_rgba_levels(base.clone(), MipFilter::Box, [Wrap::Repeat; 2]);
        assert_eq!(levels[0], base);
        for level in &levels[1..] {
            // Where nothing is there (alpha 0) the colour is the plain average of what is stored: black here.
            for t in level.texels.iter().filter(|t| t.w > 0.0) {
                assert!((t.truncate() - glam::Vec3::new(1.0, 0.2, 0.1)).abs().max_element() < 1e-6, "{t:?}");
            }
        }
        // Level 1 holds columns 0-1 (opaque), 2-3 (half), 4-5 and 6-7 (none): alpha is the coverage.
        let alpha: Vec<f32> = levels[1].texels[..4].iter().map(|t| t.w).collect();
        assert_eq!(alpha, [1.0, 0.5, 0.0, 0.0]);
        // Opaque textures are built as before, to the bit.
        let opaque =
            Plane { width: 8, height: 8, texels: (0..64).map(|i| Vec4::new(i as f32 / 64.0, 0.5, 0.2, 1.0)).collect() };
        let straight = build_levels(opaque.clone(), MipFilter::Box, [Wrap::Repeat; 2]);
        assert_eq!(build_rgba_levels(opaque, MipFilter::Box, [Wrap::Repeat; 2]), straight);
    }

    #[test]
    fn box_level_is_the_exact_average_of_covered_texels() {
        // 5 -> 2: new texel 0 covers source [0, 2.5): texels 0, 1 fully and half of 2.
        let base = Plane { width: 5, height: 1, texels: vec![1.0f32, 2.0, 4.0, 8.0, 16.0] };
        let next = base.downsample(2, 1, MipFilter::Box, [Wrap::Repeat; 2]);
        assert!((next.texels[0] - (1.0 + 2.0 + 0.5 * 4.0) / 2.5).abs() < 1e-6);
        assert!((next.texels[1] - (0.5 * 4.0 + 8.0 + 16.0) / 2.5).abs() < 1e-6);
    }
}
