//! Procedural patterns as textures and as bump functions: solid (evaluated at the object-space point,
//! u = x, v = y, w = z, so there is no parameterisation and no distortion at a sphere's poles) or laid on
//! the surface's (u,v) like an image.

use super::effects::{spline, Pattern};
use super::perlin::NoiseD;
use crate::geometry::SurfaceFrame;
use crate::texture::{Footprint, SolidPoint, Texture};
use glam::{Vec2, Vec3, Vec4};

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
    /// t and its gradient with respect to the lookup point, for a sample at `uv` (or `solid`).
    fn eval_d(&self, uv: Vec2, footprint: &Footprint, solid: &SolidPoint) -> NoiseD {
        match self.space {
            Space::Object => self.pattern.eval_d(solid.p.to_array(), solid.width),
            Space::Uv => self.pattern.eval_d([uv.x, uv.y, 0.0], uv_width(footprint)),
        }
    }

    /// The bump function F = amplitude t and its derivatives Fu, Fv from the pattern's analytic gradient:
    /// in object space by the chain rule through the surface, Fu = grad t . Pu, Fv = grad t . Pv.
    pub fn bump(&self, amplitude: f32, uv: Vec2, frame: &SurfaceFrame, footprint: &Footprint) -> NoiseD {
        let solid = solid_point(frame, footprint);
        let t = self.eval_d(uv, footprint, &solid);
        let g = Vec3::from_array(t.grad);
        let (fu, fv) = match self.space {
            Space::Object => (g.dot(frame.pu), g.dot(frame.pv)),
            Space::Uv => (g.x, g.y),
        };
        NoiseD { value: amplitude * t.value, grad: [amplitude * fu, amplitude * fv, 0.0] }
    }
}

/// The object-space point of a sample and its pixel's size there: the square root of the area spanned by
/// dP/dx = Pu du/dx + Pv dv/dx and dP/dy.
pub fn solid_point(frame: &SurfaceFrame, fp: &Footprint) -> SolidPoint {
    let dx = frame.pu * fp.dudx + frame.pv * fp.dvdx;
    let dy = frame.pu * fp.dudy + frame.pv * fp.dvdy;
    SolidPoint { p: frame.p, width: dx.cross(dy).length().sqrt() }
}

impl Texture for Procedural {
    fn sample(&self, uv: Vec2, footprint: &Footprint) -> Vec4 {
        // Without a surface point, a solid texture is read on the plane z = 0 at (u, v).
        let solid = SolidPoint { p: Vec3::new(uv.x, uv.y, 0.0), width: uv_width(footprint) };
        self.sample_at(uv, footprint, &solid)
    }

    fn sample_at(&self, uv: Vec2, footprint: &Footprint, solid: &SolidPoint) -> Vec4 {
        let t = match self.space {
            Space::Object => self.pattern.eval(solid.p.to_array(), solid.width),
            Space::Uv => self.pattern.eval([uv.x, uv.y, 0.0], uv_width(footprint)),
        };
        Vec3::from_array(spline(&self.pattern.params.colors, t)).extend(1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::super::effects::{Kind, Params};
    use super::*;
    use crate::geometry::Surface;

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
        let ca = tex.sample_at(a, &fp, &solid_point(&fa, &fp));
        let cb = tex.sample_at(b, &fp, &solid_point(&fb, &fp));
        assert!((ca - cb).length() < 0.02, "{ca} vs {cb}");
        let direct = spline(&pattern.params.colors, pattern.eval(fa.p.to_array(), 0.0));
        assert!((ca.truncate() - Vec3::from_array(direct)).length() < 1e-6);
    }

    #[test]
    fn bump_derivatives_follow_the_surface() {
        // Fu, Fv from the analytic gradient against differences of F along the surface's parameters.
        let pattern = Pattern::new(Params::new(Kind::Fbm), 3, false).unwrap();
        let bump = Procedural { pattern, space: Space::Object };
        let torus = Surface::Torus { major_radius: 1.0, minor_radius: 0.3 };
        let fp = Footprint::default();
        for i in 0..50 {
            let (u, v) = (0.013 + 0.019 * i as f32, 0.7 - 0.011 * i as f32);
            let b = bump.bump(0.1, Vec2::new(u, v), &torus.frame(u, v), &fp);
            let f = |u: f32, v: f32| bump.bump(0.1, Vec2::new(u, v), &torus.frame(u, v), &fp).value as f64;
            let h = 1e-4;
            let fu = (f(u + h, v) - f(u - h, v)) / (2.0 * h as f64);
            let fv = (f(u, v + h) - f(u, v - h)) / (2.0 * h as f64);
            assert!((b.grad[0] as f64 - fu).abs() < 2e-2 * (1.0 + fu.abs()), "Fu {} vs {fu}", b.grad[0]);
            assert!((b.grad[1] as f64 - fv).abs() < 2e-2 * (1.0 + fv.abs()), "Fv {} vs {fv}", b.grad[1]);
        }
    }
}
