//! `wrinkle envmap`: converts an environment map between the slides' layouts (latitude-longitude, cube,
//! sphere map, dual paraboloid), each texel filtered over the directions it covers, in linear light.

use crate::output::require_extension;
use clap::Args;
use std::path::PathBuf;
use std::time::Instant;
use wrinkle::envmap::convert::{convert, matching_size, picture, size_of};
use wrinkle::envmap::{files, Arrangement, Environment, EnvironmentOptions, Layout};
use wrinkle::image::color::SrgbEncoder;
use wrinkle::image::io;
use wrinkle::limits;
use wrinkle::texture::{Filter, FilterOptions};
use wrinkle::{Error, Result};

#[derive(Args, Debug)]
#[command(
    after_help = "Examples:\n  wrinkle envmap sky.hdr -o sky_cross.hdr --to cube                  latlong -> horizontal cross\n  wrinkle envmap sky.hdr -o ball.png --to sphere --size 512         the unpeeled mirror ball, 8-bit sRGB\n  wrinkle envmap px.png nx.png py.png ny.png pz.png nz.png -o sky.exr --to latlong\n  wrinkle envmap halves.png --from paraboloid -o sky.hdr --to latlong\n\nLayouts: latlong (2:1, centre column -Z, top +Y), cube (OpenGL faces +X -X +Y -Y +Z -Z; one picture as a\ncross, vertical cross or strip, or six files), sphere (OpenGL sphere map), paraboloid (two halves, +Z then\n-Z, side by side). docs/environment.md gives the formulas."
)]
pub struct EnvmapArgs {
    /// The map: one picture, six cube faces (+X -X +Y -Y +Z -Z) or two paraboloid halves (PNG, JPEG, TIFF,
    /// HDR, EXR; 8-bit files are sRGB).
    #[arg(required = true, num_args = 1..=6)]
    pub input: Vec<PathBuf>,
    /// The converted map: PNG (8-bit sRGB with alpha), HDR (Radiance) or EXR (linear float).
    #[arg(short, long)]
    pub output: PathBuf,
    /// The layout to write.
    #[arg(long, value_parser = ["latlong", "cube", "sphere", "paraboloid"])]
    pub to: String,
    /// The input's layout, when its shape does not tell (2:1 is latlong, 1:1 sphere, 4:3, 3:4, 6:1 or 1:6 a
    /// cube; two files a paraboloid, six a cube).
    #[arg(long, value_parser = ["latlong", "cube", "sphere", "paraboloid"])]
    pub from: Option<String>,
    /// Texels: a latlong map's height, a cube face's side, a sphere map's or a paraboloid half's side.
    /// Default: the input's detail at the centre of its layout.
    #[arg(long)]
    pub size: Option<usize>,
    /// How a cube's six faces are laid out in the picture.
    #[arg(long, default_value = "cross", value_parser = ["cross", "vertical-cross", "strip", "vertical-strip"])]
    pub arrangement: String,
    /// The filter over each output texel's footprint in the input.
    #[arg(long, default_value = "ewa")]
    pub filter: String,
}

pub fn run(args: &EnvmapArgs) -> Result<()> {
    require_extension(&args.output, &["png", "hdr", "exr"])?;
    let to = Layout::parse(&args.to).expect("clap checked the name");
    let from = args.from.as_deref().map(|n| Layout::parse(n).expect("clap checked the name"));
    let arrangement = Arrangement::parse(&args.arrangement).expect("clap checked the name");
    let filter = Filter::parse(&args.filter)
        .ok_or_else(|| Error::Invalid(format!("--filter must be one of {}, got {}", Filter::names(), args.filter)))?;
    let t = Instant::now();
    let (layout, images) = files::load(&args.input, from)?;
    let options =
        EnvironmentOptions { filter: FilterOptions { filter, ..FilterOptions::default() }, ..Default::default() };
    let env = Environment::new(layout, &images, options).map_err(|m| Error::read(&args.input[0], m))?;
    let size = args.size.unwrap_or_else(|| matching_size(layout, size_of(layout, &images), to));
    let (w, h) = picture_size(to, size, arrangement);
    io::check_size(w, h).map_err(|m| Error::Invalid(format!("--size {size}: the {} picture: {m}", to.name())))?;
    limits::reserve((w * h) as u64 * 16 * 2, || format!("a {w}x{h} {} map", to.name()))?;
    let out = picture(to, &convert(&env, to, size), arrangement);
    write(&args.output, &out)?;
    println!(
        "{} {} -> {} {}x{} ({} filter) in {:.0} ms",
        args.input[0].display(),
        layout.name(),
        to.name(),
        out.width,
        out.height,
        filter.name(),
        t.elapsed().as_secs_f64() * 1e3
    );
    Ok(())
}

/// The written picture's size in pixels.
fn picture_size(to: Layout, size: usize, arrangement: Arrangement) -> (usize, usize) {
    let (c, r) = match to {
        Layout::LatLong | Layout::Paraboloid => (2, 1),
        Layout::Sphere => (1, 1),
        Layout::Cube => arrangement.grid(),
    };
    (size.saturating_mul(c), size.saturating_mul(r))
}

fn write(path: &std::path::Path, image: &wrinkle::image::Image<[f32; 4]>) -> Result<()> {
    let (w, h) = (image.width, image.height);
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("exr") => {
            let channel = |c: usize| image.pixels.iter().map(|p| p[c]).collect::<Vec<f32>>();
            io::write_exr_owned(
                path,
                w,
                h,
                vec![("R", channel(0)), ("G", channel(1)), ("B", channel(2)), ("A", channel(3))],
            )
        }
        Some("hdr") => {
            let rgb: Vec<f32> = image.pixels.iter().flat_map(|p| [p[0], p[1], p[2]]).collect();
            io::write_hdr(path, w, h, &rgb)
        }
        _ => {
            let enc = SrgbEncoder::new();
            let bytes: Vec<u8> = image
                .pixels
                .iter()
                .flat_map(|p| {
                    [enc.encode(p[0]), enc.encode(p[1]), enc.encode(p[2]), (p[3].clamp(0.0, 1.0) * 255.0).round() as u8]
                })
                .collect();
            io::write_png_rgba8(path, w, h, &bytes)
        }
    }
}
