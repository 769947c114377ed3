//! `wrinkle mappings`: a contact sheet of every texture mapping of the course, each panel one mapping on
//! a sphere and on the Utah teapot (Newell's patches tessellated into a mesh, so that the patches' own
//! (u,v) show beside the projections), with a lettered checkerboard that shows where each cell lands.

use crate::sheet::{self, Panel};
use clap::Args;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use wrinkle::bump::generators::glyph;
use wrinkle::geometry::{MeshPart, Shape, TriangleMesh};
use wrinkle::image::color::srgb_to_linear;
use wrinkle::image::{io, Image};
use wrinkle::mapping::MappedTexture;
use wrinkle::scene::parse_mapping_text;
use wrinkle::texture::{FilteredTexture, TextureOptions};
use wrinkle::{render, RenderOptions, Result, Scene};

#[derive(Args, Debug)]
#[command(
    after_help = "Examples:\n  wrinkle mappings -o docs/images/mappings.png\n  wrinkle mappings -o sheet.png --width 480 --height 300 --columns 3\n\nEach mapping works in the object's own space, where the sphere has radius 1 and the teapot fits in the cube [-1, 1]^3."
)]
pub struct MappingsArgs {
    /// The sheet (PNG).
    #[arg(short, long, default_value = "mappings.png")]
    pub output: PathBuf,
    /// Width of each panel.
    #[arg(long, default_value_t = 320)]
    pub width: usize,
    /// Height of each panel.
    #[arg(long, default_value_t = 200)]
    pub height: usize,
    /// Samples per pixel (1 to 4096, stratified).
    #[arg(long, default_value_t = 4)]
    pub spp: usize,
    /// Panels per row of the sheet.
    #[arg(long, default_value_t = 4)]
    pub columns: usize,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
}

/// Every mapping of docs/mapping.md as a scene writes it, with its panel's label. Two-part mappings that
/// equal a one-part one are left out: cylinder/ISN is cylindrical, sphere/centroid spherical, plane/ISN
/// planar, box/normal box.
pub const MAPPINGS: [(&str, &str); 14] = [
    ("uv", r#"{ type = "uv" }"#),
    ("planar", r#"{ type = "planar" }"#),
    ("cylindrical", r#"{ type = "cylindrical" }"#),
    ("spherical", r#"{ type = "spherical" }"#),
    ("spherical part", r#"{ type = "spherical", longitude = [0.0, 180.0], latitude = [-45.0, 45.0] }"#),
    ("box", r#"{ type = "box" }"#),
    ("cylinder/normal", r#"{ type = "two_part", surface = "cylinder", projector = "normal" }"#),
    ("sphere/normal", r#"{ type = "two_part", surface = "sphere", projector = "normal" }"#),
    ("box/centroid", r#"{ type = "two_part", surface = "box", projector = "centroid" }"#),
    ("plane/reflected", r#"{ type = "two_part", surface = "plane", projector = "reflected" }"#),
    ("object_linear", r#"{ type = "object_linear", s = [0.35, 0.0, 0.35, 0.5], t = [0.0, 0.5, 0.0, 0.5] }"#),
    ("eye_linear", r#"{ type = "eye_linear", s = [0.25, 0.0, 0.0, 0.5], t = [0.0, 0.25, 0.0, 0.5] }"#),
    ("sphere_map", r#"{ type = "sphere_map" }"#),
    (
        "triangle",
        r#"{ type = "triangle", points = [[-1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 1.0, 0.0]], uv = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]] }"#,
    ),
];

/// The view: the sphere on the left, the teapot (a placeholder until its mesh is put in) on the right.
const VIEW: &str = r#"
[camera]
eye = [0.0, 1.2, 6.0]
look_at = [0.0, 0.0, 0.0]
fov_y = 30.0
background = [0.05, 0.05, 0.07]

[[light]]
type = "ambient"
intensity = 0.35

[[light]]
type = "directional"
direction = [-0.4, -0.5, -1.0]
intensity = 0.8

[[object]]
shape = "sphere"
transform = { translate = [-1.35, 0.0, 0.0], rotate = [0.0, 30.0, 0.0] }
material = { color = [1.0, 1.0, 1.0], specular = 0.15, shininess = 30.0 }

[[object]]
shape = "sphere"
transform = { translate = [1.3, 0.1, 0.0], rotate = [0.0, 30.0, 0.0], scale = 1.3 }
material = { color = [1.0, 1.0, 1.0], specular = 0.15, shininess = 30.0 }
"#;

/// Newell's 32 patches, as scenes/teapot.toml holds them.
const TEAPOT: &str = include_str!("../../../scenes/teapot.toml");

pub fn run(args: &MappingsArgs) -> Result<()> {
    crate::set_threads(args.threads)?;
    crate::output::require_extension(&args.output, &["png"])?;
    sheet::check_columns(args.columns)?;
    let options = RenderOptions { width: args.width, height: args.height, spp: args.spp, ..RenderOptions::default() };
    options.validate()?;
    let mut scene = Scene::parse(VIEW, Path::new("."))?;
    scene.objects[1].shape =
        Shape::Mesh(vec![MeshPart { mesh: Arc::new(unit_teapot()?), material: 1, two_sided: true }]);
    let texture = Arc::new(FilteredTexture::new(&lettered_checkerboard(), TextureOptions::default()));

    let bar = sheet::progress("mappings", MAPPINGS.len());
    let mut panels = Vec::new();
    for (label, text) in MAPPINGS {
        bar.set_message(label);
        let mapping = parse_mapping_text(text)?;
        for material in &mut scene.materials {
            material.set_colour_texture(MappedTexture { texture: texture.clone(), mapping }, false);
        }
        panels.push(Panel { label: label.to_string(), pixels: render(&scene, &options)?.color });
        bar.inc(1);
    }
    bar.finish();
    let sheet = sheet::compose(&panels, args.width, args.height, args.columns);
    io::write_png_rgb8(&args.output, sheet.width, sheet.height, &sheet.pixels)
}

/// The teapot's patches tessellated into one mesh, centred on the origin and scaled to fit the cube
/// [-1, 1]^3, where the mappings' unit surfaces lie.
fn unit_teapot() -> Result<TriangleMesh> {
    let mut mesh = TriangleMesh::default();
    for (_, part) in Scene::parse(TEAPOT, Path::new("."))?.world_meshes(12)? {
        mesh.append(&part);
    }
    let (lo, hi) = mesh.bounds();
    let (centre, half) = ((lo + hi) * 0.5, ((hi - lo) * 0.5).max_element());
    mesh.positions.iter_mut().for_each(|p| *p = (*p - centre) / half);
    Ok(mesh)
}

/// 256 x 256 texels of 8 x 8 cells: hue by column, lightness by row, and each cell lettered with its
/// column (A to H, from s = 0) and row (1 to 8, from t = 0), so a panel shows where each part of the
/// texture lands and which way it faces.
fn lettered_checkerboard() -> Image<[f32; 4]> {
    const CELL: usize = 32;
    let hues: [[u8; 3]; 8] = [
        [214, 64, 52],
        [232, 150, 40],
        [222, 206, 60],
        [92, 176, 72],
        [48, 170, 170],
        [60, 112, 206],
        [128, 80, 196],
        [204, 76, 150],
    ];
    Image::from_fn(8 * CELL, 8 * CELL, |x, y| {
        let (column, row) = (x / CELL, 7 - y / CELL);
        let (cx, cy) = (x % CELL, y % CELL);
        let shade = if (column + row) % 2 == 0 { 1.0 } else { 0.55 };
        let label = [char::from(b'A' + column as u8), char::from(b'1' + row as u8)];
        // Two 8 x 8 glyphs at 1.5 times their size, centred in the cell.
        let (gx, gy) = ((cx as i32 - 4) * 2 / 3, (cy as i32 - 10) * 2 / 3);
        let ink = (0..16).contains(&gx)
            && (0..8).contains(&gy)
            && (glyph(label[gx as usize / 8])[gy as usize] >> (gx % 8)) & 1 == 1;
        let c = if ink { [0.02; 3] } else { hues[column].map(|v| srgb_to_linear(v as f32 / 255.0) * shade) };
        [c[0], c[1], c[2], 1.0]
    })
}
