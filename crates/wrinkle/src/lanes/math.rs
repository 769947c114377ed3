//! Lane arithmetic that gives the same bits on every x86-64 CPU: fused multiply-add and the few
//! transcendental functions the shading packets need (log2, exp2, pow, atan2, asin).
//!
//! Why not `wide`'s own: its `mul_add` fuses only where the build enables FMA and otherwise rounds twice,
//! and its `ln`, `pow_f32x8`, `atan2`, `asin` are polynomials over that `mul_add`; so the x86-64-v3 build
//! and the portable one (for CPUs without AVX2) would differ in the last bits of most pixels. Here every
//! multiply-add is fused on every build (FMA instructions on x86-64-v3, the C library's exact `fmaf` per
//! lane elsewhere), and the rest is plain IEEE arithmetic, exact the same everywhere.

use super::{bits, F8, I8};
use super::{CmpEq, CmpGt, CmpLt};
use std::f32::consts::{FRAC_PI_2, FRAC_PI_4, LN_2, LOG2_E, PI, SQRT_2};

/// `a * b + c` with one rounding, on every lane and every CPU.
#[inline]
pub fn mul_add(a: F8, b: F8, c: F8) -> F8 {
    #[cfg(target_feature = "fma")]
    {
        a.mul_add(b, c)
    }
    #[cfg(not(target_feature = "fma"))]
    {
        let (a, b, c) = (a.to_array(), b.to_array(), c.to_array());
        F8::new(std::array::from_fn(|l| a[l].mul_add(b[l], c[l])))
    }
}

/// `c[0] + x (c[1] + x (c[2] + ...))`: Horner's rule, fused at each step.
#[inline]
fn horner<const N: usize>(x: F8, c: [f32; N]) -> F8 {
    let mut p = F8::splat(c[N - 1]);
    for &k in c[..N - 1].iter().rev() {
        p = mul_add(p, x, F8::splat(k));
    }
    p
}

/// The lanes' bits as integers (each lane's 32 bits kept as they are; `bits` is the way back), so a mask
/// is -1 where set.
#[inline]
pub fn to_bits(v: F8) -> I8 {
    // SAFETY: both are eight 32-bit lanes, and every bit pattern is valid in both.
    unsafe { std::mem::transmute::<F8, I8>(v) }
}

/// The sign bit of each lane of `from` put on the (non-negative) lanes of `magnitude`.
#[inline]
fn with_sign_of(magnitude: F8, from: F8) -> F8 {
    bits(to_bits(magnitude) | (to_bits(from) & I8::splat(i32::MIN)))
}

/// log2(x) per lane: -inf at 0, NaN below 0 or at NaN, +inf at +inf. Within 2 units in the last place of
/// the result away from x = 1, and of the order of 1e-7 absolute near it.
#[inline]
pub fn log2(x: F8) -> F8 {
    // Subnormals first scaled into the normal range (by 2^23, taken off the exponent below).
    let tiny = x.cmp_lt(F8::splat(f32::MIN_POSITIVE));
    let scaled = tiny.blend(x * F8::splat(8_388_608.0), x);
    let word = to_bits(scaled);
    // x = m 2^e with m in [1, 2), then m in [sqrt(1/2), sqrt(2)) so that ln m is small on both sides.
    let mut e: I8 = ((word >> 23) & I8::splat(0xFF)) - I8::splat(127);
    e -= to_bits(tiny) & I8::splat(23);
    let mut m = bits((word & I8::splat(0x007F_FFFF)) | I8::splat(0x3F80_0000));
    let high = m.cmp_gt(F8::splat(SQRT_2));
    m = high.blend(m * F8::splat(0.5), m);
    e -= to_bits(high);
    // ln m = 2 atanh(t), t = (m - 1) / (m + 1), |t| <= 0.172: the odd series to t^9 is exact to f32.
    let t = (m - F8::ONE) / (m + F8::ONE);
    let t2 = t * t;
    let ln_m = t * horner(t2, [2.0, 2.0 / 3.0, 2.0 / 5.0, 2.0 / 7.0, 2.0 / 9.0]);
    let result = mul_add(ln_m, F8::splat(LOG2_E), e.round_float());
    // The special values: 0 gives -inf, negative and NaN give NaN, +inf stays.
    let result = x.cmp_eq(F8::ZERO).blend(F8::splat(f32::NEG_INFINITY), result);
    let result = x.cmp_eq(F8::splat(f32::INFINITY)).blend(x, result);
    (x.cmp_lt(F8::ZERO) | x.is_nan()).blend(F8::splat(f32::NAN), result)
}

/// 2^x per lane: 0 far below, +inf from 128 up, NaN at NaN. Within 2 units in the last place.
#[inline]
pub fn exp2(x: F8) -> F8 {
    let clamped = x.max(F8::splat(-160.0)).min(F8::splat(129.0));
    let n = clamped.round();
    // 2^f = e^(f ln 2), |f ln 2| <= 0.347: the Taylor series to the 7th power is exact to f32.
    let z = (clamped - n) * F8::splat(LN_2);
    let p = horner(z, [1.0, 1.0, 1.0 / 2.0, 1.0 / 6.0, 1.0 / 24.0, 1.0 / 120.0, 1.0 / 720.0, 1.0 / 5040.0]);
    // 2^n in two factors, each a normal float, so that n from -160 to 129 underflows and overflows as 2^x.
    let n = n.round_int();
    let half = n >> 1;
    let power = |k: I8| bits((k + I8::splat(127)) << 23);
    let result = p * power(half) * power(n - half);
    x.is_nan().blend(x, result)
}

/// x^y per lane for x >= 0 (Phong's cosine power): 1 where y = 0, 0 where x = 0 < y.
#[inline]
pub fn pow(x: F8, y: F8) -> F8 {
    let result = exp2(y * log2(x));
    y.cmp_eq(F8::ZERO).blend(F8::ONE, result)
}

/// atan(a) for 0 <= a <= 1 (Cephes' reduction and polynomial for |t| <= tan(pi/8)).
#[inline]
fn atan_unit(a: F8) -> F8 {
    let far = a.cmp_gt(F8::splat(0.414_213_57));
    let t = far.blend((a - F8::ONE) / (a + F8::ONE), a);
    let z = t * t;
    let p = horner(z, [-0.333_329_5, 0.199_777_11, -0.138_776_85, 0.080_537_446]);
    far.blend(F8::splat(FRAC_PI_4), F8::ZERO) + mul_add(t * z, p, t)
}

/// atan2(y, x) per lane, in [-pi, pi], with the signs of zeros as IEEE's atan2. Within 3 units in the
/// last place.
#[inline]
pub fn atan2(y: F8, x: F8) -> F8 {
    let (ax, ay) = (x.abs(), y.abs());
    let (small, large) = (ax.min(ay), ax.max(ay));
    let ratio = small / large;
    // 0/0 (both zero) gives angle 0 before the quadrant; inf/inf gives the diagonal.
    let ratio = large.cmp_eq(F8::ZERO).blend(F8::ZERO, ratio);
    let ratio = (ax.cmp_eq(F8::splat(f32::INFINITY)) & ay.cmp_eq(F8::splat(f32::INFINITY))).blend(F8::ONE, ratio);
    let mut r = atan_unit(ratio);
    r = ay.cmp_gt(ax).blend(F8::splat(FRAC_PI_2) - r, r);
    let x_negative = bits(to_bits(x).cmp_lt(I8::splat(0)));
    r = x_negative.blend(F8::splat(PI) - r, r);
    let r = with_sign_of(r, y);
    (x.is_nan() | y.is_nan()).blend(F8::splat(f32::NAN), r)
}

/// asin(x) per lane for -1 <= x <= 1 (NaN outside), after Cephes: a polynomial on |x| <= 1/2, and
/// asin x = pi/2 - 2 asin(sqrt((1 - x) / 2)) above. Within 3 units in the last place.
#[inline]
pub fn asin(x: F8) -> F8 {
    let a = x.abs();
    let high = a.cmp_gt(F8::splat(0.5));
    let z = high.blend(F8::splat(0.5) * (F8::ONE - a), a * a);
    let s = high.blend(z.sqrt(), a);
    let p = horner(z, [0.166_667_52, 0.074_953_005, 0.045_470_025, 0.024_181_31, 0.042_163_2]);
    let near = mul_add(s * z, p, s);
    let r = high.blend(F8::splat(FRAC_PI_2) - (near + near), near);
    let r = a.cmp_gt(F8::ONE).blend(F8::splat(f32::NAN), r);
    with_sign_of(r, x)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Units in the last place between an f32 result and the exact (f64) value.
    fn ulps(got: f32, want: f64) -> f64 {
        let w = want as f32;
        if got == w {
            return 0.0;
        }
        let spacing = (f32::from_bits(w.abs().to_bits() + 1) - w.abs()) as f64;
        (got as f64 - want).abs() / spacing
    }

    /// Runs `f` over `inputs` eight at a time.
    fn lanes(inputs: &[f32], f: impl Fn(F8) -> F8) -> Vec<f32> {
        inputs
            .chunks(8)
            .flat_map(|c| {
                let mut a = [1.0f32; 8];
                a[..c.len()].copy_from_slice(c);
                f(F8::new(a)).to_array()[..c.len()].to_vec()
            })
            .collect()
    }

    fn spread(from: f32, to: f32, n: usize) -> Vec<f32> {
        (0..n).map(|k| from + (to - from) * k as f32 / (n - 1) as f32).collect()
    }

    #[test]
    fn fused_multiply_add_rounds_once() {
        // 1 + 2^-23 squared is 1 + 2^-22 + 2^-46: fused, the 2^-46 survives the subtraction of 1 + 2^-22.
        let a = F8::splat(1.0 + f32::EPSILON);
        let got = mul_add(a, a, F8::splat(-(1.0 + 2.0 * f32::EPSILON))).to_array()[0];
        assert_eq!(got, 2f32.powi(-46));
    }

    #[test]
    fn log2_is_within_two_ulps() {
        let mut xs = spread(1e-3, 40.0, 20_000);
        xs.extend([f32::MIN_POSITIVE, 1e-40, 3.0e-39, 1e30, f32::MAX, 0.5, 2.0, 1024.0]);
        for (x, got) in xs.iter().zip(lanes(&xs, log2)) {
            let want = (*x as f64).log2();
            let err = if want.abs() < 0.5 { (got as f64 - want).abs() / 1.2e-7 } else { ulps(got, want) };
            assert!(err <= 2.0, "log2({x}) = {got}, want {want}: {err} ulps");
        }
        let special = lanes(&[0.0, -1.0, f32::NAN, f32::INFINITY, 1.0], log2);
        assert_eq!(special[0], f32::NEG_INFINITY);
        assert!(special[1].is_nan() && special[2].is_nan());
        assert_eq!((special[3], special[4]), (f32::INFINITY, 0.0));
    }

    #[test]
    fn exp2_is_within_two_ulps() {
        let xs = spread(-125.0, 127.5, 20_000);
        for (x, got) in xs.iter().zip(lanes(&xs, exp2)) {
            let want = (*x as f64).exp2();
            assert!(ulps(got, want) <= 2.0, "exp2({x}) = {got}, want {want}");
        }
        let special = lanes(&[-200.0, 200.0, f32::NAN, 0.0, -140.0], exp2);
        assert_eq!((special[0], special[1], special[3]), (0.0, f32::INFINITY, 1.0));
        assert!(special[2].is_nan());
        assert!((special[4] as f64 - 2f64.powi(-140)).abs() <= 2f64.powi(-149));
    }

    #[test]
    fn pow_matches_phong_powers() {
        let xs = spread(0.01, 1.0, 5000);
        for shininess in [0.0f32, 1.0, 8.0, 60.5, 200.0] {
            let got = lanes(&xs, |x| pow(x, F8::splat(shininess)));
            for (x, g) in xs.iter().zip(got) {
                let want = (*x as f64).powf(shininess as f64);
                // The error of log2 carried by the exponent: a few ulps of y log2 x.
                let tolerance = 4e-7 * (1.0 + (shininess as f64 * (*x as f64).log2()).abs()) * want + 1e-38;
                assert!((g as f64 - want).abs() <= tolerance, "{x}^{shininess} = {g}, want {want}");
            }
        }
        assert_eq!(lanes(&[0.0], |x| pow(x, F8::splat(3.0)))[0], 0.0);
    }

    #[test]
    fn atan2_is_within_three_ulps_in_every_quadrant() {
        let angles = spread(-0.999_99 * PI, 0.999_99 * PI, 10_001);
        for radius in [1e-3f32, 1.0, 7e4] {
            let y: Vec<f32> = angles.iter().map(|a| radius * a.sin()).collect();
            let x: Vec<f32> = angles.iter().map(|a| radius * a.cos()).collect();
            for k in (0..y.len()).step_by(8) {
                let end = (k + 8).min(y.len());
                let (mut ya, mut xa) = ([1.0f32; 8], [1.0f32; 8]);
                ya[..end - k].copy_from_slice(&y[k..end]);
                xa[..end - k].copy_from_slice(&x[k..end]);
                let got = atan2(F8::new(ya), F8::new(xa)).to_array();
                for l in 0..end - k {
                    let want = (ya[l] as f64).atan2(xa[l] as f64);
                    assert!(ulps(got[l], want) <= 3.0, "atan2({}, {}) = {}, want {want}", ya[l], xa[l], got[l]);
                }
            }
        }
        let y = F8::new([0.0, -0.0, 0.0, -0.0, 1.0, -1.0, f32::INFINITY, f32::NAN]);
        let x = F8::new([1.0, 1.0, -1.0, -1.0, 0.0, -0.0, f32::INFINITY, 1.0]);
        let got = atan2(y, x).to_array();
        let want: Vec<f32> = y.to_array().iter().zip(x.to_array()).map(|(y, x)| y.atan2(x)).collect();
        for l in 0..7 {
            assert_eq!(got[l].to_bits(), want[l].to_bits(), "atan2 lane {l}: {} vs {}", got[l], want[l]);
        }
        assert!(got[7].is_nan());
    }

    #[test]
    fn asin_is_within_three_ulps() {
        let xs = spread(-1.0, 1.0, 20_001);
        for (x, got) in xs.iter().zip(lanes(&xs, asin)) {
            let want = (*x as f64).asin();
            let err = if want.abs() < 1e-30 { (got as f64 - want).abs() } else { ulps(got, want) };
            assert!(err <= 3.0, "asin({x}) = {got}, want {want}");
        }
        let special = lanes(&[1.5, -0.0, f32::NAN], asin);
        assert!(special[0].is_nan() && special[2].is_nan());
        assert_eq!(special[1].to_bits(), (-0.0f32).to_bits());
    }
}
