//! Lights as plain data: what shines where. How a surface or a volume reflects them is the shader's
//! business (shade/phong.rs, procedural/hypertexture.rs); this module knows nothing of materials.

pub mod shadow;
pub mod spot;

pub use shadow::{ShadowMap, ShadowSettings, Shadows};
pub use spot::Spot;

use glam::Vec3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Light {
    /// Light travelling along `direction` (unit), `radiance` = colour x intensity.
    Directional { direction: Vec3, radiance: Vec3 },
    /// A point light; its intensity falls off with the square of the distance.
    Point { position: Vec3, radiance: Vec3 },
    /// Light from everywhere, reflected diffusely without regard to the normal.
    Ambient { radiance: Vec3 },
    /// A point light limited to a cone, perhaps projecting a slide.
    Spot(Spot),
    /// The scene's environment map as a light (image-based lighting), its radiance times `radiance`.
    Environment { radiance: Vec3 },
}
