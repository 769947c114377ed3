//! The course's texel locations (Crawfis, "Mip-maps"): a pixel reads its texture at the (u,v) of its centre,
//! at the centroid of its four projected corners, or where the projected quadrilateral's diagonals cross.
//! On a floor receding in perspective each is checked against the corner rays' crossings with the floor
//! computed here in f64, through the uv AOV (the coordinates the lookups used); the footprint they filter
//! over is the quadrilateral's bimedians (texture/location.rs's unit test).

use crate::common::{parallelogram_uv, ray_plane, RefCamera};
use glam::DVec3;
use std::path::Path;
use wrinkle::render::Aovs;
use wrinkle::texture::TexelLocation;
use wrinkle::{render, RenderOptions, Scene};

/// The floor y = -0.5 from z = 1 to z = -9 (u along +x, v away from the eye), seen from (0, 0.6, 3).
const FLOOR: &str = "[camera]\neye = [0.0, 0.6, 3.0]\nlook_at = [0.0, 0.0, 0.0]\nfov_y = 40.0\n\n\
    [[light]]\ntype = \"ambient\"\nintensity = 1.0\n\n[[object]]\nshape = \"patch\"\n\
    corners = [[-1.0, -0.5, 1.0], [1.0, -0.5, 1.0], [1.0, -0.5, -9.0], [-1.0, -0.5, -9.0]]\n";

#[test]
fn texel_locations_follow_the_projected_pixel_corners() {
    let (w, h) = (64usize, 48usize);
    let (p00, e1, e2) = (DVec3::new(-1.0, -0.5, 1.0), DVec3::new(2.0, 0.0, 0.0), DVec3::new(0.0, 0.0, -10.0));
    let camera = RefCamera::perspective([0.0, 0.6, 3.0], [0.0; 3], [0.0, 1.0, 0.0], 40.0, w, h);
    let scene = Scene::parse(FLOOR, Path::new(".")).unwrap();
    let uv_of = |location: TexelLocation| {
        let aovs = Aovs { uv: true, ..Aovs::default() };
        let options = RenderOptions { width: w, height: h, aovs, texel_location: location, ..Default::default() };
        render(&scene, &options).unwrap().uv.unwrap()
    };
    let at = |x: f64, y: f64| {
        let (o, d) = camera.ray(x, y);
        ray_plane(o, d, p00, DVec3::Y).map(|t| parallelogram_uv(o + t * d, p00, e1, e2))
    };
    let (centre, centroid, diagonals) =
        (uv_of(TexelLocation::Centre), uv_of(TexelLocation::Centroid), uv_of(TexelLocation::Diagonals));
    let (mut checked, mut worst, mut apart) = (0, 0.0f64, 0.0f64);
    for j in 0..h {
        for i in 0..w {
            let (x, y) = (i as f64, j as f64);
            let corners = [(x, y), (x + 1.0, y), (x + 1.0, y + 1.0), (x, y + 1.0)].map(|(x, y)| at(x, y));
            let Some([c0, c1, c2, c3]) =
                corners.iter().copied().collect::<Option<Vec<_>>>().map(|v| [v[0], v[1], v[2], v[3]])
            else {
                continue;
            };
            let Some(mid) = at(x + 0.5, y + 0.5) else { continue };
            if ![c0, c1, c2, c3].iter().all(|c| (0.02..0.98).contains(&c.0) && (0.02..0.98).contains(&c.1)) {
                continue;
            }
            let mean = ((c0.0 + c1.0 + c2.0 + c3.0) / 4.0, (c0.1 + c1.1 + c2.1 + c3.1) / 4.0);
            // c0 + s (c2 - c0) = c1 + r (c3 - c1).
            let (ex, ey, fx, fy) = (c2.0 - c0.0, c2.1 - c0.1, c3.0 - c1.0, c3.1 - c1.1);
            let s = ((c1.0 - c0.0) * fy - (c1.1 - c0.1) * fx) / (ex * fy - ey * fx);
            let cross = (c0.0 + s * ex, c0.1 + s * ey);
            let k = j * w + i;
            for (got, want) in [(centre[k], mid), (centroid[k], mean), (diagonals[k], cross)] {
                worst = worst.max((got[0] as f64 - want.0).abs().max((got[1] as f64 - want.1).abs()));
            }
            // How far the centroid lies from the centre's (u,v), in v (away from the eye).
            apart = apart.max((mean.1 - mid.1).abs());
            checked += 1;
        }
    }
    eprintln!("{checked} pixels: worst error {worst:.2e}, centroid up to {apart:.2e} from the centre in v");
    assert!(checked > 500, "{checked} pixels");
    assert!(worst < 2e-4, "worst error {worst}");
    // The locations differ by far more than the error: the test tells them apart.
    assert!(apart > 20.0 * worst, "centroid {apart} from the centre");
}
