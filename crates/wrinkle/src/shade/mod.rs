//! Shading of eight samples: the lookup context of the exact surface frame at each sample's (u,v), the
//! bump map's perturbation, the colour and specular textures through their mappings, and Blinn-Phong
//! lighting from several lights.

pub mod material;
pub mod phong;

pub use material::Material;
pub use phong::Phong;

use crate::bump::blinn::perturbed_normal8;
use crate::geometry::frame_lanes::Frame8;
use crate::geometry::Instance;
use crate::lanes::{CmpLt, F8, LANES, V3};
use crate::light::Light;
use crate::texture::{Filter, FilterOptions, Footprint8, LookupContext8};
use glam::Vec3;

/// What the shader needs besides the surface: the eye, the lights, the materials and switches.
pub struct ShadeContext<'a> {
    pub eye: Vec3,
    /// For orthographic views, the direction towards the eye (the same for every pixel).
    pub ortho_to_eye: Option<Vec3>,
    pub lights: &'a [Light],
    pub materials: &'a [Material],
    pub bump_enabled: bool,
    /// Replaces every bump's own filter when set (`--bump-filter`).
    pub bump_filter: Option<Filter>,
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

/// Eight shaded samples (structure of arrays).
pub struct ShadedPacket {
    pub color: V3,
    pub normal: V3,
    pub depth: F8,
}

impl ShadedPacket {
    pub fn lane(&self, i: usize) -> ShadedSample {
        ShadedSample { color: self.color.lane(i), normal: self.normal.lane(i), depth: self.depth.as_array_ref()[i] }
    }
}

impl ShadeContext<'_> {
    /// Shades eight points of one surface at `uv` (whose frames are `frame` and whose screen derivatives are
    /// `footprint`, on `triangles` of the tessellation). Lookups go through their lane forms; everything
    /// else runs on all lanes at once.
    #[inline]
    pub fn shade8(
        &self,
        inst: &Instance,
        uv: (F8, F8),
        frame: &Frame8,
        footprint: Footprint8,
        triangles: [u32; LANES],
    ) -> ShadedPacket {
        let material = &self.materials[inst.material];
        let ctx = LookupContext8::on_surface(frame.p, frame.pu, frame.pv, uv, footprint, inst.object, triangles);
        let n_geo = ctx.n;
        let n_obj = match (&material.bump, self.bump_enabled) {
            (Some(bump), true) => {
                let filter = match self.bump_filter {
                    Some(filter) => FilterOptions { filter, ..bump.filter },
                    None => bump.filter,
                };
                perturbed_normal8(frame, bump.eval8(&ctx, &filter), bump.formula)
            }
            _ => n_geo,
        };
        let position = V3::transform_point(&inst.object_to_world, frame.p);
        let (to_eye, depth) = match self.ortho_to_eye {
            Some(d) => (V3::splat(d), (V3::splat(self.eye) - position).dot(V3::splat(d))),
            None => {
                let to_eye = V3::splat(self.eye) - position;
                (to_eye, to_eye.length())
            }
        };
        let v = to_eye.normalize_or_zero();
        let mut n = V3::mul_mat3(&inst.normal_matrix, n_obj).normalize_or_zero();
        if inst.two_sided {
            let back = V3::mul_mat3(&inst.normal_matrix, n_geo).dot(v).cmp_lt(F8::ZERO);
            n = V3::select(back, -n, n);
        }
        let albedo = match &material.texture {
            Some(t) => {
                let [r, g, b, _] = t.eval8(&ctx);
                V3::splat(material.color) * V3 { x: r, y: g, z: b }
            }
            None => V3::splat(material.color),
        };
        let phong = &material.phong;
        let mut color = V3::ZERO;
        match &material.specular_map {
            // Each lane has its own specular; the cutoff of the full specular stays valid for a smaller one.
            Some(m) => {
                let [r, g, b, _] = m.eval8(&ctx);
                let k = ((r + g + b) * F8::splat(1.0 / 3.0)).max(F8::ZERO).min(F8::ONE);
                for light in self.lights {
                    color = color + phong.shade8(light, position, n, v, albedo, k);
                }
            }
            None => {
                for light in self.lights {
                    color = color + phong.shade8(light, position, n, v, albedo, F8::ONE);
                }
            }
        }
        ShadedPacket { color, normal: n, depth }
    }
}
