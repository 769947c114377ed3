//! The arithmetic alone of `wrinkle emboss` and `wrinkle normalmap`, in memory, on all cores: the same row
//! kernels the commands stream through, over a 4096 x 4096 height field (no decoding, no encoding).
//! Prints the median and best of 15 runs in Mpixel/s.
//!
//!     cargo run --release -p wrinkle --example emboss_kernel [-- THREADS]

use rayon::prelude::*;
use std::time::Instant;
use wrinkle::bump::normal_map::{encode_rgb, Convention, Kernel, NormalMap};
use wrinkle::bump::schlag::{to_grey8, Emboss};
use wrinkle::image::strips::Window;

const SIDE: usize = 4096;

fn main() {
    if let Some(n) = std::env::args().nth(1).and_then(|a| a.parse().ok()) {
        rayon::ThreadPoolBuilder::new().num_threads(n).build_global().expect("one pool");
    }
    // Padded rows (one repeated pixel each side) of an 8-bit-valued height field with detail everywhere.
    let pw = SIDE + 2;
    let mut rows = vec![0.0f32; pw * SIDE];
    rows.par_chunks_mut(pw).enumerate().for_each(|(y, row)| {
        for x in 0..SIDE {
            let (xf, yf) = (x as f32, y as f32);
            row[x + 1] =
                (127.5 + 60.0 * (xf * 0.013).sin() * (yf * 0.021).cos() + 40.0 * ((xf + yf) * 0.11).sin()).round();
        }
        row[0] = row[1];
        row[pw - 1] = row[pw - 2];
    });
    let window = |y: usize| Window {
        above: &rows[y.saturating_sub(1) * pw..][..pw],
        row: &rows[y * pw..][..pw],
        below: &rows[(y + 1).min(SIDE - 1) * pw..][..pw],
    };
    let emboss = Emboss::new(135.0, 45.0, 3.0).expect("valid");
    let mut grey = vec![0u8; SIDE * SIDE];
    let emboss_rate = time(|| {
        grey.par_chunks_mut(SIDE).enumerate().for_each_init(
            || vec![0.0f32; SIDE],
            |shade, (y, out)| {
                emboss.shade_row(window(y), shade);
                to_grey8(shade, out);
            },
        )
    });
    let map = NormalMap::new(Kernel::Sobel, 3.0, Convention::OpenGl).expect("valid");
    let mut rgb = vec![0u8; 3 * SIDE * SIDE];
    let normal_rate = time(|| {
        rgb.par_chunks_mut(3 * SIDE).enumerate().for_each_init(
            || vec![0.0f32; 3 * SIDE],
            |n, (y, out)| {
                let (nx, rest) = n.split_at_mut(SIDE);
                let (ny, nz) = rest.split_at_mut(SIDE);
                map.normals_row(window(y), nx, ny, nz);
                encode_rgb(nx, ny, nz, false, out);
            },
        )
    });
    println!(
        "threads={} emboss: median {:.0} Mpixel/s, best {:.0}; normalmap: median {:.0} Mpixel/s, best {:.0} ({SIDE}x{SIDE}, checksum {})",
        rayon::current_num_threads(),
        emboss_rate.0,
        emboss_rate.1,
        normal_rate.0,
        normal_rate.1,
        grey.iter().map(|&v| v as u64).sum::<u64>() + rgb.iter().map(|&v| v as u64).sum::<u64>()
    );
}

/// (median, best) Mpixel/s of 15 runs after a warm-up.
fn time(mut f: impl FnMut()) -> (f64, f64) {
    f();
    let mut rates: Vec<f64> = (0..15)
        .map(|_| {
            let t = Instant::now();
            f();
            (SIDE * SIDE) as f64 / t.elapsed().as_secs_f64() / 1e6
        })
        .collect();
    rates.sort_by(f64::total_cmp);
    (rates[7], rates[14])
}
