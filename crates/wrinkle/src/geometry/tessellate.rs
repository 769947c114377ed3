//! Tessellation: a parametric surface becomes a grid of triangles carrying (u,v). The triangles only decide
//! which (u,v) lands in each pixel; the shader evaluates the exact surface there.
//!
//! Watertightness starts here: every grid vertex is computed once and shared by the triangles around it,
//! and the vertices of a wrapping seam (u = 1 beside u = 0) reuse the positions of the other side exactly.

use super::{Surface, TriangleMesh};
use glam::{Vec2, Vec3};
use rayon::prelude::*;

/// Triangles over one surface, in object space; each triangle runs counter-clockwise in (u,v),
/// so it faces the same way as N = Pu x Pv.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    /// Grid segments along u and v.
    pub segments: (usize, usize),
    /// Whether the grid closes on itself along u and along v (the surface's `wraps`).
    pub wraps: (bool, bool),
    pub positions: Vec<Vec3>,
    pub uvs: Vec<Vec2>,
    pub triangles: Vec<[u32; 3]>,
}

/// The most segments along one parameter; finer grids cost memory and add nothing visible.
pub const MAX_SEGMENTS: usize = 1024;

/// A grid of `nu` x `nv` quads, two triangles each; its rows of points made in parallel (the canonical
/// sphere's 38 k points took 0.6 ms of every frame on one thread).
pub fn grid(surface: &Surface, nu: usize, nv: usize) -> Mesh {
    let (wrap_u, wrap_v) = surface.wraps();
    let (nu, nv) = (nu.max(1), nv.max(1));
    let columns = nu + 1;
    let at = |i: usize, n: usize| i as f32 / n as f32;
    let mut positions = vec![Vec3::ZERO; columns * (nv + 1)];
    positions.par_chunks_mut(columns).enumerate().for_each(|(j, row)| {
        for (i, p) in row.iter_mut().enumerate() {
            // A seam takes the other side's point (the same arithmetic), so both sides meet exactly.
            let (si, sj) = (if wrap_u && i == nu { 0 } else { i }, if wrap_v && j == nv { 0 } else { j });
            *p = surface.position(at(si, nu), at(sj, nv));
        }
    });
    let uvs = (0..=nv).flat_map(|j| (0..=nu).map(move |i| Vec2::new(at(i, nu), at(j, nv)))).collect();
    let mut triangles = Vec::with_capacity(2 * nu * nv);
    for j in 0..nv {
        for i in 0..nu {
            let a = (j * columns + i) as u32;
            let b = a + 1;
            let c = a + columns as u32 + 1;
            let d = a + columns as u32;
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
    }
    Mesh { segments: (nu, nv), wraps: (wrap_u, wrap_v), positions, uvs, triangles }
}

impl Mesh {
    /// The triangles across the edges of triangle `t`, in the order of its corners (a-b, b-c, c-a), where
    /// there is one: across a wrapping seam too, none along an open edge of the grid. Quad (i, j) holds
    /// [a, b, c] and [a, c, d], with a = (i, j), b = (i+1, j), c = (i+1, j+1), d = (i, j+1).
    pub fn neighbours(&self, t: usize) -> [Option<usize>; 3] {
        let (nu, nv) = self.segments;
        let (q, (wrap_u, wrap_v)) = (t / 2, self.wraps);
        let (i, j) = (q % nu, q / nu);
        let left = if i > 0 { Some(q - 1) } else { wrap_u.then(|| q + nu - 1) };
        let right = if i + 1 < nu { Some(q + 1) } else { wrap_u.then(|| q + 1 - nu) };
        let below = if j > 0 { Some(q - nu) } else { wrap_v.then(|| q + nu * (nv - 1)) };
        let above = if j + 1 < nv { Some(q + nu) } else { wrap_v.then(|| q - nu * (nv - 1)) };
        if t.is_multiple_of(2) {
            [below.map(|q| 2 * q + 1), right.map(|q| 2 * q + 1), Some(t + 1)]
        } else {
            [Some(t - 1), above.map(|q| 2 * q), left.map(|q| 2 * q)]
        }
    }
}

/// The surface as a model's triangle mesh: the grid of `nu` x `nv` quads with its (u,v) and the exact
/// unit normal at every vertex (its limit where Pu x Pv vanishes, `SurfaceFrame::limit_normal`); where even
/// that vanishes the faces around the vertex decide.
pub fn triangle_mesh(surface: &Surface, nu: usize, nv: usize) -> TriangleMesh {
    let grid = grid(surface, nu, nv);
    let normals = grid.uvs.iter().map(|uv| surface.frame(uv.x, uv.y).limit_normal()).collect();
    let mut mesh = TriangleMesh {
        positions: grid.positions,
        normals,
        uv_sets: vec![grid.uvs],
        triangles: grid.triangles,
        ..TriangleMesh::default()
    };
    mesh.complete_normals();
    mesh
}

/// Chooses the grid for a surface so that each segment spans at most about `target_px` pixels on screen,
/// and so that the flat triangles sag at most about `sag_px` pixels from the curved surface: the (u,v) the
/// rasterizer interpolates then lands within that distance of the exact surface's.
/// `pixels_per_unit(p)` gives the local screen scale at an object-space point (0 where it is not visible).
/// A flat parallelogram needs one quad to be drawn (`Surface::is_parallelogram`), but gets segments by its
/// length here, for what moves its points (displacement).
pub fn segments_for(
    surface: &Surface,
    target_px: f32,
    sag_px: f32,
    pixels_per_unit: impl Fn(Vec3) -> f32,
) -> (usize, usize) {
    const K: usize = 16;
    let mut pts = Vec::with_capacity((K + 1) * (K + 1));
    for j in 0..=K {
        for i in 0..=K {
            pts.push(surface.position(i as f32 / K as f32, j as f32 / K as f32));
        }
    }
    let scale = pts.iter().map(|&p| pixels_per_unit(p)).fold(0.0_f32, f32::max);
    let at = |i: usize, j: usize| pts[j * (K + 1) + i];
    let (wrap_u, wrap_v) = surface.wraps();
    // Along each iso-curve: its length and how far its tangent turns. A curve of length L turning by T,
    // cut into n chords, sags by about T L / (8 n^2).
    let need = |curve: &dyn Fn(usize) -> Vec3, wraps: bool| -> usize {
        let chords: Vec<Vec3> = (0..K).map(|k| curve(k + 1) - curve(k)).collect();
        let len: f32 = chords.iter().map(|c| c.length()).sum::<f32>() * scale;
        let mut turn: f32 = chords.windows(2).map(|w| w[0].angle_between(w[1])).filter(|a| a.is_finite()).sum();
        if wraps {
            let a = chords[K - 1].angle_between(chords[0]);
            turn += if a.is_finite() { a } else { 0.0 };
        }
        let by_length = len / target_px;
        let by_sag = (turn * len / (8.0 * sag_px)).sqrt();
        by_length.max(by_sag).ceil() as usize
    };
    let (mut nu, mut nv) = (0, 0);
    for a in 0..=K {
        nu = nu.max(need(&|k| at(k, a), wrap_u));
        nv = nv.max(need(&|k| at(a, k), wrap_v));
    }
    let clamp = |n: usize, wraps: bool| n.clamp(if wraps { 8 } else { 2 }, MAX_SEGMENTS);
    (clamp(nu, wrap_u), clamp(nv, wrap_v))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sphere_seam_and_poles_share_positions() {
        let s = Surface::Sphere { radius: 1.0 };
        let m = grid(&s, 12, 6);
        let cols = 13;
        for j in 0..=6 {
            assert_eq!(m.positions[j * cols], m.positions[j * cols + 12]);
        }
        for i in 0..cols {
            assert_eq!(m.positions[i], m.positions[0]);
            assert_eq!(m.positions[6 * cols + i], m.positions[6 * cols]);
        }
        assert_eq!(m.triangles.len(), 12 * 6 * 2);
    }

    /// Each neighbour shares an edge (two vertex positions) with the triangle, and names it back.
    #[test]
    fn neighbours_share_edges() {
        for (surface, open) in [
            (Surface::Torus { major_radius: 1.0, minor_radius: 0.3 }, 0),
            (Surface::Cylinder { radius: 1.0, height: 1.0 }, 2 * 7),
        ] {
            let m = grid(&surface, 7, 5);
            let mut missing = 0;
            for t in 0..m.triangles.len() {
                for n in m.neighbours(t) {
                    let Some(n) = n else {
                        missing += 1;
                        continue;
                    };
                    let shared = m.triangles[t]
                        .iter()
                        .filter(|&&a| {
                            m.triangles[n].iter().any(|&b| m.positions[a as usize] == m.positions[b as usize])
                        })
                        .count();
                    assert_eq!(shared, 2, "{surface:?}: {t} and {n}");
                    assert!(m.neighbours(n).contains(&Some(t)));
                }
            }
            assert_eq!(missing, open, "{surface:?}");
        }
    }

    #[test]
    fn triangles_face_along_the_normal() {
        let s = Surface::Sphere { radius: 1.0 };
        let m = grid(&s, 16, 8);
        for t in &m.triangles {
            let [a, b, c] = t.map(|k| m.positions[k as usize]);
            let n = (b - a).cross(c - a);
            if n.length() > 1e-6 {
                assert!(n.dot(a + b + c) > 0.0);
            }
        }
    }

    #[test]
    fn segment_count_follows_screen_size() {
        let s = Surface::Sphere { radius: 1.0 };
        // Circumference 2 pi and meridian pi world units at 100 px per unit, 10 px per segment; a generous
        // sag allowance leaves the length the only limit.
        let (nu, nv) = segments_for(&s, 10.0, 100.0, |_| 100.0);
        assert!((60..=64).contains(&nu), "{nu}");
        assert!((30..=32).contains(&nv), "{nv}");
        // A small sphere (radius 20 px): the sag decides. The equator turns 2 pi over 2 pi 20 px, so
        // n = sqrt(2 pi * 40 pi / (8 * 0.05)) = 2 pi sqrt(20 / 0.4) ~ 44 chords (each sagging r (1 - cos(pi/n))).
        let (nu, _) = segments_for(&s, 10.0, 0.05, |_| 20.0);
        assert!((40..=48).contains(&nu), "{nu}");
        let sag = 20.0 * (1.0 - (std::f32::consts::PI / nu as f32).cos());
        assert!(sag < 0.06, "{sag}");
        // A flat unit square 1000 px across: the length alone decides.
        let flat = Surface::Patch { corners: [Vec3::ZERO, Vec3::X, Vec3::X + Vec3::Y, Vec3::Y] };
        assert_eq!(segments_for(&flat, 10.0, 0.05, |_| 1000.0), (100, 100));
    }
}
