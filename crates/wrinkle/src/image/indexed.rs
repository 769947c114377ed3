//! Colour index images: 8-bit indices into a palette, kept as indices (not expanded to colours), so a
//! texture can be filtered by nearest index and its palette swapped without touching the image.

use super::io::{check_size, decode, open_input};
use super::stream::png_error;
use super::Image;
use crate::limits;
use crate::{Error, Result};
use ::image::DynamicImage;
use std::io::BufReader;
use std::path::Path;

/// An index image and the palette its file carries (a PNG palette image's PLTE with tRNS's alphas).
pub struct IndexImage {
    pub indices: Image<u8>,
    /// RGBA entries as stored (sRGB-encoded colour, linear alpha); `None` for grey indices.
    pub palette: Option<Vec<[u8; 4]>>,
}

/// A PNG palette image (1, 2, 4 or 8 bits per index), or an 8-bit grey image of indices in any format.
pub fn load_indices(path: &Path) -> Result<IndexImage> {
    let mut signature = [0u8; 8];
    let png = std::io::Read::read(&mut open_input(path)?, &mut signature).is_ok_and(|n| n == 8)
        && signature == *b"\x89PNG\r\n\x1a\n";
    if png {
        let mut decoder = png::Decoder::new(BufReader::new(open_input(path)?));
        decoder.set_transformations(png::Transformations::IDENTITY);
        decoder.set_limits(png::Limits { bytes: usize::MAX });
        let mut reader = decoder.read_info().map_err(|e| png_error(path, e))?;
        let info = reader.info();
        use png::BitDepth as B;
        let (width, height) = (info.width as usize, info.height as usize);
        check_size(width, height).map_err(|m| Error::read(path, m))?;
        let bits = match (info.color_type, info.bit_depth) {
            (png::ColorType::Indexed, depth @ (B::One | B::Two | B::Four | B::Eight)) => depth as usize,
            (png::ColorType::Grayscale, B::Eight) => 8,
            (color, depth) => return Err(not_indices(path, &format!("a {color:?} PNG of {} bits", depth as u8))),
        };
        let palette = info.palette.as_ref().map(|rgb| {
            let alpha = info.trns.as_deref().unwrap_or(&[]);
            rgb.chunks_exact(3)
                .enumerate()
                .map(|(i, c)| [c[0], c[1], c[2], alpha.get(i).copied().unwrap_or(255)])
                .collect::<Vec<_>>()
        });
        limits::reserve((width * height) as u64 * 2, || format!("{}: {width}x{height} indices", path.display()))?;
        let mut raw = vec![0u8; reader.output_buffer_size().ok_or_else(|| Error::read(path, "too large"))?];
        let frame = reader.next_frame(&mut raw).map_err(|e| png_error(path, e))?;
        let per_byte = 8 / bits;
        let mask = ((1u16 << bits) - 1) as u8;
        let pixels = (0..height)
            .flat_map(|y| {
                let row = &raw[y * frame.line_size..(y + 1) * frame.line_size];
                (0..width).map(move |x| {
                    let shift = 8 - bits * (x % per_byte + 1);
                    (row[x / per_byte] >> shift) & mask
                })
            })
            .collect();
        return Ok(IndexImage { indices: Image { width, height, pixels }, palette });
    }
    match decode(path, |_| 1)? {
        DynamicImage::ImageLuma8(grey) => {
            let (width, height) = (grey.width() as usize, grey.height() as usize);
            Ok(IndexImage { indices: Image { width, height, pixels: grey.into_raw() }, palette: None })
        }
        other => Err(not_indices(path, &format!("a {:?} image", other.color()))),
    }
}

fn not_indices(path: &Path, got: &str) -> Error {
    Error::read(path, format!("expected colour indices (a PNG palette image or 8-bit grey), got {got}"))
}

/// A palette file: its pixels in reading order (left to right, top to bottom) are the entries, at most
/// 256, as RGBA bytes (alpha 255 where the file has none).
pub fn load_palette(path: &Path) -> Result<Vec<[u8; 4]>> {
    let image = super::io::load_rgba8(path)?;
    if image.pixels.len() > 256 {
        return Err(Error::read(
            path,
            format!("a palette has at most 256 entries, this image has {} pixels", image.pixels.len()),
        ));
    }
    Ok(image.pixels)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::scratch::Scratch;

    /// A 2-bit palette PNG with a tRNS chunk: indices unpacked from their bytes, the palette's
    /// alphas from tRNS (opaque past its end); a 16-bit grey PNG is refused.
    #[test]
    fn palette_pngs_keep_their_indices() {
        let s = Scratch::new("indexed");
        let path = s.path("p.png");
        let mut encoder = png::Encoder::new(std::fs::File::create(&path).unwrap(), 5, 2);
        encoder.set_color(png::ColorType::Indexed);
        encoder.set_depth(png::BitDepth::Two);
        encoder.set_palette(vec![255, 0, 0, 0, 255, 0, 0, 0, 255, 9, 9, 9]);
        encoder.set_trns(vec![255, 128]);
        // Rows of 5 two-bit indices: 0 1 2 3 | 1, then 3 2 1 0 | 2 (two bytes a row, low bits padded).
        let rows = [0b00_01_10_11, 0b01_000000, 0b11_10_01_00, 0b10_000000];
        encoder.write_header().unwrap().write_image_data(&rows).unwrap();
        let image = load_indices(&path).unwrap();
        assert_eq!(image.indices.pixels, vec![0, 1, 2, 3, 1, 3, 2, 1, 0, 2]);
        let palette = image.palette.unwrap();
        assert_eq!(palette, vec![[255, 0, 0, 255], [0, 255, 0, 128], [0, 0, 255, 255], [9, 9, 9, 255]]);
        let grey16 = s.path("g.png");
        let mut encoder = png::Encoder::new(std::fs::File::create(&grey16).unwrap(), 1, 1);
        encoder.set_color(png::ColorType::Grayscale);
        encoder.set_depth(png::BitDepth::Sixteen);
        encoder.write_header().unwrap().write_image_data(&[1, 2]).unwrap();
        let err = load_indices(&grey16).err().unwrap().to_string();
        assert!(err.contains("expected colour indices") && err.contains("g.png"), "{err}");
    }
}
