//! Displacement mapping against analytic outlines. A sphere seen along its pole axis by an orthographic
//! camera, displaced by F(u) alone, has the outline rho(phi) = r + F(u(phi)) (each longitude's farthest
//! point is on the equator). Every pixel centre farther than the tolerance from that curve must be covered
//! exactly when it lies inside it.

use crate::common::scratch_dir;
use std::f64::consts::TAU;
use std::path::Path;

const SIDE: usize = 240;
/// The camera's view height in world units: SIDE / VIEW pixels per unit.
const VIEW: f64 = 3.0;
const RADIUS: f64 = 1.0;

/// Writes a 512 x 4 grey PNG whose columns hold `t(s)` at their centres.
fn height_map(dir: &Path, name: &str, t: impl Fn(f64) -> f64) {
    let (w, h) = (512usize, 4usize);
    let row: Vec<u8> = (0..w).map(|i| (t((i as f64 + 0.5) / w as f64) * 255.0).round() as u8).collect();
    let file = std::fs::File::create(dir.join(name)).unwrap();
    let mut encoder = png::Encoder::new(std::io::BufWriter::new(file), w as u32, h as u32);
    encoder.set_color(png::ColorType::Grayscale);
    let mut writer = encoder.write_header().unwrap();
    writer.write_image_data(&row.repeat(h)).unwrap();
}

/// The sphere displaced by the map, seen from above (+y) along its pole axis.
fn scene(map: &str, scale: f64, extra: &str) -> String {
    format!(
        "[camera]\nprojection = \"orthographic\"\neye = [0.0, 5.0, 0.0]\nlook_at = [0.0, 0.0, 0.0]\nup = [0.0, 0.0, -1.0]\n\
         height = {VIEW:?}\nbackground = [0.0, 0.0, 0.0]\n\n[[light]]\ntype = \"ambient\"\n\n\
         [[object]]\nshape = \"sphere\"\nradius = {RADIUS:?}\n\n[object.material.displacement]\nmap = \"{map}\"\n\
         scale = {scale:?}\nfilter = \"none\"\n{extra}\n"
    )
}

/// Pixel centres that disagree with the outline rho(phi) = r + scale T(u), beyond `tolerance` pixels of it
/// (signed distance along the radius), and how many centres lie inside it.
fn outline_errors(
    ids: &[f32],
    scale: f64,
    t: &impl Fn(f64) -> f64,
    tolerance: f64,
) -> (usize, Vec<(usize, usize, f64)>) {
    let px = SIDE as f64 / VIEW;
    let (mut inside, mut wrong) = (0, Vec::new());
    for j in 0..SIDE {
        for i in 0..SIDE {
            // Screen x is world x, screen y (down) is world z (up = -z).
            let (x, z) = ((i as f64 + 0.5 - 0.5 * SIDE as f64) / px, (j as f64 + 0.5 - 0.5 * SIDE as f64) / px);
            // u is the longitude from +x, a quarter turn at -z.
            let u = (-z).atan2(x).rem_euclid(TAU) / TAU;
            let rho = RADIUS + scale * t(u);
            let beyond = (x.hypot(z) - rho) * px;
            if beyond.abs() <= tolerance {
                continue;
            }
            inside += usize::from(beyond < 0.0);
            if (beyond < 0.0) == ids[j * SIDE + i].is_nan() {
                wrong.push((i, j, beyond));
            }
        }
    }
    (inside, wrong)
}

fn ids(scene: &str, dir: &Path) -> Vec<f32> {
    crate::common::render_all_aovs(scene, dir, SIDE, SIDE, 1).id.expect("id AOV")
}

/// A constant height h grows the outline to radius r + h, within a quarter pixel.
#[test]
fn constant_height_grows_the_radius() {
    let dir = scratch_dir("displace-constant");
    height_map(&dir, "one.png", |_| 1.0);
    let flat = |_: f64| 1.0;
    for scale in [0.05, 0.15] {
        let (inside, wrong) = outline_errors(&ids(&scene("one.png", scale, ""), &dir), scale, &flat, 0.25);
        println!("h = {scale}: {inside} centres inside, {} wrong", wrong.len());
        assert!(inside > 10_000);
        assert!(wrong.is_empty(), "h = {scale}: (pixel, px beyond the outline) {:?}", &wrong[..wrong.len().min(10)]);
    }
}

/// A sinusoidal height gives the outline rho = r + h (1/2 + 1/2 sin(8 pi u)), within a quarter pixel; and
/// at every dicing rate no pixel inside it (by more than the dicing's own chord error) shows the
/// background: no cracks.
#[test]
fn sinusoidal_height_gives_the_analytic_profile_without_cracks() {
    let dir = scratch_dir("displace-sine");
    let t = |s: f64| 0.5 + 0.5 * (4.0 * TAU * s).sin();
    height_map(&dir, "sine.png", t);
    let scale = 0.12;
    let (inside, wrong) = outline_errors(&ids(&scene("sine.png", scale, ""), &dir), scale, &t, 0.25);
    println!("sine, 1 px edges: {inside} centres inside, {} wrong", wrong.len());
    assert!(wrong.is_empty(), "(pixel, px beyond the outline) {:?}", &wrong[..wrong.len().min(10)]);
    for edge_px in [0.5, 3.0, 12.0] {
        let ids = ids(&scene("sine.png", scale, &format!("edge_px = {edge_px:?}")), &dir);
        // Only holes count here: centres well inside the outline that show the background.
        let (_, wrong) = outline_errors(&ids, scale, &t, 1.0 + edge_px);
        let holes: Vec<_> = wrong.iter().filter(|w| w.2 < 0.0).collect();
        assert!(
            holes.is_empty(),
            "edge_px {edge_px}: background inside the surface at {:?}",
            &holes[..holes.len().min(10)]
        );
    }
}

/// Silhouette mode (Lingard): displacing only near the outline gives the full displacement's outline
/// within half a pixel, with the threshold found from the height and the curvature.
#[test]
fn silhouette_mode_matches_the_full_outline() {
    let dir = scratch_dir("displace-silhouette");
    let t = |s: f64| 0.5 + 0.5 * (4.0 * TAU * s).sin();
    height_map(&dir, "sine.png", t);
    let scale = 0.12;
    let (inside, wrong) =
        outline_errors(&ids(&scene("sine.png", scale, "mode = \"silhouette\""), &dir), scale, &t, 0.5);
    println!("silhouette mode: {inside} centres inside, {} wrong", wrong.len());
    assert!(inside > 10_000);
    assert!(wrong.is_empty(), "(pixel, px beyond the outline) {:?}", &wrong[..wrong.len().min(10)]);
}
