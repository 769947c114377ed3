//! Shading of one sample: the exact surface frame at the sample's (u,v), Blinn's perturbation,
//! the colour texture through its footprint, and Blinn-Phong lighting from several lights.

pub mod light;
pub mod material;

pub use light::{Light, Phong};
pub use material::{Bump, BumpFilter, BumpSource, Material};

use crate::bump::blinn::perturbed_normal;
use crate::bump::Perturbation;
use crate::geometry::{Surface, SurfaceFrame};
use crate::procedural::solid::solid_point;
use crate::texture::Footprint;
use glam::{Affine3A, Mat3, Vec2, Vec3};

/// One parametric surface placed in the world with its material.
pub struct SurfaceInstance {
    pub surface: Surface,
    pub object_to_world: Affine3A,
    pub object_to_camera: Affine3A,
    pub normal_matrix: Mat3,
    pub material: usize,
    /// The object's index in the scene.
    pub object: u32,
    /// Open surfaces are lit from whichever side faces the eye; closed ones have their back faces culled.
    pub two_sided: bool,
}

/// What the shader needs besides the surface: the eye, the lights, the materials and switches.
pub struct ShadeContext<'a> {
    pub eye: Vec3,
    /// For orthographic views, the direction towards the eye (the same for every pixel).
    pub ortho_to_eye: Option<Vec3>,
    pub lights: &'a [Light],
    pub materials: &'a [Material],
    pub bump_enabled: bool,
    /// Replaces every bump's own filter when set (`--bump-filter`).
    pub bump_filter: Option<BumpFilter>,
}

/// The result of shading one sample, with the data of the AOVs.
#[derive(Clone, Copy, Debug, Default)]
pub struct ShadedSample {
    /// Linear RGB.
    pub color: Vec3,
    /// The unit shading normal N' in world space, facing the eye for two-sided surfaces.
    pub normal: Vec3,
    /// Distance from the eye (along the view axis for orthographic views: from the camera plane).
    pub depth: f32,
}

impl ShadeContext<'_> {
    /// Shades the surface point at `uv` (whose frame is `frame` and whose screen derivatives are `footprint`).
    #[inline]
    pub fn shade(&self, inst: &SurfaceInstance, uv: Vec2, frame: &SurfaceFrame, footprint: &Footprint) -> ShadedSample {
        let material = &self.materials[inst.material];
        let n_geo = frame.pu.cross(frame.pv);
        let n_obj = match (&material.bump, self.bump_enabled) {
            (Some(bump), true) => perturbed_normal(
                frame,
                bump.perturbation(uv, frame, footprint, self.bump_filter.unwrap_or(bump.filter)),
                bump.formula,
            ),
            _ => n_geo,
        };
        let position = inst.object_to_world.transform_point3(frame.p);
        let to_eye_vec = self.ortho_to_eye.map_or(self.eye - position, |d| d);
        let depth = match self.ortho_to_eye {
            Some(d) => (self.eye - position).dot(d),
            None => to_eye_vec.length(),
        };
        let v = to_eye_vec.normalize_or_zero();
        let mut n = (inst.normal_matrix * n_obj).normalize_or_zero();
        if inst.two_sided && (inst.normal_matrix * n_geo).dot(v) < 0.0 {
            n = -n;
        }
        let solid = solid_point(frame, footprint);
        let albedo = match &material.texture {
            Some(t) => material.color * t.sample_at(uv, footprint, &solid).truncate(),
            None => material.color,
        };
        let phong = match &material.specular_map {
            // The cutoff of the full specular stays valid for a smaller one.
            Some(m) => {
                let k = m.sample_at(uv, footprint, &solid).truncate().dot(Vec3::splat(1.0 / 3.0)).clamp(0.0, 1.0);
                Phong { specular: material.phong.specular * k, ..material.phong }
            }
            None => material.phong,
        };
        let mut color = Vec3::ZERO;
        for light in self.lights {
            color += light.shade(position, n, v, albedo, &phong);
        }
        ShadedSample { color, normal: n, depth }
    }
}

impl Bump {
    /// F, Fu, Fv at surface parameters `uv` (whose frame is `frame`): a table is replicated `repeat` times
    /// and scaled by `scale`; a procedural pattern is scaled by `scale` and band-limited to the footprint.
    #[inline]
    pub fn perturbation(&self, uv: Vec2, frame: &SurfaceFrame, footprint: &Footprint, filter: BumpFilter) -> Perturbation {
        let table = match &self.source {
            BumpSource::Table(t) => t,
            BumpSource::Procedural(p) => {
                let b = p.bump(self.scale, uv, frame, footprint);
                return Perturbation { f: b.value, fu: b.grad[0], fv: b.grad[1] };
            }
        };
        let st = uv * self.repeat;
        let level = match filter {
            BumpFilter::None => 0.0,
            BumpFilter::Mip => {
                footprint.replicated(self.repeat.x, self.repeat.y).mip_level(table.width(), table.height())
            }
        };
        let b = table.sample(st.x, st.y, self.interp, level);
        Perturbation {
            f: self.scale * b.f,
            fu: self.scale * self.repeat.x * b.fs,
            fv: self.scale * self.repeat.y * b.ft,
        }
    }
}
