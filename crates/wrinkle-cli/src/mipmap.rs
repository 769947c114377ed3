//! `wrinkle mipmap`: a texture's MIP pyramid, built in linear light, written as one atlas PNG, one PNG per
//! level, or one multi-resolution file as OpenImageIO's `maketx` writes it (OpenEXR MIPMAP, tiled TIFF).

use crate::output::require_extension;
use clap::Args;
use std::path::{Path, PathBuf};
use std::time::Instant;
use wrinkle::image::color::SrgbEncoder;
use wrinkle::image::io;
use wrinkle::image::levels::{write_exr_levels, write_tiff_levels, TiffSamples};
use wrinkle::image::output::OutputSet;
use wrinkle::limits;
use wrinkle::texture::mip::{half, pyramid};
use wrinkle::{Error, Image, MipFilter, Result, Wrap};

#[derive(Args, Debug)]
#[command(
    after_help = "Examples:\n  wrinkle mipmap bricks.png -o bricks_mips.png                 atlas: level 0, the others stacked to its right\n  wrinkle mipmap bricks.png -o mips.png --filter kaiser --levels   mips_0.png, mips_1.png, ...\n  wrinkle mipmap heights.png -o h.png --linear                 data, not colour: no sRGB decoding\n  wrinkle mipmap bricks.png -o bricks.exr --format exr         one OpenEXR file with MIPMAP levels\n  wrinkle mipmap bricks.png -o bricks.tif --format tiff        one tiled TIFF, the levels after level 0 (maketx's layout)"
)]
pub struct MipmapArgs {
    /// The texture (PNG, JPEG, BMP, TGA, TIFF, EXR; 8-bit, 16-bit or float).
    pub input: PathBuf,
    /// The atlas (PNG), or the name the level files are numbered from with --levels.
    #[arg(short, long)]
    pub output: PathBuf,
    /// The low-pass filter that makes each level: box, kaiser or lanczos.
    #[arg(long, default_value = "box", value_parser = ["box", "kaiser", "lanczos"])]
    pub filter: String,
    /// The input is linear data (height or normal maps): no sRGB decoding in, no encoding out.
    #[arg(long)]
    pub linear: bool,
    /// How the edges are filtered: repeat (tiling textures), clamp or mirror.
    #[arg(long, default_value = "repeat", value_parser = ["repeat", "clamp", "mirror"])]
    pub wrap: String,
    /// One file per level (OUT_0.png, OUT_1.png, ...) instead of an atlas.
    #[arg(long)]
    pub levels: bool,
    /// png (an atlas, or --levels), exr (one OpenEXR file with MIPMAP levels: float RGBA, 64x64 tiles) or
    /// tiff (one tiled TIFF with the levels as reduced-resolution images: 8-bit sRGB, 16-bit with --linear),
    /// both readable by OpenImageIO and by wrinkle's textures, which then use these levels.
    #[arg(long, default_value = "png", value_parser = ["png", "exr", "tiff"])]
    pub format: String,
}

pub fn run(args: &MipmapArgs) -> Result<()> {
    let extensions: &[&str] = match args.format.as_str() {
        "exr" => &["exr"],
        "tiff" => &["tif", "tiff", "tx"],
        _ => &["png"],
    };
    require_extension(&args.output, extensions)?;
    if args.levels && args.format != "png" {
        return Err(Error::Invalid(format!("--levels writes PNG files; --format {} writes one file", args.format)));
    }
    let filter = MipFilter::parse(&args.filter).expect("clap checked the name");
    let wrap = Wrap::parse(&args.wrap).expect("clap checked the name");
    let image = io::load_rgba_linear(&args.input, !args.linear)?;
    let (w, h) = (image.width, image.height);
    // The float image, its pyramid (4/3 of it) and a level's copy while the pyramid is made into images, and
    // the largest 8-bit image written (the atlas, 3/2 the base).
    let pixels = (w * h) as u64;
    limits::reserve(pixels * 16 * 10 / 3 + pixels * 4 * 3 / 2, || {
        format!("{}: a MIP pyramid of {w}x{h}", args.input.display())
    })?;
    if !args.levels && args.format == "png" {
        let (aw, ah) = atlas_size(w, h);
        io::check_size(aw, ah).map_err(|m| {
            Error::Invalid(format!("{}: the atlas of a {w}x{h} texture: {m}; or write --levels", args.output.display()))
        })?;
    }
    let t = Instant::now();
    let levels = pyramid(&image, filter, [wrap; 2]);
    drop(image);
    let ms = t.elapsed().as_secs_f64() * 1e3;
    let encode = Encoder { srgb: !args.linear, table: SrgbEncoder::new() };
    if args.format == "exr" {
        write_exr_levels(&args.output, &levels)?;
    } else if args.format == "tiff" {
        let samples = if args.linear { TiffSamples::Linear16 } else { TiffSamples::Srgb8 };
        write_tiff_levels(&args.output, &levels, samples)?;
    } else if args.levels {
        let mut set = OutputSet::new();
        for (k, level) in levels.iter().enumerate() {
            set.stage(&numbered(&args.output, k), |path| {
                io::write_png_rgba8(path, level.width, level.height, &encode.plane(level))
            })?;
        }
        set.commit()?;
    } else {
        let (w, h, bytes) = atlas(&levels, &encode);
        io::write_png_rgba8(&args.output, w, h, &bytes)?;
    }
    println!(
        "{} levels from {}x{} ({} filter, {}), built in {ms:.1} ms",
        levels.len(),
        w,
        h,
        args.filter,
        if args.linear { "linear data" } else { "sRGB decoded to linear light" }
    );
    Ok(())
}

/// Linear values to 8-bit: colour channels sRGB-encoded (or scaled, for linear data), alpha scaled.
struct Encoder {
    srgb: bool,
    table: SrgbEncoder,
}

impl Encoder {
    fn texel(&self, [r, g, b, a]: [f32; 4]) -> [u8; 4] {
        let scale = |x: f32| (x.clamp(0.0, 1.0) * 255.0 + 0.5) as u8;
        let c = |x: f32| if self.srgb { self.table.encode(x) } else { scale(x) };
        [c(r), c(g), c(b), scale(a)]
    }

    /// A level as RGBA bytes, row 0 at the top.
    fn plane(&self, level: &Image<[f32; 4]>) -> Vec<u8> {
        level.pixels.iter().flat_map(|&v| self.texel(v)).collect()
    }
}

/// The atlas's width and height for a `w` x `h` base: level 0 and, to its right, the others stacked.
fn atlas_size(w: usize, h: usize) -> (usize, usize) {
    let (mut lw, mut lh, mut stacked) = (w, h, 0);
    while lw > 1 || lh > 1 {
        (lw, lh) = (half(lw), half(lh));
        stacked += lh;
    }
    (if w == 1 && h == 1 { 1 } else { w + half(w) }, h.max(stacked))
}

/// Level 0 on the left, the other levels stacked top to bottom to its right; transparent elsewhere.
fn atlas(levels: &[Image<[f32; 4]>], encode: &Encoder) -> (usize, usize, Vec<u8>) {
    let (w, h) = atlas_size(levels[0].width, levels[0].height);
    let w0 = levels[0].width;
    let mut bytes = vec![0u8; w * h * 4];
    let mut place = |level: &Image<[f32; 4]>, x0: usize, y0: usize| {
        let rgba = encode.plane(level);
        for y in 0..level.height {
            let src = &rgba[y * level.width * 4..(y + 1) * level.width * 4];
            let at = ((y0 + y) * w + x0) * 4;
            bytes[at..at + src.len()].copy_from_slice(src);
        }
    };
    place(&levels[0], 0, 0);
    let mut y = 0;
    for level in &levels[1..] {
        place(level, w0, y);
        y += level.height;
    }
    (w, h, bytes)
}

/// `out.png` -> `out_3.png`.
fn numbered(out: &Path, k: usize) -> PathBuf {
    let stem = out.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    out.with_file_name(format!("{stem}_{k}.png"))
}
