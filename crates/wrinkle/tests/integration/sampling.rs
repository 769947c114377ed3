//! Any sample count, samplers and pixel filters against a ground truth computed here: a checkerboard of
//! point-sampled (nearest) texels on a plane receding to the horizon, lit by an ambient light alone, so a
//! sample's colour is 0 or 1 by which check its ray meets. The truth of a pixel is the integral of that
//! over the pixel filter around its centre, from a 32 x 32 grid of rays a pixel intersected with the plane
//! in f64 (the renderer's samples are never used). Renders converge to it as the sample count grows, at the
//! rate of stratified and quasi-random sampling of an edge (error ~ N^-3/4), not Monte Carlo's N^-1/2.
//!
//! `cargo test --release -p wrinkle --test integration sampling -- --nocapture` prints the measured figures.

use crate::common::*;
use glam::DVec3;
use std::path::Path;
use wrinkle::image::io::write_png_rgb8;
use wrinkle::{render, PixelFilter, RenderOptions, Sampler, Scene};

const W: usize = 96;
const H: usize = 64;
/// Reference rays per pixel along each axis.
const FINE: usize = 32;
/// Checks of the 7 x 7 texture, repeated 4 times across the plane: an odd count, so flipping u or v keeps
/// the pattern and the reference needs no texel-orientation convention.
const CHECKS: usize = 7;
const REPEAT: f64 = 4.0;
const EYE: [f64; 3] = [0.0, 0.6, 2.2];
const LOOK_AT: [f64; 3] = [0.0, 0.15, 0.0];
const FOV: f64 = 50.0;
/// The floor, a parallelogram in y = 0 (P(0,0), P(1,0), P(1,1), P(0,1)), rotated about y so the checks run
/// oblique to the pixel grid.
const CORNERS: [[f64; 3]; 4] = [[-2.5, 0.0, 2.0], [1.9, 0.0, 2.9], [3.4, 0.0, -8.0], [-1.0, 0.0, -8.9]];

fn scene_text(texture: &str) -> String {
    let corners = CORNERS.map(arr).join(", ");
    format!(
        "[camera]\neye = {}\nlook_at = {}\nfov_y = {FOV:?}\nbackground = [0.0, 0.0, 0.0]\n\n\
         [[light]]\ntype = \"ambient\"\nintensity = 1.0\n\n\
         [[object]]\nshape = \"patch\"\ncorners = [{corners}]\n\n\
         [object.material]\ncolor = [1.0, 1.0, 1.0]\nspecular = 0.0\n\
         texture = {{ path = \"{texture}\", filter = \"nearest\", repeat = [{REPEAT:?}, {REPEAT:?}] }}\n",
        arr(EYE),
        arr(LOOK_AT),
    )
}

fn scene() -> Scene {
    let dir = scratch_dir("sampling");
    let texels: Vec<u8> = (0..CHECKS * CHECKS)
        .flat_map(|k| if (k % CHECKS + k / CHECKS).is_multiple_of(2) { [255; 3] } else { [0; 3] })
        .collect();
    write_png_rgb8(&dir.join("checks.png"), CHECKS, CHECKS, &texels).unwrap();
    Scene::parse(&scene_text("checks.png"), &dir).unwrap()
}

/// What a ray through screen position (x, y) sees: 1 on a white check, 0 on a black one or off the floor.
fn seen(cam: &RefCamera, x: f64, y: f64) -> f64 {
    let world = CORNERS.map(DVec3::from);
    let (p00, e1, e2) = (world[0], world[1] - world[0], world[3] - world[0]);
    let (o, d) = cam.ray(x, y);
    let Some(t) = ray_plane(o, d, p00, e1.cross(e2)).filter(|&t| t > 0.0) else { return 0.0 };
    let (u, v) = parallelogram_uv(o + t * d, p00, e1, e2);
    if !(0.0..1.0).contains(&u) || !(0.0..1.0).contains(&v) {
        return 0.0;
    }
    let check = |c: f64| ((c * REPEAT * CHECKS as f64).floor() as i64).rem_euclid(CHECKS as i64);
    ((check(u) + check(v)) % 2 == 0) as u8 as f64
}

/// The ground truth: for every pixel, the filter-weighted mean of what the fine grid of rays sees around
/// its centre (the grid covers the filter's support, past the frame's edges too).
fn truth(filter: &PixelFilter) -> Vec<f64> {
    let cam = RefCamera::perspective(EYE, LOOK_AT, [0.0, 1.0, 0.0], FOV, W, H);
    let reach = filter.radius().ceil() as usize;
    // Fine samples at the centres of a FINE x FINE grid in each pixel, over the frame and `reach` around it.
    let (fw, fh) = ((W + 2 * reach) * FINE, (H + 2 * reach) * FINE);
    let pos = |k: usize| (k as f64 + 0.5) / FINE as f64 - reach as f64;
    let fine: Vec<f64> = (0..fw * fh).map(|k| seen(&cam, pos(k % fw), pos(k / fw))).collect();
    // The filter's weights of the fine samples around a pixel centre, separable: along x, then y.
    let taps = 2 * reach * FINE + FINE;
    let weights: Vec<f64> = (0..taps).map(|t| filter.eval((pos(t) - 0.5) as f32) as f64).collect();
    let total: f64 = weights.iter().sum::<f64>().powi(2);
    let mut rows = vec![0.0; W * fh];
    for fy in 0..fh {
        for px in 0..W {
            rows[fy * W + px] = (0..taps).map(|t| weights[t] * fine[fy * fw + px * FINE + t]).sum();
        }
    }
    (0..W * H)
        .map(|p| {
            let (px, py) = (p % W, p / W);
            (0..taps).map(|t| weights[t] * rows[(py * FINE + t) * W + px]).sum::<f64>() / total
        })
        .collect()
}

fn rmse(frame: &[[f32; 3]], truth: &[f64]) -> f64 {
    let sum: f64 = frame.iter().zip(truth).map(|(c, t)| (c[1] as f64 - t).powi(2)).sum();
    (sum / truth.len() as f64).sqrt()
}

/// The slope of log(error) against log(samples): the convergence rate.
fn slope(points: &[(usize, f64)]) -> f64 {
    let n = points.len() as f64;
    let (xs, ys): (Vec<f64>, Vec<f64>) = points.iter().map(|&(s, e)| ((s as f64).ln(), e.ln())).unzip();
    let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
    let cov: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    cov / xs.iter().map(|x| (x - mx).powi(2)).sum::<f64>()
}

#[test]
fn renders_converge_to_the_filtered_ground_truth_at_the_quasi_random_rate() {
    let scene = scene();
    // (sampler, filter, the slope it must beat, the error at 256 samples it must beat)
    let cases = [
        (Sampler::Sobol, "box", -0.65, 0.005),
        (Sampler::Stratified, "box", -0.6, 0.006),
        (Sampler::Sobol, "gaussian", -0.65, 0.007),
        (Sampler::Sobol, "mitchell", -0.6, 0.008),
    ];
    for (sampler, name, rate, bound) in cases {
        let filter = PixelFilter::parse(name).unwrap();
        let truth = truth(&filter);
        let errors: Vec<(usize, f64)> = [4, 16, 64, 256]
            .iter()
            .map(|&spp| {
                let options =
                    RenderOptions { width: W, height: H, spp, sampler, pixel_filter: filter, ..Default::default() };
                (spp, rmse(&render(&scene, &options).unwrap().color, &truth))
            })
            .collect();
        let k = slope(&errors);
        println!(
            "{sampler:?} {name}: RMSE by spp {errors:.5?}, rate N^{k:.2} (must beat N^{rate}), at 256 below {bound}"
        );
        assert!(k < rate, "{sampler:?} {name}: error falls as N^{k:.2}, not faster than N^{rate}");
        assert!(errors[3].1 < bound, "{sampler:?} {name}: RMSE {} at 256 spp", errors[3].1);
    }
    // The filters differ from each other by far more than the errors: each render converges to its own.
    let (box_truth, gauss_truth) = (truth(&PixelFilter::default()), truth(&PixelFilter::parse("gaussian").unwrap()));
    let apart = rmse(&box_truth.iter().map(|&v| [v as f32; 3]).collect::<Vec<_>>(), &gauss_truth);
    println!("box and gaussian ground truths differ by RMSE {apart:.4}");
    assert!(apart > 0.03, "the two filters' truths are too alike to tell them apart: {apart}");
}

/// A crop of a frame with Sobol samples over a Lanczos filter (samples reaching three pixels past their own,
/// each pixel its own scramble) is bit-identical to the same pixels of the whole frame.
#[test]
fn a_crop_with_a_wide_filter_is_the_whole_frames_pixels() {
    let scene = scene();
    let options = RenderOptions {
        width: W,
        height: H,
        spp: 12,
        sampler: Sampler::Sobol,
        pixel_filter: PixelFilter::parse("lanczos").unwrap(),
        ..Default::default()
    };
    let whole = render(&scene, &options).unwrap();
    let crop = wrinkle::Crop { x0: 13, y0: 21, x1: 70, y1: 50 };
    let part = render(&scene, &RenderOptions { crop: Some(crop), ..options.clone() }).unwrap();
    for y in crop.y0..crop.y1 {
        for x in crop.x0..crop.x1 {
            let (a, b) = (whole.color[y * W + x], part.color[(y - crop.y0) * crop.width() + x - crop.x0]);
            assert!(a.map(f32::to_bits) == b.map(f32::to_bits), "pixel ({x},{y}): {a:?} whole, {b:?} cropped");
        }
    }
}

/// Frames whose pixels only average opaque samples take a shorter resolve than those with AOVs to fill:
/// both give the same colours to the bit, at one sample and several, shaded per sample and per pixel,
/// over a plain background and over the environment.
#[test]
fn asking_for_aovs_leaves_the_colours_as_they_are() {
    use wrinkle::{Aovs, ShadingRate};
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    for name in ["checker_floor.toml", "environment_chrome.toml"] {
        let scene = Scene::load(&scenes.join(name)).unwrap();
        for (spp, shading_rate) in [(1, ShadingRate::Sample), (4, ShadingRate::Sample), (4, ShadingRate::Pixel)] {
            let options = RenderOptions { width: 96, height: 64, spp, shading_rate, ..Default::default() };
            let plain = render(&scene, &options).unwrap();
            let aovs = Aovs { depth: true, alpha: true, ..Aovs::default() };
            let with_aovs = render(&scene, &RenderOptions { aovs, ..options }).unwrap();
            let bits = |c: &[[f32; 3]]| c.iter().map(|p| p.map(f32::to_bits)).collect::<Vec<_>>();
            assert!(bits(&plain.color) == bits(&with_aovs.color), "{name} at {spp} spp, {shading_rate:?}");
        }
    }
}
