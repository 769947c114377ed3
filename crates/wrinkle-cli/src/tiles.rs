//! `wrinkle render --tile N`: a frame rendered in N x N parts, each a crop of the whole frame (so its
//! pixels are exactly the whole frame's) and all from one setup (`render_parts`), assembled band by band of
//! tiles across the frame.

use crate::output::{format_of, stage_outputs, Format};
use crate::progress::Progress;
use glam::Vec3;
use std::path::Path;
use wrinkle::image::io::Placement;
use wrinkle::image::output::OutputSet;
use wrinkle::image::stream::{write_rows_as, OutputFormat, PngCompression, RowFormat};
use wrinkle::{limits, render_parts, Crop, Frame, RenderOptions, Result, Scene};

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
    let tiles: Vec<Crop> = (0..h)
        .step_by(n)
        .flat_map(|y0| (0..w).step_by(n).map(move |x0| Crop { x0, y0, x1: (x0 + n).min(w), y1: (y0 + n).min(h) }))
        .collect();
    let progress = bar.then(|| Progress::new("render", tiles.len() as u64, "tiles", "{pos}/{len} tiles"));
    // Each band of tiles, pasted into one frame as wide as the whole, goes to `band` once its last tile is in.
    let in_bands = |band: &mut dyn FnMut(Frame) -> Result<()>| -> Result<()> {
        let mut strip: Option<Frame> = None;
        render_parts(scene, options, &tiles, &mut |tile| {
            let p = tile.placement;
            let s = strip.get_or_insert_with(|| {
                let mut band = Frame::new(w, p.height, tile.aovs(), Vec3::ZERO);
                band.placement = Placement { x0: 0, width: w, ..p };
                band
            });
            s.paste(&tile, p.x0, 0);
            if let Some(bar) = &progress {
                bar.inc(1);
            }
            match p.x0 + p.width == w {
                true => band(strip.take().expect("the band being filled")),
                false => Ok(()),
            }
        })
    };
    let result = if format_of(out)? == Format::Png && !options.transparent && !options.aovs.any() {
        let rows = RowFormat { channels: 3, sixteen: false };
        set.stage(out, |path| {
            write_rows_as(path, OutputFormat::Png, w, h, rows, PngCompression::Fast, |sink| {
                in_bands(&mut |strip| sink(&strip.srgb8()))
            })
        })
    } else {
        let mut whole: Option<Frame> = None;
        in_bands(&mut |strip| {
            if whole.is_none() {
                limits::reserve((w * h) as u64 * strip.aovs().bytes_per_pixel(), || {
                    format!("{}: the {w}x{h} frame assembled from its tiles", out.display())
                })?;
            }
            let y0 = strip.placement.y0;
            whole.get_or_insert_with(|| Frame::new(w, h, strip.aovs(), Vec3::ZERO)).paste(&strip, 0, y0);
            Ok(())
        })
        .and_then(|()| stage_outputs(set, out, &whole.expect("at least one band")))
    };
    if let Some(p) = progress {
        p.finish();
    }
    result
}
