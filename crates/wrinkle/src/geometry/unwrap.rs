//! A texture atlas for meshes without usable texture coordinates, as the course's "3D Paint Systems" asks:
//! patches (charts) found on the model, each flattened with low distortion, packed into one square image
//! with gutters between them so that neighbours do not bleed into each other.
//!
//! - Charts grow from the largest unassigned face across shared edges (positions welded where bit for bit
//!   equal) to every face whose normal lies within `max_angle` of the seed's, as Blender's "Smart UV
//!   Project" does. Each chart is flattened by projecting it onto the plane across the seed's normal: a face
//!   tilted by a from that plane keeps its length along the tilt's axis times cos a, so a chart's anisotropy
//!   (the larger singular value of its map over the smaller) is at most 1 / cos(max_angle).
//! - Each chart is turned to its smallest bounding rectangle and packed, at one
//!   texel density for all, into shelves, with `gutter` texels between charts and half of it at the image's
//!   edges (the atlas repeats). The density is the largest the packing fits (a bisection).
//! - A chart whose flattening folds over itself (its faces overlap in the plane: a spiral ramp) is split
//!   into its faces.
//! - A vertex shared by several charts is duplicated, one copy with each chart's coordinates, as the slides
//!   warn; its position and normal are unchanged.

use super::TriangleMesh;
use crate::{Error, Result};
use glam::{Vec2, Vec3};
use std::collections::HashMap;

/// How the atlas is made.
#[derive(Clone, Copy, Debug)]
pub struct UnwrapOptions {
    /// The side of the square image the atlas is laid out for, in texels.
    pub size: usize,
    /// Texels between two charts.
    pub gutter: usize,
    /// The widest angle, in degrees, between a chart's faces and its seed's normal.
    pub max_angle: f32,
}

/// What the atlas came to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UnwrapReport {
    pub charts: usize,
    /// The share of the image the charts' triangles cover.
    pub utilisation: f32,
    /// Each face's anisotropy (the larger singular value of its (u,v)-to-surface map over the smaller),
    /// averaged over the surface's area, and its largest (over faces of at least a sixteenth of a texel).
    pub stretch_mean: f32,
    pub stretch_max: f32,
}

/// One chart: faces of one mesh and their flattened corners (world units, in the chart's own frame).
struct Chart {
    mesh: usize,
    faces: Vec<usize>,
    /// Flattened corners, three per face.
    corners: Vec<Vec2>,
    size: Vec2,
    /// Where the chart's corner lands in the atlas, texels from the top left.
    at: Vec2,
}

/// New meshes (the inputs with their vertices split where charts meet and set 0 holding the atlas's
/// (u,v), v up) and the report. Every mesh shares one atlas.
pub fn unwrap(meshes: &[&TriangleMesh], options: UnwrapOptions) -> Result<(Vec<TriangleMesh>, UnwrapReport)> {
    if options.size < 8 || options.gutter * 4 >= options.size {
        return Err(Error::parameter("size", format!("must be at least 8 and 4 gutters wide, got {}", options.size)));
    }
    if !(1.0..=89.0).contains(&options.max_angle) {
        return Err(Error::parameter("max_angle", format!("must be from 1 to 89 degrees, got {}", options.max_angle)));
    }
    let mut charts: Vec<Chart> = Vec::new();
    for (m, mesh) in meshes.iter().enumerate() {
        for faces in grow_charts(mesh, options.max_angle.to_radians().cos()) {
            charts.push(flatten(mesh, m, faces));
        }
    }
    if charts.is_empty() {
        return Err(Error::Invalid("the model has no triangles to lay out".into()));
    }
    // Pack; split any chart whose faces overlap, and pack again (a few rounds at most: single faces cannot).
    loop {
        let scale = pack(&mut charts, options)?;
        let folded = folded_charts(&charts, scale);
        if folded.is_empty() {
            return Ok(build(meshes, &charts, scale, options));
        }
        for c in folded.into_iter().rev() {
            let chart = charts.swap_remove(c);
            for (k, &face) in chart.faces.iter().enumerate() {
                let corners = chart.corners[3 * k..3 * k + 3].to_vec();
                charts.push(framed(chart.mesh, vec![face], corners));
            }
        }
    }
}

/// Faces grouped into charts by region growing over welded edges.
fn grow_charts(mesh: &TriangleMesh, min_cos: f32) -> Vec<Vec<usize>> {
    let weld: Vec<u32> = {
        let mut ids: HashMap<[u32; 3], u32> = HashMap::new();
        mesh.positions
            .iter()
            .map(|p| {
                let next = ids.len() as u32;
                *ids.entry(p.to_array().map(f32::to_bits)).or_insert(next)
            })
            .collect()
    };
    let mut by_edge: HashMap<(u32, u32), Vec<usize>> = HashMap::new();
    for (f, t) in mesh.triangles.iter().enumerate() {
        for c in 0..3 {
            let (a, b) = (weld[t[c] as usize], weld[t[(c + 1) % 3] as usize]);
            by_edge.entry((a.min(b), a.max(b))).or_default().push(f);
        }
    }
    let normal = |f: usize| {
        let p = mesh.triangles[f].map(|k| mesh.positions[k as usize]);
        (p[1] - p[0]).cross(p[2] - p[0])
    };
    let normals: Vec<Vec3> = (0..mesh.triangles.len()).map(normal).collect();
    let mut order: Vec<usize> = (0..mesh.triangles.len()).collect();
    order.sort_by(|&a, &b| normals[b].length().total_cmp(&normals[a].length()));
    let mut chart_of = vec![usize::MAX; mesh.triangles.len()];
    let mut charts = Vec::new();
    for seed in order {
        if chart_of[seed] != usize::MAX {
            continue;
        }
        let axis = normals[seed].normalize_or_zero();
        let id = charts.len();
        chart_of[seed] = id;
        let (mut faces, mut next) = (vec![seed], 0);
        while next < faces.len() {
            let t = mesh.triangles[faces[next]];
            next += 1;
            for c in 0..3 {
                let (a, b) = (weld[t[c] as usize], weld[t[(c + 1) % 3] as usize]);
                for &g in &by_edge[&(a.min(b), a.max(b))] {
                    // A degenerate face (no normal) joins whichever chart reaches it.
                    let n = normals[g].normalize_or_zero();
                    if chart_of[g] == usize::MAX && (n == Vec3::ZERO || n.dot(axis) >= min_cos) && axis != Vec3::ZERO {
                        chart_of[g] = id;
                        faces.push(g);
                    }
                }
            }
        }
        charts.push(faces);
    }
    charts
}

/// The chart's faces projected onto the plane across its seed's normal.
fn flatten(mesh: &TriangleMesh, m: usize, faces: Vec<usize>) -> Chart {
    let p = mesh.triangles[faces[0]].map(|k| mesh.positions[k as usize]);
    let axis = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
    let axis = if axis == Vec3::ZERO { Vec3::Z } else { axis };
    let (t, b) = axis.any_orthonormal_pair();
    let corners = faces
        .iter()
        .flat_map(|&f| mesh.triangles[f].map(|k| mesh.positions[k as usize]))
        .map(|q| Vec2::new(q.dot(t), q.dot(b)))
        .collect();
    framed(m, faces, corners)
}

/// A chart turned to its smallest bounding rectangle (one of whose sides lies along an edge of the convex
/// hull, Freeman and Shapira 1975) with its corner at the origin.
fn framed(mesh: usize, faces: Vec<usize>, corners: Vec<Vec2>) -> Chart {
    let hull = convex_hull(&corners);
    let mut best = (f32::MAX, Vec2::X);
    for k in 0..hull.len() {
        let Some(along) = (hull[(k + 1) % hull.len()] - hull[k]).try_normalize() else { continue };
        let across = along.perp();
        let (lo, hi) = hull.iter().fold((Vec2::splat(f32::MAX), Vec2::splat(f32::MIN)), |(lo, hi), p| {
            let q = Vec2::new(p.dot(along), p.dot(across));
            (lo.min(q), hi.max(q))
        });
        let area = (hi - lo).x * (hi - lo).y;
        if area < best.0 {
            best = (area, along);
        }
    }
    let (along, across) = (best.1, best.1.perp());
    let turned: Vec<Vec2> = corners.iter().map(|c| Vec2::new(c.dot(along), c.dot(across))).collect();
    let lo = turned.iter().fold(Vec2::splat(f32::MAX), |a, c| a.min(*c));
    let hi = turned.iter().fold(Vec2::splat(f32::MIN), |a, c| a.max(*c));
    let corners = turned.into_iter().map(|c| c - lo).collect();
    Chart { mesh, faces, corners, size: hi - lo, at: Vec2::ZERO }
}

/// The convex hull of the points, counter-clockwise (Andrew's monotone chain).
fn convex_hull(points: &[Vec2]) -> Vec<Vec2> {
    let mut sorted = points.to_vec();
    sorted.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    sorted.dedup();
    if sorted.len() < 3 {
        return sorted;
    }
    let mut hull: Vec<Vec2> = Vec::with_capacity(2 * sorted.len());
    for pass in 0..2 {
        let start = hull.len();
        let points: Box<dyn Iterator<Item = &Vec2>> =
            if pass == 0 { Box::new(sorted.iter()) } else { Box::new(sorted.iter().rev()) };
        for &p in points {
            while hull.len() >= start + 2
                && (hull[hull.len() - 1] - hull[hull.len() - 2]).perp_dot(p - hull[hull.len() - 2]) <= 0.0
            {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    hull
}

/// Shelf-packs the charts at the largest density (texels per world unit) that fits: the density.
fn pack(charts: &mut [Chart], options: UnwrapOptions) -> Result<f32> {
    let side = options.size as f32;
    let gutter = options.gutter as f32;
    let area: f32 = charts.iter().map(|c| c.size.x * c.size.y).sum::<f32>().max(1e-20);
    let largest = charts.iter().map(|c| c.size.max_element()).fold(0.0, f32::max).max(1e-20);
    // A chart's box in texels, its gutter included.
    let boxed = |c: &Chart, s: f32| (c.size * s).ceil() + Vec2::splat(gutter);
    let mut order: Vec<usize> = (0..charts.len()).collect();
    order.sort_by(|&a, &b| charts[b].size.y.total_cmp(&charts[a].size.y));
    let place = |s: f32, charts: &mut [Chart], commit: bool| -> bool {
        let (mut x, mut y, mut shelf) = (0.0, 0.0, 0.0f32);
        for &k in &order {
            let b = boxed(&charts[k], s);
            if x + b.x > side {
                (x, y, shelf) = (0.0, y + shelf, 0.0);
            }
            if x + b.x > side || y + b.y > side {
                return false;
            }
            if commit {
                charts[k].at = Vec2::new(x, y) + Vec2::splat(0.5 * gutter);
            }
            (x, shelf) = (x + b.x, shelf.max(b.y));
        }
        true
    };
    let (mut lo, mut hi) = (0.0f32, (side / largest).min((side * side / area).sqrt()));
    if !place(1e-9, charts, false) {
        return Err(Error::Invalid(format!(
            "{} charts with {} texels of gutter each do not fit a {}x{} atlas: a larger atlas is needed",
            charts.len(),
            options.gutter,
            options.size,
            options.size
        )));
    }
    for _ in 0..40 {
        let mid = 0.5 * (lo + hi);
        if place(mid, charts, false) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    place(lo, charts, true);
    Ok(lo)
}

/// Charts whose faces overlap one another once laid out: two faces covering one texel centre of the atlas
/// (found on a grid at the packing's resolution).
fn folded_charts(charts: &[Chart], scale: f32) -> Vec<usize> {
    let mut folded = Vec::new();
    for (c, chart) in charts.iter().enumerate() {
        if chart.faces.len() < 2 {
            continue;
        }
        let cells = (chart.size * scale).ceil() + Vec2::ONE;
        let (w, h) = (cells.x as usize, cells.y as usize);
        let mut covered = vec![false; w * h];
        let overlaps = chart.corners.chunks_exact(3).any(|tri| {
            let [a, b, d] = [tri[0] * scale, tri[1] * scale, tri[2] * scale];
            let area = (b - a).perp_dot(d - a);
            if area.abs() < 1e-12 {
                return false;
            }
            let (lo, hi) = (a.min(b).min(d), a.max(b).max(d));
            for y in (lo.y - 0.5).ceil().max(0.0) as usize..=((hi.y - 0.5).floor().max(0.0) as usize).min(h - 1) {
                for x in (lo.x - 0.5).ceil().max(0.0) as usize..=((hi.x - 0.5).floor().max(0.0) as usize).min(w - 1) {
                    let q = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                    let inside =
                        [(a, b), (b, d), (d, a)].iter().all(|(p, r)| (*r - *p).perp_dot(q - *p) * area.signum() > 1e-6);
                    if inside {
                        if covered[y * w + x] {
                            return true;
                        }
                        covered[y * w + x] = true;
                    }
                }
            }
            false
        });
        if overlaps {
            folded.push(c);
        }
    }
    folded
}

/// The meshes with split vertices and the atlas's (u,v), and the report.
fn build(
    meshes: &[&TriangleMesh],
    charts: &[Chart],
    scale: f32,
    options: UnwrapOptions,
) -> (Vec<TriangleMesh>, UnwrapReport) {
    let side = options.size as f32;
    let mut out: Vec<TriangleMesh> =
        meshes.iter().map(|m| TriangleMesh { triangles: m.triangles.clone(), ..TriangleMesh::default() }).collect();
    // One new vertex per (old vertex, chart).
    let mut copies: Vec<HashMap<(u32, usize), u32>> = vec![HashMap::new(); meshes.len()];
    let (mut covered, mut weighted, mut surface, mut worst) = (0.0f32, 0.0f32, 0.0f32, 1.0f32);
    for (c, chart) in charts.iter().enumerate() {
        let (source, target) = (meshes[chart.mesh], &mut out[chart.mesh]);
        for (k, &face) in chart.faces.iter().enumerate() {
            let mut uv = [Vec2::ZERO; 3];
            for (corner, old) in source.triangles[face].into_iter().enumerate() {
                let texel = chart.at + chart.corners[3 * k + corner] * scale;
                uv[corner] = Vec2::new(texel.x / side, 1.0 - texel.y / side);
                let new = *copies[chart.mesh].entry((old, c)).or_insert_with(|| {
                    target.positions.push(source.positions[old as usize]);
                    if let Some(n) = source.normals.get(old as usize) {
                        target.normals.push(*n);
                    }
                    target.uv_sets.resize(1, Vec::new());
                    target.uv_sets[0].push(uv[corner]);
                    (target.positions.len() - 1) as u32
                });
                target.triangles[face][corner] = new;
            }
            let p = source.triangles[face].map(|i| source.positions[i as usize]);
            let (area3, stretch) = anisotropy(p, uv);
            let uv_area = 0.5 * (uv[1] - uv[0]).perp_dot(uv[2] - uv[0]).abs();
            covered += uv_area;
            (weighted, surface) = (weighted + stretch * area3, surface + area3);
            // Slivers under a sixteenth of a texel are too thin for f32 (u,v) to measure their shape.
            if uv_area * side * side >= 1.0 / 16.0 {
                worst = worst.max(stretch);
            }
        }
    }
    let report = UnwrapReport {
        charts: charts.len(),
        utilisation: covered,
        stretch_mean: if surface > 0.0 { weighted / surface } else { 1.0 },
        stretch_max: worst,
    };
    (out, report)
}

/// A face's area and the ratio of the larger singular value of its (u,v)-to-surface map to the smaller.
fn anisotropy(p: [Vec3; 3], uv: [Vec2; 3]) -> (f32, f32) {
    let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
    let (d1, d2) = (uv[1] - uv[0], uv[2] - uv[0]);
    let det = d1.perp_dot(d2);
    let area = 0.5 * e1.cross(e2).length();
    if det.abs() < 1e-20 || area <= 0.0 {
        return (area, 1.0);
    }
    // dP/du and dP/dv; the singular values of [Pu Pv] from its 2x2 Gram matrix.
    let pu = (e1 * d2.y - e2 * d1.y) / det;
    let pv = (e2 * d1.x - e1 * d2.x) / det;
    let (a, b, c) = (pu.dot(pu), pu.dot(pv), pv.dot(pv));
    let root = ((a - c) * (a - c) + 4.0 * b * b).sqrt();
    let (big, small) = (0.5 * (a + c + root), (0.5 * (a + c - root)).max(0.0));
    (area, if small > 0.0 { (big / small).sqrt() } else { f32::INFINITY })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube() -> TriangleMesh {
        // Eight shared corners, twelve faces: the unwrapper must split it into six charts.
        let positions: Vec<Vec3> =
            (0..8).map(|i| Vec3::new((i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32)).collect();
        let quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
        let triangles = quads.iter().flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]).collect();
        let mut mesh = TriangleMesh { positions, triangles, ..TriangleMesh::default() };
        mesh.compute_normals();
        mesh
    }

    #[test]
    fn a_cube_unwraps_into_six_undistorted_charts() {
        let options = UnwrapOptions { size: 256, gutter: 8, max_angle: 45.0 };
        let (meshes, report) = unwrap(&[&cube()], options).unwrap();
        assert_eq!(report.charts, 6);
        assert!((report.stretch_mean - 1.0).abs() < 1e-3 && report.stretch_max < 1.001, "{report:?}");
        // Six unit squares at one density in a 256^2 atlas with 8-texel gutters: a 3x2 layout of squares
        // about 77 texels wide, over half the image.
        assert!(report.utilisation > 0.45 && report.utilisation < 0.75, "{report:?}");
        let mesh = &meshes[0];
        mesh.validate().unwrap();
        // Each face's four corners are its own: 24 vertices.
        assert_eq!(mesh.positions.len(), 24);
        assert!(mesh.uvs(0).unwrap().iter().all(|uv| (0.0..=1.0).contains(&uv.x) && (0.0..=1.0).contains(&uv.y)));
    }

    #[test]
    fn anisotropy_is_one_for_a_similarity_and_the_axis_ratio_otherwise() {
        let p = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let uv = [Vec2::ZERO, Vec2::new(0.5, 0.0), Vec2::new(0.0, 0.5)];
        assert!((anisotropy(p, uv).1 - 1.0).abs() < 1e-6);
        let uv = [Vec2::ZERO, Vec2::new(0.5, 0.0), Vec2::new(0.0, 0.25)];
        assert!((anisotropy(p, uv).1 - 2.0).abs() < 1e-5);
    }

    #[test]
    fn atlases_too_small_for_their_gutters_are_refused() {
        let e = unwrap(&[&cube()], UnwrapOptions { size: 32, gutter: 10, max_angle: 45.0 }).err().unwrap();
        assert!(e.to_string().contains("size"), "{e}");
    }
}
