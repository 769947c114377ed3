//! Resampling a colour image to another size, in linear light (sRGB decoded first, encoded after), so that
//! averaging bright and dark texels does not darken the picture.

use ::image::imageops::{resize, FilterType};
use ::image::{ImageBuffer, Rgb};

use super::color::{srgb8_decode_table, SrgbEncoder};

/// The reconstruction filter of a resampling.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Filter {
    Nearest,
    Triangle,
    CatmullRom,
    Lanczos3,
}

/// Resamples 8-bit sRGB RGB (3 bytes per pixel) from `w` x `h` to `nw` x `nh`.
pub fn resample_rgb8(rgb: &[u8], w: usize, h: usize, nw: usize, nh: usize, filter: Filter) -> Vec<u8> {
    let decode = srgb8_decode_table();
    let linear: Vec<f32> = rgb.iter().map(|&v| decode[v as usize]).collect();
    let image: ImageBuffer<Rgb<f32>, Vec<f32>> =
        ImageBuffer::from_raw(w as u32, h as u32, linear).expect("the buffer holds w * h RGB pixels");
    let filter = match filter {
        Filter::Nearest => FilterType::Nearest,
        Filter::Triangle => FilterType::Triangle,
        Filter::CatmullRom => FilterType::CatmullRom,
        Filter::Lanczos3 => FilterType::Lanczos3,
    };
    let resized = resize(&image, nw as u32, nh as u32, filter);
    let encoder = SrgbEncoder::new();
    resized.as_raw().iter().map(|&v| encoder.encode(v)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn averaging_happens_in_linear_light() {
        // A black and a white column made one pixel: the mean of 0 and 1 in linear light is sRGB 188, not 128.
        let rgb: Vec<u8> = (0..2 * 2).flat_map(|i| if i % 2 == 0 { [0u8; 3] } else { [255u8; 3] }).collect();
        let out = resample_rgb8(&rgb, 2, 2, 1, 1, Filter::Triangle);
        assert_eq!(out.len(), 3);
        for v in out {
            assert!((185..=191).contains(&v), "{v}");
        }
    }
}
