//! Where a direction lies in each environment layout of the slides, and back: latitude-longitude, the cube
//! (Greene), the sphere map (the unpeeled mirror ball) and the dual paraboloid (Heidrich and Seidel).
//!
//! A layout is one or more square or 2:1 images; a point of it is an image and (s, t) in [0, 1]^2, t up the
//! picture (row 0 at t = 1), as every texture of wrinkle. Directions are in the map's own frame: +Y up.
//! - latlong: the image's centre column looks down -Z, its left and right edges +Z, its top row +Y;
//!   s = 1/2 + atan2(x, -z) / 2pi, t = 1/2 + asin(y) / pi.
//! - cube: OpenGL's faces and orientations (images 0..6 = +X, -X, +Y, -Y, +Z, -Z); the largest component
//!   picks the face, s = (sc / |ma| + 1) / 2 and the picture's row from tc (the GL specification's table).
//! - sphere: OpenGL's sphere map, the ball seen from +Z: m = 2 sqrt(x^2 + y^2 + (z + 1)^2),
//!   s = x / m + 1/2, t = y / m + 1/2; its rim is -Z.
//! - paraboloid: image 0 the +Z half, s = x / (2 (1 + z)) + 1/2, t = y / (2 (1 + z)) + 1/2; image 1 the -Z
//!   half, mirrored in x (s = -x / (2 (1 - z)) + 1/2), so that side by side the two meet at +X.

use crate::lanes::{asin, atan2, CmpEq, CmpGe, CmpLt, F8, LANES, V3};
use glam::Vec3;
use std::f32::consts::PI;

/// How an environment's directions are laid out in its images.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Layout {
    LatLong,
    Cube,
    Sphere,
    Paraboloid,
}

impl Layout {
    pub const ALL: [(&'static str, Layout); 4] = [
        ("latlong", Layout::LatLong),
        ("cube", Layout::Cube),
        ("sphere", Layout::Sphere),
        ("paraboloid", Layout::Paraboloid),
    ];

    pub fn parse(name: &str) -> Option<Layout> {
        Layout::ALL.iter().find(|(n, _)| *n == name).map(|&(_, l)| l)
    }

    pub fn name(self) -> &'static str {
        Layout::ALL.iter().find(|(_, l)| *l == self).map(|(n, _)| *n).expect("every layout is named")
    }

    /// How many images the layout has.
    pub fn images(self) -> usize {
        match self {
            Layout::Cube => 6,
            Layout::Paraboloid => 2,
            Layout::LatLong | Layout::Sphere => 1,
        }
    }

    /// Where unit direction `d` lies, and the gradients of s and t with respect to the direction (what a
    /// small change of `d` along the sphere moves them by): `locate8` on one lane.
    pub fn locate(self, d: Vec3) -> (ChartPoint, [Vec3; 2]) {
        let (at, [ds, dt]) = self.locate8(&V3::splat(d));
        let point = ChartPoint { image: at.image[0] as usize, s: at.s.as_array_ref()[0], t: at.t.as_array_ref()[0] };
        (point, [ds.lane(0), dt.lane(0)])
    }

    /// Where eight unit directions lie, and the gradients of s and t.
    #[inline]
    pub fn locate8(self, d: &V3) -> (ChartPoints8, [V3; 2]) {
        let (one, half) = (F8::ONE, F8::splat(0.5));
        match self {
            Layout::LatLong => {
                // Away from the poles by a hair: s is undefined on them.
                let ring = (d.x * d.x + d.z * d.z).max(F8::splat(1e-12));
                let s = half + atan2(d.x, -d.z) * F8::splat(0.5 / PI);
                let t = half + asin(d.y.max(-one).min(one)) * F8::splat(1.0 / PI);
                let k = F8::splat(0.5 / PI) / ring;
                let ds = V3 { x: -d.z * k, y: F8::ZERO, z: d.x * k };
                let dt = V3 { x: F8::ZERO, y: F8::splat(1.0 / PI) / ring.sqrt(), z: F8::ZERO };
                (ChartPoints8 { image: [0; LANES], s: s.min(one), t }, [ds, dt])
            }
            Layout::Cube => {
                let face = Face::of8(d);
                let (mut ma, mut sc, mut up) = (V3::ZERO, V3::ZERO, V3::ZERO);
                for f in Face::ALL {
                    let this = face.cmp_eq(F8::splat(f as usize as f32));
                    let (m, s, u) = f.axes();
                    ma = V3::select(this, V3::splat(m), ma);
                    sc = V3::select(this, V3::splat(s), sc);
                    up = V3::select(this, V3::splat(u), up);
                }
                let m = ma.dot(*d);
                let inv = one / m;
                let (a, b) = (sc.dot(*d) * inv, up.dot(*d) * inv);
                let image = face.to_array().map(|f| f as u8);
                let k = half * inv;
                (
                    ChartPoints8 { image, s: half * (a + one), t: half * (b + one) },
                    [(sc - ma * a) * k, (up - ma * b) * k],
                )
            }
            Layout::Sphere => {
                let w = V3 { x: d.x, y: d.y, z: d.z + one };
                let m = F8::splat(2.0) * w.length().max(F8::splat(1e-6));
                let inv = one / m;
                let dm = w * (F8::splat(4.0) * inv);
                let (sx, sy) = (d.x * inv, d.y * inv);
                let ds = (V3::splat(Vec3::X) - dm * sx) * inv;
                let dt = (V3::splat(Vec3::Y) - dm * sy) * inv;
                (ChartPoints8 { image: [0; LANES], s: sx + half, t: sy + half }, [ds, dt])
            }
            Layout::Paraboloid => {
                // The back half is the front one of the direction turned half a turn about +Y.
                let back = d.z.cmp_lt(F8::ZERO);
                let mirror = back.blend(-one, one);
                let (x, z) = (mirror * d.x, mirror * d.z);
                let q = (one + z).max(F8::splat(1e-6));
                let k = half / q;
                let image = back.to_array().map(|b| u8::from(b.to_bits() != 0));
                let ds = V3 { x: mirror * k, y: F8::ZERO, z: -mirror * x * k / q };
                let dt = V3 { x: F8::ZERO, y: k, z: -mirror * d.y * k / q };
                (ChartPoints8 { image, s: x * k + half, t: d.y * k + half }, [ds, dt])
            }
        }
    }

    /// The unit direction at (s, t) of image `image`; `None` outside the sphere map's or a paraboloid's disc,
    /// and for an image the layout does not have.
    pub fn direction(self, image: usize, s: f32, t: f32) -> Option<Vec3> {
        match self {
            Layout::LatLong => {
                let (phi, polar) = ((s - 0.5) * 2.0 * PI, (1.0 - t) * PI);
                Some(Vec3::new(polar.sin() * phi.sin(), polar.cos(), -polar.sin() * phi.cos()))
            }
            Layout::Cube => {
                let (ma, sc, up) = Face::ALL.get(image)?.axes();
                Some((ma + (2.0 * s - 1.0) * sc + (2.0 * t - 1.0) * up).normalize())
            }
            Layout::Sphere => {
                let (x, y) = (2.0 * s - 1.0, 2.0 * t - 1.0);
                let r2 = x * x + y * y;
                // The ball's normal, and the view ray -Z reflected about it.
                (r2 <= 1.0).then(|| {
                    let nz = (1.0 - r2).sqrt();
                    Vec3::new(2.0 * nz * x, 2.0 * nz * y, 2.0 * nz * nz - 1.0)
                })
            }
            Layout::Paraboloid => {
                let (x, y) = (2.0 * s - 1.0, 2.0 * t - 1.0);
                let r2 = x * x + y * y;
                let mirror = if image == 0 { 1.0 } else { -1.0 };
                (r2 <= 1.0).then(|| Vec3::new(mirror * 2.0 * x, 2.0 * y, mirror * (1.0 - r2)) / (1.0 + r2))
            }
        }
    }
}

/// Eight points of a layout: each one's image and (s, t) on it.
#[derive(Clone, Copy, Debug)]
pub struct ChartPoints8 {
    pub image: [u8; LANES],
    pub s: F8,
    pub t: F8,
}

/// A point of a layout: one of its images and (s, t) on it, t up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChartPoint {
    pub image: usize,
    pub s: f32,
    pub t: f32,
}

/// A cube face, in OpenGL's order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Face {
    PosX,
    NegX,
    PosY,
    NegY,
    PosZ,
    NegZ,
}

impl Face {
    pub const ALL: [Face; 6] = [Face::PosX, Face::NegX, Face::PosY, Face::NegY, Face::PosZ, Face::NegZ];

    /// The face each of eight directions points into, as its index in `ALL`: the largest component picks
    /// the axis (ties go to x, then y), its sign the side.
    #[inline]
    pub fn of8(d: &V3) -> F8 {
        let a = V3 { x: d.x.abs(), y: d.y.abs(), z: d.z.abs() };
        let (along_x, along_y) = (a.x.cmp_ge(a.y) & a.x.cmp_ge(a.z), a.y.cmp_ge(a.z));
        let axis = along_x.blend(F8::ZERO, along_y.blend(F8::ONE, F8::splat(2.0)));
        let component = along_x.blend(d.x, along_y.blend(d.y, d.z));
        axis + axis + component.cmp_lt(F8::ZERO).blend(F8::ONE, F8::ZERO)
    }

    /// The face's outward axis, and the directions its s and t grow along (t up the picture: OpenGL's tc
    /// runs down it).
    #[inline]
    pub fn axes(self) -> (Vec3, Vec3, Vec3) {
        match self {
            Face::PosX => (Vec3::X, -Vec3::Z, Vec3::Y),
            Face::NegX => (-Vec3::X, Vec3::Z, Vec3::Y),
            Face::PosY => (Vec3::Y, Vec3::X, -Vec3::Z),
            Face::NegY => (-Vec3::Y, Vec3::X, Vec3::Z),
            Face::PosZ => (Vec3::Z, Vec3::X, Vec3::Y),
            Face::NegZ => (-Vec3::Z, -Vec3::X, Vec3::Y),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn directions() -> Vec<Vec3> {
        let mut out = Vec::new();
        for i in 0..40 {
            for j in 1..20 {
                let (phi, polar) = (i as f32 * 0.157 + 0.01, j as f32 * PI / 20.0);
                out.push(Vec3::new(polar.sin() * phi.cos(), polar.cos(), polar.sin() * phi.sin()));
            }
        }
        out
    }

    /// The six axis directions land in the centres of their cube faces.
    #[test]
    fn axes_land_in_the_centres_of_their_faces() {
        let axes = [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z];
        for (k, &d) in axes.iter().enumerate() {
            let (p, _) = Layout::Cube.locate(d);
            assert_eq!(p, ChartPoint { image: k, s: 0.5, t: 0.5 }, "{d}");
        }
    }

    /// OpenGL's table: on face +X, s grows towards -Z and the picture's rows run towards -Y.
    #[test]
    fn cube_faces_follow_opengl() {
        let (p, _) = Layout::Cube.locate(Vec3::new(1.0, 0.5, -0.5).normalize());
        assert_eq!(p.image, 0);
        assert!((p.s - 0.75).abs() < 1e-6 && (p.t - 0.75).abs() < 1e-6, "{p:?}");
        let (p, _) = Layout::Cube.locate(Vec3::new(0.5, 1.0, 0.5).normalize());
        // +Y: sc = x, tc = z (rows run towards +Z, so t falls with z).
        assert_eq!(p.image, 2);
        assert!((p.s - 0.75).abs() < 1e-6 && (p.t - 0.25).abs() < 1e-6, "{p:?}");
    }

    /// Direction -> (image, s, t) -> direction is the identity for every layout, and the gradients are
    /// the derivatives of (s, t).
    #[test]
    fn every_layout_round_trips_with_its_gradients() {
        for (name, layout) in Layout::ALL {
            for d in directions() {
                let (p, [ds, dt]) = layout.locate(d);
                let back = layout.direction(p.image, p.s, p.t).expect("inside the chart");
                assert!(back.distance(d) < 2e-5, "{name}: {d} -> {p:?} -> {back}");
                // Along two tangent directions, against central differences on the sphere.
                let tangent = d.any_orthonormal_vector();
                for e in [tangent, d.cross(tangent)] {
                    let h = 1e-3;
                    let at = |x: f32| layout.locate((d + x * e).normalize()).0;
                    let (a, b) = (at(h), at(-h));
                    if a.image != p.image || b.image != p.image || (a.s - b.s).abs() > 0.5 {
                        continue;
                    }
                    let (fs, ft) = ((a.s - b.s) / (2.0 * h), (a.t - b.t) / (2.0 * h));
                    let scale = 1.0 + fs.abs().max(ft.abs());
                    assert!((ds.dot(e) - fs).abs() < 2e-2 * scale, "{name} ds at {d}: {} vs {fs}", ds.dot(e));
                    assert!((dt.dot(e) - ft).abs() < 2e-2 * scale, "{name} dt at {d}: {} vs {ft}", dt.dot(e));
                }
            }
        }
    }

    /// The sphere map's centre is +Z (the view ray reflected straight back) and its rim -Z; the
    /// paraboloids' halves meet at +X side by side.
    #[test]
    fn sphere_and_paraboloid_conventions() {
        assert_eq!(Layout::Sphere.locate(Vec3::Z).0, ChartPoint { image: 0, s: 0.5, t: 0.5 });
        assert!(Layout::Sphere.direction(0, 1.0, 0.5).unwrap().distance(-Vec3::Z) < 1e-6);
        let front = Layout::Paraboloid.direction(0, 1.0, 0.5).unwrap();
        let back = Layout::Paraboloid.direction(1, 0.0, 0.5).unwrap();
        assert!(front.distance(Vec3::X) < 1e-6 && back.distance(Vec3::X) < 1e-6);
        assert_eq!(Layout::Sphere.direction(0, 0.0, 0.0), None);
        // The latlong image's centre looks down -Z and its top row up.
        assert!(Layout::LatLong.direction(0, 0.5, 0.5).unwrap().distance(-Vec3::Z) < 1e-6);
        assert!(Layout::LatLong.direction(0, 0.3, 1.0).unwrap().distance(Vec3::Y) < 1e-6);
        assert!(Layout::LatLong.direction(0, 0.75, 0.5).unwrap().distance(Vec3::X) < 1e-6);
    }
}
