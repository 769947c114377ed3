//! Texture coordinates from the point itself: the course's parameterisations and OpenGL's texgen modes.
//! Every one works in the mapping's own space (the object's, moved by the mapping's placement), where the
//! intermediate surfaces have unit size: the plane z = 0 over [-1, 1]^2, the cylinder of radius 1 around
//! the y axis from y = -1 to 1, the unit sphere, the cube [-1, 1]^3.
//!
//! - `planar`: s = (x + 1) / 2, t = (y + 1) / 2, projected along z.
//! - `cylindrical`: s the angle about y (0 at +x, 0.25 at -z, as the sphere shape's u), t = (y + 1) / 2.
//! - `spherical`: s the longitude (as cylindrical), t the latitude from the south pole (0) to the north (1),
//!   optionally of a part of the sphere only (Rogers): longitude and latitude ranges in degrees.
//! - `box`: the largest component of the normal picks the face, each seen from outside with s to the right
//!   and t up (as the box shape's faces).
//! - two-part (Bier and Sloan): an intermediate surface (S) and how points reach it (O): along the
//!   intermediate surface's normal (ISN; flipped into the half-space of the outward normal unless told not
//!   to), along the object's normal, from the centroid (the mapping's origin), or along the reflected ray.
//! - texgen: `object_linear` and `eye_linear` (s = plane . (x, y, z, 1) in object or eye coordinates, as
//!   glTexGen), `sphere_map` (OpenGL's: the eye-space reflection vector r, m = 2 sqrt(rx^2 + ry^2 +
//!   (rz + 1)^2), s = rx / m + 1/2, t = ry / m + 1/2).
//! - `triangle` and `quad`: the course's triangle and quadrilateral mappings from reference points with
//!   their texture coordinates (polygon.rs).

use super::polygon::{QuadMapping, TriangleMapping};
use glam::{Affine3A, Mat3, Vec2, Vec3, Vec4};
use std::f32::consts::{PI, TAU};

/// An intermediate surface of a two-part mapping.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Surface {
    Plane,
    Cylinder,
    Sphere(SphereRange),
    Box,
}

/// How a point reaches the intermediate surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Projector {
    /// Along the intermediate surface's normal through the point; with `flip`, towards the side the
    /// object's outward normal faces.
    Isn { flip: bool },
    /// Along the object's outward normal.
    Normal,
    /// From the centroid (the mapping space's origin) through the point.
    Centroid,
    /// Along the view ray reflected about the normal.
    Reflected,
}

/// The part of the sphere a spherical mapping covers, in degrees: longitude and latitude (-90 to 90).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphereRange {
    pub longitude: [f32; 2],
    pub latitude: [f32; 2],
}

impl Default for SphereRange {
    fn default() -> Self {
        SphereRange { longitude: [0.0, 360.0], latitude: [-90.0, 90.0] }
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// The surface's own (u, v).
    Uv,
    /// A mesh's second texture coordinate set (glTF's TEXCOORD_1).
    SecondUv,
    Planar,
    Cylindrical,
    Spherical(SphereRange),
    Box,
    TwoPart {
        surface: Surface,
        projector: Projector,
    },
    /// glTexGen's GL_OBJECT_LINEAR: the planes of s and t in object coordinates.
    ObjectLinear {
        s: Vec4,
        t: Vec4,
    },
    /// GL_EYE_LINEAR: the planes in eye (camera) coordinates.
    EyeLinear {
        s: Vec4,
        t: Vec4,
    },
    /// GL_SPHERE_MAP.
    SphereMap,
    /// The linear map of three reference points to their texture coordinates (polygon.rs).
    Triangle(TriangleMapping),
    /// Inverse bilinear interpolation in a quadrilateral with texture coordinates at its corners.
    Quad(QuadMapping),
}

/// What a projection reads of a sample, in mapping space (`eye` and the eye-space values for texgen).
#[derive(Clone, Copy, Debug)]
pub struct Point {
    pub q: Vec3,
    /// The outward unit normal.
    pub n: Vec3,
    /// The unit direction from the eye to the point.
    pub view: Vec3,
    /// The point and unit normal in eye coordinates.
    pub q_eye: Vec3,
    pub n_eye: Vec3,
}

/// The discrete choice a projection makes at a sample (the box face), kept fixed while its derivatives are
/// taken by differences about the sample.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Choice {
    face: usize,
}

impl Projection {
    /// The discrete choices at `at`.
    pub fn choose(&self, at: &Point) -> Choice {
        match *self {
            Projection::Box => Choice { face: box_face(at.n) },
            Projection::TwoPart { surface, projector } => {
                let (dir, _) = direction(surface, projector, at);
                let face = match surface {
                    Surface::Box => box_face(if projector == Projector::Centroid { at.q } else { dir }),
                    _ => 0,
                };
                Choice { face }
            }
            _ => Choice::default(),
        }
    }

    /// (s, t) at `at` with the choices `c` (one period of the texture per unit).
    pub fn coords(&self, at: &Point, c: &Choice) -> Vec2 {
        let q = at.q;
        match *self {
            Projection::Uv | Projection::SecondUv => unreachable!("a uv projection reads the surface's coordinates"),
            Projection::Planar => plane_st(q),
            Projection::Cylindrical => cylinder_st(q),
            Projection::Spherical(range) => sphere_st(q, &range),
            Projection::Box => box_st(q, c.face),
            Projection::TwoPart { surface, projector } => {
                let (dir, origin) = direction(surface, projector, at);
                let hit = meet(surface, origin, dir).unwrap_or(q);
                match surface {
                    Surface::Plane => plane_st(hit),
                    Surface::Cylinder => cylinder_st(hit),
                    Surface::Sphere(range) => sphere_st(hit, &range),
                    Surface::Box => box_st(hit, c.face),
                }
            }
            Projection::ObjectLinear { s, t } => Vec2::new(s.dot(q.extend(1.0)), t.dot(q.extend(1.0))),
            Projection::EyeLinear { s, t } => Vec2::new(s.dot(at.q_eye.extend(1.0)), t.dot(at.q_eye.extend(1.0))),
            Projection::Triangle(m) => m.uv(q),
            Projection::Quad(m) => m.uv(q),
            Projection::SphereMap => {
                let u = at.q_eye.normalize_or_zero();
                let r = u - 2.0 * at.n_eye * at.n_eye.dot(u);
                let m = 2.0 * (r.x * r.x + r.y * r.y + (r.z + 1.0) * (r.z + 1.0)).sqrt();
                if m == 0.0 {
                    return Vec2::splat(0.5);
                }
                Vec2::new(r.x / m + 0.5, r.y / m + 0.5)
            }
        }
    }

    /// Whether the coordinates follow the normal continuously (not only through a discrete choice), so
    /// that their footprint needs the normal's change across the pixel.
    pub fn reads_normal(&self) -> bool {
        matches!(
            self,
            Projection::SphereMap | Projection::TwoPart { projector: Projector::Normal | Projector::Reflected, .. }
        )
    }

    /// Whether s wraps around (the angle of cylinders and spheres): differences of s are taken modulo one.
    pub fn wraps(&self) -> bool {
        matches!(
            self,
            Projection::Cylindrical
                | Projection::Spherical(_)
                | Projection::TwoPart { surface: Surface::Cylinder | Surface::Sphere(_), .. }
        )
    }
}

/// The point in mapping space from object space (`to_mapping`), with the eye-space values texgen needs.
pub fn point(p: Vec3, n: Vec3, eye: Vec3, to_mapping: &Affine3A, object_to_eye: &Affine3A) -> Point {
    let q = to_mapping.transform_point3(p);
    Point {
        q,
        n: normal_through(to_mapping, n),
        view: (q - to_mapping.transform_point3(eye)).normalize_or_zero(),
        q_eye: object_to_eye.transform_point3(p),
        n_eye: normal_through(object_to_eye, n),
    }
}

/// The unit normal `n` carried by `m` (its inverse transpose).
pub fn normal_through(m: &Affine3A, n: Vec3) -> Vec3 {
    (Mat3::from(m.matrix3).inverse().transpose() * n).normalize_or_zero()
}

fn plane_st(q: Vec3) -> Vec2 {
    Vec2::new(0.5 * (q.x + 1.0), 0.5 * (q.y + 1.0))
}

/// The longitude in turns, 0 at +x and 0.25 at -z, in [0, 1).
fn longitude(q: Vec3) -> f32 {
    let a = (-q.z).atan2(q.x) / TAU;
    if a < 0.0 {
        a + 1.0
    } else {
        a
    }
}

fn cylinder_st(q: Vec3) -> Vec2 {
    Vec2::new(longitude(q), 0.5 * (q.y + 1.0))
}

fn sphere_st(q: Vec3, range: &SphereRange) -> Vec2 {
    let lon = longitude(q) * 360.0;
    let lat = (q.y / q.length()).clamp(-1.0, 1.0).asin() * (180.0 / PI);
    let [l0, l1] = range.longitude;
    let [b0, b1] = range.latitude;
    Vec2::new((lon - l0) / (l1 - l0), (lat - b0) / (b1 - b0))
}

/// +x, -x, +y, -y, +z, -z by the largest component of `d`.
fn box_face(d: Vec3) -> usize {
    let a = d.abs();
    let axis = if a.x >= a.y && a.x >= a.z {
        0
    } else if a.y >= a.z {
        1
    } else {
        2
    };
    2 * axis + usize::from(d[axis] < 0.0)
}

/// A face of the cube seen from outside, s to the right and t up (the box shape's faces).
fn box_st(q: Vec3, face: usize) -> Vec2 {
    let (s, t) = match face {
        0 => (-q.z, q.y),
        1 => (q.z, q.y),
        2 => (q.x, -q.z),
        3 => (q.x, q.z),
        4 => (q.x, q.y),
        _ => (-q.x, q.y),
    };
    Vec2::new(0.5 * (s + 1.0), 0.5 * (t + 1.0))
}

/// The outward normal of the intermediate surface at (or towards) `q`.
fn surface_normal(surface: Surface, q: Vec3) -> Vec3 {
    match surface {
        Surface::Plane => Vec3::Z,
        Surface::Cylinder => Vec3::new(q.x, 0.0, q.z).normalize_or_zero(),
        Surface::Sphere(_) => q.normalize_or_zero(),
        Surface::Box => {
            let f = box_face(q);
            let mut n = Vec3::ZERO;
            n[f / 2] = if f.is_multiple_of(2) { 1.0 } else { -1.0 };
            n
        }
    }
}

/// The line a point follows to the intermediate surface: its direction and its origin.
fn direction(surface: Surface, projector: Projector, at: &Point) -> (Vec3, Vec3) {
    match projector {
        Projector::Isn { flip } => {
            let d = surface_normal(surface, at.q);
            if flip && d.dot(at.n) < 0.0 {
                (-d, at.q)
            } else {
                (d, at.q)
            }
        }
        Projector::Normal => (at.n, at.q),
        Projector::Centroid => (at.q.normalize_or_zero(), Vec3::ZERO),
        Projector::Reflected => (at.view - 2.0 * at.n * at.n.dot(at.view), at.q),
    }
}

/// Where the line from `o` along `d` meets the intermediate surface: the nearest meeting ahead, else the
/// nearest behind; `None` where it never does.
fn meet(surface: Surface, o: Vec3, d: Vec3) -> Option<Vec3> {
    let ts: Vec<f32> = match surface {
        Surface::Plane => (d.z != 0.0).then(|| -o.z / d.z).into_iter().collect(),
        Surface::Cylinder => {
            quadratic(d.x * d.x + d.z * d.z, 2.0 * (o.x * d.x + o.z * d.z), o.x * o.x + o.z * o.z - 1.0)
        }
        Surface::Sphere(_) => quadratic(d.dot(d), 2.0 * o.dot(d), o.dot(o) - 1.0),
        Surface::Box => (0..3)
            .filter(|&k| d[k] != 0.0)
            .flat_map(|k| [(1.0 - o[k]) / d[k], (-1.0 - o[k]) / d[k]])
            .filter(|&t| (o + t * d).abs().max_element() <= 1.0 + 1e-5)
            .collect(),
    };
    let ahead = ts.iter().copied().filter(|&t| t >= 0.0).reduce(f32::min);
    let behind = ts.iter().copied().filter(|&t| t < 0.0).reduce(f32::max);
    ahead.or(behind).map(|t| o + t * d)
}

/// The real roots of a t^2 + b t + c.
fn quadratic(a: f32, b: f32, c: f32) -> Vec<f32> {
    if a == 0.0 {
        return Vec::new();
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return Vec::new();
    }
    let r = disc.sqrt();
    vec![(-b - r) / (2.0 * a), (-b + r) / (2.0 * a)]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(q: Vec3, n: Vec3) -> Point {
        Point { q, n: n.normalize(), view: -Vec3::Z, q_eye: q, n_eye: n.normalize() }
    }

    fn st(p: &Projection, q: Vec3, n: Vec3) -> Vec2 {
        let a = at(q, n);
        p.coords(&a, &p.choose(&a))
    }

    fn close(a: Vec2, b: Vec2) -> bool {
        (a - b).length() < 1e-5
    }

    #[test]
    fn cylinder_and_sphere_at_known_points() {
        let c = Projection::Cylindrical;
        // The angle about y: 0 at +x, a quarter at -z, a half at -x, three quarters at +z.
        for (q, s) in [(Vec3::X, 0.0), (-Vec3::Z, 0.25), (-Vec3::X, 0.5), (Vec3::Z, 0.75)] {
            assert!(close(st(&c, q * 2.0 + Vec3::Y * 0.5, q), Vec2::new(s, 0.75)), "{q}");
        }
        let s = Projection::Spherical(SphereRange::default());
        assert!(close(st(&s, Vec3::Y * 3.0, Vec3::Y), Vec2::new(0.0, 1.0)), "north pole");
        assert!((st(&s, -Vec3::Y, -Vec3::Y).y).abs() < 1e-6, "south pole");
        assert!(close(st(&s, -Vec3::Z, -Vec3::Z), Vec2::new(0.25, 0.5)), "equator");
        // Just either side of the seam at +x.
        let a = st(&s, Vec3::new(1.0, 0.0, -1e-3), Vec3::X).x;
        let b = st(&s, Vec3::new(1.0, 0.0, 1e-3), Vec3::X).x;
        assert!(a < 1e-3 && b > 1.0 - 1e-3, "{a} {b}");
        // Rogers' part of a sphere: longitude 0..90, latitude 0..45 map onto the whole square.
        let part = Projection::Spherical(SphereRange { longitude: [0.0, 90.0], latitude: [0.0, 45.0] });
        let q = Vec3::new(45f32.to_radians().cos(), 0.0, -45f32.to_radians().sin());
        assert!(close(st(&part, q, q), Vec2::new(0.5, 0.0)));
        let top = Vec3::new(0.0, 45f32.to_radians().sin(), -45f32.to_radians().cos());
        assert!(close(st(&part, top, top), Vec2::new(1.0, 1.0)));
    }

    #[test]
    fn box_face_follows_the_largest_normal_component() {
        let b = Projection::Box;
        // The point is the same; the normal picks the face.
        let q = Vec3::new(0.5, 0.2, 0.9);
        assert!(close(st(&b, q, Vec3::Z), Vec2::new(0.75, 0.6)));
        assert!(close(st(&b, q, Vec3::X), Vec2::new(0.05, 0.6)));
        assert!(close(st(&b, q, Vec3::new(0.1, 0.9, 0.3)), Vec2::new(0.75, 0.05)));
        assert!(close(st(&b, q, -Vec3::Z), Vec2::new(0.25, 0.6)));
        assert!(close(st(&b, q, -Vec3::Y), Vec2::new(0.75, 0.95)));
    }

    #[test]
    fn two_part_projectors() {
        let cyl = |projector| Projection::TwoPart { surface: Surface::Cylinder, projector };
        let q = Vec3::new(0.5, 0.3, 0.0);
        // ISN: straight out from the axis, at the point's own angle and height.
        assert!(close(st(&cyl(Projector::Isn { flip: true }), q, Vec3::X), Vec2::new(0.0, 0.65)));
        // A normal facing the axis flips the ISN to the far side of the cylinder.
        assert!(close(st(&cyl(Projector::Isn { flip: true }), q, -Vec3::X), Vec2::new(0.5, 0.65)));
        assert!(close(st(&cyl(Projector::Isn { flip: false }), q, -Vec3::X), Vec2::new(0.0, 0.65)));
        // The object's normal, tilted up 45 degrees: it reaches the cylinder half a unit higher.
        let n = Vec3::new(1.0, 1.0, 0.0);
        assert!(close(st(&cyl(Projector::Normal), q, n), Vec2::new(0.0, 0.9)));
        // From the centroid through the point: the height scales with the distance out.
        assert!(close(st(&cyl(Projector::Centroid), q, Vec3::X), Vec2::new(0.0, 0.8)));
        // The view along -z reflected by a normal at 45 degrees between +x and +z goes out along +x.
        let n = Vec3::new(1.0, 0.0, 1.0);
        assert!(close(st(&cyl(Projector::Reflected), q, n), Vec2::new(0.0, 0.65)));
        // Sphere / centroid is the direction of the point; plane / ISN the orthographic projection.
        let sphere =
            Projection::TwoPart { surface: Surface::Sphere(SphereRange::default()), projector: Projector::Centroid };
        assert!(close(st(&sphere, -Vec3::Z * 0.3, Vec3::Z), Vec2::new(0.25, 0.5)));
        let plane = Projection::TwoPart { surface: Surface::Plane, projector: Projector::Isn { flip: true } };
        assert!(close(st(&plane, Vec3::new(0.2, -0.4, 0.7), -Vec3::Z), Vec2::new(0.6, 0.3)));
    }

    /// A sheet z = x^3 crossing the cylinder's axis (the y axis) at x = 0, its normal (-3x^2, 0, 1) always
    /// facing +z: by the flipped ISN its points reach the cylinder on the +z side, continuously; unflipped,
    /// the points either side of the axis reach opposite sides, a jump of half a turn.
    #[test]
    fn flipped_isn_maps_a_sheet_across_the_axis_continuously() {
        let along = |flip: bool| -> Vec<f32> {
            let p = Projection::TwoPart { surface: Surface::Cylinder, projector: Projector::Isn { flip } };
            (-20..=20)
                .filter(|&k| k != 0)
                .map(|k| {
                    let x = k as f32 * 0.02;
                    st(&p, Vec3::new(x, 0.0, x * x * x), Vec3::new(-3.0 * x * x, 0.0, 1.0))
                })
                .map(|st| st.x)
                .collect()
        };
        let step =
            |s: &[f32]| s.windows(2).map(|w| (w[1] - w[0]).abs().min(1.0 - (w[1] - w[0]).abs())).fold(0.0, f32::max);
        assert!(step(&along(true)) < 0.05, "flipped: {:?}", along(true));
        assert!(step(&along(false)) > 0.45, "unflipped: {:?}", along(false));
    }

    #[test]
    fn texgen_follows_opengl() {
        // GL_OBJECT_LINEAR: s = p1 x + p2 y + p3 z + p4.
        let g = Projection::ObjectLinear { s: Vec4::new(1.0, 2.0, 0.0, 0.5), t: Vec4::new(0.0, 0.0, -1.0, 0.0) };
        assert!(close(st(&g, Vec3::new(0.1, 0.2, 0.3), Vec3::Z), Vec2::new(1.0, -0.3)));
        // GL_EYE_LINEAR: the same planes on the eye-space point.
        let e = Projection::EyeLinear { s: Vec4::new(0.0, 1.0, 0.0, 0.0), t: Vec4::new(0.0, 0.0, 1.0, 2.0) };
        let a = Point { q: Vec3::ZERO, n: Vec3::Z, view: -Vec3::Z, q_eye: Vec3::new(7.0, 0.25, -1.5), n_eye: Vec3::Z };
        assert!(close(e.coords(&a, &Choice::default()), Vec2::new(0.25, 0.5)));
        // GL_SPHERE_MAP: a normal facing the eye reflects the view straight back: the centre of the map.
        let sm = Projection::SphereMap;
        let a = Point { q: Vec3::ZERO, n: Vec3::Z, view: -Vec3::Z, q_eye: Vec3::new(0.0, 0.0, -5.0), n_eye: Vec3::Z };
        assert!(close(sm.coords(&a, &Choice::default()), Vec2::splat(0.5)));
        // A normal 22.5 degrees right reflects the view 45 degrees right: r = (sin 45, 0, cos 45).
        let n = Vec3::new(22.5f32.to_radians().sin(), 0.0, 22.5f32.to_radians().cos());
        let a = Point { n_eye: n, ..a };
        let r = Vec3::new(45f32.to_radians().sin(), 0.0, 45f32.to_radians().cos());
        let m = 2.0 * (r.x * r.x + (r.z + 1.0) * (r.z + 1.0)).sqrt();
        assert!(close(sm.coords(&a, &Choice::default()), Vec2::new(r.x / m + 0.5, 0.5)));
    }
}
