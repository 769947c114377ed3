//! wrinkle: texture mapping and Blinn bump mapping, exactly and fast.
//!
//! The pipeline (docs/architecture.md): scene -> geometry::tessellate -> raster (visibility buffer)
//! -> shade (exact surface frame, Blinn perturbation, textures, lights) -> resolve -> encode.

pub mod bump;
pub mod cpu;
pub mod envmap;
pub mod error;
pub mod geometry;
pub mod image;
pub mod lanes;
pub mod light;
pub mod limits;
pub mod mapping;
pub mod procedural;
pub mod raster;
pub mod render;
pub mod scene;
pub mod shade;
pub mod texture;

pub use error::{Error, Result};
pub use render::{render, render_until, render_with_progress, Crop, Frame, RenderOptions};
pub use scene::Scene;
