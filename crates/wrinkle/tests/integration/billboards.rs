//! Billboards in every frame of a turntable: screen-aligned ones face the view and keep the screen's up,
//! world-oriented ones face the view and keep the world's up under a rolled camera, axial ones turn only
//! about their axis towards the eye. Checked from the rendered AOVs: the normal (exact for a flat patch)
//! within 1e-4, and the billboard's up, fitted from the pixels' (u,v) and world positions, within 1e-3.

use crate::common::RefCamera;
use glam::{DMat3, DVec3};
use wrinkle::render::Aovs;
use wrinkle::{RenderOptions, Scene};

const SIZE: usize = 128;
const EYE: [f64; 3] = [0.0, 1.0, 6.0];
const TARGET: [f64; 3] = [0.0, 1.0, 0.0];

fn scene() -> String {
    let (s, c) = 20f64.to_radians().sin_cos();
    let mut text = format!(
        "[camera]\neye = [0.0, 1.0, 6.0]\nlook_at = [0.0, 1.0, 0.0]\nup = [{s:?}, {c:?}, 0.0]\nfov_y = 50.0\n\n"
    );
    for (x, align) in [(-2.0, "screen"), (0.0, "world"), (2.0, "axis")] {
        text += &format!(
            "[[object]]\nshape = \"billboard\"\nalign = \"{align}\"\nwidth = 1.2\nheight = 1.6\n\
             transform = {{ translate = [{x:?}, 1.0, 0.5] }}\n\n"
        );
    }
    text
}

/// The least-squares fit P = P0 + u A + v B over the samples; returns B.
fn along_v(samples: &[(f64, f64, DVec3)]) -> DVec3 {
    let mut m = DMat3::ZERO;
    let mut rhs = [DVec3::ZERO; 3];
    for &(u, v, p) in samples {
        let row = DVec3::new(1.0, u, v);
        m += DMat3::from_cols(row * row.x, row * row.y, row * row.z);
        for k in 0..3 {
            rhs[k] += row * p[k];
        }
    }
    let inv = m.inverse();
    DVec3::new((inv * rhs[0]).z, (inv * rhs[1]).z, (inv * rhs[2]).z)
}

#[test]
fn billboards_turn_as_aligned_in_every_frame() {
    let scene = Scene::parse(&scene(), std::path::Path::new(".")).unwrap();
    let (s, c) = 20f64.to_radians().sin_cos();
    let cam = RefCamera::perspective(EYE, TARGET, [s, c, 0.0], 50.0, SIZE, SIZE);
    let back = -cam.fwd;
    for frame in 0..6 {
        let turn = 60.0 * frame as f32;
        let aovs = Aovs { normal: true, uv: true, depth: true, primitive: true, ..Aovs::default() };
        let options = RenderOptions { width: SIZE, height: SIZE, aovs, turntable_degrees: turn, ..Default::default() };
        let out = wrinkle::render(&scene, &options).unwrap();
        let (normal, uv, depth, primitive) =
            (out.normal.unwrap(), out.uv.unwrap(), out.depth.unwrap(), out.primitive.unwrap());
        for (object, x) in [(0u32, -2.0f64), (1, 0.0), (2, 2.0)] {
            // The turntable turns the objects about +Y through the camera's target.
            let (st, ct) = f64::from(turn).to_radians().sin_cos();
            let centre = DVec3::new(x * ct + 0.5 * st, 1.0, -x * st + 0.5 * ct);
            let (want_normal, want_up) = match object {
                0 => (back, cam.up),
                1 => (back, (DVec3::Y - back * back.y).normalize()),
                _ => {
                    let to_eye = DVec3::from(EYE) - centre;
                    (DVec3::new(to_eye.x, 0.0, to_eye.z).normalize(), DVec3::Y)
                }
            };
            let mut samples = Vec::new();
            for k in (0..SIZE * SIZE).filter(|&k| primitive[k][0] == object) {
                let n = DVec3::from(normal[k].map(f64::from));
                assert!(n.distance(want_normal) < 1e-4, "frame {frame}, object {object}: normal {n} vs {want_normal}");
                let (i, j) = (k % SIZE, k / SIZE);
                let (o, d) = cam.pixel_ray(i, j);
                samples.push((f64::from(uv[k][0]), f64::from(uv[k][1]), o + d * f64::from(depth[k])));
            }
            assert!(samples.len() > 100, "frame {frame}, object {object}: {} pixels", samples.len());
            let up = along_v(&samples).normalize();
            assert!(up.distance(want_up) < 1e-3, "frame {frame}, object {object}: up {up} vs {want_up}");
        }
    }
}
