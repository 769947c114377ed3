//! End-to-end tests of `wrinkle emboss`, `bump`, `normalmap` and `heightmap`: the built binary on small
//! PNG and BMP inputs written here, its output files read back, and the one-line errors of bad input with
//! nothing left in the output folder.

use crate::common::*;
use std::fs;
use std::path::Path;

use wrinkle::image::io::{load_grey, load_rgba8, read_exr_channels};
use wrinkle::image::stream::{write_rows, ImageRows, PngCompression, RowFormat};

/// Writes rows (grey or RGB, 8 or 16 bit) to a PNG or BMP input file.
fn write_input(path: &str, w: usize, h: usize, rows: RowFormat, data: &[u8]) {
    write_rows(Path::new(path), w, h, rows, PngCompression::Fast, |sink| sink(data)).unwrap();
}

const GREY8: RowFormat = RowFormat { channels: 1, sixteen: false };
const GREY16: RowFormat = RowFormat { channels: 1, sixteen: true };
const RGB8: RowFormat = RowFormat { channels: 3, sixteen: false };

/// The emboss shade by the formula (f64, clamped borders), 8-bit.
fn emboss_reference(img: &[f64], w: usize, h: usize, az: f64, el: f64, width: f64) -> Vec<u8> {
    let (az, el) = (az.to_radians(), el.to_radians());
    let l = [az.cos() * el.cos(), az.sin() * el.cos(), el.sin()];
    let nz = 6.0 * 255.0 / width;
    let at = |x: isize, y: isize| img[y.clamp(0, h as isize - 1) as usize * w + x.clamp(0, w as isize - 1) as usize];
    let mut out = Vec::new();
    for y in 0..h as isize {
        for x in 0..w as isize {
            let iu: f64 = (-1..=1).map(|d| at(x + 1, y + d) - at(x - 1, y + d)).sum();
            let iv: f64 = (-1..=1).map(|d| at(x + d, y - 1) - at(x + d, y + 1)).sum();
            let shade = if iu == 0.0 && iv == 0.0 {
                l[2]
            } else {
                ((-iu * l[0] - iv * l[1] + nz * l[2]) / (iu * iu + iv * iv + nz * nz).sqrt()).max(0.0)
            };
            out.push((shade * 255.0).round() as u8);
        }
    }
    out
}

fn noise(len: usize, seed: u32) -> Vec<u8> {
    let mut s = seed;
    (0..len)
        .map(|_| {
            s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (s >> 24) as u8
        })
        .collect()
}

/// Bytes of an 8-bit grey output.
fn grey8_of(path: &str) -> Vec<u8> {
    load_grey(Path::new(path)).unwrap().pixels.iter().map(|&v| (v * 255.0).round() as u8).collect()
}

#[test]
fn emboss_matches_the_formula_and_writes_png_bmp_and_16_bit() {
    let s = Scratch::new("formula");
    let (w, h) = (45, 31);
    // Smoothish heights so that most pixels are neither flat nor saturated.
    let bytes: Vec<u8> = noise(w * h, 11).iter().map(|&b| b / 8 + 100).collect();
    let png8 = s.input("h8.png");
    write_input(&png8, w, h, GREY8, &bytes);
    let want = emboss_reference(&bytes.iter().map(|&b| b as f64).collect::<Vec<_>>(), w, h, 60.0, 35.0, 2.0);
    let args = ["--azimuth", "60", "--elevation", "35", "--width", "2"];
    let out = s.out("e.png");
    assert_ok(&wrinkle(&[&["emboss", &png8, "-o", &out][..], &args].concat()));
    let got = grey8_of(&out);
    let off = got.iter().zip(&want).filter(|(a, b)| a != b).count();
    let worst = got.iter().zip(&want).map(|(a, b)| (*a as i32 - *b as i32).abs()).max().unwrap();
    // f32 against f64: a value within rounding of .5 may round the other way.
    assert!(worst <= 1 && off <= w * h / 200, "{off} pixels differ, worst by {worst}");

    // The same heights as 16-bit samples (v * 257) give the same picture.
    let png16 = s.input("h16.png");
    let wide: Vec<u8> = bytes.iter().flat_map(|&b| (b as u16 * 257).to_be_bytes()).collect();
    write_input(&png16, w, h, GREY16, &wide);
    let out16 = s.out("e16.png");
    assert_ok(&wrinkle(&[&["emboss", &png16, "-o", &out16][..], &args].concat()));
    assert_eq!(grey8_of(&out16), got);

    // 24-bit BMP output, like the 1994 demo: the same pixels in R, G and B.
    let bmp = s.out("e.bmp");
    assert_ok(&wrinkle(&[&["emboss", &png8, "-o", &bmp][..], &args].concat()));
    let b = fs::read(&bmp).unwrap();
    assert_eq!(&b[..2], b"BM");
    assert_eq!(u16::from_le_bytes([b[28], b[29]]), 24, "bits per pixel");
    let rgba = load_rgba8(Path::new(&bmp)).unwrap();
    assert!(rgba.pixels.iter().zip(&got).all(|(p, &g)| p[..3] == [g, g, g]));

    // --depth 16: the 8-bit picture is its rounding.
    let deep = s.out("deep.png");
    assert_ok(&wrinkle(&[&["emboss", &png8, "-o", &deep, "--depth", "16"][..], &args].concat()));
    let rows = ImageRows::open(Path::new(&deep)).unwrap();
    assert!(rows.is_sixteen_bit());
    let g16 = load_grey(Path::new(&deep)).unwrap();
    assert!(g16.pixels.iter().zip(&got).all(|(v, &g)| ((v * 255.0).round() as i32 - g as i32).abs() <= 1));

    // The other compression levels give the same pixels.
    for level in ["default", "best"] {
        let o = s.out(&format!("{level}.png"));
        assert_ok(&wrinkle(&[&["emboss", &png8, "-o", &o, "--compression", level][..], &args].concat()));
        assert_eq!(grey8_of(&o), got);
    }
}

#[test]
fn rgb_and_bmp_heights_become_luma() {
    let s = Scratch::new("luma");
    let (w, h) = (20, 12);
    let rgb = noise(3 * w * h, 4);
    let input = s.input("c.bmp");
    write_input(&input, w, h, RGB8, &rgb);
    let luma: Vec<f64> =
        rgb.chunks(3).map(|p| 0.2126 * p[0] as f64 + 0.7152 * p[1] as f64 + 0.0722 * p[2] as f64).collect();
    let out = s.out("e.png");
    assert_ok(&wrinkle(&["emboss", &input, "-o", &out, "--width", "8"]));
    let want = emboss_reference(&luma, w, h, 135.0, 45.0, 8.0);
    let got = grey8_of(&out);
    assert!(got.iter().zip(&want).all(|(a, b)| (*a as i32 - *b as i32).abs() <= 1));
}

#[test]
fn emboss_multiplies_a_texture_of_the_same_or_another_size() {
    let s = Scratch::new("texture");
    let (w, h) = (24, 16);
    let heights: Vec<u8> = (0..w * h).map(|k| ((k % w) * 5 + (k / w) * 3) as u8).collect();
    let hp = s.input("h.png");
    write_input(&hp, w, h, GREY8, &heights);
    let tex = noise(3 * w * h, 8);
    let tp = s.input("t.png");
    write_input(&tp, w, h, RGB8, &tex);
    let grey = s.out("grey.png");
    assert_ok(&wrinkle(&["emboss", &hp, "-o", &grey, "--depth", "16"]));
    let shade = load_grey(Path::new(&grey)).unwrap().pixels;
    let out = s.out("t.png");
    assert_ok(&wrinkle(&["emboss", &hp, "-o", &out, "--texture", &tp]));
    let got = load_rgba8(Path::new(&out)).unwrap();
    for (k, p) in got.pixels.iter().enumerate() {
        for c in 0..3 {
            let want = tex[3 * k + c] as f32 * shade[k];
            assert!((p[c] as f32 - want).abs() <= 0.51, "pixel {k} channel {c}: {} vs {want}", p[c]);
        }
    }

    // Another size: resampled by default, refused with --resample none.
    let small = s.input("small.png");
    write_input(&small, 6, 4, RGB8, &noise(3 * 24, 2));
    let resampled = s.out("resampled.png");
    assert_ok(&wrinkle(&["emboss", &hp, "-o", &resampled, "--texture", &small]));
    let r = load_rgba8(Path::new(&resampled)).unwrap();
    assert_eq!((r.width, r.height), (w, h));
    fs::remove_file(&resampled).unwrap();
    fs::remove_file(&out).unwrap();
    fs::remove_file(&grey).unwrap();
    let run = wrinkle(&["emboss", &hp, "-o", &s.out("x.png"), "--texture", &small, "--resample", "none"]);
    assert_one_error(&run, 2, &["small.png", "6x4", "24x16"], &s);
}

#[test]
fn bad_inputs_give_one_line_and_no_output() {
    let s = Scratch::new("bad");
    let (w, h) = (64, 64);
    let good = s.input("good.png");
    write_input(&good, w, h, GREY8, &noise(w * h, 1));
    let out = s.out("o.png");

    let bytes = fs::read(&good).unwrap();
    let cut = s.input("cut.png");
    fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
    for cmd in ["emboss", "normalmap", "heightmap"] {
        assert_one_error(&wrinkle(&[cmd, &cut, "-o", &out]), 2, &["cut.png", "truncated or corrupt PNG"], &s);
    }

    // A zero-size image: a TGA header claiming 0x0.
    let mut header = [0u8; 18];
    header[2] = 3;
    header[16] = 8;
    let empty = s.input("empty.tga");
    fs::write(&empty, header).unwrap();
    assert_one_error(&wrinkle(&["emboss", &empty, "-o", &out]), 2, &["empty.tga"], &s);

    let text = s.input("notes.xyz");
    fs::write(&text, "not an image").unwrap();
    assert_one_error(&wrinkle(&["emboss", &text, "-o", &out]), 2, &["notes.xyz", "not a supported image"], &s);
    assert_one_error(&wrinkle(&["emboss", &good, "-o", &s.out("o.gif")]), 2, &["o.gif", ".png or .bmp"], &s);
    assert_one_error(&wrinkle(&["normalmap", &good, "-o", &s.out("o.jpg")]), 2, &["o.jpg"], &s);
    assert_one_error(
        &wrinkle(&["emboss", &s.input("missing.png"), "-o", &out]),
        2,
        &["missing.png", "no such file"],
        &s,
    );
    let run = wrinkle(&["emboss", &good, "-o", &out, "--limit", "image-side=32"]);
    assert_one_error(&run, 2, &["good.png", "32 limit", "--limit image-side=N"], &s);
    assert_one_error(&wrinkle(&["emboss", &good, "-o", &out, "--elevation", "100"]), 2, &["--elevation"], &s);
    assert_one_error(&wrinkle(&["emboss", &good, "-o", &out, "--width", "nan"]), 2, &["--width"], &s);
    assert_one_error(&wrinkle(&["normalmap", &good, "-o", &out, "--strength", "-1"]), 2, &["--strength"], &s);
    assert_one_error(&wrinkle(&["bump", &good, "-o", &out, "--light", "10"]), 2, &["--light"], &s);
    assert_one_error(&wrinkle(&["bump", &cut, "-o", &out]), 2, &["cut.png"], &s);
}

#[test]
fn normal_map_of_a_ramp_and_its_conventions() {
    let s = Scratch::new("normals");
    let (w, h) = (32, 20);
    // 16-bit ramp rising to the right: h = x / 1000.
    let ramp: Vec<u8> =
        (0..w * h).flat_map(|k| (((k % w) as f64 / 1000.0 * 65535.0).round() as u16).to_be_bytes()).collect();
    let input = s.input("ramp.png");
    write_input(&input, w, h, GREY16, &ramp);
    let strength = 50.0;
    let gx = -strength / 1000.0;
    let len = (gx * gx + 1.0f64).sqrt();
    for (convention, kernel) in [("opengl", "central"), ("directx", "scharr")] {
        let out = s.out(&format!("{convention}.png"));
        assert_ok(&wrinkle(&[
            "normalmap",
            &input,
            "-o",
            &out,
            "--strength",
            "50",
            "--depth",
            "16",
            "--convention",
            convention,
            "--kernel",
            kernel,
        ]));
        let mut rows = ImageRows::open(Path::new(&out)).unwrap();
        assert!(rows.is_sixteen_bit());
        let mut rgb = vec![0.0; 3 * w];
        for _ in 0..h {
            rows.read_rgb(&mut rgb).unwrap();
            for x in 1..w - 1 {
                let n: Vec<f64> = rgb[3 * x..3 * x + 3].iter().map(|&c| 2.0 * c as f64 - 1.0).collect();
                assert!((n[0] - gx / len).abs() < 1e-3, "{convention} x {x}: {n:?}");
                assert!(n[1].abs() < 1e-3 && (n[2] - 1.0 / len).abs() < 1e-3);
            }
        }
    }
    // A slope up the picture: OpenGL's green leans down (below half), DirectX's the other way.
    let up: Vec<u8> = (0..w * h).map(|k| (4 * (h - 1 - k / w)) as u8).collect();
    let up_path = s.input("up.png");
    write_input(&up_path, w, h, GREY8, &up);
    let green = |convention: &str| {
        let out = s.out(&format!("up_{convention}.png"));
        assert_ok(&wrinkle(&["normalmap", &up_path, "-o", &out, "--convention", convention]));
        load_rgba8(Path::new(&out)).unwrap().pixels[(h / 2) * w + w / 2][1]
    };
    let (gl, dx) = (green("opengl"), green("directx"));
    assert!(gl < 128 && dx > 128 && (gl as i32 + dx as i32 - 255).abs() <= 1, "{gl} {dx}");
}

#[test]
fn wrap_reads_the_opposite_edge() {
    let s = Scratch::new("wrap");
    let (w, h) = (40, 24);
    // One period of a sine across the width: with --wrap the border columns see the true neighbours.
    let tau = std::f64::consts::TAU;
    let v = |x: usize| 0.5 + 0.4 * (tau * x as f64 / w as f64).sin();
    let img: Vec<u8> = (0..w * h).flat_map(|k| ((v(k % w) * 65535.0).round() as u16).to_be_bytes()).collect();
    let input = s.input("sine.png");
    write_input(&input, w, h, GREY16, &img);
    let (wrapped, clamped) = (s.out("wrap.png"), s.out("clamp.png"));
    let base = ["--strength", "10", "--depth", "16", "--kernel", "central"];
    assert_ok(&wrinkle(&[&["normalmap", &input, "-o", &wrapped, "--wrap"][..], &base].concat()));
    assert_ok(&wrinkle(&[&["normalmap", &input, "-o", &clamped][..], &base].concat()));
    let red = |path: &str, x: usize| {
        let mut rows = ImageRows::open(Path::new(path)).unwrap();
        let mut rgb = vec![0.0; 3 * w];
        rows.read_rgb(&mut rgb).unwrap();
        2.0 * rgb[3 * x] as f64 - 1.0
    };
    let expect = |x: usize| {
        let g = -10.0 * (v((x + 1) % w) - v((x + w - 1) % w)) / 2.0;
        g / (g * g + 1.0).sqrt()
    };
    assert!((red(&wrapped, 0) - expect(0)).abs() < 1e-3);
    assert!((red(&wrapped, w - 1) - expect(w - 1)).abs() < 1e-3);
    assert!((red(&clamped, 0) - expect(0)).abs() > 0.01, "clamped borders differ");
}

#[test]
fn height_to_normal_map_to_height_within_one_percent() {
    let s = Scratch::new("roundtrip");
    let (w, h) = (160, 120);
    let f = |x: f64, y: f64| {
        let g = |cx: f64, cy: f64, r: f64| (-((x - cx).powi(2) + (y - cy).powi(2)) / (r * r)).exp();
        0.15 + 0.2 * x / w as f64 + 0.45 * g(55.0, 50.0, 25.0) + 0.2 * g(115.0, 80.0, 18.0)
    };
    let heights: Vec<f64> = (0..w * h).map(|k| f((k % w) as f64, (k / w) as f64)).collect();
    let bytes: Vec<u8> = heights.iter().flat_map(|&v| ((v * 65535.0).round() as u16).to_be_bytes()).collect();
    let input = s.input("h.png");
    write_input(&input, w, h, GREY16, &bytes);
    let (normal, back) = (s.out("n.png"), s.out("back.png"));
    assert_ok(&wrinkle(&["normalmap", &input, "-o", &normal, "--strength", "30", "--depth", "16"]));
    assert_ok(&wrinkle(&["heightmap", &normal, "-o", &back, "--strength", "30"]));
    let got: Vec<f64> = load_grey(Path::new(&back)).unwrap().pixels.iter().map(|&v| v as f64).collect();
    let n = got.len() as f64;
    let mean = got.iter().zip(&heights).map(|(a, b)| a - b).sum::<f64>() / n;
    let rmse = (got.iter().zip(&heights).map(|(a, b)| (a - b - mean).powi(2)).sum::<f64>() / n).sqrt();
    let range = heights.iter().cloned().fold(f64::MIN, f64::max) - heights.iter().cloned().fold(f64::MAX, f64::min);
    assert!(rmse < 0.01 * range, "RMSE {rmse} of range {range}");
    // --normalize stretches to the full range.
    let stretched = s.out("stretched.png");
    assert_ok(&wrinkle(&["heightmap", &normal, "-o", &stretched, "--strength", "30", "--normalize", "--depth", "8"]));
    let g = load_grey(Path::new(&stretched)).unwrap().pixels;
    assert_eq!(g.iter().cloned().fold(f32::MAX, f32::min), 0.0);
    assert_eq!(g.iter().cloned().fold(f32::MIN, f32::max), 1.0);
}

#[test]
fn bump_through_the_renderer_agrees_with_emboss_on_a_ramp() {
    // The same surface both ways: white is 6 pixels high (emboss --width 6, bump --scale 6). On a ramp
    // h = 3x/255 both give one normal, so the renderer's linear Lambert shade equals emboss's N.L.
    let s = Scratch::new("bump");
    let (w, h) = (48, 32);
    let ramp: Vec<u8> = (0..w * h).map(|k| (3 * (k % w)) as u8).collect();
    let input = s.input("ramp.png");
    write_input(&input, w, h, GREY8, &ramp);
    let (bumped, embossed) = (s.out("b.exr"), s.out("e.png"));
    assert_ok(&wrinkle(&["bump", &input, "-o", &bumped, "--scale", "6", "--light", "160,40"]));
    assert_ok(&wrinkle(&[
        "emboss",
        &input,
        "-o",
        &embossed,
        "--width",
        "6",
        "--azimuth",
        "160",
        "--elevation",
        "40",
        "--depth",
        "16",
    ]));
    let (bw, bh, channels) = read_exr_channels(Path::new(&bumped)).unwrap();
    assert_eq!((bw, bh), (w, h));
    let red = &channels.iter().find(|(n, _)| n == "R").unwrap().1;
    let shade = load_grey(Path::new(&embossed)).unwrap().pixels;
    // Analytic: slope 3/255 per pixel times 6 pixels of height per unit: n = normalize(-18/255, 0, 1).
    let (az, el) = (160f64.to_radians(), 40f64.to_radians());
    let gx = -18.0 / 255.0;
    let want = (gx * az.cos() * el.cos() + el.sin()) / (gx * gx + 1.0).sqrt();
    for y in 1..h - 1 {
        for x in 1..w - 1 {
            let k = y * w + x;
            assert!((red[k] as f64 - want).abs() < 1e-4, "bump ({x},{y}): {} vs {want}", red[k]);
            assert!((shade[k] as f64 - want).abs() < 1e-4, "emboss ({x},{y}): {} vs {want}", shade[k]);
        }
    }
    // With a texture and a highlight it still renders, at the height image's size.
    let tex = s.input("t.png");
    write_input(&tex, 7, 5, RGB8, &noise(3 * 35, 3));
    let textured = s.out("t.png");
    assert_ok(&wrinkle(&[
        "bump",
        &input,
        "-o",
        &textured,
        "--texture",
        &tex,
        "--specular",
        "0.5",
        "--shininess",
        "30",
    ]));
    let t = load_rgba8(Path::new(&textured)).unwrap();
    assert_eq!((t.width, t.height), (w, h));
}

/// An offset vector map made by `normalmap --offset` (central differences, 16 bits) renders the same bumps as
/// the height map it came from read as a bump table (Blinn's central differences of one table step): the
/// scale S = H * width / strength turns the stored per-pixel slopes into F's slopes per texture period.
#[test]
fn offset_maps_render_like_their_height_maps() {
    let s = Scratch::new("offset-map");
    let n = 64;
    let tau = std::f64::consts::TAU;
    let heights: Vec<u8> = (0..n * n)
        .flat_map(|k| {
            let (x, y) = ((k % n) as f64, (k / n) as f64);
            let h = 0.5 + 0.25 * (tau * 2.0 * x / n as f64).sin() * (tau * 3.0 * y / n as f64).cos();
            ((h * 65535.0).round() as u16).to_be_bytes()
        })
        .collect();
    let height = s.input("h.png");
    write_input(&height, n, n, GREY16, &heights);
    let offsets = s.input("off.png");
    let args = [
        "normalmap",
        &height,
        "-o",
        &offsets,
        "--offset",
        "--strength",
        "2",
        "--depth",
        "16",
        "--kernel",
        "central",
        "--wrap",
    ];
    assert_ok(&wrinkle(&args));
    let normals = |bump: &str| {
        let text = format!(
            "[camera]\neye = [0.0, 0.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\nfov_y = 35.0\n\n[[light]]\ntype = \"ambient\"\n\n\
             [[object]]\nshape = \"sphere\"\n[object.material.bump]\n{bump}\n"
        );
        let scene = wrinkle::Scene::parse(&text, Path::new("/")).unwrap_or_else(|e| panic!("{e}"));
        let aovs = wrinkle::render::Aovs { normal: true, ..Default::default() };
        let options = wrinkle::RenderOptions { width: 64, height: 64, aovs, ..Default::default() };
        wrinkle::render(&scene, &options).unwrap().normal.unwrap()
    };
    let table =
        normals(&format!("map = \"{height}\"\nscale = 0.1\nrepeat = [2, 1]\nfilter = \"none\"\ninterp = \"bilinear\""));
    // S = 0.1 * 64 / 2.
    let offset = normals(&format!("offsets = \"{offsets}\"\nscale = 3.2\nrepeat = [2, 1]\nfilter = \"bilinear\""));
    let angle = |a: [f32; 3], b: [f32; 3]| {
        let d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        (d.clamp(-1.0, 1.0) as f64).acos().to_degrees()
    };
    let (mut worst, mut bumped, mut seen) = (0.0f64, 0, 0);
    let unbumped = normals(&format!("map = \"{height}\"\nscale = 0.0"));
    for k in 0..64 * 64 {
        if table[k][0].is_nan() {
            continue;
        }
        seen += 1;
        worst = worst.max(angle(table[k], offset[k]));
        bumped += usize::from(angle(table[k], unbumped[k]) > 2.0);
    }
    assert!(seen > 1000 && bumped > seen / 2, "{bumped} of {seen} pixels visibly bumped");
    assert!(worst < 0.05, "offset map against height table: {worst} degrees");
}
