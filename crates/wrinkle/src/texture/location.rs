//! Where in the texture a pixel looks, and over what (the course's "texel location"): the (u,v) of the
//! pixel's centre with the footprint of its screen derivatives (the default), or the quadrilateral the
//! pixel's four corners project to, read at its centroid (the average of the corners' (u,v)) or at the
//! crossing of its diagonals, with the footprint of its bimedians. In perspective the quadrilateral is not
//! a parallelogram, so the three differ: the far side of the pixel covers more texels.
//!
//! The corners are the corner rays' crossings with the surface's tangent plane, their (u,v) from Pu and Pv
//! there: exact on flat surfaces with affine (u,v) (patches, mesh triangles), to first order elsewhere.

use crate::geometry::mesh_lanes::Rays8;
use crate::lanes::{CmpEq, CmpGt, F8, V3};
use crate::texture::Footprint8;

/// Which point of the pixel's preimage a lookup reads, and which footprint it filters over.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TexelLocation {
    /// The (u,v) of the pixel's centre; the footprint of its derivatives.
    #[default]
    Centre,
    /// The average of the projected corners' (u,v); the footprint of the quadrilateral's bimedians.
    Centroid,
    /// Where the projected quadrilateral's diagonals cross; the footprint of its bimedians.
    Diagonals,
}

impl TexelLocation {
    pub const NAMES: [(&'static str, TexelLocation); 3] = [
        ("centre", TexelLocation::Centre),
        ("centroid", TexelLocation::Centroid),
        ("diagonals", TexelLocation::Diagonals),
    ];

    pub fn parse(name: &str) -> Option<TexelLocation> {
        TexelLocation::NAMES.iter().find(|(n, _)| *n == name).map(|&(_, l)| l)
    }

    /// The (u,v) and footprint of eight samples at `p` with tangents `pu`, `pv` and (u,v) `uv`, whose rays
    /// (object space, differentials per sample cell) are `rays`. Lanes whose corner rays miss the tangent
    /// plane (edge on) keep the centre's.
    pub fn locate8(self, rays: &Rays8, p: V3, pu: V3, pv: V3, uv: (F8, F8), fp: Footprint8) -> ((F8, F8), Footprint8) {
        if self == TexelLocation::Centre {
            return (uv, fp);
        }
        let n = pu.cross(pv);
        let (d00, d01, d11) = (pu.dot(pu), pu.dot(pv), pv.dot(pv));
        let inv = F8::ONE / (d00 * d11 - d01 * d01);
        let half = F8::splat(0.5);
        // All lanes set: a mask.
        let mut hit = F8::ZERO.cmp_eq(F8::ZERO);
        // Corners (-,-), (+,-), (+,+), (-,+) in screen x and y.
        let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)].map(|(a, b): (f32, f32)| {
            let (a, b) = (F8::splat(a) * half, F8::splat(b) * half);
            let origin = rays.origin + rays.dx.0 * a + rays.dy.0 * b;
            let dir = rays.dir + rays.dx.1 * a + rays.dy.1 * b;
            let (num, den) = (n.dot(p - origin), n.dot(dir));
            let t = num / den;
            // The ray meets the plane in front of its origin, not edge on.
            let facing = (den * den).cmp_gt(F8::splat(1e-12) * n.dot(n) * dir.dot(dir));
            hit = hit & t.cmp_gt(F8::ZERO) & facing;
            let w = origin + dir * t - p;
            let (a, b) = (w.dot(pu), w.dot(pv));
            (uv.0 + (d11 * a - d01 * b) * inv, uv.1 + (d00 * b - d01 * a) * inv)
        });
        let [c0, c1, c2, c3] = corners;
        let at = match self {
            TexelLocation::Centroid => {
                let quarter = F8::splat(0.25);
                ((c0.0 + c1.0 + c2.0 + c3.0) * quarter, (c0.1 + c1.1 + c2.1 + c3.1) * quarter)
            }
            _ => {
                // c0 + s (c2 - c0) = c1 + r (c3 - c1): s = cross(c1 - c0, c3 - c1) / cross(c2 - c0, c3 - c1).
                let cross = |a: (F8, F8), b: (F8, F8)| a.0 * b.1 - a.1 * b.0;
                let sub = |a: (F8, F8), b: (F8, F8)| (a.0 - b.0, a.1 - b.1);
                let (e, f) = (sub(c2, c0), sub(c3, c1));
                let s = cross(sub(c1, c0), f) / cross(e, f);
                (c0.0 + e.0 * s, c0.1 + e.1 * s)
            }
        };
        // The bimedians: the right edge's midpoint less the left's, the top's less the bottom's.
        let footprint = Footprint8 {
            dudx: (c1.0 + c2.0 - c0.0 - c3.0) * half,
            dvdx: (c1.1 + c2.1 - c0.1 - c3.1) * half,
            dudy: (c3.0 + c2.0 - c0.0 - c1.0) * half,
            dvdy: (c3.1 + c2.1 - c0.1 - c1.1) * half,
        };
        let ok = hit & at.0.is_finite() & at.1.is_finite();
        (
            (ok.blend(at.0, uv.0), ok.blend(at.1, uv.1)),
            Footprint8 {
                dudx: ok.blend(footprint.dudx, fp.dudx),
                dvdx: ok.blend(footprint.dvdx, fp.dvdx),
                dudy: ok.blend(footprint.dudy, fp.dudy),
                dvdy: ok.blend(footprint.dvdy, fp.dvdy),
            },
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The footprint of the projected quadrilateral: unit test of the bimedians on a floor in perspective.
    #[test]
    fn the_quadrilaterals_footprint_is_its_bimedians() {
        // The eye at the origin looking down -z at a floor y = -1 with (u,v) = (x, -z): a pixel step of 0.01
        // in the image plane at unit depth.
        let s = V3::splat;
        let step = 0.01f32;
        let dir = glam::Vec3::new(0.02, -0.1, -1.0);
        let rays = Rays8 {
            origin: s(glam::Vec3::ZERO),
            dir: s(dir),
            dx: (s(glam::Vec3::ZERO), s(glam::Vec3::new(step, 0.0, 0.0))),
            dy: (s(glam::Vec3::ZERO), s(glam::Vec3::new(0.0, -step, 0.0))),
        };
        let t = -1.0 / dir.y;
        let p = dir * t;
        let uv = (F8::splat(p.x), F8::splat(-p.z));
        let (pu, pv) = (s(glam::Vec3::X), s(-glam::Vec3::Z));
        let none = Footprint8 { dudx: F8::ZERO, dvdx: F8::ZERO, dudy: F8::ZERO, dvdy: F8::ZERO };
        let ((_, _), fp) = TexelLocation::Centroid.locate8(&rays, s(p), pu, pv, uv, none);
        // The corners' (u,v) on the floor, in f64.
        let corner = |a: f64, b: f64| {
            let d = glam::DVec3::new(dir.x as f64 + a * step as f64, dir.y as f64 - b * step as f64, -1.0);
            let t = -1.0 / d.y;
            (d.x * t, -d.z * t)
        };
        let (c0, c1, c2, c3) = (corner(-0.5, -0.5), corner(0.5, -0.5), corner(0.5, 0.5), corner(-0.5, 0.5));
        let want_dudx = 0.5 * (c1.0 + c2.0 - c0.0 - c3.0);
        let want_dvdy = 0.5 * (c3.1 + c2.1 - c0.1 - c1.1);
        let got = (fp.dudx.as_array_ref()[0] as f64, fp.dvdy.as_array_ref()[0] as f64);
        assert!((got.0 - want_dudx).abs() < 1e-5 * want_dudx.abs().max(1.0), "{got:?} vs {want_dudx}");
        assert!((got.1 - want_dvdy).abs() < 1e-4 * want_dvdy.abs().max(1.0), "{got:?} vs {want_dvdy}");
    }
}
