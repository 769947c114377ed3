//! `wrinkle normalmap`: a tangent-space normal map from a height image, streamed row by row.

use crate::image_args::{write_filtered, StreamArgs};
use clap::{Args, ValueEnum};
use std::path::PathBuf;
use std::time::Instant;
use wrinkle::bump::normal_map::{encode_rgb, Convention, Kernel, NormalMap};
use wrinkle::image::stream::{ImageRows, OutputFormat, RowFormat};
use wrinkle::image::strips::{filter_3x3, last_row, Edges, Window};
use wrinkle::{Error, Result};

#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum ConventionArg {
    /// +Y (green) up the picture, as OpenGL, Blender, Unity
    Opengl,
    /// +Y down the picture, as DirectX, Unreal
    Directx,
}

impl ConventionArg {
    pub fn convention(self) -> Convention {
        match self {
            ConventionArg::Opengl => Convention::OpenGl,
            ConventionArg::Directx => Convention::DirectX,
        }
    }
}

#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum KernelArg {
    /// (h[x+1] - h[x-1]) / 2: sharpest
    Central,
    /// Sobel 3x3 (1 2 1 across the derivative, over 8)
    Sobel,
    /// Scharr 3x3 (3 10 3, over 32): the most rotation-invariant
    Scharr,
}

/// Make a tangent-space normal map (RGB = (n + 1) / 2), or an offset vector map, from a grey height image
#[derive(Args, Debug)]
#[command(after_help = "\
The surface is z = STRENGTH * h(x, y) with h the grey value in [0, 1] and x, y in pixels: STRENGTH is the
height of white above black in pixels (the same surface as `emboss --width` and `bump --scale`).
With --offset the map stores that surface's slopes instead (the slides' offset vectors, Bu and Bv in
tangent space): R = (dz/dx + 1) / 2, G = (dz/dy + 1) / 2 (y up the picture), B = 0, slopes clamped to
[-1, 1]. A scene reads it as `bump = { offsets = \"map.png\", scale = S }`: the same bumps as the height
map with `bump = { map = \"height.png\", scale = H }` when S = H * WIDTH / STRENGTH.
Border pixels read the nearest edge pixel, or the opposite edge with --wrap (tileable maps).
RGB heights become 0.2126 R + 0.7152 G + 0.0722 B. The map is data: no gamma.

Examples:
  wrinkle normalmap height.png -o normal.png
  wrinkle normalmap tile.png -o tile_n.png --strength 8 --wrap --depth 16
  wrinkle normalmap height.png -o normal_dx.png --convention directx --kernel scharr
  wrinkle normalmap height.png -o offsets.png --offset --strength 1 --depth 16")]
pub struct NormalmapArgs {
    /// Height image (PNG 8 or 16 bit, JPEG, BMP, TGA, TIFF); white is high
    pub input: PathBuf,
    /// Output image: .png (or .bmp, 8-bit)
    #[arg(short, long)]
    pub output: PathBuf,
    /// Height of white above black, in pixels
    #[arg(long, default_value_t = 3.0, allow_negative_numbers = true)]
    pub strength: f32,
    /// Which way green points
    #[arg(long, value_enum, default_value_t = ConventionArg::Opengl)]
    pub convention: ConventionArg,
    /// Derivative kernel
    #[arg(long, value_enum, default_value_t = KernelArg::Sobel)]
    pub kernel: KernelArg,
    /// Treat the image as tileable: the borders read the opposite edge
    #[arg(long)]
    pub wrap: bool,
    /// Bits per channel: 8 or 16
    #[arg(long, default_value_t = 8)]
    pub depth: u8,
    /// Write an offset vector map (the surface's slopes in R and G) instead of normals
    #[arg(long)]
    pub offset: bool,
    #[command(flatten)]
    pub stream: StreamArgs,
}

pub fn run(args: &NormalmapArgs) -> Result<()> {
    let start = Instant::now();
    let compression = args.stream.prepare()?;
    let kernel = match args.kernel {
        KernelArg::Central => Kernel::Central,
        KernelArg::Sobel => Kernel::Sobel,
        KernelArg::Scharr => Kernel::Scharr,
    };
    let map = NormalMap::new(kernel, args.strength, args.convention.convention())?;
    let sixteen = match args.depth {
        8 => false,
        16 => true,
        d => return Err(Error::Invalid(format!("--depth must be 8 or 16, got {d}"))),
    };
    OutputFormat::of(&args.output)?;
    let heights = ImageRows::open(&args.input)?;
    let (w, h) = (heights.width(), heights.height());
    let (edges, last) = if args.wrap {
        // The first row's upper neighbour is the last row: one extra decoding pass finds it.
        (Edges::Wrap, Some(last_row(ImageRows::open(&args.input)?, 1.0)?))
    } else {
        (Edges::Clamp, None)
    };
    let rows = RowFormat { channels: 3, sixteen };
    let offset = args.offset;
    let filter = |_y: usize, win: Window, _: Option<&[u8]>, scratch: &mut [f32], out: &mut [u8]| {
        let (nx, rest) = scratch.split_at_mut(w);
        let (ny, nz) = rest.split_at_mut(w);
        if offset {
            // Slopes in [-1, 1] stored like normal components, B at 0.
            map.slopes_row(win, nx, ny);
            for ((x, y), z) in nx.iter_mut().zip(ny.iter_mut()).zip(nz.iter_mut()) {
                (*x, *y, *z) = (x.clamp(-1.0, 1.0), y.clamp(-1.0, 1.0), -1.0);
            }
        } else {
            map.normals_row(win, nx, ny, nz);
        }
        encode_rgb(nx, ny, nz, sixteen, out);
    };
    write_filtered("normalmap", &args.stream, compression, &args.output, (w, h), rows, start, |sink, progress| {
        filter_3x3(heights, 1.0, edges, last, None, rows.row_bytes(w), &filter, sink, progress)
    })
}
