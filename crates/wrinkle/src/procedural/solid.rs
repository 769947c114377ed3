//! Procedural patterns as textures and as bump functions: solid (evaluated at the object-space point,
//! u = x, v = y, w = z, so there is no parameterisation and no distortion at a sphere's poles) or laid on
//! the surface's (u,v) like an image.

use super::effects::{spline, Pattern};
use super::perlin::NoiseD;
use crate::lanes::{F8, LANES};
use crate::texture::{lane_by_lane, Footprint, LookupContext, LookupContext8, Texture};
use glam::{Vec3, Vec4};

/// Where a pattern is evaluated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Space {
    /// The object-space point: a solid texture.
    Object,
    /// The surface parameters (u, v), one unit per period of the parameterisation.
    Uv,
}

/// A pattern and where it is evaluated.
#[derive(Clone, Debug)]
pub struct Procedural {
    pub pattern: Pattern,
    pub space: Space,
}

/// The pixel's size in (u,v): the square root of its area there (the slides' d = sqrt(area) of MIP maps).
fn uv_width(fp: &Footprint) -> f32 {
    (fp.dudx * fp.dvdy - fp.dvdx * fp.dudy).abs().sqrt()
}

impl Procedural {
    /// The point the pattern is evaluated at and the pixel's size there.
    #[inline]
    fn point(&self, ctx: &LookupContext) -> ([f32; 3], f32) {
        match self.space {
            Space::Object => (ctx.p.to_array(), ctx.pixel_width()),
            Space::Uv => ([ctx.uv.x, ctx.uv.y, 0.0], uv_width(&ctx.footprint)),
        }
    }

    /// t and its gradient with respect to the lookup point (the object-space point, or (u, v, 0)).
    pub fn eval_d(&self, ctx: &LookupContext) -> NoiseD {
        let (p, width) = self.point(ctx);
        self.pattern.eval_d(p, width)
    }

    fn color(&self, p: [f32; 3], width: f32) -> Vec4 {
        Vec3::from_array(spline(&self.pattern.params.colors, self.pattern.eval(p, width))).extend(1.0)
    }
}

impl Texture for Procedural {
    fn eval(&self, ctx: &LookupContext) -> Vec4 {
        let (p, width) = self.point(ctx);
        self.color(p, width)
    }

    /// The pixel sizes of a solid texture on the lanes, then the pattern lane by lane.
    fn eval8(&self, ctx: &LookupContext8<'_>) -> [F8; 4] {
        if self.space == Space::Uv {
            return lane_by_lane(self, ctx);
        }
        let widths = ctx.surface.pixel_widths();
        let texels: [Vec4; LANES] =
            std::array::from_fn(|i| self.color(ctx.surface.p.lane(i).to_array(), widths.as_array_ref()[i]));
        std::array::from_fn(|c| F8::new(texels.map(|t| t[c])))
    }
}

#[cfg(test)]
mod tests {
    use super::super::effects::{Kind, Params};
    use super::*;
    use crate::geometry::Surface;
    use glam::Vec2;

    #[test]
    fn solid_texture_reads_the_object_point_not_the_parameters() {
        // On a sphere, two (u,v) near the pole map to nearly the same point: a solid texture gives nearly the
        // same colour there while the parameters differ by half a turn.
        let pattern = Pattern::new(Params::new(Kind::Marble), 3, false).unwrap();
        let tex = Procedural { pattern: pattern.clone(), space: Space::Object };
        let sphere = Surface::Sphere { radius: 1.0 };
        let fp = Footprint::default();
        let (a, b) = (Vec2::new(0.1, 0.9999), Vec2::new(0.6, 0.9999));
        let (fa, fb) = (sphere.frame(a.x, a.y), sphere.frame(b.x, b.y));
        let ca = tex.eval(&LookupContext::on_surface(fa.p, fa.pu, fa.pv, a, fp));
        let cb = tex.eval(&LookupContext::on_surface(fb.p, fb.pu, fb.pv, b, fp));
        assert!((ca - cb).length() < 0.02, "{ca} vs {cb}");
        let direct = spline(&pattern.params.colors, pattern.eval(fa.p.to_array(), 0.0));
        assert!((ca.truncate() - Vec3::from_array(direct)).length() < 1e-6);
    }
}
