//! Filtering the distribution of a bump's normals, not its heights: the answer to the problem Blinn's
//! section 5 leaves open (averaging F smooths the bumps away instead of averaging their intensities).
//!
//! LEAN mapping (Olano and Baker 2010): the slopes b = (Fs, Ft) of the table and their products
//! (Fs^2, Ft^2, Fs Ft) are filtered linearly, by any texture filter over a pyramid of their means, so a
//! pixel receives the mean slope and the covariance of the slopes it covers,
//!     Sigma = E[b b^T] - E[b] E[b]^T.
//! The shading normal is the mean slope's; the covariance widens the specular lobe (shade/phong.rs).
//! Toksvig (2005) is the isotropic variant: the exponent s becomes s / (1 + s sigma^2), his formula with
//! sigma^2 = (1 - |Na|) / |Na| read from the same moments instead of a pyramid of averaged unit normals
//! (Blinn's normals depend on the surface's Pu and Pv, so no table-space normal pyramid can hold them).
//!
//! Level 0 of the pyramid is the table itself, its slopes and their squares made on the fly from the
//! central differences (as bump lookups do); only the coarser levels are stored, six floats a texel:
//! 24 bytes x 1/3 of the table's texels, 8 bytes per texel of the table (a 4096^2 table: 134 MB).

use super::table::Gradients;
use super::{BumpFormula, Gradient};
use crate::lanes::{F8, V3};
use crate::texture::filter::{Filter, FilterOptions, Filterable};
use crate::texture::mip::{resample, MipFilter, Resample};
use crate::texture::texel::{Plane, Texel, TexelSource};
use crate::texture::FilteredTexture;
use crate::texture::{Footprint, Wrap};
use glam::{DVec3, Mat3, Vec2, Vec3, Vec4};
use rayon::prelude::*;
use std::ops::{Add, Mul, Sub};

/// What a bump filter does about the spread of the normals under a pixel.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SlopeFilter {
    /// Nothing: the filtered F, Fu, Fv alone (Blinn's filtered table).
    #[default]
    Plain,
    /// LEAN mapping: the slopes' covariance shapes an anisotropic specular lobe.
    Lean,
    /// Toksvig: the slopes' variance lowers the Blinn-Phong exponent.
    Toksvig,
}

/// A bump's filter: the texture filter that reads its table (or its slopes' moments) and what it does
/// about the spread of the normals.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BumpFilter {
    pub texture: Filter,
    pub slopes: SlopeFilter,
}

impl BumpFilter {
    /// `none` (Blinn's bilinear FVAL on the full-resolution table), `mip` (his MIP-mapped table, the same
    /// as `trilinear`), any texture filter, `lean` and `toksvig` (through `trilinear`), or `lean:FILTER`
    /// and `toksvig:FILTER` through another texture filter.
    pub fn parse(name: &str) -> Option<BumpFilter> {
        let plain = |texture| BumpFilter { texture, slopes: SlopeFilter::Plain };
        let (spread, texture) = match name.split_once(':') {
            Some((spread, texture)) => (spread, Some(texture)),
            None => (name, None),
        };
        let slopes = match spread {
            "lean" => SlopeFilter::Lean,
            "toksvig" => SlopeFilter::Toksvig,
            _ if texture.is_some() => return None,
            "none" => return Some(plain(Filter::Reconstruct(crate::texture::reconstruct::Kernel::Bilinear))),
            "mip" => return Some(plain(Filter::Trilinear)),
            _ => return Filter::parse(name).map(plain),
        };
        let texture = match texture {
            Some(t) => Filter::parse(t)?,
            None => Filter::Trilinear,
        };
        Some(BumpFilter { texture, slopes })
    }

    /// Every name `parse` reads, for messages.
    pub fn names() -> String {
        format!("none, mip, {}, lean, toksvig, lean:FILTER, toksvig:FILTER", Filter::names())
    }
}

/// The covariance of two slopes: var(x), var(y), cov(x, y).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Spread {
    pub xx: f32,
    pub yy: f32,
    pub xy: f32,
}

impl Spread {
    /// The covariance of (r0 . b, r1 . b) where b has this covariance (R Sigma R^T, R's rows r0 and r1).
    #[inline]
    pub fn through(self, [r0, r1]: [Vec2; 2]) -> Spread {
        let quad = |a: Vec2, b: Vec2| a.x * b.x * self.xx + a.y * b.y * self.yy + (a.x * b.y + a.y * b.x) * self.xy;
        Spread { xx: quad(r0, r0), yy: quad(r1, r1), xy: quad(r0, r1) }
    }
}

/// The first and second moments of a table's slopes at one texel: (F, Fs, Ft) and (Fs^2, Ft^2, Fs Ft).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Moments {
    pub mean: Vec3,
    pub square: Vec3,
}

impl Moments {
    /// The moments of one texel's (T, Ts, Tt).
    #[inline]
    fn of(g: Vec3) -> Moments {
        Moments { mean: g, square: Vec3::new(g.y * g.y, g.z * g.z, g.y * g.z) }
    }
}

impl Add for Moments {
    type Output = Moments;
    #[inline]
    fn add(self, o: Moments) -> Moments {
        Moments { mean: self.mean + o.mean, square: self.square + o.square }
    }
}

impl Sub for Moments {
    type Output = Moments;
    #[inline]
    fn sub(self, o: Moments) -> Moments {
        Moments { mean: self.mean - o.mean, square: self.square - o.square }
    }
}

impl Mul<f32> for Moments {
    type Output = Moments;
    #[inline]
    fn mul(self, k: f32) -> Moments {
        Moments { mean: self.mean * k, square: self.square * k }
    }
}

/// `Moments` in f64, for summed-area tables.
#[derive(Clone, Copy, Debug, Default)]
pub struct WideMoments(DVec3, DVec3);

impl Add for WideMoments {
    type Output = WideMoments;
    fn add(self, o: WideMoments) -> WideMoments {
        WideMoments(self.0 + o.0, self.1 + o.1)
    }
}

impl Sub for WideMoments {
    type Output = WideMoments;
    fn sub(self, o: WideMoments) -> WideMoments {
        WideMoments(self.0 - o.0, self.1 - o.1)
    }
}

impl Mul<f64> for WideMoments {
    type Output = WideMoments;
    fn mul(self, k: f64) -> WideMoments {
        WideMoments(self.0 * k, self.1 * k)
    }
}

impl Texel for Moments {
    type Wide = WideMoments;
    fn widen(self) -> WideMoments {
        WideMoments(self.mean.as_dvec3(), self.square.as_dvec3())
    }
    fn narrow(w: WideMoments) -> Moments {
        Moments { mean: w.0.as_vec3(), square: w.1.as_vec3() }
    }
}

/// One level of the moments: the table's own (made from its texels as they are read) or stored.
#[derive(Clone, Debug)]
pub enum MomentLevel {
    Table(Gradients),
    Stored(Plane<Moments>),
}

impl TexelSource for MomentLevel {
    type Texel = Moments;
    #[inline]
    fn width(&self) -> usize {
        match self {
            MomentLevel::Table(g) => g.width(),
            MomentLevel::Stored(p) => p.width,
        }
    }
    #[inline]
    fn height(&self) -> usize {
        match self {
            MomentLevel::Table(g) => g.height(),
            MomentLevel::Stored(p) => p.height,
        }
    }
    #[inline]
    fn texel(&self, i: usize, j: usize) -> Moments {
        match self {
            MomentLevel::Table(g) => Moments::of(g.texel(i, j)),
            MomentLevel::Stored(p) => p.texel(i, j),
        }
    }
    #[inline]
    fn quad(&self, i: [usize; 2], j: [usize; 2]) -> [Moments; 4] {
        match self {
            MomentLevel::Table(g) => g.quad(i, j).map(Moments::of),
            MomentLevel::Stored(p) => p.quad(i, j),
        }
    }
    #[inline]
    fn add_row(&self, j: usize, weight: f32, sum: &mut [Moments]) {
        match self {
            MomentLevel::Table(g) => {
                for (i, s) in sum.iter_mut().enumerate() {
                    *s = *s + Moments::of(g.texel(i, j)) * weight;
                }
            }
            MomentLevel::Stored(p) => p.add_row(j, weight, sum),
        }
    }
}

impl Resample for MomentLevel {
    fn downsample(&self, nw: usize, nh: usize, filter: MipFilter, wrap: [Wrap; 2]) -> Self {
        MomentLevel::Stored(resample(self, nw, nh, filter, wrap))
    }
}

/// A table's slopes and their products, filterable by every texture filter.
pub struct SlopeMoments(Filterable<MomentLevel>);

impl SlopeMoments {
    /// The pyramid of a periodic table's moments (box-filtered levels: each is the exact mean of the
    /// texels it covers, so the variance it gives is the slopes' own).
    pub fn of_table(table: Gradients) -> SlopeMoments {
        SlopeMoments(Filterable::new(MomentLevel::Table(table), MipFilter::Box, [Wrap::Repeat; 2]))
    }

    /// The moments of the slopes a texture stores, `slope` decoding each texel of level 0 (F reads 0),
    /// wrapped as the texture is.
    pub fn of_texture(texture: &FilteredTexture, slope: impl Fn(Vec4) -> Vec2 + Sync) -> SlopeMoments {
        let (width, height) = texture.size();
        let mut texels = vec![Moments::default(); width * height];
        texels.par_chunks_mut(width.max(1)).enumerate().for_each(|(j, row)| {
            for (i, m) in row.iter_mut().enumerate() {
                let b = slope(texture.texel(i, j));
                *m = Moments::of(Vec3::new(0.0, b.x, b.y));
            }
        });
        let base = MomentLevel::Stored(Plane { width, height, texels });
        SlopeMoments(Filterable::new(base, MipFilter::Box, texture.options().wrap))
    }

    /// The mean (F, Fs, Ft) at (s,t) under the filter of `opts` and the covariance of (Fs, Ft) there.
    ///
    /// The covariance includes the spread of the texels the filter blends. Where the pixel spans less than
    /// a texel along s (or t), part of that spread is the filter kernel's, not the pixel's: a footprint
    /// f texels wide there sees about f^2 of it, so each axis is scaled by f^2 up to 1 (and plain bump
    /// mapping returns at magnification).
    #[inline]
    pub fn lookup(&self, s: f32, t: f32, fp: &Footprint, opts: &FilterOptions) -> (Gradient, Spread) {
        let m = self.0.sample(opts, Moments::default(), s, t, fp);
        let [ux, vx, uy, vy] = fp.in_texels(self.0.width(), self.0.height());
        let (share_s, share_t) = ((ux * ux + uy * uy).min(1.0), (vx * vx + vy * vy).min(1.0));
        let (fs, ft) = (m.mean.y, m.mean.z);
        let spread = Spread {
            xx: (m.square.x - fs * fs).max(0.0) * share_s,
            yy: (m.square.y - ft * ft).max(0.0) * share_t,
            xy: (m.square.z - fs * ft) * (share_s * share_t).sqrt(),
        };
        (Gradient { f: m.mean.x, fu: fs, fv: ft }, spread)
    }

    /// The level count (for tests and statistics).
    pub fn levels(&self) -> &[MomentLevel] {
        self.0.levels()
    }
}

/// Eight samples' slope covariance in the tangent plane of their world shading normal: along `t1` and
/// `t2` (unit, perpendicular to it and to each other).
#[derive(Clone, Copy, Debug)]
pub struct WorldSpread8 {
    pub t1: V3,
    pub t2: V3,
    pub xx: F8,
    pub yy: F8,
    pub xy: F8,
}

impl WorldSpread8 {
    /// The covariance `c` of (Fu, Fv) carried to the world normal `n` (unit) of a surface with Pu, Pv.
    /// Blinn's N' = N + Fu A - Fv B with A = N x Pv / |N| and B = N x Pu / |N| is linear in (Fu, Fv): in the
    /// world (`normal_matrix`) the normal turns by the slopes (Fu a + Fv b) / |M N|, which are projected onto
    /// the tangent plane of n. The scale-invariant D' tilts by |(Fu, Fv)| itself: a and b of unit length
    /// (exact where the gradient runs along u or v, as a grid's grooves do). The sign of Pu x Pv (mirrored
    /// meshes) changes no covariance.
    #[inline]
    pub fn of(pu: V3, pv: V3, formula: BumpFormula, normal_matrix: &Mat3, n: V3, c: [F8; 3]) -> WorldSpread8 {
        let big_n = pu.cross(pv);
        let world = |d: V3| V3::mul_mat3(normal_matrix, d);
        let (a, b) = (world(big_n.cross(pv)), world(big_n.cross(pu)) * (-F8::ONE));
        let (a, b) = match formula {
            BumpFormula::Invariant => (a.normalize_or_zero(), b.normalize_or_zero()),
            _ => {
                let k = F8::ONE / (big_n.length() * world(big_n).length());
                (a * k, b * k)
            }
        };
        WorldSpread8::along(a, b, n, c)
    }

    /// The covariance `c` of a tangent-space normal map's slopes (x/z, y/z) at unit normals `n_obj` with
    /// tangents `t` and bitangents `bitangent` (object space): the normal n + x t + y b turns in the world
    /// by M t and M b over |M n|.
    #[inline]
    pub fn of_tangent_frame(t: V3, bitangent: V3, n_obj: V3, normal_matrix: &Mat3, n: V3, c: [F8; 3]) -> WorldSpread8 {
        let world = |d: V3| V3::mul_mat3(normal_matrix, d);
        let k = F8::ONE / world(n_obj).length();
        WorldSpread8::along(world(t) * k, world(bitangent) * k, n, c)
    }

    /// The covariance `c` of two slopes that turn the unit world normal `n` by `a` and `b` per unit, in the
    /// tangent plane of n.
    #[inline]
    fn along(a: V3, b: V3, n: V3, c: [F8; 3]) -> WorldSpread8 {
        let t1 = (a - n * n.dot(a)).normalize_or_zero();
        let t2 = n.cross(t1);
        let (j11, j12, j21, j22) = (a.dot(t1), b.dot(t1), a.dot(t2), b.dot(t2));
        let [cuu, cvv, cuv] = c;
        let quad = |p: F8, q: F8, r: F8, s: F8| p * r * cuu + q * s * cvv + (p * s + q * r) * cuv;
        WorldSpread8 {
            t1,
            t2,
            xx: quad(j11, j12, j11, j12),
            yy: quad(j21, j22, j21, j22),
            xy: quad(j11, j12, j21, j22),
        }
    }

    /// The mean of the two variances: the isotropic sigma^2 of Toksvig's formula.
    #[inline]
    pub fn isotropic(&self) -> F8 {
        (self.xx + self.yy) * F8::splat(0.5)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bump::BumpTable;
    use crate::image::Image;
    use std::f64::consts::TAU;

    #[test]
    fn names_parse() {
        let lean = BumpFilter::parse("lean").unwrap();
        assert_eq!((lean.texture, lean.slopes), (Filter::Trilinear, SlopeFilter::Lean));
        let t = BumpFilter::parse("toksvig:ewa").unwrap();
        assert_eq!((t.texture, t.slopes), (Filter::Ewa, SlopeFilter::Toksvig));
        assert_eq!(BumpFilter::parse("mip").unwrap().texture, Filter::Trilinear);
        assert_eq!(BumpFilter::parse("aniso").unwrap().slopes, SlopeFilter::Plain);
        for bad in ["lean:", "lean:bogus", "mip:ewa", "bogus", "ewa:lean"] {
            assert!(BumpFilter::parse(bad).is_none(), "{bad}");
        }
    }

    /// A sine grid T = A sin(2 pi k x / W) sin(2 pi k y / H): its slopes' moments at every MIP level against
    /// the analytic ones of the table's central differences. A level that averages whole periods has mean
    /// slope 0 and variance E[Fs^2] = (A 2 pi k sinc)^2 / 4 (the central difference's factor sin(w)/w).
    #[test]
    fn moments_of_a_sine_grid_match_their_analytic_values() {
        let (n, k, amp) = (64usize, 4.0f64, 0.5f64);
        let w = TAU * k / n as f64;
        let img =
            Image::from_fn(n, n, |x, y| (amp * (w * (x as f64 + 0.5)).sin() * (w * (y as f64 + 0.5)).sin()) as f32);
        let table = BumpTable::new(&img);
        let moments = table.moments();
        // Central differences: Ts = A n/2 (sin(w(x+1)) - sin(w(x-1))) sin(wy) = A n sin(w) cos(wx) sin(wy).
        let slope = amp * n as f64 * w.sin();
        // From level 3 (8 x 8) on, a texel covers whole periods of sin^2 and cos^2 (n / 2k texels) both ways.
        for (level, m) in moments.levels().iter().enumerate().skip(3) {
            let mid = m.texel(m.width() / 2, m.height() / 2);
            let want = slope * slope / 4.0;
            assert!(mid.mean.y.abs() < 1e-4 && mid.mean.z.abs() < 1e-4, "level {level}: {mid:?}");
            assert!((mid.square.x as f64 - want).abs() < 1e-3 * want, "level {level}: {} vs {want}", mid.square.x);
            assert!((mid.square.y as f64 - want).abs() < 1e-3 * want);
            assert!((mid.square.z as f64).abs() < 1e-3 * want, "cross term {}", mid.square.z);
        }
        // Level 1 (2x2 blocks): the exact mean of four texels' products, computed here.
        let level1 = &moments.levels()[1];
        let ts = |x: usize, y: usize| slope * (w * (x as f64 + 0.5)).cos() * (w * (y as f64 + 0.5)).sin();
        for (i, j) in [(3, 5), (10, 0), (31, 17)] {
            let want: f64 = (0..4).map(|q| ts(2 * i + q % 2, 2 * j + q / 2).powi(2)).sum::<f64>() / 4.0;
            let got = level1.texel(i, j).square.x as f64;
            assert!((got - want).abs() < 1e-3 * (1.0 + want), "({i},{j}): {got} vs {want}");
        }
        // Through the trilinear filter at the coarsest levels: variance and mean as above.
        let opts = FilterOptions { filter: Filter::Trilinear, ..FilterOptions::default() };
        let fp = Footprint { dudx: 0.5, dvdx: 0.0, dudy: 0.0, dvdy: 0.5 };
        let (g, spread) = moments.lookup(0.3, 0.7, &fp, &opts);
        let want = (slope * slope / 4.0) as f32;
        assert!(g.fu.abs() < 1e-3 && (spread.xx - want).abs() < 1e-3 * want && spread.xy.abs() < 1e-3 * want);
        // At the texel size the spread is whole; far below it, almost none (plain bump mapping).
        let tiny = Footprint { dudx: 0.01 / n as f32, dvdx: 0.0, dudy: 0.0, dvdy: 0.01 / n as f32 };
        let (g, spread) = moments.lookup(0.3, 0.7, &tiny, &opts);
        let plain = table.lookup(0.3, 0.7, &tiny, &opts);
        assert!((g.fu - plain.fu).abs() < 1e-3 * (1.0 + plain.fu.abs()) && spread.xx < 1e-4 * want);
    }

    /// The covariance carried through a 2x2 map: R Sigma R^T.
    #[test]
    fn spread_through_a_matrix() {
        let s = Spread { xx: 2.0, yy: 0.5, xy: 0.3 };
        let r = [Vec2::new(1.0, 2.0), Vec2::new(-0.5, 3.0)];
        let got = s.through(r);
        let m = |a: Vec2, b: Vec2| a.x * (s.xx * b.x + s.xy * b.y) + a.y * (s.xy * b.x + s.yy * b.y);
        assert!((got.xx - m(r[0], r[0])).abs() < 1e-5);
        assert!((got.yy - m(r[1], r[1])).abs() < 1e-5);
        assert!((got.xy - m(r[0], r[1])).abs() < 1e-5);
    }

    /// On a flat patch with orthonormal Pu, Pv and no transform, the world slopes are Fu and Fv themselves
    /// (up to their signs): the covariance keeps its variances and the magnitude of its cross term.
    #[test]
    fn world_spread_of_a_unit_patch() {
        let s = V3::splat;
        let n = s(Vec3::Z);
        let c = [F8::splat(0.04), F8::splat(0.01), F8::splat(0.005)];
        let w = WorldSpread8::of(s(Vec3::X), s(Vec3::Y), BumpFormula::Blinn, &Mat3::IDENTITY, n, c);
        assert!((w.xx.as_array_ref()[0] - 0.04).abs() < 1e-6 && (w.yy.as_array_ref()[0] - 0.01).abs() < 1e-6);
        assert!((w.xy.as_array_ref()[0].abs() - 0.005).abs() < 1e-6);
        assert!(w.t1.lane(3).dot(Vec3::Z).abs() < 1e-6 && w.t1.lane(3).dot(w.t2.lane(3)).abs() < 1e-6);
        // Scaled by 2 in the world: slopes halve (the bump's heights do not scale with the object).
        let w2 = WorldSpread8::of(s(Vec3::X * 2.0), s(Vec3::Y * 2.0), BumpFormula::Blinn, &Mat3::IDENTITY, n, c);
        assert!((w2.xx.as_array_ref()[0] - 0.01).abs() < 1e-6);
    }
}
