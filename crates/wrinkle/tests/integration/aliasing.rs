//! Blinn section 5: a bump function that maps into a small screen region aliases. Supersampling the
//! intensities is the correct solution; filtering the bump table by the pixel footprint (its MIP level) is
//! the cheap one. Both must come closer to the converged image than plain 1-sample rendering.

use std::path::Path;
use wrinkle::bump::BumpFilter;
use wrinkle::{render, RenderOptions, Scene};

/// A sphere under a fine grid of bumps: 96 x 48 cells over the sphere, a few pixels each at 160 x 120.
const SCENE: &str = r#"
[camera]
eye = [0.0, 0.0, 3.2]
look_at = [0.0, 0.0, 0.0]
fov_y = 45.0

[[light]]
type = "directional"
direction = [0.4, -0.5, -0.75]
intensity = 1.0

[[object]]
shape = "sphere"

[object.material]
color = [0.8, 0.8, 0.8]
specular = 0.3
shininess = 20.0

[object.material.bump]
generator = { kind = "grid", size = 64, cells = 2, line_width = 0.3, soft = 0.1 }
scale = 0.004
repeat = [48, 24]
"#;

fn grey(options: &RenderOptions) -> Vec<f32> {
    let scene = Scene::parse(SCENE, Path::new(".")).unwrap();
    render(&scene, options).unwrap().color.iter().map(|c| (c[0] + c[1] + c[2]) / 3.0).collect()
}

fn rmse(a: &[f32], b: &[f32]) -> f32 {
    (a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum::<f32>() / a.len() as f32).sqrt()
}

#[test]
fn supersampling_and_mip_filtering_reduce_bump_aliasing() {
    let base = RenderOptions { width: 160, height: 120, ..RenderOptions::default() };
    // The reference: 16 stratified samples per pixel. Measured: 1 spp 0.064, mip 0.037, 4 spp 0.026.
    let reference = grey(&RenderOptions { spp: 16, ..base.clone() });
    let plain = grey(&base);
    let mip = grey(&RenderOptions { bump_filter: BumpFilter::parse("mip"), ..base.clone() });
    let four = grey(&RenderOptions { spp: 4, ..base.clone() });
    let (e_plain, e_mip, e_four) = (rmse(&plain, &reference), rmse(&mip, &reference), rmse(&four, &reference));
    eprintln!("rmse against 16 spp: 1 spp {e_plain:.4}, 1 spp + mip {e_mip:.4}, 4 spp {e_four:.4}");
    assert!(e_plain > 0.01, "the test view must alias at 1 spp ({e_plain})");
    assert!(e_four < 0.5 * e_plain, "4 spp {e_four} vs 1 spp {e_plain}");
    assert!(e_mip < 0.7 * e_plain, "mip {e_mip} vs 1 spp {e_plain}");
}
