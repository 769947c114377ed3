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
use super::texel::TexelSource;
use super::Footprint;
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

/// Heckbert's conic A u^2 + B u v + C v^2 = F of the image of the unit circle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Conic {
    pub a: f32,
    pub b: f32,
    pub c: f32,
    pub f: f32,
}

impl Conic {
    /// Heckbert's coefficients from the derivatives.
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
    #[inline]
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

fn weights() -> &'static [f32; TABLE_SIZE + 1] {
    static TABLE: OnceLock<[f32; TABLE_SIZE + 1]> = OnceLock::new();
    TABLE.get_or_init(|| {
        std::array::from_fn(|k| {
            let q = k as f32 / TABLE_SIZE as f32 * RADIUS * RADIUS;
            (-0.5 * q).exp()
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
    let (w0, h0) = (levels[0].width(), levels[0].height());
    let axes = Axes::of_footprint(fp, w0, h0).clamped(max_aniso);
    let last = levels.len() - 1;
    if !(axes.major.is_finite()) {
        return bilinear(&levels[last], addr, s, t);
    }
    // The level where the minor axis is one to two texels: the ellipse then covers at most about
    // 2 x 2 max_aniso texels per standard deviation squared, whatever the footprint.
    let level = if axes.minor > 1.0 { (axes.minor.log2() as usize).min(last) } else { 0 };
    let src = &levels[level];
    let (w, h) = (src.width(), src.height());
    let (sx, sy) = (w as f32 / w0 as f32, h as f32 / h0 as f32);
    // The axis vectors in this level's texels, scaled by the pixel Gaussian.
    let a1 = Vec2::new(axes.dir.x * sx, axes.dir.y * sy) * (axes.major * PIXEL_SIGMA);
    let a2 = Vec2::new(-axes.dir.y * sx, axes.dir.x * sy) * (axes.minor * PIXEL_SIGMA);
    let recon = RECON_SIGMA * RECON_SIGMA;
    let (v11, v12, v22) =
        (a1.x * a1.x + a2.x * a2.x + recon, a1.x * a1.y + a2.x * a2.y, a1.y * a1.y + a2.y * a2.y + recon);
    let conic = Conic::of_covariance(v11, v12, v22);
    // The ellipse Q = R^2 reaches R sqrt(v11) along u and R sqrt(v22) along v.
    let (hx, hy) = (RADIUS * v11.sqrt(), RADIUS * v22.sqrt());
    let cx = addr.wrap[0].reduce(s) * w as f32 - 0.5;
    let cy = addr.wrap[1].reduce(t) * h as f32 - 0.5;
    let (i0, i1) = ((cx - hx).ceil() as isize, (cx + hx).floor() as isize);
    let (j0, j1) = ((cy - hy).ceil() as isize, (cy + hy).floor() as isize);
    let table = weights();
    let (ka, kb, kc) = (conic.a / conic.f, conic.b / conic.f, conic.c / conic.f);
    let to_index = TABLE_SIZE as f32 / (RADIUS * RADIUS);
    let mut sum = S::Texel::default();
    let mut wsum = 0.0f32;
    let inside = i0 >= 0 && j0 >= 0 && (i1 as usize) < w && (j1 as usize) < h;
    for j in j0..=j1 {
        let dy = j as f32 - cy;
        let (qb, qc) = (kb * dy, kc * dy * dy);
        if inside {
            // The whole ellipse lies on the texture: no wrap to resolve per texel.
            for i in i0..=i1 {
                let dx = i as f32 - cx;
                let k = (((ka * dx + qb) * dx + qc) * to_index) as usize;
                if k < TABLE_SIZE {
                    sum = sum + src.texel(i as usize, j as usize) * table[k];
                    wsum += table[k];
                }
            }
            continue;
        }
        let row = addr.wrap[1].resolve(j, h);
        for i in i0..=i1 {
            let dx = i as f32 - cx;
            let k = (((ka * dx + qb) * dx + qc) * to_index) as usize;
            if k < TABLE_SIZE {
                let texel = match (row, addr.wrap[0].resolve(i, w)) {
                    (Some(r), Some(c)) => src.texel(c, r),
                    _ => addr.border,
                };
                sum = sum + texel * table[k];
                wsum += table[k];
            }
        }
    }
    if wsum > 0.0 {
        sum * (1.0 / wsum)
    } else {
        bilinear(src, addr, s, t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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

    #[test]
    fn covariance_conic_is_the_inverse() {
        let conic = Conic::of_covariance(4.0, 1.0, 2.0);
        // V^-1 = [[2, -1], [-1, 4]] / 7: Q(1, 0) = 2/7, Q(0, 1) = 4/7, Q(1, 1) = 4/7.
        assert!((conic.q(1.0, 0.0) - 2.0 / 7.0).abs() < 1e-6);
        assert!((conic.q(0.0, 1.0) - 4.0 / 7.0).abs() < 1e-6);
        assert!((conic.q(1.0, 1.0) - 4.0 / 7.0).abs() < 1e-6);
    }
}
