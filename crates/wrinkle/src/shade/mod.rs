//! Shading of one sample: the exact surface frame at the sample's (u,v), Blinn's perturbation,
//! the colour texture through its footprint, and Blinn-Phong lighting from several lights.

pub mod light;
pub mod material;

pub use light::{Light, Phong};
pub use material::{Bump, BumpFilter, BumpSource, Material};

use crate::bump::blinn::{blinn_d8, perturbed_normal};
use crate::bump::{BumpFormula, BumpTable, Perturbation};
use crate::geometry::frame_lanes::Frame8;
use crate::geometry::{Surface, SurfaceFrame};
use crate::lanes::{CmpLt, F8, LANES, V3};
use crate::texture::{FilterOptions, Footprint, SolidPoint};
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
                let (f, fu, fv) = match (&bump.source, filter) {
                    // One table level for every lane: the lookups run on all lanes at once.
                    (BumpSource::Table(table), BumpFilter::None) => bump.perturbation8(table, uv),
                    _ => {
                        let b: [Perturbation; LANES] = std::array::from_fn(|i| {
                            bump.perturbation(uv_lane(i), &frame.lane(i), &footprints[i], filter)
                        });
                        (F8::new(b.map(|b| b.f)), F8::new(b.map(|b| b.fu)), F8::new(b.map(|b| b.fv)))
                    }
                };
                match bump.formula {
                    BumpFormula::Blinn => n_geo + blinn_d8(n_geo, frame.pu, frame.pv, fu, fv),
                    formula => V3::from_lanes(&std::array::from_fn(|i| {
                        let lane = |x: F8| x.as_array_ref()[i];
                        perturbed_normal(
                            &frame.lane(i),
                            Perturbation { f: lane(f), fu: lane(fu), fv: lane(fv) },
                            formula,
                        )
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
        let solid = solid_points(frame, footprints);
        let albedo = match &material.texture {
            Some(t) => {
                let [r, g, b, _] = t.sample8(uv.0, uv.1, footprints, &solid);
                V3::splat(material.color) * V3 { x: r, y: g, z: b }
            }
            None => V3::splat(material.color),
        };
        let mut color = V3::ZERO;
        match &material.specular_map {
            // Each lane has its own specular; the cutoff of the full specular stays valid for a smaller one.
            Some(m) => {
                let [r, g, b, _] = m.sample8(uv.0, uv.1, footprints, &solid);
                let k = ((r + g + b) * F8::splat(1.0 / 3.0)).max(F8::ZERO).min(F8::ONE);
                for light in self.lights {
                    color = color + light.shade8(position, n, v, albedo, &material.phong, k);
                }
            }
            None => {
                for light in self.lights {
                    color = color + light.shade8(position, n, v, albedo, &material.phong, F8::ONE);
                }
            }
        }
        ShadedPacket { color, normal: n, depth }
    }
}

impl Bump {
    /// F, Fu, Fv at eight (u,v) from the full-resolution `table` (no footprint filtering).
    #[inline]
    pub fn perturbation8(&self, table: &BumpTable, uv: (F8, F8)) -> (F8, F8, F8) {
        let (ru, rv) = (F8::splat(self.repeat.x), F8::splat(self.repeat.y));
        let [f, fs, ft] = table.sample8(uv.0 * ru, uv.1 * rv, self.interp, 0);
        let scale = F8::splat(self.scale);
        (scale * f, scale * ru * fs, scale * rv * ft)
    }

    /// F, Fu, Fv at surface parameters `uv` (whose frame is `frame`): a table is replicated `repeat` times
    /// and scaled by `scale`; a procedural pattern is scaled by `scale` and band-limited to the footprint.
    #[inline]
    pub fn perturbation(
        &self,
        uv: Vec2,
        frame: &SurfaceFrame,
        footprint: &Footprint,
        filter: BumpFilter,
    ) -> Perturbation {
        let table = match &self.source {
            BumpSource::Table(t) => t,
            BumpSource::Procedural(p) => {
                let b = p.bump(self.scale, uv, frame, footprint);
                return Perturbation { f: b.value, fu: b.grad[0], fv: b.grad[1] };
            }
        };
        let st = uv * self.repeat;
        let fp = footprint.replicated(self.repeat.x, self.repeat.y);
        let b = match filter {
            BumpFilter::None => table.sample(st.x, st.y, self.interp, 0.0),
            BumpFilter::Mip => table.sample(st.x, st.y, self.interp, fp.mip_level(table.width(), table.height())),
            BumpFilter::Filtered(f) => {
                table.filtered(st.x, st.y, &fp, &FilterOptions { filter: f, ..FilterOptions::default() })
            }
        };
        Perturbation {
            f: self.scale * b.f,
            fu: self.scale * self.repeat.x * b.fs,
            fv: self.scale * self.repeat.y * b.ft,
        }
    }
}

/// The solid-texture points of eight samples (`procedural::solid::solid_point` on every lane): the
/// object-space point and the size of its pixel there.
#[inline]
fn solid_points(frame: &Frame8, footprints: &[Footprint; LANES]) -> [SolidPoint; LANES] {
    let lane = |f: fn(&Footprint) -> f32| F8::new(footprints.map(|p| f(&p)));
    let dx = frame.pu * lane(|p| p.dudx) + frame.pv * lane(|p| p.dvdx);
    let dy = frame.pu * lane(|p| p.dudy) + frame.pv * lane(|p| p.dvdy);
    let width = dx.cross(dy).length().sqrt();
    std::array::from_fn(|i| SolidPoint { p: frame.p.lane(i), width: width.as_array_ref()[i] })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::procedural::solid::solid_point;

    /// The lane form gives every lane what `solid_point` gives its sample: the point and the pixel's size.
    #[test]
    fn solid_points_on_lanes_equal_the_scalar_form() {
        let v = |k: usize, a: f32| Vec3::new(a + k as f32 * 0.3, 1.0 - a * k as f32 * 0.1, 0.5 * a - k as f32);
        let frames: [SurfaceFrame; LANES] = std::array::from_fn(|k| SurfaceFrame {
            p: v(k, 0.2),
            pu: v(k, 1.5),
            pv: v(k, -0.7),
            puu: Vec3::ZERO,
            puv: Vec3::ZERO,
            pvv: Vec3::ZERO,
        });
        let footprints: [Footprint; LANES] = std::array::from_fn(|k| {
            let s = 0.001 * (k + 1) as f32;
            Footprint { dudx: s, dvdx: 0.3 * s, dudy: -0.2 * s, dvdy: 2.0 * s }
        });
        let got = solid_points(&Frame8::from_lanes(&frames), &footprints);
        for k in 0..LANES {
            let want = solid_point(&frames[k], &footprints[k]);
            assert_eq!(got[k].p, want.p, "lane {k}");
            assert!(
                (got[k].width - want.width).abs() <= 1e-5 * want.width,
                "lane {k}: {} vs {}",
                got[k].width,
                want.width
            );
        }
    }
}
