//! Eight samples of a triangle mesh at once. Each sample's ray (and the rays one pixel step to the right
//! and below, its ray differentials) meets the plane of its triangle; barycentrics of the three points give
//! the interpolated texture coordinates and their screen derivatives, the vertex normals' blend and the
//! tangents. The point lies exactly on the ray, whatever clipping did to the screen triangle.
//!
//! The frame handed to the shader is Pu, Pv from the triangle's uv gradients (Blinn's bumps on meshes),
//! projected into the plane of the smooth normal, so that Pu x Pv runs along it (or against it, `side`
//! = -1, where the uv are mirrored).

use super::frame_lanes::Frame8;
use super::mesh::TriangleMesh;
use crate::lanes::{CmpGt, CmpLt, F8, LANES, V3};
use crate::texture::{Footprint8, UvSet8};
use glam::{Vec2, Vec3};

/// Rays of eight samples in object space, with their changes across one pixel step in x and in y.
#[derive(Clone, Copy, Debug)]
pub struct Rays8 {
    pub origin: V3,
    pub dir: V3,
    /// (origin, direction) changes per step in x, and in y.
    pub dx: (V3, V3),
    pub dy: (V3, V3),
}

impl Rays8 {
    /// The rays carried by `m` (camera space to object space).
    #[inline]
    pub fn transformed(&self, m: &glam::Affine3A) -> Rays8 {
        let v = |d: V3| V3::transform_vector(m, d);
        Rays8 {
            origin: V3::transform_point(m, self.origin),
            dir: v(self.dir),
            dx: (v(self.dx.0), v(self.dx.1)),
            dy: (v(self.dy.0), v(self.dy.1)),
        }
    }
}

/// What the shader needs of eight mesh samples.
#[derive(Clone, Copy, Debug)]
pub struct MeshSample8 {
    /// P and the shading-plane tangents Pu, Pv (no second derivatives: triangles are flat).
    pub frame: Frame8,
    pub uv: (F8, F8),
    pub footprint: Footprint8,
    /// Texture coordinate set 1, where asked for and the mesh has it.
    pub uv1: Option<UvSet8>,
    pub orientation: MeshFrame8,
}

/// The orientation of eight mesh samples' frames.
#[derive(Clone, Copy, Debug)]
pub struct MeshFrame8 {
    /// +1 where Pu x Pv runs along the smooth (outward) normal, -1 where against it (mirrored uv).
    pub side: F8,
    /// The unit tangent of the normal map (perpendicular to the smooth normal) and its bitangent sign w:
    /// the bitangent is w (N x T).
    pub tangent: V3,
    pub tangent_sign: F8,
    /// How P moves across one pixel step in x and y, from the ray differentials (also where the mesh has
    /// no texture coordinates to carry them).
    pub dpdx: V3,
    pub dpdy: V3,
    /// How the unit smooth normal changes across the pixel steps in x and in y.
    pub normal_change: [V3; 2],
}

/// Samples `mesh` where `rays` meet the triangles `tris` (one per lane): the frame from texture
/// coordinate set 0, and set 1 too with `second_set`.
pub fn sample8(mesh: &TriangleMesh, tris: &[u32; LANES], rays: &Rays8, second_set: bool) -> MeshSample8 {
    // Indexed lane by lane (`from_fn`, which inlines: the arrays' `map` was left as calls, a tenth of a
    // mesh frame on one thread).
    let corner = |c: usize| -> [usize; LANES] { std::array::from_fn(|l| mesh.triangles[tris[l] as usize][c] as usize) };
    let corners = [corner(0), corner(1), corner(2)];
    let gather = |data: &[Vec3], c: usize| V3::from_lanes(&std::array::from_fn(|l| data[corners[c][l]]));
    let (v0, v1, v2) = (gather(&mesh.positions, 0), gather(&mesh.positions, 1), gather(&mesh.positions, 2));
    let (n0, n1, n2) = (gather(&mesh.normals, 0), gather(&mesh.normals, 1), gather(&mesh.normals, 2));
    let corner_uvs = |set: usize| match mesh.uvs(set) {
        Some(uvs) => (gather_uv(uvs, &corners[0]), gather_uv(uvs, &corners[1]), gather_uv(uvs, &corners[2])),
        None => ((F8::ZERO, F8::ZERO), (F8::ZERO, F8::ZERO), (F8::ZERO, F8::ZERO)),
    };
    let (uv0, uv1, uv2) = corner_uvs(0);

    let (e1, e2) = (v1 - v0, v2 - v0);
    let ng = e1.cross(e2);
    let hit = |o: V3, d: V3| o + d * (ng.dot(v0 - o) / ng.dot(d));
    let p = hit(rays.origin, rays.dir);
    let px = hit(rays.origin + rays.dx.0, rays.dir + rays.dx.1);
    let py = hit(rays.origin + rays.dy.0, rays.dir + rays.dy.1);
    let (dpdx, dpdy) = (px - p, py - p);

    // Barycentrics (b1, b2) of a point w = P - v0 in the plane, and of a step in it.
    let (d00, d01, d11) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let inv = F8::ONE / (d00 * d11 - d01 * d01);
    let bary = |w: V3| {
        let (a, b) = (w.dot(e1), w.dot(e2));
        ((d11 * a - d01 * b) * inv, (d00 * b - d01 * a) * inv)
    };
    let (b1, b2) = bary(p - v0);
    let b0 = F8::ONE - b1 - b2;
    let (b1x, b2x) = bary(dpdx);
    let (b1y, b2y) = bary(dpdy);

    // Texture coordinates and their derivatives across the pixel.
    let edges = |(a, b, c): ((F8, F8), (F8, F8), (F8, F8))| ((b.0 - a.0, b.1 - a.1), (c.0 - a.0, c.1 - a.1));
    let (du1, du2) = edges((uv0, uv1, uv2));
    let along = |(e1, e2): ((F8, F8), (F8, F8)), bx: F8, by: F8| (e1.0 * bx + e2.0 * by, e1.1 * bx + e2.1 * by);
    let (dudx, dvdx) = along((du1, du2), b1x, b2x);
    let (dudy, dvdy) = along((du1, du2), b1y, b2y);
    let uv = (uv0.0 + du1.0 * b1 + du2.0 * b2, uv0.1 + du1.1 * b1 + du2.1 * b2);

    // Pu, Pv from the uv gradients: [e1 e2] = [Pu Pv] [du1 du2]. Without usable uv any right-handed pair
    // around the face normal will do (there is then nothing to take derivatives along).
    let det = du1.0 * du2.1 - du1.1 * du2.0;
    let usable = det.abs().cmp_gt(F8::splat(1e-20)) & det.is_finite();
    let inv_det = F8::ONE / det;
    let pu_uv = (e1 * du2.1 - e2 * du1.1) * inv_det;
    let pv_uv = (e2 * du1.0 - e1 * du2.0) * inv_det;
    let pv_plain = ng.normalize_or_zero().cross(e1);
    let pu = V3::select(usable, pu_uv, e1);
    let pv = V3::select(usable, pv_uv, pv_plain);

    // Set 1 with its derivatives along set 0's (u,v): d(uv1)/d(b1, b2) [du1 du2]^-1 (zero where set 0
    // gives no usable frame).
    let uv1 = (second_set && mesh.uvs(1).is_some()).then(|| {
        let corners = corner_uvs(1);
        let (a1, a2) = edges(corners);
        let (dx, dy) = (along((a1, a2), b1x, b2x), along((a1, a2), b1y, b2y));
        let inv = usable.blend(inv_det, F8::ZERO);
        // (b1, b2) per unit u: (du2.v, -du1.v) / det; per unit v: (-du2.u, du1.u) / det.
        let column = |db1: F8, db2: F8| along((a1, a2), db1 * inv, db2 * inv);
        let (du, dv) = along((a1, a2), b1, b2);
        UvSet8 {
            u: corners.0 .0 + du,
            v: corners.0 .1 + dv,
            footprint: Footprint8 { dudx: dx.0, dvdx: dx.1, dudy: dy.0, dvdy: dy.1 },
            jacobian: [column(du2.1, -du1.1), column(-du2.0, du1.0)],
        }
    });

    // The smooth normal (the face's where the vertex normals cancel), and the tangents in its plane.
    let blend = n0 * b0 + n1 * b1 + n2 * b2;
    let smooth = blend.dot(blend).cmp_gt(F8::splat(1e-24));
    let ns = V3::select(smooth, blend, ng).normalize_or_zero();
    let flat = |t: V3| t - ns * ns.dot(t);
    // The unit normal's turn across the pixel: the blend's change less its part along the normal, over
    // the blend's length (none on a face without smooth normals).
    let inv_blend = smooth.blend(F8::ONE / blend.length(), F8::ZERO);
    let turn = |b1: F8, b2: F8| flat((n1 - n0) * b1 + (n2 - n0) * b2) * inv_blend;
    let normal_change = [turn(b1x, b2x), turn(b1y, b2y)];
    let (pu, pv) = (flat(pu), flat(pv));
    let side = pu.cross(pv).dot(ns).cmp_lt(F8::ZERO).blend(F8::splat(-1.0), F8::ONE);

    let (tangent, tangent_sign) = if mesh.tangents.is_empty() {
        (pu.normalize_or_zero(), side)
    } else {
        let t = |c: usize| V3::from_lanes(&std::array::from_fn(|l| mesh.tangents[corners[c][l]].truncate()));
        let (t0, t1, t2) = (t(0), t(1), t(2));
        let w0 = F8::new(std::array::from_fn(|l| mesh.tangents[corners[0][l]].w));
        (flat(t0 * b0 + t1 * b1 + t2 * b2).normalize_or_zero(), w0)
    };
    let zero = V3::splat(Vec3::ZERO);
    MeshSample8 {
        frame: Frame8 { p, pu, pv, puu: zero, puv: zero, pvv: zero },
        uv,
        footprint: Footprint8 { dudx, dvdx, dudy, dvdy },
        uv1,
        orientation: MeshFrame8 { side, tangent, tangent_sign, dpdx, dpdy, normal_change },
    }
}

/// The texture coordinates `uvs[at[l]]` of each lane l, as (u, v) lanes.
#[inline(always)]
fn gather_uv(uvs: &[Vec2], at: &[usize; LANES]) -> (F8, F8) {
    (F8::new(std::array::from_fn(|l| uvs[at[l]].x)), F8::new(std::array::from_fn(|l| uvs[at[l]].y)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Vec2, Vec4};

    /// A tilted triangle with uv (0,0), (2,0), (0,1) at its corners, seen along -z from above.
    fn triangle() -> TriangleMesh {
        let positions = vec![Vec3::ZERO, Vec3::new(2.0, 0.0, 0.5), Vec3::new(0.0, 1.0, 0.0)];
        let mut m = TriangleMesh {
            positions,
            uv_sets: vec![vec![Vec2::ZERO, Vec2::new(2.0, 0.0), Vec2::new(0.0, 1.0)]],
            triangles: vec![[0, 1, 2]],
            ..TriangleMesh::default()
        };
        m.compute_normals();
        m
    }

    fn rays(points: [Vec2; LANES], step: f32) -> Rays8 {
        let s = V3::splat;
        let origin = V3::from_lanes(&points.map(|p| Vec3::new(p.x, p.y, 5.0)));
        Rays8 {
            origin,
            dir: s(-Vec3::Z),
            dx: (s(Vec3::new(step, 0.0, 0.0)), s(Vec3::ZERO)),
            dy: (s(Vec3::new(0.0, step, 0.0)), s(Vec3::ZERO)),
        }
    }

    #[test]
    fn points_lie_on_their_rays_and_carry_the_plane_uv() {
        let m = triangle();
        let points: [Vec2; LANES] = std::array::from_fn(|i| Vec2::new(0.1 + 0.15 * i as f32, 0.05 + 0.08 * i as f32));
        let s = sample8(&m, &[0; LANES], &rays(points, 0.01), false);
        for (i, q) in points.iter().enumerate() {
            // On the plane z = x / 4, and u = x, v = y there (the uv are affine in x, y on this triangle).
            let p = s.frame.p.lane(i);
            assert!((p - Vec3::new(q.x, q.y, q.x / 4.0)).length() < 1e-5, "{p}");
            let (u, v) = (s.uv.0.as_array_ref()[i], s.uv.1.as_array_ref()[i]);
            assert!((u - q.x).abs() < 1e-5 && (v - q.y).abs() < 1e-5);
            let fp = s.footprint.lane(i);
            assert!((fp.dudx - 0.01).abs() < 1e-6 && fp.dvdx.abs() < 1e-6 && (fp.dvdy - 0.01).abs() < 1e-6);
            // Pu = dP/du along the triangle, Pv = dP/dv, both in the flat face's plane.
            assert!((s.frame.pu.lane(i) - Vec3::new(1.0, 0.0, 0.25)).length() < 1e-5);
            assert!((s.frame.pv.lane(i) - Vec3::Y).length() < 1e-5);
            assert_eq!(s.orientation.side.as_array_ref()[i], 1.0);
        }
    }

    #[test]
    fn mirrored_uv_turn_the_side_and_tangents_come_from_the_mesh() {
        let mut m = triangle();
        m.uv_sets[0].iter_mut().for_each(|uv| uv.x = -uv.x);
        let s = sample8(&m, &[0; LANES], &rays([Vec2::new(0.3, 0.2); LANES], 0.01), false);
        assert_eq!(s.orientation.side.as_array_ref()[0], -1.0);
        // The default tangent is Pu's direction with the side as its sign: the bitangent runs along +v.
        let n = m.normals[0];
        let b = s.orientation.tangent_sign.as_array_ref()[0] * n.cross(s.orientation.tangent.lane(0));
        assert!(b.dot(Vec3::Y) > 0.99, "{b}");
        m.tangents = vec![Vec4::new(0.0, 1.0, 0.0, -1.0); 3];
        let s = sample8(&m, &[0; LANES], &rays([Vec2::new(0.3, 0.2); LANES], 0.01), false);
        assert!(
            (s.orientation.tangent.lane(3) - Vec3::Y).length() < 1e-6
                && s.orientation.tangent_sign.as_array_ref()[3] == -1.0
        );
    }

    /// The unit normal's turn across a pixel step is the difference of the interpolated unit normals at
    /// the points one step apart (to first order), and set 1 carries its own coordinates, footprint and
    /// change along set 0's (u,v).
    #[test]
    fn normals_turn_and_the_second_set_follow_the_triangle() {
        let mut m = triangle();
        m.normals = vec![
            Vec3::new(-0.3, 0.0, 1.0).normalize(),
            Vec3::new(0.4, -0.2, 1.0).normalize(),
            Vec3::new(0.0, 0.5, 1.0).normalize(),
        ];
        // Set 1 = (2u + 0.1, 3v - u): d(set 1)/du = (2, -1), d/dv = (0, 3).
        m.uv_sets.push(m.uv_sets[0].iter().map(|uv| Vec2::new(2.0 * uv.x + 0.1, 3.0 * uv.y - uv.x)).collect());
        let points: [Vec2; LANES] = std::array::from_fn(|i| Vec2::new(0.1 + 0.12 * i as f32, 0.05 + 0.07 * i as f32));
        let step = 1e-3;
        let s = sample8(&m, &[0; LANES], &rays(points, step), true);
        let moved = |d: Vec2| sample8(&m, &[0; LANES], &rays(points.map(|p| p + d), step), false);
        let normal = |s: &MeshSample8, i: usize| {
            s.frame.pu.cross(s.frame.pv).lane(i).normalize() * s.orientation.side.as_array_ref()[i]
        };
        let (sx, sy) = (moved(Vec2::new(step, 0.0)), moved(Vec2::new(0.0, step)));
        let set = s.uv1.expect("set 1 was asked for");
        for i in 0..LANES {
            for (got, next) in
                [(s.orientation.normal_change[0].lane(i), &sx), (s.orientation.normal_change[1].lane(i), &sy)]
            {
                let want = normal(next, i) - normal(&s, i);
                assert!((got - want).length() < 0.02 * want.length() + 1e-7, "lane {i}: {got} vs {want}");
            }
            let l = set.lane(i);
            let (u, v) = (s.uv.0.as_array_ref()[i], s.uv.1.as_array_ref()[i]);
            assert!((l.uv - Vec2::new(2.0 * u + 0.1, 3.0 * v - u)).length() < 1e-5, "{}", l.uv);
            let f = s.footprint.lane(i);
            assert!(
                (l.footprint.dudx - 2.0 * f.dudx).abs() < 1e-6
                    && (l.footprint.dvdy - (3.0 * f.dvdy - f.dudy)).abs() < 1e-6
            );
            for (got, want) in l.jacobian.iter().zip([Vec2::new(2.0, -1.0), Vec2::new(0.0, 3.0)]) {
                assert!((*got - want).length() < 1e-4, "lane {i}: {got} vs {want}");
            }
        }
        assert!(sample8(&m, &[0; LANES], &rays(points, step), false).uv1.is_none());
    }
}
