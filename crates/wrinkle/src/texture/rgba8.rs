//! Levels of 8-bit RGBA texels, decoded per fetch (sRGB or linear colour, linear alpha): a quarter of the
//! memory of f32 texels, so four times as much of a pyramid stays in cache. Used for 8-bit sources: level 0
//! keeps the source bytes exactly; coarser levels are built in linear light in f32 and then encoded (within
//! one code of the exact encoding). sRGB codes decode to `srgb_decode8`'s values (within 6.1e-8 of the
//! exact decoding) by table or by arithmetic, whichever this CPU does faster (`ColourDecode`), to the
//! same bits.

use super::mip::{MipFilter, Resample};
use super::texel::{Plane, TexelSource};
use super::wrap::Wrap;
use crate::image::color::SrgbEncoder;
use crate::lanes::{bits, gather_unchecked, gather_words, gather_words_split, mul_add, permute_f, CmpGt, F8, I8};
use crate::pages::{PageBuffer, Zeroable};
use glam::Vec4;
use rayon::prelude::*;
use std::sync::OnceLock;

#[derive(Clone, Debug)]
pub struct Rgba8Plane {
    pub width: usize,
    pub height: usize,
    /// Blocks of 4 x 4 texels (64 bytes: one cache line), block rows from the bottom; inside a block, rows
    /// from the bottom. A bilinear footprint then touches one or two cache lines, not two rows far apart,
    /// and mostly one memory page: on levels larger than the caches that is most of a lookup's cost. Large
    /// levels lie in 2 MB pages (`PageBuffer`), so that a lookup's page is seldom missing from the TLB.
    blocks: PageBuffer<Block>,
    blocks_per_row: usize,
    /// The last storage index a gather may read: worked out once, so that a lookup's clamp is two
    /// instructions.
    last: i32,
    decode: &'static DecodeTable,
    /// How the lanes decode the colour channels (and whether they are sRGB).
    colour: ColourDecode,
}

/// The side of a storage block, in texels.
const BLOCK: usize = 4;

/// One storage block: 4 x 4 texels, aligned to a cache line so that it fills exactly one (a `Vec` of
/// bytes would start 16 bytes into a line, and every block would straddle two).
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
struct Block([[u8; 4]; BLOCK * BLOCK]);

// SAFETY: a block is bytes: zero texels.
unsafe impl Zeroable for Block {}

/// The decode table: entries 0-255 the colour channels (sRGB or linear), 256-511 alpha (always linear),
/// so that one four-lane gather decodes a whole texel.
type DecodeTable = [f32; 512];

/// The decode table; sRGB colour holds `srgb_decode8`'s values, so the table and the arithmetic agree.
fn table(srgb: bool) -> &'static DecodeTable {
    static SRGB: OnceLock<DecodeTable> = OnceLock::new();
    static LINEAR: OnceLock<DecodeTable> = OnceLock::new();
    let with_alpha = |colour: [f32; 256]| -> DecodeTable {
        std::array::from_fn(|i| if i < 256 { colour[i] } else { (i - 256) as f32 * (1.0 / 255.0) })
    };
    if srgb {
        SRGB.get_or_init(|| {
            let codes = |first: usize| I8::new(std::array::from_fn(|l| (first + l) as i32));
            let lanes: Vec<f32> = (0..256).step_by(8).flat_map(|first| srgb_decode8(codes(first)).to_array()).collect();
            with_alpha(std::array::from_fn(|i| lanes[i]))
        })
    } else {
        LINEAR.get_or_init(|| with_alpha(std::array::from_fn(|i| i as f32 / 255.0)))
    }
}

/// How eight lanes of colour codes become linear values; every way gives the same bits.
#[derive(Clone, Copy, Debug, PartialEq)]
enum ColourDecode {
    /// code / 255.
    Linear,
    /// sRGB through the decode table, one gather per channel.
    SrgbTable,
    /// sRGB by `srgb_decode8`'s arithmetic.
    SrgbArithmetic,
}

impl ColourDecode {
    /// The way for this texture on this CPU. AMD's CPUs (Zen) issue gathers slowly: on Zen 3 the
    /// arithmetic made random trilinear batches 13 - 19% faster and anisotropic 8:1 ones 10 - 15%. Intel's
    /// issue them fast: an arithmetic decode lost 8% on Emerald Rapids (docs/architecture.md), so they keep
    /// the table, as does a build without AVX2 (a gather is then eight loads). WRINKLE_SRGB_DECODE=table or
    /// arithmetic overrides the choice (any other value leaves it), to compare the two on one machine.
    fn of(srgb: bool) -> ColourDecode {
        static SRGB: OnceLock<ColourDecode> = OnceLock::new();
        if !srgb {
            return ColourDecode::Linear;
        }
        *SRGB.get_or_init(|| match std::env::var("WRINKLE_SRGB_DECODE").as_deref() {
            Ok("table") => ColourDecode::SrgbTable,
            Ok("arithmetic") => ColourDecode::SrgbArithmetic,
            _ if cfg!(target_feature = "avx2") && crate::cpu::is_amd() => ColourDecode::SrgbArithmetic,
            _ => ColourDecode::SrgbTable,
        })
    }

    fn is_srgb(self) -> bool {
        self != ColourDecode::Linear
    }
}

/// Where texel (i, j) is stored, with `blocks_per_row` blocks in each block row: the sum of a part that
/// depends on the row only and one that depends on the column only.
#[inline]
fn block_index(i: usize, j: usize, blocks_per_row: usize) -> usize {
    row_part(j, blocks_per_row) + column_part(i)
}

#[inline]
fn row_part(j: usize, blocks_per_row: usize) -> usize {
    (j / BLOCK) * blocks_per_row * BLOCK * BLOCK + (j % BLOCK) * BLOCK
}

#[inline]
fn column_part(i: usize) -> usize {
    (i / BLOCK) * BLOCK * BLOCK + i % BLOCK
}

/// A linear texel as 8 bits: the colour sRGB-encoded where `srgb`, alpha (and linear colour) as unorm.
#[inline]
pub fn encode_texel(v: Vec4, srgb: bool, encoder: &SrgbEncoder) -> [u8; 4] {
    let unorm = |x: f32| (x.clamp(0.0, 1.0) * 255.0 + 0.5) as u8;
    let colour = |x: f32| if srgb { encoder.encode(x) } else { unorm(x) };
    [colour(v.x), colour(v.y), colour(v.z), unorm(v.w)]
}

impl Rgba8Plane {
    /// Bytes as stored in an image (row 0 at the top); `srgb`: the colour channels are sRGB-encoded.
    pub fn from_top_rows(width: usize, height: usize, rows: &[[u8; 4]], srgb: bool) -> Self {
        Rgba8Plane::from_rows(width, height, srgb, |j| &rows[(height - 1 - j) * width..][..width], |&t| t)
    }

    /// Linear texels encoded to 8 bits.
    pub fn encode(plane: &Plane<Vec4>, srgb: bool, encoder: &SrgbEncoder) -> Self {
        Rgba8Plane::from_rows(plane.width, plane.height, srgb, |j| plane.row(j), |v| encode_texel(*v, srgb, encoder))
    }

    /// Replaces texel (i, j) (j from the bottom) with 8-bit RGBA as stored.
    pub fn set(&mut self, i: usize, j: usize, texel: [u8; 4]) {
        let k = block_index(i, j, self.blocks_per_row);
        Block::texels_mut(&mut self.blocks)[k] = texel;
    }

    /// Stores the rows `row(j)` (j from the bottom) in blocks, each texel through `convert`; block rows in
    /// parallel.
    fn from_rows<'a, T: Sync + 'a>(
        width: usize,
        height: usize,
        srgb: bool,
        row: impl Fn(usize) -> &'a [T] + Sync,
        convert: impl Fn(&T) -> [u8; 4] + Sync,
    ) -> Self {
        let blocks_per_row = width.div_ceil(BLOCK);
        let count = blocks_per_row * height.div_ceil(BLOCK);
        assert!(count > 0, "an 8-bit texture level of {width}x{height} texels holds none");
        // The blocks start zeroed (the texels past the level's right and top edges stay so); each block row
        // is filled by one worker.
        let mut blocks = PageBuffer::<Block>::zeroed(count);
        blocks.par_chunks_mut(blocks_per_row).enumerate().for_each(|(b, out)| {
            let out = Block::texels_mut(out);
            for r in 0..BLOCK.min(height - b * BLOCK) {
                for (i, t) in row(b * BLOCK + r).iter().enumerate() {
                    out[block_index(i, r, blocks_per_row)] = convert(t);
                }
            }
        });
        // Indices are i32 lanes: a larger level (over 2^31 texels) is read only in its first 2^31.
        let last = (count * BLOCK * BLOCK - 1).min(i32::MAX as usize) as i32;
        Rgba8Plane { width, height, blocks, blocks_per_row, last, decode: table(srgb), colour: ColourDecode::of(srgb) }
    }

    /// Every texel in storage order (see `block_index`).
    #[inline]
    fn texels(&self) -> &[[u8; 4]] {
        Block::texels(&self.blocks)
    }

    /// One texel in linear light: one gather of four table entries.
    #[inline]
    fn decode_one(&self, t: [u8; 4]) -> Vec4 {
        #[cfg(all(target_arch = "x86_64", target_feature = "avx2"))]
        // SAFETY: AVX2 is enabled at compile time; each index is a byte (0-255), alpha's plus 256, so inside
        // the 512-entry table; `__m128` and `Vec4` are both four f32, so the transmute only renames.
        unsafe {
            use std::arch::x86_64::*;
            let bytes = _mm_cvtepu8_epi32(_mm_cvtsi32_si128(i32::from_le_bytes(t)));
            let index = _mm_add_epi32(bytes, _mm_setr_epi32(0, 0, 0, 256));
            std::mem::transmute::<__m128, Vec4>(_mm_i32gather_ps::<4>(self.decode.as_ptr(), index))
        }
        #[cfg(not(all(target_arch = "x86_64", target_feature = "avx2")))]
        {
            let d = self.decode;
            Vec4::new(d[t[0] as usize], d[t[1] as usize], d[t[2] as usize], d[256 + t[3] as usize])
        }
    }

    /// The texels in linear light.
    pub fn decode(&self) -> Plane<Vec4> {
        let texels =
            (0..self.width * self.height).into_par_iter().map(|k| self.texel(k % self.width, k / self.width)).collect();
        Plane { width: self.width, height: self.height, texels }
    }

    /// Blocks per block row: with the texel's (i, j), what the lane form of the storage index needs.
    #[inline]
    pub fn blocks_per_row(&self) -> usize {
        self.blocks_per_row
    }

    /// `row_part` on eight lanes: with `column_part8`, the storage index of texel (i, j) is their sum.
    #[inline]
    pub fn row_part8(j: I8, blocks_per_row: I8) -> I8 {
        let (mask, shift) = (I8::splat(BLOCK as i32 - 1), BLOCK.trailing_zeros() as i32);
        (((j >> shift) * blocks_per_row) << (2 * shift)) + ((j & mask) << shift)
    }

    /// `column_part` on eight lanes.
    #[inline]
    pub fn column_part8(i: I8) -> I8 {
        let (mask, shift) = (I8::splat(BLOCK as i32 - 1), BLOCK.trailing_zeros() as i32);
        ((i >> shift) << (2 * shift)) + (i & mask)
    }

    /// `row_part8` on the lanes where `is_row` is set (all bits), with their `blocks_per_row`, and
    /// `column_part8` on the others: both axes' parts in one pass.
    #[inline]
    pub fn parts8(k: I8, blocks_per_row: I8, is_row: I8) -> I8 {
        let (mask, shift) = (I8::splat(BLOCK as i32 - 1), BLOCK.trailing_zeros() as i32);
        let stride = is_row.blend(blocks_per_row, I8::splat(1));
        (((k >> shift) * stride) << (2 * shift)) + ((k & mask) << (is_row & I8::splat(shift)))
    }

    /// Asks the cache for the line of the texel at storage index `index` (see `row_part8`); an index outside
    /// asks nothing.
    #[inline]
    pub fn prefetch_index(&self, index: i32) {
        crate::lanes::prefetch(self.texels(), index as usize);
    }

    /// The texel at storage index `index` (see `row_part8`) as one word: R in the low byte, A in the high.
    /// An index outside the plane reads its nearest end, as the gathers do (a NaN coordinate gives one).
    #[inline]
    pub fn word(&self, index: i32) -> u32 {
        u32::from_le_bytes(self.texels()[index.clamp(0, self.last) as usize])
    }

    /// The texels at storage indices `index` (see `row_part8`), decoded to channel lanes. An index
    /// outside the plane reads its nearest end instead (never memory outside).
    #[inline]
    pub fn gather8(&self, index: I8) -> [F8; 4] {
        self.decode8(self.words8(index))
    }

    /// The texel words at storage indices `index`, not yet decoded (clamped as in `gather8`).
    #[inline]
    pub fn words8(&self, index: I8) -> I8 {
        let index = index.max(I8::splat(0)).min(I8::splat(self.last));
        // SAFETY: every index is in [0, last], inside the texels (see `last`).
        unsafe { gather_words(self.texels(), index) }
    }

    /// `gather8` from two planes of one texture (two levels): lanes 0-3 read `low`, lanes 4-7 `high`.
    #[inline]
    pub fn gather_split8(low: &Rgba8Plane, high: &Rgba8Plane, index: I8) -> [F8; 4] {
        let (l, h) = (low.last, high.last);
        let index = index.max(I8::splat(0)).min(I8::new([l, l, l, l, h, h, h, h]));
        // SAFETY: each half's indices are in [0, last] of its own plane, inside its texels.
        low.decode8(unsafe { gather_words_split(low.texels(), high.texels(), index) })
    }

    /// Eight texel words decoded to linear RGBA channel lanes, as `texel` decodes one.
    #[inline]
    pub fn decode8(&self, words: I8) -> [F8; 4] {
        let byte = |shift: i32| (words >> shift) & I8::splat(0xFF);
        let colour = |code: I8| match self.colour {
            // code / 255, one correctly rounded division: the table's bits.
            ColourDecode::Linear => code.round_float() / F8::splat(255.0),
            ColourDecode::SrgbArithmetic => srgb_decode8(code),
            // SAFETY: every code is a byte, inside the table's 256 colour entries.
            ColourDecode::SrgbTable => unsafe { gather_unchecked(&self.decode[..256], code) },
        };
        [colour(byte(0)), colour(byte(8)), colour(byte(16)), byte(24).round_float() * F8::splat(1.0 / 255.0)]
    }
}

/// sRGB codes (0 - 255, one per lane) in linear light by arithmetic, where a table gather is slow (see
/// `ColourDecode`): codes 0 - 10 on the line code / (255 * 12.92), every other by a polynomial of degree 4
/// per 32 codes, fitted to the exact decoding by least squares on the codes, its coefficients picked per
/// lane by permutes. Within 6.1e-8 of the exact decoding (f32 rounding at 1 is 6e-8); the same bits on
/// every x86-64 CPU.
#[inline]
fn srgb_decode8(code: I8) -> F8 {
    let piece = code >> 5;
    let u = (code & I8::splat(31)).round_float() * F8::splat(1.0 / 32.0);
    let c = |k: usize| permute_f(F8::new(SRGB_PIECES[k]), piece);
    let curve = mul_add(mul_add(mul_add(mul_add(c(4), u, c(3)), u, c(2)), u, c(1)), u, c(0));
    let line = code.round_float() * F8::splat(1.0 / (255.0 * 12.92));
    bits(code.cmp_gt(I8::splat(10))).blend(curve, line)
}

/// `srgb_decode8`'s coefficients: row k holds the coefficient of u^k for each piece of 32 codes
/// (u = (code mod 32) / 32).
#[rustfmt::skip]
const SRGB_PIECES: [[f32; 8]; 5] = [
    [8.402976e-04, 0.014443874, 0.051269468, 0.11697067, 0.2158605, 0.3515326, 0.5271151, 0.7454042],
    [0.0045054397, 0.024100574, 0.050464116, 0.08164805, 0.116726436, 0.15513687, 0.19649282, 0.2405085],
    [0.0075206826, 0.011740314, 0.014490948, 0.01662423, 0.018410755, 0.01996927, 0.021363944, 0.022633946],
    [0.0017559383, 0.0010568259, 7.827851e-04, 6.4038066e-04, 5.5076834e-04, 4.8818433e-04, 4.4150383e-04, 4.0506895e-04],
    [-1.7856034e-04, -7.2199866e-05, -3.667307e-05, -2.2845152e-05, -1.5867858e-05, -1.1796434e-05, -9.187241e-06, -7.401633e-06],
];

impl Block {
    /// The texels of consecutive blocks, in storage order.
    #[inline]
    fn texels(blocks: &[Block]) -> &[[u8; 4]] {
        // SAFETY: `Block` is `repr(C)` around 16 texels of 4 bytes: 64 bytes, its alignment, so no padding,
        // and a texel's alignment (1) divides the block's.
        unsafe { std::slice::from_raw_parts(blocks.as_ptr().cast(), blocks.len() * BLOCK * BLOCK) }
    }

    /// The same, to write.
    #[inline]
    fn texels_mut(blocks: &mut [Block]) -> &mut [[u8; 4]] {
        // SAFETY: as in `texels`; the borrow of the blocks is exclusive and lasts as long as the result.
        unsafe { std::slice::from_raw_parts_mut(blocks.as_mut_ptr().cast(), blocks.len() * BLOCK * BLOCK) }
    }
}

impl TexelSource for Rgba8Plane {
    type Texel = Vec4;
    #[inline]
    fn width(&self) -> usize {
        self.width
    }
    #[inline]
    fn height(&self) -> usize {
        self.height
    }
    #[inline]
    fn texel(&self, i: usize, j: usize) -> Vec4 {
        self.decode_one(self.texels()[block_index(i, j, self.blocks_per_row)])
    }
    #[inline]
    fn prefetch(&self, i: usize, j: usize) {
        // A hint: a texel outside the plane is not asked for.
        crate::lanes::prefetch(self.texels(), block_index(i, j, self.blocks_per_row));
    }
    #[inline]
    fn quad(&self, i: [usize; 2], j: [usize; 2]) -> [Vec4; 4] {
        let (c, r) = (i.map(column_part), j.map(|j| row_part(j, self.blocks_per_row)));
        let texels = self.texels();
        [r[0] + c[0], r[0] + c[1], r[1] + c[0], r[1] + c[1]].map(|k| self.decode_one(texels[k]))
    }
}

impl Resample for Rgba8Plane {
    fn downsample(&self, nw: usize, nh: usize, filter: MipFilter, wrap: [Wrap; 2]) -> Self {
        Rgba8Plane::encode(&self.decode().downsample(nw, nh, filter, wrap), self.colour.is_srgb(), &SrgbEncoder::new())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Blocked storage returns every texel of an odd-sized image where it was, in both index forms.
    #[test]
    fn blocks_keep_every_texel_in_place() {
        let (w, h) = (13, 6);
        let rows: Vec<[u8; 4]> = (0..w * h).map(|k| [k as u8, (k / w) as u8, (k % w) as u8, 255]).collect();
        let plane = Rgba8Plane::from_top_rows(w, h, &rows, false);
        let blocks = I8::splat(plane.blocks_per_row() as i32);
        for j in 0..h {
            for i in 0..w {
                let want = rows[(h - 1 - j) * w + i];
                assert_eq!(plane.texel(i, j), Vec4::from(want.map(|b| b as f32 / 255.0)), "({i}, {j})");
                let index =
                    Rgba8Plane::row_part8(I8::splat(j as i32), blocks) + Rgba8Plane::column_part8(I8::splat(i as i32));
                assert_eq!(plane.word(index.as_array_ref()[0]), u32::from_le_bytes(want));
            }
        }
        // A prefetch is a hint: outside the plane it does nothing (and does not panic).
        plane.prefetch(w + 3, h + 4);
    }

    /// Every code of every channel decodes on lanes, in every way, to the table's bits; the sRGB table
    /// is within 6.1e-8 of the exact decoding, the linear one code / 255.
    #[test]
    fn lane_decoding_is_the_tables_for_every_code() {
        for (srgb, ways) in
            [(false, &[ColourDecode::Linear][..]), (true, &[ColourDecode::SrgbTable, ColourDecode::SrgbArithmetic])]
        {
            for &colour in ways {
                let plane = Rgba8Plane { colour, ..Rgba8Plane::from_top_rows(1, 1, &[[0; 4]], srgb) };
                for start in (0..256).step_by(8) {
                    let words = I8::new(std::array::from_fn(|l| {
                        let c = (start + l) as u32;
                        (c | (255 - c) << 8 | (c ^ 0x5A) << 16 | c << 24) as i32
                    }));
                    let got = plane.decode8(words).map(|c| c.to_array());
                    for (l, &w) in words.as_array_ref().iter().enumerate() {
                        let w = w as u32;
                        for (k, channel) in got.iter().enumerate().take(3) {
                            let code = w >> (8 * k) & 0xFF;
                            let want = plane.decode[code as usize];
                            assert_eq!(channel[l].to_bits(), want.to_bits(), "{colour:?} code {code}");
                        }
                        assert_eq!(got[3][l].to_bits(), plane.decode[256 + (w >> 24) as usize].to_bits());
                    }
                }
            }
        }
        let (srgb, linear) = (table(true), table(false));
        for code in 0..256 {
            let exact = srgb_exact(code as u32);
            assert!((srgb[code] as f64 - exact).abs() <= 6.1e-8, "code {code}: {} vs {exact}", srgb[code]);
            assert_eq!(linear[code], code as f32 / 255.0);
            assert_eq!(srgb[256 + code], code as f32 * (1.0 / 255.0));
        }
    }

    /// sRGB code `code` in linear light, in f64.
    fn srgb_exact(code: u32) -> f64 {
        let c = code as f64 / 255.0;
        if c <= 0.04045 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }
    }

    /// Gathers clamp each index into its own plane: below it reads the first texel, past it the last.
    #[test]
    fn gathers_read_the_nearest_end_for_indices_outside() {
        let words = |n: usize, tag: u8| -> Vec<[u8; 4]> { (0..n).map(|k| [k as u8, tag, 0, 255]).collect() };
        let (low, high) = (words(4 * 4, 1), words(8 * 4, 2));
        let (low, high) = (Rgba8Plane::from_top_rows(4, 4, &low, false), Rgba8Plane::from_top_rows(8, 4, &high, false));
        let (last_low, last_high) = (16 - 1, 32 - 1);
        let index = I8::new([-5, 3, last_low, last_low + 9, -1, 7, last_high, 1 << 30]);
        let got = Rgba8Plane::gather_split8(&low, &high, index);
        let want = [0, 3, last_low, last_low, 0, 7, last_high, last_high]
            .iter()
            .enumerate()
            .map(|(l, &k)| if l < 4 { low.word(k) } else { high.word(k) })
            .collect::<Vec<_>>();
        for (l, w) in want.iter().enumerate() {
            let (tag, alpha) = ((w >> 8) & 0xFF, (w >> 24) as f32 / 255.0);
            assert_eq!(got[1].as_array_ref()[l], tag as f32 / 255.0, "lane {l}");
            assert_eq!(got[0].as_array_ref()[l], (w & 0xFF) as f32 / 255.0, "lane {l}");
            assert_eq!(got[3].as_array_ref()[l], alpha, "lane {l}");
        }
        let one = low.gather8(I8::new([-1, 0, 15, 16, 99, -99, 5, 1 << 30])).map(|c| c.to_array());
        for (l, k) in [0, 0, 15, 15, 15, 0, 5, 15].into_iter().enumerate() {
            assert_eq!(one[0][l], (low.word(k) & 0xFF) as f32 / 255.0, "lane {l}");
        }
    }
}
