//! Reconstruction filters for magnification: the texture between texel centres, read from one level.
//! Nearest, bilinear, bicubic (Catmull-Rom and cubic B-spline), Gaussian and Lanczos-3, all separable.
//! Texel (i, j) has its centre at ((i + 0.5) / W, (j + 0.5) / H).

use super::texel::{Texel, TexelSource};
use super::wrap::Wrap;

/// How texel indices outside the texture are read: a wrap mode per axis and the border colour.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Addressing<T> {
    pub wrap: [Wrap; 2],
    pub border: T,
}

impl<T: Texel> Addressing<T> {
    pub fn repeat() -> Self {
        Addressing { wrap: [Wrap::Repeat; 2], border: T::default() }
    }

    /// The texel at integer index (i, j), wherever it lies.
    #[inline]
    pub fn fetch<S: TexelSource<Texel = T>>(&self, src: &S, i: isize, j: isize) -> T {
        match (self.wrap[0].resolve(i, src.width()), self.wrap[1].resolve(j, src.height())) {
            (Some(i), Some(j)) => src.texel(i, j),
            _ => self.border,
        }
    }
}

/// A separable reconstruction kernel, by its radius in texels and its profile.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kernel {
    /// The nearest texel (a box one texel wide).
    Nearest,
    /// The tent: bilinear interpolation.
    Bilinear,
    /// Catmull-Rom cubic (B = 0, C = 1/2): interpolates the texels, slight overshoot at edges.
    CatmullRom,
    /// Uniform cubic B-spline (B = 1, C = 0): smooth, does not pass through the texels.
    BSpline,
    /// Gaussian with a standard deviation of half a texel, truncated at two texels and normalised.
    Gaussian,
    /// Lanczos-3: sinc windowed by a sinc three times wider, normalised.
    Lanczos3,
}

/// The Gaussian's standard deviation in texels: half a texel blurs as little as a Gaussian can while
/// still suppressing the texel grid.
const GAUSSIAN_SIGMA: f32 = 0.5;

impl Kernel {
    /// The kernel's weight at distance `x` texels from the sample point.
    #[inline]
    pub fn weight(self, x: f32) -> f32 {
        let x = x.abs();
        match self {
            Kernel::Nearest => (x < 0.5) as u8 as f32,
            Kernel::Bilinear => (1.0 - x).max(0.0),
            Kernel::CatmullRom => mitchell_netravali(x, 0.0, 0.5),
            Kernel::BSpline => mitchell_netravali(x, 1.0, 0.0),
            Kernel::Gaussian => {
                if x < 2.0 {
                    (-0.5 * x * x / (GAUSSIAN_SIGMA * GAUSSIAN_SIGMA)).exp()
                } else {
                    0.0
                }
            }
            Kernel::Lanczos3 => {
                if x < 3.0 {
                    sinc(x) * sinc(x / 3.0)
                } else {
                    0.0
                }
            }
        }
    }

    /// Taps per axis: twice the radius.
    pub fn taps(self) -> usize {
        match self {
            Kernel::Nearest => 1,
            Kernel::Bilinear => 2,
            Kernel::CatmullRom | Kernel::BSpline | Kernel::Gaussian => 4,
            Kernel::Lanczos3 => 6,
        }
    }
}

/// sin(pi x) / (pi x).
#[inline]
pub fn sinc(x: f32) -> f32 {
    if x.abs() < 1e-5 {
        1.0
    } else {
        let px = std::f32::consts::PI * x;
        px.sin() / px
    }
}

/// The Mitchell-Netravali family of cubics (Mitchell and Netravali 1988) at |x|.
#[inline]
fn mitchell_netravali(x: f32, b: f32, c: f32) -> f32 {
    let (x2, x3) = (x * x, x * x * x);
    let k = if x < 1.0 {
        (12.0 - 9.0 * b - 6.0 * c) * x3 + (-18.0 + 12.0 * b + 6.0 * c) * x2 + (6.0 - 2.0 * b)
    } else if x < 2.0 {
        (-b - 6.0 * c) * x3 + (6.0 * b + 30.0 * c) * x2 + (-12.0 * b - 48.0 * c) * x + (8.0 * b + 24.0 * c)
    } else {
        0.0
    };
    k / 6.0
}

/// Bilinear reconstruction of `src` at (s, t) (one period per unit): the hot path of every MIP filter.
#[inline]
pub fn bilinear<S: TexelSource>(src: &S, addr: &Addressing<S::Texel>, s: f32, t: f32) -> S::Texel {
    let x = addr.wrap[0].reduce(s) * src.width() as f32 - 0.5;
    let y = addr.wrap[1].reduce(t) * src.height() as f32 - 0.5;
    let (xf, yf) = (x.floor(), y.floor());
    let (fx, fy) = (x - xf, y - yf);
    let (i, j) = (xf as isize, yf as isize);
    // Each axis resolved once (two indices), not per texel: four compares for the four taps.
    let (w, h) = (src.width(), src.height());
    let (i0, i1) = (addr.wrap[0].resolve(i, w), addr.wrap[0].resolve(i + 1, w));
    let (j0, j1) = (addr.wrap[1].resolve(j, h), addr.wrap[1].resolve(j + 1, h));
    let [t00, t10, t01, t11] = match (i0, i1, j0, j1) {
        (Some(i0), Some(i1), Some(j0), Some(j1)) => src.quad([i0, i1], [j0, j1]),
        _ => {
            let at = |i: Option<usize>, j: Option<usize>| match (i, j) {
                (Some(i), Some(j)) => src.texel(i, j),
                _ => addr.border,
            };
            [at(i0, j0), at(i1, j0), at(i0, j1), at(i1, j1)]
        }
    };
    lerp(lerp(t00, t10, fx), lerp(t01, t11, fx), fy)
}

#[inline]
pub fn lerp<T: Texel>(a: T, b: T, f: f32) -> T {
    a + (b - a) * f
}

/// The texture at (s, t) reconstructed with `kernel` from one level. The weights are normalised, so a
/// truncated kernel (Gaussian, Lanczos) still keeps constants constant.
#[inline]
pub fn reconstruct<S: TexelSource>(src: &S, addr: &Addressing<S::Texel>, kernel: Kernel, s: f32, t: f32) -> S::Texel {
    match kernel {
        Kernel::Nearest => {
            let i = (addr.wrap[0].reduce(s) * src.width() as f32).floor() as isize;
            let j = (addr.wrap[1].reduce(t) * src.height() as f32).floor() as isize;
            addr.fetch(src, i, j)
        }
        Kernel::Bilinear => bilinear(src, addr, s, t),
        _ => {
            const MAX: usize = 6;
            let n = kernel.taps();
            let x = addr.wrap[0].reduce(s) * src.width() as f32 - 0.5;
            let y = addr.wrap[1].reduce(t) * src.height() as f32 - 0.5;
            let (xf, yf) = (x.floor(), y.floor());
            // The first tap sits n/2 - 1 texels before the texel at or left of the sample.
            let back = (n / 2 - 1) as isize;
            let (i0, j0) = (xf as isize - back, yf as isize - back);
            let (mut wx, mut wy) = ([0.0f32; MAX], [0.0f32; MAX]);
            let (mut sx, mut sy) = (0.0, 0.0);
            for k in 0..n {
                wx[k] = kernel.weight(x - (i0 + k as isize) as f32);
                wy[k] = kernel.weight(y - (j0 + k as isize) as f32);
                sx += wx[k];
                sy += wy[k];
            }
            let norm = 1.0 / (sx * sy);
            let mut sum = S::Texel::default();
            for (b, &wyb) in wy.iter().enumerate().take(n) {
                let mut row = S::Texel::default();
                for (a, &wxa) in wx.iter().enumerate().take(n) {
                    row = row + addr.fetch(src, i0 + a as isize, j0 + b as isize) * wxa;
                }
                sum = sum + row * wyb;
            }
            sum * norm
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cubics_match_their_published_values() {
        // Catmull-Rom: 1 at 0, 0 at the other integers, -1/16 at 1.5 (Keys 1981, a = -1/2).
        assert!((Kernel::CatmullRom.weight(0.0) - 1.0).abs() < 1e-6);
        assert!(Kernel::CatmullRom.weight(1.0).abs() < 1e-6);
        assert!((Kernel::CatmullRom.weight(1.5) + 0.0625).abs() < 1e-6);
        // Cubic B-spline: 2/3 at 0, 1/6 at 1, 1/48 at 1.5.
        assert!((Kernel::BSpline.weight(0.0) - 2.0 / 3.0).abs() < 1e-6);
        assert!((Kernel::BSpline.weight(1.0) - 1.0 / 6.0).abs() < 1e-6);
        assert!((Kernel::BSpline.weight(1.5) - 1.0 / 48.0).abs() < 1e-6);
        // Lanczos-3 vanishes at the integers, is 1 at 0.
        assert!((Kernel::Lanczos3.weight(0.0) - 1.0).abs() < 1e-6);
        assert!(Kernel::Lanczos3.weight(2.0).abs() < 1e-6);
        // Partitions of unity at any offset (the interpolating and approximating cubics both).
        for f in [0.0, 0.2, 0.5, 0.9] {
            for k in [Kernel::CatmullRom, Kernel::BSpline, Kernel::Bilinear] {
                let sum: f32 = (-2..=2).map(|i| k.weight(f - i as f32)).sum();
                assert!((sum - 1.0).abs() < 1e-5, "{k:?} at {f}: {sum}");
            }
        }
    }
}
