//! Environment maps against their definitions: a mirror in a constant environment shows exactly that
//! radiance; a flat mirror shows the environment along the analytically mirrored ray, and along the ray
//! mirrored about the bumped normal when it is bump-mapped; the background is the environment along the
//! camera's rays; the four layouts render alike; bad maps are refused in one line.

use crate::common::{scratch_dir, RefCamera};
use glam::{DVec3, Vec3};
use std::path::Path;
use wrinkle::envmap::convert::{convert, picture};
use wrinkle::envmap::{Arrangement, Environment, EnvironmentOptions, Layout};
use wrinkle::image::{io, Image};
use wrinkle::render::Aovs;
use wrinkle::scene::SceneEnvironment;
use wrinkle::{Frame, RenderOptions, Scene};

/// The smooth environment of these tests: linear in the direction.
fn sky(d: DVec3) -> DVec3 {
    DVec3::new(0.5 + 0.4 * d.x, 0.5 + 0.4 * d.y, 0.5 + 0.4 * d.z)
}

/// `sky` as a latlong EXR of 512 x 256 texels, named `name` in `dir`.
fn write_sky(dir: &Path, name: &str) -> Image<[f32; 4]> {
    let (w, h) = (512, 256);
    let image = Image::from_fn(w, h, |x, y| {
        let d = Layout::LatLong.direction(0, (x as f32 + 0.5) / w as f32, 1.0 - (y as f32 + 0.5) / h as f32).unwrap();
        let c = sky(d.as_dvec3()).as_vec3();
        [c.x, c.y, c.z, 1.0]
    });
    write_rgba_exr(&dir.join(name), &image);
    image
}

fn write_rgba_exr(path: &Path, image: &Image<[f32; 4]>) {
    let channel = |c: usize| image.pixels.iter().map(|p| p[c]).collect::<Vec<f32>>();
    let (r, g, b) = (channel(0), channel(1), channel(2));
    io::write_exr(path, image.width, image.height, &[("R", &r), ("G", &g), ("B", &b)]).unwrap();
}

const EYE: [f64; 3] = [0.0, 1.5, 3.0];
const SIZE: usize = 96;

/// A mirror patch in the plane z = 0 (normal +Z) seen from `EYE`, in an environment from `environment`
/// (TOML), with `bump` (TOML lines for the material's bump table, or nothing).
fn mirror_scene(environment: &str, bump: &str) -> String {
    format!(
        "[camera]\neye = [0.0, 1.5, 3.0]\nlook_at = [0.0, 0.0, 0.0]\nfov_y = 50.0\nbackground = [0.0, 0.0, 0.0]\n\n\
         [environment]\n{environment}\n\n\
         [[object]]\nshape = \"patch\"\ncorners = [[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]]\n\
         [object.material]\ncolor = [0.0, 0.0, 0.0]\nspecular = 0.0\nreflect = [1.0, 1.0, 1.0]\n{bump}\n"
    )
}

fn render(scene: &Scene) -> Frame {
    let aovs = Aovs { normal: true, depth: true, ..Aovs::default() };
    wrinkle::render(scene, &RenderOptions { width: SIZE, height: SIZE, aovs, ..Default::default() }).expect("render")
}

fn parse(text: &str, base: &Path) -> Scene {
    Scene::parse(text, base).unwrap_or_else(|e| panic!("scene does not parse: {e}\n{text}"))
}

fn camera() -> RefCamera {
    RefCamera::perspective(EYE, [0.0; 3], [0.0, 1.0, 0.0], 50.0, SIZE, SIZE)
}

fn reflect(d: DVec3, n: DVec3) -> DVec3 {
    d - 2.0 * d.dot(n) * n
}

/// A mirror sphere in a constant environment reflects exactly that radiance, at every pixel it covers.
#[test]
fn mirror_in_a_constant_environment_shows_it_exactly() {
    let text = "[camera]\neye = [0.0, 0.0, 3.0]\nlook_at = [0.0, 0.0, 0.0]\nbackground = [0.0, 0.0, 0.0]\n\n\
                [[object]]\nshape = \"sphere\"\n[object.material]\ncolor = [0.0, 0.0, 0.0]\nspecular = 0.0\n\
                reflect = [1.0, 1.0, 1.0]\n";
    let mut scene = parse(text, Path::new("."));
    let radiance = Vec3::new(0.3, 0.6, 2.5);
    scene.environment = Some(SceneEnvironment { map: Environment::constant(radiance), background: false });
    let frame = render(&scene);
    let depth = frame.depth.as_ref().unwrap();
    let mut covered = 0;
    for (c, d) in frame.color.iter().zip(depth) {
        let want = if d.is_finite() { radiance } else { Vec3::ZERO };
        assert!(Vec3::from(*c).distance(want) < 1e-5, "{c:?} vs {want}");
        covered += usize::from(d.is_finite());
    }
    assert!(covered > SIZE * SIZE / 4, "the sphere covers {covered} pixels");
}

/// A flat mirror shows the environment along the mirrored view ray (computed here in f64 from the scene
/// format's camera), and the background is the environment along the camera's rays.
#[test]
fn flat_mirror_and_background_show_the_mirrored_and_direct_rays() {
    let dir = scratch_dir("env-mirror");
    write_sky(&dir, "sky.exr");
    let frame = render(&parse(&mirror_scene("map = \"sky.exr\"", ""), &dir));
    let (cam, depth) = (camera(), frame.depth.as_ref().unwrap());
    let (mut mirrored, mut direct) = (0, 0);
    for j in 0..SIZE {
        for i in 0..SIZE {
            let k = j * SIZE + i;
            let (_, d) = cam.pixel_ray(i, j);
            let (want, count) = match depth[k].is_finite() {
                true => (sky(reflect(d, DVec3::Z)), &mut mirrored),
                false => (sky(d), &mut direct),
            };
            let got = DVec3::from(frame.color[k].map(f64::from));
            assert!((got - want).abs().max_element() < 4e-3, "pixel ({i}, {j}): {got} vs {want}");
            *count += 1;
        }
    }
    assert!(mirrored > 1000 && direct > 1000, "{mirrored} mirrored, {direct} direct");
}

/// Bumps show in reflections: a bump-mapped mirror reflects about its perturbed normal (the normal AOV),
/// which turns well away from the flat one.
#[test]
fn bumped_mirror_reflects_about_the_perturbed_normal() {
    let dir = scratch_dir("env-bump");
    write_sky(&dir, "sky.exr");
    let bump = "[object.material.bump]\ngenerator = { kind = \"rivets\", count = 4 }\nscale = 0.01\nrepeat = [2, 2]";
    let frame = render(&parse(&mirror_scene("map = \"sky.exr\"\nbackground = false", bump), &dir));
    let (cam, depth, normals) = (camera(), frame.depth.as_ref().unwrap(), frame.normal.as_ref().unwrap());
    let mut most_turned = 0.0f64;
    for j in 0..SIZE {
        for i in 0..SIZE {
            let k = j * SIZE + i;
            if !depth[k].is_finite() {
                continue;
            }
            let n = DVec3::from(normals[k].map(f64::from)).normalize();
            most_turned = most_turned.max(n.angle_between(DVec3::Z).to_degrees());
            let want = sky(reflect(cam.pixel_ray(i, j).1, n));
            let got = DVec3::from(frame.color[k].map(f64::from));
            assert!((got - want).abs().max_element() < 4e-3, "pixel ({i}, {j}): {got} vs {want}");
        }
    }
    assert!(most_turned > 10.0, "the bump turns the normal by at most {most_turned} degrees");
}

/// The same environment as latlong, cube (cross, and six files), sphere map and dual paraboloid: the
/// mirror renders alike (within 1%; the sphere map's rim, -Z, is not in view of this mirror).
#[test]
fn every_layout_renders_alike() {
    let dir = scratch_dir("env-layouts");
    let latlong = write_sky(&dir, "sky.exr");
    let options = EnvironmentOptions::default();
    let env = Environment::new(Layout::LatLong, &[latlong], options).unwrap();
    // The mirror only (the background looks towards -Z, the sphere map's rim).
    let reference = render(&parse(&mirror_scene("map = \"sky.exr\"\nbackground = false", ""), &dir));
    let faces = convert(&env, Layout::Cube, 192);
    for (k, face) in faces.iter().enumerate() {
        write_rgba_exr(&dir.join(format!("face{k}.exr")), face);
    }
    let files: Vec<String> = (0..6).map(|k| format!("\"face{k}.exr\"")).collect();
    let six = format!("map = [{}]\nbackground = false", files.join(", "));
    for (name, layout, size) in
        [("cross", Layout::Cube, 192), ("ball", Layout::Sphere, 512), ("halves", Layout::Paraboloid, 384)]
    {
        let file = format!("{name}.exr");
        write_rgba_exr(&dir.join(&file), &picture(layout, &convert(&env, layout, size), Arrangement::Cross));
        for map in [format!("map = \"{file}\"\nlayout = \"{}\"\nbackground = false", layout.name()), six.clone()] {
            let frame = render(&parse(&mirror_scene(&map, ""), &dir));
            let worst = frame
                .color
                .iter()
                .zip(&reference.color)
                .map(|(a, b)| (Vec3::from(*a) - Vec3::from(*b)).abs().max_element())
                .fold(0.0, f32::max);
            assert!(worst < 0.01, "{name} ({map}): worst difference {worst}");
        }
    }
}

/// Bad maps: one clear line naming what is wrong.
#[test]
fn bad_maps_are_refused_in_one_line() {
    let dir = scratch_dir("env-bad");
    let grey = |name: &str, w: usize, h: usize| {
        io::write_png_rgb8(&dir.join(name), w, h, &vec![128u8; w * h * 3]).unwrap();
        name.to_string()
    };
    std::fs::write(dir.join("bad.hdr"), b"#?RADIANCE\nFORMAT=32-bit_rle_xyze_nonsense\n\n-Y 2 +X 4\n\x01\x02").unwrap();
    let faces: Vec<String> =
        (0..6).map(|k| grey(&format!("f{k}.png"), if k == 3 { 8 } else { 4 }, if k == 3 { 8 } else { 4 })).collect();
    let quoted = |names: &[String]| names.iter().map(|n| format!("\"{n}\"")).collect::<Vec<_>>().join(", ");
    let cases = [
        (
            format!("map = \"{}\"\nlayout = \"cube\"", grey("wide.png", 50, 30)),
            "a cube map in one picture is a cross (4:3)",
        ),
        (format!("map = \"{}\"", grey("odd.png", 50, 30)), "cannot tell the layout of a 50x30 environment map"),
        (format!("map = [{}]", quoted(&faces)), "the images of a cube map must be one size: 4x4 and 8x8"),
        (
            format!("map = [{}]", quoted(&faces[..5])),
            "one picture, two paraboloid halves or six cube faces, got 5 files",
        ),
        ("map = \"missing.hdr\"".to_string(), "missing.hdr: no such file"),
        ("map = \"bad.hdr\"".to_string(), "bad.hdr:"),
        (format!("map = \"{}\"\nlayout = \"mercator\"", grey("ok.png", 8, 4)), "environment.layout"),
    ];
    for (environment, expected) in cases {
        let text = mirror_scene(&environment, "");
        let err = match Scene::parse(&text, &dir) {
            Err(e) => e.to_string(),
            Ok(_) => panic!("accepted: {environment}"),
        };
        assert!(err.contains(expected), "{environment}: {err}");
        assert!(!err.contains('\n'), "one line: {err}");
    }
}

/// A sphere seen head-on, lit only by the environment in `file` (`[[light]] type = "environment"`), with a
/// material's body.
fn lit_sphere(file: &str, material: &str) -> String {
    format!(
        "[camera]\neye = [0.0, 0.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\nbackground = [0.0, 0.0, 0.0]\n\n\
         [environment]\nmap = \"{file}\"\nbackground = false\n\n[[light]]\ntype = \"environment\"\n\n\
         [[object]]\nshape = \"sphere\"\n[object.material]\n{material}\n"
    )
}

/// Image-based lighting in a constant environment of radiance L: a white Lambertian surface shades to
/// exactly L (the normalisation: albedo / pi times the irradiance), and a glossy black one to ks L.
#[test]
fn constant_environment_lights_to_its_own_radiance() {
    let dir = scratch_dir("ibl-constant");
    let radiance = [0.4f32, 1.5, 3.0];
    write_rgba_exr(&dir.join("flat.exr"), &Image::new(2, 1, [radiance[0], radiance[1], radiance[2], 1.0]));
    for (material, scale) in [
        ("color = [1.0, 1.0, 1.0]\nspecular = 0.0", 1.0f32),
        ("color = [0.0, 0.0, 0.0]\nspecular = 0.35\nshininess = 80.0", 0.35),
    ] {
        let frame = render(&parse(&lit_sphere("flat.exr", material), &dir));
        let depth = frame.depth.as_ref().unwrap();
        for (c, d) in frame.color.iter().zip(depth).filter(|(_, d)| d.is_finite()) {
            for k in 0..3 {
                assert!((c[k] - scale * radiance[k]).abs() < 1e-3 * radiance[k], "{material}: {c:?} at depth {d}");
            }
        }
    }
}

/// Under one bright texel (a one-hot direction) a white Lambertian sphere's shading follows the clamped
/// cosine about that direction (within 4% of its peak: the convolved map is a small grid read bilinearly).
#[test]
fn one_hot_environment_lights_along_the_cosine_lobe() {
    let dir = scratch_dir("ibl-one-hot");
    let (w, h) = (128, 64);
    // Up, left and towards the camera (+Z lies at the left and right edges of a latlong map).
    let hot = (w / 8, h / 3);
    let image =
        Image::from_fn(w, h, |x, y| if (x, y) == hot { [500.0, 500.0, 500.0, 1.0] } else { [0.0, 0.0, 0.0, 1.0] });
    write_rgba_exr(&dir.join("hot.exr"), &image);
    let light =
        Layout::LatLong.direction(0, (hot.0 as f32 + 0.5) / w as f32, 1.0 - (hot.1 as f32 + 0.5) / h as f32).unwrap();
    // The texel's power spread over the sphere's cosine: radiance x solid angle / pi at the peak.
    let polar = |j: usize| j as f32 * std::f32::consts::PI / h as f32;
    let solid_angle = 2.0 * std::f32::consts::PI / w as f32 * (polar(hot.1).cos() - polar(hot.1 + 1).cos());
    let peak = 500.0 * solid_angle / std::f32::consts::PI;
    let frame = render(&parse(&lit_sphere("hot.exr", "color = [1.0, 1.0, 1.0]\nspecular = 0.0"), &dir));
    let (depth, normals) = (frame.depth.as_ref().unwrap(), frame.normal.as_ref().unwrap());
    let mut lit = 0;
    for k in (0..SIZE * SIZE).filter(|&k| depth[k].is_finite()) {
        let n = Vec3::from(normals[k]);
        let want = peak * n.dot(light).max(0.0);
        assert!(
            (frame.color[k][0] - want).abs() < 0.04 * peak,
            "normal {n}: {} vs {want} (peak {peak})",
            frame.color[k][0]
        );
        lit += usize::from(want > 0.5 * peak);
    }
    assert!(lit > 100, "{lit} pixels well lit");
}

/// Chrome mapping needs no environment: a constant chrome map shows its colour times `strength` exactly;
/// the slides' landscape is blue where the reflected ray looks up and brown where it looks down.
#[test]
fn chrome_mapping_looks_up_the_blurred_map_by_the_reflected_ray() {
    let dir = scratch_dir("chrome");
    write_rgba_exr(&dir.join("flat.exr"), &Image::new(2, 1, [0.5, 0.25, 2.0, 1.0]));
    let sphere = |chrome: &str| {
        format!(
            "[camera]\neye = [0.0, 0.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\nbackground = [0.0, 0.0, 0.0]\n\n\
             [[object]]\nshape = \"sphere\"\n[object.material]\ncolor = [0.0, 0.0, 0.0]\n[object.material.chrome]\n{chrome}\n"
        )
    };
    let frame = render(&parse(&sphere("map = \"flat.exr\"\nstrength = [2.0, 1.0, 0.5]"), &dir));
    let depth = frame.depth.as_ref().unwrap();
    for (c, _) in frame.color.iter().zip(depth).filter(|(_, d)| d.is_finite()) {
        assert!(Vec3::from(*c).distance(Vec3::new(1.0, 0.25, 1.0)) < 1e-4, "{c:?}");
    }
    let frame = render(&parse(&sphere("blur = 8.0"), &dir));
    // Near the top of the disc the normal tilts up and back: R looks up; near the bottom, down.
    let (top, bottom) = (frame.color[SIZE / 4 * SIZE + SIZE / 2], frame.color[SIZE * 3 / 4 * SIZE + SIZE / 2]);
    assert!(top[2] > 1.3 * top[0], "sky above: {top:?}");
    assert!(bottom[0] > 1.3 * bottom[2], "earth below: {bottom:?}");
}

/// `reflect_views`: a mirror sphere sees the scene in six views from its centroid. A red patch beside it
/// shows where the ray from the centroid along R meets the patch, black where it misses (away from the
/// patch's outline by more than the reflected rays' footprint).
#[test]
fn rendered_views_mirror_the_scene_about_the_centroid() {
    let text = "[camera]\neye = [0.0, 0.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\nbackground = [0.0, 0.0, 0.0]\n\n\
                [[light]]\ntype = \"ambient\"\n\n\
                [[object]]\nshape = \"sphere\"\nradius = 0.6\n[object.material]\ncolor = [0.0, 0.0, 0.0]\n\
                reflect = [1.0, 1.0, 1.0]\nreflect_views = 128\n\n\
                [[object]]\nshape = \"patch\"\ncorners = [[-2.0, -1.0, 1.5], [-2.0, -1.0, -1.5], [-2.0, 1.5, -1.5], [-2.0, 1.5, 1.5]]\n\
                [object.material]\ncolor = [1.0, 0.0, 0.0]\n";
    let frame = render(&parse(text, Path::new(".")));
    let cam = RefCamera::perspective([0.0, 0.0, 4.0], [0.0; 3], [0.0, 1.0, 0.0], 40.0, SIZE, SIZE);
    let (mut red, mut black) = (0, 0);
    for j in 0..SIZE {
        for i in 0..SIZE {
            let (o, d) = cam.pixel_ray(i, j);
            // The sphere of radius 0.6 at the origin.
            let b = o.dot(d);
            let disc = b * b - (o.length_squared() - 0.36);
            if disc < 1e-3 {
                continue;
            }
            let p = o + d * (-b - disc.sqrt());
            // Near the outline the reflected rays fan out across a pixel, and the filter averages them.
            if p.normalize().dot(-d) < 0.4 {
                continue;
            }
            let r = reflect(d, p.normalize());
            // The ray from the centroid along R against the plane x = -2.
            let hit = (r.x < 0.0).then(|| r * (-2.0 / r.x)).filter(|h| h.y > -1.0 && h.y < 1.5 && h.z.abs() < 1.5);
            let margin = |h: DVec3| (h.y + 1.0).min(1.5 - h.y).min(1.5 - h.z.abs());
            let got = frame.color[j * SIZE + i];
            match hit {
                Some(h) if margin(h) > 0.6 => {
                    // Filtered over the reflected rays' footprint: within 2% of the patch's red.
                    assert!(
                        (got[0] - 1.0).abs() < 0.02 && got[1].abs() < 1e-3,
                        "pixel ({i}, {j}) sees the patch: {got:?}"
                    );
                    red += 1;
                }
                None if r.x > 0.2 => {
                    assert!(got[0] < 0.02, "pixel ({i}, {j}) sees nothing: {got:?}");
                    black += 1;
                }
                _ => {}
            }
        }
    }
    assert!(red > 20 && black > 200, "{red} red, {black} black");
}
