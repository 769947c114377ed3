//! Geometry: shapes and the primitives they are made of, parametric surfaces evaluated exactly, object
//! transforms, and tessellation into triangles that carry (u,v) so the rasterizer can find which (u,v)
//! lands in each pixel.

pub mod billboard;
pub(crate) mod dice;
pub(crate) mod frame_lanes;
pub mod mesh;
pub(crate) mod mesh_lanes;
pub mod shape;
pub mod surface;
pub(crate) mod tessellate;
pub mod transform;
pub mod unwrap;

pub use mesh::TriangleMesh;
pub use shape::{Instance, MeshPart, Primitive, Shape};
pub use surface::{Surface, SurfaceFrame};
pub use transform::Transform;
