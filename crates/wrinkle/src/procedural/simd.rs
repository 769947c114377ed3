//! Eight-lane noise kernels in AVX2 (the build targets x86-64-v3, see .cargo/config.toml).
//!
//! LLVM does not vectorise the scalar kernel's table reads by itself (its cost model refuses the gathers),
//! so the lane kernels are written here with explicit vectors. The table variants' lattice hash and
//! gradient reads are gathers; the hashed variant's hash is integer multiplies and XORs. Everything else is
//! straight-line arithmetic with no branch on the hash. The value is the same blend as the scalar kernel
//! (perlin.rs), computed in the same order, so both agree to the bit.

use super::perlin::{HASH_MIX, HASH_PRIME, LANES, LATTICE_LIMIT};
use std::arch::x86_64::*;

/// The tables a lane kernel reads, borrowed from a `Perlin`.
pub(super) struct Tables<'a> {
    pub perm: &'a [i32; 512],
    pub grad: [&'a [f32; 256]; 3],
    pub period: [f32; 3],
}

/// What the hashed variant's lane kernel needs of a `Perlin`.
pub(super) struct Lattice {
    pub seed: i32,
    pub period: [f32; 3],
}

#[derive(Clone, Copy)]
struct F(__m256);
#[derive(Clone, Copy)]
struct I(__m256i);

impl F {
    #[inline(always)]
    fn splat(v: f32) -> F {
        unsafe { F(_mm256_set1_ps(v)) }
    }
    #[inline(always)]
    fn load(a: &[f32; LANES]) -> F {
        unsafe { F(_mm256_loadu_ps(a.as_ptr())) }
    }
    #[inline(always)]
    fn store(self) -> [f32; LANES] {
        let mut out = [0.0; LANES];
        unsafe { _mm256_storeu_ps(out.as_mut_ptr(), self.0) };
        out
    }
    #[inline(always)]
    fn floor(self) -> F {
        unsafe { F(_mm256_floor_ps(self.0)) }
    }
    #[inline(always)]
    fn add(self, o: F) -> F {
        unsafe { F(_mm256_add_ps(self.0, o.0)) }
    }
    #[inline(always)]
    fn sub(self, o: F) -> F {
        unsafe { F(_mm256_sub_ps(self.0, o.0)) }
    }
    #[inline(always)]
    fn div(self, o: F) -> F {
        unsafe { F(_mm256_div_ps(self.0, o.0)) }
    }
    #[inline(always)]
    fn mul(self, o: F) -> F {
        unsafe { F(_mm256_mul_ps(self.0, o.0)) }
    }
    /// self + t (b - self), as the scalar `lerp`.
    #[inline(always)]
    fn lerp_to(self, t: F, b: F) -> F {
        self.add(t.mul(b.sub(self)))
    }
    /// Zero where self >= limit.
    #[inline(always)]
    fn zero_where_at_least(self, limit: F) -> F {
        unsafe { F(_mm256_andnot_ps(_mm256_cmp_ps::<_CMP_GE_OQ>(self.0, limit.0), self.0)) }
    }
    /// The lattice index as an integer in 0..=255.
    #[inline(always)]
    fn index(self) -> I {
        unsafe { I(_mm256_and_si256(_mm256_cvttps_epi32(self.0), _mm256_set1_epi32(255))) }
    }
}

impl I {
    #[inline(always)]
    fn splat(v: i32) -> I {
        unsafe { I(_mm256_set1_epi32(v)) }
    }
    #[inline(always)]
    fn add(self, o: I) -> I {
        unsafe { I(_mm256_add_epi32(self.0, o.0)) }
    }
    #[inline(always)]
    fn xor(self, o: I) -> I {
        unsafe { I(_mm256_xor_si256(self.0, o.0)) }
    }
    /// The low 32 bits of the product, as `i32::wrapping_mul`.
    #[inline(always)]
    fn mul(self, o: I) -> I {
        unsafe { I(_mm256_mullo_epi32(self.0, o.0)) }
    }
    /// The hashed variant's gradient index of lattice points whose primed indices XOR to `self` (the seed
    /// included): the top four bits of the mixed product, as perlin.rs `lattice_hash`.
    #[inline(always)]
    fn mixed_hash(self) -> I {
        unsafe { I(_mm256_srli_epi32::<28>(self.mul(I::splat(HASH_MIX)).0)) }
    }
    /// The 2D improved gradient of index `self & 7` (perlin.rs `improved_gradient2`) dotted with (x, y), by
    /// selects: indices 0-3 are the diagonals (+-x +-y by bits 0 and 1), 4-7 the axes (+-x, then +-y).
    #[inline(always)]
    fn improved_grad2(self, x: F, y: F) -> F {
        unsafe {
            let h = _mm256_and_si256(self.0, _mm256_set1_epi32(7));
            let six = _mm256_set1_epi32(6);
            let on_y = _mm256_castsi256_ps(_mm256_cmpeq_epi32(_mm256_and_si256(h, six), six));
            let diagonal = _mm256_castsi256_ps(_mm256_cmpgt_epi32(_mm256_set1_epi32(4), h));
            let u = _mm256_blendv_ps(x.0, y.0, on_y);
            let v = _mm256_and_ps(y.0, diagonal);
            let su = _mm256_castsi256_ps(_mm256_slli_epi32::<31>(h));
            let sv = _mm256_castsi256_ps(_mm256_slli_epi32::<30>(_mm256_and_si256(h, _mm256_set1_epi32(2))));
            F(_mm256_add_ps(_mm256_xor_ps(u, su), _mm256_xor_ps(v, sv)))
        }
    }
    /// Perlin's grad(hash, x, y, z) of the improved noise, by selects on the hash's low four bits: the same
    /// two terms as the gradient table's dot product (the third is an exact zero), without three gathers.
    #[inline(always)]
    fn improved_grad(self, x: F, y: F, z: F) -> F {
        unsafe {
            let h = _mm256_and_si256(self.0, _mm256_set1_epi32(15));
            let lt8 = _mm256_castsi256_ps(_mm256_cmpgt_epi32(_mm256_set1_epi32(8), h));
            let lt4 = _mm256_castsi256_ps(_mm256_cmpgt_epi32(_mm256_set1_epi32(4), h));
            let twelve_or_14 = _mm256_castsi256_ps(_mm256_cmpeq_epi32(
                _mm256_or_si256(h, _mm256_set1_epi32(2)),
                _mm256_set1_epi32(14),
            ));
            let u = _mm256_blendv_ps(y.0, x.0, lt8);
            let v = _mm256_blendv_ps(_mm256_blendv_ps(z.0, x.0, twelve_or_14), y.0, lt4);
            // Bit 0 flips the sign of u, bit 1 that of v.
            let su = _mm256_castsi256_ps(_mm256_slli_epi32::<31>(h));
            let sv = _mm256_castsi256_ps(_mm256_slli_epi32::<30>(_mm256_and_si256(h, _mm256_set1_epi32(2))));
            F(_mm256_add_ps(_mm256_xor_ps(u, su), _mm256_xor_ps(v, sv)))
        }
    }
    /// perm[i & 511] per lane.
    #[inline(always)]
    fn perm(self, t: &Tables) -> I {
        // Safety: the mask keeps every index inside the 512-entry table.
        unsafe {
            let i = _mm256_and_si256(self.0, _mm256_set1_epi32(511));
            I(_mm256_i32gather_epi32::<4>(t.perm.as_ptr(), i))
        }
    }
    /// table[i & 255] per lane.
    #[inline(always)]
    fn gather(self, table: &[f32; 256]) -> F {
        // Safety: the mask keeps every index inside the 256-entry table.
        unsafe {
            let i = _mm256_and_si256(self.0, _mm256_set1_epi32(255));
            F(_mm256_i32gather_ps::<4>(table.as_ptr(), i))
        }
    }
}

/// Lattice indices (i0, i1) as floats and the offset in the cell, wrapped by the period as the scalar
/// `cell`.
#[inline(always)]
fn wrapped_cell(x: F, period: f32) -> (F, F, F) {
    let fl = x.floor();
    let p = F::splat(period);
    let i0 = fl.sub(p.mul(fl.div(p).floor()));
    let i0 = i0.zero_where_at_least(p);
    let i1 = i0.add(F::splat(1.0)).zero_where_at_least(p);
    (i0, i1, x.sub(fl))
}

/// The table variants' lattice indices (into the 256-entry table) and offset.
#[inline(always)]
fn cell(x: F, period: f32) -> (I, I, F) {
    let (i0, i1, f) = wrapped_cell(x, period);
    (i0.index(), i1.index(), f)
}

/// The hashed variant's lattice indices along one axis, already multiplied by the axis's hash prime, and the
/// offset: wrapped by the period when `PERIODIC`, else unwrapped (clamped to +-LATTICE_LIMIT as the scalar
/// `cell`).
#[inline(always)]
fn primed_cell<const PERIODIC: bool>(x: F, period: f32, prime: i32) -> (I, I, F) {
    let to_int = |v: F| unsafe { I(_mm256_cvttps_epi32(v.0)) };
    let prime = I::splat(prime);
    if PERIODIC {
        let (i0, i1, f) = wrapped_cell(x, period);
        (to_int(i0).mul(prime), to_int(i1).mul(prime), f)
    } else {
        let fl = x.floor();
        let clamped = unsafe {
            F(_mm256_min_ps(_mm256_max_ps(fl.0, _mm256_set1_ps(-LATTICE_LIMIT)), _mm256_set1_ps(LATTICE_LIMIT)))
        };
        let p0 = to_int(clamped).mul(prime);
        // (i + 1) * prime, wrapping, as the scalar path computes it.
        (p0, p0.add(prime), x.sub(fl))
    }
}

#[inline(always)]
fn fade<const Q: bool>(t: F) -> F {
    let s = |v: f32| F::splat(v);
    if Q {
        t.mul(t).mul(t).mul(t.mul(t.mul(s(6.0)).sub(s(15.0))).add(s(10.0)))
    } else {
        t.mul(t).mul(s(3.0).sub(s(2.0).mul(t)))
    }
}

/// 3D noise at eight points; `Q`: the improved noise (quintic fade, gradients from the hash bits),
/// else the classic one (cubic fade, gradients read from the table).
#[inline(always)]
pub(super) fn noise3<const Q: bool>(t: &Tables, x: &[f32; LANES], y: &[f32; LANES], z: &[f32; LANES]) -> [f32; LANES] {
    let (i0, i1, fx) = cell(F::load(x), t.period[0]);
    let (j0, j1, fy) = cell(F::load(y), t.period[1]);
    let (k0, k1, fz) = cell(F::load(z), t.period[2]);
    let (a0, a1) = (i0.perm(t), i1.perm(t));
    let (b00, b01, b10, b11) = (a0.add(j0).perm(t), a0.add(j1).perm(t), a1.add(j0).perm(t), a1.add(j1).perm(t));
    let one = F::splat(1.0);
    let (gx, gy, gz) = (fx.sub(one), fy.sub(one), fz.sub(one));
    let dot = |h: I, dx: F, dy: F, dz: F| {
        if Q {
            h.improved_grad(dx, dy, dz)
        } else {
            let (cx, cy, cz) = (h.gather(t.grad[0]), h.gather(t.grad[1]), h.gather(t.grad[2]));
            cx.mul(dx).add(cy.mul(dy)).add(cz.mul(dz))
        }
    };
    let n000 = dot(b00.add(k0).perm(t), fx, fy, fz);
    let n100 = dot(b10.add(k0).perm(t), gx, fy, fz);
    let n010 = dot(b01.add(k0).perm(t), fx, gy, fz);
    let n110 = dot(b11.add(k0).perm(t), gx, gy, fz);
    let n001 = dot(b00.add(k1).perm(t), fx, fy, gz);
    let n101 = dot(b10.add(k1).perm(t), gx, fy, gz);
    let n011 = dot(b01.add(k1).perm(t), fx, gy, gz);
    let n111 = dot(b11.add(k1).perm(t), gx, gy, gz);
    blend3::<Q>([n000, n100, n010, n110, n001, n101, n011, n111], fx, fy, fz).store()
}

/// The trilinear blend of the eight corner values with the fade of the offsets.
#[inline(always)]
fn blend3<const Q: bool>(n: [F; 8], fx: F, fy: F, fz: F) -> F {
    let (u, v, w) = (fade::<Q>(fx), fade::<Q>(fy), fade::<Q>(fz));
    let near = n[0].lerp_to(u, n[1]).lerp_to(v, n[2].lerp_to(u, n[3]));
    let far = n[4].lerp_to(u, n[5]).lerp_to(v, n[6].lerp_to(u, n[7]));
    near.lerp_to(w, far)
}

/// The hashed variant's 3D noise at eight points: the improved noise with the lattice hashed by integer
/// multiplies (perlin.rs `lattice_hash`), so no lane reads memory.
#[inline(always)]
pub(super) fn hashed_noise3<const PERIODIC: bool>(
    t: &Lattice,
    x: &[f32; LANES],
    y: &[f32; LANES],
    z: &[f32; LANES],
) -> [f32; LANES] {
    let (x0, x1, fx) = primed_cell::<PERIODIC>(F::load(x), t.period[0], HASH_PRIME[0]);
    let (y0, y1, fy) = primed_cell::<PERIODIC>(F::load(y), t.period[1], HASH_PRIME[1]);
    let (z0, z1, fz) = primed_cell::<PERIODIC>(F::load(z), t.period[2], HASH_PRIME[2]);
    let seed = I::splat(t.seed);
    let (s0, s1) = (seed.xor(x0), seed.xor(x1));
    let (a00, a10, a01, a11) = (s0.xor(y0), s1.xor(y0), s0.xor(y1), s1.xor(y1));
    let one = F::splat(1.0);
    let (gx, gy, gz) = (fx.sub(one), fy.sub(one), fz.sub(one));
    let n = [
        a00.xor(z0).mixed_hash().improved_grad(fx, fy, fz),
        a10.xor(z0).mixed_hash().improved_grad(gx, fy, fz),
        a01.xor(z0).mixed_hash().improved_grad(fx, gy, fz),
        a11.xor(z0).mixed_hash().improved_grad(gx, gy, fz),
        a00.xor(z1).mixed_hash().improved_grad(fx, fy, gz),
        a10.xor(z1).mixed_hash().improved_grad(gx, fy, gz),
        a01.xor(z1).mixed_hash().improved_grad(fx, gy, gz),
        a11.xor(z1).mixed_hash().improved_grad(gx, gy, gz),
    ];
    blend3::<true>(n, fx, fy, fz).store()
}

/// The hashed variant's 2D noise at eight points (the lattice hash with k = 0, its top three bits).
#[inline(always)]
pub(super) fn hashed_noise2<const PERIODIC: bool>(t: &Lattice, x: &[f32; LANES], y: &[f32; LANES]) -> [f32; LANES] {
    let (x0, x1, fx) = primed_cell::<PERIODIC>(F::load(x), t.period[0], HASH_PRIME[0]);
    let (y0, y1, fy) = primed_cell::<PERIODIC>(F::load(y), t.period[1], HASH_PRIME[1]);
    let seed = I::splat(t.seed);
    let (s0, s1) = (seed.xor(x0), seed.xor(x1));
    let index = |a: I| unsafe { I(_mm256_srli_epi32::<1>(a.mixed_hash().0)) };
    let one = F::splat(1.0);
    let (gx, gy) = (fx.sub(one), fy.sub(one));
    let n00 = index(s0.xor(y0)).improved_grad2(fx, fy);
    let n10 = index(s1.xor(y0)).improved_grad2(gx, fy);
    let n01 = index(s0.xor(y1)).improved_grad2(fx, gy);
    let n11 = index(s1.xor(y1)).improved_grad2(gx, gy);
    let (u, v) = (fade::<true>(fx), fade::<true>(fy));
    n00.lerp_to(u, n10).lerp_to(v, n01.lerp_to(u, n11)).store()
}

/// 2D noise at eight points.
#[inline(always)]
pub(super) fn noise2<const Q: bool>(
    perm: &[i32; 512],
    grad: [&[f32; 256]; 2],
    period: [f32; 2],
    x: &[f32; LANES],
    y: &[f32; LANES],
) -> [f32; LANES] {
    let t = Tables { perm, grad: [grad[0], grad[1], grad[1]], period: [period[0], period[1], 1.0] };
    let (i0, i1, fx) = cell(F::load(x), period[0]);
    let (j0, j1, fy) = cell(F::load(y), period[1]);
    let (a0, a1) = (i0.perm(&t), i1.perm(&t));
    let one = F::splat(1.0);
    let (gx, gy) = (fx.sub(one), fy.sub(one));
    let dot = |h: I, dx: F, dy: F| h.gather(grad[0]).mul(dx).add(h.gather(grad[1]).mul(dy));
    let n00 = dot(a0.add(j0).perm(&t), fx, fy);
    let n10 = dot(a1.add(j0).perm(&t), gx, fy);
    let n01 = dot(a0.add(j1).perm(&t), fx, gy);
    let n11 = dot(a1.add(j1).perm(&t), gx, gy);
    let (u, v) = (fade::<Q>(fx), fade::<Q>(fy));
    n00.lerp_to(u, n10).lerp_to(v, n01.lerp_to(u, n11)).store()
}
