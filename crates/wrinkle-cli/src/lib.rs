//! The `wrinkle` command as a library: parses a command line and hands each subcommand to its own file.
//! The binary (main.rs) runs it on the process's arguments; the Python package's farm runs image commands
//! through it on its workers, with the same options and outputs.

mod bench;
mod bench_noise;
mod bench_texture;
mod bump_image;
mod bumpgen;
mod cpu;
mod emboss;
mod envmap;
mod filters;
mod heightmap;
mod image_args;
mod mappings;
mod mipmap;
mod normalmap;
mod output;
mod paint;
mod progress;
mod render;
mod sheet;
mod tessellate;
mod texture;
mod tiles;

use clap::{Parser, Subcommand};
use std::ffi::OsString;

#[derive(Parser)]
#[command(name = "wrinkle", version, about = "Texture mapping and Blinn bump mapping: a fast CPU renderer and toolkit")]
#[command(
    after_help = "Examples:\n  wrinkle render -o cover.png\n  wrinkle render scenes/grid_patch.toml -o grid.png --spp 16\n  wrinkle bumpgen bricks -o bricks.png --size 512\n  wrinkle bench --frames 10\n  wrinkle emboss height.png -o embossed.png\n  wrinkle normalmap height.png -o normal.png"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Raise (or lower) a limit: memory=SIZE (default 3/4 of the machine's memory), image-side=N (32768),
    /// image-pixels=N (268435456), frame-side=N (16384), frame-pixels=N (67108864), triangles=N (268435456).
    /// Sizes take K, M, G, T; counts k, M, G. docs/reliability.md lists them.
    #[arg(long = "limit", global = true, value_name = "NAME=VALUE")]
    limits: Vec<String>,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene (or the embedded 1978 cover scene) to PNG or EXR.
    Render(render::RenderArgs),
    /// Write a generated bump function (grid, text, rivets, bricks) as a 16-bit PNG.
    Bumpgen(bumpgen::BumpgenArgs),
    /// Time the rendering of a scene in-process: median milliseconds per frame.
    Bench(bench::BenchArgs),
    /// Emboss a grey image (Schlag's fast embossing), alone or multiplying a colour texture.
    Emboss(emboss::EmbossArgs),
    /// Bump-map a grey image with Blinn's perturbation through the renderer (a flat patch seen head-on).
    Bump(bump_image::BumpArgs),
    /// Make a tangent-space normal map from a grey height image.
    Normalmap(normalmap::NormalmapArgs),
    /// Integrate a normal map back to a grey height image (Frankot-Chellappa).
    Heightmap(heightmap::HeightmapArgs),
    /// Render one view with every texture filter beside a ground truth; print each filter's time and error.
    Filters(filters::FiltersArgs),
    /// Build a texture's MIP pyramid in linear light and write it as an atlas or one PNG per level.
    Mipmap(mipmap::MipmapArgs),
    /// Time texture lookups per filter (isotropic and 8:1 footprints, random and scanline order) and the pyramid build.
    BenchTexture(bench_texture::BenchTextureArgs),
    /// Time 3D Perlin noise and fBm over 4,000,000 points in [0, 10)^3, and a 1024x1024 fBm texture.
    BenchNoise(bench_noise::BenchNoiseArgs),
    /// Bake a procedural texture (noise, fbm, marble, wood, fire, clouds, bricks, ...) into a PNG or EXR.
    Texture(texture::TextureArgs),
    /// Render every texture mapping on a sphere and the Utah teapot, side by side on one labelled sheet.
    Mappings(mappings::MappingsArgs),
    /// Write a scene's geometry as an OBJ model: parametric surfaces tessellated, meshes as read, in world space.
    Tessellate(tessellate::TessellateArgs),
    /// Convert an environment map between latlong, cube, sphere map and dual paraboloid layouts, filtered.
    Envmap(envmap::EnvmapArgs),
    /// Paint colour, height (bumps), specular and opacity onto a model in the browser (serves a page on 127.0.0.1).
    Paint(paint::PaintArgs),
}

/// Why a command failed: its one-line message (without `error: `) and the exit code it means.
#[derive(Debug)]
pub struct Failure {
    pub message: String,
    pub code: u8,
}

/// Runs a command line (`args` starts with the program's name, as `std::env::args_os` does). `--help` and
/// `--version` print clap's text and succeed.
pub fn execute(args: impl IntoIterator<Item = OsString>) -> Result<(), Failure> {
    let cli = match Cli::try_parse_from(args) {
        Ok(cli) => cli,
        Err(e) if !e.use_stderr() => {
            let _ = e.print();
            return Ok(());
        }
        Err(e) => {
            // One line, like every other error: clap's message, without its usage and hint lines.
            let text = e.render().to_string();
            let message: Vec<&str> = text
                .lines()
                .map(str::trim)
                .take_while(|l| !l.is_empty() && !l.starts_with("Usage:") && !l.starts_with("For more information"))
                .collect();
            return Err(Failure { message: message.join(" ").trim_start_matches("error: ").to_string(), code: 2 });
        }
    };
    let result =
        cli.limits.iter().try_for_each(|arg| wrinkle::limits::set_from_arg(arg)).and_then(|()| match &cli.command {
            Command::Render(a) => render::run(a),
            Command::Bumpgen(a) => bumpgen::run(a),
            Command::Bench(a) => bench::run(a),
            Command::Emboss(a) => emboss::run(a),
            Command::Bump(a) => bump_image::run(a),
            Command::Normalmap(a) => normalmap::run(a),
            Command::Heightmap(a) => heightmap::run(a),
            Command::Filters(a) => filters::run(a),
            Command::Mipmap(a) => mipmap::run(a),
            Command::BenchTexture(a) => bench_texture::run(a),
            Command::BenchNoise(a) => bench_noise::run(a),
            Command::Texture(a) => texture::run(a),
            Command::Mappings(a) => mappings::run(a),
            Command::Tessellate(a) => tessellate::run(a),
            Command::Envmap(a) => envmap::run(a),
            Command::Paint(a) => paint::run(a),
        });
    result.map_err(|e| Failure { message: describe(&e), code: exit_code(&e) })
}

/// Writes a frame as `wrinkle render -o OUT` does: PNG or EXR by the extension, its AOVs beside it, all
/// placed together or none.
pub fn write_frame(out: &std::path::Path, frame: &wrinkle::Frame) -> wrinkle::Result<()> {
    output::write_outputs(out, frame)
}

/// The error in the command line's words: a parameter is named by its option (`--line-width`).
fn describe(e: &wrinkle::Error) -> String {
    match e {
        wrinkle::Error::Parameter { name, message } => format!("--{} {message}", name.replace('_', "-")),
        other => other.to_string(),
    }
}

/// 2 when the request itself is wrong (arguments, scene, input files), 1 when the job failed (writing output).
fn exit_code(e: &wrinkle::Error) -> u8 {
    match e {
        wrinkle::Error::Write { .. } => 1,
        _ => 2,
    }
}

/// Sets the size of the worker pool (all cores when not given).
fn set_threads(threads: Option<usize>) -> wrinkle::Result<()> {
    if let Some(n) = threads {
        if n == 0 || n > 1024 {
            return Err(wrinkle::Error::Invalid(format!("--threads must be between 1 and 1024, got {n}")));
        }
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build_global()
            .map_err(|e| wrinkle::Error::Invalid(format!("--threads: {e}")))?;
    }
    Ok(())
}
