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

pub fn write_frame(path: &Path, frame: &Frame) -> Result<()> {
    match format_of(path)? {
        Format::Png => io::write_png_rgb8(path, frame.width, frame.height, &encode_srgb8(frame)),
        Format::Exr => {
            let ch = |k: usize| frame.color.iter().map(|c| c[k]).collect::<Vec<f32>>();
            let (r, g, b) = (ch(0), ch(1), ch(2));
            io::write_exr(path, frame.width, frame.height, &[("R", &r), ("G", &g), ("B", &b)])
        }
    }
}

/// `OUT.png` -> `OUT.{name}.exr`.
pub fn aov_path(out: &Path, name: &str) -> PathBuf {
    out.with_extension(format!("{name}.exr"))
}

/// Writes every AOV the frame holds beside `out`.
pub fn write_aovs(out: &Path, frame: &Frame) -> Result<()> {
    let (w, h) = (frame.width, frame.height);
    let split = |v: &[[f32; 3]], k: usize| v.iter().map(|c| c[k]).collect::<Vec<f32>>();
    if let Some(n) = &frame.normal {
        let (x, y, z) = (split(n, 0), split(n, 1), split(n, 2));
        io::write_exr(&aov_path(out, "normal"), w, h, &[("X", &x), ("Y", &y), ("Z", &z)])?;
    }
    if let Some(uv) = &frame.uv {
        let u: Vec<f32> = uv.iter().map(|c| c[0]).collect();
        let v: Vec<f32> = uv.iter().map(|c| c[1]).collect();
        io::write_exr(&aov_path(out, "uv"), w, h, &[("U", &u), ("V", &v)])?;
    }
    if let Some(d) = &frame.depth {
        io::write_exr(&aov_path(out, "depth"), w, h, &[("Z", d)])?;
    }
    if let Some(id) = &frame.id {
        io::write_exr(&aov_path(out, "id"), w, h, &[("id", id)])?;
    }
    Ok(())
}
