//! Clipping in camera space, before projection: against the near plane (so nothing behind the eye is
//! projected) and against a wide guard band around the screen (so fixed-point coordinates never overflow).
//!
//! A shared edge is cut at bit-identical points in both triangles that share it: the intersection is always
//! computed from the lexicographically smaller endpoint, so clipping keeps the mesh watertight.

use super::camera::{Camera, Projection, NEAR};
use crate::lanes::{CmpEq, CmpGe, F8, V3};
use glam::{Vec2, Vec3, Vec4};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClipVertex {
    pub pos: Vec3,
    pub uv: Vec2,
}

/// How far beyond the screen (in screen sizes) geometry is kept before the guard band cuts it.
const GUARD: f32 = 4.0;

/// The planes a camera clips against, as (n, d) with inside where n . p + d >= 0.
pub fn clip_planes(camera: &Camera) -> [Vec4; 5] {
    let (w, h) = (camera.width as f32, camera.height as f32);
    let gx = (GUARD + 0.5) * w.max(h) / camera.scale;
    let near = Vec4::new(0.0, 0.0, -1.0, -NEAR);
    match camera.projection {
        Projection::Perspective { .. } => [
            near,
            // gx * (-z) - x >= 0 and gx * (-z) + x >= 0, the same for y.
            Vec4::new(-1.0, 0.0, -gx, 0.0),
            Vec4::new(1.0, 0.0, -gx, 0.0),
            Vec4::new(0.0, -1.0, -gx, 0.0),
            Vec4::new(0.0, 1.0, -gx, 0.0),
        ],
        Projection::Orthographic { .. } => [
            near,
            Vec4::new(-1.0, 0.0, 0.0, gx),
            Vec4::new(1.0, 0.0, 0.0, gx),
            Vec4::new(0.0, -1.0, 0.0, gx),
            Vec4::new(0.0, 1.0, 0.0, gx),
        ],
    }
}

#[inline]
fn distance(plane: Vec4, p: Vec3) -> f32 {
    plane.x * p.x + plane.y * p.y + plane.z * p.z + plane.w
}

/// Whether a point lies inside every plane.
#[inline]
pub fn inside_all(planes: &[Vec4; 5], p: &Vec3) -> bool {
    planes.iter().all(|&pl| distance(pl, *p) >= 0.0)
}

/// `inside_all` of eight points, as a mask set on the lanes inside (the same sums in the same order).
#[inline(always)]
pub fn inside_all8(planes: &[Vec4; 5], p: &V3) -> F8 {
    let distance = |pl: &Vec4| F8::splat(pl.x) * p.x + F8::splat(pl.y) * p.y + F8::splat(pl.z) * p.z + F8::splat(pl.w);
    let every_lane = F8::ZERO.cmp_eq(F8::ZERO);
    planes.iter().fold(every_lane, |all, pl| all & distance(pl).cmp_ge(F8::ZERO))
}

fn key(p: Vec3) -> [u32; 3] {
    [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()]
}

/// The point where the edge a-b meets the plane, computed the same way whichever way round the edge is given.
fn intersect(plane: Vec4, a: ClipVertex, b: ClipVertex) -> ClipVertex {
    let (a, b) = if key(a.pos) <= key(b.pos) { (a, b) } else { (b, a) };
    let (da, db) = (distance(plane, a.pos), distance(plane, b.pos));
    let t = da / (da - db);
    ClipVertex { pos: a.pos + (b.pos - a.pos) * t, uv: a.uv + (b.uv - a.uv) * t }
}

/// Sutherland-Hodgman: clips the triangle against every plane, into `out` (a convex polygon, possibly empty).
pub fn clip_polygon(planes: &[Vec4; 5], tri: &[ClipVertex; 3], out: &mut Vec<ClipVertex>) {
    out.clear();
    out.extend_from_slice(tri);
    let mut scratch = Vec::with_capacity(9);
    for &plane in planes {
        if out.is_empty() {
            return;
        }
        scratch.clear();
        for k in 0..out.len() {
            let (a, b) = (out[k], out[(k + 1) % out.len()]);
            let (ia, ib) = (distance(plane, a.pos) >= 0.0, distance(plane, b.pos) >= 0.0);
            if ia {
                scratch.push(a);
            }
            if ia != ib {
                scratch.push(intersect(plane, a, b));
            }
        }
        std::mem::swap(out, &mut scratch);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn near_plane_cuts_and_interpolates_uv() {
        let cam = Camera::new(Vec3::ZERO, -Vec3::Z, Vec3::Y, Projection::Perspective { fov_y: 60.0 }, 100, 100);
        let planes = clip_planes(&cam);
        let v = |z: f32, u: f32| ClipVertex { pos: Vec3::new(0.0, 0.1, z), uv: Vec2::new(u, 0.0) };
        let tri = [v(-1.0, 0.0), ClipVertex { pos: Vec3::new(0.1, -0.1, 1.0), uv: Vec2::new(1.0, 0.0) }, v(-3.0, 0.5)];
        let mut out = Vec::new();
        clip_polygon(&planes, &tri, &mut out);
        assert_eq!(out.len(), 4);
        for c in &out {
            assert!(c.pos.z <= -NEAR + 1e-6);
        }
        // Swapping the order of a shared edge gives the same cut point, bit for bit.
        let (a, b) = (tri[0], tri[1]);
        assert_eq!(intersect(planes[0], a, b), intersect(planes[0], b, a));
    }
}
