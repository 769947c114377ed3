//! A 3x3-neighbourhood filter streamed through an image in strips of rows: one thread decodes the height
//! rows (and another the rows of an optional colour image), the rows of each strip are filtered in
//! parallel by rayon, and the caller's thread encodes the finished rows. Only a few strips are in memory
//! at a time, so memory does not grow with the image's height.

use std::collections::VecDeque;
use std::sync::mpsc::{channel, sync_channel, Receiver, Sender};
use std::time::{Duration, Instant};

use rayon::prelude::*;

use super::stream::ImageRows;
use super::{Image, ImageRef};
use crate::error::{Error, Result};

/// What lies beyond the image's edges.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Edges {
    /// The nearest edge pixel is repeated.
    Clamp,
    /// The image repeats: the row above the first is the last, the column left of the first is the last.
    Wrap,
}

/// The three rows around one pixel row, each padded with one pixel on either side (so `len = width + 2`):
/// pixel x of the image is at index x + 1.
#[derive(Clone, Copy)]
pub struct Window<'a> {
    pub above: &'a [f32],
    pub row: &'a [f32],
    pub below: &'a [f32],
}

/// The filter: fills every byte of one output row (which holds the bytes of an earlier strip) from the window
/// around image row `y` and, when a colour image is given, that image's row `y` (8-bit RGB). `scratch` is a
/// per-thread buffer of `3 * width` floats.
pub type RowKernel<'a> = dyn Fn(usize, Window, Option<&[u8]>, &mut [f32], &mut [u8]) + Sync + 'a;

/// Where time went: `kernel` is the wall time of the parallel filtering alone.
#[derive(Clone, Copy, Debug, Default)]
pub struct StripStats {
    pub kernel: Duration,
}

/// Rows per strip: about a quarter of a megapixel, at least 8 rows. Larger strips cost more than they save: the
/// few strips in flight are fresh memory, and in a virtual machine faulting its pages in took a tenth of an
/// emboss's CPU time with megapixel strips.
fn strip_rows(width: usize) -> usize {
    ((1 << 18) / width.max(1)).clamp(8, 4096)
}

/// Pads a decoded row into `padded` (length width + 2) by the edge rule.
fn pad(padded: &mut [f32], edges: Edges) {
    let n = padded.len();
    let (left, right) = match edges {
        Edges::Clamp => (padded[1], padded[n - 2]),
        Edges::Wrap => (padded[n - 2], padded[1]),
    };
    padded[0] = left;
    padded[n - 1] = right;
}

/// An image of the size of `image` (held in memory, an image or a view of the caller's buffer), every pixel
/// `fill` at first, filled row by row, in parallel, by `row(y, window, out_row)`, each window padded by the
/// edge rule: the in-memory form of [`filter_3x3`], for callers that hold the whole image.
pub fn filter_rows_in_memory<'a, T: Copy + Send + Sync>(
    image: impl Into<ImageRef<'a, f32>>,
    edges: Edges,
    fill: T,
    row: impl Fn(usize, Window, &mut [T]) + Sync,
) -> Image<T> {
    let image = image.into();
    let (width, height) = (image.width(), image.height());
    let mut out = Image::new(width, height, fill);
    if width == 0 || height == 0 {
        return out;
    }
    let padded: Vec<Vec<f32>> = image
        .pixels()
        .chunks_exact(width)
        .map(|r| {
            let mut p = Vec::with_capacity(width + 2);
            p.push(0.0);
            p.extend_from_slice(r);
            p.push(0.0);
            pad(&mut p, edges);
            p
        })
        .collect();
    let neighbours = |y: usize| match edges {
        Edges::Clamp => (y.saturating_sub(1), (y + 1).min(height - 1)),
        Edges::Wrap => ((y + height - 1) % height, (y + 1) % height),
    };
    out.pixels.par_chunks_mut(width).enumerate().for_each(|(y, o)| {
        let (up, down) = neighbours(y);
        row(y, Window { above: &padded[up], row: &padded[y], below: &padded[down] }, o)
    });
    out
}

/// The last row of an image, padded, read by decoding it to the end (for `Edges::Wrap`, where the first
/// row's upper neighbour is the last row).
pub fn last_row(mut rows: ImageRows, full_scale: f32) -> Result<Vec<f32>> {
    let w = rows.width();
    let mut padded = vec![0.0; w + 2];
    for _ in 0..rows.height() {
        rows.read_grey(&mut padded[1..w + 1], full_scale)?;
    }
    pad(&mut padded, Edges::Wrap);
    Ok(padded)
}

/// Filters every row of `heights` (grey values with full scale `full_scale`) with `kernel` and hands the
/// output rows, `out_row_bytes` each, in order to `sink` (several rows at a time). `wrap_last_row` is
/// the padded last row (from [`last_row`]) when `edges` is `Wrap`. `colour`, when given, must be the same
/// size; its rows are passed to the kernel alongside. `progress` is told how many rows are done.
#[allow(clippy::too_many_arguments)]
pub fn filter_3x3(
    heights: ImageRows,
    full_scale: f32,
    edges: Edges,
    wrap_last_row: Option<Vec<f32>>,
    colour: Option<ImageRows>,
    out_row_bytes: usize,
    kernel: &RowKernel,
    sink: &mut dyn FnMut(&[u8]) -> Result<()>,
    progress: &dyn Fn(usize),
) -> Result<StripStats> {
    let (w, h) = (heights.width(), heights.height());
    if let Some(c) = &colour {
        if (c.width(), c.height()) != (w, h) {
            return Err(Error::Invalid(format!(
                "{}: the colour image is {}x{}, the height image {w}x{h}",
                c.path().display(),
                c.width(),
                c.height()
            )));
        }
    }
    if edges == Edges::Wrap && wrap_last_row.is_none() {
        return Err(Error::Invalid("wrapped edges need the last row".into()));
    }
    let strip = strip_rows(w);
    let pw = w + 2;
    std::thread::scope(|scope| {
        let (height_tx, height_rx) = sync_channel::<Result<Vec<f32>>>(2);
        // Spent strips go back to be filled again: each fresh one cost its pages' faults and zeroing.
        let (spent_heights_tx, spent_heights_rx) = channel::<Vec<f32>>();
        let (spent_out_tx, spent_out_rx) = channel::<Vec<u8>>();
        scope.spawn(move || {
            let mut heights = heights;
            let mut y = 0;
            while y < h {
                let n = strip.min(h - y);
                let mut rows = spent_heights_rx.try_recv().unwrap_or_default();
                rows.resize(n * pw, 0.0);
                let result = rows.chunks_exact_mut(pw).try_for_each(|r| {
                    heights.read_grey(&mut r[1..w + 1], full_scale)?;
                    pad(r, edges);
                    Ok(())
                });
                let failed = result.is_err();
                if height_tx.send(result.map(|()| rows)).is_err() || failed {
                    return;
                }
                y += n;
            }
        });
        let colour_rx = colour.map(|mut colour| {
            let (tx, rx) = sync_channel::<Result<Vec<u8>>>(2);
            scope.spawn(move || {
                let mut y = 0;
                while y < h {
                    let n = strip.min(h - y);
                    let mut rows = vec![0u8; n * 3 * w];
                    let result = rows.chunks_exact_mut(3 * w).try_for_each(|r| colour.read_rgb8(r));
                    let failed = result.is_err();
                    if tx.send(result.map(|()| rows)).is_err() || failed {
                        return;
                    }
                    y += n;
                }
            });
            rx
        });
        let (out_tx, out_rx) = sync_channel::<Result<Vec<u8>>>(2);
        let filter = scope.spawn(move || {
            let mut stats = StripStats::default();
            let mut state = Filter {
                width: w,
                height: h,
                edges,
                strips: VecDeque::new(),
                rows_in: 0,
                first: Vec::new(),
                wrap_last: wrap_last_row,
                spent: spent_heights_tx,
            };
            let mut colour = ColourRows { width: w, rows: Vec::new(), rx: colour_rx };
            let mut next_out = 0;
            for strip in height_rx {
                let result = strip.and_then(|rows| {
                    if state.first.is_empty() {
                        state.first = rows[..pw].to_vec();
                    }
                    state.receive(rows);
                    // Row y needs row y + 1, except the last.
                    let ready = if state.rows_in == h { h } else { state.rows_in - 1 };
                    let t = Instant::now();
                    let out = colour.take(ready - next_out).and_then(|c| {
                        let out = spent_out_rx.try_recv().unwrap_or_default();
                        state.run(next_out..ready, c.as_deref(), out_row_bytes, kernel, out)
                    });
                    stats.kernel += t.elapsed();
                    next_out = ready;
                    state.forget_before(next_out.saturating_sub(1));
                    out
                });
                let failed = result.is_err();
                if out_tx.send(result).is_err() || failed {
                    break;
                }
            }
            stats
        });
        let mut done = 0;
        let mut outcome = Ok(());
        for strip in out_rx {
            match strip.and_then(|rows| {
                sink(&rows)?;
                let n = rows.len() / out_row_bytes.max(1);
                // The filter thread may have finished; then the strip is simply dropped.
                let _ = spent_out_tx.send(rows);
                Ok(n)
            }) {
                Ok(n) => {
                    done += n;
                    progress(done);
                }
                Err(e) => {
                    outcome = Err(e);
                    break;
                }
            }
        }
        // Dropping the receiver (end of the loop) stops the threads if the sink failed.
        let stats = filter.join().map_err(|_| Error::Invalid("the filter thread panicked".into()))?;
        outcome?;
        if done != h {
            return Err(Error::Invalid(format!("only {done} of the image's {h} rows were filtered")));
        }
        Ok(stats)
    })
}

/// The filtering thread's rows: the strips of decoded rows still needed, and the colour rows not yet used.
struct Filter {
    width: usize,
    height: usize,
    edges: Edges,
    /// Each strip's first row and its padded rows, oldest first; kept whole rather than copied into one
    /// window, since copying every row took more CPU than the filter's arithmetic.
    strips: VecDeque<(usize, Vec<f32>)>,
    /// Rows received so far.
    rows_in: usize,
    /// Row 0, padded (the lower neighbour of the last row when wrapping).
    first: Vec<f32>,
    wrap_last: Option<Vec<f32>>,
    /// Where strips no longer needed go, to be filled again.
    spent: Sender<Vec<f32>>,
}

/// Decoded colour rows (8-bit RGB) from the first not yet filtered, and where more come from.
struct ColourRows {
    width: usize,
    rows: Vec<u8>,
    rx: Option<Receiver<Result<Vec<u8>>>>,
}

impl ColourRows {
    /// The colour rows of the next `n` output rows (receiving strips as needed); `None` without colour.
    fn take(&mut self, n: usize) -> Result<Option<Vec<u8>>> {
        let Some(rx) = &self.rx else { return Ok(None) };
        let need = n * 3 * self.width;
        while self.rows.len() < need {
            match rx.recv() {
                Ok(strip) => self.rows.extend_from_slice(&strip?),
                Err(_) => return Err(Error::Invalid("the colour image ended early".into())),
            }
        }
        Ok(Some(self.rows.drain(..need).collect()))
    }
}

impl Filter {
    /// The padded row `y`, with the edge rule above the first row and below the last.
    fn row(&self, y: isize) -> &[f32] {
        let pw = self.width + 2;
        let h = self.height as isize;
        let y = match (self.edges, y) {
            (Edges::Wrap, -1) => return self.wrap_last.as_deref().unwrap_or(&self.first),
            (Edges::Wrap, y) if y == h => return &self.first,
            (Edges::Clamp, y) => y.clamp(0, h - 1) as usize,
            (_, y) => y as usize,
        };
        let (base, rows) = self.strips.iter().rev().find(|(base, _)| *base <= y).expect("row not yet received");
        let k = y - base;
        &rows[k * pw..(k + 1) * pw]
    }

    /// Takes the next strip of padded rows.
    fn receive(&mut self, rows: Vec<f32>) {
        let n = rows.len() / (self.width + 2);
        self.strips.push_back((self.rows_in, rows));
        self.rows_in += n;
    }

    /// Drops the strips that hold only rows above `y`.
    fn forget_before(&mut self, y: usize) {
        while self.strips.get(1).is_some_and(|(next, _)| *next <= y) {
            let (_, rows) = self.strips.pop_front().expect("a strip before the next");
            // The decoding thread may have finished; then the strip is simply dropped.
            let _ = self.spent.send(rows);
        }
    }

    /// Filters output rows `range` in parallel into `out` (a spent strip or an empty one), which the
    /// kernel overwrites whole.
    fn run(
        &self,
        range: std::ops::Range<usize>,
        colour: Option<&[u8]>,
        out_row_bytes: usize,
        kernel: &RowKernel,
        mut out: Vec<u8>,
    ) -> Result<Vec<u8>> {
        out.resize(range.len() * out_row_bytes, 0);
        let this = self;
        let w = self.width;
        out.par_chunks_mut(out_row_bytes.max(1)).enumerate().with_min_len(4).for_each_init(
            || vec![0.0f32; 3 * w],
            |scratch, (k, o)| {
                let y = range.start + k;
                let window = Window {
                    above: this.row(y as isize - 1),
                    row: this.row(y as isize),
                    below: this.row(y as isize + 1),
                };
                let c = colour.map(|c| &c[k * 3 * w..(k + 1) * 3 * w]);
                kernel(y, window, c, scratch, o);
            },
        );
        Ok(out)
    }
}
