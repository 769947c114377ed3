//! Bad numbers into the library's public numeric entry points: NaN, +-infinity, +-1e30, 3e9, -0.0 and
//! subnormals, in scalar arguments and mixed across the eight lanes of `F8` / `V3`. The house rule: bad
//! input may give any result (NaN included) but must never panic, read out of bounds or hang inside the
//! library. Each test feeds one kind of input to one area, so that one panic does not hide the others;
//! nothing here checks the values that come back, only that they come back.
//!
//! Where a call might loop for ever, it runs in a child process of this test binary (the test re-run alone,
//! `--exact`) that is killed after a timeout, so that a hang fails its test without leaving a thread
//! spinning through the rest of the run.
//!
//! A few tests feed degenerate shapes rather than bad numbers (empty images, a size of 0, an image index
//! past the layout's, no colours): they are named for it (`..._empty_...`, `..._zero_size`, ...).

use glam::{Affine3A, DVec2, DVec3, Mat3, Vec2, Vec3, Vec4};
use std::hint::black_box;
use std::process::{Command, Stdio};
use std::sync::Arc;
use std::time::{Duration, Instant};

use wrinkle::bump::blinn::{
    blinn_d, blinn_d8, full_normal, perturbed_normal, perturbed_normal_sided8, unit_normal_derivatives,
};
use wrinkle::bump::integrate::{check_strength, frankot_chellappa, gradient_of_normal, settle_heights};
use wrinkle::bump::lean::WorldSpread8;
use wrinkle::bump::normal_map::{decode_normal, encode_rgb, Convention, Kernel as NormalKernel, NormalMap};
use wrinkle::bump::schlag::{emboss_image, light_direction, modulate_rgb8, round_to_bits, to_grey16, to_grey8, Emboss};
use wrinkle::bump::{BumpFormula, Gradient};
use wrinkle::envmap::chart::{Face, Layout};
use wrinkle::envmap::convert::convert;
use wrinkle::envmap::{Environment, EnvironmentOptions};
use wrinkle::geometry::SurfaceFrame;
use wrinkle::image::strips::Edges;
use wrinkle::image::{GreyImage, Image};
use wrinkle::internals::{F8, V3};
use wrinkle::light::Spot;
use wrinkle::mapping::polygon::{bilinear, bilinear_parameters, inverse_bilinear, QuadMapping, TriangleMapping};
use wrinkle::mapping::projection::{self, Point, Projector, SphereRange, Surface as MapSurface};
use wrinkle::mapping::{MappedTexture, Projection, UvTransform};
use wrinkle::procedural::bake::{bake, bake_rows};
use wrinkle::procedural::bias_gain::{bias, gain};
use wrinkle::procedural::effects::{spline, Kind, Params, Pattern};
use wrinkle::procedural::fbm::{Fractal, Octaves, Sum};
use wrinkle::procedural::hypertexture::{Hypertexture, Modulation, Shading};
use wrinkle::procedural::perlin::uniform_points;
use wrinkle::procedural::solid::{Procedural, Space};
use wrinkle::procedural::{Perlin, Variant};
use wrinkle::shade::{Ibl, Lobe8, Mode, Phong};
use wrinkle::texture::{
    Filter, FilterOptions, FilteredTexture, Footprint, Footprint8, LookupContext, LookupContext8, SurfaceLanes,
    Texture, TextureOptions, UvSet, UvSet8,
};
use wrinkle::{Light, Mapping};

// ---------------------------------------------------------------------------------------------------
// The bad values.

const NAN: f32 = f32::NAN;
const INF: f32 = f32::INFINITY;
/// A subnormal.
const SUB: f32 = 1e-40;

/// Every bad scalar.
const BAD: [f32; 10] = [NAN, INF, -INF, 1e30, -1e30, 3e9, -3e9, -0.0, SUB, f32::MAX];

/// One bad value per lane.
const LANE_BAD: [f32; 8] = [NAN, INF, -INF, 1e30, -1e30, 3e9, -0.0, SUB];

/// The bad values in f64, with f64's own extremes.
const BAD64: [f64; 13] =
    [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 1e30, -1e30, 3e9, -3e9, -0.0, 1e-40, 5e-324, 1e300, -1e300, f64::MAX];

/// Eight-lane sets: the bad values in every rotation, one bad lane among ordinary ones, and all alike.
fn lane_sets() -> Vec<[f32; 8]> {
    let mut v = Vec::new();
    for k in 0..8 {
        let mut a = LANE_BAD;
        a.rotate_left(k);
        v.push(a);
    }
    for k in 0..8 {
        let mut a: [f32; 8] = std::array::from_fn(|i| 0.1 + 0.37 * i as f32);
        a[k] = LANE_BAD[k];
        v.push(a);
    }
    for b in LANE_BAD {
        v.push([b; 8]);
    }
    v
}

/// Vectors with bad components: all bad, or one bad component among ordinary ones; and zero.
fn bad_vecs() -> Vec<Vec3> {
    let mut v = vec![Vec3::ZERO, Vec3::splat(-0.0)];
    for b in BAD {
        v.push(Vec3::splat(b));
        v.push(Vec3::new(b, 0.3, -0.2));
        v.push(Vec3::new(0.1, b, 0.5));
        v.push(Vec3::new(0.4, -0.6, b));
    }
    v
}

/// `bad_vecs` eight at a time, in overlapping windows (padded with an ordinary vector), and each alone
/// among ordinary lanes.
fn bad_lane_vecs() -> Vec<[Vec3; 8]> {
    let vecs = bad_vecs();
    let ordinary = |i: usize| Vec3::new(0.2 + 0.1 * i as f32, 0.5, 0.8 - 0.05 * i as f32);
    let mut out = Vec::new();
    for start in (0..vecs.len()).step_by(3) {
        out.push(std::array::from_fn(|i| vecs.get(start + i).copied().unwrap_or(ordinary(i))));
    }
    for (k, &b) in vecs.iter().enumerate() {
        let mut lanes: [Vec3; 8] = std::array::from_fn(ordinary);
        lanes[k % 8] = b;
        out.push(lanes);
    }
    out
}

fn bad_v3s() -> Vec<V3> {
    bad_lane_vecs().iter().map(V3::from_lanes).collect()
}

/// Footprints with bad entries.
fn bad_footprints() -> Vec<Footprint> {
    let mut v = vec![Footprint::default()];
    for b in BAD {
        v.push(Footprint { dudx: b, dvdx: b, dudy: b, dvdy: b });
        v.push(Footprint { dudx: b, dvdx: 0.0, dudy: 0.0, dvdy: 0.01 });
        v.push(Footprint { dudx: 0.01, dvdx: 0.0, dudy: 0.0, dvdy: b });
    }
    v
}

/// Affine maps that are not: NaN, zero, huge, infinite.
fn bad_affines() -> Vec<Affine3A> {
    let mut v = vec![Affine3A::IDENTITY, Affine3A::from_scale(Vec3::ZERO)];
    for b in BAD {
        v.push(Affine3A::from_scale(Vec3::splat(b)));
        v.push(Affine3A::from_translation(Vec3::splat(b)));
    }
    v
}

/// Runs `body` in a child process of this test binary (this test alone), killed after `secs` seconds: a
/// hang fails the test with a message, and leaves nothing running. `name` is this test's name.
fn in_child_process(name: &str, secs: u64, body: impl FnOnce()) {
    if std::env::var_os("WRINKLE_NON_FINITE_CHILD").is_some() {
        body();
        return;
    }
    let exe = std::env::current_exe().expect("the test binary");
    let mut child = Command::new(exe)
        .args([name, "--exact", "--nocapture", "--test-threads=1"])
        .env("WRINKLE_NON_FINITE_CHILD", "1")
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the child test process starts");
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().expect("the child test process") {
            let out = child.wait_with_output().expect("the child's output");
            assert!(status.success(), "{name} failed in its child process:\n{}", String::from_utf8_lossy(&out.stderr));
            return;
        }
        if start.elapsed() > Duration::from_secs(secs) {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{name}: no result within {secs} s (hang)");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

// ---------------------------------------------------------------------------------------------------
// Procedural: Perlin noise.

fn noises() -> Vec<Perlin> {
    let mut v = Vec::new();
    for variant in [Variant::Improved, Variant::Classic, Variant::Hashed] {
        v.push(Perlin::new(variant, 0));
        v.push(Perlin::new(variant, 7));
        v.push(Perlin::new(variant, 3).with_period([3, 5, 4]));
        v.push(Perlin::new(variant, 3).with_period([0, u32::MAX, 1]));
        v.push(Perlin::new(variant, 3).with_period([256, 256, 256]));
    }
    v
}

/// Points with one or all coordinates bad.
fn bad_points() -> Vec<[f32; 3]> {
    let mut v = Vec::new();
    for b in BAD {
        v.extend([[b, 0.3, 0.7], [0.3, b, 0.7], [0.3, 0.7, b], [b, b, b], [b, -b, 0.5]]);
    }
    v
}

#[test]
fn perlin_noise3_scalar_non_finite_coordinates() {
    for n in noises() {
        for [x, y, z] in bad_points() {
            black_box(n.noise3(x, y, z));
            black_box(n.noise3_d(x, y, z));
        }
    }
}

#[test]
fn perlin_noise2_scalar_non_finite_coordinates() {
    for n in noises() {
        for [x, y, _] in bad_points() {
            black_box(n.noise2(x, y));
            black_box(n.noise2_d(x, y));
        }
    }
}

#[test]
fn perlin_f64_non_finite_coordinates() {
    for n in noises() {
        for b in BAD64 {
            for (x, y, z) in [(b, 0.3, 0.7), (0.3, b, 0.7), (0.3, 0.7, b), (b, b, b)] {
                black_box(n.noise3_f64(x, y, z));
                black_box(n.noise2_f64(x, y));
            }
        }
    }
    for b in BAD64 {
        black_box(wrinkle::procedural::perlin::fade_f64(b));
    }
}

#[test]
fn perlin_noise3_lanes_mixed_non_finite() {
    let sets = lane_sets();
    for n in noises() {
        for (i, x) in sets.iter().enumerate() {
            let y = &sets[(i + 3) % sets.len()];
            let z = &sets[(i + 7) % sets.len()];
            black_box(n.noise3_lanes(x, y, z));
            black_box(n.noise3_lanes(x, &[0.5; 8], &[0.25; 8]));
        }
    }
}

#[test]
fn perlin_noise2_lanes_mixed_non_finite() {
    let sets = lane_sets();
    for n in noises() {
        for (i, x) in sets.iter().enumerate() {
            let y = &sets[(i + 5) % sets.len()];
            black_box(n.noise2_lanes(x, y));
            black_box(n.noise2_lanes(&[0.5; 8], x));
        }
    }
}

/// 45 points: the sixteen-lane (AVX-512) kernel, eight lanes and single points all see bad values.
fn bulk_axis(offset: usize) -> Vec<f32> {
    (0..45).map(|i| if i % 3 == 0 { BAD[(i / 3 + offset) % BAD.len()] } else { 0.1 * i as f32 }).collect()
}

#[test]
fn perlin_noise3_many_non_finite() {
    let (x, y, z) = (bulk_axis(0), bulk_axis(3), bulk_axis(7));
    let mut out = vec![0.0; 45];
    for n in noises() {
        n.noise3_many(&x, &y, &z, &mut out);
        for b in BAD {
            n.noise3_many(&[b; 45], &[b; 45], &[b; 45], &mut out);
        }
    }
    black_box(out);
}

#[test]
fn perlin_uniform_points_non_finite_extent() {
    for b in BAD {
        black_box(uniform_points(20, b, 3));
    }
}

// ---------------------------------------------------------------------------------------------------
// Procedural: fBm and turbulence.

fn fractals(octaves: Octaves) -> Vec<Fractal> {
    let bases = [
        Perlin::new(Variant::Hashed, 1),
        Perlin::new(Variant::Improved, 0),
        Perlin::new(Variant::Classic, 2),
        Perlin::new(Variant::Hashed, 1).with_period([4, 4, 4]),
        Perlin::new(Variant::Improved, 1).with_period([3, 3, 3]),
    ];
    let mut v = Vec::new();
    for noise in bases {
        for sum in [Sum::Fbm, Sum::Turbulence] {
            v.push(Fractal::new(noise.clone(), sum, octaves));
        }
    }
    v
}

#[test]
fn fbm_eval_non_finite_points() {
    for f in fractals(Octaves { count: 5, ..Octaves::default() }) {
        for p in bad_points() {
            for dims in [2, 3] {
                for width in [0.0, 0.01, 0.7, 5.0] {
                    black_box(f.eval(p, dims, width));
                    black_box(f.eval_d(p, dims, width));
                }
            }
        }
    }
}

#[test]
fn fbm_eval_non_finite_widths() {
    for f in fractals(Octaves { count: 5, ..Octaves::default() }) {
        for width in BAD {
            for dims in [2, 3] {
                black_box(f.eval([0.3, 0.6, 0.9], dims, width));
                black_box(f.eval_d([0.3, 0.6, 0.9], dims, width));
                black_box(f.eval([width, 0.6, 0.9], dims, width));
            }
            black_box(f.all_octaves_resolved(width));
        }
    }
}

#[test]
fn fbm_lanes_mixed_non_finite() {
    let sets = lane_sets();
    for f in fractals(Octaves { count: 5, ..Octaves::default() }) {
        for (i, x) in sets.iter().enumerate() {
            let y = &sets[(i + 3) % sets.len()];
            let z = &sets[(i + 6) % sets.len()];
            black_box(f.eval3_lanes(x, y, z));
            black_box(f.eval2_lanes(x, y));
        }
    }
}

#[test]
fn fbm_bulk_non_finite() {
    let (x, y, z) = (bulk_axis(0), bulk_axis(4), bulk_axis(8));
    let mut out = vec![0.0; 45];
    for f in fractals(Octaves { count: 5, ..Octaves::default() }) {
        f.eval2_many(&x, &y, &mut out);
        f.eval3_many(&x, &y, &z, &mut out);
        for b in BAD {
            f.eval2_row(&x, b, &mut out);
            f.eval2_row(&[b; 45], 0.5, &mut out);
        }
    }
    black_box(out);
}

#[test]
fn fbm_non_finite_octave_parameters() {
    let (x, y) = (bulk_axis(0), bulk_axis(2));
    let mut out = vec![0.0; 45];
    let mut params = Vec::new();
    for b in BAD.into_iter().chain([0.0, -1.0, 1.0]) {
        params.push(Octaves { count: 6, lacunarity: b, gain: 0.5 });
        params.push(Octaves { count: 6, lacunarity: 2.0, gain: b });
        params.push(Octaves { count: 24, lacunarity: b, gain: b });
    }
    for count in [0, 1, 24, 25, u32::MAX] {
        params.push(Octaves { count, ..Octaves::default() });
    }
    for octaves in params {
        for f in fractals(octaves) {
            black_box(f.amplitude_sum());
            black_box(f.all_octaves_resolved(0.01));
            black_box(f.eval([0.3, 0.6, 0.9], 3, 0.0));
            black_box(f.eval_d([0.3, 0.6, 0.9], 2, 0.01));
            black_box(f.eval3_lanes(&[0.3; 8], &[0.6; 8], &[0.9; 8]));
            f.eval2_row(&x, 0.4, &mut out);
            f.eval2_many(&x, &y, &mut out);
        }
    }
    black_box(out);
}

#[test]
fn bias_and_gain_non_finite() {
    for b in BAD.into_iter().chain([0.0, 0.5, 1.0, -1.0]) {
        for t in BAD.into_iter().chain([0.0, 0.25, 0.5, 1.0]) {
            black_box(bias(b, t));
            black_box(gain(b, t));
        }
    }
}

// ---------------------------------------------------------------------------------------------------
// Procedural: the patterns (effects), baking and solid textures.

fn patterns(dims: usize) -> Vec<Pattern> {
    let mut v = Vec::new();
    for kind in Kind::ALL {
        for tile in [false, true] {
            if tile && !kind.tiles() {
                continue;
            }
            v.push(Pattern::new(Params::new(kind), dims, tile).expect("the defaults are valid"));
        }
    }
    v
}

#[test]
fn pattern_eval_non_finite_points() {
    for dims in [2, 3] {
        for p in patterns(dims) {
            for q in bad_points() {
                for width in [0.0, 0.01, 0.7] {
                    black_box(p.eval_d(q, width));
                    black_box(p.color(q, width));
                }
            }
        }
    }
}

#[test]
fn pattern_eval_non_finite_widths() {
    for dims in [2, 3] {
        for p in patterns(dims) {
            for width in BAD {
                black_box(p.eval_d([0.3, 0.6, 0.9], width));
                black_box(p.color([0.3, 0.6, 0.9], width));
                black_box(p.eval([width, width, width], width));
            }
        }
    }
}

#[test]
fn pattern_row_non_finite_arguments() {
    let mut out = vec![0.0; 45];
    for dims in [2, 3] {
        for p in patterns(dims) {
            for b in BAD {
                p.row(b, 0.01, 0.5, 0.001, &mut out);
                p.row(0.1, b, 0.5, 0.001, &mut out);
                p.row(0.1, 0.01, b, 0.001, &mut out);
                p.row(0.1, 0.01, 0.5, b, &mut out);
                p.row(b, b, b, b, &mut out);
            }
        }
    }
    black_box(out);
}

/// Ways to put a bad number into a pattern's float parameters: each field alone, and all of them at once.
const PARAM_SETTERS: [fn(&mut Params, f32); 10] = [
    |p, b| p.scale = b,
    |p, b| p.octaves.lacunarity = b,
    |p, b| p.octaves.gain = b,
    |p, b| p.strength = b,
    |p, b| p.rings = b,
    |p, b| p.time = b,
    |p, b| p.mortar = b,
    |p, b| p.line_width = b,
    |p, b| p.colors.iter_mut().for_each(|c| c[0] = b),
    |p, b| {
        p.scale = b;
        p.strength = b;
        p.rings = b;
        p.time = b;
        p.mortar = b;
        p.line_width = b;
    },
];

/// A pattern's value with derivatives, colour and a row of values.
fn exercise(p: &Pattern, footprint: f32, out: &mut [f32]) {
    black_box(p.eval_d([0.3, 0.6, 0.9], 0.01));
    black_box(p.color([0.3, 0.6, 0.9], 0.0));
    p.row(0.0, 0.05, 0.5, footprint, out);
}

/// Each parameter bad in turn: `Pattern::new` should refuse it (an `Err`, no panic); what it accepts is
/// evaluated.
#[test]
fn pattern_new_non_finite_parameters() {
    let mut out = vec![0.0; 20];
    // And a count of octaves from the bad number (which `new` must refuse beyond its limit).
    let count: fn(&mut Params, f32) = |p, b| p.octaves.count = if b.is_nan() { 0 } else { b.abs().min(4e9) as u32 };
    for kind in Kind::ALL {
        for set in PARAM_SETTERS.into_iter().chain([count]) {
            for b in BAD {
                for (dims, tile) in [(2, false), (3, false), (2, true)] {
                    let mut params = Params::new(kind);
                    set(&mut params, b);
                    if let Ok(p) = Pattern::new(params, dims, tile) {
                        exercise(&p, 0.05, &mut out);
                    }
                }
            }
        }
    }
}

/// `Pattern::params` is public: bad numbers written into a validated pattern.
#[test]
fn pattern_params_set_non_finite_after_validation() {
    let mut out = vec![0.0; 45];
    for dims in [2, 3] {
        for base in patterns(dims) {
            for b in BAD {
                for set in PARAM_SETTERS {
                    let mut p = base.clone();
                    set(&mut p.params, b);
                    exercise(&p, 0.001, &mut out);
                }
            }
        }
    }
}

/// `Pattern::params` is public: a validated pattern whose colour list is emptied.
#[test]
fn pattern_color_with_empty_colors() {
    let mut p = Pattern::new(Params::new(Kind::Marble), 2, false).unwrap();
    p.params.colors.clear();
    black_box(p.color([0.3, 0.6, 0.9], 0.0));
}

#[test]
fn spline_non_finite() {
    let palettes: Vec<Vec<[f32; 3]>> = vec![
        vec![[0.2, 0.4, 0.6]],
        vec![[0.0; 3], [1.0; 3]],
        vec![[0.0; 3], [0.5, 0.2, 0.1], [1.0; 3], [0.3; 3]],
        vec![[NAN, INF, -INF], [1e30, -1e30, SUB], [0.5; 3]],
        vec![[NAN; 3]; 5],
    ];
    for colors in &palettes {
        for t in BAD.into_iter().chain([0.0, 0.5, 1.0]) {
            black_box(spline(colors, t));
        }
    }
}

#[test]
fn spline_empty_colors() {
    black_box(spline(&[], 0.5));
}

#[test]
fn bake_with_non_finite_params() {
    for mut p in patterns(2) {
        p.params.scale = NAN;
        p.params.strength = INF;
        black_box(bake(&p, 9, 5));
        let mut out = vec![0.0; 9 * 2 + 4];
        bake_rows(&p, 9, 5, 3, &mut out);
        bake_rows(&p, 9, 5, usize::MAX - 1, &mut out);
    }
}

#[test]
fn bake_zero_size() {
    let p = Pattern::new(Params::new(Kind::Checker), 2, false).unwrap();
    black_box(bake(&p, 0, 4));
    black_box(bake(&p, 0, 0));
}

/// Eight surface points with the given tangents and footprint.
fn surface_lanes<'a>(p: V3, dpdu: V3, dpdv: V3, footprint: &Footprint8) -> SurfaceLanes<'a> {
    SurfaceLanes::new(p, dpdu, dpdv, footprint, 0, [0; 8])
}

fn ordinary_footprint8() -> Footprint8 {
    Footprint8 { dudx: F8::splat(0.01), dvdx: F8::ZERO, dudy: F8::ZERO, dvdy: F8::splat(0.01) }
}

fn bad_footprint8s() -> Vec<Footprint8> {
    let mut v = vec![ordinary_footprint8()];
    for set in lane_sets() {
        let f = F8::new(set);
        v.push(Footprint8 { dudx: f, dvdx: f, dudy: f, dvdy: f });
        v.push(Footprint8 { dudx: f, dvdx: F8::ZERO, dudy: F8::ZERO, dvdy: F8::splat(0.01) });
    }
    v
}

fn bad_contexts() -> Vec<LookupContext> {
    let mut v = Vec::new();
    let base = base_context();
    v.push(base);
    v.push(LookupContext::default());
    for d in bad_vecs() {
        v.push(LookupContext { p: d, ..base });
        v.push(LookupContext { n: d, ..base });
        v.push(LookupContext { dpdx: d, dpdy: d, ..base });
        v.push(LookupContext { dpdu: d, dpdv: d, ..base });
        v.push(LookupContext { dndx: d, dndy: d, ..base });
        v.push(LookupContext { p: d, n: d, dpdx: d, dpdy: d, dpdu: d, dpdv: d, dndx: d, dndy: d, ..base });
    }
    v.extend(bad_uv_contexts(base));
    for object_to_eye in bad_affines() {
        v.push(LookupContext { object_to_eye, ..base });
    }
    v
}

/// `base` with bad texture coordinates (set 0 and set 1) and bad footprints.
fn bad_uv_contexts(base: LookupContext) -> Vec<LookupContext> {
    let mut v = Vec::new();
    for b in BAD {
        v.push(LookupContext { uv: Vec2::splat(b), ..base });
        v.push(LookupContext { uv: Vec2::new(b, 0.5), ..base });
        v.push(LookupContext {
            uv1: UvSet {
                uv: Vec2::splat(b),
                footprint: Footprint { dudx: b, dvdx: b, dudy: b, dvdy: b },
                jacobian: [Vec2::splat(b); 2],
            },
            ..base
        });
    }
    for footprint in bad_footprints() {
        v.push(LookupContext { footprint, ..base });
    }
    v
}

fn solid_textures() -> Vec<Procedural> {
    let mut v = Vec::new();
    for (dims, space) in [(3, Space::Object), (2, Space::Uv)] {
        for pattern in patterns(dims) {
            v.push(Procedural { pattern, space });
        }
    }
    v
}

#[test]
fn solid_texture_eval_non_finite_contexts() {
    let contexts = bad_contexts();
    for tex in solid_textures() {
        for ctx in &contexts {
            black_box(tex.eval(ctx));
            black_box(tex.eval_d(ctx));
        }
    }
}

#[test]
fn solid_texture_eval8_mixed_lanes() {
    let v3s = bad_v3s();
    let footprints = bad_footprint8s();
    let sets = lane_sets();
    for tex in solid_textures() {
        for (i, p) in v3s.iter().enumerate() {
            let t = v3s[(i + 5) % v3s.len()];
            let footprint = footprints[i % footprints.len()];
            let surface = surface_lanes(*p, t, V3::splat(Vec3::Y), &footprint);
            let set = F8::new(sets[i % sets.len()]);
            let ctx = LookupContext8 { surface: &surface, u: set, v: F8::splat(0.5), footprint };
            black_box(tex.eval8(&ctx));
        }
    }
}

// ---------------------------------------------------------------------------------------------------
// Procedural: hypertexture.

fn egg() -> Hypertexture {
    Hypertexture {
        center: Vec3::new(0.5, 0.0, -1.0),
        radii: Vec3::new(1.0, 1.3, 1.0),
        soft: 0.4,
        density: 8.0,
        step: 0.05,
        modulations: vec![
            Modulation::noise(Sum::Fbm, 0.5, 3.0, 4, 1, Vec3::ZERO),
            Modulation::Bias(0.6),
            Modulation::Gain(0.7),
            Modulation::noise(Sum::Turbulence, 0.3, 2.0, 3, 2, Vec3::new(0.1, 0.2, 0.3)),
        ],
        shading: Shading::Lit { albedo: Vec3::new(0.8, 0.7, 0.6) },
    }
}

fn fire() -> Hypertexture {
    Hypertexture { shading: Shading::Emissive { colors: Kind::Fire.default_colors(), emission: 2.0 }, ..egg() }
}

fn lights() -> Vec<Light> {
    vec![
        Light::Directional { direction: Vec3::new(-0.3, -1.0, -0.5).normalize(), radiance: Vec3::ONE },
        Light::Point { position: Vec3::new(2.0, 3.0, 1.0), radiance: Vec3::splat(10.0) },
        Light::Ambient { radiance: Vec3::splat(0.1) },
        Light::Spot(Spot::new(Vec3::new(0.0, 4.0, 0.0), -Vec3::Y, Vec3::Z, 30.0, 10.0, Vec3::ONE)),
        Light::Environment { radiance: Vec3::ONE },
    ]
}

/// Lights with bad numbers in them.
fn bad_lights() -> Vec<Light> {
    let mut v = Vec::new();
    for d in bad_vecs() {
        v.push(Light::Directional { direction: d, radiance: Vec3::ONE });
        v.push(Light::Directional { direction: -Vec3::Y, radiance: d });
        v.push(Light::Point { position: d, radiance: Vec3::ONE });
        v.push(Light::Point { position: Vec3::Y, radiance: d });
        v.push(Light::Ambient { radiance: d });
        v.push(Light::Spot(Spot::new(d, -Vec3::Y, Vec3::Z, 30.0, 10.0, Vec3::ONE)));
        v.push(Light::Spot(Spot::new(Vec3::Y * 4.0, d, Vec3::Z, 30.0, 10.0, Vec3::ONE)));
        v.push(Light::Spot(Spot::new(Vec3::Y * 4.0, -Vec3::Y, d, 30.0, 10.0, d)));
    }
    for b in BAD {
        v.push(Light::Spot(Spot::new(Vec3::Y * 4.0, -Vec3::Y, Vec3::Z, b, 10.0, Vec3::ONE)));
        v.push(Light::Spot(Spot::new(Vec3::Y * 4.0, -Vec3::Y, Vec3::Z, 30.0, b, Vec3::ONE)));
    }
    v
}

#[test]
fn hypertexture_eval_non_finite_points() {
    for h in [egg(), fire()] {
        for x in bad_vecs() {
            black_box(h.eval(x));
        }
        for lanes in bad_lane_vecs() {
            black_box(h.density_lanes(&lanes));
        }
    }
}

/// Each numeric parameter of the hypertexture bad in turn, evaluated at ordinary points.
fn bad_hypertextures() -> Vec<Hypertexture> {
    let mut v = Vec::new();
    for d in bad_vecs() {
        v.push(Hypertexture { center: d, ..egg() });
        v.push(Hypertexture { radii: d, ..egg() });
        v.push(Hypertexture { modulations: vec![Modulation::noise(Sum::Fbm, 0.5, 3.0, 4, 1, d)], ..egg() });
    }
    for b in BAD.into_iter().chain([0.0, -1.0]) {
        v.push(Hypertexture { soft: b, ..egg() });
        v.push(Hypertexture { density: b, ..egg() });
        v.push(Hypertexture { modulations: vec![Modulation::Bias(b)], ..egg() });
        v.push(Hypertexture { modulations: vec![Modulation::Gain(b)], ..egg() });
        // (Huge negative noise amplitudes have their own tests below.)
        if b.is_nan() || b >= -1e9 {
            v.push(Hypertexture {
                modulations: vec![Modulation::noise(Sum::Turbulence, b, 3.0, 4, 1, Vec3::ZERO)],
                ..egg()
            });
        }
        v.push(Hypertexture { modulations: vec![Modulation::noise(Sum::Fbm, 0.5, b, 4, 1, Vec3::ZERO)], ..egg() });
        v.push(Hypertexture {
            shading: Shading::Emissive { colors: vec![[b, 0.5, 0.2], [1.0, b, 0.0]], emission: b },
            ..egg()
        });
        v.push(Hypertexture { shading: Shading::Lit { albedo: Vec3::splat(b) }, ..egg() });
    }
    v
}

#[test]
fn hypertexture_eval_non_finite_parameters() {
    let points = [Vec3::new(0.5, 0.0, -1.0), Vec3::new(0.9, 0.3, -0.8), Vec3::new(3.0, 0.0, 0.0)];
    for h in bad_hypertextures() {
        for x in points {
            black_box(h.eval(x));
        }
        black_box(h.density_lanes(&std::array::from_fn(|i| points[i % 3] + Vec3::splat(0.01 * i as f32))));
    }
}

/// The march with bad parameters (an ordinary step): every ray must finish.
#[test]
fn hypertexture_composite_non_finite_parameters() {
    in_child_process("hypertexture_composite_non_finite_parameters", 20, || {
        let lights = lights();
        for h in bad_hypertextures() {
            black_box(h.composite(Vec3::new(0.5, 0.0, 4.0), -Vec3::Z, INF, Vec3::splat(0.2), &lights));
        }
    });
}

/// The march along rays with bad origins, directions, ends and backgrounds.
#[test]
fn hypertexture_composite_non_finite_rays() {
    in_child_process("hypertexture_composite_non_finite_rays", 20, || {
        let lights = lights();
        for h in [egg(), fire()] {
            for d in bad_vecs() {
                black_box(h.composite(d, -Vec3::Z, INF, Vec3::ZERO, &lights));
                black_box(h.composite(Vec3::new(0.5, 0.0, 4.0), d, INF, Vec3::ZERO, &lights));
                black_box(h.composite(Vec3::new(0.5, 0.0, 4.0), -Vec3::Z, INF, d, &lights));
            }
            for b in BAD {
                black_box(h.composite(Vec3::new(0.5, 0.0, 4.0), -Vec3::Z, b, Vec3::ZERO, &lights));
            }
        }
    });
}

/// The march lit by lights with bad numbers.
#[test]
fn hypertexture_composite_non_finite_lights() {
    in_child_process("hypertexture_composite_non_finite_lights", 20, || {
        let h = egg();
        for light in bad_lights() {
            black_box(h.composite(Vec3::new(0.5, 0.0, 4.0), -Vec3::Z, INF, Vec3::ZERO, &[light]));
        }
    });
}

/// A step of 0: (end - t0) / step is infinite.
#[test]
fn hypertexture_composite_zero_step() {
    in_child_process("hypertexture_composite_zero_step", 5, || {
        let h = Hypertexture { step: 0.0, ..egg() };
        black_box(h.composite(Vec3::new(0.5, 0.0, 4.0), -Vec3::Z, INF, Vec3::ZERO, &lights()));
    });
}

/// A subnormal step.
#[test]
fn hypertexture_composite_subnormal_step() {
    in_child_process("hypertexture_composite_subnormal_step", 5, || {
        let h = Hypertexture { step: SUB, ..egg() };
        black_box(h.composite(Vec3::new(0.5, 0.0, 4.0), -Vec3::Z, INF, Vec3::ZERO, &lights()));
    });
}

/// A step of 1e-30: finite, but the number of steps is not.
#[test]
fn hypertexture_composite_tiny_step() {
    in_child_process("hypertexture_composite_tiny_step", 5, || {
        let h = Hypertexture { step: 1e-30, ..egg() };
        black_box(h.composite(Vec3::new(0.5, 0.0, 4.0), -Vec3::Z, INF, Vec3::ZERO, &lights()));
    });
}

/// A direction of length 1e-15 (not unit): the ray's parameter runs to 1e15.
#[test]
fn hypertexture_composite_tiny_direction() {
    in_child_process("hypertexture_composite_tiny_direction", 5, || {
        let h = egg();
        black_box(h.composite(Vec3::new(0.5, 0.0, 4.0), -Vec3::Z * 1e-15, INF, Vec3::ZERO, &lights()));
    });
}

/// Turbulence (|noise| >= 0) added with amplitude -3e9: the bounding ellipsoid grows to 2e9 radii while
/// the density is zero everywhere, so the march walks its 1e11 ordinary steps.
#[test]
fn hypertexture_composite_huge_negative_noise_amplitude() {
    in_child_process("hypertexture_composite_huge_negative_noise_amplitude", 5, || {
        let h = Hypertexture {
            modulations: vec![Modulation::noise(Sum::Turbulence, -3e9, 3.0, 4, 1, Vec3::ZERO)],
            ..egg()
        };
        black_box(h.composite(Vec3::new(0.5, 0.0, 4.0), -Vec3::Z, INF, Vec3::ZERO, &lights()));
    });
}

/// The same with -1e30 and -f32::MAX (the bound then overflows or underflows the ray's quadratic).
#[test]
fn hypertexture_composite_extreme_negative_noise_amplitudes() {
    in_child_process("hypertexture_composite_extreme_negative_noise_amplitudes", 5, || {
        for amplitude in [-1e30, -f32::MAX, -INF] {
            let h = Hypertexture {
                modulations: vec![Modulation::noise(Sum::Turbulence, amplitude, 3.0, 4, 1, Vec3::ZERO)],
                ..egg()
            };
            black_box(h.composite(Vec3::new(0.5, 0.0, 4.0), -Vec3::Z, INF, Vec3::ZERO, &lights()));
        }
    });
}

/// An empty volume (density 0) inside a huge but finite ellipsoid (radii 3e9): an ordinary step, and
/// nothing makes the march stop early.
#[test]
fn hypertexture_composite_zero_density_huge_radii() {
    in_child_process("hypertexture_composite_zero_density_huge_radii", 5, || {
        let h = Hypertexture { radii: Vec3::splat(3e9), density: 0.0, ..egg() };
        black_box(h.composite(Vec3::new(0.5, 0.0, 4.0), -Vec3::Z, INF, Vec3::ZERO, &lights()));
    });
}

/// The same tiny direction through an ellipsoid without noise, whose density only rises slowly from its
/// edge: the march's steps are 5e-17 world units long.
#[test]
fn hypertexture_composite_tiny_direction_plain_ellipsoid() {
    in_child_process("hypertexture_composite_tiny_direction_plain_ellipsoid", 5, || {
        let h = Hypertexture { modulations: Vec::new(), ..egg() };
        black_box(h.composite(Vec3::new(0.5, 0.0, 4.0), -Vec3::Z * 1e-15, INF, Vec3::ZERO, &lights()));
    });
}

/// Emissive shading whose colour list is empty.
#[test]
fn hypertexture_composite_empty_colors() {
    let h = Hypertexture { shading: Shading::Emissive { colors: Vec::new(), emission: 1.0 }, ..egg() };
    black_box(h.composite(Vec3::new(0.5, 0.0, 4.0), -Vec3::Z, INF, Vec3::ZERO, &lights()));
}

// ---------------------------------------------------------------------------------------------------
// Environment maps.

fn env_images(layout: Layout) -> Vec<Image<[f32; 4]>> {
    let texel = |k: usize, x: usize, y: usize| [k as f32 * 0.1, x as f32 * 0.05, y as f32 * 0.07, 1.0];
    match layout {
        Layout::LatLong => vec![Image::from_fn(8, 4, |x, y| texel(0, x, y))],
        Layout::Cube => (0..6).map(|k| Image::from_fn(4, 4, |x, y| texel(k, x, y))).collect(),
        Layout::Sphere => vec![Image::from_fn(8, 8, |x, y| texel(0, x, y))],
        Layout::Paraboloid => (0..2).map(|k| Image::from_fn(8, 8, |x, y| texel(k, x, y))).collect(),
    }
}

/// The images with bad texels sprinkled through them.
fn bad_env_images(layout: Layout) -> Vec<Image<[f32; 4]>> {
    env_images(layout)
        .into_iter()
        .map(|mut image| {
            for (i, p) in image.pixels.iter_mut().enumerate() {
                if i % 2 == 0 {
                    let b = BAD[(i / 2) % BAD.len()];
                    *p = [b, -b, b, if i % 4 == 0 { b } else { 1.0 }];
                }
            }
            image
        })
        .collect()
}

fn environments(options: EnvironmentOptions) -> Vec<Environment> {
    Layout::ALL
        .iter()
        .map(|&(_, layout)| Environment::new(layout, &env_images(layout), options).expect("valid images"))
        .collect()
}

/// Directions and derivatives: each bad in turn, and all together.
fn check_environment(env: &Environment) {
    let unit = Vec3::new(0.3, 0.5, -0.8).normalize();
    let small = Vec3::new(0.01, 0.0, 0.01);
    for d in bad_vecs() {
        black_box(env.radiance(d, Vec3::ZERO, Vec3::ZERO));
        black_box(env.radiance(d, small, small));
        black_box(env.radiance(unit, d, small));
        black_box(env.radiance(unit, small, d));
        black_box(env.radiance(d, d, d));
    }
    for axis in [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z] {
        black_box(env.radiance(axis, Vec3::splat(INF), Vec3::splat(NAN)));
        black_box(env.radiance(axis, Vec3::splat(1e30), Vec3::splat(-1e30)));
    }
}

#[test]
fn environment_radiance_non_finite_directions() {
    for env in environments(EnvironmentOptions::default()) {
        check_environment(&env);
    }
}

#[test]
fn environment_radiance8_mixed_lanes() {
    let v3s = bad_v3s();
    for env in environments(EnvironmentOptions::default()) {
        for (i, d) in v3s.iter().enumerate() {
            let ddx = v3s[(i + 3) % v3s.len()];
            let ddy = v3s[(i + 7) % v3s.len()];
            black_box(env.radiance8(d, &V3::ZERO, &V3::ZERO));
            black_box(env.radiance8(d, &ddx, &ddy));
            black_box(env.radiance8(&V3::splat(Vec3::new(0.0, 0.6, 0.8)), &ddx, &ddy));
        }
    }
}

#[test]
fn environment_non_finite_options() {
    for b in BAD {
        for options in [
            EnvironmentOptions { intensity: b, ..EnvironmentOptions::default() },
            EnvironmentOptions { rotate: b, ..EnvironmentOptions::default() },
            EnvironmentOptions {
                filter: FilterOptions { max_aniso: b, ..FilterOptions::default() },
                ..EnvironmentOptions::default()
            },
        ] {
            for env in environments(options) {
                check_environment(&env);
            }
        }
        check_environment(&Environment::constant(Vec3::splat(b)));
    }
}

#[test]
fn environment_non_finite_texels() {
    for &(_, layout) in &Layout::ALL {
        let env = Environment::new(layout, &bad_env_images(layout), EnvironmentOptions::default()).unwrap();
        check_environment(&env);
    }
}

/// Every filter the environment may be looked up through, with bad directions.
#[test]
fn environment_every_filter_non_finite_directions() {
    for (_, filter) in Filter::ALL {
        if filter == Filter::Reference {
            // The supersampled ground truth: slow, and a texture filter (outside this file's brief).
            continue;
        }
        let options = EnvironmentOptions {
            filter: FilterOptions { filter, ..FilterOptions::default() },
            ..EnvironmentOptions::default()
        };
        for env in environments(options) {
            check_environment(&env);
        }
    }
}

fn lobe_of(s: &[f32]) {
    let env = Environment::new(Layout::LatLong, &env_images(Layout::LatLong), EnvironmentOptions::default()).unwrap();
    for &s in s {
        let lobe = env.lobe(s);
        check_environment(&lobe);
    }
}

#[test]
fn environment_lobe_nan_exponent() {
    lobe_of(&[NAN]);
}

#[test]
fn environment_lobe_infinite_exponents() {
    lobe_of(&[INF, -INF]);
}

#[test]
fn environment_lobe_huge_exponents() {
    lobe_of(&[1e30, 3e9, f32::MAX, -1e30]);
}

#[test]
fn environment_lobe_zero_negative_and_subnormal_exponents() {
    lobe_of(&[0.0, -0.0, -1.0, SUB]);
}

#[test]
fn environment_lobe_of_non_finite_texels() {
    for &(_, layout) in &Layout::ALL {
        let env = Environment::new(layout, &bad_env_images(layout), EnvironmentOptions::default()).unwrap();
        check_environment(&env.lobe(1.0));
    }
}

#[test]
fn chart_locate_non_finite_directions() {
    for &(name, layout) in &Layout::ALL {
        for d in bad_vecs() {
            let (at, grads) = layout.locate(d);
            assert!(at.image < layout.images(), "{name}: {d} located in image {} of {}", at.image, layout.images());
            black_box(grads);
        }
        for d in bad_v3s() {
            let (at, grads) = layout.locate8(&d);
            for image in at.image {
                assert!((image as usize) < layout.images(), "{name}: a lane located in image {image}");
            }
            black_box((at.s, at.t, grads));
            black_box(Face::of8(&d));
        }
    }
}

#[test]
fn chart_direction_non_finite_coordinates() {
    for &(_, layout) in &Layout::ALL {
        for image in 0..layout.images() {
            for b in BAD {
                black_box(layout.direction(image, b, 0.5));
                black_box(layout.direction(image, 0.5, b));
                black_box(layout.direction(image, b, b));
            }
        }
    }
}

/// A cube face index past the six faces (an integer out of range, not a float).
#[test]
fn chart_direction_cube_image_out_of_range() {
    black_box(Layout::Cube.direction(6, 0.5, 0.5));
}

#[test]
fn convert_non_finite_environment() {
    for &(_, from) in &Layout::ALL {
        let env = Environment::new(from, &bad_env_images(from), EnvironmentOptions::default()).unwrap();
        for &(_, to) in &Layout::ALL {
            black_box(convert(&env, to, 3));
        }
    }
}

#[test]
fn convert_zero_size() {
    let env = Environment::constant(Vec3::ONE);
    for &(_, to) in &Layout::ALL {
        black_box(convert(&env, to, 0));
    }
}

fn environment_of_empty_images(layout: Layout) {
    let images = vec![Image::new(0, 0, [0.0f32; 4]); layout.images()];
    if let Ok(env) = Environment::new(layout, &images, EnvironmentOptions::default()) {
        black_box(env.radiance(Vec3::Z, Vec3::ZERO, Vec3::ZERO));
    }
}

#[test]
fn environment_of_empty_latlong_image() {
    environment_of_empty_images(Layout::LatLong);
}

#[test]
fn environment_of_empty_cube_faces() {
    environment_of_empty_images(Layout::Cube);
}

#[test]
fn environment_of_empty_sphere_image() {
    environment_of_empty_images(Layout::Sphere);
}

#[test]
fn environment_of_empty_paraboloid_images() {
    environment_of_empty_images(Layout::Paraboloid);
}

// ---------------------------------------------------------------------------------------------------
// Mapping.

fn sphere_ranges() -> Vec<SphereRange> {
    vec![
        SphereRange::default(),
        SphereRange { longitude: [0.0, 0.0], latitude: [0.0, 0.0] },
        SphereRange { longitude: [NAN, INF], latitude: [-INF, 1e30] },
        SphereRange { longitude: [SUB, -0.0], latitude: [3e9, -3e9] },
    ]
}

fn projections() -> Vec<Projection> {
    let mut v =
        vec![Projection::Uv, Projection::SecondUv, Projection::Planar, Projection::Cylindrical, Projection::Box];
    v.push(Projection::SphereMap);
    for range in sphere_ranges() {
        v.push(Projection::Spherical(range));
    }
    for surface in
        [MapSurface::Plane, MapSurface::Cylinder, MapSurface::Sphere(SphereRange::default()), MapSurface::Box]
            .into_iter()
            .chain(sphere_ranges().into_iter().skip(1).map(MapSurface::Sphere))
    {
        for projector in [
            Projector::Isn { flip: true },
            Projector::Isn { flip: false },
            Projector::Normal,
            Projector::Centroid,
            Projector::Reflected,
        ] {
            v.push(Projection::TwoPart { surface, projector });
        }
    }
    let plane = Vec4::new(0.5, 0.25, 0.0, 0.5);
    v.push(Projection::ObjectLinear { s: plane, t: Vec4::new(0.25, 0.5, 0.5, 0.0) });
    v.push(Projection::EyeLinear { s: plane, t: Vec4::new(0.25, 0.5, 0.5, 0.0) });
    for b in [NAN, INF, 1e30] {
        v.push(Projection::ObjectLinear { s: Vec4::splat(b), t: plane });
        v.push(Projection::EyeLinear { s: plane, t: Vec4::splat(b) });
    }
    let tri = TriangleMapping::new(
        [Vec3::new(0.3, -1.0, 2.0), Vec3::new(2.0, 0.5, 1.5), Vec3::new(-0.5, 1.5, 2.5)],
        [Vec2::new(0.1, 0.2), Vec2::new(0.9, 0.3), Vec2::new(0.4, 0.95)],
    )
    .unwrap();
    v.push(Projection::Triangle(tri));
    let square = [DVec3::ZERO, DVec3::X, DVec3::X + DVec3::Y, DVec3::Y];
    let uvs = [Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y];
    v.push(Projection::Quad(QuadMapping { corners: square, uv: uvs }));
    v.push(Projection::Quad(QuadMapping {
        corners: [DVec3::ZERO, DVec3::new(1.0, 0.2, 0.1), DVec3::new(0.8, 1.3, 0.0), DVec3::new(-0.1, 0.9, 0.3)],
        uv: uvs,
    }));
    v.push(Projection::Quad(QuadMapping { corners: [DVec3::ZERO; 4], uv: uvs }));
    v.push(Projection::Quad(QuadMapping { corners: [DVec3::splat(f64::NAN); 4], uv: uvs }));
    v.push(Projection::Quad(QuadMapping { corners: square, uv: [Vec2::splat(NAN); 4] }));
    v
}

fn mappings() -> Vec<Mapping> {
    let mut v = Vec::new();
    for projection in projections() {
        for to_mapping in [Affine3A::IDENTITY, Affine3A::from_scale(Vec3::splat(0.5))] {
            v.push(Mapping { projection, to_mapping, transform: UvTransform::IDENTITY });
        }
        v.push(Mapping {
            projection,
            to_mapping: Affine3A::IDENTITY,
            transform: UvTransform::new(Vec2::new(0.1, 0.2), 30.0, Vec2::new(2.0, 3.0)),
        });
    }
    v
}

fn check_mapping_contexts(contexts: &[LookupContext]) {
    for m in mappings() {
        for ctx in contexts {
            black_box(m.apply(ctx));
            black_box(m.apply_with_jacobian(ctx));
        }
        black_box(m.constant_jacobian());
    }
}

fn base_context() -> LookupContext {
    let p = Vec3::new(0.3, 0.2, 0.9);
    LookupContext {
        n: p * 2.0,
        dndx: Vec3::new(0.001, 0.0, 0.0),
        dndy: Vec3::new(0.0, 0.001, 0.0),
        object_to_eye: Affine3A::from_translation(Vec3::new(0.0, 0.0, -5.0)),
        ..LookupContext::on_surface(
            p,
            Vec3::X,
            Vec3::Y,
            Vec2::new(0.4, 0.6),
            Footprint { dudx: 0.01, dvdx: 0.0, dudy: 0.0, dvdy: 0.01 },
        )
    }
}

#[test]
fn mapping_non_finite_points() {
    let base = base_context();
    let contexts: Vec<_> = bad_vecs().into_iter().map(|p| LookupContext { p, ..base }).collect();
    check_mapping_contexts(&contexts);
}

#[test]
fn mapping_non_finite_and_zero_normals() {
    let base = base_context();
    let contexts: Vec<_> = bad_vecs().into_iter().map(|n| LookupContext { n, ..base }).collect();
    check_mapping_contexts(&contexts);
}

#[test]
fn mapping_non_finite_pixel_steps() {
    let base = base_context();
    let contexts: Vec<_> = bad_vecs().into_iter().map(|d| LookupContext { dpdx: d, dpdy: d * 0.5, ..base }).collect();
    check_mapping_contexts(&contexts);
}

#[test]
fn mapping_non_finite_tangents() {
    let base = base_context();
    let contexts: Vec<_> = bad_vecs().into_iter().map(|d| LookupContext { dpdu: d, dpdv: -d, ..base }).collect();
    check_mapping_contexts(&contexts);
}

#[test]
fn mapping_non_finite_normal_changes() {
    let base = base_context();
    let contexts: Vec<_> = bad_vecs().into_iter().map(|d| LookupContext { dndx: d, dndy: d, ..base }).collect();
    check_mapping_contexts(&contexts);
}

#[test]
fn mapping_non_finite_uv_and_footprints() {
    check_mapping_contexts(&bad_uv_contexts(base_context()));
}

#[test]
fn mapping_non_finite_object_to_eye() {
    let base = base_context();
    let contexts: Vec<_> =
        bad_affines().into_iter().map(|object_to_eye| LookupContext { object_to_eye, ..base }).collect();
    check_mapping_contexts(&contexts);
}

#[test]
fn mapping_everything_non_finite() {
    let contexts: Vec<_> = BAD
        .iter()
        .map(|&b| {
            let d = Vec3::splat(b);
            LookupContext {
                p: d,
                dpdx: d,
                dpdy: d,
                n: d,
                dpdu: d,
                dpdv: d,
                uv: Vec2::splat(b),
                footprint: Footprint { dudx: b, dvdx: b, dudy: b, dvdy: b },
                uv1: UvSet { uv: Vec2::splat(b), ..UvSet::default() },
                dndx: d,
                dndy: d,
                object_to_eye: Affine3A::from_scale(d),
                ..LookupContext::default()
            }
        })
        .collect();
    check_mapping_contexts(&contexts);
}

#[test]
fn mapping_non_finite_placement() {
    let base = base_context();
    for projection in projections() {
        for to_mapping in bad_affines() {
            for transform in [
                UvTransform::IDENTITY,
                UvTransform::new(Vec2::splat(NAN), 0.0, Vec2::ONE),
                UvTransform::new(Vec2::ZERO, NAN, Vec2::ONE),
                UvTransform::new(Vec2::ZERO, INF, Vec2::splat(1e30)),
                UvTransform::new(Vec2::ZERO, 3e9, Vec2::ZERO),
                UvTransform::repeat(Vec2::splat(SUB)),
            ] {
                let m = Mapping { projection, to_mapping, transform };
                black_box(m.apply_with_jacobian(&base));
                black_box(m.apply(&LookupContext { p: Vec3::splat(NAN), ..base }));
            }
        }
    }
}

#[test]
fn mapping_apply8_mixed_lanes() {
    let v3s = bad_v3s();
    let footprints = bad_footprint8s();
    let sets = lane_sets();
    let uv1 = UvSet8 {
        u: F8::new(LANE_BAD),
        v: F8::splat(0.5),
        footprint: footprints[1],
        jacobian: [(F8::new(LANE_BAD), F8::ZERO), (F8::ZERO, F8::new(LANE_BAD))],
    };
    for m in mappings() {
        for (i, p) in v3s.iter().enumerate().step_by(2) {
            let footprint = footprints[i % footprints.len()];
            let mut surface = surface_lanes(*p, V3::splat(Vec3::X), V3::splat(Vec3::Y), &footprint);
            surface.n = v3s[(i + 1) % v3s.len()];
            surface.dndx = v3s[(i + 2) % v3s.len()];
            surface.dndy = v3s[(i + 3) % v3s.len()];
            surface.dpdx = v3s[(i + 4) % v3s.len()];
            for with_uv1 in [false, true] {
                surface.uv1 = with_uv1.then_some(&uv1);
                let set = F8::new(sets[i % sets.len()]);
                let ctx = LookupContext8 { surface: &surface, u: set, v: F8::splat(0.25), footprint };
                black_box(m.apply8(&ctx));
            }
        }
    }
}

fn mapped_textures() -> Vec<MappedTexture> {
    let image = Image::from_fn(4, 4, |x, y| [x as f32 * 0.25, y as f32 * 0.25, 0.5, 1.0]);
    let textures: Vec<Arc<dyn Texture>> = vec![
        Arc::new(FilteredTexture::new(&image, TextureOptions::default())),
        Arc::new(Procedural {
            pattern: Pattern::new(Params::new(Kind::Checker), 3, false).unwrap(),
            space: Space::Object,
        }),
        Arc::new(Procedural { pattern: Pattern::new(Params::new(Kind::Fbm), 2, true).unwrap(), space: Space::Uv }),
    ];
    let mut v = Vec::new();
    for texture in textures {
        for mapping in mappings().into_iter().step_by(3) {
            v.push(MappedTexture { texture: Arc::clone(&texture), mapping });
        }
    }
    v
}

#[test]
fn mapped_texture_eval_non_finite_contexts() {
    let contexts = bad_contexts();
    for t in mapped_textures() {
        for ctx in contexts.iter().step_by(2) {
            black_box(t.eval(ctx));
        }
    }
}

#[test]
fn mapped_texture_eval8_mixed_lanes() {
    let v3s = bad_v3s();
    let footprints = bad_footprint8s();
    let sets = lane_sets();
    for t in mapped_textures() {
        for (i, p) in v3s.iter().enumerate().step_by(3) {
            let footprint = footprints[i % footprints.len()];
            let mut surface = surface_lanes(*p, V3::splat(Vec3::X), V3::splat(Vec3::Y), &footprint);
            surface.n = v3s[(i + 1) % v3s.len()];
            let ctx =
                LookupContext8 { surface: &surface, u: F8::new(sets[i % sets.len()]), v: F8::splat(0.5), footprint };
            black_box(t.eval8(&ctx));
            black_box(t.eval8_with_coords(&ctx));
        }
    }
}

#[test]
fn projection_point_and_normal_through_non_finite() {
    let affines = bad_affines();
    for p in bad_vecs() {
        for (i, m) in affines.iter().enumerate() {
            let other = &affines[(i + 3) % affines.len()];
            black_box(projection::point(p, Vec3::Z, Vec3::new(0.0, 0.0, 5.0), m, other));
            black_box(projection::point(Vec3::ONE, p, Vec3::new(0.0, 0.0, 5.0), m, other));
            black_box(projection::point(Vec3::ONE, Vec3::Z, p, m, other));
            black_box(projection::normal_through(m, p));
        }
    }
}

#[test]
fn projection_coords_non_finite_points() {
    let mut points = Vec::new();
    for d in bad_vecs() {
        let ok = Vec3::new(0.3, 0.4, 0.5);
        points.push(Point { q: d, n: Vec3::Z, view: -Vec3::Z, q_eye: ok, n_eye: Vec3::Z });
        points.push(Point { q: ok, n: d, view: -Vec3::Z, q_eye: ok, n_eye: d });
        points.push(Point { q: ok, n: Vec3::Z, view: d, q_eye: d, n_eye: Vec3::Z });
        points.push(Point { q: d, n: d, view: d, q_eye: d, n_eye: d });
    }
    for projection in projections() {
        if matches!(projection, Projection::Uv | Projection::SecondUv) {
            // `coords` is documented as unreachable for the uv projections (see the report).
            continue;
        }
        for at in &points {
            let choice = projection.choose(at);
            black_box(projection.coords(at, &choice));
            black_box(projection.coords(at, &Default::default()));
        }
    }
}

#[test]
fn uv_transform_non_finite() {
    let sets = lane_sets();
    for b in BAD {
        for t in [
            UvTransform::new(Vec2::splat(b), 0.0, Vec2::ONE),
            UvTransform::new(Vec2::ZERO, b, Vec2::ONE),
            UvTransform::new(Vec2::ZERO, 45.0, Vec2::splat(b)),
            UvTransform::new(Vec2::splat(b), b, Vec2::splat(b)),
            UvTransform::repeat(Vec2::new(b, 1.0)),
        ] {
            black_box(t.linear());
            black_box(t.point(Vec2::splat(b)));
            black_box(t.point(Vec2::new(0.3, 0.4)));
            black_box(t.footprint(&Footprint { dudx: b, dvdx: 0.0, dudy: 0.0, dvdy: b }));
            for set in &sets {
                black_box(t.point8(F8::new(*set), F8::splat(0.5)));
                let f = F8::new(*set);
                black_box(t.footprint8(&Footprint8 { dudx: f, dvdx: f, dudy: f, dvdy: f }));
            }
        }
    }
}

#[test]
fn triangle_mapping_non_finite() {
    let ok = [Vec3::new(0.3, -1.0, 2.0), Vec3::new(2.0, 0.5, 1.5), Vec3::new(-0.5, 1.5, 2.5)];
    let uvs = [Vec2::new(0.1, 0.2), Vec2::new(0.9, 0.3), Vec2::new(0.4, 0.95)];
    for d in bad_vecs() {
        for k in 0..3 {
            let mut points = ok;
            points[k] = d;
            if let Some(m) = TriangleMapping::new(points, uvs) {
                black_box(m.uv(Vec3::ONE));
            }
            let mut bad_uvs = uvs;
            bad_uvs[k] = d.truncate();
            if let Some(m) = TriangleMapping::new(ok, bad_uvs) {
                black_box(m.uv(Vec3::ONE));
                black_box(m.uv(d));
            }
        }
        black_box(TriangleMapping::new([d; 3], uvs));
        black_box(TriangleMapping::new(ok, uvs).unwrap().uv(d));
    }
}

#[test]
fn quad_mapping_non_finite() {
    let square = [DVec3::ZERO, DVec3::X, DVec3::X + DVec3::Y, DVec3::Y];
    let skew = [DVec3::ZERO, DVec3::new(1.0, 0.2, 0.1), DVec3::new(0.8, 1.3, 0.0), DVec3::new(-0.1, 0.9, 0.3)];
    let uvs = [Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y];
    for b in BAD64 {
        let bad = [DVec3::splat(b), DVec3::new(b, 0.5, 0.0), DVec3::new(0.5, b, 0.0), DVec3::new(0.5, 0.5, b)];
        for corners in [square, skew] {
            for p in bad {
                black_box(inverse_bilinear(p, corners));
                black_box(bilinear_parameters(p, corners));
                for k in 0..4 {
                    let mut c = corners;
                    c[k] = p;
                    black_box(inverse_bilinear(DVec3::new(0.5, 0.5, 0.0), c));
                    black_box(bilinear_parameters(DVec3::new(0.5, 0.5, 0.0), c));
                    black_box(QuadMapping { corners: c, uv: uvs }.uv(Vec3::new(0.5, 0.5, 0.0)));
                }
            }
        }
        black_box(bilinear(uvs, DVec2::splat(b)));
        black_box(bilinear([Vec2::splat(b as f32); 4], DVec2::splat(0.5)));
    }
    for d in bad_vecs() {
        for corners in [square, skew, [DVec3::ZERO; 4]] {
            black_box(QuadMapping { corners, uv: uvs }.uv(d));
        }
    }
}

// ---------------------------------------------------------------------------------------------------
// Emboss (Schlag) and normal maps.

/// A `w` x `h` height image whose pixels run through the bad values among ordinary ones.
fn bad_height_image(w: usize, h: usize, offset: usize) -> GreyImage {
    let values = [0.5, NAN, INF, -INF, 1e30, -1e30, 3e9, -0.0, SUB, 255.0, f32::MAX, -3e9];
    Image::from_fn(w, h, |x, y| values[(x + 3 * y + offset) % values.len()])
}

fn height_images() -> Vec<GreyImage> {
    let mut v = Vec::new();
    for (w, h) in [(1, 1), (2, 1), (1, 3), (5, 4), (17, 3)] {
        for offset in [0, 1, 5] {
            v.push(bad_height_image(w, h, offset));
        }
    }
    for b in BAD {
        v.push(Image::new(6, 5, b));
    }
    v
}

#[test]
fn emboss_image_non_finite_pixels() {
    let emboss = Emboss::new(45.0, 30.0, 3.0).unwrap();
    for image in height_images() {
        black_box(emboss_image(&image, &emboss));
    }
}

#[test]
fn emboss_non_finite_parameters() {
    let image = bad_height_image(7, 5, 0);
    let plain = Image::from_fn(7, 5, |x, y| (x * 30 + y * 11) as f32);
    for b in BAD.into_iter().chain([0.0, -1.0, 91.0]) {
        for e in
            [Emboss::new(b, 45.0, 3.0), Emboss::new(30.0, b, 3.0), Emboss::new(30.0, 45.0, b)].into_iter().flatten()
        {
            black_box(emboss_image(&image, &e));
        }
        // The fields are public: an `Emboss` made without `new`.
        for e in [
            Emboss { light: [b, b, b], nz: b, flat: b },
            Emboss { light: [0.5, 0.5, 0.7], nz: b, flat: 0.7 },
            Emboss { light: [b, 0.0, 1.0], nz: 100.0, flat: 1.0 },
        ] {
            black_box(emboss_image(&image, &e));
            black_box(emboss_image(&plain, &e));
        }
    }
}

#[test]
fn emboss_light_direction_non_finite() {
    for a in BAD.into_iter().chain([0.0, 90.0, 360.0]) {
        for e in BAD.into_iter().chain([0.0, 45.0, 90.0]) {
            black_box(light_direction(a, e));
        }
    }
}

#[test]
fn emboss_conversions_non_finite_shades() {
    let shades: Vec<f32> = BAD.into_iter().chain([0.0, 0.5, 1.0, -1.0, 2.0]).collect();
    let mut g8 = vec![0u8; shades.len()];
    let mut g16 = vec![0u8; 2 * shades.len()];
    let texture = vec![200u8; 3 * shades.len()];
    let mut rgb = vec![0u8; 3 * shades.len()];
    to_grey8(&shades, &mut g8);
    to_grey16(&shades, &mut g16);
    modulate_rgb8(&shades, &texture, &mut rgb);
    for &s in &shades {
        black_box(round_to_bits(s));
    }
    black_box((g8, g16, rgb));
}

#[test]
fn emboss_image_empty() {
    let emboss = Emboss::new(45.0, 30.0, 3.0).unwrap();
    black_box(emboss_image(&Image::new(0, 0, 0.0f32), &emboss));
    black_box(emboss_image(&Image::new(0, 3, 0.0f32), &emboss));
}

fn normal_maps(strength: f32) -> Vec<NormalMap> {
    let mut v = Vec::new();
    for kernel in [NormalKernel::Central, NormalKernel::Sobel, NormalKernel::Scharr] {
        for convention in [Convention::OpenGl, Convention::DirectX] {
            v.push(NormalMap { kernel, strength, convention });
        }
    }
    v
}

#[test]
fn normal_map_images_non_finite_pixels() {
    for map in normal_maps(4.0) {
        for image in height_images() {
            for edges in [Edges::Clamp, Edges::Wrap] {
                black_box(map.normals_image(&image, edges));
                black_box(map.slopes_image(&image, edges));
            }
        }
    }
}

#[test]
fn normal_map_non_finite_strength() {
    let image = bad_height_image(7, 5, 2);
    let plain = Image::from_fn(7, 5, |x, y| (x as f32 * 0.1 + y as f32 * 0.05).fract());
    for b in BAD.into_iter().chain([0.0, -1.0]) {
        for kernel in [NormalKernel::Central, NormalKernel::Sobel, NormalKernel::Scharr] {
            if let Ok(map) = NormalMap::new(kernel, b, Convention::OpenGl) {
                black_box(map.normals_image(&plain, Edges::Clamp));
            }
        }
        // The fields are public: a `NormalMap` made without `new`.
        for map in normal_maps(b) {
            for edges in [Edges::Clamp, Edges::Wrap] {
                black_box(map.normals_image(&image, edges));
                black_box(map.normals_image(&plain, edges));
                black_box(map.slopes_image(&plain, edges));
            }
        }
    }
}

#[test]
fn normal_map_encode_decode_non_finite() {
    let values: Vec<f32> = BAD.into_iter().chain([0.0, 1.0, -1.0]).collect();
    let n = values.len();
    let rotated = |k: usize| -> Vec<f32> { (0..n).map(|i| values[(i + k) % n]).collect() };
    let (x, y, z) = (rotated(0), rotated(3), rotated(7));
    let mut out8 = vec![0u8; 3 * n];
    let mut out16 = vec![0u8; 6 * n];
    encode_rgb(&x, &y, &z, false, &mut out8);
    encode_rgb(&x, &y, &z, true, &mut out16);
    for i in 0..n {
        for convention in [Convention::OpenGl, Convention::DirectX] {
            black_box(decode_normal([x[i], y[i], z[i]], convention));
        }
    }
    black_box((out8, out16));
}

#[test]
fn normal_map_integration_non_finite() {
    for b in BAD.into_iter().chain([0.0, -1.0]) {
        let _ = black_box(check_strength(b));
        black_box(gradient_of_normal([b, 0.1, 0.9], 2.0));
        black_box(gradient_of_normal([0.1, b, b], 2.0));
        black_box(gradient_of_normal([0.1, 0.2, 0.9], b));
    }
    let mut heights: Vec<f32> = BAD.to_vec();
    black_box(settle_heights(&mut heights, true));
    black_box(settle_heights(&mut [NAN; 5], true));
    black_box(settle_heights(&mut [INF, -INF], true));
    black_box(settle_heights(&mut [], true));
    let (w, h) = (4, 3);
    let field = |k: usize| -> Vec<f32> {
        (0..w * h).map(|i| if i % 3 == 0 { BAD[(i + k) % BAD.len()] } else { 0.1 }).collect()
    };
    for wrap in [true, false] {
        black_box(frankot_chellappa(&field(0), &field(4), w, h, wrap));
        for b in BAD {
            black_box(frankot_chellappa(&vec![b; w * h], &vec![0.0; w * h], w, h, wrap));
        }
    }
}

#[test]
fn normal_map_image_empty() {
    let map = NormalMap::new(NormalKernel::Sobel, 2.0, Convention::OpenGl).unwrap();
    black_box(map.normals_image(&Image::new(0, 0, 0.0f32), Edges::Clamp));
    black_box(map.slopes_image(&Image::new(0, 2, 0.0f32), Edges::Wrap));
}

#[test]
fn normal_map_integration_zero_size() {
    black_box(frankot_chellappa(&[], &[], 0, 0, true));
    black_box(frankot_chellappa(&[], &[], 0, 0, false));
}

// ---------------------------------------------------------------------------------------------------
// Shading helpers: Blinn-Phong, the widened (LEAN) lobe, spot lights, Blinn's perturbed normal.

#[test]
fn phong_non_finite_parameters() {
    let s = V3::splat;
    for specular in BAD.into_iter().chain([0.0, -1.0, 0.5]) {
        for shininess in BAD.into_iter().chain([0.0, -1.0, 20.0]) {
            let phong = Phong::new(specular, shininess);
            for light in lights() {
                black_box(phong.shade8(
                    &light,
                    s(Vec3::ZERO),
                    s(Vec3::Z),
                    s(Vec3::new(0.2, 0.1, 1.0).normalize()),
                    s(Vec3::splat(0.5)),
                    F8::splat(specular),
                    None,
                    None,
                ));
            }
        }
    }
}

#[test]
fn phong_shade8_mixed_lanes() {
    let v3s = bad_v3s();
    let sets = lane_sets();
    let phong = Phong::new(0.4, 30.0);
    let mut all_lights = lights();
    all_lights.extend(bad_lights().into_iter().step_by(5));
    for light in &all_lights {
        for (i, p) in v3s.iter().enumerate().step_by(2) {
            let n = v3s[(i + 1) % v3s.len()];
            let v = v3s[(i + 2) % v3s.len()];
            let albedo = v3s[(i + 3) % v3s.len()];
            let ks = F8::new(sets[i % sets.len()]);
            let exponent = F8::new(sets[(i + 4) % sets.len()]);
            let unit = V3::splat(Vec3::new(0.1, 0.2, 1.0).normalize());
            black_box(phong.shade8(light, *p, n, v, albedo, ks, None, None));
            black_box(phong.shade8(light, V3::ZERO, unit, unit, V3::splat(Vec3::ONE), ks, Some(exponent), None));
            black_box(phong.shade8(light, V3::ZERO, n, unit, V3::splat(Vec3::ONE), F8::ONE, None, None));
        }
    }
}

#[test]
fn phong_widened_lobe_non_finite() {
    let v3s = bad_v3s();
    let sets = lane_sets();
    let phong = Phong::new(0.4, 30.0);
    let unit = V3::splat(Vec3::new(0.1, 0.2, 1.0).normalize());
    let light = Light::Directional { direction: -Vec3::Z, radiance: Vec3::ONE };
    for (i, set) in sets.iter().enumerate() {
        let f = F8::new(*set);
        let spreads = [
            WorldSpread8 { t1: V3::splat(Vec3::X), t2: V3::splat(Vec3::Y), xx: f, yy: f, xy: f },
            WorldSpread8 {
                t1: V3::splat(Vec3::X),
                t2: V3::splat(Vec3::Y),
                xx: F8::splat(0.01),
                yy: F8::splat(0.01),
                xy: f,
            },
            WorldSpread8 {
                t1: v3s[i % v3s.len()],
                t2: v3s[(i + 1) % v3s.len()],
                xx: F8::splat(0.01),
                yy: F8::splat(0.02),
                xy: F8::ZERO,
            },
        ];
        for spread in spreads {
            for s in [F8::splat(30.0), f, F8::ZERO] {
                let lobe = Lobe8::widened(spread, s);
                black_box(phong.shade8(&light, V3::ZERO, unit, unit, V3::splat(Vec3::ONE), F8::ONE, None, Some(&lobe)));
                black_box(phong.shade8(
                    &light,
                    V3::ZERO,
                    v3s[(i + 2) % v3s.len()],
                    unit,
                    V3::splat(Vec3::ONE),
                    F8::ONE,
                    None,
                    Some(&lobe),
                ));
            }
        }
    }
}

#[test]
fn ibl_phong_exponent_non_finite() {
    for b in BAD {
        black_box(Ibl::phong_exponent(b));
    }
}

#[test]
fn spot_non_finite() {
    let v3s = bad_v3s();
    let mut spots = Vec::new();
    for light in bad_lights() {
        if let Light::Spot(spot) = light {
            spots.push(spot);
        }
    }
    spots.push(Spot::new(Vec3::Y, Vec3::ZERO, Vec3::ZERO, 0.0, 0.0, Vec3::ONE));
    spots.push(Spot::new(Vec3::Y, -Vec3::Y, -Vec3::Y, 90.0, 90.0, Vec3::ONE));
    for spot in spots {
        for p in v3s.iter().step_by(3) {
            black_box(spot.cone8(*p));
            black_box(spot.slide8(*p));
        }
    }
}

fn bad_frames() -> Vec<SurfaceFrame> {
    let base = SurfaceFrame {
        p: Vec3::new(0.1, 0.2, 0.3),
        pu: Vec3::X,
        pv: Vec3::Y,
        puu: Vec3::new(0.0, 0.0, -0.1),
        puv: Vec3::ZERO,
        pvv: Vec3::new(0.0, 0.0, -0.1),
    };
    let mut v = vec![base];
    for d in bad_vecs() {
        v.push(SurfaceFrame { pu: d, ..base });
        v.push(SurfaceFrame { pv: d, ..base });
        v.push(SurfaceFrame { puu: d, puv: d, pvv: d, ..base });
        v.push(SurfaceFrame { p: d, pu: d, pv: d, puu: d, puv: d, pvv: d });
    }
    v
}

#[test]
fn blinn_perturbed_normal_non_finite() {
    let mut gradients = vec![Gradient { f: 0.1, fu: 0.2, fv: -0.3 }];
    for b in BAD {
        gradients.push(Gradient { f: b, fu: 0.2, fv: -0.3 });
        gradients.push(Gradient { f: 0.1, fu: b, fv: -0.3 });
        gradients.push(Gradient { f: 0.1, fu: 0.2, fv: b });
        gradients.push(Gradient { f: b, fu: b, fv: b });
    }
    for frame in bad_frames() {
        black_box(unit_normal_derivatives(&frame));
        for &g in &gradients {
            for formula in [BumpFormula::Blinn, BumpFormula::Invariant, BumpFormula::Full] {
                black_box(perturbed_normal(&frame, g, formula));
            }
            black_box(full_normal(&frame, g));
            black_box(blinn_d(frame.pu.cross(frame.pv), frame.pu, frame.pv, g.fu, g.fv));
        }
    }
}

#[test]
fn blinn_perturbed_normal8_mixed_lanes() {
    let v3s = bad_v3s();
    let sets = lane_sets();
    for (i, pu) in v3s.iter().enumerate() {
        let pv = v3s[(i + 1) % v3s.len()];
        let g =
            [F8::new(sets[i % sets.len()]), F8::new(sets[(i + 1) % sets.len()]), F8::new(sets[(i + 2) % sets.len()])];
        let side = F8::new(sets[(i + 3) % sets.len()]);
        for formula in [BumpFormula::Blinn, BumpFormula::Invariant, BumpFormula::Full] {
            black_box(perturbed_normal_sided8(*pu, pv, g, formula, side));
            black_box(perturbed_normal_sided8(V3::splat(Vec3::X), V3::splat(Vec3::Y), g, formula, F8::ONE));
        }
        black_box(blinn_d8(pu.cross(pv), *pu, pv, g[1], g[2]));
    }
}

#[test]
fn normal_through_singular_matrices() {
    for m in [Mat3::ZERO, Mat3::from_diagonal(Vec3::new(NAN, 1.0, 1.0)), Mat3::from_diagonal(Vec3::splat(1e30))] {
        let a = Affine3A::from_mat3(m);
        for n in bad_vecs() {
            black_box(projection::normal_through(&a, n));
        }
    }
}

#[test]
fn layer_modes_mixed_lanes() {
    let v3s = bad_v3s();
    let sets = lane_sets();
    let modes =
        [Mode::Replace, Mode::Modulate, Mode::Decal, Mode::Blend(Vec3::splat(NAN)), Mode::Blend(Vec3::ONE), Mode::Add];
    for mode in modes {
        for (i, c) in v3s.iter().enumerate() {
            let a = F8::new(sets[i % sets.len()]);
            let b = F8::new(sets[(i + 5) % sets.len()]);
            for rgba in [false, true] {
                black_box(mode.colour8((*c, a), (v3s[(i + 1) % v3s.len()], b), rgba));
                black_box(mode.alpha8(a, b, rgba));
            }
            black_box(mode.scalar8(a, b));
        }
    }
}
