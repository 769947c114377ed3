//! The perturbed normal of Blinn (1978), sections 2 and 4.
//!
//! The displaced surface is P' = P + F N/|N|. With the approximation that F is negligibly small,
//!     N' = N + D,   D = (Fu (N x Pv) - Fv (N x Pu)) / |N|
//! (the extracted text lost the "D" of "N' = N + D"; it follows from the expansion just above it).
//! The scale-invariant variant replaces D by D' = a |N| / |D| D with a = sqrt(Fu^2 + Fv^2).
//! The full formula keeps every term: P'u = Pu + Fu N^ + F N^u, P'v = Pv + Fv N^ + F N^v, N' = P'u x P'v,
//! the exact normal of the displaced surface.

use super::Gradient;
use crate::geometry::frame_lanes::Frame8;
use crate::geometry::SurfaceFrame;
use crate::lanes::{CmpGt, F8, V3};
use glam::Vec3;

/// Which normal a bump function produces.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BumpFormula {
    /// N' = N + D, Blinn's approximation.
    Blinn,
    /// N' = N + D' with |D'| = sqrt(Fu^2 + Fv^2) |N| (section 4): the tilt no longer depends on the object's size.
    Invariant,
    /// The exact normal of P + F N^, with N^u and N^v from the surface's second derivatives.
    Full,
}

/// Blinn's D = (Fu (N x Pv) - Fv (N x Pu)) / |N|.
#[inline]
pub fn blinn_d(n: Vec3, pu: Vec3, pv: Vec3, fu: f32, fv: f32) -> Vec3 {
    (fu * n.cross(pv) - fv * n.cross(pu)) / n.length()
}

/// Blinn's D on eight lanes at once (the packet shader's form of `blinn_d`).
#[inline]
pub fn blinn_d8(n: V3, pu: V3, pv: V3, fu: F8, fv: F8) -> V3 {
    (n.cross(pv) * fu - n.cross(pu) * fv) * (F8::ONE / n.length())
}

/// The perturbed (unnormalised) normal N' at a surface frame.
#[inline]
pub fn perturbed_normal(frame: &SurfaceFrame, bump: Gradient, formula: BumpFormula) -> Vec3 {
    let n = frame.pu.cross(frame.pv);
    match formula {
        BumpFormula::Blinn => n + blinn_d(n, frame.pu, frame.pv, bump.fu, bump.fv),
        BumpFormula::Invariant => {
            let d = blinn_d(n, frame.pu, frame.pv, bump.fu, bump.fv);
            let len_d = d.length();
            if len_d == 0.0 {
                return n;
            }
            let a = bump.fu.hypot(bump.fv);
            n + d * (a * n.length() / len_d)
        }
        BumpFormula::Full => full_normal(frame, bump),
    }
}

/// `perturbed_normal` on eight lanes: Blinn's N + D and the full formula on the lanes, the invariant form
/// lane by lane.
#[inline]
pub fn perturbed_normal8(frame: &Frame8, g: [F8; 3], formula: BumpFormula) -> V3 {
    let [f, fu, fv] = g;
    let n = frame.pu.cross(frame.pv);
    match formula {
        BumpFormula::Blinn => n + blinn_d8(n, frame.pu, frame.pv, fu, fv),
        BumpFormula::Full => full_normal8(frame, g),
        formula => V3::from_lanes(&std::array::from_fn(|i| {
            let lane = |x: F8| x.as_array_ref()[i];
            perturbed_normal(&frame.lane(i), Gradient { f: lane(f), fu: lane(fu), fv: lane(fv) }, formula)
        })),
    }
}

/// The perturbed normal of eight samples of flat triangles whose Pu x Pv may point against the outward
/// normal (`side` = -1 on lanes where a mesh's uv are mirrored). The bump displaces along the outward
/// normal, so N' = side N + D (D' for the invariant form); without second derivatives the full formula is
/// Blinn's.
#[inline]
pub fn perturbed_normal_sided8(pu: V3, pv: V3, g: [F8; 3], formula: BumpFormula, side: F8) -> V3 {
    let [_, fu, fv] = g;
    let n = pu.cross(pv);
    let d = blinn_d8(n, pu, pv, fu, fv);
    let d = match formula {
        BumpFormula::Blinn | BumpFormula::Full => d,
        BumpFormula::Invariant => {
            let len_d = d.length();
            let a = (fu * fu + fv * fv).sqrt();
            let k = len_d.cmp_gt(F8::ZERO).blend(a * n.length() / len_d, F8::ZERO);
            d * k
        }
    };
    n * side + d
}

/// The derivatives of the unit normal N^ = N/|N| along u and v, from the second derivatives of P.
pub fn unit_normal_derivatives(frame: &SurfaceFrame) -> (Vec3, Vec3) {
    let n = frame.pu.cross(frame.pv);
    let len = n.length();
    let nh = n / len;
    let nu = frame.puu.cross(frame.pv) + frame.pu.cross(frame.puv);
    let nv = frame.puv.cross(frame.pv) + frame.pu.cross(frame.pvv);
    // d(N/|N|) = (dN - N^ (N^ . dN)) / |N|
    ((nu - nh * nh.dot(nu)) / len, (nv - nh * nh.dot(nv)) / len)
}

/// The exact normal of the displaced surface P + F N^ (Blinn's expansion before the approximation).
pub fn full_normal(frame: &SurfaceFrame, bump: Gradient) -> Vec3 {
    let nh = frame.pu.cross(frame.pv).normalize();
    let (nhu, nhv) = unit_normal_derivatives(frame);
    let pu = frame.pu + bump.fu * nh + bump.f * nhu;
    let pv = frame.pv + bump.fv * nh + bump.f * nhv;
    pu.cross(pv)
}

/// `full_normal` on eight lanes.
#[inline]
pub fn full_normal8(frame: &Frame8, g: [F8; 3]) -> V3 {
    let [f, fu, fv] = g;
    let n = frame.pu.cross(frame.pv);
    let inv_len = F8::ONE / n.length();
    let nh = n * inv_len;
    let nu = frame.puu.cross(frame.pv) + frame.pu.cross(frame.puv);
    let nv = frame.puv.cross(frame.pv) + frame.pu.cross(frame.pvv);
    let nhu = (nu - nh * nh.dot(nu)) * inv_len;
    let nhv = (nv - nh * nh.dot(nv)) * inv_len;
    let pu = frame.pu + nh * fu + nhu * f;
    let pv = frame.pv + nh * fv + nhv * f;
    pu.cross(pv)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Surface;

    #[test]
    fn flat_unit_patch_gives_the_papers_d() {
        // Section 4: X = u, Y = v, Z = 0 gives N = (0,0,1), D = (-Fu, -Fv, 0), tan theta = sqrt(Fu^2 + Fv^2).
        let patch = Surface::Patch { corners: [Vec3::ZERO, Vec3::X, Vec3::X + Vec3::Y, Vec3::Y] };
        let f = patch.frame(0.3, 0.6);
        let b = Gradient { f: 0.2, fu: 0.3, fv: -0.4 };
        let n = f.pu.cross(f.pv);
        assert_eq!(n, Vec3::Z);
        let d = blinn_d(n, f.pu, f.pv, b.fu, b.fv);
        assert!((d - Vec3::new(-0.3, 0.4, 0.0)).length() < 1e-7);
        let d8 = blinn_d8(V3::splat(n), V3::splat(f.pu), V3::splat(f.pv), F8::splat(b.fu), F8::splat(b.fv));
        assert!((d8.lane(5) - d).length() < 1e-7);
        // On a flat patch the approximation is exact: every form agrees.
        let blinn = perturbed_normal(&f, b, BumpFormula::Blinn);
        let full = perturbed_normal(&f, b, BumpFormula::Full);
        let inv = perturbed_normal(&f, b, BumpFormula::Invariant);
        assert!((blinn - full).length() < 1e-6 && (blinn - inv).length() < 1e-6);
    }

    #[test]
    fn unit_normal_derivatives_match_finite_differences() {
        let s = Surface::Torus { major_radius: 1.0, minor_radius: 0.4 };
        let h = 1e-3;
        let nh = |u: f32, v: f32| {
            let f = s.frame(u, v);
            f.pu.cross(f.pv).normalize()
        };
        let (u, v) = (0.21, 0.37);
        let (a, b) = unit_normal_derivatives(&s.frame(u, v));
        let fu = (nh(u + h, v) - nh(u - h, v)) / (2.0 * h);
        let fv = (nh(u, v + h) - nh(u, v - h)) / (2.0 * h);
        assert!((a - fu).length() < 1e-2 * fu.length().max(1.0), "{a} {fu}");
        assert!((b - fv).length() < 1e-2 * fv.length().max(1.0), "{b} {fv}");
    }

    #[test]
    fn invariant_tilt_is_a() {
        let s = Surface::Sphere { radius: 3.0 };
        let f = s.frame(0.4, 0.55);
        let b = Gradient { f: 0.0, fu: 0.7, fv: 0.2 };
        let n = f.pu.cross(f.pv);
        let np = perturbed_normal(&f, b, BumpFormula::Invariant);
        let tan = (np - n).length() / n.length();
        assert!((tan - 0.7f32.hypot(0.2)).abs() < 1e-5);
    }

    /// The lane form of the full formula agrees with the scalar one, on a torus (all second derivatives
    /// at work).
    #[test]
    fn full_normal_on_lanes_matches_the_scalar_formula() {
        let s = Surface::Torus { major_radius: 1.0, minor_radius: 0.4 };
        let frames: [SurfaceFrame; 8] = std::array::from_fn(|i| s.frame(0.1 + 0.1 * i as f32, 0.9 - 0.11 * i as f32));
        let g = [F8::new(std::array::from_fn(|i| 0.05 * i as f32)), F8::splat(0.3), F8::splat(-0.2)];
        let lanes = perturbed_normal8(&Frame8::from_lanes(&frames), g, BumpFormula::Full);
        for (i, f) in frames.iter().enumerate() {
            let b = Gradient { f: 0.05 * i as f32, fu: 0.3, fv: -0.2 };
            let want = full_normal(f, b);
            assert!((lanes.lane(i) - want).length() < 1e-5 * want.length(), "{i}: {} {want}", lanes.lane(i));
        }
    }
}
