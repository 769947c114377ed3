//! From a normal map back to heights: Frankot and Chellappa's projection of the gradient field onto the
//! nearest integrable one (IEEE PAMI 10(4), 1988), solved in the Fourier domain:
//!
//!     H(wx, wy) = (-i wx P - i wy Q) / (wx^2 + wy^2),   H(0, 0) = 0,
//!
//! with P and Q the transforms of p = dh/dx and q = dh/dy. The transform treats the image as periodic:
//! right for tileable maps (`wrap`); otherwise the gradients are first mirrored into a 2W x 2H field (p odd
//! across vertical mirrors, q across horizontal ones), which makes the mirrored height periodic and removes
//! the seams a plain transform would invent at the borders. Both p and q ride in one complex transform
//! (z = p + i q), split by symmetry.

use rayon::prelude::*;
use rustfft::num_complex::Complex32;
use rustfft::FftPlanner;

/// Bytes of working memory per pixel of the transformed field (one complex f32 and a transposed copy).
pub const BYTES_PER_FIELD_PIXEL: usize = 16;

/// The size of the field transformed for a `width` x `height` image.
pub fn field_size(width: usize, height: usize, wrap: bool) -> (usize, usize) {
    if wrap {
        (width, height)
    } else {
        (2 * width, 2 * height)
    }
}

/// Normals closer to the picture's plane than this z are treated as this steep (the slope stays finite).
const MIN_NZ: f32 = 1e-3;

/// Checks the `strength` a normal map was made with (the height of white above black in pixels).
pub fn check_strength(strength: f32) -> crate::Result<()> {
    match strength.is_finite() && strength > 0.0 {
        true => Ok(()),
        false => Err(crate::Error::parameter("strength", format!("must be a positive number, got {strength}"))),
    }
}

/// The height gradient (p = dh/dx, q = dh/dy with y down the rows) of heights in [0, 1] under the unit
/// normal `n` (OpenGL convention: y up the picture) of a map made with `strength` (the height of white above
/// black in pixels).
#[inline]
pub fn gradient_of_normal(n: [f32; 3], strength: f32) -> (f32, f32) {
    let nz = n[2].max(MIN_NZ) * strength;
    // n_y points up the picture: dh/d(up) = -ny/nz, so dh/d(down) = ny/nz.
    (-n[0] / nz, n[1] / nz)
}

/// Shifts integrated heights so the lowest is 0, and with `normalize` stretches them so the highest is 1.
/// Returns the span (highest - lowest) before stretching.
pub fn settle_heights(heights: &mut [f32], normalize: bool) -> f32 {
    let lo = heights.iter().copied().fold(f32::INFINITY, f32::min);
    let hi = heights.iter().copied().fold(f32::NEG_INFINITY, f32::max);
    let scale = if normalize && hi > lo { 1.0 / (hi - lo) } else { 1.0 };
    for v in heights.iter_mut() {
        *v = (*v - lo) * scale;
    }
    hi - lo
}

/// Heights (up to a constant; mean zero over the field) whose gradient is nearest to (p, q) in the least
/// squares sense. `p` is dh/dx with x to the right, `q` is dh/dy with y down the rows, both per pixel,
/// row 0 at the top, `width * height` values each.
///
/// # Panics
/// Where `p` or `q` does not hold `width * height` values (the message says which and how many).
pub fn frankot_chellappa(p: &[f32], q: &[f32], width: usize, height: usize, wrap: bool) -> Vec<f32> {
    let n = width.checked_mul(height);
    for (name, slope) in [("p", p), ("q", q)] {
        assert!(
            n == Some(slope.len()),
            "frankot_chellappa: {name} holds {} values, not width * height = {width} x {height}",
            slope.len()
        );
    }
    if width == 0 || height == 0 {
        return Vec::new();
    }
    let (fw, fh) = field_size(width, height, wrap);
    // z = p + i q over the (mirrored) field.
    let mut field = vec![Complex32::new(0.0, 0.0); fw * fh];
    field.par_chunks_mut(fw).enumerate().for_each(|(y, row)| {
        let (sy, flip_y) = if y < height { (y, 1.0) } else { (2 * height - 1 - y, -1.0) };
        for (x, z) in row.iter_mut().enumerate() {
            let (sx, flip_x) = if x < width { (x, 1.0) } else { (2 * width - 1 - x, -1.0) };
            let k = sy * width + sx;
            *z = Complex32::new(flip_x * p[k], flip_y * q[k]);
        }
    });
    fft_2d(&mut field, fw, fh, false);
    let mut heights = vec![Complex32::new(0.0, 0.0); fw * fh];
    let omega = |k: usize, n: usize| {
        let k = if 2 * k > n { k as f32 - n as f32 } else { k as f32 };
        std::f32::consts::TAU * k / n as f32
    };
    heights.par_chunks_mut(fw).enumerate().for_each(|(ky, row)| {
        let wy = omega(ky, fh);
        let ky_neg = (fh - ky) % fh;
        for (kx, out) in row.iter_mut().enumerate() {
            let wx = omega(kx, fw);
            let denom = wx * wx + wy * wy;
            if denom == 0.0 {
                continue;
            }
            let z = field[ky * fw + kx];
            let zc = field[ky_neg * fw + (fw - kx) % fw].conj();
            let pk = (z + zc) * 0.5;
            let qk = (z - zc) * Complex32::new(0.0, -0.5);
            *out = (pk * Complex32::new(0.0, -wx) + qk * Complex32::new(0.0, -wy)) / denom;
        }
    });
    drop(field);
    fft_2d(&mut heights, fw, fh, true);
    let norm = 1.0 / (fw * fh) as f32;
    let mut out = Vec::with_capacity(width * height);
    for row in heights.chunks_exact(fw).take(height) {
        out.extend(row[..width].iter().map(|z| z.re * norm));
    }
    out
}

/// A 2D FFT in place: rows, transpose, rows, transpose back (unnormalised).
fn fft_2d(data: &mut Vec<Complex32>, w: usize, h: usize, inverse: bool) {
    let mut planner = FftPlanner::<f32>::new();
    for (len, stride_rows) in [(w, h), (h, w)] {
        let fft = if inverse { planner.plan_fft_inverse(len) } else { planner.plan_fft_forward(len) };
        data.par_chunks_mut(len).with_min_len(4).for_each_init(
            || vec![Complex32::new(0.0, 0.0); fft.get_inplace_scratch_len()],
            |scratch, row| fft.process_with_scratch(row, scratch),
        );
        *data = transpose(data, len, stride_rows);
    }
}

/// The transpose of a `w` x `h` row-major matrix, in blocks for the cache.
fn transpose(src: &[Complex32], w: usize, h: usize) -> Vec<Complex32> {
    const B: usize = 32;
    let mut dst = vec![Complex32::new(0.0, 0.0); w * h];
    dst.par_chunks_mut(h * B).enumerate().for_each(|(bx, block)| {
        let x0 = bx * B;
        let xs = B.min(w - x0);
        for y0 in (0..h).step_by(B) {
            for y in y0..(y0 + B).min(h) {
                for dx in 0..xs {
                    block[dx * h + y] = src[y * w + x0 + dx];
                }
            }
        }
    });
    dst
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rms_after_mean(a: &[f32], b: &[f32]) -> f32 {
        let n = a.len() as f32;
        let mean = a.iter().zip(b).map(|(x, y)| x - y).sum::<f32>() / n;
        (a.iter().zip(b).map(|(x, y)| (x - y - mean).powi(2)).sum::<f32>() / n).sqrt()
    }

    #[test]
    fn periodic_sine_comes_back() {
        // h = sin(2 pi x / W) cos(2 pi 2 y / H): its exact gradients integrate back exactly.
        let (w, h) = (64usize, 32usize);
        let tau = std::f32::consts::TAU;
        let height = |x: f32, y: f32| (tau * x / w as f32).sin() * (tau * 2.0 * y / h as f32).cos();
        let mut p = vec![0.0; w * h];
        let mut q = vec![0.0; w * h];
        let mut want = vec![0.0; w * h];
        for y in 0..h {
            for x in 0..w {
                let (xf, yf) = (x as f32, y as f32);
                want[y * w + x] = height(xf, yf);
                p[y * w + x] = tau / w as f32 * (tau * xf / w as f32).cos() * (tau * 2.0 * yf / h as f32).cos();
                q[y * w + x] = -tau * 2.0 / h as f32 * (tau * xf / w as f32).sin() * (tau * 2.0 * yf / h as f32).sin();
            }
        }
        let got = frankot_chellappa(&p, &q, w, h, true);
        assert!(rms_after_mean(&got, &want) < 1e-4, "{}", rms_after_mean(&got, &want));
    }

    /// Slopes of another size than the field's are refused with a message naming them, not read past.
    #[test]
    #[should_panic(expected = "q holds 11 values, not width * height = 4 x 3")]
    fn slopes_of_the_wrong_size_are_named() {
        frankot_chellappa(&[0.0; 12], &[0.0; 11], 4, 3, false);
    }

    #[test]
    fn transpose_is_exact_for_odd_sizes() {
        let (w, h) = (37, 70);
        let src: Vec<Complex32> = (0..w * h).map(|i| Complex32::new(i as f32, -(i as f32))).collect();
        let t = transpose(&src, w, h);
        for y in 0..h {
            for x in 0..w {
                assert_eq!(t[x * h + y], src[y * w + x]);
            }
        }
    }
}
