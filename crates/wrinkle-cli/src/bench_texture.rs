//! `wrinkle bench-texture`: lookups per second of each texture filter on a large RGBA8 texture, for
//! isotropic and 8:1 anisotropic footprints, in random and in scanline order, on one thread and on all;
//! and the time to build the MIP pyramid.

use clap::Args;
use glam::{Vec2, Vec4};
use rayon::prelude::*;
use std::hint::black_box;
use std::time::Instant;
use wrinkle::bump::BumpTable;
use wrinkle::image::color::srgb8_decode_table;
use wrinkle::texture::mip::pyramid;
use wrinkle::{
    Error, Filter, FilterOptions, FilteredTexture, Footprint, Image, MipFilter, Result, TextureOptions, Wrap,
};

#[derive(Args, Debug)]
#[command(
    after_help = "Examples:\n  wrinkle bench-texture                                  4096x4096, trilinear, aniso and ewa\n  wrinkle bench-texture --filters bilinear,trilinear,ripmap,sat,aniso,ewa --lookups 4000000\n  wrinkle bench-texture --size 1024 --threads 1"
)]
pub struct BenchTextureArgs {
    /// Texture side in texels (RGBA8, sRGB).
    #[arg(long, default_value_t = 4096)]
    pub size: usize,
    /// Lookups per timed run.
    #[arg(long, default_value_t = 1_000_000)]
    pub lookups: usize,
    /// Filters to time (comma-separated).
    #[arg(long, value_delimiter = ',', default_value = "trilinear,aniso,ewa")]
    pub filters: Vec<String>,
    /// Timed runs per figure; the median is printed. A run lasts at least 50 ms: a short set of lookups is
    /// repeated within it.
    #[arg(long, default_value_t = 3)]
    pub rounds: usize,
    /// Worker threads for the all-cores figures and the pyramid (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Lookups per `lookup_batch` call in the batch figures (16: OpenImageIO's batch width).
    #[arg(long, default_value_t = 16, value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub batch: u32,
}

/// The lookups of one run: where and how large.
#[derive(Default)]
struct Lookups {
    st: Vec<Vec2>,
    fp: Vec<Footprint>,
}

impl Lookups {
    fn push(&mut self, st: Vec2, fp: Footprint) {
        self.st.push(st);
        self.fp.push(fp);
    }
}

/// A small xorshift generator: the same sets on every run.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }
}

/// A footprint of width `w` (one period units), `ratio`:1 anisotropic (major axis `ratio` w), at `angle`.
fn footprint(w: f32, ratio: f32, angle: f32) -> Footprint {
    let (c, s) = (angle.cos(), angle.sin());
    Footprint { dudx: ratio * w * c, dvdx: ratio * w * s, dudy: -w * s, dvdy: w * c }
}

/// Widths log-uniform between 1/4096 and 1/64.
fn width(rng: &mut Rng) -> f32 {
    (2f32).powf(-12.0 + 6.0 * rng.next())
}

/// `n` lookups at random (s, t), or walking along rows one footprint width apart (as a render reads).
fn lookups(n: usize, ratio: f32, scanline: bool) -> Lookups {
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15 ^ (ratio as u64) ^ (scanline as u64) << 8);
    let mut out = Lookups::default();
    if !scanline {
        for _ in 0..n {
            let st = Vec2::new(rng.next(), rng.next());
            out.push(st, footprint(width(&mut rng), ratio, rng.next() * std::f32::consts::TAU));
        }
        return out;
    }
    while out.st.len() < n {
        // One row of 256 lookups: one width and angle, the start anywhere.
        let (w, angle) = (width(&mut rng), rng.next() * std::f32::consts::TAU);
        let start = Vec2::new(rng.next(), rng.next());
        for k in 0..256.min(n - out.st.len()) {
            out.push(start + Vec2::new(k as f32 * w, 0.0), footprint(w, ratio, angle));
        }
    }
    out
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// CPU time this thread has run, in seconds, so that one-thread rates on a shared, loaded machine count the
/// time the thread actually ran, not the time it waited for a core. The thread's CPU clock is exact to the
/// nanosecond when read; /proc/thread-self/schedstat, read before, is brought up to date only at scheduler
/// ticks, so runs of a few milliseconds read whole ticks of CPU time or none: rates of hundreds of millions
/// of lookups a second, and infinite ones.
fn thread_cpu_s() -> Option<f64> {
    let mut t = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: clock_gettime writes one timespec, which `t` is.
    let ok = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut t) } == 0;
    ok.then_some(t.tv_sec as f64 + t.tv_nsec as f64 * 1e-9)
}

/// The shortest timed round: a set of lookups that takes less is run again within the round, so that the
/// clocks' resolution and the start of the workers weigh little in any figure.
const MIN_ROUND_S: f64 = 0.05;

/// Million lookups per second, on this thread or on every worker: (per wall-clock second, per CPU second of
/// this thread when on one thread).
fn rate(tex: &FilteredTexture, set: &Lookups, parallel: bool, rounds: usize) -> (f64, Option<f64>) {
    let run =
        |st: &[Vec2], fp: &[Footprint]| st.iter().zip(fp).fold(Vec4::ZERO, |acc, (p, f)| acc + tex.lookup(p.x, p.y, f));
    timed(set, parallel, rounds, run)
}

/// The same through `FilteredTexture::lookup_batch`, `batch` lookups a call.
fn rate_batch(tex: &FilteredTexture, set: &Lookups, batch: usize, parallel: bool, rounds: usize) -> (f64, Option<f64>) {
    let run = |st: &[Vec2], fp: &[Footprint]| {
        let mut out = [Vec4::ZERO; CHUNK];
        for ((st, fp), out) in st.chunks(batch).zip(fp.chunks(batch)).zip(out[..st.len()].chunks_mut(batch)) {
            tex.lookup_batch(st, fp, out);
        }
        out.iter().sum()
    };
    timed(set, parallel, rounds, run)
}

/// Lookups per call of a timed closure (and per parallel task).
const CHUNK: usize = 4096;

/// Times `run` over the set in chunks, on this thread or on every worker.
fn timed(
    set: &Lookups,
    parallel: bool,
    rounds: usize,
    run: impl Fn(&[Vec2], &[Footprint]) -> Vec4 + Sync + Send,
) -> (f64, Option<f64>) {
    let chunks = || set.st.chunks(CHUNK).zip(set.fp.chunks(CHUNK));
    let (mut wall, mut cpu) = (Vec::new(), Vec::new());
    for _ in 0..rounds {
        let (t, c) = (Instant::now(), thread_cpu_s());
        let mut passes = 0;
        while passes == 0 || t.elapsed().as_secs_f64() < MIN_ROUND_S {
            let sum = if parallel {
                set.st
                    .par_chunks(CHUNK)
                    .zip(set.fp.par_chunks(CHUNK))
                    .map(|(s, f)| run(s, f))
                    .reduce(|| Vec4::ZERO, |a, b| a + b)
            } else {
                chunks().map(|(s, f)| run(s, f)).sum()
            };
            black_box(sum);
            passes += 1;
        }
        // Seconds per pass over the set.
        wall.push(t.elapsed().as_secs_f64() / passes as f64);
        if let (Some(c0), Some(c1)) = (c, thread_cpu_s()) {
            cpu.push((c1 - c0) / passes as f64);
        }
    }
    let per_s = |v: Vec<f64>| set.st.len() as f64 / median(v) / 1e6;
    (per_s(wall), (!parallel && cpu.len() == rounds).then(|| per_s(cpu)))
}

pub fn run(args: &BenchTextureArgs) -> Result<()> {
    crate::set_threads(args.threads)?;
    if !(16..=16384).contains(&args.size) {
        return Err(Error::Invalid(format!("--size must be between 16 and 16384, got {}", args.size)));
    }
    if args.lookups == 0 || args.lookups > 100_000_000 {
        return Err(Error::Invalid(format!("--lookups must be between 1 and 100000000, got {}", args.lookups)));
    }
    if args.rounds == 0 || args.rounds > 100 {
        return Err(Error::Invalid(format!("--rounds must be between 1 and 100, got {}", args.rounds)));
    }
    let filters = args
        .filters
        .iter()
        .map(|n| {
            Filter::parse(n.trim()).ok_or_else(|| {
                Error::Invalid(format!("--filters: unknown filter \"{n}\" (expected {})", Filter::names()))
            })
        })
        .collect::<Result<Vec<_>>>()?;
    let n = args.size;
    let threads = rayon::current_num_threads();
    // Value noise with some structure: every texel different, like a photograph at this scale.
    let mut rng = Rng(7);
    let bytes: Vec<[u8; 4]> = (0..n * n).map(|_| [0, 1, 2, 3].map(|_| (rng.next() * 255.0) as u8)).collect();
    let image = Image { width: n, height: n, pixels: bytes };
    // The pyramid alone: every level from the decoded full-resolution texture, in linear light, as images.
    let decode = srgb8_decode_table();
    let linear = Image {
        width: n,
        height: n,
        pixels: image
            .pixels
            .iter()
            .map(|p| [decode[p[0] as usize], decode[p[1] as usize], decode[p[2] as usize], p[3] as f32 / 255.0])
            .collect(),
    };
    let builds: Vec<f64> = (0..args.rounds)
        .map(|_| {
            let t = Instant::now();
            black_box(pyramid(&linear, MipFilter::Box, [Wrap::Repeat; 2]));
            t.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    drop(linear);
    // The whole texture as a scene loads it: decode, pyramid, levels stored in 8 bits.
    let t = Instant::now();
    let texture = FilteredTexture::from_rgba8(&image, true, TextureOptions::default());
    let whole_ms = t.elapsed().as_secs_f64() * 1e3;
    println!(
        "pyramid size={n}x{n} filter=box threads={threads} build_ms={:.1} texture_ms={whole_ms:.1} (texture: sRGB decode, pyramid, 8-bit levels)",
        median(builds)
    );
    drop(image);
    // A bump table of the same size: its pyramid, then the moments of its slopes for LEAN filtering.
    let heights = Image { width: n, height: n, pixels: (0..n * n).map(|_| rng.next()).collect::<Vec<f32>>() };
    let (mut tables, mut moments) = (Vec::new(), Vec::new());
    for _ in 0..args.rounds {
        let t = Instant::now();
        let table = BumpTable::new(&heights);
        tables.push(t.elapsed().as_secs_f64() * 1e3);
        let t = Instant::now();
        black_box(table.moments());
        moments.push(t.elapsed().as_secs_f64() * 1e3);
    }
    drop(heights);
    println!(
        "bump-pyramid size={n}x{n} threads={threads} table_ms={:.1} lean_moments_ms={:.1}",
        median(tables),
        median(moments)
    );
    for filter in filters {
        let tex = texture.with_options(FilterOptions { filter, ..FilterOptions::default() });
        // Ripmaps and summed-area tables are built on first use: not part of the lookups timed.
        tex.lookup(0.5, 0.5, &footprint(1.0 / 256.0, 1.0, 0.0));
        for (shape, ratio) in [("iso", 1.0), ("aniso8", 8.0)] {
            for (order, scanline) in [("random", false), ("scanline", true)] {
                let set = lookups(args.lookups, ratio, scanline);
                let (one, one_cpu) = rate(&tex, &set, false, args.rounds);
                let (all, _) = rate(&tex, &set, true, args.rounds);
                let cpu = one_cpu.map_or(String::new(), |c| format!(" mlookups_per_cpu_s_1thread={c:.2}"));
                let batch = args.batch as usize;
                let (one_b, one_b_cpu) = rate_batch(&tex, &set, batch, false, args.rounds);
                let (all_b, _) = rate_batch(&tex, &set, batch, true, args.rounds);
                let cpu_b = one_b_cpu.map_or(String::new(), |c| format!(" batch_per_cpu_s_1thread={c:.2}"));
                println!(
                    "filter={} footprint={shape} order={order} mlookups_per_s_1thread={one:.2}{cpu} mlookups_per_s_{threads}threads={all:.2} batch={batch} batch_1thread={one_b:.2}{cpu_b} batch_{threads}threads={all_b:.2}",
                    filter.name()
                );
            }
        }
    }
    Ok(())
}
