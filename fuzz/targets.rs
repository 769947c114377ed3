//! The bodies of wrinkle's fuzz targets, in one place: the cargo-fuzz binaries (fuzz/fuzz_targets/*.rs)
//! and the stable replay and mutation harness (crates/wrinkle/tests/fuzz_corpus.rs) both include this file
//! with `#[path]`, so an input means the same thing to both.
//!
//! The invariant every target checks: any input gives `Ok` or `Err`, never a panic, a hang or a huge
//! allocation. Results are dropped; nothing is rendered.
//!
//! Inputs that name files are written to a scratch folder of their own (one per process and thread,
//! under `std::env::temp_dir()`), which also holds two tiny 2x2 RGB PNG textures, `t.png` (colours) and
//! `h.png` (black and white), for model files to name. The OBJ and glTF targets take one optional side file after the
//! line [`SIDE_FILE`]: the OBJ's `fuzz.mtl`, or the glTF's `fuzz.bin`.

#![allow(dead_code)]

use std::cell::RefCell;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use wrinkle::image::io;
use wrinkle::image::stream::ImageRows;
use wrinkle::Scene;

/// A target's body: any input must come back, `Ok` or `Err`.
pub type Target = fn(&[u8]);

/// Every target by name, as its corpus folder `fuzz/corpus/<name>/` and its fuzz binary are named.
pub const TARGETS: &[(&str, Target)] = &[
    ("scene", scene),
    ("image_png", image_png),
    ("image_jpeg", image_jpeg),
    ("image_bmp", image_bmp),
    ("image_tga", image_tga),
    ("image_tiff", image_tiff),
    ("image_exr", image_exr),
    ("obj", obj),
    ("gltf", gltf),
];

/// The line that separates a model file from its side file in the OBJ and glTF targets' inputs.
pub const SIDE_FILE: &[u8] = b"\n#--side-file--\n";

/// A 512 MB memory budget for every target, so that a small valid input asking for much work (a dozen
/// 8192-texel bump tables) meets wrinkle's own budget check, as a user's would, instead of the fuzzer's
/// memory and time limits. Under 1 GB that input built three tables before the check stopped it, 11 s
/// under AddressSanitizer, past libFuzzer's 10 s timeout; under 512 MB the first is refused.
fn bounded() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| wrinkle::limits::set(wrinkle::limits::Limit::Memory, 512 << 20).expect("a valid budget"));
}

/// A scene file's text, parsed (and validated, with its textures and models read) against the
/// repository's `scenes/` folder, so that the corpus' `tiles_color.png` and `models/uv_sphere.obj` resolve.
pub fn scene(data: &[u8]) {
    bounded();
    let Ok(text) = std::str::from_utf8(data) else { return };
    let _ = Scene::parse(text, &repo_root().join("scenes"));
}

pub fn image_png(data: &[u8]) {
    image(data, "png");
}

pub fn image_jpeg(data: &[u8]) {
    image(data, "jpg");
}

pub fn image_bmp(data: &[u8]) {
    image(data, "bmp");
}

pub fn image_tga(data: &[u8]) {
    image(data, "tga");
}

pub fn image_tiff(data: &[u8]) {
    image(data, "tif");
}

/// An OpenEXR file through every reader of it: its channels, as a height map, as a colour texture.
pub fn image_exr(data: &[u8]) {
    let path = scratch_file("input.exr", data);
    let _ = io::read_exr_channels(&path);
    let _ = io::load_grey(&path);
    let _ = io::load_texels(&path, srgb_of(data));
    let _ = wrinkle::image::indexed::load_indices(&path);
    let _ = wrinkle::image::indexed::load_palette(&path);
}

/// An image file (recognised by content, else by the extension `ext`) as a height map, as a colour
/// texture, and row by row through the streaming reader (`png_rows` for a plain PNG, the png crate's row
/// decoder for the other PNGs).
fn image(data: &[u8], ext: &str) {
    let path = scratch_file(&format!("input.{ext}"), data);
    let _ = io::load_grey(&path);
    let _ = io::load_texels(&path, srgb_of(data));
    if let Ok(mut rows) = ImageRows::open(&path) {
        let width = rows.width();
        let (mut grey, mut rgb8, mut rgb) = (vec![0.0f32; width], vec![0u8; 3 * width], vec![0.0f32; 3 * width]);
        for y in 0..rows.height() {
            let row = match y % 3 {
                0 => rows.read_grey(&mut grey, 1.0),
                1 => rows.read_rgb8(&mut rgb8),
                _ => rows.read_rgb(&mut rgb),
            };
            if row.is_err() {
                break;
            }
        }
    }
}

/// An OBJ model (with `fuzz.mtl` after [`SIDE_FILE`], absent without it) as a scene's mesh object.
pub fn obj(data: &[u8]) {
    let (model, side) = split_side(data);
    model_scene("input.obj", model, "fuzz.mtl", side);
}

/// A glTF model, `.glb` when it starts with the GLB magic, else `.gltf` (with `fuzz.bin` after
/// [`SIDE_FILE`]), as a scene's mesh object.
pub fn gltf(data: &[u8]) {
    let (model, side) = split_side(data);
    let name = if model.starts_with(b"glTF") { "input.glb" } else { "input.gltf" };
    model_scene(name, model, "fuzz.bin", side);
}

/// `data` up to the first [`SIDE_FILE`] line, and what follows it.
fn split_side(data: &[u8]) -> (&[u8], Option<&[u8]>) {
    match data.windows(SIDE_FILE.len()).position(|w| w == SIDE_FILE) {
        Some(k) => (&data[..k], Some(&data[k + SIDE_FILE.len()..])),
        None => (data, None),
    }
}

/// Writes the model file (and its side file, or removes a stale one) and parses a scene of one mesh object
/// naming it, which loads the model, its materials and textures.
fn model_scene(name: &str, model: &[u8], side_name: &str, side: Option<&[u8]>) {
    let path = scratch_file(name, model);
    let dir = path.parent().expect("scratch files lie in a folder").to_path_buf();
    match side {
        Some(bytes) => {
            scratch_file(side_name, bytes);
        }
        None => {
            let _ = std::fs::remove_file(dir.join(side_name));
        }
    }
    let text = format!(
        "[camera]\neye = [0.0, 0.0, 5.0]\nlook_at = [0.0, 0.0, 0.0]\n\n\
         [[object]]\nshape = \"mesh\"\nfile = \"{name}\"\n"
    );
    let _ = Scene::parse(&text, &dir);
}

/// Whether colour textures of this input are read as sRGB: both ways, chosen by the input.
fn srgb_of(data: &[u8]) -> bool {
    data.len().is_multiple_of(2)
}

/// The repository's root: the first folder above this crate's manifest with both `scenes/` and `fuzz/`.
pub fn repo_root() -> PathBuf {
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR"));
    manifest
        .ancestors()
        .find(|p| p.join("scenes").is_dir() && p.join("fuzz").is_dir())
        .unwrap_or(manifest)
        .to_path_buf()
}

thread_local! {
    /// This thread's scratch folder, made (with its two textures) on first use.
    static SCRATCH: RefCell<Option<PathBuf>> = const { RefCell::new(None) };
}

/// This thread's scratch folder.
pub fn scratch_dir() -> PathBuf {
    static NEXT: AtomicUsize = AtomicUsize::new(0);
    SCRATCH.with(|s| {
        s.borrow_mut()
            .get_or_insert_with(|| {
                let n = NEXT.fetch_add(1, Ordering::Relaxed);
                if n == 0 {
                    remove_stale_scratch_dirs();
                }
                let dir = std::env::temp_dir().join(format!("wrinkle-fuzz-{}-{n}", std::process::id()));
                std::fs::create_dir_all(&dir).expect("create the fuzz scratch folder");
                io::write_png_rgb8(&dir.join("t.png"), 2, 2, &[200, 40, 40, 40, 200, 40, 40, 40, 200, 250, 250, 250])
                    .expect("write t.png");
                io::write_png_rgb8(&dir.join("h.png"), 2, 2, &[0, 0, 0, 255, 255, 255, 255, 255, 255, 0, 0, 0])
                    .expect("write h.png");
                dir
            })
            .clone()
    })
}

/// Removes the scratch folders of processes that have ended (libFuzzer exits without unwinding, and
/// its fork mode starts many processes), where /proc tells which are running.
fn remove_stale_scratch_dirs() {
    if !Path::new("/proc/self").exists() {
        return;
    }
    let Ok(entries) = std::fs::read_dir(std::env::temp_dir()) else { return };
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some(rest) = name.to_str().and_then(|n| n.strip_prefix("wrinkle-fuzz-")) else { continue };
        let Some(pid) = rest.split('-').next().filter(|p| !p.is_empty() && p.bytes().all(|b| b.is_ascii_digit()))
        else {
            continue;
        };
        if !Path::new("/proc").join(pid).exists() {
            let _ = std::fs::remove_dir_all(entry.path());
        }
    }
}

/// Removes this thread's scratch folder (the next input makes a new one).
pub fn remove_scratch_dir() {
    if let Some(dir) = SCRATCH.with(|s| s.borrow_mut().take()) {
        let _ = std::fs::remove_dir_all(dir);
    }
}

/// Writes `data` to `name` in this thread's scratch folder.
fn scratch_file(name: &str, data: &[u8]) -> PathBuf {
    bounded();
    let path = scratch_dir().join(name);
    std::fs::write(&path, data).expect("write a fuzz input to the scratch folder");
    path
}
