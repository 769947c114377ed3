//! Texture layers and the alpha test against their definitions: every texture environment mode against
//! the OpenGL 1.x equations for RGB and RGBA textures on unlit quads, the alpha each mode leaves (seen
//! through the alpha test's cutoff), the alpha test showing exactly what lies behind, and the coverage of a
//! cut edge at 16 samples per pixel against the analytic area.

use crate::common::scratch_dir;
use std::path::Path;
use wrinkle::image::io::write_png_rgba8;
use wrinkle::render::Aovs;
use wrinkle::{Frame, RenderOptions, Scene};

/// An orthographic view of the square [-1, 1]^2 at z = 0, lit by an ambient light of 1 (so a pixel is its
/// albedo), with `objects` (TOML) in it.
fn unlit(objects: &str) -> String {
    format!(
        "[camera]\neye = [0.0, 0.0, 5.0]\nlook_at = [0.0, 0.0, 0.0]\nprojection = \"orthographic\"\nheight = 2.0\n\
         background = [0.0, 0.0, 0.0]\n\n[[light]]\ntype = \"ambient\"\n\n{objects}"
    )
}

/// A patch filling the view at depth `z`, with a material table's body.
fn quad(z: f64, material: &str) -> String {
    format!(
        "[[object]]\nshape = \"patch\"\ncorners = [[-1.0, -1.0, {z:?}], [1.0, -1.0, {z:?}], [1.0, 1.0, {z:?}], \
         [-1.0, 1.0, {z:?}]]\n[object.material]\n{material}\n"
    )
}

fn render(scene: &str, base: &Path, size: usize, spp: usize) -> Frame {
    let scene = Scene::parse(scene, base).unwrap_or_else(|e| panic!("scene does not parse: {e}\n{scene}"));
    let aovs = Aovs::default();
    wrinkle::render(&scene, &RenderOptions { width: size, height: size, spp, aovs, ..Default::default() })
        .expect("render")
}

/// A one-texel image (an RGB file when `alpha` is `None`), stored linear.
fn texel_png(dir: &Path, name: &str, rgb: [u8; 3], alpha: Option<u8>) -> String {
    let path = dir.join(name);
    match alpha {
        Some(a) => write_png_rgba8(&path, 1, 1, &[rgb[0], rgb[1], rgb[2], a]).unwrap(),
        None => wrinkle::image::io::write_png_rgb8(&path, 1, 1, &rgb).unwrap(),
    }
    name.to_string()
}

/// The OpenGL 1.x texture environment (glTexEnv, RGB and RGBA base formats), written out per mode.
fn opengl(mode: &str, cf: [f64; 3], af: f64, ct: [f64; 3], at: f64, rgba: bool, cc: [f64; 3]) -> ([f64; 3], f64) {
    let each = |f: &dyn Fn(usize) -> f64| [f(0), f(1), f(2)];
    match (mode, rgba) {
        ("replace", false) => (ct, af),
        ("replace", true) => (ct, at),
        ("modulate", false) => (each(&|i| cf[i] * ct[i]), af),
        ("modulate", true) => (each(&|i| cf[i] * ct[i]), af * at),
        ("decal", false) => (ct, af),
        ("decal", true) => (each(&|i| cf[i] * (1.0 - at) + ct[i] * at), af),
        ("blend", false) => (each(&|i| cf[i] * (1.0 - ct[i]) + cc[i] * ct[i]), af),
        ("blend", true) => (each(&|i| cf[i] * (1.0 - ct[i]) + cc[i] * ct[i]), af * at),
        ("add", false) => (each(&|i| (cf[i] + ct[i]).min(1.0)), af),
        ("add", true) => (each(&|i| (cf[i] + ct[i]).min(1.0)), af * at),
        _ => unreachable!(),
    }
}

/// Each mode's pixel equals its OpenGL equation, for an RGB and an RGBA texture; the alpha it leaves is
/// the equation's too: a cutoff just below it keeps the quad, one just above removes it.
#[test]
fn every_mode_follows_the_opengl_equations_for_rgb_and_rgba_textures() {
    let dir = scratch_dir("layer-modes");
    let (ct8, at8) = ([200u8, 90, 30], 153u8);
    let ct = ct8.map(|c| c as f64 / 255.0);
    let at = at8 as f64 / 255.0;
    let (cf, af, cc) = ([0.8, 0.4, 0.6], 0.9, [0.1, 0.9, 0.3]);
    let rgb = texel_png(&dir, "rgb.png", ct8, None);
    let rgba = texel_png(&dir, "rgba.png", ct8, Some(at8));
    for mode in ["replace", "modulate", "decal", "blend", "add"] {
        for (file, is_rgba) in [(&rgb, false), (&rgba, true)] {
            let (want, alpha) = opengl(mode, cf, af, ct, at, is_rgba, cc);
            let layer = format!(
                "color = [0.8, 0.4, 0.6]\nopacity = 0.9\n[[object.material.layer]]\n\
                 texture = {{ path = \"{file}\", srgb = false, filter = \"nearest\" }}\nmode = \"{mode}\"\n{}",
                if mode == "blend" { "blend_color = [0.1, 0.9, 0.3]\n" } else { "" }
            );
            let frame = render(&unlit(&quad(0.0, &layer)), &dir, 8, 1);
            let got = frame.color[4 * 8 + 4];
            for c in 0..3 {
                assert!((got[c] as f64 - want[c]).abs() < 1e-5, "{mode} {file}: {got:?} != {want:?}");
            }
            // The alpha, through the alpha test: the quad stays at a cutoff 0.01 below it, goes 0.01 above.
            for (delta, kept) in [(-0.01, true), (0.01, false)] {
                let masked = layer.replacen(
                    "opacity = 0.9\n",
                    &format!("opacity = 0.9\nalpha_mode = \"mask\"\nalpha_cutoff = {:?}\n", alpha + delta),
                    1,
                );
                let frame = render(&unlit(&quad(0.0, &masked)), &dir, 8, 1);
                let covered = frame.color[4 * 8 + 4] != [0.0; 3];
                assert_eq!(covered, kept, "{mode} {file}: alpha {alpha}, cutoff {}", alpha + delta);
            }
        }
    }
}

/// Layers apply in order, each on what the ones before left; ks and shininess layers change the highlight;
/// an emission layer adds light with no light at all.
#[test]
fn layers_chain_and_reach_every_target() {
    let dir = scratch_dir("layer-targets");
    let grey = texel_png(&dir, "grey.png", [128, 128, 128], None);
    let red = texel_png(&dir, "red.png", [255, 0, 0], None);
    let tex = |f: &str| format!("texture = {{ path = \"{f}\", filter = \"nearest\" }}");
    // modulate by grey 128 (data on ks, colour on kd), then add red.
    let material = format!(
        "color = [0.5, 0.5, 0.5]\n[[object.material.layer]]\n{}\nmode = \"modulate\"\n\
         [[object.material.layer]]\n{}\nmode = \"add\"\n",
        tex(&grey),
        tex(&red)
    );
    let got = render(&unlit(&quad(0.0, &material)), &dir, 8, 1).color[36];
    // Colour targets decode sRGB: 128 is 0.2158605 in linear light.
    let k = 0.215_860_5_f32;
    let want = [(0.5 * k + 1.0f32).min(1.0), 0.5 * k, 0.5 * k];
    assert!(got.iter().zip(want).all(|(g, w)| (g - w).abs() < 1e-5), "{got:?} != {want:?}");

    // A head-on light and eye: N.H = 1, so the highlight is ks whatever the exponent; ks is data, so 128
    // halves it.
    let lit = |material: &str| {
        let scene = unlit(&quad(0.0, material))
            .replace("type = \"ambient\"", "type = \"directional\"\ndirection = [0.0, 0.0, -1.0]");
        render(&scene, &dir, 8, 1).color[36][0]
    };
    let base = "color = [0.0, 0.0, 0.0]\nspecular = 0.8\nshininess = 50.0\n";
    assert!((lit(base) - 0.8).abs() < 1e-5);
    let half = lit(&format!("{base}[[object.material.layer]]\n{}\ntarget = \"ks\"\n", tex(&grey)));
    assert!((half - 0.8 * 128.0 / 255.0).abs() < 1e-5, "ks layer: {half}");
    // Off the mirror direction the exponent shows: the grey layer halves it, so the highlight is wider.
    let tilted = |material: &str| {
        let scene = unlit(&quad(0.0, material))
            .replace("type = \"ambient\"", "type = \"directional\"\ndirection = [0.5, 0.0, -1.0]");
        render(&scene, &dir, 8, 1).color[36][0] as f64
    };
    let ndoth = {
        let l = glam::DVec3::new(-0.5, 0.0, 1.0).normalize();
        (l + glam::DVec3::Z).normalize().z
    };
    let full = tilted(base);
    let halved = tilted(&format!("{base}[[object.material.layer]]\n{}\ntarget = \"shininess\"\n", tex(&grey)));
    assert!((full - 0.8 * ndoth.powf(50.0)).abs() < 1e-5, "{full}");
    assert!((halved - 0.8 * ndoth.powf(50.0 * 128.0 / 255.0)).abs() < 1e-5, "{halved}");

    // Emission, with the ambient light at 0: only what the layer emits.
    let dark = unlit(&quad(
        0.0,
        &format!("[[object.material.layer]]\n{}\ntarget = \"emission\"\nmode = \"replace\"\n", tex(&red)),
    ))
    .replace("type = \"ambient\"", "type = \"ambient\"\nintensity = 0.0");
    assert_eq!(render(&dark, &dir, 8, 1).color[36], [1.0, 0.0, 0.0]);
    // Emission is light, not a reflectance: add is not clamped.
    let brighter = dark.replace("mode = \"replace\"", "mode = \"add\"").replacen(
        "[[object.material.layer]]",
        "emission = [0.5, 0.25, 0.0]\n[[object.material.layer]]",
        1,
    );
    assert_eq!(render(&brighter, &dir, 8, 1).color[36], [1.5, 0.25, 0.0]);
}

/// A 2x1 alpha texture, transparent on its left half, opaque white on its right: with nearest filtering
/// and clamping the cut runs exactly along u = 0.5 (turned by the uv transform's `rotate`).
fn cut_texture(dir: &Path) -> String {
    write_png_rgba8(&dir.join("cut.png"), 2, 1, &[255, 255, 255, 0, 255, 255, 255, 255]).unwrap();
    "cut.png".into()
}

/// Where alpha is below the cutoff the alpha test removes the quad: the pixels there are exactly those of
/// the scene without it (a sphere behind), at 1 and 16 samples per pixel; elsewhere the quad covers all.
#[test]
fn the_alpha_test_shows_what_lies_behind_exactly() {
    let dir = scratch_dir("alpha-behind");
    let cut = cut_texture(&dir);
    let sphere = "[[object]]\nshape = \"sphere\"\nradius = 0.8\ntransform = { translate = [0.0, 0.0, -2.0] }\n\
                  [object.material]\ncolor = [0.2, 0.5, 0.9]\n";
    let cutout = quad(
        0.0,
        &format!(
            "color = [1.0, 0.9, 0.1]\nalpha_mode = \"mask\"\n\
             texture = {{ path = \"{cut}\", filter = \"nearest\", wrap = \"clamp\" }}\n"
        ),
    );
    let size = 32;
    for spp in [1, 16] {
        let behind = render(&unlit(sphere), &dir, size, spp);
        let both = render(&unlit(&format!("{sphere}{cutout}")), &dir, size, spp);
        let (mut seen, mut sphere_pixels) = (0, 0);
        for y in 0..size {
            for x in 0..size {
                let i = y * size + x;
                if x < size / 2 {
                    assert_eq!(both.color[i], behind.color[i], "spp {spp}: pixel ({x}, {y}) left of the cut");
                    seen += 1;
                    sphere_pixels += usize::from(behind.color[i] != [0.0; 3]);
                } else {
                    // The mean of 16 equal samples in f32 is off by a rounding.
                    let quad = both.color[i].iter().zip([1.0, 0.9, 0.1]).all(|(g, w)| (g - w).abs() < 1e-6);
                    assert!(quad, "spp {spp}: pixel ({x}, {y}) right of the cut: {:?}", both.color[i]);
                }
            }
        }
        assert!(seen == size * size / 2 && sphere_pixels > 100, "the sphere shows through: {sphere_pixels}");
    }
    // A second cut quad in front, red: on the left both are peeled away and the sphere shows exactly; on
    // the right the nearer one covers.
    let nearer = quad(
        1.0,
        &format!(
            "color = [1.0, 0.0, 0.0]\nalpha_mode = \"mask\"\n\
             texture = {{ path = \"{cut}\", filter = \"nearest\", wrap = \"clamp\" }}\n"
        ),
    );
    let behind = render(&unlit(sphere), &dir, size, 1);
    let frame = render(&unlit(&format!("{sphere}{cutout}{nearer}")), &dir, size, 1);
    for y in 0..size {
        for x in 0..size {
            let i = y * size + x;
            let want = if x < size / 2 { behind.color[i] } else { [1.0, 0.0, 0.0] };
            assert_eq!(frame.color[i], want, "two cut quads: pixel ({x}, {y})");
        }
    }
}

/// The area of the unit pixel square [x, x+1] x [y, y+1] where a.(p) >= c, by clipping the square by the
/// half-plane.
fn covered_area(x: f64, y: f64, a: [f64; 2], c: f64) -> f64 {
    let corners = [[x, y], [x + 1.0, y], [x + 1.0, y + 1.0], [x, y + 1.0]];
    let f = |p: [f64; 2]| a[0] * p[0] + a[1] * p[1] - c;
    let mut poly = Vec::new();
    for k in 0..4 {
        let (p, q) = (corners[k], corners[(k + 1) % 4]);
        let (fp, fq) = (f(p), f(q));
        if fp >= 0.0 {
            poly.push(p);
        }
        if (fp >= 0.0) != (fq >= 0.0) {
            let t = fp / (fp - fq);
            poly.push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
        }
    }
    let n = poly.len();
    (0..n).map(|k| poly[k][0] * poly[(k + 1) % n][1] - poly[(k + 1) % n][0] * poly[k][1]).sum::<f64>().abs() * 0.5
}

/// At 16 samples per pixel the cut edge is antialiased: each pixel's coverage (white quad, black
/// background, unlit) is within 1/16 of the analytic area on average along the edge, and never off by more
/// than 3/16.
#[test]
fn a_cut_edge_at_16_samples_covers_the_analytic_area() {
    let dir = scratch_dir("alpha-edge");
    let cut = cut_texture(&dir);
    let size = 48;
    // The texture turned by 30 degrees about its origin: u' = u cos(30) + v sin(30) after the turn, so the
    // cut u' = 0.5 is a line across the quad. u = (X + 1) / 2 and v = (Y + 1) / 2 on the quad, pixel
    // (px, py) spans X = px / 24 - 1 and Y = 1 - py / 24.
    let material = format!(
        "color = [1.0, 1.0, 1.0]\nalpha_mode = \"mask\"\n\
         texture = {{ path = \"{cut}\", filter = \"nearest\", wrap = \"clamp\", rotate = 30.0 }}\n"
    );
    let frame = render(&unlit(&quad(0.0, &material)), &dir, size, 16);
    // The uv transform rotates (u, v) counter-clockwise by 30 degrees: u' = u cos - v sin.
    let (s, c) = 30f64.to_radians().sin_cos();
    // u' >= 0.5 with u = px / 48, v = 1 - py / 48: (c / 48) px + (s / 48) py >= 0.5 + s.
    let (a, c0) = ([c / 48.0, s / 48.0], 0.5 + s);
    let (mut sum, mut worst, mut edge) = (0.0, 0.0f64, 0);
    for py in 0..size {
        for px in 0..size {
            let want = covered_area(px as f64, py as f64, a, c0);
            let got = frame.color[py * size + px][0] as f64;
            if want > 0.0 && want < 1.0 {
                edge += 1;
                sum += (got - want).abs();
                worst = worst.max((got - want).abs());
            } else {
                assert!((got - want).abs() < 1e-6, "pixel ({px}, {py}) away from the edge: {got} vs {want}");
            }
        }
    }
    assert!(edge > 40, "the edge crosses the frame: {edge} pixels");
    assert!(sum / edge as f64 <= 1.0 / 16.0, "mean coverage error {} over {edge} edge pixels", sum / edge as f64);
    assert!(worst <= 3.0 / 16.0 + 1e-6, "worst coverage error {worst}");
}

/// Bad layers and alpha fields are one line naming the field.
#[test]
fn bad_layers_name_their_field() {
    let dir = scratch_dir("layer-errors");
    let png = texel_png(&dir, "t.png", [1, 2, 3], None);
    let cases = [
        (
            format!("[[object.material.layer]]\ntexture = \"{png}\"\nmode = \"overlay\""),
            "objects[0].material.layer[0].mode: expected one of \"replace\"",
        ),
        (
            format!("[[object.material.layer]]\ntexture = \"{png}\"\ntarget = \"ks\"\nmode = \"decal\""),
            "objects[0].material.layer[0].mode: \"decal\" applies to colour targets",
        ),
        (
            format!("[[object.material.layer]]\ntexture = \"{png}\"\ntarget = \"albedo\""),
            "objects[0].material.layer[0].target: expected one of \"kd\"",
        ),
        ("[[object.material.layer]]\nmode = \"add\"".into(), "objects[0].material.layer[0].texture: missing field"),
        (
            format!("[[object.material.layer]]\ntexture = \"{png}\"\nblend_color = [1.0, 0.0, 0.0]"),
            "objects[0].material.layer[0].blend_color: applies to mode = \"blend\" only",
        ),
        (
            "alpha_mode = \"glass\"".into(),
            "objects[0].material.alpha_mode: expected one of \"opaque\", \"mask\", \"blend\"",
        ),
        ("alpha_cutoff = 0.3".into(), "objects[0].material.alpha_cutoff: applies to alpha_mode = \"mask\" only"),
        (
            "alpha_mode = \"mask\"\nalpha_cutoff = 1.5".into(),
            "objects[0].material.alpha_cutoff: expected a number from 0 to 1",
        ),
        ("opacity = -1.0".into(), "objects[0].material.opacity: expected a number from 0 to 1"),
        (
            "[object.material.bump]\nprocedural = { pattern = \"fbm\" }\nparallax = { steps = 8 }".into(),
            "objects[0].material.bump.parallax: marches a height table",
        ),
        (
            "[object.material.bump]\ngenerator = { kind = \"grid\" }\nparallax = { depth_replace = 1 }".into(),
            "objects[0].material.bump.parallax.depth_replace",
        ),
        (
            "[object.material.bump]\ngenerator = { kind = \"grid\" }\nparallax = { steps = 0 }".into(),
            "objects[0].material.bump.parallax.steps",
        ),
    ];
    for (material, want) in cases {
        let text = unlit(&quad(0.0, &material));
        let err = Scene::parse(&text, &dir).err().unwrap_or_else(|| panic!("accepted: {material}")).to_string();
        assert!(err.starts_with(want), "{err}\nexpected: {want}");
        assert!(!err.contains('\n'));
    }
}

/// A PNG palette image of `bits` bits per index.
fn palette_png(path: &Path, width: u32, height: u32, indices: &[u8], bits: png::BitDepth, palette: &[[u8; 3]]) {
    let mut encoder = png::Encoder::new(std::fs::File::create(path).unwrap(), width, height);
    encoder.set_color(png::ColorType::Indexed);
    encoder.set_depth(bits);
    encoder.set_palette(palette.iter().flatten().copied().collect::<Vec<u8>>());
    let per_byte = 8 / bits as usize;
    let row_bytes = (width as usize).div_ceil(per_byte);
    let mut packed = vec![0u8; row_bytes * height as usize];
    for y in 0..height as usize {
        for x in 0..width as usize {
            let shift = 8 - bits as usize * (x % per_byte + 1);
            packed[y * row_bytes + x / per_byte] |= indices[y * width as usize + x] << shift;
        }
    }
    encoder.write_header().unwrap().write_image_data(&packed).unwrap();
}

/// Colour index textures: each pixel is the palette entry of its nearest index, for 2- and 8-bit palette
/// PNGs and grey indices with a palette file; swapping the palette changes the colours and nothing else; a
/// LUT maps the filtered intensity.
#[test]
fn colour_index_textures_look_up_the_palette() {
    let dir = scratch_dir("colour-index");
    // 4x2 indices, row 0 at the top; an orthographic 16x8 view: each texel covers 4x4 pixels.
    let indices = [0u8, 1, 2, 3, 3, 2, 1, 0];
    let palette = [[255u8, 0, 0], [0, 255, 0], [0, 0, 255], [255, 255, 255]];
    let swapped = [[10u8, 20, 30], [40, 50, 60], [70, 80, 90], [100, 110, 120]];
    palette_png(&dir.join("i2.png"), 4, 2, &indices, png::BitDepth::Two, &palette);
    palette_png(&dir.join("i8.png"), 4, 2, &indices, png::BitDepth::Eight, &palette);
    wrinkle::image::io::write_png_rgb8(&dir.join("swap.png"), 4, 1, &swapped.concat()).unwrap();
    let grey =
        wrinkle::image::GreyImage { width: 4, height: 2, pixels: indices.iter().map(|&i| i as f32 / 255.0).collect() };
    wrinkle::image::io::write_png_grey8(&dir.join("grey.png"), &grey).unwrap();
    let wide = |material: &str| {
        let scene = unlit(&format!(
            "[[object]]\nshape = \"patch\"\ncorners = [[-2.0, -1.0, 0.0], [2.0, -1.0, 0.0], [2.0, 1.0, 0.0], [-2.0, 1.0, 0.0]]\n\
             [object.material]\ncolor = [1.0, 1.0, 1.0]\ntexture = {{ {material} }}\n"
        ));
        let scene = Scene::parse(&scene, &dir).unwrap_or_else(|e| panic!("{e}"));
        let options = RenderOptions { width: 16, height: 8, aovs: Aovs::default(), ..Default::default() };
        wrinkle::render(&scene, &options).unwrap().color
    };
    let linear = |c: u8| wrinkle::image::color::srgb_to_linear(c as f32 / 255.0);
    let expect = |pixels: &[[f32; 3]], table: &[[u8; 3]], what: &str| {
        for py in 0..8 {
            for px in 0..16 {
                let entry = table[indices[(py / 4) * 4 + px / 4] as usize].map(linear);
                let got = pixels[py * 16 + px];
                assert!(
                    got.iter().zip(entry).all(|(g, w)| (g - w).abs() < 1e-6),
                    "{what}: ({px}, {py}) {got:?} != {entry:?}"
                );
            }
        }
    };
    expect(&wide("path = \"i2.png\", indexed = true"), &palette, "2-bit palette PNG");
    expect(&wide("path = \"i8.png\", indexed = true"), &palette, "8-bit palette PNG");
    expect(&wide("path = \"i8.png\", palette = \"swap.png\""), &swapped, "palette swapped");
    expect(&wide("path = \"grey.png\", palette = \"swap.png\""), &swapped, "grey indices");
    // The image expanded as usual is the same picture as its indices through its palette.
    expect(&wide("path = \"i8.png\", filter = \"nearest\""), &palette, "expanded");

    // The lookup after filtering: a grey ramp of 0 and 1 filtered bilinearly, then through a 3-entry table.
    wrinkle::image::io::write_png_rgb8(&dir.join("lut.png"), 3, 1, &[255, 0, 0, 0, 255, 0, 0, 0, 255]).unwrap();
    let ramp = wrinkle::image::GreyImage { width: 2, height: 1, pixels: vec![0.0, 1.0] };
    wrinkle::image::io::write_png_grey8(&dir.join("ramp.png"), &ramp).unwrap();
    let pixels = wide("path = \"ramp.png\", lut = \"lut.png\", srgb = false, filter = \"bilinear\", wrap = \"clamp\"");
    for px in 0..16 {
        // Texel centres at u = 1/4 and 3/4; the intensity rises linearly between them.
        let u = (px as f32 + 0.5) / 16.0;
        let t = ((u - 0.25) * 2.0).clamp(0.0, 1.0);
        let want = if t < 0.5 { [1.0 - 2.0 * t, 2.0 * t, 0.0] } else { [0.0, 2.0 - 2.0 * t, 2.0 * t - 1.0] };
        let got = pixels[4 * 16 + px];
        assert!(got.iter().zip(want).all(|(g, w)| (g - w).abs() < 1e-4), "lut at {px}: {got:?} != {want:?}");
    }

    // Errors: an index past the palette, grey indices without a palette, a filter other than nearest.
    wrinkle::image::io::write_png_rgb8(&dir.join("short.png"), 2, 1, &[1, 2, 3, 4, 5, 6]).unwrap();
    for (material, want) in [
        ("path = \"i8.png\", palette = \"short.png\"", "index 3 is outside the palette's 2 entries"),
        ("path = \"grey.png\", indexed = true", "has no palette"),
        ("path = \"i8.png\", indexed = true, filter = \"trilinear\"", "looked up by nearest index"),
        ("path = \"swap.png\", indexed = true", "expected colour indices"),
        ("path = \"i8.png\", indexed = true, lut = \"lut.png\"", "not both"),
    ] {
        let text = unlit(&quad(0.0, &format!("texture = {{ {material} }}")));
        let err = Scene::parse(&text, &dir).err().unwrap_or_else(|| panic!("accepted: {material}")).to_string();
        assert!(err.contains(want), "{material}: {err}");
    }
}

/// Parallax occlusion mapping on a flat patch seen at 60 degrees: the (u,v) every lookup reads (the uv AOV
/// of the colour texture) is where the pixel's ray meets the height field carved into the patch, within
/// one step of the march, against the intersection found in f64 along the ray; without parallax, where the
/// ray meets the patch.
#[test]
fn parallax_reads_where_the_ray_meets_the_height_field() {
    let dir = scratch_dir("parallax");
    let tau = std::f64::consts::TAU;
    let field = |u: f64| 0.5 + 0.45 * (tau * 2.0 * u).sin();
    let n = 1024;
    let heights = wrinkle::image::GreyImage::from_fn(n, 4, |x, _| field((x as f64 + 0.5) / n as f64) as f32);
    wrinkle::image::io::write_png_grey16(&dir.join("h.png"), &heights).unwrap();
    texel_png(&dir, "c.png", [200, 200, 200], None);
    let (h, steps) = (0.2, 32);
    let angle = 60f64.to_radians();
    let eye = [4.0 * angle.sin(), 0.0, 4.0 * angle.cos()];
    let scene = |parallax: &str| {
        format!(
            "[camera]\neye = {}\nlook_at = [0.0, 0.0, 0.0]\nprojection = \"orthographic\"\nheight = 1.0\n\n\
             [[light]]\ntype = \"ambient\"\n\n[[object]]\nshape = \"patch\"\n\
             corners = [[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]]\n\
             [object.material]\ntexture = \"c.png\"\n[object.material.bump]\nmap = \"h.png\"\nscale = {h:?}\n{parallax}\n",
            crate::common::arr(eye)
        )
    };
    let size = 32;
    let shifted =
        crate::common::render_all_aovs(&scene(&format!("parallax = {{ steps = {steps} }}")), &dir, size, size, 1);
    let flat = crate::common::render_all_aovs(&scene(""), &dir, size, size, 1);
    let camera = crate::common::RefCamera::orthographic(eye, [0.0; 3], [0.0, 1.0, 0.0], 1.0, size, size);
    // Along the ray, each unit of depth below the patch moves u by -tan(60) / 2 (u = (x + 1) / 2).
    let du_per_depth = -angle.tan() / 2.0;
    let one_step = du_per_depth.abs() * h / steps as f64;
    let (mut worst, mut moved) = (0.0f64, 0.0f64);
    for py in 0..size {
        for px in 0..size {
            let (o, d) = camera.pixel_ray(px, py);
            let t = crate::common::ray_plane(o, d, glam::DVec3::ZERO, glam::DVec3::Z).unwrap();
            let u0 = (o.x + t * d.x + 1.0) / 2.0;
            let uv_flat = flat.uv.as_ref().unwrap()[py * size + px];
            assert!((uv_flat[0] as f64 - u0).abs() < 1e-4, "without parallax the ray meets the patch");
            // The first depth where the ray is below the field: fine scan, then bisection.
            let gap = |depth: f64| depth - h * (1.0 - field(u0 + du_per_depth * depth));
            let mut lo = 0.0;
            while gap(lo + 1e-4) < 0.0 {
                lo += 1e-4;
            }
            let mut hi = lo + 1e-4;
            for _ in 0..40 {
                let mid = 0.5 * (lo + hi);
                if gap(mid) < 0.0 {
                    lo = mid
                } else {
                    hi = mid
                }
            }
            let want = u0 + du_per_depth * lo;
            let got = shifted.uv.as_ref().unwrap()[py * size + px][0] as f64;
            worst = worst.max((got - want).abs());
            moved = moved.max((want - u0).abs());
        }
    }
    assert!(moved > 10.0 * one_step, "the relief moves the lookups: {moved}");
    assert!(worst <= one_step, "parallax (u,v) off the ray-field intersection by {worst} (one step: {one_step})");
}

/// Depth replacement: a wall whose left half is carved 0.5 deep by its parallax height field, and a sphere
/// of radius 0.5 pushed into it (its front 0.2 out of the wall). On the right, where the field reaches the
/// wall, only the part of the sphere in front of the wall shows (a disc of radius 0.4); on the left the whole
/// sphere shows in front of the carved floor, and the wall's depth there is the floor's. Without depth
/// replacement the wall hides the sphere alike on both sides.
#[test]
fn depth_replace_lets_objects_show_in_the_carved_field() {
    let dir = scratch_dir("depth-replace");
    let field = wrinkle::image::GreyImage { width: 2, height: 1, pixels: vec![0.0, 1.0] };
    wrinkle::image::io::write_png_grey8(&dir.join("step.png"), &field).unwrap();
    let scene = |replace: bool| {
        format!(
            "[camera]\neye = [0.0, 0.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\nprojection = \"orthographic\"\nheight = 2.0\n\n\
             [[light]]\ntype = \"ambient\"\n\n\
             [[object]]\nshape = \"patch\"\ncorners = [[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]]\n\
             [object.material.bump]\nmap = \"step.png\"\nscale = 0.5\ninterp = \"nearest\"\n\
             parallax = {{ steps = 8, depth_replace = {replace} }}\n\n\
             [[object]]\nshape = \"sphere\"\nradius = 0.5\ntransform = {{ translate = [0.0, 0.0, -0.3] }}\n"
        )
    };
    let size = 64;
    for replace in [true, false] {
        let frame = crate::common::render_all_aovs(&scene(replace), &dir, size, size, 1);
        let (ids, depth) = (frame.id.as_ref().unwrap(), frame.depth.as_ref().unwrap());
        let mut checked = 0;
        for py in 0..size {
            for px in 0..size {
                let (x, y) = ((px as f64 + 0.5) / 32.0 - 1.0, 1.0 - (py as f64 + 0.5) / 32.0);
                let rho = (x * x + y * y).sqrt();
                let carved = x < 0.0 && replace;
                let radius = if carved { 0.5 } else { 0.4 };
                if (rho - radius).abs() < 0.03 || x.abs() < 0.03 || x.abs() > 0.97 {
                    continue;
                }
                let sphere = ids[py * size + px] == 1.0;
                assert_eq!(sphere, rho < radius, "replace {replace}: pixel ({px}, {py}) at rho {rho:.3}");
                if !sphere {
                    let want = if x < 0.0 && replace { 4.5 } else { 4.0 };
                    assert!((depth[py * size + px] as f64 - want).abs() < 1e-4, "wall depth at ({px}, {py})");
                }
                checked += 1;
            }
        }
        assert!(checked > size * size / 2);
    }
}
