//! Sample positions inside a pixel: 1 at the centre, or 4 or 16 stratified (one jittered sample in each
//! cell of a 2x2 or 4x4 grid), in fixed point.

use super::SUBPIXEL;

#[derive(Clone, Debug)]
pub struct SamplePattern {
    /// Offsets from the pixel's top-left corner, in 1/SUBPIXEL pixel.
    pub offsets: Vec<[i64; 2]>,
}

impl SamplePattern {
    /// `spp` must be 1, 4 or 16.
    pub fn new(spp: usize) -> Option<SamplePattern> {
        let n = match spp {
            1 => return Some(SamplePattern { offsets: vec![[SUBPIXEL / 2, SUBPIXEL / 2]] }),
            4 => 2,
            16 => 4,
            _ => return None,
        };
        let mut offsets = Vec::with_capacity(spp);
        for b in 0..n {
            for a in 0..n {
                // A fixed jitter from a small integer hash keeps renders reproducible.
                let (jx, jy) = (hash01(a * 7 + b * 131 + 1), hash01(a * 59 + b * 17 + 1000));
                let x = ((a as f32 + 0.1 + 0.8 * jx) / n as f32 * SUBPIXEL as f32) as i64;
                let y = ((b as f32 + 0.1 + 0.8 * jy) / n as f32 * SUBPIXEL as f32) as i64;
                offsets.push([x, y]);
            }
        }
        Some(SamplePattern { offsets })
    }

    /// Samples per pixel.
    pub fn count(&self) -> usize {
        self.offsets.len()
    }

    /// The offset of sample `s` in pixels.
    pub fn offset(&self, s: usize) -> (f32, f32) {
        let [x, y] = self.offsets[s];
        (x as f32 / SUBPIXEL as f32, y as f32 / SUBPIXEL as f32)
    }
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

    #[test]
    fn one_sample_per_stratum() {
        assert_eq!(SamplePattern::new(1).unwrap().offset(0), (0.5, 0.5));
        assert!(SamplePattern::new(3).is_none());
        for (spp, n) in [(4, 2), (16, 4)] {
            let p = SamplePattern::new(spp).unwrap();
            let mut seen = vec![false; spp];
            for s in 0..spp {
                let (x, y) = p.offset(s);
                let cell = (y * n as f32) as usize * n + (x * n as f32) as usize;
                assert!(!seen[cell]);
                seen[cell] = true;
            }
        }
    }
}
