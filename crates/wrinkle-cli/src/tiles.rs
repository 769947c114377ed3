//! `wrinkle render --tile N`: a frame rendered in N x N parts, one after another, each a crop of the whole
//! frame (so its pixels are exactly the whole frame's), assembled band by band of tiles across the frame.

use crate::output::{encode_srgb8, format_of, stage_outputs, Format};
use crate::progress::Progress;
use glam::Vec3;
use std::path::Path;
use wrinkle::image::output::OutputSet;
use wrinkle::image::stream::{write_rows_as, OutputFormat, PngCompression, RowFormat};
use wrinkle::{limits, render, Crop, Frame, RenderOptions, Result, Scene};

/// Renders the frame in `n` x `n` tiles and stages its outputs at `out` in `set`: a PNG of colour alone is
/// encoded band by band as the bands come, so only one band of tiles is held; anything else (EXR, AOVs, a
/// transparent background) is assembled into the whole frame first. `bar`: show the tiles' progress.
pub fn render_in_tiles(
    scene: &Scene,
    options: &RenderOptions,
    n: usize,
    out: &Path,
    set: &mut OutputSet,
    bar: bool,
) -> Result<()> {
    let (w, h) = (options.width, options.height);
    let (bands, across) = (h.div_ceil(n), w.div_ceil(n));
    let progress = bar.then(|| Progress::new("render", (bands * across) as u64, "tiles", "{pos}/{len} tiles"));
    // Band `b`: its tiles rendered left to right and pasted into one frame as wide as the whole.
    let band = |b: usize| -> Result<Frame> {
        let (y0, y1) = (b * n, ((b + 1) * n).min(h));
        let mut strip: Option<Frame> = None;
        for x0 in (0..w).step_by(n) {
            let crop = Crop { x0, y0, x1: (x0 + n).min(w), y1 };
            let tile = render(scene, &RenderOptions { crop: Some(crop), ..options.clone() })?;
            strip.get_or_insert_with(|| Frame::new(w, y1 - y0, tile.aovs(), Vec3::ZERO)).paste(&tile, x0, 0);
            if let Some(p) = &progress {
                p.inc(1);
            }
        }
        Ok(strip.expect("a band holds at least one tile"))
    };
    let colour_only = !options.transparent && !options.aovs.any();
    let result = if format_of(out)? == Format::Png && colour_only {
        let rows = RowFormat { channels: 3, sixteen: false };
        set.stage(out, |path| {
            write_rows_as(path, OutputFormat::Png, w, h, rows, PngCompression::Fast, |sink| {
                (0..bands).try_for_each(|b| sink(&encode_srgb8(&band(b)?)))
            })
        })
    } else {
        let first = band(0)?;
        limits::reserve((w * h) as u64 * first.aovs().bytes_per_pixel(), || {
            format!("{}: the {w}x{h} frame assembled from its tiles", out.display())
        })?;
        let mut whole = Frame::new(w, h, first.aovs(), Vec3::ZERO);
        whole.paste(&first, 0, 0);
        drop(first);
        for b in 1..bands {
            whole.paste(&band(b)?, 0, b * n);
        }
        stage_outputs(set, out, &whole)
    };
    if let Some(p) = progress {
        p.finish();
    }
    result
}
