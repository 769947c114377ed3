//! Sums of noise over octaves (the slides' "turbulence"): fBm = sum of noise(f p) / f (1/f noise) and
//! turbulence = sum of |noise(f p)| / f, with f = lacunarity^i and amplitude gain^i.
//!
//! Band limiting ("limit the sum to the Nyquist limit of the current pixel sampling"): `width` is the size
//! of the pixel in the noise's lattice units at the first octave (the square root of its area, as the
//! slides' MIP level d). At octave i the pixel spans s = width * f_i lattice cells; noise has most of its
//! energy near half a cycle per cell, whose Nyquist limit is one sample per cell, so the octave's weight
//! falls smoothly from 1 at s = 1/2 to 0 at s = 1. (Fading from 1/4 to 1/2 instead blurs more: on the
//! grazing-plane test, tests/integration/procedural_aliasing.rs, the RMS error against 256 spp is 0.039 instead of
//! 0.034.) What a faded octave no longer adds is replaced by its mean (0 for noise, E|noise| for
//! turbulence), so a distant surface keeps its average brightness.

use super::perlin::{NoiseD, Perlin, LANES};

/// The pixel size (in lattice cells) at which an octave starts to fade out.
pub const FADE_START: f32 = 0.5;
/// The pixel size at which it is gone.
pub const FADE_END: f32 = 1.0;

/// The mean of |noise| over space, measured over 10^7 points (see the test below), per variant and dimension.
fn mean_abs(noise: &Perlin, dims: usize) -> f32 {
    use super::perlin::Variant;
    match (noise.variant(), dims) {
        (Variant::Improved, 3) => MEAN_ABS_IMPROVED_3D,
        (Variant::Improved, _) => MEAN_ABS_IMPROVED_2D,
        (Variant::Hashed, 3) => MEAN_ABS_HASHED_3D,
        (Variant::Hashed, _) => MEAN_ABS_HASHED_2D,
        (Variant::Classic, 3) => MEAN_ABS_CLASSIC_3D,
        (Variant::Classic, _) => MEAN_ABS_CLASSIC_2D,
    }
}

const MEAN_ABS_IMPROVED_3D: f32 = 0.2204;
const MEAN_ABS_IMPROVED_2D: f32 = 0.2166;
// The improved gradients drawn independently at every corner (the permutation table's 2D hash is not quite).
const MEAN_ABS_HASHED_3D: f32 = 0.2203;
const MEAN_ABS_HASHED_2D: f32 = 0.2134;
// The classic noise's gradients are random, so its mean depends slightly on the seed (about 1%).
const MEAN_ABS_CLASSIC_3D: f32 = 0.1471;
const MEAN_ABS_CLASSIC_2D: f32 = 0.1724;

/// One axis of the points of a bulk evaluation: a coordinate for each point, or one for all of them (the
/// rows of an image).
#[derive(Clone, Copy)]
pub(super) enum Axis<'a> {
    Each(&'a [f32]),
    All(f32),
}

impl Axis<'_> {
    /// The coordinate of point i.
    fn at(&self, i: usize) -> f32 {
        match self {
            Axis::Each(c) => c[i],
            Axis::All(c) => *c,
        }
    }

    /// The coordinates of the eight points from i.
    fn lanes(&self, i: usize) -> [f32; LANES] {
        match self {
            Axis::Each(c) => c[i..i + LANES].try_into().expect("one lane group"),
            Axis::All(c) => [*c; LANES],
        }
    }
}

/// Which sum.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sum {
    /// sum noise / f: smooth, zero mean.
    Fbm,
    /// sum |noise| / f: creases where noise crosses zero (the abs adds first-derivative discontinuities).
    Turbulence,
}

/// The octave parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Octaves {
    pub count: u32,
    /// Frequency ratio between octaves (2: one octave per doubling).
    pub lacunarity: f32,
    /// Amplitude ratio between octaves (0.5: 1/f).
    pub gain: f32,
}

impl Default for Octaves {
    fn default() -> Self {
        Octaves { count: 6, lacunarity: 2.0, gain: 0.5 }
    }
}

/// The most octaves a sum may have (beyond 24 doublings f32 coordinates have no fraction left).
pub const MAX_OCTAVES: u32 = 24;

/// A fractal sum of one noise over octaves.
#[derive(Clone, Debug)]
pub struct Fractal {
    pub sum: Sum,
    /// One noise per octave: the same table, with the period scaled by the octave's frequency when tileable.
    noises: Vec<Perlin>,
    /// Per octave: frequency and amplitude.
    freq: Vec<f32>,
    amp: Vec<f32>,
}

/// Each octave is shifted by a multiple of this vector so that the octaves' lattices (and their zeros at
/// the origin) do not line up.
const OCTAVE_SHIFT: [f32; 3] = [0.379, 0.617, 0.853];

impl Fractal {
    /// A sum of `octaves` of `noise`. A tileable noise keeps tiling at every octave when the lacunarity is
    /// a whole number (its period is multiplied by lacunarity^i).
    pub fn new(noise: Perlin, sum: Sum, octaves: Octaves) -> Fractal {
        let count = octaves.count.clamp(1, MAX_OCTAVES) as usize;
        let mut noises = Vec::with_capacity(count);
        let (mut freq, mut amp) = (Vec::with_capacity(count), Vec::with_capacity(count));
        let (mut f, mut a) = (1.0f32, 1.0f32);
        for _ in 0..count {
            noises.push(match noise.period() {
                Some(p) => noise.clone().with_period(p.map(|c| (c as f32 * f).round() as u32)),
                None => noise.clone(),
            });
            freq.push(f);
            amp.push(a);
            f *= octaves.lacunarity;
            a *= octaves.gain;
        }
        Fractal { sum, noises, freq, amp }
    }

    /// The largest value the sum can reach in magnitude, for |noise| <= 1: sum of the amplitudes.
    pub fn amplitude_sum(&self) -> f32 {
        self.amp.iter().sum()
    }

    /// Whether a pixel `width` lattice cells wide sees every octave at full weight (no band limiting).
    pub fn all_octaves_resolved(&self, width: f32) -> bool {
        self.freq.last().is_none_or(|f| width * f <= FADE_START)
    }

    /// The weight of octave `i` for a pixel of `width` lattice cells at the first octave.
    #[inline(always)]
    fn weight(&self, i: usize, width: f32) -> f32 {
        let s = width * self.freq[i];
        let t = ((FADE_END - s) / (FADE_END - FADE_START)).clamp(0.0, 1.0);
        t * t * (3.0 - 2.0 * t)
    }

    #[inline(always)]
    fn shifted(&self, i: usize, p: [f32; 3]) -> [f32; 3] {
        let (f, k) = (self.freq[i], i as f32);
        [p[0] * f + k * OCTAVE_SHIFT[0], p[1] * f + k * OCTAVE_SHIFT[1], p[2] * f + k * OCTAVE_SHIFT[2]]
    }

    /// The sum at `p` (3D, or 2D with p[2] ignored when `dims` is 2) and its gradient with respect to p,
    /// for a pixel `width` lattice cells wide (0: every octave).
    #[inline]
    pub fn eval_d(&self, p: [f32; 3], dims: usize, width: f32) -> NoiseD {
        let mut out = NoiseD::default();
        for i in 0..self.noises.len() {
            let w = self.weight(i, width);
            let (a, mean) = (self.amp[i], self.mean(i, dims));
            if w == 0.0 {
                // Every later octave is finer still.
                for rest in i..self.noises.len() {
                    out.value += self.amp[rest] * mean;
                }
                break;
            }
            let q = self.shifted(i, p);
            let mut n =
                if dims == 2 { self.noises[i].noise2_d(q[0], q[1]) } else { self.noises[i].noise3_d(q[0], q[1], q[2]) };
            if self.sum == Sum::Turbulence && n.value < 0.0 {
                n.value = -n.value;
                n.grad = n.grad.map(|g| -g);
            }
            out.value += a * (w * n.value + (1.0 - w) * mean);
            let k = a * w * self.freq[i];
            for axis in 0..3 {
                out.grad[axis] += k * n.grad[axis];
            }
        }
        out
    }

    /// The sum at `p` without its gradient.
    #[inline]
    pub fn eval(&self, p: [f32; 3], dims: usize, width: f32) -> f32 {
        let mut value = 0.0;
        for i in 0..self.noises.len() {
            let w = self.weight(i, width);
            let mean = self.mean(i, dims);
            if w == 0.0 {
                for rest in i..self.noises.len() {
                    value += self.amp[rest] * mean;
                }
                break;
            }
            let q = self.shifted(i, p);
            let n = if dims == 2 { self.noises[i].noise2(q[0], q[1]) } else { self.noises[i].noise3(q[0], q[1], q[2]) };
            let n = if self.sum == Sum::Turbulence { n.abs() } else { n };
            value += self.amp[i] * (w * n + (1.0 - w) * mean);
        }
        value
    }

    #[inline(always)]
    fn mean(&self, i: usize, dims: usize) -> f32 {
        match self.sum {
            Sum::Fbm => 0.0,
            Sum::Turbulence => mean_abs(&self.noises[i], dims),
        }
    }

    /// The full sum (no band limit) at eight 3D points at once.
    #[inline]
    pub fn eval3_lanes(&self, x: &[f32; LANES], y: &[f32; LANES], z: &[f32; LANES]) -> [f32; LANES] {
        let mut out = [0.0; LANES];
        for i in 0..self.noises.len() {
            let (f, k, a) = (self.freq[i], i as f32, self.amp[i]);
            let q = |c: &[f32; LANES], axis: usize| c.map(|v| v * f + k * OCTAVE_SHIFT[axis]);
            let n = self.noises[i].noise3_lanes(&q(x, 0), &q(y, 1), &q(z, 2));
            for l in 0..LANES {
                out[l] += a * if self.sum == Sum::Turbulence { n[l].abs() } else { n[l] };
            }
        }
        out
    }

    /// The full sum (no band limit) at eight 2D points at once.
    #[inline]
    pub fn eval2_lanes(&self, x: &[f32; LANES], y: &[f32; LANES]) -> [f32; LANES] {
        let mut out = [0.0; LANES];
        for i in 0..self.noises.len() {
            let (f, k, a) = (self.freq[i], i as f32, self.amp[i]);
            let q = |c: &[f32; LANES], axis: usize| c.map(|v| v * f + k * OCTAVE_SHIFT[axis]);
            let n = self.noises[i].noise2_lanes(&q(x, 0), &q(y, 1));
            for l in 0..LANES {
                out[l] += a * if self.sum == Sum::Turbulence { n[l].abs() } else { n[l] };
            }
        }
        out
    }

    /// The octaves as a sixteen-lane sum, where the CPU has AVX-512 and the noise is the hashed one.
    #[cfg(target_arch = "x86_64")]
    fn wide_octaves(&self) -> Option<Vec<super::simd512::Octave>> {
        (0..self.noises.len())
            .map(|i| {
                // The lanes' octave point, p * f + k * shift, with k * shift rounded as there.
                let shift = OCTAVE_SHIFT.map(|s| i as f32 * s);
                self.noises[i].wide_octave(self.freq[i], shift, self.amp[i])
            })
            .collect()
    }

    /// The full sum at every whole group of sixteen points of D dimensions (`p`: each axis's coordinates)
    /// where `wide_octaves` runs; returns how many points it wrote.
    fn wide_eval<const D: usize>(&self, p: [Axis; D], out: &mut [f32]) -> usize {
        #[cfg(target_arch = "x86_64")]
        if let Some(o) = self.wide_octaves() {
            return super::simd512::sum(&o, self.sum == Sum::Turbulence, p, out);
        }
        let _ = (p, out);
        0
    }

    /// The full 2D sum at every point of two coordinate slices into `out`.
    pub fn eval2_many(&self, x: &[f32], y: &[f32], out: &mut [f32]) {
        assert!(x.len() == out.len() && y.len() == out.len(), "coordinate slices must match the output");
        self.eval2_axes([Axis::Each(x), Axis::Each(y)], out);
    }

    /// The full 2D sum along a row: at (x[i], y) for every i, into `out`. The same values as `eval2_many`
    /// with y repeated; the sixteen-lane kernel works out each octave's lattice row once.
    pub fn eval2_row(&self, x: &[f32], y: f32, out: &mut [f32]) {
        assert!(x.len() == out.len(), "the coordinate slice must match the output");
        self.eval2_axes([Axis::Each(x), Axis::All(y)], out);
    }

    /// The full 2D sum at every point of the two axes into `out`: sixteen lanes, then eight, then one at a time.
    fn eval2_axes(&self, [x, y]: [Axis; 2], out: &mut [f32]) {
        let n = out.len();
        let wide = self.wide_eval([x, y], out);
        let full = wide + (n - wide) / LANES * LANES;
        for i in (wide..full).step_by(LANES) {
            out[i..i + LANES].copy_from_slice(&self.eval2_lanes(&x.lanes(i), &y.lanes(i)));
        }
        for (i, o) in out.iter_mut().enumerate().skip(full) {
            *o = self.eval([x.at(i), y.at(i), 0.0], 2, 0.0);
        }
    }

    /// The full 3D sum at every point of three coordinate slices into `out`.
    pub fn eval3_many(&self, x: &[f32], y: &[f32], z: &[f32], out: &mut [f32]) {
        let n = out.len();
        assert!(x.len() == n && y.len() == n && z.len() == n, "coordinate slices must match the output");
        let [x, y, z] = [x, y, z].map(Axis::Each);
        let wide = self.wide_eval([x, y, z], out);
        let full = wide + (n - wide) / LANES * LANES;
        for i in (wide..full).step_by(LANES) {
            out[i..i + LANES].copy_from_slice(&self.eval3_lanes(&x.lanes(i), &y.lanes(i), &z.lanes(i)));
        }
        for (i, o) in out.iter_mut().enumerate().skip(full) {
            *o = self.eval([x.at(i), y.at(i), z.at(i)], 3, 0.0);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::perlin::Variant;
    use super::*;

    /// Along a row (one y for every point) the sum is the same, to the bit, as at each point alone: on the
    /// sixteen-lane kernel where the CPU has AVX-512, on eight lanes, and one point at a time.
    #[test]
    fn rows_equal_points_to_the_bit() {
        // 45 points: two groups of sixteen, one of eight, five single points.
        let x: Vec<f32> = (0..45).map(|i| -3.7 + i as f32 * 0.61).collect();
        for (sum, period) in [(Sum::Fbm, None), (Sum::Turbulence, None), (Sum::Fbm, Some([4, 4, 1]))] {
            for y in [-2.3f32, 0.0, 0.37, 5.999] {
                let noise = Perlin::new(Variant::Hashed, 9);
                let noise = if let Some(p) = period { noise.with_period(p) } else { noise };
                let fractal = Fractal::new(noise, sum, Octaves { count: 5, ..Octaves::default() });
                let (mut row, mut many) = (vec![0.0; x.len()], vec![0.0; x.len()]);
                fractal.eval2_row(&x, y, &mut row);
                fractal.eval2_many(&x, &vec![y; x.len()], &mut many);
                for (i, (r, m)) in row.iter().zip(&many).enumerate() {
                    let single = fractal.eval([x[i], y, 0.0], 2, 0.0);
                    assert_eq!(r.to_bits(), single.to_bits(), "{sum:?} {period:?} y {y} point {i}: {r} vs {single}");
                    assert_eq!(m.to_bits(), single.to_bits(), "{sum:?} {period:?} y {y} point {i}: {m} vs {single}");
                }
            }
        }
    }
}
