//! The placement of a texture in (u,v): scaled (the repeat count), rotated, then offset, as OpenGL's
//! texture matrix and glTF's KHR_texture_transform place it: st = offset + R(rotation) (scale * uv).

use crate::lanes::F8;
use crate::texture::{Footprint, Footprint8};
use glam::Vec2;

/// st = A uv + offset, A = R(rotation) diag(scale).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UvTransform {
    /// The columns of A: d(st)/du and d(st)/dv.
    columns: [Vec2; 2],
    offset: Vec2,
    /// A is diagonal (no rotation but whole half turns): s depends on u alone and t on v alone, half the
    /// arithmetic per lookup (the common case of a plain repeat).
    diagonal: bool,
}

impl UvTransform {
    pub const IDENTITY: UvTransform = UvTransform { columns: [Vec2::X, Vec2::Y], offset: Vec2::ZERO, diagonal: true };

    /// `scale` copies per unit of (u, v) (the repeat count), rotated counter-clockwise by `rotation_degrees`,
    /// then moved by `offset`.
    pub fn new(offset: Vec2, rotation_degrees: f32, scale: Vec2) -> UvTransform {
        // Whole quarter turns exactly: a rotation of 0 must leave st = scale * uv bit for bit.
        let (sin, cos) = match rotation_degrees.rem_euclid(360.0) {
            0.0 => (0.0, 1.0),
            90.0 => (1.0, 0.0),
            180.0 => (0.0, -1.0),
            270.0 => (-1.0, 0.0),
            r => r.to_radians().sin_cos(),
        };
        let columns = [Vec2::new(cos, sin) * scale.x, Vec2::new(-sin, cos) * scale.y];
        UvTransform { columns, offset, diagonal: sin == 0.0 }
    }

    /// `scale` copies per unit of (u, v) and nothing else.
    pub fn repeat(scale: Vec2) -> UvTransform {
        UvTransform::new(Vec2::ZERO, 0.0, scale)
    }

    /// The columns of the linear part: d(st)/du and d(st)/dv.
    #[inline]
    pub fn linear(&self) -> [Vec2; 2] {
        self.columns
    }

    #[inline]
    pub fn point(&self, uv: Vec2) -> Vec2 {
        let [a, b] = self.columns;
        if self.diagonal {
            return Vec2::new(a.x * uv.x, b.y * uv.y) + self.offset;
        }
        a * uv.x + b * uv.y + self.offset
    }

    #[inline]
    pub fn point8(&self, u: F8, v: F8) -> (F8, F8) {
        let [a, b] = self.columns;
        let o = self.offset;
        if self.diagonal {
            return (F8::splat(a.x) * u + F8::splat(o.x), F8::splat(b.y) * v + F8::splat(o.y));
        }
        let s = |a: f32, b: f32, o: f32| F8::splat(a) * u + F8::splat(b) * v + F8::splat(o);
        (s(a.x, b.x, o.x), s(a.y, b.y, o.y))
    }

    /// The footprint of the transformed coordinates: A applied to each screen step.
    #[inline]
    pub fn footprint(&self, fp: &Footprint) -> Footprint {
        let [a, b] = self.columns;
        if self.diagonal {
            return Footprint { dudx: a.x * fp.dudx, dvdx: b.y * fp.dvdx, dudy: a.x * fp.dudy, dvdy: b.y * fp.dvdy };
        }
        let dx = a * fp.dudx + b * fp.dvdx;
        let dy = a * fp.dudy + b * fp.dvdy;
        Footprint { dudx: dx.x, dvdx: dx.y, dudy: dy.x, dvdy: dy.y }
    }
}

impl UvTransform {
    /// `footprint` on eight lanes.
    #[inline]
    pub fn footprint8(&self, fp: &Footprint8) -> Footprint8 {
        let [a, b] = self.columns;
        let k = F8::splat;
        if self.diagonal {
            let (su, sv) = (k(a.x), k(b.y));
            return Footprint8 { dudx: fp.dudx * su, dvdx: fp.dvdx * sv, dudy: fp.dudy * su, dvdy: fp.dvdy * sv };
        }
        let row = |x: f32, y: f32, du: F8, dv: F8| k(x) * du + k(y) * dv;
        Footprint8 {
            dudx: row(a.x, b.x, fp.dudx, fp.dvdx),
            dvdx: row(a.y, b.y, fp.dudx, fp.dvdx),
            dudy: row(a.x, b.x, fp.dudy, fp.dvdy),
            dvdy: row(a.y, b.y, fp.dudy, fp.dvdy),
        }
    }
}

impl Default for UvTransform {
    fn default() -> Self {
        UvTransform::IDENTITY
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_plain_repeat_is_exactly_a_scale() {
        let t = UvTransform::repeat(Vec2::new(8.0, 4.0));
        for (u, v) in [(0.1f32, 0.7f32), (0.333, 0.999), (-2.5, 1e-7)] {
            assert_eq!(t.point(Vec2::new(u, v)), Vec2::new(8.0 * u, 4.0 * v));
            let (s, tt) = t.point8(F8::splat(u), F8::splat(v));
            assert_eq!((s.as_array_ref()[3], tt.as_array_ref()[3]), (8.0 * u, 4.0 * v));
        }
        let fp = Footprint { dudx: 0.01, dvdx: -0.002, dudy: 0.003, dvdy: 0.02 };
        let got = t.footprint(&fp);
        assert_eq!(got, Footprint { dudx: 0.08, dvdx: -0.008, dudy: 0.024, dvdy: 0.08 });
    }

    /// Scale, then rotate counter-clockwise, then offset; the footprint follows the same linear map.
    #[test]
    fn scale_rotate_offset_in_that_order() {
        let t = UvTransform::new(Vec2::new(0.5, -0.25), 30.0, Vec2::new(2.0, 3.0));
        let (s, c) = 30f32.to_radians().sin_cos();
        let uv = Vec2::new(0.2, 0.6);
        let scaled = Vec2::new(2.0 * uv.x, 3.0 * uv.y);
        let want = Vec2::new(c * scaled.x - s * scaled.y, s * scaled.x + c * scaled.y) + Vec2::new(0.5, -0.25);
        assert!((t.point(uv) - want).length() < 1e-6);
        let h = 1e-3;
        let fp = Footprint { dudx: h, dvdx: 0.0, dudy: 0.0, dvdy: h };
        let mapped = t.footprint(&fp);
        let dx = (t.point(uv + Vec2::new(h, 0.0)) - t.point(uv)).to_array();
        assert!((mapped.dudx - dx[0]).abs() < 1e-6 && (mapped.dvdx - dx[1]).abs() < 1e-6);
        // A quarter turn is exact.
        assert_eq!(UvTransform::new(Vec2::ZERO, 90.0, Vec2::ONE).point(Vec2::new(1.0, 0.0)), Vec2::new(0.0, 1.0));
    }
}
