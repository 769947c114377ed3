//! Schlag's fast embossing of raster images (Graphics Gems IV, VIII.1, 1994), as Lingard's notes give it.
//!
//! The image is a surface P(u,v) = [u v i(u,v)] with normal N = [-i_u, -i_v, 1]. The derivatives come from
//! the 3x3 masks
//!
//!     i_u:  | -1 0 1 |      i_v:  |  1  1  1 |
//!           | -1 0 1 |            |  0  0  0 |
//!           | -1 0 1 |            | -1 -1 -1 |
//!
//! (the top row of a mask is the image row above the pixel, so v points up the picture), and the z
//! component is scaled instead of the intensities: N = [-i_u, -i_v, N_z] with N_z = 6 * 255 / w, where a
//! ramp i = a u gives i_u = 6a, so `w` is the width of a 45-degree bevel's worth of slope. Intensities are
//! on the 0..255 scale (16-bit images are divided by 257). The shade is Lambert's N.L / (|N| |L|),
//! 0 where N.L < 0, and exactly [0 0 1].L on flat pixels (i_u = i_v = 0), precomputed.
//!
//! The light L = [cos az cos el, sin az cos el, sin el]: azimuth 0 is light from the right (+u), 90 from
//! the top of the picture (+v), counter-clockwise; elevation 90 is straight above the picture.

use crate::error::{Error, Result};
use crate::image::strips::{filter_rows_in_memory, Edges, Window};
use crate::image::{GreyImage, ImageRef};

/// The constants of one embossing: the unit light vector, N_z and the flat-pixel shade.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Emboss {
    pub light: [f32; 3],
    pub nz: f32,
    /// [0 0 1].L: the shade of every flat pixel.
    pub flat: f32,
}

impl Emboss {
    /// Azimuth and elevation in degrees (elevation in [0, 90]), bevel width `w` > 0 in pixels.
    pub fn new(azimuth_deg: f32, elevation_deg: f32, width: f32) -> Result<Emboss> {
        if !azimuth_deg.is_finite() {
            return Err(Error::parameter("azimuth", format!("must be a finite number of degrees, got {azimuth_deg}")));
        }
        if !(0.0..=90.0).contains(&elevation_deg) {
            return Err(Error::parameter(
                "elevation",
                format!("must be between 0 and 90 degrees, got {elevation_deg}"),
            ));
        }
        if !(width.is_finite() && width > 0.0) {
            return Err(Error::parameter("width", format!("must be a positive number of pixels, got {width}")));
        }
        let light = light_direction(azimuth_deg, elevation_deg);
        Ok(Emboss { light, nz: 6.0 * 255.0 / width, flat: light[2] })
    }

    /// The shade in [0, 1] of every pixel of one row, from its padded 3x3 window (intensities 0..255).
    #[inline]
    pub fn shade_row(&self, win: Window, out: &mut [f32]) {
        let n = out.len();
        let (a, b, c) = (&win.above[..n + 2], &win.row[..n + 2], &win.below[..n + 2]);
        let [lx, ly, lz] = self.light;
        let (nz2, nzlz, flat) = (self.nz * self.nz, self.nz * lz, self.flat);
        for x in 0..n {
            // Sums of whole integers on the 0..255 scale: exact in f32.
            let iu = (a[x + 2] + b[x + 2] + c[x + 2]) - (a[x] + b[x] + c[x]);
            let iv = (a[x] + a[x + 1] + a[x + 2]) - (c[x] + c[x + 1] + c[x + 2]);
            let ndotl = nzlz - iu * lx - iv * ly;
            let shade = ndotl.max(0.0) / (iu * iu + iv * iv + nz2).sqrt();
            // Schlag's shortcut, as a select so that the loop stays vectorised.
            out[x] = if iu == 0.0 && iv == 0.0 { flat } else { shade };
        }
    }
}

/// The unit vector towards a light at `azimuth` and `elevation` degrees (see the module's conventions).
pub fn light_direction(azimuth_deg: f32, elevation_deg: f32) -> [f32; 3] {
    let (az, el) = (f64::from(azimuth_deg).to_radians(), f64::from(elevation_deg).to_radians());
    [(az.cos() * el.cos()) as f32, (az.sin() * el.cos()) as f32, el.sin() as f32]
}

/// The nearest integer to `v` in [0, 2^23) (ties to even), as bits: adding 2^23 leaves exactly that integer
/// in the mantissa. Unlike a saturating `as` cast this compiles to a few vector instructions per 8 values.
#[inline(always)]
pub fn round_to_bits(v: f32) -> u32 {
    (v + 8_388_608.0).to_bits() & 0x7f_ffff
}

/// Shades in [0, 1] to 8-bit grey, rounded to nearest.
#[inline]
pub fn to_grey8(shade: &[f32], out: &mut [u8]) {
    for (o, &s) in out.iter_mut().zip(shade) {
        *o = round_to_bits(s.clamp(0.0, 1.0) * 255.0) as u8;
    }
}

/// Shades in [0, 1] to 16-bit grey, rounded to nearest, big-endian (as PNG stores it).
#[inline]
pub fn to_grey16(shade: &[f32], out: &mut [u8]) {
    for (o, &s) in out.chunks_exact_mut(2).zip(shade) {
        o.copy_from_slice(&(round_to_bits(s.clamp(0.0, 1.0) * 65535.0) as u16).to_be_bytes());
    }
}

/// The shade multiplying an 8-bit RGB texture row (stored values, as the 1994 demo does), rounded to nearest.
#[inline]
pub fn modulate_rgb8(shade: &[f32], texture: &[u8], out: &mut [u8]) {
    for ((o, t), &s) in out.chunks_exact_mut(3).zip(texture.chunks_exact(3)).zip(shade) {
        let s = s.clamp(0.0, 1.0);
        for k in 0..3 {
            o[k] = round_to_bits(f32::from(t[k]) * s) as u8;
        }
    }
}

/// Embosses a whole grey image held in memory (intensities 0..255, row 0 at the top; an image or a view of
/// the caller's buffer), border pixels reading the nearest edge pixel: what the streaming command computes,
/// for callers holding the image.
pub fn emboss_image<'a>(heights: impl Into<ImageRef<'a, f32>>, emboss: &Emboss) -> GreyImage {
    filter_rows_in_memory(heights, Edges::Clamp, 0.0, |_, win, o| emboss.shade_row(win, o))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn light_directions_turn_counter_clockwise_from_the_right() {
        let close = |a: [f32; 3], b: [f32; 3]| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-6);
        assert!(close(light_direction(0.0, 0.0), [1.0, 0.0, 0.0]));
        assert!(close(light_direction(90.0, 0.0), [0.0, 1.0, 0.0]));
        assert!(close(light_direction(180.0, 60.0), [-0.5, 0.0, 0.866_025_4]));
        assert!(close(light_direction(0.0, 90.0), [0.0, 0.0, 1.0]));
    }

    #[test]
    fn bad_parameters_are_refused() {
        assert!(Emboss::new(f32::NAN, 45.0, 3.0).is_err());
        assert!(matches!(Emboss::new(0.0, 91.0, 3.0), Err(Error::Parameter { name: "elevation", .. })));
        assert!(matches!(Emboss::new(0.0, 45.0, 0.0), Err(Error::Parameter { name: "width", .. })));
        assert!(Emboss::new(0.0, 45.0, f32::INFINITY).is_err());
    }

    #[test]
    fn conversions_round_and_saturate() {
        let mut g = [0u8; 4];
        to_grey8(&[0.0, 0.6 / 255.0, 1.0, 0.499], &mut g);
        assert_eq!(g, [0, 1, 255, 127]);
        // Ties go to the even neighbour; out-of-range shades saturate.
        to_grey8(&[0.5 / 255.0, 1.5 / 255.0, 2.0, -1.0], &mut g);
        assert_eq!(g, [0, 2, 255, 0]);
        let mut g16 = [0u8; 4];
        to_grey16(&[1.0, 0.5], &mut g16);
        assert_eq!(g16, [255, 255, 128, 0]);
        let mut rgb = [0u8; 3];
        modulate_rgb8(&[0.5], &[255, 100, 3], &mut rgb);
        assert_eq!(rgb, [128, 50, 2]);
    }
}
