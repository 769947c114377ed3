//! Bump functions as tables (Blinn section 3): F looked up by nearest (FVAL) or bilinear interpolation,
//! Fu and Fv by central differences with E = one table step, periodic wrap, and a MIP pyramid of the
//! table for filtering the bump function by the pixel footprint (section 5); every texture filter
//! (trilinear, ripmap, SAT, anisotropic, EWA) reads the table through the same code as colour textures.
//!
//! Blinn's central difference of a lookup shifted by exactly one table step lands on the neighbouring
//! texels with the same interpolation weights, so
//!     (FVAL(u+E) - FVAL(u-E)) / 2E  ==  lookup of the table G[i] = (T[i+1] - T[i-1]) / 2E.
//! A lookup therefore reads the 4x4 neighbourhood once and returns F, Fu and Fv together, exactly equal
//! to Blinn's three lookups (nearest or bilinear alike).
//!
//! Texel (i,j) has its centre at ((i+0.5)/W, (j+0.5)/H), j counted from the bottom (the project's
//! convention). Blinn's FORTRAN bilinear FVAL puts table entries at the cell corners i/W instead: the same
//! function shifted by half a step, which we do not copy so that nearest and bilinear agree at texel centres.

use super::bytes::{decode8, HeightBytes};
use super::lean::{SlopeMoments, Spread};
use super::range::Ranges;
use super::Gradient;
use crate::image::GreyImage;
use crate::lanes::{gather, CmpEq, CmpGe, CmpGt, F8, I8, LANES};
use crate::texture::filter::{Filter, FilterOptions, Filterable};
use crate::texture::mip::{resample_changed, LevelRule, MipFilter, Resample, Span, Taps};
use crate::texture::reconstruct::Kernel;
use crate::texture::texel::{Plane, TexelSource};
use crate::texture::{bilinear_taps, wrap01, Footprint, Footprint8, Wrap};
use glam::{Vec2, Vec3};
use std::sync::{Arc, OnceLock};

/// How F is read from the table between texel centres.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interp {
    /// Blinn's first FVAL: constant squares one table step wide.
    Nearest,
    /// Blinn's second FVAL: bilinear interpolation.
    Bilinear,
}

/// One level of the table, T only (row 0 at the bottom, t near 0). As a texel source for the texture
/// filters it reads (T, dT/ds, dT/dt) per texel, the derivatives by central differences on the fly, so
/// every texture filter filters the bump function and its derivatives alike.
#[derive(Clone, Debug)]
pub struct Gradients(Arc<Plane<f32>>);

/// A periodic bump table with its MIP pyramid (and, on first use by those filters, its ripmap and
/// summed-area table).
pub struct BumpTable {
    data: Filterable<Gradients>,
    /// Level 0's heights as bytes where they are an 8-bit image's, read by the bilinear lane lookups.
    bytes: Option<HeightBytes>,
    /// The largest |T| of the table (what a displacement by it can reach).
    largest: f32,
    /// The slopes' moments for LEAN and Toksvig filtering, built on first use.
    moments: OnceLock<SlopeMoments>,
    /// Where the table is constant (for displacement's dicer), built on first use.
    ranges: OnceLock<Ranges>,
}

impl BumpTable {
    /// The table from a grey image (row 0 at the top, as images are stored).
    pub fn new(image: &GreyImage) -> Self {
        let base = Gradients(Arc::new(Plane::from_top_rows(image.width, image.height, &image.pixels)));
        let largest = image.pixels.iter().fold(0.0f32, |m, t| m.max(t.abs()));
        let bytes = HeightBytes::of(base.0.width, base.0.height, &base.0.texels);
        BumpTable {
            data: Filterable::new(base, MipFilter::Box, [Wrap::Repeat; 2]),
            bytes,
            largest,
            moments: OnceLock::new(),
            ranges: OnceLock::new(),
        }
    }

    /// Replaces level 0's heights in columns `x0..x1` and rows `y0..y1` (row 0 at the top) with
    /// `height(i, row)`, and brings the pyramid up to date where it reads them, bit for bit as `new` builds
    /// it (a painted height channel costs what a dab covers). The slopes' moments are made again on first
    /// use; `largest` stays at least the largest |T|.
    pub fn update(&mut self, (x0, y0, x1, y1): (usize, usize, usize, usize), height: impl Fn(usize, usize) -> f32) {
        let levels = self.data.levels_mut();
        let (w, h) = (levels[0].0.width, levels[0].0.height);
        let (x1, y1) = (x1.min(w), y1.min(h));
        if x0 >= x1 || y0 >= y1 {
            return;
        }
        let base = Arc::make_mut(&mut levels[0].0);
        for row in y0..y1 {
            for i in x0..x1 {
                let v = height(i, row);
                base.texels[(h - 1 - row) * w + i] = v;
                self.largest = self.largest.max(v.abs());
                // A height that is no 8-bit code leaves the lookups to the f32 table from now on.
                if self.bytes.as_mut().is_some_and(|b| !b.update(i, h - 1 - row, v)) {
                    self.bytes = None;
                }
            }
        }
        let mut span = Span { x: (x0, x1), y: (h - y1, h - y0) };
        for level in 1..levels.len() {
            let (before, after) = levels.split_at_mut(level);
            let src = &before[level - 1].0;
            let taps = Taps::between(src, &after[0].0, MipFilter::Box, [Wrap::Repeat; 2]);
            span = resample_changed(src, Arc::make_mut(&mut after[0].0), &taps, span, |_, _, _| {});
        }
        self.moments = OnceLock::new();
        self.ranges = OnceLock::new();
    }

    /// Whether the full-table lookups (nearest and bilinear) read one value all over the (s,t) box from
    /// `lo` to `hi`: every texel whose taps reach into it is the same.
    pub fn is_constant_over(&self, lo: Vec2, hi: Vec2) -> bool {
        if !(lo.is_finite() && hi.is_finite()) {
            return false;
        }
        let plane = &self.data.levels()[0].0;
        let ranges = self.ranges.get_or_init(|| Ranges::of(plane.width, plane.height, &plane.texels));
        // A bilinear lookup at s reads the texels either side of s W - 1/2 (one more each way, for the
        // rounding of the lookup's own arithmetic); more than a whole period is all of it. Coordinates too
        // far out to count texels in are not judged.
        let taps = |lo: f32, hi: f32, n: usize| {
            let n = n as f64;
            let (a, b) = (f64::from(lo) * n - 0.5, f64::from(hi) * n - 0.5);
            match b - a < n {
                _ if a.abs().max(b.abs()) > 1e15 => None,
                true => Some((a.floor() as i64 - 1, b.floor() as i64 + 2)),
                false => Some((0, n as i64)),
            }
        };
        match (taps(lo.x, hi.x, plane.width), taps(lo.y, hi.y, plane.height)) {
            (Some(x), Some(y)) => ranges.is_constant(x, y),
            _ => false,
        }
    }

    /// The largest |T| in the table.
    pub fn largest(&self) -> f32 {
        self.largest
    }

    pub fn width(&self) -> usize {
        self.data.width()
    }

    pub fn height(&self) -> usize {
        self.data.height()
    }

    pub fn level_count(&self) -> usize {
        self.data.levels().len()
    }

    /// F at (s,t) on level 0, the way Blinn's FVAL does it (without derivatives).
    pub fn fval(&self, s: f32, t: f32, interp: Interp) -> f32 {
        self.data.levels()[0].lookup(s, t, interp)[0]
    }

    /// F, Fs, Ft at (s,t). `level` selects the MIP level (fractional: linear between two levels);
    /// 0 is the full-resolution table, where E is one step of the table.
    #[inline]
    pub fn sample(&self, s: f32, t: f32, interp: Interp, level: f32) -> Gradient {
        let levels = self.data.levels();
        let last = (levels.len() - 1) as f32;
        let level = level.clamp(0.0, last);
        let l0 = level.floor() as usize;
        let frac = level - l0 as f32;
        let mut v = levels[l0].lookup(s, t, interp);
        if frac > 0.0 {
            let v1 = levels[l0 + 1].lookup(s, t, interp);
            for k in 0..3 {
                v[k] += frac * (v1[k] - v[k]);
            }
        }
        Gradient { f: v[0], fu: v[1], fv: v[2] }
    }

    /// `sample` at eight (s,t) on one level (0 for an unfiltered table): (F, Fs, Ft) per lane. Bilinear
    /// lookups compute their taps on all lanes at once; nearest ones go lane by lane.
    #[inline]
    pub fn sample8(&self, s: F8, t: F8, interp: Interp, level: usize) -> [F8; 3] {
        let levels = self.data.levels();
        let index = level.min(levels.len() - 1);
        let level = &levels[index];
        match (interp, &self.bytes) {
            (Interp::Bilinear, Some(bytes)) if index == 0 => {
                let (texel, fx, fy) = level.byte_neighbourhood8(bytes, s, t);
                level.bilinear8_of(texel, fx, fy)
            }
            (Interp::Bilinear, _) => {
                let (texel, fx, fy) = level.neighbourhood_texels8(s, t);
                level.bilinear8_of(texel, fx, fy)
            }
            (Interp::Nearest, _) => {
                let (s, t) = (s.as_array_ref(), t.as_array_ref());
                let v: [[f32; 3]; LANES] = std::array::from_fn(|i| level.lookup(s[i], t[i], interp));
                std::array::from_fn(|k| F8::new(v.map(|v| v[k])))
            }
        }
    }

    /// F, Fs, Ft at (s,t) through the filter of `opts`, `fp` the footprint in (s,t) units. Blinn's two FVALs
    /// (nearest and bilinear on the full table) and the trilinear MIP filter of section 5 read the table
    /// directly; every other filter goes through the texture filters.
    #[inline]
    pub fn lookup(&self, s: f32, t: f32, fp: &Footprint, opts: &FilterOptions) -> Gradient {
        match opts.filter {
            Filter::Reconstruct(Kernel::Nearest) => self.sample(s, t, Interp::Nearest, 0.0),
            Filter::Reconstruct(Kernel::Bilinear) => self.sample(s, t, Interp::Bilinear, 0.0),
            Filter::Trilinear if opts.level_rule == LevelRule::Longest => {
                self.sample(s, t, Interp::Bilinear, fp.mip_level(self.width(), self.height()))
            }
            _ => self.filtered(s, t, fp, opts),
        }
    }

    /// `lookup` at eight (s,t): the full-table FVALs on the lanes, every other filter lane by lane.
    #[inline]
    pub fn lookup8(&self, s: F8, t: F8, fp: &Footprint8, opts: &FilterOptions) -> [F8; 3] {
        match opts.filter {
            Filter::Reconstruct(Kernel::Nearest) => self.sample8(s, t, Interp::Nearest, 0),
            Filter::Reconstruct(Kernel::Bilinear) => {
                if let Some(bytes) = &self.bytes {
                    bytes.prefetch_below(s, t, fp);
                }
                self.sample8(s, t, Interp::Bilinear, 0)
            }
            _ => {
                let (s, t) = (s.as_array_ref(), t.as_array_ref());
                let g: [Gradient; LANES] = std::array::from_fn(|i| self.lookup(s[i], t[i], &fp.lane(i), opts));
                [F8::new(g.map(|g| g.f)), F8::new(g.map(|g| g.fu)), F8::new(g.map(|g| g.fv))]
            }
        }
    }

    /// F alone at (s,t): `lookup`'s F without its derivatives where the filter reads the full table.
    pub fn height_at(&self, s: f32, t: f32, fp: &Footprint, opts: &FilterOptions) -> f32 {
        match opts.filter {
            Filter::Reconstruct(Kernel::Nearest) => self.data.levels()[0].height(s, t, Interp::Nearest),
            Filter::Reconstruct(Kernel::Bilinear) => self.data.levels()[0].height(s, t, Interp::Bilinear),
            _ => self.lookup(s, t, fp, opts).f,
        }
    }

    /// F alone at eight (s,t) (what a parallax march reads at each step): the bilinear full-table FVAL from
    /// its four taps on the lanes, every other filter through `lookup8`.
    #[inline]
    pub fn height8(&self, s: F8, t: F8, fp: &Footprint8, opts: &FilterOptions) -> F8 {
        match opts.filter {
            Filter::Reconstruct(Kernel::Bilinear) => {
                let level = &self.data.levels()[0];
                match &self.bytes {
                    Some(bytes) => {
                        let (texel, fx, fy) = level.byte_neighbourhood8(bytes, s, t);
                        bilinear_height8_of(texel, fx, fy)
                    }
                    None => {
                        let (texel, fx, fy) = level.neighbourhood_texels8(s, t);
                        bilinear_height8_of(texel, fx, fy)
                    }
                }
            }
            _ => self.lookup8(s, t, fp, opts)[0],
        }
    }

    /// The pyramid of the slopes' first and second moments (LEAN mapping), built on first use.
    pub fn moments(&self) -> &SlopeMoments {
        self.moments.get_or_init(|| SlopeMoments::of_table(self.data.levels()[0].clone()))
    }

    /// The mean F, Fs, Ft at (s,t) through the filter of `opts` and the covariance of (Fs, Ft) under it.
    #[inline]
    pub fn lookup_spread(&self, s: f32, t: f32, fp: &Footprint, opts: &FilterOptions) -> (Gradient, Spread) {
        self.moments().lookup(s, t, fp, opts)
    }

    /// F, Fs, Ft at (s,t) through any texture filter, `fp` the footprint in (s,t) units.
    #[inline]
    pub fn filtered(&self, s: f32, t: f32, fp: &Footprint, opts: &FilterOptions) -> Gradient {
        let v = self.data.sample(opts, Vec3::ZERO, s, t, fp);
        Gradient { f: v.x, fu: v.y, fv: v.z }
    }
}

impl TexelSource for Gradients {
    type Texel = Vec3;
    #[inline]
    fn width(&self) -> usize {
        self.0.width
    }
    #[inline]
    fn height(&self) -> usize {
        self.0.height
    }
    #[inline]
    fn texel(&self, i: usize, j: usize) -> Vec3 {
        let (w, h) = (self.0.width, self.0.height);
        let (ip, in_) = (if i == 0 { w - 1 } else { i - 1 }, if i + 1 == w { 0 } else { i + 1 });
        let (jp, jn) = (if j == 0 { h - 1 } else { j - 1 }, if j + 1 == h { 0 } else { j + 1 });
        Vec3::new(
            self.at(i, j),
            (self.at(in_, j) - self.at(ip, j)) * (w as f32 * 0.5),
            (self.at(i, jn) - self.at(i, jp)) * (h as f32 * 0.5),
        )
    }

    /// The four texels of a bilinear footprint from the twelve table entries their differences read (each
    /// texel as `texel` computes it).
    #[inline]
    fn quad(&self, i: [usize; 2], j: [usize; 2]) -> [Vec3; 4] {
        let (w, h) = (self.0.width, self.0.height);
        let prev = |k: usize, n: usize| if k == 0 { n - 1 } else { k - 1 };
        let next = |k: usize, n: usize| if k + 1 == n { 0 } else { k + 1 };
        let (hw, hh) = (w as f32 * 0.5, h as f32 * 0.5);
        let row = |r: usize| &self.0.texels[r * w..(r + 1) * w];
        let (r0, r1) = (row(j[0]), row(j[1]));
        // The rows beyond each tap row: below j0 and above j1, or the other tap row where they are adjacent.
        let one = |ii: usize, r: &[f32], below: &[f32], above: &[f32]| {
            Vec3::new(r[ii], (r[next(ii, w)] - r[prev(ii, w)]) * hw, (above[ii] - below[ii]) * hh)
        };
        let (b0, a0) = (row(prev(j[0], h)), row(next(j[0], h)));
        let (b1, a1) = (row(prev(j[1], h)), row(next(j[1], h)));
        [one(i[0], r0, b0, a0), one(i[1], r0, b0, a0), one(i[0], r1, b1, a1), one(i[1], r1, b1, a1)]
    }
}

impl Resample for Gradients {
    fn downsample(&self, nw: usize, nh: usize, filter: MipFilter, wrap: [Wrap; 2]) -> Self {
        Gradients(Arc::new(self.0.downsample(nw, nh, filter, wrap)))
    }
}

impl Gradients {
    #[inline]
    fn at(&self, i: usize, j: usize) -> f32 {
        self.0.texels[j * self.0.width + i]
    }

    /// T alone at (s,t): `lookup`'s first value, by the same arithmetic, without the neighbours the
    /// derivatives read.
    fn height(&self, s: f32, t: f32, interp: Interp) -> f32 {
        let (w, h) = (self.0.width, self.0.height);
        match interp {
            Interp::Nearest => self.at(nearest(s, w), nearest(t, h)),
            Interp::Bilinear => {
                let (i0, i1, fx) = bilinear_taps(s, w);
                let (j0, j1, fy) = bilinear_taps(t, h);
                lerp2(fx, fy, self.at(i0, j0), self.at(i1, j0), self.at(i0, j1), self.at(i1, j1))
            }
        }
    }

    /// (T, dT/ds, dT/dt) at (s,t). The derivatives are Blinn's central differences with E = one step,
    /// (T[i+1] - T[i-1]) / (2 / W), read from the neighbours on the fly: the table stays one f32 per texel,
    /// four times smaller (and faster to stream through the cache) than storing the gradients.
    #[inline]
    fn lookup(&self, s: f32, t: f32, interp: Interp) -> [f32; 3] {
        let (w, h) = (self.0.width, self.0.height);
        let values = &self.0.texels;
        let (hw, hh) = (w as f32 * 0.5, h as f32 * 0.5);
        let prev = |i: usize, n: usize| if i == 0 { n - 1 } else { i - 1 };
        let next = |i: usize, n: usize| if i + 1 == n { 0 } else { i + 1 };
        match interp {
            Interp::Nearest => {
                let (i, j) = (nearest(s, w), nearest(t, h));
                let gs = (self.at(next(i, w), j) - self.at(prev(i, w), j)) * hw;
                let gt = (self.at(i, next(j, h)) - self.at(i, prev(j, h))) * hh;
                [self.at(i, j), gs, gt]
            }
            Interp::Bilinear => {
                let (i0, i1, fx) = bilinear_taps(s, w);
                let (j0, j1, fy) = bilinear_taps(t, h);
                let (im, i2) = (prev(i0, w), next(i1, w));
                let (jm, j2) = (prev(j0, h), next(j1, h));
                let (r0, r1) = (&values[j0 * w..(j0 + 1) * w], &values[j1 * w..(j1 + 1) * w]);
                let (rm, r2) = (&values[jm * w..(jm + 1) * w], &values[j2 * w..(j2 + 1) * w]);
                let lerp2 = |a: f32, b: f32, c: f32, d: f32| lerp2(fx, fy, a, b, c, d);
                let f = lerp2(r0[i0], r0[i1], r1[i0], r1[i1]);
                let gs = lerp2(r0[i1] - r0[im], r0[i2] - r0[i0], r1[i1] - r1[im], r1[i2] - r1[i0]) * hw;
                let gt = lerp2(r1[i0] - rm[i0], r1[i1] - rm[i1], r2[i0] - r0[i0], r2[i1] - r0[i1]) * hh;
                [f, gs, gt]
            }
        }
    }

    /// The texels of the 4x4 neighbourhood of eight bilinear lookups (row `r`, column `c`, 0..4: the taps'
    /// outer neighbours, the two taps, the outer neighbours) and the bilinear weights.
    #[inline(always)]
    fn neighbourhood_texels8(&self, s: F8, t: F8) -> (impl Fn(usize, usize) -> F8 + '_, F8, F8) {
        let w = self.0.width;
        let (cols, fx) = neighbourhood8(s, w);
        let (rows, fy) = neighbourhood8(t, self.0.height);
        let row_starts = rows.map(|r| r * I8::splat(w as i32));
        (move |r: usize, c: usize| gather(&self.0.texels, row_starts[r] + cols[c]), fx, fy)
    }

    /// `neighbourhood_texels8` read from the level's heights as bytes (four gathers, one per row).
    #[inline(always)]
    fn byte_neighbourhood8<'a>(
        &self,
        bytes: &'a HeightBytes,
        s: F8,
        t: F8,
    ) -> (impl Fn(usize, usize) -> F8 + 'a, F8, F8) {
        let (cols, fx) = neighbourhood8(s, self.0.width);
        let (rows, fy) = neighbourhood8(t, self.0.height);
        let words = bytes.rows8(cols[1], rows[1]);
        (move |r: usize, c: usize| decode8(words[r], c as u32), fx, fy)
    }

    /// The bilinear `lookup` on eight lanes, from the texels of their 4x4 neighbourhoods and the weights.
    #[inline(always)]
    fn bilinear8_of(&self, texel: impl Fn(usize, usize) -> F8, fx: F8, fy: F8) -> [F8; 3] {
        let (w, h) = (self.0.width, self.0.height);
        // The twelve texels of the 4x4 neighbourhood that the three lookups read (the corners are unused).
        let (r0m, r00, r01, r02) = (texel(1, 0), texel(1, 1), texel(1, 2), texel(1, 3));
        let (r1m, r10, r11, r12) = (texel(2, 0), texel(2, 1), texel(2, 2), texel(2, 3));
        let (rm0, rm1, r20, r21) = (texel(0, 1), texel(0, 2), texel(3, 1), texel(3, 2));
        let lerp2 = |a: F8, b: F8, c: F8, d: F8| lerp2(fx, fy, a, b, c, d);
        let f = lerp2(r00, r01, r10, r11);
        let gs = lerp2(r01 - r0m, r02 - r00, r11 - r1m, r12 - r10) * F8::splat(w as f32 * 0.5);
        let gt = lerp2(r10 - rm0, r11 - rm1, r20 - r00, r21 - r01) * F8::splat(h as f32 * 0.5);
        [f, gs, gt]
    }
}

/// The bilinear F alone on eight lanes from the texels of their 4x4 neighbourhoods (`bilinear8_of`'s F).
#[inline(always)]
fn bilinear_height8_of(texel: impl Fn(usize, usize) -> F8, fx: F8, fy: F8) -> F8 {
    lerp2(fx, fy, texel(1, 1), texel(1, 2), texel(2, 1), texel(2, 2))
}

/// Bilinear interpolation with weights (fx, fy) between a, b (the lower row) and c, d (the upper), of one
/// value or of eight lanes.
#[inline(always)]
fn lerp2<T: Copy + std::ops::Add<Output = T> + std::ops::Sub<Output = T> + std::ops::Mul<Output = T>>(
    fx: T,
    fy: T,
    a: T,
    b: T,
    c: T,
    d: T,
) -> T {
    let bottom = a + fx * (b - a);
    bottom + fy * (c + fx * (d - c) - bottom)
}

/// The texel Blinn's first FVAL reads at `s` along a periodic table `n` long: IU = IFIX(W * U), masked to
/// the table.
#[inline(always)]
fn nearest(s: f32, n: usize) -> usize {
    ((wrap01(s) * n as f32) as usize).min(n - 1)
}

/// On eight lanes: the bilinear taps of `bilinear_taps` (i0, i1 and the weight of i1) with their outer
/// neighbours, as [i0 - 1, i0, i1, i1 + 1] wrapped into the table.
#[inline]
pub(super) fn neighbourhood8(s: F8, n: usize) -> ([I8; 4], F8) {
    let wrapped = s - s.floor();
    // s just below an integer can round to exactly 1.0: that is 0.
    let wrapped = wrapped.cmp_ge(F8::ONE).blend(F8::ZERO, wrapped);
    let x = wrapped * F8::splat(n as f32) + F8::splat(0.5);
    let floor = x.floor();
    // k is in [0, n] (a NaN gives 0): the taps are k - 1 and k, periodic.
    let k = floor.trunc_int();
    let (zero, one, last) = (I8::splat(0), I8::splat(1), I8::splat(n as i32 - 1));
    let i0 = k.cmp_eq(zero).blend(last, (k - one).min(last));
    let i1 = k.cmp_gt(last).blend(zero, k);
    let before = i0.cmp_eq(zero).blend(last, i0 - one);
    let after = i1.cmp_eq(last).blend(zero, i1 + one);
    ([before, i0, i1, after], x - floor)
}

#[cfg(test)]
mod tests {
    /// Heights painted region by region equal a table built from the whole image, level by level.
    #[test]
    fn updates_equal_a_whole_build_bit_for_bit() {
        let (w, h) = (203, 130);
        let mut pixels: Vec<f32> = (0..w * h).map(|k| ((k * 7919) % 1000) as f32 / 1000.0).collect();
        let mut table = BumpTable::new(&crate::image::Image { width: w, height: h, pixels: pixels.clone() });
        for (n, (x0, y0, x1, y1)) in [(0, 0, 5, 7), (198, 120, 203, 130), (40, 33, 90, 61)].into_iter().enumerate() {
            for row in y0..y1 {
                for i in x0..x1 {
                    pixels[row * w + i] = 2.0 + (i * 3 + row + n) as f32 * 0.01;
                }
            }
            table.update((x0, y0, x1, y1), |i, row| pixels[row * w + i]);
            let whole = BumpTable::new(&crate::image::Image { width: w, height: h, pixels: pixels.clone() });
            assert_eq!(table.level_count(), whole.level_count());
            for (l, (a, b)) in table.data.levels().iter().zip(whole.data.levels()).enumerate() {
                assert!(a.0 == b.0, "after edit {n}: level {l} differs");
            }
            assert!(table.largest() >= whole.largest() && whole.largest() > 2.0);
        }
    }

    use super::*;
    use crate::image::Image;

    /// A 4x4 table with distinct values; row 0 of the image is the top.
    fn table() -> (GreyImage, BumpTable) {
        let img = Image::from_fn(4, 4, |x, y| (x + 4 * y) as f32 / 16.0);
        let t = BumpTable::new(&img);
        (img, t)
    }

    /// The image value of texel (i, j counted from the bottom).
    fn texel(img: &GreyImage, i: usize, j: usize) -> f32 {
        img.get(i % 4, 3 - (j % 4))
    }

    #[test]
    fn nearest_gives_constant_squares_one_step_wide() {
        let (img, t) = table();
        let e = 1e-4;
        for j in 0..4 {
            for i in 0..4 {
                let want = texel(&img, i, j);
                for (ds, dt) in [(e, e), (0.25 - e, e), (e, 0.25 - e), (0.125, 0.2)] {
                    let (s, tt) = (i as f32 / 4.0 + ds, j as f32 / 4.0 + dt);
                    assert_eq!(t.fval(s, tt, Interp::Nearest), want, "({s},{tt})");
                }
            }
        }
    }

    #[test]
    fn periodic_wrap_and_replication() {
        let (img, t) = table();
        let e = 1e-3;
        // Just below 1 is the last column, just above 1 (or 0) is the first.
        assert_eq!(t.fval(1.0 - e, 0.1, Interp::Nearest), texel(&img, 3, 0));
        assert_eq!(t.fval(1.0 + e, 0.1, Interp::Nearest), texel(&img, 0, 0));
        assert_eq!(t.fval(-e, 0.1, Interp::Nearest), texel(&img, 3, 0));
        // Replicated three times: u' = 3u lands in the same cell pattern.
        for k in 0..3 {
            assert_eq!(t.fval(k as f32 + 0.6, 0.6, Interp::Nearest), texel(&img, 2, 2));
        }
        // Bilinear across the wrap: half way between column 3 and column 0.
        let b = t.fval(1.0, 0.125, Interp::Bilinear);
        assert!((b - 0.5 * (texel(&img, 3, 0) + texel(&img, 0, 0))).abs() < 1e-6);
    }

    /// The stored gradient equals Blinn's three-lookup central difference, for both interpolations.
    #[test]
    fn derivatives_equal_blinns_central_differences() {
        let img = Image::from_fn(8, 8, |x, y| ((x * 7 + y * 3) % 5) as f32 / 4.0 + 0.1 * (x as f32).sin());
        let t = BumpTable::new(&img);
        let (es, et) = (1.0 / 8.0, 1.0 / 8.0);
        for interp in [Interp::Nearest, Interp::Bilinear] {
            for &(s, tt) in &[(0.13, 0.77), (0.51, 0.02), (0.97, 0.49), (0.3333, 0.6666)] {
                let got = t.sample(s, tt, interp, 0.0);
                let fs = (t.fval(s + es, tt, interp) - t.fval(s - es, tt, interp)) / (2.0 * es);
                let ft = (t.fval(s, tt + et, interp) - t.fval(s, tt - et, interp)) / (2.0 * et);
                assert!((got.fu - fs).abs() < 1e-4, "{interp:?} fs {} vs {fs}", got.fu);
                assert!((got.fv - ft).abs() < 1e-4, "{interp:?} ft {} vs {ft}", got.fv);
                assert!((got.f - t.fval(s, tt, interp)).abs() < 1e-6);
            }
        }
    }

    /// Through the texture filters, the table and its derivatives are what Blinn's lookups give: bilinear
    /// equals the bilinear FVAL with central differences, trilinear equals the table's own MIP lookup.
    #[test]
    fn texture_filters_read_the_same_table_and_derivatives() {
        use crate::texture::{Filter, FilterOptions, Footprint};
        let img = Image::from_fn(32, 16, |x, y| ((x * 7 + y * 3) % 5) as f32 / 4.0 + 0.1 * (x as f32).sin());
        let t = BumpTable::new(&img);
        let opts = |name: &str| FilterOptions { filter: Filter::parse(name).unwrap(), ..FilterOptions::default() };
        for &(s, tt) in &[(0.13, 0.77), (0.51, 0.02), (0.97, 0.49)] {
            let want = t.sample(s, tt, Interp::Bilinear, 0.0);
            let got = t.filtered(s, tt, &Footprint::default(), &opts("bilinear"));
            assert!(
                (got.f - want.f).abs() < 1e-5 && (got.fu - want.fu).abs() < 1e-3 && (got.fv - want.fv).abs() < 1e-3
            );
            // A footprint of 2.5 texels: level log2(2.5) of the pyramid.
            let fp = Footprint { dudx: 2.5 / 32.0, dvdx: 0.0, dudy: 0.0, dvdy: 1.0 / 16.0 };
            let want = t.sample(s, tt, Interp::Bilinear, 2.5f32.log2());
            let got = t.filtered(s, tt, &fp, &opts("trilinear"));
            assert!(
                (got.f - want.f).abs() < 1e-5 && (got.fu - want.fu).abs() < 1e-3 && (got.fv - want.fv).abs() < 1e-3
            );
            // EWA of the derivatives is the derivative of the EWA: close to trilinear's on this smooth scale.
            let ewa = t.filtered(s, tt, &fp, &opts("ewa"));
            assert!((ewa.f - want.f).abs() < 0.2, "{} vs {}", ewa.f, want.f);
        }
    }

    #[test]
    fn eight_lanes_equal_eight_lookups() {
        // Heights of no 8-bit image (the f32 table), and an 8-bit image's (its bytes).
        let real = BumpTable::new(&Image::from_fn(7, 5, |x, y| ((x * 37 + y * 11) % 13) as f32 / 13.0));
        let eight_bit = BumpTable::new(&Image::from_fn(7, 5, |x, y| ((x * 37 + y * 11) % 256) as f32 / 255.0));
        assert!(real.bytes.is_none() && eight_bit.bytes.is_some());
        for table in [real, eight_bit] {
            lanes_equal_lookups(&table);
        }
    }

    /// An 8-bit table's lookups through its bytes give the bits of the same lookups through its f32 table.
    #[test]
    fn bytes_give_the_f32_tables_bits() {
        let image = Image::from_fn(33, 17, |x, y| ((x * 91 + y * 29) % 256) as f32 / 255.0);
        let (bytes, mut floats) = (BumpTable::new(&image), BumpTable::new(&image));
        floats.bytes = None;
        let fp = Footprint8 { dudx: F8::ZERO, dvdx: F8::ZERO, dudy: F8::ZERO, dvdy: F8::ZERO };
        let opts = FilterOptions { filter: Filter::Reconstruct(Kernel::Bilinear), ..FilterOptions::default() };
        for k in 0..200 {
            let s = F8::new(std::array::from_fn(|i| ((k * 8 + i) as f32 * 0.618_034).fract() * 3.0 - 1.0));
            let t = F8::new(std::array::from_fn(|i| ((k * 8 + i) as f32 * 0.414_214).fract() * 2.0 - 0.5));
            let (a, b) = (bytes.sample8(s, t, Interp::Bilinear, 0), floats.sample8(s, t, Interp::Bilinear, 0));
            for c in 0..3 {
                assert_eq!(a[c].to_array().map(f32::to_bits), b[c].to_array().map(f32::to_bits));
            }
            assert_eq!(bytes.height8(s, t, &fp, &opts).to_array(), floats.height8(s, t, &fp, &opts).to_array());
        }
    }

    fn lanes_equal_lookups(table: &BumpTable) {
        // Inside cells, on texel centres, across both wraps, negative and beyond one period.
        let s = F8::new([0.01, 0.2, 0.5, 0.999_99, -0.3, 1.7, 0.125, 3.0]);
        let t = F8::new([0.99, 0.0, 0.33, 0.999_99, 2.4, -0.01, 0.875, 0.5]);
        for interp in [Interp::Bilinear, Interp::Nearest] {
            for level in [0, 1] {
                let lanes = table.sample8(s, t, interp, level);
                for i in 0..LANES {
                    let one = table.sample(s.as_array_ref()[i], t.as_array_ref()[i], interp, level as f32);
                    let got = [0, 1, 2].map(|k| lanes[k].as_array_ref()[i]);
                    let want = [one.f, one.fu, one.fv];
                    for k in 0..3 {
                        assert!(
                            (got[k] - want[k]).abs() <= 1e-4 * (1.0 + want[k].abs()),
                            "{interp:?} lane {i}: {got:?} vs {want:?}"
                        );
                    }
                }
            }
        }
        // F alone, as a parallax march reads it, is the F of the full lookup to the bit.
        let fp = Footprint8 { dudx: F8::splat(0.01), dvdx: F8::ZERO, dudy: F8::ZERO, dvdy: F8::splat(0.01) };
        for filter in [Filter::Reconstruct(Kernel::Bilinear), Filter::Reconstruct(Kernel::Nearest), Filter::Trilinear] {
            let opts = FilterOptions { filter, ..FilterOptions::default() };
            assert_eq!(table.height8(s, t, &fp, &opts).to_array(), table.lookup8(s, t, &fp, &opts)[0].to_array());
            // And one at a time, as displacement's dicer reads it.
            for i in 0..LANES {
                let (s, t, fp) = (s.as_array_ref()[i], t.as_array_ref()[i], fp.lane(i));
                assert_eq!(table.height_at(s, t, &fp, &opts).to_bits(), table.lookup(s, t, &fp, &opts).f.to_bits());
            }
        }
    }

    /// A table constant but for one texel is constant over every box whose bilinear taps miss it, and
    /// not over those whose taps reach it.
    #[test]
    fn constancy_follows_the_bilinear_taps() {
        let table = BumpTable::new(&Image::from_fn(64, 32, |x, y| if (x, y) == (40, 31 - 10) { 0.5 } else { 0.25 }));
        // Texel (40, 10) (counted from the bottom) is read by lookups with s in (39.5, 41.5) / 64.
        let at = |x: f32, y: f32| Vec2::new(x / 64.0, y / 32.0);
        assert!(!table.is_constant_over(at(40.5, 10.5), at(40.5, 10.5)));
        assert!(!table.is_constant_over(at(20.0, 5.0), at(39.7, 10.0)));
        assert!(table.is_constant_over(at(2.0, 2.0), at(30.0, 8.0)));
        // Across the wrap, far from the spot.
        assert!(table.is_constant_over(at(-10.0, 20.0), at(10.0, 28.0)));
        assert!(!table.is_constant_over(at(-30.0, 9.0), at(-23.0, 11.0)));
        assert!(!table.is_constant_over(Vec2::splat(f32::NAN), Vec2::ONE));
        assert!(!table.is_constant_over(Vec2::splat(3e38), Vec2::splat(3e38)));
    }

    #[test]
    fn pyramid_keeps_the_mean_for_odd_sizes() {
        let img = Image::from_fn(7, 5, |x, y| ((x * 3 + y * 5) % 4) as f32);
        let mean: f32 = img.pixels.iter().sum::<f32>() / 35.0;
        let t = BumpTable::new(&img);
        assert_eq!(t.level_count(), 3); // 7x5, 3x2, 1x1
        let top = t.sample(0.5, 0.5, Interp::Nearest, 99.0);
        assert!((top.f - mean).abs() < 1e-5, "{} vs {mean}", top.f);
    }

    /// NaN, infinite and huge coordinates and footprints through every filter, on the f32 and the 8-bit
    /// tables, one a call and on lanes: each returns without a panic (no read outside the table).
    #[test]
    fn non_finite_lookups_return_without_a_panic() {
        let heights = |x: usize, y: usize| ((x * 37 + y * 11) % 13) as f32 / 13.0;
        let bytes = |x: usize, y: usize| ((x * 37 + y * 11) % 256) as f32 / 255.0;
        let odd = [f32::NAN, f32::INFINITY, f32::NEG_INFINITY, 1e30, -1e30, 3.0e9, -1e-12, 0.5];
        let sizes = [f32::NAN, f32::INFINITY, 0.0, 1e30, 1e-30, 0.03, 2.0, -0.5];
        for table in [BumpTable::new(&Image::from_fn(19, 11, heights)), BumpTable::new(&Image::from_fn(19, 11, bytes))]
        {
            for &(_, filter) in Filter::ALL.iter() {
                let opts = FilterOptions { filter, max_aniso: 8.0, ..FilterOptions::default() };
                for k in 0..LANES {
                    let lane = |v: &[f32; 8], step: usize| F8::new(std::array::from_fn(|l| v[(l * step + k) % 8]));
                    let (s, t, w) = (lane(&odd, 1), lane(&odd, 3), lane(&sizes, 5));
                    let fp = Footprint8 { dudx: w, dvdx: F8::ZERO, dudy: F8::ZERO, dvdy: w };
                    table.lookup8(s, t, &fp, &opts);
                    table.height8(s, t, &fp, &opts);
                    for l in 0..LANES {
                        let (s, t) = (s.as_array_ref()[l], t.as_array_ref()[l]);
                        table.lookup(s, t, &fp.lane(l), &opts);
                        table.lookup_spread(s, t, &fp.lane(l), &opts);
                    }
                }
            }
        }
    }
}
