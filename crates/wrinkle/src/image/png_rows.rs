//! The rows of a plain PNG (not interlaced, 8 or 16 bits a sample, grey or RGB with or without alpha, no
//! palette or transparency key), decoded on two threads: one reads the file and inflates its image data,
//! the reader's thread undoes the row filters. The `png` crate does both on one thread, which was the
//! longest thread of the emboss command on a 4096^2 grey PNG (BENCHMARKS.md, "Emboss and normal maps").

use std::fs::File;
use std::io::{BufReader, Read};
use std::path::{Path, PathBuf};
use std::sync::mpsc::{channel, sync_channel, Receiver, Sender, SyncSender};
use std::thread::JoinHandle;

use super::io::{open_input, open_message};
use crate::error::{Error, Result};

/// Bytes of output the inflater keeps behind its position: deflate refers back at most 32 KiB.
const WINDOW: usize = 32 << 10;
/// Bytes of inflated data handed over at a time.
const BATCH: usize = 256 << 10;
/// Rows unfiltered together (see `paeth_wavefront`).
const GROUP: usize = 4;

/// A PNG's rows top to bottom, their filters undone: `row_bytes` bytes each, samples as the file stores them.
pub(super) struct PngRows {
    row_bytes: usize,
    /// Bytes per pixel, the distance of a filter's left neighbour.
    bpp: usize,
    rows_left: usize,
    inflated: Inflated,
    /// The filter type of each row of the group.
    kinds: [u8; GROUP],
    /// The row above the group, then the group's rows, unfiltered.
    rows: Vec<u8>,
    /// Rows in the group, and the next to hand out (counting the row above as 0).
    in_group: usize,
    next: usize,
}

/// The inflating thread's batches, and where spent ones go back to it.
type Batches = (Receiver<Result<Vec<u8>>>, Sender<Vec<u8>>);

/// The inflated image data as it comes from the inflating thread, which starts at the first read and is
/// joined when this is dropped.
struct Inflated {
    path: PathBuf,
    batches: Option<Batches>,
    thread: Option<JoinHandle<()>>,
    batch: Vec<u8>,
    at: usize,
    /// Bytes still to come.
    left: usize,
}

impl PngRows {
    /// The rows of the PNG at `path`, whose header says `width` x `height` pixels of `bpp` bytes each.
    pub(super) fn new(path: &Path, width: usize, height: usize, bpp: usize) -> PngRows {
        let row_bytes = width * bpp;
        let inflated = Inflated {
            path: path.to_path_buf(),
            batches: None,
            thread: None,
            batch: Vec::new(),
            at: 0,
            left: height * (row_bytes + 1),
        };
        PngRows {
            row_bytes,
            bpp,
            rows_left: height,
            inflated,
            kinds: [0; GROUP],
            rows: vec![0; (GROUP + 1) * row_bytes],
            in_group: 0,
            next: 1,
        }
    }

    /// The next row.
    pub(super) fn next_row(&mut self) -> Result<&[u8]> {
        if self.next > self.in_group {
            self.read_group()?;
        }
        let (r, rb) = (self.next, self.row_bytes);
        self.next += 1;
        Ok(&self.rows[r * rb..(r + 1) * rb])
    }

    /// Reads and unfilters the next group of rows; the last row of the one before becomes the row above.
    fn read_group(&mut self) -> Result<()> {
        let rb = self.row_bytes;
        if self.rows_left == 0 {
            return Err(Error::read(&self.inflated.path, "truncated or corrupt PNG: fewer rows than its header says"));
        }
        self.rows.copy_within(self.in_group * rb..(self.in_group + 1) * rb, 0);
        let n = self.rows_left.min(GROUP);
        for r in 1..=n {
            let mut kind = [0u8];
            self.inflated.read(&mut kind)?;
            self.kinds[r - 1] = kind[0];
            self.inflated.read(&mut self.rows[r * rb..(r + 1) * rb])?;
        }
        unfilter_group(&self.kinds[..n], self.bpp, rb, &mut self.rows[..(n + 1) * rb]).map_err(|kind| {
            Error::read(
                &self.inflated.path,
                format!("corrupt PNG: a row has filter type {kind}, which PNG does not define"),
            )
        })?;
        (self.in_group, self.next) = (n, 1);
        self.rows_left -= n;
        Ok(())
    }
}

impl Inflated {
    /// Fills `out` with the next inflated bytes.
    fn read(&mut self, out: &mut [u8]) -> Result<()> {
        let fewer = || Error::read(&self.path, "truncated or corrupt PNG: fewer rows than its header says");
        if out.len() > self.left {
            return Err(fewer());
        }
        if self.batches.is_none() {
            let (tx, rx) = sync_channel(4);
            // Spent batches go back to be filled again, rather than each a fresh allocation.
            let (spent_tx, spent_rx) = channel();
            let (path, expected) = (self.path.clone(), self.left);
            let thread = std::thread::Builder::new()
                .name("png-inflate".into())
                .spawn(move || {
                    if let Err(e) = inflate(&path, expected, &tx, &spent_rx) {
                        // The reader may be gone already; then nobody needs the error.
                        let _ = tx.send(Err(e));
                    }
                })
                .map_err(|e| Error::read(&self.path, format!("cannot start a thread to inflate it: {e}")))?;
            (self.batches, self.thread) = (Some((rx, spent_tx)), Some(thread));
        }
        let (batches, spent) = self.batches.as_ref().expect("the inflating thread was started");
        let mut have = 0;
        while have < out.len() {
            if self.at == self.batch.len() {
                let next = batches.recv().map_err(|_| fewer())??;
                // The inflater may have finished; then the batch is simply dropped.
                let _ = spent.send(std::mem::replace(&mut self.batch, next));
                self.at = 0;
            }
            let n = (out.len() - have).min(self.batch.len() - self.at);
            out[have..have + n].copy_from_slice(&self.batch[self.at..self.at + n]);
            have += n;
            self.at += n;
        }
        self.left -= out.len();
        Ok(())
    }
}

impl Drop for Inflated {
    /// Stops the inflating thread (its next batch finds no reader) and waits for it: a reader dropped early
    /// leaves no thread behind reading a file it no longer wants.
    fn drop(&mut self) {
        self.batches = None;
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

/// Reads the PNG's chunks and sends its image data inflated, `BATCH` bytes at a time, until `expected` bytes.
/// Chunks are read in pieces of a fixed size, so that a corrupt length cannot ask for gigabytes.
fn inflate(path: &Path, expected: usize, tx: &SyncSender<Result<Vec<u8>>>, spent: &Receiver<Vec<u8>>) -> Result<()> {
    let corrupt = |what: &str| Error::read(path, format!("truncated or corrupt PNG: {what}"));
    let mut file = BufReader::with_capacity(1 << 16, open_input(path)?);
    let read = |file: &mut BufReader<File>, buf: &mut [u8]| -> Result<()> {
        file.read_exact(buf).map_err(|e| match e.kind() {
            std::io::ErrorKind::UnexpectedEof => corrupt("the file ends inside its image data"),
            _ => Error::read(path, open_message(&e)),
        })
    };
    read(&mut file, &mut [0; 8])?;
    let mut inflater = fdeflate::Decompressor::new();
    let mut out = Output { bytes: vec![0u8; WINDOW + BATCH], pos: 0, sent: 0, total: 0 };
    let mut piece = vec![0u8; 1 << 16];
    while !inflater.is_done() {
        let mut header = [0u8; 8];
        read(&mut file, &mut header)?;
        let len = u32::from_be_bytes([header[0], header[1], header[2], header[3]]) as usize;
        if len > i32::MAX as usize {
            return Err(corrupt("a chunk is longer than PNG allows"));
        }
        let kind = [header[4], header[5], header[6], header[7]];
        if &kind == b"IEND" {
            return Err(corrupt("the image data ends early"));
        }
        let mut hasher = crc32fast::Hasher::new();
        hasher.update(&kind);
        let mut left = len;
        while left > 0 {
            let n = left.min(piece.len());
            read(&mut file, &mut piece[..n])?;
            left -= n;
            if &kind != b"IDAT" {
                continue;
            }
            hasher.update(&piece[..n]);
            let mut input = &piece[..n];
            while !inflater.is_done() {
                let room = out.bytes.len() - out.pos;
                let (used, made) = inflater
                    .read(input, &mut out.bytes, out.pos, false)
                    .map_err(|e| corrupt(&format!("the image data does not inflate ({e:?})")))?;
                if used == 0 && made == 0 && !input.is_empty() {
                    return Err(corrupt("the image data does not inflate"));
                }
                input = &input[used..];
                if !out.made(made, expected, tx, spent).map_err(|()| corrupt("more image data than its header says"))? {
                    return Ok(());
                }
                // A full buffer may have held output back: it comes out on the next call, input or not.
                if input.is_empty() && made < room {
                    break;
                }
            }
        }
        let mut crc = [0u8; 4];
        read(&mut file, &mut crc)?;
        if &kind == b"IDAT" && hasher.finalize() != u32::from_be_bytes(crc) {
            return Err(corrupt("an image data chunk fails its CRC check"));
        }
    }
    // A short stream is reported by the reader, which counts its rows.
    let _ = tx.send(Ok(out.bytes[out.sent..out.pos].to_vec()));
    Ok(())
}

/// The inflater's output buffer: the last `WINDOW` bytes sent (what later bytes may refer back to), then the
/// bytes not yet sent up to `pos`; `total` bytes made in all.
struct Output {
    bytes: Vec<u8>,
    pos: usize,
    sent: usize,
    total: usize,
}

impl Output {
    /// Counts `made` more bytes and, when the buffer is full, sends them and keeps the window. Fails when
    /// the bytes exceed `expected`; returns false when the reader is gone.
    fn made(
        &mut self,
        made: usize,
        expected: usize,
        tx: &SyncSender<Result<Vec<u8>>>,
        spent: &Receiver<Vec<u8>>,
    ) -> std::result::Result<bool, ()> {
        self.pos += made;
        self.total += made;
        if self.total > expected {
            return Err(());
        }
        if self.pos == self.bytes.len() {
            let mut batch = spent.try_recv().unwrap_or_default();
            batch.clear();
            batch.extend_from_slice(&self.bytes[self.sent..self.pos]);
            if tx.send(Ok(batch)).is_err() {
                return Ok(false);
            }
            self.bytes.copy_within(self.pos - WINDOW..self.pos, 0);
            (self.pos, self.sent) = (WINDOW, WINDOW);
        }
        Ok(true)
    }
}

/// Undoes filter `kind` (None, Sub, Up or Average: PNG specification, section 9) on `row`, given the
/// unfiltered row above; returns the kind back when it is not one of them.
fn unfilter(kind: u8, bpp: usize, above: &[u8], row: &mut [u8]) -> std::result::Result<(), u8> {
    match (kind, bpp) {
        (0, _) => {}
        (1, _) => {
            for i in bpp..row.len() {
                row[i] = row[i].wrapping_add(row[i - bpp]);
            }
        }
        (2, _) => {
            for (x, &b) in row.iter_mut().zip(above) {
                *x = x.wrapping_add(b);
            }
        }
        (3, _) => {
            for i in 0..row.len() {
                let a = if i >= bpp { u16::from(row[i - bpp]) } else { 0 };
                row[i] = row[i].wrapping_add(((a + u16::from(above[i])) / 2) as u8);
            }
        }
        (kind, _) => return Err(kind),
    }
    Ok(())
}

/// Undoes the filters of the rows of `rows` after its first, the row above them; `kinds` are their filter
/// types. A whole group of Paeth rows goes through the wavefront.
fn unfilter_group(kinds: &[u8], bpp: usize, row_bytes: usize, rows: &mut [u8]) -> std::result::Result<(), u8> {
    if kinds == [4; GROUP] && bpp <= 4 {
        paeth_rows::<GROUP>(bpp, rows, row_bytes);
        return Ok(());
    }
    for (r, &kind) in kinds.iter().enumerate() {
        let pair = &mut rows[r * row_bytes..(r + 2) * row_bytes];
        if kind == 4 {
            paeth_rows::<1>(bpp, pair, row_bytes);
        } else {
            let (above, row) = pair.split_at_mut(row_bytes);
            unfilter(kind, bpp, above, row)?;
        }
    }
    Ok(())
}

/// The Paeth filter undone on the `ROWS` rows after the first of `rows`, pixels of `bpp` bytes.
fn paeth_rows<const ROWS: usize>(bpp: usize, rows: &mut [u8], row_bytes: usize) {
    match bpp {
        1 => paeth_wavefront::<1, ROWS>(rows, row_bytes),
        2 => paeth_wavefront::<2, ROWS>(rows, row_bytes),
        3 => paeth_wavefront::<3, ROWS>(rows, row_bytes),
        4 => paeth_wavefront::<4, ROWS>(rows, row_bytes),
        6 => paeth_wavefront::<6, ROWS>(rows, row_bytes),
        8 => paeth_wavefront::<8, ROWS>(rows, row_bytes),
        _ => unreachable!("PNG pixels are 1, 2, 3, 4, 6 or 8 bytes"),
    }
}

/// The Paeth filter undone on `ROWS` rows at once (after the row above them, the first of `rows`), each
/// row one pixel behind the row above it. Each byte depends on its left neighbour, a chain of about six
/// cycles a byte that a single row cannot hide; in the wavefront the rows' chains are independent, and a
/// row's upper neighbours are the values the row above held a step earlier, still in registers. The left,
/// upper and upper-left neighbours are carried in registers per channel.
fn paeth_wavefront<const BPP: usize, const ROWS: usize>(rows: &mut [u8], row_bytes: usize) {
    let (above, group) = rows.split_at_mut(row_bytes);
    let mut rows: [&mut [u8]; ROWS] = {
        let mut chunks = group.chunks_exact_mut(row_bytes);
        std::array::from_fn(|_| chunks.next().expect("a group has its rows"))
    };
    let pixels = row_bytes / BPP;
    let mut left = [[0i16; BPP]; ROWS];
    let mut corner = [[0i16; BPP]; ROWS];
    // Row r takes pixel j of step j + r; later rows first, so that a row reads its upper neighbour before
    // the row above moves on.
    let mut step = |rows: &mut [&mut [u8]; ROWS], r: usize, j: usize| {
        for k in 0..BPP {
            let up = if r == 0 { i16::from(above[j * BPP + k]) } else { left[r - 1][k] };
            let x = &mut rows[r][j * BPP + k];
            *x = x.wrapping_add(predict(left[r][k], up, corner[r][k]));
            left[r][k] = i16::from(*x);
            corner[r][k] = up;
        }
    };
    for i in 0..pixels + ROWS - 1 {
        if i >= ROWS - 1 && i < pixels {
            for r in (0..ROWS).rev() {
                step(&mut rows, r, i - r);
            }
        } else {
            for r in (0..ROWS).rev() {
                if let Some(j) = i.checked_sub(r).filter(|&j| j < pixels) {
                    step(&mut rows, r, j);
                }
            }
        }
    }
}

/// Paeth's predictor: of a (left), b (up) and c (upper left), the one nearest a + b - c, ties to a then b.
/// This form (Sean Barrett's) needs no absolute values: c against thresholds made from a and b.
#[inline(always)]
fn predict(a: i16, b: i16, c: i16) -> u8 {
    let threshold = 3 * c - (a + b);
    let (lo, hi) = (a.min(b), a.max(b));
    let t0 = if hi <= threshold { lo } else { c };
    (if threshold <= lo { hi } else { t0 }) as u8
}

#[cfg(test)]
mod tests {
    use super::super::scratch::Scratch;
    use super::*;

    /// A PNG of `pixels` (samples as PNG stores them) written by the png crate with `filter` on every row.
    fn encode(
        path: &Path,
        (w, h): (usize, usize),
        color: png::ColorType,
        sixteen: bool,
        filter: png::Filter,
        pixels: &[u8],
    ) {
        let file = std::io::BufWriter::new(File::create(path).unwrap());
        let mut encoder = png::Encoder::new(file, w as u32, h as u32);
        encoder.set_color(color);
        encoder.set_depth(if sixteen { png::BitDepth::Sixteen } else { png::BitDepth::Eight });
        encoder.set_filter(filter);
        // Small chunks, so that rows and the inflater's batches straddle IDAT chunks.
        let mut writer = encoder.write_header().unwrap();
        let mut stream = writer.stream_writer_with_size(7).unwrap();
        std::io::Write::write_all(&mut stream, pixels).unwrap();
        stream.finish().unwrap();
    }

    /// Every row of the PNG at `path` through `PngRows`.
    fn decode(path: &Path, (w, h): (usize, usize), bpp: usize) -> Result<Vec<u8>> {
        let mut rows = PngRows::new(path, w, h, bpp);
        let mut all = Vec::new();
        for _ in 0..h {
            all.extend_from_slice(rows.next_row()?);
        }
        Ok(all)
    }

    #[test]
    fn rows_match_the_png_crate_for_every_filter_layout_and_size() {
        let dir = Scratch::new("png-rows-filters");
        let path = dir.path("x.png");
        use png::ColorType as C;
        let layouts = [
            (C::Grayscale, false),
            (C::Grayscale, true),
            (C::GrayscaleAlpha, false),
            (C::Rgb, false),
            (C::Rgb, true),
            (C::Rgba, false),
            (C::Rgba, true),
        ];
        let filters = [
            png::Filter::NoFilter,
            png::Filter::Sub,
            png::Filter::Up,
            png::Filter::Avg,
            png::Filter::Paeth,
            png::Filter::Adaptive,
        ];
        let mut seed = 0x2545_f491_u32;
        for (color, sixteen) in layouts {
            let bpp = color.samples() * if sixteen { 2 } else { 1 };
            for (w, h) in [(1, 1), (2, 3), (5, 4), (37, 9), (64, 13)] {
                // Smooth values with noise, so that Paeth picks each of its three neighbours.
                let pixels: Vec<u8> = (0..w * h * bpp)
                    .map(|i| {
                        seed ^= seed << 13;
                        seed ^= seed >> 17;
                        seed ^= seed << 5;
                        ((i / bpp % w) as u32 * 3 + (i / bpp / w) as u32 * 5 + seed % 23) as u8
                    })
                    .collect();
                for filter in filters {
                    encode(&path, (w, h), color, sixteen, filter, &pixels);
                    assert_eq!(
                        decode(&path, (w, h), bpp).unwrap(),
                        pixels,
                        "{color:?} sixteen={sixteen} {w}x{h} {filter:?}"
                    );
                }
            }
        }
    }

    /// A grey PNG of `pixels` with `filter` on every row, written and read back whole.
    fn assert_grey_round_trip(name: &str, (w, h): (usize, usize), filter: png::Filter, pixels: &[u8]) {
        let dir = Scratch::new(name);
        let path = dir.path("x.png");
        encode(&path, (w, h), png::ColorType::Grayscale, false, filter, pixels);
        assert_eq!(decode(&path, (w, h), 1).unwrap(), pixels);
    }

    #[test]
    fn a_large_paeth_image_crosses_batches_intact() {
        let (w, h) = (1031, 600);
        let pixels: Vec<u8> = (0..w * h).map(|i| ((i % w) ^ (i / w * 7) ^ ((i * 2_654_435_761) >> 27)) as u8).collect();
        assert_grey_round_trip("png-rows-large", (w, h), png::Filter::Paeth, &pixels);
    }

    #[test]
    fn long_runs_that_fill_the_inflaters_buffer_come_out_whole() {
        // Rows of one value compress to long back-references, which stop mid-copy when the buffer fills.
        let (w, h) = (1500, 1000);
        let pixels: Vec<u8> = (0..w * h).map(|i| (i / w / 97) as u8).collect();
        assert_grey_round_trip("png-rows-runs", (w, h), png::Filter::NoFilter, &pixels);
    }

    #[test]
    fn damaged_files_are_refused_with_what_is_wrong() {
        let dir = Scratch::new("png-rows-damaged");
        let path = dir.path("x.png");
        let (w, h) = (40, 30);
        let pixels: Vec<u8> = (0..w * h).map(|i| (i * 7 % 251) as u8).collect();
        encode(&path, (w, h), png::ColorType::Grayscale, false, png::Filter::Paeth, &pixels);
        let good = std::fs::read(&path).unwrap();
        let idat = good.windows(4).position(|k| k == b"IDAT").unwrap();
        let damaged = |name: &str, bytes: &[u8]| {
            let p = dir.path(name);
            std::fs::write(&p, bytes).unwrap();
            decode(&p, (w, h), 1).unwrap_err().to_string()
        };
        let err = damaged("short.png", &good[..good.len() / 2]);
        assert!(err.contains("short.png") && err.contains("truncated or corrupt PNG"), "{err}");
        // A length of nearly 2 GiB is read in pieces, not allocated, and ends with the file.
        let mut long = good.clone();
        long[idat - 4..idat].copy_from_slice(&0x7fff_0000u32.to_be_bytes());
        let err = damaged("long.png", &long);
        assert!(err.contains("the file ends inside its image data"), "{err}");
        let mut bad_crc = good.clone();
        bad_crc[idat + 6] ^= 0x40;
        let err = damaged("crc.png", &bad_crc);
        assert!(err.contains("fails its CRC check"), "{err}");
        // One row too many for the header: the image data is longer than it says.
        let err = decode(&path, (w, h - 1), 1).unwrap_err().to_string();
        assert!(err.contains("more image data than its header says"), "{err}");
        let err = decode(&path, (w, h + 1), 1).unwrap_err().to_string();
        assert!(err.contains("the image data ends early") || err.contains("fewer rows"), "{err}");
    }

    /// The predictor as PNG's specification writes it.
    fn predict_by_the_book(a: u8, b: u8, c: u8) -> u8 {
        let p = i16::from(a) + i16::from(b) - i16::from(c);
        let (pa, pb, pc) = ((p - i16::from(a)).abs(), (p - i16::from(b)).abs(), (p - i16::from(c)).abs());
        if pa <= pb && pa <= pc {
            a
        } else if pb <= pc {
            b
        } else {
            c
        }
    }

    #[test]
    fn the_predictor_is_the_specifications_for_every_triple() {
        for a in 0..=255u8 {
            for b in 0..=255u8 {
                for c in 0..=255u8 {
                    assert_eq!(predict(a.into(), b.into(), c.into()), predict_by_the_book(a, b, c), "{a} {b} {c}");
                }
            }
        }
    }
}
