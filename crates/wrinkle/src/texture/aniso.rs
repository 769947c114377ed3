//! Anisotropic MIP filtering: several trilinear probes spaced along the footprint's major axis, each on the
//! level of the minor axis (the major axis divided among the probes), averaged. Up to `max_aniso` probes;
//! beyond that ratio the level rises so the probes still cover the whole major axis.

use super::ewa::Axes;
use super::mip::trilinear;
use super::reconstruct::Addressing;
use super::texel::TexelSource;
use super::Footprint;

pub fn sample<S: TexelSource>(
    levels: &[S],
    addr: &Addressing<S::Texel>,
    s: f32,
    t: f32,
    fp: &Footprint,
    max_aniso: f32,
) -> S::Texel {
    let (w, h) = (levels[0].width(), levels[0].height());
    let axes = Axes::of_footprint(fp, w, h);
    if !axes.major.is_finite() {
        return trilinear(levels, addr, s, t, f32::MAX);
    }
    let ratio = if axes.minor > 0.0 { axes.major / axes.minor } else { f32::MAX };
    let probes = ratio.min(max_aniso).ceil().max(1.0) as usize;
    // Each probe covers an equal part of the major axis, and at least the minor axis.
    let width = (axes.major / probes as f32).max(axes.minor);
    let level = if width > 1.0 { width.log2() } else { 0.0 };
    if probes == 1 {
        return trilinear(levels, addr, s, t, level);
    }
    // The major axis in (s, t) units; the probes sit at the centres of its equal parts.
    let (ds, dt) = (axes.dir.x * axes.major / w as f32, axes.dir.y * axes.major / h as f32);
    let inv = 1.0 / probes as f32;
    let mut sum = S::Texel::default();
    for k in 0..probes {
        let off = (k as f32 + 0.5) * inv - 0.5;
        sum = sum + trilinear(levels, addr, s + off * ds, t + off * dt, level);
    }
    sum * inv
}
