//! Writes past the caches, into buffers far larger than they are that are written once and read later: a
//! frame (1080p in f32 RGB is 25 MB) and the set-up triangles of a large mesh (tens of MB). An ordinary
//! store to such a buffer misses every cache, and its line is read from memory before it is written over (a
//! read for ownership); the stores wait on those reads. Streaming stores write whole lines without reading
//! them.

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

/// Writes `value` into `dst`, by streaming stores where `dst` starts on a 16-byte boundary and `T` is a
/// whole number of 16-byte pieces (else by an ordinary store). Call `fence` before another thread reads it.
#[inline(always)]
pub fn store<T: Copy>(dst: &mut MaybeUninit<T>, value: T) {
    let size = std::mem::size_of::<T>();
    let to = dst.as_mut_ptr().cast::<u8>();
    if !cfg!(target_arch = "x86_64") || !size.is_multiple_of(16) || !(to as usize).is_multiple_of(16) {
        dst.write(value);
        return;
    }
    #[cfg(target_arch = "x86_64")]
    // SAFETY: `to` is 16-byte aligned (tested above) and `dst` is `size` bytes, a multiple of 16; `from`
    // reads the `size` bytes of `value`, a `Copy` value on the stack.
    unsafe {
        use std::arch::x86_64::{__m128i, _mm_loadu_si128, _mm_stream_si128};
        let from = (&value as *const T).cast::<u8>();
        for i in (0..size).step_by(16) {
            _mm_stream_si128(to.add(i).cast::<__m128i>(), _mm_loadu_si128(from.add(i).cast()));
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

    /// A value lands whole wherever it is stored: on a 16-byte boundary (streamed), off one (an ordinary
    /// store), and a size that is no whole number of 16-byte pieces.
    #[test]
    fn values_store_whole_on_and_off_the_boundary() {
        #[repr(C, align(16))]
        struct Slots {
            on: MaybeUninit<[u64; 6]>,
            pad: u64,
            off: MaybeUninit<[u64; 2]>,
            odd: MaybeUninit<[u8; 3]>,
        }
        let mut slots =
            Slots { on: MaybeUninit::uninit(), pad: 7, off: MaybeUninit::uninit(), odd: MaybeUninit::uninit() };
        assert_eq!((&slots.off as *const _ as usize) % 16, 8, "the test needs a slot off the boundary");
        store(&mut slots.on, [1, 2, 3, 4, 5, u64::MAX]);
        store(&mut slots.off, [9, 10]);
        store(&mut slots.odd, [11, 12, 13]);
        fence();
        // SAFETY: each slot was just written.
        let (on, off, odd) = unsafe { (slots.on.assume_init(), slots.off.assume_init(), slots.odd.assume_init()) };
        assert_eq!((on, slots.pad, off, odd), ([1, 2, 3, 4, 5, u64::MAX], 7, [9, 10], [11, 12, 13]));
    }

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
