//! Exact coverage along the outline of a parametric surface. The tessellation is inscribed in the curved
//! surface, so the flat triangles' outline on screen lies up to their sag (a quarter pixel) inside the
//! surface's. The triangles along the outline are therefore widened on screen (`OUTLINE_MARGIN_PX`), and
//! the samples they cover (at a fold all of them, along an open edge those of the margin) ask the exact
//! surface whether their ray meets it: the sphere by its quadratic, the other surfaces by Newton's method on
//! screen(P(u,v)) = sample position, started from the triangle's (u,v). Samples whose ray misses are given
//! to what lies behind (the visibility buffer's `peel`).

use super::camera::Camera;
use super::refine::OnScreen8;
use crate::geometry::frame_lanes::Frame8;
use crate::geometry::mesh_lanes::Rays8;
use crate::geometry::tessellate::Mesh;
use crate::geometry::{Surface, SurfaceFrame};
use crate::lanes::{mask_of, CmpGt, CmpLt, F8, LANES};
use glam::{Affine3A, DVec3, Vec2, Vec3};
use rayon::prelude::*;

/// How far (in pixels) the triangles along an outline are widened: twice the tessellation's sag allowance,
/// which is itself an estimate.
pub const OUTLINE_MARGIN_PX: f32 = 0.5;

/// Where a triangle lies against its surface's outline on screen.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Outline {
    /// Inside: the flat triangle's samples are the surface's.
    #[default]
    Inside,
    /// Along a curved open edge of the surface: the samples of the widened margin are tested. The flat
    /// triangle's own samples are taken as the surface's, which leaves up to the sag where the edge curves
    /// in on screen.
    Edge,
    /// Where the surface turns away from the eye (or beside a pole): every sample is tested, since near a
    /// fold of a surface that is not convex the flat triangle may also reach beyond the surface.
    Fold,
}

/// Newton steps at most; each halves the distance to a solution near the fold of the outline, and then
/// converges quadratically.
const NEWTON_STEPS: usize = 16;

/// A ray meets the surface where the exact point is this close to it on screen (pixels): above the f32
/// rounding of screen positions (1e-4 px at 2000 px), below the 1e-3 px left open at the outline.
const HIT_PX: f32 = 5e-4;

/// Where the rays through `screen` meet `surface` (placed by `object_to_camera`) in the lanes `lanes`
/// (bit i: lane i), starting from the (u,v) `start` of the triangle each sample was found on: the lanes
/// whose ray meets it (bit i: lane i), and the (u,v) there (elsewhere the start). `max_step` is one
/// tessellation segment in (u,v).
#[allow(clippy::too_many_arguments)]
pub fn exact8(
    camera: &Camera,
    surface: &Surface,
    object_to_camera: &Affine3A,
    camera_to_object: &Affine3A,
    start: (F8, F8),
    screen: (F8, F8),
    max_step: Vec2,
    lanes: u8,
) -> (u8, (F8, F8)) {
    match *surface {
        Surface::Sphere { radius } => {
            let rays = camera.rays8(screen.0, screen.1, 1.0).transformed(camera_to_object);
            sphere_hits(radius, &rays, start, lanes)
        }
        _ => newton_hits(camera, surface, object_to_camera, start, screen, max_step, lanes),
    }
}

/// The surface frames at eight (u,v) (lane by lane for the lanes `lanes` alone, but the sphere's on all),
/// and the (u,v) footprint of a pixel there: du/dx, dv/dx, du/dy, dv/dy.
pub fn frames_at(
    camera: &Camera,
    surface: &Surface,
    object_to_camera: &Affine3A,
    uv: (F8, F8),
    lanes: u8,
) -> (Frame8, [F8; 4]) {
    let frame = if let Surface::Sphere { .. } = surface {
        surface.frame8(uv.0, uv.1)
    } else {
        let mut frames = [SurfaceFrame::default(); LANES];
        surface.frames_of_lanes(uv.0, uv.1, lanes, &mut frames);
        Frame8::from_lanes(&frames)
    };
    let duv = OnScreen8::of(camera, object_to_camera, &frame).uv_derivatives();
    (frame, duv)
}

/// The sphere's first crossing with each ray, in double precision: near the outline the discriminant is
/// the small difference of two large numbers.
fn sphere_hits(radius: f32, rays: &Rays8, start: (F8, F8), lanes: u8) -> (u8, (F8, F8)) {
    let (mut u, mut v) = (*start.0.as_array_ref(), *start.1.as_array_ref());
    let mut hits = 0;
    for i in (0..LANES).filter(|i| lanes >> i & 1 == 1) {
        let (o, d) = (rays.origin.lane(i).as_dvec3(), rays.dir.lane(i).as_dvec3());
        let r = radius as f64;
        let (a, b, c) = (d.dot(d), o.dot(d), o.dot(o) - r * r);
        let disc = b * b - a * c;
        if disc < 0.0 || a == 0.0 {
            continue;
        }
        let t = (-b - disc.sqrt()) / a;
        hits |= 1 << i;
        (u[i], v[i]) = sphere_uv(o + d * t, r);
    }
    (hits, (F8::new(u), F8::new(v)))
}

/// The inverse of the sphere's parametrisation (geometry/surface.rs): longitude from +x towards -z, and
/// latitude from the south pole.
fn sphere_uv(p: DVec3, r: f64) -> (f32, f32) {
    use std::f64::consts::{PI, TAU};
    let u = (-p.z).atan2(p.x) / TAU;
    let v = (p.y / r).clamp(-1.0, 1.0).asin() / PI + 0.5;
    ((u - u.floor()) as f32, v as f32)
}

/// Newton's method, lane by lane for the surface (the sphere, the one surface on lanes, has its own test)
/// and on lanes for the rest: each lane stops where its point lies within `HIT_PX` of its ray on screen, and
/// hits there if (u,v) lies on the surface (inside [0,1] in a parameter that does not wrap). A lane gives
/// up where its step is not finite or it has left the surface by a whole period.
fn newton_hits(
    camera: &Camera,
    surface: &Surface,
    object_to_camera: &Affine3A,
    start: (F8, F8),
    screen: (F8, F8),
    max_step: Vec2,
    lanes: u8,
) -> (u8, (F8, F8)) {
    let (wrap_u, wrap_v) = surface.wraps();
    let (mut u, mut v) = start;
    let (mut converged, mut done) = (0u8, !lanes);
    let close = F8::splat(HIT_PX * HIT_PX);
    // A step longer than a segment is shortened to one, keeping its direction.
    let (max_u, max_v) = (F8::splat(max_step.x.max(1e-6)), F8::splat(max_step.y.max(1e-6)));
    let far = |x: F8, wraps: bool| {
        if wraps {
            0
        } else {
            ((x - F8::splat(0.5)).abs().cmp_gt(F8::splat(1.5))).move_mask() as u8
        }
    };
    let mut frames = [SurfaceFrame::default(); LANES];
    for _ in 0..NEWTON_STEPS {
        surface.frames_of_lanes(u, v, !done, &mut frames);
        let at = OnScreen8::of(camera, object_to_camera, &Frame8::from_lanes(&frames));
        let (rx, ry) = (screen.0 - at.x, screen.1 - at.y);
        let close_now = (rx * rx + ry * ry).cmp_lt(close).move_mask() as u8 & !done;
        converged |= close_now;
        done |= close_now;
        if done == 0xff {
            break;
        }
        let (du, dv) = at.step_to(screen);
        let longest = (du.abs() / max_u).max(dv.abs() / max_v).max(F8::ONE);
        let (du, dv) = (du / longest, dv / longest);
        done |= !(du.is_finite() & dv.is_finite()).move_mask() as u8;
        let moving = mask_of(!done);
        let wrap = |x: F8, wraps: bool| if wraps { x - x.floor() } else { x };
        u = moving.blend(wrap(u + du, wrap_u), u);
        v = moving.blend(wrap(v + dv, wrap_v), v);
        done |= far(u, wrap_u) | far(v, wrap_v);
    }
    let inside =
        |x: F8, wraps: bool| if wraps { 0xff } else { (!x.cmp_lt(F8::ZERO) & !F8::ONE.cmp_lt(x)).move_mask() as u8 };
    (converged & inside(u, wrap_u) & inside(v, wrap_v), (u, v))
}

/// Where each triangle of a surface's grid lies against its outline on screen, given the grid's vertices in
/// camera space: a fold where it faces the eye the other way from a neighbour (or a neighbour is degenerate,
/// at a pole), an edge along a curved open edge of the surface.
pub fn outline_triangles(
    surface: &Surface,
    grid: &Mesh,
    camera_position: impl Fn(u32) -> Vec3 + Sync,
    perspective: bool,
) -> Vec<Outline> {
    if surface.is_parallelogram() {
        return vec![Outline::Inside; grid.triangles.len()];
    }
    // A bilinear patch's edges are straight: its triangles follow them exactly.
    let curved_edges = !matches!(surface, Surface::Patch { .. });
    // Both passes in parallel chunks: the grids of large surfaces have hundreds of thousands of triangles.
    const CHUNK: usize = 4096;
    let facing: Vec<i8> = grid
        .triangles
        .par_iter()
        .with_min_len(CHUNK)
        .map(|t| {
            let [a, b, c] = t.map(&camera_position);
            let towards_eye = if perspective { -a } else { Vec3::Z };
            let f = (b - a).cross(c - a).dot(towards_eye);
            (f > 0.0) as i8 - (f < 0.0) as i8
        })
        .collect();
    (0..grid.triangles.len())
        .into_par_iter()
        .with_min_len(CHUNK)
        .map(|t| {
            let neighbours = grid.neighbours(t);
            if facing[t] == 0 || neighbours.iter().flatten().any(|&n| facing[n] != facing[t]) {
                Outline::Fold
            } else if curved_edges && neighbours.contains(&None) {
                Outline::Edge
            } else {
                Outline::Inside
            }
        })
        .collect()
}

/// The lanes (bit i: lane i, of the first `len`) whose samples the exact test decides: those on fold
/// triangles, and those on edge triangles outside the flat triangle (barycentrics `bary`).
pub fn tested_lanes(outlines: [Outline; LANES], bary: [F8; 2], len: usize) -> u8 {
    let [b1, b2] = bary;
    let inside =
        (!b1.cmp_lt(F8::ZERO) & !b2.cmp_lt(F8::ZERO) & !F8::ONE.cmp_lt(b1 + b2) & b1.is_finite() & b2.is_finite())
            .move_mask();
    (0..len).fold(0, |bits, i| match outlines[i] {
        Outline::Inside => bits,
        Outline::Edge if inside >> i & 1 == 1 => bits,
        _ => bits | 1 << i,
    })
}

/// A (u,v) to start from for each lane: the interpolated one kept within its triangle's (u,v) bounds (beyond
/// the flat triangle, where the widened outline's samples lie, the interpolation extrapolates, and on a
/// triangle seen edge-on it may not be finite).
pub fn start_within(uv: (F8, F8), corners: &[[Vec2; 3]; LANES]) -> (F8, F8) {
    let (u, v) = (uv.0.as_array_ref(), uv.1.as_array_ref());
    let keep = |x: f32, lo: f32, hi: f32| if x.is_finite() { x.clamp(lo, hi) } else { 0.5 * (lo + hi) };
    let lanes: [Vec2; LANES] = std::array::from_fn(|i| {
        let c = corners[i];
        let (lo, hi) = (c[0].min(c[1]).min(c[2]), c[0].max(c[1]).max(c[2]));
        Vec2::new(keep(u[i], lo.x, hi.x), keep(v[i], lo.y, hi.y))
    });
    (F8::new(lanes.map(|p| p.x)), F8::new(lanes.map(|p| p.y)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::raster::camera::Projection;

    fn camera() -> Camera {
        Camera::new(Vec3::new(0.3, 0.4, 5.0), Vec3::ZERO, Vec3::Y, Projection::Perspective { fov_y: 30.0 }, 320, 240)
    }

    /// The sphere's inverse parametrisation gives back (u,v).
    #[test]
    fn sphere_uv_inverts_the_parametrisation() {
        let s = Surface::Sphere { radius: 1.5 };
        for &(u, v) in &[(0.1, 0.2), (0.6, 0.9), (0.99, 0.5), (0.3, 0.01)] {
            let (gu, gv) = sphere_uv(s.position(u, v).as_dvec3(), 1.5);
            assert!((gu - u).abs() < 1e-5 && (gv - v).abs() < 1e-5, "({u},{v}) -> ({gu},{gv})");
        }
    }

    /// Newton from a nearby (u,v) finds the point of a torus on a sample's ray, and refuses rays that pass
    /// beside a bicubic patch's edge.
    #[test]
    fn newton_hits_and_misses() {
        let cam = camera();
        let to_cam = cam.world_to_camera;
        let torus = Surface::Torus { major_radius: 1.0, minor_radius: 0.3 };
        let target = cam.project(to_cam.transform_point3(torus.position(0.31, 0.12))).0;
        let s = F8::splat;
        let (hits, (u, v)) =
            newton_hits(&cam, &torus, &to_cam, (s(0.3), s(0.1)), (s(target.x), s(target.y)), Vec2::splat(0.05), 0xff);
        assert_eq!(hits, 0xff);
        let got = cam.project(to_cam.transform_point3(torus.position(u.as_array_ref()[0], v.as_array_ref()[0]))).0;
        assert!((got - target).length() < HIT_PX, "{got} vs {target}");

        // A flat bicubic patch over [-1,1]^2 at z = 0: a sample two pixels beyond its right edge misses.
        let mut points = [Vec3::ZERO; 16];
        for (k, p) in points.iter_mut().enumerate() {
            *p = Vec3::new((k % 4) as f32 * 2.0 / 3.0 - 1.0, (k / 4) as f32 * 2.0 / 3.0 - 1.0, 0.0);
        }
        let patch = Surface::Bicubic { points };
        let edge = cam.project(to_cam.transform_point3(Vec3::new(1.0, 0.0, 0.0))).0;
        let (hits, _) =
            newton_hits(&cam, &patch, &to_cam, (s(0.98), s(0.5)), (s(edge.x + 2.0), s(edge.y)), Vec2::splat(0.1), 0xff);
        assert_eq!(hits, 0);
    }
}
