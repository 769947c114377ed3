//! FastNoise2 on `wrinkle bench-noise`'s workload: 3D Perlin noise and 6-octave fBm at points uniform in
//! [0, 10)^3, and a 1024x1024 6-octave 2D fBm image; medians and bests of the rounds after a warm-up, in
//! the same key=value form as wrinkle's line. Usage: fastnoise2-bench [POINTS] [ROUNDS] [THREADS]
use fastnoise2::Node;
use std::time::Instant;

/// Points handed to one thread at a time (as bench-noise's chunks).
const CHUNK: usize = 1 << 14;

fn perlin() -> Node {
    let mut n = Node::from_name("Perlin").expect("FastNoise2 has Perlin");
    // Lattice cells of one unit, as wrinkle's noise (the default feature scale is 100).
    n.set("Feature Scale", 1.0f32).expect("Perlin has a feature scale");
    n
}

fn fbm(octaves: i32) -> Node {
    let source = perlin();
    let mut n = Node::from_name("FractalFBm").expect("FastNoise2 has FractalFBm");
    n.set("Source", &source).expect("fBm has a source");
    n.set("Octaves", octaves).expect("fBm has octaves");
    n.set("Gain", 0.5f32).expect("fBm has a gain");
    n.set("Lacunarity", 2.0f32).expect("fBm has a lacunarity");
    n
}

/// A SplitMix64 stream mapped to [0, 10).
fn points(count: usize, seed: u64) -> Vec<f32> {
    let mut s = seed;
    (0..count)
        .map(|_| {
            s = s.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = s;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32 * 10.0
        })
        .collect()
}

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

/// Runs `make`'s node over every chunk of the points on `threads` threads (one node per thread).
fn run(make: &(dyn Fn() -> Node + Sync), xyz: &[Vec<f32>; 3], out: &mut [f32], threads: usize) {
    let per = out.len().div_ceil(threads).div_ceil(CHUNK) * CHUNK;
    std::thread::scope(|s| {
        for (t, o) in out.chunks_mut(per).enumerate() {
            s.spawn(move || {
                let node = make();
                for (c, oc) in o.chunks_mut(CHUNK).enumerate() {
                    let start = t * per + c * CHUNK;
                    let r = start..start + oc.len();
                    // SAFETY: every slice has the output's length and the node's sources are set.
                    unsafe {
                        node.gen_position_array_3d_unchecked(
                            oc,
                            &xyz[0][r.clone()],
                            &xyz[1][r.clone()],
                            &xyz[2][r],
                            0.0,
                            0.0,
                            0.0,
                            0,
                        );
                    }
                }
            });
        }
    });
}

fn main() {
    let arg = |i: usize, d: usize| std::env::args().nth(i).map_or(d, |a| a.parse().expect("a count"));
    let (count, rounds, threads) = (arg(1, 4_000_000), arg(2, 10), arg(3, 1).max(1));
    let xyz = [points(count, 1), points(count, 2), points(count, 3)];
    let mut out = vec![0.0f32; count];
    let (noise_ms, noise_min) = time(rounds, || run(&perlin, &xyz, &mut out, threads));
    let checksum: f64 = out.iter().map(|&v| v as f64).sum();
    let (fbm_ms, fbm_min) = time(rounds, || run(&|| fbm(6), &xyz, &mut out, threads));
    let image = fbm(6);
    let mut pixels = vec![0.0f32; 1024 * 1024];
    // One thread: FastNoise2 generates a grid in one call.
    let (tex_ms, tex_min) = time(rounds, || unsafe {
        image.gen_uniform_grid_2d_unchecked(&mut pixels, 0.0, 0.0, 1024, 1024, 4.0 / 1024.0, 4.0 / 1024.0, 0);
    });
    let mps = |ms: f64| count as f64 / (ms * 1e3);
    println!(
        "fastnoise2 simd_level={} threads={threads} points={count} perlin3_mpts={:.1} perlin3_best_mpts={:.1} fbm6_mpts={:.1} fbm6_best_mpts={:.1} texture1024_fbm_ms={tex_ms:.1} texture1024_fbm_best_ms={tex_min:.1} checksum={checksum:.3}",
        image.get_simd_level(),
        mps(noise_ms),
        mps(noise_min),
        mps(fbm_ms),
        mps(fbm_min),
    );
}
