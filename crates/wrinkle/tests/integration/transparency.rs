//! Sorted and exact transparency against the slides' "Blending Example" and against compositing worked out
//! here: c = alpha C + (1 - alpha) c over what lies behind, back to front.

use std::path::Path;
use wrinkle::render::Transparency;
use wrinkle::{RenderOptions, Scene};

const SIZE: usize = 32;

/// A square of side 2 facing +Z at depth `z`, emitting `intensity` (grey) and nothing else, with `opacity`
/// (`None`: opaque).
fn square(z: f64, intensity: f64, opacity: Option<f64>) -> String {
    let blend = match opacity {
        Some(a) => format!("alpha_mode = \"blend\"\nopacity = {a}\n"),
        None => String::new(),
    };
    format!(
        "[[object]]\nshape = \"patch\"\ncorners = [[-1.0, -1.0, {z}], [1.0, -1.0, {z}], [1.0, 1.0, {z}], [-1.0, 1.0, {z}]]\n\
         [object.material]\ncolor = [0.0, 0.0, 0.0]\nspecular = 0.0\nemission = [{intensity}, {intensity}, {intensity}]\n{blend}\n"
    )
}

/// Looking down -Z (orthographic, 4 units high) at `objects`, over a black background.
fn scene(objects: &[String]) -> String {
    let camera = "[camera]\neye = [0.0, 0.0, 10.0]\nlook_at = [0.0, 0.0, 0.0]\nprojection = \"orthographic\"\n\
                  height = 4.0\nbackground = [0.0, 0.0, 0.0]\n\n";
    format!("{camera}{}", objects.concat())
}

fn render(text: &str, transparency: Transparency) -> Vec<[f32; 3]> {
    let scene = Scene::parse(text, Path::new(".")).unwrap_or_else(|e| panic!("{e}\n{text}"));
    let options = RenderOptions { width: SIZE, height: SIZE, transparency, ..Default::default() };
    wrinkle::render(&scene, &options).unwrap().color
}

/// The centre pixel's red.
fn centre(colour: &[[f32; 3]]) -> f64 {
    f64::from(colour[(SIZE / 2) * SIZE + SIZE / 2][0])
}

/// Every order of three items.
fn orders<T: Clone>(items: [T; 3]) -> Vec<Vec<T>> {
    let [a, b, c] = items;
    vec![
        vec![a.clone(), b.clone(), c.clone()],
        vec![a.clone(), c.clone(), b.clone()],
        vec![b.clone(), a.clone(), c.clone()],
        vec![b.clone(), c.clone(), a.clone()],
        vec![c.clone(), a.clone(), b.clone()],
        vec![c, b, a],
    ]
}

/// The slides: polygons A, B, C with transparencies K_A = 0.2, K_B = 0.5 (opacities 0.8 and 0.5) and
/// intensities I_A = 1, I_B = 0.5, I_C = 1 (C opaque). A in front of B gives rI_A = 0.95; B in front of A gives
/// rI_B = 0.75; whatever the order of the objects in the file, in both modes.
#[test]
fn the_slides_blending_example() {
    for transparency in [Transparency::Sorted, Transparency::Exact] {
        for (front, back, expected) in [((1.0, 0.8), (0.5, 0.5), 0.95), ((0.5, 0.5), (1.0, 0.8), 0.75)] {
            let items =
                [square(2.0, front.0, Some(front.1)), square(1.0, back.0, Some(back.1)), square(0.0, 1.0, None)];
            for objects in orders(items) {
                let got = centre(&render(&scene(&objects), transparency));
                assert!((got - expected).abs() < 1e-5, "{transparency:?}: {got}, expected {expected}");
            }
        }
    }
}

/// Two translucent squares crossing along x = 0 (one tilted through the other): on each side a different
/// one is in front. The exact mode composites each pixel's fragments by their own depth; the sorted mode
/// by the squares' centres, so on one side it is wrong: the case the exact mode is for.
#[test]
fn crossing_squares_need_the_exact_mode() {
    let tilted = "[[object]]\nshape = \"patch\"\ncorners = [[-1.0, -1.0, -0.5], [1.0, -1.0, 0.5], [1.0, 1.0, 0.5], [-1.0, 1.0, -0.5]]\n\
                  [object.material]\ncolor = [0.0, 0.0, 0.0]\nspecular = 0.0\nemission = [0.0, 1.0, 0.0]\n\
                  alpha_mode = \"blend\"\nopacity = 0.6\n";
    let flat = square(0.0, 1.0, Some(0.3)).replace("emission = [1, 1, 1]", "emission = [1.0, 0.0, 0.0]");
    let flat = flat.replace("emission = [1.0, 1.0, 1.0]", "emission = [1.0, 0.0, 0.0]");
    let text = scene(&[flat, tilted.to_string()]);
    // Left (x < 0): the flat red square (0.3) in front of the green tilted one (0.6), over black; right:
    // the green in front.
    let left = [0.3, 0.7 * 0.6];
    let right = [0.4 * 0.3, 0.6];
    for (transparency, right_is_exact) in [(Transparency::Exact, true), (Transparency::Sorted, false)] {
        let colour = render(&text, transparency);
        let row = SIZE / 2;
        let (l, r) = (colour[row * SIZE + 3 * SIZE / 8], colour[row * SIZE + 5 * SIZE / 8]);
        let near =
            |c: [f32; 3], e: [f64; 2]| (f64::from(c[0]) - e[0]).abs() < 1e-5 && (f64::from(c[1]) - e[1]).abs() < 1e-5;
        // The sorted mode puts one square in front everywhere: right on one side only.
        assert!(near(l, left) || near(r, right), "{transparency:?}: left {l:?}, right {r:?}");
        if right_is_exact {
            assert!(near(l, left) && near(r, right), "exact: left {l:?} (want {left:?}), right {r:?} (want {right:?})");
        } else {
            assert!(!(near(l, left) && near(r, right)), "sorted got both sides right: {l:?} {r:?}");
        }
    }
}

/// A translucent surface is lit as an opaque one (lights and shadows) and composited with its opacity: over
/// black, alpha x the opaque rendering; with a transparent background its alpha is its coverage times its
/// opacity.
#[test]
fn translucent_surfaces_are_lit_and_cover_by_their_opacity() {
    let lit = "[camera]\neye = [0.0, 1.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\nfov_y = 40.0\nbackground = [0.0, 0.0, 0.0]\n\n\
               [[light]]\ntype = \"directional\"\ndirection = [0.3, -0.5, -1.0]\n\n\
               [[object]]\nshape = \"sphere\"\nradius = 1.0\n[object.material]\ncolor = [0.9, 0.5, 0.2]\nspecular = 0.4\n";
    let translucent = format!("{lit}alpha_mode = \"blend\"\nopacity = 0.4\n");
    let (opaque, glass) = (render(lit, Transparency::Sorted), render(&translucent, Transparency::Exact));
    let mut covered = 0;
    for (o, g) in opaque.iter().zip(&glass) {
        for c in 0..3 {
            assert!((0.4 * o[c] - g[c]).abs() < 1e-5, "{o:?} x 0.4 vs {g:?}");
        }
        covered += usize::from(o[0] > 0.0);
    }
    assert!(covered > SIZE * SIZE / 8, "{covered}");
    let scene = Scene::parse(&translucent, Path::new(".")).unwrap();
    let options = RenderOptions { width: SIZE, height: SIZE, transparent: true, ..Default::default() };
    let frame = wrinkle::render(&scene, &options).unwrap();
    let alpha = frame.alpha.unwrap();
    let inside = alpha.iter().filter(|&&a| (a - 0.4).abs() < 1e-6).count();
    assert!(alpha.iter().all(|&a| a == 0.0 || a <= 0.4 + 1e-6) && inside > covered / 2, "{inside} of {covered}");
}
