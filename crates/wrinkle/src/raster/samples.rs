//! Where a pixel's samples lie and what each weighs. A sampler places `spp` points in the unit square:
//! stratified (jittered strata, the same in every pixel) or Sobol points Owen-scrambled per pixel. The
//! pixel filter then moves them onto its support, in proportion to the filter's magnitude (filter
//! importance sampling, as pbrt-v4's film does): every sample belongs to the one pixel it was drawn for,
//! so tiles and crops need no samples from their neighbours, and weighs +1 or -1 (the filter's sign).
//! Offsets are fixed point, from the pixel's top-left corner, and may reach past the pixel.

use super::{SUBPIXEL, SUBPIXEL_BITS};
use crate::{Error, Result};

/// The most samples a pixel may take.
pub const MAX_SPP: usize = 4096;

/// How the samples of a pixel are placed in it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Sampler {
    /// One jittered sample in each cell of an n x m grid (n * m = spp, as square as spp allows), the same
    /// jitter in every pixel; a single sample is the pixel's centre.
    #[default]
    Stratified,
    /// The first spp points of the 2D Sobol sequence, Owen-scrambled by a hash of the pixel (Burley 2020),
    /// so no two pixels share a pattern and any spp stays well spread.
    Sobol,
}

impl Sampler {
    pub const NAMES: [&str; 2] = ["stratified", "sobol"];

    pub fn parse(name: &str) -> Option<Sampler> {
        match name {
            "stratified" => Some(Sampler::Stratified),
            "sobol" => Some(Sampler::Sobol),
            _ => None,
        }
    }
}

/// How often a pixel's samples are shaded.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ShadingRate {
    /// Every sample (supersampling): what varies inside a pixel (bump detail, highlights) is averaged too.
    #[default]
    Sample,
    /// Once per pixel and triangle (multisampling): visibility and coverage still at every sample; each
    /// triangle seen in the pixel is shaded at its covered sample nearest the pixel's centre, with the
    /// whole pixel's texture footprint, and that colour stands for all its samples there.
    Pixel,
}

impl ShadingRate {
    pub const NAMES: [&str; 2] = ["sample", "pixel"];

    pub fn parse(name: &str) -> Option<ShadingRate> {
        match name {
            "sample" => Some(ShadingRate::Sample),
            "pixel" => Some(ShadingRate::Pixel),
            _ => None,
        }
    }
}

/// The pixel reconstruction filter: how much a sample at (x, y) from the pixel's centre counts, the
/// product of the one-dimensional filter in x and in y. Radii are in pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PixelFilter {
    /// 1 within the radius (0.5: the pixel itself).
    Box { radius: f32 },
    /// 1 - |x| / radius.
    Tent { radius: f32 },
    /// exp(-x^2 / 2 sigma^2), less its value at the radius so it reaches zero there.
    Gaussian { radius: f32, sigma: f32 },
    /// Mitchell and Netravali's cubic with parameters B and C, stretched over the radius.
    Mitchell { radius: f32, b: f32, c: f32 },
    /// sinc(x) sinc(x / tau), cut at the radius.
    Lanczos { radius: f32, tau: f32 },
}

impl Default for PixelFilter {
    fn default() -> Self {
        PixelFilter::Box { radius: 0.5 }
    }
}

impl PixelFilter {
    pub const NAMES: [&str; 5] = ["box", "tent", "gaussian", "mitchell", "lanczos"];

    /// A filter by name with the usual parameters (box 0.5, tent 1, gaussian 1.5 with sigma 0.5, mitchell 2
    /// with B = C = 1/3, lanczos 3 lobes), or `NAME:RADIUS` (a Gaussian's sigma a third of its radius, a
    /// Lanczos's tau its radius).
    pub fn parse(text: &str) -> Result<PixelFilter> {
        let (name, radius) = match text.split_once(':') {
            Some((name, r)) => {
                let r: f32 = r.trim().parse().map_err(|_| bad_filter(text))?;
                (name, Some(r))
            }
            None => (text, None),
        };
        let filter = match (name.trim(), radius) {
            ("box", r) => PixelFilter::Box { radius: r.unwrap_or(0.5) },
            ("tent", r) => PixelFilter::Tent { radius: r.unwrap_or(1.0) },
            ("gaussian", None) => PixelFilter::Gaussian { radius: 1.5, sigma: 0.5 },
            ("gaussian", Some(r)) => PixelFilter::Gaussian { radius: r, sigma: r / 3.0 },
            ("mitchell", r) => PixelFilter::Mitchell { radius: r.unwrap_or(2.0), b: 1.0 / 3.0, c: 1.0 / 3.0 },
            ("lanczos", r) => {
                let radius = r.unwrap_or(3.0);
                PixelFilter::Lanczos { radius, tau: radius }
            }
            _ => return Err(bad_filter(text)),
        };
        filter.validated()
    }

    /// The filter if its parameters are usable: a radius from 0.5 to 8 pixels, positive sigma and tau.
    pub fn validated(self) -> Result<PixelFilter> {
        let r = self.radius();
        if !(0.5..=8.0).contains(&r) {
            return Err(Error::parameter("pixel_filter", format!("radius must be between 0.5 and 8 pixels, got {r}")));
        }
        let shape_ok = match self {
            PixelFilter::Gaussian { sigma, .. } => sigma > 0.0,
            PixelFilter::Lanczos { tau, .. } => tau > 0.0,
            PixelFilter::Mitchell { b, c, .. } => b.is_finite() && c.is_finite(),
            _ => true,
        };
        if !shape_ok {
            return Err(Error::parameter("pixel_filter", "sigma and tau must be positive".to_string()));
        }
        Ok(self)
    }

    pub fn radius(&self) -> f32 {
        match *self {
            PixelFilter::Box { radius }
            | PixelFilter::Tent { radius }
            | PixelFilter::Gaussian { radius, .. }
            | PixelFilter::Mitchell { radius, .. }
            | PixelFilter::Lanczos { radius, .. } => radius,
        }
    }

    /// The one-dimensional filter at `x` pixels from the centre.
    pub fn eval(&self, x: f32) -> f32 {
        let ax = x.abs();
        if ax > self.radius() {
            return 0.0;
        }
        match *self {
            PixelFilter::Box { .. } => 1.0,
            PixelFilter::Tent { radius } => 1.0 - ax / radius,
            PixelFilter::Gaussian { radius, sigma } => {
                let g = |x: f32| (-x * x / (2.0 * sigma * sigma)).exp();
                (g(x) - g(radius)).max(0.0)
            }
            PixelFilter::Mitchell { radius, b, c } => {
                let t = 2.0 * ax / radius;
                let v = if t < 1.0 {
                    (12.0 - 9.0 * b - 6.0 * c) * t * t * t + (-18.0 + 12.0 * b + 6.0 * c) * t * t + (6.0 - 2.0 * b)
                } else {
                    (-b - 6.0 * c) * t * t * t
                        + (6.0 * b + 30.0 * c) * t * t
                        + (-12.0 * b - 48.0 * c) * t
                        + (8.0 * b + 24.0 * c)
                };
                v / 6.0
            }
            PixelFilter::Lanczos { tau, .. } => sinc(x) * sinc(x / tau),
        }
    }

    /// Whether the filter is negative anywhere (its samples then weigh -1 there).
    fn has_negative_lobes(&self) -> bool {
        matches!(self, PixelFilter::Mitchell { .. } | PixelFilter::Lanczos { .. })
    }
}

fn bad_filter(text: &str) -> Error {
    Error::parameter(
        "pixel_filter",
        format!("expected one of {} (or NAME:RADIUS), got \"{text}\"", PixelFilter::NAMES.join(", ")),
    )
}

fn sinc(x: f32) -> f32 {
    let px = std::f32::consts::PI * x;
    if px.abs() < 1e-5 {
        1.0
    } else {
        px.sin() / px
    }
}

/// Steps of the tabulated inverse of a filter's cumulative magnitude.
const WARP_STEPS: usize = 1024;

/// Moves a uniform coordinate in [0, 1) to an offset from the pixel's centre with density proportional
/// to the filter's magnitude: the inverse of its cumulative integral, tabulated and interpolated.
#[derive(Clone, Debug)]
struct Warp {
    /// x at u = k / WARP_STEPS, k = 0..=WARP_STEPS; empty for a box (x = (2u - 1) radius).
    inverse: Vec<f32>,
    radius: f32,
}

impl Warp {
    fn new(filter: &PixelFilter) -> Warp {
        let radius = filter.radius();
        if matches!(filter, PixelFilter::Box { .. }) {
            return Warp { inverse: Vec::new(), radius };
        }
        // The magnitude's integral over fine cells (midpoint rule), then x for evenly spaced fractions of it.
        const CELLS: usize = 8192;
        let dx = 2.0 * radius as f64 / CELLS as f64;
        let mut cdf = Vec::with_capacity(CELLS + 1);
        cdf.push(0.0f64);
        for i in 0..CELLS {
            let x = -radius as f64 + (i as f64 + 0.5) * dx;
            cdf.push(cdf[i] + filter.eval(x as f32).abs() as f64 * dx);
        }
        let total = cdf[CELLS];
        let mut inverse = Vec::with_capacity(WARP_STEPS + 1);
        let mut cell = 0;
        for k in 0..=WARP_STEPS {
            let target = total * k as f64 / WARP_STEPS as f64;
            while cell < CELLS - 1 && cdf[cell + 1] < target {
                cell += 1;
            }
            let span = cdf[cell + 1] - cdf[cell];
            let t = if span > 0.0 { ((target - cdf[cell]) / span).clamp(0.0, 1.0) } else { 0.0 };
            inverse.push((-radius as f64 + (cell as f64 + t) * dx) as f32);
        }
        Warp { inverse, radius }
    }

    /// The offset from the pixel's centre for uniform `u` in [0, 1).
    #[inline]
    fn apply(&self, u: f32) -> f32 {
        if self.inverse.is_empty() {
            return (2.0 * u - 1.0) * self.radius;
        }
        let t = u * WARP_STEPS as f32;
        let k = (t as usize).min(WARP_STEPS - 1);
        let f = t - k as f32;
        self.inverse[k] + (self.inverse[k + 1] - self.inverse[k]) * f
    }
}

/// The samples of every pixel of a frame: their count, the sampler and the pixel filter.
#[derive(Clone, Debug)]
pub struct SamplePattern {
    spp: usize,
    filter: PixelFilter,
    warp: Warp,
    /// The offsets every pixel shares (stratified), in 1/SUBPIXEL pixel; none where each pixel has its own.
    same: Option<Vec<[i64; 2]>>,
    /// Pixels beyond its own that a pixel's samples may reach, on each side.
    reach: usize,
    /// The one-dimensional filter's sign at each fixed-point offset from -reach pixels on, where it has
    /// negative lobes (a table: the sinc of a Lanczos filter costs more than the rest of a sample's resolve).
    signs: Vec<f32>,
    /// Mixed into every pixel's scramble (Sobol): another seed, other patterns of the same quality.
    seed: u32,
}

impl SamplePattern {
    /// Checks the sample count (1 to MAX_SPP) and the filter's parameters without building the tables.
    pub fn check(spp: usize, filter: PixelFilter) -> Result<PixelFilter> {
        if !(1..=MAX_SPP).contains(&spp) {
            return Err(Error::parameter("spp", format!("must be between 1 and {MAX_SPP}, got {spp}")));
        }
        filter.validated()
    }

    /// The pattern of `spp` samples (1 to MAX_SPP) by `sampler`, spread over `filter`.
    pub fn new(spp: usize, sampler: Sampler, filter: PixelFilter) -> Result<SamplePattern> {
        let filter = SamplePattern::check(spp, filter)?;
        let warp = Warp::new(&filter);
        let reach = (filter.radius() - 0.5).max(0.0).ceil() as usize;
        let signs = match filter.has_negative_lobes() {
            true => (0..(2 * reach as i64 + 1) * SUBPIXEL)
                .map(|o| {
                    let at = (o as f32 + 0.5) / SUBPIXEL as f32 - reach as f32 - 0.5;
                    if filter.eval(at) < 0.0 {
                        -1.0
                    } else {
                        1.0
                    }
                })
                .collect(),
            false => Vec::new(),
        };
        let mut pattern = SamplePattern { spp, filter, warp, same: None, reach, signs, seed: 0 };
        if sampler == Sampler::Stratified {
            pattern.same = Some(pattern.stratified());
        }
        Ok(pattern)
    }

    /// The pattern with every pixel's Sobol scramble seeded by `seed` too (stratified patterns do not
    /// change): independent renders of the same sample count, for error estimates.
    pub fn seeded(self, seed: u32) -> SamplePattern {
        SamplePattern { seed, ..self }
    }

    /// One sample at the centre of every pixel: the pattern of shadow maps.
    pub fn centre() -> SamplePattern {
        SamplePattern::new(1, Sampler::Stratified, PixelFilter::default()).expect("one box-filtered sample")
    }

    /// Samples per pixel.
    pub fn count(&self) -> usize {
        self.spp
    }

    pub fn reach(&self) -> usize {
        self.reach
    }

    /// The offsets every pixel shares (fixed point, from the pixel's corner); none where each has its own.
    pub fn shared_offsets(&self) -> Option<&[[i64; 2]]> {
        self.same.as_deref()
    }

    /// Whether some samples weigh -1.
    pub fn has_negative_weights(&self) -> bool {
        !self.signs.is_empty()
    }

    /// The weight of a sample at `offset` (fixed point, from the pixel's corner): the filter's sign over
    /// the fixed-point cell there.
    #[inline]
    pub fn weight(&self, offset: [i64; 2]) -> f32 {
        if self.signs.is_empty() {
            return 1.0;
        }
        let sign = |o: i64| {
            let k = (o + self.reach as i64 * SUBPIXEL).clamp(0, self.signs.len() as i64 - 1);
            self.signs[k as usize]
        };
        sign(offset[0]) * sign(offset[1])
    }

    /// The offsets of the samples of pixel (x, y) into `out` (spp of them).
    pub fn offsets_into(&self, x: usize, y: usize, out: &mut [[i64; 2]]) {
        match &self.same {
            Some(same) => out.copy_from_slice(same),
            None => {
                let seed = pixel_seed(x, y) ^ mix(self.seed.wrapping_mul(0x9e37_79b9));
                let seeds = [seed, mix(seed ^ 0x5bd1_e995)];
                for (i, o) in out.iter_mut().enumerate() {
                    let p = sobol2(i as u32);
                    *o = std::array::from_fn(|d| self.fixed(owen_scramble(p[d], seeds[d])));
                }
            }
        }
    }

    /// The offset of uniform coordinate `u` (32-bit fixed point) after the filter's warp.
    #[inline]
    fn fixed(&self, u: u32) -> i64 {
        if self.filter == PixelFilter::default() {
            return (u >> (32 - SUBPIXEL_BITS)) as i64;
        }
        self.at(u as f32 * (1.0 / 4_294_967_296.0))
    }

    /// The fixed-point offset from the pixel's corner of uniform `u` in [0, 1) warped by the filter.
    #[inline]
    fn at(&self, u: f32) -> i64 {
        ((0.5 + self.warp.apply(u)) * SUBPIXEL as f32).floor() as i64
    }

    /// Jittered strata, nx by ny: a fixed jitter from a small integer hash keeps renders reproducible.
    fn stratified(&self) -> Vec<[i64; 2]> {
        if self.spp == 1 {
            return vec![[SUBPIXEL / 2, SUBPIXEL / 2]];
        }
        let ny = (1..=self.spp).filter(|d| self.spp.is_multiple_of(*d) && d * d <= self.spp).max().unwrap_or(1);
        let nx = self.spp / ny;
        let mut offsets = Vec::with_capacity(self.spp);
        for b in 0..ny {
            for a in 0..nx {
                let (jx, jy) = (hash01(a * 7 + b * 131 + 1), hash01(a * 59 + b * 17 + 1000));
                let u = (a as f32 + 0.1 + 0.8 * jx) / nx as f32;
                let v = (b as f32 + 0.1 + 0.8 * jy) / ny as f32;
                offsets.push(match self.filter == PixelFilter::default() {
                    true => [(u * SUBPIXEL as f32) as i64, (v * SUBPIXEL as f32) as i64],
                    false => [self.at(u), self.at(v)],
                });
            }
        }
        offsets
    }
}

/// The offsets of the samples of one rectangle of pixels (a tile), looked up by pixel.
#[derive(Clone, Debug, Default)]
pub struct TileOffsets {
    x0: usize,
    y0: usize,
    width: usize,
    spp: usize,
    /// Every pixel's spp offsets, row by row; or one pixel's, when all pixels share them.
    offsets: Vec<[i64; 2]>,
    same: bool,
}

impl TileOffsets {
    /// The offsets of pixels x0..x0 + width by y0..y0 + height.
    #[cfg(any(test, feature = "internals"))]
    pub fn of(pattern: &SamplePattern, rect: (usize, usize, usize, usize)) -> TileOffsets {
        let mut tile = TileOffsets::default();
        tile.fill(pattern, rect);
        tile
    }

    /// Makes these the offsets of `rect` = (x0, y0, width, height), reusing the storage.
    pub fn fill(&mut self, pattern: &SamplePattern, (x0, y0, width, height): (usize, usize, usize, usize)) {
        let spp = pattern.count();
        (self.x0, self.y0, self.width, self.spp) = (x0, y0, width, spp);
        self.same = pattern.shared_offsets().is_some();
        let pixels = if self.same { 1 } else { width * height };
        self.offsets.resize(pixels * spp, [0, 0]);
        for (p, out) in self.offsets.chunks_exact_mut(spp).enumerate() {
            pattern.offsets_into(x0 + p % width.max(1), y0 + p / width.max(1), out);
        }
    }

    /// The offsets every pixel shares, where they do.
    #[inline]
    pub fn shared(&self) -> Option<&[[i64; 2]]> {
        self.same.then_some(&self.offsets[..])
    }

    /// The offsets of pixel (x, y) (screen coordinates, within the rectangle).
    #[inline]
    pub fn at(&self, x: usize, y: usize) -> &[[i64; 2]] {
        if self.same {
            return &self.offsets;
        }
        let p = (y - self.y0) * self.width + (x - self.x0);
        &self.offsets[p * self.spp..(p + 1) * self.spp]
    }

    /// The offset of sample `s` of pixel (x, y) in pixels.
    #[inline]
    pub fn offset(&self, x: usize, y: usize, s: usize) -> (f32, f32) {
        let [ox, oy] = self.at(x, y)[s];
        (ox as f32 / SUBPIXEL as f32, oy as f32 / SUBPIXEL as f32)
    }
}

/// Point `i` of the 2D Sobol sequence (the van der Corput sequence and Sobol's second dimension), as
/// 32-bit fractions.
fn sobol2(i: u32) -> [u32; 2] {
    let (mut y, mut v, mut k) = (0u32, 1u32 << 31, i);
    while k != 0 {
        if k & 1 == 1 {
            y ^= v;
        }
        k >>= 1;
        v ^= v >> 1;
    }
    [i.reverse_bits(), y]
}

/// A nested uniform (Owen) scramble of a 32-bit fraction by a hash: each bit flipped by a hash of the bits
/// above it, which keeps every stratification of the points (Burley 2020, with Vegdahl's constants).
#[inline]
fn owen_scramble(v: u32, seed: u32) -> u32 {
    let mut v = v.reverse_bits();
    v ^= v.wrapping_mul(0x3d20_adea);
    v = v.wrapping_add(seed);
    v = v.wrapping_mul((seed >> 16) | 1);
    v ^= v.wrapping_mul(0x0552_6c56);
    v ^= v.wrapping_mul(0x53a2_2864);
    v.reverse_bits()
}

/// A pixel's scrambling seed.
#[inline]
fn pixel_seed(x: usize, y: usize) -> u32 {
    mix((x as u32).wrapping_mul(0x8da6_b343) ^ (y as u32).wrapping_mul(0xd816_3841) ^ 0x2545_f491)
}

#[inline]
fn mix(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^ (x >> 16)
}

fn hash01(k: usize) -> f32 {
    let mut x = (k as u32).wrapping_mul(0x9E37_79B9) ^ 0x85EB_CA6B;
    x ^= x >> 16;
    x = x.wrapping_mul(0x7FEB_352D);
    x ^= x >> 15;
    (x >> 8) as f32 / (1u32 << 24) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    fn offsets(pattern: &SamplePattern, x: usize, y: usize) -> Vec<[i64; 2]> {
        let mut out = vec![[0, 0]; pattern.count()];
        pattern.offsets_into(x, y, &mut out);
        out
    }

    #[test]
    fn stratified_has_one_sample_per_stratum() {
        let centre = SamplePattern::new(1, Sampler::Stratified, PixelFilter::default()).unwrap();
        assert_eq!(offsets(&centre, 3, 4), vec![[SUBPIXEL / 2, SUBPIXEL / 2]]);
        for (spp, nx, ny) in [(4, 2, 2), (16, 4, 4), (6, 3, 2), (7, 7, 1), (64, 8, 8)] {
            let p = SamplePattern::new(spp, Sampler::Stratified, PixelFilter::default()).unwrap();
            let mut seen = vec![false; spp];
            for [x, y] in offsets(&p, 0, 0) {
                let cell = (y as usize * ny / SUBPIXEL as usize) * nx + x as usize * nx / SUBPIXEL as usize;
                assert!(!seen[cell], "{spp} spp: two samples in stratum {cell}");
                seen[cell] = true;
            }
            assert_eq!(offsets(&p, 0, 0), offsets(&p, 9, 5), "stratified is the same in every pixel");
        }
    }

    /// Owen-scrambled Sobol points at a power of two are a (0, m, 2)-net in every pixel: every elementary
    /// box of area 1/spp (1 x spp, 2 x spp/2, ...) holds exactly one sample; and pixels differ.
    #[test]
    fn scrambled_sobol_is_a_net_in_every_pixel() {
        for spp in [4usize, 16, 64, 256] {
            let p = SamplePattern::new(spp, Sampler::Sobol, PixelFilter::default()).unwrap();
            for (x, y, seed) in [(0, 0, 0), (1, 0, 0), (17, 33, 0), (1919, 1079, 0), (17, 33, 3)] {
                let o = offsets(&p.clone().seeded(seed), x, y);
                let mut nx = 1;
                while nx <= spp {
                    let ny = spp / nx;
                    let mut seen = vec![false; spp];
                    for &[ox, oy] in &o {
                        assert!((0..SUBPIXEL).contains(&ox) && (0..SUBPIXEL).contains(&oy));
                        let cell = (oy as usize * ny / SUBPIXEL as usize) * nx + ox as usize * nx / SUBPIXEL as usize;
                        assert!(!seen[cell], "{spp} spp, pixel ({x},{y}): boxes {nx}x{ny} not a net");
                        seen[cell] = true;
                    }
                    nx *= 2;
                }
            }
            assert_ne!(offsets(&p, 0, 0), offsets(&p, 1, 0));
            assert_ne!(offsets(&p, 0, 0), offsets(&p, 0, 1));
            let other = p.clone().seeded(7);
            assert_ne!(offsets(&p, 5, 5), offsets(&other, 5, 5), "the seed changes the scramble");
        }
    }

    /// Warped samples are distributed as the filter's magnitude: the histogram of 64k Sobol samples over
    /// the support against the filter integrated over each bin, and their signs as the filter's.
    #[test]
    fn warped_samples_follow_the_filter() {
        for name in ["tent", "gaussian", "mitchell", "lanczos", "box:1.5"] {
            let filter = PixelFilter::parse(name).unwrap();
            let p = SamplePattern::new(MAX_SPP, Sampler::Sobol, filter).unwrap();
            let r = filter.radius();
            const BINS: usize = 16;
            let mut hist = [0usize; BINS];
            let mut negative = 0usize;
            let n = 16;
            for pixel in 0..n {
                for &[ox, oy] in &offsets(&p, pixel, 3) {
                    let x = ox as f32 / SUBPIXEL as f32 - 0.5;
                    assert!(x.abs() <= r + 1.0 / SUBPIXEL as f32, "{name}: {x} outside the radius");
                    let bin = (((x + r) / (2.0 * r)) * BINS as f32).clamp(0.0, BINS as f32 - 1.0) as usize;
                    hist[bin] += 1;
                    negative += (p.weight([ox, oy]) < 0.0) as usize;
                }
            }
            let total = (n * MAX_SPP) as f64;
            let integral = |a: f64, b: f64| {
                let steps = 400;
                (0..steps)
                    .map(|i| filter.eval((a + (b - a) * (i as f64 + 0.5) / steps as f64) as f32).abs() as f64)
                    .sum::<f64>()
                    * (b - a)
                    / steps as f64
            };
            let whole = integral(-r as f64, r as f64);
            for (b, &count) in hist.iter().enumerate() {
                let a = -r as f64 + 2.0 * r as f64 * b as f64 / BINS as f64;
                let expected = integral(a, a + 2.0 * r as f64 / BINS as f64) / whole;
                let got = count as f64 / total;
                assert!((got - expected).abs() < 0.004 + 0.02 * expected, "{name} bin {b}: {got} vs {expected}");
            }
            // The negative share of a separable filter: 2 n (1 - n) where n is the 1D negative share.
            let neg1 = {
                let steps = 4000;
                let dx = 2.0 * r as f64 / steps as f64;
                (0..steps)
                    .map(|i| filter.eval((-r as f64 + (i as f64 + 0.5) * dx) as f32))
                    .filter(|f| *f < 0.0)
                    .map(|f| -f as f64 * dx)
                    .sum::<f64>()
                    / whole
            };
            let expected = 2.0 * neg1 * (1.0 - neg1);
            let got = negative as f64 / total;
            assert!((got - expected).abs() < 0.005, "{name}: {got} of samples negative, expected {expected}");
            assert_eq!(p.reach(), (r - 0.5).ceil() as usize);
        }
    }

    #[test]
    fn filters_parse_and_check() {
        assert_eq!(PixelFilter::parse("box").unwrap(), PixelFilter::default());
        assert_eq!(PixelFilter::parse("gaussian:3").unwrap(), PixelFilter::Gaussian { radius: 3.0, sigma: 1.0 });
        assert!(PixelFilter::parse("sinc").unwrap_err().to_string().contains("mitchell"));
        assert!(PixelFilter::parse("tent:0.1").unwrap_err().to_string().contains("radius"));
        assert!(PixelFilter::parse("tent:x").is_err());
        assert!(SamplePattern::new(0, Sampler::Sobol, PixelFilter::default()).is_err());
        assert!(SamplePattern::new(MAX_SPP + 1, Sampler::Sobol, PixelFilter::default()).is_err());
        // Mitchell at 0 is (6 - 2B) / 6 and reaches zero at its radius; Lanczos is 1 at 0 and 0 at each integer.
        let m = PixelFilter::parse("mitchell").unwrap();
        assert!((m.eval(0.0) - (6.0 - 2.0 / 3.0) / 6.0).abs() < 1e-6 && m.eval(2.0).abs() < 1e-6);
        let l = PixelFilter::parse("lanczos").unwrap();
        assert!((l.eval(0.0) - 1.0).abs() < 1e-6 && l.eval(1.0).abs() < 1e-6 && l.eval(2.0).abs() < 1e-6);
    }
}
