//! `wrinkle paint`: serves the paint page for a model or scene on 127.0.0.1 (docs/paint.md).

use clap::Args;
use std::path::PathBuf;
use wrinkle::Result;
use wrinkle_paint::{serve, Opening, Options, Session, DEFAULT_PORT};

#[derive(Args, Debug)]
#[command(
    after_help = "Examples:\n  wrinkle paint scenes/paint_sphere.toml                 serves http://127.0.0.1:8478/ (or the next free port)\n  wrinkle paint model.obj --atlas-size 2048 --open       a mesh with its texture coordinates, in a browser\n  wrinkle paint model-painted/scene.toml                 resumes painting a saved model\n\nThe page: left drag paints, right drag (or Alt + drag) orbits, Shift + drag pans, the wheel zooms.\nThe same API the page uses answers at /api/... (docs/paint.md)."
)]
pub struct PaintArgs {
    /// A scene file (its first object is painted, or --object N) or a model file (OBJ, glTF, GLB).
    pub model: PathBuf,
    /// The port to listen on (default: 8478, or the next free one).
    #[arg(long)]
    pub port: Option<u16>,
    /// The side of the square texture atlas painted, in texels (a saved scene's channels keep their size).
    #[arg(long, default_value_t = 1024)]
    pub atlas_size: usize,
    /// Which object of a scene file to paint (its index in the file).
    #[arg(long, default_value_t = 0)]
    pub object: usize,
    /// The view's size in pixels, WIDTHxHEIGHT.
    #[arg(long, default_value = "960x540", value_parser = parse_size)]
    pub view: (usize, usize),
    /// Lay out a new texture atlas for a mesh even where it has texture coordinates (overlapping or
    /// mirrored ones); a mesh without any always gets one.
    #[arg(long)]
    pub new_atlas: bool,
    /// Where Save writes the channels and the scene (default: MODEL-painted/ beside the model).
    #[arg(long)]
    pub save_dir: Option<PathBuf>,
    /// Open the page in a browser, where one is found.
    #[arg(long)]
    pub open: bool,
    /// Serve nothing: time N orbit frames and N brush dabs (radius 30 px) in-process and print the medians.
    #[arg(long, value_name = "N")]
    pub bench: Option<usize>,
}

fn opening(args: &PaintArgs) -> Opening {
    Opening { object: args.object, atlas_size: args.atlas_size, view: args.view, new_atlas: args.new_atlas }
}

fn parse_size(text: &str) -> std::result::Result<(usize, usize), String> {
    let parsed = text.split_once('x').and_then(|(w, h)| Some((w.trim().parse().ok()?, h.trim().parse().ok()?)));
    parsed.ok_or_else(|| format!("expected WIDTHxHEIGHT, such as 960x540, got {text}"))
}

pub fn run(args: &PaintArgs) -> Result<()> {
    if let Some(steps) = args.bench {
        return bench(args, steps.max(1));
    }
    let options =
        Options { model: args.model.clone(), opening: opening(args), port: args.port, save_dir: args.save_dir.clone() };
    let open = args.open;
    serve(options, |address, session| {
        let url = format!("http://{address}/");
        if args.port.is_none() && address.port() != DEFAULT_PORT {
            eprintln!("port {DEFAULT_PORT} is taken: listening on {}", address.port());
        }
        let state = session.state();
        println!(
            "wrinkle paint: {url} ({}, atlas {}x{}, saves to {}; Ctrl-C stops)",
            state.model,
            state.atlas_size,
            state.atlas_size,
            session.save_dir.display()
        );
        if let Some(u) = &state.unwrapped {
            println!(
                "texture atlas laid out: {} charts, {:.0}% of the image used, stretch {:.2} mean, {:.2} at most",
                u.charts,
                100.0 * u.utilisation,
                u.stretch_mean,
                u.stretch_max
            );
        }
        if open && open_browser(&url).is_err() {
            eprintln!("no browser could be opened: open {url} yourself");
        }
    })
}

/// Medians and best of the in-process frame and dab times (BENCHMARKS.md, "Painting").
fn bench(args: &PaintArgs, steps: usize) -> Result<()> {
    let mut session = Session::open(&args.model, &opening(args))?;
    let times = wrinkle_paint::bench::measure(&mut session, steps, 30.0)?;
    let (w, h) = args.view;
    println!("wrinkle paint --bench: {w}x{h}, atlas {}, {} threads", args.atlas_size, rayon::current_num_threads());
    let rows = [
        ("orbit frame (render + JPEG)", times.orbit),
        ("dab of 30 px + frame", times.colour_dab),
        ("height dab of 30 px + frame", times.height_dab),
    ];
    for (name, mut t) in rows {
        t.sort_by(f64::total_cmp);
        let median = t[t.len() / 2];
        println!("{name:30} median {median:7.2} ms  best {:7.2} ms  ({:.1} per second)", t[0], 1e3 / median);
    }
    Ok(())
}

fn open_browser(url: &str) -> std::io::Result<()> {
    let opener = if cfg!(target_os = "macos") { "open" } else { "xdg-open" };
    std::process::Command::new(opener).arg(url).spawn().map(|_| ())
}
