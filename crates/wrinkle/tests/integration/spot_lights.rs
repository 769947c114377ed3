//! Spot lights against their definition, on a white floor seen from straight above (orthographic, unlit
//! but for the spot): inside the cone a pixel is the point light's Lambert term E (N.L) / d^2, outside it
//! black, between the two cones the smoothstep; a projected slide tints each pixel by the texel the
//! light's ray passes through.

use crate::common::scratch_dir;
use wrinkle::image::io::write_png_rgb8;
use wrinkle::{RenderOptions, Scene};

const SIZE: usize = 128;
const HEIGHT: f64 = 2.0;

/// A white floor [-2, 2]^2 at y = 0 seen from above, lit by one spot straight down from (0, 2, 0).
fn scene(spot: &str) -> String {
    format!(
        "[camera]\neye = [0.0, 5.0, 0.0]\nlook_at = [0.0, 0.0, 0.0]\nup = [0.0, 0.0, -1.0]\nprojection = \"orthographic\"\n\
         height = 4.0\nbackground = [0.0, 0.0, 0.0]\n\n[[light]]\ntype = \"spot\"\nposition = [0.0, 2.0, 0.0]\n\
         direction = [0.0, -1.0, 0.0]\nup = [0.0, 0.0, -1.0]\nintensity = 4.0\n{spot}\n\n\
         [[object]]\nshape = \"patch\"\ncorners = [[-2.0, 0.0, 2.0], [2.0, 0.0, 2.0], [2.0, 0.0, -2.0], [-2.0, 0.0, -2.0]]\n\
         [object.material]\ncolor = [1.0, 1.0, 1.0]\n"
    )
}

fn render(text: &str, base: &std::path::Path) -> Vec<[f32; 3]> {
    let scene = Scene::parse(text, base).unwrap_or_else(|e| panic!("{e}\n{text}"));
    wrinkle::render(&scene, &RenderOptions { width: SIZE, height: SIZE, ..Default::default() }).unwrap().color
}

/// The floor point under pixel (i, j): x right, z down the picture (the camera's up is -Z).
fn floor(i: usize, j: usize) -> (f64, f64) {
    let k = 4.0 / SIZE as f64;
    ((i as f64 + 0.5) * k - 2.0, (j as f64 + 0.5) * k - 2.0)
}

/// Point light at height 2 over (x, z): E (N.L) / d^2 with E = 4.
fn lambert(x: f64, z: f64) -> f64 {
    let d2 = x * x + z * z + HEIGHT * HEIGHT;
    4.0 * (HEIGHT / d2.sqrt()) / d2
}

#[test]
fn the_cone_lights_inside_and_softens_its_edge() {
    let colour = render(&scene("angle = 30.0\nfalloff = 10.0"), std::path::Path::new("."));
    let (inner, outer) = (HEIGHT * 20f64.to_radians().tan(), HEIGHT * 30f64.to_radians().tan());
    let (mut inside, mut outside, mut between) = (0, 0, 0);
    for j in 0..SIZE {
        for i in 0..SIZE {
            let (x, z) = floor(i, j);
            let r = (x * x + z * z).sqrt();
            let got = f64::from(colour[j * SIZE + i][0]);
            if r < inner * 0.98 {
                assert!((got - lambert(x, z)).abs() < 1e-4 * lambert(x, z), "({x}, {z}) inside: {got}");
                inside += 1;
            } else if r > outer * 1.02 {
                assert_eq!(got, 0.0, "({x}, {z}) outside");
                outside += 1;
            } else if r > inner * 1.02 && r < outer * 0.98 {
                // The smoothstep in the cosine of the angle from the axis.
                let c = HEIGHT / (r * r + HEIGHT * HEIGHT).sqrt();
                let (co, ci) = (30f64.to_radians().cos(), 20f64.to_radians().cos());
                let t = ((c - co) / (ci - co)).clamp(0.0, 1.0);
                let want = lambert(x, z) * t * t * (3.0 - 2.0 * t);
                assert!((got - want).abs() < 1e-3 * lambert(x, z), "({x}, {z}) on the edge: {got} vs {want}");
                between += 1;
            }
        }
    }
    assert!(inside > 500 && outside > 500 && between > 200, "{inside} {outside} {between}");
}

#[test]
fn a_slide_tints_the_light_by_its_texels() {
    let dir = scratch_dir("spot-slide");
    // A slide of four quadrants: red, green on top; blue, white below (row 0 at the top), 64 texels wide so
    // that the filter reads one colour well inside each.
    let quadrant = |x: usize, y: usize| match (x < 32, y < 32) {
        (true, true) => [255, 0, 0],
        (false, true) => [0, 255, 0],
        (true, false) => [0, 0, 255],
        (false, false) => [255, 255, 255],
    };
    let bytes: Vec<u8> = (0..64 * 64).flat_map(|k| quadrant(k % 64, k / 64)).collect();
    write_png_rgb8(&dir.join("slide.png"), 64, 64, &bytes).unwrap();
    let colour = render(&scene("angle = 40.0\nfalloff = 0.0\ntexture = \"slide.png\""), &dir);
    // Seen from above with -Z up the picture: the slide's up is -Z and its right +X (right = forward x up).
    let quadrants = [
        ((-0.5, -0.5), [1.0, 0.0, 0.0]),
        ((0.5, -0.5), [0.0, 1.0, 0.0]),
        ((-0.5, 0.5), [0.0, 0.0, 1.0]),
        ((0.5, 0.5), [1.0, 1.0, 1.0]),
    ];
    for ((x, z), texel) in quadrants {
        let (i, j) = (((x + 2.0) / 4.0 * SIZE as f64) as usize, ((z + 2.0) / 4.0 * SIZE as f64) as usize);
        let got = colour[j * SIZE + i];
        let (fx, fz) = floor(i, j);
        for c in 0..3 {
            let want = lambert(fx, fz) * texel[c];
            assert!((f64::from(got[c]) - want).abs() < 1e-3, "({x}, {z}) channel {c}: {got:?} vs {want}");
        }
    }
}
