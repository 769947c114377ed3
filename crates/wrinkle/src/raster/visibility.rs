//! The visibility buffer of one screen tile: for each sample, the depth key and the triangle of the nearest
//! surface. Tiles are independent, so they render in parallel; triangles are binned to the tiles their
//! bounding boxes touch.

use super::exact::Outline;
use super::samples::{SamplePattern, TileOffsets};
use super::setup::{covers_sample, ScreenTriangle};
use super::SUBPIXEL;
use crate::lanes::prefetch;
use glam::Vec2;
use rayon::prelude::*;

/// No triangle covers this sample.
pub const EMPTY: u32 = u32::MAX;

/// For each tile, the indices of the triangles whose bounding box touches it, in submission order: all the
/// tiles' lists in one vector, tile by tile.
pub struct Bins {
    pub tile_size: usize,
    pub tiles_x: usize,
    pub tiles_y: usize,
    /// Tile t's triangles are `indices[starts[t]..starts[t + 1]]`.
    starts: Vec<usize>,
    indices: Vec<u32>,
}

/// Some triangles' entries in the bins, made apart from the others' (by one parallel job) and joined after:
/// (tile, triangle) in submission order. A part holds its entries alone, not a count per tile: a
/// million-triangle mesh's setup makes a hundred parts, and a large frame has millions of tiles.
pub struct BinPart {
    shift: u32,
    tiles_x: usize,
    entries: Vec<(u32, u32)>,
}

impl BinPart {
    /// An empty part for tiles of `tile_size` (a power of two) on a screen `width` pixels wide.
    pub fn new(width: usize, tile_size: usize) -> BinPart {
        assert!(tile_size.is_power_of_two(), "tiles are a power of two on a side");
        // A shift, not a division: a million small triangles are four million of them.
        BinPart { shift: tile_size.trailing_zeros(), tiles_x: width.div_ceil(tile_size), entries: Vec::new() }
    }

    /// Bins triangle `triangle`, whose box in pixels (inclusive, on the screen) is `bbox`.
    #[inline]
    pub fn add(&mut self, bbox: [i32; 4], triangle: u32) {
        let [x0, y0, x1, y1] = bbox.map(|c| c as usize >> self.shift);
        for ty in y0..y1 + 1 {
            for tx in x0..x1 + 1 {
                self.entries.push(((ty * self.tiles_x + tx) as u32, triangle));
            }
        }
    }
}

impl Bins {
    #[cfg(test)]
    pub fn new(triangles: &[ScreenTriangle], width: usize, height: usize, tile_size: usize) -> Bins {
        Bins::of(triangles, width, height, tile_size, |_| true)
    }

    /// The bins of the triangles that `keep` keeps (their indices still into all of `triangles`). Large
    /// sets are binned in parallel chunks, joined in submission order.
    pub fn of(
        triangles: &[ScreenTriangle],
        width: usize,
        height: usize,
        tile_size: usize,
        keep: impl Fn(&ScreenTriangle) -> bool + Sync,
    ) -> Bins {
        const CHUNK: usize = 1 << 16;
        let parts: Vec<BinPart> = triangles
            .par_chunks(CHUNK)
            .enumerate()
            .map(|(c, chunk)| {
                let mut part = BinPart::new(width, tile_size);
                for (i, t) in chunk.iter().enumerate().filter(|(_, t)| keep(t)) {
                    part.add(t.bbox, (c * CHUNK + i) as u32);
                }
                part
            })
            .collect();
        Bins::join(width, height, tile_size, &parts)
    }

    /// The bins of the triangles of `parts`, each part's after the ones before it.
    pub fn join(width: usize, height: usize, tile_size: usize, parts: &[BinPart]) -> Bins {
        let (tiles_x, tiles_y) = (width.div_ceil(tile_size), height.div_ceil(tile_size));
        let tiles = tiles_x * tiles_y;
        // Counted, then placed: each tile's entries after the tiles' before it.
        let mut starts = vec![0usize; tiles + 1];
        for part in parts {
            for &(tile, _) in &part.entries {
                starts[tile as usize + 1] += 1;
            }
        }
        for t in 0..tiles {
            starts[t + 1] += starts[t];
        }
        let mut next = starts[..tiles].to_vec();
        let mut indices = vec![0u32; starts[tiles]];
        for part in parts {
            for &(tile, triangle) in &part.entries {
                let at = &mut next[tile as usize];
                indices[*at] = triangle;
                *at += 1;
            }
        }
        Bins { tile_size, tiles_x, tiles_y, starts, indices }
    }

    /// The triangles binned to tile (tx, ty).
    #[inline]
    pub fn bin(&self, (tx, ty): (usize, usize)) -> &[u32] {
        let t = ty * self.tiles_x + tx;
        &self.indices[self.starts[t]..self.starts[t + 1]]
    }
}

/// The samples of one tile, `(y * tile_width + x) * spp + s`.
pub struct VisBuffer {
    /// Tile origin and size in pixels.
    pub x0: usize,
    pub y0: usize,
    pub width: usize,
    pub height: usize,
    pub spp: usize,
    pub depth: Vec<f32>,
    pub triangle: Vec<u32>,
    /// Whether a triangle along a curved surface's outline reaches the tile (its samples then get the
    /// exact test), and per sample the (u,v) where the test found the sample's ray meets the surface.
    pub outline: bool,
    pub exact_uv: Vec<[f32; 2]>,
    /// The alpha test's depth peeling: per sample, the fragment (depth key, triangle) it refused, and
    /// whether the sample is open to the fragments behind it. Sized on first use.
    refused: Vec<(f32, u32)>,
    reopened: Vec<bool>,
    /// The triangles near the samples being peeled one by one.
    nearby: Vec<u32>,
    /// Where the tile's samples lie in their pixels.
    samples: TileOffsets,
}

impl VisBuffer {
    pub fn new(tile_size: usize, spp: usize) -> VisBuffer {
        let n = tile_size * tile_size * spp;
        VisBuffer {
            x0: 0,
            y0: 0,
            width: 0,
            height: 0,
            spp,
            depth: vec![f32::NEG_INFINITY; n],
            triangle: vec![EMPTY; n],
            outline: false,
            exact_uv: vec![[0.0; 2]; n],
            refused: Vec::new(),
            reopened: Vec::new(),
            nearby: Vec::new(),
            samples: TileOffsets::default(),
        }
    }

    /// Rasterizes every triangle binned to tile (tx, ty): depth and triangle per sample.
    pub fn render_tile(
        &mut self,
        bins: &Bins,
        tile: (usize, usize),
        screen: (usize, usize),
        triangles: &[ScreenTriangle],
        pattern: &SamplePattern,
    ) {
        self.begin_tile(bins.tile_size, tile, screen, pattern);
        self.outline = false;
        // Small triangles are a few samples of work each: their records come from memory, asked for ahead.
        const AHEAD: usize = 8;
        let bin = bins.bin(tile);
        for (i, &t) in bin.iter().enumerate() {
            if let Some(&next) = bin.get(i + AHEAD) {
                prefetch(triangles, next as usize);
            }
            let tri = &triangles[t as usize];
            self.outline |= tri.outline != Outline::Inside;
            self.rasterize(tri, t);
        }
    }

    /// Places the buffer on tile (tx, ty) of a `screen` (width, height), places its samples and clears it.
    fn begin_tile(&mut self, tile_size: usize, tile: (usize, usize), screen: (usize, usize), pattern: &SamplePattern) {
        self.x0 = tile.0 * tile_size;
        self.y0 = tile.1 * tile_size;
        self.width = tile_size.min(screen.0 - self.x0);
        self.height = tile_size.min(screen.1 - self.y0);
        self.samples.fill(pattern, (self.x0, self.y0, self.width, self.height));
        let n = self.width * self.height * self.spp;
        self.depth[..n].fill(f32::NEG_INFINITY);
        self.triangle[..n].fill(EMPTY);
    }

    /// Depth-tests triangle `id` into the buffer at every sample it covers.
    fn rasterize(&mut self, tri: &ScreenTriangle, id: u32) {
        let (x0, y0, width, spp) = (self.x0, self.y0, self.width, self.spp);
        let (depth, triangle) = (&mut self.depth, &mut self.triangle);
        cover(tri, &self.samples, (x0, y0, width, self.height), |x, y, s, dx, dy| {
            let d = tri.depth.at(dx, dy);
            let k = ((y - y0) * width + x - x0) * spp + s;
            // Ties go to the lower triangle index, so the result does not depend on binning order.
            if nearer((d, id), (depth[k], triangle[k])) {
                depth[k] = d;
                triangle[k] = id;
            }
        });
    }

    /// Takes the triangles at samples `refused` out of those samples (the alpha test found them
    /// transparent there, or their ray misses the exact surface) and finds in the tile's triangles the
    /// nearest fragment behind the refused one at each: one layer of depth peeling. Fragments are ordered
    /// by depth key, then triangle index (the order of `rasterize`), so each pass moves strictly back and
    /// peeling ends. A few samples (an outline's) are tested triangle by triangle; many (a cut-out leaf's)
    /// by rasterizing the tile's triangles again into those samples alone.
    pub fn peel(&mut self, bins: &Bins, tile: (usize, usize), triangles: &[ScreenTriangle], refused: &[usize]) {
        let bin = bins.bin(tile);
        // One sample against the triangles near its band is a few bounds and edge tests each; rasterizing
        // walks the whole bounding box of every triangle of the tile. Samples one by one won on outlines
        // (tens of refused samples a tile, hundreds of triangles) until about an eighth of the tile.
        if refused.len() * 8 < self.width * self.height * self.spp {
            self.peel_one_by_one(bin, triangles, refused);
        } else {
            self.peel_by_rasterizing(bin, triangles, refused);
        }
    }

    /// `peel` sample by sample, in bands of eight rows: the triangles that reach a band's samples, then each
    /// sample against those.
    fn peel_one_by_one(&mut self, bin: &[u32], triangles: &[ScreenTriangle], refused: &[usize]) {
        let (x0, y0, width, spp) = (self.x0, self.y0, self.width, self.spp);
        let pixel = move |k: usize| {
            let p = k / spp;
            ((x0 + p % width) as i32, (y0 + p / width) as i32)
        };
        let mut nearby = std::mem::take(&mut self.nearby);
        for band in refused.chunk_by(|&a, &b| pixel(a).1 / 8 == pixel(b).1 / 8) {
            let (mut lo, mut hi) = ((i32::MAX, i32::MAX), (i32::MIN, i32::MIN));
            for &k in band {
                let (x, y) = pixel(k);
                (lo, hi) = ((lo.0.min(x), lo.1.min(y)), (hi.0.max(x), hi.1.max(y)));
            }
            nearby.clear();
            nearby.extend(bin.iter().copied().filter(|&t| {
                let b = triangles[t as usize].bbox;
                b[0] <= hi.0 && b[2] >= lo.0 && b[1] <= hi.1 && b[3] >= lo.1
            }));
            for &k in band {
                self.peel_sample(k, &nearby, triangles);
            }
        }
        self.nearby = nearby;
    }

    /// `peel` by rasterizing the tile's triangles `bin` again into the refused samples alone.
    fn peel_by_rasterizing(&mut self, bin: &[u32], triangles: &[ScreenTriangle], refused: &[usize]) {
        let n = self.depth.len();
        self.refused.resize(n, (f32::INFINITY, EMPTY));
        self.reopened.resize(n, false);
        for &k in refused {
            self.refused[k] = (self.depth[k], self.triangle[k]);
            self.reopened[k] = true;
            self.depth[k] = f32::NEG_INFINITY;
            self.triangle[k] = EMPTY;
        }
        let (x0, y0, width, spp) = (self.x0, self.y0, self.width, self.spp);
        let (depth, triangle, bound, open) = (&mut self.depth, &mut self.triangle, &self.refused, &self.reopened);
        for &id in bin {
            let tri = &triangles[id as usize];
            cover(tri, &self.samples, (x0, y0, width, self.height), |x, y, s, dx, dy| {
                let k = ((y - y0) * width + x - x0) * spp + s;
                if !open[k] {
                    return;
                }
                let d = tri.depth.at(dx, dy);
                let (bd, bid) = bound[k];
                if behind((d, id), (bd, bid)) && nearer((d, id), (depth[k], triangle[k])) {
                    depth[k] = d;
                    triangle[k] = id;
                }
            });
        }
        for &k in refused {
            self.reopened[k] = false;
        }
    }

    /// `peel` for one sample: the nearest fragment behind its own among the triangles `bin`.
    fn peel_sample(&mut self, k: usize, bin: &[u32], triangles: &[ScreenTriangle]) {
        let bound = (self.depth[k], self.triangle[k]);
        let mut best = (f32::NEG_INFINITY, EMPTY);
        let (s, pixel) = (k % self.spp, k / self.spp);
        let (x, y) = (self.x0 + pixel % self.width, self.y0 + pixel / self.width);
        let offset = self.samples.at(x, y)[s];
        let (ox, oy) = self.samples.offset(x, y, s);
        for &id in bin {
            let tri = &triangles[id as usize];
            let [bx0, by0, bx1, by1] = tri.bbox.map(|c| c as usize);
            if x < bx0 || x > bx1 || y < by0 || y > by1 {
                continue;
            }
            if !covers_sample(&tri.edges(), (x as i64, y as i64), offset) {
                continue;
            }
            let d = tri.depth.at(x as f32 + (ox - tri.origin.x), y as f32 + (oy - tri.origin.y));
            if behind((d, id), bound) && nearer((d, id), best) {
                best = (d, id);
            }
        }
        (self.depth[k], self.triangle[k]) = best;
    }

    /// The screen position of sample `s` of tile pixel (x, y).
    #[inline]
    pub fn sample_position(&self, x: usize, y: usize, s: usize) -> Vec2 {
        let (x, y) = (self.x0 + x, self.y0 + y);
        let (ox, oy) = self.samples.offset(x, y, s);
        Vec2::new(x as f32 + ox, y as f32 + oy)
    }

    /// The sample offsets of tile pixel (x, y), from its top-left corner (fixed point).
    #[inline]
    pub fn sample_offsets(&self, x: usize, y: usize) -> &[[i64; 2]] {
        self.samples.at(self.x0 + x, self.y0 + y)
    }

    /// The sample offsets that every pixel of the tile shares, where they share them.
    pub fn shared_offsets(&self) -> Option<&[[i64; 2]]> {
        self.samples.shared()
    }

    /// The weight of sample `s` of tile pixel (x, y) under the pattern's filter (+1 or -1).
    #[inline]
    pub fn sample_weight(&self, x: usize, y: usize, s: usize, pattern: &SamplePattern) -> f32 {
        pattern.weight(self.samples.at(self.x0 + x, self.y0 + y)[s])
    }
}

/// Whether fragment (depth key, triangle) `a` lies behind `b`: depth first, then the triangle index.
#[inline]
fn behind(a: (f32, u32), b: (f32, u32)) -> bool {
    a.0 < b.0 || (a.0 == b.0 && a.1 > b.1)
}

/// Whether fragment `a` wins the depth test against `b` (the order of `rasterize`).
#[inline]
fn nearer(a: (f32, u32), b: (f32, u32)) -> bool {
    a.0 > b.0 || (a.0 == b.0 && a.1 < b.1)
}

/// Calls `hit(x, y, s, dx, dy)` for every sample s of pixel (x, y) inside `rect` = (x0, y0, width, height)
/// that the triangle covers under the fill rule; (dx, dy) is the sample's offset from the triangle's origin.
/// `samples` holds the rectangle's sample offsets.
#[inline]
pub fn cover(
    tri: &ScreenTriangle,
    samples: &TileOffsets,
    rect: (usize, usize, usize, usize),
    hit: impl FnMut(usize, usize, usize, f32, f32),
) {
    // Offsets every pixel shares, in a common count, unroll the per-pixel sample loop.
    match samples.shared() {
        Some(o) if o.len() == 1 => cover_same::<1>(tri, o, rect, hit),
        Some(o) if o.len() == 4 => cover_same::<4>(tri, o, rect, hit),
        Some(o) if o.len() == 16 => cover_same::<16>(tri, o, rect, hit),
        _ => cover_each(tri, samples, rect, hit),
    }
}

/// The pixels of `rect` within the triangle's box, as (x_lo, x_hi, y_lo, y_hi); none where they miss.
#[inline]
fn pixels_of(tri: &ScreenTriangle, (rx, ry, rw, rh): (usize, usize, usize, usize)) -> Option<[usize; 4]> {
    let x_lo = (tri.bbox[0] as usize).max(rx);
    let x_hi = (tri.bbox[2] as usize).min(rx + rw - 1);
    let y_lo = (tri.bbox[1] as usize).max(ry);
    let y_hi = (tri.bbox[3] as usize).min(ry + rh - 1);
    (x_lo <= x_hi && y_lo <= y_hi).then_some([x_lo, x_hi, y_lo, y_hi])
}

/// The edge function `e` at pixel (x, y)'s corner.
#[inline]
fn edge_at_pixel(e: [i64; 3], x: usize, y: usize) -> i64 {
    e[0] * (x as i64 * SUBPIXEL) + e[1] * (y as i64 * SUBPIXEL) + e[2]
}

/// `cover` where every pixel has the same SPP offsets: each edge's value at each offset is found once.
#[inline]
fn cover_same<const SPP: usize>(
    tri: &ScreenTriangle,
    offsets: &[[i64; 2]],
    rect: (usize, usize, usize, usize),
    mut hit: impl FnMut(usize, usize, usize, f32, f32),
) {
    let Some([x_lo, x_hi, y_lo, y_hi]) = pixels_of(tri, rect) else { return };
    let edges = tri.edges();
    let [e0, e1, e2] = edges;
    // Per-sample offsets of each edge function, and the sample's position relative to the triangle's origin
    // (less the pixel's).
    let offs: [[i64; 3]; SPP] = std::array::from_fn(|s| {
        let o = offsets[s];
        std::array::from_fn(|k| edges[k][0] * o[0] + edges[k][1] * o[1])
    });
    let rel: [(f32, f32); SPP] = std::array::from_fn(|s| {
        let [ox, oy] = offsets[s];
        (ox as f32 / SUBPIXEL as f32 - tri.origin.x, oy as f32 / SUBPIXEL as f32 - tri.origin.y)
    });
    let (sx0, sx1, sx2) = (e0[0] * SUBPIXEL, e1[0] * SUBPIXEL, e2[0] * SUBPIXEL);
    // Half-open ranges: an inclusive range's extra test per step showed on triangles of a pixel or two.
    for y in y_lo..y_hi + 1 {
        let (mut w0, mut w1, mut w2) =
            (edge_at_pixel(e0, x_lo, y), edge_at_pixel(e1, x_lo, y), edge_at_pixel(e2, x_lo, y));
        for x in x_lo..x_hi + 1 {
            for s in 0..SPP {
                let o = offs[s];
                if (w0 + o[0]) | (w1 + o[1]) | (w2 + o[2]) >= 0 {
                    hit(x, y, s, x as f32 + rel[s].0, y as f32 + rel[s].1);
                }
            }
            w0 += sx0;
            w1 += sx1;
            w2 += sx2;
        }
    }
}

/// `cover` for any count and offsets of each pixel's own.
#[inline]
fn cover_each(
    tri: &ScreenTriangle,
    samples: &TileOffsets,
    rect: (usize, usize, usize, usize),
    mut hit: impl FnMut(usize, usize, usize, f32, f32),
) {
    let Some([x_lo, x_hi, y_lo, y_hi]) = pixels_of(tri, rect) else { return };
    let [e0, e1, e2] = tri.edges();
    for y in y_lo..y_hi + 1 {
        for x in x_lo..x_hi + 1 {
            let (w0, w1, w2) = (edge_at_pixel(e0, x, y), edge_at_pixel(e1, x, y), edge_at_pixel(e2, x, y));
            for (s, &[ox, oy]) in samples.at(x, y).iter().enumerate() {
                let at = |w: i64, e: [i64; 3]| w + e[0] * ox + e[1] * oy;
                if at(w0, e0) | at(w1, e1) | at(w2, e2) >= 0 {
                    let (fx, fy) = (ox as f32 / SUBPIXEL as f32, oy as f32 / SUBPIXEL as f32);
                    hit(x, y, s, x as f32 + (fx - tri.origin.x), y as f32 + (fy - tri.origin.y));
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::raster::samples::{PixelFilter, Sampler};
    use crate::raster::setup::ProjectedMesh;
    use crate::raster::{Camera, Cull, Projection, TriangleSetup};
    use glam::{Affine3A, Vec3};

    /// The triangles (object-space corners, two-sided) set up for `camera` and the samples of `pattern`.
    fn set_up(
        camera: &Camera,
        pattern: &SamplePattern,
        positions: &[Vec3],
        triangles: &[[u32; 3]],
        object_to_camera: &Affine3A,
    ) -> Vec<ScreenTriangle> {
        let mut setup = TriangleSetup::new(camera, pattern);
        let vertices = setup.project_vertices(positions, None, object_to_camera);
        let cull = Cull::Nothing;
        let mesh = ProjectedMesh { vertices: &vertices, triangles, surface: 0, first: 0, cull, outline: None };
        setup.triangles_of(mesh)
    }

    /// Binning in parallel chunks lists every tile's triangles as one pass in submission order does, `keep`
    /// included: 200,000 boxes of every size, a third of them left out.
    #[test]
    fn parallel_binning_keeps_submission_order() {
        let camera = Camera::new(
            Vec3::new(0.0, 0.0, 5.0),
            Vec3::ZERO,
            Vec3::Y,
            Projection::Perspective { fov_y: 40.0 },
            640,
            480,
        );
        // Camera space: in front of the eye, along -z.
        let positions = [Vec3::new(-1.0, -1.0, -5.0), Vec3::new(1.0, -1.0, -5.0), Vec3::new(0.0, 1.0, -5.0)];
        let centre = SamplePattern::centre();
        let one = set_up(&camera, &centre, &positions, &[[0, 1, 2]], &Affine3A::IDENTITY)
            .pop()
            .expect("a triangle on screen");
        let (w, h, tile) = (640usize, 480usize, 64usize);
        let triangles: Vec<ScreenTriangle> = (0..200_000u32)
            .map(|k| {
                let x0 = (k.wrapping_mul(2_654_435_761) % w as u32) as i32;
                let y0 = (k.wrapping_mul(40_503) % h as u32) as i32;
                let size = (k % 7) as i32 * 40;
                let bbox = [x0, y0, (x0 + size).min(w as i32 - 1), (y0 + size / 2).min(h as i32 - 1)];
                ScreenTriangle { bbox, surface: k % 3, ..one }
            })
            .collect();
        let bins = Bins::of(&triangles, w, h, tile, |t| t.surface != 1);
        let tiles_x = w.div_ceil(tile);
        let mut want = vec![Vec::new(); tiles_x * h.div_ceil(tile)];
        for (i, t) in triangles.iter().enumerate().filter(|(_, t)| t.surface != 1) {
            for ty in t.bbox[1] as usize / tile..=t.bbox[3] as usize / tile {
                for tx in t.bbox[0] as usize / tile..=t.bbox[2] as usize / tile {
                    want[ty * tiles_x + tx].push(i as u32);
                }
            }
        }
        let got: Vec<&[u32]> = (0..want.len()).map(|t| bins.bin((t % tiles_x, t / tiles_x))).collect();
        assert!(got == want, "the parallel bins differ from one pass's");
    }

    /// The setup drops triangles that cover none of the samples in their box, and boxes only the pixels
    /// with a sample in a triangle's extent; what the samples see does not change. Thousands of triangles
    /// of 0.2 to 3 pixels at several depths, and as many with corners on a grid of eighths of a pixel, set
    /// up for shared stratified offsets (1, 4 and 16 a pixel, and 4 spread over a Mitchell filter, past the
    /// pixel), are rasterized against the same triangles set up as for per-pixel Sobol offsets of the same
    /// reach (whole-pixel boxes, nothing tested): every sample keeps the same triangle at the same depth; at
    /// 1 sample a pixel more than half of the triangles are dropped.
    #[test]
    fn triangles_between_the_samples_are_dropped_and_nothing_seen_changes() {
        let (w, h) = (64usize, 48usize);
        let camera =
            Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y, Projection::Perspective { fov_y: 40.0 }, 64, 48);
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut random = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 40) as f32 / (1u64 << 24) as f32
        };
        // A pixel is about 0.076 units wide at the distance of 5.
        let (mut positions, mut triangles) = (Vec::new(), Vec::new());
        for k in 0..4000u32 {
            let centre = Vec3::new(random() * 5.2 - 2.6, random() * 3.9 - 1.95, -random() * 0.8);
            let size = 0.076 * (0.2 + 2.8 * random() * random());
            let (a, squash) = (random() * std::f32::consts::TAU, 0.3 + random());
            let corner = |t: f32| Vec3::new((a + t).cos(), (a + t).sin() * squash, 0.0) * size;
            positions.extend([centre + corner(0.0), centre + corner(2.0), centre + corner(4.1)]);
            triangles.push([3 * k, 3 * k + 1, 3 * k + 2]);
        }
        // And triangles with corners on a grid of eighths of a pixel, at the distance of 5: edges through
        // pixel centres and corners, extents ending exactly on them.
        let to_camera = 5.0 / camera.scale;
        for k in 4000..6000u32 {
            let (x, y) = ((random() * w as f32 * 8.0).floor(), (random() * h as f32 * 8.0).floor());
            let mut corner = || {
                let (dx, dy) = ((random() * 17.0).floor() - 8.0, (random() * 17.0).floor() - 8.0);
                let (sx, sy) = ((x + dx) / 8.0, (y + dy) / 8.0);
                Vec3::new((sx - 0.5 * w as f32) * to_camera, (0.5 * h as f32 - sy) * to_camera, 0.0)
            };
            positions.extend([corner(), corner(), corner()]);
            triangles.push([3 * k, 3 * k + 1, 3 * k + 2]);
        }
        let mitchell = PixelFilter::parse("mitchell").unwrap();
        for (spp, filter, least_dropped) in [
            (1, PixelFilter::default(), 0.5),
            (4, PixelFilter::default(), 0.15),
            (16, PixelFilter::default(), 0.0),
            (4, mitchell, 0.12),
        ] {
            let pattern = SamplePattern::new(spp, Sampler::Stratified, filter).unwrap();
            let whole = SamplePattern::new(spp, Sampler::Sobol, filter).unwrap();
            assert!(pattern.shared_offsets().is_some() && whole.shared_offsets().is_none());
            let to_camera = Affine3A::from_translation(-5.0 * Vec3::Z);
            let set_up = |samples: &SamplePattern| set_up(&camera, samples, &positions, &triangles, &to_camera);
            let seen = |tris: &[ScreenTriangle]| {
                let mut vis = VisBuffer::new(w, spp);
                vis.render_tile(&Bins::new(tris, w, h, w), (0, 0), (w, h), tris, &pattern);
                let of = |t: u32| if t == EMPTY { EMPTY } else { tris[t as usize].triangle };
                (0..w * h * spp).map(|k| (of(vis.triangle[k]), vis.depth[k].to_bits())).collect::<Vec<_>>()
            };
            let (kept, all) = (set_up(&pattern), set_up(&whole));
            let dropped = 1.0 - kept.len() as f64 / all.len() as f64;
            assert!(dropped >= least_dropped, "{spp} spp, {filter:?}: {dropped} of the triangles dropped");
            assert!(all.len() > 5000 && dropped >= 0.0);
            let (got, want) = (seen(&kept), seen(&all));
            assert!(want.iter().filter(|s| s.0 != EMPTY).count() > w * h * spp / 4, "too little covered");
            assert!(got == want, "{spp} spp, {filter:?}: the samples see otherwise");
        }
    }

    /// Both ways of peeling find the same fragments behind, to the bit: a fan of overlapping triangles at
    /// several depths, every fourth sample refused, at 1 and 16 stratified samples per pixel and 8 scrambled
    /// Sobol samples spread over a Mitchell filter (offsets past the pixel, each pixel its own).
    #[test]
    fn peeling_one_by_one_equals_rasterizing_again() {
        let camera =
            Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y, Projection::Perspective { fov_y: 40.0 }, 64, 48);
        let mut positions = Vec::new();
        let mut triangles = Vec::new();
        for k in 0..12 {
            let (a, z) = (k as f32 * 0.5, -0.15 * k as f32);
            let (c, s) = (a.cos(), a.sin());
            let base = positions.len() as u32;
            positions.extend([
                Vec3::new(c, s, z),
                Vec3::new(-s * 1.5, c * 1.5, z + 0.3),
                Vec3::new(-c, -s * 0.7, z - 0.2),
            ]);
            triangles.push([base, base + 1, base + 2]);
        }
        let mitchell = PixelFilter::parse("mitchell").unwrap();
        for (spp, sampler, filter) in [
            (1, Sampler::Stratified, PixelFilter::default()),
            (16, Sampler::Stratified, PixelFilter::default()),
            (8, Sampler::Sobol, mitchell),
        ] {
            let pattern = SamplePattern::new(spp, sampler, filter).unwrap();
            let tris = set_up(&camera, &pattern, &positions, &triangles, &Affine3A::IDENTITY);
            let bins = Bins::new(&tris, 64, 48, 64);
            let peeled = |one_by_one: bool| {
                let mut vis = VisBuffer::new(64, spp);
                vis.render_tile(&bins, (0, 0), (64, 48), &tris, &pattern);
                let refused: Vec<usize> =
                    (0..64 * 48 * spp).filter(|k| k % 4 == 1 && vis.triangle[*k] != EMPTY).collect();
                assert!(refused.len() > 100);
                let before: Vec<u32> = refused.iter().map(|&k| vis.triangle[k]).collect();
                if one_by_one {
                    vis.peel_one_by_one(bins.bin((0, 0)), &tris, &refused);
                } else {
                    vis.peel_by_rasterizing(bins.bin((0, 0)), &tris, &refused);
                }
                // Most refused samples find a triangle behind theirs.
                let behind =
                    refused.iter().zip(&before).filter(|&(&k, &t)| vis.triangle[k] != EMPTY && vis.triangle[k] != t);
                assert!(behind.count() * 2 > refused.len(), "{spp} spp: too few fragments behind");
                (vis.triangle.clone(), vis.depth.iter().map(|d| d.to_bits()).collect::<Vec<_>>())
            };
            let (a, b) = (peeled(true), peeled(false));
            assert!(a == b, "{spp} spp: the two peels differ");
        }
    }
}
