//! `wrinkle texture`: bake a procedural pattern into an image (8/16-bit PNG or linear EXR).

use crate::output::{format_of, Format};
use clap::Args;
use rayon::prelude::*;
use std::path::PathBuf;
use wrinkle::image::color::linear_to_srgb;
use wrinkle::image::io;
use wrinkle::image::stream::{write_rows, PngCompression, RowFormat};
use wrinkle::procedural::bake::bake_rows;
use wrinkle::procedural::effects::{spline, Kind, Params, Pattern};
use wrinkle::procedural::fbm::Octaves;
use wrinkle::procedural::Variant;
use wrinkle::{Error, Result};

/// Bake a procedural texture (noise, fbm, turbulence, marble, wood, fire, clouds, bricks, checker, grid)
/// into an image.
#[derive(Args, Debug)]
#[command(after_help = "\
The image covers [0, 1) in u (left to right) and v (bottom to top); SCALE lattice cells (pattern
periods) span it. Options that do not belong to the kind are ignored (see --list).
PNG is sRGB-encoded for colour patterns and linear for noise, fbm and turbulence (data such as height
maps), unless --encoding says otherwise; EXR is always linear.

Examples:
  wrinkle texture --list
  wrinkle texture marble -o marble.png --size 512x512 --octaves 6
  wrinkle texture fbm -o height.png --size 1024x1024 --tileable --bits 16 --seed 7
  wrinkle texture clouds -o sky.exr --size 1024x512 --time 2.5")]
pub struct TextureArgs {
    /// The pattern: noise, fbm, turbulence, marble, wood, fire, clouds, bricks, checker, grid
    #[arg(required_unless_present = "list")]
    pub kind: Option<String>,
    /// List the patterns with their options and exit
    #[arg(long)]
    pub list: bool,
    /// Output file: .png or .exr
    #[arg(short, long, required_unless_present = "list")]
    pub output: Option<PathBuf>,
    /// Image size WIDTHxHEIGHT
    #[arg(long, default_value = "512x512")]
    pub size: String,
    /// Seed of the noise's permutation (0: Perlin's published table)
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Repeat seamlessly across the image's edges (SCALE is rounded to a whole number)
    #[arg(long)]
    pub tileable: bool,
    /// PNG bits per channel: 8 or 16
    #[arg(long, default_value_t = 8)]
    pub bits: u8,
    /// PNG encoding of the values: srgb or linear (default: linear for noise, fbm, turbulence; else srgb)
    #[arg(long)]
    pub encoding: Option<String>,
    /// Lattice cells (pattern periods) across the image
    #[arg(long, allow_negative_numbers = true, default_value_t = 4.0)]
    pub scale: f32,
    /// Noise variant: hashed (the default: the 2002 noise with a hashed lattice, fast), improved (2002,
    /// Perlin's permutation table and reference values) or classic (1985)
    #[arg(long)]
    pub variant: Option<String>,
    /// Octaves of the noise sums
    #[arg(long, default_value_t = Octaves::default().count)]
    pub octaves: u32,
    /// Frequency ratio between octaves
    #[arg(long, allow_negative_numbers = true, default_value_t = Octaves::default().lacunarity)]
    pub lacunarity: f32,
    /// Amplitude ratio between octaves
    #[arg(long, allow_negative_numbers = true, default_value_t = Octaves::default().gain)]
    pub gain: f32,
    /// marble, wood, fire: how strongly the noise distorts the pattern [default: marble 0.5, wood 0.3, fire 1]
    #[arg(long, allow_negative_numbers = true)]
    pub strength: Option<f32>,
    /// wood: rings per unit of radius
    #[arg(long, allow_negative_numbers = true)]
    pub rings: Option<f32>,
    /// fire, clouds: animation time
    #[arg(long, allow_negative_numbers = true)]
    pub time: Option<f32>,
    /// bricks: mortar width as a fraction of a course
    #[arg(long, allow_negative_numbers = true)]
    pub mortar: Option<f32>,
    /// grid: line width as a fraction of a cell
    #[arg(long, allow_negative_numbers = true)]
    pub line_width: Option<f32>,
    /// Colours of the spline from t = 0 to 1, linear RGB: "r,g,b;r,g,b;..."
    #[arg(long)]
    pub colors: Option<String>,
}

/// "WxH" -> (W, H).
fn parse_size(s: &str) -> Result<(usize, usize)> {
    let bad = || Error::Invalid(format!("--size: expected WIDTHxHEIGHT such as 512x512, got \"{s}\""));
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    let (w, h): (usize, usize) = (w.trim().parse().map_err(|_| bad())?, h.trim().parse().map_err(|_| bad())?);
    io::check_size(w, h).map_err(|m| Error::Invalid(format!("--size: {m}")))?;
    Ok((w, h))
}

/// "r,g,b;r,g,b" -> colours.
fn parse_colors(s: &str) -> Result<Vec<[f32; 3]>> {
    s.split(';')
        .map(|c| {
            let v: Vec<f32> =
                c.split(',').map(|x| x.trim().parse::<f32>()).collect::<std::result::Result<_, _>>().map_err(|_| {
                    Error::Invalid(format!("--colors: expected \"r,g,b;r,g,b;...\" numbers, got \"{c}\""))
                })?;
            <[f32; 3]>::try_from(v)
                .map_err(|_| Error::Invalid(format!("--colors: expected three numbers per colour, got \"{c}\"")))
        })
        .collect()
}

fn list() {
    println!("Patterns (wrinkle texture KIND -o OUT.png):");
    for k in Kind::ALL {
        println!("  {:<11} {}", k.name(), k.describe());
    }
    println!("Every pattern also takes --size, --seed, --tileable, --bits, --encoding and --colors.");
}

impl TextureArgs {
    fn params(&self, kind: Kind) -> Result<Params> {
        let mut p = Params::new(kind);
        p.scale = self.scale;
        p.seed = self.seed;
        if let Some(name) = &self.variant {
            p.variant = Variant::from_name(name).ok_or_else(|| {
                Error::Invalid(format!("--variant: expected {}, got \"{name}\"", Variant::name_list("")))
            })?;
        }
        p.octaves = Octaves { count: self.octaves, lacunarity: self.lacunarity, gain: self.gain };
        p.strength = self.strength.unwrap_or(p.strength);
        p.rings = self.rings.unwrap_or(p.rings);
        p.time = self.time.unwrap_or(p.time);
        p.mortar = self.mortar.unwrap_or(p.mortar);
        p.line_width = self.line_width.unwrap_or(p.line_width);
        if let Some(c) = &self.colors {
            p.colors = parse_colors(c)?;
        }
        Ok(p)
    }
}

pub fn run(args: &TextureArgs) -> Result<()> {
    if args.list {
        list();
        return Ok(());
    }
    let (Some(name), Some(out)) = (&args.kind, &args.output) else {
        return Err(Error::Invalid("give a KIND and -o OUT (or --list)".into()));
    };
    let kind = Kind::from_name(name).ok_or_else(|| {
        let names: Vec<&str> = Kind::ALL.iter().map(|k| k.name()).collect();
        Error::Invalid(format!("unknown texture kind \"{name}\" (expected one of {})", names.join(", ")))
    })?;
    let format = format_of(out)?;
    let (w, h) = parse_size(&args.size)?;
    if args.bits != 8 && args.bits != 16 {
        return Err(Error::Invalid(format!("--bits must be 8 or 16, got {}", args.bits)));
    }
    let data = matches!(kind, Kind::Noise | Kind::Fbm | Kind::Turbulence);
    let srgb = match args.encoding.as_deref() {
        None => !data,
        Some("srgb") => true,
        Some("linear") => false,
        Some(other) => return Err(Error::Invalid(format!("--encoding: expected srgb or linear, got \"{other}\""))),
    };
    let pattern = Pattern::new(args.params(kind)?, 2, args.tileable)?;
    let t = std::time::Instant::now();
    let rows = RowFormat { channels: 3, sixteen: args.bits == 16 };
    // Baked, coloured and encoded a band of rows at a time: a 16384 x 16384 PNG never exists whole.
    let band = ((1 << 20) / w).clamp(1, h);
    let bake_band = |y0: usize| -> Vec<f32> {
        let mut t = vec![0.0f32; band.min(h - y0) * w];
        bake_rows(&pattern, w, h, y0, &mut t);
        t
    };
    match format {
        Format::Exr => {
            let mut channels = [0, 1, 2].map(|_| Vec::with_capacity(w * h));
            for y0 in (0..h).step_by(band) {
                let rgb: Vec<[f32; 3]> = bake_band(y0).par_iter().map(|&t| spline(&pattern.params.colors, t)).collect();
                for (c, channel) in channels.iter_mut().enumerate() {
                    channel.extend(rgb.iter().map(|p| p[c]));
                }
            }
            let [r, g, b] = channels;
            io::write_exr_owned(out, w, h, vec![("R", r), ("G", g), ("B", b)])?;
        }
        Format::Png => write_rows(out, w, h, rows, PngCompression::Fast, |sink| {
            let per_pixel = rows.row_bytes(1);
            let mut bytes = vec![0u8; band * w * per_pixel];
            for y0 in (0..h).step_by(band) {
                let t = bake_band(y0);
                let bytes = &mut bytes[..t.len() * per_pixel];
                bytes.par_chunks_mut(per_pixel).zip(&t).for_each(|(px, &t)| {
                    let rgb = spline(&pattern.params.colors, t).map(|v| if srgb { linear_to_srgb(v) } else { v });
                    for (c, v) in rgb.into_iter().enumerate() {
                        let v = v.clamp(0.0, 1.0);
                        if rows.sixteen {
                            px[2 * c..2 * c + 2].copy_from_slice(&((v * 65535.0).round() as u16).to_be_bytes());
                        } else {
                            px[c] = (v * 255.0).round() as u8;
                        }
                    }
                });
                sink(bytes)?;
            }
            Ok(())
        })?,
    }
    let bake_ms = t.elapsed().as_secs_f64() * 1e3;
    println!(
        "wrote {} ({w}x{h}, {}{}, baked and written in {bake_ms:.1} ms)",
        out.display(),
        kind.name(),
        if args.tileable { ", tileable" } else { "" }
    );
    Ok(())
}
