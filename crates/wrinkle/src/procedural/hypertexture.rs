//! Hypertexture (Perlin and Hoffert 1989): an object density function D(x), here an ellipsoid's radial
//! soft region, shaped by density modulation functions H = f_n(... f_1(D(x))) (bias, gain, noise,
//! turbulence), and rendered by marching rays through it.
//!
//! D = clamp((1 - r) / soft, 0, 1) with r the ellipsoidal radius (1 on the surface): 1 in the core,
//! falling to 0 over the outer `soft` fraction. Noise and turbulence add amplitude * sum(p) to the density;
//! bias and gain bend it. Every step keeps its gradient (chain rule, analytic noise derivatives), so lit
//! volumes are shaded by the normal -grad H / |grad H| without extra evaluations.

use super::bias_gain::{bias, gain};
use super::effects::spline;
use super::fbm::{Fractal, Octaves, Sum};
use super::perlin::{NoiseD, Perlin, Variant, LANES};
use crate::light::Light;
use glam::Vec3;

/// One density modulation function.
#[derive(Clone, Debug)]
pub enum Modulation {
    Bias(f32),
    Gain(f32),
    /// Adds amplitude * sum(frequency (x - drift)) (one octave: noise; several: fBm or turbulence).
    Noise {
        amplitude: f32,
        frequency: f32,
        drift: Vec3,
        sum: Fractal,
    },
}

/// How the volume gives light.
#[derive(Clone, Debug)]
pub enum Shading {
    /// Reflects the lights with this albedo, shaded by the density gradient (the fractal egg).
    Lit { albedo: Vec3 },
    /// Glows with the colour spline at the density, times `emission` (fire).
    Emissive { colors: Vec<[f32; 3]>, emission: f32 },
}

/// A hypertextured ellipsoid in world space.
#[derive(Clone, Debug)]
pub struct Hypertexture {
    pub center: Vec3,
    pub radii: Vec3,
    /// Width of the soft region, as a fraction of the radius (0, 1].
    pub soft: f32,
    /// Extinction per unit length where H = 1.
    pub density: f32,
    /// March step, world units.
    pub step: f32,
    pub modulations: Vec<Modulation>,
    pub shading: Shading,
}

impl Modulation {
    /// A noise sum of `octaves` (1: plain noise) of the default (hashed) noise with `seed`.
    pub fn noise(sum: Sum, amplitude: f32, frequency: f32, octaves: u32, seed: u64, drift: Vec3) -> Modulation {
        let octaves = Octaves { count: octaves, ..Octaves::default() };
        Modulation::Noise {
            amplitude,
            frequency,
            drift,
            sum: Fractal::new(Perlin::new(Variant::default(), seed), sum, octaves),
        }
    }

    /// The largest value the modulation can add.
    fn reach(&self) -> f32 {
        match self {
            Modulation::Noise { amplitude, sum, .. } => amplitude.abs() * sum.amplitude_sum() * 1.02,
            _ => 0.0,
        }
    }
}

/// The most steps a ray takes through the volume: 65536 steps of the default 0.01 span a volume 650 units
/// across.
pub const MAX_MARCH_STEPS: usize = 1 << 16;

impl Hypertexture {
    /// H and its gradient at the world point `x`.
    pub fn eval(&self, x: Vec3) -> NoiseD {
        let q = (x - self.center) / self.radii;
        let r = q.length();
        // d r / d x = q / (r radii).
        let dr = if r > 0.0 { q / (r * self.radii) } else { Vec3::ZERO };
        let mut v = (1.0 - r) / self.soft;
        let mut g = -dr / self.soft;
        if v >= 1.0 {
            (v, g) = (1.0, Vec3::ZERO);
        }
        for m in &self.modulations {
            match m {
                Modulation::Bias(b) => {
                    let t = v.clamp(0.0, 1.0);
                    let k = -b.log2();
                    // Where the clamp holds the value, it no longer moves.
                    g *= if t > 0.0 && t < 1.0 { k * t.powf(k - 1.0) } else { 0.0 };
                    v = bias(*b, t);
                }
                Modulation::Gain(gg) => {
                    let t = v.clamp(0.0, 1.0);
                    let k = -(1.0 - gg).log2();
                    let s = if t < 0.5 { 2.0 * t } else { 2.0 - 2.0 * t };
                    g *= if t > 0.0 && t < 1.0 { k * s.powf(k - 1.0) } else { 0.0 };
                    v = gain(*gg, t);
                }
                Modulation::Noise { amplitude, frequency, drift, sum } => {
                    let p = (x - *drift) * *frequency;
                    let n = sum.eval_d(p.to_array(), 3, 0.0);
                    v += amplitude * n.value;
                    g += Vec3::from_array(n.grad) * (amplitude * frequency);
                }
            }
        }
        if v <= 0.0 {
            return NoiseD::default();
        }
        if v > 1.0 {
            (v, g) = (1.0, Vec3::ZERO);
        }
        NoiseD { value: v, grad: g.to_array() }
    }

    /// H alone at eight points (the noise sums run in SIMD lanes): the marching loop's workhorse.
    pub fn density_lanes(&self, x: &[Vec3; LANES]) -> [f32; LANES] {
        let mut v: [f32; LANES] = std::array::from_fn(|l| {
            let r = ((x[l] - self.center) / self.radii).length();
            ((1.0 - r) / self.soft).min(1.0)
        });
        for m in &self.modulations {
            match m {
                Modulation::Bias(b) => v = v.map(|t| bias(*b, t.clamp(0.0, 1.0))),
                Modulation::Gain(g) => v = v.map(|t| gain(*g, t.clamp(0.0, 1.0))),
                Modulation::Noise { amplitude, frequency, drift, sum } => {
                    let axis = |a: usize| -> [f32; LANES] { std::array::from_fn(|l| (x[l][a] - drift[a]) * frequency) };
                    let n = sum.eval3_lanes(&axis(0), &axis(1), &axis(2));
                    for l in 0..LANES {
                        v[l] += amplitude * n[l];
                    }
                }
            }
        }
        v.map(|t| t.clamp(0.0, 1.0))
    }

    /// The radius (in units of `radii`) beyond which H is zero: the soft edge pushed out by the noise.
    fn bound(&self) -> f32 {
        1.0 + self.soft * self.modulations.iter().map(Modulation::reach).sum::<f32>()
    }

    /// Where the ray `origin + t dir` (unit dir) is inside the bounding ellipsoid: [t0, t1].
    fn span(&self, origin: Vec3, dir: Vec3) -> Option<(f32, f32)> {
        let s = self.bound();
        let o = (origin - self.center) / (self.radii * s);
        let d = dir / (self.radii * s);
        let (a, b, c) = (d.dot(d), o.dot(d), o.dot(o) - 1.0);
        let disc = b * b - a * c;
        if disc <= 0.0 {
            return None;
        }
        let root = disc.sqrt();
        let (t0, t1) = ((-b - root) / a, (-b + root) / a);
        (t1 > 0.0).then_some((t0.max(0.0), t1))
    }

    /// Marches the ray up to `t_max` (the opaque surface's distance; infinity for the background) and
    /// composites the volume over `behind`: front to back, C += T a c, T *= 1 - a with a = 1 - exp(-density H dt).
    pub fn composite(&self, origin: Vec3, dir: Vec3, t_max: f32, behind: Vec3, lights: &[Light]) -> Vec3 {
        let Some((t0, t1)) = self.span(origin, dir) else { return behind };
        let end = t1.min(t_max);
        if end <= t0 {
            return behind;
        }
        // At most `MAX_MARCH_STEPS`: a step far below the volume's size (or of 0) widens, rather than march
        // for ever.
        let steps = ((end - t0) / self.step).ceil().clamp(1.0, MAX_MARCH_STEPS as f32);
        let dt = (end - t0) / steps;
        let (mut color, mut transmit) = (Vec3::ZERO, 1.0f32);
        let lit = matches!(self.shading, Shading::Lit { .. });
        // The middle of each step, eight steps at a time.
        let steps = steps as usize;
        'march: for first in (0..steps).step_by(LANES) {
            let x: [Vec3; LANES] = std::array::from_fn(|l| origin + dir * (t0 + ((first + l) as f32 + 0.5) * dt));
            let h = self.density_lanes(&x);
            for l in 0..LANES.min(steps - first) {
                if h[l] <= 0.0 {
                    continue;
                }
                let alpha = 1.0 - (-self.density * h[l] * dt).exp();
                // Lit volumes need the gradient: one scalar evaluation where there is density.
                let at = if lit { self.eval(x[l]) } else { NoiseD { value: h[l], grad: [0.0; 3] } };
                color += transmit * alpha * self.radiance(x[l], &at, dir, lights);
                transmit *= 1.0 - alpha;
                // Below 1/256 of what lies behind: invisible in 8 bits.
                if transmit < 4e-3 {
                    break 'march;
                }
            }
        }
        color + transmit * behind
    }

    fn radiance(&self, x: Vec3, h: &NoiseD, dir: Vec3, lights: &[Light]) -> Vec3 {
        match &self.shading {
            Shading::Emissive { colors, emission } => Vec3::from_array(spline(colors, h.value)) * *emission,
            Shading::Lit { albedo } => {
                let g = Vec3::from_array(h.grad);
                // The normal points out of the density (down its gradient), towards the eye where flat.
                let n = if g.length_squared() > 1e-12 { -g.normalize() } else { -dir };
                let mut c = Vec3::ZERO;
                for l in lights {
                    c += match *l {
                        Light::Directional { direction, radiance } => radiance * n.dot(-direction).max(0.0),
                        Light::Point { position, radiance } => {
                            let d = position - x;
                            let d2 = d.length_squared().max(1e-12);
                            radiance / d2 * n.dot(d / d2.sqrt()).max(0.0)
                        }
                        // The cone, not the slide.
                        Light::Spot(spot) => {
                            let d = spot.position - x;
                            let d2 = d.length_squared().max(1e-12);
                            let cone = spot.cone8(crate::lanes::V3::splat(x)).as_array_ref()[0];
                            spot.radiance * cone / d2 * n.dot(d / d2.sqrt()).max(0.0)
                        }
                        Light::Ambient { radiance } => radiance,
                        // Volumes are not lit by the environment map (yet).
                        Light::Environment { .. } => Vec3::ZERO,
                    };
                }
                *albedo * c
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn egg() -> Hypertexture {
        Hypertexture {
            center: Vec3::new(0.5, 0.0, -1.0),
            radii: Vec3::new(1.0, 1.3, 1.0),
            soft: 0.4,
            density: 10.0,
            step: 0.01,
            modulations: vec![
                Modulation::noise(Sum::Turbulence, 0.5, 3.0, 4, 2, Vec3::ZERO),
                Modulation::Bias(0.7),
                Modulation::Gain(0.8),
            ],
            shading: Shading::Lit { albedo: Vec3::ONE },
        }
    }

    #[test]
    fn radial_density_without_modulation() {
        let mut v = egg();
        v.modulations.clear();
        // Core, half way through the soft region, outside.
        assert_eq!(v.eval(v.center).value, 1.0);
        assert!((v.eval(v.center + Vec3::new(0.8, 0.0, 0.0)).value - 0.5).abs() < 1e-5);
        assert_eq!(v.eval(v.center + Vec3::new(0.0, 1.31, 0.0)).value, 0.0);
    }

    #[test]
    fn gradient_matches_central_differences() {
        let v = egg();
        let mut checked = 0;
        for i in 0..400 {
            let x = v.center
                + Vec3::new(
                    0.9 * (i as f32 * 0.37).sin(),
                    1.1 * (i as f32 * 0.21).cos(),
                    0.8 * (i as f32 * 0.13).sin(),
                );
            let h = v.eval(x);
            if h.value <= 0.02 || h.value >= 0.98 {
                continue;
            }
            let e = 1e-3;
            for a in 0..3 {
                let mut d = Vec3::ZERO;
                d[a] = e;
                let (lo, hi) = (v.eval(x - d).value, v.eval(x + d).value);
                let mid = v.eval(x).value;
                let (fwd, back) = ((hi - mid) / e, (mid - lo) / e);
                // Turbulence creases: skip where the one-sided differences disagree.
                if (fwd - back).abs() > 0.05 * (1.0 + fwd.abs()) || lo <= 0.0 || hi >= 1.0 {
                    continue;
                }
                // A crease just outside the quarter stencil can lie inside this one: either must agree.
                let quarter = (v.eval(x + d / 4.0).value - v.eval(x - d / 4.0).value) / (e / 2.0);
                let c = [(hi - lo) / (2.0 * e), quarter];
                let ok = c.iter().any(|c| (h.grad[a] - c).abs() < 3e-2 * (1.0 + c.abs()));
                assert!(ok, "axis {a}: {} vs {c:?}", h.grad[a]);
                checked += 1;
            }
        }
        assert!(checked > 100, "{checked}");
    }

    #[test]
    fn compositing_matches_the_beer_lambert_law_for_a_uniform_slab() {
        // With no soft region the core is uniform: transmittance exp(-density * length).
        let mut v = egg();
        v.modulations.clear();
        v.soft = 1e-4;
        v.radii = Vec3::ONE;
        v.center = Vec3::ZERO;
        v.density = 1.5;
        v.shading = Shading::Emissive { colors: vec![[0.0; 3]], emission: 0.0 };
        let out = v.composite(Vec3::new(0.0, 0.0, 5.0), -Vec3::Z, f32::INFINITY, Vec3::ONE, &[]);
        assert!((out.x - (-1.5f32 * 2.0).exp()).abs() < 1e-3, "{out}");
        // An opaque surface at the centre cuts the path in half.
        let half = v.composite(Vec3::new(0.0, 0.0, 5.0), -Vec3::Z, 5.0, Vec3::ONE, &[]);
        assert!((half.x - (-1.5f32).exp()).abs() < 1e-3, "{half}");
        // A ray that misses leaves the background untouched.
        assert_eq!(v.composite(Vec3::new(3.0, 0.0, 5.0), -Vec3::Z, f32::INFINITY, Vec3::ONE, &[]), Vec3::ONE);
    }
}
