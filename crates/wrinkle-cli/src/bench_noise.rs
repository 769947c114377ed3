//! `wrinkle bench-noise`: throughput of 3D Perlin noise and of fBm over points uniform in [0, 10)^3, and
//! the time of a 1024x1024 6-octave fBm texture; the default (hashed) noise and Perlin's reference
//! (improved, permutation table) side by side.

use clap::Args;
use rayon::prelude::*;
use std::time::Instant;
use wrinkle::procedural::bake::bake;
use wrinkle::procedural::effects::{Kind, Params, Pattern};
use wrinkle::procedural::fbm::{Fractal, Octaves, Sum};
use wrinkle::procedural::perlin::uniform_points;
use wrinkle::procedural::{Perlin, Variant};
use wrinkle::{Error, Result};

#[derive(Args, Debug)]
#[command(after_help = "Examples:\n  wrinkle bench-noise\n  wrinkle bench-noise --threads 1 --rounds 20")]
pub struct BenchNoiseArgs {
    /// Points per round, uniform in [0, 10)^3
    #[arg(long, default_value_t = 4_000_000)]
    pub points: usize,
    /// Timed rounds per measurement (after one warm-up round); the median is reported
    #[arg(long, default_value_t = 10)]
    pub rounds: usize,
    /// Octaves of the fBm measurement
    #[arg(long, default_value_t = 6)]
    pub octaves: u32,
    /// Worker threads (all cores when omitted)
    #[arg(long)]
    pub threads: Option<usize>,
}

/// A kernel over coordinate slices into an output slice.
type Kernel<'a> = dyn Fn(&[f32], &[f32], &[f32], &mut [f32]) + Sync + 'a;

/// Points handed to one worker at a time.
const CHUNK: usize = 1 << 14;

/// Median and minimum of `rounds` timings of `job`, milliseconds, after one warm-up run.
fn time(rounds: usize, mut job: impl FnMut()) -> (f64, f64) {
    job();
    let mut t: Vec<f64> = (0..rounds)
        .map(|_| {
            let s = Instant::now();
            job();
            s.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    t.sort_by(f64::total_cmp);
    (t[t.len() / 2], t[0])
}

pub fn run(args: &BenchNoiseArgs) -> Result<()> {
    if args.points == 0 || args.points > 100_000_000 {
        return Err(Error::Invalid(format!("--points must be between 1 and 100000000, got {}", args.points)));
    }
    if args.rounds == 0 || args.rounds > 10_000 {
        return Err(Error::Invalid(format!("--rounds must be between 1 and 10000, got {}", args.rounds)));
    }
    if args.octaves == 0 || args.octaves > wrinkle::procedural::fbm::MAX_OCTAVES {
        return Err(Error::Invalid(format!("--octaves must be between 1 and 24, got {}", args.octaves)));
    }
    crate::set_threads(args.threads)?;
    let [x, y, z] = uniform_points(args.points, 10.0, 1);
    let mut out = vec![0.0f32; args.points];
    let chunks = |out: &mut [f32], f: &Kernel<'_>| {
        out.par_chunks_mut(CHUNK).enumerate().for_each(|(c, o)| {
            let r = c * CHUNK..c * CHUNK + o.len();
            f(&x[r.clone()], &y[r.clone()], &z[r], o)
        })
    };
    let mps = |ms: f64| args.points as f64 / (ms * 1e3);
    let mut line = format!("threads={} points={}", rayon::current_num_threads(), args.points);
    let mut checksum = 0.0;
    for (name, variant) in [("", Variant::Hashed), ("_reference", Variant::Improved)] {
        let noise = Perlin::new(variant, 0);
        let fbm = Fractal::new(noise.clone(), Sum::Fbm, Octaves { count: args.octaves, ..Octaves::default() });
        let (noise_ms, noise_min) = time(args.rounds, || chunks(&mut out, &|x, y, z, o| noise.noise3_many(x, y, z, o)));
        checksum += out.iter().map(|&v| v as f64).sum::<f64>();
        let (fbm_ms, fbm_min) = time(args.rounds, || chunks(&mut out, &|x, y, z, o| fbm.eval3_many(x, y, z, o)));
        // The texture tool's workload: a 1024x1024 fBm image (2D noise, all octaves resolved, on lanes).
        let mut params = Params::new(Kind::Fbm);
        params.octaves.count = args.octaves;
        params.variant = variant;
        let pattern = Pattern::new(params, 2, false)?;
        let (tex_ms, tex_min) = time(args.rounds, || {
            bake(&pattern, 1024, 1024);
        });
        let o = args.octaves;
        line += &format!(
            " perlin3{name}_mpts={:.1} perlin3{name}_best_mpts={:.1} fbm{o}{name}_mpts={:.1} fbm{o}{name}_best_mpts={:.1} texture1024_fbm{name}_ms={tex_ms:.1} texture1024_fbm{name}_best_ms={tex_min:.1}",
            mps(noise_ms),
            mps(noise_min),
            mps(fbm_ms),
            mps(fbm_min),
        );
    }
    println!("{line} checksum={checksum:.3}");
    Ok(())
}
