//! Sixteen-lane sums of the hashed noise in AVX-512, chosen at run time where the CPU has it (AMD Zen 4 and
//! 5, Intel Xeon since Skylake-SP): the bulk paths (`Perlin::noise3_many`, `Fractal::eval3_many`, the rows of
//! a baked fBm or turbulence image) run here, twice the points per instruction of the AVX2 lanes.
//!
//! The gradient of a hash is read from three sixteen-entry registers by `vpermps` (one instruction per
//! component) and dotted by a multiply and two fused multiply-adds; one component is zero and the others are
//! +-1, so every product is exact and the fused sums round as the scalar kernel's separate ones. The rest is
//! the scalar kernel's arithmetic in its order (perlin.rs), so every lane equals `Perlin::noise3` to the bit.
//!
//! Along an image's row y is the same at every point, so each octave's lattice row (its primed indices with
//! the seed, offset and fade) is worked out once per row rather than once per sixteen points: a tenth off a
//! 2D fBm image on Intel.

use super::fbm::Axis;
use super::perlin::{improved_gradient2, improved_gradient3, HASH_MIX, HASH_PRIME, LATTICE_LIMIT};
use std::arch::x86_64::*;

/// Points per vector.
const WIDTH: usize = 16;

/// One octave of a sum: its noise's lattice, where its points come from, and its weight. One exists only
/// where this CPU has AVX-512F, which makes `sum` safe.
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
/// points of D dimensions (2 or 3; `p` holds each axis's coordinates: each point's, or one for all on the
/// last axis only); returns how many points it wrote (the rest are the caller's).
pub(super) fn sum<const D: usize>(octaves: &[Octave], turbulence: bool, p: [Axis; D], out: &mut [f32]) -> usize {
    let each = |a: usize| matches!(p[a], Axis::Each(_));
    if octaves.is_empty() || !(0..D - 1).all(each) {
        return 0;
    }
    // SAFETY: an `Octave` exists only where the CPU has AVX-512F.
    unsafe {
        if each(D - 1) {
            hashed_sum::<D, false>(octaves, turbulence, p, out)
        } else {
            hashed_sum::<D, true>(octaves, turbulence, p, out)
        }
    }
}

/// `sum`, with `ROW` where the last axis holds one coordinate for every point (an image's row): its cells
/// are then worked out once per octave.
#[target_feature(enable = "avx512f")]
unsafe fn hashed_sum<const D: usize, const ROW: bool>(
    octaves: &[Octave],
    turbulence: bool,
    p: [Axis; D],
    out: &mut [f32],
) -> usize {
    let n = p.iter().fold(out.len(), |n, axis| match axis {
        Axis::Each(c) => n.min(c.len()),
        Axis::All(_) => n,
    });
    let full = n - n % WIDTH;
    let gradients = Gradients::<D>::new();
    let row: Vec<RowCells> = match p[D - 1] {
        Axis::All(y) if ROW => octaves.iter().map(|o| RowCells::new::<D>(o, y)).collect(),
        _ => Vec::new(),
    };
    for i in (0..full).step_by(WIDTH) {
        let at: [__m512; D] = std::array::from_fn(|a| match p[a] {
            // SAFETY: i + WIDTH <= full <= the slice's length.
            Axis::Each(c) => unsafe { _mm512_loadu_ps(c.as_ptr().add(i)) },
            Axis::All(c) => _mm512_set1_ps(c),
        });
        let mut sum = _mm512_setzero_ps();
        for (k, o) in octaves.iter().enumerate() {
            let f = _mm512_set1_ps(o.frequency);
            let q = std::array::from_fn(|a| _mm512_add_ps(_mm512_mul_ps(at[a], f), _mm512_set1_ps(o.shift[a])));
            let v = noise::<D, ROW>(o, &gradients, q, row.get(k));
            let v = if turbulence { _mm512_abs_ps(v) } else { v };
            sum = _mm512_add_ps(sum, _mm512_mul_ps(_mm512_set1_ps(o.amplitude), v));
        }
        _mm512_storeu_ps(out.as_mut_ptr().add(i), sum);
    }
    full
}

/// The last axis's lattice cells along an image row, for one octave: the primed indices below and above,
/// XORed with the seed (which every corner's hash takes), the offset from the lower one and its fade.
#[derive(Clone, Copy)]
struct RowCells {
    near: __m512i,
    far: __m512i,
    offset: __m512,
    fade: __m512,
}

impl RowCells {
    /// The cells of octave `o`'s last axis (of D) at the coordinate y.
    #[target_feature(enable = "avx512f")]
    fn new<const D: usize>(o: &Octave, y: f32) -> RowCells {
        let q = _mm512_set1_ps(y * o.frequency + o.shift[D - 1]);
        let (near, far, offset) = primed_cell(q, o.period.map(|p| p[D - 1]), HASH_PRIME[D - 1]);
        let seed = _mm512_set1_epi32(o.seed);
        RowCells { near: _mm512_xor_si512(near, seed), far: _mm512_xor_si512(far, seed), offset, fade: fade(offset) }
    }
}

/// The improved gradients of D dimensions, one register per component, indexed by the hash (sixteen
/// entries in 3D, eight in 2D).
struct Gradients<const D: usize>([__m512; D]);

impl<const D: usize> Gradients<D> {
    #[inline]
    #[target_feature(enable = "avx512f")]
    fn new() -> Gradients<D> {
        let g: [[f32; 3]; 16] = std::array::from_fn(|h| match D {
            3 => improved_gradient3(h),
            _ => {
                let g = improved_gradient2(h);
                [g[0], g[1], 0.0]
            }
        });
        Gradients(std::array::from_fn(|c| {
            let v: [f32; 16] = std::array::from_fn(|h| g[h][c]);
            // SAFETY: an unaligned load of sixteen floats from an array of sixteen.
            unsafe { _mm512_loadu_ps(v.as_ptr()) }
        }))
    }

    /// The gradient of hash `h` dotted with the offsets d, summed in the scalar kernel's order.
    #[inline]
    #[target_feature(enable = "avx512f")]
    fn dot(&self, h: __m512i, d: [__m512; D]) -> __m512 {
        let mut sum = _mm512_mul_ps(_mm512_permutexvar_ps(h, self.0[0]), d[0]);
        for (g, d) in self.0.iter().zip(d).skip(1) {
            sum = _mm512_fmadd_ps(_mm512_permutexvar_ps(h, *g), d, sum);
        }
        sum
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

/// The hashed improved noise of octave `o` at sixteen points of D dimensions (2 or 3), with the last axis's
/// cells given along a row (`ROW`; an instance for each caller keeps it inlined).
#[inline]
#[target_feature(enable = "avx512f")]
fn noise<const D: usize, const ROW: bool>(
    o: &Octave,
    g: &Gradients<D>,
    p: [__m512; D],
    row: Option<&RowCells>,
) -> __m512 {
    // Each axis's cells named (D <= 3): built through `std::array::from_fn`, they left this kernel out of line.
    let cell = |a: usize| primed_cell(p[a], o.period.map(|p| p[a]), HASH_PRIME[a]);
    let row = row.filter(|_| ROW);
    let x = cell(0);
    let y = match row {
        Some(r) if D == 2 => (r.near, r.far, r.offset),
        _ => cell(1),
    };
    let z = match row {
        Some(r) => (r.near, r.far, r.offset),
        None if D == 3 => cell(D - 1),
        None => y,
    };
    let cells = [x, y, z];
    // A row's indices hold the seed already.
    let seed = if row.is_some() { _mm512_setzero_si512() } else { _mm512_set1_epi32(o.seed) };
    let mix = _mm512_set1_epi32(HASH_MIX);
    let one = _mm512_set1_ps(1.0);
    // Corner c (index bits x, y, z = 1, 2, 4): its primed indices XORed with the seed, and its offsets.
    let corner = |c: usize| {
        let mut h = seed;
        let mut d = [one; D];
        for (a, (i0, i1, f)) in cells.iter().enumerate().take(D) {
            let far = c >> a & 1 == 1;
            h = _mm512_xor_si512(h, if far { *i1 } else { *i0 });
            d[a] = if far { _mm512_sub_ps(*f, one) } else { *f };
        }
        // The top four bits of the mixed hash (3D), or its top three (2D).
        let h = _mm512_srli_epi32::<28>(_mm512_mullo_epi32(h, mix));
        let h = if D == 2 { _mm512_srli_epi32::<1>(h) } else { h };
        g.dot(h, d)
    };
    let lerp = |t: __m512, a: __m512, b: __m512| _mm512_add_ps(a, _mm512_mul_ps(t, _mm512_sub_ps(b, a)));
    let u = fade(x.2);
    let v = match row {
        Some(r) if D == 2 => r.fade,
        _ => fade(y.2),
    };
    let near = lerp(v, lerp(u, corner(0), corner(1)), lerp(u, corner(2), corner(3)));
    if D == 2 {
        return near;
    }
    let w = match row {
        Some(r) => r.fade,
        None => fade(z.2),
    };
    let far = lerp(v, lerp(u, corner(4), corner(5)), lerp(u, corner(6), corner(7)));
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
