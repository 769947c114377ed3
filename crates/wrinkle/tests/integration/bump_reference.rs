//! Blinn's perturbed normal (sections 2 and 4 of the 1978 paper) against independent references:
//! the exact normal of the displaced surface P + F N/|N| written out analytically or by f64 finite
//! differences in this file, and the paper's own statements about scale.
//!
//! Run with `cargo test --release -p wrinkle --test integration bump_reference -- --nocapture` to see the measured figures.

use crate::common::*;
use glam::DVec3;
use std::f64::consts::TAU;
use std::path::Path;
use wrinkle::bump::blinn::perturbed_normal;
use wrinkle::bump::{BumpFormula, BumpTable, Gradient, Interp};
use wrinkle::geometry::Surface;
use wrinkle::image::{io::write_png_grey16, Image};

// ---------------------------------------------------------------------------------------------
// 1. Flat patch with a smooth, known height table: the normal AOV against the exact normal.
// ---------------------------------------------------------------------------------------------

/// One period of a smooth tileable height, values in [0, 1]: [h, dh/ds, dh/dt].
fn height(s: f64, t: f64) -> [f64; 3] {
    let (a, b, c) = (2.0 * TAU * s, 3.0 * TAU * t, TAU * s);
    [
        0.5 + 0.25 * a.sin() * b.sin() + 0.25 * c.cos(),
        0.25 * 2.0 * TAU * a.cos() * b.sin() - 0.25 * TAU * c.sin(),
        0.25 * 3.0 * TAU * a.sin() * b.cos(),
    ]
}

/// Side of the square height table, in texels.
const TABLE: usize = 512;

/// Writes `height` sampled at texel centres ((i + 0.5) / W, (j + 0.5) / H), j counted from the
/// bottom (image row 0 is the top, v near 1), as a 16-bit grey PNG.
fn write_height_map(dir: &Path) {
    let n = TABLE as f64;
    let img = Image::from_fn(TABLE, TABLE, |x, y| height((x as f64 + 0.5) / n, 1.0 - (y as f64 + 0.5) / n)[0] as f32);
    write_png_grey16(&dir.join("h.png"), &img).expect("write height map");
}

/// What the rendered normal must equal.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Expected {
    /// The exact normal of the displaced surface (P'u x P'v of P + F N^).
    Displaced,
    /// Section 4's scale-invariant tilt: N rotated downhill by theta with tan theta = sqrt(Fu^2 + Fv^2).
    UnitTilt,
}

struct FlatCase {
    name: &'static str,
    /// P(0,0), P(1,0), P(1,1), P(0,1) in object space (a parallelogram).
    corners: [[f64; 3]; 4],
    transform: RefTransform,
    eye: [f64; 3],
    /// Bump scale (object units) and replication.
    scale: f64,
    repeat: [f64; 2],
    /// Extra lines of the bump table (formula, invariant).
    options: &'static str,
    expected: Expected,
}

/// Figures of one flat-patch render.
struct FlatResult {
    covered: usize,
    max_angle: MaxErr,
    max_tilt: f64,
    coverage_mismatches: usize,
    /// The largest | |N'| - 1 | of the AOV, which holds unit normals.
    worst_unit: f64,
}

fn render_flat_case(c: &FlatCase, dir: &Path, w: usize, h: usize) -> FlatResult {
    let look_at = [0.0, 0.0, 0.0];
    let corners = c.corners.map(arr).join(", ");
    let scene = format!(
        "{}[[object]]\nshape = \"patch\"\ncorners = [{corners}]\ntransform = {}\n\n[object.material.bump]\n\
         map = \"h.png\"\nscale = {:?}\nrepeat = [{:?}, {:?}]\ninterp = \"bilinear\"\n{}\n",
        camera_toml(c.eye, look_at, 40.0),
        c.transform.toml(),
        c.scale,
        c.repeat[0],
        c.repeat[1],
        c.options
    );
    let frame = render_all_aovs(&scene, dir, w, h, 1);
    let normals = frame.normal.as_ref().expect("normal AOV");
    let cam = RefCamera::perspective(c.eye, look_at, [0.0, 1.0, 0.0], 40.0, w, h);

    // Object-space parallelogram P(u,v) = p00 + u e1 + v e2 and its world image.
    let [p00, p10, _, p01] = c.corners.map(DVec3::from);
    let (e1, e2) = (p10 - p00, p01 - p00);
    let n_obj = e1.cross(e2);
    let nh = n_obj.normalize();
    let w00 = c.transform.point(p00);
    let (we1, we2) = (c.transform.point(p10) - w00, c.transform.point(p01) - w00);
    let n_world = we1.cross(we2);

    let mut res =
        FlatResult { covered: 0, max_angle: MaxErr::default(), max_tilt: 0.0, coverage_mismatches: 0, worst_unit: 0.0 };
    for j in 0..h {
        for i in 0..w {
            let got = normals[j * w + i];
            let (o, d) = cam.pixel_ray(i, j);
            let Some(t) = ray_plane(o, d, w00, n_world) else {
                res.coverage_mismatches += usize::from(!got[0].is_nan());
                continue;
            };
            let (u, v) = parallelogram_uv(o + t * d, w00, we1, we2);
            // Away from the border (more than 0.2% of the patch) coverage is unambiguous.
            let margin = 2e-3;
            let inside = [u, v].iter().all(|&x| x > margin && x < 1.0 - margin);
            let outside = [u, v].iter().any(|&x| x < -margin || x > 1.0 + margin);
            if got[0].is_nan() {
                res.coverage_mismatches += usize::from(inside);
                continue;
            }
            res.coverage_mismatches += usize::from(outside);
            res.covered += 1;

            // F(u,v) = scale * h(repeat_u u, repeat_v v); its derivatives come from h's, analytically.
            let [_, hs, ht] = height(c.repeat[0] * u, c.repeat[1] * v);
            let (fu, fv) = (c.scale * c.repeat[0] * hs, c.scale * c.repeat[1] * ht);
            let want_obj = match c.expected {
                Expected::Displaced => (e1 + fu * nh).cross(e2 + fv * nh),
                Expected::UnitTilt => {
                    let downhill = fu * n_obj.cross(e2) - fv * n_obj.cross(e1);
                    let a = fu.hypot(fv);
                    if downhill.length() > 0.0 {
                        nh + a * downhill.normalize()
                    } else {
                        nh
                    }
                }
            };
            let mut want = c.transform.direction(want_obj);
            // Open patches are shaded from the side facing the eye.
            if n_world.dot(-d) < 0.0 {
                want = -want;
            }
            let got = DVec3::new(got[0] as f64, got[1] as f64, got[2] as f64);
            res.worst_unit = res.worst_unit.max((got.length() - 1.0).abs());
            res.max_tilt = res.max_tilt.max(angle_deg(want, n_world * n_world.dot(-d).signum()));
            res.max_angle.add(angle_deg(got, want), || {
                format!("pixel ({i},{j}) uv ({u:.4},{v:.4}) got {got} want {}", want.normalize())
            });
        }
    }
    res
}

/// At every covered pixel of a bump-mapped flat patch the normal AOV is the exact normal of the
/// displaced surface z = F(u(x,y), v(x,y)) (Blinn's formula is exact on a flat patch; only the table's
/// central differences and 16-bit quantisation differ), within 0.5 degrees. (u,v) per pixel comes from
/// the analytic ray-plane intersection, F's derivatives from the analytic height function.
#[test]
fn flat_patch_normals_match_the_displaced_surface() {
    let dir = scratch_dir("flat-patch");
    write_height_map(&dir);
    let square = [[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]];
    let unit = [[-0.5, -0.5, 0.0], [0.5, -0.5, 0.0], [0.5, 0.5, 0.0], [-0.5, 0.5, 0.0]];
    let tilted = RefTransform { translate: [0.1, -0.2, -0.3], rotate: [25.0, -35.0, 15.0], scale: 1.25 };
    let cases = [
        FlatCase {
            name: "bilinear, oblique camera",
            corners: square,
            transform: RefTransform::IDENTITY,
            eye: [0.7, -0.9, 3.3],
            scale: 0.12,
            repeat: [2.0, 1.0],
            options: "",
            expected: Expected::Displaced,
        },
        FlatCase {
            name: "rotated, scaled and moved by its transform (world normal)",
            corners: square,
            transform: tilted,
            eye: [0.3, 0.4, 4.2],
            scale: 0.12,
            repeat: [2.0, 1.0],
            options: "",
            expected: Expected::Displaced,
        },
        FlatCase {
            name: "formula = full, transformed",
            corners: square,
            transform: tilted,
            eye: [0.3, 0.4, 4.2],
            scale: 0.12,
            repeat: [2.0, 1.0],
            options: "formula = \"full\"",
            expected: Expected::Displaced,
        },
        FlatCase {
            // Section 4: on the unit square X = u, Y = v the invariant D' equals D.
            name: "invariant = true on the unit patch",
            corners: unit,
            transform: RefTransform::IDENTITY,
            eye: [0.4, -0.5, 1.8],
            scale: 0.06,
            repeat: [2.0, 1.0],
            options: "invariant = true",
            expected: Expected::Displaced,
        },
        FlatCase {
            // Section 4 on a patch twice the unit size: tan theta = a = sqrt(Fu^2 + Fv^2), not the displaced surface's.
            name: "invariant = true on a 2x2 patch (section 4 tilt)",
            corners: square,
            transform: RefTransform::IDENTITY,
            eye: [0.7, -0.9, 3.3],
            scale: 0.05,
            repeat: [2.0, 1.0],
            options: "invariant = true",
            expected: Expected::UnitTilt,
        },
    ];
    let (w, h) = (192, 160);
    for c in &cases {
        let r = render_flat_case(c, &dir, w, h);
        println!(
            "flat patch [{}]: {} covered pixels, max tilt {:.1} deg, max angle to reference {:.3e} deg (bound 0.5) at {}",
            c.name, r.covered, r.max_tilt, r.max_angle.max, r.max_angle.at
        );
        assert!(r.covered > w * h / 6, "[{}] only {} pixels covered", c.name, r.covered);
        assert_eq!(r.coverage_mismatches, 0, "[{}] pixels covered (or not) against the analytic patch outline", c.name);
        assert!(r.worst_unit < 1e-4, "[{}] the normal AOV holds a vector of length off 1 by {}", c.name, r.worst_unit);
        assert!(r.max_tilt > 10.0, "[{}] bumps too flat to test: max tilt {} deg", c.name, r.max_tilt);
        assert!(r.max_angle.max < 0.5, "[{}] max angle {} deg at {}", c.name, r.max_angle.max, r.max_angle.at);
    }
}

// ---------------------------------------------------------------------------------------------
// 2. Sphere with a small-amplitude F: Blinn's approximation against the displaced surface.
// ---------------------------------------------------------------------------------------------

/// Central-difference step of the f64 reference.
const FD_STEP: f64 = 1e-5;

/// The true normal of the displaced sphere P + F P/r (P/r is the outward unit normal), by central
/// differences of that displaced surface in f64.
fn displaced_sphere_normal(r: f64, u: f64, v: f64, f: &dyn Fn(f64, f64) -> f64) -> DVec3 {
    let q = |u: f64, v: f64| sphere_point(r, u, v) * (1.0 + f(u, v) / r);
    let qu = (q(u + FD_STEP, v) - q(u - FD_STEP, v)) / (2.0 * FD_STEP);
    let qv = (q(u, v + FD_STEP) - q(u, v - FD_STEP)) / (2.0 * FD_STEP);
    qu.cross(qv)
}

/// Parameter points over the sphere, away from the poles (v in [0.1, 0.9]), as f32 (what the library takes).
fn sphere_points() -> Vec<(f32, f32)> {
    let mut pts = Vec::new();
    for j in 0..=32 {
        for i in 0..48 {
            pts.push((((i as f64 + 0.31) / 48.0) as f32, (0.1 + 0.8 * j as f64 / 32.0) as f32));
        }
    }
    pts
}

fn v64(v: glam::Vec3) -> DVec3 {
    d3(v)
}

/// The angle between Blinn's N' and the true normal of P + F N/|N| on a unit sphere, for F = A sin(8 pi u)
/// sin(4 pi v) with exact Fu, Fv. Blinn drops F (N/|N|)_u, which is O(F) against Pu; its effect on the
/// normal's direction is the tilt (O(A)) times F/r (O(A)): the error relative to the tilt falls in
/// proportion to A (x2 per doubling) and the absolute angle as A^2 (x4). The full formula keeps every
/// term and agrees at every amplitude within f32 rounding.
#[test]
fn sphere_blinn_error_shrinks_with_amplitude_and_full_formula_is_exact() {
    let sphere = Surface::Sphere { radius: 1.0 };
    let pts = sphere_points();
    let amplitudes = [1e-3, 2e-3, 4e-3, 8e-3];
    let mut rows = Vec::new();
    for &a in &amplitudes {
        let f = move |u: f64, v: f64| a * (4.0 * TAU * u).sin() * (2.0 * TAU * v).sin();
        let (mut blinn, mut full, mut tilt) = (MaxErr::default(), MaxErr::default(), 0.0f64);
        for &(u, v) in &pts {
            let (u64_, v64_) = (u as f64, v as f64);
            let pert = Gradient {
                f: f(u64_, v64_) as f32,
                fu: (a * 4.0 * TAU * (4.0 * TAU * u64_).cos() * (2.0 * TAU * v64_).sin()) as f32,
                fv: (a * 2.0 * TAU * (4.0 * TAU * u64_).sin() * (2.0 * TAU * v64_).cos()) as f32,
            };
            let frame = sphere.frame(u, v);
            let truth = displaced_sphere_normal(1.0, u64_, v64_, &f);
            tilt = tilt.max(angle_deg(truth, sphere_point(1.0, u64_, v64_)));
            let nb = v64(perturbed_normal(&frame, pert, BumpFormula::Blinn));
            let nf = v64(perturbed_normal(&frame, pert, BumpFormula::Full));
            blinn.add(angle_deg(nb, truth), || format!("({u},{v})"));
            full.add(angle_deg(nf, truth), || format!("({u},{v})"));
        }
        println!(
            "sphere A = {a:e}: max tilt {tilt:.3} deg, Blinn max error {:.3e} deg (relative to tilt {:.3e}), full max error {:.3e} deg",
            blinn.max,
            blinn.max / tilt,
            full.max
        );
        assert!(full.max < 1e-3, "A = {a}: full formula off by {} deg at {}", full.max, full.at);
        assert!(
            blinn.max > 5.0 * full.max,
            "A = {a}: Blinn's error {} is not measurable above {}",
            blinn.max,
            full.max
        );
        rows.push((a, tilt, blinn.max));
    }
    for pair in rows.windows(2) {
        let ((a0, t0, e0), (a1, t1, e1)) = (pair[0], pair[1]);
        let relative = (e1 / t1) / (e0 / t0);
        let absolute = e1 / e0;
        println!("A {a0:e} -> {a1:e}: relative error x{relative:.3} (bound 1.6..2.5), absolute angle x{absolute:.3} (bound 3.2..5)");
        assert!((1.6..=2.5).contains(&relative), "error relative to the tilt grew x{relative} for A {a0} -> {a1}");
        assert!((3.2..=5.0).contains(&absolute), "absolute error grew x{absolute} for A {a0} -> {a1}");
    }
}

/// The same F through a bump table (512 x 256 texels sampled at texel centres, bilinear, central
/// differences with E = one step): the full formula's N' agrees with the finite-difference truth within
/// the error of the table's derivatives. That error is bounded by the central-difference error
/// itself (a normal built from the exact central differences of the analytic F, measured here) plus
/// bilinear interpolation of the differences, which is of the same order: the bound is 2.5x the former.
#[test]
fn sphere_full_formula_through_a_table_is_within_the_central_difference_error() {
    let (tw, th) = (512usize, 256usize);
    let t_fn = |s: f64, t: f64| 0.5 + 0.5 * (4.0 * TAU * s).sin() * (2.0 * TAU * t).sin();
    let img =
        Image::from_fn(tw, th, |x, y| t_fn((x as f64 + 0.5) / tw as f64, 1.0 - (y as f64 + 0.5) / th as f64) as f32);
    let table = BumpTable::new(&img);
    let sphere = Surface::Sphere { radius: 1.0 };
    let (es, et) = (1.0 / tw as f64, 1.0 / th as f64);
    for a in [1e-3, 2e-3, 4e-3, 8e-3] {
        // F = 2A T, i.e. A + A sin(8 pi u) sin(4 pi v) (the table holds values in [0, 1]).
        let f = move |u: f64, v: f64| 2.0 * a * t_fn(u, v);
        let (mut table_err, mut cd_err) = (MaxErr::default(), MaxErr::default());
        for (u, v) in sphere_points() {
            let (u64_, v64_) = (u as f64, v as f64);
            let b = table.sample(u, v, Interp::Bilinear, 0.0);
            let k = (2.0 * a) as f32;
            let pert = Gradient { f: k * b.f, fu: k * b.fu, fv: k * b.fv };
            let got = v64(perturbed_normal(&sphere.frame(u, v), pert, BumpFormula::Full));
            let truth = displaced_sphere_normal(1.0, u64_, v64_, &f);
            table_err.add(angle_deg(got, truth), || format!("({u},{v})"));

            // The exact displaced normal with F's derivatives replaced by its central differences (E = one step).
            let p = |u: f64, v: f64| sphere_point(1.0, u, v);
            let pu = (p(u64_ + FD_STEP, v64_) - p(u64_ - FD_STEP, v64_)) / (2.0 * FD_STEP);
            let pv = (p(u64_, v64_ + FD_STEP) - p(u64_, v64_ - FD_STEP)) / (2.0 * FD_STEP);
            let fu_cd = (f(u64_ + es, v64_) - f(u64_ - es, v64_)) / (2.0 * es);
            let fv_cd = (f(u64_, v64_ + et) - f(u64_, v64_ - et)) / (2.0 * et);
            let (nh, grow) = (p(u64_, v64_), 1.0 + f(u64_, v64_));
            let cd = (grow * pu + fu_cd * nh).cross(grow * pv + fv_cd * nh);
            cd_err.add(angle_deg(cd, truth), || format!("({u},{v})"));
        }
        let bound = 2.5 * cd_err.max + 1e-4;
        println!(
            "table A = {a:e}: full-formula max error {:.3e} deg at {}; central-difference error {:.3e} deg; bound {bound:.3e}",
            table_err.max, table_err.at, cd_err.max
        );
        assert!(table_err.max <= bound, "A = {a}: {} deg > {bound} at {}", table_err.max, table_err.at);
    }
}

// ---------------------------------------------------------------------------------------------
// 3. Dependence on scale (section 4).
// ---------------------------------------------------------------------------------------------

/// tan theta = |N' - N| / |N| with N = Pu x Pv, as the paper measures the tilt.
fn tan_theta(s: &Surface, u: f32, v: f32, p: Gradient, formula: BumpFormula) -> f64 {
    let frame = s.frame(u, v);
    let n = v64(frame.pu.cross(frame.pv));
    (v64(perturbed_normal(&frame, p, formula)) - n).length() / n.length()
}

fn patch(corners: [[f64; 3]; 4], k: f64) -> Surface {
    Surface::Patch { corners: corners.map(|c| (DVec3::from(c) * k).as_vec3()) }
}

/// Scaling an object's geometry by 2 halves tan theta of Blinn's D (|N| grows x4, |D| x2) and leaves
/// the invariant D' unchanged, within 1%; the absolute tilts match the paper's closed forms:
/// tan theta = |Fu Pv - Fv Pu| / |Pu x Pv| (from |D| = |A|) for D, and tan theta' = sqrt(Fu^2 + Fv^2) for D'.
#[test]
fn scaling_by_two_halves_blinns_tilt_and_keeps_the_invariant_one() {
    let sheared = [[0.0, 0.0, 0.0], [1.5, 0.2, 0.1], [1.8, 1.2, -0.1], [0.3, 1.0, -0.2]];
    let square = [[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]];
    let shapes: Vec<(&str, Surface, Surface)> = vec![
        ("sphere r 1 -> 2", Surface::Sphere { radius: 1.0 }, Surface::Sphere { radius: 2.0 }),
        ("square patch", patch(square, 1.0), patch(square, 2.0)),
        ("sheared parallelogram", patch(sheared, 1.0), patch(sheared, 2.0)),
    ];
    let perts = [(0.3, -0.2, 0.05), (-0.05, 0.11, 0.0), (1.2, 0.4, -0.3), (0.0, -0.7, 0.1)];
    let (mut worst_blinn, mut worst_inv, mut worst_abs) = (0.0f64, 0.0f64, 0.0f64);
    for (name, one, two) in &shapes {
        for j in 1..8 {
            for i in 0..9 {
                let (u, v) = ((i as f32 + 0.4) / 9.0, j as f32 / 8.0);
                for &(fu, fv, f) in &perts {
                    let p = Gradient { f, fu, fv };
                    let (b1, b2) =
                        (tan_theta(one, u, v, p, BumpFormula::Blinn), tan_theta(two, u, v, p, BumpFormula::Blinn));
                    let (i1, i2) = (
                        tan_theta(one, u, v, p, BumpFormula::Invariant),
                        tan_theta(two, u, v, p, BumpFormula::Invariant),
                    );
                    let at = format!("{name} ({u},{v}) Fu {fu} Fv {fv}");
                    worst_blinn = worst_blinn.max((b2 / b1 / 0.5 - 1.0).abs());
                    worst_inv = worst_inv.max((i2 / i1 - 1.0).abs());
                    assert!((b2 / b1 - 0.5).abs() < 0.005, "{at}: Blinn tan ratio {}", b2 / b1);
                    assert!((i2 / i1 - 1.0).abs() < 0.01, "{at}: invariant tan ratio {}", i2 / i1);

                    // The paper's closed forms, with Pu, Pv from f64 differences of the geometry.
                    for (s, k, b, inv) in [(one, 1.0, b1, i1), (two, 2.0, b2, i2)] {
                        let pos = |u: f64, v: f64| match s {
                            Surface::Sphere { radius } => sphere_point(*radius as f64, u, v),
                            Surface::Patch { corners } => {
                                let c = corners.map(d3);
                                c[0].lerp(c[1], u).lerp(c[3].lerp(c[2], u), v)
                            }
                            _ => unreachable!("only spheres and patches here"),
                        };
                        let (u, v) = (u as f64, v as f64);
                        let pu = (pos(u + FD_STEP, v) - pos(u - FD_STEP, v)) / (2.0 * FD_STEP);
                        let pv = (pos(u, v + FD_STEP) - pos(u, v - FD_STEP)) / (2.0 * FD_STEP);
                        let want_blinn = (fu as f64 * pv - fv as f64 * pu).length() / pu.cross(pv).length();
                        let want_inv = (fu as f64).hypot(fv as f64);
                        let err = ((b - want_blinn) / want_blinn).abs().max(((inv - want_inv) / want_inv).abs());
                        worst_abs = worst_abs.max(err);
                        assert!(err < 1e-3, "{at} scale {k}: tan {b} vs {want_blinn}, invariant {inv} vs {want_inv}");
                    }
                }
            }
        }
    }
    println!(
        "scale x2: Blinn tan ratio off 0.5 by at most {:.2e} (relative; bound 1e-2), invariant ratio off 1 by {:.2e} (bound 1e-2), \
         closed forms matched within {:.2e} (bound 1e-3)",
        worst_blinn, worst_inv, worst_abs
    );
}

/// Per-pixel tan theta of the rendered normal against a flat patch's geometric normal (world +z).
fn rendered_tans(scene: &str, dir: &Path, n: usize) -> Vec<f64> {
    let frame = render_all_aovs(scene, dir, n, n, 1);
    frame
        .normal
        .expect("normal AOV")
        .iter()
        .map(|m| if m[0].is_nan() { f64::NAN } else { (m[0] as f64).hypot(m[1] as f64) / m[2] as f64 })
        .collect()
}

/// The same through scene files. The patch [-1,1]^2 seen from `eye` and the patch [-2,2]^2 seen from
/// 2 `eye` put every pixel on the same (u,v), so per pixel: Blinn's tan theta halves, the invariant one
/// stays. With `transform = { scale = 2 }` instead of doubled corners the tilt stays too: the scene
/// applies the bump in object space, so the transform scales the bump heights with the object (the
/// whole displaced surface is scaled, and a uniform scale does not change normal directions).
#[test]
fn scaling_through_the_scene() {
    let dir = scratch_dir("scaling");
    write_height_map(&dir);
    let n = 128;
    let eye = [0.5, 0.3, 4.0];
    let scene = |k: f64, transform_scale: f64, options: &str| {
        let corners =
            [[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]].map(|c| arr(c.map(|x| x * k)));
        let eye_k = eye.map(|x| x * k * transform_scale);
        format!(
            "{}[[object]]\nshape = \"patch\"\ncorners = [{}]\ntransform = {{ scale = {transform_scale:?} }}\n\n\
             [object.material.bump]\nmap = \"h.png\"\nscale = 0.1\nrepeat = [2.0, 1.0]\n{options}\n",
            camera_toml(eye_k, [0.0; 3], 40.0),
            corners.join(", ")
        )
    };
    let compare = |label: &str, a: &[f64], b: &[f64], want: f64| {
        let (mut worst, mut count) = (0.0f64, 0usize);
        for (k, (&ta, &tb)) in a.iter().zip(b).enumerate() {
            assert_eq!(ta.is_nan(), tb.is_nan(), "{label}: coverage differs at pixel {k}");
            if ta > 0.05 {
                count += 1;
                worst = worst.max((tb / ta / want - 1.0).abs());
            }
        }
        println!(
            "scene scale [{label}]: tan ratio {want} within {worst:.2e} (relative; bound 1e-2) over {count} pixels"
        );
        assert!(count > n * n / 4, "{label}: only {count} pixels with a visible tilt");
        assert!(worst < 0.01, "{label}: tan ratio off {want} by {worst} (relative)");
    };
    let blinn1 = rendered_tans(&scene(1.0, 1.0, ""), &dir, n);
    let blinn2 = rendered_tans(&scene(2.0, 1.0, ""), &dir, n);
    compare("Blinn, corners x2", &blinn1, &blinn2, 0.5);
    let inv1 = rendered_tans(&scene(1.0, 1.0, "invariant = true"), &dir, n);
    let inv2 = rendered_tans(&scene(2.0, 1.0, "invariant = true"), &dir, n);
    compare("invariant, corners x2", &inv1, &inv2, 1.0);
    let transformed = rendered_tans(&scene(1.0, 2.0, ""), &dir, n);
    compare("Blinn, transform scale = 2 (bump scaled with the object)", &blinn1, &transformed, 1.0);
}
