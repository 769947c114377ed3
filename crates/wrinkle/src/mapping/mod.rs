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
        if matches!(self.projection, Projection::Uv) {
            let mapped = LookupContext { uv: t.point(ctx.uv), footprint: t.footprint(&ctx.footprint), ..*ctx };
            return (mapped, t.linear());
        }
        let sample = self.at_point(ctx);
        let (st, footprint, jacobian) = (sample.st(), sample.footprint(), sample.jacobian());
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
            // Colour lookups need no Jacobian: only the coordinates and their footprint.
            let sample = self.at_point(&c);
            let st = sample.st();
            (t.point(st), t.footprint(&sample.footprint()), st)
        });
        let lane = |f: fn(&(Vec2, Footprint, Vec2)) -> f32| F8::new(lanes.map(|l| f(&l)));
        let footprint = Footprint8::from_lanes(&lanes.map(|l| l.1));
        let mapped = LookupContext8 { u: lane(|l| l.0.x), v: lane(|l| l.0.y), footprint, surface: ctx.surface };
        (mapped, (lane(|l| l.2.x), lane(|l| l.2.y)))
    }

    /// A projection from the point evaluated at the sample of `ctx`.
    fn at_point<'a>(&'a self, ctx: &'a LookupContext) -> AtPoint<'a> {
        let eye = ctx.object_to_eye.inverse().transform_point3(Vec3::ZERO);
        let n = if ctx.n.length_squared() > 0.0 { ctx.n } else { Vec3::Z };
        let at = projection::point(ctx.p, n, eye, &self.to_mapping, &ctx.object_to_eye);
        AtPoint { mapping: self, ctx, choice: self.projection.choose(&at), at }
    }

    /// d(s,t)/du and d(s,t)/dv where they are the same everywhere (the uv projection): the uv transform's
    /// columns; `None` for projections from the point.
    #[inline]
    pub fn constant_jacobian(&self) -> Option<[Vec2; 2]> {
        matches!(self.projection, Projection::Uv).then(|| self.transform.linear())
    }
}

/// A projection from the point at one sample: its coordinates, and their change across steps of the point
/// taken as a difference about it (the discrete choices held fixed, an angle's seam taken modulo one turn).
struct AtPoint<'a> {
    mapping: &'a Mapping,
    ctx: &'a LookupContext,
    at: Point,
    choice: projection::Choice,
}

impl AtPoint<'_> {
    /// (s,t) before the uv transform.
    fn st(&self) -> Vec2 {
        self.mapping.projection.coords(&self.at, &self.choice)
    }

    /// The change of (s,t) across the step `dp` of the point.
    fn along(&self, dp: Vec3) -> Vec2 {
        let (m, ctx, at) = (self.mapping, self.ctx, &self.at);
        let moved = |k: f32| {
            let d = dp * k;
            let q = Point {
                q: at.q + m.to_mapping.transform_vector3(d),
                q_eye: at.q_eye + ctx.object_to_eye.transform_vector3(d),
                ..*at
            };
            m.projection.coords(&q, &self.choice)
        };
        let mut d = moved(0.5) - moved(-0.5);
        if m.projection.wraps() {
            d.x -= d.x.round();
        }
        d
    }

    /// The footprint: the change across one pixel step in x and in y.
    fn footprint(&self) -> Footprint {
        let (dx, dy) = (self.along(self.ctx.dpdx), self.along(self.ctx.dpdy));
        Footprint { dudx: dx.x, dvdx: dx.y, dudy: dy.x, dvdy: dy.y }
    }

    /// d(s,t)/du and d(s,t)/dv, by steps along Pu and Pv about as long as the pixel's (or small ones where
    /// there is no pixel).
    fn jacobian(&self) -> [Vec2; 2] {
        let ctx = self.ctx;
        let reach = ctx.dpdx.length().max(ctx.dpdy.length()).max(1e-4 * ctx.p.length().max(1.0));
        let column = |t: Vec3| {
            let len = t.length();
            if len == 0.0 {
                return Vec2::ZERO;
            }
            let h = reach / len;
            self.along(t * h) / h
        };
        [column(ctx.dpdu), column(ctx.dpdv)]
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
