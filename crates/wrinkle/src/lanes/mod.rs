//! Eight samples at a time: f32x8 lanes and 3-vectors of them (structure of arrays), for the shading of
//! sample packets. Gathers (table and texture lookups) stay per lane; the arithmetic around them runs on
//! all eight lanes at once. Every path gives the same bits on every x86-64 CPU (see `math`).

mod math;

pub use math::{asin, atan2, log2, mul_add, pow, to_bits};

use glam::{Affine3A, Mat3, Vec3, Vec3A};
use std::ops::{Add, Mul, Neg, Sub};
pub use wide::{f32x8 as F8, i32x8 as I8, CmpEq, CmpGe, CmpGt, CmpLe, CmpLt};

/// The number of samples in a packet.
pub const LANES: usize = 8;

/// 0, 1, .. 7: each lane's own index.
#[inline]
pub fn lane_index() -> F8 {
    F8::new(std::array::from_fn(|l| l as f32))
}

/// The mask of the lanes whose bits are set in `bits` (bit i: lane i), for `blend` and `V3::select`.
#[inline]
pub fn mask_of(bits: u8) -> F8 {
    F8::new(std::array::from_fn(|i| if bits >> i & 1 == 1 { f32::from_bits(u32::MAX) } else { 0.0 }))
}

/// A lane mask of integer comparisons (each lane all ones or all zeros) as one for `F8::blend`.
#[inline]
pub fn bits(mask: I8) -> F8 {
    // SAFETY: `I8` and `F8` are both eight 32-bit lanes; the bits are kept as they are.
    unsafe { std::mem::transmute::<I8, F8>(mask) }
}

/// `values[index]` per lane. An index outside the slice reads its nearest end instead, never memory outside.
#[inline]
pub fn gather(values: &[f32], index: I8) -> F8 {
    let index = clamp_index(index, values.len());
    // SAFETY: every index is inside `values` (clamped above).
    unsafe { gather_unchecked(values, index) }
}

/// `values[index]` per lane, of 32-bit integers. An index outside the slice reads its nearest end instead,
/// never memory outside.
#[inline]
pub fn gather_i32(values: &[i32], index: I8) -> I8 {
    let index = clamp_index(index, values.len());
    #[cfg(all(target_arch = "x86_64", target_feature = "avx2"))]
    // SAFETY: AVX2 is enabled at compile time and every index is inside `values` (clamped above); `I8` and
    // `__m256i` are both eight i32, so the transmutes only rename.
    unsafe {
        use std::arch::x86_64::*;
        std::mem::transmute::<__m256i, I8>(_mm256_i32gather_epi32::<4>(
            values.as_ptr(),
            std::mem::transmute::<I8, __m256i>(index),
        ))
    }
    #[cfg(not(all(target_arch = "x86_64", target_feature = "avx2")))]
    I8::new(index.to_array().map(|k| values[k as usize]))
}

/// `values[index]` per lane, for indices known to be inside (a byte into a 256-entry table, say), without
/// `gather`'s clamp.
///
/// # Safety
/// Every index is inside `values`.
#[inline]
pub unsafe fn gather_unchecked(values: &[f32], index: I8) -> F8 {
    debug_assert!(index.to_array().iter().all(|&k| k >= 0 && (k as usize) < values.len()));
    #[cfg(all(target_arch = "x86_64", target_feature = "avx2"))]
    // SAFETY: AVX2 is enabled at compile time and every index is inside `values` (the caller's promise); `I8`
    // and `__m256i` are both eight i32, `F8` and `__m256` eight f32, so the transmutes only rename.
    unsafe {
        use std::arch::x86_64::*;
        std::mem::transmute::<__m256, F8>(_mm256_i32gather_ps::<4>(
            values.as_ptr(),
            std::mem::transmute::<I8, __m256i>(index),
        ))
    }
    #[cfg(not(all(target_arch = "x86_64", target_feature = "avx2")))]
    F8::new(index.to_array().map(|k| values[k as usize]))
}

/// Asks the cache for the lines holding `values[index]`, ahead of its use; an index outside asks nothing.
#[inline]
pub fn prefetch<T>(values: &[T], index: usize) {
    const LINE: usize = 64;
    let Some(value) = values.get(index) else { return };
    let start = (value as *const T).cast::<u8>();
    // The first byte's line; for an element longer than a line, each a line on and the last byte's.
    let size = std::mem::size_of::<T>();
    let last = (size > LINE).then(|| size - 1);
    for offset in (0..size.max(1)).step_by(LINE).chain(last) {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: a prefetch never faults, and the address is a byte of the element.
        unsafe {
            std::arch::x86_64::_mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T0 }>(start.add(offset).cast())
        };
        #[cfg(not(target_arch = "x86_64"))]
        let _ = (start, offset);
    }
}

/// The four bytes `bytes[offset..offset + 4]` per lane as one little-endian word. An offset past the last
/// whole word reads that word instead, never memory outside.
#[inline]
pub fn gather_bytes4(bytes: &[u8], offset: I8) -> I8 {
    assert!(bytes.len() >= 4, "a word gather from fewer than four bytes");
    let offset = clamp_index(offset, bytes.len() - 3);
    #[cfg(all(target_arch = "x86_64", target_feature = "avx2"))]
    // SAFETY: AVX2 is enabled at compile time and every offset is at most len - 4 (clamped above), so the
    // four bytes each lane reads are inside `bytes`; `I8` and `__m256i` are both eight i32.
    unsafe {
        use std::arch::x86_64::*;
        std::mem::transmute::<__m256i, I8>(_mm256_i32gather_epi32::<1>(
            bytes.as_ptr().cast(),
            std::mem::transmute::<I8, __m256i>(offset),
        ))
    }
    #[cfg(not(all(target_arch = "x86_64", target_feature = "avx2")))]
    I8::new(offset.to_array().map(|k| {
        let k = k as usize;
        i32::from_le_bytes([bytes[k], bytes[k + 1], bytes[k + 2], bytes[k + 3]])
    }))
}

/// The four bytes `values[index]` per lane as one little-endian word each.
///
/// # Safety
/// Every index is inside `values` (the caller clamps them, with bounds it worked out once).
#[inline]
pub unsafe fn gather_words(values: &[[u8; 4]], index: I8) -> I8 {
    debug_assert!(index.to_array().iter().all(|&k| k >= 0 && (k as usize) < values.len()));
    #[cfg(all(target_arch = "x86_64", target_feature = "avx2"))]
    // SAFETY: AVX2 is enabled at compile time and every index is inside `values` (the caller's promise); the
    // gather reads four unaligned bytes per lane; `I8` and `__m256i` are both eight i32.
    unsafe {
        use std::arch::x86_64::*;
        std::mem::transmute::<__m256i, I8>(_mm256_i32gather_epi32::<4>(
            values.as_ptr().cast(),
            std::mem::transmute::<I8, __m256i>(index),
        ))
    }
    #[cfg(not(all(target_arch = "x86_64", target_feature = "avx2")))]
    I8::new(index.to_array().map(|k| i32::from_le_bytes(values[k as usize])))
}

/// `gather_words` from two slices: lanes 0-3 read `low`, lanes 4-7 read `high` (two MIP levels, say).
///
/// # Safety
/// Each index is inside its own slice.
#[inline]
pub unsafe fn gather_words_split(low: &[[u8; 4]], high: &[[u8; 4]], index: I8) -> I8 {
    debug_assert!(index.to_array().iter().enumerate().all(|(l, &k)| {
        let len = if l < 4 { low.len() } else { high.len() };
        k >= 0 && (k as usize) < len
    }));
    #[cfg(all(target_arch = "x86_64", target_feature = "avx2"))]
    // SAFETY: as in `gather_words`, each half of the lanes indexing its own slice.
    unsafe {
        use std::arch::x86_64::*;
        let index = std::mem::transmute::<I8, __m256i>(index);
        let low = _mm_i32gather_epi32::<4>(low.as_ptr().cast(), _mm256_castsi256_si128(index));
        let high = _mm_i32gather_epi32::<4>(high.as_ptr().cast(), _mm256_extracti128_si256::<1>(index));
        std::mem::transmute::<__m256i, I8>(_mm256_set_m128i(high, low))
    }
    #[cfg(not(all(target_arch = "x86_64", target_feature = "avx2")))]
    {
        let index = index.to_array();
        I8::new(std::array::from_fn(|k| {
            let s = if k < 4 { low } else { high };
            i32::from_le_bytes(s[index[k] as usize])
        }))
    }
}

/// `v[from[l]]` on each lane `l` (a lane shuffle across the whole vector).
#[inline]
pub fn permute(v: I8, from: I8) -> I8 {
    #[cfg(all(target_arch = "x86_64", target_feature = "avx2"))]
    // SAFETY: AVX2 is enabled at compile time; `I8` and `__m256i` are both eight i32, so the transmutes only
    // rename; the instruction uses the low three bits of each `from` lane, always a lane of `v`.
    unsafe {
        use std::arch::x86_64::*;
        let (v, from) = (std::mem::transmute::<I8, __m256i>(v), std::mem::transmute::<I8, __m256i>(from));
        std::mem::transmute::<__m256i, I8>(_mm256_permutevar8x32_epi32(v, from))
    }
    #[cfg(not(all(target_arch = "x86_64", target_feature = "avx2")))]
    {
        let (v, from) = (v.to_array(), from.to_array());
        I8::new(from.map(|k| v[(k & 7) as usize]))
    }
}

/// `permute` for f32 lanes.
#[inline]
pub fn permute_f(v: F8, from: I8) -> F8 {
    // SAFETY: `F8` and `I8` are both eight 32-bit lanes and every bit pattern is valid in both, so the
    // transmutes only rename; the shuffle moves lanes whole.
    unsafe { std::mem::transmute::<I8, F8>(permute(std::mem::transmute::<F8, I8>(v), from)) }
}

/// Indices clamped into a slice of `len` elements.
#[inline]
fn clamp_index(index: I8, len: usize) -> I8 {
    index.max(I8::splat(0)).min(I8::splat(last_index(len)))
}

/// The last index a gather may read in a slice of `len` elements (at most 2^31 - 1 for a longer one).
#[inline]
fn last_index(len: usize) -> i32 {
    assert!(len > 0, "a gather from an empty slice");
    (len - 1).min(i32::MAX as usize) as i32
}

/// The sums of four vectors' lanes: [sum of a[0]'s lanes, .., sum of a[3]'s].
#[inline]
pub fn sum_lanes(a: [F8; 4]) -> [f32; 4] {
    #[cfg(all(target_arch = "x86_64", target_feature = "avx2"))]
    // SAFETY: AVX is enabled at compile time; `F8` and `__m256` are both eight f32, `[f32; 4]` and `__m128`
    // four, so the transmutes only rename.
    unsafe {
        use std::arch::x86_64::*;
        let [p, q, r, s] = a.map(|v| std::mem::transmute::<F8, __m256>(v));
        // Pairwise sums: after three, each 128-bit half holds the four vectors' sums over its four lanes.
        let h = _mm256_hadd_ps(_mm256_hadd_ps(p, q), _mm256_hadd_ps(r, s));
        std::mem::transmute::<__m128, [f32; 4]>(_mm_add_ps(_mm256_castps256_ps128(h), _mm256_extractf128_ps::<1>(h)))
    }
    // The same additions in the same order as the AVX2 path, so that both give the same bits.
    #[cfg(not(all(target_arch = "x86_64", target_feature = "avx2")))]
    a.map(|v| {
        let v = v.to_array();
        ((v[0] + v[1]) + (v[2] + v[3])) + ((v[4] + v[5]) + (v[6] + v[7]))
    })
}

/// Eight 3-vectors, one per lane.
#[derive(Clone, Copy, Debug)]
pub struct V3 {
    pub x: F8,
    pub y: F8,
    pub z: F8,
}

impl V3 {
    pub const ZERO: V3 = V3 { x: F8::ZERO, y: F8::ZERO, z: F8::ZERO };

    #[inline]
    pub fn splat(v: Vec3) -> V3 {
        V3 { x: F8::splat(v.x), y: F8::splat(v.y), z: F8::splat(v.z) }
    }

    /// The vectors of the lanes, lane 0 first.
    #[inline]
    pub fn from_lanes(v: &[Vec3; LANES]) -> V3 {
        V3 {
            x: F8::new(std::array::from_fn(|i| v[i].x)),
            y: F8::new(std::array::from_fn(|i| v[i].y)),
            z: F8::new(std::array::from_fn(|i| v[i].z)),
        }
    }

    #[inline]
    pub fn lane(&self, i: usize) -> Vec3 {
        Vec3::new(self.x.as_array_ref()[i], self.y.as_array_ref()[i], self.z.as_array_ref()[i])
    }

    /// Replaces lane `i`.
    #[inline]
    pub fn set_lane(&mut self, i: usize, v: Vec3) {
        self.x.as_array_mut()[i] = v.x;
        self.y.as_array_mut()[i] = v.y;
        self.z.as_array_mut()[i] = v.z;
    }

    #[inline]
    pub fn dot(self, o: V3) -> F8 {
        mul_add(self.x, o.x, mul_add(self.y, o.y, self.z * o.z))
    }

    #[inline]
    pub fn cross(self, o: V3) -> V3 {
        V3 { x: self.y * o.z - self.z * o.y, y: self.z * o.x - self.x * o.z, z: self.x * o.y - self.y * o.x }
    }

    #[inline]
    pub fn length(self) -> F8 {
        self.dot(self).sqrt()
    }

    /// The unit vector, or zero where the length is zero (as glam's normalize_or_zero).
    #[inline]
    pub fn normalize_or_zero(self) -> V3 {
        let len = self.length();
        let inv = len.cmp_gt(F8::ZERO).blend(F8::ONE / len, F8::ZERO);
        self * inv
    }

    /// `mask` (all bits set per lane) picks `t`, else `f`.
    #[inline]
    pub fn select(mask: F8, t: V3, f: V3) -> V3 {
        V3 { x: mask.blend(t.x, f.x), y: mask.blend(t.y, f.y), z: mask.blend(t.z, f.z) }
    }

    #[inline]
    pub fn mul_mat3(m: &Mat3, v: V3) -> V3 {
        let c = |k: Vec3| V3::splat(k);
        c(m.x_axis) * v.x + c(m.y_axis) * v.y + c(m.z_axis) * v.z
    }

    #[inline]
    pub fn transform_point(a: &Affine3A, p: V3) -> V3 {
        V3::transform_vector(a, p) + V3::splat_aligned(a.translation)
    }

    /// `mul_mat3` straight from the affine map's aligned columns: made into a `Mat3` first, they went
    /// through the stack, where loads overlapping the stores just made stalled (6% of the canonical frame).
    #[inline]
    pub fn transform_vector(a: &Affine3A, v: V3) -> V3 {
        let (c, m) = (V3::splat_aligned, &a.matrix3);
        c(m.x_axis) * v.x + c(m.y_axis) * v.y + c(m.z_axis) * v.z
    }

    #[inline]
    fn splat_aligned(v: Vec3A) -> V3 {
        V3 { x: F8::splat(v.x), y: F8::splat(v.y), z: F8::splat(v.z) }
    }
}

impl Add for V3 {
    type Output = V3;
    #[inline]
    fn add(self, o: V3) -> V3 {
        V3 { x: self.x + o.x, y: self.y + o.y, z: self.z + o.z }
    }
}

impl Sub for V3 {
    type Output = V3;
    #[inline]
    fn sub(self, o: V3) -> V3 {
        V3 { x: self.x - o.x, y: self.y - o.y, z: self.z - o.z }
    }
}

impl Neg for V3 {
    type Output = V3;
    #[inline]
    fn neg(self) -> V3 {
        V3 { x: -self.x, y: -self.y, z: -self.z }
    }
}

impl Mul<F8> for V3 {
    type Output = V3;
    #[inline]
    fn mul(self, k: F8) -> V3 {
        V3 { x: self.x * k, y: self.y * k, z: self.z * k }
    }
}

impl Mul<V3> for V3 {
    type Output = V3;
    /// Lane- and component-wise.
    #[inline]
    fn mul(self, o: V3) -> V3 {
        V3 { x: self.x * o.x, y: self.y * o.y, z: self.z * o.z }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn permutes_take_each_lane_from_the_lane_named() {
        let from = I8::new([7, 0, 3, 3, 1, 6, 2, 5]);
        let v = I8::new([10, 11, 12, 13, 14, 15, 16, 17]);
        assert_eq!(permute(v, from).to_array(), [17, 10, 13, 13, 11, 16, 12, 15]);
        let f = F8::new([0.5, -1.0, 2.25, 3.0, f32::MAX, -0.0, 6.5, 7.0]);
        assert_eq!(permute_f(f, from).to_array(), [7.0, 0.5, 3.0, 3.0, -1.0, 6.5, 2.25, -0.0]);
    }

    #[test]
    fn byte_gathers_read_little_endian_words_inside_the_slice() {
        let bytes: Vec<u8> = (1..=10).collect();
        let got = gather_bytes4(&bytes, I8::new([0, 1, 6, 5, 9, -3, 2, 100])).to_array();
        let word = |k: usize| i32::from_le_bytes([bytes[k], bytes[k + 1], bytes[k + 2], bytes[k + 3]]);
        assert_eq!(got, [word(0), word(1), word(6), word(5), word(6), word(0), word(2), word(6)]);
    }

    #[test]
    fn integer_gathers_read_inside_the_slice() {
        let values = [5, -7, i32::MIN, 9, i32::MAX];
        let got = gather_i32(&values, I8::new([4, 0, 2, 1, -1, 5, i32::MIN, 3])).to_array();
        assert_eq!(got, [i32::MAX, 5, i32::MIN, -7, 5, i32::MAX, 5, 9]);
    }

    #[test]
    fn lanes_agree_with_glam() {
        let a: [Vec3; LANES] =
            std::array::from_fn(|i| Vec3::new(i as f32 - 3.0, 0.5 * i as f32, 2.0 - i as f32 * 0.25));
        let b: [Vec3; LANES] = std::array::from_fn(|i| Vec3::new(1.0, -(i as f32), 0.3 * i as f32));
        let (va, vb) = (V3::from_lanes(&a), V3::from_lanes(&b));
        let m = Affine3A::from_scale_rotation_translation(
            Vec3::new(1.0, 2.0, -1.0),
            glam::Quat::from_rotation_y(0.7),
            Vec3::new(0.1, 0.2, 0.3),
        );
        let (dot, cross, unit, tp) = (va.dot(vb), va.cross(vb), va.normalize_or_zero(), V3::transform_point(&m, va));
        for i in 0..LANES {
            assert!((dot.as_array_ref()[i] - a[i].dot(b[i])).abs() < 1e-5);
            assert!((cross.lane(i) - a[i].cross(b[i])).length() < 1e-5);
            assert!((unit.lane(i) - a[i].normalize_or_zero()).length() < 1e-6);
            assert!((tp.lane(i) - m.transform_point3(a[i])).length() < 1e-5);
        }
        assert_eq!(V3::ZERO.normalize_or_zero().lane(0), Vec3::ZERO);
    }

    #[test]
    fn split_gather_reads_each_half_from_its_slice() {
        let low: Vec<[u8; 4]> = (0..5u8).map(|k| [k, 0, 0, 0]).collect();
        let high: Vec<[u8; 4]> = (0..9u8).map(|k| [k, 1, 0, 0]).collect();
        // SAFETY: lanes 0-3 index `low` (5 words), lanes 4-7 `high` (9 words), all inside.
        let got = unsafe { gather_words_split(&low, &high, I8::new([4, 0, 3, 1, 8, 0, 7, 2])) }.to_array();
        let word = |k: u8, half: u8| i32::from_le_bytes([k, half, 0, 0]);
        assert_eq!(
            got,
            [word(4, 0), word(0, 0), word(3, 0), word(1, 0), word(8, 1), word(0, 1), word(7, 1), word(2, 1)]
        );
    }

    #[test]
    fn lane_sums_of_four_vectors() {
        let a: [F8; 4] = std::array::from_fn(|k| F8::new(std::array::from_fn(|l| (k * 10 + l) as f32)));
        assert_eq!(sum_lanes(a), [28.0, 108.0, 188.0, 268.0]);
    }
}
