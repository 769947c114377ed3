//! Dicing for displacement mapping (Lingard): the triangles of a coarse base tessellation are cut into
//! triangles about a pixel across, and every vertex is moved along the surface's normal by its height.
//!
//! Crack-free by construction. Each base edge gets one rate (its length on screen over the target edge
//! length), worked out once, so the triangles on either side cut it at the same points; a triangle's inner
//! grid takes its longest edge's rate and snaps its border onto its edges' points. Positions belong to
//! welded vertices (corners that are one point: a seam, a pole, a mesh's split vertices, the shared sides
//! of a box's faces), and a welded vertex's height and direction are the mean over the triangles around it,
//! so all of them move it to the same place. Attributes ((u,v), normals) belong to the base's own vertices,
//! so a texture seam keeps both of its sides.

use glam::{Vec2, Vec3};
use rayon::prelude::*;
use rustc_hash::FxHashMap;

/// The most cuts of one base edge.
pub const MAX_RATE: u32 = 1024;

/// How far (pixels) an uncut edge where F is uniform may stray from the surface: half the sag the base's
/// own edges are allowed, so that an edge sagging that much, moved outwards, is cut in two.
const OFFSET_SAG_PX: f32 = 0.125;

/// A point of the base: its triangle and its barycentric weights on the triangle's three corners.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BasePoint {
    pub triangle: u32,
    pub bary: [f32; 3],
}

/// The surface under the base at one point, as the dicer needs it.
#[derive(Clone, Copy, Debug, Default)]
pub struct DiceSample {
    /// The undisplaced point (object space).
    pub p: Vec3,
    /// The unit direction of the displacement.
    pub normal: Vec3,
    /// How far the point moves along `normal`.
    pub height: f32,
    /// Why the surface here needs no dicing, as bits (`Skip`); an edge whose points share one is left whole.
    pub skip: u8,
    /// For a point with reasons of facing (`Skip::FACING`): how far N.V may change (as the normal turns)
    /// with all of them still holding; 0 without such reasons.
    pub clearance: f32,
}

/// Reasons a point needs no dicing, as bits of `DiceSample::skip`.
pub struct Skip;

impl Skip {
    /// Not displaced (silhouette mode away from the outline).
    pub const FLAT: u8 = 1;
    /// On a culled surface, facing away well beyond the outline.
    pub const FACING_AWAY: u8 = 2;
    /// Off the screen past its left, right, top or bottom side (by a margin).
    pub const LEFT: u8 = 4;
    pub const RIGHT: u8 = 8;
    pub const TOP: u8 = 16;
    pub const BOTTOM: u8 = 32;
    /// The reasons that depend on which way the surface faces.
    pub const FACING: u8 = Skip::FLAT | Skip::FACING_AWAY;
    /// The reasons that depend on where the point is on the screen.
    pub const OFF_SCREEN: u8 = Skip::LEFT | Skip::RIGHT | Skip::TOP | Skip::BOTTOM;
}

/// What the dicer reads of the surface under its base triangles.
pub trait DiceSurface: Sync {
    fn sample(&self, at: BasePoint) -> DiceSample;
    /// `sample` at each of `at`, into `out` (as long): a surface may sample several points together.
    fn sample_into(&self, at: &[BasePoint], out: &mut [DiceSample]) {
        for (out, &at) in out.iter_mut().zip(at) {
            *out = self.sample(at);
        }
    }
    /// Where an object-space point lands on the screen (pixels), if it is in front of the eye.
    fn screen(&self, p: Vec3) -> Option<Vec2>;
    /// Screen pixels per object-space unit near an object-space point (0 behind the eye).
    fn pixels_per_unit(&self, p: Vec3) -> f32;
    /// Whether F is certainly one value all over the part of the base spanned by `points` (an edge's ends,
    /// a face's corners): there the surface moves only as far as its samples' heights differ (silhouette
    /// mode's blend), and needs no cuts of its own for F. False where it cannot tell.
    fn uniform(&self, _points: &[BasePoint]) -> bool {
        false
    }
}

/// How long a curve through `points` (at most three) is on screen (pixels): measured on screen where all of
/// them are in front of the eye, else in the object at the largest scale of those that are.
fn screen_length(surface: &impl DiceSurface, points: &[Vec3]) -> f32 {
    debug_assert!(points.len() <= 3);
    let mut on_screen = [Vec2::ZERO; 3];
    let seen = points.iter().zip(&mut on_screen).all(|(&p, s)| surface.screen(p).map(|at| *s = at).is_some());
    let length = |v: &[Vec2]| v.windows(2).map(|w| w[0].distance(w[1])).sum::<f32>();
    if seen {
        return length(&on_screen[..points.len()]);
    }
    let ppu = points.iter().map(|&p| surface.pixels_per_unit(p)).fold(0.0, f32::max);
    points.windows(2).map(|w| w[0].distance(w[1])).sum::<f32>() * ppu
}

/// The base to dice: faces over vertices, each vertex also known by its welded number.
pub struct Base<'a> {
    pub faces: &'a [Face],
    /// Per vertex, its welded number: vertices at one point share it.
    pub weld: &'a [u32],
    /// The number of welded vertices.
    pub welded: usize,
}

/// A face of the base: a triangle, or a quad (a cell of a parametric surface's grid, diced with a rate of
/// its own along each direction, so a cell seen edge-on is not cut finely across) made of two triangles.
/// Points on it are named by the base triangles they lie in, which carry the attributes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Face {
    /// Counter-clockwise; a triangle's fourth is unused.
    pub corners: [u32; 4],
    pub sides: u8,
    /// Its base triangle: a triangle's own corners; for a quad [a, b, c, d], [a, b, c] and the next one
    /// [a, c, d].
    pub triangle: u32,
}

impl Face {
    pub fn triangle(corners: [u32; 3], triangle: u32) -> Face {
        let [a, b, c] = corners;
        Face { corners: [a, b, c, c], sides: 3, triangle }
    }

    pub fn quad(corners: [u32; 4], first_triangle: u32) -> Face {
        Face { corners, sides: 4, triangle: first_triangle }
    }

    /// Corner `k` (`sides` is corner 0 again).
    fn corner(&self, k: usize) -> u32 {
        let sides = self.sides as usize;
        self.corners[if k >= sides { k - sides } else { k }]
    }

    /// The base point at (s, t): a triangle's point with weights (1 - s - t, s, t) on its corners; a quad's
    /// at s along a -> b and t along a -> d.
    fn point(&self, s: f32, t: f32) -> BasePoint {
        match self.sides {
            3 => BasePoint { triangle: self.triangle, bary: [1.0 - s - t, s, t] },
            _ if s >= t => BasePoint { triangle: self.triangle, bary: [1.0 - s, s - t, t] },
            _ => BasePoint { triangle: self.triangle + 1, bary: [1.0 - t, s, t - s] },
        }
    }

    /// The base point `x` of the way along edge `k`, from corner k to the next.
    fn on_edge(&self, k: u8, x: f32) -> BasePoint {
        let (s, t) = match (self.sides, k) {
            (3, 0) | (4, 0) => (x, 0.0),
            (3, 1) => (1.0 - x, x),
            (3, _) => (0.0, 1.0 - x),
            (_, 1) => (1.0, x),
            (_, 2) => (1.0 - x, 1.0),
            _ => (0.0, 1.0 - x),
        };
        self.point(s, t)
    }

    fn at_corner(&self, k: u8) -> BasePoint {
        self.on_edge(k, 0.0)
    }
}

/// The diced surface: vertices (displaced positions and the base point each one's attributes come from)
/// and triangles over them, counter-clockwise like the base.
#[derive(Clone, Debug, Default)]
pub struct Diced {
    pub positions: Vec<Vec3>,
    pub sources: Vec<BasePoint>,
    pub triangles: Vec<[u32; 3]>,
    /// Per triangle, the base face it was cut from.
    pub origins: Vec<u32>,
}

/// An edge of the base, as a pair of vertex numbers, smaller first.
type EdgeKey = (u32, u32);

fn key(a: u32, b: u32) -> EdgeKey {
    (a.min(b), a.max(b))
}

/// Numbers the edges of `faces` (over vertex numbers `of`): each face's edges k -> k+1, the edges' ends,
/// and their first two faces as (face, edge within it).
struct Edges {
    of_face: Vec<[u32; 4]>,
    ends: Vec<EdgeKey>,
    users: Vec<[(u32, u8); 2]>,
}

impl Edges {
    /// The edges of faces `chosen` (ascending); the other faces have none (their `of_face` is unused).
    fn new(faces: &[Face], chosen: &[usize], of: impl Fn(u32) -> u32) -> Edges {
        let sides = 4 * chosen.len();
        let mut index: FxHashMap<EdgeKey, u32> = FxHashMap::with_capacity_and_hasher(sides, Default::default());
        let mut edges = Edges {
            of_face: vec![[0; 4]; faces.len()],
            ends: Vec::with_capacity(sides),
            users: Vec::with_capacity(sides),
        };
        for &f in chosen {
            let face = &faces[f];
            for k in 0..face.sides as usize {
                let ends = key(of(face.corner(k)), of(face.corner(k + 1)));
                let user = (f as u32, k as u8);
                let id = *index.entry(ends).or_insert_with(|| {
                    edges.ends.push(ends);
                    edges.users.push([user; 2]);
                    edges.ends.len() as u32 - 1
                });
                edges.of_face[f][k] = id;
                let users = &mut edges.users[id as usize];
                if users[0] != user {
                    users[1] = user;
                }
            }
        }
        edges
    }
}

/// The mean of samples of one point seen from several faces: the first one's point, the mean height and
/// direction, and the reasons to skip it they all share, with the least clearance.
fn mean(samples: impl Iterator<Item = DiceSample>) -> DiceSample {
    let (mut first, mut normal, mut height, mut count) = (None, Vec3::ZERO, 0.0, 0.0);
    for s in samples {
        let f = first.get_or_insert(s);
        f.skip &= s.skip;
        f.clearance = f.clearance.min(s.clearance);
        normal += s.normal;
        height += s.height;
        count += 1.0;
    }
    let first = first.expect("a point of at least one face");
    DiceSample { normal: normal.normalize_or_zero(), height: height / count, ..first }
}

fn displaced(s: &DiceSample) -> Vec3 {
    s.p + s.normal * s.height
}

/// The inner grid of a face: a triangle's n cuts along every side, a quad's (along a -> b, along a -> d).
fn grid_of(face: &Face, rates: [u32; 4]) -> (u32, u32) {
    match face.sides {
        3 => {
            let n = rates[..3].iter().copied().max().unwrap_or(1);
            (n, n)
        }
        _ => (rates[0].max(rates[2]), rates[1].max(rates[3])),
    }
}

/// Dices `base` so that edges are about `edge_px` pixels long on screen where the surface is displaced and
/// may be seen (single base edges elsewhere). Refuses (naming the count) to make more than `max_triangles`.
pub fn dice(base: &Base, surface: &impl DiceSurface, edge_px: f32, max_triangles: usize) -> Result<Diced, usize> {
    let faces = base.faces;
    let weld = |v: u32| base.weld[v as usize];
    // Faces with fewer than three corners at distinct points (a pole's triangles) cover nothing.
    let alive: Vec<bool> = faces
        .par_iter()
        .map(|f| {
            let w = &f.corners.map(weld)[..f.sides as usize];
            let distinct = (0..w.len()).filter(|&k| !w[..k].contains(&w[k])).count();
            distinct >= 3
        })
        .collect();
    // The faces around each welded vertex, as (face, corner within it): vertex w's are
    // `users[starts[w]..starts[w + 1]]`.
    let mut starts = vec![0u32; base.welded + 1];
    for (face, _) in faces.iter().zip(&alive).filter(|&(_, &alive)| alive) {
        for k in 0..face.sides as usize {
            starts[weld(face.corner(k)) as usize + 1] += 1;
        }
    }
    for w in 0..base.welded {
        starts[w + 1] += starts[w];
    }
    let mut users = vec![(0u32, 0u8); starts[base.welded] as usize];
    let mut next = starts.clone();
    // Each base vertex is sampled once, from the first face corner at it: `used` in the order of first use.
    let (mut is_used, mut used) = (vec![false; base.weld.len()], Vec::with_capacity(base.weld.len()));
    for (f, face) in faces.iter().enumerate().filter(|&(f, _)| alive[f]) {
        for k in 0..face.sides {
            let v = face.corner(k as usize);
            let w = weld(v) as usize;
            users[next[w] as usize] = (f as u32, k);
            next[w] += 1;
            if !std::mem::replace(&mut is_used[v as usize], true) {
                used.push((w as u32, (f as u32, k)));
            }
        }
    }
    // A welded vertex's sample is the mean over its base vertices in that order: vertex w's are
    // `seen[first[w]..first[w + 1]]`.
    let mut first = vec![0usize; base.welded + 1];
    for &(w, _) in &used {
        first[w as usize + 1] += 1;
    }
    for w in 0..base.welded {
        first[w + 1] += first[w];
    }
    let (mut at, mut ordered) = (first.clone(), vec![(0u32, 0u8); used.len()]);
    for (w, corner) in used {
        ordered[at[w as usize]] = corner;
        at[w as usize] += 1;
    }
    let points: Vec<BasePoint> = ordered.par_iter().map(|&(f, k)| faces[f as usize].at_corner(k)).collect();
    let seen = sample_all(surface, &points);
    // A vertex on faces left out only is never one of the result.
    let corners: Vec<DiceSample> = first
        .par_windows(2)
        .map(|r| if r[0] == r[1] { DiceSample::default() } else { mean(seen[r[0]..r[1]].iter().copied()) })
        .collect();
    // Faces left whole by their corners alone go straight to the output; only the others (the band that
    // is diced, and its neighbours) have their edges numbered, measured and cut. Per face: whether it is
    // whole, and (where that took asking) whether F is uniform over it.
    let (whole, uniform): (Vec<bool>, Vec<bool>) = faces
        .par_iter()
        .zip(&alive)
        .map(|(face, &alive)| {
            let at = |k: usize| &corners[weld(face.corners[k]) as usize];
            let corners = &[at(0), at(1), at(2), at(3)][..face.sides as usize];
            if !alive || is_whole(corners) {
                return (alive, false);
            }
            let uniform = surface.uniform(&[0, 1, 2, 3].map(|k| face.at_corner(k))[..face.sides as usize]);
            (uniform && is_offset(surface, corners), uniform)
        })
        .unzip();
    let cut: Vec<bool> = alive.iter().zip(&whole).map(|(&alive, &whole)| alive && !whole).collect();
    // Positions: welded vertices and welded edges, each sampled from every face around it; attributes:
    // the base's own vertices and edges.
    let cut_faces: Vec<usize> = (0..faces.len()).filter(|&f| cut[f]).collect();
    let (welded_edges, edges) =
        rayon::join(|| Edges::new(faces, &cut_faces, weld), || Edges::new(faces, &cut_faces, |v| v));
    let rate_of = |px: f32| if px.is_finite() { (px / edge_px).ceil().clamp(1.0, MAX_RATE as f32) as u32 } else { 1 };
    // An edge of a whole face keeps its ends alone on the other side too (found among the faces around its
    // smaller end); the others are sampled at their middle.
    let shares_whole = |&(a, b): &EdgeKey| {
        users[starts[a as usize] as usize..starts[a as usize + 1] as usize].iter().any(|&(f, k)| {
            let face = &faces[f as usize];
            let k = k as usize;
            whole[f as usize] && (weld(face.corner(k + 1)) == b || weld(face.corner(k + face.sides as usize - 1)) == b)
        })
    };
    let kept_whole: Vec<bool> = welded_edges.ends.par_iter().map(shares_whole).collect();
    let middles: Vec<BasePoint> = welded_edges
        .users
        .iter()
        .zip(&kept_whole)
        .filter(|(_, &kept)| !kept)
        .map(|(&[(f, k), _], _)| faces[f as usize].on_edge(k, 0.5))
        .collect();
    let middles = sample_all(surface, &middles);
    let mut middle_of = Vec::with_capacity(welded_edges.ends.len());
    let mut next_middle = 0;
    for &kept in &kept_whole {
        middle_of.push(next_middle);
        next_middle += usize::from(!kept);
    }
    // Per welded edge, the cuts it gets, and the cuts it would get if F varied along it (what a face across
    // which F varies takes).
    let rates: Vec<(u32, u32)> = welded_edges
        .ends
        .par_iter()
        .zip(&welded_edges.users)
        .zip(middle_of.par_iter().zip(&kept_whole))
        .map(|((ends, &[(f, k), _]), (&middle, &kept))| {
            if kept {
                return (1, 1);
            }
            let (a, b) = (&corners[ends.0 as usize], &corners[ends.1 as usize]);
            let face = &faces[f as usize];
            let mid = middles[middle];
            // All three off the same side of the screen, all facing away, or all flat: the faces on both
            // sides are left whole along it (a face whose edges are all out on one side lies out there).
            if a.skip & b.skip & mid.skip != 0 {
                return (1, 1);
            }
            // On screen, so that edges seen edge-on (near the outline, where silhouette mode dices) are cut
            // as finely as they show, not as long as they are.
            let along = screen_length(surface, &[a.p, mid.p, b.p]);
            let chord = screen_length(surface, &[displaced(a), displaced(b)]);
            let full = rate_of(along.max(chord));
            // Where F is one value the edge is the base's, moved: cut only as far as its ends move apart
            // and as its middle strays from their chord (a chord sags by a quarter for each halving).
            if !surface.uniform(&[face.at_corner(k), face.on_edge(k, 1.0)]) {
                return (full, full);
            }
            let (da, db) = (displaced(a), displaced(b));
            let sag = screen_length(surface, &[displaced(&mid), 0.5 * (da + db)]);
            let apart = rate_of((a.height - b.height).abs() * surface.pixels_per_unit(mid.p));
            let bend = (sag / OFFSET_SAG_PX).sqrt().ceil();
            let bend = if bend.is_finite() { bend.clamp(1.0, MAX_RATE as f32) as u32 } else { 1 };
            (apart.max(bend).min(full), full)
        })
        .collect();
    let grids: Vec<(u32, u32)> = faces
        .par_iter()
        .zip(&welded_edges.of_face)
        .zip(cut.par_iter().zip(&whole).zip(&uniform))
        .map(|((face, e), ((&cut, &whole), &uniform))| match (cut, whole, uniform) {
            (true, _, true) => grid_of(face, e.map(|e| rates[e as usize].0)),
            (true, _, false) => grid_of(face, e.map(|e| rates[e as usize].1)),
            (false, true, _) => (1, 1),
            (false, false, _) => (0, 0),
        })
        .collect();
    let count: u64 = faces
        .iter()
        .zip(&grids)
        .map(|(f, &(n, m))| u64::from(n) * u64::from(m) * if f.sides == 3 { 1 } else { 2 })
        .sum();
    if count > max_triangles as u64 {
        return Err(count.min(usize::MAX as u64) as usize);
    }
    // The points along each welded edge, from its smaller welded end: edge e's are
    // `edge_points[edge_start[e]..edge_start[e + 1]]`, each sampled from both of its users (the mean)
    // unless they share the base's own edge.
    let own_edge = |&(f, k): &(u32, u8)| {
        let face = &faces[f as usize];
        key(face.corner(k as usize), face.corner(k as usize + 1))
    };
    let (mut edge_start, mut seen_from, mut points) = (Vec::with_capacity(rates.len() + 1), Vec::new(), Vec::new());
    for ((&(a, _), users), &(rate, _)) in welded_edges.ends.iter().zip(&welded_edges.users).zip(&rates) {
        edge_start.push(seen_from.len());
        let alike = own_edge(&users[0]) == own_edge(&users[1]);
        for j in 1..rate {
            let s = j as f32 / rate as f32;
            seen_from.push(points.len());
            for &(f, k) in users.iter().take(if alike { 1 } else { 2 }) {
                // The user's edge runs from its corner k; the points run from the smaller end.
                let face = &faces[f as usize];
                let forward = weld(face.corner(k as usize)) == a;
                points.push(face.on_edge(k, if forward { s } else { 1.0 - s }));
            }
        }
    }
    edge_start.push(seen_from.len());
    seen_from.push(points.len());
    let seen = sample_all(surface, &points);
    let edge_points: Vec<Vec3> =
        seen_from.par_windows(2).map(|r| displaced(&mean(seen[r[0]..r[1]].iter().copied()))).collect();
    // Vertices: the base's own (at their welded position), then the points of its own edges, then each
    // face's inner points.
    let mut diced = Diced {
        positions: Vec::with_capacity(count as usize),
        sources: Vec::with_capacity(count as usize),
        triangles: Vec::with_capacity(count as usize),
        origins: Vec::with_capacity(count as usize),
    };
    diced.positions.extend((0..base.weld.len()).map(|v| displaced(&corners[weld(v as u32) as usize])));
    diced.sources.resize(base.weld.len(), BasePoint { triangle: 0, bary: [1.0, 0.0, 0.0] });
    for (face, _) in faces.iter().zip(&alive).filter(|(_, &alive)| alive) {
        for k in 0..face.sides {
            diced.sources[face.corner(k as usize) as usize] = face.at_corner(k);
        }
    }
    let mut edge_first = Vec::with_capacity(edges.ends.len());
    for (e, &(a, b)) in edges.ends.iter().enumerate() {
        edge_first.push(diced.positions.len() as u32);
        let [(f, k), _] = edges.users[e];
        let face = &faces[f as usize];
        let w = welded_edges.of_face[f as usize][k as usize] as usize;
        let points = &edge_points[edge_start[w]..edge_start[w + 1]];
        // This edge runs from vertex a; the welded points run from the smaller welded end.
        let same_way = weld(a) == welded_edges.ends[w].0 || weld(a) == weld(b);
        let forward = face.corner(k as usize) == a;
        let rate = rates[w].0;
        for j in 1..rate {
            let s = j as f32 / rate as f32;
            diced.positions.push(points[if same_way { j - 1 } else { rate - j - 1 } as usize]);
            diced.sources.push(face.on_edge(k, if forward { s } else { 1.0 - s }));
        }
    }
    // The inner points and triangles of each face, in parallel, numbered afterwards.
    let shared = &diced.positions;
    // Each face's inner points, where they come from, and its triangles.
    type FacePart = (Vec<Vec3>, Vec<BasePoint>, Vec<[u32; 3]>);
    // Each worker keeps its grid's numbers, row starts and samples from face to face.
    type Scratch = (Vec<u32>, Vec<usize>, Vec<DiceSample>);
    let parts: Vec<FacePart> = cut_faces
        .par_iter()
        .map_init(Scratch::default, |(ids, starts, samples), &f| {
            let (n, m) = grids[f];
            let face = &faces[f];
            let (own, welded) = (edges.of_face[f], welded_edges.of_face[f]);
            let quad = face.sides == 4;
            let mut sources = Vec::new();
            // Grid vertex (i, j) lies at (i / n, j / m) in the face's (s, t). Inner ones are numbered from
            // u32::MAX downwards until the face's first inner vertex is known.
            ids.clear();
            starts.clear();
            for j in 0..=m {
                starts.push(ids.len());
                let last = if quad { n } else { n - j };
                for i in 0..=last {
                    // The side the point lies on, and how far along it (in grid steps, of how many).
                    let side = match (quad, i, j) {
                        (_, _, 0) => Some((0, i, n)),
                        (true, _, _) if i == n => Some((1, j, m)),
                        (true, _, _) if j == m => Some((2, n - i, n)),
                        (true, 0, _) => Some((3, m - j, m)),
                        (false, _, _) if i + j == n => Some((1, j, n)),
                        (false, 0, _) => Some((2, n - j, n)),
                        _ => None,
                    };
                    let id = match side {
                        Some((k, s, of)) => snapped(
                            face,
                            k,
                            s,
                            of,
                            rates[welded[k] as usize].0,
                            edges.ends[own[k] as usize],
                            edge_first[own[k] as usize],
                        ),
                        None => {
                            sources.push(face.point(i as f32 / n as f32, j as f32 / m as f32));
                            u32::MAX - (sources.len() as u32 - 1)
                        }
                    };
                    ids.push(id);
                }
            }
            samples.clear();
            samples.resize(sources.len(), DiceSample::default());
            surface.sample_into(&sources, samples);
            let points: Vec<Vec3> = samples.iter().map(displaced).collect();
            let id = |i: u32, j: u32| ids[starts[j as usize] + i as usize];
            let position = |v: u32| if v > u32::MAX / 2 { points[(u32::MAX - v) as usize] } else { shared[v as usize] };
            let mut out = Vec::with_capacity((2 * n * m) as usize);
            let mut push = |c: [u32; 3]| {
                if !collapsed(c.map(position)) {
                    out.push(c);
                }
            };
            for j in 0..m {
                match quad {
                    true => {
                        for i in 0..n {
                            push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                            push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
                        }
                    }
                    false => {
                        for i in 0..n - j {
                            push([id(i, j), id(i + 1, j), id(i, j + 1)]);
                            if i + j + 2 <= n {
                                push([id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
                            }
                        }
                    }
                }
            }
            (points, sources, out)
        })
        .collect();
    // A whole face is its base triangles: a triangle's own, or a quad's [a, b, c] and [a, c, d].
    let halves = |face: &Face| {
        let c = face.corners;
        let halves = [[c[0], c[1], c[2]], [c[0], c[2], c[3]]];
        (halves, face.sides as usize - 2)
    };
    let whole_kept: Vec<u8> = faces
        .par_iter()
        .zip(&whole)
        .map(|(face, &whole)| {
            let (halves, count) = halves(face);
            let kept = |t: &[u32; 3]| !collapsed(t.map(|v| diced.positions[v as usize]));
            (0..count).filter(|&h| whole && kept(&halves[h])).fold(0, |bits, h| bits | 1 << h)
        })
        .collect();
    // The rest of the output is written in parallel, by blocks of faces, each at its place: per face its
    // whole halves, then its part's triangles, and its part's inner points.
    const BLOCK: usize = 1024;
    let block_parts = |start: usize| cut_faces.partition_point(|&f| f < start);
    let sizes: Vec<(usize, usize)> = (0..faces.len())
        .into_par_iter()
        .step_by(BLOCK)
        .map(|start| {
            let end = (start + BLOCK).min(faces.len());
            let halves: usize = whole_kept[start..end].iter().map(|bits| bits.count_ones() as usize).sum();
            parts[block_parts(start)..block_parts(end)]
                .iter()
                .fold((0, halves), |(points, triangles), part| (points + part.0.len(), triangles + part.2.len()))
        })
        .collect();
    let (points, triangles) = sizes.iter().fold((0, 0), |(p, t), &(bp, bt)| (p + bp, t + bt));
    let inner_first = diced.positions.len();
    diced.positions.resize(inner_first + points, Vec3::ZERO);
    diced.sources.resize(inner_first + points, BasePoint { triangle: 0, bary: [1.0, 0.0, 0.0] });
    diced.triangles.resize(triangles, [0; 3]);
    diced.origins.resize(triangles, 0);
    let mut places = Vec::with_capacity(sizes.len());
    let (mut positions, mut sources) = (&mut diced.positions[inner_first..], &mut diced.sources[inner_first..]);
    let (mut triangles, mut origins) = (&mut diced.triangles[..], &mut diced.origins[..]);
    let mut block_first = inner_first;
    for (b, &(points, count)) in sizes.iter().enumerate() {
        let (p, s, t, o);
        (p, positions) = std::mem::take(&mut positions).split_at_mut(points);
        (s, sources) = std::mem::take(&mut sources).split_at_mut(points);
        (t, triangles) = std::mem::take(&mut triangles).split_at_mut(count);
        (o, origins) = std::mem::take(&mut origins).split_at_mut(count);
        places.push((b * BLOCK, block_first, p, s, t, o));
        block_first += points;
    }
    places.into_par_iter().for_each(|(start, block_first, positions, sources, triangles, origins)| {
        let (mut part, mut point, mut triangle) = (block_parts(start), 0, 0);
        for f in start..(start + BLOCK).min(faces.len()) {
            let (halves, count) = halves(&faces[f]);
            for h in (0..count).filter(|&h| whole_kept[f] & (1 << h) != 0) {
                (triangles[triangle], origins[triangle]) = (halves[h], f as u32);
                triangle += 1;
            }
            if !cut[f] {
                continue;
            }
            let (points, from, inner) = &parts[part];
            part += 1;
            positions[point..point + points.len()].copy_from_slice(points);
            sources[point..point + points.len()].copy_from_slice(from);
            let number = (block_first + point) as u32;
            let renumber = |v: u32| if v > u32::MAX / 2 { number + (u32::MAX - v) } else { v };
            for c in inner {
                (triangles[triangle], origins[triangle]) = (c.map(renumber), f as u32);
                triangle += 1;
            }
            point += points.len();
        }
    });
    Ok(diced)
}

/// Whether a face over which F is uniform, whose corners' samples are `corners`, is the base moved
/// outwards as it is: every corner moved alike, and each side's arc (its chord turning by the angle between
/// its ends' normals sags about chord x angle / 8) within `OFFSET_SAG_PX` of its chord on screen.
fn is_offset(surface: &impl DiceSurface, corners: &[&DiceSample]) -> bool {
    let height = corners[0].height;
    let alike = corners.iter().all(|c| (c.height - height).abs() <= 1e-6 * height.abs());
    let sag_px = |a: &DiceSample, b: &DiceSample| {
        let turn = a.normal.angle_between(b.normal);
        let ppu = surface.pixels_per_unit(a.p).max(surface.pixels_per_unit(b.p));
        displaced(a).distance(displaced(b)) * turn / 8.0 * ppu
    };
    let sides = corners.len();
    alike && (0..sides).all(|k| sag_px(corners[k], corners[(k + 1) % sides]) <= OFFSET_SAG_PX)
}

/// `sample` at every point, in parallel, in batches a surface may sample together.
fn sample_all(surface: &impl DiceSurface, points: &[BasePoint]) -> Vec<DiceSample> {
    const BATCH: usize = 256;
    let mut out = vec![DiceSample::default(); points.len()];
    out.par_chunks_mut(BATCH).zip(points.par_chunks(BATCH)).for_each(|(out, at)| surface.sample_into(at, out));
    out
}

/// Whether a triangle's corners are not three distinct points (corners snapped together, or at one welded
/// point as at a pole): it covers nothing and is dropped.
fn collapsed(corners: [Vec3; 3]) -> bool {
    let [a, b, c] = corners.map(|p| p.to_array().map(f32::to_bits));
    a == b || b == c || c == a
}

/// Whether a face whose corners' samples are `corners` is left whole without looking between them: they
/// share a side of the screen they lie beyond, or a reason of facing that holds all over the face. The
/// normals inside a face lie about among its corners' ones, and the direction to the eye turns far less
/// across one face than the normal does near an outline; twice the corners' largest difference of normal
/// bounds how much N.V changes over the face.
fn is_whole(corners: &[&DiceSample]) -> bool {
    let shared = corners.iter().fold(u8::MAX, |s, c| s & c.skip);
    if shared & Skip::OFF_SCREEN != 0 {
        return true;
    }
    if shared & Skip::FACING == 0 {
        return false;
    }
    let clearance = corners.iter().map(|c| c.clearance).fold(f32::INFINITY, f32::min);
    let mut spread = 0.0f32;
    for (k, a) in corners.iter().enumerate() {
        for b in &corners[k + 1..] {
            spread = spread.max(a.normal.distance(b.normal));
        }
    }
    2.0 * spread < clearance
}

/// The vertex that grid point `s` of `n` along edge `k` of `face` snaps to: one of the edge's
/// `rate` - 1 points or an end, the nearest. Since `rate` <= `n`, consecutive grid points snap to the same or
/// consecutive points (no edge point is skipped), and a corner's first cells reach at most two grid steps
/// along its edges, so they never turn over.
/// `ends` are the edge's two vertices and `first` the number of its first own point.
fn snapped(face: &Face, k: usize, s: u32, n: u32, rate: u32, ends: EdgeKey, first: u32) -> u32 {
    let (from, to) = (face.corner(k), face.corner(k + 1));
    let q = (2 * s * rate + n) / (2 * n);
    if q == 0 {
        return from;
    }
    if q == rate {
        return to;
    }
    // The edge's own points run from its smaller vertex.
    let from_smaller = ends.0 == from && from != to;
    first + if from_smaller { q - 1 } else { rate - q - 1 }
}

/// Welds vertices closer than `tolerance`, or with `tolerance` 0 bit-equal ones: each vertex's welded
/// number, and the count.
pub fn weld(positions: &[Vec3], tolerance: f32) -> (Vec<u32>, usize) {
    let mut numbers = Vec::with_capacity(positions.len());
    if tolerance == 0.0 {
        let mut index: FxHashMap<[u32; 3], u32> =
            FxHashMap::with_capacity_and_hasher(positions.len(), Default::default());
        for &p in positions {
            let next = index.len() as u32;
            numbers.push(*index.entry((p + Vec3::ZERO).to_array().map(f32::to_bits)).or_insert(next));
        }
        return (numbers, index.len());
    }
    let at = |p: Vec3| (p / tolerance).floor().as_ivec3();
    let mut grid: FxHashMap<glam::IVec3, Vec<u32>> =
        FxHashMap::with_capacity_and_hasher(positions.len(), Default::default());
    let mut reps = Vec::<Vec3>::new();
    for &p in positions {
        let c = at(p);
        let mut found = None;
        'search: for dz in -1..=1 {
            for dy in -1..=1 {
                for dx in -1..=1 {
                    if let Some(list) = grid.get(&(c + glam::IVec3::new(dx, dy, dz))) {
                        if let Some(&w) = list.iter().find(|&&w| reps[w as usize].distance(p) <= tolerance) {
                            found = Some(w);
                            break 'search;
                        }
                    }
                }
            }
        }
        let w = found.unwrap_or_else(|| {
            reps.push(p);
            grid.entry(c).or_default().push(reps.len() as u32 - 1);
            reps.len() as u32 - 1
        });
        numbers.push(w);
    }
    (numbers, reps.len())
}

/// A value at a base point from its triangle's three `corners` (positions, normals, (u,v)) and the weights.
pub fn interpolate<T: Copy + std::ops::Mul<f32, Output = T> + std::ops::Add<Output = T>>(
    corners: [T; 3],
    bary: [f32; 3],
) -> T {
    corners[0] * bary[0] + corners[1] * bary[1] + corners[2] * bary[2]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::tessellate::grid;
    use crate::geometry::Surface;

    /// A surface under a base mesh: points interpolated on the flat base triangles, heights from a function
    /// of the position, and a screen scale that makes rates vary from edge to edge; optionally a region
    /// left flat (not displaced, faces there left whole) and one where the height is uniform.
    struct Flat<'a> {
        surface: &'a Surface,
        positions: &'a [Vec3],
        triangles: &'a [[u32; 3]],
        height: fn(Vec3) -> f32,
        ppu: fn(Vec3) -> f32,
        regions: Option<Regions>,
    }

    /// Where a test surface is flat, and where its height is uniform (decided by the base point's position).
    #[derive(Clone, Copy)]
    struct Regions {
        flat: fn(Vec3) -> bool,
        uniform: fn(Vec3) -> bool,
    }

    /// The outward direction at a point near a unit sphere at the origin or a torus of major radius 1
    /// around y (from the nearest point of its ring), by the shape of the base.
    fn outward(surface: &Surface, p: Vec3) -> Vec3 {
        match surface {
            Surface::Torus { .. } => (p - Vec3::new(p.x, 0.0, p.z).normalize()).normalize(),
            _ => p.normalize(),
        }
    }

    impl Flat<'_> {
        fn outward(&self, p: Vec3) -> Vec3 {
            outward(self.surface, p)
        }

        fn at(&self, at: BasePoint) -> Vec3 {
            interpolate(self.triangles[at.triangle as usize].map(|v| self.positions[v as usize]), at.bary)
        }
    }

    impl DiceSurface for Flat<'_> {
        fn sample(&self, at: BasePoint) -> DiceSample {
            let p = self.at(at);
            match self.regions {
                Some(r) if (r.flat)(p) => {
                    DiceSample { p, normal: self.outward(p), height: 0.0, skip: Skip::FLAT, clearance: 10.0 }
                }
                _ => DiceSample { p, normal: self.outward(p), height: (self.height)(p), skip: 0, clearance: 0.0 },
            }
        }
        fn uniform(&self, points: &[BasePoint]) -> bool {
            self.regions.is_some_and(|r| points.iter().all(|&at| (r.uniform)(self.at(at))))
        }
        fn screen(&self, p: Vec3) -> Option<Vec2> {
            Some(p.truncate() * (self.ppu)(p))
        }
        fn pixels_per_unit(&self, p: Vec3) -> f32 {
            (self.ppu)(p)
        }
    }

    /// On closed surfaces, whatever mix of rates, with triangle faces and with quad faces: no diced
    /// triangle faces inwards, and every diced edge is met from the other side (no cracks); on the torus,
    /// which has no poles, exactly once each way (no folds either). On the sphere triangle faces are also
    /// filled exactly: their pieces' areas sum to their own.
    #[test]
    fn dicing_is_watertight_and_fills_each_face() {
        for surface in [Surface::Sphere { radius: 1.0 }, Surface::Torus { major_radius: 1.0, minor_radius: 0.4 }] {
            dice_closed(&surface);
        }
    }

    fn dice_closed(surface: &Surface) {
        let poles = matches!(surface, Surface::Sphere { .. });
        let m = grid(surface, 12, 7);
        let (weld_of, welded) = weld(&m.positions, 0.0);
        let triangles: Vec<Face> = m.triangles.iter().enumerate().map(|(t, &c)| Face::triangle(c, t as u32)).collect();
        let quads: Vec<Face> = (0..m.triangles.len() / 2)
            .map(|q| {
                let ([a, b, c], [_, _, d]) = (m.triangles[2 * q], m.triangles[2 * q + 1]);
                Face::quad([a, b, c, d], 2 * q as u32)
            })
            .collect();
        let rates: [fn(Vec3) -> f32; 3] = [|_| 3.0, |p| 2.0 + 30.0 * (p.x + 1.0), |p| 3.0 * (p.z + 1.1).powi(3)];
        // Faces left whole where x is not within 0.1 of 0.25 (some of them across that band, which their
        // corners miss), cut only as the height moves where z < 0, beside faces cut in full.
        let regions = Regions { flat: |p| (p.x - 0.25).abs() > 0.1, uniform: |p| p.z < -1e-3 };
        let combinations =
            [(&triangles, true), (&quads, false)].into_iter().flat_map(|f| [(f, None), (f, Some(regions))]);
        for ((faces, are_triangles), regions) in combinations {
            for ppu in rates {
                // On the torus the base is left flat, so that which way a triangle turns is the dicing's doing.
                let height: fn(Vec3) -> f32 = match (poles, regions.is_some()) {
                    (false, _) => |_| 0.0,
                    (true, false) => |p| 0.1 * (5.0 * p.x).sin(),
                    (true, true) => |p| if p.z < 0.0 { 0.05 } else { 0.1 * (5.0 * p.x).sin() },
                };
                let flat = Flat { surface, positions: &m.positions, triangles: &m.triangles, height, ppu, regions };
                let base = Base { faces, weld: &weld_of, welded };
                let d = dice(&base, &flat, 1.0, 1 << 24).unwrap();
                let mut pieces = vec![0usize; faces.len()];
                d.origins.iter().for_each(|&f| pieces[f as usize] += 1);
                match regions {
                    None => assert!(d.triangles.len() > 2 * faces.len()),
                    // Both kinds side by side.
                    Some(_) => assert!(pieces.iter().any(|&n| n <= 2) && pieces.iter().any(|&n| n >= 3), "{pieces:?}"),
                }
                let mut area = vec![0.0f64; faces.len()];
                for (tri, &f) in d.triangles.iter().zip(&d.origins) {
                    let [a, b, c] = tri.map(|v| d.positions[v as usize]);
                    // Against the face's own triangles (the base is flat on the torus, curved on the sphere).
                    let face = &faces[f as usize];
                    let base_normal = (face.triangle..face.triangle + u32::from(face.sides - 2))
                        .map(|t| m.triangles[t as usize].map(|v| m.positions[v as usize]))
                        .map(|[p, q, r]| (q - p).cross(r - p))
                        .sum::<Vec3>();
                    let towards = if poles { outward(surface, a + b + c) } else { base_normal };
                    let turn = (b - a).cross(c - a).dot(towards);
                    // Zero where a coarse face is stitched to its finely cut edge by a fan in the edge's plane.
                    assert!(turn >= -1e-6, "triangles {are_triangles}: face {f} turns inwards ({turn}): {a} {b} {c}");
                    if are_triangles && poles {
                        let bary = tri.map(|v| locate(&m, f, d.positions[v as usize]));
                        area[f as usize] += f64::from((bary[1] - bary[0]).perp_dot(bary[2] - bary[0])) * 0.5;
                    }
                }
                for (t, a) in area.iter().enumerate().filter(|_| are_triangles && poles) {
                    let [p, q, r] = m.triangles[t].map(|v| m.positions[v as usize]);
                    let want = if (q - p).cross(r - p).length() < 1e-9 { 0.0 } else { 0.5 };
                    assert!((a - want).abs() < 1e-4, "base triangle {t}: diced area {a}, want {want}");
                }
                let mut directed: FxHashMap<(Vec3Key, Vec3Key), i32> = FxHashMap::default();
                for tri in &d.triangles {
                    for k in 0..3 {
                        let (a, b) = (d.positions[tri[k] as usize], d.positions[tri[(k + 1) % 3] as usize]);
                        *directed.entry((k3(a), k3(b))).or_default() += 1;
                    }
                }
                for (&(a, b), &n) in &directed {
                    let f = |k: Vec3Key| Vec3::from_array(k.map(f32::from_bits));
                    assert!(directed.contains_key(&(b, a)), "a crack: {} -> {}", f(a), f(b));
                    if !poles {
                        assert_eq!((n, directed.get(&(b, a))), (1, Some(&1)), "a fold at {} -> {}", f(a), f(b));
                    }
                }
            }
        }
    }

    type Vec3Key = [u32; 3];
    fn k3(p: Vec3) -> Vec3Key {
        (p + Vec3::ZERO).to_array().map(f32::to_bits)
    }

    /// The weights of corners 1 and 2 of base triangle t at a diced vertex: the displacement is radial, so
    /// the ray from the origin through the vertex meets the triangle's plane where it came from.
    fn locate(m: &crate::geometry::tessellate::Mesh, t: u32, p: Vec3) -> Vec2 {
        let [a, b, c] = m.triangles[t as usize].map(|v| m.positions[v as usize]);
        let n = (b - a).cross(c - a);
        let q = p * (n.dot(a) / n.dot(p));
        let (e1, e2, r) = (b - a, c - a, q - a);
        let (d11, d12, d22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
        let (r1, r2) = (r.dot(e1), r.dot(e2));
        let det = d11 * d22 - d12 * d12;
        Vec2::new((r1 * d22 - r2 * d12) / det, (r2 * d11 - r1 * d12) / det)
    }
}
