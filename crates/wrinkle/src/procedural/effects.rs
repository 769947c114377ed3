//! The classic procedural patterns of the slides (Perlin 1985, Peachey 1985): plain noise, fBm, turbulence,
//! marble, wood, fire, clouds, bricks with mortar, an anti-aliased checkerboard and a grid.
//!
//! Every pattern is a scalar t(p) in [0, 1] at a point p (already multiplied by the pattern's scale), with
//! its gradient dt/dp, band-limited to `width` (the pixel's size in the same units): noise sums fade
//! their octaves (fbm.rs), the periodic patterns replace their profile by its box-filtered average over
//! the pixel (exact for the checkerboard, grid and mortar lines, Peachey's "analytic prefiltering"). The
//! colour is a Catmull-Rom spline through the pattern's colours at t.

use super::fbm::{Fractal, Octaves, Sum};
use super::perlin::{NoiseD, Perlin};
use crate::{Error, Result};
use std::f32::consts::TAU;

/// The kinds of pattern.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    Noise,
    Fbm,
    Turbulence,
    Marble,
    Wood,
    Fire,
    Clouds,
    Bricks,
    Checker,
    Grid,
}

impl Kind {
    pub const ALL: [Kind; 10] = [
        Kind::Noise,
        Kind::Fbm,
        Kind::Turbulence,
        Kind::Marble,
        Kind::Wood,
        Kind::Fire,
        Kind::Clouds,
        Kind::Bricks,
        Kind::Checker,
        Kind::Grid,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Kind::Noise => "noise",
            Kind::Fbm => "fbm",
            Kind::Turbulence => "turbulence",
            Kind::Marble => "marble",
            Kind::Wood => "wood",
            Kind::Fire => "fire",
            Kind::Clouds => "clouds",
            Kind::Bricks => "bricks",
            Kind::Checker => "checker",
            Kind::Grid => "grid",
        }
    }

    pub fn from_name(name: &str) -> Option<Kind> {
        Kind::ALL.into_iter().find(|k| k.name() == name)
    }

    /// One line on what the pattern is and which parameters it reads.
    pub fn describe(self) -> &'static str {
        match self {
            Kind::Noise => "Perlin gradient noise, 0.5 + 0.5 noise(p) (scale, seed, variant)",
            Kind::Fbm => "sum of noise/f over octaves, 0.5 + 0.5 fbm(p) (scale, octaves, lacunarity, gain)",
            Kind::Turbulence => "sum of |noise|/f over octaves (scale, octaves, lacunarity, gain)",
            Kind::Marble => "colour spline of sin(2 pi (x + strength turbulence(p))) (scale, octaves, strength)",
            Kind::Wood => "rings around the z axis distorted by fBm (scale, rings, strength); does not tile",
            Kind::Fire => {
                "flames rising in +y from turbulence moving with time (scale, octaves, strength, time); does not tile"
            }
            Kind::Clouds => "fBm drifting in x and y with time (scale, octaves, time)",
            Kind::Bricks => "running-bond bricks 1 x 0.5 with mortar lines, box-filtered (scale, mortar)",
            Kind::Checker => "checkerboard of 0.5 cells, exactly box-filtered over the pixel (scale)",
            Kind::Grid => "lines at whole x and y, exactly box-filtered over the pixel (scale, line_width)",
        }
    }

    /// Whether the pattern can repeat over a tile (with a whole-number scale).
    pub fn tiles(self) -> bool {
        !matches!(self, Kind::Wood | Kind::Fire)
    }

    /// The default colours: from t = 0 to t = 1, linear RGB.
    pub fn default_colors(self) -> Vec<[f32; 3]> {
        match self {
            Kind::Noise | Kind::Fbm | Kind::Turbulence => vec![[0.0; 3], [1.0; 3]],
            Kind::Marble => vec![[0.05, 0.05, 0.09], [0.55, 0.52, 0.5], [0.92, 0.9, 0.86], [0.98, 0.97, 0.95]],
            Kind::Wood => vec![[0.45, 0.24, 0.09], [0.2, 0.08, 0.02]],
            Kind::Fire => {
                vec![[0.0, 0.0, 0.0], [0.6, 0.05, 0.0], [1.0, 0.35, 0.02], [1.0, 0.8, 0.25], [1.0, 1.0, 0.85]]
            }
            Kind::Clouds => vec![[0.12, 0.3, 0.75], [0.35, 0.55, 0.9], [0.95, 0.95, 0.97], [1.0, 1.0, 1.0]],
            Kind::Bricks => vec![[0.55, 0.55, 0.52], [0.5, 0.12, 0.06]],
            Kind::Checker => vec![[0.05, 0.05, 0.05], [0.9, 0.9, 0.9]],
            Kind::Grid => vec![[0.9, 0.9, 0.9], [0.05, 0.05, 0.05]],
        }
    }
}

/// Every parameter of a pattern (each kind reads the ones `Kind::describe` names).
#[derive(Clone, Debug, PartialEq)]
pub struct Params {
    pub kind: Kind,
    /// Lattice cells (or pattern periods) per unit of the input coordinates.
    pub scale: f32,
    pub seed: u64,
    pub variant: super::perlin::Variant,
    pub octaves: Octaves,
    /// Marble, wood and fire: how strongly the noise distorts the pattern.
    pub strength: f32,
    /// Wood: rings per unit of radius.
    pub rings: f32,
    /// Fire and clouds: the animation time (noise units moved).
    pub time: f32,
    /// Bricks: mortar width as a fraction of a course's height.
    pub mortar: f32,
    /// Grid: line width as a fraction of a cell.
    pub line_width: f32,
    /// Colours from t = 0 to t = 1 (at least one).
    pub colors: Vec<[f32; 3]>,
}

impl Params {
    /// The defaults of `kind`.
    pub fn new(kind: Kind) -> Params {
        Params {
            kind,
            scale: 4.0,
            seed: 0,
            variant: super::perlin::Variant::default(),
            octaves: Octaves::default(),
            strength: match kind {
                Kind::Wood => 0.3,
                Kind::Fire => 1.0,
                _ => 0.5,
            },
            rings: 4.0,
            time: 0.0,
            mortar: 0.1,
            line_width: 0.05,
            colors: kind.default_colors(),
        }
    }

    /// Checks every parameter, naming the first one out of range.
    pub fn validate(&self) -> Result<()> {
        let bad =
            |name: &'static str, what: &str, v: f32| Err(Error::parameter(name, format!("must be {what}, got {v}")));
        if !(self.scale.is_finite() && self.scale > 0.0) {
            return bad("scale", "a positive number", self.scale);
        }
        if self.octaves.count == 0 || self.octaves.count > super::fbm::MAX_OCTAVES {
            return bad("octaves", "a whole number from 1 to 24", self.octaves.count as f32);
        }
        if !(self.octaves.lacunarity.is_finite() && self.octaves.lacunarity > 1.0 && self.octaves.lacunarity <= 16.0) {
            return bad("lacunarity", "a number above 1 and at most 16", self.octaves.lacunarity);
        }
        if !(self.octaves.gain.is_finite() && self.octaves.gain > 0.0 && self.octaves.gain < 1.0) {
            return bad("gain", "a number between 0 and 1", self.octaves.gain);
        }
        for (name, v) in [("strength", self.strength), ("rings", self.rings), ("time", self.time)] {
            if !v.is_finite() || (name != "time" && v < 0.0) {
                return bad(name, "a finite non-negative number", v);
            }
        }
        for (name, v) in [("mortar", self.mortar), ("line_width", self.line_width)] {
            if !(0.0..=1.0).contains(&v) {
                return bad(name, "a fraction from 0 to 1", v);
            }
        }
        if self.colors.is_empty() {
            return Err(Error::parameter("colors", "must hold at least one colour"));
        }
        if let Some(c) = self.colors.iter().find(|c| c.iter().any(|v| !v.is_finite() || *v < 0.0)) {
            return Err(Error::parameter(
                "colors",
                format!("must have non-negative components, got [{}, {}, {}]", c[0], c[1], c[2]),
            ));
        }
        Ok(())
    }
}

/// A pattern ready to evaluate: its parameters and its noise sums.
#[derive(Clone, Debug)]
pub struct Pattern {
    pub params: Params,
    noise: Perlin,
    fbm: Fractal,
    turbulence: Fractal,
    /// 2 for images and uv-mapped textures (z ignored), 3 for solid textures.
    dims: usize,
}

impl Pattern {
    /// The pattern in `dims` (2 or 3) dimensions; `tile`: repeat every `scale` units of the input (the
    /// scale is then rounded to a whole number of lattice cells, at least 1).
    pub fn new(params: Params, dims: usize, tile: bool) -> Result<Pattern> {
        params.validate()?;
        let mut params = params;
        let mut noise = Perlin::new(params.variant, params.seed);
        if tile {
            if !params.kind.tiles() {
                return Err(Error::Invalid(format!(
                    "{} cannot tile (its pattern is not periodic)",
                    params.kind.name()
                )));
            }
            params.scale = params.scale.round().max(1.0);
            let p = params.scale as u32;
            noise = noise.with_period([p, p, p]);
            // Whole-number frequency ratios keep every octave periodic.
            params.octaves.lacunarity = params.octaves.lacunarity.round().max(2.0);
        }
        let fbm = Fractal::new(noise.clone(), Sum::Fbm, params.octaves);
        let turbulence = Fractal::new(noise.clone(), Sum::Turbulence, params.octaves);
        Ok(Pattern { params, noise, fbm, turbulence, dims: dims.clamp(2, 3) })
    }

    /// t(p) in [0, 1] and its gradient with respect to the unscaled input point `p`, for a pixel `width`
    /// units of the unscaled input wide.
    pub fn eval_d(&self, p: [f32; 3], width: f32) -> NoiseD {
        let s = self.params.scale;
        let q = [p[0] * s, p[1] * s, if self.dims == 3 { p[2] * s } else { 0.0 }];
        let mut t = self.scaled(q, width * s);
        // Chain rule for the scale, then clamp to [0, 1] (where clamped, the gradient is zero).
        t.grad = t.grad.map(|g| g * s);
        if self.dims == 2 {
            t.grad[2] = 0.0;
        }
        if !(0.0..=1.0).contains(&t.value) {
            t.value = t.value.clamp(0.0, 1.0);
            t.grad = [0.0; 3];
        }
        t
    }

    /// t(p) alone.
    pub fn eval(&self, p: [f32; 3], width: f32) -> f32 {
        self.eval_d(p, width).value
    }

    /// The colour at `p`: the spline through the colours at t(p).
    pub fn color(&self, p: [f32; 3], width: f32) -> [f32; 3] {
        spline(&self.params.colors, self.eval(p, width))
    }

    /// t along one row of a 2D image: the points (u0 + (i + 0.5) du, v) for every i of `out`, each pixel
    /// `width` units wide. fBm and turbulence whose octaves are all resolved run on lanes (`eval2_row`).
    pub fn row(&self, u0: f32, du: f32, v: f32, width: f32, out: &mut [f32]) {
        let s = self.params.scale;
        let sum = match self.params.kind {
            Kind::Fbm => Some((&self.fbm, 0.5, 0.5)),
            Kind::Turbulence => Some((&self.turbulence, 0.0, 1.0)),
            _ => None,
        };
        match sum {
            Some((fractal, a, k)) if self.dims == 2 && fractal.all_octaves_resolved(width * s) => {
                let x: Vec<f32> = (0..out.len()).map(|i| (u0 + (i as f32 + 0.5) * du) * s).collect();
                fractal.eval2_row(&x, v * s, out);
                for o in out.iter_mut() {
                    *o = (a + k * *o).clamp(0.0, 1.0);
                }
            }
            _ => {
                for (i, o) in out.iter_mut().enumerate() {
                    *o = self.eval([u0 + (i as f32 + 0.5) * du, v, 0.0], width);
                }
            }
        }
    }

    /// The pattern at the scaled point q, for a pixel `w` scaled units wide.
    fn scaled(&self, q: [f32; 3], w: f32) -> NoiseD {
        let d = self.dims;
        let pr = &self.params;
        match pr.kind {
            Kind::Noise => {
                // A single octave fades like the first octave of a sum.
                let n = if d == 2 { self.noise.noise2_d(q[0], q[1]) } else { self.noise.noise3_d(q[0], q[1], q[2]) };
                let k = octave_fade(w);
                affine(0.5, 0.5 * k, n)
            }
            Kind::Fbm => affine(0.5, 0.5, self.fbm.eval_d(q, d, w)),
            Kind::Turbulence => self.turbulence.eval_d(q, d, w),
            Kind::Marble => {
                // sin(2 pi (x + strength turbulence)): the stripes' own frequency is one per unit along x.
                let turb = self.turbulence.eval_d(q, d, w);
                let phase = q[0] + pr.strength * turb.value;
                let k = octave_fade(w);
                let (sin, cos) = (TAU * phase).sin_cos();
                let dphase = [1.0 + pr.strength * turb.grad[0], pr.strength * turb.grad[1], pr.strength * turb.grad[2]];
                NoiseD { value: 0.5 + 0.5 * k * sin, grad: dphase.map(|g| 0.5 * k * TAU * cos * g) }
            }
            Kind::Wood => {
                let n = self.fbm.eval_d(q, d, w);
                let r = (q[0] * q[0] + q[1] * q[1]).sqrt();
                let (rx, ry) = if r > 0.0 { (q[0] / r, q[1] / r) } else { (0.0, 0.0) };
                let phase = pr.rings * r + pr.strength * n.value;
                // The rings fade to their mean once a ring is narrower than two pixels.
                let k = octave_fade(w * pr.rings);
                let (sin, cos) = (TAU * phase).sin_cos();
                let dphase = [
                    pr.rings * rx + pr.strength * n.grad[0],
                    pr.rings * ry + pr.strength * n.grad[1],
                    pr.strength * n.grad[2],
                ];
                // 0.5 - 0.5 cos: the dark late wood at whole rings.
                NoiseD { value: 0.5 - 0.5 * k * cos, grad: dphase.map(|g| 0.5 * k * TAU * sin * g) }
            }
            Kind::Fire => {
                // Turbulence scrolling downwards through the flame as time passes: the flames rise.
                let moving = [q[0], q[1] - pr.time, q[2]];
                let turb = self.turbulence.eval_d(moving, d, w);
                let height = q[1] / pr.scale;
                // Hot at the bottom (y = 0), cooling upwards, torn by the turbulence.
                let value = 1.0 - height - pr.strength * (turb.value - 0.3);
                let grad = [
                    -pr.strength * turb.grad[0],
                    -1.0 / pr.scale - pr.strength * turb.grad[1],
                    -pr.strength * turb.grad[2],
                ];
                NoiseD { value, grad }
            }
            Kind::Clouds => {
                let moving = [q[0] + pr.time, q[1] + 0.5 * pr.time, q[2]];
                affine(0.5, 0.8, self.fbm.eval_d(moving, d, w))
            }
            Kind::Bricks => bricks(q, w, pr.mortar),
            Kind::Checker => {
                // Cells 0.5 wide: one period per unit. t = 1/2 - 1/2 prod(square waves), each box-filtered.
                let axes = if d == 3 { 3 } else { 2 };
                let mut f = [1.0f32; 3];
                let mut df = [0.0f32; 3];
                for a in 0..axes {
                    (f[a], df[a]) = filtered_square(2.0 * q[a], 2.0 * w);
                    df[a] *= 2.0;
                }
                let value = 0.5 - 0.5 * f[0] * f[1] * f[2];
                let grad = [-0.5 * df[0] * f[1] * f[2], -0.5 * f[0] * df[1] * f[2], -0.5 * f[0] * f[1] * df[2]];
                NoiseD { value, grad }
            }
            Kind::Grid => {
                let (lx, dlx) = filtered_lines(q[0], w, pr.line_width);
                let (ly, dly) = filtered_lines(q[1], w, pr.line_width);
                // Covered by a line along x or along y.
                NoiseD { value: 1.0 - (1.0 - lx) * (1.0 - ly), grad: [dlx * (1.0 - ly), dly * (1.0 - lx), 0.0] }
            }
        }
    }
}

/// a + k n (value and gradient).
fn affine(a: f32, k: f32, n: NoiseD) -> NoiseD {
    NoiseD { value: a + k * n.value, grad: n.grad.map(|g| k * g) }
}

/// The weight of a feature one unit wide seen through a pixel `w` units wide (fbm.rs's octave fade).
fn octave_fade(w: f32) -> f32 {
    let t = ((super::fbm::FADE_END - w) / (super::fbm::FADE_END - super::fbm::FADE_START)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// The square wave +1 on [0, 1), -1 on [1, 2) (period 2), averaged over [x - w/2, x + w/2], and its
/// derivative. Its integral is the triangle wave S(x) = 1 - |1 - (x mod 2)|.
fn filtered_square(x: f32, w: f32) -> (f32, f32) {
    let square = |x: f32| if x.rem_euclid(2.0) < 1.0 { 1.0 } else { -1.0 };
    if w <= 1e-6 {
        return (square(x), 0.0);
    }
    let tri = |x: f32| 1.0 - (1.0 - x.rem_euclid(2.0)).abs();
    let (a, b) = (x - 0.5 * w, x + 0.5 * w);
    ((tri(b) - tri(a)) / w, (square(b) - square(a)) / w)
}

/// Lines of width `lw` (a fraction of the unit period) centred on whole numbers, averaged over the pixel
/// [x - w/2, x + w/2], and the derivative. Integral of the line indicator: floor(y) lw + min(frac(y), lw)
/// with y = x + lw/2.
fn filtered_lines(x: f32, w: f32, lw: f32) -> (f32, f32) {
    let on = |x: f32| if (x + 0.5 * lw).rem_euclid(1.0) < lw { 1.0 } else { 0.0 };
    if w <= 1e-6 {
        return (on(x), 0.0);
    }
    let integral = |x: f32| {
        let y = x + 0.5 * lw;
        y.floor() * lw + (y - y.floor()).min(lw)
    };
    let (a, b) = (x - 0.5 * w, x + 0.5 * w);
    ((integral(b) - integral(a)) / w, (on(b) - on(a)) / w)
}

/// Running-bond bricks one unit long and half a unit high, mortar of width `mortar` courses: t = 1 on the
/// brick, 0 in the mortar, box-filtered across the bed joints and the head joints of the pixel's course.
fn bricks(q: [f32; 3], w: f32, mortar: f32) -> NoiseD {
    // Courses are 0.5 high: in course units y' = 2 y, the bed joints are lines at whole y'.
    let (bed, dbed) = filtered_lines(2.0 * q[1], 2.0 * w, mortar);
    let course = (2.0 * q[1]).floor();
    // Every other course is shifted by half a brick; head joints are lines at whole x', width mortar / 2
    // (the joint is as wide as the bed joint: mortar courses = mortar/2 units; a brick is 1 unit).
    let shift = if course.rem_euclid(2.0) == 1.0 { 0.5 } else { 0.0 };
    let (head, dhead) = filtered_lines(q[0] + shift, w, 0.5 * mortar);
    let value = (1.0 - bed) * (1.0 - head);
    NoiseD { value, grad: [-(1.0 - bed) * dhead, -2.0 * dbed * (1.0 - head), 0.0] }
}

/// The Catmull-Rom spline through `colors` evenly spaced over [0, 1], at t (Perlin's colour spline).
pub fn spline(colors: &[[f32; 3]], t: f32) -> [f32; 3] {
    let n = colors.len();
    match n {
        // No colours: black (a scene always gives at least one).
        0 => return [0.0; 3],
        1 => return colors[0],
        // Two colours: a straight blend (the spline's clamped end tangents would bend it).
        2 => return std::array::from_fn(|c| colors[0][c] + t.clamp(0.0, 1.0) * (colors[1][c] - colors[0][c])),
        _ => {}
    }
    let x = t.clamp(0.0, 1.0) * (n - 1) as f32;
    let i = (x as usize).min(n - 2);
    let f = x - i as f32;
    let at = |k: isize| colors[k.clamp(0, n as isize - 1) as usize];
    let (p0, p1, p2, p3) = (at(i as isize - 1), at(i as isize), at(i as isize + 1), at(i as isize + 2));
    let mut out = [0.0; 3];
    for c in 0..3 {
        let v = 0.5
            * ((2.0 * p1[c])
                + (-p0[c] + p2[c]) * f
                + (2.0 * p0[c] - 5.0 * p1[c] + 4.0 * p2[c] - p3[c]) * f * f
                + (-p0[c] + 3.0 * p1[c] - 3.0 * p2[c] + p3[c]) * f * f * f);
        out[c] = v.max(0.0);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The mean of the unfiltered pattern over the pixel [x - w/2, x + w/2] x [y - w/2, y + w/2]
    /// (64 x 64 stratified points): the box filter's ground truth.
    fn supersampled(p: &Pattern, q: [f32; 3], w: f32) -> f32 {
        let n = 64;
        let mut sum = 0.0;
        for i in 0..n {
            for j in 0..n {
                let dx = ((i as f32 + 0.5) / n as f32 - 0.5) * w;
                let dy = ((j as f32 + 0.5) / n as f32 - 0.5) * w;
                sum += p.eval([q[0] + dx, q[1] + dy, q[2]], 0.0);
            }
        }
        sum / (n * n) as f32
    }

    #[test]
    fn box_filtered_patterns_match_the_supersampled_pixel() {
        for kind in [Kind::Checker, Kind::Grid, Kind::Bricks] {
            let mut params = Params::new(kind);
            params.scale = 1.0;
            params.line_width = 0.2;
            params.mortar = 0.2;
            let p = Pattern::new(params, 2, false).unwrap();
            for (k, w) in [0.05f32, 0.3, 0.7, 1.3].into_iter().enumerate() {
                for i in 0..40 {
                    let q = [0.137 * i as f32 - 2.0 + 0.01 * k as f32, 0.071 * i as f32 - 1.3, 0.0];
                    let truth = supersampled(&p, q, w);
                    let filtered = p.eval(q, w);
                    // Bricks filter the head joints of the centre's course only: exact while the pixel
                    // stays inside one course (w < 0.5 - mortar), an approximation beyond.
                    let tol = if kind == Kind::Bricks && w > 0.25 { 0.15 } else { 2e-2 };
                    assert!((filtered - truth).abs() < tol, "{kind:?} w {w} at {q:?}: {filtered} vs {truth}");
                }
            }
        }
    }

    #[test]
    fn gradients_match_central_differences() {
        let mut checked = 0;
        for kind in Kind::ALL {
            let p = Pattern::new(Params::new(kind), 3, false).unwrap();
            for i in 0..200 {
                let x = [0.0173 * i as f32 + 0.3, 0.5 - 0.0091 * i as f32, 0.2 + 0.0037 * i as f32];
                let d = p.eval_d(x, 0.0);
                let h = 2e-4;
                for a in 0..3 {
                    let (mut lo, mut hi) = (x, x);
                    lo[a] -= h;
                    hi[a] += h;
                    let (flo, fhi) = (p.eval(lo, 0.0), p.eval(hi, 0.0));
                    // Skip the edges of the step patterns and the clamps, where the difference jumps.
                    if (fhi - flo).abs() > 0.2 || [flo, fhi, d.value].iter().any(|v| *v <= 0.0 || *v >= 1.0) {
                        continue;
                    }
                    // Turbulence has creases where an octave crosses zero; where the two one-sided differences
                    // disagree, a crease lies inside the stencil and the difference means nothing.
                    let f0 = p.eval(x, 0.0);
                    let (fwd, back) = ((fhi - f0) / h, (f0 - flo) / h);
                    if (fwd - back).abs() > 0.05 * (1.0 + fwd.abs()) {
                        continue;
                    }
                    // A crease just outside the smaller stencil can still lie inside this one: a quarter step
                    // must then agree.
                    let (mut lo4, mut hi4) = (x, x);
                    lo4[a] -= h / 4.0;
                    hi4[a] += h / 4.0;
                    let c = [(fhi - flo) / (2.0 * h), (p.eval(hi4, 0.0) - p.eval(lo4, 0.0)) / (h / 2.0)];
                    checked += 1;
                    // Rounding the value to f32 costs the differences about 2e-3 |grad f| (a ring pattern's
                    // phase reaches 40, so its ulp moves the value by ~1e-5 against steps of 1e-4).
                    let norm = d.grad.iter().map(|g| g * g).sum::<f32>().sqrt();
                    let ok = c.iter().any(|c| (d.grad[a] - c).abs() < 2e-2 * (1.0 + c.abs()) + 2e-3 * norm);
                    assert!(ok, "{kind:?} axis {a} at {x:?}: {} vs {c:?}", d.grad[a]);
                }
            }
        }
        assert!(checked > 2000, "only {checked} smooth points");
    }

    #[test]
    fn rows_of_lanes_equal_single_points() {
        // 45 pixels: two groups of sixteen (AVX-512, where the CPU has it), eight lanes, five single points.
        for (kind, tileable) in
            [Kind::Fbm, Kind::Turbulence, Kind::Marble].into_iter().flat_map(|k| [(k, true), (k, false)])
        {
            let p = Pattern::new(Params::new(kind), 2, tileable).unwrap();
            let mut row = vec![0.0; 45];
            p.row(0.1, 0.01, 0.37, 0.001, &mut row);
            for (i, t) in row.iter().enumerate() {
                let single = p.eval([0.1 + (i as f32 + 0.5) * 0.01, 0.37, 0.0], 0.001);
                assert!((t - single).abs() < 1e-5, "{kind:?} tileable {tileable} pixel {i}: {t} vs {single}");
            }
        }
    }

    #[test]
    fn spline_passes_through_its_colours() {
        let colors = [[0.0, 0.1, 0.2], [1.0, 0.5, 0.0], [0.3, 0.3, 0.3], [0.9, 0.9, 1.0]];
        for (i, c) in colors.iter().enumerate() {
            let got = spline(&colors, i as f32 / 3.0);
            assert!(got.iter().zip(c).all(|(a, b)| (a - b).abs() < 1e-6), "{got:?} vs {c:?}");
        }
        // Two colours: a straight line.
        let mid = spline(&[[0.0; 3], [1.0; 3]], 0.25);
        assert!((mid[0] - 0.25).abs() < 1e-6);
    }

    #[test]
    fn wood_and_fire_refuse_to_tile() {
        for kind in [Kind::Wood, Kind::Fire] {
            assert!(Pattern::new(Params::new(kind), 2, true).is_err());
        }
        let mut bad = Params::new(Kind::Marble);
        bad.octaves.gain = 1.5;
        let e = Pattern::new(bad, 3, false).unwrap_err();
        assert!(matches!(e, Error::Parameter { name: "gain", .. }), "{e}");
    }
}
