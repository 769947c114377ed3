//! `wrinkle filters`: one view rendered with every texture filter side by side, labelled, beside a ground
//! truth panel, with the time and error of each filter against that ground truth; with `--bump`, a shiny
//! bump-mapped view with every bump filter beside Blinn's correct solution, the intensities supersampled.
//!
//! The ground truth is the integral of the bilinear texture (of the intensity, for bumps: each sample
//! shaded with the full-resolution bump table) over each pixel's preimage: TRUTH_SPP Sobol samples a pixel,
//! each at its own exact (u,v) on the surface. Rendered again with another seed, the two estimates'
//! agreement is printed as the truth's own noise floor.

use crate::render::load_scene;
use crate::sheet;
use clap::Args;
use glam::Vec2;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;
use wrinkle::bump::generators::{text as text_image, TextParams};
use wrinkle::bump::{BumpFilter, SlopeFilter};
use wrinkle::image::color::srgb_to_linear;
use wrinkle::image::{io, Image};
use wrinkle::mapping::{MappedTexture, Mapping, UvTransform};
use wrinkle::texture::reconstruct::Kernel;
use wrinkle::texture::{Filter, FilteredTexture, TextureOptions};
use wrinkle::{render, Error, RenderOptions, Result, Sampler, Scene};

#[derive(Args, Debug)]
#[command(
    after_help = "Examples:\n  wrinkle filters -o sheet.png                    the classic view: a checkerboard plane to the horizon and a lettered sphere\n  wrinkle filters scene.toml -o sheet.png --json  any scene: every colour texture takes each filter in turn\n  wrinkle filters -o sheet.png --filters bilinear,trilinear,ewa --width 480 --height 360"
)]
pub struct FiltersArgs {
    /// Scene file (TOML); the classic grazing-plane view when omitted.
    pub scene: Option<PathBuf>,
    /// The sheet (PNG).
    #[arg(short, long, default_value = "filters.png")]
    pub output: PathBuf,
    /// Width of each panel.
    #[arg(long, default_value_t = 320)]
    pub width: usize,
    /// Height of each panel.
    #[arg(long, default_value_t = 240)]
    pub height: usize,
    /// The filters to compare (comma-separated); default: every filter.
    #[arg(long, value_delimiter = ',')]
    pub filters: Vec<String>,
    /// Compare the bump filters instead (none, mip and the texture filters) on a shiny bump-mapped view,
    /// against the intensities supersampled over the full-resolution bump table (Blinn's correct solution).
    #[arg(long)]
    pub bump: bool,
    /// Panels per row of the sheet.
    #[arg(long, default_value_t = 4)]
    pub columns: usize,
    /// Print the table as JSON instead of text.
    #[arg(long)]
    pub json: bool,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
}

/// The ground truth's samples per pixel.
const TRUTH_SPP: usize = 256;

/// The filters of the sheet by default, in the order of the slides' ladder.
const DEFAULT_FILTERS: [&str; 11] =
    ["nearest", "bilinear", "bicubic", "gaussian", "lanczos", "trilinear", "ripmap", "sat", "aniso", "ewa", "bspline"];
/// The bump filters of the `--bump` sheet by default: Blinn's unfiltered table, the MIP-based filters, and
/// the filters of the normals' distribution (Toksvig, LEAN through trilinear and through EWA).
const DEFAULT_BUMP_FILTERS: [&str; 10] =
    ["none", "mip", "ripmap", "sat", "aniso", "ewa", "bspline", "toksvig", "lean", "lean:ewa"];

/// The classic view: a plane receding to the horizon and a sphere, lit softly so the textures dominate.
/// The plane is laid as rows of patches that double in size with distance (the renderer tessellates a
/// patch uniformly, so one huge patch would cost a million triangles).
const CLASSIC: &str = r#"
[camera]
eye = [0.0, 1.1, 4.0]
look_at = [0.0, 0.55, -4.0]
fov_y = 50.0
background = [0.55, 0.7, 0.9]

[[light]]
type = "ambient"
intensity = 0.55

[[light]]
type = "directional"
direction = [-0.4, -1.0, -0.5]
intensity = 0.6

[[object]]
shape = "sphere"
radius = 0.75
transform = { translate = [1.3, 0.75, 0.6], rotate = [0.0, 200.0, 0.0] }
material = { color = [1.0, 1.0, 1.0], specular = 0.2, shininess = 30.0 }
"#;

/// The checkerboard's period on the plane, in world units.
const PERIOD: f32 = 4.0;
/// The plane's rows: (near z, far z, half width). Boundaries and widths are whole periods apart, so the
/// checks run on unbroken from row to row.
const ROWS: [(f32, f32, f32); 6] = [
    (3.0, -1.0, 4.0),
    (-1.0, -9.0, 12.0),
    (-9.0, -25.0, 20.0),
    (-25.0, -57.0, 44.0),
    (-57.0, -121.0, 88.0),
    (-121.0, -249.0, 180.0),
];

/// The classic scene with its textures: a 64 x 64 checkerboard (4-texel checks, one period every 4 units)
/// on the plane, and "TEXTURE" in 8 x 8 letters around the sphere.
fn classic_scene() -> Result<Scene> {
    let mut text = CLASSIC.to_string();
    for (near, far, half) in ROWS {
        text += &format!(
            "\n[[object]]\nshape = \"patch\"\ncorners = [[{}, 0.0, {near}], [{half}, 0.0, {near}], [{half}, 0.0, {far}], [{}, 0.0, {far}]]\nmaterial = {{ color = [1.0, 1.0, 1.0] }}\n",
            -half, -half
        );
    }
    let mut scene = Scene::parse(&text, std::path::Path::new("."))?;
    let colour = |c: [u8; 3]| c.map(|v| srgb_to_linear(v as f32 / 255.0));
    let (red, cream, ink) = (colour([190, 45, 30]), colour([245, 238, 215]), colour([25, 40, 90]));
    let rgba = |c: [f32; 3]| [c[0], c[1], c[2], 1.0];
    let letters = text_image(32, &TextParams { text: "TEXTURE".into(), soft: 0.0 })?;
    let lettered = Image::from_fn(letters.width, letters.height, |x, y| {
        let k = letters.get(x, y);
        rgba([0, 1, 2].map(|c| ink[c] * k + cream[c] * (1.0 - k)))
    });
    let mapped = |texture: &Arc<FilteredTexture>, repeat: Vec2| MappedTexture {
        texture: texture.clone(),
        mapping: Mapping::uv(UvTransform::repeat(repeat)),
    };
    let sphere = Arc::new(FilteredTexture::new(&lettered, TextureOptions::default()));
    scene.materials[0].set_colour_texture(mapped(&sphere, Vec2::new(2.0, 5.0)), false);
    let checks = Image::from_fn(64, 64, |x, y| if (x / 4 + y / 4) % 2 == 0 { rgba(red) } else { rgba(cream) });
    let board = Arc::new(FilteredTexture::new(&checks, TextureOptions::default()));
    for (k, (near, far, half)) in ROWS.into_iter().enumerate() {
        let repeat = Vec2::new(2.0 * half / PERIOD, (near - far) / PERIOD);
        scene.materials[k + 1].set_colour_texture(mapped(&board, repeat), false);
    }
    Ok(scene)
}

/// The `--bump` view: the classic plane and sphere, grey and shiny, the plane carrying a grid of grooves
/// (the same on every row: Blinn's scale-invariant D), lit from beyond the horizon so every groove glints.
fn bump_scene() -> Result<Scene> {
    let mut text = CLASSIC
        .replace("intensity = 0.55", "intensity = 0.15")
        .replace("direction = [-0.4, -1.0, -0.5]\nintensity = 0.6", "direction = [0.15, -0.35, 1.0]\nintensity = 1.0");
    text = text.replace(
        "material = { color = [1.0, 1.0, 1.0], specular = 0.2, shininess = 30.0 }",
        "material = { color = [0.6, 0.6, 0.6], specular = 0.7, shininess = 60.0 }",
    );
    for (near, far, half) in ROWS {
        let repeat = [2.0 * half / PERIOD, (near - far) / PERIOD];
        text += &format!(
            "\n[[object]]\nshape = \"patch\"\ncorners = [[{}, 0.0, {near}], [{half}, 0.0, {near}], [{half}, 0.0, {far}], [{}, 0.0, {far}]]\n\
             [object.material]\ncolor = [0.45, 0.45, 0.5]\nspecular = 0.8\nshininess = 80.0\n\
             bump = {{ generator = {{ kind = \"grid\", size = 64, cells = 2, line_width = 0.25, soft = 0.15 }}, scale = 0.02, invariant = true, repeat = [{:?}, {:?}] }}\n",
            -half, -half, repeat[0], repeat[1]
        );
    }
    Scene::parse(&text, std::path::Path::new("."))
}

/// What a sheet compares: the colour textures' filters, or the bump functions'.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Subject {
    Textures,
    Bumps,
}

impl Subject {
    /// The options that render `scene` with every texture (or bump) filtered by `filter` (a colour texture
    /// takes its texture filter).
    fn with_filter(self, scene: &mut Scene, options: &RenderOptions, filter: BumpFilter) -> RenderOptions {
        match self {
            Subject::Textures => {
                scene.set_texture_filter(filter.texture);
                options.clone()
            }
            Subject::Bumps => RenderOptions { bump_filter: Some(filter), ..options.clone() },
        }
    }

    /// The filter named `name`, as `--filters` (or `--bump-filter`, for bumps) reads it.
    fn parse(self, name: &str) -> Result<BumpFilter> {
        match self {
            Subject::Textures => match Filter::parse(name) {
                Some(texture) => Ok(BumpFilter { texture, slopes: SlopeFilter::Plain }),
                None => {
                    Err(Error::Invalid(format!("--filters: unknown filter \"{name}\" (expected {})", Filter::names())))
                }
            },
            Subject::Bumps => BumpFilter::parse(name).ok_or_else(|| {
                Error::Invalid(format!("--filters: unknown bump filter \"{name}\" (expected {})", BumpFilter::names()))
            }),
        }
    }
}

/// A filter's panel with its time and its error against the ground truth.
struct Panel {
    name: String,
    pixels: Vec<[f32; 3]>,
    ms: f64,
    rmse: f64,
}

fn rmse(a: &[[f32; 3]], b: &[[f32; 3]]) -> f64 {
    let sum: f64 =
        a.iter().zip(b).map(|(x, y)| (0..3).map(|c| ((x[c] - y[c]) as f64).powi(2)).sum::<f64>() / 3.0).sum();
    (sum / a.len() as f64).sqrt()
}

fn psnr(rmse: f64) -> f64 {
    if rmse > 0.0 {
        -20.0 * rmse.log10()
    } else {
        f64::INFINITY
    }
}

pub fn run(args: &FiltersArgs) -> Result<()> {
    crate::set_threads(args.threads)?;
    crate::output::require_extension(&args.output, &["png"])?;
    sheet::check_columns(args.columns)?;
    let subject = if args.bump { Subject::Bumps } else { Subject::Textures };
    let defaults: &[&str] = if args.bump { &DEFAULT_BUMP_FILTERS } else { &DEFAULT_FILTERS };
    let names: Vec<String> = if args.filters.is_empty() {
        defaults.iter().map(|s| s.to_string()).collect()
    } else {
        args.filters.iter().map(|s| s.trim().to_string()).collect()
    };
    let filters = names.iter().map(|n| subject.parse(n)).collect::<Result<Vec<_>>>()?;
    let options = RenderOptions { width: args.width, height: args.height, ..RenderOptions::default() };
    options.validate()?;
    let mut scene = match (&args.scene, subject) {
        (Some(_), _) => load_scene(args.scene.as_deref())?,
        (None, Subject::Textures) => classic_scene()?,
        (None, Subject::Bumps) => bump_scene()?,
    };
    let has_subject = |m: &wrinkle::Material| match subject {
        Subject::Textures => m.colour_texture().is_some(),
        Subject::Bumps => m.bump.is_some(),
    };
    if !scene.materials.iter().any(has_subject) {
        let what = if args.bump { "bump map" } else { "colour texture" };
        return Err(Error::Invalid(format!("the scene has no {what} to filter")));
    }

    let bar = sheet::progress("filters", filters.len() + 2);
    bar.set_message("ground truth");
    // Each sample reads the bilinear texture (or bump table, full resolution) at its own (u,v): the samples
    // integrate the colour over the preimage.
    let bilinear = BumpFilter { texture: Filter::Reconstruct(Kernel::Bilinear), slopes: SlopeFilter::Plain };
    let exact = subject.with_filter(&mut scene, &options, bilinear);
    let truth_of = |seed: u32| {
        let truth = RenderOptions { spp: TRUTH_SPP, sampler: Sampler::Sobol, seed, ..exact.clone() };
        let t = Instant::now();
        let frame = render(&scene, &truth).map(|f| (f.color, t.elapsed().as_secs_f64() * 1e3));
        bar.inc(1);
        frame
    };
    let (truth, _) = truth_of(0)?;
    // The same truth from other samples: how far it is from the first is the truth's own noise floor.
    let (again, again_ms) = truth_of(1)?;
    let floor = Panel { name: "truth, seed 1".into(), rmse: rmse(&again, &truth), pixels: again, ms: again_ms };
    let mut panels = Vec::new();
    for (name, &filter) in names.iter().zip(&filters) {
        bar.set_message(name.clone());
        let options = subject.with_filter(&mut scene, &options, filter);
        // Warm up (ripmaps and summed-area tables are built on first use), then time the second frame.
        render(&scene, &options)?;
        let t = Instant::now();
        let pixels = render(&scene, &options)?.color;
        let ms = t.elapsed().as_secs_f64() * 1e3;
        panels.push(Panel { name: name.clone(), rmse: rmse(&pixels, &truth), pixels, ms });
        bar.inc(1);
    }
    bar.finish();
    // Its label: its own noise floor.
    let truth_label = format!("truth ({:.1} dB)", psnr(floor.rmse));
    panels.push(Panel { name: truth_label, pixels: truth, ms: f64::NAN, rmse: 0.0 });

    let labelled: Vec<sheet::Panel> = panels
        .iter()
        .map(|p| sheet::Panel {
            label: if p.rmse > 0.0 { format!("{}  {:.1} dB", p.name, psnr(p.rmse)) } else { p.name.clone() },
            pixels: p.pixels.clone(),
        })
        .collect();
    let sheet = sheet::compose(&labelled, args.width, args.height, args.columns);
    io::write_png_rgb8(&args.output, sheet.width, sheet.height, &sheet.pixels)?;
    let mut rows: Vec<&Panel> = panels[..panels.len() - 1].iter().collect();
    rows.push(&floor);
    print_table(&rows, args.json);
    Ok(())
}

/// The filters' rows, and last the truth rendered with another seed against the truth (its noise floor).
fn print_table(panels: &[&Panel], json: bool) {
    if json {
        let rows: Vec<String> = panels
            .iter()
            .map(|p| {
                format!(
                    "  {{\"filter\": \"{}\", \"ms\": {:.3}, \"rmse\": {:.6}, \"psnr_db\": {:.3}}}",
                    p.name,
                    p.ms,
                    p.rmse,
                    psnr(p.rmse)
                )
            })
            .collect();
        println!("[\n{}\n]", rows.join(",\n"));
    } else {
        println!("{:<12} {:>9} {:>9} {:>9}", "filter", "ms", "rmse", "psnr_db");
        for p in panels {
            println!("{:<12} {:>9.2} {:>9.5} {:>9.2}", p.name, p.ms, p.rmse, psnr(p.rmse));
        }
    }
}
