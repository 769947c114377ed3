//! The scene: camera, lights, objects and their materials, read from TOML (docs/scene-format.md)
//! and validated on load.

mod animation;
mod build;
mod contain;
mod environment;
mod export;
mod fields;
mod gltf;
mod layer;
mod load;
mod mapping;
mod model;
mod obj;
mod procedural;
mod texture;

pub use animation::{Animation, Interpolation};
pub use export::write_obj;
pub use load::DEFAULT_SCENE;
pub use mapping::parse_mapping_text;

use crate::envmap::Environment;
use crate::geometry::{Shape, Transform};
use crate::light::{Light, ShadowSettings};
use crate::procedural::hypertexture::Hypertexture;
/// The camera's projection (perspective or orthographic), with validated constructors.
pub use crate::raster::Projection;
use crate::shade::Material;
use crate::texture::FilteredTexture;
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

pub struct Object {
    pub shape: Shape,
    pub transform: Transform,
    /// Index into `Scene::materials`.
    pub material: usize,
    /// (u,v) interpolated linearly on the screen, not perspective-correctly (`interp = "affine"`).
    pub affine: bool,
}

pub struct Scene {
    pub camera: CameraDesc,
    pub lights: Vec<Light>,
    /// How each light casts shadows (one per light, in the same order).
    pub shadows: Vec<ShadowSettings>,
    pub objects: Vec<Object>,
    pub materials: Vec<Material>,
    /// Hypertextured volumes, ray marched over the opaque scene.
    pub volumes: Vec<Hypertexture>,
    pub environment: Option<SceneEnvironment>,
    /// The pictures spot lights project (`Spot::slide` indexes them).
    pub slides: Vec<FilteredTexture>,
    /// The scene file's `[[animation]]` tracks, where it has any: `Animation::scene_at` gives the scene at
    /// another time (this one is at time 0).
    pub animation: Option<std::sync::Arc<Animation>>,
}

/// The light arriving from far away in every direction.
pub struct SceneEnvironment {
    pub map: Environment,
    /// Seen where the camera sees no object (else the camera's background colour is).
    pub background: bool,
}
