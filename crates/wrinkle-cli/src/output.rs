//! Writing frames: PNG (8-bit sRGB) or EXR (linear float) by the output's extension, and the AOVs beside it.

use rayon::prelude::*;
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use wrinkle::image::output::OutputSet;
use wrinkle::image::{color::SrgbEncoder, io};
use wrinkle::{Error, Frame, Result};

/// The output formats, chosen by extension.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Format {
    Png,
    Exr,
}

/// `-o -`: the frame goes to the standard output, as PNG.
pub fn is_stdout(path: &Path) -> bool {
    path == Path::new("-")
}

/// Refuses `-o -` when the standard output is a terminal (a PNG there is noise), before any work.
pub fn check_stdout() -> Result<()> {
    if std::io::stdout().is_terminal() {
        return Err(Error::Invalid("-o -: the standard output is a terminal; send it to a file or a pipe".into()));
    }
    Ok(())
}

/// `-o -`: the frame as PNG (RGBA with a transparent background) on the standard output.
pub fn write_stdout(frame: &Frame) -> Result<()> {
    let name = Path::new("the standard output");
    let size = (frame.width, frame.height);
    let mut out = std::io::stdout().lock();
    match &frame.alpha {
        None => io::encode_png8(&mut out, name, size, 3, &frame.srgb8())?,
        Some(alpha) => io::encode_png8(&mut out, name, size, 4, &encode_srgba8(frame, alpha))?,
    }
    out.flush().map_err(|e| Error::write(name, e))
}

pub fn format_of(path: &Path) -> Result<Format> {
    if is_stdout(path) {
        return Ok(Format::Png);
    }
    require_extension(path, &["png", "exr"])?;
    let exr = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("exr"));
    Ok(if exr { Format::Exr } else { Format::Png })
}

/// The frame's premultiplied colour and its coverage `alpha` as 8-bit RGBA: sRGB colour divided by alpha
/// (PNG's alpha is straight), alpha linear.
pub fn encode_srgba8(frame: &Frame, alpha: &[f32]) -> Vec<u8> {
    let enc = SrgbEncoder::new();
    let mut out = vec![0u8; frame.width * frame.height * 4];
    out.par_chunks_mut(frame.width * 4)
        .zip(frame.color.par_chunks(frame.width).zip(alpha.par_chunks(frame.width)))
        .for_each(|(dst, (src, alpha))| {
            for ((d, s), &a) in dst.chunks_exact_mut(4).zip(src).zip(alpha) {
                let straight = if a > 0.0 { 1.0 / a } else { 0.0 };
                for c in 0..3 {
                    d[c] = enc.encode(s[c] * straight);
                }
                d[3] = (a.clamp(0.0, 1.0) * 255.0).round() as u8;
            }
        });
    out
}

/// One file to write: its final path and the writer that produces it at a given path.
type Output<'a> = (PathBuf, Box<dyn Fn(&Path) -> Result<()> + 'a>);

/// The frame as PNG or EXR (by the extension of `out`), and every AOV it holds as `OUT.<name>.exr`.
fn outputs<'a>(out: &Path, frame: &'a Frame) -> Result<Vec<Output<'a>>> {
    let (w, h) = (frame.width, frame.height);
    // A crop's EXRs carry its place in the frame (their data window); its PNG is the crop alone.
    let at = frame.placement;
    let mut list: Vec<Output<'a>> = Vec::new();
    match format_of(out)? {
        Format::Png => list.push((
            out.to_path_buf(),
            match &frame.alpha {
                None => Box::new(move |p| io::write_png_rgb8(p, w, h, &frame.srgb8())),
                Some(alpha) => Box::new(move |p| io::write_png_rgba8(p, w, h, &encode_srgba8(frame, alpha))),
            },
        )),
        // Premultiplied, as EXR's colour and alpha are.
        Format::Exr => list.push((
            out.to_path_buf(),
            Box::new(move |p| {
                let (r, g, b) = (channel(&frame.color, 0), channel(&frame.color, 1), channel(&frame.color, 2));
                match &frame.alpha {
                    None => io::write_exr_placed(p, at, &[("R", &r), ("G", &g), ("B", &b)]),
                    Some(a) => io::write_exr_placed(p, at, &[("R", &r), ("G", &g), ("B", &b), ("A", a)]),
                }
            }),
        )),
    }
    if let Some(n) = &frame.normal {
        list.push((
            aov_path(out, "normal"),
            Box::new(move |p| {
                let (x, y, z) = (channel(n, 0), channel(n, 1), channel(n, 2));
                io::write_exr_placed(p, at, &[("X", &x), ("Y", &y), ("Z", &z)])
            }),
        ));
    }
    if let Some(uv) = &frame.uv {
        list.push((
            aov_path(out, "uv"),
            Box::new(move |p| io::write_exr_placed(p, at, &[("U", &channel(uv, 0)), ("V", &channel(uv, 1))])),
        ));
    }
    if let Some(d) = &frame.depth {
        list.push((aov_path(out, "depth"), Box::new(move |p| io::write_exr_placed(p, at, &[("Z", d)]))));
    }
    if let Some(id) = &frame.id {
        list.push((aov_path(out, "id"), Box::new(move |p| io::write_exr_placed(p, at, &[("id", id)]))));
    }
    if let Some(ids) = &frame.primitive {
        list.push((
            aov_path(out, "primitive"),
            Box::new(move |p| {
                let (object, triangle): (Vec<u32>, Vec<u32>) = ids.iter().map(|&[o, t]| (o, t)).unzip();
                io::write_exr_u32(p, at, &[("object", &object), ("triangle", &triangle)])
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

/// Writes the frame and its AOVs as one unit: none of them is placed unless all are written.
pub fn write_outputs(out: &Path, frame: &Frame) -> Result<()> {
    let mut set = OutputSet::new();
    stage_outputs(&mut set, out, frame)?;
    set.commit()
}

/// Writes the frame and its AOVs into `set`, to be placed with the rest of it.
pub fn stage_outputs(set: &mut OutputSet, out: &Path, frame: &Frame) -> Result<()> {
    for (path, write) in outputs(out, frame)? {
        set.stage(&path, write)?;
    }
    Ok(())
}

/// `Ok` if `path` ends in one of the `allowed` extensions (any case), else an error naming them: an output
/// is never written in a format its name does not say.
pub fn require_extension(path: &Path, allowed: &[&str]) -> Result<()> {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    if ext.as_deref().is_some_and(|e| allowed.contains(&e)) {
        return Ok(());
    }
    let list: Vec<String> = allowed.iter().map(|e| format!(".{e}")).collect();
    Err(Error::Invalid(format!("{}: output must end in {}", path.display(), list.join(" or "))))
}
