//! The shapes a scene names, and the primitives the renderer draws: parametric surfaces (a box is six
//! patches) and triangle meshes, each placed in the world as an instance.

use super::billboard::{Billboard, Viewer};
use super::mesh::TriangleMesh;
use super::surface::Surface;
use glam::{Affine3A, Mat3, Vec3};
use std::sync::Arc;

/// The shape of an object: one parametric surface, a box made of six flat patches, or triangle meshes.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    Surface(Surface),
    /// Edge lengths along x, y, z, centred on the origin.
    Box {
        size: Vec3,
    },
    /// The meshes of a model file, each with its own material.
    Mesh(Vec<MeshPart>),
    /// A rectangle turned towards the camera every frame, centred on the object's origin.
    Billboard(Billboard),
}

/// One mesh of a model with the material it is drawn with.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshPart {
    pub mesh: Arc<TriangleMesh>,
    /// Index into the scene's materials.
    pub material: usize,
    /// Drawn from both sides (glTF's doubleSided; OBJ meshes always), else back faces are culled.
    pub two_sided: bool,
}

impl Shape {
    /// The primitives of the shape. A box's faces are patches seen from outside with u to the
    /// right and v up: +z and -z with v along +y, +x and -x with v along +y, +y and -y with u along +x.
    pub fn primitives(&self) -> Vec<Primitive> {
        match self {
            Shape::Surface(s) => vec![Primitive::Parametric(s.clone())],
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
                faces.iter().map(|&corners| Primitive::Parametric(Surface::Patch { corners })).collect()
            }
            Shape::Mesh(parts) => parts.iter().map(|p| Primitive::Mesh(p.mesh.clone())).collect(),
            // Unturned (facing +Z) where no camera is given: `Billboard::corners` turns it.
            Shape::Billboard(b) => {
                let viewer = Viewer { right: Vec3::X, up: Vec3::Y, back: Vec3::Z, eye: None };
                vec![Primitive::Parametric(Surface::Patch { corners: b.corners(Vec3::ZERO, &viewer) })]
            }
        }
    }

    /// Whether no part of the shape can cast a shadow onto another part's lit side: convex solids and
    /// flat pieces (their shadow maps then need not test them against themselves).
    pub fn cannot_shadow_itself(&self) -> bool {
        match self {
            Shape::Surface(s) => s.cannot_shadow_itself(),
            Shape::Box { .. } | Shape::Billboard(_) => true,
            Shape::Mesh(_) => false,
        }
    }

    /// Whether the shape encloses a volume, so faces turned away from the eye are never seen.
    pub fn is_closed(&self) -> bool {
        match self {
            Shape::Surface(s) => s.is_closed(),
            Shape::Box { .. } => true,
            Shape::Mesh(_) | Shape::Billboard(_) => false,
        }
    }
}

/// What the renderer draws: one piece of a shape, with its own way of finding the surface at a sample.
#[derive(Clone, Debug, PartialEq)]
pub enum Primitive {
    /// A parametric surface: P(u,v) and its derivatives evaluated exactly at each sample's (u,v).
    Parametric(Surface),
    /// A triangle mesh: each sample's ray meets its triangle, and the vertex data are interpolated there.
    Mesh(Arc<TriangleMesh>),
}

/// One primitive placed in the world with its material.
pub struct Instance {
    pub primitive: Primitive,
    pub object_to_world: Affine3A,
    pub object_to_camera: Affine3A,
    pub camera_to_object: Affine3A,
    /// The inverse transpose of `object_to_world`'s linear part: carries normals to the world.
    pub normal_matrix: Mat3,
    /// Index into the scene's materials.
    pub material: usize,
    /// The object's index in the scene.
    pub object: u32,
    /// Open surfaces are lit from whichever side faces the eye; closed ones have their back faces culled.
    pub two_sided: bool,
    /// (u,v) interpolated linearly on the screen (a parametric surface's `interp = "affine"`).
    pub affine: bool,
}

impl Instance {
    /// Every primitive of `shape` placed by `object_to_world`, seen through `world_to_camera`, drawn with
    /// `material` (mesh parts with their own).
    pub fn of_shape(
        shape: &Shape,
        object_to_world: Affine3A,
        world_to_camera: Affine3A,
        material: usize,
        object: u32,
        affine: bool,
    ) -> Vec<Instance> {
        let normal_matrix = Mat3::from(object_to_world.matrix3).inverse().transpose();
        let object_to_camera = world_to_camera * object_to_world;
        let camera_to_object = object_to_camera.inverse();
        let place = |primitive: Primitive, material: usize, two_sided: bool| Instance {
            primitive,
            object_to_world,
            object_to_camera,
            camera_to_object,
            normal_matrix,
            material,
            object,
            two_sided,
            affine,
        };
        match shape {
            Shape::Mesh(parts) => {
                parts.iter().map(|p| place(Primitive::Mesh(p.mesh.clone()), p.material, p.two_sided)).collect()
            }
            _ => shape.primitives().into_iter().map(|p| place(p, material, !shape.is_closed())).collect(),
        }
    }
}
