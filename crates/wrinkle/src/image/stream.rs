//! Images one row at a time, so that a 16384 x 16384 picture never has to be held whole.
//!
//! [`ImageRows`] reads rows from top to bottom: non-interlaced PNG files (8 and 16 bit, any colour type)
//! are decoded row by row, plain ones by `png_rows` (inflated on a thread of their own), those with a
//! palette, fewer bits or a transparency key by the `png` crate; every other input (interlaced PNG, JPEG,
//! BMP, TGA, TIFF) is decoded whole by the `image` crate and then handed out row by row. [`write_rows`]
//! writes rows as a PNG through the `png` crate's streaming encoder, or collects them into a 24-bit BMP
//! (BMP stores rows bottom up, so it cannot be streamed). Outputs are placed whole (`output::write_atomic`).

use std::fs::File;
use std::io::{BufReader, Read, Write};
use std::path::{Path, PathBuf};

use ::image::{DynamicImage, ImageReader};

use super::io::{decode, decode_error, open_input, open_message, LUMA};
use super::output::write_atomic;
use super::png_rows::PngRows;
use crate::error::{Error, Result};
use crate::limits::Limit;

const PNG_SIGNATURE: [u8; 8] = [137, 80, 78, 71, 13, 10, 26, 10];

/// The sample layout of the rows handed out: `channels` interleaved samples per pixel (1 grey, 2 grey and
/// alpha, 3 RGB, 4 RGBA), 8 bits or 16 bits (big-endian, as PNG stores them) each.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Layout {
    channels: usize,
    sixteen: bool,
}

enum Backend {
    /// A plain PNG, inflated on a thread of its own.
    PlainPng(PngRows),
    Png(Box<png::Reader<BufReader<File>>>),
    /// A decoded image converted to 8-bit or 16-bit samples, and the next row to hand out.
    Memory {
        image: DynamicImage,
        next: usize,
    },
}

/// The rows of an image file, top to bottom.
pub struct ImageRows {
    path: PathBuf,
    width: usize,
    height: usize,
    layout: Layout,
    backend: Backend,
    /// The current row's samples, for the in-memory backend (16-bit samples turned big-endian).
    scratch: Vec<u8>,
}

impl ImageRows {
    /// Opens `path` and reads its header. Images wider or taller than the image-side limit are refused
    /// before any pixel is decoded; so are empty ones. Streamed PNG rows need no pixel-count limit; other
    /// formats, decoded whole, are held to every limit of `io`.
    pub fn open(path: &Path) -> Result<ImageRows> {
        let mut signature = [0u8; 8];
        let is_png = open_input(path)?.read(&mut signature).map_err(|e| Error::read(path, open_message(&e)))? == 8
            && signature == PNG_SIGNATURE;
        if is_png {
            let file = open_input(path)?;
            let mut decoder = png::Decoder::new(BufReader::with_capacity(1 << 16, file));
            decoder.set_transformations(png::Transformations::EXPAND);
            // Sizes are checked against the side limit here; the rows themselves are small.
            decoder.set_limits(png::Limits { bytes: usize::MAX });
            let reader = decoder.read_info().map_err(|e| png_error(path, e))?;
            let (width, height) = (reader.info().width as usize, reader.info().height as usize);
            check_side(path, width, height)?;
            if !reader.info().interlaced {
                let (color, depth) = reader.output_color_type();
                let layout = Layout { channels: color.samples(), sixteen: depth == png::BitDepth::Sixteen };
                let info = reader.info();
                let plain = (info.color_type, info.bit_depth) == (color, depth) && info.trns.is_none();
                let backend = if plain {
                    let bpp = layout.channels * if layout.sixteen { 2 } else { 1 };
                    Backend::PlainPng(PngRows::new(path, width, height, bpp))
                } else {
                    Backend::Png(Box::new(reader))
                };
                return Ok(ImageRows { path: path.to_path_buf(), width, height, layout, backend, scratch: Vec::new() });
            }
            // Adam7 interlacing spreads every row over seven passes: decode it whole below.
        } else {
            let dims = ImageReader::open(path)
                .and_then(ImageReader::with_guessed_format)
                .map_err(|e| Error::read(path, open_message(&e)))?;
            let format = dims.format();
            let (w, h) = dims.into_dimensions().map_err(|e| decode_error(path, format, e))?;
            check_side(path, w as usize, h as usize)?;
        }
        Self::in_memory(path, decode(path, |_| 8)?)
    }

    /// Rows of an 8-bit RGB image held in memory (3 bytes per pixel, row 0 at the top); `path` names it in
    /// errors.
    pub fn from_rgb8(path: &Path, width: usize, height: usize, rgb: Vec<u8>) -> Result<ImageRows> {
        let image = ::image::RgbImage::from_raw(width as u32, height as u32, rgb)
            .ok_or_else(|| Error::Invalid(format!("{}: not a {width}x{height} RGB buffer", path.display())))?;
        Self::in_memory(path, DynamicImage::ImageRgb8(image))
    }

    /// Rows of an image already decoded.
    fn in_memory(path: &Path, image: DynamicImage) -> Result<ImageRows> {
        use ::image::ColorType as C;
        let image = match image.color() {
            C::L8 | C::La8 | C::Rgb8 | C::Rgba8 | C::L16 | C::La16 | C::Rgb16 | C::Rgba16 => image,
            c if c.has_alpha() => DynamicImage::ImageRgba16(image.to_rgba16()),
            _ => DynamicImage::ImageRgb16(image.to_rgb16()),
        };
        let layout = Layout {
            channels: usize::from(image.color().channel_count()),
            sixteen: image.color().bytes_per_pixel() / image.color().channel_count() == 2,
        };
        let (width, height) = (image.width() as usize, image.height() as usize);
        let backend = Backend::Memory { image, next: 0 };
        Ok(ImageRows { path: path.to_path_buf(), width, height, layout, backend, scratch: Vec::new() })
    }

    pub fn width(&self) -> usize {
        self.width
    }

    pub fn height(&self) -> usize {
        self.height
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Whether the file stores 16 bits per sample.
    pub fn is_sixteen_bit(&self) -> bool {
        self.layout.sixteen
    }

    /// The next row's samples in the layout of `self.layout`.
    fn next_raw(&mut self) -> Result<&[u8]> {
        let path = &self.path;
        match &mut self.backend {
            Backend::PlainPng(rows) => rows.next_row(),
            Backend::Png(reader) => match reader.next_row().map_err(|e| png_error(path, e))? {
                Some(row) => Ok(row.data()),
                None => Err(Error::read(path, "truncated or corrupt PNG: fewer rows than its header says")),
            },
            Backend::Memory { image, next } => {
                let bytes = image.as_bytes();
                let row_len = bytes.len() / self.height;
                let row = &bytes[*next * row_len..(*next + 1) * row_len];
                *next += 1;
                self.scratch.clear();
                if self.layout.sixteen {
                    // The image crate keeps 16-bit samples in native order; rows here are big-endian like PNG's.
                    for pair in row.chunks_exact(2) {
                        self.scratch.extend_from_slice(&u16::from_ne_bytes([pair[0], pair[1]]).to_be_bytes());
                    }
                } else {
                    self.scratch.extend_from_slice(row);
                }
                Ok(&self.scratch)
            }
        }
    }

    /// The next row as grey values scaled so that the file's full scale (255 or 65535) is `full_scale`.
    /// Colour pixels become the Rec. 709 luma 0.2126 R + 0.7152 G + 0.0722 B of the stored values;
    /// alpha is ignored. `out` holds `width` values.
    pub fn read_grey(&mut self, out: &mut [f32], full_scale: f32) -> Result<()> {
        let Layout { channels, sixteen } = self.layout;
        let scale = full_scale / if sixteen { 65535.0 } else { 255.0 };
        let raw = self.next_raw()?;
        let bytes = if sixteen { 2 } else { 1 };
        let sample = |px: &[u8], c: usize| -> f32 {
            if sixteen {
                f32::from(u16::from_be_bytes([px[2 * c], px[2 * c + 1]]))
            } else {
                f32::from(px[c])
            }
        };
        if channels < 3 && !sixteen {
            // The common case, kept to one multiply per value so that it vectorises.
            for (o, px) in out.iter_mut().zip(raw.chunks_exact(channels)) {
                *o = f32::from(px[0]) * scale;
            }
        } else if channels < 3 {
            for (o, px) in out.iter_mut().zip(raw.chunks_exact(channels * bytes)) {
                *o = sample(px, 0) * scale;
            }
        } else {
            for (o, px) in out.iter_mut().zip(raw.chunks_exact(channels * bytes)) {
                *o = (LUMA[0] * sample(px, 0) + LUMA[1] * sample(px, 1) + LUMA[2] * sample(px, 2)) * scale;
            }
        }
        Ok(())
    }

    /// The next row as 8-bit RGB, 3 bytes per pixel: grey copied to R, G and B, 16-bit samples rounded to
    /// 8 bits, alpha dropped. `out` holds `3 * width` bytes.
    pub fn read_rgb8(&mut self, out: &mut [u8]) -> Result<()> {
        let Layout { channels, sixteen } = self.layout;
        let raw = self.next_raw()?;
        let bytes = if sixteen { 2 } else { 1 };
        let sample = |px: &[u8], c: usize| -> u8 {
            if sixteen {
                // Round v * 255 / 65535 = v / 257.
                ((u32::from(u16::from_be_bytes([px[2 * c], px[2 * c + 1]])) * 255 + 32767) / 65535) as u8
            } else {
                px[c]
            }
        };
        for (o, px) in out.chunks_exact_mut(3).zip(raw.chunks_exact(channels * bytes)) {
            if channels >= 3 {
                o.copy_from_slice(&[sample(px, 0), sample(px, 1), sample(px, 2)]);
            } else {
                o.fill(sample(px, 0));
            }
        }
        Ok(())
    }

    /// The next row as RGB in [0, 1] of full scale, 3 values per pixel (grey copied, alpha dropped): for
    /// data such as normal maps, which keep all 16 bits.
    pub fn read_rgb(&mut self, out: &mut [f32]) -> Result<()> {
        let Layout { channels, sixteen } = self.layout;
        let raw = self.next_raw()?;
        let bytes = if sixteen { 2 } else { 1 };
        let sample = |px: &[u8], c: usize| -> f32 {
            if sixteen {
                f32::from(u16::from_be_bytes([px[2 * c], px[2 * c + 1]])) / 65535.0
            } else {
                f32::from(px[c]) / 255.0
            }
        };
        for (o, px) in out.chunks_exact_mut(3).zip(raw.chunks_exact(channels * bytes)) {
            if channels >= 3 {
                o.copy_from_slice(&[sample(px, 0), sample(px, 1), sample(px, 2)]);
            } else {
                o.fill(sample(px, 0));
            }
        }
        Ok(())
    }

    /// Reads the whole image as 8-bit RGB (for textures that must be resampled).
    pub fn read_all_rgb8(&mut self) -> Result<Vec<u8>> {
        let mut all = vec![0u8; 3 * self.width * self.height];
        for row in all.chunks_exact_mut(3 * self.width) {
            self.read_rgb8(row)?;
        }
        Ok(all)
    }
}

/// Refuses empty images and images larger than the image-side limit on either side.
fn check_side(path: &Path, width: usize, height: usize) -> Result<()> {
    let side = Limit::ImageSide.count();
    if width == 0 || height == 0 {
        Err(Error::read(path, format!("image is {width}x{height}, it has no pixels")))
    } else if width > side || height > side {
        Err(Error::read(
            path,
            format!("image is {width}x{height} pixels, larger than the {side} limit ({})", Limit::ImageSide.hint()),
        ))
    } else {
        Ok(())
    }
}

pub(crate) fn png_error(path: &Path, e: png::DecodingError) -> Error {
    match e {
        png::DecodingError::IoError(io) if io.kind() == std::io::ErrorKind::UnexpectedEof => {
            Error::read(path, "truncated or corrupt PNG: unexpected end of file")
        }
        png::DecodingError::IoError(io) => Error::read(path, format!("cannot read: {io}")),
        other => Error::read(path, format!("truncated or corrupt PNG: {other}")),
    }
}

/// How hard the PNG encoder works: `Fast` is several times quicker than `Best` for files a few tens of
/// percent larger.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PngCompression {
    /// fdeflate's fast mode with the Up filter on every row.
    Fast,
    /// zlib level 6 with the filter chosen per row.
    Default,
    /// zlib level 9 with the filter chosen per row.
    Best,
}

/// The file format of an output, from its extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutputFormat {
    Png,
    /// 24-bit Windows bitmap, like the 1994 emboss demo.
    Bmp,
}

impl OutputFormat {
    /// `.png` or `.bmp` (any case); anything else is an error naming the file.
    pub fn of(path: &Path) -> Result<OutputFormat> {
        match path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).as_deref() {
            Some("png") => Ok(OutputFormat::Png),
            Some("bmp") => Ok(OutputFormat::Bmp),
            _ => Err(Error::Invalid(format!("{}: output must end in .png or .bmp", path.display()))),
        }
    }
}

/// What the rows given to [`write_rows`] hold.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RowFormat {
    /// 1 (grey) or 3 (RGB) samples per pixel.
    pub channels: usize,
    /// 16-bit big-endian samples (PNG only) instead of bytes.
    pub sixteen: bool,
}

impl RowFormat {
    pub fn row_bytes(&self, width: usize) -> usize {
        width * self.channels * if self.sixteen { 2 } else { 1 }
    }
}

/// Writes a `width` x `height` image to `path` (PNG or 24-bit BMP by its extension): `produce` is called
/// once with a sink that takes whole rows, top to bottom, in `rows` layout; it must give every row.
/// Nothing is left at `path` if `produce` or the writing fails.
pub fn write_rows(
    path: &Path,
    width: usize,
    height: usize,
    rows: RowFormat,
    compression: PngCompression,
    produce: impl FnOnce(&mut dyn FnMut(&[u8]) -> Result<()>) -> Result<()>,
) -> Result<()> {
    write_rows_as(path, OutputFormat::of(path)?, width, height, rows, compression, produce)
}

/// [`write_rows`] in the given format, whatever `path` is called (a staged output's hidden name).
pub fn write_rows_as(
    path: &Path,
    format: OutputFormat,
    width: usize,
    height: usize,
    rows: RowFormat,
    compression: PngCompression,
    produce: impl FnOnce(&mut dyn FnMut(&[u8]) -> Result<()>) -> Result<()>,
) -> Result<()> {
    if format == OutputFormat::Bmp && rows.sixteen {
        return Err(Error::Invalid(format!("{}: BMP output is 8 bits per channel", path.display())));
    }
    let row_bytes = rows.row_bytes(width);
    let (w32, h32) = (u32::try_from(width), u32::try_from(height));
    let (Ok(w32), Ok(h32)) = (w32, h32) else {
        return Err(Error::Invalid(format!("{}: image is {width}x{height}, too large", path.display())));
    };
    let mut written = 0usize;
    let count = |written: &mut usize, data: &[u8]| -> Result<()> {
        if !data.len().is_multiple_of(row_bytes) || *written + data.len() / row_bytes > height {
            return Err(Error::Invalid(format!("{}: rows do not fit a {width}x{height} image", path.display())));
        }
        *written += data.len() / row_bytes;
        Ok(())
    };
    let png_err = |e: png::EncodingError| Error::write(path, e);
    match format {
        OutputFormat::Png => write_atomic(path, |out| {
            let mut encoder = png::Encoder::new(out, w32, h32);
            encoder.set_color(if rows.channels == 3 { png::ColorType::Rgb } else { png::ColorType::Grayscale });
            encoder.set_depth(if rows.sixteen { png::BitDepth::Sixteen } else { png::BitDepth::Eight });
            let (level, filter) = match compression {
                PngCompression::Fast => (png::Compression::Fast, png::Filter::Up),
                PngCompression::Default => (png::Compression::Balanced, png::Filter::Adaptive),
                PngCompression::Best => (png::Compression::High, png::Filter::Adaptive),
            };
            encoder.set_compression(level);
            encoder.set_filter(filter);
            let mut writer = encoder.write_header().map_err(png_err)?;
            let mut stream = writer.stream_writer_with_size(row_bytes.max(1 << 16)).map_err(png_err)?;
            produce(&mut |data| {
                count(&mut written, data)?;
                stream.write_all(data).map_err(|e| Error::write(path, e))
            })?;
            if written != height {
                return Err(Error::Invalid(format!("{}: {written} of {height} rows were given", path.display())));
            }
            stream.finish().map_err(png_err)?;
            writer.finish().map_err(png_err)
        }),
        OutputFormat::Bmp => {
            let mut rgb = Vec::with_capacity(width * height * 3);
            produce(&mut |data| {
                count(&mut written, data)?;
                if rows.channels == 3 {
                    rgb.extend_from_slice(data);
                } else {
                    rgb.extend(data.iter().flat_map(|&v| [v, v, v]));
                }
                Ok(())
            })?;
            if written != height {
                return Err(Error::Invalid(format!("{}: {written} of {height} rows were given", path.display())));
            }
            write_atomic(path, |mut out| {
                ::image::codecs::bmp::BmpEncoder::new(&mut out)
                    .encode(&rgb, w32, h32, ::image::ExtendedColorType::Rgb8)
                    .map_err(|e| Error::write(path, e))
            })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("wrinkle-stream-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn png_rows_round_trip_in_every_layout() {
        let dir = scratch("layouts");
        let (w, h) = (5usize, 3usize);
        let grey: Vec<u8> = (0..w * h).map(|i| (i * 17) as u8).collect();
        for (name, rows) in [
            ("g8.png", RowFormat { channels: 1, sixteen: false }),
            ("rgb8.bmp", RowFormat { channels: 3, sixteen: false }),
            ("g16.png", RowFormat { channels: 1, sixteen: true }),
        ] {
            let path = dir.join(name);
            let data: Vec<u8> = grey
                .iter()
                .flat_map(|&v| {
                    let px: Vec<u8> = if rows.sixteen { vec![v, v] } else { vec![v; rows.channels] };
                    px
                })
                .collect();
            write_rows(&path, w, h, rows, PngCompression::Fast, |sink| {
                data.chunks(rows.row_bytes(w)).try_for_each(sink)
            })
            .unwrap();
            let mut src = ImageRows::open(&path).unwrap();
            assert_eq!((src.width(), src.height(), src.is_sixteen_bit()), (w, h, rows.sixteen));
            let mut row = vec![0.0; w];
            for y in 0..h {
                src.read_grey(&mut row, 255.0).unwrap();
                for x in 0..w {
                    // 16-bit v * 257 reads back as exactly v on the 0..255 scale.
                    assert!((row[x] - grey[y * w + x] as f32).abs() < 1e-4, "{name} ({x},{y})");
                }
            }
        }
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn limits_and_unknown_outputs_are_refused() {
        let dir = scratch("limits");
        let path = dir.join("wide.png");
        let rows = RowFormat { channels: 1, sixteen: false };
        write_rows(&path, 32769, 2, rows, PngCompression::Default, |sink| sink(&[7u8; 2 * 32769])).unwrap();
        let err = ImageRows::open(&path).err().unwrap().to_string();
        assert!(err.contains("larger than the 32768 limit (raise it with --limit image-side=N)"), "{err}");
        let err = write_rows(&dir.join("x.gif"), 1, 1, rows, PngCompression::Fast, |s| s(&[0])).unwrap_err();
        assert!(err.to_string().contains("must end in .png or .bmp"));
        // Too few rows: an error, and no file.
        let short = dir.join("short.png");
        assert!(write_rows(&short, 2, 2, rows, PngCompression::Fast, |s| s(&[0, 0])).is_err());
        assert!(!short.exists());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
