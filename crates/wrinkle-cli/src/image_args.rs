//! Options and helpers shared by the image commands (emboss, normalmap, heightmap): PNG compression,
//! the size limit, resampling filters and the progress bar over rows.

use crate::progress::Progress;
use clap::{Args, ValueEnum};
use std::path::Path;
use std::time::Instant;
use wrinkle::image::resample::Filter;
use wrinkle::image::stream::{write_rows, PngCompression, RowFormat};
use wrinkle::image::strips::StripStats;
use wrinkle::Result;

/// Images with at least this many pixels show a progress bar.
const LONG_IMAGE_PIXELS: usize = 16 << 20;

#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Compression {
    /// Fastest encoding (fdeflate, Up filter): several times quicker, files some tens of percent larger
    Fast,
    /// zlib level 6 with a filter chosen per row
    Default,
    /// zlib's strongest level with a filter chosen per row: the smallest files, slowest
    Best,
}

#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Resample {
    /// Refuse a colour image of another size than the height image
    None,
    Nearest,
    Triangle,
    CatmullRom,
    Lanczos3,
}

impl Resample {
    pub fn filter(self) -> Option<Filter> {
        match self {
            Resample::None => None,
            Resample::Nearest => Some(Filter::Nearest),
            Resample::Triangle => Some(Filter::Triangle),
            Resample::CatmullRom => Some(Filter::CatmullRom),
            Resample::Lanczos3 => Some(Filter::Lanczos3),
        }
    }
}

/// The options every streaming image command has.
#[derive(Args, Debug)]
pub struct StreamArgs {
    /// PNG encoding effort: fast is several times quicker than best, for files some tens of percent larger
    #[arg(long, value_enum, default_value_t = Compression::Fast)]
    pub compression: Compression,
    /// Worker threads (default: all cores)
    #[arg(long)]
    pub threads: Option<usize>,
    /// Print the time of the whole command and of the arithmetic alone
    #[arg(long)]
    pub stats: bool,
}

impl StreamArgs {
    /// Checks the options and sets up the worker pool.
    pub fn prepare(&self) -> Result<PngCompression> {
        crate::set_threads(self.threads)?;
        Ok(match self.compression {
            Compression::Fast => PngCompression::Fast,
            Compression::Default => PngCompression::Default,
            Compression::Best => PngCompression::Best,
        })
    }
}

/// A bar over the rows of a large image (hidden for small ones and when stderr is not a terminal).
pub fn row_bar(what: &str, width: usize, height: usize) -> Progress {
    if width * height < LONG_IMAGE_PIXELS {
        return Progress::hidden();
    }
    Progress::new(what, height as u64, "rows", "{pos}/{len} rows")
}

/// Writes `output` from the rows that `filter` streams into its sink (reporting rows done), with a bar over
/// the rows; with `--stats`, prints the whole command's time since `start` as `what`.
#[allow(clippy::too_many_arguments)]
pub fn write_filtered(
    what: &str,
    stream: &StreamArgs,
    compression: PngCompression,
    output: &Path,
    (w, h): (usize, usize),
    rows: RowFormat,
    start: Instant,
    filter: impl FnOnce(&mut dyn FnMut(&[u8]) -> Result<()>, &dyn Fn(usize)) -> Result<StripStats>,
) -> Result<()> {
    let bar = row_bar(what, w, h);
    let mut kernel_time = Default::default();
    write_rows(output, w, h, rows, compression, |sink| {
        kernel_time = filter(sink, &|done| bar.set_position(done as u64))?.kernel;
        Ok(())
    })?;
    bar.finish();
    if stream.stats {
        print_stats(what, w, h, start.elapsed(), kernel_time);
    }
    Ok(())
}

/// Prints the `--stats` line: whole-command time and the arithmetic's throughput.
fn print_stats(what: &str, width: usize, height: usize, total: std::time::Duration, kernel: std::time::Duration) {
    let mpix = (width * height) as f64 / 1e6;
    eprintln!(
        "{what}: {width}x{height}, total {:.1} ms ({:.0} Mpixel/s), arithmetic {:.1} ms ({:.0} Mpixel/s), threads={}",
        total.as_secs_f64() * 1e3,
        mpix / total.as_secs_f64(),
        kernel.as_secs_f64() * 1e3,
        mpix / kernel.as_secs_f64().max(1e-9),
        rayon::current_num_threads()
    );
}
