//! Writes the seed corpus, fuzz/corpus/<target>/, from the repository's own files and from small files made
//! here with the crates wrinkle reads them with (every colour type, bit depth and compression worth a
//! seed), before `cargo fuzz cmin` minimises it. Run from fuzz/:
//!
//!     cargo run --release --features seeds --bin make_seeds
//!
//! It only adds files (named `seed-*`); files the fuzzer found stay. Every seed is kept under 64 KB.

use std::fs;
use std::io::Cursor;
use std::path::{Path, PathBuf};

use exr::prelude::{
    f16, AnyChannel, AnyChannels, Blocks, Compression, Encoding, FlatSamples, Image as ExrImage, Layer,
    LayerAttributes, LineOrder, Vec2 as ExrVec2, WritableImage,
};
use image::ExtendedColorType;

#[path = "../targets.rs"]
#[allow(dead_code)]
mod targets;

// The glTF writer of the integration tests, from the specification rather than through the gltf crate.
#[path = "../../crates/wrinkle/tests/common/gltf.rs"]
#[allow(dead_code)]
mod gltf_writer;

const MAX_SEED: usize = 64 * 1024;

fn main() {
    let root = targets::repo_root();
    let corpus = root.join("fuzz/corpus");
    let mut seeds = Seeds { corpus, count: 0 };
    scene_seeds(&root, &mut seeds);
    image_seeds(&root, &mut seeds);
    obj_seeds(&mut seeds);
    gltf_seeds(&mut seeds);
    println!("wrote {} seeds", seeds.count);
}

struct Seeds {
    corpus: PathBuf,
    count: usize,
}

impl Seeds {
    fn add(&mut self, target: &str, name: &str, bytes: &[u8]) {
        if bytes.len() > MAX_SEED {
            println!("skipped {target}/{name}: {} bytes", bytes.len());
            return;
        }
        let dir = self.corpus.join(target);
        fs::create_dir_all(&dir).unwrap();
        fs::write(dir.join(format!("seed-{name}")), bytes).unwrap();
        self.count += 1;
    }

    fn copy(&mut self, target: &str, file: &Path) {
        let name = file.file_name().unwrap().to_string_lossy().into_owned();
        self.add(target, &name, &fs::read(file).unwrap());
    }
}

fn files_with(dir: &Path, ext: &str) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e.eq_ignore_ascii_case(ext)))
        .collect();
    files.sort();
    files
}

/// Every scene of scenes/, the embedded default scene, and the TOML examples of docs/scene-format.md.
fn scene_seeds(root: &Path, seeds: &mut Seeds) {
    for file in files_with(&root.join("scenes"), "toml") {
        seeds.copy("scene", &file);
    }
    seeds.copy("scene", &root.join("crates/wrinkle/src/scene/default.toml"));
    let doc = fs::read_to_string(root.join("docs/scene-format.md")).unwrap();
    for (k, block) in doc.split("```toml\n").skip(1).enumerate() {
        let text = block.split("```").next().unwrap();
        seeds.add("scene", &format!("scene-format-{k}.toml"), text.as_bytes());
    }
}

/// A 6x5 test picture: a colour ramp with a dark diagonal, RGBA with a varying alpha.
fn picture() -> (u32, u32, Vec<u8>) {
    let (w, h) = (6u32, 5u32);
    let mut rgba = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let d = if x == y { 0 } else { 1 };
            rgba.extend_from_slice(&[
                (40 * x * d) as u8,
                (50 * y * d) as u8,
                (200 - 30 * x) as u8,
                (255 - 20 * y) as u8,
            ]);
        }
    }
    (w, h, rgba)
}

fn channels(rgba: &[u8], n: usize) -> Vec<u8> {
    rgba.chunks(4)
        .flat_map(|p| match n {
            1 => vec![p[0] / 3 + p[1] / 3 + p[2] / 3],
            2 => vec![p[0] / 3 + p[1] / 3 + p[2] / 3, p[3]],
            3 => p[..3].to_vec(),
            _ => p.to_vec(),
        })
        .collect()
}

fn widen(bytes: &[u8]) -> Vec<u16> {
    bytes.iter().map(|&b| u16::from(b) * 257 + 3).collect()
}

fn image_seeds(root: &Path, seeds: &mut Seeds) {
    // The repository's own small images.
    for dir in [root.join("scenes"), root.join("scenes/models"), root.join("docs/images")] {
        for file in files_with(&dir, "png") {
            if fs::metadata(&file).unwrap().len() as usize <= MAX_SEED / 4 {
                seeds.copy("image_png", &file);
            }
        }
    }
    seeds.copy("image_exr", &root.join("scenes/zbuffer_sphere.depth.exr"));
    png_seeds(seeds);
    let (w, h, rgba) = picture();
    let encode = |f: &dyn Fn(&mut Vec<u8>)| {
        let mut out = Vec::new();
        f(&mut out);
        out
    };
    // JPEG: grey and RGB, two qualities (the image crate writes baseline JPEG only).
    for (n, kind) in [(1, ExtendedColorType::L8), (3, ExtendedColorType::Rgb8)] {
        for q in [30u8, 95] {
            let data = channels(&rgba, n);
            let bytes = encode(&|out| {
                image::codecs::jpeg::JpegEncoder::new_with_quality(out, q).encode(&data, w, h, kind).unwrap()
            });
            seeds.add("image_jpeg", &format!("c{n}-q{q}.jpg"), &bytes);
        }
    }
    // BMP: grey (paletted), 24 and 32 bit; and a hand-made 8-bit RLE one.
    for (n, kind) in [(1, ExtendedColorType::L8), (3, ExtendedColorType::Rgb8), (4, ExtendedColorType::Rgba8)] {
        let data = channels(&rgba, n);
        let bytes = encode(&|out| image::codecs::bmp::BmpEncoder::new(out).encode(&data, w, h, kind).unwrap());
        seeds.add("image_bmp", &format!("c{n}.bmp"), &bytes);
    }
    seeds.add("image_bmp", "rle8.bmp", &bmp_rle8());
    // TGA: grey, grey-alpha, RGB, RGBA, each run-length encoded and raw.
    for (n, kind) in [
        (1, ExtendedColorType::L8),
        (2, ExtendedColorType::La8),
        (3, ExtendedColorType::Rgb8),
        (4, ExtendedColorType::Rgba8),
    ] {
        let data = channels(&rgba, n);
        let rle = encode(&|out| image::codecs::tga::TgaEncoder::new(out).encode(&data, w, h, kind).unwrap());
        let raw =
            encode(&|out| image::codecs::tga::TgaEncoder::new(out).disable_rle().encode(&data, w, h, kind).unwrap());
        seeds.add("image_tga", &format!("c{n}-rle.tga"), &rle);
        seeds.add("image_tga", &format!("c{n}-raw.tga"), &raw);
    }
    tiff_seeds(seeds, w, h, &rgba);
    exr_seeds(seeds);
}

/// PNG: every colour type and bit depth, a palette with transparency, and an Adam7-interlaced file
/// (which the streaming reader decodes whole).
fn png_seeds(seeds: &mut Seeds) {
    let (w, h, rgba) = picture();
    let write = |color: png::ColorType, depth: png::BitDepth, data: &[u8], palette: Option<(&[u8], &[u8])>| {
        let mut out = Vec::new();
        {
            let mut e = png::Encoder::new(&mut out, w, h);
            e.set_color(color);
            e.set_depth(depth);
            if let Some((plte, trns)) = palette {
                e.set_palette(plte.to_vec());
                e.set_trns(trns.to_vec());
            }
            let mut writer = e.write_header().unwrap();
            writer.write_image_data(data).unwrap();
        }
        out
    };
    use png::{BitDepth as B, ColorType as C};
    for (n, color) in [(1, C::Grayscale), (2, C::GrayscaleAlpha), (3, C::Rgb), (4, C::Rgba)] {
        let data = channels(&rgba, n);
        seeds.add("image_png", &format!("c{n}-8.png"), &write(color, B::Eight, &data, None));
        let wide: Vec<u8> = widen(&data).iter().flat_map(|v| v.to_be_bytes()).collect();
        seeds.add("image_png", &format!("c{n}-16.png"), &write(color, B::Sixteen, &wide, None));
    }
    // Grey at 1, 2 and 4 bits: rows packed to whole bytes.
    for bits in [1u32, 2, 4] {
        let depth = match bits {
            1 => B::One,
            2 => B::Two,
            _ => B::Four,
        };
        let row_bytes = (w * bits).div_ceil(8) as usize;
        let data: Vec<u8> = (0..h as usize * row_bytes).map(|k| (k * 37 + 11) as u8).collect();
        seeds.add("image_png", &format!("grey-{bits}.png"), &write(C::Grayscale, depth, &data, None));
    }
    let plte: Vec<u8> = (0..4).flat_map(|k| [60 * k as u8, 255 - 60 * k as u8, 128]).collect();
    let indices: Vec<u8> = (0..(w * h) as usize).map(|k| (k % 4) as u8).collect();
    seeds.add("image_png", "palette-trns.png", &write(C::Indexed, B::Eight, &indices, Some((&plte, &[255, 128, 0]))));
    seeds.add("image_png", "adam7.png", &png_adam7(w, h, &channels(&rgba, 3)));
}

/// An 8-bit RGB PNG written by hand with Adam7 interlacing, filter type 0 on every row.
fn png_adam7(w: u32, h: u32, rgb: &[u8]) -> Vec<u8> {
    const PASSES: [(u32, u32, u32, u32); 7] =
        [(0, 0, 8, 8), (4, 0, 8, 8), (0, 4, 4, 8), (2, 0, 4, 4), (0, 2, 2, 4), (1, 0, 2, 2), (0, 1, 1, 2)];
    let mut raw = Vec::new();
    for (x0, y0, dx, dy) in PASSES {
        if x0 >= w || y0 >= h {
            continue;
        }
        for y in (y0..h).step_by(dy as usize) {
            raw.push(0);
            for x in (x0..w).step_by(dx as usize) {
                let k = 3 * (y * w + x) as usize;
                raw.extend_from_slice(&rgb[k..k + 3]);
            }
        }
    }
    let mut ihdr = Vec::new();
    ihdr.extend_from_slice(&w.to_be_bytes());
    ihdr.extend_from_slice(&h.to_be_bytes());
    ihdr.extend_from_slice(&[8, 2, 0, 0, 1]);
    let mut out = vec![137, 80, 78, 71, 13, 10, 26, 10];
    let mut chunk = |kind: &[u8; 4], data: &[u8]| {
        out.extend_from_slice(&(data.len() as u32).to_be_bytes());
        let start = out.len();
        out.extend_from_slice(kind);
        out.extend_from_slice(data);
        let crc = crc32fast::hash(&out[start..]);
        out.extend_from_slice(&crc.to_be_bytes());
    };
    chunk(b"IHDR", &ihdr);
    chunk(b"IDAT", &miniz_oxide::deflate::compress_to_vec_zlib(&raw, 6));
    chunk(b"IEND", &[]);
    out
}

/// A 4x3 BMP of 8-bit palette indices, RLE8 compressed: encoded runs, an absolute run, end of line and
/// end of bitmap.
fn bmp_rle8() -> Vec<u8> {
    let pixels: Vec<u8> = vec![
        4, 1, 0, 0, // row 0 (the bottom): four of index 1
        0, 4, 2, 3, 2, 3, 0, 0, // row 1: absolute run 2 3 2 3
        2, 0, 2, 1, 0, 1, // row 2: two of 0, two of 1, end of bitmap
    ];
    let palette: Vec<u8> = [[0u8, 0, 0, 0], [255, 255, 255, 0], [0, 0, 255, 0], [0, 255, 0, 0]].concat();
    let offset = 14 + 40 + palette.len() as u32;
    let mut out = Vec::new();
    out.extend_from_slice(b"BM");
    out.extend_from_slice(&(offset + pixels.len() as u32).to_le_bytes());
    out.extend_from_slice(&[0; 4]);
    out.extend_from_slice(&offset.to_le_bytes());
    out.extend_from_slice(&40u32.to_le_bytes());
    out.extend_from_slice(&4i32.to_le_bytes());
    out.extend_from_slice(&3i32.to_le_bytes());
    out.extend_from_slice(&1u16.to_le_bytes());
    out.extend_from_slice(&8u16.to_le_bytes());
    out.extend_from_slice(&1u32.to_le_bytes()); // BI_RLE8
    out.extend_from_slice(&(pixels.len() as u32).to_le_bytes());
    out.extend_from_slice(&[0; 8]);
    out.extend_from_slice(&4u32.to_le_bytes());
    out.extend_from_slice(&0u32.to_le_bytes());
    out.extend_from_slice(&palette);
    out.extend_from_slice(&pixels);
    out
}

/// TIFF: 8- and 16-bit grey and RGB, RGBA, grey and RGB 32-bit float (wrinkle's own reader of grey
/// float), uncompressed, LZW, Deflate and PackBits.
fn tiff_seeds(seeds: &mut Seeds, w: u32, h: u32, rgba: &[u8]) {
    use tiff::encoder::{colortype, Compression as C, DeflateLevel, TiffEncoder};
    let grey = channels(rgba, 1);
    let rgb = channels(rgba, 3);
    let grey_f: Vec<f32> = grey.iter().map(|&v| f32::from(v) / 255.0).collect();
    let rgb_f: Vec<f32> = rgb.iter().map(|&v| f32::from(v) / 255.0 + 0.25).collect();
    macro_rules! tiff {
        ($name:expr, $color:ty, $data:expr, $compression:expr) => {{
            let mut out = Cursor::new(Vec::new());
            let mut e = TiffEncoder::new(&mut out).unwrap().with_compression($compression);
            e.new_image::<$color>(w, h).unwrap().write_data($data).unwrap();
            seeds.add("image_tiff", $name, out.get_ref());
        }};
    }
    tiff!("grey8.tif", colortype::Gray8, &grey, C::Uncompressed);
    tiff!("grey8-lzw.tif", colortype::Gray8, &grey, C::Lzw);
    tiff!("grey16-deflate.tif", colortype::Gray16, &widen(&grey), C::Deflate(DeflateLevel::default()));
    tiff!("rgb8-packbits.tif", colortype::RGB8, &rgb, C::Packbits);
    tiff!("rgb16.tif", colortype::RGB16, &widen(&rgb), C::Uncompressed);
    tiff!("rgba8-lzw.tif", colortype::RGBA8, rgba, C::Lzw);
    tiff!("greyf32.tif", colortype::Gray32Float, &grey_f, C::Uncompressed);
    tiff!("greyf32-deflate.tif", colortype::Gray32Float, &grey_f, C::Deflate(DeflateLevel::default()));
    tiff!("rgbf32.tif", colortype::RGB32Float, &rgb_f, C::Uncompressed);
}

/// OpenEXR: wrinkle's own writer (ZIP over 16 lines, f32 and u32), and through the exr crate every
/// compression on half and float channels, scan lines and tiles, RGBA, grey Y, depth Z.
fn exr_seeds(seeds: &mut Seeds) {
    let dir = std::env::temp_dir().join(format!("wrinkle-seeds-{}", std::process::id()));
    fs::create_dir_all(&dir).unwrap();
    let (w, h) = (7usize, 5usize);
    let ramp: Vec<f32> = (0..w * h).map(|k| k as f32 / 7.0).collect();
    let depth: Vec<f32> = (0..w * h).map(|k| if k % 5 == 0 { f32::NAN } else { 2.0 + k as f32 * 0.1 }).collect();
    let path = dir.join("a.exr");
    wrinkle::image::io::write_exr(&path, w, h, &[("R", &ramp), ("G", &ramp), ("B", &depth)]).unwrap();
    seeds.add("image_exr", "wrinkle-rgb.exr", &fs::read(&path).unwrap());
    wrinkle::image::io::write_exr(&path, w, h, &[("Z", &depth)]).unwrap();
    seeds.add("image_exr", "wrinkle-z.exr", &fs::read(&path).unwrap());
    let ids: Vec<u32> = (0..(w * h) as u32).collect();
    wrinkle::image::io::write_exr_u32(&path, w, h, &[("object", &ids), ("triangle", &ids)]).unwrap();
    seeds.add("image_exr", "wrinkle-u32.exr", &fs::read(&path).unwrap());
    let _ = fs::remove_dir_all(&dir);

    let compressions = [
        ("none", Compression::Uncompressed),
        ("rle", Compression::RLE),
        ("zip1", Compression::ZIP1),
        ("zip16", Compression::ZIP16),
        ("piz", Compression::PIZ),
        ("pxr24", Compression::PXR24),
        ("b44", Compression::B44),
        ("b44a", Compression::B44A),
    ];
    let half: Vec<f16> = ramp.iter().map(|&v| f16::from_f32(v)).collect();
    for (name, compression) in compressions {
        for (blocks_name, blocks) in [("lines", Blocks::ScanLines), ("tiles", Blocks::Tiles(ExrVec2(4, 4)))] {
            let encoding = Encoding { compression, blocks, line_order: LineOrder::Increasing };
            let rgba = AnyChannels::sort(smallvec_of(vec![
                AnyChannel::new("R", FlatSamples::F16(half.clone())),
                AnyChannel::new("G", FlatSamples::F32(ramp.clone())),
                AnyChannel::new("B", FlatSamples::F16(half.clone())),
                AnyChannel::new("A", FlatSamples::F32(ramp.clone())),
            ]));
            let bytes = exr_bytes(Layer::new((w, h), LayerAttributes::default(), encoding, rgba));
            seeds.add("image_exr", &format!("rgba-{name}-{blocks_name}.exr"), &bytes);
        }
        let encoding = Encoding { compression, blocks: Blocks::ScanLines, line_order: LineOrder::Decreasing };
        let y = AnyChannels::sort(smallvec_of(vec![AnyChannel::new("Y", FlatSamples::F16(half.clone()))]));
        let bytes = exr_bytes(Layer::new((w, h), LayerAttributes::default(), encoding, y));
        seeds.add("image_exr", &format!("y-{name}.exr"), &bytes);
    }
}

fn smallvec_of(channels: Vec<AnyChannel<FlatSamples>>) -> exr::prelude::SmallVec<[AnyChannel<FlatSamples>; 4]> {
    channels.into_iter().collect()
}

fn exr_bytes(layer: Layer<AnyChannels<FlatSamples>>) -> Vec<u8> {
    let mut out = Cursor::new(Vec::new());
    ExrImage::from_layer(layer).write().to_buffered(&mut out).unwrap();
    out.into_inner()
}

/// OBJ models, each with its .mtl after the side-file line where it has one: a tetrahedron with texture
/// coordinates and normals, quads and polygons to triangulate, negative indices, groups and objects,
/// materials with every texture statement and option the loader reads (naming the scratch folder's t.png
/// and h.png), a coarse UV sphere like scenes/models/uv_sphere.obj.
fn obj_seeds(seeds: &mut Seeds) {
    let side = std::str::from_utf8(targets::SIDE_FILE).unwrap();
    let tetra = "# a tetrahedron\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvt 0 0\nvt 1 0\nvt 0 1\n\
                 vn 0 0 -1\nvn 0 -1 0\nvn -1 0 0\nvn 0.577 0.577 0.577\n\
                 f 1/1/1 3/3/1 2/2/1\nf 1/1/2 2/2/2 4/3/2\nf 1/1/3 4/3/3 3/2/3\nf 2/2/4 3/3/4 4/1/4\n";
    seeds.add("obj", "tetra.obj", tetra.as_bytes());
    let plain = "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nv 0 0 1\nf 1 2 3 4\nf -5 -4 -1\nf 2//1 3//1 5//1\n";
    seeds.add("obj", "quad-negative.obj", plain.as_bytes());
    let mtl = "newmtl red\nKd 0.8 0.1 0.1\nKs 0.5 0.5 0.5\nNs 60\nmap_Kd -o 0.5 0.5 -s 2 2 t.png\n\
               map_Ks -clamp on h.png\nbump -bm 0.5 h.png\nnorm t.png\n\
               newmtl plain\nKd 0.2 0.9 0.2\nmap_Bump -blendu on -mm 0 1 -t 0.1 0.1 h.png\n";
    let groups = format!(
        "mtllib fuzz.mtl\no first\nusemtl red\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n\
         f 1/1 2/2 3/3 4/4\ng second\nusemtl plain\nv 0 0 1\nv 1 0 1\nv 0.5 1 1\nf 5 6 7\ns 1\nf 1 2 5\n{side}{mtl}"
    );
    seeds.add("obj", "groups-mtl.obj", groups.as_bytes());
    let missing = "mtllib absent.mtl\nusemtl gone\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    seeds.add("obj", "missing-mtl.obj", missing.as_bytes());
    // A coarse UV sphere: 8 longitudes, 5 latitudes.
    let mut sphere = String::from("mtllib fuzz.mtl\nusemtl red\n");
    let (nu, nv) = (8, 5);
    for j in 0..=nv {
        for i in 0..=nu {
            let (u, v) = (i as f32 / nu as f32, j as f32 / nv as f32);
            let (phi, theta) = (u * std::f32::consts::TAU, (v - 0.5) * std::f32::consts::PI);
            let (x, y, z) = (theta.cos() * phi.cos(), theta.sin(), -theta.cos() * phi.sin());
            sphere += &format!("v {x:.5} {y:.5} {z:.5}\nvt {u:.5} {v:.5}\nvn {x:.5} {y:.5} {z:.5}\n");
        }
    }
    for j in 0..nv {
        for i in 0..nu {
            let k = |i: usize, j: usize| j * (nu + 1) + i + 1;
            let (a, b, c, d) = (k(i, j), k(i + 1, j), k(i + 1, j + 1), k(i, j + 1));
            sphere += &format!("f {a}/{a}/{a} {b}/{b}/{b} {c}/{c}/{c} {d}/{d}/{d}\n");
        }
    }
    sphere += &format!("{side}newmtl red\nKd 1 1 1\nmap_Kd t.png\nnorm t.png\n");
    seeds.add("obj", "uv-sphere.obj", sphere.as_bytes());
}

/// glTF models from the integration tests' writer: a buffer in a data URI, in a side file, or in a GLB;
/// with normals, texture coordinates and tangents or without; a material with an embedded texture
/// (base colour, normal map, a sampler, KHR_texture_transform) or none; a node matrix.
fn gltf_seeds(seeds: &mut Seeds) {
    use gltf_writer::{File, Layout, Primitive};
    let png = {
        let dir = targets::scratch_dir();
        let png = gltf_writer::png_of(&dir, [200, 100, 50]);
        targets::remove_scratch_dir();
        png
    };
    let full = Primitive {
        positions: vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.5]],
        normals: Some(vec![[0.0, 0.0, 1.0]; 4]),
        uvs: Some(vec![[0.0, 1.0], [1.0, 1.0], [0.0, 0.0], [1.0, 0.0]]),
        tangents: Some(vec![[1.0, 0.0, 0.0, 1.0]; 4]),
        indices: vec![0, 1, 2, 2, 1, 3],
    };
    let bare = Primitive {
        positions: vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        indices: vec![0, 1, 2],
        ..Primitive::default()
    };
    let textured = "{\"pbrMetallicRoughness\": {\"baseColorFactor\": [1, 0.5, 0.5, 1], \
                    \"baseColorTexture\": {\"index\": 0, \"extensions\": {\"KHR_texture_transform\": \
                    {\"offset\": [0.5, 0], \"scale\": [2, 2], \"rotation\": 0.3}}}}, \
                    \"normalTexture\": {\"index\": 0, \"scale\": 0.5}, \"doubleSided\": true}";
    let files = [
        ("full", File { primitive: full.clone(), matrix: None, material: textured.into(), png: Some(png.clone()) }),
        (
            "matrix",
            File {
                primitive: full,
                matrix: Some([2.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.5, 0.0, 0.0, 1.0]),
                material: "{}".into(),
                png: None,
            },
        ),
        ("bare", File { primitive: bare, matrix: None, material: "{\"doubleSided\": false}".into(), png: None }),
    ];
    for (name, file) in &files {
        let (json, _) = file.write(Layout::Embedded, "fuzz.bin");
        seeds.add("gltf", &format!("{name}-embedded.gltf"), &json);
        let (json, bin) = file.write(Layout::Separate, "fuzz.bin");
        seeds.add("gltf", &format!("{name}-separate.gltf"), &[json, targets::SIDE_FILE.to_vec(), bin].concat());
        let (glb, _) = file.write(Layout::Binary, "fuzz.bin");
        seeds.add("gltf", &format!("{name}.glb"), &glb);
    }
    // An image by URI (the scratch folder's t.png), with a sampler.
    let (json, bin) = files[0].1.write(Layout::Separate, "fuzz.bin");
    let json = String::from_utf8(json).unwrap().replacen(
        "\"images\": [{\"bufferView\"",
        "\"samplers\": [{\"wrapS\": 33071, \"wrapT\": 33648, \"minFilter\": 9728, \"magFilter\": 9729}], \
         \"images\": [{\"uri\": \"t.png\"}, {\"bufferView\"",
        1,
    );
    let json = json.replacen("\"textures\": [{\"source\": 0}]", "\"textures\": [{\"source\": 0, \"sampler\": 0}]", 1);
    seeds.add("gltf", "uri-image-sampler.gltf", &[json.into_bytes(), targets::SIDE_FILE.to_vec(), bin].concat());
}
