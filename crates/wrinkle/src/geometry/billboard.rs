//! Billboards (the slides' "Sprites and Billboards"): a textured rectangle turned towards the camera every
//! frame, in one of three ways.
//! - screen: parallel to the screen, its up the screen's up (the camera's own frame);
//! - world: facing along the view direction, its up the world's `axis` (so it keeps world up when the
//!   camera rolls: the head may tilt);
//! - axis: turning only about the world's `axis` towards the eye (trees, flames).
//!
//! Its (u,v) run from (0, 0) at the bottom left to (1, 1) at the top right as the camera sees it.

use glam::Vec3;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Align {
    Screen,
    World,
    Axis,
}

impl Align {
    pub const NAMES: [(&'static str, Align); 3] =
        [("screen", Align::Screen), ("world", Align::World), ("axis", Align::Axis)];
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Billboard {
    pub width: f32,
    pub height: f32,
    pub align: Align,
    /// The world's up for `World`, the axis turned about for `Axis` (unit).
    pub axis: Vec3,
}

/// What a billboard turns towards: the camera's right, up and backward axes (it looks down -back) and,
/// for perspective views, the eye.
#[derive(Clone, Copy, Debug)]
pub struct Viewer {
    pub right: Vec3,
    pub up: Vec3,
    pub back: Vec3,
    pub eye: Option<Vec3>,
}

impl Billboard {
    /// The corners (bottom left, bottom right, top right, top left) of the billboard centred on `centre`
    /// (world space), turned towards `viewer`.
    pub fn corners(&self, centre: Vec3, viewer: &Viewer) -> [Vec3; 4] {
        let (right, up) = match self.align {
            Align::Screen => (viewer.right, viewer.up),
            Align::World => {
                let n = viewer.back;
                let up = (self.axis - n * n.dot(self.axis)).try_normalize().unwrap_or(viewer.up);
                (up.cross(n), up)
            }
            Align::Axis => {
                let up = self.axis;
                let to_eye = viewer.eye.map_or(viewer.back, |eye| eye - centre);
                let n = (to_eye - up * up.dot(to_eye)).try_normalize().unwrap_or_else(|| up.any_orthonormal_vector());
                (up.cross(n), up)
            }
        };
        let (r, u) = (right * (0.5 * self.width), up * (0.5 * self.height));
        [centre - r - u, centre + r - u, centre + r + u, centre - r + u]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn viewer() -> Viewer {
        // A camera rolled by 30 degrees, looking down -Z from (0, 0, 5).
        let (s, c) = 30f32.to_radians().sin_cos();
        Viewer {
            right: Vec3::new(c, s, 0.0),
            up: Vec3::new(-s, c, 0.0),
            back: Vec3::Z,
            eye: Some(Vec3::new(0.0, 0.0, 5.0)),
        }
    }

    fn frame(c: [Vec3; 4]) -> (Vec3, Vec3, Vec3) {
        let (r, u) = ((c[1] - c[0]).normalize(), (c[3] - c[0]).normalize());
        (r, u, r.cross(u))
    }

    #[test]
    fn each_alignment_turns_as_named() {
        let v = viewer();
        let centre = Vec3::new(2.0, 1.0, 0.0);
        let b = |align| Billboard { width: 2.0, height: 3.0, align, axis: Vec3::Y };
        let (r, u, n) = frame(b(Align::Screen).corners(centre, &v));
        assert!(r.distance(v.right) < 1e-6 && u.distance(v.up) < 1e-6 && n.distance(v.back) < 1e-6);
        let (_, u, n) = frame(b(Align::World).corners(centre, &v));
        assert!(u.distance(Vec3::Y) < 1e-6 && n.distance(v.back) < 1e-6, "world keeps +Y up: {u}");
        let (_, u, n) = frame(b(Align::Axis).corners(centre, &v));
        let to_eye = (v.eye.unwrap() - centre) * Vec3::new(1.0, 0.0, 1.0);
        assert!(u.distance(Vec3::Y) < 1e-6 && n.distance(to_eye.normalize()) < 1e-6, "axis faces the eye: {n}");
        let c = b(Align::Screen).corners(centre, &v);
        assert!((c[1].distance(c[0]) - 2.0).abs() < 1e-5 && (c[3].distance(c[0]) - 3.0).abs() < 1e-5);
        assert!(((c[0] + c[2]) * 0.5).distance(centre) < 1e-6);
    }
}
