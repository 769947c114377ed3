//! Pixel rows written into a frame past the caches. A 1080p frame of f32 RGB is 25 MB: each line a tile
//! stores into it missed every cache and was read from memory before it was written over (a read for
//! ownership), and the stores waited on those reads. Streaming stores write whole lines without reading them.

use std::mem::MaybeUninit;

/// Writes `src` into `dst` (of one length), the aligned middle by streaming stores. Call `fence` before
/// another thread reads what was written.
#[inline]
pub fn copy_row(dst: &mut [MaybeUninit<[f32; 3]>], src: &[[f32; 3]]) {
    assert_eq!(dst.len(), src.len(), "copy_row: rows of different lengths");
    let n = dst.len() * 3;
    let to = dst.as_mut_ptr().cast::<f32>();
    let from = src.as_ptr().cast::<f32>();
    // The floats before the first 16-byte boundary, the whole vectors, and the floats after them.
    let head = ((to as usize).wrapping_neg() % 16 / 4).min(n);
    let body = head + (n - head) / 4 * 4;
    // SAFETY: every index is below n, the number of floats in both rows ([f32; 3] is three floats, no
    // padding); `to + i` for i in head..body steps by four from a 16-byte boundary, as the streaming store
    // asks.
    unsafe {
        for i in (0..head).chain(body..n) {
            to.add(i).write(*from.add(i));
        }
        #[cfg(target_arch = "x86_64")]
        for i in (head..body).step_by(4) {
            use std::arch::x86_64::{_mm_loadu_ps, _mm_stream_ps};
            _mm_stream_ps(to.add(i), _mm_loadu_ps(from.add(i)));
        }
        #[cfg(not(target_arch = "x86_64"))]
        for i in head..body {
            to.add(i).write(*from.add(i));
        }
    }
}

/// Orders the streaming stores of this thread before its later stores (the release of its work to the
/// thread that joins it).
#[inline]
pub fn fence() {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: a fence has no operands.
    unsafe {
        std::arch::x86_64::_mm_sfence()
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every float lands where a plain copy puts it, whatever the alignment and length of the row.
    #[test]
    fn rows_copy_exactly_at_every_alignment() {
        let src: Vec<[f32; 3]> = (0..70).map(|i| [i as f32, i as f32 + 0.25, -(i as f32)]).collect();
        let mut frame = vec![MaybeUninit::new([f32::NAN; 3]); 80];
        for start in 0..5 {
            for len in [0, 1, 2, 5, 64, 70] {
                let dst = &mut frame[start..start + len];
                copy_row(dst, &src[..len]);
                fence();
                // SAFETY: every element was initialised by `vec!`.
                let got: Vec<[f32; 3]> = dst.iter().map(|p| unsafe { p.assume_init() }).collect();
                assert_eq!(got, &src[..len], "start {start}, length {len}");
            }
        }
    }
}
