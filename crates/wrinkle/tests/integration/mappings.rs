//! Mappings rendered against shapes whose own (u,v) they reproduce: planar on a flat square, cylindrical
//! on the cylinder, spherical on the sphere. The pictures must agree with the uv mapping's: the projected
//! coordinates, and the footprints from dP/dx and dP/dy that the filters read (at a grazing angle, where a
//! wrong footprint blurs or aliases visibly), and for bump maps the chain rule's Jacobian.

use crate::common::{render_all_aovs, scratch_dir};
use glam::DVec3;
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

/// The course's triangle mapping gives a mesh without texture coordinates the ones three reference points
/// define; a patch's `uv_corners` (inverse bilinear interpolation) place the corners' coordinates.
#[test]
fn triangle_and_quad_mappings_from_reference_points() {
    let dir = scratch_dir("reference-points");
    let tex = tiles();
    let quad = "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n";
    std::fs::write(
        dir.join("with_uv.obj"),
        format!("{quad}vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n"),
    )
    .unwrap();
    std::fs::write(dir.join("bare.obj"), format!("{quad}f 1 2 3\nf 1 3 4\n")).unwrap();
    let size = 64;
    let with_uv =
        format!("shape = \"mesh\"\nfile = \"with_uv.obj\"\nmaterial = {{ texture = {{ path = \"{tex}\" }} }}");
    let bare = format!(
        "shape = \"mesh\"\nfile = \"bare.obj\"\nmaterial = {{ texture = {{ path = \"{tex}\", mapping = {{ type = \"triangle\", \
         points = [[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [-1.0, 1.0, 0.0]], uv = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]] }} }} }}"
    );
    let a = render_all_aovs(&scene(&with_uv), &dir, size, size, 1);
    let b = render_all_aovs(&scene(&bare), &dir, size, size, 1);
    let d = mean_difference(&a.color, &b.color);
    assert!(d < 2e-3, "triangle mapping against the mesh's own uv: {d}");

    // uv_corners stretch the patch's u twice over: the uv AOV reads (2u, v), and (u, v) without them.
    let patch =
        "shape = \"patch\"\ncorners = [[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.2, 1.0, -0.5], [-0.8, 1.0, -0.5]]";
    let plain = format!("{patch}\nmaterial = {{ texture = {{ path = \"{tex}\" }} }}");
    let cornered = format!("{patch}\nuv_corners = [[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]]\nmaterial = {{ texture = {{ path = \"{tex}\" }} }}");
    let (p, c) =
        (render_all_aovs(&scene(&plain), &dir, size, size, 1), render_all_aovs(&scene(&cornered), &dir, size, size, 1));
    let (pu, cu) = (p.uv.as_ref().unwrap(), c.uv.as_ref().unwrap());
    let mut n = 0;
    for (x, y) in pu.iter().zip(cu).filter(|(x, _)| x[0].is_finite()) {
        assert!((y[0] - 2.0 * x[0]).abs() < 2e-3 && (y[1] - x[1]).abs() < 2e-3, "{x:?} -> {y:?}");
        n += 1;
    }
    assert!(n > 500, "{n} pixels on the patch");
}

/// `interp = "affine"` interpolates (u,v) linearly on the screen (the slides' "Uh oh"): on a quad receding
/// from the eye the default perspective-correct (u,v) match the ray-plane intersection, the affine ones are
/// measurably off, and most where the two triangles meet along the diagonal.
#[test]
fn affine_interpolation_is_off_the_ray_and_perspective_is_not() {
    let dir = scratch_dir("affine");
    let tex = tiles();
    // The floor y = -0.5 from z = 1 to z = -9: u along +x, v away from the eye.
    let (p00, e1, e2) = (DVec3::new(-1.0, -0.5, 1.0), DVec3::new(2.0, 0.0, 0.0), DVec3::new(0.0, 0.0, -10.0));
    let object = |interp: &str| {
        format!(
            "shape = \"patch\"\ncorners = [[-1.0, -0.5, 1.0], [1.0, -0.5, 1.0], [1.0, -0.5, -9.0], [-1.0, -0.5, -9.0]]\n\
             interp = \"{interp}\"\nmaterial = {{ texture = {{ path = \"{tex}\" }} }}"
        )
    };
    let (w, h) = (64, 48);
    let camera = crate::common::RefCamera::perspective([0.0, 0.6, 3.0], [0.0; 3], [0.0, 1.0, 0.0], 40.0, w, h);
    let error = |interp: &str| {
        let frame = render_all_aovs(&scene(&object(interp)), &dir, w, h, 1);
        let uv = frame.uv.as_ref().unwrap();
        let mut worst: f64 = 0.0;
        for j in 0..h {
            for i in 0..w {
                let (o, d) = camera.pixel_ray(i, j);
                let Some(t) = crate::common::ray_plane(o, d, p00, DVec3::Y) else { continue };
                let (u, v) = crate::common::parallelogram_uv(o + t * d, p00, e1, e2);
                if !(0.02..0.98).contains(&u) || !(0.02..0.98).contains(&v) || !uv[j * w + i][0].is_finite() {
                    continue;
                }
                let got = uv[j * w + i];
                worst = worst.max((got[0] as f64 - u).abs().max((got[1] as f64 - v).abs()));
            }
        }
        worst
    };
    let (perspective, affine) = (error("perspective"), error("affine"));
    assert!(perspective < 2e-3, "perspective-correct (u,v) off by {perspective}");
    assert!(affine > 0.03, "affine (u,v) off by only {affine}");
}
