//! A scene built in code, without a scene file, rendered and written as a PNG:
//! `cargo run --release -p wrinkle --example scene_in_code -- out.png`. The same scene in TOML renders the
//! same bytes (tests/integration/public_api.rs).

use glam::Vec3;
use std::sync::Arc;
use wrinkle::bump::generators::{Generator, GridParams};
use wrinkle::image::{color::SrgbEncoder, io};
use wrinkle::{
    render, BumpMap, BumpSource, BumpTable, CameraDesc, Light, Material, Projection, RenderOptions, Result, Scene,
    Shape, Surface, Transform,
};

/// A red sphere under one directional light, bumped by Blinn's grid (his figure 5).
pub fn scene() -> Result<Scene> {
    let projection = Projection::perspective(35.0)?;
    let camera = CameraDesc::new(Vec3::new(0.5, 1.0, 4.0), Vec3::ZERO, Vec3::Y, projection, Vec3::ZERO)?;
    let mut scene = Scene::new(camera);
    scene
        .add_light(Light::directional(Vec3::new(1.0, -1.0, -1.0), Vec3::new(1.0, 0.95, 0.9))?)
        .add_light(Light::ambient(Vec3::splat(0.08))?);
    let grid = Generator::Grid(GridParams { cells: 16, line_width: 0.1, soft: 0.2 }).generate(256)?;
    let bump = BumpMap::new(BumpSource::Table(Arc::new(BumpTable::new(&grid))), 0.01)?;
    let red = scene.add_material(Material { color: Vec3::new(0.8, 0.3, 0.2), bump: Some(bump), ..Material::default() });
    let turned = Transform { rotate: Vec3::new(0.0, 30.0, 0.0), ..Transform::default() };
    scene.add_object(Shape::Surface(Surface::Sphere { radius: 1.0 }), turned, red)?;
    Ok(scene)
}

fn main() -> Result<()> {
    let out = std::env::args().nth(1).unwrap_or_else(|| "scene_in_code.png".into());
    let frame = render(&scene()?, &RenderOptions { width: 640, height: 480, ..RenderOptions::default() })?;
    let encoder = SrgbEncoder::new();
    let bytes: Vec<u8> = frame.color.iter().flat_map(|c| c.map(|v| encoder.encode(v))).collect();
    io::write_png_rgb8(std::path::Path::new(&out), frame.width, frame.height, &bytes)?;
    println!("wrote {out}");
    Ok(())
}
