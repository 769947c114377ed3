//! The transparent pass: surfaces with `alpha_mode = "blend"` stay out of the opaque visibility and are
//! composited over it, each fragment lit like an opaque one. A tile finds every translucent fragment in
//! front of each sample's opaque surface by depth peeling (the nearest, then the next behind it, ...), so
//! the outline test of curved surfaces applies to them as to opaque ones; then composites them back to
//! front over the sample: c = alpha C + (1 - alpha) c, the slides' rI_K = (1 - K_K) I_K + K_K rI_behind with
//! opacity alpha = 1 - K.

use super::{frame, Drawn, TileJob, TileScratch};
use crate::geometry::{Instance, Primitive};
use crate::lanes::{CmpLt, F8, LANES, V3};
use crate::raster::visibility::EMPTY;
use crate::raster::{Camera, ScreenTriangle, VisBuffer};
use crate::shade::SurfaceSamples8;
use glam::{Mat3, Vec3};

/// The order in which the translucent fragments over a sample are composited.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Transparency {
    /// As sorted drawing does it: objects back to front by their centres' distance, and each object's
    /// triangles back to front by theirs. Right for objects apart from one another (panes, leaves, glass
    /// shells seen from outside); wrong where translucent surfaces cross or enclose one another.
    #[default]
    Sorted,
    /// Each sample's own fragments back to front by their distance (an A-buffer): right wherever
    /// translucent surfaces intersect, at the cost of keeping every fragment of a tile.
    Exact,
}

/// The most translucent fragments over one sample that count (the nearest ones); what lies behind them
/// shows through as if they were not there.
pub const MAX_LAYERS: usize = 32;

/// One translucent fragment: its sample in the tile, its place in the compositing order (ascending: back
/// to front), its lit colour and its alpha.
pub(super) struct Fragment {
    pub sample: usize,
    pub order: f32,
    pub color: Vec3,
    pub alpha: f32,
}

impl TileJob<'_> {
    /// The translucent fragments of the tile in front of each sample's opaque surface (`opaque`: the
    /// tile's visibility), shaded, into `out` in compositing order, sample by sample.
    pub(super) fn translucent_fragments(
        &self,
        layers: &mut TileScratch,
        tile: (usize, usize),
        screen: (usize, usize),
        opaque: &VisBuffer,
        out: &mut Vec<Fragment>,
    ) {
        out.clear();
        let Some(bins) = self.blend_bins else { return };
        if bins.bin(tile).is_empty() {
            return;
        }
        // The same job over the translucent triangles: its peeling and tests see only them.
        let job = TileJob { bins, ..*self };
        layers.vis.render_tile(bins, tile, screen, self.triangles, self.pattern);
        let n = layers.vis.width * layers.vis.height * layers.vis.spp;
        layers.last.clear();
        layers.last.resize(n, (EMPTY, 0.0));
        for layer in 0..MAX_LAYERS {
            if layer > 0 {
                let TileScratch { vis, refused, .. } = layers;
                refused.clear();
                refused.extend((0..n).filter(|&k| vis.triangle[k] != EMPTY));
                vis.peel(bins, tile, self.triangles, refused);
            }
            if job.any_masked || layers.vis.outline {
                job.fix_visibility(layers, tile);
            }
            // What lies behind the opaque surface is hidden: it ends the sample's layers.
            let TileScratch { vis, candidates, last, .. } = layers;
            candidates.clear();
            for k in 0..n {
                if vis.triangle[k] != EMPTY {
                    if vis.depth[k] < opaque.depth[k] {
                        vis.triangle[k] = EMPTY;
                    } else {
                        candidates.push(k);
                    }
                }
            }
            if candidates.is_empty() {
                break;
            }
            job.shade_layer(vis, candidates, last, out);
        }
        out.sort_unstable_by(|a, b| a.sample.cmp(&b.sample).then(a.order.total_cmp(&b.order)));
    }

    /// Shades the fragments of one layer at the samples `candidates`: colour and alpha. A curved surface's
    /// triangles along its outline are widened, so a sample may meet the surface through two of them at
    /// one point (`last`, per sample the surface and distance of its last fragment, keeps it once; spheres
    /// and flat patches, which a ray meets once, once in all), or, near the outline, where its ray leaves
    /// a closed surface (not seen: closed surfaces show their outside).
    fn shade_layer(&self, vis: &mut VisBuffer, candidates: &[usize], last: &mut [(u32, f32)], out: &mut Vec<Fragment>) {
        self.packets_of(
            vis,
            candidates,
            &[],
            |_| true,
            |vis, packet| {
                let (lit, alpha, back) = self.with_samples(vis, packet, |inst, at| {
                    (self.shade.shade8(inst, at), self.shade.alpha8(inst, at), turned_away(self.camera, inst, at))
                });
                let alpha = alpha.to_array();
                let distance = lit.depth.to_array();
                // A ray meets a sphere's outside or a flat patch once.
                let once = matches!(&self.instances[packet.surface as usize].primitive,
                    Primitive::Parametric(s) if s.cannot_shadow_itself());
                for i in 0..packet.len.min(LANES) {
                    let k = packet.samples[i];
                    let (surface, before) = last[k];
                    let again = surface == packet.surface && (once || (distance[i] - before).abs() <= 1e-3 * before);
                    if again || back >> i & 1 == 1 {
                        continue;
                    }
                    last[k] = (packet.surface, distance[i]);
                    let order = match self.transparency {
                        Transparency::Exact => -distance[i],
                        Transparency::Sorted => self.blend_order[packet.triangles[i] as usize] as f32,
                    };
                    let color = lit.color.lane(i);
                    out.push(Fragment { sample: k, order, color, alpha: alpha[i].clamp(0.0, 1.0) });
                }
            },
        );
    }
}

/// The lanes (bits) of a closed parametric surface whose point faces away from the eye (`camera`'s).
fn turned_away(camera: &Camera, inst: &Instance, at: &SurfaceSamples8) -> u8 {
    if inst.two_sided || at.mesh.is_some() {
        return 0;
    }
    // Normals go to camera space by the inverse transpose of object_to_camera's linear part.
    let n = V3::mul_mat3(&Mat3::from(inst.camera_to_object.matrix3).transpose(), at.frame.pu.cross(at.frame.pv));
    let p = V3::transform_point(&inst.object_to_camera, at.frame.p);
    let towards = match camera.is_perspective() {
        true => -p,
        false => V3::splat(Vec3::Z),
    };
    n.dot(towards).cmp_lt(F8::ZERO).move_mask() as u8
}

/// Each translucent triangle's place in sorted drawing (0: the farthest, drawn first): objects back to
/// front by the distance of their bounding box's centre from the eye, then each object's triangles back to
/// front by their centroids'. Other triangles get 0.
pub(super) fn sorted_order(camera: &Camera, instances: &[Instance], drawn: &Drawn, blending: &[bool]) -> Vec<u32> {
    let distance = |p: Vec3| if camera.is_perspective() { p.length() } else { -p.z };
    let objects = instances.iter().map(|i| i.object as usize + 1).max().unwrap_or(0);
    let mut boxes = vec![(Vec3::INFINITY, Vec3::NEG_INFINITY); objects];
    for (s, inst) in instances.iter().enumerate().filter(|&(s, _)| blending[s]) {
        let b = &mut boxes[inst.object as usize];
        for &p in drawn.meshes[s].positions() {
            let c = inst.object_to_camera.transform_point3(p);
            *b = (b.0.min(c), b.1.max(c));
        }
    }
    let centroid = |t: &ScreenTriangle| {
        let s = t.surface as usize;
        let mesh = &drawn.meshes[s];
        let corners = mesh.triangles()[(t.triangle - drawn.first_triangles[s]) as usize];
        let sum: Vec3 = corners.iter().map(|&k| mesh.positions()[k as usize]).sum();
        instances[s].object_to_camera.transform_point3(sum / 3.0)
    };
    let mut keyed: Vec<(f32, u32, f32, u32)> = drawn
        .triangles
        .iter()
        .enumerate()
        .filter(|(_, t)| blending[t.surface as usize])
        .map(|(i, t)| {
            let object = instances[t.surface as usize].object;
            let (lo, hi) = boxes[object as usize];
            (distance(0.5 * (lo + hi)), object, distance(centroid(t)), i as u32)
        })
        .collect();
    keyed.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)).then(b.2.total_cmp(&a.2)).then(a.3.cmp(&b.3)));
    let mut order = vec![0; drawn.triangles.len()];
    for (rank, &(.., i)) in keyed.iter().enumerate() {
        order[i as usize] = rank as u32;
    }
    order
}

/// Composites the fragments of sample `k` (from `next` on in `fragments`, which are in sample order) over
/// its colour `c`, adding what they cover of it to `acc` (by the sample's `weight`); returns the colour
/// and where the next sample's fragments begin.
pub(super) fn composite(
    fragments: &[Fragment],
    next: usize,
    k: usize,
    mut c: Vec3,
    covered: bool,
    weight: f32,
    acc: &mut frame::AovSample,
) -> (Vec3, usize) {
    let mut through = 1.0;
    let mut next = next;
    while let Some(f) = fragments.get(next).filter(|f| f.sample == k) {
        c = f.color * f.alpha + c * (1.0 - f.alpha);
        through *= 1.0 - f.alpha;
        next += 1;
    }
    if !covered {
        acc.cover(1.0 - through, weight);
    }
    (c, next)
}
