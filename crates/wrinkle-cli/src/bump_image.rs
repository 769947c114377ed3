//! `wrinkle bump`: Blinn bump mapping of a height image, rendered by the renderer itself: the image is the
//! bump table of a flat patch seen head-on through an orthographic camera, one pixel per texel.

use crate::output::{format_of, write_outputs};
use clap::Args;
use glam::Vec3;
use std::path::PathBuf;
use std::sync::Arc;
use wrinkle::bump::schlag::light_direction;
use wrinkle::bump::{BumpMap, BumpSource, BumpTable};
use wrinkle::geometry::{Shape, Surface, Transform};
use wrinkle::image::io::{load_grey, load_rgba8};
use wrinkle::light::{Light, ShadowSettings};
use wrinkle::mapping::{MappedTexture, Mapping};
use wrinkle::scene::{CameraDesc, Object, Projection};
use wrinkle::shade::{Material, Phong};
use wrinkle::texture::{FilteredTexture, TextureOptions};
use wrinkle::{render, Error, RenderOptions, Result, Scene};

/// Bump-map a grey height image with Blinn's perturbation, through the renderer (a flat patch seen head-on)
#[derive(Args, Debug)]
#[command(after_help = "\
The image is the bump function F = SCALE * h (h the grey value in [0, 1]) on a flat patch one unit per
pixel, so SCALE is the height of white above black in pixels (the surface of `emboss --width SCALE`).
The light uses emboss's conventions (azimuth 0 from the right, 90 from the top). Derivatives are Blinn's
central differences on the table, which is periodic: border pixels read the opposite edge. The output is
rendered light, sRGB-encoded in PNG (linear in EXR), unlike emboss which stores the shade itself.

Examples:
  wrinkle bump height.png -o bumped.png
  wrinkle bump height.png -o brick.png --texture bricks.jpg --light 120,35 --scale 6 --specular 0.4 --shininess 40")]
pub struct BumpArgs {
    /// Height image (PNG 8 or 16 bit, JPEG, BMP, TGA, TIFF); white is high
    pub input: PathBuf,
    /// Output image: .png (8-bit sRGB) or .exr (linear float)
    #[arg(short, long)]
    pub output: PathBuf,
    /// Colour image on the patch (any size: stretched over it, bilinear, sRGB decoded)
    #[arg(long)]
    pub texture: Option<PathBuf>,
    /// Light direction AZ,EL in degrees (azimuth counter-clockwise from the right, elevation above the picture)
    #[arg(long, default_value = "135,45", allow_hyphen_values = true)]
    pub light: String,
    /// Height of white above black, in pixels
    #[arg(long, default_value_t = 3.0, allow_negative_numbers = true)]
    pub scale: f32,
    /// Strength of the Blinn-Phong highlight
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub specular: f32,
    /// Exponent of the highlight (larger is tighter)
    #[arg(long, default_value_t = 20.0, allow_negative_numbers = true)]
    pub shininess: f32,
    /// Light reaching every point regardless of its normal (0 to 1)
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub ambient: f32,
    /// Worker threads (default: all cores)
    #[arg(long)]
    pub threads: Option<usize>,
}

/// `AZ,EL` in degrees, elevation in [0, 90].
fn parse_light(text: &str) -> Result<(f32, f32)> {
    let bad = || Error::Invalid(format!("--light must be AZ,EL in degrees (elevation 0 to 90), got \"{text}\""));
    let (az, el) = text.split_once(',').ok_or_else(bad)?;
    let (az, el): (f32, f32) = (az.trim().parse().map_err(|_| bad())?, el.trim().parse().map_err(|_| bad())?);
    if !az.is_finite() || !(0.0..=90.0).contains(&el) {
        return Err(bad());
    }
    Ok((az, el))
}

/// The scene: a `w` x `h` patch in the z = 0 plane (one unit per pixel), an orthographic camera on its
/// axis seeing exactly the patch, and one directional light.
pub fn scene(args: &BumpArgs, table: BumpTable, texture: Option<FilteredTexture>) -> Result<Scene> {
    let (az, el) = parse_light(&args.light)?;
    for (name, v, ok) in [
        ("--scale", args.scale, args.scale.is_finite()),
        ("--specular", args.specular, args.specular.is_finite() && args.specular >= 0.0),
        ("--shininess", args.shininess, args.shininess.is_finite() && args.shininess > 0.0),
        ("--ambient", args.ambient, (0.0..=1.0).contains(&args.ambient)),
    ] {
        if !ok {
            return Err(Error::Invalid(format!("{name}: {v} is out of range")));
        }
    }
    let (w, h) = (table.width() as f32, table.height() as f32);
    let centre = Vec3::new(0.5 * w, 0.5 * h, 0.0);
    let corners = [Vec3::ZERO, Vec3::new(w, 0.0, 0.0), Vec3::new(w, h, 0.0), Vec3::new(0.0, h, 0.0)];
    let mut lights = vec![Light::Directional { direction: -Vec3::from(light_direction(az, el)), radiance: Vec3::ONE }];
    if args.ambient > 0.0 {
        lights.push(Light::Ambient { radiance: Vec3::splat(args.ambient) });
    }
    // Blinn's bilinear FVAL on the full table, the surface's own (u,v).
    let bump = BumpMap::new(BumpSource::Table(Arc::new(table)), args.scale)?;
    let mut material = Material {
        color: Vec3::ONE,
        phong: Phong::new(args.specular, args.shininess),
        bump: Some(bump),
        ..Material::default()
    };
    if let Some(t) = texture {
        material.set_colour_texture(MappedTexture { texture: Arc::new(t), mapping: Mapping::default() }, false);
    }
    Ok(Scene {
        camera: CameraDesc {
            eye: centre + Vec3::new(0.0, 0.0, w.max(h)),
            look_at: centre,
            up: Vec3::Y,
            projection: Projection::Orthographic { height: h },
            background: Vec3::ZERO,
        },
        shadows: vec![ShadowSettings::OFF; lights.len()],
        lights,
        objects: vec![Object {
            shape: Shape::Surface(Surface::Patch { corners }),
            transform: Transform::default(),
            material: 0,
            affine: false,
        }],
        materials: vec![material],
        volumes: Vec::new(),
        environment: None,
        slides: Vec::new(),
        animation: None,
    })
}

pub fn run(args: &BumpArgs) -> Result<()> {
    format_of(&args.output)?;
    crate::set_threads(args.threads)?;
    let heights = load_grey(&args.input)?;
    let (w, h) = (heights.width, heights.height);
    let options = RenderOptions { width: w, height: h, ..RenderOptions::default() };
    options.validate().map_err(|e| Error::read(&args.input, format!("image is {w}x{h}, too large to render: {e}")))?;
    let texture = match &args.texture {
        Some(path) => Some(FilteredTexture::from_rgba8(&load_rgba8(path)?, true, TextureOptions::default())),
        None => None,
    };
    let scene = scene(args, BumpTable::new(&heights), texture)?;
    let frame = render(&scene, &options)?;
    write_outputs(&args.output, &frame)
}
