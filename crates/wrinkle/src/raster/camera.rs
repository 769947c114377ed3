//! The camera: a right-handed frame looking down its -Z axis, perspective or orthographic projection
//! onto a screen of pixels with row 0 at the top.

use crate::geometry::mesh_lanes::Rays8;
use crate::lanes::{mul_add, F8, V3};
use glam::{Affine3A, Vec2, Vec3};

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// Full vertical field of view in degrees; the image aspect sets the horizontal one.
    Perspective { fov_y: f32 },
    /// World units seen vertically.
    Orthographic { height: f32 },
}

#[derive(Clone, Debug)]
pub struct Camera {
    pub eye: Vec3,
    pub world_to_camera: Affine3A,
    pub camera_to_world: Affine3A,
    pub projection: Projection,
    pub width: u32,
    pub height: u32,
    /// Pixels per unit of x/w (perspective) or per world unit (orthographic).
    pub scale: f32,
}

/// Nothing nearer than this (in front of the eye) is drawn.
pub const NEAR: f32 = 1e-3;

impl Camera {
    /// `up` need not be perpendicular to the view direction, only not parallel to it.
    pub fn new(eye: Vec3, look_at: Vec3, up: Vec3, projection: Projection, width: u32, height: u32) -> Camera {
        let world_to_camera = Affine3A::look_at_rh(eye, look_at, up);
        let scale = match projection {
            Projection::Perspective { fov_y } => 0.5 * height as f32 / (0.5 * fov_y.to_radians()).tan(),
            Projection::Orthographic { height: h } => height as f32 / h,
        };
        Camera { eye, world_to_camera, camera_to_world: world_to_camera.inverse(), projection, width, height, scale }
    }

    pub fn is_perspective(&self) -> bool {
        matches!(self.projection, Projection::Perspective { .. })
    }

    /// Screen position (pixels, y down) of a camera-space point in front of the eye, and 1/w
    /// (1 for orthographic), the quantity that is affine in screen space for perspective-correct interpolation.
    #[inline]
    pub fn project(&self, p: Vec3) -> (Vec2, f32) {
        let (cx, cy) = (0.5 * self.width as f32, 0.5 * self.height as f32);
        match self.projection {
            Projection::Perspective { .. } => {
                let q = 1.0 / -p.z;
                (Vec2::new(cx + self.scale * p.x * q, cy - self.scale * p.y * q), q)
            }
            Projection::Orthographic { .. } => (Vec2::new(cx + self.scale * p.x, cy - self.scale * p.y), 1.0),
        }
    }

    /// How the screen position of camera-space point `p` moves along camera-space direction `d`.
    #[inline]
    pub fn project_derivative(&self, p: Vec3, d: Vec3) -> Vec2 {
        match self.projection {
            Projection::Perspective { .. } => {
                // s = c + k (x, -y) / w with w = -z, so ds = k / w (dx + (x/w) dz, -(dy + (y/w) dz)).
                let inv_w = 1.0 / -p.z;
                Vec2::new(d.x + p.x * inv_w * d.z, -(d.y + p.y * inv_w * d.z)) * (self.scale * inv_w)
            }
            Projection::Orthographic { .. } => Vec2::new(d.x, -d.y) * self.scale,
        }
    }

    /// Screen pixels per world unit near a world point; 0 behind the eye.
    pub fn pixels_per_unit(&self, world: Vec3) -> f32 {
        self.pixels_per_unit_at(self.world_to_camera.transform_point3(world))
    }

    /// `pixels_per_unit` at a camera-space point.
    #[inline]
    pub fn pixels_per_unit_at(&self, seen: Vec3) -> f32 {
        match self.projection {
            Projection::Perspective { .. } if -seen.z > NEAR => self.scale / -seen.z,
            Projection::Perspective { .. } => 0.0,
            Projection::Orthographic { .. } => self.scale,
        }
    }

    /// The world-space ray through a screen position (pixels, y down): origin and unit direction.
    pub fn ray(&self, screen: Vec2) -> (Vec3, Vec3) {
        let x = (screen.x - 0.5 * self.width as f32) / self.scale;
        let y = (0.5 * self.height as f32 - screen.y) / self.scale;
        match self.projection {
            Projection::Perspective { .. } => {
                let dir = self.camera_to_world.transform_vector3(Vec3::new(x, y, -1.0)).normalize();
                (self.eye, dir)
            }
            Projection::Orthographic { .. } => {
                let origin = self.camera_to_world.transform_point3(Vec3::new(x, y, 0.0));
                (origin, self.camera_to_world.transform_vector3(-Vec3::Z).normalize())
            }
        }
    }
}

impl Camera {
    /// `project` on eight lanes to the same bits: screen x, screen y and 1/w (what the triangle setup
    /// snaps; `project8` takes fewer steps, within rounding).
    #[inline]
    pub fn project_exact8(&self, p: &V3) -> (F8, F8, F8) {
        let (cx, cy) = (F8::splat(0.5 * self.width as f32), F8::splat(0.5 * self.height as f32));
        let scale = F8::splat(self.scale);
        match self.projection {
            Projection::Perspective { .. } => {
                let q = F8::ONE / -p.z;
                (cx + scale * p.x * q, cy - scale * p.y * q, q)
            }
            Projection::Orthographic { .. } => (cx + scale * p.x, cy - scale * p.y, F8::ONE),
        }
    }

    /// Screen positions of eight camera-space points (`project` on every lane, within rounding).
    #[inline]
    pub fn project8(&self, p: V3) -> (F8, F8) {
        let (cx, cy) = (F8::splat(0.5 * self.width as f32), F8::splat(0.5 * self.height as f32));
        let k = F8::splat(self.scale);
        match self.projection {
            Projection::Perspective { .. } => {
                let q = k / -p.z;
                (cx + p.x * q, cy - p.y * q)
            }
            Projection::Orthographic { .. } => (cx + p.x * k, cy - p.y * k),
        }
    }

    /// `project_derivative` on every lane.
    #[inline]
    pub fn project_derivative8(&self, p: V3, d: V3) -> (F8, F8) {
        let k = F8::splat(self.scale);
        match self.projection {
            Projection::Perspective { .. } => {
                let inv_w = F8::ONE / -p.z;
                let (x_w, y_w) = (p.x * inv_w, p.y * inv_w);
                let kw = k * inv_w;
                (mul_add(x_w, d.z, d.x) * kw, -(mul_add(y_w, d.z, d.y) * kw))
            }
            Projection::Orthographic { .. } => (d.x * k, -d.y * k),
        }
    }

    /// The camera-space rays through eight screen positions (directions not unit), with their changes per
    /// `step` pixels right and down: the ray differentials of a sample whose footprint is `step` pixels.
    #[inline]
    pub fn rays8(&self, sx: F8, sy: F8, step: f32) -> Rays8 {
        let k = F8::splat(1.0 / self.scale);
        let x = (sx - F8::splat(0.5 * self.width as f32)) * k;
        let y = (F8::splat(0.5 * self.height as f32) - sy) * k;
        let s = V3::splat;
        let (right, down) = (s(Vec3::new(step / self.scale, 0.0, 0.0)), s(Vec3::new(0.0, -step / self.scale, 0.0)));
        match self.projection {
            Projection::Perspective { .. } => Rays8 {
                origin: s(Vec3::ZERO),
                dir: V3 { x, y, z: F8::splat(-1.0) },
                dx: (s(Vec3::ZERO), right),
                dy: (s(Vec3::ZERO), down),
            },
            Projection::Orthographic { .. } => Rays8 {
                origin: V3 { x, y, z: F8::ZERO },
                dir: s(-Vec3::Z),
                dx: (right, s(Vec3::ZERO)),
                dy: (down, s(Vec3::ZERO)),
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn projects_and_casts_consistently() {
        let cam = Camera::new(
            Vec3::new(1.0, 2.0, 5.0),
            Vec3::ZERO,
            Vec3::Y,
            Projection::Perspective { fov_y: 40.0 },
            320,
            200,
        );
        let (o, d) = cam.ray(Vec2::new(160.0, 100.0));
        assert!((d - (-o).normalize()).length() < 1e-6);
        let world = o + 3.0 * cam.ray(Vec2::new(37.5, 150.25)).1;
        let (s, q) = cam.project(cam.world_to_camera.transform_point3(world));
        assert!((s - Vec2::new(37.5, 150.25)).length() < 1e-3);
        assert!(q > 0.0);
        // The analytic derivative of the projection against a finite difference.
        let p = Vec3::new(0.3, -0.2, -3.0);
        let dir = Vec3::new(0.5, 0.7, -0.4);
        let h = 1e-3;
        let fd = (cam.project(p + h * dir).0 - cam.project(p - h * dir).0) / (2.0 * h);
        assert!((cam.project_derivative(p, dir) - fd).length() < 1e-2, "{fd}");
        // The top of the field of view is 20 degrees above the axis.
        let (_, top) = cam.ray(Vec2::new(160.0, 0.0));
        assert!((top.angle_between(d).to_degrees() - 20.0).abs() < 1e-3);
    }
}
