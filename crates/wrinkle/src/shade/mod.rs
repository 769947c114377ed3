//! Shading of one sample: the exact surface frame at the sample's (u,v), Blinn's perturbation,
//! the colour texture through its footprint, and Blinn-Phong lighting from several lights.

pub mod light;
pub mod material;

pub use light::{Light, Phong};
pub use material::{Bump, BumpFilter, Material};

use crate::bump::blinn::{blinn_d8, perturbed_normal};
use crate::bump::{BumpFormula, Perturbation};
use crate::geometry::frame_lanes::Frame8;
use crate::geometry::Surface;
use crate::lanes::{CmpLt, F8, LANES, V3};
use crate::texture::{FilterOptions, Footprint};
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
    /// `footprints`). Table and texture lookups run lane by lane; everything else on all lanes at once.
    #[inline]
    pub fn shade8(
        &self,
        inst: &SurfaceInstance,
        uv: (F8, F8),
        frame: &Frame8,
        footprints: &[Footprint; LANES],
    ) -> ShadedPacket {
        let material = &self.materials[inst.material];
        let (us, vs) = (uv.0.as_array_ref(), uv.1.as_array_ref());
        let uv_lane = |i: usize| Vec2::new(us[i], vs[i]);
        let n_geo = frame.pu.cross(frame.pv);
        let n_obj = match (&material.bump, self.bump_enabled) {
            (Some(bump), true) => {
                let filter = self.bump_filter.unwrap_or(bump.filter);
                let (f, fu, fv) = match filter {
                    // One table level for every lane: the lookups run on all lanes at once.
                    BumpFilter::None => bump.perturbation8(uv),
                    _ => {
                        let b: [Perturbation; LANES] =
                            std::array::from_fn(|i| bump.perturbation(uv_lane(i), &footprints[i], filter));
                        (F8::new(b.map(|b| b.f)), F8::new(b.map(|b| b.fu)), F8::new(b.map(|b| b.fv)))
                    }
                };
                match bump.formula {
                    BumpFormula::Blinn => n_geo + blinn_d8(n_geo, frame.pu, frame.pv, fu, fv),
                    formula => V3::from_lanes(&std::array::from_fn(|i| {
                        let lane = |x: F8| x.as_array_ref()[i];
                        perturbed_normal(&frame.lane(i), Perturbation { f: lane(f), fu: lane(fu), fv: lane(fv) }, formula)
                    })),
                }
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
                let [r, g, b, _] = t.sample8(uv.0, uv.1, footprints);
                V3::splat(material.color) * V3 { x: r, y: g, z: b }
            }
            None => V3::splat(material.color),
        };
        let mut color = V3::ZERO;
        for light in self.lights {
            color = color + light.shade8(position, n, v, albedo, &material.phong);
        }
        ShadedPacket { color, normal: n, depth }
    }
}

impl Bump {
    /// F, Fu, Fv at eight (u,v) from the full-resolution table (no footprint filtering).
    #[inline]
    pub fn perturbation8(&self, uv: (F8, F8)) -> (F8, F8, F8) {
        let (ru, rv) = (F8::splat(self.repeat.x), F8::splat(self.repeat.y));
        let [f, fs, ft] = self.table.sample8(uv.0 * ru, uv.1 * rv, self.interp, 0);
        let scale = F8::splat(self.scale);
        (scale * f, scale * ru * fs, scale * rv * ft)
    }

    /// F, Fu, Fv at surface parameters `uv`: the table is replicated `repeat` times and scaled by `scale`.
    #[inline]
    pub fn perturbation(&self, uv: Vec2, footprint: &Footprint, filter: BumpFilter) -> Perturbation {
        let st = uv * self.repeat;
        let level = match filter {
            BumpFilter::None | BumpFilter::Filtered(_) => 0.0,
            BumpFilter::Mip => {
                footprint.replicated(self.repeat.x, self.repeat.y).mip_level(self.table.width(), self.table.height())
            }
        };
        let b = match filter {
            BumpFilter::Filtered(f) => {
                let fp = footprint.replicated(self.repeat.x, self.repeat.y);
                self.table.filtered(st.x, st.y, &fp, &FilterOptions { filter: f, ..FilterOptions::default() })
            }
            _ => self.table.sample(st.x, st.y, self.interp, level),
        };
        Perturbation {
            f: self.scale * b.f,
            fu: self.scale * self.repeat.x * b.fs,
            fv: self.scale * self.repeat.y * b.ft,
        }
    }
}
