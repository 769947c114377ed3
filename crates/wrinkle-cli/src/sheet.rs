//! Contact sheets: rendered panels in a grid, each under a label in font8x8 letters, as 8-bit sRGB. What
//! `wrinkle filters` and `wrinkle mappings` draw.

use crate::progress::Progress;
use wrinkle::bump::generators::glyph;
use wrinkle::image::color::SrgbEncoder;
use wrinkle::image::Image;
use wrinkle::{Error, Result};

/// One panel: its label and its linear RGB pixels, `width` x `height` as every panel of the sheet.
pub struct Panel {
    pub label: String,
    pub pixels: Vec<[f32; 3]>,
}

/// `--columns`: panels per row, 1 to 64.
pub fn check_columns(columns: usize) -> Result<()> {
    if columns == 0 || columns > 64 {
        return Err(Error::Invalid(format!("--columns must be between 1 and 64, got {columns}")));
    }
    Ok(())
}

/// Progress over a sheet's `panels` for the command `what`, its message naming the panel being rendered.
pub fn progress(what: &str, panels: usize) -> Progress {
    Progress::new(what, panels as u64, "panels", "{pos}/{len} panels  {msg}")
}

/// Height of the label strip above each panel, and the gap between panels.
const LABEL: usize = 20;
const GAP: usize = 4;

/// The panels in a grid of `columns`, each `w` x `h` under its label; RGB bytes, three per pixel.
pub fn compose(panels: &[Panel], w: usize, h: usize, columns: usize) -> Image<u8> {
    let columns = columns.min(panels.len()).max(1);
    let rows = panels.len().div_ceil(columns);
    let (cw, ch) = (w + GAP, h + LABEL + GAP);
    let (sw, sh) = (columns * cw + GAP, rows * ch + GAP);
    let mut sheet = Image::new(sw * 3, sh, 24u8);
    let enc = SrgbEncoder::new();
    for (k, p) in panels.iter().enumerate() {
        let (x0, y0) = (GAP + (k % columns) * cw, GAP + (k / columns) * ch);
        for y in 0..h {
            for x in 0..w {
                let c = p.pixels[y * w + x];
                for (ch, v) in c.iter().enumerate() {
                    sheet.set((x0 + x) * 3 + ch, y0 + LABEL + y, enc.encode(*v));
                }
            }
        }
        draw_text(&mut sheet, x0 + 4, y0 + 2, &p.label, w - 8);
    }
    Image { width: sw, height: sh, pixels: sheet.pixels }
}

/// White letters of font8x8 at twice their size, clipped to `max_width` pixels.
fn draw_text(sheet: &mut Image<u8>, x0: usize, y0: usize, text: &str, max_width: usize) {
    for (k, c) in text.chars().enumerate() {
        let g = glyph(c);
        for (gy, row) in g.iter().enumerate() {
            for gx in 0..8 {
                if (row >> gx) & 1 == 0 {
                    continue;
                }
                for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    let x = k * 16 + gx * 2 + dx;
                    if x < max_width {
                        for ch in 0..3 {
                            sheet.set((x0 + x) * 3 + ch, y0 + gy * 2 + dy, 235);
                        }
                    }
                }
            }
        }
    }
}
