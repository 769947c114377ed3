//! Height maps from float images: OpenEXR (one channel, Y, Z or RGB) and 32-bit float TIFF load as bump
//! tables with their stored values, the renderer's own depth AOV among them (Blinn's Z-buffer bumps), and
//! data maps are never sRGB-decoded.

use crate::common::{render_all_aovs, scratch_dir};
use std::path::Path;
use wrinkle::image::io::{load_grey, write_exr, write_png_grey16};
use wrinkle::image::Image;

/// A ramp with a bump in it, values beyond [0, 1] as float files may hold.
fn heights(w: usize, h: usize) -> Vec<f32> {
    (0..w * h).map(|k| ((k % w) as f32 * 0.37 - (k / w) as f32 * 0.11).sin() * 3.0 + 0.25).collect()
}

#[test]
fn exr_and_float_tiff_height_maps_keep_their_values() {
    let dir = scratch_dir("float-heights");
    let (w, h) = (23, 17);
    let values = heights(w, h);
    let exr = dir.join("h.exr");
    write_exr(&exr, w, h, &[("Y", &values)]).unwrap();
    let tiff = dir.join("h.tiff");
    let rgb: Vec<f32> = values.iter().flat_map(|&v| [v, v, v]).collect();
    image::Rgb32FImage::from_raw(w as u32, h as u32, rgb).unwrap().save(&tiff).unwrap();
    // Grey float TIFF as GIMP writes it (through the tiff crate, which the image crate does not decode).
    let grey_tiff = dir.join("grey.tif");
    let mut out = tiff::encoder::TiffEncoder::new(std::fs::File::create(&grey_tiff).unwrap()).unwrap();
    out.write_image::<tiff::encoder::colortype::Gray32Float>(w as u32, h as u32, &values).unwrap();
    for path in [&exr, &tiff, &grey_tiff] {
        let grey = load_grey(path).unwrap();
        assert_eq!((grey.width, grey.height), (w, h), "{path:?}");
        for (k, (&got, &want)) in grey.pixels.iter().zip(&values).enumerate() {
            assert!((got - want).abs() <= 1e-6 * want.abs().max(1.0), "{path:?} sample {k}: {got} vs {want}");
        }
    }
    // An EXR of R, G, B is read as its luma; a depth AOV's Z as it is.
    let rgb_exr = dir.join("rgb.exr");
    let (r, g, b) = (vec![1.0; w * h], vec![0.0; w * h], vec![0.5; w * h]);
    write_exr(&rgb_exr, w, h, &[("R", &r), ("G", &g), ("B", &b)]).unwrap();
    let luma = 0.2126 + 0.0722 * 0.5;
    assert!(load_grey(&rgb_exr).unwrap().pixels.iter().all(|&v| (v - luma).abs() < 1e-6));
}

/// The depth AOV of an orthographic sphere is the Z-buffer Blinn made rivets from: the nearest depth at the
/// centre, the background (NaN in the AOV) read as the farthest depth seen. As a bump of negative scale its
/// centre stands out and its rim slopes down, so light from the upper left brightens the rivet's upper left.
#[test]
fn the_depth_aov_is_a_z_buffer_bump_map() {
    let dir = scratch_dir("z-buffer");
    let sphere = "[camera]\neye = [0.0, 0.0, 3.0]\nlook_at = [0.0, 0.0, 0.0]\nprojection = \"orthographic\"\n\
                  height = 2.0\n\n[[object]]\nshape = \"sphere\"\nradius = 0.8\n";
    let n = 64;
    let frame = render_all_aovs(sphere, &dir, n, n, 1);
    let depth = frame.depth.as_ref().unwrap();
    write_exr(&dir.join("z.exr"), n, n, &[("Z", depth)]).unwrap();
    let z = load_grey(&dir.join("z.exr")).unwrap();
    let centre = z.pixels[(n / 2) * n + n / 2];
    assert!((centre - 2.2).abs() < 0.01, "centre depth {centre}");
    let far = depth.iter().copied().filter(|v| v.is_finite()).fold(0.0, f32::max);
    assert_eq!(z.pixels[0], far, "the background reads as the farthest depth");
    assert!(z.pixels.iter().all(|v| v.is_finite()));

    let lit = |scale: f32| {
        let text = format!(
            "[camera]\neye = [0.0, 0.0, 3.0]\nlook_at = [0.0, 0.0, 0.0]\nprojection = \"orthographic\"\nheight = 2.0\n\n\
             [[light]]\ntype = \"directional\"\ndirection = [0.6, -0.6, -1.0]\n\n\
             [[object]]\nshape = \"patch\"\ncorners = [[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]]\n\
             material = {{ color = [1.0, 1.0, 1.0], bump = {{ map = \"z.exr\", scale = {scale} }} }}\n"
        );
        render_all_aovs(&text, &dir, n, n, 1).color
    };
    let (flat, bumped) = (lit(0.0), lit(-0.5));
    let at = |c: &[[f32; 3]], x: usize, y: usize| c[y * n + x][0];
    // Upper left of the rivet (facing the light) brighter than flat, lower right darker.
    let (q, r) = (n / 2 - n / 5, n / 2 + n / 5);
    assert!(at(&bumped, q, q) > at(&flat, q, q) + 0.05, "{} vs {}", at(&bumped, q, q), at(&flat, q, q));
    assert!(at(&bumped, r, r) < at(&flat, r, r) - 0.05, "{} vs {}", at(&bumped, r, r), at(&flat, r, r));
}

/// A 16-bit height map and the same heights as a float EXR make the same bump table values.
#[test]
fn png_and_exr_heights_agree() {
    let dir = scratch_dir("heights-agree");
    let (w, h) = (16, 9);
    let values: Vec<f32> = (0..w * h).map(|k| ((k * 7919) % 65536) as f32 / 65535.0).collect();
    write_png_grey16(&dir.join("h.png"), &Image { width: w, height: h, pixels: values.clone() }).unwrap();
    write_exr(&dir.join("h.exr"), w, h, &[("height", &values)]).unwrap();
    let (a, b) = (load_grey(Path::new(&dir.join("h.png"))).unwrap(), load_grey(&dir.join("h.exr")).unwrap());
    for (x, y) in a.pixels.iter().zip(&b.pixels) {
        assert!((x - y).abs() < 1e-6, "{x} vs {y}");
    }
}
