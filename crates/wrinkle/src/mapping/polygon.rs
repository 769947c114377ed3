//! Texture coordinates inside a triangle or a quadrilateral from those at its corners (the course's
//! "Triangle Mapping" and quadrilateral mapping).
//!
//! A triangle defines linear maps u = A x + B y + C z + D, v = E x + F y + G z + H. The three points alone
//! leave them underdetermined (any multiple of the plane equation can be added), so, as the slides solve it,
//! the plane equation is solved for its largest coefficient: that coordinate is dropped and u, v become affine
//! functions of the other two, fitted exactly at the three corners (Cramer's rule). Points off the plane map
//! as their projection along the dropped axis.
//!
//! A quadrilateral maps by inverse bilinear interpolation: the (a, b) with P = bilerp(P00, P10, P11, P01; a, b)
//! (a quadratic in one unknown; linear where the quad is a parallelogram), then the corner (u, v) interpolated
//! bilinearly at (a, b). Computed in f64.

use glam::{DVec2, DVec3, Vec2, Vec3};

/// The linear map of a triangle's corners to their texture coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleMapping {
    /// The two coordinates kept (the one of the normal's largest component dropped).
    keep: [usize; 2],
    /// u = u0 + du . (q - q0), v = v0 + dv . (q - q0) over the kept coordinates q.
    origin: DVec2,
    at_origin: DVec2,
    du: DVec2,
    dv: DVec2,
}

impl TriangleMapping {
    /// The map taking `points[k]` to `uvs[k]`; `None` for a degenerate (zero-area) triangle.
    pub fn new(points: [Vec3; 3], uvs: [Vec2; 3]) -> Option<TriangleMapping> {
        let p = points.map(|p| p.as_dvec3());
        let n = (p[1] - p[0]).cross(p[2] - p[0]);
        let a = n.abs();
        let drop = if a.x >= a.y && a.x >= a.z {
            0
        } else if a.y >= a.z {
            1
        } else {
            2
        };
        let keep = [(drop + 1) % 3, (drop + 2) % 3];
        let q = p.map(|p| DVec2::new(p[keep[0]], p[keep[1]]));
        let (e1, e2) = (q[1] - q[0], q[2] - q[0]);
        let det = e1.x * e2.y - e1.y * e2.x;
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        let t = uvs.map(|t| t.as_dvec2());
        // Gradient g of a function with values f0, f1, f2: g . e1 = f1 - f0, g . e2 = f2 - f0.
        let gradient = |f1: f64, f2: f64| DVec2::new(f1 * e2.y - f2 * e1.y, f2 * e1.x - f1 * e2.x) / det;
        Some(TriangleMapping {
            keep,
            origin: q[0],
            at_origin: t[0],
            du: gradient(t[1].x - t[0].x, t[2].x - t[0].x),
            dv: gradient(t[1].y - t[0].y, t[2].y - t[0].y),
        })
    }

    /// The texture coordinates at `p`.
    pub fn uv(&self, p: Vec3) -> Vec2 {
        let p = p.as_dvec3();
        let d = DVec2::new(p[self.keep[0]], p[self.keep[1]]) - self.origin;
        (self.at_origin + DVec2::new(self.du.dot(d), self.dv.dot(d))).as_vec2()
    }
}

/// (a, b) in [0, 1]^2 (up to rounding) with P = (1-a)(1-b) P00 + a(1-b) P10 + a b P11 + (1-a) b P01, for
/// a point `p` of the planar quad `corners` = [P00, P10, P11, P01]; `None` outside it or for a degenerate quad.
pub fn inverse_bilinear(p: DVec3, corners: [DVec3; 4]) -> Option<DVec2> {
    let eps = 1e-9;
    let inside = |x: f64| (-eps..=1.0 + eps).contains(&x);
    bilinear_parameters(p, corners).into_iter().find(|ab| inside(ab.x) && inside(ab.y))
}

/// The solutions (a, b) of the bilinear equation, inside the quad or not (one for a parallelogram, up to two
/// otherwise), for a point in the quad's plane or projected onto it along its dominant axis.
pub fn bilinear_parameters(p: DVec3, corners: [DVec3; 4]) -> Vec<DVec2> {
    let [p00, p10, p11, p01] = corners;
    // P(a, b) = p00 + a e + b f + a b g.
    let (e, f, g) = (p10 - p00, p01 - p00, p00 - p10 + p11 - p01);
    let h = p - p00;
    // Work in the quad's plane: coordinates along two axes of the dominant plane.
    let n = e.cross(f);
    let a = n.abs();
    let (i, j) = if a.x >= a.y && a.x >= a.z {
        (1, 2)
    } else if a.y >= a.z {
        (2, 0)
    } else {
        (0, 1)
    };
    let cross2 = |u: DVec3, v: DVec3| u[i] * v[j] - u[j] * v[i];
    // h = a e + b f + a b g  =>  (h - b f) x (e + b g) = 0: k2 b^2 + k1 b + k0 = 0.
    let k2 = cross2(g, f);
    let k1 = cross2(e, f) + cross2(h, g);
    let k0 = cross2(h, e);
    let scale = (cross2(e, f)).abs().max(f64::MIN_POSITIVE);
    let bs: Vec<f64> = if k2.abs() <= 1e-12 * scale {
        // A parallelogram (or a trapezoid with its parallel sides along a): linear.
        if k1 == 0.0 {
            return Vec::new();
        }
        vec![-k0 / k1]
    } else {
        let disc = k1 * k1 - 4.0 * k0 * k2;
        if disc < 0.0 {
            return Vec::new();
        }
        let r = disc.sqrt();
        // The stable pair of roots.
        let qr = -0.5 * (k1 + k1.signum() * r);
        let mut roots = vec![qr / k2];
        if qr != 0.0 {
            roots.push(k0 / qr);
        }
        roots
    };
    bs.into_iter()
        .filter_map(|b| {
            let den = e + b * g;
            let k = if den[i].abs() >= den[j].abs() { i } else { j };
            (den[k] != 0.0).then(|| DVec2::new((h[k] - b * f[k]) / den[k], b))
        })
        .collect()
}

/// The corner texture coordinates [at P00, P10, P11, P01] interpolated bilinearly at (a, b).
pub fn bilinear(uv: [Vec2; 4], ab: DVec2) -> Vec2 {
    let [t00, t10, t11, t01] = uv.map(|t| t.as_dvec2());
    let (a, b) = (ab.x, ab.y);
    ((t00 * (1.0 - a) + t10 * a) * (1.0 - b) + (t01 * (1.0 - a) + t11 * a) * b).as_vec2()
}

/// A quadrilateral mapping: the corners' texture coordinates at the point's bilinear parameters in the quad
/// (the solution nearest the quad where the point lies outside it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuadMapping {
    pub corners: [DVec3; 4],
    pub uv: [Vec2; 4],
}

impl QuadMapping {
    pub fn uv(&self, p: Vec3) -> Vec2 {
        let outside = |ab: &DVec2| (ab.clamp(DVec2::ZERO, DVec2::ONE) - *ab).length_squared();
        let ab = bilinear_parameters(p.as_dvec3(), self.corners)
            .into_iter()
            .min_by(|a, b| outside(a).total_cmp(&outside(b)))
            .unwrap_or(DVec2::ZERO);
        bilinear(self.uv, ab)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small deterministic generator for the random cases.
    fn rng(seed: &mut u64) -> f64 {
        *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (*seed >> 11) as f64 / (1u64 << 53) as f64
    }

    #[test]
    fn triangle_mapping_is_exact_at_the_corners_and_linear_between() {
        let points = [Vec3::new(0.3, -1.0, 2.0), Vec3::new(2.0, 0.5, 1.5), Vec3::new(-0.5, 1.5, 2.5)];
        let uvs = [Vec2::new(0.1, 0.2), Vec2::new(0.9, 0.3), Vec2::new(0.4, 0.95)];
        let m = TriangleMapping::new(points, uvs).unwrap();
        for k in 0..3 {
            assert!((m.uv(points[k]) - uvs[k]).length() < 1e-6);
        }
        // Barycentric combinations map to the same combinations of the uv.
        let (l0, l1, l2) = (0.2, 0.5, 0.3);
        let p = points[0] * l0 + points[1] * l1 + points[2] * l2;
        assert!((m.uv(p) - (uvs[0] * l0 + uvs[1] * l1 + uvs[2] * l2)).length() < 1e-6);
        // The special cases the slides warn of: a triangle in a coordinate plane (x = const, y = const).
        let wall = [Vec3::new(1.0, 0.0, 0.0), Vec3::new(1.0, 1.0, 0.0), Vec3::new(1.0, 0.0, 1.0)];
        let m = TriangleMapping::new(wall, [Vec2::ZERO, Vec2::X, Vec2::Y]).unwrap();
        assert!((m.uv(Vec3::new(1.0, 0.25, 0.5)) - Vec2::new(0.25, 0.5)).length() < 1e-6);
        assert!(TriangleMapping::new([Vec3::ZERO, Vec3::X, Vec3::X * 2.0], [Vec2::ZERO; 3]).is_none());
    }

    #[test]
    fn inverse_bilinear_round_trips_random_convex_quads() {
        let mut seed = 7;
        let mut worst: f64 = 0.0;
        for _ in 0..2000 {
            // A convex quad: corners on a jittered circle in order, in a random plane.
            let angles: Vec<f64> =
                (0..4).map(|k| (k as f64 + 0.35 * (rng(&mut seed) - 0.5)) * std::f64::consts::FRAC_PI_2).collect();
            let radii: Vec<f64> = (0..4).map(|_| 0.5 + rng(&mut seed)).collect();
            let (ax, ay) = (DVec3::new(1.0, 0.2 * rng(&mut seed), 0.3), DVec3::new(-0.1, 1.0, 0.5 * rng(&mut seed)));
            let c: Vec<DVec3> = (0..4).map(|k| (ax * angles[k].cos() + ay * angles[k].sin()) * radii[k]).collect();
            let corners = [c[0], c[1], c[2], c[3]];
            let (a, b) = (rng(&mut seed), rng(&mut seed));
            let [p00, p10, p11, p01] = corners;
            let p = p00 * (1.0 - a) * (1.0 - b) + p10 * a * (1.0 - b) + p11 * a * b + p01 * (1.0 - a) * b;
            let got = inverse_bilinear(p, corners).expect("inside");
            worst = worst.max((got - DVec2::new(a, b)).abs().max_element());
        }
        assert!(worst < 1e-6, "worst round trip {worst}");
    }

    #[test]
    fn inverse_bilinear_of_parallelograms_is_linear_and_exact() {
        let mut seed = 11;
        let mut worst: f64 = 0.0;
        for _ in 0..2000 {
            let o = DVec3::new(rng(&mut seed), rng(&mut seed), rng(&mut seed));
            let e = DVec3::new(1.0 + rng(&mut seed), 0.3 * rng(&mut seed), 0.1);
            let f = DVec3::new(0.2 * rng(&mut seed), 1.0 + rng(&mut seed), -0.4);
            let corners = [o, o + e, o + e + f, o + f];
            let (a, b) = (rng(&mut seed), rng(&mut seed));
            let got = inverse_bilinear(o + e * a + f * b, corners).expect("inside");
            worst = worst.max((got - DVec2::new(a, b)).abs().max_element());
        }
        assert!(worst < 1e-9, "worst round trip {worst}");
        // Outside: none.
        let sq = [DVec3::ZERO, DVec3::X, DVec3::X + DVec3::Y, DVec3::Y];
        assert!(inverse_bilinear(DVec3::new(1.5, 0.5, 0.0), sq).is_none());
    }
}
