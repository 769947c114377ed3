//! Every filter by name, and the texture data they read: the MIP pyramid, with the ripmap and the
//! summed-area table built the first time a filter needs them.

use super::mip::{build_levels, nearest_level, trilinear, LevelRule, MipFilter, Resample};
use super::reconstruct::{reconstruct, Addressing, Kernel};
use super::ripmap::Ripmap;
use super::sat::Sat;
use super::texel::Texel;
use super::wrap::Wrap;
use super::{aniso, ewa, ground_truth, Footprint};
use std::sync::OnceLock;

/// A texture filter: how a lookup integrates the texture over the pixel's footprint.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Filter {
    /// Magnification only (the full-resolution texture whatever the footprint): the texture's own kernel.
    Reconstruct(Kernel),
    /// Bilinear on the nearest MIP level.
    MipNearest,
    /// Bilinear on the two nearest MIP levels, blended (Williams 1983).
    Trilinear,
    /// Separately prefiltered in x and y, from the footprint's extents.
    Ripmap,
    /// The summed-area table's box (Crow 1984).
    Sat,
    /// Trilinear probes along the major axis.
    Aniso,
    /// Heckbert's elliptical weighted average.
    Ewa,
    /// The supersampled integral over the footprint (slow: the ground truth).
    Reference,
}

impl Filter {
    /// Every filter with its name, in the order of the slides' ladder.
    pub const ALL: [(&'static str, Filter); 14] = [
        ("nearest", Filter::Reconstruct(Kernel::Nearest)),
        ("bilinear", Filter::Reconstruct(Kernel::Bilinear)),
        ("bicubic", Filter::Reconstruct(Kernel::CatmullRom)),
        ("bspline", Filter::Reconstruct(Kernel::BSpline)),
        ("gaussian", Filter::Reconstruct(Kernel::Gaussian)),
        ("lanczos", Filter::Reconstruct(Kernel::Lanczos3)),
        ("mip-nearest", Filter::MipNearest),
        ("trilinear", Filter::Trilinear),
        ("ripmap", Filter::Ripmap),
        ("sat", Filter::Sat),
        ("aniso", Filter::Aniso),
        ("ewa", Filter::Ewa),
        ("reference", Filter::Reference),
        // Alias: the Catmull-Rom cubic by its own name.
        ("catmull-rom", Filter::Reconstruct(Kernel::CatmullRom)),
    ];

    pub fn parse(name: &str) -> Option<Filter> {
        Filter::ALL.iter().find(|(n, _)| *n == name).map(|&(_, f)| f)
    }

    pub fn name(self) -> &'static str {
        Filter::ALL.iter().find(|(_, f)| *f == self).map(|(n, _)| *n).expect("every filter is named")
    }

    /// "nearest, bilinear, ..." for error messages and help.
    pub fn names() -> String {
        Filter::ALL.iter().map(|(n, _)| *n).collect::<Vec<_>>().join(", ")
    }
}

/// Everything that decides one lookup besides the texture and the point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilterOptions {
    pub filter: Filter,
    /// How MIP filters pick their level.
    pub level_rule: LevelRule,
    /// The most probes (aniso) or the largest axis ratio (EWA).
    pub max_aniso: f32,
    /// Samples per side of the reference filter (8: with 16 samples per pixel, 32 x 32 per pixel).
    pub reference_samples: usize,
}

impl Default for FilterOptions {
    fn default() -> Self {
        FilterOptions {
            filter: Filter::Trilinear,
            level_rule: LevelRule::Longest,
            max_aniso: 16.0,
            reference_samples: 8,
        }
    }
}

/// A texture ready for every filter: its pyramid now, its ripmap and summed-area table on first use.
pub struct Filterable<S: Resample> {
    levels: Vec<S>,
    wrap: [Wrap; 2],
    mip_filter: MipFilter,
    ripmap: OnceLock<Ripmap<S>>,
    sat: OnceLock<Sat<<S::Texel as Texel>::Wide>>,
}

impl<S: Resample> Filterable<S> {
    /// Builds the pyramid of `base` with `mip_filter`; `wrap` decides how the pyramid treats the edges.
    pub fn new(base: S, mip_filter: MipFilter, wrap: [Wrap; 2]) -> Self {
        Filterable {
            levels: build_levels(base, mip_filter, wrap),
            wrap,
            mip_filter,
            ripmap: OnceLock::new(),
            sat: OnceLock::new(),
        }
    }

    /// A pyramid built elsewhere (levels[0] the full texture, each next level from the one before).
    pub fn from_levels(levels: Vec<S>, mip_filter: MipFilter, wrap: [Wrap; 2]) -> Self {
        Filterable { levels, wrap, mip_filter, ripmap: OnceLock::new(), sat: OnceLock::new() }
    }

    pub fn levels(&self) -> &[S] {
        &self.levels
    }

    /// The levels to change in place; the ripmap and summed-area table made of the old ones are dropped.
    pub fn levels_mut(&mut self) -> &mut [S] {
        (self.ripmap, self.sat) = (OnceLock::new(), OnceLock::new());
        &mut self.levels
    }

    pub fn wrap(&self) -> [Wrap; 2] {
        self.wrap
    }

    pub fn width(&self) -> usize {
        self.levels[0].width()
    }

    pub fn height(&self) -> usize {
        self.levels[0].height()
    }

    pub fn ripmap(&self) -> &Ripmap<S> {
        self.ripmap.get_or_init(|| Ripmap::build(&self.levels[0], self.mip_filter, self.wrap))
    }

    pub fn sat(&self) -> &Sat<<S::Texel as Texel>::Wide> {
        self.sat.get_or_init(|| Sat::build(&self.levels[0]))
    }

    /// The filtered texture at (s, t) (one period per unit) for footprint `fp` (in the same units).
    #[inline]
    pub fn sample(&self, opts: &FilterOptions, border: S::Texel, s: f32, t: f32, fp: &Footprint) -> S::Texel {
        let addr = Addressing { wrap: self.wrap, border };
        let base = &self.levels[0];
        match opts.filter {
            Filter::Reconstruct(kernel) => reconstruct(base, &addr, kernel, s, t),
            Filter::MipNearest => {
                nearest_level(&self.levels, &addr, s, t, opts.level_rule.level(fp, base.width(), base.height()))
            }
            Filter::Trilinear => {
                trilinear(&self.levels, &addr, s, t, opts.level_rule.level(fp, base.width(), base.height()))
            }
            Filter::Ripmap => self.ripmap().sample(&addr, s, t, fp),
            Filter::Sat => self.sat().sample(&addr, s, t, fp),
            Filter::Aniso => aniso::sample(&self.levels, &addr, s, t, fp, opts.max_aniso),
            Filter::Ewa => ewa::sample(&self.levels, &addr, s, t, fp, opts.max_aniso),
            Filter::Reference => ground_truth::sample(base, &addr, s, t, fp, opts.reference_samples),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::texel::Plane;
    use glam::Vec4;

    /// Footprints from magnification to far beyond the texture, isotropic and 8:1 at an angle.
    fn footprints(w: usize) -> Vec<Footprint> {
        let t = 1.0 / w as f32;
        let (c, s) = (0.5f32, 0.866f32);
        let mut fps = vec![Footprint::default()];
        for k in [0.3, 1.0, 3.0, 17.0, 500.0] {
            fps.push(Footprint { dudx: k * t, dvdx: 0.0, dudy: 0.0, dvdy: k * t });
            fps.push(Footprint { dudx: 8.0 * k * c * t, dvdx: 8.0 * k * s * t, dudy: -k * s * t, dvdy: k * c * t });
        }
        fps
    }

    fn every_filter() -> impl Iterator<Item = Filter> {
        Filter::ALL.iter().map(|&(_, f)| f)
    }

    #[test]
    fn constant_texture_is_constant_under_every_filter_and_footprint() {
        let (w, h) = (37, 23);
        let c = Vec4::new(0.2, 0.5, 0.7, 1.0);
        for wrap in [Wrap::Repeat, Wrap::Clamp, Wrap::Mirror] {
            for mip in [MipFilter::Box, MipFilter::Kaiser, MipFilter::Lanczos] {
                let data = Filterable::new(Plane { width: w, height: h, texels: vec![c; w * h] }, mip, [wrap; 2]);
                for filter in every_filter() {
                    let opts = FilterOptions { filter, reference_samples: 8, ..FilterOptions::default() };
                    for fp in footprints(w) {
                        for (s, t) in [(0.5, 0.5), (0.01, 0.99), (-3.3, 7.7)] {
                            let got = data.sample(&opts, Vec4::ONE, s, t, &fp);
                            assert!((got - c).abs().max_element() < 1e-4, "{filter:?} {wrap:?} {mip:?} {fp:?}: {got}");
                        }
                    }
                }
            }
        }
    }

    /// Issue 19: footprints of 1e5 and 1e30 periods and NaN or infinite ones end under every filter (EWA
    /// looped over the whole ellipse on the 1 x 1 level, the SAT's sums overflowed to NaN) with a finite
    /// value, and but for NaN with the texture's mean under the MIP filters. The reconstruction filters and
    /// the reference read a fixed number of taps whatever the footprint (tried with `Repeat` only: far-off
    /// coordinates under the other modes are not the point here).
    #[test]
    fn huge_and_non_finite_footprints_end_under_every_filter() {
        let (w, h) = (37, 23);
        let texels: Vec<Vec4> =
            (0..w * h).map(|k| Vec4::new((k % 5) as f32 / 4.0, (k % 3) as f32 / 2.0, 0.5, 1.0)).collect();
        let mean = texels.iter().copied().sum::<Vec4>() / (w * h) as f32;
        for wrap in [Wrap::Repeat, Wrap::Clamp, Wrap::Mirror, Wrap::Border] {
            let data =
                Filterable::new(Plane { width: w, height: h, texels: texels.clone() }, MipFilter::Box, [wrap; 2]);
            for filter in every_filter() {
                let fixed = matches!(filter, Filter::Reconstruct(_) | Filter::Reference);
                if fixed && wrap != Wrap::Repeat {
                    continue;
                }
                let opts = FilterOptions { filter, ..FilterOptions::default() };
                for k in [1e5, 1e30, f32::NAN, f32::INFINITY] {
                    let fp = Footprint { dudx: k, dvdx: 0.3 * k, dudy: -0.2 * k, dvdy: 0.9 * k };
                    let got = data.sample(&opts, Vec4::ONE, 0.3, 0.6, &fp);
                    if !fixed {
                        assert!(got.is_finite(), "{filter:?} {wrap:?} {k}: {got}");
                    }
                    if !k.is_nan() && !fixed && wrap != Wrap::Border {
                        assert!((got - mean).abs().max_element() < 1e-3, "{filter:?} {wrap:?} {k}: {got} vs {mean}");
                    }
                }
            }
        }
    }

    /// Far outside a texture with `border` wrap, every filter returns the border colour; with `clamp`, the
    /// edge texel's colour.
    #[test]
    fn border_and_clamp_outside_the_texture() {
        let (w, h) = (16, 8);
        let texels =
            (0..w * h).map(|k| if k % w == w - 1 { Vec4::new(0.0, 1.0, 0.0, 1.0) } else { Vec4::ONE }).collect();
        let plane = Plane { width: w, height: h, texels };
        let border = Vec4::new(1.0, 0.0, 0.0, 1.0);
        let bordered = Filterable::new(plane.clone(), MipFilter::Box, [Wrap::Border; 2]);
        let clamped = Filterable::new(plane, MipFilter::Box, [Wrap::Clamp, Wrap::Repeat]);
        let fp = Footprint { dudx: 0.5 / w as f32, dvdx: 0.0, dudy: 0.0, dvdy: 0.5 / h as f32 };
        for filter in every_filter() {
            let opts = FilterOptions { filter, ..FilterOptions::default() };
            let got = bordered.sample(&opts, border, 3.0, 0.5, &fp);
            assert!((got - border).abs().max_element() < 1e-5, "{filter:?} border: {got}");
            // To the right of the green last column, clamped: green.
            let got = clamped.sample(&opts, border, 1.8, 0.5, &fp);
            assert!((got - Vec4::new(0.0, 1.0, 0.0, 1.0)).abs().max_element() < 1e-5, "{filter:?} clamp: {got}");
        }
    }

    /// A ramp in u: every filter returns the ramp's value at the footprint's centre, away from the edges.
    #[test]
    fn linear_ramp_returns_its_value_at_the_centre() {
        let (w, h) = (256, 128);
        let texels = (0..w * h).map(|k| ((k % w) as f32 + 0.5) / w as f32).collect();
        let data = Filterable::new(Plane { width: w, height: h, texels }, MipFilter::Box, [Wrap::Clamp; 2]);
        let texel = 1.0 / w as f32;
        for filter in every_filter() {
            let opts = FilterOptions { filter, reference_samples: 16, ..FilterOptions::default() };
            for fp in footprints(w).into_iter().filter(|fp| fp.dudx.abs() * w as f32 <= 24.0) {
                for (s, t) in [(0.5, 0.5), (0.4123, 0.55), (0.61, 0.47)] {
                    let got = data.sample(&opts, 0.0, s, t, &fp);
                    // Nearest returns the value of the texel the centre lies in.
                    let want = if filter == Filter::Reconstruct(Kernel::Nearest) {
                        ((s * w as f32).floor() + 0.5) / w as f32
                    } else {
                        s
                    };
                    assert!((got - want).abs() < 0.25 * texel, "{filter:?} {fp:?} at {s}: {got} vs {want}");
                }
            }
        }
    }
}
