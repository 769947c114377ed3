//! `wrinkle bench`: renders a scene repeatedly in-process and prints the median time per frame.

use crate::render::FrameArgs;
use clap::Args;
use std::path::PathBuf;
use wrinkle::{render, Error, Result};

#[derive(Args, Debug)]
#[command(
    after_help = "Examples:\n  wrinkle bench bench/canonical/sphere.toml --width 1920 --height 1080 --frames 20\n  wrinkle bench --spp 16 --frames 5"
)]
pub struct BenchArgs {
    /// Scene file (TOML); the embedded cover scene when omitted.
    pub scene: Option<PathBuf>,
    #[command(flatten)]
    pub frame: FrameArgs,
    /// Timed frames, after one warm-up frame.
    #[arg(long, default_value_t = 10)]
    pub frames: usize,
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

pub fn run(args: &BenchArgs) -> Result<()> {
    if args.frames == 0 || args.frames > 10_000 {
        return Err(Error::Invalid(format!("--frames must be between 1 and 10000, got {}", args.frames)));
    }
    let options = args.frame.options()?;
    let scene = args.frame.load_scene(args.scene.as_deref())?;
    render(&scene, &options)?;
    let mut totals = Vec::with_capacity(args.frames);
    let mut stages: [Vec<f64>; 5] = Default::default();
    for _ in 0..args.frames {
        let t = std::time::Instant::now();
        let frame = render(&scene, &options)?;
        totals.push(t.elapsed().as_secs_f64() * 1e3);
        let s = frame.stats;
        for (v, x) in stages.iter_mut().zip([s.tessellate_ms, s.setup_ms, s.bin_ms, s.shadow_ms, s.raster_shade_ms]) {
            v.push(x);
        }
    }
    let min = totals.iter().cloned().fold(f64::INFINITY, f64::min);
    let med = median(&mut totals);
    let mpix = (options.width * options.height) as f64 / (med * 1e3);
    println!(
        "median_ms={med:.2} min_ms={min:.2} mpixel_per_s={mpix:.1} frames={} size={}x{} spp={} bump={} threads={} tessellate_ms={:.2} setup_ms={:.2} bin_ms={:.2} shadow_ms={:.2} raster_shade_ms={:.2}",
        args.frames,
        options.width,
        options.height,
        options.spp,
        options.bump,
        rayon::current_num_threads(),
        median(&mut stages[0]),
        median(&mut stages[1]),
        median(&mut stages[2]),
        median(&mut stages[3]),
        median(&mut stages[4]),
    );
    Ok(())
}
