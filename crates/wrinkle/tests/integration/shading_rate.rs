//! Shading once per pixel and triangle (`ShadingRate::Pixel`, multisampling): coverage stays that of every
//! sample, and each triangle seen in a pixel is shaded once.

use std::path::Path;
use wrinkle::{render, RenderOptions, Scene, ShadingRate};

/// A tilted, flatly lit patch without texture over a black background: every sample that sees it has the
/// same colour, so a pixel is that colour times the share of its samples that see the patch.
const EDGES: &str = r#"
[camera]
eye = [0.0, 0.0, 3.0]
look_at = [0.0, 0.0, 0.0]
fov_y = 40.0
background = [0.0, 0.0, 0.0]

[[light]]
type = "ambient"
intensity = 1.0

[[object]]
shape = "patch"
corners = [[-0.9, -0.5, 0.0], [0.7, -0.8, 0.0], [0.8, 0.6, 0.0], [-0.6, 0.7, 0.0]]

[object.material]
color = [0.8, 0.6, 0.4]
specular = 0.0
"#;

fn frame(scene: &str, spp: usize, shading_rate: ShadingRate) -> Vec<[f32; 3]> {
    let scene = Scene::parse(scene, Path::new(".")).unwrap();
    let options = RenderOptions { width: 160, height: 120, spp, shading_rate, ..RenderOptions::default() };
    render(&scene, &options).unwrap().color
}

#[test]
fn coverage_stays_per_sample() {
    let every = frame(EDGES, 16, ShadingRate::Sample);
    let once = frame(EDGES, 16, ShadingRate::Pixel);
    let colour = [0.8f32, 0.6, 0.4];
    let mut partial = 0;
    for (a, b) in every.iter().zip(&once) {
        for c in 0..3 {
            assert!((a[c] - b[c]).abs() <= 1e-6, "{a:?} shading every sample, {b:?} once per pixel");
        }
        // Sixteenths of the colour: the share of the pixel's samples on the patch.
        let share = b[0] / colour[0];
        assert!((share * 16.0 - (share * 16.0).round()).abs() < 1e-3, "{b:?} is not a sixteenth of the colour");
        partial += usize::from(share > 0.01 && share < 0.99);
    }
    // The patch's four slanted sides cross about 290 pixels.
    assert!(partial > 200, "only {partial} pixels partly covered");
}

#[test]
fn each_triangle_is_shaded_once_per_pixel() {
    // The checker floor: point-sampled checks under flat light, so a sample's colour is the dark or the
    // light check's. Shaded once, a pixel that sees one triangle and nothing else is one of the two exactly;
    // only where the floor's two triangles, or the floor and the sky, meet does a pixel mix colours.
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/checker_floor.toml");
    let scene = Scene::load(&path).unwrap();
    let frame = |spp, shading_rate| {
        let options = RenderOptions { width: 240, height: 160, spp, shading_rate, ..RenderOptions::default() };
        render(&scene, &options).unwrap().color
    };
    // The lighting rounds differently from sample to sample, in the last bits.
    let alike = |a: &[f32; 3], b: &[f32; 3]| (0..3).all(|c| (a[c] - b[c]).abs() <= 1e-5);
    let mut pure: Vec<[f32; 3]> = Vec::new();
    for c in frame(1, ShadingRate::Sample) {
        if !pure.iter().any(|p| alike(p, &c)) {
            pure.push(c);
        }
    }
    assert_eq!(pure.len(), 3, "the 1-sample frame is the sky and two checks: {pure:?}");
    let mixed = |f: &[[f32; 3]]| f.iter().filter(|c| !pure.iter().any(|p| alike(p, c))).count();
    let (once, every) = (mixed(&frame(16, ShadingRate::Pixel)), mixed(&frame(16, ShadingRate::Sample)));
    eprintln!("pixels of mixed colour: once per pixel {once}, every sample {every}");
    // Measured: 262 of the 38400 pixels (the horizon and the floor's diagonal) against 4888 (the checks'
    // edges too).
    assert!(once < 500, "shaded once per pixel, {once} pixels mix colours");
    assert!(every > 5 * once, "shaded every sample, only {every} pixels mix colours");
}
