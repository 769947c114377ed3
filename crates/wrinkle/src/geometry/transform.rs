//! Object transforms: scale, then rotate about x, y, z (degrees, in that order), then translate.

use glam::{Affine3A, Quat, Vec3};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transform {
    pub translate: Vec3,
    /// Degrees about x, then y, then z.
    pub rotate: Vec3,
    pub scale: Vec3,
}

impl Default for Transform {
    fn default() -> Self {
        Transform { translate: Vec3::ZERO, rotate: Vec3::ZERO, scale: Vec3::ONE }
    }
}

impl Transform {
    pub fn rotation(&self) -> Quat {
        let r = self.rotate * (std::f32::consts::PI / 180.0);
        Quat::from_rotation_z(r.z) * Quat::from_rotation_y(r.y) * Quat::from_rotation_x(r.x)
    }

    /// Object to world.
    pub fn matrix(&self) -> Affine3A {
        Affine3A::from_scale_rotation_translation(self.scale, self.rotation(), self.translate)
    }
}
