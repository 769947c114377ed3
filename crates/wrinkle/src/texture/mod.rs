//! Textures: sources looked up at a surface sample (its lookup context), images through the pixel's
//! footprint in texture space.

pub(crate) mod aniso;
pub(crate) mod colour_table;
pub mod context;
pub mod editable;
pub(crate) mod ewa;
pub mod filter;
pub mod filtered;
pub mod footprint;
pub(crate) mod ground_truth;
pub mod location;
pub mod mip;
pub mod reconstruct;
pub(crate) mod rgba8;
pub(crate) mod ripmap;
pub(crate) mod sat;
pub(crate) mod texel;
pub(crate) mod trilinear8;
pub mod wrap;

pub use context::{LookupContext, LookupContext8, PrimitiveId, SurfaceLanes, UvSet, UvSet8};
pub use editable::EditableTexture;
pub use filter::{Filter, FilterOptions, Filterable};
pub use filtered::{FilteredTexture, TextureOptions};
pub use footprint::{Footprint, Footprint8};
pub use location::TexelLocation;
pub use mip::{LevelRule, MipFilter};
pub use wrap::Wrap;

use crate::lanes::{F8, LANES};
use glam::Vec4;

/// Anything that can be looked up at a surface sample. The context tells the lookup where the sample is
/// and how large its pixel is, so that a filter can integrate over it; filters plug in here without
/// touching the shader.
pub trait Texture: Send + Sync {
    /// Linear-light RGBA at the sample: an image reads `ctx.uv` (one period is [0,1]; the source decides
    /// how it wraps) and its footprint, a solid texture the point `ctx.p`.
    fn eval(&self, ctx: &LookupContext) -> Vec4;

    /// Eight lookups at once (the packet shader's), as four channel lanes (R, G, B, A). Sources with a
    /// faster way override it; by default, one `eval` per lane.
    fn eval8(&self, ctx: &LookupContext8<'_>) -> [F8; 4] {
        lane_by_lane(self, ctx)
    }

    /// The same texture looked up with its filter options or level-of-detail bias changed by `change`
    /// (`--filter` and `--lod-bias` overriding a scene), where the source is an image with that choice;
    /// `None` keeps it as it is. Only those two take effect: the wrap, border and MIP filter stay as the
    /// data was prepared.
    fn with_lookup(&self, _change: &dyn Fn(&mut TextureOptions)) -> Option<std::sync::Arc<dyn Texture>> {
        None
    }

    /// The image behind the texture, where it is one (what LEAN filtering of a normal map reads).
    fn image(&self) -> Option<&FilteredTexture> {
        None
    }
}

/// `eval` once per lane, transposed to channel lanes.
pub fn lane_by_lane<T: Texture + ?Sized>(texture: &T, ctx: &LookupContext8<'_>) -> [F8; 4] {
    let texels: [Vec4; LANES] = std::array::from_fn(|i| texture.eval(&ctx.lane(i)));
    std::array::from_fn(|c| F8::new(texels.map(|t| t[c])))
}

/// Wraps a coordinate into [0, 1) periodically.
#[inline]
pub fn wrap01(x: f32) -> f32 {
    let f = x - x.floor();
    // x slightly below an integer can round to exactly 1.0.
    if f >= 1.0 {
        0.0
    } else {
        f
    }
}

/// The two texels around `s` (one period per unit, texel centres at (i + 0.5) / n, periodic) and the
/// weight of the second: the bilinear taps along one axis. No division and no modulo: this runs per sample.
#[inline]
pub fn bilinear_taps(s: f32, n: usize) -> (usize, usize, f32) {
    let x = wrap01(s) * n as f32 + 0.5;
    // x is in [0.5, n + 0.5]: truncation is the floor, and x - 1 is the position in texel-centre units.
    // Through i32: a float-to-usize conversion costs several times more instructions.
    let k = x as i32;
    let f = x - k as f32;
    let k = k as usize;
    let i0 = if k == 0 { n - 1 } else { k - 1 };
    let i1 = if k >= n { k - n } else { k };
    (i0.min(n - 1), i1.min(n - 1), f)
}
