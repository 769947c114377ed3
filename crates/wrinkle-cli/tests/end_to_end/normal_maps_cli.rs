//! `wrinkle normalmap` output rendered as a tangent-space normal map looks like Blinn's bump mapping of
//! the height map it came from, on a parametric sphere and on a triangle-mesh sphere (MikkTSpace tangents).

use crate::common::*;
use std::fmt::Write as _;
use std::path::Path;
use wrinkle::image::io::read_exr_channels;

const SIZE: usize = 160;

/// The scene around one sphere object (`shape` fields) with `material` fields (each after a comma).
fn scene(shape: &str, material: &str) -> String {
    format!(
        "[camera]\neye = [0.0, 0.3, 3.2]\nlook_at = [0.0, 0.0, 0.0]\n\n\
         [[light]]\ntype = \"directional\"\ndirection = [-0.5, -0.4, -1.0]\n\n\
         [[object]]\n{shape}\nmaterial = {{ color = [0.8, 0.6, 0.4], specular = 0.3, shininess = 30{material} }}\n"
    )
}

/// Linear RGB of a render of `scene`.
fn render(s: &Scratch, name: &str, scene: &str) -> Vec<[f32; 3]> {
    let path = s.write_input(&format!("{name}.toml"), scene);
    let out = s.out(&format!("{name}.exr"));
    let size = SIZE.to_string();
    assert_ok(&wrinkle(&["render", &path, "-o", &out, "--width", &size, "--height", &size]));
    let (w, h, channels) = read_exr_channels(Path::new(&out)).unwrap();
    assert_eq!((w, h), (SIZE, SIZE));
    let get = |n: &str| channels.iter().find(|(c, _)| c == n).map(|(_, v)| v.clone()).unwrap();
    let (r, g, b) = (get("R"), get("G"), get("B"));
    (0..w * h).map(|k| [r[k], g[k], b[k]]).collect()
}

/// The mean absolute difference of two renders over the sphere's middle band (|latitude| < 30 degrees, where
/// one strength of the normal map matches the bump's tilt along u and v alike).
fn band_difference(a: &[[f32; 3]], b: &[[f32; 3]]) -> f64 {
    let (mut sum, mut n) = (0.0, 0);
    for y in SIZE * 5 / 16..SIZE * 9 / 16 {
        for x in SIZE / 5..SIZE * 4 / 5 {
            let k = y * SIZE + x;
            sum += (0..3).map(|c| (a[k][c] - b[k][c]).abs() as f64).sum::<f64>() / 3.0;
            n += 1;
        }
    }
    sum / n as f64
}

/// A unit UV sphere as OBJ, with the parametric sphere's (u, v): u the longitude from +x (0.25 at -z),
/// v the latitude from the south pole.
fn sphere_obj(segments: usize) -> String {
    let (nu, nv) = (2 * segments, segments);
    let mut s = String::new();
    for j in 0..=nv {
        for i in 0..=nu {
            let (u, v) = (i as f64 / nu as f64, j as f64 / nv as f64);
            let (phi, theta) = (std::f64::consts::TAU * u, std::f64::consts::PI * (v - 0.5));
            let p = [theta.cos() * phi.cos(), theta.sin(), -theta.cos() * phi.sin()];
            writeln!(s, "v {} {} {}\nvn {} {} {}\nvt {u} {v}", p[0], p[1], p[2], p[0], p[1], p[2]).unwrap();
        }
    }
    for j in 0..nv {
        for i in 0..nu {
            let a = j * (nu + 1) + i + 1;
            let (b, c, d) = (a + 1, a + nu + 2, a + nu + 1);
            writeln!(s, "f {a}/{a}/{a} {b}/{b}/{b} {c}/{c}/{c}\nf {a}/{a}/{a} {c}/{c}/{c} {d}/{d}/{d}").unwrap();
        }
    }
    s
}

#[test]
fn normal_maps_render_like_the_bump_map_they_came_from() {
    let s = Scratch::new("normal-maps");
    let height = s.input("bricks.png");
    assert_ok(&wrinkle(&["bumpgen", "bricks", "-o", &height, "--size", "256"]));
    // A bump of scale k on a unit sphere, the table W = H = 256 texels repeated [2, 1], tilts the normal by
    // k 2 W / (2 pi) dh/dx along u at the equator and k H / pi dh/dy along v: strength 256 k / pi for both.
    let k = 0.02;
    let strength = format!("{}", 256.0 * k / std::f64::consts::PI);
    let normals = s.input("normals.png");
    assert_ok(&wrinkle(&["normalmap", &height, "-o", &normals, "--strength", &strength, "--wrap"]));
    s.write_input("sphere.obj", sphere_obj(64));
    let bump = format!(", bump = {{ map = \"bricks.png\", scale = {k}, repeat = [2, 1] }}");
    let normal = ", normal_map = { path = \"normals.png\", repeat = [2, 1] }";
    let parametric = "shape = \"sphere\"";
    let mesh = "shape = \"mesh\"\nfile = \"sphere.obj\"";
    let bumped = render(&s, "bumped", &scene(parametric, &bump));
    let flat = render(&s, "flat", &scene(parametric, ""));
    let control = band_difference(&bumped, &flat);
    for (name, shape) in [("parametric", parametric), ("mesh", mesh)] {
        let mapped = render(&s, name, &scene(shape, normal));
        let d = band_difference(&bumped, &mapped);
        // The bricks' edges shift the shading by about `control`; the normal map must follow them closely.
        assert!(d < 0.2 * control, "{name}: {d} against the unbumped sphere's {control}");
    }
    // The mesh sphere bumped the way the parametric one is: Blinn's perturbation on a triangle mesh.
    let mesh_bumped = render(&s, "mesh_bumped", &scene(mesh, &bump));
    let d = band_difference(&bumped, &mesh_bumped);
    assert!(d < 0.2 * control, "Blinn on the mesh: {d} against {control}");
}
