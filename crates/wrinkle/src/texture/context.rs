//! The one argument of every texture lookup, colour or bump (pbrt-v4's `TextureEvalContext`): where the
//! sample is on the surface, how large its pixel is there, and which primitive it belongs to. A mapping
//! (crate::mapping) rewrites its texture coordinates; a texture reads what it needs: an image the
//! coordinates and their footprint, a solid texture the point and the pixel's size.
//!
//! A mesh may carry a second texture coordinate set (glTF's TEXCOORD_1; glTF asks viewers to draw two):
//! the context holds it beside the first, with its derivatives along the first set's (u,v), which is what
//! the surface tangents Pu, Pv and so a bump's chain rule are taken along.

use super::{Footprint, Footprint8};
use crate::lanes::{F8, LANES, V3};
use glam::{Affine3A, Vec2, Vec3};

/// Which primitive a sample lies on: the object's index in the scene and the triangle's within the object
/// (for parametric surfaces, the tessellation's).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PrimitiveId {
    pub object: u32,
    pub triangle: u32,
}

/// One surface sample as a texture sees it. Positions and vectors are in object space.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LookupContext {
    pub p: Vec3,
    /// How P moves across one pixel step in x and in y.
    pub dpdx: Vec3,
    pub dpdy: Vec3,
    /// The geometric normal Pu x Pv (not unit).
    pub n: Vec3,
    /// The surface tangents along the surface parameters: what a bump's Fu and Fv are taken along.
    pub dpdu: Vec3,
    pub dpdv: Vec3,
    /// The texture coordinates and their screen derivatives: the surface parameters until a mapping
    /// replaces them with its own.
    pub uv: Vec2,
    pub footprint: Footprint,
    /// The second texture coordinate set (zero where the surface has none).
    pub uv1: UvSet,
    /// How the unit normal changes across one pixel step in x and in y (zero unless a mapping that reads
    /// the normal asked for it): the footprint of projections along the normal or the reflected ray.
    pub dndx: Vec3,
    pub dndy: Vec3,
    pub primitive: PrimitiveId,
    /// Object space to eye (camera) space, for mappings defined in eye coordinates.
    pub object_to_eye: Affine3A,
}

/// A texture coordinate set at one sample: the coordinates, their screen derivatives, and their
/// derivatives along the surface parameters, d(s,t)/du and d(s,t)/dv.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct UvSet {
    pub uv: Vec2,
    pub footprint: Footprint,
    pub jacobian: [Vec2; 2],
}

/// `UvSet` on eight lanes.
#[derive(Clone, Copy, Debug)]
pub struct UvSet8 {
    pub u: F8,
    pub v: F8,
    pub footprint: Footprint8,
    /// d(s,t)/du and d(s,t)/dv.
    pub jacobian: [(F8, F8); 2],
}

impl UvSet8 {
    pub fn lane(&self, i: usize) -> UvSet {
        let at = |x: F8| x.as_array_ref()[i];
        UvSet {
            uv: Vec2::new(at(self.u), at(self.v)),
            footprint: self.footprint.lane(i),
            jacobian: self.jacobian.map(|(s, t)| Vec2::new(at(s), at(t))),
        }
    }
}

impl LookupContext {
    /// The context of a point with tangents `dpdu`, `dpdv` at `uv` whose screen derivatives are `footprint`:
    /// dP/dx = Pu du/dx + Pv dv/dx, and alike for y.
    pub fn on_surface(p: Vec3, dpdu: Vec3, dpdv: Vec3, uv: Vec2, footprint: Footprint) -> LookupContext {
        LookupContext {
            p,
            dpdx: dpdu * footprint.dudx + dpdv * footprint.dvdx,
            dpdy: dpdu * footprint.dudy + dpdv * footprint.dvdy,
            n: dpdu.cross(dpdv),
            dpdu,
            dpdv,
            uv,
            footprint,
            uv1: UvSet::default(),
            dndx: Vec3::ZERO,
            dndy: Vec3::ZERO,
            primitive: PrimitiveId::default(),
            object_to_eye: Affine3A::IDENTITY,
        }
    }

    /// A lookup at texture coordinates alone, with no surface behind them: the point is (u, v, 0) on the
    /// plane z = 0 whose tangents are the axes (what a solid texture reads when it is shown as an image).
    pub fn at_uv(uv: Vec2, footprint: Footprint) -> LookupContext {
        LookupContext::on_surface(uv.extend(0.0), Vec3::X, Vec3::Y, uv, footprint)
    }

    /// The pixel's size at P: the square root of the area spanned by dP/dx and dP/dy.
    pub fn pixel_width(&self) -> f32 {
        self.dpdx.cross(self.dpdy).length().sqrt()
    }
}

/// What eight samples of one primitive share with every lookup besides their texture coordinates: the
/// surface at each (object space), as structures of arrays.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceLanes<'a> {
    pub p: V3,
    pub dpdx: V3,
    pub dpdy: V3,
    /// The outward geometric normal (not unit).
    pub n: V3,
    pub dpdu: V3,
    pub dpdv: V3,
    /// The unit normal's change per pixel step in x and in y (zero unless a mapping reads it).
    pub dndx: V3,
    pub dndy: V3,
    /// A mesh's second texture coordinate set, where the material reads it.
    pub uv1: Option<&'a UvSet8>,
    pub object: u32,
    pub triangles: [u32; LANES],
    pub object_to_eye: Affine3A,
}

impl SurfaceLanes<'_> {
    /// Eight points with tangents `dpdu`, `dpdv` whose (u,v) screen derivatives are `footprint`:
    /// dP/dx = Pu du/dx + Pv dv/dx on every lane.
    #[inline]
    pub fn new(p: V3, dpdu: V3, dpdv: V3, footprint: &Footprint8, object: u32, triangles: [u32; LANES]) -> Self {
        SurfaceLanes {
            p,
            dpdx: dpdu * footprint.dudx + dpdv * footprint.dvdx,
            dpdy: dpdu * footprint.dudy + dpdv * footprint.dvdy,
            n: dpdu.cross(dpdv),
            dpdu,
            dpdv,
            dndx: V3::ZERO,
            dndy: V3::ZERO,
            uv1: None,
            object,
            triangles,
            object_to_eye: Affine3A::IDENTITY,
        }
    }

    /// `LookupContext::pixel_width` on every lane.
    #[inline]
    pub fn pixel_widths(&self) -> F8 {
        self.dpdx.cross(self.dpdy).length().sqrt()
    }
}

/// Eight contexts of one primitive at once (the packet shader's): the shared surface, borrowed, and each
/// lookup's own texture coordinates, so that a mapping makes a new context without copying the surface.
#[derive(Clone, Copy, Debug)]
pub struct LookupContext8<'a> {
    pub surface: &'a SurfaceLanes<'a>,
    pub u: F8,
    pub v: F8,
    pub footprint: Footprint8,
}

impl LookupContext8<'_> {
    /// The context of lane `i`.
    pub fn lane(&self, i: usize) -> LookupContext {
        let s = self.surface;
        LookupContext {
            p: s.p.lane(i),
            dpdx: s.dpdx.lane(i),
            dpdy: s.dpdy.lane(i),
            n: s.n.lane(i),
            dpdu: s.dpdu.lane(i),
            dpdv: s.dpdv.lane(i),
            uv: Vec2::new(self.u.as_array_ref()[i], self.v.as_array_ref()[i]),
            footprint: self.footprint.lane(i),
            uv1: s.uv1.map_or(UvSet::default(), |set| set.lane(i)),
            dndx: s.dndx.lane(i),
            dndy: s.dndy.lane(i),
            primitive: PrimitiveId { object: s.object, triangle: s.triangles[i] },
            object_to_eye: s.object_to_eye,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The lane form holds on every lane what the scalar form holds for its sample.
    #[test]
    fn lanes_equal_the_scalar_form() {
        let v = |k: usize, a: f32| Vec3::new(a + k as f32 * 0.3, 1.0 - a * k as f32 * 0.1, 0.5 * a - k as f32);
        let footprints: [Footprint; LANES] = std::array::from_fn(|k| {
            let s = 0.001 * (k + 1) as f32;
            Footprint { dudx: s, dvdx: 0.3 * s, dudy: -0.2 * s, dvdy: 2.0 * s }
        });
        let lanes = |a: f32| V3::from_lanes(&std::array::from_fn(|k| v(k, a)));
        let uv = (F8::new(std::array::from_fn(|k| 0.1 * k as f32)), F8::splat(0.25));
        let triangles = std::array::from_fn(|k| 10 * k as u32);
        let footprint = Footprint8::from_lanes(&footprints);
        let surface = SurfaceLanes::new(lanes(0.2), lanes(1.5), lanes(-0.7), &footprint, 3, triangles);
        let ctx8 = LookupContext8 { surface: &surface, u: uv.0, v: uv.1, footprint };
        let widths = surface.pixel_widths();
        for (k, &fp) in footprints.iter().enumerate() {
            let mut want =
                LookupContext::on_surface(v(k, 0.2), v(k, 1.5), v(k, -0.7), Vec2::new(0.1 * k as f32, 0.25), fp);
            want.primitive = PrimitiveId { object: 3, triangle: 10 * k as u32 };
            let got = ctx8.lane(k);
            for (a, b) in [(got.dpdx, want.dpdx), (got.dpdy, want.dpdy), (got.n, want.n)] {
                assert!((a - b).length() <= 1e-6 * b.length().max(1.0), "lane {k}: {a} vs {b}");
            }
            assert_eq!(
                (got.p, got.uv, got.footprint, got.primitive),
                (want.p, want.uv, want.footprint, want.primitive)
            );
            let w = want.pixel_width();
            assert!((widths.as_array_ref()[k] - w).abs() <= 1e-5 * w, "lane {k}: {} vs {w}", widths.as_array_ref()[k]);
        }
    }
}
