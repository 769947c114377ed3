//! Lights and the Blinn-Phong reflection of one light.

use glam::Vec3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Light {
    /// Light travelling along `direction` (unit), `radiance` = colour x intensity.
    Directional { direction: Vec3, radiance: Vec3 },
    /// A point light; its intensity falls off with the square of the distance.
    Point { position: Vec3, radiance: Vec3 },
    /// Light from everywhere, reflected diffusely without regard to the normal.
    Ambient { radiance: Vec3 },
}

impl Light {
    /// Blinn-Phong: albedo (N.L) + specular (N.H)^shininess, times the light's radiance at `p`.
    #[inline]
    pub fn shade(&self, p: Vec3, n: Vec3, v: Vec3, albedo: Vec3, phong: &Phong) -> Vec3 {
        let (l, radiance) = match *self {
            Light::Directional { direction, radiance } => (-direction, radiance),
            Light::Point { position, radiance } => {
                let d = position - p;
                let d2 = d.length_squared();
                (d / d2.sqrt(), radiance / d2)
            }
            Light::Ambient { radiance } => return radiance * albedo,
        };
        let ndotl = n.dot(l);
        if ndotl <= 0.0 {
            return Vec3::ZERO;
        }
        let h = (l + v).normalize_or_zero();
        let ndoth = n.dot(h);
        let spec = if ndoth > phong.cutoff { phong.specular * ndoth.powf(phong.shininess) } else { 0.0 };
        radiance * (albedo * ndotl + Vec3::splat(spec))
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
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lambert_and_highlight() {
        let light = Light::Directional { direction: -Vec3::Z, radiance: Vec3::splat(2.0) };
        // Head-on: N.L = 1, N.H = 1.
        let c = light.shade(Vec3::ZERO, Vec3::Z, Vec3::Z, Vec3::splat(0.5), &Phong::new(0.25, 10.0));
        assert!((c - Vec3::splat(2.0 * (0.5 + 0.25))).length() < 1e-6);
        // At 60 degrees N.L = 0.5; the eye along the normal puts H at 30 degrees.
        let n = Vec3::new(3f32.sqrt() / 2.0, 0.0, 0.5);
        let c = light.shade(Vec3::ZERO, n, n, Vec3::ONE, &Phong::new(1.0, 2.0));
        let ndoth = (30f32.to_radians()).cos();
        assert!((c.x - 2.0 * (0.5 + ndoth * ndoth)).abs() < 1e-5);
        // From behind: nothing.
        assert_eq!(light.shade(Vec3::ZERO, -Vec3::Z, Vec3::Z, Vec3::ONE, &Phong::new(1.0, 2.0)), Vec3::ZERO);
        // The cutoff drops only what is below 1e-6.
        let phong = Phong::new(0.5, 80.0);
        assert!(0.5 * phong.cutoff.powf(80.0) <= 1.0001e-6);
        assert_eq!(Phong::new(0.0, 10.0).cutoff, f32::INFINITY);
        let point = Light::Point { position: Vec3::new(0.0, 0.0, 2.0), radiance: Vec3::splat(4.0) };
        let c = point.shade(Vec3::ZERO, Vec3::Z, Vec3::Z, Vec3::ONE, &Phong::new(0.0, 1.0));
        assert!((c - Vec3::ONE).length() < 1e-6);
    }
}
