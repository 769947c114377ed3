//! Perlin's gradient noise in 2D and 3D: zero at every integer lattice point, a pseudo-random gradient there,
//! and a smooth interpolation between the eight (or four) corner ramps of the cell.
//!
//! Three variants:
//! - `Improved` (Perlin 2002): the quintic fade 6t^5 - 15t^4 + 10t^3 (continuous second derivative) and the
//!   twelve edge gradients of the cube (sixteen entries, four repeated), chosen by the hash's low four bits;
//! - `Classic` (Perlin 1985, the slides): the Hermite cubic 3t^2 - 2t^3 and random unit gradients, a fresh
//!   one per hash value;
//! - `Hashed` (the default): the improved noise with a multiplicative lattice hash in place of the table.
//!
//! `Improved` and `Classic` hash a lattice point (i, j, k) by the permutation table P as P[P[P[i] + j] + k]
//! (Perlin's reference code), so they repeat every 256 cells. Seed 0 is the published permutation; any other
//! seed shuffles it. `Hashed` multiplies each lattice index by a large odd constant, XORs the three with the
//! seed, multiplies by one more odd constant and takes the top four bits (the bits every input bit reaches):
//! no table read, so the lanes need no gather, which makes it about 3x faster on AMD Zen, whose gathers are
//! slow (the scheme FastNoise2 uses). It does not repeat before 2^30 cells. A period (in lattice cells,
//! per axis) wraps the lattice before hashing, so the noise repeats exactly: tileable textures.
//!
//! The f32 path evaluates the trilinear (bilinear) blend in polynomial form, which gives the analytic
//! gradient at little extra cost; the lane functions run it over eight points at once, written as plain
//! loops over `[f32; 8]` that LLVM turns into AVX2 (gathers for the table reads). The f64 path
//! (`noise3_f64`) follows the reference implementation's lerp chain literally and is the oracle for the f32
//! path and for the published values.

/// Points evaluated together by the lane functions.
pub const LANES: usize = 8;

/// Perlin's published permutation of 0..=255 (Improved Noise reference implementation, 2002).
pub const REFERENCE_PERMUTATION: [u8; 256] = [
    151, 160, 137, 91, 90, 15, 131, 13, 201, 95, 96, 53, 194, 233, 7, 225, 140, 36, 103, 30, 69, 142, 8, 99, 37, 240,
    21, 10, 23, 190, 6, 148, 247, 120, 234, 75, 0, 26, 197, 62, 94, 252, 219, 203, 117, 35, 11, 32, 57, 177, 33, 88,
    237, 149, 56, 87, 174, 20, 125, 136, 171, 168, 68, 175, 74, 165, 71, 134, 139, 48, 27, 166, 77, 146, 158, 231, 83,
    111, 229, 122, 60, 211, 133, 230, 220, 105, 92, 41, 55, 46, 245, 40, 244, 102, 143, 54, 65, 25, 63, 161, 1, 216,
    80, 73, 209, 76, 132, 187, 208, 89, 18, 169, 200, 196, 135, 130, 116, 188, 159, 86, 164, 100, 109, 198, 173, 186,
    3, 64, 52, 217, 226, 250, 124, 123, 5, 202, 38, 147, 118, 126, 255, 82, 85, 212, 207, 206, 59, 227, 47, 16, 58, 17,
    182, 189, 28, 42, 223, 183, 170, 213, 119, 248, 152, 2, 44, 154, 163, 70, 221, 153, 101, 155, 167, 43, 172, 9, 129,
    22, 39, 253, 19, 98, 108, 110, 79, 113, 224, 232, 178, 185, 112, 104, 218, 246, 97, 228, 251, 34, 242, 193, 238,
    210, 144, 12, 191, 179, 162, 241, 81, 51, 145, 235, 249, 14, 239, 107, 49, 192, 214, 31, 181, 199, 106, 157, 184,
    84, 204, 176, 115, 121, 50, 45, 127, 4, 150, 254, 138, 236, 205, 93, 222, 114, 67, 29, 24, 72, 243, 141, 128, 195,
    78, 66, 215, 61, 156, 180,
];

/// Which of Perlin's noises, and how its lattice is hashed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Variant {
    /// 2002: quintic fade, the cube's edge gradients, the permutation table (Perlin's reference values).
    Improved,
    /// 1985: Hermite cubic fade, random unit gradients.
    Classic,
    /// The 2002 noise with a multiplicative lattice hash: no table reads, the fast default.
    #[default]
    Hashed,
}

impl Variant {
    /// The names scenes, the command line and Python give the variants.
    pub const NAMES: [(&'static str, Variant); 3] =
        [("hashed", Variant::Hashed), ("improved", Variant::Improved), ("classic", Variant::Classic)];

    /// The variant called `name`.
    pub fn from_name(name: &str) -> Option<Variant> {
        Variant::NAMES.iter().find(|(n, _)| *n == name).map(|&(_, v)| v)
    }

    /// The names, quoted as `quote` and listed for an error message: "a, b or c".
    pub fn name_list(quote: &str) -> String {
        let names: Vec<String> = Variant::NAMES.iter().map(|(n, _)| format!("{quote}{n}{quote}")).collect();
        format!("{} or {}", names[..names.len() - 1].join(", "), names[names.len() - 1])
    }
}

/// The odd constants of the multiplicative lattice hash (FastNoise2's primes and final multiplier).
pub(super) const HASH_PRIME: [i32; 3] = [501_125_321, 1_136_930_381, 1_720_413_743];
pub(super) const HASH_MIX: i32 = 0x27d4_eb2d;

/// The unwrapped lattice index stays within +-2^30, where i32 arithmetic cannot overflow and f32 still
/// resolves every cell.
pub(super) const LATTICE_LIMIT: f32 = (1 << 30) as f32;

/// The hashed variant's gradient index (0..16) of lattice point (i, j, k).
#[inline(always)]
fn lattice_hash(seed: i32, i: i32, j: i32, k: i32) -> usize {
    let primed = [i.wrapping_mul(HASH_PRIME[0]), j.wrapping_mul(HASH_PRIME[1]), k.wrapping_mul(HASH_PRIME[2])];
    ((seed ^ primed[0] ^ primed[1] ^ primed[2]).wrapping_mul(HASH_MIX) as u32 >> 28) as usize
}

/// Noise value and its gradient (d/dx, d/dy, d/dz; the third is 0 in 2D).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct NoiseD {
    pub value: f32,
    pub grad: [f32; 3],
}

/// A Perlin noise: its variant, permutation, gradient tables and period.
#[derive(Clone, Debug)]
pub struct Perlin {
    variant: Variant,
    /// P twice over, so that P[P[i] + j] needs no wrap; i32 so that the lanes read it by gathers.
    perm: Box<[i32; 512]>,
    /// 3D gradient of each hash value, per component.
    grad3: Box<[[f32; 256]; 3]>,
    /// 2D gradient of each hash value, per component.
    grad2: Box<[[f32; 256]; 2]>,
    /// Lattice period per axis (cells); 256 is the table's own period, i.e. no extra wrap.
    period: [f32; 3],
    /// Whether a period was asked for (tileable output).
    periodic: bool,
    /// The seed the hashed variant mixes into every lattice hash.
    hash_seed: i32,
}

/// The largest period accepted: the lattice index stays exact in f32 far beyond it.
pub const MAX_PERIOD: u32 = 1 << 20;

impl Perlin {
    /// The noise with `seed` (0: Perlin's published permutation), repeating every 256 cells.
    pub fn new(variant: Variant, seed: u64) -> Perlin {
        let mut p = REFERENCE_PERMUTATION;
        let mut rng = SplitMix64(seed);
        if seed != 0 {
            // Fisher-Yates shuffle of the reference table.
            for i in (1..256).rev() {
                let j = (rng.next() % (i as u64 + 1)) as usize;
                p.swap(i, j);
            }
        }
        let perm = Box::new(std::array::from_fn(|i| p[i & 255] as i32));
        let mut grad3 = Box::new([[0.0f32; 256]; 3]);
        let mut grad2 = Box::new([[0.0f32; 256]; 2]);
        for h in 0..256 {
            let (g3, g2) = match variant {
                Variant::Improved | Variant::Hashed => (improved_gradient3(h), improved_gradient2(h)),
                Variant::Classic => (rng.unit3(), rng.unit2()),
            };
            for c in 0..3 {
                grad3[c][h] = g3[c];
            }
            for c in 0..2 {
                grad2[c][h] = g2[c];
            }
        }
        let hash_seed = (SplitMix64(seed).next() >> 32) as i32;
        Perlin { variant, perm, grad3, grad2, period: [256.0; 3], periodic: false, hash_seed }
    }

    /// The same noise repeating every `period` lattice cells along each axis (1..=MAX_PERIOD).
    pub fn with_period(mut self, period: [u32; 3]) -> Perlin {
        self.period = period.map(|p| p.clamp(1, MAX_PERIOD) as f32);
        self.periodic = true;
        self
    }

    pub fn variant(&self) -> Variant {
        self.variant
    }

    /// The period per axis in lattice cells, when one was set.
    pub fn period(&self) -> Option<[u32; 3]> {
        self.periodic.then(|| self.period.map(|p| p as u32))
    }

    /// The fade curve and its derivative: quintic (`Q`, improved) or Hermite cubic (classic). A const
    /// parameter, so that the lane loops hold no branch.
    #[inline(always)]
    fn fade<const Q: bool>(t: f32) -> (f32, f32) {
        if Q {
            (t * t * t * (t * (t * 6.0 - 15.0) + 10.0), 30.0 * t * t * (t * (t - 2.0) + 1.0))
        } else {
            (t * t * (3.0 - 2.0 * t), 6.0 * t * (1.0 - t))
        }
    }

    /// Whether the lattice goes unwrapped: the hashed variant without a period (the table variants always
    /// wrap, by 256 without a period).
    #[inline(always)]
    fn unwrapped(&self) -> bool {
        self.variant == Variant::Hashed && !self.periodic
    }

    /// The two lattice indices around `x` along `axis` (wrapped by the period where one applies) and the
    /// offset of `x` from the first.
    #[inline(always)]
    fn cell(&self, x: f32, axis: usize) -> (i32, i32, f32) {
        let fl = x.floor();
        if self.unwrapped() {
            let i0 = fl.clamp(-LATTICE_LIMIT, LATTICE_LIMIT) as i32;
            return (i0, i0 + 1, x - fl);
        }
        let p = self.period[axis];
        let i0 = fl - p * (fl / p).floor();
        // `i0` can round up to exactly p for tiny negative x.
        let i0 = if i0 >= p { 0.0 } else { i0 };
        let i1 = if i0 + 1.0 >= p { 0.0 } else { i0 + 1.0 };
        (i0 as i32, i1 as i32, x - fl)
    }

    #[inline(always)]
    fn p(&self, i: usize) -> usize {
        // The mask is a no-op (i < 512 always) that proves the read in bounds, so the lanes need no check.
        self.perm[i & 511] as usize
    }

    /// The permutation table's hash of (i, j, k), each taken modulo 256.
    #[inline(always)]
    fn table_hash(&self, i: i32, j: i32, k: i32) -> usize {
        let m = |v: i32| (v & 255) as usize;
        self.p(self.p(self.p(m(i)) + m(j)) + m(k))
    }

    /// The gradient index of lattice point (i, j, k): the variant's hash.
    #[inline(always)]
    fn hash3(&self, i: i32, j: i32, k: i32) -> usize {
        match self.variant {
            Variant::Hashed => lattice_hash(self.hash_seed, i, j, k),
            Variant::Improved | Variant::Classic => self.table_hash(i, j, k),
        }
    }

    /// The gradient index of lattice point (i, j) of the 2D noise.
    #[inline(always)]
    fn hash2(&self, i: i32, j: i32) -> usize {
        match self.variant {
            // The top three bits pick one of the eight 2D gradients.
            Variant::Hashed => lattice_hash(self.hash_seed, i, j, 0) >> 1,
            Variant::Improved | Variant::Classic => self.p(self.p((i & 255) as usize) + (j & 255) as usize),
        }
    }

    /// Noise at (x, y, z), and its gradient when `D`.
    #[inline(always)]
    fn eval3<const D: bool, const Q: bool>(&self, x: f32, y: f32, z: f32) -> NoiseD {
        let (i0, i1, fx) = self.cell(x, 0);
        let (j0, j1, fy) = self.cell(y, 1);
        let (k0, k1, fz) = self.cell(z, 2);
        // Corner hashes, index bits (x, y, z) = (1, 2, 4).
        let h = [
            self.hash3(i0, j0, k0),
            self.hash3(i1, j0, k0),
            self.hash3(i0, j1, k0),
            self.hash3(i1, j1, k0),
            self.hash3(i0, j0, k1),
            self.hash3(i1, j0, k1),
            self.hash3(i0, j1, k1),
            self.hash3(i1, j1, k1),
        ];
        let [gx, gy, gz] = &*self.grad3;
        let g = |c: usize| [gx[h[c] & 255], gy[h[c] & 255], gz[h[c] & 255]];
        let dot = |c: usize| {
            let d = [fx - (c & 1) as f32, fy - ((c >> 1) & 1) as f32, fz - (c >> 2) as f32];
            let gc = g(c);
            gc[0] * d[0] + gc[1] * d[1] + gc[2] * d[2]
        };
        let n = [dot(0), dot(1), dot(2), dot(3), dot(4), dot(5), dot(6), dot(7)];
        let (u, du) = Self::fade::<Q>(fx);
        let (v, dv) = Self::fade::<Q>(fy);
        let (w, dw) = Self::fade::<Q>(fz);
        let value = trilerp(u, v, w, n);
        if !D {
            return NoiseD { value, grad: [0.0; 3] };
        }
        // d/dx = (the same blend of the corner gradients) + du/dx * d(blend of the corner values)/du.
        let gs = [g(0), g(1), g(2), g(3), g(4), g(5), g(6), g(7)];
        let blend = |axis: usize| trilerp(u, v, w, gs.map(|g| g[axis]));
        let [a, b, c, d, e, f, g, h] = n;
        let dn_du = lerp(w, lerp(v, b - a, d - c), lerp(v, f - e, h - g));
        let dn_dv = lerp(w, lerp(u, c - a, d - b), lerp(u, g - e, h - f));
        let dn_dw = lerp(v, lerp(u, e - a, f - b), lerp(u, g - c, h - d));
        let grad = [blend(0) + du * dn_du, blend(1) + dv * dn_dv, blend(2) + dw * dn_dw];
        NoiseD { value, grad }
    }

    /// Noise at (x, y), and its gradient when `D`.
    #[inline(always)]
    fn eval2<const D: bool, const Q: bool>(&self, x: f32, y: f32) -> NoiseD {
        let (i0, i1, fx) = self.cell(x, 0);
        let (j0, j1, fy) = self.cell(y, 1);
        let h = [self.hash2(i0, j0), self.hash2(i1, j0), self.hash2(i0, j1), self.hash2(i1, j1)];
        let [gx, gy] = &*self.grad2;
        let g = |c: usize| [gx[h[c] & 255], gy[h[c] & 255]];
        let dot = |c: usize| {
            let gc = g(c);
            gc[0] * (fx - (c & 1) as f32) + gc[1] * (fy - (c >> 1) as f32)
        };
        let n = [dot(0), dot(1), dot(2), dot(3)];
        let (u, du) = Self::fade::<Q>(fx);
        let (v, dv) = Self::fade::<Q>(fy);
        let value = bilerp(u, v, n);
        if !D {
            return NoiseD { value, grad: [0.0; 3] };
        }
        let gs = [g(0), g(1), g(2), g(3)];
        let [a, b, c, d] = n;
        let grad = [
            bilerp(u, v, gs.map(|g| g[0])) + du * lerp(v, b - a, d - c),
            bilerp(u, v, gs.map(|g| g[1])) + dv * lerp(u, c - a, d - b),
            0.0,
        ];
        NoiseD { value, grad }
    }

    /// 3D noise.
    #[inline]
    pub fn noise3(&self, x: f32, y: f32, z: f32) -> f32 {
        match self.variant {
            Variant::Improved | Variant::Hashed => self.eval3::<false, true>(x, y, z).value,
            Variant::Classic => self.eval3::<false, false>(x, y, z).value,
        }
    }

    /// 3D noise and its analytic gradient.
    #[inline]
    pub fn noise3_d(&self, x: f32, y: f32, z: f32) -> NoiseD {
        match self.variant {
            Variant::Improved | Variant::Hashed => self.eval3::<true, true>(x, y, z),
            Variant::Classic => self.eval3::<true, false>(x, y, z),
        }
    }

    /// 2D noise.
    #[inline]
    pub fn noise2(&self, x: f32, y: f32) -> f32 {
        match self.variant {
            Variant::Improved | Variant::Hashed => self.eval2::<false, true>(x, y).value,
            Variant::Classic => self.eval2::<false, false>(x, y).value,
        }
    }

    /// 2D noise and its analytic gradient (the third component is 0).
    #[inline]
    pub fn noise2_d(&self, x: f32, y: f32) -> NoiseD {
        match self.variant {
            Variant::Improved | Variant::Hashed => self.eval2::<true, true>(x, y),
            Variant::Classic => self.eval2::<true, false>(x, y),
        }
    }

    /// 3D noise at eight points at once.
    #[inline]
    pub fn noise3_lanes(&self, x: &[f32; LANES], y: &[f32; LANES], z: &[f32; LANES]) -> [f32; LANES] {
        match self.variant {
            Variant::Improved => self.lanes3::<true>(x, y, z),
            Variant::Classic => self.lanes3::<false>(x, y, z),
            Variant::Hashed => self.hashed_lanes3(x, y, z),
        }
    }

    #[cfg(all(target_arch = "x86_64", target_feature = "avx2"))]
    #[inline(always)]
    fn lanes3<const Q: bool>(&self, x: &[f32; LANES], y: &[f32; LANES], z: &[f32; LANES]) -> [f32; LANES] {
        let tables = super::simd::Tables {
            perm: &self.perm,
            grad: [&self.grad3[0], &self.grad3[1], &self.grad3[2]],
            period: self.period,
        };
        super::simd::noise3::<Q>(&tables, x, y, z)
    }

    /// Without AVX2: the scalar kernel per lane.
    #[cfg(not(all(target_arch = "x86_64", target_feature = "avx2")))]
    #[inline(always)]
    fn lanes3<const Q: bool>(&self, x: &[f32; LANES], y: &[f32; LANES], z: &[f32; LANES]) -> [f32; LANES] {
        let mut out = [0.0; LANES];
        for l in 0..LANES {
            out[l] = self.eval3::<false, Q>(x[l], y[l], z[l]).value;
        }
        out
    }

    #[cfg(all(target_arch = "x86_64", target_feature = "avx2"))]
    #[inline(always)]
    fn hashed_lanes3(&self, x: &[f32; LANES], y: &[f32; LANES], z: &[f32; LANES]) -> [f32; LANES] {
        let lattice = super::simd::Lattice { seed: self.hash_seed, period: self.period };
        if self.periodic {
            super::simd::hashed_noise3::<true>(&lattice, x, y, z)
        } else {
            super::simd::hashed_noise3::<false>(&lattice, x, y, z)
        }
    }

    #[cfg(not(all(target_arch = "x86_64", target_feature = "avx2")))]
    #[inline(always)]
    fn hashed_lanes3(&self, x: &[f32; LANES], y: &[f32; LANES], z: &[f32; LANES]) -> [f32; LANES] {
        self.lanes3::<true>(x, y, z)
    }

    /// 2D noise at eight points at once.
    #[inline]
    pub fn noise2_lanes(&self, x: &[f32; LANES], y: &[f32; LANES]) -> [f32; LANES] {
        match self.variant {
            Variant::Improved => self.lanes2::<true>(x, y),
            Variant::Classic => self.lanes2::<false>(x, y),
            Variant::Hashed => self.hashed_lanes2(x, y),
        }
    }

    #[cfg(all(target_arch = "x86_64", target_feature = "avx2"))]
    #[inline(always)]
    fn lanes2<const Q: bool>(&self, x: &[f32; LANES], y: &[f32; LANES]) -> [f32; LANES] {
        let period = [self.period[0], self.period[1]];
        super::simd::noise2::<Q>(&self.perm, [&self.grad2[0], &self.grad2[1]], period, x, y)
    }

    /// Without AVX2: the scalar kernel per lane.
    #[cfg(not(all(target_arch = "x86_64", target_feature = "avx2")))]
    #[inline(always)]
    fn lanes2<const Q: bool>(&self, x: &[f32; LANES], y: &[f32; LANES]) -> [f32; LANES] {
        let mut out = [0.0; LANES];
        for l in 0..LANES {
            out[l] = self.eval2::<false, Q>(x[l], y[l]).value;
        }
        out
    }

    #[cfg(all(target_arch = "x86_64", target_feature = "avx2"))]
    #[inline(always)]
    fn hashed_lanes2(&self, x: &[f32; LANES], y: &[f32; LANES]) -> [f32; LANES] {
        let lattice = super::simd::Lattice { seed: self.hash_seed, period: self.period };
        if self.periodic {
            super::simd::hashed_noise2::<true>(&lattice, x, y)
        } else {
            super::simd::hashed_noise2::<false>(&lattice, x, y)
        }
    }

    #[cfg(not(all(target_arch = "x86_64", target_feature = "avx2")))]
    #[inline(always)]
    fn hashed_lanes2(&self, x: &[f32; LANES], y: &[f32; LANES]) -> [f32; LANES] {
        self.lanes2::<true>(x, y)
    }

    /// 3D noise at every point of three coordinate slices (of equal length) into `out`.
    pub fn noise3_many(&self, x: &[f32], y: &[f32], z: &[f32], out: &mut [f32]) {
        let n = out.len();
        assert!(x.len() == n && y.len() == n && z.len() == n, "coordinate slices must match the output");
        #[cfg(target_arch = "x86_64")]
        let wide = self
            .wide_octave(1.0, [0.0; 3], 1.0)
            .map_or(0, |o| super::simd512::sum(&[o], false, [x, y, z].map(super::fbm::Axis::Each), out));
        #[cfg(not(target_arch = "x86_64"))]
        let wide = 0;
        let full = wide + (n - wide) / LANES * LANES;
        for i in (wide..full).step_by(LANES) {
            let lanes = |s: &[f32]| -> [f32; LANES] { s[i..i + LANES].try_into().expect("one lane group") };
            out[i..i + LANES].copy_from_slice(&self.noise3_lanes(&lanes(x), &lanes(y), &lanes(z)));
        }
        for i in full..n {
            out[i] = self.noise3(x[i], y[i], z[i]);
        }
    }

    /// This noise as one octave (p * frequency + shift, weighted by amplitude) of a sixteen-lane sum: where
    /// the CPU has AVX-512 and the variant is the hashed one, else none.
    #[cfg(target_arch = "x86_64")]
    pub(super) fn wide_octave(
        &self,
        frequency: f32,
        shift: [f32; 3],
        amplitude: f32,
    ) -> Option<super::simd512::Octave> {
        if self.variant != Variant::Hashed {
            return None;
        }
        super::simd512::Octave::new(self.hash_seed, self.periodic.then_some(self.period), frequency, shift, amplitude)
    }

    /// The f64 noise, following Perlin's reference code step by step (floor, fade, lerp chain, grad by
    /// hash). For `Improved` with seed 0 and no period this is his published function.
    pub fn noise3_f64(&self, x: f64, y: f64, z: f64) -> f64 {
        let (cell, fade) = (|x, axis| self.cell_f64(x, axis), |t| self.fade_f64(t));
        let grad = |h: usize, x: f64, y: f64, z: f64| {
            self.grad3[0][h] as f64 * x + self.grad3[1][h] as f64 * y + self.grad3[2][h] as f64 * z
        };
        let (x0, x1, x) = cell(x, 0);
        let (y0, y1, y) = cell(y, 1);
        let (z0, z1, z) = cell(z, 2);
        let hash = |i, j, k| self.hash3(i, j, k);
        let (u, v, w) = (fade(x), fade(y), fade(z));
        lerp64(
            w,
            lerp64(
                v,
                lerp64(u, grad(hash(x0, y0, z0), x, y, z), grad(hash(x1, y0, z0), x - 1.0, y, z)),
                lerp64(u, grad(hash(x0, y1, z0), x, y - 1.0, z), grad(hash(x1, y1, z0), x - 1.0, y - 1.0, z)),
            ),
            lerp64(
                v,
                lerp64(u, grad(hash(x0, y0, z1), x, y, z - 1.0), grad(hash(x1, y0, z1), x - 1.0, y, z - 1.0)),
                lerp64(
                    u,
                    grad(hash(x0, y1, z1), x, y - 1.0, z - 1.0),
                    grad(hash(x1, y1, z1), x - 1.0, y - 1.0, z - 1.0),
                ),
            ),
        )
    }
}

#[inline(always)]
fn lerp(t: f32, a: f32, b: f32) -> f32 {
    a + t * (b - a)
}

/// Bilinear blend of four corner values, index bits (x, y) = (1, 2).
#[inline(always)]
fn bilerp(u: f32, v: f32, c: [f32; 4]) -> f32 {
    lerp(v, lerp(u, c[0], c[1]), lerp(u, c[2], c[3]))
}

/// Trilinear blend of eight corner values, index bits (x, y, z) = (1, 2, 4).
#[inline(always)]
fn trilerp(u: f32, v: f32, w: f32, c: [f32; 8]) -> f32 {
    lerp(w, bilerp(u, v, [c[0], c[1], c[2], c[3]]), bilerp(u, v, [c[4], c[5], c[6], c[7]]))
}

impl Perlin {
    /// The 2D noise in f64, in the same steps as `noise3_f64`.
    pub fn noise2_f64(&self, x: f64, y: f64) -> f64 {
        let (cell, fade) = (|x, axis| self.cell_f64(x, axis), |t| self.fade_f64(t));
        let grad = |h: usize, x: f64, y: f64| self.grad2[0][h] as f64 * x + self.grad2[1][h] as f64 * y;
        let (x0, x1, x) = cell(x, 0);
        let (y0, y1, y) = cell(y, 1);
        let hash = |i, j| self.hash2(i, j);
        let (u, v) = (fade(x), fade(y));
        lerp64(
            v,
            lerp64(u, grad(hash(x0, y0), x, y), grad(hash(x1, y0), x - 1.0, y)),
            lerp64(u, grad(hash(x0, y1), x, y - 1.0), grad(hash(x1, y1), x - 1.0, y - 1.0)),
        )
    }

    fn cell_f64(&self, x: f64, axis: usize) -> (i32, i32, f64) {
        let fl = x.floor();
        if self.unwrapped() {
            let i0 = fl.clamp(-LATTICE_LIMIT as f64, LATTICE_LIMIT as f64) as i32;
            return (i0, i0 + 1, x - fl);
        }
        let p = self.period[axis] as f64;
        let i0 = fl - p * (fl / p).floor();
        let i0 = if i0 >= p { 0.0 } else { i0 };
        let i1 = if i0 + 1.0 >= p { 0.0 } else { i0 + 1.0 };
        (i0 as i32, i1 as i32, x - fl)
    }

    fn fade_f64(&self, t: f64) -> f64 {
        match self.variant {
            Variant::Improved | Variant::Hashed => fade_f64(t),
            Variant::Classic => t * t * (3.0 - 2.0 * t),
        }
    }
}

fn lerp64(t: f64, a: f64, b: f64) -> f64 {
    a + t * (b - a)
}

/// Perlin's fade of the improved noise, in f64: 6t^5 - 15t^4 + 10t^3.
pub fn fade_f64(t: f64) -> f64 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

/// The gradient Perlin's `grad(hash, x, y, z)` dots with: h = hash & 15 picks one of the cube's twelve
/// edge directions (four of them twice).
pub(super) fn improved_gradient3(hash: usize) -> [f32; 3] {
    let h = hash & 15;
    // u = h<8 ? x : y;  v = h<4 ? y : h==12||h==14 ? x : z;  +-u +-v by bits 0 and 1.
    let axis_u = if h < 8 { 0 } else { 1 };
    let axis_v = if h < 4 {
        1
    } else if h == 12 || h == 14 {
        0
    } else {
        2
    };
    let mut g = [0.0; 3];
    g[axis_u] += if h & 1 == 0 { 1.0 } else { -1.0 };
    g[axis_v] += if h & 2 == 0 { 1.0 } else { -1.0 };
    g
}

/// The 2D counterpart: the four diagonals and the four axis directions, by the low three bits.
pub(super) fn improved_gradient2(hash: usize) -> [f32; 2] {
    const G: [[f32; 2]; 8] =
        [[1.0, 1.0], [-1.0, 1.0], [1.0, -1.0], [-1.0, -1.0], [1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]];
    G[hash & 7]
}

/// `count` points uniform in [0, extent)^3 as three coordinate arrays (deterministic for a seed): the
/// workload of the noise benchmark.
pub fn uniform_points(count: usize, extent: f32, seed: u64) -> [Vec<f32>; 3] {
    let mut rng = SplitMix64(seed);
    let mut axis = || -> Vec<f32> { (0..count).map(|_| (rng.signed() * 0.5 + 0.5) * extent).collect() };
    [axis(), axis(), axis()]
}

/// A small, well-mixed generator for shuffling tables and drawing gradients (Steele et al. 2014).
struct SplitMix64(u64);

impl SplitMix64 {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [-1, 1).
    fn signed(&mut self) -> f32 {
        ((self.next() >> 40) as f32 / (1u64 << 24) as f32) * 2.0 - 1.0
    }

    /// A uniformly distributed unit vector (rejection from the cube, as Perlin's Monte Carlo step).
    fn unit3(&mut self) -> [f32; 3] {
        loop {
            let v = [self.signed(), self.signed(), self.signed()];
            let l2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
            if l2 > 1e-4 && l2 <= 1.0 {
                let k = 1.0 / l2.sqrt();
                return v.map(|c| c * k);
            }
        }
    }

    fn unit2(&mut self) -> [f32; 2] {
        loop {
            let v = [self.signed(), self.signed()];
            let l2 = v[0] * v[0] + v[1] * v[1];
            if l2 > 1e-4 && l2 <= 1.0 {
                let k = 1.0 / l2.sqrt();
                return v.map(|c| c * k);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn all_noises() -> Vec<Perlin> {
        let mut v = Vec::new();
        for variant in [Variant::Improved, Variant::Classic, Variant::Hashed] {
            for seed in [0, 7] {
                v.push(Perlin::new(variant, seed));
                v.push(Perlin::new(variant, seed).with_period([3, 5, 4]));
            }
        }
        v
    }

    /// Deterministic points spread over [-20, 20)^3.
    fn points(n: usize) -> Vec<[f32; 3]> {
        let mut rng = SplitMix64(99);
        (0..n).map(|_| [rng.signed() * 20.0, rng.signed() * 20.0, rng.signed() * 20.0]).collect()
    }

    #[test]
    fn reference_permutation_is_a_permutation() {
        let mut seen = [false; 256];
        for &p in &REFERENCE_PERMUTATION {
            assert!(!seen[p as usize]);
            seen[p as usize] = true;
        }
    }

    #[test]
    #[allow(clippy::approx_constant)] // 3.14 is the published argument, not pi
    fn published_values_of_the_reference_implementation() {
        let n = Perlin::new(Variant::Improved, 0);
        assert_eq!(n.noise3_f64(3.14, 42.0, 7.0), 0.13691995878400012);
        assert_eq!(n.noise3_f64(-4.2, 10.0, 6.0), 0.14208000000000043);
        assert_eq!(fade_f64(0.75), 0.896484375);
    }

    #[test]
    fn f32_path_agrees_with_the_f64_path() {
        for n in all_noises() {
            let mut worst = 0.0f64;
            for p in points(20_000) {
                // Compare at the f32 point itself, so only the arithmetic differs.
                let reference = n.noise3_f64(p[0] as f64, p[1] as f64, p[2] as f64);
                worst = worst.max((n.noise3(p[0], p[1], p[2]) as f64 - reference).abs());
            }
            assert!(worst < 1e-6, "{:?} period {:?}: worst {worst}", n.variant(), n.period());
        }
    }

    #[test]
    fn lanes_equal_single_points() {
        for n in all_noises() {
            lanes_equal_single_points_of(&n);
        }
    }

    fn lanes_equal_single_points_of(n: &Perlin) {
        let pts = points(37);
        let (x, y, z): (Vec<f32>, Vec<f32>, Vec<f32>) = (
            pts.iter().map(|p| p[0]).collect(),
            pts.iter().map(|p| p[1]).collect(),
            pts.iter().map(|p| p[2]).collect(),
        );
        let mut out = vec![0.0; pts.len()];
        n.noise3_many(&x, &y, &z, &mut out);
        for (p, o) in pts.iter().zip(&out) {
            assert_eq!(*o, n.noise3(p[0], p[1], p[2]));
        }
        let l2 = n.noise2_lanes(&x[..8].try_into().unwrap(), &y[..8].try_into().unwrap());
        for l in 0..8 {
            assert_eq!(l2[l], n.noise2(x[l], y[l]));
        }
    }

    /// The range and mean |noise| over 10^7 points uniform in [0, 256)^3 (one whole period), as documented
    /// in docs/procedural.md: improved 3D [-0.9881, 1.0114] (Perlin's function itself slightly exceeds 1),
    /// improved 2D [-0.9998, 0.9998], classic 3D [-0.709, 0.676], classic 2D [-0.692, 0.693], hashed 3D
    /// [-0.9883, 0.9979], hashed 2D [-0.9995, 0.9996]. The hashed means are those of gradients drawn
    /// independently and uniformly at every corner (0.2203 in 3D, 0.2134 in 2D, a Monte Carlo of 4 * 10^6
    /// cells in NumPy); the permutation table's 2D hash is slightly biased away from that (0.2166).
    #[test]
    fn measured_range_and_mean_magnitude() {
        let check = |variant, dims: usize, count: usize, lo: f32, hi: f32, mean_abs: f64| {
            let n = Perlin::new(variant, 0);
            let [x, y, z] = uniform_points(count, 256.0, 11);
            let mut out = vec![0.0; count];
            if dims == 3 {
                n.noise3_many(&x, &y, &z, &mut out);
            } else {
                for (i, o) in out.chunks_exact_mut(LANES).enumerate() {
                    let r = i * LANES..(i + 1) * LANES;
                    o.copy_from_slice(&n.noise2_lanes(&x[r.clone()].try_into().unwrap(), &y[r].try_into().unwrap()));
                }
            }
            let (mn, mx) = out.iter().fold((f32::MAX, f32::MIN), |(a, b), &v| (a.min(v), b.max(v)));
            let mean = out.iter().map(|v| v.abs() as f64).sum::<f64>() / count as f64;
            // The extremes of 10^7 samples lie within 0.01 of the documented ones; the means within 0.5%.
            assert!((mn - lo).abs() < 0.01 && (mx - hi).abs() < 0.01, "{variant:?} {dims}D: [{mn}, {mx}]");
            assert!((mean / mean_abs - 1.0).abs() < 5e-3, "{variant:?} {dims}D: mean |n| {mean}");
        };
        check(Variant::Improved, 3, 10_000_000, -0.9881, 1.0114, 0.2204);
        check(Variant::Improved, 2, 10_000_000, -0.9998, 0.9998, 0.2166);
        check(Variant::Classic, 3, 10_000_000, -0.709, 0.676, 0.1471);
        check(Variant::Classic, 2, 10_000_000, -0.692, 0.693, 0.1724);
        check(Variant::Hashed, 3, 10_000_000, -0.9883, 0.9979, 0.2203);
        check(Variant::Hashed, 2, 10_000_000, -0.9995, 0.9996, 0.2134);
    }

    #[test]
    fn zero_at_every_lattice_point() {
        for n in all_noises() {
            for i in -9..9 {
                for j in -9..9 {
                    assert_eq!(n.noise2(i as f32, j as f32), 0.0);
                    for k in [-300, -1, 0, 2, 255, 256, 1000] {
                        assert_eq!(n.noise3(i as f32, j as f32, k as f32), 0.0);
                    }
                }
            }
        }
    }

    #[test]
    fn continuous_across_cell_borders() {
        // Approaching a cell face from both sides gives the same value: the eight corner ramps agree there.
        for n in all_noises() {
            for p in points(2000) {
                let face = p[0].floor();
                let (below, above) = (face - 1e-4, face + 1e-4);
                let jump = (n.noise3(below, p[1], p[2]) - n.noise3(above, p[1], p[2])).abs();
                // |gradient| is at most a few units, so a step of 2e-4 changes the value by < 1e-3.
                assert!(jump < 1e-3, "jump {jump} at x = {face}");
                let jump2 = (n.noise2(p[1], face - 1e-4) - n.noise2(p[1], face + 1e-4)).abs();
                assert!(jump2 < 1e-3);
            }
        }
    }

    #[test]
    fn analytic_gradient_matches_central_differences() {
        for n in all_noises() {
            let f64_noise = |x: f64, y: f64, z: f64| n.noise3_f64(x, y, z);
            for p in points(3000) {
                let d = n.noise3_d(p[0], p[1], p[2]);
                assert_eq!(d.value, n.noise3(p[0], p[1], p[2]));
                // Central differences of the f64 noise with h = 1e-5: truncation error ~ h^2 |f'''| ~ 1e-8.
                let h = 1e-5;
                let (x, y, z) = (p[0] as f64, p[1] as f64, p[2] as f64);
                let c = [
                    (f64_noise(x + h, y, z) - f64_noise(x - h, y, z)) / (2.0 * h),
                    (f64_noise(x, y + h, z) - f64_noise(x, y - h, z)) / (2.0 * h),
                    (f64_noise(x, y, z + h) - f64_noise(x, y, z - h)) / (2.0 * h),
                ];
                for (a, (g, c)) in d.grad.iter().zip(c).enumerate() {
                    assert!((*g as f64 - c).abs() < 1e-4, "{:?} axis {a}: {} vs {}", n.variant(), g, c);
                }
            }
        }
    }

    #[test]
    fn analytic_gradient_2d_matches_central_differences() {
        for n in all_noises() {
            for p in points(3000) {
                let (x, y) = (p[0], p[1]);
                let d = n.noise2_d(x, y);
                assert_eq!(d.value, n.noise2(x, y));
                let (xd, yd, h) = (x as f64, y as f64, 1e-5);
                let c = [
                    (n.noise2_f64(xd + h, yd) - n.noise2_f64(xd - h, yd)) / (2.0 * h),
                    (n.noise2_f64(xd, yd + h) - n.noise2_f64(xd, yd - h)) / (2.0 * h),
                ];
                assert!((d.value as f64 - n.noise2_f64(xd, yd)).abs() < 1e-6);
                for (axis, (g, c)) in d.grad.iter().zip(c).enumerate() {
                    assert!((*g as f64 - c).abs() < 1e-4, "axis {axis}: {} vs {}", g, c);
                }
                assert_eq!(d.grad[2], 0.0);
            }
        }
    }

    #[test]
    fn periodic_noise_repeats_exactly() {
        let n = Perlin::new(Variant::Improved, 5).with_period([3, 5, 4]);
        for p in points(500) {
            let v = n.noise3(p[0], p[1], p[2]);
            assert!((n.noise3(p[0] + 3.0, p[1], p[2]) - v).abs() < 1e-5);
            assert!((n.noise3(p[0], p[1] - 5.0, p[2]) - v).abs() < 1e-5);
            assert!((n.noise3(p[0], p[1], p[2] + 8.0) - v).abs() < 1e-5);
            assert!((n.noise2(p[0] + 6.0, p[1] + 5.0) - n.noise2(p[0], p[1])).abs() < 1e-5);
        }
        // And an unwrapped noise does not repeat at those periods.
        let free = Perlin::new(Variant::Improved, 5);
        let moved: f32 = points(100)
            .iter()
            .map(|p| (free.noise3(p[0] + 3.0, p[1], p[2]) - free.noise3(p[0], p[1], p[2])).abs())
            .sum();
        assert!(moved > 1.0);
    }

    #[test]
    fn seeds_give_different_noises() {
        let (a, b) = (Perlin::new(Variant::Improved, 0), Perlin::new(Variant::Improved, 1));
        let differ = points(200)
            .iter()
            .filter(|p| (a.noise3(p[0], p[1], p[2]) - b.noise3(p[0], p[1], p[2])).abs() > 1e-3)
            .count();
        assert!(differ > 150);
    }
}
