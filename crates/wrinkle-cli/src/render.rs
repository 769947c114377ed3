//! `wrinkle render`: one frame, or a turntable animation of numbered frames.

use crate::output::{check_stdout, format_of, is_stdout, stage_outputs, write_stdout};
use crate::progress::Progress;
use clap::builder::PossibleValuesParser;
use clap::Args;
use std::path::{Path, PathBuf};
use wrinkle::bump::BumpFilter;
use wrinkle::image::output::OutputSet;
use wrinkle::render::{Aovs, Transparency};
use wrinkle::texture::{Filter, TexelLocation};
use wrinkle::{render_with_progress, Crop, Error, PixelFilter, RenderOptions, Result, Sampler, Scene, ShadingRate};

#[derive(Args, Debug)]
#[command(
    after_help = "Examples:\n  wrinkle render -o cover.png                       the embedded 1978 cover scene\n  wrinkle render scenes/grid_patch.toml -o grid.png --spp 16\n  wrinkle render scene.toml -o out.png --aov normal,uv,depth,id\n  wrinkle render scene.toml -o out.png --filter ewa --bump-filter trilinear\n  wrinkle render scenes/turntable.toml -o spin.png --frames 36 --turntable"
)]
pub struct RenderArgs {
    /// Scene file (TOML); the embedded cover scene when omitted.
    pub scene: Option<PathBuf>,
    /// Output image: .png (8-bit sRGB) or .exr (linear float); - writes PNG to the standard output
    #[arg(short, long, default_value = "wrinkle.png")]
    pub output: PathBuf,
    #[command(flatten)]
    pub frame: FrameArgs,
    /// AOVs written beside the output as OUT.<name>.exr: any of normal, uv, depth, id, primitive
    /// (comma-separated; primitive is the item buffer: object and triangle as 32-bit integers).
    #[arg(long, value_delimiter = ',')]
    pub aov: Vec<String>,
    /// The frames of an animation (a scene's [[animation]] tracks, or --turntable): N renders frames 0 to
    /// N - 1, A..B frames A to B (both included), each written as OUT_<frame>.png (OUT_0000.png, ...).
    #[arg(long, default_value = "1", value_name = "N|A..B", value_parser = parse_frames)]
    pub frames: Frames,
    /// Frames per second: frame f shows the scene's animation at time f / FPS seconds.
    #[arg(long, default_value_t = 24.0)]
    pub fps: f64,
    /// Rotate the objects one full turn about the vertical axis through the camera's target over the frames
    /// (frame f of A..B at 360 (f - A) / (B - A + 1) degrees).
    #[arg(long)]
    pub turntable: bool,
    /// Print the time of each pipeline stage.
    #[arg(long)]
    pub stats: bool,
    /// What lies behind the objects: the scene's (its camera's background colour, or its environment), or
    /// nothing: alpha 0 there (PNG RGBA with straight alpha; EXR RGBA premultiplied).
    #[arg(long, default_value = "scene", value_parser = ["scene", "transparent"])]
    pub background: String,
    /// Render the frame in tiles of N x N pixels, one after another, each exactly as the whole frame renders
    /// it, assembled into the output. A PNG of colour alone is written band by band as its tiles come, so a
    /// frame too large to render at once (up to 65536 on a side) needs the memory of one band of tiles;
    /// EXR, AOVs and transparent PNGs are assembled whole first.
    #[arg(long, value_name = "N")]
    pub tile: Option<usize>,
}

/// Frames with at least this many samples (about 2 s of work) show a progress bar.
const LONG_FRAME_SAMPLES: usize = 32 << 20;

/// The options shared by `render` and `bench`.
#[derive(Args, Debug)]
pub struct FrameArgs {
    #[arg(long, default_value_t = 1280)]
    pub width: usize,
    #[arg(long, default_value_t = 720)]
    pub height: usize,
    /// Samples per pixel, 1 to 4096 (1 stratified sample is the pixel's centre).
    #[arg(long, default_value_t = 1)]
    pub spp: usize,
    /// How samples are placed in each pixel: stratified (jittered strata, the same in every pixel) or sobol
    /// (the Sobol sequence, Owen-scrambled per pixel: well spread at any --spp).
    #[arg(long, default_value = "stratified", value_parser = Sampler::NAMES)]
    pub sampler: String,
    /// The pixel reconstruction filter: box (the pixel), tent (radius 1), gaussian (1.5, sigma 0.5), mitchell
    /// (2, B = C = 1/3) or lanczos (3 lobes); NAME:RADIUS for another radius in pixels. Samples are drawn in
    /// proportion to the filter around each pixel's centre, so a wide filter needs several --spp.
    #[arg(long, default_value = "box", value_name = "NAME[:RADIUS]")]
    pub pixel_filter: String,
    /// How often the samples are shaded: sample (every one: supersampling, bump detail inside a pixel
    /// averaged too) or pixel (each triangle once per pixel, at its covered sample nearest the centre with
    /// the whole pixel's footprint: multisampling, coverage still at every sample).
    #[arg(long, default_value = "sample", value_parser = ShadingRate::NAMES)]
    pub shading_rate: String,
    /// Seeds the Sobol sampler's per-pixel scrambles: renders with other seeds are independent estimates of
    /// the same image.
    #[arg(long, default_value_t = 0)]
    pub seed: u32,
    /// Where each pixel reads its textures and bumps: centre (the (u,v) of its centre, the footprint of
    /// their derivatives), centroid (the average (u,v) of its four corners projected onto the surface) or
    /// diagonals (where that quadrilateral's diagonals cross), both with the quadrilateral's footprint.
    #[arg(long, default_value = "centre", value_parser = TexelLocation::NAMES.map(|(n, _)| n))]
    pub texel_location: String,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Render without bump mapping.
    #[arg(long)]
    pub no_bump: bool,
    /// Filter every bump function: none (the full-resolution table, bilinear), mip (MIP level from the pixel
    /// footprint: trilinear), any texture filter (nearest, trilinear, ripmap, sat, aniso, ewa, ...), or
    /// filter the distribution of the normals: lean (LEAN mapping), toksvig, lean:FILTER, toksvig:FILTER.
    #[arg(long, value_parser = parse_bump_filter)]
    pub bump_filter: Option<BumpFilter>,
    /// Filter every colour texture with this filter instead of the scene's: nearest, bilinear, bicubic,
    /// gaussian, lanczos (magnification only), trilinear, ripmap, sat, aniso, ewa, ...
    #[arg(long, value_parser = PossibleValuesParser::new(Filter::ALL.map(|(n, _)| n)))]
    pub filter: Option<String>,
    /// Add this many levels to every image texture's level of detail instead of the scene's lod_bias
    /// (-4 to 4): the footprints are scaled by 2^LEVELS. -0.5 with --spp 2 or more brings trilinear textures
    /// closest to their supersampled limit (docs/filtering.md).
    #[arg(long, value_name = "LEVELS", allow_hyphen_values = true, value_parser = parse_lod_bias)]
    pub lod_bias: Option<f32>,
    /// How translucent (alpha_mode = "blend") surfaces are put in order: sorted (objects, then their
    /// triangles, back to front: right unless translucent surfaces cross) or exact (each sample's own
    /// fragments by depth, an A-buffer: right where they cross).
    #[arg(long, default_value = "sorted", value_parser = ["sorted", "exact"])]
    pub transparency: String,
    /// Render only pixels X0..X1, Y0..Y1 of the frame (row 0 at the top), exactly as the whole frame
    /// renders them, into an image of that size: a frame too large to hold is rendered in parts.
    #[arg(long, value_name = "X0,Y0,X1,Y1")]
    pub crop: Option<String>,
}

impl FrameArgs {
    pub fn options(&self) -> Result<RenderOptions> {
        self.options_in_tiles(None)
    }

    /// The options of a frame rendered in `tile` x `tile` parts where asked: each part is then checked as
    /// the crop it is, so the whole frame may be larger than one render holds.
    pub fn options_in_tiles(&self, tile: Option<usize>) -> Result<RenderOptions> {
        crate::set_threads(self.threads)?;
        let options = RenderOptions {
            width: self.width,
            height: self.height,
            spp: self.spp,
            sampler: Sampler::parse(&self.sampler).expect("clap checked the sampler"),
            texel_location: TexelLocation::parse(&self.texel_location).expect("clap checked the location"),
            pixel_filter: PixelFilter::parse(&self.pixel_filter)?,
            shading_rate: ShadingRate::parse(&self.shading_rate).expect("clap checked the shading rate"),
            seed: self.seed,
            bump: !self.no_bump,
            bump_filter: self.bump_filter,
            transparency: match self.transparency.as_str() {
                "exact" => Transparency::Exact,
                _ => Transparency::Sorted,
            },
            crop: self.crop.as_deref().map(parse_crop).transpose()?,
            ..RenderOptions::default()
        };
        match tile {
            None => options.validate()?,
            Some(n) => {
                if options.crop.is_some() {
                    return Err(Error::Invalid(
                        "--tile splits the whole frame: give --crop or --tile, not both".into(),
                    ));
                }
                if !(16..=1 << 16).contains(&n) {
                    return Err(Error::parameter("tile", format!("must be between 16 and 65536, got {n}")));
                }
                let first = Crop { x0: 0, y0: 0, x1: n.min(options.width), y1: n.min(options.height) };
                RenderOptions { crop: Some(first), ..options.clone() }.validate()?;
            }
        }
        Ok(options)
    }
}

impl FrameArgs {
    /// The scene with `--filter` and `--lod-bias` applied to its colour textures.
    pub fn load_scene(&self, path: Option<&Path>) -> Result<Scene> {
        let mut scene = load_scene(path)?;
        if let Some(f) = self.filter.as_deref().and_then(Filter::parse) {
            scene.set_texture_filter(f);
        }
        if let Some(bias) = self.lod_bias {
            scene.set_texture_lod_bias(bias);
        }
        Ok(scene)
    }
}

fn parse_lod_bias(text: &str) -> std::result::Result<f32, String> {
    match text.trim().parse::<f32>() {
        Ok(b) if (-4.0..=4.0).contains(&b) => Ok(b),
        _ => Err(format!("expected a number of levels from -4 to 4, got \"{text}\"")),
    }
}

/// The scene file, or the embedded default.
pub fn load_scene(path: Option<&Path>) -> Result<Scene> {
    match path {
        Some(p) => Scene::load(p),
        None => Ok(Scene::default_scene()),
    }
}

fn parse_aovs(names: &[String]) -> Result<Aovs> {
    let mut a = Aovs::default();
    for n in names {
        match n.trim() {
            "normal" => a.normal = true,
            "uv" => a.uv = true,
            "depth" => a.depth = true,
            "id" => a.id = true,
            "primitive" => a.primitive = true,
            other => {
                return Err(Error::Invalid(format!(
                    "--aov: unknown AOV \"{other}\" (expected normal, uv, depth, id, primitive)"
                )))
            }
        }
    }
    Ok(a)
}

/// Which frames to render.
#[derive(Clone, Copy, Debug)]
pub struct Frames {
    pub first: usize,
    pub last: usize,
    /// Whether outputs carry their frame's number (a range, or more than one frame).
    pub numbered: bool,
}

impl Frames {
    pub fn count(&self) -> usize {
        self.last - self.first + 1
    }
}

/// `--frames N` (frames 0 to N - 1) or `--frames A..B` (A to B, both included).
fn parse_frames(text: &str) -> std::result::Result<Frames, String> {
    const MOST: usize = 100_000;
    let whole =
        |t: &str| t.trim().parse::<usize>().map_err(|_| format!("expected N or A..B (whole numbers), got \"{text}\""));
    let frames = match text.split_once("..") {
        Some((a, b)) => Frames { first: whole(a)?, last: whole(b)?, numbered: true },
        None => {
            let n = whole(text)?;
            if n == 0 {
                return Err("must be at least 1 frame".into());
            }
            Frames { first: 0, last: n - 1, numbered: n > 1 }
        }
    };
    if frames.first > frames.last {
        return Err(format!("the range must not run backwards, got {text}"));
    }
    if frames.count() > MOST || frames.last >= 10 * MOST {
        return Err(format!("at most {MOST} frames, numbered below {}, got {text}", 10 * MOST));
    }
    Ok(frames)
}

/// `out.png` -> `out_0007.png`.
fn numbered(out: &Path, k: usize) -> PathBuf {
    let stem = out.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let ext = out.extension().map(|e| e.to_string_lossy().into_owned()).unwrap_or_default();
    out.with_file_name(format!("{stem}_{k:04}.{ext}"))
}

pub fn run(args: &RenderArgs) -> Result<()> {
    format_of(&args.output)?;
    let to_stdout = is_stdout(&args.output);
    if to_stdout {
        if !args.aov.is_empty() || args.frames.numbered || args.tile.is_some() {
            return Err(Error::Invalid(
                "-o -: the standard output holds one PNG: no --aov, no --frames, no --tile".into(),
            ));
        }
        check_stdout()?;
    }
    let mut options = args.frame.options_in_tiles(args.tile)?;
    options.aovs = parse_aovs(&args.aov)?;
    options.transparent = args.background == "transparent";
    if !(args.fps.is_finite() && args.fps > 0.0 && args.fps <= 1000.0) {
        return Err(Error::parameter("fps", format!("must be above 0 and at most 1000, got {}", args.fps)));
    }
    let loading = std::time::Instant::now();
    let scene = args.frame.load_scene(args.scene.as_deref())?;
    if args.frames.count() > 1 && scene.animation.is_none() && !args.turntable {
        return Err(Error::Invalid(
            "--frames: the scene has no [[animation]] tracks, so every frame would be the same (add --turntable)"
                .into(),
        ));
    }
    if args.stats {
        eprintln!(
            "scene: loaded in {:.1} ms (models, textures and their pyramids)",
            loading.elapsed().as_secs_f64() * 1e3
        );
    }
    let frames = args.frames;
    let animated = frames.numbered;
    let bar =
        (frames.count() > 1).then(|| Progress::new("render", frames.count() as u64, "frames", "{pos}/{len} frames"));
    // An animation's frames are placed together at the end: a failed frame leaves none of them.
    let mut set = OutputSet::new();
    for k in frames.first..=frames.last {
        let turn = (k - frames.first) as f32 / frames.count() as f32;
        options.turntable_degrees = if args.turntable { 360.0 * turn } else { 0.0 };
        let out = if animated { numbered(&args.output, k) } else { args.output.clone() };
        let moved;
        let scene = match &scene.animation {
            Some(animation) if k > 0 => {
                moved = animation.scene_at(k as f64 / args.fps)?;
                &moved
            }
            _ => &scene,
        };
        if let Some(n) = args.tile {
            let t = std::time::Instant::now();
            crate::tiles::render_in_tiles(scene, &options, n, &out, &mut set, !animated)?;
            if args.stats {
                eprintln!(
                    "{}: {n}x{n} tiles rendered and written in {:.1} ms",
                    out.display(),
                    t.elapsed().as_secs_f64() * 1e3
                );
            }
            if let Some(b) = &bar {
                b.inc(1);
            }
            continue;
        }
        // One long frame (many samples, or ray-marched volumes) gets a bar of its own (bands of tiles); an
        // animation has one over its frames.
        let long = !animated
            && (options.width * options.height * options.spp >= LONG_FRAME_SAMPLES || !scene.volumes.is_empty());
        let frame_bar = long.then(|| Progress::new("render", 0, "bands", "{percent}% of the frame"));
        let frame = render_with_progress(scene, &options, &|done, total| {
            if let Some(b) = &frame_bar {
                b.set_length(total as u64);
                b.set_position(done as u64);
            }
        })?;
        if let Some(b) = frame_bar {
            b.finish();
        }
        let t = std::time::Instant::now();
        if to_stdout {
            write_stdout(&frame)?;
        } else {
            stage_outputs(&mut set, &out, &frame)?;
        }
        if args.stats {
            let s = &frame.stats;
            eprintln!(
                "{}: tessellate {:.1} ms, setup {:.1} ms ({} triangles), bin {:.1} ms, shadow maps {:.1} ms, raster+shade+resolve {:.1} ms, encode+write {:.1} ms",
                out.display(),
                s.tessellate_ms,
                s.setup_ms,
                s.triangles,
                s.bin_ms,
                s.shadow_ms,
                s.raster_shade_ms,
                t.elapsed().as_secs_f64() * 1e3
            );
        }
        if let Some(b) = &bar {
            b.inc(1);
        }
    }
    set.commit()?;
    if let Some(b) = bar {
        b.finish();
    }
    Ok(())
}

/// `--crop X0,Y0,X1,Y1`: four whole numbers (the range is checked with the frame's size).
fn parse_crop(text: &str) -> Result<Crop> {
    let numbers: Vec<usize> = text
        .split(',')
        .map(|n| n.trim().parse())
        .collect::<std::result::Result<_, _>>()
        .map_err(|_| Error::parameter("crop", format!("must be four whole numbers X0,Y0,X1,Y1, got \"{text}\"")))?;
    match numbers[..] {
        [x0, y0, x1, y1] => Ok(Crop { x0, y0, x1, y1 }),
        _ => Err(Error::parameter("crop", format!("must be four whole numbers X0,Y0,X1,Y1, got \"{text}\""))),
    }
}

/// A `--bump-filter` name as a filter: `none` is Blinn's bilinear FVAL on the full-resolution table.
fn parse_bump_filter(name: &str) -> std::result::Result<BumpFilter, String> {
    BumpFilter::parse(name).ok_or_else(|| format!("expected one of {}", BumpFilter::names()))
}
