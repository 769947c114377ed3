//! Trilinear lookups of a repeating 8-bit texture on eight lanes: the usual case of a colour texture on a
//! rendered surface. `trilinear8` serves the packet shader, eight lookups at once: levels, weights and tap
//! positions are computed on all lanes, and the texels are gathered where all lanes read one level, else
//! read lane by lane. `trilinear_taps8` serves one lookup, its eight taps (four per level) on the lanes.
//! Both equal `mip::trilinear` (within f32 rounding).

use super::footprint::{floor_log2_above_one, mip_level_of};
use super::rgba8::Rgba8Plane;
use super::texel::TexelSource;
use super::{Footprint, Footprint8};
use crate::lanes::{log2, mul_add, permute, permute_f, sum_lanes, to_bits, CmpEq, CmpGt, CmpLt, F8, I8, LANES};
use glam::Vec4;

/// RGBA as four channel lanes.
pub type Rgba8 = [F8; 4];

/// The trilinear lookup at (s, t) (one period per unit, repeating) with footprints `fp` in the same units,
/// the level chosen by the longest pixel axis (Williams 1983).
#[inline]
pub fn trilinear8(levels: &[Rgba8Plane], s: F8, t: F8, fp: &Footprint8) -> Rgba8 {
    let (w, h) = (levels[0].width() as f32, levels[0].height() as f32);
    let (ux, vx) = (fp.dudx * F8::splat(w), fp.dvdx * F8::splat(h));
    let (uy, vy) = (fp.dudy * F8::splat(w), fp.dvdy * F8::splat(h));
    let len2 = (ux * ux + vx * vx).max(uy * uy + vy * vy);
    let last = (levels.len() - 1) as f32;
    // log2 of the longer axis, from its square; 0 below one texel.
    let level = len2.cmp_gt(F8::ONE).blend(F8::splat(0.5) * log2(len2), F8::ZERO);
    let level = level.min(F8::splat(last));
    let l0 = level.floor();
    let frac = level - l0;
    let (s, t) = (s - s.floor(), t - t.floor());
    // The texels' places wait only on the finer level read from len2's exponent (as in
    // `level_pair_from_exponent`); where the log2's level is another (it rounded up to an integer), the
    // lookup is made again on the log2's levels.
    let guess = fine_levels_from_exponent(len2, levels.len() - 1);
    if !guess.round_float().cmp_eq(l0).all() {
        return trilinear8_on_levels(levels, l0.as_array_ref().map(|l| l as usize), frac, s, t);
    }
    let l0 = guess.as_array_ref().map(|l| l as usize);
    trilinear8_on_levels(levels, l0, frac, s, t)
}

/// `trilinear8` on the finer levels `l0` (the coarser ones are one on), `frac` the coarser ones' shares.
#[inline(always)]
fn trilinear8_on_levels(levels: &[Rgba8Plane], l0: [usize; LANES], frac: F8, s: F8, t: F8) -> Rgba8 {
    let coarse = l0.map(|l| (l + 1).min(levels.len() - 1));
    let a = bilinear8(levels, &l0, s, t);
    if frac.cmp_gt(F8::ZERO).none() {
        return a;
    }
    lerp8(a, bilinear8(levels, &coarse, s, t), frac)
}

/// One trilinear lookup at (s, t) (one period per unit, repeating), the level chosen by the longest pixel
/// axis: `TrilinearTaps::at(...).sum()`.
#[inline]
pub fn trilinear_taps8(levels: &[Rgba8Plane], s: f32, t: f32, fp: &Footprint) -> Vec4 {
    TrilinearTaps::at(levels, s, t, fp).sum()
}

/// One trilinear lookup's eight taps, worked out but not yet read: the finer level's four bilinear taps
/// on lanes 0-3, the coarser level's on lanes 4-7, each weighted by its share of the result. A batch of
/// lookups works out many before it reads any, asking the cache for their texels first (`prefetch`), so
/// that the misses of a texture larger than the caches overlap.
pub struct TrilinearTaps<'a> {
    fine: &'a Rgba8Plane,
    coarse: &'a Rgba8Plane,
    /// Storage indices (see `Rgba8Plane::row_part8`), unclamped.
    index: I8,
    weight: F8,
}

impl<'a> TrilinearTaps<'a> {
    /// The taps of the lookup at (s, t) with footprint `fp`. The tap positions are worked out per axis
    /// first, on lanes (x, x + 1, y, y + 1) of each level, then paired up by two shuffles: half the
    /// arithmetic of working on the taps, so more lookups' cache misses overlap.
    ///
    /// The taps' places wait only on the finer level's number, which is read from the exponent of the
    /// footprint's squared length; the log2 that gives the levels' shares runs beside them, so a lookup's
    /// chain of dependent steps, and with it the time before its texels are asked for, is shorter.
    #[inline]
    pub fn at(levels: &'a [Rgba8Plane], s: f32, t: f32, fp: &Footprint) -> Self {
        let len2 = fp.longer_axis_squared(levels[0].width(), levels[0].height());
        let (fine, coarse, frac) = level_pair_from_exponent(len2, levels.len());
        Self::on_levels(levels, (fine, coarse, frac), s, t)
    }

    /// The taps at (s, t) on the levels `fine` and `coarse`, `frac` the coarser one's share.
    #[inline(always)]
    fn on_levels(levels: &'a [Rgba8Plane], (fine, coarse, frac): (usize, usize, f32), s: f32, t: f32) -> Self {
        let (fine, coarse) = (&levels[fine], &levels[coarse]);
        let (fw, fh, cw, ch) = (fine.width as i32, fine.height as i32, coarse.width as i32, coarse.height as i32);
        let size = I8::new([fw, fw, fh, fh, cw, cw, ch, ch]);
        let (s, t) = (s - s.floor(), t - t.floor());
        // Each lane's position along its axis, in texels of its level, and the texel column or row it reads:
        // the second tap of each axis is one texel on.
        let pos = F8::new([s, s, t, t, s, s, t, t]) * size.round_float() - F8::splat(0.5);
        let floor = pos.floor();
        let next = I8::new([0, 1, 0, 1, 0, 1, 0, 1]);
        // floor(pos) as an integer without waiting on the rounding (pos >= -0.5): truncated, one less below 0.
        let texel = wrapped(pos.fast_trunc_int() + to_bits(pos.cmp_lt(F8::ZERO)) + next, size);
        let (fb, cb) = (fine.blocks_per_row() as i32, coarse.blocks_per_row() as i32);
        let blocks = I8::new([0, 0, fb, fb, 0, 0, cb, cb]);
        let part = Rgba8Plane::parts8(texel, blocks, I8::new([0, 0, -1, -1, 0, 0, -1, -1]));
        // Tap k of a level is texel (x + (k & 1), y + (k >> 1)): its storage index is a column part plus a
        // row part.
        let (columns, rows) = (I8::new([0, 1, 0, 1, 4, 5, 4, 5]), I8::new([2, 2, 3, 3, 6, 6, 7, 7]));
        let index = permute(part, columns) + permute(part, rows);
        // The tent's weights per axis (1 - f for the first tap, f for the second), the level's share on x.
        let nextf = next.round_float();
        let tent = mul_add(pos - floor, nextf + nextf - F8::ONE, F8::ONE - nextf)
            * F8::new([1.0 - frac, 1.0 - frac, 1.0, 1.0, frac, frac, 1.0, 1.0]);
        let weight = permute_f(tent, columns) * permute_f(tent, rows);
        TrilinearTaps { fine, coarse, index, weight }
    }

    /// Asks the cache for the lines of the taps: each level's first and last tap, which share a 4 x 4 block
    /// with the other two unless the four straddle a corner of blocks (one lookup in sixteen).
    #[inline]
    pub fn prefetch(&self) {
        let index = self.index.as_array_ref();
        self.fine.prefetch_index(index[0]);
        self.fine.prefetch_index(index[3]);
        self.coarse.prefetch_index(index[4]);
        self.coarse.prefetch_index(index[7]);
    }

    /// The weighted sum of the taps.
    #[inline]
    pub fn sum(&self) -> Vec4 {
        let texels = Rgba8Plane::gather_split8(self.fine, self.coarse, self.index);
        Vec4::from(sum_lanes(texels.map(|c| c * self.weight)))
    }
}

/// `level_pair` of `mip_level_of(len2)` with the finer level read from len2's exponent: floor(log2(len2) / 2)
/// is half the exponent, rounded down. log2 rounded up to the next integer (len2 just below a power of two,
/// the exponent odd) gives that level a share of 0 and the coarser one a share of 1, where `level_pair` moves
/// one level on with shares of 1 and 0: the same texels of the same level with the same weights, summed in the
/// same order (`sum_lanes` adds the halves' sums, and x + 0 = x), so the same bits. (libm's log2f is never
/// below the exponent at or above a power of two, as a correctly rounded log2 is not; the tests hold both.)
#[inline]
fn level_pair_from_exponent(len2: f32, count: usize) -> (usize, usize, f32) {
    let last = count - 1;
    let fine = (floor_log2_above_one(len2) >> 1).min(last as u32) as usize;
    let level = mip_level_of(len2).min(last as f32);
    (fine, (fine + 1).min(last), level - fine as f32)
}

/// The finer level of `level_pair_from_exponent` on lanes.
#[inline]
fn fine_levels_from_exponent(len2: F8, last: usize) -> I8 {
    let half_exponent: I8 = ((to_bits(len2) >> 23_i32) - I8::splat(127)) >> 1_i32;
    to_bits(len2.cmp_gt(F8::ONE)) & half_exponent.min(I8::splat(last as i32))
}

/// Texel `k` in [-1, n] wrapped into [0, n).
#[inline]
fn wrapped(k: I8, n: I8) -> I8 {
    let k = k.cmp_lt(I8::splat(0)).blend(k + n, k);
    k.cmp_lt(n).blend(k, k - n)
}

/// a + (b - a) t, channel by channel.
#[inline]
pub(super) fn lerp8(a: Rgba8, b: Rgba8, t: F8) -> Rgba8 {
    std::array::from_fn(|c| a[c] + (b[c] - a[c]) * t)
}

/// Bilinear lookups at (s, t) in [0, 1], lane i on level `level[i]`, repeating.
#[inline]
fn bilinear8(levels: &[Rgba8Plane], level: &[usize; LANES], s: F8, t: F8) -> Rgba8 {
    if level.iter().all(|&l| l == level[0]) {
        bilinear8_on(&OneLevel(&levels[level[0]]), s, t)
    } else {
        bilinear8_on(&LevelPerLane(std::array::from_fn(|i| &levels[level[i]])), s, t)
    }
}

/// Where a lane lookup reads its texels: the levels' sizes and the texels at storage indices.
pub(super) trait LaneTexels {
    /// Width, height and blocks per block row, per lane.
    fn sizes(&self) -> [I8; 3];
    /// The texels at `index` (storage indices, see `Rgba8Plane::row_part8`), decoded.
    fn fetch(&self, index: I8) -> Rgba8;
}

/// Every lane on one level: the texels are gathered (the common case: a lookup's probes, or a packet
/// of neighbouring samples).
pub(super) struct OneLevel<'a>(pub &'a Rgba8Plane);

impl LaneTexels for OneLevel<'_> {
    #[inline]
    fn sizes(&self) -> [I8; 3] {
        [self.0.width, self.0.height, self.0.blocks_per_row()].map(|n| I8::splat(n as i32))
    }
    #[inline]
    fn fetch(&self, index: I8) -> Rgba8 {
        self.0.gather8(index)
    }
}

/// A level per lane: the texels are read lane by lane.
struct LevelPerLane<'a>([&'a Rgba8Plane; LANES]);

impl LaneTexels for LevelPerLane<'_> {
    #[inline]
    fn sizes(&self) -> [I8; 3] {
        let mut sizes = [[0i32; LANES]; 3];
        for (l, plane) in self.0.iter().enumerate() {
            sizes[0][l] = plane.width as i32;
            sizes[1][l] = plane.height as i32;
            sizes[2][l] = plane.blocks_per_row() as i32;
        }
        sizes.map(I8::new)
    }
    #[inline]
    fn fetch(&self, index: I8) -> Rgba8 {
        let index = index.as_array_ref();
        let mut words = [0i32; LANES];
        for l in 0..LANES {
            words[l] = self.0[l].word(index[l]) as i32;
        }
        // The levels of one texture share its decoding.
        self.0[0].decode8(I8::new(words))
    }
}

/// Bilinear lookups at (s, t) in [0, 1], repeating. Tap positions, wraps and weights run on the lanes.
#[inline]
pub(super) fn bilinear8_on(src: &impl LaneTexels, s: F8, t: F8) -> Rgba8 {
    BilinearTaps8::at(src, s, t).sum(src)
}

/// Eight bilinear lookups' taps, worked out but not yet read: their storage indices per row and column, and
/// the weights across.
pub(super) struct BilinearTaps8 {
    rows: [I8; 2],
    columns: [I8; 2],
    fx: F8,
    fy: F8,
}

impl BilinearTaps8 {
    /// The taps of the lookups at (s, t) in [0, 1], repeating.
    #[inline]
    pub(super) fn at(src: &impl LaneTexels, s: F8, t: F8) -> Self {
        let [w, h, blocks] = src.sizes();
        let (x, y) = (s * w.round_float() - F8::splat(0.5), t * h.round_float() - F8::splat(0.5));
        let (xf, yf) = (x.floor(), y.floor());
        // x is in [-0.5, w - 0.5]: the taps are floor(x) and the next, -1 and w wrapping round.
        let (i0, i1) = wrapped_pair(xf.fast_trunc_int(), w);
        let (j0, j1) = wrapped_pair(yf.fast_trunc_int(), h);
        BilinearTaps8 {
            rows: [Rgba8Plane::row_part8(j0, blocks), Rgba8Plane::row_part8(j1, blocks)],
            columns: [Rgba8Plane::column_part8(i0), Rgba8Plane::column_part8(i1)],
            fx: x - xf,
            fy: y - yf,
        }
    }

    /// Asks the cache for the lines of the first `lanes` lookups' taps on `plane`: each one's first and last
    /// tap, which share a 4 x 4 block with the other two unless the four straddle a corner of blocks.
    #[inline]
    pub(super) fn prefetch(&self, plane: &Rgba8Plane, lanes: usize) {
        let [first, _, _, last] = self.indices();
        for l in 0..lanes.min(LANES) {
            plane.prefetch_index(first.as_array_ref()[l]);
            plane.prefetch_index(last.as_array_ref()[l]);
        }
    }

    /// The taps' texel words on `plane` (taps 00, 10, 01, 11), gathered but not yet decoded: a lookup on
    /// two levels asks for all eight gathers before it waits on any.
    #[inline]
    pub(super) fn words(&self, plane: &Rgba8Plane) -> [I8; 4] {
        let [i00, i10, i01, i11] = self.indices();
        [plane.words8(i00), plane.words8(i10), plane.words8(i01), plane.words8(i11)]
    }

    /// The bilinear values of `words`, this lookup's taps' words on `plane`.
    #[inline]
    pub(super) fn sum_words(&self, plane: &Rgba8Plane, [w00, w10, w01, w11]: [I8; 4]) -> Rgba8 {
        self.weigh([plane.decode8(w00), plane.decode8(w10), plane.decode8(w01), plane.decode8(w11)])
    }

    /// The bilinear values. (The four taps written out: through an array's `map` the fetch was left out
    /// of line, a call per tap, 7% of the canonical frame on Intel.)
    #[inline]
    pub(super) fn sum(&self, src: &impl LaneTexels) -> Rgba8 {
        let [i00, i10, i01, i11] = self.indices();
        self.weigh([src.fetch(i00), src.fetch(i10), src.fetch(i01), src.fetch(i11)])
    }

    /// The storage indices of the taps 00, 10, 01, 11.
    #[inline]
    fn indices(&self) -> [I8; 4] {
        let ([r0, r1], [c0, c1]) = (self.rows, self.columns);
        [r0 + c0, r0 + c1, r1 + c0, r1 + c1]
    }

    /// The bilinear blend of the taps' decoded texels (00, 10, 01, 11).
    #[inline]
    fn weigh(&self, [t00, t10, t01, t11]: [Rgba8; 4]) -> Rgba8 {
        lerp8(lerp8(t00, t10, self.fx), lerp8(t01, t11, self.fx), self.fy)
    }
}

/// Texel `k` in [-1, n - 1] and the next one, both wrapped into [0, n).
#[inline]
fn wrapped_pair(k: I8, n: I8) -> (I8, I8) {
    (wrapped(k, n), wrapped(k + 1, n))
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::texture::mip::{level_pair, trilinear, LevelRule, MipFilter};
    use crate::texture::reconstruct::Addressing;
    use crate::texture::{Filterable, Wrap};
    use glam::Vec4;

    /// A 64 x 64 sRGB texture of noise, as a pyramid of 8-bit levels.
    pub(in crate::texture) fn noise_pyramid() -> Filterable<Rgba8Plane> {
        let bytes: Vec<[u8; 4]> =
            (0..64 * 64).map(|k| [(k * 37 % 251) as u8, (k * 91 % 256) as u8, (k * 13 % 199) as u8, 200]).collect();
        Filterable::new(Rgba8Plane::from_top_rows(64, 64, &bytes, true), MipFilter::Box, [Wrap::Repeat; 2])
    }

    /// Every power of two 2^e for e in `exponents` and the 63 floats on either side of it, with those below
    /// whose log2 rounds up to e (the case a level read from the exponent alone would get wrong) for an `e`
    /// that `counts`. At and above 2^e, log2 is held to be at least e (as the exponent's levels suppose).
    pub(in crate::texture) fn around_powers_of_two(
        exponents: std::ops::Range<i32>,
        counts: impl Fn(i32) -> bool,
    ) -> (Vec<f32>, usize) {
        let (mut values, mut rounded_up) = (Vec::new(), 0);
        for e in exponents {
            let p = (2.0f32).powi(e);
            for k in 1..64u32 {
                let (below, above) = (f32::from_bits(p.to_bits() - k), f32::from_bits(p.to_bits() + k));
                rounded_up += (counts(e) && below.log2() == e as f32) as usize;
                assert!(above.log2() >= e as f32, "log2({above}) = {} is below {e}", above.log2());
                values.extend([below, above]);
            }
            assert_eq!(p.log2(), e as f32);
            values.push(p);
        }
        (values, rounded_up)
    }

    #[test]
    fn levels_from_the_exponent_give_the_bits_of_the_log2_levels() {
        let data = noise_pyramid();
        let levels = data.levels();
        // Squared lengths at and just around every power of two the levels reach (half the exponent: an odd
        // one is one level short if log2 rounds up), and beyond the last level.
        let (mut lengths, rounded_up) = around_powers_of_two(0..28, |e| e % 2 == 1);
        assert!(rounded_up > 0, "no squared length whose log2 rounds up to the next integer was tried");
        lengths.extend([0.0, 0.5, f32::NAN, f32::INFINITY, 1e30]);
        for (k, &len2) in lengths.iter().enumerate() {
            let (s, t) = (k as f32 * 0.137 % 1.0, k as f32 * 0.291 % 1.0);
            let got = TrilinearTaps::on_levels(levels, level_pair_from_exponent(len2, levels.len()), s, t).sum();
            let exact = TrilinearTaps::on_levels(levels, level_pair(mip_level_of(len2), levels.len()), s, t).sum();
            assert_eq!(got.to_array().map(f32::to_bits), exact.to_array().map(f32::to_bits), "len2 {len2}");
        }
    }

    #[test]
    fn lanes_and_taps_on_lanes_equal_the_generic_trilinear() {
        // An odd-sized noisy sRGB texture, so every level differs.
        let (w, h) = (37, 20);
        let bytes: Vec<[u8; 4]> =
            (0..w * h).map(|k| [(k * 37 % 251) as u8, (k * 91 % 256) as u8, (k * 13 % 199) as u8, 255]).collect();
        let base = Rgba8Plane::from_top_rows(w, h, &bytes, true);
        let data = Filterable::new(base, MipFilter::Box, [Wrap::Repeat; 2]);
        let levels = data.levels();
        let addr = Addressing { wrap: [Wrap::Repeat; 2], border: Vec4::ZERO };
        // Magnified, one texel, several levels up, beyond the last level, anisotropic; wrapping coordinates.
        let sizes = [0.1, 1.0, 2.5, 7.0, 300.0, 3.0, 0.6, 12.0];
        let fp: [Footprint; LANES] = std::array::from_fn(|i| {
            let k = sizes[i] / w as f32;
            Footprint { dudx: k, dvdx: 0.3 * k, dudy: -0.2 * k, dvdy: k * if i == 5 { 4.0 } else { 1.0 } }
        });
        let s = F8::new([0.01, 0.5, 0.99, -0.2, 1.37, 0.25, 0.999_9, 3.5]);
        let t = F8::new([0.99, 0.02, 0.5, 2.75, -0.6, 0.33, 0.000_1, 0.5]);
        let got = trilinear8(levels, s, t, &Footprint8::from_lanes(&fp));
        for (i, fp) in fp.iter().enumerate() {
            let level = LevelRule::Longest.level(fp, w, h);
            let (si, ti) = (s.as_array_ref()[i], t.as_array_ref()[i]);
            let want = trilinear(levels, &addr, si, ti, level);
            let one = trilinear_taps8(levels, si, ti, fp);
            for c in 0..4 {
                let g = got[c].as_array_ref()[i];
                assert!((g - want[c]).abs() < 2e-5, "lane {i} channel {c}: {g} vs {}", want[c]);
                assert!((one[c] - want[c]).abs() < 2e-5, "one lookup {i} channel {c}: {} vs {}", one[c], want[c]);
            }
        }
    }

    /// Coordinates and footprints that are NaN, infinite or huge, on lanes whose levels differ (the lane-by-lane
    /// path) and on one level: every lookup reads inside the texture and returns without a panic.
    #[test]
    fn non_finite_coordinates_read_inside_the_texture() {
        let data = noise_pyramid();
        let levels = data.levels();
        let odd = [f32::NAN, f32::INFINITY, f32::NEG_INFINITY, 1e30, -1e30, 3.0e9, -0.0, 1.0];
        for sizes in
            [[0.5, 3.0, 9.0, 20.0, 0.1, 2.0, 40.0, 1.0], [2.0; LANES], [f32::NAN; LANES], [f32::INFINITY; LANES]]
        {
            for k in 0..LANES {
                let s = F8::new(std::array::from_fn(|l| odd[(l + k) % LANES]));
                let t = F8::new(std::array::from_fn(|l| odd[(l + 2 * k + 1) % LANES]));
                let fp = Footprint8::from_lanes(&sizes.map(|w| Footprint {
                    dudx: w / 64.0,
                    dvdx: 0.0,
                    dudy: 0.0,
                    dvdy: w / 64.0,
                }));
                trilinear8(levels, s, t, &fp);
                for l in 0..LANES {
                    trilinear_taps8(levels, s.as_array_ref()[l], t.as_array_ref()[l], &fp.lane(l));
                }
            }
        }
    }
}
