//! Mappings: how a surface sample finds its texture coordinates. A mapping turns a lookup context into
//! the context a texture reads, with the coordinates (s,t) and their footprint; it also says how (s,t)
//! change along the surface parameters, which a bump's chain rule needs (Fu = Fs ds/du + Ft dt/du).
//! Knows nothing of scenes or rasters.

mod uv_transform;

pub use uv_transform::UvTransform;

use crate::lanes::F8;
use crate::texture::{LookupContext, LookupContext8, Texture};
use glam::{Vec2, Vec4};
use std::sync::Arc;

/// Where texture coordinates come from, then placed by a uv transform.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mapping {
    pub transform: UvTransform,
}

impl Mapping {
    /// The surface's own (u,v) through `transform`.
    pub fn uv(transform: UvTransform) -> Mapping {
        Mapping { transform }
    }

    /// The context with its texture coordinates and footprint mapped.
    #[inline]
    pub fn apply(&self, ctx: &LookupContext) -> LookupContext {
        let t = &self.transform;
        LookupContext { uv: t.point(ctx.uv), footprint: t.footprint(&ctx.footprint), ..*ctx }
    }

    /// `apply` on eight lanes.
    #[inline]
    pub fn apply8(&self, ctx: &LookupContext8) -> LookupContext8 {
        let t = &self.transform;
        let (u, v) = t.point8(ctx.u, ctx.v);
        LookupContext8 { u, v, footprint: t.footprint8(&ctx.footprint), ..*ctx }
    }

    /// d(s,t)/du and d(s,t)/dv: the columns of the mapping's Jacobian with respect to the surface parameters.
    #[inline]
    pub fn jacobian(&self) -> [Vec2; 2] {
        self.transform.linear()
    }
}

impl Default for Mapping {
    fn default() -> Self {
        Mapping::uv(UvTransform::IDENTITY)
    }
}

/// A texture seen through a mapping: what a material binds to a target.
#[derive(Clone)]
pub struct MappedTexture {
    pub texture: Arc<dyn Texture>,
    pub mapping: Mapping,
}

impl MappedTexture {
    #[inline]
    pub fn eval(&self, ctx: &LookupContext) -> Vec4 {
        self.texture.eval(&self.mapping.apply(ctx))
    }

    #[inline]
    pub fn eval8(&self, ctx: &LookupContext8) -> [F8; 4] {
        self.texture.eval8(&self.mapping.apply8(ctx))
    }
}
