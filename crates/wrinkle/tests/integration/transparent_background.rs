//! A transparent background (`RenderOptions::transparent`): alpha is each pixel's coverage, exactly 0 where
//! nothing is seen and 1 inside; along a cut edge at 16 samples per pixel it is the covered share of the
//! 4 x 4 sample grid (within 1/16 of the analytic area on average, never more than 1/8, half a column of
//! the grid), and the colour is premultiplied by it.

use wrinkle::{RenderOptions, Scene};

/// Unlit (ambient 1): an orange patch over the left part of an orthographic view of [-1, 1]^2, its right
/// edge slanted, in front of a green background and an environment-free scene.
const SCENE: &str = r#"
[camera]
eye = [0.0, 0.0, 5.0]
look_at = [0.0, 0.0, 0.0]
projection = "orthographic"
height = 2.0
background = [0.0, 1.0, 0.0]

[[light]]
type = "ambient"

[[object]]
shape = "patch"
corners = [[-1.0, -1.0, 0.0], [0.1, -1.0, 0.0], [0.4, 1.0, 0.0], [-1.0, 1.0, 0.0]]
[object.material]
color = [0.8, 0.4, 0.1]
"#;

#[test]
fn alpha_is_coverage_and_colour_is_premultiplied() {
    let scene = Scene::parse(SCENE, std::path::Path::new(".")).unwrap();
    let size = 64;
    let options = RenderOptions { width: size, height: size, spp: 16, transparent: true, ..Default::default() };
    let frame = wrinkle::render(&scene, &options).unwrap();
    let alpha = frame.alpha.as_ref().expect("a transparent frame keeps its alpha");
    let albedo = [0.8f32, 0.4, 0.1];
    let (mut edge_pixels, mut worst, mut sum) = (0, 0.0f64, 0.0);
    for y in 0..size {
        for x in 0..size {
            let k = y * size + x;
            // The edge x = 0.1 + 0.15 (1 + wy) in the world; a pixel spans 2 / size world units.
            let cover = |px: f64, py: f64| {
                let (wx, wy) = (px * 2.0 / size as f64 - 1.0, 1.0 - py * 2.0 / size as f64);
                wx < 0.1 + 0.15 * (1.0 + wy)
            };
            // The analytic share, by a fine grid over the pixel.
            let n = 64;
            let inside = (0..n * n)
                .filter(|i| {
                    cover(
                        x as f64 + (i % n) as f64 / n as f64 + 0.5 / n as f64,
                        y as f64 + (i / n) as f64 / n as f64 + 0.5 / n as f64,
                    )
                })
                .count();
            let area = inside as f64 / (n * n) as f64;
            let a = alpha[k];
            match area {
                0.0 => assert_eq!(a, 0.0, "pixel ({x}, {y}) sees nothing"),
                1.0 => assert_eq!(a, 1.0, "pixel ({x}, {y}) is covered"),
                _ => {
                    edge_pixels += 1;
                    worst = worst.max((f64::from(a) - area).abs());
                    sum += (f64::from(a) - area).abs();
                }
            }
            for (got, albedo) in frame.color[k].iter().zip(albedo) {
                assert!((got - albedo * a).abs() < 1e-6, "pixel ({x}, {y}): {:?} at alpha {a}", frame.color[k]);
            }
        }
    }
    assert!(edge_pixels >= size, "{edge_pixels} pixels on the edge");
    let mean = sum / edge_pixels as f64;
    assert!(mean <= 1.0 / 16.0 && worst <= 1.0 / 8.0 + 1e-3, "coverage off by {mean} on average, {worst} at worst");
    // Without it: no alpha, and the background colour.
    let opaque = wrinkle::render(&scene, &RenderOptions { transparent: false, ..options }).unwrap();
    assert!(opaque.alpha.is_none());
    assert_eq!(opaque.color[size - 1], [0.0, 1.0, 0.0]);
}
