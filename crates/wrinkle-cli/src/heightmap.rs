//! `wrinkle heightmap`: heights from a normal map, by integrating its gradient field (Frankot-Chellappa).

use crate::image_args::{row_bar, StreamArgs};
use crate::normalmap::ConventionArg;
use clap::Args;
use std::path::PathBuf;
use wrinkle::bump::integrate::{
    check_strength, field_size, frankot_chellappa, gradient_of_normal, settle_heights, BYTES_PER_FIELD_PIXEL,
};
use wrinkle::bump::normal_map::decode_normal;
use wrinkle::image::stream::{write_rows, ImageRows, OutputFormat, RowFormat};
use wrinkle::{Error, Result};

/// Integrate a tangent-space normal map back to a grey height image (Frankot-Chellappa)
#[derive(Args, Debug)]
#[command(after_help = "\
The heights are found up to a constant: the lowest point is made black. With the --strength and
--convention the map was made with (`wrinkle normalmap`), the heights come back at their own scale;
--normalize stretches them to the full range instead. Without --wrap the gradients are mirrored before
the Fourier transform (4x the work and memory, no seams at the borders); with --wrap the map is taken as
tileable. Memory: about 64 bytes per pixel without --wrap, 16 with it.

Examples:
  wrinkle heightmap normal.png -o height.png
  wrinkle heightmap tile_n.png -o tile_h.png --wrap --strength 8
  wrinkle heightmap normal_dx.png -o height.png --convention directx --normalize")]
pub struct HeightmapArgs {
    /// Normal map (RGB = (n + 1) / 2; PNG 8 or 16 bit, or any input format)
    pub input: PathBuf,
    /// Output grey image: .png (or .bmp, 8-bit)
    #[arg(short, long)]
    pub output: PathBuf,
    /// Height of white above black in pixels that the map was made with
    #[arg(long, default_value_t = 3.0, allow_negative_numbers = true)]
    pub strength: f32,
    /// Which way the map's green points
    #[arg(long, value_enum, default_value_t = ConventionArg::Opengl)]
    pub convention: ConventionArg,
    /// The map is tileable (periodic)
    #[arg(long)]
    pub wrap: bool,
    /// Stretch the heights to the full range (black lowest, white highest)
    #[arg(long)]
    pub normalize: bool,
    /// Bits per sample: 8 or 16
    #[arg(long, default_value_t = 16)]
    pub depth: u8,
    #[command(flatten)]
    pub stream: StreamArgs,
}

pub fn run(args: &HeightmapArgs) -> Result<()> {
    let start = std::time::Instant::now();
    let compression = args.stream.prepare()?;
    check_strength(args.strength)?;
    let sixteen = match args.depth {
        8 => false,
        16 => true,
        d => return Err(Error::Invalid(format!("--depth must be 8 or 16, got {d}"))),
    };
    OutputFormat::of(&args.output)?;
    let mut normals = ImageRows::open(&args.input)?;
    let (w, h) = (normals.width(), normals.height());
    let (fw, fh) = field_size(w, h, args.wrap);
    // The transformed field, and the gradients read into it (8 bytes a pixel).
    let need = (fw * fh * BYTES_PER_FIELD_PIXEL + w * h * 8) as u64;
    wrinkle::limits::reserve(need, || {
        let hint = if args.wrap { "" } else { " (--wrap needs 4x less)" };
        format!("{}: integrating a {w}x{h} map{hint}", args.input.display())
    })?;
    // Gradients per pixel of heights in [0, 1]: p = dh/dx, q = dh/dy with y down the rows.
    let convention = args.convention.convention();
    let (mut p, mut q) = (Vec::with_capacity(w * h), Vec::with_capacity(w * h));
    let mut rgb = vec![0.0; 3 * w];
    let bar = row_bar("heightmap", w, h);
    for y in 0..h {
        normals.read_rgb(&mut rgb)?;
        for px in rgb.chunks_exact(3) {
            let (dx, dy) = gradient_of_normal(decode_normal([px[0], px[1], px[2]], convention), args.strength);
            p.push(dx);
            q.push(dy);
        }
        bar.set_position(y as u64);
    }
    let mut heights = frankot_chellappa(&p, &q, w, h, args.wrap);
    drop((p, q));
    let span = settle_heights(&mut heights, args.normalize);
    if !args.normalize && span > 1.0 {
        eprintln!(
            "warning: the heights span {span:.3} of full scale; values above white are clipped (use --normalize or a larger --strength)"
        );
    }
    let rows = RowFormat { channels: 1, sixteen };
    write_rows(&args.output, w, h, rows, compression, |sink| {
        let mut bytes = Vec::with_capacity(rows.row_bytes(w));
        for row in heights.chunks_exact(w) {
            bytes.clear();
            for &v in row {
                let v = v.clamp(0.0, 1.0);
                if sixteen {
                    bytes.extend_from_slice(&((v * 65535.0 + 0.5) as u16).to_be_bytes());
                } else {
                    bytes.push((v * 255.0 + 0.5) as u8);
                }
            }
            sink(&bytes)?;
        }
        Ok(())
    })?;
    bar.finish();
    if args.stream.stats {
        eprintln!("heightmap: {w}x{h}, total {:.1} ms", start.elapsed().as_secs_f64() * 1e3);
    }
    Ok(())
}
