//! Shared helpers of the integration tests: an f64 reference camera written from the scene format's
//! definition (not from wrinkle::raster::Camera), the documented object transform in f64, ray
//! intersections, angles, scratch folders and a one-call render of scene text with every AOV.
#![allow(dead_code)]

pub mod gltf;

use glam::{DMat3, DVec3, Vec3};
use std::path::{Path, PathBuf};
use wrinkle::render::Aovs;
use wrinkle::{Frame, RenderOptions, Scene};

pub fn d3(v: Vec3) -> DVec3 {
    v.as_dvec3()
}

/// The angle between two vectors in degrees (robust for tiny angles).
pub fn angle_deg(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b)).to_degrees()
}

/// A camera in f64 from the scene format's definition: right-handed, looking from `eye` at `look_at`,
/// `fov_y` the full vertical field of view (or `height` world units seen vertically), square pixels,
/// pixel (i,j) spanning [i,i+1] x [j,j+1] with row 0 at the top.
pub struct RefCamera {
    pub eye: DVec3,
    pub fwd: DVec3,
    pub right: DVec3,
    pub up: DVec3,
    /// Pixels per unit of x/z (perspective) or per world unit (orthographic).
    pub scale: f64,
    pub width: f64,
    pub height: f64,
    pub ortho: bool,
}

impl RefCamera {
    fn frame(eye: [f64; 3], look_at: [f64; 3], up: [f64; 3]) -> (DVec3, DVec3, DVec3, DVec3) {
        let eye = DVec3::from(eye);
        let fwd = (DVec3::from(look_at) - eye).normalize();
        let right = fwd.cross(DVec3::from(up)).normalize();
        (eye, fwd, right, right.cross(fwd))
    }

    pub fn perspective(eye: [f64; 3], look_at: [f64; 3], up: [f64; 3], fov_y: f64, w: usize, h: usize) -> Self {
        let (eye, fwd, right, up) = Self::frame(eye, look_at, up);
        let scale = 0.5 * h as f64 / (0.5 * fov_y.to_radians()).tan();
        RefCamera { eye, fwd, right, up, scale, width: w as f64, height: h as f64, ortho: false }
    }

    pub fn orthographic(eye: [f64; 3], look_at: [f64; 3], up: [f64; 3], view_height: f64, w: usize, h: usize) -> Self {
        let (eye, fwd, right, up) = Self::frame(eye, look_at, up);
        RefCamera { eye, fwd, right, up, scale: h as f64 / view_height, width: w as f64, height: h as f64, ortho: true }
    }

    /// The ray through a screen position (pixels, y down): origin and unit direction.
    pub fn ray(&self, x: f64, y: f64) -> (DVec3, DVec3) {
        let a = (x - 0.5 * self.width) / self.scale;
        let b = (0.5 * self.height - y) / self.scale;
        if self.ortho {
            (self.eye + a * self.right + b * self.up, self.fwd)
        } else {
            (self.eye, (self.fwd + a * self.right + b * self.up).normalize())
        }
    }

    /// The ray through the centre of pixel (i, j).
    pub fn pixel_ray(&self, i: usize, j: usize) -> (DVec3, DVec3) {
        self.ray(i as f64 + 0.5, j as f64 + 0.5)
    }

    /// Screen position (pixels, y down) of a world point in front of the camera.
    pub fn project(&self, p: DVec3) -> [f64; 2] {
        let d = p - self.eye;
        let (x, y) = (d.dot(self.right), d.dot(self.up));
        let k = if self.ortho { self.scale } else { self.scale / d.dot(self.fwd) };
        [0.5 * self.width + k * x, 0.5 * self.height - k * y]
    }
}

/// The documented object transform (scene format): scale, then rotate about x, then y, then z
/// (degrees), then translate, written out in f64 with explicit rotation matrices.
#[derive(Clone, Copy, Debug)]
pub struct RefTransform {
    pub translate: [f64; 3],
    pub rotate: [f64; 3],
    pub scale: f64,
}

impl RefTransform {
    pub const IDENTITY: RefTransform = RefTransform { translate: [0.0; 3], rotate: [0.0; 3], scale: 1.0 };

    pub fn rotation(&self) -> DMat3 {
        let [a, b, c] = self.rotate.map(f64::to_radians);
        let rx = DMat3::from_cols(DVec3::X, DVec3::new(0.0, a.cos(), a.sin()), DVec3::new(0.0, -a.sin(), a.cos()));
        let ry = DMat3::from_cols(DVec3::new(b.cos(), 0.0, -b.sin()), DVec3::Y, DVec3::new(b.sin(), 0.0, b.cos()));
        let rz = DMat3::from_cols(DVec3::new(c.cos(), c.sin(), 0.0), DVec3::new(-c.sin(), c.cos(), 0.0), DVec3::Z);
        rz * ry * rx
    }

    pub fn point(&self, p: DVec3) -> DVec3 {
        self.rotation() * (self.scale * p) + DVec3::from(self.translate)
    }

    /// A direction (or normal: the scale is uniform) carried to world space.
    pub fn direction(&self, v: DVec3) -> DVec3 {
        self.rotation() * v
    }

    pub fn toml(&self) -> String {
        format!("{{ translate = {}, rotate = {}, scale = {:?} }}", arr(self.translate), arr(self.rotate), self.scale)
    }
}

/// A TOML array of three floats.
pub fn arr(v: [f64; 3]) -> String {
    format!("[{:?}, {:?}, {:?}]", v[0], v[1], v[2])
}

/// The sphere of radius r as documented (poles on y, u = longitude from +x with 0.25 at -z, v = latitude
/// from the south pole 0 to the north pole 1), in f64.
pub fn sphere_point(r: f64, u: f64, v: f64) -> DVec3 {
    let (phi, theta) = (std::f64::consts::TAU * u, std::f64::consts::PI * (v - 0.5));
    r * DVec3::new(theta.cos() * phi.cos(), theta.sin(), -theta.cos() * phi.sin())
}

/// The ray parameter where the ray meets the plane through `p0` with normal `n`, if it does (t > 0).
pub fn ray_plane(o: DVec3, d: DVec3, p0: DVec3, n: DVec3) -> Option<f64> {
    let den = d.dot(n);
    if den.abs() < 1e-15 {
        return None;
    }
    let t = (p0 - o).dot(n) / den;
    (t > 0.0).then_some(t)
}

/// The nearest positive ray parameter where the ray (unit direction) meets a sphere.
pub fn ray_sphere(o: DVec3, d: DVec3, centre: DVec3, r: f64) -> Option<f64> {
    let oc = o - centre;
    let b = oc.dot(d);
    let disc = b * b - (oc.length_squared() - r * r);
    if disc < 0.0 {
        return None;
    }
    let s = disc.sqrt();
    [-b - s, -b + s].into_iter().find(|&t| t > 0.0)
}

/// (u, v) of the point x in the plane of the parallelogram p00 + u e1 + v e2 (least squares in the plane).
pub fn parallelogram_uv(x: DVec3, p00: DVec3, e1: DVec3, e2: DVec3) -> (f64, f64) {
    let q = x - p00;
    let (a, b, c) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let (r1, r2) = (q.dot(e1), q.dot(e2));
    let det = a * c - b * b;
    ((r1 * c - r2 * b) / det, (a * r2 - b * r1) / det)
}

/// A fresh folder for the files of one test.
pub fn scratch_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("wrinkle-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("create scratch folder");
    dir
}

/// Renders scene text at `w` x `h` with `spp` samples per pixel and every AOV kept.
pub fn render_all_aovs(scene: &str, base: &Path, w: usize, h: usize, spp: usize) -> Frame {
    let scene = Scene::parse(scene, base).unwrap_or_else(|e| panic!("scene does not parse: {e}\n{scene}"));
    let aovs = Aovs { normal: true, uv: true, depth: true, id: true, primitive: true, alpha: true };
    wrinkle::render(&scene, &RenderOptions { width: w, height: h, spp, aovs, ..Default::default() }).expect("render")
}

/// The `[camera]` and one light of a perspective scene.
pub fn camera_toml(eye: [f64; 3], look_at: [f64; 3], fov_y: f64) -> String {
    format!(
        "[camera]\neye = {}\nlook_at = {}\nup = [0.0, 1.0, 0.0]\nfov_y = {fov_y:?}\nbackground = [0.0, 0.0, 0.0]\n\n\
         [[light]]\ntype = \"directional\"\ndirection = [-0.3, -0.4, -1.0]\n\n",
        arr(eye),
        arr(look_at)
    )
}

/// A running maximum that remembers where it was reached.
#[derive(Debug, Default)]
pub struct MaxErr {
    pub max: f64,
    pub at: String,
    pub count: usize,
}

impl MaxErr {
    pub fn add(&mut self, err: f64, at: impl FnOnce() -> String) {
        self.count += 1;
        // NaN counts as the worst error and sticks.
        if self.max.is_nan() {
            return;
        }
        if err.is_nan() || err > self.max || self.count == 1 {
            self.max = err;
            self.at = at();
        }
    }
}
