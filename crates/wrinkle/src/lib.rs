//! wrinkle: texture mapping and Blinn bump mapping, exactly and fast.
//!
//! The pipeline (docs/architecture.md): scene -> geometry::tessellate -> raster (visibility buffer)
//! -> shade (exact surface frame, Blinn perturbation, textures, lights) -> resolve -> encode.
//!
//! The public face: the nouns most programs need are at the root; each module below holds the rest of
//! its subject.
//!
//! | to ... | use |
//! | --- | --- |
//! | load or build a scene and render it | [`Scene`] ([`Scene::load`], [`Scene::new`]), [`CameraDesc`], [`Light`], [`Material`], [`Shape`], [`render`], [`RenderOptions`], [`Frame`] |
//! | find what a pixel sees (picking) | [`CameraDesc::screen`] gives the [`Camera`]: `ray` through a pixel, `project` a point; the frame's `depth` and `primitive` AOVs |
//! | hold and read images | [`Image`], [`ImageRef`] (a view of the caller's buffer), [`image::io`], [`image::stream`] |
//! | filter textures | [`FilteredTexture`], [`TextureOptions`], [`Filter`], [`Footprint`], [`texture::mip::pyramid`] |
//! | bump-map | [`BumpMap`], [`BumpTable`], [`bump::generators`], [`bump::schlag`] (emboss), [`bump::normal_map`], [`bump::integrate`] |
//! | make noise and procedural textures | [`Perlin`], [`procedural::fbm`], [`procedural::effects`], [`procedural::bake`] |
//! | map textures onto surfaces | [`Mapping`], [`mapping::MappedTexture`] |
//! | use environment maps | [`envmap::Environment`], [`envmap::convert`] |
//!
//! Errors are front-end neutral: a value out of range is [`Error::Parameter`] with the parameter's own
//! name, which the CLI words as `--name`, a scene as the field's path and Python as `name=`.
//!
//! The eight-lane types, the rasteriser and texel storage are the crate's own; its reference tests and
//! benchmarks reach them through [`internals`] with the `internals` feature.

pub mod bump;
pub mod cpu;
pub mod envmap;
mod error;
pub mod geometry;
pub mod image;
pub(crate) mod lanes;
pub mod light;
pub mod limits;
pub mod mapping;
mod pages;
pub mod procedural;
pub(crate) mod raster;
pub mod render;
pub mod scene;
pub mod shade;
mod stream;
pub mod texture;

pub use bump::{BumpFormula, BumpMap, BumpSource, BumpTable};
pub use error::{Error, Result};
pub use geometry::{Shape, Surface, Transform, TriangleMesh};
pub use image::{GreyImage, Image, ImageRef};
pub use light::{Light, ShadowSettings};
pub use mapping::Mapping;
pub use procedural::Perlin;
pub use raster::Camera;
pub use render::{
    render, render_parts, render_until, render_with_progress, Aovs, Crop, Frame, PixelFilter, RenderOptions, Sampler,
    ShadingRate,
};
pub use scene::{CameraDesc, Projection, Scene};
pub use shade::Material;
pub use texture::{Filter, FilterOptions, FilteredTexture, Footprint, MipFilter, TextureOptions, Wrap};

/// What the crate's reference tests and benchmarks reach into: not part of the public face, and free to
/// change with the implementation.
#[cfg(feature = "internals")]
pub mod internals {
    pub use crate::geometry::tessellate::{grid, Mesh};
    pub use crate::lanes::{F8, LANES, V3};
    pub use crate::raster::samples::TileOffsets;
    pub use crate::raster::setup::ProjectedMesh;
    pub use crate::raster::visibility::cover;
    pub use crate::raster::{Cull, SamplePattern, TriangleSetup};
    pub use crate::texture::ewa::Axes;
}
