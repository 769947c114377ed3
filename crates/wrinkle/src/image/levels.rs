//! Multi-resolution texture files as OpenImageIO's `maketx` and Pixar's `txmake` write them: OpenEXR with
//! MIPMAP or RIPMAP levels (tiled), and TIFF whose further images are the reduced-resolution levels (maketx:
//! tiled, 64 x 64). Read so that their levels serve the filters instead of being rebuilt; written by
//! `wrinkle mipmap --format exr|tiff`. Levels are linear RGBA, row 0 at the top.

use super::color::{linear_to_srgb, srgb_to_linear};
use super::io::{check_size, first_exr_header, open_input};
use super::output::write_atomic;
use super::Image;
use crate::error::{Error, Result};
use crate::limits;
use exr::meta::attribute::LevelMode;
use exr::prelude::{
    AnyChannel, AnyChannels, Blocks, Encoding, FlatSamples, IntegerBounds, Layer, LayerAttributes, Levels,
    ReadChannels, ReadLayers, WritableImage,
};
use std::io::{BufReader, Cursor};
use std::path::Path;
use tiff::decoder::{Decoder, DecodingResult};
use tiff::encoder::TiffEncoder;
use tiff::tags::Tag;

/// A texture's levels: level 0 first, each smaller than the one before; and whether it has alpha.
pub struct FileLevels {
    pub levels: Vec<Image<[f32; 4]>>,
    pub alpha: bool,
}

/// The levels of a multi-resolution file (an OpenEXR MIPMAP or RIPMAP, or a TIFF of more than one image
/// whose images halve), `None` for a file of one resolution. `srgb`: 8- and 16-bit TIFF colour is sRGB.
pub fn read_levels(path: &Path, srgb: bool) -> Result<Option<FileLevels>> {
    let extension = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    match extension.as_deref() {
        Some("exr") => read_exr_levels(path),
        Some("tif" | "tiff" | "tx" | "tex") => read_tiff_levels(path, srgb),
        _ => Ok(None),
    }
}

/// Checks that each level (width, height) is its predecessor halved (rounded down or up, at least 1).
pub fn check_chain(path: &Path, sizes: &[(usize, usize)]) -> Result<()> {
    let halves = |big: usize, small: usize| small == (big / 2).max(1) || small == big.div_ceil(2).max(1);
    for (k, pair) in sizes.windows(2).enumerate() {
        let ((aw, ah), (bw, bh)) = (pair[0], pair[1]);
        if !halves(aw, bw) || !halves(ah, bh) {
            let message = format!("level {} is {bw}x{bh}, not half of level {k}'s {aw}x{ah}", k + 1);
            return Err(Error::read(path, message));
        }
    }
    Ok(())
}

/// The (width, height) of each level.
pub fn sizes(levels: &[Image<[f32; 4]>]) -> Vec<(usize, usize)> {
    levels.iter().map(|l| (l.width, l.height)).collect()
}

fn read_exr_levels(path: &Path) -> Result<Option<FileLevels>> {
    let header = first_exr_header(path)?;
    let exr::meta::BlockDescription::Tiles(tiles) = header.blocks else { return Ok(None) };
    if tiles.level_mode == LevelMode::Singular {
        return Ok(None);
    }
    let (width, height) = (header.layer_size.width(), header.layer_size.height());
    check_size(width, height).map_err(|m| Error::read(path, m))?;
    // Every level in f32, RGBA: at most 4/3 of the base (a ripmap's diagonal; its other levels are read too).
    let per_pixel: u64 = header.channels.list.iter().map(|c| c.sample_type.bytes_per_sample() as u64 + 4).sum();
    let ripmap = if tiles.level_mode == LevelMode::RipMap { 4 } else { 2 };
    limits::reserve((width * height) as u64 * (per_pixel * ripmap + 16 * 4 / 3), || {
        format!("{}: decoding its {width}x{height} levels", path.display())
    })?;
    let image = exr::prelude::read()
        .no_deep_data()
        .all_resolution_levels()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .map_err(|e| Error::read(path, format!("not a valid OpenEXR file: {e}")))?;
    let layer = image.layer_data;
    let channels = &layer.channel_data.list;
    let find = |name: &str| channels.iter().find(|c| c.name.to_string() == name);
    let (r, g, b) = match (find("R"), find("G"), find("B")) {
        (Some(r), Some(g), Some(b)) => (r, g, b),
        _ if channels.len() == 1 => (&channels[0], &channels[0], &channels[0]),
        _ => return Err(Error::read(path, "expected channels R, G, B (or a single grey channel)")),
    };
    let a = find("A");
    // The levels as (samples, size) per channel; a ripmap gives its diagonal (the same rate on both axes).
    let levels_of = |c: &AnyChannel<Levels<FlatSamples>>| -> Vec<(Vec<f32>, usize, usize)> {
        let all: Vec<_> = layer.levels_with_resolution(&c.sample_data).collect();
        let diagonal: Vec<_> = match &c.sample_data {
            Levels::Rip { level_data, .. } => {
                let count = level_data.level_count;
                (0..count.0.min(count.1)).map(|k| all[k * count.0 + k]).collect()
            }
            _ => all,
        };
        diagonal.into_iter().map(|(s, size)| (s.values_as_f32().collect(), size.width(), size.height())).collect()
    };
    let (rs, gs, bs) = (levels_of(r), levels_of(g), levels_of(b));
    let alphas = a.map(levels_of);
    let levels: Vec<Image<[f32; 4]>> = (0..rs.len())
        .map(|k| {
            let (w, h) = (rs[k].1, rs[k].2);
            let pixels = (0..w * h)
                .map(|i| [rs[k].0[i], gs[k].0[i], bs[k].0[i], alphas.as_ref().map_or(1.0, |a| a[k].0[i])])
                .collect();
            Image { width: w, height: h, pixels }
        })
        .collect();
    check_chain(path, &sizes(&levels))?;
    Ok(Some(FileLevels { levels, alpha: a.is_some() }))
}

fn read_tiff_levels(path: &Path, srgb: bool) -> Result<Option<FileLevels>> {
    let tiff_error = |e: tiff::TiffError| Error::read(path, format!("malformed TIFF: {e}"));
    let Ok(mut decoder) = Decoder::new(BufReader::new(open_input(path)?)) else { return Ok(None) };
    // The images' sizes first (their directories only): pages that do not halve are a multi-page document,
    // not a pyramid, and its first page is the texture; nothing of theirs is decoded here.
    let mut sizes = Vec::new();
    loop {
        let (w, h) = decoder.dimensions().map_err(tiff_error)?;
        sizes.push((w as usize, h as usize));
        if !decoder.more_images() {
            break;
        }
        decoder.next_image().map_err(tiff_error)?;
    }
    if sizes.len() < 2 || check_chain(path, &sizes).is_err() {
        return Ok(None);
    }
    let mut decoder = Decoder::new(BufReader::new(open_input(path)?)).map_err(tiff_error)?;
    let mut levels = Vec::new();
    let mut alpha = false;
    for (k, &(w, h)) in sizes.iter().enumerate() {
        if k > 0 {
            decoder.next_image().map_err(tiff_error)?;
        }
        check_size(w, h).map_err(|m| Error::read(path, m))?;
        limits::reserve((w * h) as u64 * 24, || format!("{}: decoding its {w}x{h} level", path.display()))?;
        let channels = match decoder.colortype().map_err(tiff_error)? {
            tiff::ColorType::Gray(_) => 1,
            tiff::ColorType::GrayA(_) => 2,
            tiff::ColorType::RGB(_) => 3,
            tiff::ColorType::RGBA(_) => 4,
            other => {
                return Err(Error::read(path, format!("a TIFF level of {other:?} texels; expected grey, RGB or RGBA")))
            }
        };
        alpha |= channels % 2 == 0;
        // Integer colour is sRGB where asked; float colour is linear.
        let (samples, encoded): (Vec<f32>, bool) = match decoder.read_image().map_err(tiff_error)? {
            DecodingResult::U8(v) => (v.iter().map(|&x| x as f32 / 255.0).collect(), srgb),
            DecodingResult::U16(v) => (v.iter().map(|&x| x as f32 / 65535.0).collect(), srgb),
            DecodingResult::F32(v) => (v, false),
            _ => return Err(Error::read(path, "a TIFF level of samples other than 8-bit, 16-bit or float")),
        };
        let colour = |v: f32| if encoded { srgb_to_linear(v) } else { v };
        if samples.len() != w * h * channels {
            return Err(Error::read(path, "a TIFF level with the wrong number of samples"));
        }
        let pixels = samples
            .chunks_exact(channels)
            .map(|p| match channels {
                1 => [colour(p[0]), colour(p[0]), colour(p[0]), 1.0],
                2 => [colour(p[0]), colour(p[0]), colour(p[0]), p[1]],
                3 => [colour(p[0]), colour(p[1]), colour(p[2]), 1.0],
                _ => [colour(p[0]), colour(p[1]), colour(p[2]), p[3]],
            })
            .collect();
        levels.push(Image { width: w, height: h, pixels });
    }
    Ok(Some(FileLevels { levels, alpha }))
}

/// Writes `levels` (level 0 first, each half the one before rounded down) as one OpenEXR file with
/// MIPMAP levels (f32 RGBA, 64 x 64 tiles, ZIP), as OpenImageIO's `maketx` writes them.
pub fn write_exr_levels(path: &Path, levels: &[Image<[f32; 4]>]) -> Result<()> {
    let base = &levels[0];
    check_size(base.width, base.height).map_err(|m| Error::write(path, m))?;
    let channel = |c: usize, name: &str| {
        let level_data = levels.iter().map(|l| FlatSamples::F32(l.pixels.iter().map(|p| p[c]).collect())).collect();
        AnyChannel::new(name, Levels::Mip { level_data, rounding_mode: exr::math::RoundingMode::Down })
    };
    let channels = AnyChannels::sort([channel(0, "R"), channel(1, "G"), channel(2, "B"), channel(3, "A")].into());
    let encoding = Encoding { blocks: Blocks::Tiles(exr::math::Vec2(64, 64)), ..Encoding::SMALL_LOSSLESS };
    let layer = Layer::new((base.width, base.height), LayerAttributes::default(), encoding, channels);
    let mut image = exr::prelude::Image::from_layer(layer);
    image.attributes.display_window = IntegerBounds::new((0, 0), (base.width, base.height));
    let mut bytes = Cursor::new(Vec::new());
    image.write().to_buffered(&mut bytes).map_err(|e| Error::write(path, e))?;
    write_atomic(path, |out| out.write_all(bytes.get_ref()).map_err(|e| Error::write(path, e)))
}

/// How a TIFF's samples are stored.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TiffSamples {
    /// 8-bit, colour sRGB-encoded (alpha linear).
    Srgb8,
    /// 16-bit, linear (data maps).
    Linear16,
}

/// The side of a TIFF tile.
const TILE: usize = 64;
/// The private TIFF tags of Pixar's texture files (libtiff's TIFFTAG_PIXAR_TEXTUREFORMAT, _WRAPMODES).
const PIXAR_TEXTUREFORMAT: u16 = 33302;
const PIXAR_WRAPMODES: u16 = 33303;

/// Writes `levels` as one tiled TIFF (64 x 64 tiles, RGBA, uncompressed), level 0 the first image and each
/// further level a reduced-resolution image after it: the layout of OpenImageIO's `maketx`.
pub fn write_tiff_levels(path: &Path, levels: &[Image<[f32; 4]>], samples: TiffSamples) -> Result<()> {
    let base = &levels[0];
    check_size(base.width, base.height).map_err(|m| Error::write(path, m))?;
    let mut bytes = Cursor::new(Vec::new());
    let failed = |e: tiff::TiffError| Error::write(path, e);
    {
        let mut encoder = TiffEncoder::new(&mut bytes).map_err(failed)?;
        for (k, level) in levels.iter().enumerate() {
            let (w, h) = (level.width, level.height);
            let (across, down) = (w.div_ceil(TILE), h.div_ceil(TILE));
            let mut dir = encoder.image_directory().map_err(failed)?;
            let mut offsets = Vec::with_capacity(across * down);
            let mut counts = Vec::with_capacity(across * down);
            for ty in 0..down {
                for tx in 0..across {
                    // A whole tile, padded with zeros beyond the image (as TIFF requires).
                    let texel = |x: usize, y: usize| -> [f32; 4] {
                        let (x, y) = (tx * TILE + x, ty * TILE + y);
                        if x < w && y < h {
                            level.pixels[y * w + x]
                        } else {
                            [0.0; 4]
                        }
                    };
                    let encode = |p: [f32; 4], c: usize| {
                        let v = if c < 3 && samples == TiffSamples::Srgb8 { linear_to_srgb(p[c]) } else { p[c] };
                        v.clamp(0.0, 1.0)
                    };
                    let values = (0..TILE * TILE).flat_map(|i| (0..4).map(move |c| (i, c)));
                    let offset = match samples {
                        TiffSamples::Srgb8 => {
                            let tile: Vec<u8> = values
                                .map(|(i, c)| (encode(texel(i % TILE, i / TILE), c) * 255.0).round() as u8)
                                .collect();
                            counts.push(tile.len() as u32);
                            dir.write_data(&tile[..]).map_err(failed)?
                        }
                        TiffSamples::Linear16 => {
                            let tile: Vec<u16> = values
                                .map(|(i, c)| (encode(texel(i % TILE, i / TILE), c) * 65535.0).round() as u16)
                                .collect();
                            counts.push(2 * tile.len() as u32);
                            dir.write_data(&tile[..]).map_err(failed)?
                        }
                    };
                    offsets.push(
                        u32::try_from(offset).map_err(|_| Error::write(path, "over 4 GiB: too large for a TIFF"))?,
                    );
                }
            }
            let bits = match samples {
                TiffSamples::Srgb8 => 8u16,
                TiffSamples::Linear16 => 16,
            };
            // NewSubfileType 1: a reduced-resolution version of the image before it.
            dir.write_tag(Tag::NewSubfileType, u32::from(k > 0)).map_err(failed)?;
            dir.write_tag(Tag::ImageWidth, w as u32).map_err(failed)?;
            dir.write_tag(Tag::ImageLength, h as u32).map_err(failed)?;
            dir.write_tag(Tag::BitsPerSample, &[bits; 4][..]).map_err(failed)?;
            dir.write_tag(Tag::Compression, 1u16).map_err(failed)?;
            dir.write_tag(Tag::PhotometricInterpretation, 2u16).map_err(failed)?;
            dir.write_tag(Tag::SamplesPerPixel, 4u16).map_err(failed)?;
            dir.write_tag(Tag::PlanarConfiguration, 1u16).map_err(failed)?;
            // The fourth sample is unassociated (straight) alpha.
            dir.write_tag(Tag::ExtraSamples, &[2u16][..]).map_err(failed)?;
            dir.write_tag(Tag::SampleFormat, &[1u16; 4][..]).map_err(failed)?;
            dir.write_tag(Tag::TileWidth, TILE as u32).map_err(failed)?;
            dir.write_tag(Tag::TileLength, TILE as u32).map_err(failed)?;
            // Pixar's texture tags, which tell OpenImageIO (and PRMan) that the images are MIP levels.
            dir.write_tag(Tag::Unknown(PIXAR_TEXTUREFORMAT), "Plain Texture").map_err(failed)?;
            dir.write_tag(Tag::Unknown(PIXAR_WRAPMODES), "periodic,periodic").map_err(failed)?;
            dir.write_tag(Tag::TileOffsets, &offsets[..]).map_err(failed)?;
            dir.write_tag(Tag::TileByteCounts, &counts[..]).map_err(failed)?;
            dir.finish().map_err(failed)?;
        }
    }
    write_atomic(path, |out| out.write_all(bytes.get_ref()).map_err(|e| Error::write(path, e)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::mip::pyramid;
    use crate::texture::{MipFilter, Wrap};

    fn source() -> Image<[f32; 4]> {
        Image::from_fn(37, 20, |x, y| {
            [x as f32 / 37.0, y as f32 / 20.0, ((x * y) % 7) as f32 / 7.0, 0.5 + 0.01 * x as f32]
        })
    }

    /// Written and read back: every level, the EXR exactly, the TIFF to its 8- or 16-bit step.
    #[test]
    fn levels_round_trip_through_exr_and_tiff() {
        let dir = std::env::temp_dir().join(format!("wrinkle-levels-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let levels = pyramid(&source(), MipFilter::Box, [Wrap::Repeat; 2]);
        assert_eq!(levels.len(), 6); // 37x20 .. 1x1
        let exr = dir.join("mips.exr");
        write_exr_levels(&exr, &levels).unwrap();
        let back = read_levels(&exr, true).unwrap().expect("a MIP-mapped EXR");
        assert!(back.alpha);
        assert_eq!(back.levels.len(), levels.len());
        for (a, b) in back.levels.iter().zip(&levels) {
            assert_eq!((a.width, a.height), (b.width, b.height));
            assert_eq!(a.pixels, b.pixels);
        }
        for (samples, step) in [(TiffSamples::Srgb8, 1.0 / 255.0), (TiffSamples::Linear16, 1.0 / 65535.0)] {
            let tif = dir.join("mips.tif");
            write_tiff_levels(&tif, &levels, samples).unwrap();
            let back = read_levels(&tif, samples == TiffSamples::Srgb8).unwrap().expect("a TIFF pyramid");
            assert_eq!(back.levels.len(), levels.len());
            for (a, b) in back.levels.iter().zip(&levels) {
                assert_eq!((a.width, a.height), (b.width, b.height));
                for (p, q) in a.pixels.iter().zip(&b.pixels) {
                    for c in 0..4 {
                        let (p, q) = match (samples, c) {
                            (TiffSamples::Srgb8, 0..=2) => (linear_to_srgb(p[c]), linear_to_srgb(q[c])),
                            _ => (p[c], q[c]),
                        };
                        assert!((p - q).abs() <= 0.51 * step + 1e-6, "{p} vs {q}");
                    }
                }
            }
        }
        // A RIPMAP gives its diagonal: level k reduced k times on both axes (each level a constant k here).
        let size = exr::math::Vec2(16usize, 8usize);
        let rip: Vec<(exr::math::Vec2<usize>, exr::math::Vec2<usize>)> =
            exr::meta::rip_map_levels(exr::math::RoundingMode::Down, size).collect();
        let count = exr::math::Vec2(
            rip.iter().map(|(i, _)| i.0).max().unwrap() + 1,
            rip.iter().map(|(i, _)| i.1).max().unwrap() + 1,
        );
        let channel = |name: &str| {
            let map_data = rip
                .iter()
                .map(|(index, s)| FlatSamples::F32(vec![(index.0 * 10 + index.1) as f32; s.area()]))
                .collect();
            let level_data = exr::image::RipMaps { map_data, level_count: count };
            AnyChannel::new(name, Levels::Rip { level_data, rounding_mode: exr::math::RoundingMode::Down })
        };
        let channels = AnyChannels::sort(vec![channel("R"), channel("G"), channel("B")].into());
        let encoding = Encoding { blocks: Blocks::Tiles(exr::math::Vec2(8, 8)), ..Encoding::SMALL_LOSSLESS };
        let layer = Layer::new((16, 8), LayerAttributes::default(), encoding, channels);
        let ripmap = dir.join("rip.exr");
        exr::prelude::Image::from_layer(layer).write().to_file(&ripmap).unwrap();
        let back = read_levels(&ripmap, false).unwrap().expect("a RIPMAP");
        let sizes: Vec<(usize, usize)> = back.levels.iter().map(|l| (l.width, l.height)).collect();
        assert_eq!(sizes, [(16, 8), (8, 4), (4, 2), (2, 1)]);
        for (k, level) in back.levels.iter().enumerate() {
            assert!(level.pixels.iter().all(|p| p[0] == (k * 11) as f32 && p[3] == 1.0), "level {k}");
        }
        // A file of one resolution has no levels to give.
        let flat = dir.join("flat.exr");
        crate::image::io::write_exr(&flat, 2, 2, &[("R", &[0.0; 4]), ("G", &[0.0; 4]), ("B", &[0.0; 4])]).unwrap();
        assert!(read_levels(&flat, false).unwrap().is_none());
        std::fs::remove_dir_all(&dir).ok();
    }
}
