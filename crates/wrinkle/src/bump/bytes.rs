//! A bump table's full-resolution heights as bytes, where every height is an 8-bit image's code / 255 (the
//! usual height map). A quarter of the f32 table's memory, which is what a minified bilinear lookup spends
//! its time fetching; and padded by the table's periodic wrap (one column and row before, two after) so
//! that each row of a lookup's 4x4 neighbourhood is one four-byte word: four gathers instead of twelve.
//! A code decodes as code / 255, one correctly rounded division, which is the height's own f32: lookups
//! through the bytes give the same bits as through the f32 table.

use super::table::neighbourhood8;
use crate::lanes::{gather_bytes4, prefetch, F8, I8};
use crate::texture::Footprint8;

/// The heights' codes, rows of `width + 3` bytes: column c holds table column (c - 1) mod width, row r
/// table row (r - 1) mod height.
#[derive(Clone, Debug)]
pub struct HeightBytes {
    width: usize,
    height: usize,
    codes: Vec<u8>,
}

/// The byte whose code / 255 is exactly `v`, if one is.
fn code_of(v: f32) -> Option<u8> {
    let code = (v * 255.0).round();
    let exact = (0.0..=255.0).contains(&code) && decode(code as u8).to_bits() == v.to_bits();
    exact.then_some(code as u8)
}

#[inline]
fn decode(code: u8) -> f32 {
    f32::from(code) / 255.0
}

impl HeightBytes {
    /// The codes of `heights` (`width` x `height`, row 0 at the bottom), or `None` where a height is not a
    /// code / 255 or the padded table is too large to index with 32-bit offsets.
    pub fn of(width: usize, height: usize, heights: &[f32]) -> Option<Self> {
        let stride = width + 3;
        if width == 0 || height == 0 || stride.checked_mul(height + 3)? > i32::MAX as usize {
            return None;
        }
        let table: Vec<u8> = heights.iter().map(|&v| code_of(v)).collect::<Option<_>>()?;
        let mut codes = Vec::with_capacity(stride * (height + 3));
        for r in 0..height + 3 {
            let row = &table[(r + height - 1) % height * width..][..width];
            codes.push(row[width - 1]);
            codes.extend_from_slice(row);
            codes.extend_from_slice(&[row[0], row[1 % width]]);
        }
        Some(HeightBytes { width, height, codes })
    }

    /// Sets table texel (i, j) to `v` (with its wrapped copies in the padding); `false`, and the codes
    /// unusable, where `v` is not a code / 255.
    pub fn update(&mut self, i: usize, j: usize, v: f32) -> bool {
        code_of(v).map(|code| self.set(i, j, code)).is_some()
    }

    fn set(&mut self, i: usize, j: usize, code: u8) {
        let stride = self.width + 3;
        // The padded positions of index k along a side n long: those p < n + 3 with p - 1 = k (mod n).
        let copies = |k: usize, n: usize| ((k + 1) % n..n + 3).step_by(n);
        for r in copies(j, self.height) {
            for c in copies(i, self.width) {
                self.codes[r * stride + c] = code;
            }
        }
    }

    /// The four rows (table rows j0 - 1 .. j0 + 2) of eight lookups' neighbourhoods, each a word of the
    /// columns i0 - 1 .. i0 + 2, where (i0, j0) is the lower-left tap, wrapped into the table.
    #[inline]
    pub fn rows8(&self, i0: I8, j0: I8) -> [I8; 4] {
        let (first, stride) = (self.first8(i0, j0), I8::splat((self.width + 3) as i32));
        std::array::from_fn(|r| gather_bytes4(&self.codes, first + stride * I8::splat(r as i32)))
    }

    /// Asks the cache for the rows that the packet a row of pixels down reads, for eight samples along a
    /// row of pixels at (s, t) with footprint `fp`: lanes 0 and 7 moved down a pixel. A minified table's
    /// rows are new cache lines at almost every packet, and the packet below comes a tile's width later:
    /// their latency is hidden (5% of the canonical frame on one thread). The next packet along the row,
    /// or both ends of the lanes, cost more to ask for than they saved.
    #[inline]
    pub fn prefetch_below(&self, s: F8, t: F8, fp: &Footprint8) {
        let (cols, _) = neighbourhood8(s + fp.dudy, self.width);
        let (rows, _) = neighbourhood8(t + fp.dvdy, self.height);
        let first = self.first8(cols[1], rows[1]).to_array();
        for lane in [0, 7] {
            for r in 0..4 {
                prefetch(&self.codes, first[lane] as usize + r * (self.width + 3));
            }
        }
    }

    /// The offset of each lane's first row word: padded row j0 is table row j0 - 1, padded column i0
    /// table column i0 - 1.
    #[inline(always)]
    fn first8(&self, i0: I8, j0: I8) -> I8 {
        j0 * I8::splat((self.width + 3) as i32) + i0
    }
}

/// The height in byte `c` (0 lowest) of each lane's word.
#[inline(always)]
pub fn decode8(words: I8, c: u32) -> F8 {
    ((words >> (8 * c as i32)) & I8::splat(0xFF)).round_float() / F8::splat(255.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every code decodes to the f32 an 8-bit image loads it as, and only those heights are codes.
    #[test]
    fn codes_are_exactly_the_eight_bit_heights() {
        for code in 0..=255u8 {
            let v = f32::from(code) / 255.0;
            assert_eq!(code_of(v), Some(code));
            assert_eq!(decode8(I8::splat(i32::from(code) << 16), 2).to_array(), [v; 8]);
        }
        assert_eq!(code_of(0.5), None);
        assert_eq!(code_of(-0.0), None);
        assert_eq!(code_of(f32::NAN), None);
        assert_eq!(code_of(2.0), None);
    }

    /// The words hold the wrapped neighbourhood, at the table's edges too, on tables as small as one texel.
    #[test]
    fn rows_hold_the_wrapped_neighbourhood() {
        for (w, h) in [(5, 4), (1, 2), (2, 1), (3, 3)] {
            let heights: Vec<f32> = (0..w * h).map(|k| (k * 37 % 256) as f32 / 255.0).collect();
            let bytes = HeightBytes::of(w, h, &heights).unwrap();
            let code = |i: i32, j: i32| {
                let (i, j) = (i.rem_euclid(w as i32) as usize, j.rem_euclid(h as i32) as usize);
                (heights[j * w + i] * 255.0).round() as i32
            };
            for j0 in 0..h as i32 {
                for i0 in 0..w as i32 {
                    let rows = bytes.rows8(I8::splat(i0), I8::splat(j0));
                    for (r, word) in rows.iter().enumerate() {
                        for c in 0..4 {
                            let got = (word.to_array()[0] >> (8 * c)) & 0xFF;
                            assert_eq!(got, code(i0 + c - 1, j0 + r as i32 - 1), "{w}x{h} tap ({i0}, {j0}) row {r}");
                        }
                    }
                }
            }
        }
    }

    /// A painted code shows in every wrapped copy; a height that is no code is refused.
    #[test]
    fn updates_reach_the_wrapped_copies() {
        let (w, h) = (4, 3);
        let mut bytes = HeightBytes::of(w, h, &[0.0; 12]).unwrap();
        assert!(bytes.update(0, h - 1, 9.0 / 255.0));
        // Seen right of the last column and below the first row.
        let corner = bytes.rows8(I8::splat(w as i32 - 1), I8::splat(h as i32 - 2));
        assert_eq!((corner[2].to_array()[0] >> 16) & 0xFF, 9);
        let below = bytes.rows8(I8::splat(0), I8::splat(0));
        assert_eq!((below[0].to_array()[0] >> 8) & 0xFF, 9);
        assert!(!bytes.update(1, 1, 0.3));
        assert!(HeightBytes::of(2, 2, &[0.0, 0.5, 1.0, 0.25]).is_none());
    }
}
