//! Surface frames of eight (u,v) at once, for packet shading. The sphere, the usual case, is evaluated on
//! all lanes together; the other surfaces lane by lane through their scalar frames.

use super::surface::{Surface, SurfaceFrame};
use crate::lanes::{mul_add, CmpGe, CmpGt, CmpLe, CmpLt, F8, LANES, V3};
use crate::texture::Footprint8;
use std::f32::consts::{PI, TAU};
use wide::CmpEq;

/// Eight surface frames, one per lane.
#[derive(Clone, Copy, Debug)]
pub struct Frame8 {
    pub p: V3,
    pub pu: V3,
    pub pv: V3,
    pub puu: V3,
    pub puv: V3,
    pub pvv: V3,
}

impl Frame8 {
    pub fn from_lanes(f: &[SurfaceFrame; LANES]) -> Frame8 {
        let field = |get: fn(&SurfaceFrame) -> glam::Vec3| V3::from_lanes(&std::array::from_fn(|i| get(&f[i])));
        Frame8 {
            p: field(|f| f.p),
            pu: field(|f| f.pu),
            pv: field(|f| f.pv),
            puu: field(|f| f.puu),
            puv: field(|f| f.puv),
            pvv: field(|f| f.pvv),
        }
    }

    pub fn lane(&self, i: usize) -> SurfaceFrame {
        SurfaceFrame {
            p: self.p.lane(i),
            pu: self.pu.lane(i),
            pv: self.pv.lane(i),
            puu: self.puu.lane(i),
            puv: self.puv.lane(i),
            pvv: self.pvv.lane(i),
        }
    }

    pub fn set_lane(&mut self, i: usize, f: &SurfaceFrame) {
        self.p.set_lane(i, f.p);
        self.pu.set_lane(i, f.pu);
        self.pv.set_lane(i, f.pv);
        self.puu.set_lane(i, f.puu);
        self.puv.set_lane(i, f.puv);
        self.pvv.set_lane(i, f.pvv);
    }

    /// Lane by lane, `t` where `mask` is set and `f` elsewhere.
    #[inline]
    pub fn select(mask: F8, t: &Frame8, f: &Frame8) -> Frame8 {
        let pick = |a: V3, b: V3| V3::select(mask, a, b);
        Frame8 {
            p: pick(t.p, f.p),
            pu: pick(t.pu, f.pu),
            pv: pick(t.pv, f.pv),
            puu: pick(t.puu, f.puu),
            puv: pick(t.puv, f.puv),
            pvv: pick(t.pvv, f.pvv),
        }
    }

    /// SurfaceFrame::advanced on every lane.
    #[inline]
    pub fn advanced(&self, du: F8, dv: F8) -> Frame8 {
        let half = F8::splat(0.5);
        Frame8 {
            p: self.p
                + self.pu * du
                + self.pv * dv
                + (self.puu * (du * du) + self.pvv * (dv * dv)) * half
                + self.puv * (du * dv),
            pu: self.pu + self.puu * du + self.puv * dv,
            pv: self.pv + self.puv * du + self.pvv * dv,
            ..*self
        }
    }

    /// `SurfaceFrame::max_curvature` on the lanes.
    #[inline]
    pub fn max_curvature8(&self) -> F8 {
        let n = self.pu.cross(self.pv).normalize_or_zero();
        let (e, f, g) = (n.dot(self.puu), n.dot(self.puv), n.dot(self.pvv));
        let (ee, ff, gg) = (self.pu.dot(self.pu), self.pu.dot(self.pv), self.pv.dot(self.pv));
        let det = ee * gg - ff * ff;
        let degenerate = !(F8::splat(1e-12) * (ee * gg).max(F8::splat(f32::MIN_POSITIVE))).cmp_lt(det);
        let mean = (e * gg - F8::splat(2.0) * f * ff + g * ee) / (F8::splat(2.0) * det);
        let gauss = (e * g - f * f) / det;
        let k = mean.abs() + (mean * mean - gauss).max(F8::ZERO).sqrt();
        degenerate.blend(F8::splat(f32::INFINITY), k)
    }

    /// How the unit normal Pu x Pv / |Pu x Pv| changes across one pixel step in x and in y, where (u,v)
    /// change by `footprint`: N's derivatives Nu = Puu x Pv + Pu x Puv and Nv = Puv x Pv + Pu x Pvv, less
    /// their part along N, over |N|.
    #[inline]
    pub fn unit_normal_change(&self, footprint: &Footprint8) -> [V3; 2] {
        let n = self.pu.cross(self.pv);
        let len = n.length();
        let inv_len = F8::ONE / len;
        let unit = n * inv_len;
        let nu = self.puu.cross(self.pv) + self.pu.cross(self.puv);
        let nv = self.puv.cross(self.pv) + self.pu.cross(self.pvv);
        let turn = |d: V3| {
            let t = (d - unit * unit.dot(d)) * inv_len;
            V3::select(len.cmp_gt(F8::ZERO), t, V3::ZERO)
        };
        [turn(nu * footprint.dudx + nv * footprint.dvdx), turn(nu * footprint.dudy + nv * footprint.dvdy)]
    }
}

impl Surface {
    /// The frames at eight (u,v).
    pub fn frame8(&self, u: F8, v: F8) -> Frame8 {
        match *self {
            Surface::Sphere { radius } => sphere8(radius, u, v),
            Surface::Bicubic { ref points } => bezier8(points, u, v),
            _ => {
                let (u, v) = (u.as_array_ref(), v.as_array_ref());
                Frame8::from_lanes(&std::array::from_fn(|i| self.frame(u[i], v[i])))
            }
        }
    }

    /// The scalar frames of the lanes `lanes` (bit i: lane i) at eight (u,v) into `frames`; the other lanes
    /// keep theirs (a few samples of a packet need the surface, not all eight).
    pub fn frames_of_lanes(&self, u: F8, v: F8, lanes: u8, frames: &mut [SurfaceFrame; LANES]) {
        let (u, v) = (u.as_array_ref(), v.as_array_ref());
        for (i, f) in frames.iter_mut().enumerate().filter(|(i, _)| lanes >> i & 1 == 1) {
            *f = self.frame(u[i], v[i]);
        }
    }
}

/// The cubic Bernstein basis and its first and second derivatives on every lane: the scalar `bernstein`'s
/// operations in its order, so the frames are the scalar ones to the bit.
#[inline]
fn bernstein8(t: F8) -> ([F8; 4], [F8; 4], [F8; 4]) {
    let k = F8::splat;
    let s = F8::ONE - t;
    let b = [s * s * s, k(3.0) * t * s * s, k(3.0) * t * t * s, t * t * t];
    let d = [k(-3.0) * s * s, k(3.0) * s * s - k(6.0) * t * s, k(6.0) * t * s - k(3.0) * t * t, k(3.0) * t * t];
    let dd = [k(6.0) * s, k(18.0) * t - k(12.0), k(6.0) - k(18.0) * t, k(6.0) * t];
    (b, d, dd)
}

/// The bicubic Bezier patch's frame on every lane (the scalar `bezier`'s sums in its order: the same bits).
fn bezier8(points: &[glam::Vec3; 16], u: F8, v: F8) -> Frame8 {
    let (bu, du, ddu) = bernstein8(u);
    let (bv, dv, ddv) = bernstein8(v);
    let mut f = Frame8 { p: V3::ZERO, pu: V3::ZERO, pv: V3::ZERO, puu: V3::ZERO, puv: V3::ZERO, pvv: V3::ZERO };
    for j in 0..4 {
        for i in 0..4 {
            let q = V3::splat(points[4 * j + i]);
            f.p = f.p + q * (bu[i] * bv[j]);
            f.pu = f.pu + q * (du[i] * bv[j]);
            f.pv = f.pv + q * (bu[i] * dv[j]);
            f.puu = f.puu + q * (ddu[i] * bv[j]);
            f.puv = f.puv + q * (du[i] * dv[j]);
            f.pvv = f.pvv + q * (bu[i] * ddv[j]);
        }
    }
    f
}

/// sin_cos_turns on every lane: the same polynomial and octant reduction.
#[inline]
pub fn sin_cos_turns8(t: F8) -> (F8, F8) {
    let x = t - t.round();
    let q = (x * F8::splat(4.0)).round();
    let a = F8::splat(TAU) * (x - F8::splat(0.25) * q);
    let a2 = a * a;
    let poly = |c: [f32; 4], first: f32| {
        let mut p = F8::splat(c[3]);
        for k in (0..3).rev() {
            p = mul_add(p, a2, F8::splat(c[k]));
        }
        mul_add(p, a2, F8::splat(first))
    };
    let s = a * poly([-1.0 / 6.0, 1.0 / 120.0, -1.0 / 5040.0, 1.0 / 362_880.0], 1.0);
    let c = poly([-0.5, 1.0 / 24.0, -1.0 / 720.0, 1.0 / 40_320.0], 1.0);
    // The quadrant q mod 4 (q is in -2..=2).
    let quadrant = q - F8::splat(4.0) * (q * F8::splat(0.25)).floor();
    let (q1, q2, q3) =
        (quadrant.cmp_eq(F8::splat(1.0)), quadrant.cmp_eq(F8::splat(2.0)), quadrant.cmp_eq(F8::splat(3.0)));
    let sin = q1.blend(c, q2.blend(-s, q3.blend(-c, s)));
    let cos = q1.blend(-s, q2.blend(-c, q3.blend(s, c)));
    (sin, cos)
}

fn sphere8(r: f32, u: F8, v: F8) -> Frame8 {
    let (sp, cp) = sin_cos_turns8(u);
    let (st, ct) = sin_cos_turns8(F8::splat(0.5) * (v - F8::splat(0.5)));
    // Exact poles, as the scalar frame has them.
    let (south, north) = (v.cmp_le(F8::ZERO), v.cmp_ge(F8::ONE));
    let st = south.blend(F8::splat(-1.0), north.blend(F8::ONE, st));
    let ct = (south | north).blend(F8::ZERO, ct);
    let (a, b) = (TAU, PI);
    let k = |s: f32| F8::splat(r * s);
    let v3 = |x: F8, y: F8, z: F8| V3 { x, y, z };
    let z = F8::ZERO;
    Frame8 {
        p: v3(ct * cp, st, -ct * sp) * k(1.0),
        pu: v3(-sp, z, -cp) * (k(a) * ct),
        pv: v3(-st * cp, ct, st * sp) * k(b),
        puu: v3(-cp, z, sp) * (k(a * a) * ct),
        puv: v3(sp, z, cp) * (k(a * b) * st),
        pvv: v3(-ct * cp, -st, ct * sp) * k(b * b),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::surface::sin_cos_turns;
    use glam::Vec3;

    #[test]
    fn lanes_match_the_scalar_frames() {
        let surfaces = [
            Surface::Sphere { radius: 1.3 },
            Surface::Torus { major_radius: 1.0, minor_radius: 0.3 },
            Surface::Patch { corners: [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.4), Vec3::Y] },
        ];
        // Every quadrant of both angles, the seam and both poles.
        let u = F8::new([0.0, 0.13, 0.26, 0.49, 0.51, 0.74, 0.99, 1.0]);
        let v = F8::new([0.0, 0.07, 0.3, 0.5, 0.62, 0.88, 0.97, 1.0]);
        for s in &surfaces {
            let f8 = s.frame8(u, v);
            for i in 0..LANES {
                let f = s.frame(u.as_array_ref()[i], v.as_array_ref()[i]);
                let g = f8.lane(i);
                for (a, b) in [(f.p, g.p), (f.pu, g.pu), (f.pv, g.pv), (f.puu, g.puu), (f.puv, g.puv), (f.pvv, g.pvv)] {
                    assert!((a - b).length() <= 1e-5 * (1.0 + a.length()), "{s:?} lane {i}: {a} vs {b}");
                }
            }
        }
        let t = F8::new([-0.6, -0.3, -0.1, 0.0, 0.2, 0.4, 0.77, 1.3]);
        let (s8, c8) = sin_cos_turns8(t);
        for i in 0..LANES {
            let (s, c) = sin_cos_turns(t.as_array_ref()[i]);
            assert!((s - s8.as_array_ref()[i]).abs() < 1e-7 && (c - c8.as_array_ref()[i]).abs() < 1e-7);
        }
    }

    /// The Bezier patch on lanes is its scalar frame to the bit (the teapot's pixels do not depend on
    /// which path shaded them).
    #[test]
    fn bezier_lanes_are_the_scalar_frames_exactly() {
        let points: [Vec3; 16] = std::array::from_fn(|k| {
            Vec3::new((k % 4) as f32 * 0.7, (k / 4) as f32 * 0.45, ((k * 7) % 5) as f32 * 0.31 - 0.6)
        });
        let s = Surface::Bicubic { points };
        let u = F8::new([0.0, 0.13, 0.26, 0.49, 0.51, 0.74, 0.99, 1.0]);
        let v = F8::new([1.0, 0.07, 0.3, 0.5, 0.62, 0.88, 0.97, 0.0]);
        let f8 = s.frame8(u, v);
        for i in 0..LANES {
            let (f, g) = (s.frame(u.as_array_ref()[i], v.as_array_ref()[i]), f8.lane(i));
            for (a, b) in [(f.p, g.p), (f.pu, g.pu), (f.pv, g.pv), (f.puu, g.puu), (f.puv, g.puv), (f.pvv, g.pvv)] {
                assert_eq!(a.to_array().map(f32::to_bits), b.to_array().map(f32::to_bits), "lane {i}: {a} vs {b}");
            }
        }
    }

    /// The unit normal's change across a step of (u,v) against the central difference of the exact unit
    /// normals, on a torus (two different curvatures, and both signs of Gaussian curvature).
    #[test]
    fn unit_normal_change_is_the_normals_difference_across_the_step() {
        let s = Surface::Torus { major_radius: 1.0, minor_radius: 0.3 };
        let (u, v) =
            (F8::new([0.0, 0.1, 0.2, 0.35, 0.5, 0.6, 0.8, 0.95]), F8::new([0.05, 0.2, 0.3, 0.45, 0.6, 0.7, 0.85, 0.9]));
        let h = 1e-3;
        let footprint =
            Footprint8 { dudx: F8::splat(h), dvdx: F8::splat(0.5 * h), dudy: F8::splat(-0.3 * h), dvdy: F8::splat(h) };
        let [dx, dy] = s.frame8(u, v).unit_normal_change(&footprint);
        let normal = |u: f32, v: f32| {
            let f = s.frame(u, v);
            f.pu.cross(f.pv).normalize()
        };
        for i in 0..LANES {
            let (u, v) = (u.as_array_ref()[i], v.as_array_ref()[i]);
            let fp = footprint.lane(i);
            let central = |du: f32, dv: f32| normal(u + du / 2.0, v + dv / 2.0) - normal(u - du / 2.0, v - dv / 2.0);
            for (got, want) in [(dx.lane(i), central(fp.dudx, fp.dvdx)), (dy.lane(i), central(fp.dudy, fp.dvdy))] {
                assert!((got - want).length() < 2e-3 * want.length() + 1e-6, "lane {i}: {got} vs {want}");
            }
        }
    }

    #[test]
    fn advanced_lanes_match_the_scalar_step() {
        let s = Surface::Sphere { radius: 1.0 };
        let f8 = s.frame8(F8::splat(0.3), F8::splat(0.6));
        let (du, dv) = (F8::new([1e-3, -2e-3, 0.0, 5e-4, 1e-4, -1e-4, 3e-3, 0.0]), F8::splat(-7e-4));
        let a8 = f8.advanced(du, dv);
        for i in 0..LANES {
            let a = s.frame(0.3, 0.6).advanced(du.as_array_ref()[i], dv.as_array_ref()[i]);
            assert!((a.p - a8.lane(i).p).length() < 1e-6 && (a.pu - a8.lane(i).pu).length() < 1e-5);
        }
    }

    #[test]
    fn max_curvature_on_lanes_matches_the_scalar_form() {
        let s = Surface::Torus { major_radius: 1.0, minor_radius: 0.4 };
        let frames: [SurfaceFrame; 8] = std::array::from_fn(|i| s.frame(0.05 + 0.12 * i as f32, 0.1 * i as f32));
        let lanes = Frame8::from_lanes(&frames).max_curvature8();
        for (i, f) in frames.iter().enumerate() {
            let want = f.max_curvature();
            assert!((lanes.as_array_ref()[i] - want).abs() < 1e-4 * want, "{i}");
            // A torus's largest curvature is the tube's, 1 / 0.4.
            assert!((want - 2.5).abs() < 1e-3, "{want}");
        }
    }
}
