//! Mappings: how a surface sample finds its texture coordinates. A mapping turns a lookup context into
//! the context a texture reads, with the coordinates (s,t) and their footprint; it also says how (s,t)
//! change along the surface parameters, which a bump's chain rule needs (Fu = Fs ds/du + Ft dt/du).
//! A projection (projection.rs) names where the coordinates come from; a uv transform then places the
//! texture (repeat, rotate, offset). Knows nothing of scenes or rasters.
//!
//! The surface's own (u,v) are mapped on the lanes. A projection from the point maps each lane on its own,
//! its footprint by differences across the pixel: (s,t) at P + dP/dx / 2 less (s,t) at P - dP/dx / 2, the
//! discrete choices (a box face) held fixed and the seam of an angle taken modulo one turn.

pub mod polygon;
pub mod projection;
mod uv_transform;

pub use projection::Projection;
pub use uv_transform::UvTransform;

use crate::lanes::F8;
use crate::texture::{Footprint, Footprint8, LookupContext, LookupContext8, Texture};
use glam::{Affine3A, Vec2, Vec3, Vec4};
use projection::Point;
use std::sync::Arc;

/// Where texture coordinates come from, then placed by a uv transform.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mapping {
    pub projection: Projection,
    /// Object space to the projection's space (the inverse of the projection's placement).
    pub to_mapping: Affine3A,
    pub transform: UvTransform,
}

impl Mapping {
    /// The surface's own (u,v) through `transform`.
    pub fn uv(transform: UvTransform) -> Mapping {
        Mapping { projection: Projection::Uv, to_mapping: Affine3A::IDENTITY, transform }
    }

    /// The context with its texture coordinates and footprint mapped.
    #[inline]
    pub fn apply(&self, ctx: &LookupContext) -> LookupContext {
        self.apply_with_jacobian(ctx).0
    }

    /// `apply`, and d(s,t)/du and d(s,t)/dv there (the columns of the mapping's Jacobian with respect to
    /// the surface parameters).
    #[inline]
    pub fn apply_with_jacobian(&self, ctx: &LookupContext) -> (LookupContext, [Vec2; 2]) {
        let t = &self.transform;
        let (st, footprint, jacobian) = match self.projection {
            Projection::Uv => {
                return (
                    LookupContext { uv: t.point(ctx.uv), footprint: t.footprint(&ctx.footprint), ..*ctx },
                    t.linear(),
                )
            }
            _ => self.projected(ctx),
        };
        let [a, b] = t.linear();
        let jacobian = jacobian.map(|c| a * c.x + b * c.y);
        (LookupContext { uv: t.point(st), footprint: t.footprint(&footprint), ..*ctx }, jacobian)
    }

    /// `apply` on eight lanes, and the coordinates before the uv transform (what the uv AOV shows).
    #[inline(always)]
    pub fn apply8<'a>(&self, ctx: &LookupContext8<'a>) -> (LookupContext8<'a>, (F8, F8)) {
        if !matches!(self.projection, Projection::Uv) {
            return self.projected8(ctx);
        }
        let t = &self.transform;
        let (u, v) = t.point8(ctx.u, ctx.v);
        (LookupContext8 { u, v, footprint: t.footprint8(&ctx.footprint), surface: ctx.surface }, (ctx.u, ctx.v))
    }

    /// `apply8` of a projection from the point: lane by lane.
    #[inline(never)]
    fn projected8<'a>(&self, ctx: &LookupContext8<'a>) -> (LookupContext8<'a>, (F8, F8)) {
        let t = &self.transform;
        let lanes: [(Vec2, Footprint, Vec2); 8] = std::array::from_fn(|i| {
            let c = ctx.lane(i);
            let (st, fp, _) = self.projected(&c);
            let mapped = t.point(st);
            (mapped, t.footprint(&fp), st)
        });
        let lane = |f: fn(&(Vec2, Footprint, Vec2)) -> f32| F8::new(lanes.map(|l| f(&l)));
        let footprint = Footprint8::from_lanes(&lanes.map(|l| l.1));
        let mapped = LookupContext8 { u: lane(|l| l.0.x), v: lane(|l| l.0.y), footprint, surface: ctx.surface };
        (mapped, (lane(|l| l.2.x), lane(|l| l.2.y)))
    }

    /// (s,t) of a projection before the uv transform, its footprint and its Jacobian along u and v.
    fn projected(&self, ctx: &LookupContext) -> (Vec2, Footprint, [Vec2; 2]) {
        let p = &self.projection;
        let eye = ctx.object_to_eye.inverse().transform_point3(Vec3::ZERO);
        let n = if ctx.n.length_squared() > 0.0 { ctx.n } else { Vec3::Z };
        let at = projection::point(ctx.p, n, eye, &self.to_mapping, &ctx.object_to_eye);
        let choice = p.choose(&at);
        let st = p.coords(&at, &choice);
        // The change of (s,t) across a step dp of the point, as a difference about it.
        let along = |dp: Vec3| -> Vec2 {
            let moved = |k: f32| {
                let d = dp * k;
                let q = Point {
                    q: at.q + self.to_mapping.transform_vector3(d),
                    q_eye: at.q_eye + ctx.object_to_eye.transform_vector3(d),
                    ..at
                };
                p.coords(&q, &choice)
            };
            let mut d = moved(0.5) - moved(-0.5);
            if p.wraps() {
                d.x -= d.x.round();
            }
            d
        };
        let (dx, dy) = (along(ctx.dpdx), along(ctx.dpdy));
        let footprint = Footprint { dudx: dx.x, dvdx: dx.y, dudy: dy.x, dvdy: dy.y };
        // Along u and v by a step about as long as the pixel's (or a small one where there is no pixel).
        let reach = ctx.dpdx.length().max(ctx.dpdy.length()).max(1e-4 * ctx.p.length().max(1.0));
        let column = |t: Vec3| {
            let len = t.length();
            if len == 0.0 {
                return Vec2::ZERO;
            }
            let h = reach / len;
            along(t * h) / h
        };
        (st, footprint, [column(ctx.dpdu), column(ctx.dpdv)])
    }

    /// d(s,t)/du and d(s,t)/dv where they are the same everywhere (the uv projection): the uv transform's
    /// columns; `None` for projections from the point.
    #[inline]
    pub fn constant_jacobian(&self) -> Option<[Vec2; 2]> {
        matches!(self.projection, Projection::Uv).then(|| self.transform.linear())
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
    pub fn eval8(&self, ctx: &LookupContext8<'_>) -> [F8; 4] {
        self.eval8_with_coords(ctx).0
    }

    /// `eval8`, and the coordinates before the uv transform.
    #[inline]
    pub fn eval8_with_coords(&self, ctx: &LookupContext8<'_>) -> ([F8; 4], (F8, F8)) {
        let (mapped, coords) = self.mapping.apply8(ctx);
        (self.texture.eval8(&mapped), coords)
    }
}
