//! Shadow maps against geometry: a sphere above a white floor seen from straight above (orthographic),
//! lit by one light and nothing else, so each floor pixel's value over the unshadowed Lambert term is the
//! light's visibility there. The analytic shadow: a floor point is dark exactly when its ray towards the
//! light meets the sphere. Pixels more than the allowed distance (in shadow-map texels, measured across
//! the light's rays, where the map's texels lie) from that outline must be wholly lit or wholly dark, and
//! the dark area must match the analytic one to within a texel's shift of the outline.

use glam::DVec3;
use std::path::Path;
use wrinkle::{RenderOptions, Scene};

const SIZE: usize = 256;
/// The floor spans [-HALF, HALF]^2.
const HALF: f64 = 4.0;
const CENTRE: DVec3 = DVec3::new(-0.4, 1.3, -0.2);
const RADIUS: f64 = 0.6;
const MAP: usize = 256;

/// The floor and `object` under one `light` (its shadow map `MAP` texels on its longer side).
fn scene(light: &str, object: &str) -> String {
    format!(
        "[camera]\neye = [0.0, 10.0, 0.0]\nlook_at = [0.0, 0.0, 0.0]\nup = [0.0, 0.0, -1.0]\n\
         projection = \"orthographic\"\nheight = {}\nbackground = [0.0, 0.0, 0.0]\n\n[[light]]\n{light}\n\
         shadow_size = {MAP}\n\n[[object]]\nshape = \"patch\"\n\
         corners = [[-{HALF}, 0.0, {HALF}], [{HALF}, 0.0, {HALF}], [{HALF}, 0.0, -{HALF}], [-{HALF}, 0.0, -{HALF}]]\n\
         [object.material]\ncolor = [1.0, 1.0, 1.0]\n\n[[object]]\n{object}\n[object.material]\ncolor = [1.0, 1.0, 1.0]\n",
        2.0 * HALF,
    )
}

/// The sphere as a parametric shape.
fn sphere() -> String {
    format!(
        "shape = \"sphere\"\nradius = {RADIUS}\ntransform = {{ translate = [{}, {}, {}] }}",
        CENTRE.x, CENTRE.y, CENTRE.z
    )
}

/// The scene with its light's shadows turned off.
fn unshadowed(text: &str) -> String {
    text.replace("shadow_size", "shadow = false\nshadow_size")
}

fn render(text: &str, base: &Path) -> Vec<[f32; 3]> {
    let scene = Scene::parse(text, base).unwrap_or_else(|e| panic!("{e}\n{text}"));
    wrinkle::render(&scene, &RenderOptions { width: SIZE, height: SIZE, ..Default::default() }).unwrap().color
}

/// The length of a vector's part along the floor.
fn across(v: DVec3) -> f64 {
    v.x.hypot(v.z)
}

/// The floor point under pixel (i, j): x right, z down the picture.
fn floor(i: usize, j: usize) -> DVec3 {
    let k = 2.0 * HALF / SIZE as f64;
    DVec3::new((i as f64 + 0.5) * k - HALF, 0.0, (j as f64 + 0.5) * k - HALF)
}

/// The unit direction towards a light from a floor point.
type Towards = dyn Fn(DVec3) -> DVec3;

/// The distance of the sphere's centre from the ray from `p` towards the light, less the radius: negative
/// where the ray meets the sphere (in shadow; a point light behind the sphere's centre is not counted).
fn margin(p: DVec3, to_light: DVec3) -> f64 {
    let c = CENTRE - p;
    let along = c.dot(to_light);
    if along < 0.0 {
        return c.length() - RADIUS;
    }
    (c - to_light * along).length() - RADIUS
}

/// Checks the render of `text` against the analytic shadow, pixel by pixel as a fraction of the render
/// without shadows; `texel`: the world size of a shadow-map texel at the sphere.
fn check(text: &str, towards: &Towards, texel: f64) {
    let (colour, reference) = (render(text, Path::new(".")), render(&unshadowed(text), Path::new(".")));
    let pixel = 2.0 * HALF / SIZE as f64;
    // Half the floor pixel's diagonal, plus a texel and a half (the lookup's one-texel box and the
    // receiver's normal offset of up to a texel).
    let allowed = 1.5 * texel + 0.75 * pixel;
    let (mut lit, mut dark, mut rendered_dark, mut analytic_dark, mut edge) = (0, 0, 0.0, 0.0, 0.0);
    // The dark areas' first moments: where their centres are.
    let (mut rendered_at, mut analytic_at) = (DVec3::ZERO, DVec3::ZERO);
    for j in 0..SIZE {
        for i in 0..SIZE {
            let p = floor(i, j);
            let unlit = f64::from(reference[j * SIZE + i][0]);
            // The sphere itself hides this floor pixel from the camera; or the light does not reach it.
            if across(p - CENTRE) < RADIUS + pixel || unlit < 1e-3 {
                continue;
            }
            let seen = f64::from(colour[j * SIZE + i][0]) / unlit;
            let m = margin(p, towards(p));
            rendered_dark += 1.0 - seen;
            rendered_at += p * (1.0 - seen);
            if m < 0.0 {
                analytic_dark += 1.0;
                analytic_at += p;
            }
            if m > allowed {
                assert!(seen > 0.999, "{p} is {m} outside the shadow but only {seen} lit");
                lit += 1;
            } else if m < -allowed {
                assert!(seen < 0.001, "{p} is {} inside the shadow but {seen} lit", -m);
                dark += 1;
            } else {
                edge += 1.0;
            }
        }
    }
    assert!(lit > 1000 && dark > 200, "lit {lit}, dark {dark}");
    // The dark areas differ by the outline's mean shift times its length; the edge band is about
    // 2 x allowed wide (floor pixels).
    let outline_pixels = edge / (2.0 * allowed / pixel);
    let shift = (rendered_dark - analytic_dark).abs() / outline_pixels * pixel;
    // Within one texel, as asked; half a texel here, measured at a fifth.
    assert!(shift < 0.5 * texel, "the outline moved by {shift} on average, a texel is {texel}");
    let moved = across(rendered_at / rendered_dark - analytic_at / analytic_dark);
    assert!(moved < 0.5 * texel, "the shadow moved by {moved}, a texel is {texel}");
}

#[test]
fn a_directional_light_casts_the_projected_ellipse() {
    let d = DVec3::new(0.55, -1.0, 0.3).normalize();
    let light = format!("type = \"directional\"\ndirection = [{}, {}, {}]", d.x, d.y, d.z);
    // The map spans the scene's box across the light's rays (its longer side over MAP texels), upright
    // towards +Y.
    let right = d.cross(DVec3::Y).normalize();
    let up = right.cross(d);
    let (lo, hi) = (DVec3::new(-HALF, 0.0, -HALF), DVec3::new(HALF, CENTRE.y + RADIUS, HALF));
    let corners = (0..8).map(|k| DVec3::select(glam::BVec3::new(k & 1 == 1, k & 2 == 2, k & 4 == 4), hi, lo));
    let extent = |axis: DVec3| {
        let along = corners.clone().map(|c| c.dot(axis));
        along.clone().fold(f64::MIN, f64::max) - along.fold(f64::MAX, f64::min)
    };
    let texel = extent(right).max(extent(up)) / MAP as f64;
    check(&scene(&light, &sphere()), &move |_| -d, texel);
}

#[test]
fn point_and_spot_lights_cast_the_projected_cone() {
    let at = DVec3::new(0.3, 3.5, 0.4);
    let towards = move |p: DVec3| (at - p).normalize();
    let position = format!("position = [{}, {}, {}]\nintensity = 6.0", at.x, at.y, at.z);
    let distance = (CENTRE - at).length() + RADIUS;
    // A cube face spans 90 degrees over its MAP texels: 2 units at unit distance.
    let cube_texel = 2.0 * distance / MAP as f64;
    check(&scene(&format!("type = \"point\"\n{position}"), &sphere()), &towards, cube_texel);
    // A wide spot is a cube too; a narrower one has one view of 2 tan(angle) at unit distance.
    let spot = |angle: f64| format!("type = \"spot\"\n{position}\ndirection = [-0.3, -1.0, -0.3]\nangle = {angle}");
    check(&scene(&spot(75.0), &sphere()), &towards, cube_texel);
    let one_view_texel = 2.0 * 55f64.to_radians().tan() * distance / MAP as f64;
    check(&scene(&spot(55.0), &sphere()), &towards, one_view_texel);
}

/// A mesh sphere is not exempt from its own map as the parametric sphere is: lit from any side, it shades
/// exactly as without shadows (no acne) wherever the light meets it more than a facet's turn (about 10
/// degrees: N.L > 0.2) from grazing (nearer the terminator its flat facets do shadow one another, before its
/// interpolated normal turns away), and its shadow still falls on the floor.
#[test]
fn a_lit_convex_mesh_does_not_shadow_itself() {
    let base = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let mesh = format!(
        "shape = \"mesh\"\nfile = \"models/uv_sphere.obj\"\ntransform = {{ scale = {RADIUS}, translate = [{}, {}, {}] }}",
        CENTRE.x, CENTRE.y, CENTRE.z
    );
    for d in [DVec3::new(0.55, -1.0, 0.3), DVec3::new(-0.2, -0.4, 0.9), DVec3::new(0.9, -0.15, -0.2)] {
        let light = format!("type = \"directional\"\ndirection = [{}, {}, {}]", d.x, d.y, d.z);
        let text = scene(&light, &mesh);
        let (shadowed, reference) = (render(&text, &base), render(&unshadowed(&text), &base));
        let (mut same, mut floor_darker) = (0, 0);
        for j in 0..SIZE {
            for i in 0..SIZE {
                let p = floor(i, j);
                let (a, b) = (shadowed[j * SIZE + i][0], reference[j * SIZE + i][0]);
                if across(p - CENTRE) < RADIUS * 0.98 && b > 0.2 {
                    assert!((a - b).abs() <= 1e-6, "light {d}: the sphere at {p} is {a}, unshadowed {b}");
                    same += 1;
                } else if a < 0.5 * b {
                    floor_darker += 1;
                }
            }
        }
        assert!(same > 200 && floor_darker > 100, "light {d}: {same} sphere pixels, {floor_darker} shadowed");
    }
}
