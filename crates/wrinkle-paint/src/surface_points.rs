//! Where on the model each atlas texel lies: the object-space points a texel stands for, found once when the
//! model loads, and a uniform grid over them so that a brush (a sphere in object space) finds its texels
//! without visiting the rest.
//!
//! A parametric surface gives P(u,v) at each texel's centre. A mesh is rasterised triangle by triangle in its
//! (u,v); the texels of a gutter `GUTTER` texels wide around each island take the point of the nearest
//! triangle, so paint bleeds past island borders and neither bilinear lookups nor coarser MIP levels pull in
//! unpainted texels. A texel may stand for several points (a box's six faces share one (u,v) square, mirrored
//! halves of a model one island).

use glam::{Vec2, Vec3};
use wrinkle::geometry::{Primitive, TriangleMesh};
use wrinkle::{Error, Result};

/// How far (in texels) paint bleeds past a mesh island's border.
pub const GUTTER: usize = 4;

pub struct SurfacePoints {
    /// Sorted by grid cell.
    points: Vec<Vec3>,
    /// The texel (row * size + column, row 0 at v = 1) of each point.
    texels: Vec<u32>,
    grid: Grid,
    /// The points' bounding box.
    bounds: (Vec3, Vec3),
}

struct Grid {
    origin: Vec3,
    cell: f32,
    dims: [usize; 3],
    /// Points of cell k are `starts[k]..starts[k + 1]`.
    starts: Vec<u32>,
}

impl SurfacePoints {
    /// The points of every texel of a `size` x `size` atlas over the primitives' (u,v) (a mesh's first set).
    pub fn of_primitives(primitives: &[Primitive], size: usize) -> Result<SurfacePoints> {
        let mut found = Found::default();
        for primitive in primitives {
            match primitive {
                Primitive::Parametric(surface) => {
                    for k in 0..size * size {
                        let (u, v) = texel_uv(k, size);
                        found.push(k as u32, surface.position(u, v));
                    }
                }
                Primitive::Mesh(mesh) => rasterise_mesh(mesh, size, &mut found)?,
            }
        }
        if found.points.is_empty() {
            return Err(Error::Invalid(
                "the model covers no texel of the atlas (its texture coordinates are degenerate)".into(),
            ));
        }
        Ok(SurfacePoints::sorted(found))
    }

    fn sorted(found: Found) -> SurfacePoints {
        let (lo, hi) = found
            .points
            .iter()
            .fold((Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
        let extent = (hi - lo).max(Vec3::splat(1e-6));
        // About 16 points a cell.
        let cells_wanted = (found.points.len() / 16).max(1) as f32;
        let cell = (extent.x * extent.y * extent.z / cells_wanted).cbrt().max(extent.max_element() / 1024.0);
        let dims = [0, 1, 2].map(|a| ((extent[a] / cell) as usize + 1).min(1024));
        let mut grid = Grid { origin: lo, cell, dims, starts: vec![0; dims[0] * dims[1] * dims[2] + 1] };
        let cells: Vec<usize> = found.points.iter().map(|&p| grid.cell_of(p)).collect();
        for &c in &cells {
            grid.starts[c + 1] += 1;
        }
        for k in 1..grid.starts.len() {
            grid.starts[k] += grid.starts[k - 1];
        }
        let mut next = grid.starts.clone();
        let mut points = vec![Vec3::ZERO; found.points.len()];
        let mut texels = vec![0; found.points.len()];
        for ((&c, &p), &t) in cells.iter().zip(&found.points).zip(&found.texels) {
            let at = next[c] as usize;
            (points[at], texels[at]) = (p, t);
            next[c] += 1;
        }
        SurfacePoints { points, texels, grid, bounds: (lo, hi) }
    }

    /// Calls `visit(texel, point, distance)` for every point within `radius` of `centre`.
    pub fn within(&self, centre: Vec3, radius: f32, mut visit: impl FnMut(u32, Vec3, f32)) {
        let g = &self.grid;
        let lo = g.coords(centre - Vec3::splat(radius));
        let hi = g.coords(centre + Vec3::splat(radius));
        for z in lo[2]..=hi[2] {
            for y in lo[1]..=hi[1] {
                let row = (z * g.dims[1] + y) * g.dims[0];
                let (start, end) = (g.starts[row + lo[0]] as usize, g.starts[row + hi[0] + 1] as usize);
                for (&p, &t) in self.points[start..end].iter().zip(&self.texels[start..end]) {
                    let d = p.distance(centre);
                    if d < radius {
                        visit(t, p, d);
                    }
                }
            }
        }
    }

    /// The points' bounding box in object space.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.bounds
    }

    pub fn points(&self) -> impl Iterator<Item = Vec3> + '_ {
        self.points.iter().copied()
    }
}

impl Grid {
    fn coords(&self, p: Vec3) -> [usize; 3] {
        let q = (p - self.origin) / self.cell;
        [0, 1, 2].map(|a| (q[a].max(0.0) as usize).min(self.dims[a] - 1))
    }

    fn cell_of(&self, p: Vec3) -> usize {
        let [x, y, z] = self.coords(p);
        (z * self.dims[1] + y) * self.dims[0] + x
    }
}

#[derive(Default)]
struct Found {
    points: Vec<Vec3>,
    texels: Vec<u32>,
}

impl Found {
    fn push(&mut self, texel: u32, point: Vec3) {
        self.points.push(point);
        self.texels.push(texel);
    }
}

/// The (u,v) of texel `k`'s centre (row 0 at the top of the image, v = 1).
pub fn texel_uv(k: usize, size: usize) -> (f32, f32) {
    let (col, row) = (k % size, k / size);
    ((col as f32 + 0.5) / size as f32, 1.0 - (row as f32 + 0.5) / size as f32)
}

/// The texel index of a column and row that may lie outside the atlas (texture coordinates repeat).
fn wrapped(col: i64, row: i64, size: usize) -> u32 {
    let s = size as i64;
    (row.rem_euclid(s) * s + col.rem_euclid(s)) as u32
}

/// Texels whose centres lie in a triangle take its interpolated point; then the texels no triangle covers,
/// within `GUTTER` of one, take the point of its nearest place.
fn rasterise_mesh(mesh: &TriangleMesh, size: usize, found: &mut Found) -> Result<()> {
    let uvs = mesh.uvs(0).ok_or_else(|| {
        Error::Invalid(
            "the model has no texture coordinates to paint on (texture atlases for such models are not built yet)"
                .into(),
        )
    })?;
    // Texel space: x along u, y down the image; a texel's centre at (col + 0.5, row + 0.5).
    let to_texels = |uv: Vec2| Vec2::new(uv.x * size as f32, (1.0 - uv.y) * size as f32);
    let mut covered = vec![false; size * size];
    let mut near: Vec<(u32, Vec3, f32)> = Vec::new();
    for tri in &mesh.triangles {
        let [a, b, c] = tri.map(|i| to_texels(uvs[i as usize]));
        let [pa, pb, pc] = tri.map(|i| mesh.positions[i as usize]);
        let area = (b - a).perp_dot(c - a);
        if area.abs() < 1e-12 || !area.is_finite() {
            continue;
        }
        let margin = GUTTER as f32;
        let lo = a.min(b).min(c) - Vec2::splat(margin);
        let hi = a.max(b).max(c) + Vec2::splat(margin);
        if (hi - lo).max_element() > 4.0 * size as f32 {
            continue; // a triangle spanning many periods of (u,v) is not paintable texel by texel
        }
        for row in (lo.y.floor() as i64)..=(hi.y.ceil() as i64) {
            for col in (lo.x.floor() as i64)..=(hi.x.ceil() as i64) {
                let q = Vec2::new(col as f32 + 0.5, row as f32 + 0.5);
                let w = barycentric(q, a, b, c, area);
                let texel = wrapped(col, row, size);
                if w.min_element() >= -1e-6 {
                    covered[texel as usize] = true;
                    found.push(texel, pa * w.x + pb * w.y + pc * w.z);
                } else {
                    let (w, d) = nearest_on_triangle(q, a, b, c, area);
                    if d <= margin {
                        near.push((texel, pa * w.x + pb * w.y + pc * w.z, d));
                    }
                }
            }
        }
    }
    // The gutter: each uncovered texel takes its nearest triangle's point.
    near.sort_by(|x, y| x.0.cmp(&y.0).then(x.2.total_cmp(&y.2)));
    let mut last = None;
    for (texel, point, _) in near {
        if !covered[texel as usize] && last != Some(texel) {
            found.push(texel, point);
            last = Some(texel);
        }
    }
    Ok(())
}

/// Barycentric weights of `q` in triangle (a, b, c) of signed double area `area`.
fn barycentric(q: Vec2, a: Vec2, b: Vec2, c: Vec2, area: f32) -> Vec3 {
    let wa = (b - q).perp_dot(c - q) / area;
    let wb = (c - q).perp_dot(a - q) / area;
    Vec3::new(wa, wb, 1.0 - wa - wb)
}

/// The weights of the triangle's point nearest `q`, and its distance.
fn nearest_on_triangle(q: Vec2, a: Vec2, b: Vec2, c: Vec2, area: f32) -> (Vec3, f32) {
    let on_edge = |p: Vec2, r: Vec2| {
        let e = r - p;
        let t = ((q - p).dot(e) / e.length_squared().max(1e-20)).clamp(0.0, 1.0);
        (t, q.distance(p + e * t))
    };
    let (tab, dab) = on_edge(a, b);
    let (tbc, dbc) = on_edge(b, c);
    let (tca, dca) = on_edge(c, a);
    let best = [
        (Vec3::new(1.0 - tab, tab, 0.0), dab),
        (Vec3::new(0.0, 1.0 - tbc, tbc), dbc),
        (Vec3::new(tca, 0.0, 1.0 - tca), dca),
    ];
    let inside = barycentric(q, a, b, c, area);
    if inside.min_element() >= 0.0 {
        return (inside, 0.0);
    }
    best.into_iter().min_by(|x, y| x.1.total_cmp(&y.1)).unwrap()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;
    use wrinkle::Surface;

    #[test]
    fn sphere_points_lie_at_their_texels_uv() {
        let size = 128;
        let sphere = Surface::Sphere { radius: 1.0 };
        let points = SurfacePoints::of_primitives(&[Primitive::Parametric(sphere.clone())], size).unwrap();
        let centre = sphere.position(0.75, 0.5);
        let mut seen = Vec::new();
        points.within(centre, 0.3, |texel, p, d| {
            let (u, v) = texel_uv(texel as usize, size);
            assert!(sphere.position(u, v).distance(p) < 1e-5);
            assert!((p.distance(centre) - d).abs() < 1e-6 && d < 0.3);
            seen.push(texel);
        });
        // Every texel whose point lies within the radius, and no other: against a scan of all of them.
        let mut all: Vec<u32> = (0..size * size)
            .filter(|&k| {
                let (u, v) = texel_uv(k, size);
                sphere.position(u, v).distance(centre) < 0.3
            })
            .map(|k| k as u32)
            .collect();
        seen.sort();
        all.sort();
        assert_eq!(seen, all);
        assert!(seen.len() > 100, "{} texels", seen.len());
    }

    #[test]
    fn mesh_islands_bleed_into_a_gutter() {
        // One triangle in the lower-left half of the (u,v) square.
        let mesh = TriangleMesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            normals: vec![Vec3::Z; 3],
            uv_sets: vec![vec![Vec2::new(0.25, 0.25), Vec2::new(0.75, 0.25), Vec2::new(0.25, 0.75)]],
            tangents: Vec::new(),
            triangles: vec![[0, 1, 2]],
        };
        let size = 32;
        let points = SurfacePoints::of_primitives(&[Primitive::Mesh(Arc::new(mesh))], size).unwrap();
        let mut texels = Vec::new();
        points.within(Vec3::new(0.3, 0.3, 0.0), 10.0, |t, p, _| {
            assert!(p.z.abs() < 1e-6 && p.x >= -1e-6 && p.y >= -1e-6 && p.x + p.y <= 1.0 + 1e-5);
            texels.push(t as usize);
        });
        // The triangle covers about 32^2 / 8 = 128 texel centres; the gutter adds a band 4 texels wide
        // around its 55 texels of perimeter, with rounded corners: about 270.
        let inside = texels.iter().filter(|&&k| {
            let (u, v) = texel_uv(k, size);
            u >= 0.25 && v >= 0.25 && (u - 0.25) + (v - 0.25) <= 0.5
        });
        assert!((110..=140).contains(&inside.count()));
        let outside = texels.iter().filter(|&&k| {
            let (u, v) = texel_uv(k, size);
            u < 0.25 || v < 0.25 || (u - 0.25) + (v - 0.25) > 0.5
        });
        let gutter = outside.count();
        assert!((230..=300).contains(&gutter), "gutter texels {gutter}");
        // Nothing beyond the gutter.
        for &k in &texels {
            let (u, v) = texel_uv(k, size);
            assert!(u > 0.25 - 5.0 / 32.0 && v > 0.25 - 5.0 / 32.0, "texel {k} at ({u}, {v})");
        }
    }
}
