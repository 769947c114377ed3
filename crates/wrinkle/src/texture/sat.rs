//! The summed-area table (Crow 1984): S(i, j) = the sum of every texel left of i and below j, so the sum
//! over any box is four lookups. Sums are kept in f64: an 8k x 8k texture of values up to 1 sums to at
//! most 6.7e7, leaving 26 bits below the point, so a one-texel box is as exact as the texel.
//!
//! The filter is the slides': a box centred on the footprint, with the footprint's bounding-box aspect
//! ratio and the pixel's area. Between grid points the table is interpolated bilinearly, which is the exact
//! integral of the piecewise-constant texels, so box edges move smoothly with the footprint; a box one
//! texel wide is then exactly bilinear interpolation. With `Repeat`, boxes wrap around the texture edge
//! (whole periods are added from the row and column totals); with the other modes the box is cut at the
//! edge (the border colour fills the cut part with `Border`).

use super::reconstruct::Addressing;
use super::texel::{Texel, TexelSource};
use super::wrap::Wrap;
use super::Footprint;

pub struct Sat<W> {
    width: usize,
    height: usize,
    /// (width + 1) x (height + 1) sums, row 0 at the bottom (all zero), column 0 all zero.
    sums: Vec<W>,
}

impl<W: Copy + Default + std::ops::Add<Output = W> + std::ops::Sub<Output = W> + std::ops::Mul<f64, Output = W>>
    Sat<W>
{
    pub fn build<S: TexelSource>(src: &S) -> Self
    where
        S::Texel: Texel<Wide = W>,
    {
        let (w, h) = (src.width(), src.height());
        let stride = w + 1;
        let mut sums = vec![W::default(); stride * (h + 1)];
        for j in 0..h {
            let mut row = W::default();
            for i in 0..w {
                row = row + src.texel(i, j).widen();
                sums[(j + 1) * stride + i + 1] = sums[j * stride + i + 1] + row;
            }
        }
        Sat { width: w, height: h, sums }
    }

    #[inline]
    fn at(&self, i: usize, j: usize) -> W {
        self.sums[j * (self.width + 1) + i]
    }

    /// The integral of the texels over [0, x] x [0, y], x in [0, W], y in [0, H] (texel units).
    #[inline]
    fn corner(&self, x: f64, y: f64) -> W {
        let i = (x as usize).min(self.width - 1);
        let j = (y as usize).min(self.height - 1);
        let (fx, fy) = (x - i as f64, y - j as f64);
        let bottom = self.at(i, j) + (self.at(i + 1, j) - self.at(i, j)) * fx;
        let top = self.at(i, j + 1) + (self.at(i + 1, j + 1) - self.at(i, j + 1)) * fx;
        bottom + (top - bottom) * fy
    }

    /// The integral over [0, x] x [0, y] of the texture repeated periodically, for any x, y: whole periods
    /// come from the totals of the last row and column.
    #[inline]
    fn periodic_corner(&self, x: f64, y: f64) -> W {
        let (w, h) = (self.width as f64, self.height as f64);
        let (q, p) = ((x / w).floor(), (y / h).floor());
        let (r, rr) = (x - q * w, y - p * h);
        let (r, rr) = (r.clamp(0.0, w), rr.clamp(0.0, h));
        let total = self.at(self.width, self.height);
        self.corner(r, rr) + self.corner(w, rr) * q + self.corner(r, h) * p + total * (q * p)
    }

    /// The sum of the texels over the box [x0, x1] x [y0, y1] (texel units, x0 <= x1, y0 <= y1), and the
    /// area of the box that lies on the texture; each axis wraps (`Repeat`) or is cut at the edge.
    pub fn box_sum(&self, x0: f64, x1: f64, y0: f64, y1: f64, wrap: [Wrap; 2]) -> (W, f64) {
        let (w, h) = (self.width as f64, self.height as f64);
        let cut = |lo: f64, hi: f64, n: f64, mode: Wrap| {
            if mode == Wrap::Repeat {
                (lo, hi)
            } else {
                (lo.clamp(0.0, n), hi.clamp(0.0, n))
            }
        };
        let (x0, x1) = cut(x0, x1, w, wrap[0]);
        let (y0, y1) = cut(y0, y1, h, wrap[1]);
        let c = |x, y| self.periodic_corner(x, y);
        (c(x1, y1) - c(x0, y1) - c(x1, y0) + c(x0, y0), (x1 - x0) * (y1 - y0))
    }

    /// The mean of the texture over the slides' box for footprint `fp` centred at (s, t).
    pub fn sample<T: Texel<Wide = W>>(&self, addr: &Addressing<T>, s: f32, t: f32, fp: &Footprint) -> T {
        let (w, h) = (self.width, self.height);
        let [ux, vx, uy, vy] = fp.in_texels(w, h);
        let (bx, by) = box_size(ux, vx, uy, vy);
        let (cx, cy) = (addr.wrap[0].reduce(s) as f64 * w as f64, addr.wrap[1].reduce(t) as f64 * h as f64);
        let (hx, hy) = (0.5 * bx as f64, 0.5 * by as f64);
        let (sum, inside) = self.box_sum(cx - hx, cx + hx, cy - hy, cy + hy, addr.wrap);
        let area = bx as f64 * by as f64;
        let border_part = area - inside;
        let cut = addr.wrap.iter().any(|&m| m != Wrap::Repeat);
        if !cut {
            T::narrow(sum * (1.0 / area))
        } else if addr.wrap.contains(&Wrap::Border) {
            T::narrow(sum * (1.0 / area)) + addr.border * (border_part / area) as f32
        } else if inside > 1e-12 {
            T::narrow(sum * (1.0 / inside))
        } else {
            // The whole box lies off a clamped or mirrored texture: its nearest edge texel.
            let x = cx.clamp(0.0, w as f64 - 0.5);
            let y = cy.clamp(0.0, h as f64 - 0.5);
            self.texel_of(x as usize, y as usize)
        }
    }

    /// One texel, recovered from its four corners.
    fn texel_of<T: Texel<Wide = W>>(&self, i: usize, j: usize) -> T {
        let v = self.at(i + 1, j + 1) - self.at(i, j + 1) - self.at(i + 1, j) + self.at(i, j);
        T::narrow(v)
    }
}

/// The longest footprint axis component a box is made from, in texels. A box that long over a 32768-texel
/// texture holds 2^25 periods, so its mean is the texture's to 3e-8, and f64 still places its edges to
/// 2^-12 texels; longer (or infinite) footprints would overflow the area in f32 and make the sums NaN.
const LONGEST: f32 = (1u64 << 40) as f32;

/// The slides' box for a footprint in texels: the aspect ratio of the footprint's bounding box and the
/// area of the pixel's parallelogram, at least one texel on each side (so magnification is bilinear) and,
/// the components held to `LONGEST`, at most 2 `LONGEST`.
#[inline]
pub fn box_size(ux: f32, vx: f32, uy: f32, vy: f32) -> (f32, f32) {
    let [ux, vx, uy, vy] = [ux, vx, uy, vy].map(|d| d.clamp(-LONGEST, LONGEST));
    let (ex, ey) = (ux.abs() + uy.abs(), vx.abs() + vy.abs());
    let area = (ux * vy - uy * vx).abs();
    let (bx, by) = if ex > 0.0 && ey > 0.0 && area > 0.0 {
        let aspect = ex / ey;
        ((area * aspect).sqrt(), (area / aspect).sqrt())
    } else {
        // A degenerate (line or point) footprint: its extents.
        (ex, ey)
    };
    (bx.max(1.0), by.max(1.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::texel::Plane;

    fn random_plane(w: usize, h: usize) -> Plane<f32> {
        let mut x = 12345u32;
        let texels = (0..w * h)
            .map(|_| {
                x ^= x << 13;
                x ^= x >> 17;
                x ^= x << 5;
                (x % 1000) as f32 / 999.0
            })
            .collect();
        Plane { width: w, height: h, texels }
    }

    /// Integer boxes, wrapping or not, against the brute-force sum of the texels they cover.
    #[test]
    fn box_sums_equal_brute_force_sums() {
        let p = random_plane(13, 7);
        let sat = Sat::build(&p);
        let brute = |x0: isize, x1: isize, y0: isize, y1: isize| {
            let mut s = 0.0f64;
            for y in y0..y1 {
                for x in x0..x1 {
                    s += p.texels[y.rem_euclid(7) as usize * 13 + x.rem_euclid(13) as usize] as f64;
                }
            }
            s
        };
        for &(x0, x1, y0, y1) in
            &[(0, 13, 0, 7), (2, 5, 1, 4), (-3, 4, 5, 9), (10, 30, -8, -1), (-20, -19, 3, 4), (0, 1, 0, 1)]
        {
            let (got, area) = sat.box_sum(x0 as f64, x1 as f64, y0 as f64, y1 as f64, [Wrap::Repeat; 2]);
            let want = brute(x0, x1, y0, y1);
            assert!((got - want).abs() < 1e-9, "box {x0}..{x1} x {y0}..{y1}: {got} vs {want}");
            assert_eq!(area, ((x1 - x0) * (y1 - y0)) as f64);
        }
        // Cut at the edge with clamp: only the part on the texture counts.
        let (got, area) = sat.box_sum(-2.0, 3.0, 5.0, 9.0, [Wrap::Clamp; 2]);
        assert!((got - brute(0, 3, 5, 7)).abs() < 1e-9);
        assert_eq!(area, 6.0);
    }

    /// Fractional boxes: the integral of the piecewise-constant texels, from a fine brute-force quadrature.
    #[test]
    fn fractional_boxes_integrate_the_texels() {
        let p = random_plane(9, 6);
        let sat = Sat::build(&p);
        let (x0, x1, y0, y1) = (1.3, 7.45, -0.8, 2.2);
        let n = 2000;
        let mut want = 0.0;
        for b in 0..n {
            for a in 0..n {
                let x = x0 + (a as f64 + 0.5) / n as f64 * (x1 - x0);
                let y = y0 + (b as f64 + 0.5) / n as f64 * (y1 - y0);
                let (i, j) = ((x.floor() as isize).rem_euclid(9), (y.floor() as isize).rem_euclid(6));
                want += p.texels[j as usize * 9 + i as usize] as f64;
            }
        }
        want *= (x1 - x0) * (y1 - y0) / (n * n) as f64;
        let (got, _) = sat.box_sum(x0, x1, y0, y1, [Wrap::Repeat; 2]);
        assert!((got - want).abs() < 2e-3, "{got} vs {want}");
    }

    #[test]
    fn box_has_the_footprints_aspect_and_area() {
        // A footprint 8 texels along u and 2 along v, rotated 0: the box is 8 x 2.
        let (bx, by) = box_size(8.0, 0.0, 0.0, 2.0);
        assert!((bx - 8.0).abs() < 1e-5 && (by - 2.0).abs() < 1e-5);
        // Rotated 45 degrees: the bounding box is square, the area stays 16.
        let c = std::f32::consts::FRAC_1_SQRT_2;
        let (bx, by) = box_size(8.0 * c, 8.0 * c, -2.0 * c, 2.0 * c);
        assert!((bx - 4.0).abs() < 1e-4 && (by - 4.0).abs() < 1e-4, "{bx} {by}");
    }
}
