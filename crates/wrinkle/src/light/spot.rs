//! Spot lights: a point light limited to a cone, with a soft edge, that may project a picture (the slides'
//! slide projector). Plain data: the picture is one of the scene's slides, by index.

use crate::lanes::{F8, V3};
use glam::Vec3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spot {
    pub position: Vec3,
    /// Colour x intensity; like a point light's, it falls off with the square of the distance.
    pub radiance: Vec3,
    /// The cone's axis (unit), and the slide's right and up axes, making a right-handed frame with -forward.
    pub forward: Vec3,
    pub right: Vec3,
    pub up: Vec3,
    /// The cosines of the cone's half-angle and of the angle where its soft edge begins.
    pub cos_outer: f32,
    pub cos_inner: f32,
    /// The tangent of the half-angle: the slide spans [-tan, tan] at unit distance along the axis.
    pub tan_half: f32,
    /// Which of the scene's slides it projects, if any.
    pub slide: Option<usize>,
}

impl Spot {
    /// A spot at `position` pointing along `direction` (any length), its cone `angle` degrees from the axis,
    /// softened over the last `falloff` degrees; the slide upright towards `up`.
    pub fn new(position: Vec3, direction: Vec3, up: Vec3, angle: f32, falloff: f32, radiance: Vec3) -> Spot {
        let forward = direction.normalize();
        let right = forward.cross(up).try_normalize().unwrap_or_else(|| forward.any_orthonormal_vector());
        let up = right.cross(forward);
        let (outer, inner) = (angle.to_radians(), (angle - falloff).max(0.0).to_radians());
        Spot {
            position,
            radiance,
            forward,
            right,
            up,
            cos_outer: outer.cos(),
            cos_inner: inner.cos(),
            tan_half: outer.tan(),
            slide: None,
        }
    }

    /// How much of the light reaches eight points: 1 inside the inner cone, 0 outside the outer one,
    /// smoothstep between (in the cosine of the angle from the axis).
    #[inline]
    pub fn cone8(&self, p: V3) -> F8 {
        let d = (p - V3::splat(self.position)).normalize_or_zero();
        let c = d.dot(V3::splat(self.forward));
        let span = (self.cos_inner - self.cos_outer).max(1e-6);
        let x = ((c - F8::splat(self.cos_outer)) * F8::splat(1.0 / span)).max(F8::ZERO).min(F8::ONE);
        x * x * (F8::splat(3.0) - x - x)
    }

    /// Where eight points fall on the slide: (s, t) in [0, 1] across the cone's square, t up; and the
    /// distance along the axis (points behind the light have it negative).
    #[inline]
    pub fn slide8(&self, p: V3) -> (F8, F8, F8) {
        let d = p - V3::splat(self.position);
        let z = d.dot(V3::splat(self.forward));
        let k = F8::splat(0.5 / self.tan_half) / z;
        let half = F8::splat(0.5);
        (half + d.dot(V3::splat(self.right)) * k, half + d.dot(V3::splat(self.up)) * k, z)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cone_and_slide_follow_the_axis() {
        let spot = Spot::new(Vec3::new(0.0, 4.0, 0.0), -Vec3::Y, Vec3::Z, 30.0, 10.0, Vec3::ONE);
        let at = |p: Vec3| spot.cone8(V3::splat(p)).as_array_ref()[0];
        // On the axis, inside 20 degrees, at 25 degrees (between), beyond 30.
        assert_eq!(at(Vec3::ZERO), 1.0);
        assert_eq!(at(Vec3::new(4.0 * 19f32.to_radians().tan(), 0.0, 0.0)), 1.0);
        let mid = at(Vec3::new(4.0 * 25f32.to_radians().tan(), 0.0, 0.0));
        assert!(mid > 0.2 && mid < 0.8, "{mid}");
        assert_eq!(at(Vec3::new(4.0 * 31f32.to_radians().tan(), 0.0, 0.0)), 0.0);
        // The slide: its centre on the axis, its right edge at the cone's edge along `right`.
        let (s, t, z) = spot.slide8(V3::splat(Vec3::ZERO));
        assert_eq!((s.as_array_ref()[0], t.as_array_ref()[0], z.as_array_ref()[0]), (0.5, 0.5, 4.0));
        let edge = spot.position + 4.0 * spot.forward + 4.0 * spot.tan_half * spot.right;
        let (s, _, _) = spot.slide8(V3::splat(edge));
        assert!((s.as_array_ref()[0] - 1.0).abs() < 1e-5);
    }
}
