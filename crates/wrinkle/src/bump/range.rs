//! Where a periodic table is constant: the least and largest entry over blocks of it, a pyramid of
//! blocks from 8 texels wide up to the whole table, so that a displacement's dicer can tell in a few reads
//! that F does not change over a piece of the surface (a brick's face) and leave it uncut.

/// The first level's blocks are this many texels wide: finer ones would cost more memory than they save
/// cuts (a piece of surface spans tens of texels).
const BLOCK: usize = 8;

/// One level: the least and largest entry over each block, row-major, rows counted as the table's.
struct Level {
    /// Texels per block side.
    block: usize,
    columns: usize,
    rows: usize,
    least: Vec<f32>,
    largest: Vec<f32>,
}

/// The ranges of a `width` x `height` periodic table over ever larger blocks.
pub struct Ranges {
    width: usize,
    height: usize,
    levels: Vec<Level>,
}

impl Ranges {
    /// The pyramid of `texels` (`width` x `height`, row-major).
    pub fn of(width: usize, height: usize, texels: &[f32]) -> Ranges {
        let (columns, rows) = (width.div_ceil(BLOCK), height.div_ceil(BLOCK));
        let mut first = Level {
            block: BLOCK,
            columns,
            rows,
            least: vec![f32::INFINITY; columns * rows],
            largest: vec![f32::NEG_INFINITY; columns * rows],
        };
        for (y, row) in texels.chunks_exact(width).enumerate() {
            for (x, &v) in row.iter().enumerate() {
                let b = (y / BLOCK) * columns + x / BLOCK;
                first.least[b] = first.least[b].min(v);
                first.largest[b] = first.largest[b].max(v);
            }
        }
        let mut levels = vec![first];
        while let Some(below) = levels.last().filter(|l| l.columns > 1 || l.rows > 1) {
            let (columns, rows) = (below.columns.div_ceil(2), below.rows.div_ceil(2));
            let mut level = Level {
                block: below.block * 2,
                columns,
                rows,
                least: vec![f32::INFINITY; columns * rows],
                largest: vec![f32::NEG_INFINITY; columns * rows],
            };
            for y in 0..below.rows {
                for x in 0..below.columns {
                    let (from, to) = (y * below.columns + x, (y / 2) * columns + x / 2);
                    level.least[to] = level.least[to].min(below.least[from]);
                    level.largest[to] = level.largest[to].max(below.largest[from]);
                }
            }
            levels.push(level);
        }
        Ranges { width, height, levels }
    }

    /// Whether every entry in columns `x.0..=x.1` and rows `y.0..=y.1` is the same; the ranges may run
    /// past the table's sides (it repeats) but span at least one texel each.
    pub fn is_constant(&self, x: (i64, i64), y: (i64, i64)) -> bool {
        let span = (x.1 - x.0 + 1).max(y.1 - y.0 + 1).max(1) as usize;
        // The finest level whose blocks are at least half the span: at most three blocks along each side
        // of each piece the wrap cuts the ranges into.
        let level = self.levels.iter().find(|l| 2 * l.block >= span).unwrap_or(&self.levels[self.levels.len() - 1]);
        let (mut least, mut largest) = (f32::INFINITY, f32::NEG_INFINITY);
        let (xs, ys) = (pieces(x, self.width), pieces(y, self.height));
        for &(x0, x1) in xs.iter().flatten() {
            for &(y0, y1) in ys.iter().flatten() {
                for by in y0 / level.block..=y1 / level.block {
                    for bx in x0 / level.block..=x1 / level.block {
                        let b = by * level.columns + bx;
                        least = least.min(level.least[b]);
                        largest = largest.max(level.largest[b]);
                    }
                }
            }
        }
        least == largest
    }
}

/// The inclusive range `r` of a table `n` long that repeats, as at most two ranges within it (the whole
/// of it where `r` covers it all).
fn pieces(r: (i64, i64), n: usize) -> [Option<(usize, usize)>; 2] {
    let n = n as i64;
    if r.1 - r.0 + 1 >= n {
        return [Some((0, n as usize - 1)), None];
    }
    let (a, b) = (r.0.rem_euclid(n), r.1.rem_euclid(n));
    match a <= b {
        true => [Some((a as usize, b as usize)), None],
        false => [Some((a as usize, n as usize - 1)), Some((0, b as usize))],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Against every texel of the ranges, for ranges of all sizes and places, wrapping included, on a table
    /// whose size is not a multiple of the blocks.
    #[test]
    fn constancy_matches_a_scan_of_the_texels() {
        let (w, h) = (53usize, 37usize);
        // Constant but for a few spots.
        let mut texels = vec![0.5f32; w * h];
        for &(x, y) in &[(3usize, 4usize), (30, 20), (52, 36), (17, 0)] {
            texels[y * w + x] = 0.75;
        }
        let ranges = Ranges::of(w, h, &texels);
        let at = |x: i64, y: i64| texels[(y.rem_euclid(h as i64) * w as i64 + x.rem_euclid(w as i64)) as usize];
        let mut seen = [0; 2];
        for x0 in (-60i64..60).step_by(7) {
            for y0 in (-40i64..40).step_by(5) {
                for (dx, dy) in [(0, 0), (1, 1), (4, 2), (9, 13), (30, 3), (60, 60)] {
                    let (x, y) = ((x0, x0 + dx), (y0, y0 + dy));
                    let scan = (y.0..=y.1).all(|yy| (x.0..=x.1).all(|xx| at(xx, yy) == at(x.0, y.0)));
                    let got = ranges.is_constant(x, y);
                    // Blocks cover more than the ranges: constant ranges may be missed, never made up.
                    assert!(!got || scan, "{x:?} {y:?}: constant by the blocks, not by the texels");
                    seen[usize::from(got)] += 1;
                }
            }
        }
        assert!(seen[0] > 100 && seen[1] > 100, "{seen:?}");
        assert!(Ranges::of(w, h, &vec![0.25; w * h]).is_constant((-100, 100), (5, 6)));
    }
}
