//! Mappings: how a surface sample finds its texture coordinates. A mapping turns a lookup context into
//! the context a texture reads, with the coordinates (s,t) and their footprint; it also says how (s,t)
//! change along the surface parameters, which a bump's chain rule needs (Fu = Fs ds/du + Ft dt/du).
//! A projection (projection.rs) names where the coordinates come from; a uv transform then places the
//! texture (repeat, rotate, offset). Knows nothing of scenes or rasters.
//!
//! The surface's own (u,v) are mapped on the lanes. A projection from the point maps each lane on its own,
//! its footprint by differences across the pixel: (s,t) at P + dP/dx / 2 less (s,t) at P - dP/dx / 2, the
//! discrete choices (a box face) held fixed and the seam of an angle taken modulo one turn. Where the
//! coordinates follow the normal (sphere_map, the normal and reflected-ray projectors), the normal moves
//! across the pixel too, by the context's dN/dx and dN/dy, and the view direction with the point: a
//! curved mirror's footprint is mostly the normal's turn.

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
        let (st, footprint, jacobian) = if matches!(self.projection, Projection::SecondUv) {
            (ctx.uv1.uv, ctx.uv1.footprint, ctx.uv1.jacobian)
        } else {
            let sample = self.at_point(ctx);
            (sample.st(), sample.footprint(), sample.jacobian())
        };
        let [a, b] = t.linear();
        let jacobian = jacobian.map(|c| a * c.x + b * c.y);
        (LookupContext { uv: t.point(st), footprint: t.footprint(&footprint), ..*ctx }, jacobian)
    }

    /// `apply` on eight lanes, and the coordinates before the uv transform (what the uv AOV shows).
    #[inline(always)]
    pub fn apply8<'a>(&self, ctx: &LookupContext8<'a>) -> (LookupContext8<'a>, (F8, F8)) {
        let (u, v, footprint) = match (&self.projection, &ctx.surface.uv1) {
            (Projection::Uv, _) => (ctx.u, ctx.v, &ctx.footprint),
            (Projection::SecondUv, Some(set)) => (set.u, set.v, &set.footprint),
            _ => return self.projected8(ctx),
        };
        let t = &self.transform;
        let (s, st) = t.point8(u, v);
        (LookupContext8 { u: s, v: st, footprint: t.footprint8(footprint), surface: ctx.surface }, (u, v))
    }

    /// `apply8` of a projection from the point (or of a second set the surface lacks): lane by lane.
    #[inline(never)]
    fn projected8<'a>(&self, ctx: &LookupContext8<'a>) -> (LookupContext8<'a>, (F8, F8)) {
        let t = &self.transform;
        let lanes: [(Vec2, Footprint, Vec2); 8] = std::array::from_fn(|i| {
            let c = ctx.lane(i);
            if matches!(self.projection, Projection::SecondUv) {
                return (t.point(c.uv1.uv), t.footprint(&c.uv1.footprint), c.uv1.uv);
            }
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
        let eye = self.to_mapping.transform_point3(eye);
        AtPoint { mapping: self, ctx, choice: self.projection.choose(&at), at, n: n.normalize(), eye }
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
    /// The unit normal in object space, and the eye in mapping space.
    n: Vec3,
    eye: Vec3,
}

impl AtPoint<'_> {
    /// (s,t) before the uv transform.
    fn st(&self) -> Vec2 {
        self.mapping.projection.coords(&self.at, &self.choice)
    }

    /// The change of (s,t) across the step `dp` of the point, over which the unit normal changes by `dn`.
    fn along(&self, dp: Vec3, dn: Vec3) -> Vec2 {
        let (m, ctx, at) = (self.mapping, self.ctx, &self.at);
        let reads_normal = m.projection.reads_normal();
        let moved = |k: f32| {
            let d = dp * k;
            let mut q = Point {
                q: at.q + m.to_mapping.transform_vector3(d),
                q_eye: at.q_eye + ctx.object_to_eye.transform_vector3(d),
                ..*at
            };
            if reads_normal {
                let n = self.n + dn * k;
                q.n = projection::normal_through(&m.to_mapping, n);
                q.n_eye = projection::normal_through(&ctx.object_to_eye, n);
                q.view = (q.q - self.eye).normalize_or_zero();
            }
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
        let ctx = self.ctx;
        let (dx, dy) = (self.along(ctx.dpdx, ctx.dndx), self.along(ctx.dpdy, ctx.dndy));
        Footprint { dudx: dx.x, dvdx: dx.y, dudy: dy.x, dvdy: dy.y }
    }

    /// d(s,t)/du and d(s,t)/dv, by steps along Pu and Pv about as long as the pixel's (or small ones where
    /// there is no pixel).
    fn jacobian(&self) -> [Vec2; 2] {
        let ctx = self.ctx;
        let reach = ctx.dpdx.length().max(ctx.dpdy.length()).max(1e-4 * ctx.p.length().max(1.0));
        let [dndu, dndv] = normal_along_uv(ctx);
        let column = |t: Vec3, dn: Vec3| {
            let len = t.length();
            if len == 0.0 {
                return Vec2::ZERO;
            }
            let h = reach / len;
            self.along(t * h, dn * h) / h
        };
        [column(ctx.dpdu, dndu), column(ctx.dpdv, dndv)]
    }
}

/// dN/du and dN/dv from the normal's change across the pixel, through the inverse of the (u,v) footprint:
/// dN/dx = dN/du du/dx + dN/dv dv/dx, and alike for y. Zero where the footprint is singular.
fn normal_along_uv(ctx: &LookupContext) -> [Vec3; 2] {
    let f = &ctx.footprint;
    let det = f.dudx * f.dvdy - f.dvdx * f.dudy;
    if det == 0.0 || !det.is_finite() {
        return [Vec3::ZERO; 2];
    }
    [(ctx.dndx * f.dvdy - ctx.dndy * f.dvdx) / det, (ctx.dndy * f.dudx - ctx.dndx * f.dudy) / det]
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

#[cfg(test)]
mod tests {
    use super::projection::{Projector, SphereRange, Surface};
    use super::*;
    use crate::texture::UvSet;

    /// A unit sphere seen from (0, 0, 5): its unit normal is the point, so across a pixel step dP the
    /// normal turns by dP too. The footprint of projections that follow the normal must equal the central
    /// difference of their coordinates between the sphere's points half a step either side, each with its
    /// own normal; holding the normal fixed, as a flat surface would, gets it badly wrong. The mapping
    /// space is the object's halved, so the intermediate surfaces enclose the sphere.
    #[test]
    fn footprints_of_normal_projections_follow_the_turning_normal() {
        let object_to_eye = Affine3A::from_translation(Vec3::new(0.0, 0.0, -5.0));
        let eye = Vec3::new(0.0, 0.0, 5.0);
        // Whether holding the normal fixed is far off: on mirrors; along a sphere's own normal, which runs
        // through its centre, a parallel shift of the point moves the coordinates almost alike.
        let reflected = Projector::Reflected;
        let projections = [
            ("sphere_map", Projection::SphereMap, true),
            (
                "sphere/reflected",
                Projection::TwoPart { surface: Surface::Sphere(SphereRange::default()), projector: reflected },
                true,
            ),
            (
                "cylinder/normal",
                Projection::TwoPart { surface: Surface::Cylinder, projector: Projector::Normal },
                false,
            ),
        ];
        let h = 2e-3;
        for p in [Vec3::new(0.3, 0.2, 0.93), Vec3::new(0.85, -0.3, 0.4), Vec3::new(-0.2, 0.95, 0.25)] {
            let p = p.normalize();
            let t1 = p.cross(Vec3::Y).normalize();
            let t2 = p.cross(t1);
            let (dpdx, dpdy) = (t1 * h, (t1 * 0.3 + t2) * h);
            let ctx = LookupContext {
                p,
                dpdx,
                dpdy,
                n: p * 2.0,
                dndx: dpdx,
                dndy: dpdy,
                object_to_eye,
                ..LookupContext::default()
            };
            for (name, projection, turn_matters) in projections {
                let to_mapping = Affine3A::from_scale(Vec3::splat(0.5));
                let m = Mapping { projection, to_mapping, transform: UvTransform::IDENTITY };
                let at = |q: Vec3| {
                    let q = q.normalize();
                    let point = projection::point(q, q, eye, &to_mapping, &object_to_eye);
                    projection.coords(&point, &projection.choose(&point))
                };
                let central = |d: Vec3| {
                    let mut st = at(p + d * 0.5) - at(p - d * 0.5);
                    st.x -= if projection.wraps() { st.x.round() } else { 0.0 };
                    st
                };
                let got = m.apply(&ctx).footprint;
                let (wx, wy) = (central(dpdx), central(dpdy));
                let err =
                    (Vec2::new(got.dudx, got.dvdx) - wx).length().max((Vec2::new(got.dudy, got.dvdy) - wy).length());
                let size = wx.length().max(wy.length());
                assert!(err < 0.02 * size, "{name} at {p}: ({got:?}) against {wx} {wy}");
                let held = m.apply(&LookupContext { dndx: Vec3::ZERO, dndy: Vec3::ZERO, ..ctx }).footprint;
                let held_err = (Vec2::new(held.dudx, held.dvdx) - wx).length();
                assert!(!turn_matters || held_err > 0.2 * size, "{name} at {p}: the normal's turn should matter");
            }
        }
    }

    /// Set 1 comes from the context's second set, its Jacobian composed with the uv transform.
    #[test]
    fn the_second_set_reads_the_contexts_second_coordinates() {
        let uv1 = UvSet {
            uv: Vec2::new(0.25, 0.75),
            footprint: Footprint { dudx: 0.01, dvdx: 0.0, dudy: 0.0, dvdy: 0.02 },
            jacobian: [Vec2::new(2.0, 0.0), Vec2::new(-1.0, 3.0)],
        };
        let ctx = LookupContext { uv: Vec2::new(0.5, 0.5), uv1, ..LookupContext::default() };
        let transform = UvTransform::new(Vec2::new(0.1, 0.0), 0.0, Vec2::splat(2.0));
        let m = Mapping { projection: Projection::SecondUv, ..Mapping::uv(transform) };
        let (mapped, jacobian) = m.apply_with_jacobian(&ctx);
        assert!((mapped.uv - Vec2::new(0.6, 1.5)).length() < 1e-6, "{}", mapped.uv);
        assert!((mapped.footprint.dudx - 0.02).abs() < 1e-7 && (mapped.footprint.dvdy - 0.04).abs() < 1e-7);
        assert_eq!(jacobian, [Vec2::new(4.0, 0.0), Vec2::new(-2.0, 6.0)]);
        assert_eq!(m.constant_jacobian(), None);
    }
}
