//! Textures from other tools' files: MIP-mapped OpenEXR and tiled TIFF (as OpenImageIO's maketx writes
//! them, and `wrinkle mipmap --format` does), and levels given one file each (as glTexImage2D takes them).
//! Their levels are used, not rebuilt: a file of wrinkle's own pyramid renders as the flat source does, and
//! levels made deliberately different show where the renderer reads them.

use crate::common::scratch_dir;
use std::path::Path;
use wrinkle::image::io::write_png_rgba8;
use wrinkle::image::levels::{write_exr_levels, write_tiff_levels, TiffSamples};
use wrinkle::texture::mip::pyramid;
use wrinkle::texture::{MipFilter, Wrap};
use wrinkle::{render, Image, RenderOptions, Scene};

/// A floor receding from the eye, every level of the texture in view.
fn floor(texture: &str) -> String {
    format!(
        "[camera]\neye = [0.0, 0.6, 3.0]\nlook_at = [0.0, 0.0, 0.0]\nfov_y = 40.0\n\n\
         [[light]]\ntype = \"ambient\"\nintensity = 1.0\n\n[[object]]\nshape = \"patch\"\n\
         corners = [[-1.0, -0.5, 1.0], [1.0, -0.5, 1.0], [1.0, -0.5, -9.0], [-1.0, -0.5, -9.0]]\n\
         material = {{ texture = {texture} }}\n"
    )
}

fn frame(scene: &str, dir: &Path) -> Vec<u8> {
    let scene = Scene::parse(scene, dir).unwrap_or_else(|e| panic!("{e}"));
    let options = RenderOptions { width: 160, height: 120, ..Default::default() };
    let colour = render(&scene, &options).unwrap().color;
    colour
        .iter()
        .flat_map(|c| *c)
        .map(|c| (wrinkle::image::color::linear_to_srgb(c).clamp(0.0, 1.0) * 255.0).round() as u8)
        .collect()
}

/// A 64 x 32 texture of coloured tiles, as 8-bit sRGB bytes.
fn tiles() -> Image<[u8; 4]> {
    Image::from_fn(64, 32, |x, y| {
        let k = (x / 8 + 3 * (y / 8)) % 4;
        [[200, 40, 30, 255], [30, 160, 60, 255], [40, 60, 210, 255], [230, 220, 200, 255]][k]
    })
}

#[test]
fn mip_mapped_files_render_as_their_flat_source() {
    let dir = scratch_dir("texture-files");
    let source = tiles();
    let bytes: Vec<u8> = source.pixels.iter().flatten().copied().collect();
    write_png_rgba8(&dir.join("tiles.png"), 64, 32, &bytes).unwrap();
    let linear = Image { width: 64, height: 32, pixels: wrinkle::image::color::decode_rgba8(&source.pixels, true) };
    let levels = pyramid(&linear, MipFilter::Box, [Wrap::Repeat; 2]);
    write_exr_levels(&dir.join("tiles.exr"), &levels).unwrap();
    write_tiff_levels(&dir.join("tiles.tif"), &levels, TiffSamples::Srgb8).unwrap();
    let tex = |name: &str| format!("{{ path = \"{name}\", repeat = [2, 10] }}");
    let flat = frame(&floor(&tex("tiles.png")), &dir);
    for file in ["tiles.exr", "tiles.tif"] {
        let got = frame(&floor(&tex(file)), &dir);
        let worst = flat.iter().zip(&got).map(|(a, b)| (*a as i32 - *b as i32).abs()).max().unwrap();
        assert!(worst <= 1, "{file}: {worst} codes from the flat PNG");
    }
}

#[test]
fn levels_given_one_file_each_are_the_ones_read() {
    let dir = scratch_dir("texture-levels");
    let source = tiles();
    let bytes: Vec<u8> = source.pixels.iter().flatten().copied().collect();
    write_png_rgba8(&dir.join("tiles.png"), 64, 32, &bytes).unwrap();
    // Levels 1 to 6 all pure red: rebuilt ones would be the tiles' average, a light grey-brown.
    let mut names = Vec::new();
    let (mut w, mut h) = (32usize, 16usize);
    for k in 1..=6 {
        let red: Vec<u8> = (0..w * h).flat_map(|_| [255u8, 0, 0, 255]).collect();
        let name = format!("level{k}.png");
        write_png_rgba8(&dir.join(&name), w, h, &red).unwrap();
        names.push(format!("\"{name}\""));
        (w, h) = ((w / 2).max(1), (h / 2).max(1));
    }
    let levels = format!("{{ path = \"tiles.png\", repeat = [2, 10], levels = [{}] }}", names.join(", "));
    let got = frame(&floor(&levels), &dir);
    let flat = frame(&floor("{ path = \"tiles.png\", repeat = [2, 10] }"), &dir);
    // The far rows (minified: levels 1 and beyond) turn red; the near ones (level 0) are the tiles.
    let pixel =
        |f: &[u8], x: usize, y: usize| [f[3 * (y * 160 + x)], f[3 * (y * 160 + x) + 1], f[3 * (y * 160 + x) + 2]];
    let red = |f: &[u8]| (0..160).map(|x| pixel(f, x, 62)).filter(|p| p[0] > 200 && p[1] < 10 && p[2] < 10).count();
    assert!(red(&got) > 20, "{} red pixels far away", red(&got));
    assert_eq!(red(&flat), 0, "the rebuilt pyramid has no pure red");
    assert_eq!(pixel(&got, 80, 118), pixel(&flat, 80, 118), "level 0 is the file's own");
    // A level of the wrong size is named.
    let wrong = format!("{{ path = \"tiles.png\", levels = [{}] }}", names[1]);
    let e = Scene::parse(&floor(&wrong), &dir).err().expect("a level of the wrong size").to_string();
    assert!(e.contains("level 1 is 16x8, not half of level 0's 64x32"), "{e}");
}
