//! The visibility pass: triangles carrying (u,v) are clipped, projected, snapped to fixed point and
//! rasterized per screen tile into a visibility buffer (depth, object, triangle, barycentrics per sample).

pub mod camera;
pub mod clip;
mod cull_lanes;
pub mod exact;
pub mod refine;
pub mod samples;
pub mod setup;
pub mod visibility;

pub use camera::{Camera, Projection};
pub use samples::SamplePattern;
pub use setup::{Cull, ScreenTriangle, TriangleSetup};
pub use visibility::{Bins, VisBuffer};

/// Sub-pixel precision of the rasterizer: 8 bits (1/256 pixel).
pub const SUBPIXEL_BITS: u32 = 8;
pub const SUBPIXEL: i64 = 1 << SUBPIXEL_BITS;
