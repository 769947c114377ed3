//! `wrinkle emboss`: Schlag's fast embossing of a grey image, alone or multiplying a colour texture,
//! streamed row by row from decoding to encoding.

use crate::image_args::{write_filtered, Resample, StreamArgs};
use clap::Args;
use std::path::{Path, PathBuf};
use std::time::Instant;
use wrinkle::bump::schlag::{modulate_rgb8, to_grey16, to_grey8, Emboss};
use wrinkle::image::resample::resample_rgb8;
use wrinkle::image::stream::{ImageRows, RowFormat};
use wrinkle::image::strips::{filter_3x3, Edges, Window};
use wrinkle::{Error, Result};

/// Emboss a grey height image (Schlag, Graphics Gems IV): Lambert shading of the normal [-i_u, -i_v, 6*255/w]
#[derive(Args, Debug)]
#[command(after_help = "\
Conventions: azimuth 0 lights from the right, 90 from the top of the picture (counter-clockwise);
elevation 90 is straight above. v points up the picture (the mask's top row is the row above).
Border pixels read the nearest edge pixel. RGB heights become 0.2126 R + 0.7152 G + 0.0722 B.
The output is the shade N.L/(|N||L|) stored as grey (0 black, 1 white; no gamma), or the texture's
stored values multiplied by it. OUT ending in .bmp gives a 24-bit BMP, like the 1994 demo.

Examples:
  wrinkle emboss height.png -o embossed.png
  wrinkle emboss height.png -o lit.png --azimuth 45 --elevation 30 --width 6
  wrinkle emboss height.png -o stone.bmp --texture stone.jpg")]
pub struct EmbossArgs {
    /// Height image (PNG 8 or 16 bit, JPEG, BMP, TGA, TIFF); white is high
    pub input: PathBuf,
    /// Output image: .png or .bmp (24-bit)
    #[arg(short, long)]
    pub output: PathBuf,
    /// Direction the light comes from, degrees counter-clockwise from the right
    #[arg(long, default_value_t = 135.0, allow_negative_numbers = true)]
    pub azimuth: f32,
    /// Height of the light above the picture, degrees (0 to 90)
    #[arg(long, default_value_t = 45.0, allow_negative_numbers = true)]
    pub elevation: f32,
    /// Bevel width w: N_z = 6 * 255 / w (larger is steeper; 3 matches ImageMagick's -shade)
    #[arg(long, default_value_t = 3.0, allow_negative_numbers = true)]
    pub width: f32,
    /// Colour image multiplied by the shade (resampled to the height image's size if it differs)
    #[arg(long)]
    pub texture: Option<PathBuf>,
    /// Filter for resampling a texture of another size, in linear light; none refuses it
    #[arg(long, value_enum, default_value_t = Resample::Lanczos3)]
    pub resample: Resample,
    /// Bits per sample of grey PNG output: 8 or 16
    #[arg(long, default_value_t = 8)]
    pub depth: u8,
    #[command(flatten)]
    pub stream: StreamArgs,
}

pub fn run(args: &EmbossArgs) -> Result<()> {
    let start = Instant::now();
    let compression = args.stream.prepare()?;
    let emboss = Emboss::new(args.azimuth, args.elevation, args.width)?;
    let sixteen = match args.depth {
        8 => false,
        16 if args.texture.is_none() => true,
        16 => return Err(Error::Invalid("--depth 16 is for grey output; a textured emboss is 8-bit RGB".into())),
        d => return Err(Error::Invalid(format!("--depth must be 8 or 16, got {d}"))),
    };
    wrinkle::image::stream::OutputFormat::of(&args.output)?;
    let heights = ImageRows::open(&args.input)?;
    let (w, h) = (heights.width(), heights.height());
    let texture = match &args.texture {
        Some(path) => Some(open_texture(path, w, h, args.resample)?),
        None => None,
    };
    let rows = RowFormat { channels: if texture.is_some() { 3 } else { 1 }, sixteen };
    let kernel = |_y: usize, win: Window, tex: Option<&[u8]>, shade: &mut [f32], out: &mut [u8]| {
        let shade = &mut shade[..w];
        emboss.shade_row(win, shade);
        match tex {
            Some(t) => modulate_rgb8(shade, t, out),
            None if sixteen => to_grey16(shade, out),
            None => to_grey8(shade, out),
        }
    };
    write_filtered("emboss", &args.stream, compression, &args.output, (w, h), rows, start, |sink, progress| {
        filter_3x3(heights, 255.0, Edges::Clamp, None, texture, rows.row_bytes(w), &kernel, sink, progress)
    })
}

/// The texture's rows at the height image's size: streamed when the sizes agree, else decoded whole and
/// resampled (or refused with `--resample none`).
pub fn open_texture(path: &Path, w: usize, h: usize, resample: Resample) -> Result<ImageRows> {
    let mut texture = ImageRows::open(path)?;
    let (tw, th) = (texture.width(), texture.height());
    if (tw, th) == (w, h) {
        return Ok(texture);
    }
    let Some(filter) = resample.filter() else {
        return Err(Error::Invalid(format!(
            "{}: the texture is {tw}x{th} but the height image is {w}x{h}; give one of the same size or a --resample filter",
            path.display()
        )));
    };
    let rgb = texture.read_all_rgb8()?;
    ImageRows::from_rgb8(path, w, h, resample_rgb8(&rgb, tw, th, w, h, filter))
}
