//! The setup's count of a mesh's kept triangles, eight at a time on lanes: the decisions of
//! `TriangleSetup::keep` (area, facing, box on the screen, a tiny triangle's samples) in 32-bit integers.
//! They are exact where a triangle spans at most `EXTENT` on each axis and lies within `REACH` of the
//! screen's corner; the lanes leave every other triangle (and those that need clipping) to `keep`. A
//! million-triangle mesh's count, one triangle at a time, took an eighth of its frame.

use super::setup::{Cull, TESTED_IN_SETUP};
use super::SUBPIXEL_BITS;
use crate::lanes::{gather_i32, permute, CmpEq, CmpGt, CmpLt, I8};

/// The most a triangle decided on lanes spans on each axis, in 1/SUBPIXEL pixel (64 pixels): its edge
/// functions' slopes are within it, and their products with a sample's distance from a corner fit 32 bits.
const EXTENT: i32 = 1 << 14;

/// The farthest from the screen's corner a corner of a triangle decided on lanes lies, in 1/SUBPIXEL
/// pixel: its box's arithmetic fits 32 bits. The clip planes' outside mark (`i32::MIN`) lies beyond it.
const REACH: i32 = 1 << 24;

/// The farthest a pixel's samples lie from its corner (the samples' span, their offsets) for the lanes to
/// be used: a sample's distance from a corner then stays within 2^15.
const SAMPLE_SPAN: i64 = 1 << 12;

/// Where every lane's box may reach on the screen, which triangles the setup drops by their facing, and
/// the samples it tests in tiny triangles.
pub(super) struct LaneCull {
    /// Each axis's least and greatest sample offset from a pixel's corner (`SampleSpan::axes`).
    lo: [I8; 2],
    hi: [I8; 2],
    /// The last pixel column and row.
    last: [I8; 2],
    /// The offsets every pixel shares, where the setup tests a tiny triangle's samples (at most
    /// `TESTED_IN_SETUP` of them; else none).
    offsets: Vec<[I8; 2]>,
    /// Drop the triangles of positive area (Some(true)), of negative area (Some(false)), or none.
    drop_positive: Option<bool>,
}

/// The pixels a box of at most `TESTED_IN_SETUP` pixels may hold, from its first: 4 x 1, 1 x 4 and 2 x 2
/// boxes and all smaller.
const TESTED_PIXELS: [[i32; 2]; 8] = [[0, 0], [1, 0], [2, 0], [3, 0], [0, 1], [1, 1], [0, 2], [0, 3]];

impl LaneCull {
    /// The lanes' decisions for a screen of `size` pixels, samples spanning `axes` from a pixel's corner
    /// (least and greatest on each axis) with `shared` offsets where every pixel has the same; none where
    /// the samples span too far for 32 bits.
    pub(super) fn new(axes: [[i64; 2]; 2], shared: Option<&[[i64; 2]]>, size: [i64; 2], cull: Cull) -> Option<Self> {
        let near = |v: i64| v.abs() < SAMPLE_SPAN;
        let shared = shared.filter(|o| o.len() as i64 <= TESTED_IN_SETUP).unwrap_or(&[]);
        if !axes.iter().flatten().chain(shared.iter().flatten()).all(|&v| near(v)) {
            return None;
        }
        let lanes = |v: i64| I8::splat(v as i32);
        Some(LaneCull {
            lo: axes.map(|a| lanes(a[0])),
            hi: axes.map(|a| lanes(a[1])),
            last: size.map(|s| lanes(s.clamp(1, REACH as i64) - 1)),
            offsets: shared.iter().map(|o| o.map(lanes)).collect(),
            drop_positive: match cull {
                Cull::Nothing => None,
                // Counter-clockwise in (u,v) is a negative area on the screen (`keep`).
                Cull::FacingAway { mirrored } => Some(!mirrored),
            },
        })
    }

    /// The screen points (x and y of each corner) of triangles `triangles` (eight, as vertex indices into
    /// `screen`, a point's x and y one after the other).
    #[inline(always)]
    pub(super) fn corners(screen: &[i32], triangles: &[[u32; 3]]) -> ([I8; 3], [I8; 3]) {
        // The 24 indices are three vectors' worth; corner c of triangle l is index 3 l + c, lane (3 l + c) % 8
        // of vector (3 l + c) / 8: moved by a shuffle, not gathered.
        let indices = triangles.as_flattened();
        let words: [I8; 3] = std::array::from_fn(|k| I8::new(std::array::from_fn(|l| indices[8 * k + l] as i32)));
        let vertex = |c: usize| {
            let lane = I8::new(std::array::from_fn(|l| ((3 * l + c) % 8) as i32));
            let word = |k: usize| I8::new(std::array::from_fn(|l| -i32::from((3 * l + c) / 8 == k)));
            let [a, b, d] = words.map(|w| permute(w, lane));
            let v = word(0).blend(a, word(1).blend(b, d));
            (gather_i32(screen, v + v), gather_i32(screen, v + v + I8::splat(1)))
        };
        let [(x0, y0), (x1, y1), (x2, y2)] = [vertex(0), vertex(1), vertex(2)];
        ([x0, x1, x2], [y0, y1, y2])
    }

    /// Which of eight triangles (their corners' screen points) the setup keeps, and which the lanes leave
    /// to it (beyond their range, or outside a clip plane): bit l for lane l. A bit is in one mask at most.
    #[inline(always)]
    pub(super) fn keep8(&self, x: [I8; 3], y: [I8; 3]) -> (u32, u32) {
        let least = [x[0].min(x[1]).min(x[2]), y[0].min(y[1]).min(y[2])];
        let most = [x[0].max(x[1]).max(x[2]), y[0].max(y[1]).max(y[2])];
        let (reach, extent) = (I8::splat(REACH), I8::splat(EXTENT));
        let unsure = (0..2).fold(I8::splat(0), |u, d| {
            u | least[d].cmp_lt(-reach) | most[d].cmp_gt(reach) | (most[d] - least[d]).cmp_gt(extent)
        });
        let area = (x[1] - x[0]) * (y[2] - y[0]) - (y[1] - y[0]) * (x[2] - x[0]);
        let positive = area.cmp_gt(I8::splat(0));
        let mut dropped = area.cmp_eq(I8::splat(0));
        match self.drop_positive {
            Some(true) => dropped |= positive,
            Some(false) => dropped |= !positive,
            None => {}
        }
        // The pixels one of whose samples may lie within the extent (`keep`'s span): the floor of a
        // division by SUBPIXEL is an arithmetic shift.
        let first = |d: usize| (I8::splat(0) - ((self.hi[d] - least[d]) >> SUBPIXEL_BITS as i32)).max(I8::splat(0));
        let last = |d: usize| ((most[d] - self.lo[d]) >> SUBPIXEL_BITS as i32).min(self.last[d]);
        let (min, max) = ([first(0), first(1)], [last(0), last(1)]);
        dropped |= min[0].cmp_gt(max[0]) | min[1].cmp_gt(max[1]);
        if !self.offsets.is_empty() && (!(dropped | unsure)).move_mask() != 0 {
            dropped |= self.misses_every_sample(x, y, positive, min, max);
        }
        let keep = !(dropped | unsure);
        (keep.move_mask() as u32, unsure.move_mask() as u32)
    }

    /// The lanes whose triangle's box holds at most `TESTED_IN_SETUP` samples none of which it covers
    /// (`keep`'s test of a tiny triangle, with its vertices ordered to a positive area and the fill rule).
    #[inline(always)]
    fn misses_every_sample(&self, x: [I8; 3], y: [I8; 3], positive: I8, min: [I8; 2], max: [I8; 2]) -> I8 {
        let zero = I8::splat(0);
        // Vertices 1 and 2 swapped where the area is negative, as `keep` orders them.
        let (x1, y1) = (positive.blend(x[1], x[2]), positive.blend(y[1], y[2]));
        let (x2, y2) = (positive.blend(x[2], x[1]), positive.blend(y[2], y[1]));
        let corners = [(x[0], y[0]), (x1, y1), (x2, y2)];
        // E = A (sx - xa) + B (sy - ya) + bias from the edge's first corner a: `edge_functions` less its
        // constant part, which keeps every term within 32 bits.
        let edges = [(1, 2), (2, 0), (0, 1)].map(|(a, b)| {
            let ((xa, ya), (xb, yb)) = (corners[a], corners[b]);
            let (slope_x, slope_y) = (ya - yb, xb - xa);
            let owns = slope_x.cmp_gt(zero) | (slope_x.cmp_eq(zero) & slope_y.cmp_gt(zero));
            (slope_x, slope_y, xa, ya, !owns)
        });
        let (width, height) = (max[0] - min[0] + I8::splat(1), max[1] - min[1] + I8::splat(1));
        let tested =
            (width * height * I8::splat(self.offsets.len() as i32)).cmp_lt(I8::splat(TESTED_IN_SETUP as i32 + 1));
        let in_box = TESTED_PIXELS.map(|[dx, dy]| width.cmp_gt(I8::splat(dx)) & height.cmp_gt(I8::splat(dy)));
        let pixel = |v: I8| v << SUBPIXEL_BITS as i32;
        // The sign bit set where a sample of the box is covered: all three edge values there are >= 0.
        let mut covered = zero;
        for offset in &self.offsets {
            let (sx, sy) = (pixel(min[0]) + offset[0], pixel(min[1]) + offset[1]);
            // Each edge at the box's first sample, then a pixel's step at a time to the others of
            // `TESTED_PIXELS`, in its order.
            let values = edges.map(|(a, b, xa, ya, bias)| {
                let first = a * (sx - xa) + b * (sy - ya) + bias;
                let (step_x, step_y) = (pixel(a), pixel(b));
                let (right, down) = (first + step_x, first + step_y);
                let (right2, down2) = (right + step_x, down + step_y);
                [first, right, right2, right2 + step_x, down, down + step_x, down2, down2 + step_y]
            });
            for (c, &in_box) in in_box.iter().enumerate() {
                covered |= in_box & !(values[0][c] | values[1][c] | values[2][c]);
            }
        }
        tested & covered.cmp_gt(I8::splat(-1))
    }
}
