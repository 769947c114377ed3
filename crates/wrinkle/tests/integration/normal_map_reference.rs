//! Normal maps and their integration against analytic references: a ramp's normal is one constant vector
//! with the sign of each convention, for every kernel, streamed from a 16-bit PNG; Frankot-Chellappa gives
//! back a smooth non-periodic height from its exact gradients, and from the normals the streamed kernel made.

use std::path::PathBuf;
use wrinkle::bump::integrate::frankot_chellappa;
use wrinkle::bump::normal_map::{decode_normal, encode_rgb, Convention, Kernel, NormalMap};
use wrinkle::image::stream::{write_rows, ImageRows, PngCompression, RowFormat};
use wrinkle::image::strips::{filter_3x3, Edges, Window};

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("wrinkle-normal-ref-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Writes heights in [0, 1] as a 16-bit grey PNG.
fn write_heights16(path: &std::path::Path, w: usize, h: usize, heights: &[f64]) {
    let bytes: Vec<u8> = heights.iter().flat_map(|&v| ((v * 65535.0).round() as u16).to_be_bytes()).collect();
    let rows = RowFormat { channels: 1, sixteen: true };
    write_rows(path, w, h, rows, PngCompression::Fast, |sink| sink(&bytes)).unwrap();
}

/// The normal map of a PNG height file, streamed: unit normals as f32 triples, row 0 at the top.
fn normals_of(path: &std::path::Path, map: NormalMap) -> (usize, usize, Vec<[f32; 3]>) {
    let rows = ImageRows::open(path).unwrap();
    let (w, h) = (rows.width(), rows.height());
    let kernel = |_: usize, win: Window, _: Option<&[u8]>, s: &mut [f32], out: &mut [u8]| {
        let (nx, rest) = s.split_at_mut(w);
        let (ny, nz) = rest.split_at_mut(w);
        map.normals_row(win, nx, ny, nz);
        for x in 0..w {
            out[12 * x..12 * x + 12].copy_from_slice(&bytemuck_triple([nx[x], ny[x], nz[x]]));
        }
    };
    let mut raw = Vec::new();
    filter_3x3(
        rows,
        1.0,
        Edges::Clamp,
        None,
        None,
        12 * w,
        &kernel,
        &mut |r| {
            raw.extend_from_slice(r);
            Ok(())
        },
        &|_| {},
    )
    .unwrap();
    let normals = raw
        .chunks_exact(12)
        .map(|c| {
            let f = |k: usize| f32::from_le_bytes([c[4 * k], c[4 * k + 1], c[4 * k + 2], c[4 * k + 3]]);
            [f(0), f(1), f(2)]
        })
        .collect();
    (w, h, normals)
}

fn bytemuck_triple(v: [f32; 3]) -> [u8; 12] {
    let mut out = [0u8; 12];
    for k in 0..3 {
        out[4 * k..4 * k + 4].copy_from_slice(&v[k].to_le_bytes());
    }
    out
}

#[test]
fn a_ramps_normal_is_one_vector_with_the_conventions_sign() {
    // h = 0.2 + 0.003 x + 0.002 (up the picture): rising to the right and upwards.
    let (w, h) = (48, 32);
    let heights: Vec<f64> = (0..w * h).map(|k| 0.2 + 0.003 * (k % w) as f64 + 0.002 * (h - 1 - k / w) as f64).collect();
    let dir = scratch("ramp");
    let path = dir.join("ramp.png");
    write_heights16(&path, w, h, &heights);
    let strength = 40.0;
    // n = normalize(-S dh/dx, -S dh/dv, 1): tilted left and down the picture.
    let (gx, gy) = (-strength * 0.003f64, -strength * 0.002f64);
    let len = (gx * gx + gy * gy + 1.0).sqrt();
    for kernel in [Kernel::Central, Kernel::Sobel, Kernel::Scharr] {
        for convention in [Convention::OpenGl, Convention::DirectX] {
            let map = NormalMap::new(kernel, strength as f32, convention).unwrap();
            let (_, _, normals) = normals_of(&path, map);
            let sign_y = if convention == Convention::OpenGl { 1.0 } else { -1.0 };
            for y in 1..h - 1 {
                for x in 1..w - 1 {
                    let n = normals[y * w + x];
                    // 16-bit quantisation of the heights moves the slope by at most 1e-5 per pixel.
                    assert!((n[0] as f64 - gx / len).abs() < 2e-3, "{kernel:?} {convention:?} x ({x},{y}) {n:?}");
                    assert!((n[1] as f64 - sign_y * gy / len).abs() < 2e-3, "{kernel:?} {convention:?} y ({x},{y})");
                    assert!((n[2] as f64 - 1.0 / len).abs() < 2e-3);
                }
            }
            // Encoded: red below half (the normal leans left); the slope rises up the picture, so the normal
            // leans down it: OpenGL's green is below half, DirectX's above.
            let n = normals[(h / 2) * w + w / 2];
            let mut rgb = [0u8; 3];
            encode_rgb(&[n[0]], &[n[1]], &[n[2]], false, &mut rgb);
            assert!(rgb[0] < 128);
            assert_eq!(rgb[1] < 128, convention == Convention::OpenGl, "{convention:?} {rgb:?}");
            let back = decode_normal([rgb[0] as f32 / 255.0, rgb[1] as f32 / 255.0, rgb[2] as f32 / 255.0], convention);
            assert!((back[1] as f64 - gy / len).abs() < 0.01, "decoded to OpenGL's y");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Two smooth bumps and a slope: not periodic, with heights at every border.
fn smooth(x: f64, y: f64, w: f64, h: f64) -> f64 {
    let g = |cx: f64, cy: f64, r: f64| (-((x - cx).powi(2) + (y - cy).powi(2)) / (r * r)).exp();
    0.1 + 0.3 * x / w + 0.4 * g(0.3 * w, 0.4 * h, 0.15 * w) + 0.25 * g(0.7 * w, 0.65 * h, 0.1 * w) + 0.05 * y / h
}

fn rmse_after_mean(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len() as f64;
    let mean = a.iter().zip(b).map(|(x, y)| x - y).sum::<f64>() / n;
    (a.iter().zip(b).map(|(x, y)| (x - y - mean).powi(2)).sum::<f64>() / n).sqrt()
}

#[test]
fn frankot_chellappa_recovers_a_smooth_non_periodic_height() {
    let (w, h) = (96usize, 64usize);
    let (wf, hf) = (w as f64, h as f64);
    let want: Vec<f64> = (0..w * h).map(|k| smooth((k % w) as f64, (k / w) as f64, wf, hf)).collect();
    // Exact gradients by central differences of the analytic function (y down the rows).
    let e = 1e-4;
    let (mut p, mut q) = (Vec::new(), Vec::new());
    for k in 0..w * h {
        let (x, y) = ((k % w) as f64, (k / w) as f64);
        p.push(((smooth(x + e, y, wf, hf) - smooth(x - e, y, wf, hf)) / (2.0 * e)) as f32);
        q.push(((smooth(x, y + e, wf, hf) - smooth(x, y - e, wf, hf)) / (2.0 * e)) as f32);
    }
    let range = want.iter().cloned().fold(f64::MIN, f64::max) - want.iter().cloned().fold(f64::MAX, f64::min);
    let mirrored: Vec<f64> = frankot_chellappa(&p, &q, w, h, false).iter().map(|&v| v as f64).collect();
    let err = rmse_after_mean(&mirrored, &want);
    assert!(err < 0.01 * range, "mirrored: RMSE {err} of range {range}");
    // Taken as periodic, the same field is wrong at the seams: the mirroring is what makes it work.
    let periodic: Vec<f64> = frankot_chellappa(&p, &q, w, h, true).iter().map(|&v| v as f64).collect();
    assert!(rmse_after_mean(&periodic, &want) > 3.0 * err);
}

#[test]
fn height_to_normals_to_height_round_trip() {
    let (w, h) = (128usize, 96usize);
    let (wf, hf) = (w as f64, h as f64);
    let heights: Vec<f64> = (0..w * h).map(|k| smooth((k % w) as f64, (k / w) as f64, wf, hf)).collect();
    let dir = scratch("round");
    let path = dir.join("h.png");
    write_heights16(&path, w, h, &heights);
    let strength = 20.0f32;
    let (_, _, normals) = normals_of(&path, NormalMap::new(Kernel::Sobel, strength, Convention::OpenGl).unwrap());
    // p = dh/dx = -nx / (S nz), q = dh/dy down the rows = +ny / (S nz) (ny points up the picture).
    let p: Vec<f32> = normals.iter().map(|n| -n[0] / (strength * n[2])).collect();
    let q: Vec<f32> = normals.iter().map(|n| n[1] / (strength * n[2])).collect();
    let back: Vec<f64> = frankot_chellappa(&p, &q, w, h, false).iter().map(|&v| v as f64).collect();
    let range = heights.iter().cloned().fold(f64::MIN, f64::max) - heights.iter().cloned().fold(f64::MAX, f64::min);
    let err = rmse_after_mean(&back, &heights);
    assert!(err < 0.01 * range, "RMSE {err} of range {range}");
    let _ = std::fs::remove_dir_all(&dir);
}
