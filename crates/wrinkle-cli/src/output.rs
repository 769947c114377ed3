//! Writing frames: PNG (8-bit sRGB) or EXR (linear float) by the output's extension, and the AOVs beside it.

use rayon::prelude::*;
use std::path::{Path, PathBuf};
use wrinkle::image::{color::SrgbEncoder, io};
use wrinkle::{Error, Frame, Result};

/// The output formats, chosen by extension.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Format {
    Png,
    Exr,
}

pub fn format_of(path: &Path) -> Result<Format> {
    match path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).as_deref() {
        Some("png") => Ok(Format::Png),
        Some("exr") => Ok(Format::Exr),
        _ => Err(Error::Invalid(format!("{}: output must end in .png or .exr", path.display()))),
    }
}

/// The frame's linear RGB as 8-bit sRGB bytes.
pub fn encode_srgb8(frame: &Frame) -> Vec<u8> {
    let enc = SrgbEncoder::new();
    let mut out = vec![0u8; frame.width * frame.height * 3];
    out.par_chunks_mut(frame.width * 3).zip(frame.color.par_chunks(frame.width)).for_each(|(dst, src)| {
        for (d, s) in dst.chunks_exact_mut(3).zip(src) {
            d[0] = enc.encode(s[0]);
            d[1] = enc.encode(s[1]);
            d[2] = enc.encode(s[2]);
        }
    });
    out
}

/// One file to write: its final path and the writer that produces it at a given path.
type Output<'a> = (PathBuf, Box<dyn Fn(&Path) -> Result<()> + 'a>);

/// The frame as PNG or EXR (by the extension of `out`), and every AOV it holds as `OUT.<name>.exr`.
fn outputs<'a>(out: &Path, frame: &'a Frame) -> Result<Vec<Output<'a>>> {
    let (w, h) = (frame.width, frame.height);
    let mut list: Vec<Output<'a>> = Vec::new();
    match format_of(out)? {
        Format::Png => {
            list.push((out.to_path_buf(), Box::new(move |p| io::write_png_rgb8(p, w, h, &encode_srgb8(frame)))))
        }
        Format::Exr => list.push((
            out.to_path_buf(),
            Box::new(move |p| {
                let (r, g, b) = (channel(&frame.color, 0), channel(&frame.color, 1), channel(&frame.color, 2));
                io::write_exr(p, w, h, &[("R", &r), ("G", &g), ("B", &b)])
            }),
        )),
    }
    if let Some(n) = &frame.normal {
        list.push((
            aov_path(out, "normal"),
            Box::new(move |p| {
                let (x, y, z) = (channel(n, 0), channel(n, 1), channel(n, 2));
                io::write_exr(p, w, h, &[("X", &x), ("Y", &y), ("Z", &z)])
            }),
        ));
    }
    if let Some(uv) = &frame.uv {
        list.push((
            aov_path(out, "uv"),
            Box::new(move |p| io::write_exr(p, w, h, &[("U", &channel(uv, 0)), ("V", &channel(uv, 1))])),
        ));
    }
    if let Some(d) = &frame.depth {
        list.push((aov_path(out, "depth"), Box::new(move |p| io::write_exr(p, w, h, &[("Z", d)]))));
    }
    if let Some(id) = &frame.id {
        list.push((aov_path(out, "id"), Box::new(move |p| io::write_exr(p, w, h, &[("id", id)]))));
    }
    if let Some(ids) = &frame.primitive {
        list.push((
            aov_path(out, "primitive"),
            Box::new(move |p| {
                let (object, triangle): (Vec<u32>, Vec<u32>) = ids.iter().map(|&[o, t]| (o, t)).unzip();
                io::write_exr_u32(p, w, h, &[("object", &object), ("triangle", &triangle)])
            }),
        ));
    }
    Ok(list)
}

/// One channel of an interleaved buffer.
fn channel<const N: usize>(pixels: &[[f32; N]], k: usize) -> Vec<f32> {
    pixels.iter().map(|c| c[k]).collect()
}

/// `OUT.png` -> `OUT.{name}.exr`.
pub fn aov_path(out: &Path, name: &str) -> PathBuf {
    out.with_extension(format!("{name}.exr"))
}

/// A hidden name beside `path` where it is written before it is renamed into place.
fn staging_path(path: &Path) -> PathBuf {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    path.with_file_name(format!(".{name}.{}.staged", std::process::id()))
}

/// Writes the frame and its AOVs as one unit: every file is written under a staging name first and renamed
/// into place only when all of them are complete, so a failure leaves none of them behind.
pub fn write_outputs(out: &Path, frame: &Frame) -> Result<()> {
    let list = outputs(out, frame)?;
    let mut staged: Vec<(PathBuf, &Path)> = Vec::with_capacity(list.len());
    let mut result = Ok(());
    for (path, write) in &list {
        let tmp = staging_path(path);
        match write(&tmp) {
            Ok(()) => staged.push((tmp, path)),
            Err(e) => {
                result = Err(with_path(e, path));
                break;
            }
        }
    }
    if result.is_ok() {
        // A folder in the way is the one common reason a rename fails: find it before renaming anything.
        if let Some((_, path)) = staged.iter().find(|(_, p)| p.is_dir()) {
            result = Err(Error::write(*path, "a folder of that name is in the way"));
        }
    }
    let mut placed = 0;
    if result.is_ok() {
        for (tmp, path) in &staged {
            if let Err(e) = std::fs::rename(tmp, path) {
                result = Err(Error::write(*path, e));
                break;
            }
            placed += 1;
        }
    }
    if result.is_err() {
        // Nothing of this frame stays: neither the staged files nor those already renamed into place.
        for (k, (tmp, path)) in staged.iter().enumerate() {
            let _ = std::fs::remove_file(if k < placed { *path } else { tmp.as_path() });
        }
    }
    result
}

/// The error of writing a staged file, told of the file the user asked for.
fn with_path(e: Error, path: &Path) -> Error {
    match e {
        Error::Write { message, .. } => Error::Write { path: path.to_path_buf(), message },
        Error::Invalid(m) => Error::Invalid(m),
        other => Error::write(path, other),
    }
}
