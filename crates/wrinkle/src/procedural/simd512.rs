//! Sixteen-lane sums of the hashed noise in AVX-512, chosen at run time where the CPU has it (AMD Zen 4 and
//! 5, Intel Xeon since Skylake-SP): the bulk paths (`Perlin::noise3_many`, `Fractal::eval3_many`) run here,
//! twice the points per instruction of the AVX2 lanes.
//!
//! The gradient of a hash is read from three sixteen-entry registers by `vpermps` (one instruction per
//! component) and dotted by a multiply and two fused multiply-adds; one component is zero and the others are
//! +-1, so every product is exact and the fused sums round as the scalar kernel's separate ones. The rest is
//! the scalar kernel's arithmetic in its order (perlin.rs), so every lane equals `Perlin::noise3` to the bit.

use super::perlin::{improved_gradient3, HASH_MIX, HASH_PRIME, LATTICE_LIMIT};
use std::arch::x86_64::*;

/// Points per vector.
pub(super) const WIDTH: usize = 16;

/// One octave of a sum: its noise's lattice, where its points come from, and its weight. One exists only
/// where this CPU has AVX-512F, which makes `sum3` safe.
pub(super) struct Octave {
    seed: i32,
    /// Lattice period per axis, when the noise tiles.
    period: Option<[f32; 3]>,
    /// The octave's point is p * frequency + shift, per axis.
    frequency: f32,
    shift: [f32; 3],
    amplitude: f32,
}

impl Octave {
    /// The octave, where this CPU runs the kernels here (the standard library caches the CPUID answer).
    pub(super) fn new(
        seed: i32,
        period: Option<[f32; 3]>,
        frequency: f32,
        shift: [f32; 3],
        amplitude: f32,
    ) -> Option<Octave> {
        is_x86_feature_detected!("avx512f").then_some(Octave { seed, period, frequency, shift, amplitude })
    }
}

/// sum over `octaves` of amplitude * noise (or |noise| when `turbulence`) at every whole group of sixteen
/// points; returns how many points it wrote (the rest are the caller's).
pub(super) fn sum3(octaves: &[Octave], turbulence: bool, x: &[f32], y: &[f32], z: &[f32], out: &mut [f32]) -> usize {
    if octaves.is_empty() {
        return 0;
    }
    // SAFETY: an `Octave` exists only where the CPU has AVX-512F.
    unsafe { hashed_sum3(octaves, turbulence, x, y, z, out) }
}

#[target_feature(enable = "avx512f")]
unsafe fn hashed_sum3(octaves: &[Octave], turbulence: bool, x: &[f32], y: &[f32], z: &[f32], out: &mut [f32]) -> usize {
    let n = out.len().min(x.len()).min(y.len()).min(z.len());
    let full = n - n % WIDTH;
    let gradients = Gradients::new();
    for i in (0..full).step_by(WIDTH) {
        // SAFETY: i + WIDTH <= full <= every slice's length.
        let (px, py, pz) = (
            _mm512_loadu_ps(x.as_ptr().add(i)),
            _mm512_loadu_ps(y.as_ptr().add(i)),
            _mm512_loadu_ps(z.as_ptr().add(i)),
        );
        let mut sum = _mm512_setzero_ps();
        for o in octaves {
            let f = _mm512_set1_ps(o.frequency);
            let at = |p: __m512, axis: usize| _mm512_add_ps(_mm512_mul_ps(p, f), _mm512_set1_ps(o.shift[axis]));
            let v = noise3(o, &gradients, at(px, 0), at(py, 1), at(pz, 2));
            let v = if turbulence { _mm512_abs_ps(v) } else { v };
            sum = _mm512_add_ps(sum, _mm512_mul_ps(_mm512_set1_ps(o.amplitude), v));
        }
        _mm512_storeu_ps(out.as_mut_ptr().add(i), sum);
    }
    full
}

/// The improved gradients, one register per component, indexed by the four-bit hash.
struct Gradients([__m512; 3]);

impl Gradients {
    #[inline]
    #[target_feature(enable = "avx512f")]
    fn new() -> Gradients {
        let g: [[f32; 3]; 16] = std::array::from_fn(improved_gradient3);
        let component = |c: usize| {
            let v: [f32; 16] = std::array::from_fn(|h| g[h][c]);
            // SAFETY: an unaligned load of sixteen floats from an array of sixteen.
            unsafe { _mm512_loadu_ps(v.as_ptr()) }
        };
        Gradients([component(0), component(1), component(2)])
    }

    /// The gradient of hash `h` dotted with (dx, dy, dz).
    #[inline]
    #[target_feature(enable = "avx512f")]
    fn dot(&self, h: __m512i, dx: __m512, dy: __m512, dz: __m512) -> __m512 {
        let [gx, gy, gz] = &self.0;
        let p = _mm512_mul_ps(_mm512_permutexvar_ps(h, *gx), dx);
        let p = _mm512_fmadd_ps(_mm512_permutexvar_ps(h, *gy), dy, p);
        _mm512_fmadd_ps(_mm512_permutexvar_ps(h, *gz), dz, p)
    }
}

/// Lattice indices along one axis, multiplied by the axis's prime, and the offset in the cell: as the
/// scalar `cell` (wrapped by the period, or clamped to +-LATTICE_LIMIT).
#[inline]
#[target_feature(enable = "avx512f")]
fn primed_cell(x: __m512, period: Option<f32>, prime: i32) -> (__m512i, __m512i, __m512) {
    let fl = _mm512_roundscale_ps::<{ _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC }>(x);
    let frac = _mm512_sub_ps(x, fl);
    let prime = _mm512_set1_epi32(prime);
    match period {
        Some(p) => {
            let p = _mm512_set1_ps(p);
            let q = _mm512_roundscale_ps::<{ _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC }>(_mm512_div_ps(fl, p));
            let i0 = _mm512_sub_ps(fl, _mm512_mul_ps(p, q));
            // Zero where i0 >= p (rounding of tiny negative x), then i1 likewise.
            let i0 = _mm512_maskz_mov_ps(_mm512_cmp_ps_mask::<_CMP_LT_OQ>(i0, p), i0);
            let i1 = _mm512_add_ps(i0, _mm512_set1_ps(1.0));
            let i1 = _mm512_maskz_mov_ps(_mm512_cmp_ps_mask::<_CMP_LT_OQ>(i1, p), i1);
            let to_primed = |v: __m512| _mm512_mullo_epi32(_mm512_cvttps_epi32(v), prime);
            (to_primed(i0), to_primed(i1), frac)
        }
        None => {
            let limit = _mm512_set1_ps(LATTICE_LIMIT);
            let clamped = _mm512_min_ps(_mm512_max_ps(fl, _mm512_sub_ps(_mm512_setzero_ps(), limit)), limit);
            let p0 = _mm512_mullo_epi32(_mm512_cvttps_epi32(clamped), prime);
            (p0, _mm512_add_epi32(p0, prime), frac)
        }
    }
}

/// The hashed improved noise at sixteen points.
#[inline]
#[target_feature(enable = "avx512f")]
fn noise3(o: &Octave, g: &Gradients, x: __m512, y: __m512, z: __m512) -> __m512 {
    let period = |axis: usize| o.period.map(|p| p[axis]);
    let (x0, x1, fx) = primed_cell(x, period(0), HASH_PRIME[0]);
    let (y0, y1, fy) = primed_cell(y, period(1), HASH_PRIME[1]);
    let (z0, z1, fz) = primed_cell(z, period(2), HASH_PRIME[2]);
    let seed = _mm512_set1_epi32(o.seed);
    let (s0, s1) = (_mm512_xor_si512(seed, x0), _mm512_xor_si512(seed, x1));
    let xy = [_mm512_xor_si512(s0, y0), _mm512_xor_si512(s1, y0), _mm512_xor_si512(s0, y1), _mm512_xor_si512(s1, y1)];
    let mix = _mm512_set1_epi32(HASH_MIX);
    let hash = |a: __m512i, zp: __m512i| _mm512_srli_epi32::<28>(_mm512_mullo_epi32(_mm512_xor_si512(a, zp), mix));
    let one = _mm512_set1_ps(1.0);
    let (gx, gy, gz) = (_mm512_sub_ps(fx, one), _mm512_sub_ps(fy, one), _mm512_sub_ps(fz, one));
    let n000 = g.dot(hash(xy[0], z0), fx, fy, fz);
    let n100 = g.dot(hash(xy[1], z0), gx, fy, fz);
    let n010 = g.dot(hash(xy[2], z0), fx, gy, fz);
    let n110 = g.dot(hash(xy[3], z0), gx, gy, fz);
    let n001 = g.dot(hash(xy[0], z1), fx, fy, gz);
    let n101 = g.dot(hash(xy[1], z1), gx, fy, gz);
    let n011 = g.dot(hash(xy[2], z1), fx, gy, gz);
    let n111 = g.dot(hash(xy[3], z1), gx, gy, gz);
    let (u, v, w) = (fade(fx), fade(fy), fade(fz));
    let lerp = |t: __m512, a: __m512, b: __m512| _mm512_add_ps(a, _mm512_mul_ps(t, _mm512_sub_ps(b, a)));
    let near = lerp(v, lerp(u, n000, n100), lerp(u, n010, n110));
    let far = lerp(v, lerp(u, n001, n101), lerp(u, n011, n111));
    lerp(w, near, far)
}

/// The quintic fade t^3 (t (6t - 15) + 10), in the scalar kernel's order.
#[inline]
#[target_feature(enable = "avx512f")]
fn fade(t: __m512) -> __m512 {
    let s = _mm512_set1_ps;
    let inner = _mm512_add_ps(_mm512_mul_ps(t, _mm512_sub_ps(_mm512_mul_ps(t, s(6.0)), s(15.0))), s(10.0));
    _mm512_mul_ps(_mm512_mul_ps(_mm512_mul_ps(t, t), t), inner)
}
