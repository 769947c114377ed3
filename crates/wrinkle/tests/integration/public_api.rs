//! The library's public face used as a Rust program would: a scene built in code (the example of
//! crates/wrinkle/examples/scene_in_code.rs) renders the same bytes as the same scene read from TOML (so the constructors' defaults are the scene format's), the constructors
//! refuse bad values by the parameter's name, images are read through views of the caller's buffer, and the
//! batched and pyramid entry points agree with their one-at-a-time and analytic references.

use glam::{Vec2, Vec3, Vec4};
use std::sync::Arc;
use wrinkle::texture::mip::pyramid;
use wrinkle::{
    render, BumpMap, BumpSource, BumpTable, CameraDesc, Error, Filter, FilterOptions, FilteredTexture, Footprint,
    Image, ImageRef, Light, Material, MipFilter, Projection, RenderOptions, Scene, Shape, Surface, TextureOptions,
    Transform, Wrap,
};

const TOML: &str = r#"
[camera]
eye = [0.5, 1.0, 4.0]
look_at = [0.0, 0.0, 0.0]
fov_y = 35

[[light]]
type = "directional"
direction = [1.0, -1.0, -1.0]
color = [1.0, 0.95, 0.9]

[[light]]
type = "ambient"
intensity = 0.08

[[object]]
shape = "sphere"
radius = 1.0
transform = { rotate = [0, 30, 0] }
material = { color = [0.8, 0.3, 0.2], bump = { generator = { kind = "grid", size = 256, cells = 16, line_width = 0.1, soft = 0.2 }, scale = 0.01 } }
"#;

/// The example of the README and crates/wrinkle/examples: a scene built with the constructors.
#[allow(dead_code)]
#[path = "../../examples/scene_in_code.rs"]
mod scene_in_code;

#[test]
fn a_scene_built_in_code_renders_the_bytes_of_the_same_scene_in_toml() {
    let options = RenderOptions { width: 96, height: 72, ..RenderOptions::default() };
    let from_toml = render(&Scene::parse(TOML, std::path::Path::new(".")).unwrap(), &options).unwrap();
    let in_code = render(&scene_in_code::scene().unwrap(), &options).unwrap();
    assert!(from_toml.color == in_code.color, "the two renders differ");
    // Not a blank frame: the sphere and its grid of bumps are there.
    let lit = from_toml.color.iter().filter(|p| p.iter().any(|&c| c > 0.05)).count();
    assert!(lit > 96 * 72 / 5, "only {lit} lit pixels");
}

/// The parameter an error names, or a panic naming what came instead.
fn parameter<T>(r: wrinkle::Result<T>) -> &'static str {
    match r {
        Err(Error::Parameter { name, .. }) => name,
        Err(e) => panic!("expected a parameter error, got {e}"),
        Ok(_) => panic!("expected a parameter error, got a value"),
    }
}

#[test]
fn constructors_refuse_bad_values_by_the_parameters_name() {
    let (eye, at) = (Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO);
    assert_eq!(parameter(CameraDesc::looking_at(eye, eye)), "look_at");
    assert_eq!(parameter(CameraDesc::new(eye, at, Vec3::Z, Projection::default(), Vec3::ZERO)), "up");
    assert_eq!(parameter(CameraDesc::new(Vec3::NAN, at, Vec3::Y, Projection::default(), Vec3::ZERO)), "eye");
    assert_eq!(parameter(CameraDesc::new(eye, at, Vec3::Y, Projection::default(), -Vec3::X)), "background");
    assert_eq!(
        parameter(CameraDesc::new(eye, at, Vec3::Y, Projection::Perspective { fov_y: 0.0 }, Vec3::ZERO)),
        "fov_y"
    );
    assert_eq!(parameter(Projection::perspective(180.0)), "fov_y");
    assert_eq!(parameter(Projection::orthographic(f32::INFINITY)), "height");
    assert_eq!(parameter(Light::directional(Vec3::ZERO, Vec3::ONE)), "direction");
    assert_eq!(parameter(Light::point(Vec3::ZERO, Vec3::new(1.0, -1.0, 0.0))), "radiance");
    assert_eq!(parameter(Light::spot(Vec3::Y, -Vec3::Y, Vec3::Z, 95.0, 5.0, Vec3::ONE)), "angle");
    assert_eq!(parameter(Light::spot(Vec3::Y, -Vec3::Y, Vec3::Z, 30.0, 31.0, Vec3::ONE)), "falloff");
    let table = BumpTable::new(&Image::new(4, 4, 0.5));
    assert_eq!(parameter(BumpMap::new(BumpSource::Table(Arc::new(table)), f32::NAN)), "scale");
    let mut scene = Scene::new(CameraDesc::default());
    assert_eq!(parameter(scene.add_object(Shape::Box { size: Vec3::ONE }, Transform::default(), 0)), "material");
    let sphere = |radius| Shape::Surface(Surface::Sphere { radius });
    let material = scene.add_material(Material::default());
    assert_eq!(parameter(scene.add_object(sphere(-1.0), Transform::default(), material)), "radius");
    assert_eq!(
        parameter(scene.add_object(Shape::Box { size: Vec3::new(1.0, f32::NAN, 1.0) }, Transform::default(), material)),
        "size"
    );
    let flat = Transform { scale: Vec3::new(1.0, 0.0, 1.0), ..Transform::default() };
    assert_eq!(parameter(scene.add_object(sphere(1.0), flat, material)), "scale");
    assert_eq!(scene.add_object(sphere(1.0), Transform::default(), material).unwrap(), 0);
    assert_eq!(parameter(ImageRef::new(3, 2, &[0.0f32; 5])), "image");
    assert_eq!(parameter(ImageRef::new(0, 2, &[0.0f32; 0])), "image");
    // The same constructors check a scene file, their errors worded as the field's path.
    let bad = TOML.replace("fov_y = 35", "fov_y = 180");
    let e = Scene::parse(&bad, std::path::Path::new(".")).err().expect("fov_y = 180 is refused").to_string();
    assert_eq!(e, "camera.fov_y: must be degrees between 0 and 180, got 180");
    let bad = TOML.replace("direction = [1.0, -1.0, -1.0]", "direction = [0, 0, 0]");
    let e = Scene::parse(&bad, std::path::Path::new(".")).err().expect("a zero direction is refused").to_string();
    assert_eq!(e, "lights[0].direction: must not be [0, 0, 0]");
    let bad = TOML.replace("radius = 1.0", "radius = -1.0");
    let e = Scene::parse(&bad, std::path::Path::new(".")).err().expect("a negative radius is refused").to_string();
    assert_eq!(e, "objects[0].radius: must be a positive length, got -1");
}

/// A small sRGB-free test picture: every texel different.
fn picture(w: usize, h: usize) -> Vec<[f32; 4]> {
    (0..w * h).map(|k| [(k % 7) as f32 / 6.0, (k % 5) as f32 / 4.0, (k % 3) as f32 / 2.0, 1.0]).collect()
}

#[test]
fn a_texture_reads_the_callers_buffer_through_a_view() {
    let (w, h) = (24, 10);
    let buffer = picture(w, h);
    let view = ImageRef::new(w, h, &buffer).unwrap();
    assert!(std::ptr::eq(view.pixels(), buffer.as_slice()), "the view holds the caller's buffer, not a copy");
    assert_eq!(view.row(1)[0], buffer[w]);
    let owned = view.to_image();
    let (a, b) = (
        FilteredTexture::new(view, TextureOptions::default()),
        FilteredTexture::new(&owned, TextureOptions::default()),
    );
    assert_eq!(a.size(), (w, h));
    let fp = Footprint { dudx: 0.01, dvdx: 0.0, dudy: 0.0, dvdy: 0.02 };
    for k in 0..50 {
        let (s, t) = (k as f32 * 0.037, k as f32 * 0.061);
        assert_eq!(a.lookup(s, t, &fp), b.lookup(s, t, &fp));
    }
}

#[test]
fn batched_lookups_equal_single_ones_for_every_filter() {
    let bytes: Vec<[u8; 4]> =
        (0..64 * 48).map(|k| [(k * 37 % 251) as u8, (k * 91 % 256) as u8, (k % 199) as u8, 255]).collect();
    let base = FilteredTexture::from_rgba8(ImageRef::new(64, 48, &bytes).unwrap(), true, TextureOptions::default());
    // Batches work lookups out in runs (of 16 for trilinear, 4 for aniso): 69 leaves the last run short.
    // Every size and shape of footprint, wrapping coordinates.
    let n = 69;
    let st: Vec<Vec2> = (0..n).map(|k| Vec2::new(k as f32 * 0.173 - 2.0, k as f32 * 0.311 + 0.05)).collect();
    let fp: Vec<Footprint> = (0..n)
        .map(|k| {
            let w = 2f32.powf(-9.0 + (k % 9) as f32);
            Footprint { dudx: w, dvdx: 0.3 * w, dudy: -0.2 * w, dvdy: w * (1 + k % 4) as f32 }
        })
        .collect();
    for (name, filter) in Filter::ALL {
        for lod_bias in [0.0, -1.0] {
            let tex = base.with_lookup(FilterOptions { filter, ..FilterOptions::default() }, lod_bias);
            for len in [n, 3, 0] {
                let mut out = vec![Vec4::ZERO; len];
                tex.lookup_batch(&st[..len], &fp[..len], &mut out);
                for i in 0..len {
                    let one = tex.lookup(st[i].x, st[i].y, &fp[i]);
                    assert_eq!(out[i], one, "{name}, bias {lod_bias}, lookup {i} of {len}");
                }
            }
        }
    }
}

#[test]
fn the_pyramid_averages_blocks_of_four_and_keeps_the_picture_upright() {
    // 4 x 4: the top half white, the bottom half black, a red texel at the top left.
    let mut image = Image::from_fn(4, 4, |_, y| if y < 2 { [1.0; 4] } else { [0.0, 0.0, 0.0, 1.0] });
    image.set(0, 0, [1.0, 0.0, 0.0, 1.0]);
    let levels = pyramid(&image, MipFilter::Box, [Wrap::Repeat; 2]);
    let sizes: Vec<(usize, usize)> = levels.iter().map(|l| (l.width, l.height)).collect();
    assert_eq!(sizes, [(4, 4), (2, 2), (1, 1)]);
    assert_eq!(levels[0], image);
    let close = |a: [f32; 4], b: [f32; 4]| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-6);
    assert!(close(levels[1].get(0, 0), [1.0, 0.75, 0.75, 1.0]), "{:?}", levels[1].get(0, 0));
    assert!(close(levels[1].get(1, 0), [1.0; 4]), "{:?}", levels[1].get(1, 0));
    assert!(close(levels[1].get(0, 1), [0.0, 0.0, 0.0, 1.0]), "{:?}", levels[1].get(0, 1));
    assert!(close(levels[2].get(0, 0), [0.5, 0.4375, 0.4375, 1.0]), "{:?}", levels[2].get(0, 0));
    // A texture's own pyramid is the same (level 0 as given, the others from it in f32).
    let texture = FilteredTexture::new(&image, TextureOptions::default());
    assert_eq!(texture.pyramid(), levels);
}
