//! Tangent-space normal maps from height maps: the normal of the surface z = strength * h(x, y), with h
//! the grey value in [0, 1] and x, y in pixels (x to the right, y = v up the picture), so `strength` is the
//! height of white above black in pixels: n = normalize(-strength dh/dx, -strength dh/dy, 1).
//!
//! The derivatives are 3x3 kernels normalised to one pixel step: central differences (h[x+1] - h[x-1]) / 2,
//! Sobel (rows weighted 1 2 1, over 8) and Scharr (3 10 3, over 32), the last two smoothing across the
//! derivative. A component c in [-1, 1] is stored as (c + 1) / 2 of full scale. OpenGL's convention puts
//! +Y up the picture (+v); DirectX's stores -Y.

use super::schlag::round_to_bits;
use crate::error::{Error, Result};
use crate::image::strips::{filter_rows_in_memory, Edges, Window};
use crate::image::{Image, ImageRef};

/// The derivative kernel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kernel {
    Central,
    Sobel,
    Scharr,
}

/// Which way the green channel points.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Convention {
    /// +Y is up the picture (+v): green is brighter on slopes facing up.
    OpenGl,
    /// +Y is down the picture: the green channel of OpenGL's map inverted.
    DirectX,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NormalMap {
    pub kernel: Kernel,
    pub strength: f32,
    pub convention: Convention,
}

impl NormalMap {
    pub fn new(kernel: Kernel, strength: f32, convention: Convention) -> Result<NormalMap> {
        if !(strength.is_finite() && strength > 0.0) {
            return Err(Error::parameter("strength", format!("must be a positive number, got {strength}")));
        }
        Ok(NormalMap { kernel, strength, convention })
    }

    /// (weight of the outer rows, weight of the middle row) of the kernel.
    fn weights(&self) -> (f32, f32) {
        match self.kernel {
            Kernel::Central => (0.0, 1.0),
            Kernel::Sobel => (1.0, 2.0),
            Kernel::Scharr => (3.0, 10.0),
        }
    }

    /// The slopes (gx, gy) of z = strength * h per pixel along x and y (y in the map's convention) of every
    /// pixel of a row from its padded window (heights in [0, 1]): the offset vectors.
    #[inline]
    pub fn slopes_row(&self, win: Window, gx: &mut [f32], gy: &mut [f32]) {
        let n = gx.len();
        let (a, b, c) = (&win.above[..n + 2], &win.row[..n + 2], &win.below[..n + 2]);
        let gy = &mut gy[..n];
        let (k0, k1) = self.weights();
        // One pixel step: the kernel's response to h = x is 2 (k0 + k1 + k0).
        let s = self.strength / (2.0 * (2.0 * k0 + k1));
        let sy = match self.convention {
            Convention::OpenGl => s,
            Convention::DirectX => -s,
        };
        for x in 0..n {
            let du = k0 * (a[x + 2] - a[x]) + k1 * (b[x + 2] - b[x]) + k0 * (c[x + 2] - c[x]);
            // Up the picture is the row above.
            let dv = k0 * (a[x] - c[x]) + k1 * (a[x + 1] - c[x + 1]) + k0 * (a[x + 2] - c[x + 2]);
            gx[x] = s * du;
            gy[x] = sy * dv;
        }
    }

    /// The unit normal of every pixel of a row from its padded window (heights in [0, 1]), as three
    /// planes: x, y (in the map's convention) and z: normalize(-gx, -gy, 1) of the slopes.
    #[inline]
    pub fn normals_row(&self, win: Window, nx: &mut [f32], ny: &mut [f32], nz: &mut [f32]) {
        self.slopes_row(win, nx, ny);
        for ((x, y), z) in nx.iter_mut().zip(ny.iter_mut()).zip(nz.iter_mut()) {
            let (gx, gy) = (-*x, -*y);
            let inv = 1.0 / (gx * gx + gy * gy + 1.0).sqrt();
            *x = gx * inv;
            *y = gy * inv;
            *z = inv;
        }
    }

    /// The unit normal of every pixel of a whole height image held in memory (heights in [0, 1], row 0 at
    /// the top; an image or a view of the caller's buffer).
    pub fn normals_image<'a>(&self, heights: impl Into<ImageRef<'a, f32>>, edges: Edges) -> Image<[f32; 3]> {
        filter_rows_in_memory(heights, edges, [0.0; 3], |_, win, o| {
            let n = o.len();
            let mut planes = vec![0.0; 3 * n];
            let (nx, rest) = planes.split_at_mut(n);
            let (ny, nz) = rest.split_at_mut(n);
            self.normals_row(win, nx, ny, nz);
            for (i, p) in o.iter_mut().enumerate() {
                *p = [nx[i], ny[i], nz[i]];
            }
        })
    }

    /// The slopes (the offset vectors) of every pixel of a whole height image held in memory.
    pub fn slopes_image<'a>(&self, heights: impl Into<ImageRef<'a, f32>>, edges: Edges) -> Image<[f32; 2]> {
        filter_rows_in_memory(heights, edges, [0.0; 2], |_, win, o| {
            let n = o.len();
            let mut planes = vec![0.0; 2 * n];
            let (gx, gy) = planes.split_at_mut(n);
            self.slopes_row(win, gx, gy);
            for (i, p) in o.iter_mut().enumerate() {
                *p = [gx[i], gy[i]];
            }
        })
    }
}

/// Unit normals to interleaved RGB samples: 8-bit, or 16-bit big-endian.
#[inline]
pub fn encode_rgb(nx: &[f32], ny: &[f32], nz: &[f32], sixteen: bool, out: &mut [u8]) {
    if sixteen {
        for (((o, &x), &y), &z) in out.chunks_exact_mut(6).zip(nx).zip(ny).zip(nz) {
            let q = |c: f32| round_to_bits((c + 1.0) * 32767.5) as u16;
            let (x, y, z) = (q(x).to_be_bytes(), q(y).to_be_bytes(), q(z).to_be_bytes());
            o.copy_from_slice(&[x[0], x[1], y[0], y[1], z[0], z[1]]);
        }
    } else {
        for (((o, &x), &y), &z) in out.chunks_exact_mut(3).zip(nx).zip(ny).zip(nz) {
            let q = |c: f32| round_to_bits((c + 1.0) * 127.5) as u8;
            o.copy_from_slice(&[q(x), q(y), q(z)]);
        }
    }
}

/// The unit normal stored in a normal map's RGB (each in [0, 1] of full scale), in the OpenGL convention
/// (y up the picture) whichever convention `convention` names.
pub fn decode_normal(rgb: [f32; 3], convention: Convention) -> [f32; 3] {
    let y = 2.0 * rgb[1] - 1.0;
    [2.0 * rgb[0] - 1.0, if convention == Convention::DirectX { -y } else { y }, 2.0 * rgb[2] - 1.0]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ramp_window(slope_x: f32, slope_y: f32) -> (Vec<f32>, Vec<f32>, Vec<f32>) {
        // h = slope_x x + slope_y (v), v up: the row above is higher by slope_y.
        let row = |dy: f32| (0..6).map(|x| 0.5 + slope_x * (x as f32 - 1.0) + slope_y * dy).collect::<Vec<f32>>();
        (row(1.0), row(0.0), row(-1.0))
    }

    #[test]
    fn every_kernel_gives_the_ramps_normal() {
        let (a, b, c) = ramp_window(0.01, -0.02);
        let win = Window { above: &a, row: &b, below: &c };
        for kernel in [Kernel::Central, Kernel::Sobel, Kernel::Scharr] {
            let map = NormalMap::new(kernel, 10.0, Convention::OpenGl).unwrap();
            let (mut x, mut y, mut z) = ([0.0; 4], [0.0; 4], [0.0; 4]);
            map.normals_row(win, &mut x, &mut y, &mut z);
            // n = normalize(-10 * 0.01, +10 * 0.02, 1).
            let len = (0.1f32 * 0.1 + 0.2 * 0.2 + 1.0).sqrt();
            for k in 0..4 {
                assert!((x[k] + 0.1 / len).abs() < 1e-6 && (y[k] - 0.2 / len).abs() < 1e-6, "{kernel:?}");
                assert!((z[k] - 1.0 / len).abs() < 1e-6);
            }
        }
    }

    #[test]
    fn encoding_and_decoding_agree() {
        let mut out = [0u8; 3];
        encode_rgb(&[0.0], &[-1.0], &[1.0], false, &mut out);
        assert_eq!(out, [128, 0, 255]);
        let n = decode_normal([0.5, 0.25, 1.0], Convention::DirectX);
        assert_eq!(n, [0.0, 0.5, 1.0]);
        assert!(NormalMap::new(Kernel::Sobel, -1.0, Convention::OpenGl).is_err());
    }
}
