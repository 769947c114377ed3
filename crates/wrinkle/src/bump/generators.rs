//! Bump-function tables made by program, after section 3 of Blinn (1978): a grid of high and low
//! values (fig. 5), embossed bitmap letters (fig. 6), the Z-buffer of a sphere replicated into rivets
//! (fig. 7) and a unit cell of bricks (fig. 8, hand drawn in the paper).
//!
//! Heights lie in [0, 1], 0 low (black) and 1 high (white). Every table is one period of a periodic
//! function: column 0 follows column W-1 and row 0 follows row H-1, so the renderer can replicate it.
//! Texel (i, j) has its centre at ((i + 0.5) / W, (j + 0.5) / H) in texture space; u runs left to
//! right, v bottom to top, and image row 0 is the top (v near 1).

use std::fmt::Display;

use font8x8::{UnicodeFonts, BASIC_FONTS};

use crate::image::{GreyImage, Image};
use crate::{Error, Result};

/// The largest width or height of a generated table, in texels.
const MAX_SIZE: usize = 32768;

/// Parameters of [`grid`], the gridwork of fig. 5.
#[derive(Clone, Debug, PartialEq)]
pub struct GridParams {
    /// Grid cells along each side of the table.
    pub cells: usize,
    /// Fraction of a cell covered by each high line, measured where the edge ramp is half way up.
    pub line_width: f32,
    /// Fraction of a cell over which a line's edge ramps smoothly from high to low.
    pub soft: f32,
}

impl Default for GridParams {
    fn default() -> Self {
        GridParams { cells: 8, line_width: 0.25, soft: 0.1 }
    }
}

/// Parameters of [`text`], the embossed letters of fig. 6.
#[derive(Clone, Debug, PartialEq)]
pub struct TextParams {
    /// The letters, drawn from font8x8's basic (ASCII) set; any other character becomes '?'.
    pub text: String,
    /// Blur radius as a fraction of one glyph pixel (a glyph is 8 x 8 of them).
    pub soft: f32,
}

impl Default for TextParams {
    fn default() -> Self {
        TextParams { text: "WRINKLE".into(), soft: 0.25 }
    }
}

/// Parameters of [`rivets`], the Z-buffer pattern of fig. 7.
#[derive(Clone, Debug, PartialEq)]
pub struct RivetParams {
    /// Rivets along each side of the table.
    pub count: usize,
    /// Radius of each rivet as a fraction of its cell.
    pub radius: f32,
}

impl Default for RivetParams {
    fn default() -> Self {
        RivetParams { count: 4, radius: 0.35 }
    }
}

/// Parameters of [`bricks`], the brick unit cell of fig. 8.
#[derive(Clone, Debug, PartialEq)]
pub struct BrickParams {
    /// Courses of bricks in the table (even, so that the running bond tiles).
    pub rows: usize,
    /// Bricks in each course.
    pub bricks_per_row: usize,
    /// Width of a mortar joint as a fraction of a course's height, half on each side of the joint.
    pub mortar: f32,
    /// Width of the linear ramp from mortar up to brick, as a fraction of a course's height.
    pub bevel: f32,
}

impl Default for BrickParams {
    fn default() -> Self {
        BrickParams { rows: 4, bricks_per_row: 2, mortar: 0.06, bevel: 0.05 }
    }
}

/// One of the generators of this module with its parameters (as named in a scene file).
#[derive(Clone, Debug, PartialEq)]
pub enum Generator {
    Grid(GridParams),
    Text(TextParams),
    Rivets(RivetParams),
    Bricks(BrickParams),
}

impl Generator {
    /// The table of this generator at `size` texels (for text, the height; the width is `size` per letter).
    pub fn generate(&self, size: usize) -> Result<GreyImage> {
        let letters = match self {
            Generator::Text(p) => p.text.chars().count().max(1),
            _ => 1,
        };
        let texels = (size as u64).saturating_mul(size as u64).saturating_mul(letters as u64);
        // The grey image, and the bump table with its pyramid (4/3 of 4 bytes a texel) that is made from it.
        if size <= MAX_SIZE {
            // A table is held whole, as an image file is: the same size limits, checked before any work.
            crate::image::io::check_size(size * letters, size)
                .map_err(|m| Error::parameter("size", format!("{size} is too large: the table's {m}")))?;
            crate::limits::reserve(texels.saturating_mul(4 + 16 / 3), || format!("a {size}-texel bump table"))?;
        }
        match self {
            Generator::Grid(p) => grid(size, p),
            Generator::Text(p) => text(size, p),
            Generator::Rivets(p) => rivets(size, p),
            Generator::Bricks(p) => bricks(size, p),
        }
    }
}

/// Fig. 5: a gridwork of high lines on a low floor, `size` x `size` texels, one line centred on
/// every cell boundary, with smoothstep edges `soft` cells wide.
pub fn grid(size: usize, p: &GridParams) -> Result<GreyImage> {
    check("size", size, 1, MAX_SIZE)?;
    check("cells", p.cells, 1, size)?;
    check("line_width", p.line_width, 0.0, 1.0)?;
    check("soft", p.soft, 0.0, 1.0)?;
    let (cells, soft) = (p.cells as f64, p.soft as f64);
    let outer = (p.line_width as f64 + soft) / 2.0;
    let line = |t: f64| smoothstep(ramp(outer - (t - t.round()).abs(), soft));
    Ok(Image::from_fn(size, size, |x, y| {
        let (u, v) = texel_uv(x, y, size, size);
        line(u * cells).max(line(v * cells)) as f32
    }))
}

/// Fig. 6: the letters of `p.text` raised (1) on a low floor (0) in one row, each in a square cell
/// `size` texels high; glyph pixels are scaled by nearest neighbour, then softened by a periodic
/// tent blur of radius `soft` glyph pixels.
pub fn text(size: usize, p: &TextParams) -> Result<GreyImage> {
    check("size", size, 1, MAX_SIZE)?;
    if p.text.is_empty() {
        return Err(Error::parameter("text", "must not be empty"));
    }
    check("soft", p.soft, 0.0, 1.0)?;
    let glyphs: Vec<[u8; 8]> = p.text.chars().map(glyph).collect();
    let width = size.saturating_mul(glyphs.len());
    if width > MAX_SIZE {
        return Err(Error::parameter(
            "text",
            format!("of {} characters at size {size} is {width} texels wide, more than {MAX_SIZE}", glyphs.len()),
        ));
    }
    // Nearest neighbour: texel k of a cell samples glyph pixel floor((k + 0.5) * 8 / size).
    let glyph_pixel = |k: usize| (8 * (k % size) + 4) / size;
    let bitmap = Image::from_fn(width, size, |x, y| {
        // Row 0 of a font8x8 glyph is its top; bit k of a row is column k from the left.
        let row = glyphs[x / size][glyph_pixel(y)];
        f32::from((row >> glyph_pixel(x)) & 1)
    });
    Ok(periodic_blur(&bitmap, p.soft as f64 * size as f64 / 8.0))
}

/// Fig. 7: the Z-buffer of a sphere replicated into rivets. One cell of `size / count` texels is
/// rendered by casting an orthographic ray through each texel centre at a hemisphere of radius
/// `radius` cells (depth sqrt(r^2 - d^2) / r, 0 where the ray misses), and that cell is repeated
/// `count` x `count` times.
pub fn rivets(size: usize, p: &RivetParams) -> Result<GreyImage> {
    check("size", size, 1, MAX_SIZE)?;
    check("count", p.count, 1, size)?;
    if !size.is_multiple_of(p.count) {
        return Err(Error::parameter(
            "count",
            format!(
                "must divide the size so that every rivet cell is a whole number of texels, got {} for size {size}",
                p.count
            ),
        ));
    }
    check("radius", p.radius, 0.0, 0.5)?;
    let (cell, r) = (size / p.count, p.radius as f64);
    let depth = Image::from_fn(cell, cell, |x, y| {
        let (u, v) = texel_uv(x, y, cell, cell);
        let d = (u - 0.5).hypot(v - 0.5);
        if d < r {
            (1.0 - (d / r).powi(2)).sqrt() as f32
        } else {
            0.0
        }
    });
    Ok(replicate(&depth, p.count, p.count))
}

/// Fig. 8: a running-bond brick unit cell, `size` x `size` texels. Each course is offset by half a
/// brick from the one below; bricks are 1 with a linear bevel down to the mortar, which is 0.
pub fn bricks(size: usize, p: &BrickParams) -> Result<GreyImage> {
    check("size", size, 1, MAX_SIZE)?;
    check("rows", p.rows, 2, size)?;
    if !p.rows.is_multiple_of(2) {
        return Err(Error::parameter("rows", format!("must be even so that the running bond tiles, got {}", p.rows)));
    }
    check("bricks_per_row", p.bricks_per_row, 1, size)?;
    check("mortar", p.mortar, 0.0, 1.0)?;
    check("bevel", p.bevel, 0.0, 1.0)?;
    // Lengths below are in course heights.
    let rows = p.rows as f64;
    let brick = rows / p.bricks_per_row as f64;
    let (half_joint, bevel) = (p.mortar as f64 / 2.0, p.bevel as f64);
    Ok(Image::from_fn(size, size, |x, y| {
        let (u, v) = texel_uv(x, y, size, size);
        let course = (v * rows).floor();
        let shift = if course.rem_euclid(2.0) == 1.0 { brick / 2.0 } else { 0.0 };
        let across = v * rows - course;
        let along = (u * rows + shift).rem_euclid(brick);
        let to_joint = across.min(1.0 - across).min(along).min(brick - along);
        ramp(to_joint - half_joint, bevel) as f32
    }))
}

/// Texture coordinates (u, v) of the centre of texel (x, y) of a `width` x `height` table whose
/// row 0 is the top.
fn texel_uv(x: usize, y: usize, width: usize, height: usize) -> (f64, f64) {
    ((x as f64 + 0.5) / width as f64, 1.0 - (y as f64 + 0.5) / height as f64)
}

/// 0 for `x <= 0`, rising linearly to 1 at `x = width` (a step at 0 when `width` is 0).
fn ramp(x: f64, width: f64) -> f64 {
    if width > 0.0 {
        (x / width).clamp(0.0, 1.0)
    } else {
        f64::from(u8::from(x > 0.0))
    }
}

/// The cubic 3t^2 - 2t^3 on [0, 1]: a ramp whose ends have zero slope.
fn smoothstep(t: f64) -> f64 {
    t * t * (3.0 - 2.0 * t)
}

/// The glyph of `c` in font8x8's basic set, '?' for characters outside it.
pub fn glyph(c: char) -> [u8; 8] {
    BASIC_FONTS.get(if c.is_ascii() { c } else { '?' }).unwrap_or_default()
}

/// `cell` repeated `across` times left to right and `down` times top to bottom.
fn replicate(cell: &GreyImage, across: usize, down: usize) -> GreyImage {
    Image::from_fn(cell.width * across, cell.height * down, |x, y| cell.get(x % cell.width, y % cell.height))
}

/// Separable tent blur that wraps around the edges: tap k has weight max(0, radius + 1 - |k|),
/// so radius 0 leaves the image unchanged. Prefix sums make each texel cost the same whatever the radius.
fn periodic_blur(img: &GreyImage, radius: f64) -> GreyImage {
    let (width, height) = (img.width, img.height);
    let mut out = img.clone();
    let mut line = Vec::new();
    for y in 0..height {
        line.clear();
        line.extend((0..width).map(|x| out.get(x, y) as f64));
        for (x, v) in periodic_tent(&line, radius).into_iter().enumerate() {
            out.set(x, y, v as f32);
        }
    }
    for x in 0..width {
        line.clear();
        line.extend((0..height).map(|y| out.get(x, y) as f64));
        for (y, v) in periodic_tent(&line, radius).into_iter().enumerate() {
            out.set(x, y, v as f32);
        }
    }
    out
}

/// One periodic line through the tent: sum over |k| <= r of (radius + 1 - |k|) x[i+k], normalised, as
/// (radius + 1) * (box sum) - (sum of |k| x[i+k]), both from prefix sums of x and of t x over the line
/// extended by r on each side.
fn periodic_tent(x: &[f64], radius: f64) -> Vec<f64> {
    let n = x.len();
    let r = radius.ceil() as usize;
    let total: f64 = (radius + 1.0) * (2 * r + 1) as f64 - (r * (r + 1)) as f64;
    // Extended line e[t] = x[(t - r) mod n] for t in 0 .. n + 2r, with prefix sums p0 (of e) and p1 (of t e).
    let (mut p0, mut p1) = (vec![0.0; n + 2 * r + 1], vec![0.0; n + 2 * r + 1]);
    for t in 0..n + 2 * r {
        let e = x[wrap(t, -(r as isize), n)];
        p0[t + 1] = p0[t] + e;
        p1[t + 1] = p1[t] + t as f64 * e;
    }
    (0..n)
        .map(|i| {
            let c = i + r; // i's place in the extended line
            let (lo, hi) = (c - r, c + r + 1);
            let boxed = p0[hi] - p0[lo];
            // sum of |t - c| e[t] over [lo, hi): right half minus c times its sum, and the mirror on the left.
            let right = (p1[hi] - p1[c + 1]) - c as f64 * (p0[hi] - p0[c + 1]);
            let left = c as f64 * (p0[c] - p0[lo]) - (p1[c] - p1[lo]);
            ((radius + 1.0) * boxed - right - left) / total
        })
        .collect()
}

/// Index `i + k` taken modulo `n`.
fn wrap(i: usize, k: isize, n: usize) -> usize {
    (i as isize + k).rem_euclid(n as isize) as usize
}

/// `Error::Parameter` naming `name` unless `lo <= value <= hi` (NaN is never in range).
fn check<T: PartialOrd + Display>(name: &'static str, value: T, lo: T, hi: T) -> Result<()> {
    if lo <= value && value <= hi {
        Ok(())
    } else {
        Err(Error::parameter(name, format!("must be between {lo} and {hi}, got {value}")))
    }
}

#[cfg(test)]
mod tests {

    /// The prefix-sum tent equals the direct weighted sum, for fractional radii and radii beyond the line.
    #[test]
    fn periodic_tent_matches_the_direct_sum() {
        let x: Vec<f64> = (0..23).map(|i| ((i * 37 % 11) as f64).sin()).collect();
        for radius in [0.0, 0.4, 1.0, 2.5, 7.0, 30.0] {
            let got = periodic_tent(&x, radius);
            let reach = radius.ceil() as isize;
            for (i, g) in got.iter().enumerate() {
                let (mut sum, mut total) = (0.0, 0.0);
                for k in -reach..=reach {
                    let w = radius + 1.0 - k.abs() as f64;
                    sum += w * x[wrap(i, k, x.len())];
                    total += w;
                }
                assert!((g - sum / total).abs() < 1e-9, "radius {radius} at {i}: {g} vs {}", sum / total);
            }
        }
    }

    use super::*;

    /// Over every row and column, how much the step across the wrap-around seam (last texel to
    /// first) exceeds the largest step between neighbours inside that row or column: positive
    /// means the seam shows.
    fn seam_excess(img: &GreyImage) -> f32 {
        let excess = |line: Vec<f32>| {
            let interior = line.windows(2).map(|p| (p[1] - p[0]).abs()).fold(0.0, f32::max);
            (line[line.len() - 1] - line[0]).abs() - interior
        };
        let rows = (0..img.height).map(|y| excess(img.row(y).to_vec()));
        let cols = (0..img.width).map(|x| excess((0..img.height).map(|y| img.get(x, y)).collect()));
        rows.chain(cols).fold(f32::NEG_INFINITY, f32::max)
    }

    /// A periodic table may put its steepest step on the seam when its period is not a whole
    /// number of texels, so allow a little; a broken seam jumps by far more.
    fn assert_tiles(img: &GreyImage) {
        let excess = seam_excess(img);
        assert!(excess <= 0.01, "seam step exceeds the interior steps by {excess}");
    }

    fn assert_in_unit_range(img: &GreyImage) {
        assert!(img.pixels.iter().all(|v| (0.0..=1.0).contains(v)));
    }

    fn invalid_message(r: Result<GreyImage>) -> String {
        match r {
            Err(e @ Error::Parameter { .. }) => e.to_string(),
            other => panic!("expected Error::Parameter, got {other:?}"),
        }
    }

    #[test]
    fn seam_check_catches_a_gradient() {
        let ramp = Image::from_fn(32, 32, |x, _| x as f32 / 31.0);
        assert!(seam_excess(&ramp) > 0.9);
    }

    #[test]
    fn every_generator_tiles_and_stays_in_range() {
        let tables = [
            grid(200, &GridParams::default()).unwrap(),
            grid(97, &GridParams { cells: 5, line_width: 0.3, soft: 0.4 }).unwrap(),
            text(48, &TextParams { text: "#W".into(), soft: 1.0 }).unwrap(),
            rivets(240, &RivetParams { count: 3, radius: 0.5 }).unwrap(),
            bricks(256, &BrickParams::default()).unwrap(),
            bricks(300, &BrickParams { rows: 6, bricks_per_row: 3, mortar: 0.1, bevel: 0.15 }).unwrap(),
        ];
        for t in &tables {
            assert_tiles(t);
            assert_in_unit_range(t);
        }
    }

    #[test]
    fn grid_high_fraction_matches_line_width() {
        // Cells and lines a whole number of texels wide, so that the count is exact up to rounding.
        for (size, w) in [(256, 0.25f32), (320, 0.1), (512, 0.5)] {
            let img = grid(size, &GridParams { cells: 8, line_width: w, soft: 0.1 }).unwrap();
            let high = img.pixels.iter().filter(|&&v| v > 0.5).count() as f32 / img.pixels.len() as f32;
            let expected = 1.0 - (1.0 - w) * (1.0 - w);
            assert!((high - expected).abs() < 1e-4, "w {w}: high fraction {high}, expected {expected}");
        }
    }

    #[test]
    fn grid_repeats_every_cell_and_has_soft_edges() {
        let img = grid(256, &GridParams::default()).unwrap();
        for y in 0..256 {
            for x in 0..256 {
                assert_eq!(img.get(x, y), img.get((x + 32) % 256, y));
                assert_eq!(img.get(x, y), img.get(x, (y + 32) % 256));
            }
        }
        // Lines are centred on cell boundaries: texel 0 is on a line, texel 16 (mid cell) is not.
        assert_eq!(img.get(0, 16), 1.0);
        assert_eq!(img.get(16, 16), 0.0);
        assert!(img.pixels.iter().any(|&v| v > 0.1 && v < 0.9));
        let hard = grid(256, &GridParams { soft: 0.0, ..GridParams::default() }).unwrap();
        assert!(hard.pixels.iter().all(|&v| v == 0.0 || v == 1.0));
    }

    #[test]
    fn rivet_depths_are_the_analytic_hemisphere() {
        // Cells of 15 texels: texel 7 of a cell sits exactly on the cell centre.
        let (cell, r) = (15usize, 0.35f64);
        let img = rivets(45, &RivetParams { count: 3, radius: r as f32 }).unwrap();
        let hemisphere = |dx: f64, dy: f64| {
            let d = dx.hypot(dy) / cell as f64;
            if d < r {
                (1.0 - (d / r) * (d / r)).sqrt()
            } else {
                0.0
            }
        };
        for (cx, cy) in [(0, 0), (1, 2), (2, 1)] {
            let (ox, oy) = (cx * cell + 7, cy * cell + 7);
            assert_eq!(img.get(ox, oy), 1.0);
            for (dx, dy) in [(3, 0), (0, -4), (2, 3), (5, 0), (4, 4), (7, 7), (6, 0)] {
                let got = img.get((ox as i64 + dx) as usize, (oy as i64 + dy) as usize) as f64;
                let want = hemisphere(dx as f64, dy as f64);
                assert!((got - want).abs() < 1e-6, "offset ({dx},{dy}): {got} vs {want}");
            }
        }
        // 3 texels from the centre is 0.2 cell: sqrt(1 - (0.2 / 0.35)^2).
        assert!((img.get(10, 7) as f64 - (1.0f64 - (0.2f64 / 0.35).powi(2)).sqrt()).abs() < 1e-6);
        // (7, 7) texels off is 0.66 cell, outside the rivet.
        assert_eq!(img.get(0, 0), 0.0);
    }

    #[test]
    fn text_h_has_font8x8_strokes_the_right_way_up() {
        // font8x8's 'H', top row first, leftmost column first.
        const H: [&str; 8] =
            ["##..##..", "##..##..", "##..##..", "######..", "##..##..", "##..##..", "##..##..", "........"];
        for size in [8, 12, 16, 40] {
            let img = text(size, &TextParams { text: "H".into(), soft: 0.0 }).unwrap();
            assert_eq!((img.width, img.height), (size, size));
            // Each texel shows the glyph pixel under its centre.
            let glyph_pixel = |k: usize| ((k as f64 + 0.5) * 8.0 / size as f64) as usize;
            for y in 0..size {
                for x in 0..size {
                    let want = if H[glyph_pixel(y)].as_bytes()[glyph_pixel(x)] == b'#' { 1.0 } else { 0.0 };
                    assert_eq!(img.get(x, y), want, "size {size}, texel ({x}, {y})");
                }
            }
        }
    }

    #[test]
    fn text_cells_sit_side_by_side_and_unknown_chars_are_question_marks() {
        let one = |s: &str| text(24, &TextParams { text: s.into(), soft: 0.0 }).unwrap();
        let pair = one("HI");
        assert_eq!((pair.width, pair.height), (48, 24));
        let (h, i) = (one("H"), one("I"));
        for y in 0..24 {
            assert_eq!(&pair.row(y)[..24], h.row(y));
            assert_eq!(&pair.row(y)[24..], i.row(y));
        }
        assert_eq!(one("é"), one("?"));
        assert_ne!(one("?"), one("H"));
    }

    #[test]
    fn text_blur_keeps_the_mean_and_softens_edges() {
        let p = |soft| TextParams { text: "Hi!".into(), soft };
        let (hard, soft) = (text(64, &p(0.0)).unwrap(), text(64, &p(0.5)).unwrap());
        let mean = |img: &GreyImage| img.pixels.iter().map(|&v| v as f64).sum::<f64>() / img.pixels.len() as f64;
        assert!((mean(&hard) - mean(&soft)).abs() < 1e-5);
        assert!(soft.pixels.iter().filter(|&&v| v > 0.05 && v < 0.95).count() > 500);
        assert_in_unit_range(&soft);
    }

    #[test]
    fn blur_wraps_around_both_edges() {
        let mut dot = Image::new(9, 7, 0.0f32);
        dot.set(0, 0, 1.0);
        let b = periodic_blur(&dot, 2.0);
        assert!(b.get(8, 0) > 0.0 && (b.get(8, 0) - b.get(1, 0)).abs() < 1e-7);
        assert!(b.get(0, 6) > 0.0 && (b.get(0, 6) - b.get(0, 1)).abs() < 1e-7);
        assert!((b.get(8, 6) - b.get(1, 1)).abs() < 1e-7);
        assert!((b.pixels.iter().sum::<f32>() - 1.0).abs() < 1e-6);
        assert_eq!(periodic_blur(&dot, 0.0), dot);
    }

    #[test]
    fn brick_courses_are_offset_by_half_a_brick() {
        // 4 courses of 16 texels, bricks 32 texels long, joints 4 texels wide, bevels 2 texels.
        let p = BrickParams { rows: 4, bricks_per_row: 2, mortar: 0.25, bevel: 0.125 };
        let img = bricks(64, &p).unwrap();
        // The bottom course (image rows 48..64) has its vertical joints at u = 0 and 1/2,
        // the course above it (rows 32..48) at u = 1/4 and 3/4.
        for (y, joints, solid) in [(56, [0, 31, 32, 63], [15, 16, 47, 48]), (40, [15, 16, 47, 48], [0, 31, 32, 63])] {
            for x in joints {
                assert_eq!(img.get(x, y), 0.0, "joint at ({x}, {y})");
            }
            for x in solid {
                assert_eq!(img.get(x, y), 1.0, "brick at ({x}, {y})");
            }
        }
        // Horizontal joints between courses, and the bevel: texel centres 2.5 and 3.5 texels above
        // the joint line are 0.5 and 1.5 texels up a bevel 2 texels wide.
        assert!((0..64).all(|x| img.get(x, 47) == 0.0 && img.get(x, 48) == 0.0));
        assert!((img.get(8, 45) - 0.25).abs() < 1e-6);
        assert!((img.get(8, 44) - 0.75).abs() < 1e-6);
        assert_eq!(img.get(8, 40), 1.0);
        // Faces: 8 of every 16 texels up a course and 24 of every 32 along a brick; mortar: all but
        // 12 of 16 and 28 of 32.
        let count = |h: f32| img.pixels.iter().filter(|&&v| v == h).count();
        assert_eq!(count(1.0), 64 * 64 * 8 * 24 / (16 * 32));
        assert_eq!(count(0.0), 64 * 64 - 64 * 64 * 12 * 28 / (16 * 32));
    }

    #[test]
    fn generate_dispatches_to_each_generator() {
        assert_eq!(
            Generator::Grid(GridParams::default()).generate(64).unwrap(),
            grid(64, &GridParams::default()).unwrap()
        );
        assert_eq!(
            Generator::Text(TextParams::default()).generate(16).unwrap(),
            text(16, &TextParams::default()).unwrap()
        );
        assert_eq!(
            Generator::Rivets(RivetParams::default()).generate(64).unwrap(),
            rivets(64, &RivetParams::default()).unwrap()
        );
        assert_eq!(
            Generator::Bricks(BrickParams::default()).generate(64).unwrap(),
            bricks(64, &BrickParams::default()).unwrap()
        );
    }

    #[test]
    fn invalid_parameters_are_rejected_with_their_names() {
        let (g, b) = (GridParams::default, BrickParams::default);
        let cases = [
            (grid(0, &g()), "size must be between 1 and 32768, got 0"),
            (grid(32769, &g()), "size must be between 1 and 32768, got 32769"),
            (grid(64, &GridParams { cells: 0, ..g() }), "cells must be between 1 and 64, got 0"),
            (grid(64, &GridParams { line_width: -0.1, ..g() }), "line_width must be between 0 and 1, got -0.1"),
            (grid(64, &GridParams { soft: f32::NAN, ..g() }), "soft must be between 0 and 1, got NaN"),
            (text(64, &TextParams { text: String::new(), soft: 0.1 }), "text must not be empty"),
            (text(64, &TextParams { text: "A".into(), soft: f32::INFINITY }), "soft must be between 0 and 1, got inf"),
            (
                text(8192, &TextParams { text: "HELLO".into(), soft: 0.1 }),
                "text of 5 characters at size 8192 is 40960 texels wide, more than 32768",
            ),
            (rivets(64, &RivetParams { count: 0, radius: 0.3 }), "count must be between 1 and 64, got 0"),
            (
                rivets(64, &RivetParams { count: 3, radius: 0.3 }),
                "count must divide the size so that every rivet cell is a whole number of texels, got 3 for size 64",
            ),
            (rivets(64, &RivetParams { count: 4, radius: 0.6 }), "radius must be between 0 and 0.5, got 0.6"),
            (bricks(64, &BrickParams { rows: 3, ..b() }), "rows must be even so that the running bond tiles, got 3"),
            (bricks(64, &BrickParams { bricks_per_row: 0, ..b() }), "bricks_per_row must be between 1 and 64, got 0"),
            (bricks(64, &BrickParams { mortar: -0.5, ..b() }), "mortar must be between 0 and 1, got -0.5"),
            (bricks(64, &BrickParams { bevel: f32::NEG_INFINITY, ..b() }), "bevel must be between 0 and 1, got -inf"),
        ];
        for (result, message) in cases {
            assert_eq!(invalid_message(result), message);
        }
    }
}
