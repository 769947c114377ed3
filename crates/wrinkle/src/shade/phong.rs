//! The Blinn-Phong reflection of one light.

use crate::bump::lean::WorldSpread8;
use crate::lanes::{pow, CmpGt, F8, V3};
use crate::light::{Light, Spot};

/// The Blinn-Phong lobe widened by the covariance Sigma of the slopes under a pixel (LEAN mapping). With H's
/// slopes h = (H.t1, H.t2) / H.N in the frame of the mean normal N, Blinn-Phong is exactly
/// (N.H)^s = (1 + |h|^2)^(-s/2), near its peak the Gaussian exp(-s |h|^2 / 2) of variance 1/s. Convolved
/// with the slopes' Gaussian that variance becomes A = I/s + Sigma, so the lobe is
///     (1 + h^T P h)^(-s/2) / (s sqrt(det A)),   P = A^-1 / s,
/// which keeps the lobe's integral and is Blinn-Phong itself where Sigma = 0 (P = I, the factor 1).
#[derive(Clone, Copy, Debug)]
pub struct Lobe8 {
    spread: WorldSpread8,
    p11: F8,
    p12: F8,
    p22: F8,
    ratio: F8,
    /// -s/2: the power of the lobe of exponent s it was widened from.
    power: F8,
}

impl Lobe8 {
    /// The lobe of exponent `s` (per lane) widened by `spread`.
    #[inline]
    pub fn widened(spread: WorldSpread8, s: F8) -> Lobe8 {
        let inv_s = F8::ONE / s;
        // A covariance's cross term is at most sqrt(xx yy): estimates beyond it (or rounded) are held to it,
        // so A = I/s + Sigma stays positive definite.
        let (xx, yy) = (spread.xx, spread.yy);
        let bound = (xx * yy).sqrt();
        let (a11, a22, a12) = (inv_s + xx, inv_s + yy, spread.xy.min(bound).max(-bound));
        // det A expanded, so that wide spreads do not cancel it away: 1/s^2 + (xx + yy)/s + det Sigma.
        let det = inv_s * (inv_s + xx + yy) + (xx * yy - a12 * a12).max(F8::ZERO);
        let k = F8::ONE / (det * s);
        let ratio = F8::ONE / (s * det.sqrt());
        Lobe8 { spread, p11: a22 * k, p12: -a12 * k, p22: a11 * k, ratio, power: s * F8::splat(-0.5) }
    }

    /// The lobe at half vector `h` (unit) where N.H = `ndoth` > 0.
    #[inline]
    fn eval(&self, h: V3, ndoth: F8) -> F8 {
        let inv = F8::ONE / ndoth;
        let (h1, h2) = (h.dot(self.spread.t1) * inv, h.dot(self.spread.t2) * inv);
        let x = F8::ONE + self.p11 * h1 * h1 + (self.p12 + self.p12) * h1 * h2 + self.p22 * h2 * h2;
        self.ratio * pow(x, self.power)
    }
}

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
    /// where layers vary it (else the material's `shininess`); `lobe` replaces the highlight by its widened
    /// one (LEAN; it carries its own exponent).
    #[inline]
    #[allow(clippy::too_many_arguments)]
    pub fn shade8(
        &self,
        light: &Light,
        p: V3,
        n: V3,
        v: V3,
        albedo: V3,
        ks: F8,
        exponent: Option<F8>,
        lobe: Option<&Lobe8>,
    ) -> V3 {
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
        let spec = match lobe {
            Some(lobe) => {
                let facing = ndoth.cmp_gt(F8::ZERO);
                match facing.any() {
                    true => facing.blend(ks * lobe.eval(h, ndoth.max(F8::splat(1e-6))), F8::ZERO),
                    false => F8::ZERO,
                }
            }
            None => {
                let glints = ndoth.cmp_gt(F8::splat(self.cutoff));
                match glints.any() {
                    true => glints.blend(ks * pow(ndoth, exponent.unwrap_or(F8::splat(self.shininess))), F8::ZERO),
                    false => F8::ZERO,
                }
            }
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
        phong.shade8(light, s(p), s(n), s(v), s(albedo), F8::splat(phong.specular), None, None).lane(2)
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

    /// The widened lobe without spread is Blinn-Phong to rounding; with an isotropic spread sigma^2 it is the
    /// convolution's Gaussian near the peak: peak 1/(1 + s sigma^2) and variance 1/s + sigma^2.
    #[test]
    fn widened_lobe() {
        let s = V3::splat;
        let light = Light::Directional { direction: -Vec3::Z, radiance: Vec3::ONE };
        let phong = Phong::new(1.0, 60.0);
        let shininess = F8::splat(60.0);
        // The frame of a normal tilted about y: t1 perpendicular to it in the xz plane, t2 = y.
        let spread = |n: Vec3, sigma2: f32| WorldSpread8 {
            t1: s(Vec3::new(n.z, 0.0, -n.x)),
            t2: s(Vec3::Y),
            xx: F8::splat(sigma2),
            yy: F8::splat(sigma2),
            xy: F8::ZERO,
        };
        let at = |n: Vec3, lobe: Option<&Lobe8>| {
            phong.shade8(&light, V3::ZERO, s(n), s(Vec3::Z), V3::ZERO, F8::ONE, None, lobe).lane(0).x
        };
        let tilted = |t: f32| Vec3::new(t.sin(), 0.0, t.cos());
        for tilt in [0.0f32, 0.05, 0.1, 0.2, 0.4] {
            let n = tilted(tilt);
            let (plain, got) = (at(n, None), at(n, Some(&Lobe8::widened(spread(n, 0.0), shininess))));
            assert!((got - plain).abs() < 1e-5 * (1.0 + plain), "tilt {tilt}: {got} vs {plain}");
        }
        let sigma2 = 0.01f32;
        let peak = at(Vec3::Z, Some(&Lobe8::widened(spread(Vec3::Z, sigma2), shininess)));
        assert!((peak - 1.0 / (1.0 + 60.0 * sigma2)).abs() < 1e-5, "peak {peak}");
        // A small tilt t of N tilts H's slope by tan t: the Gaussian of variance 1/s + sigma^2.
        let t = 0.05f32;
        let want = peak * (-(t.tan().powi(2)) / (2.0 * (1.0 / 60.0 + sigma2))).exp();
        let got = at(tilted(t), Some(&Lobe8::widened(spread(tilted(t), sigma2), shininess)));
        assert!((got - want).abs() < 0.02 * want, "{got} vs {want}");
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
                None,
            );
            for (i, n) in normals.iter().enumerate() {
                let alone = shade(&light, Vec3::ZERO, *n, eye, albedo, &phong);
                assert!((all.lane(i) - alone).length() < 1e-6, "{light:?} lane {i}");
            }
        }
    }
}
