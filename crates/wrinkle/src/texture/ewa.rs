//! Elliptical weighted average (Heckbert 1989): the pixel's footprint is an ellipse in texture space, and
//! the texture is averaged under a Gaussian over that ellipse, on the MIP level whose texels the ellipse
//! covers a bounded number of.
//!
//! The ellipse, derived again. With J = [[ux, uy], [vx, vy]] (ux = du/dx, vx = dv/dx, uy = du/dy,
//! vy = dv/dy) the pixel offset c = (x, y) lands at p = J c in texture space. The circle |c| = r maps to
//! the points with |J^-1 p| = r, i.e. p^T (J J^T)^-1 p = r^2. With
//!     J J^T = [[ux^2 + uy^2, ux vx + uy vy], [ux vx + uy vy, vx^2 + vy^2]],
//!     (J J^T)^-1 = adj(J J^T) / det(J J^T),  det(J J^T) = det(J)^2 = (ux vy - uy vx)^2,
//! multiplying out p^T adj(J J^T) p = det gives A u^2 + B u v + C v^2 = F r^2 with
//!     A = vx^2 + vy^2,  B = -2 (ux vx + uy vy),  C = ux^2 + uy^2,  F = (ux vy - uy vx)^2 = A C - B^2 / 4,
//! which are Heckbert's coefficients (the slides' copy lost characters in extraction).
//!
//! The same algebra holds for any covariance matrix V in place of J J^T: a Gaussian pixel filter of
//! standard deviation PIXEL_SIGMA maps to the covariance PIXEL_SIGMA^2 J J^T, and convolving with the
//! texel reconstruction Gaussian adds RECON_SIGMA^2 I to it (Heckbert's "add 1 to A and C"). The weight of
//! a texel at offset p is exp(-Q / 2) with Q = (A u^2 + B u v + C v^2) / F computed from that V.

use super::reconstruct::{bilinear, Addressing};
use super::texel::{Texel, TexelSource};
use super::{Footprint, Wrap};
use crate::lanes::{lane_index, F8, I8, LANES};
use glam::Vec2;
use std::sync::OnceLock;

/// Standard deviations of the pixel's Gaussian (in pixels) and of the texel reconstruction Gaussian (in
/// texels of the level read): a little above those of the one-pixel box (0.289) and of the bilinear tent
/// (0.408) that the ground truth integrates. These measured best against it on the grazing plane (wider
/// Gaussians blur, narrower ones alias; docs/filtering.md).
const PIXEL_SIGMA: f32 = 0.3;
const RECON_SIGMA: f32 = 0.42;
/// The Gaussian is cut where Q reaches RADIUS^2 (2.5 standard deviations: weight 4%).
const RADIUS: f32 = 2.5;
const TABLE_SIZE: usize = 256;
/// The relative widening of R^2 for the rows' spans (see `Ellipse::spans`).
const SPAN_SLACK: f32 = 0.01;
/// Q times this is the table index.
const Q_TO_INDEX: f32 = TABLE_SIZE as f32 / (RADIUS * RADIUS);
/// The farthest an ellipse's centre is placed from the origin, in texels.
const FAR: f32 = (1 << 24) as f32;

/// The most texels one lookup reads, whatever the footprint. On the level read the ellipse's axes are at
/// most 2 `max_aniso` texels: the minor axis is one to two texels there and the eccentricity clamp keeps
/// the major within `max_aniso` of it, and a footprint beyond the coarsest level is squeezed or shrunk
/// to fit (`Ellipse::on_level`). The Gaussian's covariance then has no eigenvalue above
/// (2 PIXEL_SIGMA max_aniso)^2 + RECON_SIGMA^2, so the cut-off ellipse lies in a square of side 2 H with
/// H = RADIUS sqrt of that, which holds at most (floor(2 H) + 1)^2 texels: 2401 for `max_aniso` = 16,
/// 37249 for 64. (The spans read the ellipse, not its box: about 85 texels for 16:1, at most 142.)
#[cfg(test)]
pub fn max_texels(max_aniso: f32) -> usize {
    let major = 2.0 * PIXEL_SIGMA * max_aniso;
    let h = RADIUS * (major * major + RECON_SIGMA * RECON_SIGMA).sqrt();
    let side = (2.0 * h).floor() as usize + 1;
    side * side
}

/// Heckbert's conic A u^2 + B u v + C v^2 = F of the image of the unit circle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Conic {
    pub a: f32,
    pub b: f32,
    pub c: f32,
    pub f: f32,
}

impl Conic {
    /// Heckbert's coefficients from the derivatives (the tests' reference for `of_covariance`).
    #[cfg(test)]
    pub fn heckbert(ux: f32, vx: f32, uy: f32, vy: f32) -> Conic {
        Conic {
            a: vx * vx + vy * vy,
            b: -2.0 * (ux * vx + uy * vy),
            c: ux * ux + uy * uy,
            f: (ux * vy - uy * vx) * (ux * vy - uy * vx),
        }
    }

    /// The conic of the Gaussian with covariance [[v11, v12], [v12, v22]]: A = v22, B = -2 v12, C = v11,
    /// F = det V (the adjugate form above).
    pub fn of_covariance(v11: f32, v12: f32, v22: f32) -> Conic {
        Conic { a: v22, b: -2.0 * v12, c: v11, f: v11 * v22 - v12 * v12 }
    }

    /// (A u^2 + B u v + C v^2) / F: 1 on the ellipse.
    #[cfg(test)]
    pub fn q(&self, u: f32, v: f32) -> f32 {
        (self.a * u * u + self.b * u * v + self.c * v * v) / self.f
    }
}

/// The ellipse's semi-axes in texels: `major` along the unit vector `dir`, `minor` across it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Axes {
    pub major: f32,
    pub minor: f32,
    pub dir: Vec2,
}

impl Axes {
    /// The singular values and major direction of J, from the eigen decomposition of J J^T (robust for
    /// degenerate footprints, where F = 0 and the conic has no inverse).
    pub fn of_jacobian(ux: f32, vx: f32, uy: f32, vy: f32) -> Axes {
        let (p, q, r) = (ux * ux + uy * uy, ux * vx + uy * vy, vx * vx + vy * vy);
        let mean = 0.5 * (p + r);
        let d = (0.25 * (p - r) * (p - r) + q * q).sqrt();
        let (big, small) = (mean + d, (mean - d).max(0.0));
        let dir = if q.abs() > 1e-12 * (p + r) {
            Vec2::new(q, big - p).normalize()
        } else if p >= r {
            Vec2::X
        } else {
            Vec2::Y
        };
        Axes { major: big.sqrt(), minor: small.sqrt(), dir }
    }

    /// The footprint's axes in texels of a `w` x `h` level.
    pub fn of_footprint(fp: &Footprint, w: usize, h: usize) -> Axes {
        let [ux, vx, uy, vy] = fp.in_texels(w, h);
        Axes::of_jacobian(ux, vx, uy, vy)
    }

    /// The minor axis raised so that major / minor is at most `max_aniso` (the eccentricity clamp): very
    /// thin ellipses would otherwise touch thousands of texels on a fine level.
    pub fn clamped(self, max_aniso: f32) -> Axes {
        Axes { minor: self.minor.max(self.major / max_aniso), ..self }
    }
}

/// exp(-Q / 2) at Q = k R^2 / TABLE_SIZE, and zero at k = TABLE_SIZE: the weight beyond the cut.
fn weights() -> &'static [f32; TABLE_SIZE + 1] {
    static TABLE: OnceLock<[f32; TABLE_SIZE + 1]> = OnceLock::new();
    TABLE.get_or_init(|| {
        std::array::from_fn(|k| {
            let q = k as f32 / TABLE_SIZE as f32 * RADIUS * RADIUS;
            if k < TABLE_SIZE {
                (-0.5 * q).exp()
            } else {
                0.0
            }
        })
    })
}

/// EWA over a MIP pyramid (`levels[0]` the full texture) at (s, t) for footprint `fp`.
pub fn sample<S: TexelSource>(
    levels: &[S],
    addr: &Addressing<S::Texel>,
    s: f32,
    t: f32,
    fp: &Footprint,
    max_aniso: f32,
) -> S::Texel {
    let Some((level, ellipse)) = Ellipse::on_level(levels, addr, s, t, fp, max_aniso) else {
        return bilinear(&levels[levels.len() - 1], addr, s, t);
    };
    let src = &levels[level];
    let (sum, wsum) = if ellipse.inside(src.width(), src.height()) {
        ellipse.sum_inside(src)
    } else {
        ellipse.sum_wrapped(src, addr)
    };
    if wsum > 0.0 {
        sum * (1.0 / wsum)
    } else {
        bilinear(src, addr, s, t)
    }
}

/// The Gaussian's cut-off ellipse Q = R^2 on the level read, in that level's texels.
struct Ellipse {
    /// The centre, in texel index units (texel i's centre at i).
    cx: f32,
    cy: f32,
    /// Q(dx, dy) = ka dx^2 + kb dx dy + kc dy^2 at the offset (dx, dy) from the centre.
    ka: f32,
    kb: f32,
    kc: f32,
    /// The bounding box: columns i0..=i1, rows j0..=j1.
    i0: isize,
    i1: isize,
    j0: isize,
    j1: isize,
    /// 1 / (2 ka), for the roots along a row.
    half_over_ka: f32,
    table: &'static [f32; TABLE_SIZE + 1],
}

impl Ellipse {
    /// The level whose texels the footprint's minor axis covers one to two of (the coarsest for larger
    /// footprints), and the ellipse on it, within `max_texels`; `None` for a footprint with no finite
    /// extent (infinite or NaN derivatives).
    fn on_level<S: TexelSource>(
        levels: &[S],
        addr: &Addressing<S::Texel>,
        s: f32,
        t: f32,
        fp: &Footprint,
        max_aniso: f32,
    ) -> Option<(usize, Ellipse)> {
        let (w0, h0) = (levels[0].width(), levels[0].height());
        let axes = Axes::of_footprint(fp, w0, h0).clamped(max_aniso);
        if !(axes.major.is_finite()) {
            return None;
        }
        // The level where the minor axis is one to two texels, so the major is at most 2 max_aniso.
        let last = levels.len() - 1;
        let level = if axes.minor > 1.0 { (axes.minor.log2() as usize).min(last) } else { 0 };
        let (w, h) = (levels[level].width(), levels[level].height());
        // This level's texels per texel of level 0, along u and v. Where the level is one texel wide and
        // shows no border the texture is constant along that axis, so the ellipse's extent there changes
        // nothing: it is squeezed to two texels. A footprint beyond the coarsest level so reads its
        // 1 x 1 texel, the texture's mean, with a handful of taps.
        let (dx, dy) = (axes.dir.x, axes.dir.y);
        let scale = |n: usize, n0: usize, wrap: Wrap, along: f32, across: f32| {
            let s = n as f32 / n0 as f32;
            if n == 1 && wrap != Wrap::Border {
                // The ellipse reaches this far along the axis, in texels of level 0.
                s.min(2.0 / (along * axes.major).hypot(across * axes.minor))
            } else {
                s
            }
        };
        let (sx, sy) = (scale(w, w0, addr.wrap[0], dx, dy), scale(h, h0, addr.wrap[1], dy, dx));
        // The work bound (`max_texels`): the axes at most 2 max_aniso texels of this level. The level
        // choice keeps ordinary footprints within it; this shrinks those that outgrow the coarsest level.
        let fit = (2.0 * max_aniso / (axes.major * sx.max(sy))).min(1.0);
        // The axis vectors in this level's texels, scaled by the pixel Gaussian.
        let a1 = Vec2::new(dx * sx, dy * sy) * (axes.major * fit * PIXEL_SIGMA);
        let a2 = Vec2::new(-dy * sx, dx * sy) * (axes.minor * fit * PIXEL_SIGMA);
        let recon = RECON_SIGMA * RECON_SIGMA;
        let (v11, v12, v22) =
            (a1.x * a1.x + a2.x * a2.x + recon, a1.x * a1.y + a2.x * a2.y, a1.y * a1.y + a2.y * a2.y + recon);
        let conic = Conic::of_covariance(v11, v12, v22);
        // The ellipse Q = R^2 reaches R sqrt(v11) along u and R sqrt(v22) along v.
        let (hx, hy) = (RADIUS * v11.sqrt(), RADIUS * v22.sqrt());
        // Beyond 2^24 texels f32 cannot place a texel; held there (clamp, mirror and border coordinates far
        // off the texture), every index stays far from overflow.
        let cx = (addr.wrap[0].reduce(s) * w as f32 - 0.5).clamp(-FAR, FAR);
        let cy = (addr.wrap[1].reduce(t) * h as f32 - 0.5).clamp(-FAR, FAR);
        let ka = conic.a / conic.f;
        let ellipse = Ellipse {
            cx,
            cy,
            ka,
            kb: conic.b / conic.f,
            kc: conic.c / conic.f,
            i0: (cx - hx).ceil() as isize,
            i1: (cx + hx).floor() as isize,
            j0: (cy - hy).ceil() as isize,
            j1: (cy + hy).floor() as isize,
            half_over_ka: 0.5 / ka,
            table: weights(),
        };
        Some((level, ellipse))
    }

    /// Whether the bounding box lies on a `w` x `h` texture: no wrap to resolve per texel.
    fn inside(&self, w: usize, h: usize) -> bool {
        self.i0 >= 0 && self.j0 >= 0 && (self.i1 as usize) < w && (self.j1 as usize) < h
    }

    /// The columns of the eight rows from `first` that can be inside the ellipse (first and last column
    /// of each, empty where last < first): between the roots of ka dx^2 + (kb dy) dx + kc dy^2 =
    /// R^2 (1 + SPAN_SLACK), within the bounding box. The slack widens each span by at least 0.005 texels
    /// (Q's slope at the ellipse is at most 2 R sqrt(ka), ka at most 1 / RECON_SIGMA^2), more than the
    /// roots' rounding (1e-3 texels at 4096 texels from the origin): every texel the weights keep is in.
    #[inline]
    fn spans(&self, first: isize) -> ([i32; LANES], [i32; LANES]) {
        let dy = F8::splat(first as f32) + lane_index() - F8::splat(self.cy);
        let (qb, qc) = (F8::splat(self.kb) * dy, F8::splat(self.kc) * dy * dy);
        let disc = qb * qb - F8::splat(4.0 * self.ka) * (qc - F8::splat(RADIUS * RADIUS * (1.0 + SPAN_SLACK)));
        let half = disc.fast_max(F8::ZERO).sqrt() * F8::splat(self.half_over_ka);
        let mid = F8::splat(self.cx) - qb * F8::splat(self.half_over_ka);
        let (i0, i1) = (I8::splat(self.i0 as i32), I8::splat(self.i1 as i32));
        let lo = (mid - half).ceil().fast_trunc_int().max(i0);
        let hi = (mid + half).floor().fast_trunc_int().min(i1);
        (lo.to_array(), hi.to_array())
    }

    /// The table indices of the eight columns from `first` in row j: Q scaled so that R^2 reads entry
    /// TABLE_SIZE (zero), computed operation for operation as the original `(scaled Q) as usize` (negative
    /// rounding noise reads entry 0).
    #[inline]
    fn indices(&self, first: i32, j: isize) -> [i32; LANES] {
        let dy = j as f32 - self.cy;
        let (qb, qc) = (self.kb * dy, self.kc * dy * dy);
        let dx = F8::splat(first as f32) + lane_index() - F8::splat(self.cx);
        let q = ((F8::splat(self.ka) * dx + F8::splat(qb)) * dx + F8::splat(qc)) * F8::splat(Q_TO_INDEX);
        q.fast_max(F8::ZERO).fast_min(F8::splat(TABLE_SIZE as f32)).fast_trunc_int().to_array()
    }

    /// The weighted sum and the sum of weights over row j's columns `lo..=hi`, `fetch(i, j)` reading
    /// texel (i, j); eight columns' weights at a time.
    #[inline]
    fn sum_row<T: Texel>(&self, j: isize, lo: i32, hi: i32, fetch: &impl Fn(isize, isize) -> T) -> (T, f32) {
        let (mut sum, mut wsum) = (T::default(), 0.0);
        // Exclusive ranges: their iterators compile to plainer loops than inclusive ones.
        for first in (lo..hi + 1).step_by(LANES) {
            let k = self.indices(first, j);
            for (i, &k) in (first..hi + 1).zip(&k) {
                let weight = self.table[k as usize];
                sum = sum + fetch(i as isize, j) * weight;
                wsum += weight;
            }
        }
        (sum, wsum)
    }

    /// The weighted sum and the sum of weights over the ellipse, `fetch(i, j)` reading texel (i, j) and
    /// `prefetch(i, j)` asking for it ahead.
    #[inline]
    fn sum<T: Texel>(&self, fetch: impl Fn(isize, isize) -> T, prefetch: impl Fn(i32, isize)) -> (T, f32) {
        let (mut sum, mut wsum) = (T::default(), 0.0);
        for first in (self.j0..self.j1 + 1).step_by(LANES) {
            let (lo, hi) = self.spans(first);
            // Both ends of the next eight rows first, so that their cache misses overlap (an anisotropic
            // ellipse's rows are a few texels long: one or two cache lines each).
            for ((j, &lo), &hi) in (first..self.j1 + 1).zip(&lo).zip(&hi).filter(|((_, lo), hi)| lo <= hi) {
                prefetch(lo, j);
                prefetch(hi, j);
            }
            for ((j, lo), hi) in (first..self.j1 + 1).zip(lo).zip(hi) {
                // A sum per row: the rows' dependency chains overlap.
                let (row_sum, row_wsum) = self.sum_row(j, lo, hi, &fetch);
                sum = sum + row_sum;
                wsum += row_wsum;
            }
        }
        (sum, wsum)
    }

    /// The weighted sum and the sum of weights, the whole ellipse on the texture.
    fn sum_inside<S: TexelSource>(&self, src: &S) -> (S::Texel, f32) {
        self.sum(|i, j| src.texel(i as usize, j as usize), |i, j| src.prefetch(i as usize, j as usize))
    }

    /// The same where the ellipse crosses an edge: every texel through the wrap modes.
    fn sum_wrapped<S: TexelSource>(&self, src: &S, addr: &Addressing<S::Texel>) -> (S::Texel, f32) {
        self.sum(|i, j| addr.fetch(src, i, j), |_, _| {})
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::mip::{MipFilter, Resample};
    use crate::texture::rgba8::Rgba8Plane;
    use crate::texture::texel::Plane;
    use crate::texture::Filterable;
    use glam::Vec4;
    use std::sync::atomic::{AtomicUsize, Ordering};

    /// A circle of radius r in pixels maps, through J, onto Heckbert's ellipse A u^2 + B u v + C v^2 = F r^2.
    #[test]
    fn circle_of_radius_r_maps_to_heckberts_ellipse() {
        let (ux, vx, uy, vy) = (3.0f32, 1.0, -0.5, 2.0);
        let conic = Conic::heckbert(ux, vx, uy, vy);
        assert!((conic.f - (conic.a * conic.c - 0.25 * conic.b * conic.b)).abs() < 1e-3);
        for r in [0.5f32, 1.0, 2.0] {
            for k in 0..16 {
                let th = k as f32 * std::f32::consts::TAU / 16.0;
                let (x, y) = (r * th.cos(), r * th.sin());
                let (u, v) = (ux * x + uy * y, vx * x + vy * y);
                assert!((conic.q(u, v) - r * r).abs() < 1e-4 * r * r, "r {r} angle {th}: {}", conic.q(u, v));
            }
        }
        // The axes: a pure scale by 4 along u and 1 along v, rotated by 30 degrees.
        let (c, s) = (30f32.to_radians().cos(), 30f32.to_radians().sin());
        let ax = Axes::of_jacobian(4.0 * c, 4.0 * s, -s, c);
        assert!((ax.major - 4.0).abs() < 1e-4 && (ax.minor - 1.0).abs() < 1e-4, "{ax:?}");
        assert!((ax.dir.dot(Vec2::new(c, s)).abs() - 1.0).abs() < 1e-5);
        // The eccentricity clamp.
        let thin = Axes::of_jacobian(64.0, 0.0, 0.0, 0.5).clamped(16.0);
        assert_eq!((thin.major, thin.minor), (64.0, 4.0));
    }

    /// The filter as first written: every texel of the bounding box through the wrap modes, weighted
    /// where Q < R^2.
    fn brute_force<S: TexelSource>(
        levels: &[S],
        addr: &Addressing<S::Texel>,
        s: f32,
        t: f32,
        fp: &Footprint,
    ) -> S::Texel {
        let (level, e) = Ellipse::on_level(levels, addr, s, t, fp, 16.0).unwrap();
        let (mut sum, mut wsum) = (S::Texel::default(), 0.0);
        for j in e.j0..=e.j1 {
            let dy = j as f32 - e.cy;
            for i in e.i0..=e.i1 {
                let dx = i as f32 - e.cx;
                let k = (((e.ka * dx + e.kb * dy) * dx + e.kc * dy * dy) * Q_TO_INDEX) as usize;
                if k < TABLE_SIZE {
                    sum = sum + addr.fetch(&levels[level], i, j) * weights()[k];
                    wsum += weights()[k];
                }
            }
        }
        sum * (1.0 / wsum)
    }

    #[test]
    fn row_spans_sum_the_same_texels_as_the_bounding_box() {
        let mut random = xorshift();
        // A small texture, and a wide one where x reaches 2048 texels (coarser f32 steps in i - cx); f32
        // texels and 8-bit blocked ones (which prefetch).
        for ((w, h), wrap) in
            [(64, 48), (2048, 8)].into_iter().flat_map(|size| Wrap::NAMES.map(|(_, wrap)| (size, wrap)))
        {
            let texels = (0..w * h).map(|_| Vec4::new(random(), random(), random(), random())).collect();
            let base = Plane { width: w, height: h, texels };
            agrees_with_brute_force(&Filterable::new(base, MipFilter::Box, [wrap; 2]), &mut random);
            let bytes: Vec<[u8; 4]> = (0..w * h).map(|_| [0; 4].map(|_| (random() * 255.0) as u8)).collect();
            let base = Rgba8Plane::from_top_rows(w, h, &bytes, true);
            agrees_with_brute_force(&Filterable::new(base, MipFilter::Box, [wrap; 2]), &mut random);
        }
    }

    /// A uniform random number in [0, 1), the same sequence on every run.
    fn xorshift() -> impl FnMut() -> f32 {
        let mut seed = 0x2545_F491_4F6C_DD1Du64;
        move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 40) as f32 / (1u64 << 24) as f32
        }
    }

    /// 2000 lookups of widths from 1/4096 to 1/8, isotropic and 8:1, half of them across the texture's edges,
    /// against the bounding-box loop.
    fn agrees_with_brute_force<S: Resample<Texel = Vec4>>(data: &Filterable<S>, random: &mut impl FnMut() -> f32) {
        let wrap = data.wrap()[0];
        let addr = Addressing { wrap: [wrap; 2], border: Vec4::new(0.9, 0.1, 0.5, 1.0) };
        for k in 0..2000 {
            let (ratio, width, angle) =
                (if k % 2 == 0 { 1.0 } else { 8.0 }, 2f32.powf(-12.0 + 9.0 * random()), random() * 7.0);
            let (c, sn) = (angle.cos(), angle.sin());
            let fp =
                Footprint { dudx: ratio * width * c, dvdx: ratio * width * sn, dudy: -width * sn, dvdy: width * c };
            // Half the centres near a corner, so that the ellipse crosses the edges.
            let (s, t) =
                if k % 4 < 2 { (random(), random()) } else { (random() * 0.1 - 0.05, 1.0 + random() * 0.1 - 0.05) };
            let got = sample(data.levels(), &addr, s, t, &fp, 16.0);
            let want = brute_force(data.levels(), &addr, s, t, &fp);
            assert!((got - want).abs().max_element() < 1e-5, "{wrap:?} {fp:?} at ({s}, {t}): {got} vs {want}");
        }
    }

    /// A source that counts the texels read from it.
    struct Counting<'a, S> {
        src: &'a S,
        reads: AtomicUsize,
    }

    impl<S: TexelSource> TexelSource for Counting<'_, S> {
        type Texel = S::Texel;
        fn width(&self) -> usize {
            self.src.width()
        }
        fn height(&self) -> usize {
            self.src.height()
        }
        fn texel(&self, i: usize, j: usize) -> S::Texel {
            self.reads.fetch_add(1, Ordering::Relaxed);
            self.src.texel(i, j)
        }
    }

    /// One lookup and the number of texels it read, from every level.
    fn counted<S: TexelSource>(
        levels: &[S],
        addr: &Addressing<S::Texel>,
        (s, t): (f32, f32),
        fp: &Footprint,
        max_aniso: f32,
    ) -> (S::Texel, usize) {
        let counting: Vec<_> = levels.iter().map(|src| Counting { src, reads: AtomicUsize::new(0) }).collect();
        let got = sample(&counting, addr, s, t, fp, max_aniso);
        (got, counting.iter().map(|c| c.reads.load(Ordering::Relaxed)).sum())
    }

    /// An n:1 footprint `size` periods across its minor axis, at `angle`.
    fn footprint(size: f32, ratio: f32, angle: f32) -> Footprint {
        let (c, sn) = (angle.cos(), angle.sin());
        Footprint { dudx: ratio * size * c, dvdx: ratio * size * sn, dudy: -size * sn, dvdy: size * c }
    }

    #[test]
    fn max_texels_follows_its_formula() {
        assert_eq!(max_texels(16.0), 49 * 49);
        assert_eq!(max_texels(64.0), 193 * 193);
        assert_eq!(max_texels(1.0), 4 * 4);
    }

    /// Issue 19: a texture repeated 1e5 times across a pixel took EWA forever (the ellipse on the 1 x 1
    /// level was 1e5 texels wide). Every footprint, from a fraction of a texel to 1e30 periods and beyond
    /// the eccentricity clamp, reads at most `max_texels`; those beyond the coarsest level read the
    /// texture's mean (the 1 x 1 level), off a bordered texture a mix of the mean and the border colour.
    #[test]
    fn huge_footprints_read_the_mean_within_the_bound() {
        let mut random = xorshift();
        let border = Vec4::new(0.9, 0.1, 0.5, 1.0);
        // A square-ish texture, one whose rows run out of levels first, and a one-texel-wide one.
        for (w, h) in [(64, 48), (256, 4), (1, 9)] {
            let texels: Vec<Vec4> = (0..w * h).map(|_| Vec4::new(random(), random(), random(), 1.0)).collect();
            let mean = texels.iter().copied().sum::<Vec4>() / (w * h) as f32;
            for wrap in [Wrap::Repeat, Wrap::Clamp, Wrap::Mirror, Wrap::Border] {
                let plane = Plane { width: w, height: h, texels: texels.clone() };
                let data = Filterable::new(plane, MipFilter::Box, [wrap; 2]);
                let addr = Addressing { wrap: [wrap; 2], border };
                for max_aniso in [1.0, 16.0, 64.0] {
                    let bound = max_texels(max_aniso);
                    for k in 0..200 {
                        // Ordinary footprints: widths from 1/4096 to 8 texels.
                        let size = 2f32.powf(-12.0 + 15.0 * random()) / w.max(h) as f32;
                        let fp = footprint(size, 1.0 + 31.0 * random(), 7.0 * random());
                        let (_, reads) = counted(data.levels(), &addr, (random(), random()), &fp, max_aniso);
                        assert!(reads <= bound, "{w}x{h} {wrap:?} {fp:?}, {max_aniso}: {reads} > {bound}");
                        // Beyond the texture: 300 to 1e30 periods across.
                        let size = [300.0, 1e5, 1e12, 1e30][k % 4];
                        let fp = footprint(size, [1.0, 8.0, 1000.0][k % 3], 7.0 * random());
                        let (got, reads) = counted(data.levels(), &addr, (random(), random()), &fp, max_aniso);
                        assert!(reads <= bound, "{w}x{h} {wrap:?} {fp:?}, {max_aniso}: {reads} > {bound}");
                        if wrap == Wrap::Border {
                            let (lo, hi) = (mean.min(border), mean.max(border));
                            assert!(got.cmpge(lo - 1e-4).all() && got.cmple(hi + 1e-4).all(), "{got} {mean}");
                        } else {
                            // A handful of taps on the 1 x 1 level.
                            assert!(reads <= 16, "{w}x{h} {wrap:?} {fp:?}: {reads} texels");
                            let err = (got - mean).abs().max_element();
                            assert!(err < 1e-4, "{w}x{h} {wrap:?} {fp:?}: {got} vs the mean {mean}");
                        }
                    }
                }
            }
        }
    }

    /// NaN and infinite derivatives end at once, on the coarsest level (no loop over an unbounded box).
    #[test]
    fn non_finite_footprints_read_the_coarsest_level() {
        let texels: Vec<Vec4> = (0..64 * 48).map(|k| Vec4::splat((k % 7) as f32 / 6.0)).collect();
        let mean = texels.iter().copied().sum::<Vec4>() / texels.len() as f32;
        let data = Filterable::new(Plane { width: 64, height: 48, texels }, MipFilter::Box, [Wrap::Repeat; 2]);
        let addr = Addressing::repeat();
        for x in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY, f32::MAX] {
            for fp in [Footprint { dudx: x, ..footprint(0.01, 2.0, 0.3) }, footprint(x, 1.0, 0.0)] {
                let (got, reads) = counted(data.levels(), &addr, (0.3, 0.6), &fp, 16.0);
                assert!(reads <= 16, "{fp:?}: {reads} texels");
                assert!((got - mean).abs().max_element() < 1e-4, "{fp:?}: {got} vs {mean}");
            }
        }
    }

    #[test]
    fn covariance_conic_is_the_inverse() {
        let conic = Conic::of_covariance(4.0, 1.0, 2.0);
        // V^-1 = [[2, -1], [-1, 4]] / 7: Q(1, 0) = 2/7, Q(0, 1) = 4/7, Q(1, 1) = 4/7.
        assert!((conic.q(1.0, 0.0) - 2.0 / 7.0).abs() < 1e-6);
        assert!((conic.q(0.0, 1.0) - 4.0 / 7.0).abs() < 1e-6);
        assert!((conic.q(1.0, 1.0) - 4.0 / 7.0).abs() < 1e-6);
    }
}
