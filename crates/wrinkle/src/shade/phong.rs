//! The Blinn-Phong reflection of one light.

use crate::lanes::{pow, CmpGt, F8, V3};
use crate::light::{Light, Spot};

/// The specular lobe of Blinn-Phong: specular (N.H)^shininess.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Phong {
    pub specular: f32,
    pub shininess: f32,
    /// Below this N.H the highlight adds less than 1e-6 (far below one 8-bit step), so the power is skipped.
    pub cutoff: f32,
}

impl Phong {
    pub fn new(specular: f32, shininess: f32) -> Phong {
        let cutoff = if specular > 0.0 { (1e-6 / specular).min(1.0).powf(1.0 / shininess) } else { f32::INFINITY };
        Phong { specular, shininess, cutoff }
    }

    /// Blinn-Phong on eight samples: albedo (N.L) + ks (N.H)^exponent, times `light`'s radiance at `p`;
    /// `ks` is each lane's specular (the material's, or what its layers made of it), `exponent` each lane's
    /// where layers vary it (else the material's `shininess`).
    #[inline]
    #[allow(clippy::too_many_arguments)]
    pub fn shade8(&self, light: &Light, p: V3, n: V3, v: V3, albedo: V3, ks: F8, exponent: Option<F8>) -> V3 {
        let (l, radiance) = match *light {
            Light::Directional { direction, radiance } => (V3::splat(-direction), V3::splat(radiance)),
            // A spot is a point light here; its cone and slide tint the result (ShadeContext::shade8).
            Light::Point { position, radiance } | Light::Spot(Spot { position, radiance, .. }) => {
                let d = V3::splat(position) - p;
                let d2 = d.dot(d);
                (d * (F8::ONE / d2.sqrt()), V3::splat(radiance) * (F8::ONE / d2))
            }
            Light::Ambient { radiance } => return V3::splat(radiance) * albedo,
            // Shaded from its convolved maps (shade::Ibl), which this lobe does not see.
            Light::Environment { .. } => return V3::ZERO,
        };
        let ndotl = n.dot(l);
        let lit = ndotl.cmp_gt(F8::ZERO);
        if lit.none() {
            return V3::ZERO;
        }
        let h = (l + v).normalize_or_zero();
        let ndoth = n.dot(h);
        let glints = ndoth.cmp_gt(F8::splat(self.cutoff));
        let spec = if glints.any() {
            glints.blend(ks * pow(ndoth, exponent.unwrap_or(F8::splat(self.shininess))), F8::ZERO)
        } else {
            F8::ZERO
        };
        let diffuse = lit.blend(ndotl, F8::ZERO);
        let spec = lit.blend(spec, F8::ZERO);
        radiance * (albedo * diffuse + V3 { x: spec, y: spec, z: spec })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// One sample shaded in every lane; lane 2 read back.
    fn shade(light: &Light, p: Vec3, n: Vec3, v: Vec3, albedo: Vec3, phong: &Phong) -> Vec3 {
        let s = V3::splat;
        phong.shade8(light, s(p), s(n), s(v), s(albedo), F8::splat(phong.specular), None).lane(2)
    }

    #[test]
    fn lambert_and_highlight() {
        let light = Light::Directional { direction: -Vec3::Z, radiance: Vec3::splat(2.0) };
        // Head-on: N.L = 1, N.H = 1.
        let c = shade(&light, Vec3::ZERO, Vec3::Z, Vec3::Z, Vec3::splat(0.5), &Phong::new(0.25, 10.0));
        assert!((c - Vec3::splat(2.0 * (0.5 + 0.25))).length() < 1e-6);
        // At 60 degrees N.L = 0.5; the eye along the normal puts H at 30 degrees.
        let n = Vec3::new(3f32.sqrt() / 2.0, 0.0, 0.5);
        let c = shade(&light, Vec3::ZERO, n, n, Vec3::ONE, &Phong::new(1.0, 2.0));
        let ndoth = (30f32.to_radians()).cos();
        assert!((c.x - 2.0 * (0.5 + ndoth * ndoth)).abs() < 1e-5);
        // From behind: nothing.
        assert_eq!(shade(&light, Vec3::ZERO, -Vec3::Z, Vec3::Z, Vec3::ONE, &Phong::new(1.0, 2.0)), Vec3::ZERO);
        // The cutoff drops only what is below 1e-6.
        let phong = Phong::new(0.5, 80.0);
        assert!(0.5 * phong.cutoff.powf(80.0) <= 1.0001e-6);
        assert_eq!(Phong::new(0.0, 10.0).cutoff, f32::INFINITY);
        let point = Light::Point { position: Vec3::new(0.0, 0.0, 2.0), radiance: Vec3::splat(4.0) };
        let c = shade(&point, Vec3::ZERO, Vec3::Z, Vec3::Z, Vec3::ONE, &Phong::new(0.0, 1.0));
        assert!((c - Vec3::ONE).length() < 1e-6);
    }

    /// Lanes are independent: mixed lit, unlit and glinting lanes give what each gives alone.
    #[test]
    fn lanes_do_not_mix() {
        let normals: [Vec3; 8] = std::array::from_fn(|i| {
            let a = i as f32 * 0.8;
            Vec3::new(a.cos(), 0.3 * a.sin(), a.sin()).normalize()
        });
        let eye = Vec3::new(0.2, 0.1, 1.0).normalize();
        let phong = Phong::new(0.4, 30.0);
        for light in [
            Light::Directional {
                direction: Vec3::new(-0.3, 0.0, -1.0).normalize(),
                radiance: Vec3::new(1.0, 0.5, 2.0),
            },
            Light::Point { position: Vec3::new(1.0, 2.0, 3.0), radiance: Vec3::splat(5.0) },
            Light::Ambient { radiance: Vec3::splat(0.1) },
        ] {
            let albedo = Vec3::new(0.9, 0.6, 0.3);
            let all = phong.shade8(
                &light,
                V3::ZERO,
                V3::from_lanes(&normals),
                V3::splat(eye),
                V3::splat(albedo),
                F8::splat(0.4),
                None,
            );
            for (i, n) in normals.iter().enumerate() {
                let alone = shade(&light, Vec3::ZERO, *n, eye, albedo, &phong);
                assert!((all.lane(i) - alone).length() < 1e-6, "{light:?} lane {i}");
            }
        }
    }
}
