//! Shadow maps (the slides' depth textures): what each light sees, as the distance of the nearest surface
//! per texel, and the percentage-closer lookup that tells how much of a light reaches a point. The maps are
//! rendered by the rasterizer (render/shadows.rs); this file only holds and reads them.

use crate::envmap::chart::Face;
use crate::lanes::{bits, gather, gather_words, CmpEq, CmpGt, CmpLt, F8, I8, LANES, V3};
use crate::raster::visibility::EMPTY;
use crate::raster::Camera;
use glam::{Vec2, Vec3};
use rayon::prelude::*;

/// The widest percentage-closer kernel, in texels from its centre: a receiver whose footprint covers more
/// of the map than this is under-sampled by the map whatever the kernel does.
pub const MAX_RADIUS: f32 = 4.0;
/// Texels beyond the edge of each face of a cube of maps, so that kernels near a face's edge stay on it.
pub const CUBE_MARGIN: usize = MAX_RADIUS as usize + 1;

/// How a light casts shadows: a scene's `shadow`, `shadow_size` and `shadow_bias`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadowSettings {
    pub enabled: bool,
    /// Texels along the map's longer side (per face of a point light's cube); `None`: the frame's larger
    /// side, rounded up to a power of two.
    pub size: Option<usize>,
    /// Scales the depth bias (1: the default).
    pub bias: f32,
}

impl ShadowSettings {
    pub const OFF: ShadowSettings = ShadowSettings { enabled: false, size: None, bias: 1.0 };
}

impl Default for ShadowSettings {
    /// Shadows on, the map as large as the frame, the usual bias: a scene light's defaults.
    fn default() -> Self {
        ShadowSettings { enabled: true, ..ShadowSettings::OFF }
    }
}

/// The side of the blocks of texels whose summaries let most lookups skip the texels.
const BLOCK: usize = 8;
/// A block's object where it holds more than one.
const MIXED: u32 = EMPTY - 1;

/// One depth image seen from a light.
pub struct ShadowView {
    pub camera: Camera,
    /// The nearest surface's distance along the light's axis per texel (rows from the top); infinity where
    /// nothing is seen.
    pub depth: Vec<f32>,
    /// That surface's object (`EMPTY` where none), as little-endian words for the gathers.
    pub object: Vec<[u8; 4]>,
    /// Per block of BLOCK x BLOCK texels, what bounds its depths from below.
    blocks: Vec<Block>,
    blocks_x: usize,
}

/// What a block of texels holds, summed up: the least depth, a plane no texel lies in front of (where every
/// texel sees a surface), and the one object seen there (`EMPTY` for none, `MIXED` for several).
#[derive(Clone, Copy)]
struct Block {
    least: f32,
    /// The plane's depth at the block's first texel and its change per texel right and down.
    plane: Option<(f32, f32, f32)>,
    object: u32,
}

/// A receiver's plane over the map: depth `compared` at screen position `s`, changing by `g` per texel.
#[derive(Clone, Copy)]
struct ReceiverPlane {
    s: Vec2,
    g: Vec2,
    compared: f32,
}

impl ReceiverPlane {
    /// Its depth at the centre of texel (x, y).
    fn at(&self, x: usize, y: usize) -> f32 {
        self.compared + self.g.x * (x as f32 + 0.5 - self.s.x) + self.g.y * (y as f32 + 0.5 - self.s.y)
    }
}

impl ShadowView {
    /// A view of `camera`'s `depth` and `object` per texel.
    pub fn new(camera: Camera, depth: Vec<f32>, object: Vec<[u8; 4]>) -> ShadowView {
        let (w, h) = (camera.width as usize, camera.height as usize);
        let (blocks_x, blocks_y) = (w.div_ceil(BLOCK), h.div_ceil(BLOCK));
        let mut blocks = vec![Block { least: f32::INFINITY, plane: None, object: EMPTY }; blocks_x * blocks_y];
        blocks.par_chunks_mut(blocks_x).enumerate().for_each(|(by, row)| {
            let (y0, y1) = (by * BLOCK, ((by + 1) * BLOCK).min(h) - 1);
            for (bx, block) in row.iter_mut().enumerate() {
                let (x0, x1) = (bx * BLOCK, ((bx + 1) * BLOCK).min(w) - 1);
                // The block's rows of texels, as (y, the row's depths, its objects): plain slices, which
                // the loops below run through several times faster than nested iterator closures.
                let rows = || (y0..=y1).map(|y| (y, &depth[y * w + x0..=y * w + x1], &object[y * w + x0..=y * w + x1]));
                let mut finite = true;
                for (_, depths, objects) in rows() {
                    for (&d, o) in depths.iter().zip(objects) {
                        let o = u32::from_le_bytes(*o);
                        block.least = block.least.min(d);
                        finite &= d.is_finite();
                        block.object = match block.object {
                            EMPTY => o,
                            b if b == o || o == EMPTY => b,
                            _ => MIXED,
                        };
                    }
                }
                // The plane through the corners' slopes, lowered under every texel.
                let d = |x: usize, y: usize| depth[y * w + x];
                if x1 == x0 || y1 == y0 || !finite {
                    continue;
                }
                let gx = (d(x1, y0) - d(x0, y0) + d(x1, y1) - d(x0, y1)) / (2 * (x1 - x0)) as f32;
                let gy = (d(x0, y1) - d(x0, y0) + d(x1, y1) - d(x1, y0)) / (2 * (y1 - y0)) as f32;
                let mut lowered = 0.0f32;
                for (y, depths, _) in rows() {
                    for (i, &texel) in depths.iter().enumerate() {
                        let above = d(x0, y0) + gx * i as f32 + gy * (y - y0) as f32 - texel;
                        lowered = lowered.max(above);
                    }
                }
                block.plane = Some((d(x0, y0) - lowered, gx, gy));
            }
        });
        ShadowView { camera, depth, object, blocks, blocks_x }
    }

    /// Whether no texel in x0..=x1, y0..=y1 (within the view) is nearer than any of the receivers' planes
    /// there, or is of `own`: read from the block summaries, block by block, by the least depth against the
    /// planes' farthest, or by the block's plane against theirs (both linear: compared at the corners).
    fn clear(
        &self,
        (x0, x1): (usize, usize),
        (y0, y1): (usize, usize),
        planes: &[ReceiverPlane],
        own: Option<u32>,
    ) -> bool {
        (y0 / BLOCK..=y1 / BLOCK).all(|by| {
            (x0 / BLOCK..=x1 / BLOCK).all(|bx| {
                let b = &self.blocks[by * self.blocks_x + bx];
                if b.object == EMPTY || Some(b.object) == own {
                    return true;
                }
                let (ax, ay) = (bx * BLOCK, by * BLOCK);
                let (cx, cy) = ([x0.max(ax), x1.min(ax + BLOCK - 1)], [y0.max(ay), y1.min(ay + BLOCK - 1)]);
                let corners = [(cx[0], cy[0]), (cx[1], cy[0]), (cx[0], cy[1]), (cx[1], cy[1])];
                planes.iter().all(|r| {
                    let farthest = corners.iter().map(|&(x, y)| r.at(x, y)).fold(f32::NEG_INFINITY, f32::max);
                    b.least >= farthest
                        || b.plane.is_some_and(|(base, gx, gy)| {
                            corners
                                .iter()
                                .all(|&(x, y)| base + gx * (x - ax) as f32 + gy * (y - ay) as f32 >= r.at(x, y))
                        })
                })
            })
        })
    }
}

/// What one light sees: one view (directional light, narrow spot), or a cube of six (point light, wide
/// spot) in the order of `envmap::chart::Face::ALL` (+X, -X, +Y, -Y, +Z, -Z) of the direction from the light.
pub struct ShadowMap {
    pub views: Vec<ShadowView>,
    /// The light's position, for a cube's choice of face.
    pub origin: Vec3,
    /// The settings' bias scale.
    pub bias: f32,
}

/// Every light's shadow map (`None` where it casts none), and per object whether it cannot shadow itself
/// (a convex solid or a flat piece: only its faces turned away from a light are dark, which the shading
/// already knows), so that its own texels never shadow it and it shows no acne at all.
pub struct Shadows {
    pub maps: Vec<Option<ShadowMap>>,
    pub self_shadowless: Vec<bool>,
}

impl ShadowMap {
    /// How much of the light reaches eight points (1 lit, 0 in shadow) at world positions `p` with unit
    /// geometric normals `n`, changing by `dpdx` and `dpdy` across their share of the pixel:
    /// percentage-closer filtering over the part of the map their footprint covers (at least one texel),
    /// each texel's depth compared with the receiver's plane there, less a bias of half a texel and half a
    /// texel per unit of the plane's slope (how far a flat texel and a tessellated surface may be off),
    /// from the receiver moved off its surface by sin(N, L) texels.
    /// `own`: the receivers' object where it cannot shadow itself.
    pub fn visibility8(&self, p: V3, n: V3, dpdx: V3, dpdy: V3, own: Option<u32>) -> F8 {
        if self.views.len() == 1 {
            return self.view_visibility8(&self.views[0], p, n, dpdx, dpdy, own);
        }
        // A cube: each lane reads the face its direction from the light points into.
        let faces = Face::of8(&(p - V3::splat(self.origin))).to_array().map(|f| f as usize);
        let mut out = [1.0; LANES];
        for face in 0..6 {
            if faces.contains(&face) {
                let seen = self.view_visibility8(&self.views[face], p, n, dpdx, dpdy, own).to_array();
                for i in (0..LANES).filter(|&i| faces[i] == face) {
                    out[i] = seen[i];
                }
            }
        }
        F8::new(out)
    }

    fn view_visibility8(&self, view: &ShadowView, p: V3, n: V3, dpdx: V3, dpdy: V3, own: Option<u32>) -> F8 {
        let cam = &view.camera;
        let half = F8::splat(0.5);
        // World size of a texel at the receiver.
        let texel_at = |z: F8| match cam.is_perspective() {
            true => z * F8::splat(1.0 / cam.scale),
            false => F8::splat(1.0 / cam.scale),
        };
        // The normal turned towards the light; the receiver moved along it by up to a texel as it turns
        // away (normal offset: what keeps a surface near its terminator from shadowing itself).
        let nc = V3::transform_vector(&cam.world_to_camera, n);
        let back = nc.z.cmp_lt(F8::ZERO);
        let nc = V3::select(back, -nc, nc);
        let sin = (F8::ONE - nc.z * nc.z).max(F8::ZERO).sqrt();
        let on_surface = V3::transform_point(&cam.world_to_camera, p);
        let c = on_surface + nc * (texel_at(-on_surface.z) * F8::splat(self.bias) * sin);
        let z = -c.z;
        let texel = texel_at(z);
        let (sx, sy) = cam.project8(c);
        let along = |d: V3| {
            let (x, y) = cam.project_derivative8(c, V3::transform_vector(&cam.world_to_camera, d));
            (x.abs(), y.abs())
        };
        let ((ax, ay), (bx, by)) = (along(dpdx), along(dpdy));
        let widest = F8::splat(MAX_RADIUS);
        let rx = (half * ax.max(bx)).max(half).min(widest);
        let ry = (half * ay.max(by)).max(half).min(widest);
        // The receiver's plane: its depth per texel right and down; and the slope-scaled bias.
        let cos = nc.z.max(F8::splat(0.1));
        let inv = F8::ONE / cos;
        let (gx, gy) = (nc.x * inv * texel, -nc.y * inv * texel);
        let tan = (F8::ONE - cos * cos).max(F8::ZERO).sqrt() * inv;
        let compared = z - texel * F8::splat(self.bias) * (half + half * tan);
        if view.clear8((sx, sy), (rx, ry), (gx, gy), compared, own) {
            return F8::ONE;
        }
        let seen = view.bilinear8((sx, sy), (gx, gy), compared, z, own);
        // Footprints wider than a texel (few, where the map is coarse for the frame) go one by one.
        let wide = (rx.cmp_gt(half) | ry.cmp_gt(half)).move_mask();
        if wide == 0 {
            return seen;
        }
        let mut out = seen.to_array();
        let lanes = [sx, sy, rx, ry, gx, gy, compared, z].map(|v| v.to_array());
        for i in (0..LANES).filter(|i| wide >> i & 1 == 1) {
            let [sx, sy, rx, ry, gx, gy, compared, z] = lanes.map(|v| v[i]);
            out[i] = view.percentage_closer(Vec2::new(sx, sy), (rx, ry), (gx, gy), compared, z, own);
        }
        F8::new(out)
    }
}

impl ShadowView {
    /// Whether no texel of any of eight boxes (half-widths `r` about `s`) can shadow its receiver (planes
    /// `compared` at `s` changing by `g` per texel): from the block summaries, over the box about all eight
    /// where they are close together (a packet of neighbouring samples).
    fn clear8(
        &self,
        (sx, sy): (F8, F8),
        (rx, ry): (F8, F8),
        (gx, gy): (F8, F8),
        compared: F8,
        own: Option<u32>,
    ) -> bool {
        let least = |v: F8| v.to_array().into_iter().fold(f32::INFINITY, f32::min);
        let most = |v: F8| v.to_array().into_iter().fold(f32::NEG_INFINITY, f32::max);
        let (x0, x1, y0, y1) = (least(sx - rx), most(sx + rx), least(sy - ry), most(sy + ry));
        let span = (BLOCK * 4) as f32;
        let finite = [gx, gy, compared].iter().all(|v| least(*v).is_finite() && most(*v).is_finite());
        if !(x1 - x0 <= span && y1 - y0 <= span && finite) {
            return false;
        }
        let (w, h) = (self.camera.width as f32, self.camera.height as f32);
        let (x0, x1) = (x0.floor().max(0.0), x1.floor().min(w - 1.0));
        let (y0, y1) = (y0.floor().max(0.0), y1.floor().min(h - 1.0));
        if x0 > x1 || y0 > y1 {
            return true;
        }
        let [sx, sy, gx, gy, compared] = [sx, sy, gx, gy, compared].map(|v| v.to_array());
        let planes: [ReceiverPlane; LANES] = std::array::from_fn(|i| ReceiverPlane {
            s: Vec2::new(sx[i], sy[i]),
            g: Vec2::new(gx[i], gy[i]),
            compared: compared[i],
        });
        self.clear((x0 as usize, x1 as usize), (y0 as usize, y1 as usize), &planes, own)
    }

    /// `percentage_closer` with a box of one texel (the four texels about each sample, weighted
    /// bilinearly) on eight lanes at once.
    fn bilinear8(&self, (sx, sy): (F8, F8), (gx, gy): (F8, F8), compared: F8, z: F8, own: Option<u32>) -> F8 {
        let (w, h) = (self.camera.width as i32, self.camera.height as i32);
        let (fx, fy) = (sx - F8::splat(0.5), sy - F8::splat(0.5));
        let (x0, y0) = (fx.floor(), fy.floor());
        let (ax, ay) = (fx - x0, fy - y0);
        // Far outside the map (or not a number): clamped, then masked as lit.
        let limit = F8::splat(1e6);
        let (x0, y0) = (x0.max(-limit).min(limit).round_int(), y0.max(-limit).min(limit).round_int());
        let inside = |x: I8, y: I8| {
            x.cmp_gt(I8::splat(-1)) & x.cmp_lt(I8::splat(w)) & y.cmp_gt(I8::splat(-1)) & y.cmp_lt(I8::splat(h))
        };
        let mut shadowed = F8::ZERO;
        for (dy, wy) in [(0, F8::ONE - ay), (1, ay)] {
            for (dx, wx) in [(0, F8::ONE - ax), (1, ax)] {
                let (x, y) = (x0 + I8::splat(dx), y0 + I8::splat(dy));
                let index = y * I8::splat(w) + x;
                let depth = gather(&self.depth, index);
                let mut counted = inside(x, y);
                if let Some(own) = own {
                    // SAFETY: `gather` clamps its indices into `depth`, which is as long as `object`; the same
                    // clamp is applied here.
                    let object =
                        unsafe { gather_words(&self.object, index.max(I8::splat(0)).min(I8::splat(w * h - 1))) };
                    counted &= !object.cmp_eq(I8::splat(own as i32));
                }
                let offset =
                    (x.round_float() + F8::splat(0.5) - sx) * gx + (y.round_float() + F8::splat(0.5) - sy) * gy;
                let occluded = depth.cmp_lt(compared + offset) & bits(counted);
                shadowed += occluded.blend(wx * wy, F8::ZERO);
            }
        }
        let behind = !z.cmp_gt(F8::splat(crate::raster::camera::NEAR));
        behind.blend(F8::ONE, F8::ONE - shadowed)
    }

    /// The lit fraction of a box of half-widths `r` (texels) about screen position `s`: each texel whose
    /// depth is less than the receiver's plane there (`compared` at `s`, changing by `g` per texel) shadows
    /// it by its share of the box. `z`: the receiver's own depth (lit where it is behind the light).
    fn percentage_closer(&self, s: Vec2, r: (f32, f32), g: (f32, f32), compared: f32, z: f32, own: Option<u32>) -> f32 {
        let ((rx, ry), (gx, gy)) = (r, g);
        let in_front = z > crate::raster::camera::NEAR;
        if !in_front || !s.is_finite() || !rx.is_finite() || !ry.is_finite() {
            return 1.0;
        }
        let (w, h) = (self.camera.width as i64, self.camera.height as i64);
        let (x0, x1) = (((s.x - rx).floor() as i64).max(0), ((s.x + rx).floor() as i64).min(w - 1));
        let (y0, y1) = (((s.y - ry).floor() as i64).max(0), ((s.y + ry).floor() as i64).min(h - 1));
        if x0 > x1 || y0 > y1 {
            return 1.0;
        }
        let plane = ReceiverPlane { s, g: Vec2::new(gx, gy), compared };
        if self.clear((x0 as usize, x1 as usize), (y0 as usize, y1 as usize), &[plane], own) {
            return 1.0;
        }
        let overlap = |lo: f32, hi: f32, t: i64| (hi.min(t as f32 + 1.0) - lo.max(t as f32)).max(0.0);
        let mut shadowed = 0.0;
        for ty in y0..=y1 {
            let wy = overlap(s.y - ry, s.y + ry, ty);
            let row = (ty * w) as usize;
            for tx in x0..=x1 {
                let k = row + tx as usize;
                // Empty texels are infinitely far: they never pass the depth test.
                if self.depth[k] < plane.at(tx as usize, ty as usize) && Some(u32::from_le_bytes(self.object[k])) != own
                {
                    shadowed += wy * overlap(s.x - rx, s.x + rx, tx);
                }
            }
        }
        1.0 - shadowed / (4.0 * rx * ry)
    }
}

/// The depth a view stores for a depth key of the rasterizer (1/w in perspective, camera z otherwise).
pub fn depth_of_key(camera: &Camera, key: f32) -> f32 {
    match camera.is_perspective() {
        true => 1.0 / key,
        false => -key,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::raster::Projection;

    /// A 16x16 orthographic view down -Y over [-8, 8]^2, with a wall of depth 1 over x < 0 (texels 0..8)
    /// and nothing elsewhere.
    fn half_wall() -> ShadowMap {
        let camera = Camera::new(
            Vec3::new(0.0, 10.0, 0.0),
            Vec3::ZERO,
            Vec3::NEG_Z,
            Projection::Orthographic { height: 16.0 },
            16,
            16,
        );
        let depth = (0..256).map(|k| if k % 16 < 8 { 1.0 } else { f32::INFINITY }).collect();
        let object = (0..256).map(|k| if k % 16 < 8 { 7u32 } else { EMPTY }.to_le_bytes()).collect();
        ShadowMap { views: vec![ShadowView::new(camera, depth, object)], origin: Vec3::ZERO, bias: 1.0 }
    }

    fn at(map: &ShadowMap, p: Vec3, footprint: f32, own: Option<u32>) -> f32 {
        let s = V3::splat;
        map.visibility8(s(p), s(Vec3::Y), s(Vec3::X * footprint), s(Vec3::Z * footprint), own).as_array_ref()[3]
    }

    #[test]
    fn percentage_closer_across_an_edge() {
        let map = half_wall();
        // Far from the edge: shadowed, lit; on the edge, half; the kernel's width follows the footprint.
        assert_eq!(at(&map, Vec3::new(-4.0, 0.0, 0.3), 0.0, None), 0.0);
        assert_eq!(at(&map, Vec3::new(4.0, 0.0, 0.3), 0.0, None), 1.0);
        assert!((at(&map, Vec3::new(0.0, 0.0, 0.3), 0.0, None) - 0.5).abs() < 1e-6);
        // A quarter texel into the lit side: the one-texel kernel sees a quarter of the wall...
        assert!((at(&map, Vec3::new(0.25, 0.0, 0.3), 0.0, None) - 0.75).abs() < 1e-6);
        // ...a four-texel one (footprint 4 units = 4 texels) sees 1.75 of 4 texels of it.
        assert!((at(&map, Vec3::new(0.25, 0.0, 0.3), 4.0, None) - (1.0 - 1.75 / 4.0)).abs() < 1e-6);
        // Its own object never shadows a receiver that cannot shadow itself; above the wall, nothing does.
        assert_eq!(at(&map, Vec3::new(-4.0, 0.0, 0.3), 0.0, Some(7)), 1.0);
        assert_eq!(at(&map, Vec3::new(-4.0, 9.5, 0.3), 0.0, None), 1.0);
    }
}
