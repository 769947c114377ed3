//! Triangle setup: projection, snapping to fixed point, orientation and culling, edge functions with the
//! fill rule, and the screen-space planes that give perspective-correct barycentrics and (u,v) derivatives.

use super::camera::Camera;
use super::clip::{clip_planes, clip_polygon, inside_all, inside_all8, ClipVertex};
use super::cull_lanes::LaneCull;
use super::exact::{Outline, OUTLINE_MARGIN_PX};
use super::samples::SamplePattern;
use super::SUBPIXEL;
use crate::lanes::{prefetch, to_bits, CmpGe, CmpLe, F8, I8, LANES, V3};
use crate::stream;
use glam::{Affine3A, Vec2, Vec3, Vec4};
use rayon::prelude::*;
use std::mem::MaybeUninit;
use std::sync::Mutex;

/// a(x, y) = a0 + ax (x - x0) + ay (y - y0): an attribute that is affine in screen space.
#[derive(Clone, Copy, Debug, Default)]
pub struct Plane {
    pub a0: f32,
    pub ax: f32,
    pub ay: f32,
}

impl Plane {
    #[inline]
    pub fn at(&self, dx: f32, dy: f32) -> f32 {
        self.a0 + self.ax * dx + self.ay * dy
    }
}

/// The attributes of eight samples, each on its own triangle.
#[derive(Clone, Copy, Debug)]
pub struct Interpolated8 {
    /// Perspective-correct barycentrics of vertices 1 and 2.
    pub bary: [F8; 2],
    pub uv: (F8, F8),
    /// du/dx, dv/dx, du/dy, dv/dy.
    pub duv: [F8; 4],
}

/// A `Plane` on eight lanes.
struct Plane8 {
    a0: F8,
    ax: F8,
    ay: F8,
}

impl Plane8 {
    /// Lane i holds the plane `f(tris[i])`.
    #[inline]
    fn gather(tris: &[&ScreenTriangle; LANES], f: impl Fn(&ScreenTriangle) -> &Plane) -> Plane8 {
        Plane8 { a0: gather8(tris, |t| f(t).a0), ax: gather8(tris, |t| f(t).ax), ay: gather8(tris, |t| f(t).ay) }
    }

    #[inline]
    fn at(&self, dx: F8, dy: F8) -> F8 {
        self.a0 + self.ax * dx + self.ay * dy
    }
}

/// A triangle ready to rasterize and to interpolate.
#[derive(Clone, Copy, Debug)]
pub struct ScreenTriangle {
    /// Edge functions E = A x + B y + C in fixed point, E >= 0 inside, with the fill rule folded into C (one
    /// less on the edges that do not own the samples exactly on them): each edge's (A, B), 32 bits (the
    /// guard band and `Limit::FrameSide` bound them), and its C (`edges` gives all three).
    pub slopes: [[i32; 2]; 3],
    pub offsets: [i64; 3],
    /// Bounding box in whole pixels, inclusive, clipped to the screen.
    pub bbox: [i32; 4],
    /// Screen position of vertex 0, the origin of the planes.
    pub origin: Vec2,
    /// Depth key (larger is nearer): 1/w for perspective, camera z for orthographic. In perspective it
    /// is also q = 1/w, the S of the barycentrics, which is not stored twice (orthographically S is 1).
    pub depth: Plane,
    /// b1 q1 and b2 q2: barycentrics are b_k = B_k / S.
    pub b1: Plane,
    pub b2: Plane,
    pub uv: [Vec2; 3],
    /// The surface (one parametric surface of one object) the triangle belongs to.
    pub surface: u32,
    /// The index within its object of the triangle it was set up from (clipped pieces share it).
    pub triangle: u32,
    /// Where it lies against a curved surface's outline: along it, it is widened by
    /// `exact::OUTLINE_MARGIN_PX` and samples it covers are tested against the exact surface (raster/exact.rs).
    pub outline: Outline,
    /// Seen in perspective (else orthographically, where q is 1).
    pub perspective: bool,
}

impl ScreenTriangle {
    /// The edge functions as (A, B, C).
    #[inline]
    pub fn edges(&self) -> [[i64; 3]; 3] {
        std::array::from_fn(|e| [self.slopes[e][0] as i64, self.slopes[e][1] as i64, self.offsets[e]])
    }
}

/// The memory of the last frame's set-up triangles, kept for the next frame: a million-triangle mesh sets up
/// about 60 MB, and fresh memory costs page faults that took as long as the setup itself. Animations,
/// turntables, the paint page and Python loops draw many frames; one frame alone gains nothing and loses
/// nothing.
static SPARE_TRIANGLES: Mutex<Vec<ScreenTriangle>> = Mutex::new(Vec::new());

/// The most memory kept between frames.
const SPARE_BYTES: usize = 256 << 20;

/// An empty vector with room for `capacity` triangles: the last frame's, when no other frame holds it.
pub fn triangle_buffer(capacity: usize) -> Vec<ScreenTriangle> {
    let mut buffer = SPARE_TRIANGLES.try_lock().map(|mut spare| std::mem::take(&mut *spare)).unwrap_or_default();
    buffer.clear();
    buffer.reserve(capacity);
    buffer
}

/// Keeps a frame's triangle memory for the next frame (the larger of two, up to `SPARE_BYTES`).
pub fn keep_triangle_buffer(buffer: Vec<ScreenTriangle>) {
    if buffer.capacity() * std::mem::size_of::<ScreenTriangle>() > SPARE_BYTES {
        return;
    }
    if let Ok(mut spare) = SPARE_TRIANGLES.try_lock() {
        if buffer.capacity() > spare.capacity() {
            *spare = buffer;
        }
    }
}

/// Which surface a triangle belongs to, and its number within its object.
#[derive(Clone, Copy)]
struct TriangleId {
    surface: u32,
    triangle: u32,
    outline: Outline,
}

/// Everything interpolated at eight screen positions (x, y), lane i on triangle `tris[i]`: perspective-correct
/// barycentrics, (u,v) and its screen derivatives, from one evaluation of the planes and one division. The
/// triangles' numbers are gathered into lanes; the arithmetic runs on all lanes at once.
#[inline]
pub fn interpolate8(tris: &[&ScreenTriangle; LANES], x: F8, y: F8) -> Interpolated8 {
    let plane = |f: fn(&ScreenTriangle) -> &Plane| Plane8::gather(tris, f);
    // The triangles of one frame share its projection.
    let s = match tris[0].perspective {
        true => plane(|t| &t.depth),
        false => Plane8 { a0: F8::ONE, ax: F8::ZERO, ay: F8::ZERO },
    };
    let (b1_plane, b2_plane) = (plane(|t| &t.b1), plane(|t| &t.b2));
    let (dx, dy) = (x - gather8(tris, |t| t.origin.x), y - gather8(tris, |t| t.origin.y));
    let inv = F8::ONE / s.at(dx, dy);
    let (b1, b2) = (b1_plane.at(dx, dy) * inv, b2_plane.at(dx, dy) * inv);
    let vertex_uv = |k: usize| (gather8(tris, |t| t.uv[k].x), gather8(tris, |t| t.uv[k].y));
    let (uv0, uv1, uv2) = (vertex_uv(0), vertex_uv(1), vertex_uv(2));
    let (e1, e2) = ((uv1.0 - uv0.0, uv1.1 - uv0.1), (uv2.0 - uv0.0, uv2.1 - uv0.1));
    // d(B/S) = (dB - b dS) / S
    let db1x = (b1_plane.ax - b1 * s.ax) * inv;
    let db1y = (b1_plane.ay - b1 * s.ay) * inv;
    let db2x = (b2_plane.ax - b2 * s.ax) * inv;
    let db2y = (b2_plane.ay - b2 * s.ay) * inv;
    let along = |d1: F8, d2: F8| (d1 * e1.0 + d2 * e2.0, d1 * e1.1 + d2 * e2.1);
    let (ddx, ddy) = (along(db1x, db2x), along(db1y, db2y));
    let uv = (uv0.0 + b1 * e1.0 + b2 * e2.0, uv0.1 + b1 * e1.1 + b2 * e2.1);
    Interpolated8 { bary: [b1, b2], uv, duv: [ddx.0, ddx.1, ddy.0, ddy.1] }
}

/// One number of each lane's triangle, as lanes.
#[inline]
fn gather8(tris: &[&ScreenTriangle; LANES], f: impl Fn(&ScreenTriangle) -> f32) -> F8 {
    F8::new(std::array::from_fn(|i| f(tris[i])))
}

/// Which triangles the setup drops by the way they face.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cull {
    /// Keep every triangle (open surfaces, seen from both sides).
    Nothing,
    /// Drop triangles whose (u,v) winding faces away from the eye (closed surfaces); `mirrored` when the
    /// object's transform has a negative determinant, which turns the winding over.
    FacingAway { mirrored: bool },
}

/// A mesh vertex in camera space with its projection, computed once and shared by its triangles.
#[derive(Clone, Copy, Debug)]
pub struct ProjectedVertex {
    pub clip: ClipVertex,
    /// 1/w (1 for orthographic).
    q: f32,
}

/// A vertex's snapped screen position, 1/SUBPIXEL pixel units; `OUTSIDE` where the vertex lies outside a
/// clip plane (its triangles are clipped, and their pieces projected anew). Inside the planes' guard band
/// every position fits 32 bits (`Limit::FrameSide`).
type ScreenPoint = [i32; 2];

/// The screen point of a vertex outside a clip plane.
const OUTSIDE: ScreenPoint = [i32::MIN; 2];

/// A mesh's vertices projected: each in camera space, and apart from those, its screen point. Which
/// triangles are kept is decided from the screen points alone, 8 bytes a vertex: read with the rest (48 bytes
/// a vertex), a million-triangle mesh's count of them waited on memory for a third of its time.
pub struct ProjectedVertices {
    pub camera: Vec<ProjectedVertex>,
    screen: Vec<ScreenPoint>,
}

/// Triangles of a projected mesh to set up: all of surface `surface`, the first of them numbered `first`
/// within its object; `cull` says which to drop by the way they face, `outline` (where given, one flag per
/// triangle) which lie along the surface's outline.
#[derive(Clone, Copy)]
pub struct ProjectedMesh<'a> {
    pub vertices: &'a ProjectedVertices,
    pub triangles: &'a [[u32; 3]],
    pub surface: u32,
    pub first: u32,
    pub cull: Cull,
    pub outline: Option<&'a [Outline]>,
}

/// Projects and sets up triangles of one camera, clipping where needed.
pub struct TriangleSetup<'a> {
    camera: &'a Camera,
    planes: [Vec4; 5],
    polygon: Vec<ClipVertex>,
    /// Where a pixel's samples may lie: each triangle's box holds the pixels with a sample in its extent.
    samples: SampleSpan<'a>,
}

/// Where the samples of a pixel may lie, in 1/SUBPIXEL pixel from its corner, as the least and greatest
/// offset on each axis; and the offsets themselves where every pixel has the same.
#[derive(Clone, Debug)]
struct SampleSpan<'a> {
    /// The samples' extent: the shared offsets', or the pixel and `reach` pixels around it.
    axes: [[i64; 2]; 2],
    /// The pixel and `reach` pixels around it.
    reach: [i64; 2],
    shared: Option<&'a [[i64; 2]]>,
}

impl<'a> SampleSpan<'a> {
    /// The samples of `pattern`.
    fn of(pattern: &'a SamplePattern) -> SampleSpan<'a> {
        let around = pattern.reach() as i64 * SUBPIXEL;
        let reach = [-around, SUBPIXEL - 1 + around];
        let extent = |offsets: &[[i64; 2]], d: usize| {
            offsets.iter().fold([i64::MAX, i64::MIN], |[lo, hi], o| [lo.min(o[d]), hi.max(o[d])])
        };
        let shared = pattern.shared_offsets();
        let axes = shared.map_or([reach; 2], |o| [extent(o, 0), extent(o, 1)]);
        SampleSpan { axes, reach, shared }
    }
}

impl<'a> TriangleSetup<'a> {
    /// The setup for `camera` and the samples of `pattern`: a triangle's box is the pixels with a sample in
    /// its extent, and triangles that cover none of a few samples are dropped.
    pub fn new(camera: &'a Camera, pattern: &'a SamplePattern) -> Self {
        let planes = clip_planes(camera);
        TriangleSetup { camera, planes, polygon: Vec::with_capacity(9), samples: SampleSpan::of(pattern) }
    }

    /// Carries a mesh's object-space vertices into camera space and onto the screen.
    pub fn project_vertices(
        &self,
        positions: &[Vec3],
        uvs: Option<&[Vec2]>,
        object_to_camera: &Affine3A,
    ) -> ProjectedVertices {
        // Big meshes in parallel chunks: one mesh is often the whole scene.
        const CHUNK: usize = 1 << 14;
        let uv = |k: usize| uvs.map_or(Vec2::ZERO, |u| u[k]);
        let n = positions.len();
        let (mut camera, mut screen) = (Vec::with_capacity(n), Vec::with_capacity(n));
        // Each vertex stored where it belongs: collected through rayon's consumer, it went through the
        // stack and was read back in wider pieces than it was written, which stalled the store forwarding.
        let chunks = camera.spare_capacity_mut()[..n]
            .par_chunks_mut(CHUNK)
            .zip(screen.spare_capacity_mut()[..n].par_chunks_mut(CHUNK));
        chunks.zip(positions.par_chunks(CHUNK)).enumerate().for_each(|(c, ((to_camera, to_screen), from))| {
            // Eight vertices at a time on lanes, then the rest one by one: the same bits.
            let lanes = from.len() / LANES * LANES;
            for (j, ((to_camera, to_screen), from)) in to_camera[..lanes]
                .chunks_exact_mut(LANES)
                .zip(to_screen[..lanes].chunks_exact_mut(LANES))
                .zip(from.chunks_exact(LANES))
                .enumerate()
            {
                let pos = V3::transform_point(object_to_camera, V3::from_lanes(from.try_into().expect("eight")));
                let (points, q) = self.project8(&pos);
                let (x, y, z, q) = (pos.x.to_array(), pos.y.to_array(), pos.z.to_array(), q.to_array());
                for l in 0..LANES {
                    let clip = ClipVertex { pos: Vec3::new(x[l], y[l], z[l]), uv: uv(c * CHUNK + j * LANES + l) };
                    to_camera[l].write(ProjectedVertex { clip, q: q[l] });
                    to_screen[l].write(points[l]);
                }
            }
            let rest = to_camera[lanes..].iter_mut().zip(&mut to_screen[lanes..]).zip(&from[lanes..]);
            for (i, ((to_camera, to_screen), &p)) in rest.enumerate() {
                let clip = ClipVertex { pos: object_to_camera.transform_point3(p), uv: uv(c * CHUNK + lanes + i) };
                let (vertex, point) = self.project(clip);
                to_camera.write(vertex);
                to_screen.write(if inside_all(&self.planes, &clip.pos) { point } else { OUTSIDE });
            }
        });
        // SAFETY: the chunks tile the first n slots of both, and each slot of each chunk was written.
        unsafe {
            camera.set_len(n);
            screen.set_len(n);
        }
        ProjectedVertices { camera, screen }
    }

    /// `project` of eight camera-space points, with `OUTSIDE` for those outside a clip plane: their screen
    /// points and 1/w.
    #[inline(always)]
    fn project8(&self, pos: &V3) -> ([ScreenPoint; LANES], F8) {
        let inside = inside_all8(&self.planes, pos);
        let (sx, sy, q) = self.camera.project_exact8(pos);
        let (x, y) = (round_to_int(sx * F8::splat(SUBPIXEL as f32)), round_to_int(sy * F8::splat(SUBPIXEL as f32)));
        let outside = I8::splat(i32::MIN);
        let inside = to_bits(inside);
        let (x, y) = (inside.blend(x, outside).to_array(), inside.blend(y, outside).to_array());
        (std::array::from_fn(|l| [x[l], y[l]]), q)
    }

    /// The vertex in camera space and its screen point. Points behind the eye project to nonsense (the
    /// casts saturate), but their triangles take the clipping path and never use it. Inlined, so that the
    /// chunk loop of `project_vertices` stores each vertex in place.
    #[inline(always)]
    fn project(&self, clip: ClipVertex) -> (ProjectedVertex, ScreenPoint) {
        let (screen, q) = self.camera.project(clip.pos);
        let fixed = [(screen.x * SUBPIXEL as f32).round() as i32, (screen.y * SUBPIXEL as f32).round() as i32];
        (ProjectedVertex { clip, q }, fixed)
    }

    /// The triangles of a projected mesh set up. The frame counts and writes them in place instead
    /// (`count_triangles`, `write_triangles`); the tests take them whole.
    #[cfg(any(test, feature = "internals"))]
    pub fn triangles_of(&mut self, mesh: ProjectedMesh) -> Vec<ScreenTriangle> {
        let mut out = Vec::with_capacity(mesh.triangles.len());
        self.each_kept(mesh, 0..mesh.triangles.len(), false, |setup, tri, kept, _| out.push(setup.finish(tri, kept)));
        out
    }

    /// How many triangles of a projected mesh the setup keeps (clipped pieces counted one by one), and
    /// which of the mesh's triangles give any.
    pub fn count_triangles(&mut self, mesh: ProjectedMesh) -> Counted {
        let n = mesh.triangles.len();
        let mut counted = Counted::nothing_of(n);
        // Eight at a time on lanes where they decide exactly; the rest, and the tail, one by one.
        let screen = mesh.vertices.screen.as_flattened();
        let lanes = (screen.len() <= i32::MAX as usize).then(|| self.lane_cull(mesh.cull)).flatten();
        let whole = if lanes.is_some() { n / LANES * LANES } else { 0 };
        let mut rest = Vec::new();
        if let Some(lanes) = &lanes {
            for start in (0..whole).step_by(LANES) {
                // Eight triangles are a line and a half: two asks reach every line.
                prefetch(mesh.triangles, start + PREFETCH_AHEAD);
                prefetch(mesh.triangles, start + PREFETCH_AHEAD + LANES / 2);
                let (x, y) = LaneCull::corners(screen, &mesh.triangles[start..start + LANES]);
                let (mut kept, mut unsure) = lanes.keep8(x, y);
                // Along an outline the box widens by a margin: those are left to `keep`.
                if let Some(outline) = mesh.outline {
                    let along = outline[start..start + LANES].iter().enumerate();
                    let along = along.fold(0, |bits, (l, &o)| bits | u32::from(o != Outline::Inside) << l);
                    (kept, unsure) = (kept & !along, unsure | along);
                }
                counted.kept[start / 64] |= u64::from(kept) << (start % 64);
                counted.count += kept.count_ones() as usize;
                rest.extend(set_bits(&[u64::from(unsure)]).map(|l| start + l));
            }
        }
        self.each_kept(mesh, rest.into_iter().chain(whole..n), false, |_, _, _, k| counted.mark(k));
        counted
    }

    /// The lanes' count for this setup's screen and samples, and `cull`; none where the samples span too
    /// far for them.
    fn lane_cull(&self, cull: Cull) -> Option<LaneCull> {
        let size = [self.camera.width as i64, self.camera.height as i64];
        LaneCull::new(self.samples.axes, self.samples.shared, size, cull)
    }

    /// Writes into `out` the triangles of a projected mesh set up, which `count_triangles` counted to
    /// exactly `out.len()` (visiting only those it marked kept, not the culled ones again), and hands each
    /// to `written` with its index in `out`; panics where they are not as many.
    pub fn write_triangles(
        &mut self,
        mesh: ProjectedMesh,
        counted: &Counted,
        out: &mut [MaybeUninit<ScreenTriangle>],
        mut written: impl FnMut(usize, &ScreenTriangle),
    ) {
        let mut n = 0;
        self.each_kept(mesh, set_bits(&counted.kept), true, |setup, tri, kept, _| {
            let triangle = setup.finish(tri, kept);
            written(n, &triangle);
            // Past the caches: the whole set is far larger than they are, and is read only by the tiles.
            stream::store(&mut out[n], triangle);
            n += 1;
        });
        stream::fence();
        assert_eq!(n, out.len(), "triangle setup counted otherwise than it wrote");
    }

    /// Calls `visit` with each triangle among `which` (indices into the mesh's triangles) that the setup
    /// keeps (each piece of one that is clipped), what it keeps of it and its index; the triangle's
    /// vertices are read only where `visit` asks for them. With `counted`, those of `which` that need no
    /// clipping are known to cover a sample (the count tested them).
    fn each_kept(
        &mut self,
        mesh: ProjectedMesh,
        which: impl Iterator<Item = usize>,
        counted: bool,
        mut visit: impl FnMut(&Self, Found, Kept, usize),
    ) {
        let ProjectedMesh { vertices, triangles, surface, first, cull, outline } = mesh;
        let mut poly = std::mem::take(&mut self.polygon);
        for k in which {
            let outline = outline.map_or(Outline::Inside, |o| o[k]);
            let id = TriangleId { surface, triangle: first + k as u32, outline };
            // Indexed outright: arrays' `map` with closures was left as calls.
            let [a, b, c] = triangles[k].map(|v| v as usize);
            let points = [vertices.screen[a], vertices.screen[b], vertices.screen[c]];
            if !points.contains(&OUTSIDE) {
                if let Some(kept) = self.keep(points.map(|p| p.map(i64::from)), id, cull, !counted) {
                    visit(self, Found::Mesh { vertices, at: [a, b, c] }, kept, k);
                }
            } else {
                let tri = [vertices.camera[a], vertices.camera[b], vertices.camera[c]];
                self.each_clipped_piece(&tri, &mut poly, |piece| {
                    if let Some(kept) = self.keep(piece.points.map(|p| p.map(i64::from)), id, cull, true) {
                        visit(self, Found::Piece(piece), kept, k);
                    }
                });
            }
        }
        self.polygon = poly;
    }

    /// Calls `visit` with each piece of the triangle clipped to the frustum. Out of line: few triangles
    /// cross the frustum, and inlined into the loop over all of them, this code changed how that loop was
    /// compiled, and its speed, whenever unrelated code moved.
    #[cold]
    #[inline(never)]
    fn each_clipped_piece(
        &self,
        tri: &[ProjectedVertex; 3],
        poly: &mut Vec<ClipVertex>,
        mut visit: impl FnMut(Corners),
    ) {
        clip_polygon(&self.planes, &tri.map(|v| v.clip), poly);
        for p in 1..poly.len().saturating_sub(1) {
            let [(v0, f0), (v1, f1), (v2, f2)] = [poly[0], poly[p], poly[p + 1]].map(|c| self.project(c));
            visit(Corners { vertices: [&v0, &v1, &v2], points: [f0, f1, f2] });
        }
    }

    /// Whether the triangle with screen points `fixed` is kept (it covers some area, faces the way `cull`
    /// keeps, its box meets the screen, and where `test` it covers a sample), and if so its vertices' order
    /// and box.
    #[inline(always)]
    fn keep(&self, fixed: [[i64; 2]; 3], id: TriangleId, cull: Cull, test: bool) -> Option<Kept> {
        let area = edge_at(fixed[0], fixed[1], fixed[2]);
        if area == 0 {
            return None;
        }
        // Counter-clockwise in (u,v) faces along N; on a screen with y down that is a negative area
        // (a positive one when the object's transform mirrors it).
        if let Cull::FacingAway { mirrored } = cull {
            if (area > 0) != mirrored {
                return None;
            }
        }
        // Order the vertices so the area is positive and E >= 0 inside.
        let order = if area > 0 { [0, 1, 2] } else { [0, 2, 1] };
        let fx = order.map(|k| fixed[k]);
        // Along an outline the edges move out by a margin; they meet beyond the corners (far beyond at sharp
        // ones), and the box keeps what lies within the margin of the triangle, which is all the outline needs.
        let pad = if id.outline != Outline::Inside { OUTLINE_MARGIN_PX.ceil() as i64 * SUBPIXEL } else { 0 };
        let (w, h) = (self.camera.width as i64, self.camera.height as i64);
        // The pixels one of whose samples may lie within the triangle's extent on each axis: from the first
        // whose last sample reaches its least coordinate to the last whose first sample reaches its greatest.
        // An outline's edges, moved out, reach past its extent at sharp corners: it keeps every pixel that
        // meets the extent.
        let span = |d: usize, size: i64| {
            let [lo, hi] = if pad == 0 { self.samples.axes[d] } else { self.samples.reach };
            let least = fx.iter().map(|p| p[d]).min().unwrap_or(0) - pad;
            let most = fx.iter().map(|p| p[d]).max().unwrap_or(0) + pad;
            ((-(hi - least).div_euclid(SUBPIXEL)).max(0), (most - lo).div_euclid(SUBPIXEL).min(size - 1))
        };
        let ((minx, maxx), (miny, maxy)) = (span(0, w), span(1, h));
        if minx > maxx || miny > maxy {
            return None;
        }
        let bbox = [minx, miny, maxx, maxy];
        // A triangle of a few samples that covers none of them is dropped: most of a dense mesh's triangles
        // are smaller than a pixel, and many of those fall between the samples.
        if let Some(offsets) = self.samples.shared.filter(|_| test && pad == 0) {
            let pixels = (maxx - minx + 1) * (maxy - miny + 1);
            if pixels * offsets.len() as i64 <= TESTED_IN_SETUP && !covers_a_sample(&fx, bbox, offsets) {
                return None;
            }
        }
        Some(Kept { order, bbox, id })
    }

    /// The kept triangle's edge functions and planes.
    fn finish(&self, found: Found, kept: Kept) -> ScreenTriangle {
        let Kept { order, bbox, id } = kept;
        let tri = found.corners();
        // Indexed outright: arrays' `map` with closures was left as calls.
        let v = [tri.vertices[order[0]], tri.vertices[order[1]], tri.vertices[order[2]]];
        let fx = [order[0], order[1], order[2]].map(|k| tri.points[k].map(i64::from));
        let edges = edge_functions(&fx);
        let (mut slopes, mut offsets) = ([[0i32; 2]; 3], [0i64; 3]);
        for (e, &[ca, cb, c]) in edges.iter().enumerate() {
            debug_assert!(i32::try_from(ca).is_ok() && i32::try_from(cb).is_ok(), "edge slopes beyond 32 bits");
            (slopes[e], offsets[e]) = ([ca as i32, cb as i32], c);
            if id.outline != Outline::Inside {
                // Each edge moved out by the margin: E is the distance in subpixels times |(A, B)|.
                let margin = OUTLINE_MARGIN_PX as f64 * SUBPIXEL as f64 * ((ca * ca + cb * cb) as f64).sqrt();
                offsets[e] += margin.ceil() as i64;
            }
        }
        // Planes from the snapped positions, so interpolation agrees with coverage.
        let pos = std::array::from_fn(|k| fx[k].map(|c| c as f64 / SUBPIXEL as f64));
        let q = [v[0].q as f64, v[1].q as f64, v[2].q as f64];
        let perspective = self.camera.is_perspective();
        let depth_key = match perspective {
            true => q,
            false => [v[0].clip.pos.z as f64, v[1].clip.pos.z as f64, v[2].clip.pos.z as f64],
        };
        let basis = PlaneBasis::new(&pos);
        ScreenTriangle {
            slopes,
            offsets,
            bbox: bbox.map(|c| c as i32),
            origin: Vec2::new(pos[0][0] as f32, pos[0][1] as f32),
            depth: basis.plane(depth_key),
            b1: basis.plane([0.0, q[1], 0.0]),
            b2: basis.plane([0.0, 0.0, q[2]]),
            uv: [v[0].clip.uv, v[1].clip.uv, v[2].clip.uv],
            surface: id.surface,
            triangle: id.triangle,
            outline: id.outline,
            perspective,
        }
    }
}

/// What `count_triangles` found of a projected mesh: how many triangles the setup keeps, and a bit for each
/// of the mesh's triangles that gives any (bit i of word w: triangle 64 w + i).
pub struct Counted {
    pub count: usize,
    kept: Vec<u64>,
}

impl Counted {
    /// None kept yet of a mesh's `n` triangles.
    fn nothing_of(n: usize) -> Counted {
        Counted { count: 0, kept: vec![0; n.div_ceil(64)] }
    }

    /// Triangle `k` gives one triangle more.
    fn mark(&mut self, k: usize) {
        self.kept[k / 64] |= 1 << (k % 64);
        self.count += 1;
    }
}

/// `x.round() as i32` per lane (halves away from zero), for |x| below 2^31; other lanes are undefined.
#[inline(always)]
fn round_to_int(x: F8) -> I8 {
    let t = x.fast_trunc_int();
    // The fraction x - trunc(x) is exact in f32.
    let fraction = x - t.round_float();
    // A true mask is -1 as an integer.
    t - to_bits(fraction.cmp_ge(F8::splat(0.5))) + to_bits(fraction.cmp_le(F8::splat(-0.5)))
}

/// A triangle's three vertices and their screen points. By reference: copies of the vertices, read back at
/// once, stalled the store forwarding.
#[derive(Clone, Copy)]
struct Corners<'v> {
    vertices: [&'v ProjectedVertex; 3],
    points: [ScreenPoint; 3],
}

/// Where a kept triangle's corners are, read only when its planes are made: three vertices of the mesh,
/// or a piece of a clipped triangle.
enum Found<'v> {
    Mesh { vertices: &'v ProjectedVertices, at: [usize; 3] },
    Piece(Corners<'v>),
}

impl<'v> Found<'v> {
    #[inline(always)]
    fn corners(self) -> Corners<'v> {
        match self {
            Found::Mesh { vertices, at: [a, b, c] } => Corners {
                vertices: [&vertices.camera[a], &vertices.camera[b], &vertices.camera[c]],
                points: [vertices.screen[a], vertices.screen[b], vertices.screen[c]],
            },
            Found::Piece(corners) => corners,
        }
    }
}

/// What the setup keeps of a triangle before making its planes: the order of its vertices that makes its
/// area positive, its box in whole pixels (clipped to the screen) and its numbers.
#[derive(Clone, Copy)]
struct Kept {
    order: [usize; 3],
    bbox: [i64; 4],
    id: TriangleId,
}

/// The indices of the set bits of `words`, lowest first (bit i of word w is index 64 w + i).
fn set_bits(words: &[u64]) -> impl Iterator<Item = usize> + '_ {
    words.iter().enumerate().flat_map(|(w, &word)| {
        std::iter::successors(Some(word).filter(|&b| b != 0), |&b| Some(b & (b - 1)).filter(|&b| b != 0))
            .map(move |b| w * 64 + b.trailing_zeros() as usize)
    })
}

/// The most samples (pixels of its box times samples a pixel) a triangle's setup tests for coverage: more
/// are left to the rasterizer, which walks them anyway.
pub(super) const TESTED_IN_SETUP: i64 = 4;

/// How many triangles ahead the lanes' count asks the cache for the indices: they stream from memory, and
/// the count waited on them for a third of its time (about 2 KB ahead, 0.5 ms of 2.5 a million triangles).
const PREFETCH_AHEAD: usize = 192;

/// The edge functions E = A x + B y + C of a triangle with positive area (fixed point), E >= 0 inside, with
/// the fill rule in C: a sample exactly on an edge belongs to the triangle for which (A, B) points "right or
/// down"; the neighbour across the edge has (-A, -B), so exactly one of the two owns it.
#[inline(always)]
fn edge_functions(fx: &[[i64; 2]; 3]) -> [[i64; 3]; 3] {
    // Indexed outright: arrays' `map` with closures was left as calls.
    let edge = |pa: [i64; 2], pb: [i64; 2]| {
        let (ca, cb) = (-(pb[1] - pa[1]), pb[0] - pa[0]);
        let bias = if ca > 0 || (ca == 0 && cb > 0) { 0 } else { -1 };
        [ca, cb, bias - (ca * pa[0] + cb * pa[1])]
    };
    [edge(fx[1], fx[2]), edge(fx[2], fx[0]), edge(fx[0], fx[1])]
}

/// Whether the triangle of `edges` (`edge_functions`) covers the sample at `offset` (fixed point) in pixel
/// (x, y): what the rasterizer's walk over the pixels (`visibility::cover`) finds there.
#[inline(always)]
pub fn covers_sample(edges: &[[i64; 3]; 3], (x, y): (i64, i64), offset: [i64; 2]) -> bool {
    let (sx, sy) = (x * SUBPIXEL + offset[0], y * SUBPIXEL + offset[1]);
    let at = |e: &[i64; 3]| e[0] * sx + e[1] * sy + e[2];
    at(&edges[0]) | at(&edges[1]) | at(&edges[2]) >= 0
}

/// Whether the triangle (vertices in fixed point, positive area) covers a sample of the pixels of `bbox`,
/// each with the same `offsets`.
#[inline(always)]
fn covers_a_sample(fx: &[[i64; 2]; 3], [minx, miny, maxx, maxy]: [i64; 4], offsets: &[[i64; 2]]) -> bool {
    let edges = edge_functions(fx);
    // Loops, not nested `any`: their closures were left as calls in the setup's hot loop.
    for y in miny..=maxy {
        for x in minx..=maxx {
            for &o in offsets {
                if covers_sample(&edges, (x, y), o) {
                    return true;
                }
            }
        }
    }
    false
}

/// The edge function of a-b at p (twice the signed area of a, b, p), in fixed point.
#[inline]
fn edge_at(a: [i64; 2], b: [i64; 2], p: [i64; 2]) -> i64 {
    (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])
}

/// Screen-space geometry of a triangle, relative to its first vertex, for fitting affine attributes.
struct PlaneBasis {
    x1: f64,
    y1: f64,
    x2: f64,
    y2: f64,
    inv_det: f64,
}

impl PlaneBasis {
    fn new(p: &[[f64; 2]; 3]) -> PlaneBasis {
        let (x1, y1) = (p[1][0] - p[0][0], p[1][1] - p[0][1]);
        let (x2, y2) = (p[2][0] - p[0][0], p[2][1] - p[0][1]);
        PlaneBasis { x1, y1, x2, y2, inv_det: 1.0 / (x1 * y2 - x2 * y1) }
    }

    /// The affine function with values `a` at the three points, relative to the first.
    fn plane(&self, a: [f64; 3]) -> Plane {
        let (a1, a2) = (a[1] - a[0], a[2] - a[0]);
        Plane {
            a0: a[0] as f32,
            ax: ((a1 * self.y2 - a2 * self.y1) * self.inv_det) as f32,
            ay: ((self.x1 * a2 - self.x2 * a1) * self.inv_det) as f32,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn set_bits_are_the_indices_of_the_ones() {
        let words = [0b1011u64, 0, 1 << 63, u64::MAX];
        let want: Vec<usize> = [0, 1, 3, 191].into_iter().chain(192..256).collect();
        assert_eq!(set_bits(&words).collect::<Vec<_>>(), want);
        assert_eq!(set_bits(&[]).count(), 0);
    }

    /// Lanes round to the nearest integer as `f32::round` does, halves away from zero.
    #[test]
    fn lanes_round_halves_away_from_zero() {
        let values = [0.5, 1.5, -0.5, -1.5, 2.5, -2.5, 0.49999997, -0.49999997, 1e6 + 0.5, -8388607.5, 3.0, 0.0];
        for eight in values.chunks(LANES) {
            let lanes = F8::new(std::array::from_fn(|l| eight.get(l).copied().unwrap_or(0.0)));
            let got = round_to_int(lanes).to_array();
            for (l, &v) in eight.iter().enumerate() {
                assert_eq!(got[l], v.round() as i32, "{v}");
            }
        }
    }

    /// Vertices projected eight at a time on lanes give the bits of `project` one by one, in perspective
    /// and orthographically: points inside, outside the clip planes and behind the eye, and the tail after
    /// the last whole eight.
    #[test]
    fn vertices_project_on_lanes_as_one_by_one() {
        use super::super::camera::Projection;
        let pattern = SamplePattern::centre();
        let positions: Vec<Vec3> = (0..203)
            .map(|i| {
                let t = i as f32 * 0.618_034;
                Vec3::new((t * 7.3).sin() * 3.0, (t * 3.1).cos() * 2.0, (t * 1.7).sin() * 6.0)
            })
            .collect();
        for projection in [Projection::Perspective { fov_y: 40.0 }, Projection::Orthographic { height: 4.0 }] {
            let camera = Camera::new(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, Vec3::Y, projection, 640, 360);
            let setup = TriangleSetup::new(&camera, &pattern);
            let uvs: Vec<Vec2> = (0..positions.len()).map(|i| Vec2::new(i as f32, -(i as f32))).collect();
            let to_camera = camera.world_to_camera;
            let projected = setup.project_vertices(&positions, Some(&uvs), &to_camera);
            let mut outside = 0;
            for (k, &p) in positions.iter().enumerate() {
                let clip = ClipVertex { pos: to_camera.transform_point3(p), uv: uvs[k] };
                let (vertex, point) = setup.project(clip);
                let point = if inside_all(&setup.planes, &clip.pos) { point } else { OUTSIDE };
                outside += (point == OUTSIDE) as usize;
                let got = &projected.camera[k];
                assert_eq!(got.clip.pos.to_array().map(f32::to_bits), clip.pos.to_array().map(f32::to_bits), "{k}");
                assert_eq!((got.clip.uv, got.q.to_bits()), (vertex.clip.uv, vertex.q.to_bits()), "vertex {k}");
                assert_eq!(projected.screen[k], point, "vertex {k}");
            }
            assert!(outside > 10 && outside < positions.len() - 10, "{outside} outside");
        }
    }

    /// The count on lanes keeps exactly the triangles `keep` keeps one by one: tiny, small, large and
    /// degenerate triangles, some behind the eye or beyond the frustum, both facings, outline triangles,
    /// every cull, in perspective and orthographically, for samples the lanes test (one, two and four a
    /// pixel), samples beyond their test (sixteen), each pixel's own (Sobol) and a wide pixel filter.
    #[test]
    fn lanes_count_the_triangles_keep_keeps() {
        use super::super::camera::Projection;
        use super::super::samples::{PixelFilter, Sampler};
        let mut seed = 0x2545_f491_u32;
        let mut random = move || {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            seed as f32 / u32::MAX as f32
        };
        // Triangles about a random point, of a random size from a hundredth of a pixel to 200 pixels (on
        // this screen about 100 pixels a unit at the origin), their corners shared now and then.
        let mut positions = Vec::new();
        let mut triangles = Vec::new();
        for t in 0..6000u32 {
            let centre = Vec3::new(random() * 8.0 - 4.0, random() * 4.5 - 2.25, random() * 7.0 - 4.5);
            let size = 10f32.powf(random() * 4.3 - 4.0);
            let base = positions.len() as u32;
            for _ in 0..3 {
                let corner = Vec3::new(random() - 0.5, random() - 0.5, random() - 0.5);
                positions.push(centre + corner * size);
            }
            triangles.push(match t % 11 {
                // A corner of the last triangle's, or a corner twice (no area).
                5 if t > 0 => [base - 1, base, base + 1],
                7 => [base, base + 1, base],
                _ => [base, base + 1, base + 2],
            });
        }
        let outline: Vec<Outline> = (0..triangles.len())
            .map(|k| [Outline::Inside, Outline::Inside, Outline::Inside, Outline::Edge, Outline::Fold][k % 5])
            .collect();
        let patterns = [
            SamplePattern::centre(),
            SamplePattern::new(2, Sampler::Stratified, PixelFilter::default()).unwrap(),
            SamplePattern::new(4, Sampler::Stratified, PixelFilter::default()).unwrap(),
            SamplePattern::new(16, Sampler::Stratified, PixelFilter::default()).unwrap(),
            SamplePattern::new(4, Sampler::Sobol, PixelFilter::default()).unwrap(),
            SamplePattern::new(4, Sampler::Stratified, PixelFilter::Gaussian { radius: 1.5, sigma: 0.5 }).unwrap(),
        ];
        let culls = [Cull::Nothing, Cull::FacingAway { mirrored: false }, Cull::FacingAway { mirrored: true }];
        for projection in [Projection::Perspective { fov_y: 50.0 }, Projection::Orthographic { height: 4.5 }] {
            let camera = Camera::new(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, Vec3::Y, projection, 640, 360);
            for pattern in &patterns {
                let mut setup = TriangleSetup::new(&camera, pattern);
                assert!(setup.lane_cull(Cull::Nothing).is_some(), "the lanes count for {:?}", pattern.count());
                let vertices = setup.project_vertices(&positions, None, &camera.world_to_camera);
                for cull in culls {
                    for outline in [None, Some(&outline[..])] {
                        let mesh = ProjectedMesh {
                            vertices: &vertices,
                            triangles: &triangles,
                            surface: 0,
                            first: 0,
                            cull,
                            outline,
                        };
                        let mut one_by_one = Counted::nothing_of(triangles.len());
                        setup.each_kept(mesh, 0..triangles.len(), false, |_, _, _, k| one_by_one.mark(k));
                        let on_lanes = setup.count_triangles(mesh);
                        assert_eq!(on_lanes.count, one_by_one.count, "{} spp, {cull:?}", pattern.count());
                        assert!(on_lanes.kept == one_by_one.kept, "{} spp, {cull:?}: other triangles", pattern.count());
                        let kept = set_bits(&one_by_one.kept).count();
                        assert!(kept > 500 && kept < 5700, "{kept} of 6000 kept");
                    }
                    // The lanes decide most triangles themselves.
                    let lanes = setup.lane_cull(cull).unwrap();
                    let screen = vertices.screen.as_flattened();
                    let left: u32 = triangles
                        .chunks_exact(LANES)
                        .map(|eight| {
                            let (x, y) = LaneCull::corners(screen, eight);
                            lanes.keep8(x, y).1.count_ones()
                        })
                        .sum();
                    assert!(left > 100 && left < 1500, "{left} of 6000 left to keep");
                }
            }
        }
    }

    #[test]
    fn plane_reproduces_vertex_values() {
        let p = [[1.0, 2.0], [11.0, 3.0], [4.0, 9.0]];
        let pl = PlaneBasis::new(&p).plane([0.5, 2.0, -1.0]);
        for (k, v) in [0.5f32, 2.0, -1.0].iter().enumerate() {
            let got = pl.at((p[k][0] - p[0][0]) as f32, (p[k][1] - p[0][1]) as f32);
            assert!((got - v).abs() < 1e-5);
        }
    }
}
