//! Trilinear lookups of a repeating 8-bit texture on eight lanes, for the packet shader: the usual case of
//! a colour texture on a rendered surface. Levels, weights and tap positions are computed on all lanes at
//! once; the texel reads go lane by lane. The result equals `mip::trilinear` (within f32 rounding).

use super::rgba8::Rgba8Plane;
use super::texel::TexelSource;
use super::Footprint;
use crate::lanes::{CmpGt, F8, LANES};

/// RGBA as four channel lanes.
pub type Rgba8 = [F8; 4];

/// The trilinear lookup at (s, t) (one period per unit, repeating) with footprints `fp` in the same units,
/// the level chosen by the longest pixel axis (Williams 1983).
pub fn trilinear8(levels: &[Rgba8Plane], s: F8, t: F8, fp: &[Footprint; LANES]) -> Rgba8 {
    let (w, h) = (levels[0].width() as f32, levels[0].height() as f32);
    let lane = |f: fn(&Footprint) -> f32| F8::new(fp.map(|p| f(&p)));
    let (ux, vx) = (lane(|p| p.dudx) * F8::splat(w), lane(|p| p.dvdx) * F8::splat(h));
    let (uy, vy) = (lane(|p| p.dudy) * F8::splat(w), lane(|p| p.dvdy) * F8::splat(h));
    let len2 = (ux * ux + vx * vx).max(uy * uy + vy * vy);
    let last = (levels.len() - 1) as f32;
    // log2 of the longer axis, from its square; 0 below one texel.
    let level = len2.cmp_gt(F8::ONE).blend(F8::splat(0.5 * std::f32::consts::LOG2_E) * len2.ln(), F8::ZERO);
    let level = level.min(F8::splat(last));
    let l0 = level.floor();
    let frac = level - l0;
    let (s, t) = (s - s.floor(), t - t.floor());
    let l0 = l0.as_array_ref().map(|l| l as usize);
    let coarse = l0.map(|l| (l + 1).min(levels.len() - 1));
    let a = bilinear8(levels, &l0, s, t);
    if frac.cmp_gt(F8::ZERO).none() {
        return a;
    }
    let b = bilinear8(levels, &coarse, s, t);
    std::array::from_fn(|c| a[c] + (b[c] - a[c]) * frac)
}

/// Bilinear lookups at (s, t) in [0, 1), lane i on level `level[i]`, repeating.
#[inline]
fn bilinear8(levels: &[Rgba8Plane], level: &[usize; LANES], s: F8, t: F8) -> Rgba8 {
    let (w, h) = (F8::new(level.map(|l| levels[l].width as f32)), F8::new(level.map(|l| levels[l].height as f32)));
    let (x, y) = (s * w - F8::splat(0.5), t * h - F8::splat(0.5));
    let (xf, yf) = (x.floor(), y.floor());
    let (fx, fy) = (x - xf, y - yf);
    let (xf, yf) = (xf.as_array_ref(), yf.as_array_ref());
    // Texel i of lane l: [i0j0, i1j0, i0j1, i1j1] by channel.
    let mut taps = [[[0.0f32; LANES]; 4]; 4];
    for l in 0..LANES {
        let plane = &levels[level[l]];
        let (pw, ph) = (plane.width as i32, plane.height as i32);
        // x is in [-0.5, w - 0.5): the taps are floor(x) and the next, -1 and w wrapping round.
        let i0 = xf[l] as i32;
        let (i0, i1) = (if i0 < 0 { pw - 1 } else { i0 }, if i0 + 1 >= pw { 0 } else { i0 + 1 });
        let j0 = yf[l] as i32;
        let (j0, j1) = (if j0 < 0 { ph - 1 } else { j0 }, if j0 + 1 >= ph { 0 } else { j0 + 1 });
        for (k, (i, j)) in [(i0, j0), (i1, j0), (i0, j1), (i1, j1)].into_iter().enumerate() {
            let texel = plane.texel(i as usize, j as usize).to_array();
            for c in 0..4 {
                taps[k][c][l] = texel[c];
            }
        }
    }
    let [t00, t10, t01, t11] = taps.map(|t| t.map(F8::new));
    std::array::from_fn(|c| {
        let bottom = t00[c] + (t10[c] - t00[c]) * fx;
        let top = t01[c] + (t11[c] - t01[c]) * fx;
        bottom + (top - bottom) * fy
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::mip::{trilinear, LevelRule, MipFilter};
    use crate::texture::reconstruct::Addressing;
    use crate::texture::{Filterable, Wrap};
    use glam::Vec4;

    #[test]
    fn lanes_equal_the_generic_trilinear() {
        // An odd-sized noisy sRGB texture, so every level differs.
        let (w, h) = (37, 20);
        let bytes: Vec<[u8; 4]> =
            (0..w * h).map(|k| [(k * 37 % 251) as u8, (k * 91 % 256) as u8, (k * 13 % 199) as u8, 255]).collect();
        let base = Rgba8Plane::from_top_rows(w, h, &bytes, true);
        let data = Filterable::new(base, MipFilter::Box, [Wrap::Repeat; 2]);
        let levels = data.levels();
        let addr = Addressing { wrap: [Wrap::Repeat; 2], border: Vec4::ZERO };
        // Magnified, one texel, several levels up, beyond the last level, anisotropic; wrapping coordinates.
        let sizes = [0.1, 1.0, 2.5, 7.0, 300.0, 3.0, 0.6, 12.0];
        let fp: [Footprint; LANES] = std::array::from_fn(|i| {
            let k = sizes[i] / w as f32;
            Footprint { dudx: k, dvdx: 0.3 * k, dudy: -0.2 * k, dvdy: k * if i == 5 { 4.0 } else { 1.0 } }
        });
        let s = F8::new([0.01, 0.5, 0.99, -0.2, 1.37, 0.25, 0.999_9, 3.5]);
        let t = F8::new([0.99, 0.02, 0.5, 2.75, -0.6, 0.33, 0.000_1, 0.5]);
        let got = trilinear8(levels, s, t, &fp);
        for (i, fp) in fp.iter().enumerate() {
            let level = LevelRule::Longest.level(fp, w, h);
            let want = trilinear(levels, &addr, s.as_array_ref()[i], t.as_array_ref()[i], level);
            for c in 0..4 {
                let g = got[c].as_array_ref()[i];
                assert!((g - want[c]).abs() < 2e-5, "lane {i} channel {c}: {g} vs {}", want[c]);
            }
        }
    }
}
