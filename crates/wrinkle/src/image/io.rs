//! Reading and writing image files: height maps and colour textures in (PNG, JPEG, BMP, TGA, TIFF or
//! Radiance HDR),
//! rendered pictures out as PNG and float data (AOVs) out as OpenEXR. Every output file is placed by
//! `output::write_atomic`: whole or not at all.

use std::fs::{self, File};
use std::io::{self, BufReader, Cursor, Write};
use std::path::Path;

use ::image::{ColorType, DynamicImage, ImageDecoder, ImageError, ImageFormat, ImageReader};
use exr::prelude::{
    AnyChannel, AnyChannels, Encoding, FlatSamples, IntegerBounds, Layer, LayerAttributes, ReadChannels, ReadLayers,
    Text, Vec2, WritableImage,
};

use super::output::write_atomic;
use super::{GreyImage, Image};
use crate::error::{Error, Result};
use crate::limits::{self, Limit};

pub(crate) const NOT_SUPPORTED: &str = "not a supported image (expected PNG, JPEG, BMP, TGA, TIFF or Radiance HDR)";

/// Rec. 709 luma weights for R, G, B.
pub const LUMA: [f32; 3] = [0.2126, 0.7152, 0.0722];

/// PNG filter for every row: with `png::Compression::Fast` (fdeflate), `Up` gave the best
/// speed/size balance on rendered pictures.
const PNG_FILTER: png::Filter = png::Filter::Up;

/// EXR encoding: ZIP over blocks of 16 scan lines, lossless and compressed in parallel.
const EXR_ENCODING: Encoding = Encoding::SMALL_LOSSLESS;

/// Loads a grey image (a height map) from a PNG (8 or 16 bit), JPEG, BMP, TGA or TIFF (integer or 32-bit
/// float) file, recognised by its content, else by its extension, or from OpenEXR by extension.
///
/// Values are the stored ones scaled to [0, 1] (8-bit / 255, 16-bit / 65535; float samples
/// as stored), with no sRGB decoding. Colour pixels become
/// 0.2126 R + 0.7152 G + 0.0722 B (Rec. 709 luma) of the stored values; alpha is ignored. An EXR file's
/// grey is its one channel, else Y, else Z (a depth AOV), else the luma of R, G, B; its non-finite samples
/// (a depth AOV's background is NaN) read as its largest finite one, the farthest depth.
pub fn load_grey(path: &Path) -> Result<GreyImage> {
    if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("exr")) {
        return load_exr_grey(path);
    }
    if let Some(grey) = load_tiff_grey_f32(path) {
        return grey;
    }
    // Grey f32 out; colour types without flat samples of their own go through RGB f32 first.
    let img = decode(path, |c| {
        if matches!(c, ColorType::L8 | ColorType::L16 | ColorType::Rgb8 | ColorType::Rgba8) {
            4
        } else {
            16
        }
    })?;
    let channels = usize::from(img.color().channel_count());
    let pixels = if let Some(s) = img.as_flat_samples_u8() {
        grey_pixels(s.samples, channels, 255.0)
    } else if let Some(s) = img.as_flat_samples_u16() {
        grey_pixels(s.samples, channels, 65535.0)
    } else if let Some(s) = img.as_flat_samples_f32() {
        grey_pixels(s.samples, channels, 1.0)
    } else {
        grey_pixels(img.to_rgb32f().as_raw(), 3, 1.0)
    };
    Ok(Image { width: img.width() as usize, height: img.height() as usize, pixels })
}

/// Loads a colour texture as RGBA bytes as stored (sRGB-encoded, not decoded), from the same
/// formats as [`load_grey`]. 16-bit samples are rounded to 8 bits, grey is copied to R, G and B,
/// and alpha is 255 where the file has none.
pub fn load_rgba8(path: &Path) -> Result<Image<[u8; 4]>> {
    let rgba = decode(path, |_| 8)?.into_rgba8();
    let (width, height) = (rgba.width() as usize, rgba.height() as usize);
    let pixels = rgba.pixels().map(|p| p.0).collect();
    Ok(Image { width, height, pixels })
}

/// A colour texture's texels as its file holds them: 8-bit bytes as stored (still sRGB-encoded where they
/// are), or anything deeper already in linear light.
pub enum Texels {
    Rgba8(Image<[u8; 4]>),
    Linear(Image<[f32; 4]>),
}

/// Loads a colour texture from 8-bit, 16-bit or float images (the formats of [`load_grey`], and OpenEXR by
/// extension). 8-bit images come back as bytes; with `srgb`, 16-bit colour channels are decoded from sRGB to
/// linear; float images are linear already. Alpha is never decoded; it is opaque where the file has none.
pub fn load_texels(path: &Path, srgb: bool) -> Result<Texels> {
    Ok(load_texture_file(path, srgb)?.texels)
}

/// A texture's texels, whether its file has an alpha channel (OpenGL's RGBA base format, not RGB), and the
/// coarser levels a multi-resolution file brings (linear RGBA, level 1 first; empty for most files).
pub struct TextureFile {
    pub texels: Texels,
    pub alpha: bool,
    pub levels: Vec<Image<[f32; 4]>>,
}

/// [`load_texels`], whether the file has an alpha channel, and its own coarser levels where it is
/// MIP-mapped (`super::levels::read_levels`).
pub fn load_texture_file(path: &Path, srgb: bool) -> Result<TextureFile> {
    if let Some(file) = super::levels::read_levels(path, srgb)? {
        let mut levels = file.levels.into_iter();
        let base = levels.next().expect("a file's levels start with level 0");
        return Ok(TextureFile { texels: Texels::Linear(base), alpha: file.alpha, levels: levels.collect() });
    }
    if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("exr")) {
        let (image, alpha) = load_exr_rgba(path)?;
        return Ok(TextureFile { texels: Texels::Linear(image), alpha, levels: Vec::new() });
    }
    if let Some(grey) = load_tiff_grey_f32(path) {
        let grey = grey?;
        let pixels = grey.pixels.iter().map(|&g| [g, g, g, 1.0]).collect();
        let texels = Texels::Linear(Image { width: grey.width, height: grey.height, pixels });
        return Ok(TextureFile { texels, alpha: false, levels: Vec::new() });
    }
    // RGBA bytes (twice: converted, then collected), or RGBA f32 (likewise), or 16-bit then f32.
    let img = decode(path, |c| match c.bytes_per_pixel() / c.channel_count() {
        1 => 8,
        2 => 24,
        _ => 32,
    })?;
    let (width, height) = (img.width() as usize, img.height() as usize);
    let float = matches!(img.color(), ColorType::Rgb32F | ColorType::Rgba32F);
    let alpha = img.color().has_alpha();
    let texels = if float {
        Texels::Linear(Image { width, height, pixels: img.into_rgba32f().pixels().map(|p| p.0).collect() })
    } else if img.color().bytes_per_pixel() / img.color().channel_count() == 1 {
        Texels::Rgba8(Image { width, height, pixels: img.into_rgba8().pixels().map(|p| p.0).collect() })
    } else {
        let table: Vec<f32> = (0..=65535u32)
            .map(|i| {
                let v = i as f32 / 65535.0;
                if srgb {
                    super::color::srgb_to_linear(v)
                } else {
                    v
                }
            })
            .collect();
        let pixels = img
            .into_rgba16()
            .pixels()
            .map(|p| [table[p[0] as usize], table[p[1] as usize], table[p[2] as usize], p[3] as f32 / 65535.0])
            .collect();
        Texels::Linear(Image { width, height, pixels })
    };
    Ok(TextureFile { texels, alpha, levels: Vec::new() })
}

/// A colour texture in linear light as RGBA f32: [`load_texels`] with 8-bit texels decoded too.
pub fn load_rgba_linear(path: &Path, srgb: bool) -> Result<Image<[f32; 4]>> {
    Ok(load_texels(path, srgb)?.into_linear(srgb))
}

impl Texels {
    /// The texels in linear RGBA f32: 8-bit ones decoded (from sRGB with `srgb`), float ones as they are.
    pub fn into_linear(self, srgb: bool) -> Image<[f32; 4]> {
        match self {
            Texels::Linear(image) => image,
            Texels::Rgba8(image) => {
                let pixels = super::color::decode_rgba8(&image.pixels, srgb);
                Image { width: image.width, height: image.height, pixels }
            }
        }
    }
}

/// A grey 32-bit float TIFF (what GIMP and Krita write for a float height map), which the image crate
/// refuses; `None` for any other file, left to the image crate.
fn load_tiff_grey_f32(path: &Path) -> Option<Result<GreyImage>> {
    let file = open_input(path).ok()?;
    let mut decoder = tiff::decoder::Decoder::new(BufReader::new(file)).ok()?;
    if decoder.colortype().ok()? != tiff::ColorType::Gray(32) {
        return None;
    }
    let mut read = || -> std::result::Result<GreyImage, String> {
        let (w, h) = decoder.dimensions().map_err(|e| e.to_string())?;
        check_size(w as usize, h as usize)?;
        limits::reserve(u64::from(w) * u64::from(h) * 8, || format!("decoding its {w}x{h} pixels"))
            .map_err(|e| e.to_string())?;
        match decoder.read_image().map_err(|e| format!("malformed TIFF: {e}"))? {
            tiff::decoder::DecodingResult::F32(pixels) if pixels.len() == w as usize * h as usize => {
                Ok(Image { width: w as usize, height: h as usize, pixels })
            }
            _ => Err("a grey TIFF of 32-bit samples that are not floats, or of the wrong count".into()),
        }
    };
    Some(read().map_err(|m| Error::read(path, m)))
}

/// The grey of an OpenEXR file, as `load_grey` describes it.
fn load_exr_grey(path: &Path) -> Result<GreyImage> {
    let (width, height, channels) = read_exr_channels(path)?;
    let find = |name: &str| channels.iter().find(|(n, _)| n == name).map(|(_, v)| v.clone());
    let mut pixels = match (channels.len(), find("Y").or_else(|| find("Z")), find("R"), find("G"), find("B")) {
        (1, _, _, _, _) => channels[0].1.clone(),
        (_, Some(grey), _, _, _) => grey,
        (_, None, Some(r), Some(g), Some(b)) => {
            (0..width * height).map(|k| LUMA[0] * r[k] + LUMA[1] * g[k] + LUMA[2] * b[k]).collect()
        }
        _ => return Err(Error::read(path, "expected one channel, or Y, Z, or R, G, B")),
    };
    let far = pixels.iter().copied().filter(|v| v.is_finite()).fold(f32::NEG_INFINITY, f32::max);
    if far == f32::NEG_INFINITY {
        return Err(Error::read(path, "has no finite sample"));
    }
    pixels.iter_mut().filter(|v| !v.is_finite()).for_each(|v| *v = far);
    Ok(Image { width, height, pixels })
}

/// R, G, B (and A when present) of an OpenEXR file; a single channel (Y or any name) is grey.
fn load_exr_rgba(path: &Path) -> Result<(Image<[f32; 4]>, bool)> {
    let (width, height, channels) = read_exr_channels(path)?;
    let find = |name: &str| channels.iter().find(|(n, _)| n == name).map(|(_, v)| v);
    let (r, g, b) = match (find("R"), find("G"), find("B")) {
        (Some(r), Some(g), Some(b)) => (r, g, b),
        _ if channels.len() == 1 => (&channels[0].1, &channels[0].1, &channels[0].1),
        _ => return Err(Error::read(path, "expected channels R, G, B (or a single grey channel)")),
    };
    let a = find("A");
    let pixels = (0..width * height).map(|k| [r[k], g[k], b[k], a.map_or(1.0, |a| a[k])]).collect();
    Ok((Image { width, height, pixels }, a.is_some()))
}

/// Writes a Radiance HDR (RGBE) file from linear `rgb`, 3 floats per pixel, row 0 at the top.
pub fn write_hdr(path: &Path, width: usize, height: usize, rgb: &[f32]) -> Result<()> {
    let pixels: Vec<::image::Rgb<f32>> = rgb.chunks_exact(3).map(|p| ::image::Rgb([p[0], p[1], p[2]])).collect();
    write_atomic(path, |out| {
        ::image::codecs::hdr::HdrEncoder::new(out).encode(&pixels, width, height).map_err(|e| Error::write(path, e))
    })
}

/// The PNG colour type of 1 (grey), 2 (grey and alpha), 3 (RGB) or 4 (RGBA) channels.
fn png_colour(path: &Path, channels: usize) -> Result<png::ColorType> {
    use png::ColorType::*;
    [Grayscale, GrayscaleAlpha, Rgb, Rgba]
        .get(channels.wrapping_sub(1))
        .copied()
        .ok_or_else(|| invalid(path, format!("a PNG holds 1 to 4 channels, not {channels}")))
}

/// Writes an 8-bit PNG of 1 to 4 channels (grey, grey and alpha, RGB, RGBA) from `samples` as stored, row 0 at
/// the top.
pub fn write_png8(path: &Path, width: usize, height: usize, channels: usize, samples: &[u8]) -> Result<()> {
    write_atomic(path, |out| encode_png8(out, path, (width, height), channels, samples))
}

/// Encodes an 8-bit PNG of 1 to 4 channels into `out` (a pipe, the standard output), as `write_png8` writes
/// it to a file; errors name `name`.
pub fn encode_png8(
    out: &mut dyn Write,
    name: &Path,
    (width, height): (usize, usize),
    channels: usize,
    samples: &[u8],
) -> Result<()> {
    let colour = png_colour(name, channels)?;
    check_buffer(name, width, height, channels, samples.len())?;
    encode_png(out, name, width, height, colour, png::BitDepth::Eight, samples)
}

/// Writes a 16-bit PNG of 1 to 4 channels from `samples` as stored, row 0 at the top.
pub fn write_png16(path: &Path, width: usize, height: usize, channels: usize, samples: &[u16]) -> Result<()> {
    write_atomic(path, |out| encode_png16(out, path, (width, height), channels, samples))
}

/// Encodes a 16-bit PNG of 1 to 4 channels into `out`, as `write_png16` writes it to a file; errors name
/// `name`.
pub fn encode_png16(
    out: &mut dyn Write,
    name: &Path,
    (width, height): (usize, usize),
    channels: usize,
    samples: &[u16],
) -> Result<()> {
    let colour = png_colour(name, channels)?;
    check_buffer(name, width, height, channels, samples.len())?;
    let bytes: Vec<u8> = samples.iter().flat_map(|v| v.to_be_bytes()).collect();
    encode_png(out, name, width, height, colour, png::BitDepth::Sixteen, &bytes)
}

/// Writes an 8-bit RGB PNG from `rgb`, 3 bytes per pixel, row 0 at the top.
pub fn write_png_rgb8(path: &Path, width: usize, height: usize, rgb: &[u8]) -> Result<()> {
    write_png8(path, width, height, 3, rgb)
}

/// Writes an 8-bit RGBA PNG from `rgba`, 4 bytes per pixel, row 0 at the top.
pub fn write_png_rgba8(path: &Path, width: usize, height: usize, rgba: &[u8]) -> Result<()> {
    write_png8(path, width, height, 4, rgba)
}

/// Writes a 16-bit RGB PNG from `rgb`, 3 values per pixel: clamped to [0, 1], scaled by 65535, rounded.
pub fn write_png_rgb16(path: &Path, width: usize, height: usize, rgb: &[f32]) -> Result<()> {
    check_buffer(path, width, height, 3, rgb.len())?;
    let bytes: Vec<u8> = rgb.iter().flat_map(|&v| quantize(v, 65535.0).to_be_bytes()).collect();
    write_png(path, width, height, png::ColorType::Rgb, png::BitDepth::Sixteen, &bytes)
}

/// Writes a 16-bit grey PNG: values clamped to [0, 1] and scaled by 65535, rounded (NaN gives 0).
pub fn write_png_grey16(path: &Path, img: &GreyImage) -> Result<()> {
    check_buffer(path, img.width, img.height, 1, img.pixels.len())?;
    let bytes: Vec<u8> = img.pixels.iter().flat_map(|&v| quantize(v, 65535.0).to_be_bytes()).collect();
    write_png(path, img.width, img.height, png::ColorType::Grayscale, png::BitDepth::Sixteen, &bytes)
}

/// Writes an 8-bit grey PNG: values clamped to [0, 1] and scaled by 255, rounded (NaN gives 0).
pub fn write_png_grey8(path: &Path, img: &GreyImage) -> Result<()> {
    check_buffer(path, img.width, img.height, 1, img.pixels.len())?;
    let bytes: Vec<u8> = img.pixels.iter().map(|&v| quantize(v, 255.0) as u8).collect();
    write_png(path, img.width, img.height, png::ColorType::Grayscale, png::BitDepth::Eight, &bytes)
}

/// Writes a linear float32 OpenEXR file with one layer holding the named channels
/// (e.g. `[("R", r), ("G", g), ("B", b)]` or `[("Z", depth)]`), each `width * height` samples,
/// row 0 at the top. Compression is ZIP (16 scan lines per block), which is lossless:
/// every value, NaN included, reads back bit for bit.
pub fn write_exr(path: &Path, width: usize, height: usize, channels: &[(&str, &[f32])]) -> Result<()> {
    write_exr_placed(path, Placement::whole(width, height), channels)
}

/// Where an image lies in a larger picture: its pixels are the `width` x `height` starting at (x0, y0),
/// row 0 at the top, of a picture of `full_width` x `full_height` (OpenEXR's data window within its
/// display window).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Placement {
    pub x0: usize,
    pub y0: usize,
    pub width: usize,
    pub height: usize,
    pub full_width: usize,
    pub full_height: usize,
}

impl Placement {
    /// An image that is the whole picture.
    pub fn whole(width: usize, height: usize) -> Placement {
        Placement { x0: 0, y0: 0, width, height, full_width: width, full_height: height }
    }
}

/// `write_exr` of a part of a picture: the file's data window is the part, its display window the picture,
/// so that viewers and compositors put the part in its place.
pub fn write_exr_placed(path: &Path, placement: Placement, channels: &[(&str, &[f32])]) -> Result<()> {
    let samples = channels.iter().map(|&(name, s)| (name, FlatSamples::F32(s.to_vec()))).collect();
    write_exr_samples(path, placement, samples)
}

/// `write_exr` taking the channels' samples over, for data too large to copy.
pub fn write_exr_owned(path: &Path, width: usize, height: usize, channels: Vec<(&str, Vec<f32>)>) -> Result<()> {
    let samples = channels.into_iter().map(|(name, s)| (name, FlatSamples::F32(s))).collect();
    write_exr_samples(path, Placement::whole(width, height), samples)
}

/// `write_exr_placed` with 32-bit unsigned integer channels (indices that f32 would round beyond 2^24).
pub fn write_exr_u32(path: &Path, placement: Placement, channels: &[(&str, &[u32])]) -> Result<()> {
    let samples = channels.iter().map(|&(name, s)| (name, FlatSamples::U32(s.to_vec()))).collect();
    write_exr_samples(path, placement, samples)
}

fn write_exr_samples(path: &Path, at: Placement, channels: Vec<(&str, FlatSamples)>) -> Result<()> {
    let (width, height) = (at.width, at.height);
    check_size(width, height).map_err(|m| invalid(path, m))?;
    let fits = |x0: usize, w: usize, full: usize| x0.checked_add(w).is_some_and(|end| end <= full);
    if !fits(at.x0, width, at.full_width)
        || !fits(at.y0, height, at.full_height)
        || at.full_width > i32::MAX as usize
        || at.full_height > i32::MAX as usize
    {
        return Err(invalid(
            path,
            format!(
                "the part {width}x{height} at ({}, {}) is not inside the {}x{} picture",
                at.x0, at.y0, at.full_width, at.full_height
            ),
        ));
    }
    let list = channels
        .into_iter()
        .map(|(name, samples)| exr_channel(path, name, samples, width * height))
        .collect::<Result<_>>()?;
    let channels = AnyChannels::sort(list);
    check_channel_names(path, &channels)?;
    let attributes = LayerAttributes { layer_position: Vec2(at.x0 as i32, at.y0 as i32), ..LayerAttributes::default() };
    let layer = Layer::new((width, height), attributes, EXR_ENCODING, channels);
    let mut image = exr::prelude::Image::from_layer(layer);
    image.attributes.display_window = IntegerBounds::new((0, 0), (at.full_width, at.full_height));
    let mut bytes = Cursor::new(Vec::new());
    image.write().to_buffered(&mut bytes).map_err(|e| Error::write(path, e))?;
    write_atomic(path, |out| out.write_all(bytes.get_ref()).map_err(|e| Error::write(path, e)))
}

/// The header of an OpenEXR file's first layer, read without its pixels.
pub(crate) fn first_exr_header(path: &Path) -> Result<exr::meta::header::Header> {
    let meta = exr::meta::MetaData::read_from_buffered(BufReader::new(open_input(path)?), false)
        .map_err(|e| exr_read_error(path, e))?;
    meta.headers.into_iter().next().ok_or_else(|| Error::read(path, "not a valid OpenEXR file: it has no layer"))
}

/// Where the first layer of an OpenEXR file lies: its data window within its display window.
pub fn read_exr_placement(path: &Path) -> Result<Placement> {
    let header = first_exr_header(path)?;
    let display = header.shared_attributes.display_window;
    let position = header.own_attributes.layer_position;
    let (x0, y0) = (position.x() - display.position.x(), position.y() - display.position.y());
    if x0 < 0 || y0 < 0 {
        return Err(Error::read(path, "its data window starts outside its display window"));
    }
    Ok(Placement {
        x0: x0 as usize,
        y0: y0 as usize,
        width: header.layer_size.width(),
        height: header.layer_size.height(),
        full_width: display.size.width(),
        full_height: display.size.height(),
    })
}

/// Reads every channel of the first layer of an OpenEXR file as `(width, height, [(name, samples)])`,
/// channels in the file's (alphabetical) order, samples row by row from the top.
/// Half-float and integer channels are converted to f32.
#[allow(clippy::type_complexity)] // the tuple is the documented interface
pub fn read_exr_channels(path: &Path) -> Result<(usize, usize, Vec<(String, Vec<f32>)>)> {
    let header = first_exr_header(path)?;
    let (width, height) = (header.layer_size.width(), header.layer_size.height());
    check_size(width, height).map_err(|m| Error::read(path, m))?;
    // Samples are decoded at their stored width, then widened to f32.
    let bytes_per_pixel: usize = header.channels.list.iter().map(|c| c.sample_type.bytes_per_sample() + 4).sum();
    limits::reserve((width * height * bytes_per_pixel) as u64, || {
        format!("{}: decoding its {width}x{height} pixels", path.display())
    })?;
    let image = exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .map_err(|e| exr_read_error(path, e))?;
    let layer = image.layer_data;
    let channels =
        layer.channel_data.list.into_iter().map(|c| (c.name.to_string(), samples_f32(c.sample_data))).collect();
    Ok((layer.size.width(), layer.size.height(), channels))
}

/// Opens and decodes an image file, refusing empty, oversized and cut-short images before decoding pixels,
/// and images whose decoding, with `converted_per_pixel(colour type)` more bytes per pixel for the caller's
/// conversion, would not fit in the memory budget.
pub(crate) fn decode(path: &Path, converted_per_pixel: impl FnOnce(ColorType) -> u64) -> Result<DynamicImage> {
    let mut reader = ImageReader::new(BufReader::new(open_input(path)?));
    if let Ok(format) = ImageFormat::from_path(path) {
        reader.set_format(format);
    }
    let mut reader = reader.with_guessed_format().map_err(|e| Error::read(path, open_message(&e)))?;
    let format = reader.format();
    // Sizes are checked against the limits below, memory against the budget: no byte limit beyond those.
    reader.no_limits();
    let decoder = reader.into_decoder().map_err(|e| decode_error(path, format, e))?;
    let (width, height) = decoder.dimensions();
    check_size(width as usize, height as usize).map_err(|m| Error::read(path, m))?;
    if format == Some(ImageFormat::Jpeg) {
        check_jpeg_complete(path)?;
    }
    let pixels = u64::from(width) * u64::from(height);
    let converted = converted_per_pixel(decoder.color_type());
    limits::reserve(decoder.total_bytes() + pixels * converted, || {
        format!("{}: decoding its {width}x{height} pixels", path.display())
    })?;
    DynamicImage::from_decoder(decoder).map_err(|e| decode_error(path, format, e))
}

/// Opens an input file, refusing anything but a regular file: reading a FIFO or a device could block
/// forever or never end.
pub fn open_input(path: &Path) -> Result<File> {
    check_input(path)?;
    File::open(path).map_err(|e| Error::read(path, open_message(&e)))
}

/// `Ok` if `path` names a regular file (through any symlinks), else a read error saying what it is.
pub fn check_input(path: &Path) -> Result<()> {
    if path.as_os_str().is_empty() {
        return Err(Error::Invalid("an input file name is empty".into()));
    }
    let meta = fs::metadata(path).map_err(|e| Error::read(path, open_message(&e)))?;
    if meta.is_dir() {
        Err(Error::read(path, "is a folder, not a file"))
    } else if !meta.is_file() {
        Err(Error::read(path, "not a regular file (a FIFO, socket or device cannot be read as an input)"))
    } else {
        Ok(())
    }
}

/// A JPEG cut short has no end-of-image marker after its last scan; the decoder would fill the missing
/// rows in silently, so a small cut file could pose as a huge image. Marker bytes cannot occur inside
/// entropy-coded data (an 0xFF there is always followed by 0x00 or a restart marker), so a byte search
/// finds them.
fn check_jpeg_complete(path: &Path) -> Result<()> {
    let bytes = fs::read(path).map_err(|e| Error::read(path, open_message(&e)))?;
    let last_scan = bytes.windows(2).rposition(|m| m == [0xFF, 0xDA]);
    match last_scan {
        Some(at) if bytes[at..].windows(2).any(|m| m == [0xFF, 0xD9]) => Ok(()),
        _ => Err(Error::read(path, "truncated or corrupt JPEG: no end-of-image marker after its last scan")),
    }
}

/// Grey values from interleaved samples with `channels` per pixel, divided by `full_scale`.
fn grey_pixels<S: Copy + Into<f32>>(samples: &[S], channels: usize, full_scale: f32) -> Vec<f32> {
    samples
        .chunks_exact(channels)
        .map(|p| {
            let grey = if channels >= 3 {
                LUMA[0] * p[0].into() + LUMA[1] * p[1].into() + LUMA[2] * p[2].into()
            } else {
                p[0].into()
            };
            grey / full_scale
        })
        .collect()
}

/// `Ok` if `width` x `height` is a usable image size within the limits on image files (a small file
/// claiming a huge size must not make a reader allocate many gigabytes), else what is wrong with it.
pub fn check_size(width: usize, height: usize) -> std::result::Result<(), String> {
    let (side, pixels) = (Limit::ImageSide.count(), Limit::ImagePixels.count());
    if width == 0 || height == 0 {
        Err(format!("image is {width}x{height}, it has no pixels"))
    } else if width > side || height > side {
        Err(format!("image is {width}x{height} pixels, larger than the {side} limit ({})", Limit::ImageSide.hint()))
    } else if width.saturating_mul(height) > pixels {
        Err(format!(
            "image is {width}x{height} pixels, more than the {pixels} pixel limit ({})",
            Limit::ImagePixels.hint()
        ))
    } else {
        Ok(())
    }
}

/// Checks an image size and that a buffer holds exactly its `width * height * per_pixel` samples.
fn check_buffer(path: &Path, width: usize, height: usize, per_pixel: usize, len: usize) -> Result<()> {
    check_size(width, height).map_err(|m| invalid(path, m))?;
    let expected = width * height * per_pixel;
    if len == expected {
        Ok(())
    } else {
        Err(invalid(path, format!("{width}x{height} image needs {expected} samples, got {len}")))
    }
}

fn invalid(path: &Path, message: impl std::fmt::Display) -> Error {
    Error::Invalid(format!("{}: {message}", path.display()))
}

/// A value clamped to [0, 1] as an integer in 0..=max, rounded; NaN gives 0.
fn quantize(value: f32, max: f32) -> u16 {
    (value.clamp(0.0, 1.0) * max).round() as u16
}

fn write_png(
    path: &Path,
    width: usize,
    height: usize,
    color: png::ColorType,
    depth: png::BitDepth,
    data: &[u8],
) -> Result<()> {
    write_atomic(path, |out| encode_png(out, path, width, height, color, depth, data))
}

fn encode_png(
    out: &mut dyn Write,
    path: &Path,
    width: usize,
    height: usize,
    color: png::ColorType,
    depth: png::BitDepth,
    data: &[u8],
) -> Result<()> {
    let png_error = |e: png::EncodingError| Error::write(path, e);
    // Sizes were checked against the side limit (at most 2^20), so they fit in u32.
    let mut encoder = png::Encoder::new(out, width as u32, height as u32);
    encoder.set_color(color);
    encoder.set_depth(depth);
    encoder.set_compression(png::Compression::Fast);
    encoder.set_filter(PNG_FILTER);
    let mut writer = encoder.write_header().map_err(png_error)?;
    writer.write_image_data(data).map_err(png_error)?;
    writer.finish().map_err(png_error)
}

pub(crate) fn open_message(e: &io::Error) -> String {
    match e.kind() {
        io::ErrorKind::NotFound => "no such file".to_string(),
        _ => format!("cannot read: {e}"),
    }
}

/// A one-line read error for a failure of the `image` crate, naming the format it was read as.
pub(crate) fn decode_error(path: &Path, format: Option<ImageFormat>, e: ImageError) -> Error {
    let name = format.map_or("image", format_name);
    let message = match e {
        ImageError::Unsupported(_) if format.is_none() => NOT_SUPPORTED.to_string(),
        ImageError::Unsupported(u) if name == "image" => format!("{NOT_SUPPORTED}: {u}"),
        ImageError::Unsupported(u) => format!("unsupported kind of {name}: {u}"),
        ImageError::Decoding(d) => match std::error::Error::source(&d) {
            Some(cause) => format!("truncated or corrupt {name}: {cause}"),
            None => format!("truncated or corrupt {name}"),
        },
        ImageError::IoError(io) if io.kind() == io::ErrorKind::UnexpectedEof => {
            format!("truncated or corrupt {name}: unexpected end of file")
        }
        ImageError::IoError(io) => format!("cannot read: {io}"),
        other => other.to_string(),
    };
    Error::read(path, message)
}

fn format_name(format: ImageFormat) -> &'static str {
    match format {
        ImageFormat::Png => "PNG",
        ImageFormat::Jpeg => "JPEG",
        ImageFormat::Bmp => "BMP",
        ImageFormat::Tga => "TGA",
        ImageFormat::Tiff => "TIFF",
        _ => "image",
    }
}

/// One EXR channel from a slice that must hold exactly `len` samples.
fn exr_channel(path: &Path, name: &str, samples: FlatSamples, len: usize) -> Result<AnyChannel<FlatSamples>> {
    if samples.len() != len {
        return Err(invalid(path, format!("EXR channel {name:?} has {} samples, expected {len}", samples.len())));
    }
    let text = Some(name)
        .filter(|n| !n.is_empty())
        .and_then(Text::new_or_none)
        .ok_or_else(|| invalid(path, format!("{name:?} is not a valid EXR channel name")))?;
    Ok(AnyChannel::new(text, samples))
}

/// Refuses an empty channel list and repeated names (`channels` is sorted by name).
fn check_channel_names(path: &Path, channels: &AnyChannels<FlatSamples>) -> Result<()> {
    if channels.list.is_empty() {
        return Err(invalid(path, "an EXR file needs at least one channel"));
    }
    match channels.list.windows(2).find(|pair| pair[0].name == pair[1].name) {
        Some(pair) => Err(invalid(path, format!("EXR channel {:?} is given twice", pair[0].name.to_string()))),
        None => Ok(()),
    }
}

fn exr_read_error(path: &Path, e: exr::error::Error) -> Error {
    match e {
        exr::error::Error::Io(io) if io.kind() == io::ErrorKind::UnexpectedEof => {
            Error::read(path, "truncated OpenEXR file")
        }
        exr::error::Error::Io(io) => Error::read(path, open_message(&io)),
        other => Error::read(path, format!("not a valid OpenEXR file: {other}")),
    }
}

fn samples_f32(samples: FlatSamples) -> Vec<f32> {
    match samples {
        FlatSamples::F32(values) => values,
        other => other.values_as_f32().collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::super::scratch::Scratch;
    use super::*;

    fn read_message(result: Result<impl std::fmt::Debug>, expected_path: &Path) -> String {
        match result {
            Err(Error::Read { path, message }) => {
                assert_eq!(path, expected_path);
                message
            }
            other => panic!("expected a read error, got {other:?}"),
        }
    }

    fn invalid_message(result: Result<()>) -> String {
        match result {
            Err(Error::Invalid(message)) => message,
            other => panic!("expected an invalid-parameter error, got {other:?}"),
        }
    }

    /// Deterministic bytes that do not compress well.
    fn noise_bytes(len: usize) -> Vec<u8> {
        let mut state = 0x1234_5678u32;
        (0..len)
            .map(|_| {
                state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                (state >> 24) as u8
            })
            .collect()
    }

    #[test]
    fn grey8_round_trip_is_exact() {
        let dir = Scratch::new("grey8");
        let path = dir.path("h.png");
        let img = Image::from_fn(256, 3, |x, y| ((x + 85 * y) % 256) as f32 / 255.0);
        write_png_grey8(&path, &img).unwrap();
        assert_eq!(load_grey(&path).unwrap(), img);
        assert_eq!(dir.entries(), ["h.png"]);
    }

    #[test]
    fn grey8_clamps_and_rounds() {
        let dir = Scratch::new("grey8q");
        let path = dir.path("q.png");
        let img = Image { width: 5, height: 1, pixels: vec![-0.5, 0.4 / 255.0, 0.6 / 255.0, 2.0, f32::NAN] };
        write_png_grey8(&path, &img).unwrap();
        assert_eq!(load_grey(&path).unwrap().pixels, [0.0, 0.0, 1.0 / 255.0, 1.0, 0.0]);
    }

    #[test]
    fn grey16_round_trip_is_exact() {
        let dir = Scratch::new("grey16");
        let path = dir.path("h16.png");
        // Both ends of the range and a spread of codes in between.
        let code = |i: usize| match i {
            0 => 0,
            599 => 65535,
            _ => (i * 109 + 7) % 65536,
        };
        let img = Image::from_fn(300, 2, |x, y| code(x + 300 * y) as f32 / 65535.0);
        write_png_grey16(&path, &img).unwrap();
        assert_eq!(load_grey(&path).unwrap(), img);
    }

    #[test]
    fn colour_to_grey_uses_rec709_weights_on_stored_values() {
        let dir = Scratch::new("luma");
        let path = dir.path("rgb.png");
        let rgb = [255, 0, 0, 0, 255, 0, 0, 0, 255, 10, 200, 30];
        write_png_rgb8(&path, 2, 2, &rgb).unwrap();
        let grey = load_grey(&path).unwrap();
        let mixed = (0.2126 * 10.0 + 0.7152 * 200.0 + 0.0722 * 30.0) / 255.0;
        for (got, want) in grey.pixels.iter().zip([0.2126, 0.7152, 0.0722, mixed]) {
            assert!((got - want).abs() < 1e-6, "{got} vs {want}");
        }
        let rgba = load_rgba8(&path).unwrap();
        assert_eq!((rgba.width, rgba.height), (2, 2));
        assert_eq!(rgba.pixels, [[255, 0, 0, 255], [0, 255, 0, 255], [0, 0, 255, 255], [10, 200, 30, 255]]);
    }

    #[test]
    fn alpha_is_ignored_for_grey_and_kept_for_rgba() {
        let dir = Scratch::new("alpha");
        let path = dir.path("rgba.png");
        write_png(&path, 1, 1, png::ColorType::Rgba, png::BitDepth::Eight, &[100, 100, 100, 0]).unwrap();
        assert_eq!(load_grey(&path).unwrap().pixels, [100.0 / 255.0]);
        assert_eq!(load_rgba8(&path).unwrap().pixels, [[100, 100, 100, 0]]);
    }

    #[test]
    fn rgba8_from_grey16_rounds_and_expands() {
        let dir = Scratch::new("rgba16");
        let path = dir.path("g16.png");
        let img = Image { width: 4, height: 1, pixels: vec![0.0, 32896.0 / 65535.0, 1.0, 300.0 / 65535.0] };
        write_png_grey16(&path, &img).unwrap();
        let rgba = load_rgba8(&path).unwrap();
        assert_eq!(rgba.pixels, [[0, 0, 0, 255], [128, 128, 128, 255], [255, 255, 255, 255], [1, 1, 1, 255]]);
    }

    #[test]
    fn formats_are_detected_by_content_then_extension() {
        let dir = Scratch::new("formats");
        let rgb = [10, 20, 30, 40, 50, 60, 70, 80, 90, 200, 210, 220];
        // A BMP named .png is found by its signature; TGA has none, so its extension decides.
        for (name, format) in
            [("bmp-really.png", ImageFormat::Bmp), ("t.tga", ImageFormat::Tga), ("t.tif", ImageFormat::Tiff)]
        {
            let path = dir.path(name);
            ::image::save_buffer_with_format(&path, &rgb, 2, 2, ::image::ExtendedColorType::Rgb8, format).unwrap();
            let rgba = load_rgba8(&path).unwrap();
            let want: Vec<[u8; 4]> = rgb.chunks(3).map(|p| [p[0], p[1], p[2], 255]).collect();
            assert_eq!(rgba.pixels, want, "{name}");
            let grey = load_grey(&path).unwrap();
            assert!((grey.pixels[3] - (0.2126 * 200.0 + 0.7152 * 210.0 + 0.0722 * 220.0) / 255.0).abs() < 1e-6);
        }
        let path = dir.path("flat.jpg");
        ::image::save_buffer_with_format(
            &path,
            &[77; 16 * 8],
            16,
            8,
            ::image::ExtendedColorType::L8,
            ImageFormat::Jpeg,
        )
        .unwrap();
        let grey = load_grey(&path).unwrap();
        assert_eq!((grey.width, grey.height), (16, 8));
        assert!(grey.pixels.iter().all(|&v| (v - 77.0 / 255.0).abs() <= 2.0 / 255.0));
    }

    #[test]
    fn truncated_png_is_a_read_error_naming_the_file() {
        let dir = Scratch::new("truncated");
        let path = dir.path("cut.png");
        write_png(&path, 64, 64, png::ColorType::Grayscale, png::BitDepth::Eight, &noise_bytes(64 * 64)).unwrap();
        let bytes = fs::read(&path).unwrap();
        fs::write(&path, &bytes[..bytes.len() / 2]).unwrap();
        let err = load_grey(&path).unwrap_err();
        assert!(err.to_string().contains("cut.png"), "{err}");
        let message = read_message(Err::<(), _>(err), &path);
        assert!(message.starts_with("truncated or corrupt PNG"), "{message}");
        let message = read_message(load_rgba8(&path), &path);
        assert!(message.starts_with("truncated or corrupt PNG"), "{message}");
    }

    #[test]
    fn missing_and_unknown_files_say_what_is_wrong() {
        let dir = Scratch::new("unknown");
        let missing = dir.path("missing.png");
        assert_eq!(read_message(load_grey(&missing), &missing), "no such file");
        let notes = dir.path("notes.xyz");
        fs::write(&notes, "hello, this is not an image").unwrap();
        assert_eq!(read_message(load_grey(&notes), &notes), NOT_SUPPORTED);
        assert_eq!(read_message(load_rgba8(&notes), &notes), NOT_SUPPORTED);
        let fake = dir.path("fake.png");
        fs::write(&fake, "hello, this is not an image").unwrap();
        assert!(read_message(load_grey(&fake), &fake).starts_with("truncated or corrupt PNG: "));
    }

    #[test]
    fn empty_and_oversized_images_are_refused() {
        let dir = Scratch::new("sizes");
        assert_eq!(check_size(0, 0).unwrap_err(), "image is 0x0, it has no pixels");
        let out = dir.path("out.png");
        assert!(invalid_message(write_png_grey8(&out, &Image::new(0, 0, 0.0))).contains("0x0"));
        assert!(invalid_message(write_png_rgb8(&out, 0, 4, &[])).contains("0x4"));
        let wide = Image::new(32769, 1, 0.5);
        assert!(invalid_message(write_png_grey16(&out, &wide)).contains("larger than the 32768 limit"));
        assert!(invalid_message(write_png_rgb8(&out, 2, 2, &[0; 11])).contains("needs 12 samples, got 11"));
        assert!(dir.entries().is_empty());

        // A 0x0 TGA header: refused on reading (here by the decoder itself).
        let empty = dir.path("empty.tga");
        let mut header = [0u8; 18];
        header[2] = 3; // uncompressed grey
        header[16] = 8; // bits per pixel
        fs::write(&empty, header).unwrap();
        read_message(load_grey(&empty), &empty);

        // A valid 40000x1 PNG is refused before its pixels are decoded.
        let huge = dir.path("huge.png");
        write_png(&huge, 40000, 1, png::ColorType::Grayscale, png::BitDepth::Eight, &vec![0; 40000]).unwrap();
        assert_eq!(
            read_message(load_grey(&huge), &huge),
            "image is 40000x1 pixels, larger than the 32768 limit (raise it with --limit image-side=N)"
        );
    }

    #[test]
    fn float_tiffs_load_as_height_maps_and_colour_textures() {
        use tiff::encoder::{colortype, TiffEncoder};
        let dir = Scratch::new("float-tiff");
        let grey: Vec<f32> = vec![0.0, 0.25, 1.5, -2.0, 1e-3, 7.0];
        let rgb: Vec<f32> = (0..18).map(|i| i as f32 * 0.125 - 0.5).collect();
        let write = |name: &str, f: &dyn Fn(&mut TiffEncoder<File>)| {
            let path = dir.path(name);
            f(&mut TiffEncoder::new(File::create(&path).unwrap()).unwrap());
            path
        };
        let grey_path = write("g.tif", &|e| e.write_image::<colortype::Gray32Float>(3, 2, &grey).unwrap());
        let rgb_path = write("c.tif", &|e| e.write_image::<colortype::RGB32Float>(3, 2, &rgb).unwrap());
        assert_eq!(load_grey(&grey_path).unwrap().pixels, grey);
        for (path, want) in [
            (&grey_path, grey.iter().map(|&g| [g, g, g, 1.0]).collect::<Vec<_>>()),
            (&rgb_path, rgb.chunks(3).map(|c| [c[0], c[1], c[2], 1.0]).collect()),
        ] {
            match load_texels(path, true).unwrap() {
                Texels::Linear(image) => assert_eq!(image.pixels, want, "{}", path.display()),
                Texels::Rgba8(_) => panic!("{}: float texels came back as bytes", path.display()),
            }
        }
        let luma: Vec<f32> = rgb.chunks(3).map(|c| LUMA[0] * c[0] + LUMA[1] * c[1] + LUMA[2] * c[2]).collect();
        for (got, want) in load_grey(&rgb_path).unwrap().pixels.iter().zip(&luma) {
            assert!((got - want).abs() < 1e-6, "{got} vs {want}");
        }
    }

    #[test]
    fn a_jpeg_cut_short_is_refused_though_its_decoder_would_fill_it_in() {
        let dir = Scratch::new("cut-jpeg");
        let path = dir.path("cut.jpg");
        let pixels = noise_bytes(256 * 256);
        ::image::save_buffer_with_format(&path, &pixels, 256, 256, ::image::ExtendedColorType::L8, ImageFormat::Jpeg)
            .unwrap();
        assert_eq!(load_grey(&path).unwrap().width, 256);
        let bytes = fs::read(&path).unwrap();
        fs::write(&path, &bytes[..bytes.len() / 2]).unwrap();
        let message = read_message(load_grey(&path), &path);
        assert_eq!(message, "truncated or corrupt JPEG: no end-of-image marker after its last scan");
        read_message(load_rgba8(&path), &path);
        // Bytes after the end-of-image marker (a camera's trailer) are allowed.
        let mut trailer = bytes.clone();
        trailer.extend_from_slice(b"trailing data");
        fs::write(&path, &trailer).unwrap();
        assert_eq!(load_grey(&path).unwrap().height, 256);
    }

    #[test]
    fn inputs_that_are_not_regular_files_are_refused_without_blocking() {
        let dir = Scratch::new("special");
        let fifo = dir.path("pipe.png");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status().is_ok_and(|s| s.success());
        assert!(made, "mkfifo failed");
        assert!(read_message(load_grey(&fifo), &fifo).starts_with("not a regular file"));
        assert!(read_message(load_texels(&fifo, true).map(|_| ()), &fifo).starts_with("not a regular file"));
        assert!(read_message(read_exr_channels(&fifo), &fifo).starts_with("not a regular file"));
        assert_eq!(read_message(load_grey(&dir.0), &dir.0), "is a folder, not a file");
        assert!(matches!(load_grey(Path::new("")), Err(Error::Invalid(m)) if m == "an input file name is empty"));
    }

    #[test]
    fn exr_round_trip_is_bit_exact_with_nan() {
        let dir = Scratch::new("exr");
        let path = dir.path("aov.exr");
        let (width, height) = (5, 3);
        let special = [f32::NAN, f32::from_bits(0x7fc0_1234), f32::INFINITY, f32::NEG_INFINITY, -0.0, 1e-40, f32::MAX];
        let z: Vec<f32> = (0..15).map(|i| special.get(i).copied().unwrap_or(i as f32 * 0.25)).collect();
        let r: Vec<f32> = (0..15).map(|i| i as f32 / 7.0).collect();
        let g: Vec<f32> = (0..15).map(|i| -(i as f32) * 1e3).collect();
        write_exr(&path, width, height, &[("Z", &z), ("R", &r), ("G", &g)]).unwrap();
        assert_eq!(dir.entries(), ["aov.exr"]);

        let (w, h, channels) = read_exr_channels(&path).unwrap();
        assert_eq!((w, h), (width, height));
        let names: Vec<&str> = channels.iter().map(|(name, _)| name.as_str()).collect();
        assert_eq!(names, ["G", "R", "Z"]);
        let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        for (name, want) in [("G", &g), ("R", &r), ("Z", &z)] {
            let got = &channels.iter().find(|(n, _)| n == name).unwrap().1;
            assert_eq!(bits(got), bits(want), "channel {name}");
        }
    }

    #[test]
    fn exr_arguments_are_checked() {
        let dir = Scratch::new("exrargs");
        let path = dir.path("bad.exr");
        let four = [0.0f32; 4];
        assert!(
            invalid_message(write_exr(&path, 2, 2, &[("R", &four), ("G", &four[..3])])).contains("\"G\" has 3 samples")
        );
        assert!(invalid_message(write_exr(&path, 2, 2, &[("R", &four), ("R", &four)])).contains("given twice"));
        assert!(invalid_message(write_exr(&path, 2, 2, &[])).contains("at least one channel"));
        assert!(invalid_message(write_exr(&path, 2, 2, &[("", &four)])).contains("not a valid EXR channel name"));
        assert!(invalid_message(write_exr(&path, 0, 2, &[])).contains("0x2"));
        assert!(dir.entries().is_empty());

        assert_eq!(read_message(read_exr_channels(&path), &path), "no such file");
        let png_file = dir.path("grey.png");
        write_png_grey8(&png_file, &Image::new(2, 2, 0.5)).unwrap();
        assert!(read_message(read_exr_channels(&png_file), &png_file).starts_with("not a valid OpenEXR file"));
    }
}
