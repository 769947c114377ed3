//! Mappings rendered against shapes whose own (u,v) they reproduce: planar on a flat square, cylindrical
//! on the cylinder, spherical on the sphere. The pictures must agree with the uv mapping's: the projected
//! coordinates, and the footprints from dP/dx and dP/dy that the filters read (at a grazing angle, where a
//! wrong footprint blurs or aliases visibly), and for bump maps the chain rule's Jacobian.

mod common;

use common::{render_all_aovs, scratch_dir};
use std::path::Path;

fn tiles() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/tiles_color.png").to_str().unwrap().replace('\\', "/")
}

/// One object seen at a grazing angle, lit from the upper left.
fn scene(object: &str) -> String {
    format!(
        "[camera]\neye = [0.0, 0.6, 3.0]\nlook_at = [0.0, 0.0, 0.0]\n\n\
         [[light]]\ntype = \"directional\"\ndirection = [-0.4, -0.5, -1.0]\n\n\
         [[light]]\ntype = \"ambient\"\nintensity = 0.2\n\n[[object]]\n{object}\n"
    )
}

fn mean_difference(a: &[[f32; 3]], b: &[[f32; 3]]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (0..3).map(|c| (x[c] - y[c]).abs() as f64).sum::<f64>() / 3.0).sum::<f64>()
        / a.len() as f64
}

#[test]
fn projections_reproduce_the_shapes_own_uv() {
    let dir = scratch_dir("mappings");
    let tex = tiles();
    let square =
        "shape = \"patch\"\ncorners = [[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, -2.0], [-1.0, 1.0, -2.0]]";
    let cases = [
        // The square tilted back: planar along z must be placed along its normal.
        ("planar", square, "type = \"planar\", placement = { rotate = [-45.0, 0.0, 0.0], scale = [1.0, 1.41421356, 1.0], translate = [0.0, 0.0, -1.0] }"),
        ("cylindrical", "shape = \"cylinder\"\nradius = 0.8\nheight = 2.0", "type = \"cylindrical\""),
        ("spherical", "shape = \"sphere\"", "type = \"spherical\""),
        ("two-part sphere", "shape = \"sphere\"", "type = \"two_part\", surface = \"sphere\", projector = \"centroid\""),
    ];
    let size = 96;
    for (name, shape, mapping) in cases {
        for filter in ["trilinear", "ewa"] {
            let uv = format!("{shape}\nmaterial = {{ texture = {{ path = \"{tex}\", repeat = [2.0, 1.0], filter = \"{filter}\" }} }}");
            let projected = format!(
                "{shape}\nmaterial = {{ texture = {{ path = \"{tex}\", repeat = [2.0, 1.0], filter = \"{filter}\", mapping = {{ {mapping} }} }} }}"
            );
            let a = render_all_aovs(&scene(&uv), &dir, size, size, 1);
            let b = render_all_aovs(&scene(&projected), &dir, size, size, 1);
            let d = mean_difference(&a.color, &b.color);
            // The same picture, up to rounding where a wrapped seam meets its other side.
            assert!(d < 2e-3, "{name}, {filter}: the pictures differ by {d}");
            // The uv AOV shows the projected coordinates before the repeat: the shape's own (u,v).
            let (ua, ub) = (a.uv.as_ref().unwrap(), b.uv.as_ref().unwrap());
            let mut worst: f32 = 0.0;
            for (p, q) in ua.iter().zip(ub).filter(|(p, _)| p[0].is_finite()) {
                let du = (p[0] - q[0]).abs();
                worst = worst.max(du.min(1.0 - du)).max((p[1] - q[1]).abs());
            }
            assert!(worst < 2e-3, "{name}: uv AOVs differ by {worst}");
        }
    }
    // A mapping that is not the shape's own gives another picture: the test can tell.
    let uv = format!("shape = \"sphere\"\nmaterial = {{ texture = {{ path = \"{tex}\" }} }}");
    let boxed = format!(
        "shape = \"sphere\"\nmaterial = {{ texture = {{ path = \"{tex}\", mapping = {{ type = \"box\" }} }} }}"
    );
    let d = mean_difference(
        &render_all_aovs(&scene(&uv), &dir, size, size, 1).color,
        &render_all_aovs(&scene(&boxed), &dir, size, size, 1).color,
    );
    assert!(d > 0.02, "box against uv: {d}");
}

/// Bumps through a projection: Fu and Fv by the chain rule through the mapping's Jacobian, which the
/// cylinder's own (u,v) give exactly.
#[test]
fn projected_bump_maps_match_the_uv_bump() {
    let dir = scratch_dir("mapped-bumps");
    let bump = |mapping: &str| {
        format!(
            "shape = \"cylinder\"\nradius = 0.8\nheight = 2.0\n\
             material = {{ specular = 0.3, bump = {{ generator = {{ kind = \"bricks\", size = 128 }}, scale = 0.01, repeat = [3.0, 2.0], filter = \"trilinear\"{mapping} }} }}"
        )
    };
    let size = 96;
    let uv = render_all_aovs(&scene(&bump("")), &dir, size, size, 1);
    let projected = render_all_aovs(&scene(&bump(", mapping = { type = \"cylindrical\" }")), &dir, size, size, 1);
    let flat = render_all_aovs(
        &scene("shape = \"cylinder\"\nradius = 0.8\nheight = 2.0\nmaterial = { specular = 0.3 }"),
        &dir,
        size,
        size,
        1,
    );
    let (d, control) = (mean_difference(&uv.color, &projected.color), mean_difference(&uv.color, &flat.color));
    assert!(d < 0.05 * control, "projected bumps differ by {d}, the bumps themselves make {control}");
}
