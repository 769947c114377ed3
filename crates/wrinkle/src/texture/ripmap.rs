//! The ripmap: the texture prefiltered separately in x and in y, image (a, b) being W / 2^a x H / 2^b
//! (about four times the memory of the texture). A lookup picks the images whose texels match the
//! footprint's extent along u and along v, so an axis-aligned stretched footprint is filtered by an
//! axis-aligned stretched box instead of the square of its longer side.

use super::mip::{half, MipFilter, Resample};
use super::reconstruct::{bilinear, lerp, Addressing};
use super::wrap::Wrap;
use super::Footprint;

pub struct Ripmap<S> {
    /// Images along x (a = 0..nx) and y (b = 0..ny).
    nx: usize,
    ny: usize,
    /// Image (a, b) at index b * nx + a.
    images: Vec<S>,
}

impl<S: Resample> Ripmap<S> {
    /// Halves `base` along x until one texel wide, and every one of those along y until one texel high.
    pub fn build(base: &S, filter: MipFilter, wrap: [Wrap; 2]) -> Self {
        let mut first_row = vec![base.clone()];
        while first_row[first_row.len() - 1].width() > 1 {
            let last = &first_row[first_row.len() - 1];
            let next = last.downsample(half(last.width()), last.height(), filter, wrap);
            first_row.push(next);
        }
        let nx = first_row.len();
        let mut columns: Vec<Vec<S>> = first_row.into_iter().map(|img| vec![img]).collect();
        for column in &mut columns {
            while column[column.len() - 1].height() > 1 {
                let last = &column[column.len() - 1];
                let next = last.downsample(last.width(), half(last.height()), filter, wrap);
                column.push(next);
            }
        }
        let ny = columns[0].len();
        let mut images = Vec::with_capacity(nx * ny);
        for b in 0..ny {
            for column in &columns {
                images.push(column[b].clone());
            }
        }
        Ripmap { nx, ny, images }
    }

    /// Total texels held, for the memory figure.
    pub fn texel_count(&self) -> usize {
        self.images.iter().map(|i| i.width() * i.height()).sum()
    }

    /// The texture over the footprint's axis-aligned extent: bilinear in each of the four images around
    /// (log2 extent along u, log2 extent along v), blended bilinearly between them.
    #[inline]
    pub fn sample(&self, addr: &Addressing<S::Texel>, s: f32, t: f32, fp: &Footprint) -> S::Texel {
        let base = &self.images[0];
        let [ux, vx, uy, vy] = fp.in_texels(base.width(), base.height());
        let ex = ux.abs().max(uy.abs());
        let ey = vx.abs().max(vy.abs());
        let level = |e: f32, n: usize| if e > 1.0 { e.log2().min((n - 1) as f32) } else { 0.0 };
        let (la, lb) = (level(ex, self.nx), level(ey, self.ny));
        let (a0, b0) = (la as usize, lb as usize);
        let (fa, fb) = (la - a0 as f32, lb - b0 as f32);
        let (a1, b1) = ((a0 + 1).min(self.nx - 1), (b0 + 1).min(self.ny - 1));
        let at = |a: usize, b: usize| bilinear(&self.images[b * self.nx + a], addr, s, t);
        let lower = if fa > 0.0 { lerp(at(a0, b0), at(a1, b0), fa) } else { at(a0, b0) };
        if fb > 0.0 {
            let upper = if fa > 0.0 { lerp(at(a0, b1), at(a1, b1), fa) } else { at(a0, b1) };
            lerp(lower, upper, fb)
        } else {
            lower
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::texel::Plane;

    #[test]
    fn images_are_halved_per_axis_and_hold_about_four_times_the_texels() {
        let base = Plane { width: 64, height: 16, texels: vec![0.5f32; 64 * 16] };
        let r = Ripmap::build(&base, MipFilter::Box, [Wrap::Repeat; 2]);
        assert_eq!((r.nx, r.ny), (7, 5));
        assert_eq!((r.images[3 * 7 + 2].width, r.images[3 * 7 + 2].height), (16, 2));
        let ratio = r.texel_count() as f32 / (64.0 * 16.0);
        assert!(ratio > 3.5 && ratio < 4.0, "{ratio}");
    }

    /// A footprint stretched along u only blurs along u: stripes along u (constant in v) stay sharp.
    #[test]
    fn stretched_footprint_filters_only_its_long_axis() {
        // Horizontal stripes: value depends on the row only, alternating every texel.
        let (w, h) = (64, 64);
        let texels = (0..w * h).map(|k| ((k / w) % 2) as f32).collect();
        let base = Plane { width: w, height: h, texels };
        let r = Ripmap::build(&base, MipFilter::Box, [Wrap::Repeat; 2]);
        let addr = Addressing::repeat();
        let fp = Footprint { dudx: 16.0 / w as f32, dvdx: 0.0, dudy: 0.0, dvdy: 1.0 / h as f32 };
        // At a row centre, the stripe's own value, not the grey of a square 16-texel box.
        let (s, t) = (0.3, 5.5 / h as f32);
        assert!((r.sample(&addr, s, t, &fp) - 1.0).abs() < 1e-5);
    }
}
