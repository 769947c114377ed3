//! Anisotropic MIP filtering: several trilinear probes spaced along the footprint's major axis, each on the
//! level of the minor axis (the major axis divided among the probes), averaged. Up to `max_aniso` probes;
//! beyond that ratio the level rises so the probes still cover the whole major axis.

use super::ewa::Axes;
use super::footprint::floor_log2_above_one;
use super::mip::{level_pair, trilinear};
use super::reconstruct::Addressing;
use super::rgba8::Rgba8Plane;
use super::texel::TexelSource;
use super::trilinear8::{lerp8, BilinearTaps8, OneLevel};
use super::wrap::Wrap;
use super::Footprint;
use crate::lanes::{lane_index, sum_lanes, CmpLt, F8, LANES};
use glam::{Vec2, Vec4};

/// Where one lookup's probes go: `count` trilinear probes on `level`, centred on the lookup and spread
/// evenly along `axis` (the whole major axis in (s, t) units).
struct Probes {
    count: usize,
    level: f32,
    /// floor(level) as read from the exponent of the probes' width (before the level is clamped to the
    /// pyramid): what the lane lookups place their taps by, without waiting on the log2.
    floor_level: u32,
    axis: Vec2,
}

impl Probes {
    fn of_footprint(fp: &Footprint, w: usize, h: usize, max_aniso: f32) -> Probes {
        let axes = Axes::of_footprint(fp, w, h);
        if !axes.major.is_finite() {
            return Probes { count: 1, level: f32::MAX, floor_level: u32::MAX, axis: Vec2::ZERO };
        }
        let ratio = if axes.minor > 0.0 { axes.major / axes.minor } else { f32::MAX };
        // Rounding in the axes puts an exact 8:1 footprint at 8.000002 as often as at 7.999998: a ratio
        // within 1e-4 (relative) above a whole number takes that number of probes, not one more.
        let count = (ratio.min(max_aniso) * (1.0 - 1e-4)).ceil().max(1.0) as usize;
        // Each probe covers an equal part of the major axis, and at least the minor axis.
        let width = (axes.major / count as f32).max(axes.minor);
        let (level, floor_level) = Probes::levels_of_width(width);
        let axis = Vec2::new(axes.dir.x * axes.major / w as f32, axes.dir.y * axes.major / h as f32);
        Probes { count, level, floor_level, axis }
    }

    /// The level of probes `width` texels wide (log2, 0 below one texel), and its floor from the exponent.
    fn levels_of_width(width: f32) -> (f32, u32) {
        (if width > 1.0 { width.log2() } else { 0.0 }, floor_log2_above_one(width))
    }

    /// Probe `k`'s offset along the axis: the centre of the k-th of `count` equal parts.
    #[inline]
    fn offset(&self, k: f32) -> f32 {
        (k + 0.5) / self.count as f32 - 0.5
    }
}

pub fn sample<S: TexelSource>(
    levels: &[S],
    addr: &Addressing<S::Texel>,
    s: f32,
    t: f32,
    fp: &Footprint,
    max_aniso: f32,
) -> S::Texel {
    let probes = Probes::of_footprint(fp, levels[0].width(), levels[0].height(), max_aniso);
    probe_by_probe(levels, addr, s, t, &probes)
}

/// The mean of the probes, one trilinear lookup each.
fn probe_by_probe<S: TexelSource>(
    levels: &[S],
    addr: &Addressing<S::Texel>,
    s: f32,
    t: f32,
    probes: &Probes,
) -> S::Texel {
    if probes.count == 1 {
        return trilinear(levels, addr, s, t, probes.level);
    }
    let mut sum = S::Texel::default();
    for k in 0..probes.count {
        let off = probes.offset(k as f32);
        sum = sum + trilinear(levels, addr, s + off * probes.axis.x, t + off * probes.axis.y, probes.level);
    }
    sum * (1.0 / probes.count as f32)
}

/// The same filter on a repeating 8-bit pyramid, its probes eight at a time on lanes: for 8:1 footprints
/// all eight probes of a lookup are one lane lookup per level.
///
/// Always inlined into `FilteredTexture::lookup`: left to the inliner, it was inlined or not as unrelated
/// code moved between codegen units, and out of line random 8:1 lookups one a call ran 10 - 15% slower.
#[inline(always)]
pub fn sample_rgba8_repeating(levels: &[Rgba8Plane], s: f32, t: f32, fp: &Footprint, max_aniso: f32) -> Vec4 {
    // Asked for first, the probes' texels on both levels arrive together, instead of the coarser level's
    // after the finer's: on a 4096^2 texture, random 8:1 lookups run a third faster.
    AnisoLookup::at(levels, s, t, fp, max_aniso).sum(levels, Prefetch::Ask)
}

/// The texels of the smallest level whose probes are asked of the cache ahead: 1 MB of them, a Zen 4
/// core's L2 (Intel's cores have 1.25 to 2 MB).
const PREFETCH_FROM_TEXELS: usize = 1 << 18;

/// Whether asking the cache ahead for the lines of probes whose finer level is `fine` pays: not where that
/// level fits in a core's L2, where asking costs more than it saves.
#[inline]
fn worth_asking(fine: &Rgba8Plane) -> bool {
    fine.width * fine.height >= PREFETCH_FROM_TEXELS
}

/// Lookups of up to this many probes take them one by one: a lane lookup costs about three scalar probes.
const SCALAR_PROBES_UP_TO: usize = 3;

/// Whether `AnisoLookup::sum` asks the cache for each chunk's texel lines before it gathers them: one lookup
/// alone does, a batch asked for them all at once beforehand (`AnisoLookup::prefetch`).
#[derive(Clone, Copy, PartialEq)]
pub enum Prefetch {
    Ask,
    AlreadyAsked,
}

/// One anisotropic lookup on a repeating 8-bit pyramid, its probes placed but not yet read: a batch of
/// lookups places many before it reads any, asking the cache for their texels first (`prefetch`), so that
/// the misses of a texture larger than the caches overlap.
pub struct AnisoLookup {
    s: f32,
    t: f32,
    probes: Probes,
}

/// The taps of eight probes on the finer level, and on the coarser one where it weighs.
type ChunkTaps = (BilinearTaps8, Option<BilinearTaps8>);

impl AnisoLookup {
    #[inline]
    pub fn at(levels: &[Rgba8Plane], s: f32, t: f32, fp: &Footprint, max_aniso: f32) -> Self {
        AnisoLookup { s, t, probes: Probes::of_footprint(fp, levels[0].width(), levels[0].height(), max_aniso) }
    }

    /// Asks the cache for the lines of every probe's taps on both levels, unless the finer level fits in a
    /// core's L2 (`worth_asking`).
    pub fn prefetch(&self, levels: &[Rgba8Plane]) {
        let (fine, coarse, frac) = level_pair(self.probes.level, levels.len());
        if !worth_asking(&levels[fine]) {
            return;
        }
        for chunk in (0..self.probes.count).step_by(LANES) {
            let taps = self.chunk_taps(&levels[fine], &levels[coarse], frac, chunk);
            self.ask_for(&taps, &levels[fine], &levels[coarse], chunk);
        }
    }

    /// The filtered value: the mean of the probes, on lanes where there are enough of them to fill lanes.
    pub fn sum(&self, levels: &[Rgba8Plane], prefetch: Prefetch) -> Vec4 {
        let probes = &self.probes;
        if probes.count <= SCALAR_PROBES_UP_TO {
            if prefetch == Prefetch::Ask {
                self.prefetch(levels);
            }
            let addr = Addressing { wrap: [Wrap::Repeat; 2], border: Vec4::ZERO };
            return probe_by_probe(levels, &addr, self.s, self.t, probes);
        }
        // The taps' places wait only on the level read from the exponent; the log2's level gives the
        // coarser level's share. Where the log2 rounded up to the next integer (the share would be 1), or
        // a log2 less exact than libm's fell below the exponent, the lookup is made on the log2's levels
        // instead, so that the bits are theirs.
        let last = levels.len() - 1;
        let fine = (probes.floor_level as usize).min(last);
        let frac = probes.level.min(last as f32) - fine as f32;
        if !(0.0..1.0).contains(&frac) {
            return self.sum_on_log2_levels(levels, prefetch);
        }
        self.sum_on((&levels[fine], &levels[(fine + 1).min(last)], frac), prefetch)
    }

    /// `sum` where the exponent's level is not the log2's.
    #[cold]
    #[inline(never)]
    fn sum_on_log2_levels(&self, levels: &[Rgba8Plane], prefetch: Prefetch) -> Vec4 {
        let (fine, coarse, frac) = level_pair(self.probes.level, levels.len());
        self.sum_on((&levels[fine], &levels[coarse], frac), prefetch)
    }

    /// The mean of the probes on lanes, on the levels `fine` and `coarse`, `frac` the coarser one's share.
    #[inline(always)]
    fn sum_on(&self, (fine, coarse, frac): (&Rgba8Plane, &Rgba8Plane, f32), prefetch: Prefetch) -> Vec4 {
        let probes = &self.probes;
        let ask = prefetch == Prefetch::Ask && worth_asking(fine);
        let mut sum = [F8::ZERO; 4];
        for chunk in (0..probes.count).step_by(LANES) {
            let taps = self.chunk_taps(fine, coarse, frac, chunk);
            if ask {
                self.ask_for(&taps, fine, coarse, chunk);
            }
            // Both levels' texels are asked for before either is decoded.
            let (fine_taps, coarse_taps) = taps;
            let fine_words = fine_taps.words(fine);
            let coarse_gathered = coarse_taps.map(|taps| {
                let words = taps.words(coarse);
                (taps, words)
            });
            let mut value = fine_taps.sum_words(fine, fine_words);
            if let Some((taps, words)) = coarse_gathered {
                value = lerp8(value, taps.sum_words(coarse, words), F8::splat(frac));
            }
            // Lanes past the last probe add nothing.
            let live = (lane_index() + F8::splat(chunk as f32)).cmp_lt(F8::splat(probes.count as f32));
            for c in 0..4 {
                sum[c] += live.blend(value[c], F8::ZERO);
            }
        }
        Vec4::from(sum_lanes(sum)) * (1.0 / probes.count as f32)
    }

    /// The taps of probes `chunk..chunk + 8` on `fine`, and on `coarse` where its weight `frac` is not 0.
    #[inline]
    fn chunk_taps(&self, fine: &Rgba8Plane, coarse: &Rgba8Plane, frac: f32, chunk: usize) -> ChunkTaps {
        let (ps, pt) = self.positions(chunk);
        (BilinearTaps8::at(&OneLevel(fine), ps, pt), (frac > 0.0).then(|| BilinearTaps8::at(&OneLevel(coarse), ps, pt)))
    }

    /// Asks the cache for the lines of probes `chunk..chunk + 8`'s taps.
    #[inline]
    fn ask_for(&self, (fine_taps, coarse_taps): &ChunkTaps, fine: &Rgba8Plane, coarse: &Rgba8Plane, chunk: usize) {
        let lanes = self.probes.count - chunk;
        fine_taps.prefetch(fine, lanes);
        if let Some(taps) = coarse_taps {
            taps.prefetch(coarse, lanes);
        }
    }

    /// Where probes `chunk..chunk + 8` sit, in [0, 1).
    #[inline]
    fn positions(&self, chunk: usize) -> (F8, F8) {
        let probes = &self.probes;
        let k = lane_index() + F8::splat(chunk as f32);
        let off = (k + F8::splat(0.5)) * F8::splat(1.0 / probes.count as f32) - F8::splat(0.5);
        let (ps, pt) =
            (F8::splat(self.s) + off * F8::splat(probes.axis.x), F8::splat(self.t) + off * F8::splat(probes.axis.y));
        (ps - ps.floor(), pt - pt.floor())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::mip::MipFilter;
    use crate::texture::trilinear8::tests::{around_powers_of_two, noise_pyramid};
    use crate::texture::Filterable;

    /// An n:1 footprint takes n probes at every angle and size, whatever the rounding in its axes.
    #[test]
    fn whole_ratios_take_that_many_probes() {
        for k in 0..1000 {
            let (angle, size) = (k as f32 * 0.0137, 2f32.powf(-12.0 + 6.0 * (k as f32 * 0.618).fract()));
            let (c, sn) = (angle.cos(), angle.sin());
            for ratio in [2.0, 8.0, 16.0] {
                let fp =
                    Footprint { dudx: ratio * size * c, dvdx: ratio * size * sn, dudy: -size * sn, dvdy: size * c };
                assert_eq!(Probes::of_footprint(&fp, 4096, 4096, 16.0).count, ratio as usize, "{fp:?}");
            }
        }
    }

    /// The lane lookups' levels read from the exponent give the bits of the log2's levels, also where the
    /// log2 rounds up to the next integer (those take the log2's levels).
    #[test]
    fn levels_from_the_exponent_give_the_bits_of_the_log2_levels() {
        let data = noise_pyramid();
        let levels = data.levels();
        let (mut widths, rounded_up) = around_powers_of_two(0..16, |_| true);
        assert!(rounded_up > 0, "no width whose log2 rounds up to the next integer was tried");
        widths.extend([0.5, 1e30]);
        // Only the widths whose log2 rounds up take the log2's levels: a wrong floor would take them all
        // there (the same bits, but not the exponent's levels this test is about).
        let fallbacks = widths
            .iter()
            .map(|&w| Probes::levels_of_width(w))
            .filter(|&(level, floor)| !(0.0..1.0).contains(&(level - floor as f32)))
            .count();
        assert_eq!(fallbacks, rounded_up, "widths whose exponent's level is not the log2's floor");
        for (k, &width) in widths.iter().enumerate() {
            let (level, floor_level) = Probes::levels_of_width(width);
            let probes = Probes { count: 8, level, floor_level, axis: Vec2::new(0.05, 0.02) };
            let lookup = AnisoLookup { s: k as f32 * 0.137 % 1.0, t: k as f32 * 0.291 % 1.0, probes };
            let got = lookup.sum(levels, Prefetch::AlreadyAsked).to_array().map(f32::to_bits);
            let exact = lookup.sum_on_log2_levels(levels, Prefetch::AlreadyAsked).to_array().map(f32::to_bits);
            assert_eq!(got, exact, "width {width}");
        }
    }

    /// The lane form equals the generic filter, from one probe to more than eight.
    #[test]
    fn lanes_equal_the_generic_aniso() {
        let (w, h) = (64, 40);
        let bytes: Vec<[u8; 4]> =
            (0..w * h).map(|k| [(k * 37 % 251) as u8, (k * 91 % 256) as u8, (k * 13 % 199) as u8, 200]).collect();
        let data = Filterable::new(Rgba8Plane::from_top_rows(w, h, &bytes, true), MipFilter::Box, [Wrap::Repeat; 2]);
        let addr = Addressing { wrap: [Wrap::Repeat; 2], border: Vec4::ZERO };
        for (ratio, size, angle) in
            [(1.0, 2.0, 0.3), (3.0, 1.5, 1.0), (8.0, 0.7, 2.0), (12.0, 3.0, -0.4), (40.0, 0.2, 0.8)]
        {
            let (c, sn) = (f32::cos(angle), f32::sin(angle));
            let k = size / w as f32;
            let fp = Footprint { dudx: ratio * k * c, dvdx: ratio * k * sn, dudy: -k * sn, dvdy: k * c };
            for (s, t) in [(0.5, 0.5), (0.99, 0.01), (-1.3, 2.7)] {
                let want = sample(data.levels(), &addr, s, t, &fp, 16.0);
                let got = sample_rgba8_repeating(data.levels(), s, t, &fp, 16.0);
                assert!((got - want).abs().max_element() < 2e-5, "{ratio}:1 at ({s}, {t}): {got} vs {want}");
            }
        }
    }
}
