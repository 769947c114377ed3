//! Ray-exact (u,v). The rasterizer interpolates (u,v) over flat triangles inscribed in a curved surface,
//! so the exact point P(u,v) it names sits up to the triangles' sag away from the pixel's ray. One Newton
//! step on  screen(P(u,v)) = sample position  moves (u,v) onto the ray: the error falls from the sag
//! (a fraction of a pixel) to its square over the surface's radius of curvature (thousandths of a pixel).
//! For the usual short step the frame at the refined (u,v) comes from the second-order Taylor expansion of
//! the one already evaluated (what that leaves out is below f32 precision); longer steps evaluate it again.

use super::camera::Camera;
use super::setup::ScreenTriangle;
use crate::geometry::frame_lanes::Frame8;
use crate::geometry::Surface;
use crate::lanes::{CmpLt, F8, LANES, V3};
use glam::{Affine3A, Vec2};

/// Refines eight (u,v) so that each exact surface point lies on the ray through its screen position, and
/// returns them with the surface frames there. Steps longer than `max_step` (about one tessellation segment)
/// are not taken: they happen only where the ray grazes the surface or misses it, and there the interpolated
/// (u,v) is kept.
#[inline(always)]
pub fn refine_uv8(
    camera: &Camera,
    surface: &Surface,
    object_to_camera: &Affine3A,
    uv: (F8, F8),
    screen: (F8, F8),
    max_step: Vec2,
) -> ((F8, F8), Frame8) {
    let (u, v) = uv;
    let frame = surface.frame8(u, v);
    let at = OnScreen8::of(camera, object_to_camera, &frame);
    let (det, (step_u, step_v)) = (at.det(), at.step_to(screen));
    let max = (F8::splat(max_step.x), F8::splat(max_step.y));
    let taken = F8::splat(1e-12).cmp_lt(det.abs())
        & step_u.is_finite()
        & step_v.is_finite()
        & !max.0.cmp_lt(step_u.abs())
        & !max.1.cmp_lt(step_v.abs());
    let (step_u, step_v) = (taken.blend(step_u, F8::ZERO), taken.blend(step_v, F8::ZERO));
    let (wrap_u, wrap_v) = surface.wraps();
    let settle = |x: F8, wraps: bool| if wraps { x - x.floor() } else { x.max(F8::ZERO).min(F8::ONE) };
    let refined = (taken.blend(settle(u + step_u, wrap_u), u), taken.blend(settle(v + step_v, wrap_v), v));
    // Across a seam the wrapped coordinate jumps by one period; the surface moved by the step itself.
    let moved = |wraps: bool, from: F8, to: F8, step: F8| if wraps { step } else { to - from };
    let mut out = frame.advanced(moved(wrap_u, u, refined.0, step_u), moved(wrap_v, v, refined.1, step_v));
    // The usual step is a few hundredths of a segment, where the expansion is exact to f32 precision;
    // longer ones (towards grazing views) evaluate the surface again.
    let short =
        step_u.abs().cmp_lt(max.0 * F8::splat(TAYLOR_STEP)) & step_v.abs().cmp_lt(max.1 * F8::splat(TAYLOR_STEP));
    let long = short.move_mask() ^ 0xff;
    if long != 0 {
        let (ru, rv) = (refined.0.as_array_ref(), refined.1.as_array_ref());
        for i in (0..LANES).filter(|i| long & (1 << i) != 0) {
            out.set_lane(i, &surface.frame(ru[i], rv[i]));
        }
    }
    (refined, out)
}

/// Where eight surface points land on the screen, and how their screen positions change with u and v.
#[derive(Clone, Copy)]
pub struct OnScreen8 {
    pub x: F8,
    pub y: F8,
    /// d(x, y)/du and d(x, y)/dv.
    pub su: (F8, F8),
    pub sv: (F8, F8),
}

impl OnScreen8 {
    #[inline(always)]
    pub fn of(camera: &Camera, object_to_camera: &Affine3A, frame: &Frame8) -> OnScreen8 {
        let p = V3::transform_point(object_to_camera, frame.p);
        let (x, y) = camera.project8(p);
        let su = camera.project_derivative8(p, V3::transform_vector(object_to_camera, frame.pu));
        let sv = camera.project_derivative8(p, V3::transform_vector(object_to_camera, frame.pv));
        OnScreen8 { x, y, su, sv }
    }

    /// The determinant of the Jacobian d(x, y)/d(u, v).
    #[inline(always)]
    pub fn det(&self) -> F8 {
        self.su.0 * self.sv.1 - self.su.1 * self.sv.0
    }

    /// The Newton step (du, dv) that moves the points onto the screen positions `to`.
    #[inline(always)]
    pub fn step_to(&self, to: (F8, F8)) -> (F8, F8) {
        let (rx, ry) = (to.0 - self.x, to.1 - self.y);
        let inv_det = F8::ONE / self.det();
        ((rx * self.sv.1 - ry * self.sv.0) * inv_det, (self.su.0 * ry - self.su.1 * rx) * inv_det)
    }

    /// du/dx, dv/dx, du/dy, dv/dy: the inverse of the Jacobian, the (u,v) footprint of one pixel.
    #[inline]
    pub fn uv_derivatives(&self) -> [F8; 4] {
        let inv_det = F8::ONE / self.det();
        [self.sv.1 * inv_det, -self.su.1 * inv_det, -self.sv.0 * inv_det, self.su.0 * inv_det]
    }
}

/// The largest step, as a fraction of a tessellation segment, taken by Taylor expansion of the frame.
const TAYLOR_STEP: f32 = 0.05;

/// (u,v) interpolated linearly on the screen across each lane's triangle instead of perspective-correctly
/// (the course's "Uh oh"): the triangle's corners, P at their (u,v) projected onto the screen, give the
/// sample's screen barycentrics. Lane by lane: it serves a comparison, not speed, and keeps the screen
/// triangles free of anything only it would read.
pub fn affine_uv8(
    camera: &Camera,
    surface: &Surface,
    object_to_camera: &Affine3A,
    tris: &[&ScreenTriangle; LANES],
    screen: (F8, F8),
) -> (F8, F8) {
    let (sx, sy) = (screen.0.as_array_ref(), screen.1.as_array_ref());
    let uv: [Vec2; LANES] = std::array::from_fn(|i| {
        let corners = tris[i].uv;
        let at = corners.map(|c| camera.project(object_to_camera.transform_point3(surface.position(c.x, c.y))).0);
        let (e1, e2, p) = (at[1] - at[0], at[2] - at[0], Vec2::new(sx[i], sy[i]) - at[0]);
        let det = e1.perp_dot(e2);
        if det == 0.0 {
            return corners[0];
        }
        let (l1, l2) = (p.perp_dot(e2) / det, e1.perp_dot(p) / det);
        corners[0] + (corners[1] - corners[0]) * l1 + (corners[2] - corners[0]) * l2
    });
    (F8::new(uv.map(|t| t.x)), F8::new(uv.map(|t| t.y)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::SurfaceFrame;
    use crate::raster::Projection;
    use glam::Vec3;

    /// One (u,v) refined in every lane; lane 3 is read back (all lanes agree).
    fn refine_one(
        camera: &Camera,
        surface: &Surface,
        to_cam: &Affine3A,
        uv: Vec2,
        screen: Vec2,
        max_step: Vec2,
    ) -> (Vec2, SurfaceFrame) {
        let s = |x: f32| F8::splat(x);
        let ((u, v), frame) =
            refine_uv8(camera, surface, to_cam, (s(uv.x), s(uv.y)), (s(screen.x), s(screen.y)), max_step);
        (Vec2::new(u.as_array_ref()[3], v.as_array_ref()[3]), frame.lane(3))
    }

    /// A 400x300 perspective view of the origin from `eye`, and the screen position of a world point.
    fn view_from(eye: Vec3) -> (Camera, impl Fn(Vec3) -> Vec2) {
        let camera = Camera::new(eye, Vec3::ZERO, Vec3::Y, Projection::Perspective { fov_y: 40.0 }, 400, 300);
        let view = camera.clone();
        (camera, move |p: Vec3| view.project(view.world_to_camera.transform_point3(p)).0)
    }

    /// The refined point projects onto the sample position, to a small fraction of the initial error.
    #[test]
    fn one_step_lands_on_the_ray() {
        let (camera, screen_of) = view_from(Vec3::new(0.3, 0.2, 4.0));
        let sphere = Surface::Sphere { radius: 1.0 };
        let to_cam = camera.world_to_camera;
        for &(u, v) in &[(0.7, 0.5), (0.8, 0.62), (0.66, 0.3)] {
            // The true point's screen position, and a (u,v) nudged off it by about half a pixel's worth.
            let target = screen_of(sphere.position(u, v));
            let start = Vec2::new(u + 0.0006, v - 0.0004);
            let start_screen = screen_of(sphere.position(start.x, start.y));
            let (refined, frame) = refine_one(&camera, &sphere, &to_cam, start, target, Vec2::splat(0.05));
            let got = screen_of(frame.p);
            let before = (start_screen - target).length();
            let after = (got - target).length();
            assert!(before > 0.2, "{before}");
            assert!(after < 2e-3 && after < before * 0.01, "{before} px -> {after} px");
            assert!((refined - Vec2::new(u, v)).length() < 1e-4);
        }
    }

    /// A step across the sphere's seam (u = 1 beside u = 0) wraps u and still lands on the ray.
    #[test]
    fn steps_across_the_seam() {
        // Looking at the seam (+x side of the sphere) from an angle.
        let (camera, screen_of) = view_from(Vec3::new(4.0, 0.5, 1.5));
        let sphere = Surface::Sphere { radius: 1.0 };
        let to_cam = camera.world_to_camera;
        for &(start_u, true_u) in &[(0.9998, 0.0003), (0.0002, 0.9997)] {
            let target = screen_of(sphere.position(true_u, 0.52));
            let (refined, frame) =
                refine_one(&camera, &sphere, &to_cam, Vec2::new(start_u, 0.5201), target, Vec2::splat(0.05));
            let got = screen_of(frame.p);
            assert!((got - target).length() < 2e-3, "{got} vs {target}");
            assert!((refined.x - true_u).abs() < 1e-4 && (0.0..1.0).contains(&refined.x), "{refined}");
            assert!((frame.p - sphere.position(refined.x, refined.y)).length() < 1e-5);
        }
    }
}
