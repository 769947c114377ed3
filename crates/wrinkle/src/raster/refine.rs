//! Ray-exact (u,v). The rasterizer interpolates (u,v) over flat triangles inscribed in a curved surface,
//! so the exact point P(u,v) it names sits up to the triangles' sag away from the pixel's ray. One Newton
//! step on  screen(P(u,v)) = sample position  moves (u,v) onto the ray: the error falls from the sag
//! (a fraction of a pixel) to its square over the surface's radius of curvature (thousandths of a pixel).
//! For the usual short step the frame at the refined (u,v) comes from the second-order Taylor expansion of
//! the one already evaluated (what that leaves out is below f32 precision); longer steps evaluate it again.

use super::camera::Camera;
use crate::geometry::{Surface, SurfaceFrame};
use glam::{Affine3A, Vec2};

/// Refines `uv` so that the exact surface point lies on the ray through `screen`, and returns it with the
/// surface frame there. Steps longer than `max_step` (about one tessellation segment) are not taken: they
/// happen only where the ray grazes the surface or misses it, and there the interpolated (u,v) is kept.
#[inline]
pub fn refine_uv(
    camera: &Camera,
    surface: &Surface,
    object_to_camera: &Affine3A,
    uv: Vec2,
    screen: Vec2,
    max_step: Vec2,
) -> (Vec2, SurfaceFrame) {
    let frame = surface.frame(uv.x, uv.y);
    let p = object_to_camera.transform_point3(frame.p);
    let (s, _) = camera.project(p);
    let su = camera.project_derivative(p, object_to_camera.transform_vector3(frame.pu));
    let sv = camera.project_derivative(p, object_to_camera.transform_vector3(frame.pv));
    let r = screen - s;
    let det = su.x * sv.y - su.y * sv.x;
    if det.abs() < 1e-12 {
        return (uv, frame);
    }
    let step = Vec2::new(r.x * sv.y - r.y * sv.x, su.x * r.y - su.y * r.x) / det;
    if step.x.abs() > max_step.x || step.y.abs() > max_step.y || !step.is_finite() {
        return (uv, frame);
    }
    let (wrap_u, wrap_v) = surface.wraps();
    let settle = |x: f32, wraps: bool| if wraps { x - x.floor() } else { x.clamp(0.0, 1.0) };
    let refined = Vec2::new(settle(uv.x + step.x, wrap_u), settle(uv.y + step.y, wrap_v));
    // The usual step is a few hundredths of a segment, where the expansion is exact to f32 precision;
    // longer ones (towards grazing views) evaluate the surface again.
    let frame = if step.x.abs() < TAYLOR_STEP * max_step.x && step.y.abs() < TAYLOR_STEP * max_step.y {
        // Across a seam the wrapped coordinate jumps by one period; the surface moved by the step itself.
        let taken = |wraps: bool, from: f32, to: f32, step: f32| if wraps { step } else { to - from };
        frame.advanced(taken(wrap_u, uv.x, refined.x, step.x), taken(wrap_v, uv.y, refined.y, step.y))
    } else {
        surface.frame(refined.x, refined.y)
    };
    (refined, frame)
}

/// The largest step, as a fraction of a tessellation segment, taken by Taylor expansion of the frame.
const TAYLOR_STEP: f32 = 0.05;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::raster::Projection;
    use glam::Vec3;

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
            let (refined, frame) = refine_uv(&camera, &sphere, &to_cam, start, target, Vec2::splat(0.05));
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
                refine_uv(&camera, &sphere, &to_cam, Vec2::new(start_u, 0.5201), target, Vec2::splat(0.05));
            let got = screen_of(frame.p);
            assert!((got - target).length() < 2e-3, "{got} vs {target}");
            assert!((refined.x - true_u).abs() < 1e-4 && (0.0..1.0).contains(&refined.x), "{refined}");
            assert!((frame.p - sphere.position(refined.x, refined.y)).length() < 1e-5);
        }
    }
}
