//! Schlag's emboss against references computed here from the formula of Lingard's notes (f64, explicit
//! 3x3 masks, clamped borders), a small image worked by hand, and the proof's properties: flat regions give
//! exactly [0 0 1].L, a ramp gives one shade away from the border, turning the light by 180 degrees mirrors
//! a symmetric bump. Also the streamed pipeline (PNG rows in strips) against the whole-image function.

use std::path::PathBuf;
use wrinkle::bump::schlag::{emboss_image, light_direction, to_grey8, Emboss};
use wrinkle::image::stream::{write_rows, ImageRows, PngCompression, RowFormat};
use wrinkle::image::strips::{filter_3x3, Edges, Window};
use wrinkle::ImageRef;

/// The masks of the notes: the top row of each is the image row above the pixel.
const MASK_U: [[f64; 3]; 3] = [[-1.0, 0.0, 1.0], [-1.0, 0.0, 1.0], [-1.0, 0.0, 1.0]];
const MASK_V: [[f64; 3]; 3] = [[1.0, 1.0, 1.0], [0.0, 0.0, 0.0], [-1.0, -1.0, -1.0]];

/// The emboss shade by the notes' formula in f64: N = [-i_u, -i_v, 6*255/w], N.L / (|N||L|), 0 when
/// negative, [0 0 1].L when i_u = i_v = 0. Pixels beyond the border repeat the nearest edge pixel.
fn reference(img: &[f64], w: usize, h: usize, az: f64, el: f64, width: f64) -> Vec<f64> {
    let (az, el) = (az.to_radians(), el.to_radians());
    let l = [az.cos() * el.cos(), az.sin() * el.cos(), el.sin()];
    let nz = 6.0 * 255.0 / width;
    let at = |x: isize, y: isize| img[y.clamp(0, h as isize - 1) as usize * w + x.clamp(0, w as isize - 1) as usize];
    let mut out = Vec::with_capacity(w * h);
    for y in 0..h as isize {
        for x in 0..w as isize {
            let (mut iu, mut iv) = (0.0, 0.0);
            for (r, dy) in (-1..=1).enumerate() {
                for (c, dx) in (-1..=1).enumerate() {
                    iu += MASK_U[r][c] * at(x + dx, y + dy);
                    iv += MASK_V[r][c] * at(x + dx, y + dy);
                }
            }
            let n = [-iu, -iv, nz];
            let shade = if iu == 0.0 && iv == 0.0 {
                l[2]
            } else {
                let ndotl = n[0] * l[0] + n[1] * l[1] + n[2] * l[2];
                (ndotl / (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt()).max(0.0)
            };
            out.push(shade);
        }
    }
    out
}

/// Deterministic pseudo-random bytes.
fn noise(len: usize, seed: u32) -> Vec<u8> {
    let mut s = seed;
    (0..len)
        .map(|_| {
            s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (s >> 24) as u8
        })
        .collect()
}

#[test]
fn three_by_three_worked_by_hand() {
    // 10 20 30       i_u = (30 + 60 + 90) - (10 + 40 + 70) = 60
    // 40 50 60       i_v = (10 + 20 + 30) - (70 + 80 + 90) = -180
    // 70 80 90       w = 6: N_z = 6 * 255 / 6 = 255, N = [-60, 180, 255], |N| = sqrt(101025) = 317.8443...
    // Light from the left on the horizon (azimuth 180, elevation 0): L = [-1, 0, 0], N.L = 60,
    // shade = 60 / 317.8443 = 0.188772..., 8-bit 48.137 -> 48.
    // Straight above (elevation 90): shade = 255 / 317.8443 = 0.802279..., 8-bit 204.58 -> 205.
    let img: Vec<f32> = (1..=9).map(|k| 10.0 * k as f32).collect();
    let left = emboss_image(ImageRef::new(3, 3, &img).unwrap(), &Emboss::new(180.0, 0.0, 6.0).unwrap()).pixels;
    assert!((left[4] - 0.188_772_2).abs() < 1e-6, "{}", left[4]);
    let above = emboss_image(ImageRef::new(3, 3, &img).unwrap(), &Emboss::new(0.0, 90.0, 6.0).unwrap()).pixels;
    assert!((above[4] - 0.802_279_3).abs() < 1e-6, "{}", above[4]);
    let mut bytes = [0u8; 2];
    to_grey8(&[left[4], above[4]], &mut bytes);
    assert_eq!(bytes, [48, 205]);
    // The corner (0,0) with clamped borders: columns -1,0,1 read 10,10,20 / 10,10,20 / 40,40,50, so
    // i_u = (20 + 20 + 50) - (10 + 10 + 40) = 30 and i_v = (10 + 10 + 20) - (40 + 40 + 50) = -90.
    let n = [-30.0f64, 90.0, 255.0];
    let want = n[2] / (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    assert!((above[0] as f64 - want).abs() < 1e-6);
}

#[test]
fn every_pixel_matches_the_formula() {
    let (w, h) = (37, 23);
    let bytes = noise(w * h, 5);
    let img: Vec<f32> = bytes.iter().map(|&b| (b / 4) as f32).collect();
    let img64: Vec<f64> = img.iter().map(|&v| v as f64).collect();
    for (az, el, width) in [(135.0, 45.0, 3.0), (10.0, 80.0, 1.0), (250.0, 5.0, 40.0), (-30.0, 30.0, 0.5)] {
        let got = emboss_image(ImageRef::new(w, h, &img).unwrap(), &Emboss::new(az, el, width).unwrap()).pixels;
        let want = reference(&img64, w, h, az as f64, el as f64, width as f64);
        for (k, (g, r)) in got.iter().zip(&want).enumerate() {
            assert!((*g as f64 - r).abs() < 2e-6, "az {az} el {el} w {width} pixel {k}: {g} vs {r}");
        }
    }
}

#[test]
fn flat_regions_give_exactly_the_flat_shade() {
    let img = vec![77.0f32; 16 * 9];
    for (az, el) in [(135.0f32, 45.0f32), (0.0, 0.0), (300.0, 89.0), (45.0, 90.0)] {
        let e = Emboss::new(az, el, 3.0).unwrap();
        let flat = light_direction(az, el)[2];
        assert!(
            emboss_image(ImageRef::new(16, 9, &img).unwrap(), &e).pixels.iter().all(|&s| s == flat),
            "az {az} el {el}"
        );
        assert_eq!(flat, (el as f64).to_radians().sin() as f32);
    }
    // A flat patch inside a busy image: only pixels whose 3x3 neighbourhood is flat get the shortcut.
    let (w, h) = (12, 12);
    let mut img: Vec<f32> = noise(w * h, 9).iter().map(|&b| b as f32).collect();
    for y in 3..9 {
        for x in 3..9 {
            img[y * w + x] = 200.0;
        }
    }
    let e = Emboss::new(135.0, 45.0, 3.0).unwrap();
    let out = emboss_image(ImageRef::new(w, h, &img).unwrap(), &e).pixels;
    for y in 4..8 {
        for x in 4..8 {
            assert_eq!(out[y * w + x], e.flat);
        }
    }
}

#[test]
fn a_ramp_gives_one_shade_away_from_the_border() {
    // i = 4 x: i_u = 6 * 4 = 24 at every interior pixel, i_v = 0.
    let (w, h) = (40, 10);
    let img: Vec<f32> = (0..w * h).map(|k| 4.0 * (k % w) as f32).collect();
    let (az, el, width) = (30.0f32, 40.0f32, 5.0f32);
    let out = emboss_image(ImageRef::new(w, h, &img).unwrap(), &Emboss::new(az, el, width).unwrap()).pixels;
    let l = light_direction(az, el).map(f64::from);
    let nz = 6.0 * 255.0 / width as f64;
    let want = (-24.0 * l[0] + nz * l[2]) / (24.0f64 * 24.0 + nz * nz).sqrt();
    for y in 0..h {
        for x in 1..w - 1 {
            assert!((out[y * w + x] as f64 - want).abs() < 1e-6, "({x},{y})");
        }
        // The border columns see half the slope (the edge pixel repeats) and so differ.
        assert!((out[y * w] as f64 - want).abs() > 1e-3);
        assert!((out[y * w + w - 1] as f64 - want).abs() > 1e-3);
    }
}

#[test]
fn turning_the_light_by_180_degrees_mirrors_a_symmetric_bump() {
    // A round bump centred on the image: symmetric under the half-turn (x, y) -> (w-1-x, h-1-y).
    let (w, h) = (31, 25);
    let img: Vec<f32> = (0..w * h)
        .map(|k| {
            let (x, y) = ((k % w) as f32 - 15.0, (k / w) as f32 - 12.0);
            (250.0 * (-(x * x + y * y) / 40.0).exp()).round()
        })
        .collect();
    for (az, el) in [(135.0, 45.0), (20.0, 30.0), (90.0, 60.0)] {
        let a = emboss_image(ImageRef::new(w, h, &img).unwrap(), &Emboss::new(az, el, 3.0).unwrap()).pixels;
        let b = emboss_image(ImageRef::new(w, h, &img).unwrap(), &Emboss::new(az + 180.0, el, 3.0).unwrap()).pixels;
        let mut lit_differently = 0;
        for y in 0..h {
            for x in 0..w {
                let (p, q) = (a[y * w + x], b[(h - 1 - y) * w + (w - 1 - x)]);
                assert!((p - q).abs() < 1e-6, "az {az} ({x},{y}): {p} vs {q}");
                lit_differently += usize::from((p - b[y * w + x]).abs() > 0.05);
            }
        }
        // Not trivially symmetric: the same pixel is lit differently from the two sides.
        assert!(lit_differently > 50, "{lit_differently}");
    }
}

/// A scratch folder for the streamed tests.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("wrinkle-emboss-ref-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn streamed_strips_equal_the_whole_image() {
    // Tall enough for several strips (about a megapixel each) and the hand-over rows between them.
    let (w, h) = (512, 4500);
    let dir = scratch("strips");
    let input = dir.join("h.png");
    let bytes = noise(w * h, 3).iter().map(|&b| b / 2 + 60).collect::<Vec<u8>>();
    let grey = RowFormat { channels: 1, sixteen: false };
    write_rows(&input, w, h, grey, PngCompression::Fast, |sink| sink(&bytes)).unwrap();
    let e = Emboss::new(135.0, 45.0, 3.0).unwrap();
    let rows = ImageRows::open(&input).unwrap();
    let kernel = |_: usize, win: Window, _: Option<&[u8]>, s: &mut [f32], out: &mut [u8]| {
        e.shade_row(win, &mut s[..w]);
        to_grey8(&s[..w], out);
    };
    let mut streamed = Vec::new();
    filter_3x3(
        rows,
        255.0,
        Edges::Clamp,
        None,
        None,
        w,
        &kernel,
        &mut |r| {
            streamed.extend_from_slice(r);
            Ok(())
        },
        &|_| {},
    )
    .unwrap();
    let img: Vec<f32> = bytes.iter().map(|&b| b as f32).collect();
    let mut whole = vec![0u8; w * h];
    to_grey8(&emboss_image(ImageRef::new(w, h, &img).unwrap(), &e).pixels, &mut whole);
    assert_eq!(streamed.len(), whole.len());
    assert!(streamed == whole, "first difference at {:?}", streamed.iter().zip(&whole).position(|(a, b)| a != b));
    let _ = std::fs::remove_dir_all(&dir);
}
