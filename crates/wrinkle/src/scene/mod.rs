//! The scene: camera, lights, objects and their materials, read from TOML (docs/scene-format.md)
//! and validated on load.

mod fields;
mod load;
mod procedural;
mod texture;

pub use load::DEFAULT_SCENE;

use crate::geometry::{Surface, Transform};
use crate::procedural::hypertexture::Hypertexture;
use crate::raster::Projection;
use crate::shade::{Light, Material};
use glam::Vec3;

#[derive(Clone, Debug, PartialEq)]
pub struct CameraDesc {
    pub eye: Vec3,
    pub look_at: Vec3,
    pub up: Vec3,
    pub projection: Projection,
    /// Linear RGB of pixels that see no object.
    pub background: Vec3,
}

/// The shape of an object: one parametric surface, or a box made of six flat patches.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    Surface(Surface),
    /// Edge lengths along x, y, z, centred on the origin.
    Box {
        size: Vec3,
    },
}

impl Shape {
    /// The parametric surfaces of the shape. A box's faces are patches seen from outside with u to the
    /// right and v up: +z and -z with v along +y, +x and -x with v along +y, +y and -y with u along +x.
    pub fn surfaces(&self) -> Vec<Surface> {
        match self {
            Shape::Surface(s) => vec![s.clone()],
            Shape::Box { size } => {
                let h = *size * 0.5;
                let p = |x: f32, y: f32, z: f32| Vec3::new(x * h.x, y * h.y, z * h.z);
                let faces = [
                    [p(-1., -1., 1.), p(1., -1., 1.), p(1., 1., 1.), p(-1., 1., 1.)],
                    [p(1., -1., -1.), p(-1., -1., -1.), p(-1., 1., -1.), p(1., 1., -1.)],
                    [p(1., -1., 1.), p(1., -1., -1.), p(1., 1., -1.), p(1., 1., 1.)],
                    [p(-1., -1., -1.), p(-1., -1., 1.), p(-1., 1., 1.), p(-1., 1., -1.)],
                    [p(-1., 1., 1.), p(1., 1., 1.), p(1., 1., -1.), p(-1., 1., -1.)],
                    [p(-1., -1., -1.), p(1., -1., -1.), p(1., -1., 1.), p(-1., -1., 1.)],
                ];
                faces.iter().map(|&corners| Surface::Patch { corners }).collect()
            }
        }
    }

    /// Whether the shape encloses a volume, so faces turned away from the eye are never seen.
    pub fn is_closed(&self) -> bool {
        match self {
            Shape::Surface(s) => s.is_closed(),
            Shape::Box { .. } => true,
        }
    }
}

pub struct Object {
    pub shape: Shape,
    pub transform: Transform,
    /// Index into `Scene::materials`.
    pub material: usize,
}

pub struct Scene {
    pub camera: CameraDesc,
    pub lights: Vec<Light>,
    pub objects: Vec<Object>,
    pub materials: Vec<Material>,
    /// Hypertextured volumes, ray marched over the opaque scene.
    pub volumes: Vec<Hypertexture>,
}
