//! What is painted: a scene file (one of its objects) or a model file placed in a scene of its own, the
//! scene as a TOML document (what saving rewrites), and the painted material: the channels of the atlas as a
//! `replace` layer on kd, ks and opacity and the height as Blinn's bump table, exactly as the saved scene
//! file declares them.

use crate::channels::{read_channel, Atlas, Channel};
use crate::surface_points::{texel_uv, SurfacePoints, GUTTER};
use glam::Vec3;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use wrinkle::bump::BumpSource;
use wrinkle::geometry::unwrap::{unwrap, UnwrapOptions, UnwrapReport};
use wrinkle::geometry::Shape;
use wrinkle::geometry::TriangleMesh;
use wrinkle::mapping::{MappedTexture, Projection};
use wrinkle::scene::write_obj;
use wrinkle::shade::{AlphaMode, Layer, Mode, Target};
use wrinkle::texture::Texture;
use wrinkle::{BumpMap, BumpTable, Error, FilteredTexture, Image, Mapping, Material, Result, Scene, TextureOptions};

/// The file a saved scene's unwrapped model is written to, beside it.
const MODEL_FILE: &str = "model.obj";
/// The widest angle between a chart's faces and its seed's normal: stretch at most 1 / cos 45 = 1.41.
const MAX_CHART_ANGLE: f32 = 45.0;
/// The bump scale of a new height channel, per unit of the object's bounding radius.
const HEIGHT_SCALE: f32 = 0.03;
/// The alpha test's cutoff on the painted opacity.
const ALPHA_CUTOFF: f32 = 0.5;

pub struct Model {
    pub scene: Scene,
    /// The painted object's index in the scene.
    pub object: usize,
    /// The materials it is drawn with (its own, or its mesh parts').
    materials: Vec<usize>,
    pub points: SurfacePoints,
    /// The scene file, rewritten on save.
    document: toml::Table,
    /// The folder the scene's relative file names resolve against.
    pub base: PathBuf,
    /// The model's file name without its extension (names the save folder).
    pub stem: String,
    /// F = `bump_scale` x height, object units.
    pub bump_scale: f32,
    /// The atlas laid out for a mesh without usable texture coordinates (saved as `model.obj`).
    pub unwrapped: Option<UnwrapReport>,
}

impl Model {
    /// Opens a scene file (`.toml`, painting object `object`) or a model file (OBJ, glTF, GLB), and the atlas
    /// it starts with: the channels a saved scene names, else the material's colour (and colour texture),
    /// specular, full opacity and a flat height.
    /// A mesh without texture coordinates, or any mesh with `new_atlas`, gets an atlas of its own
    /// (`wrinkle::geometry::unwrap`).
    pub fn open(path: &Path, object: usize, atlas_size: usize, new_atlas: bool) -> Result<(Model, Atlas)> {
        let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "model".into());
        let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
        let is_scene = crate::session::is_scene_file(path);
        let text = if is_scene {
            std::fs::read_to_string(path).map_err(|e| Error::read(path, e.to_string()))?
        } else {
            scene_for_model(&std::path::absolute(path).map_err(|e| Error::read(path, e.to_string()))?)
        };
        let document: toml::Table =
            text.parse().map_err(|e: toml::de::Error| Error::read(path, e.message().to_string()))?;
        let mut scene = if is_scene { Scene::load(path)? } else { Scene::parse(&text, &base)? };
        let count = scene.objects.len();
        let Some(target) = scene.objects.get(object) else {
            return Err(Error::parameter("object", format!("must be below the scene's {count} objects, got {object}")));
        };
        let materials = match &target.shape {
            Shape::Mesh(parts) => parts.iter().map(|p| p.material).collect(),
            Shape::Billboard(_) => {
                return Err(Error::parameter("object", "is a billboard, which turns to the camera: paint another"))
            }
            _ => vec![target.material],
        };
        let given = saved_channels(&document, object, &base)?;
        let size = match given.iter().find(|(c, _)| *c == Channel::Color) {
            Some((_, file)) => image_side(file)?.unwrap_or(atlas_size),
            None => atlas_size,
        };
        let unwrapped = lay_out_atlas(&mut scene.objects[object].shape, size, new_atlas)?;
        let target = &scene.objects[object];
        let points = SurfacePoints::of_primitives(&target.shape.primitives(), size)?;
        let (lo, hi) = points.bounds();
        let scale = target.transform.scale.abs().max_element();
        let bump_scale = saved_bump_scale(&document, object).unwrap_or(HEIGHT_SCALE * 0.5 * (hi - lo).length() * scale);
        let mut channels = Vec::new();
        for (channel, file) in &given {
            channels.push((*channel, read_channel(*channel, file, size)?));
        }
        let under = &scene.materials[materials[0]];
        if !given.iter().any(|(c, _)| *c == Channel::Color) {
            channels.push((Channel::Color, colour_start(under, size)));
        }
        let specular = under.phong.specular.clamp(0.0, 1.0);
        let mut atlas = Atlas::new(
            size,
            |c| match c {
                Channel::Color => under.color,
                Channel::Height => Vec3::splat(0.5),
                Channel::Specular => Vec3::splat(specular),
                Channel::Opacity => Vec3::ONE,
            },
            channels,
        );
        let mut model = Model { scene, object, materials, points, document, base, stem, bump_scale, unwrapped };
        model.install(&mut atlas)?;
        Ok((model, atlas))
    }

    /// Draws the painted object's materials with the atlas: each channel a `replace` layer (colour on kd,
    /// specular on ks, opacity on opacity, under the alpha test) and the height as the bump table.
    fn install(&mut self, atlas: &mut Atlas) -> Result<()> {
        let layers =
            [(Channel::Color, Target::Kd), (Channel::Specular, Target::Ks), (Channel::Opacity, Target::Opacity)].map(
                |(channel, target)| Layer {
                    source: MappedTexture { texture: atlas.texture(channel), mapping: Mapping::default() },
                    target,
                    mode: Mode::Replace,
                    rgba: false,
                },
            );
        let table = atlas.bump_table();
        for &m in &self.materials {
            let material: &mut Material = &mut self.scene.materials[m];
            material.layers = layers.to_vec();
            material.normal_map = None;
            material.bump = Some(BumpMap::new(BumpSource::Table(table.clone()), self.bump_scale)?);
            material.alpha_mode = AlphaMode::Mask { cutoff: ALPHA_CUTOFF };
        }
        Ok(())
    }

    /// Puts a channel's current texels into the painted materials.
    pub fn repaint(&mut self, atlas: &mut Atlas, channel: Channel) {
        let layer = match channel {
            Channel::Height => {
                // As for the textures below: the bumps let go of the table first, so it changes in place.
                let blank = Arc::new(BumpTable::new(&Image { width: 1, height: 1, pixels: vec![0.5] }));
                self.set_bump_tables(&blank);
                self.set_bump_tables(&atlas.bump_table());
                return;
            }
            Channel::Color => 0,
            Channel::Specular => 1,
            Channel::Opacity => 2,
        };
        // The layers let go of the channel's texture first, so that its levels are changed in place rather
        // than copied (`EditableTexture`).
        let blank: Arc<dyn Texture> = Arc::new(FilteredTexture::from_rgba8(
            &Image { width: 1, height: 1, pixels: vec![[0, 0, 0, 255]] },
            false,
            TextureOptions::default(),
        ));
        for &m in &self.materials {
            self.scene.materials[m].layers[layer].source.texture = blank.clone();
        }
        let texture = atlas.texture(channel);
        for &m in &self.materials {
            self.scene.materials[m].layers[layer].source.texture = texture.clone();
        }
    }

    fn set_bump_tables(&mut self, table: &Arc<BumpTable>) {
        for &m in &self.materials {
            if let Some(bump) = &mut self.scene.materials[m].bump {
                bump.source = BumpSource::Table(table.clone());
            }
        }
    }

    /// The object's place in the world.
    pub fn object_to_world(&self) -> glam::Affine3A {
        self.scene.objects[self.object].transform.matrix()
    }

    /// The scene file that renders the painted model: the original with the painted object's material
    /// reading the channels from `dir` (file names relative to it), and every other relative file name made
    /// absolute where `dir` is not the scene's folder.
    pub fn saved_document(&self, dir: &Path) -> String {
        let mut document = self.document.clone();
        if std::path::absolute(dir).ok() != std::path::absolute(&self.base).ok() {
            absolute_files(&mut document, &self.base);
        }
        let object = document
            .get_mut("object")
            .and_then(|o| o.as_array_mut())
            .and_then(|a| a.get_mut(self.object))
            .and_then(|o| o.as_table_mut())
            .expect("the document holds the painted object");
        if self.unwrapped.is_some() {
            object.insert("file".into(), MODEL_FILE.into());
        }
        let material = object.entry("material").or_insert(toml::Value::Table(toml::Table::new()));
        let material = material.as_table_mut().expect("a material is a table");
        if self.unwrapped.is_some() {
            // The saved model has no materials of its own: the file's exponent goes with the scene.
            let shininess = self.scene.materials[self.materials[0]].phong.shininess;
            material.insert("shininess".into(), toml::Value::Float(shininess as f64));
        }
        for field in ["texture", "filter", "specular_map", "layer", "bump", "normal_map", "alpha_mode", "alpha_cutoff"]
        {
            material.remove(field);
        }
        let layer = |channel: Channel, target: &str| {
            let mut texture = toml::Table::new();
            texture.insert("path".into(), channel.file_name().into());
            if !channel.is_colour() {
                texture.insert("srgb".into(), false.into());
            }
            let mut layer = toml::Table::new();
            layer.insert("texture".into(), texture.into());
            layer.insert("target".into(), target.into());
            layer.insert("mode".into(), "replace".into());
            toml::Value::Table(layer)
        };
        material.insert(
            "layer".into(),
            toml::Value::Array(vec![
                layer(Channel::Color, "kd"),
                layer(Channel::Specular, "ks"),
                layer(Channel::Opacity, "opacity"),
            ]),
        );
        let mut bump = toml::Table::new();
        bump.insert("map".into(), Channel::Height.file_name().into());
        bump.insert("scale".into(), toml::Value::Float(self.bump_scale as f64));
        material.insert("bump".into(), bump.into());
        material.insert("alpha_mode".into(), "mask".into());
        material.insert("alpha_cutoff".into(), toml::Value::Float(ALPHA_CUTOFF as f64));
        format!(
            "# Painted with `wrinkle paint`: the channels are the files beside this one (docs/paint.md).\n{}",
            toml::to_string(&document).expect("a TOML table serialises")
        )
    }
}

/// The painted meshes with their atlas's (u,v), as OBJ text (what a saved scene of an unwrapped model reads).
impl Model {
    pub fn unwrapped_obj(&self) -> Option<String> {
        self.unwrapped?;
        let Shape::Mesh(parts) = &self.scene.objects[self.object].shape else { return None };
        let meshes: Vec<(String, TriangleMesh)> =
            parts.iter().enumerate().map(|(k, p)| (format!("part_{k}"), (*p.mesh).clone())).collect();
        Some(write_obj(&meshes, "wrinkle paint (the painted model with its texture atlas)"))
    }
}

/// Gives a mesh without texture coordinates (or any mesh, with `always`) an atlas of its own, laid out for
/// a `size` x `size` image with gutters wider than two of the paint's: what it came to.
fn lay_out_atlas(shape: &mut Shape, size: usize, always: bool) -> Result<Option<UnwrapReport>> {
    let Shape::Mesh(parts) = shape else { return Ok(None) };
    if !always && parts.iter().all(|p| p.mesh.uvs(0).is_some()) {
        return Ok(None);
    }
    let meshes: Vec<&TriangleMesh> = parts.iter().map(|p| p.mesh.as_ref()).collect();
    let options = UnwrapOptions { size, gutter: 2 * GUTTER + 2, max_angle: MAX_CHART_ANGLE };
    let (laid_out, report) = unwrap(&meshes, options)?;
    for (part, mesh) in parts.iter_mut().zip(laid_out) {
        part.mesh = Arc::new(mesh);
    }
    Ok(Some(report))
}

/// A scene for a model file: the model at the origin, a key light and an ambient one (the camera is the
/// painter's orbit).
fn scene_for_model(model: &Path) -> String {
    let file = toml::Value::String(model.to_string_lossy().into_owned());
    format!(
        "[camera]\neye = [0.0, 0.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\nfov_y = 35.0\nbackground = [0.06, 0.06, 0.08]\n\n\
         [[light]]\ntype = \"directional\"\ndirection = [-0.4, -0.5, -1.0]\n\n\
         [[light]]\ntype = \"directional\"\ndirection = [0.6, 0.2, 0.5]\nintensity = 0.3\n\n\
         [[light]]\ntype = \"ambient\"\nintensity = 0.15\n\n\
         [[object]]\nshape = \"mesh\"\nfile = {file}\n"
    )
}

/// The painted object's material table in the document, where it has one.
fn material_of(document: &toml::Table, object: usize) -> Option<&toml::Table> {
    document.get("object")?.as_array()?.get(object)?.get("material")?.as_table()
}

/// The channel files a saved scene names: `replace` layers on kd, ks and opacity, and the bump's map, each
/// with the file name the channel is saved under.
fn saved_channels(document: &toml::Table, object: usize, base: &Path) -> Result<Vec<(Channel, PathBuf)>> {
    let Some(material) = material_of(document, object) else { return Ok(Vec::new()) };
    let mut found = Vec::new();
    let named = |path: &str, channel: Channel| Path::new(path).file_name().is_some_and(|n| *n == *channel.file_name());
    for layer in material.get("layer").and_then(|l| l.as_array()).into_iter().flatten() {
        let path = layer.get("texture").and_then(|t| t.get("path")).and_then(|p| p.as_str());
        let mode = layer.get("mode").and_then(|m| m.as_str());
        let target = layer.get("target").and_then(|t| t.as_str()).unwrap_or("kd");
        let channel = match target {
            "kd" => Channel::Color,
            "ks" => Channel::Specular,
            "opacity" => Channel::Opacity,
            _ => continue,
        };
        if let (Some(path), Some("replace")) = (path, mode) {
            if named(path, channel) {
                found.push((channel, base.join(path)));
            }
        }
    }
    if let Some(map) = material.get("bump").and_then(|b| b.get("map")).and_then(|m| m.as_str()) {
        if named(map, Channel::Height) {
            found.push((Channel::Height, base.join(map)));
        }
    }
    Ok(found)
}

fn saved_bump_scale(document: &toml::Table, object: usize) -> Option<f32> {
    let bump = material_of(document, object)?.get("bump")?;
    bump.get("map")?.as_str().filter(|m| m.ends_with(&Channel::Height.file_name()))?;
    Some(bump.get("scale")?.as_float()? as f32)
}

/// The side of a square image file; `None` where it is not square (the atlas then keeps its own size).
fn image_side(path: &Path) -> Result<Option<usize>> {
    let (w, h) = image::image_dimensions(path).map_err(|e| Error::read(path, e.to_string()))?;
    Ok((w == h).then_some(w as usize))
}

/// The colour channel of a new atlas: the material's colour, times its colour texture where it reads the
/// surface's own (u,v) through a uv transform (the nearest texel, repeating, at each atlas texel's centre).
fn colour_start(material: &Material, size: usize) -> Vec<u32> {
    let texture = material
        .colour_texture()
        .filter(|t| t.mapping.projection == Projection::Uv)
        .and_then(|t| Some((t.texture.image()?, t.mapping.transform)));
    (0..size * size)
        .map(|k| {
            let c = match texture {
                Some((image, transform)) => {
                    let (w, h) = image.size();
                    let (u, v) = texel_uv(k, size);
                    let st = transform.point(glam::Vec2::new(u, v));
                    let column = (st.x * w as f32).floor().rem_euclid(w as f32) as usize;
                    let from_bottom = (st.y * h as f32).floor().rem_euclid(h as f32) as usize;
                    material.color * image.texel(column.min(w - 1), from_bottom.min(h - 1)).truncate()
                }
                None => material.color,
            };
            Channel::Color.encode(c)
        })
        .collect()
}

/// Makes every string of the document that names a file relative to `base` absolute.
fn absolute_files(document: &mut toml::Table, base: &Path) {
    fn walk(value: &mut toml::Value, base: &Path) {
        match value {
            toml::Value::String(s) => {
                let p = Path::new(s.as_str());
                if p.is_relative() && base.join(p).is_file() {
                    if let Ok(abs) = std::path::absolute(base.join(p)) {
                        *s = abs.to_string_lossy().into_owned();
                    }
                }
            }
            toml::Value::Array(a) => a.iter_mut().for_each(|v| walk(v, base)),
            toml::Value::Table(t) => t.iter_mut().for_each(|(_, v)| walk(v, base)),
            _ => {}
        }
    }
    document.iter_mut().for_each(|(_, v)| walk(v, base));
}
