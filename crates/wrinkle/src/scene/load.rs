//! Reading a scene from TOML, field by field, with paths resolved against the scene file's folder.

use super::contain::contain_panics;
use super::environment::{parse_chrome, parse_environment};
use super::fields::{clip_backquoted, number_value, points, quoted, vec3_value, Fields};
use super::layer::{parse_alpha_mode, parse_layers};
use super::mapping::{parse_mapping, uv_list};
use super::procedural;
use super::texture::{load_texture, parse_normal_map, parse_texture, Role};
use super::{Animation, CameraDesc, Object, Scene};
use crate::bump::generators::{BrickParams, Generator, GridParams, RivetParams, TextParams};
use crate::bump::{
    BumpFilter, BumpFormula, BumpMap, BumpSource, BumpTable, Displacement, DisplacementMode, OffsetMap, Parallax,
    SlopeFilter,
};
use crate::geometry::billboard::{Align, Billboard};
use crate::geometry::{MeshPart, Shape, Surface, Transform};
use crate::image::io;
use crate::light::{Light, ShadowSettings};
use crate::mapping::polygon::QuadMapping;
use crate::mapping::{Projection as MapProjection, UvTransform};
use crate::procedural::solid::Space;
use crate::raster::Projection;
use crate::shade::{Layer, Material, Phong, Target};
use crate::texture::reconstruct::Kernel;
use crate::texture::{Filter, FilterOptions, FilteredTexture, TextureOptions, Wrap};
use crate::{Error, Result};
use glam::{Vec2, Vec3};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use toml::Value;

/// The embedded default scene: the cover logo of the 1978 proceedings.
pub const DEFAULT_SCENE: &str = include_str!("default.toml");

impl Scene {
    /// Reads and validates a scene file.
    pub fn load(path: &Path) -> Result<Scene> {
        let text = std::fs::read_to_string(path).map_err(|e| Error::read(path, io_message(&e)))?;
        let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
        Scene::parse(&text, &base).map_err(|e| match e {
            Error::Scene { path: field, message } if field.is_empty() => Error::read(path, message),
            other => other,
        })
    }

    /// The embedded default scene.
    pub fn default_scene() -> Scene {
        Scene::parse(DEFAULT_SCENE, Path::new(".")).expect("the embedded default scene is valid")
    }

    /// Parses scene text; relative file names resolve against `base`. An animated scene is its frame at
    /// time 0.
    pub fn parse(text: &str, base: &Path) -> Result<Scene> {
        let root: Value = toml::from_str::<toml::Table>(text).map(Value::Table).map_err(|e| toml_error(text, &e))?;
        match Animation::of(&root, base)? {
            Some(animation) => Arc::new(animation).scene_at(0.0),
            None => Scene::build(&root, base),
        }
    }

    /// The scene of a parsed document (its `[[animation]]` tables aside).
    pub(super) fn build(root: &Value, base: &Path) -> Result<Scene> {
        let top = Fields::new("", root, &["camera", "light", "object", "volume", "environment", "animation"])?;
        let camera = parse_camera(top.get("camera").ok_or_else(|| Error::scene("camera", "missing table [camera]"))?)?;
        let mut slides = Vec::new();
        let lights = top
            .tables("light")?
            .iter()
            .enumerate()
            .map(|(i, v)| parse_light(&format!("lights[{i}]"), v, base, &mut slides))
            .collect::<Result<Vec<_>>>()?;
        let (lights, shadows): (Vec<Light>, Vec<ShadowSettings>) = lights.into_iter().unzip();
        let mut objects = Vec::new();
        let mut materials = Vec::new();
        for (i, v) in top.tables("object")?.iter().enumerate() {
            objects.push(parse_object(&format!("objects[{i}]"), v, base, &mut materials)?);
        }
        let volumes = top
            .tables("volume")?
            .iter()
            .enumerate()
            .map(|(i, v)| procedural::parse_volume(&format!("volumes[{i}]"), v))
            .collect::<Result<Vec<_>>>()?;
        let environment = top.get("environment").map(|v| parse_environment(v, base)).transpose()?;
        if let (Some(i), None) = (lights.iter().position(|l| matches!(l, Light::Environment { .. })), &environment) {
            return Err(Error::scene(
                format!("lights[{i}].type"),
                "\"environment\" lights the scene with its [environment] map: add one",
            ));
        }
        Ok(Scene { camera, lights, shadows, objects, materials, volumes, environment, slides, animation: None })
    }
}

/// A TOML syntax error as one line with its position: `malformed TOML at line 3, column 8: invalid table header; expected `.`, `]``.
fn toml_error(text: &str, e: &toml::de::Error) -> Error {
    let message = e.message().lines().map(str::trim).filter(|l| !l.is_empty()).collect::<Vec<_>>().join("; ");
    let message = clip_backquoted(&message);
    let position = e.span().map(|span| {
        let before = &text[..span.start.min(text.len())];
        let line = before.matches('\n').count() + 1;
        let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
        format!(" at line {line}, column {column}")
    });
    Error::scene("", format!("malformed TOML{}: {message}", position.unwrap_or_default()))
}

fn io_message(e: &std::io::Error) -> String {
    match e.kind() {
        std::io::ErrorKind::NotFound => "no such file".into(),
        _ => e.to_string(),
    }
}

fn positive(x: f32) -> bool {
    x > 0.0
}

fn non_negative(x: f32) -> bool {
    x >= 0.0
}

fn parse_camera(v: &Value) -> Result<CameraDesc> {
    let f = Fields::new("camera", v, &["eye", "look_at", "up", "fov_y", "projection", "height", "background"])?;
    let eye = f.required("eye", f.vec3("eye")?)?;
    let look_at = f.required("look_at", f.vec3("look_at")?)?;
    let up = f.vec3("up")?.unwrap_or(Vec3::Y);
    let kind =
        f.choice("projection", "perspective", &[("perspective", "perspective"), ("orthographic", "orthographic")])?;
    let projection = if kind == "perspective" {
        if f.get("height").is_some() {
            return Err(Error::scene(f.at("height"), "only for projection = \"orthographic\""));
        }
        Projection::perspective(f.number_or("fov_y", 40.0)?)
    } else {
        if f.get("fov_y").is_some() {
            return Err(Error::scene(f.at("fov_y"), "only for projection = \"perspective\""));
        }
        Projection::orthographic(f.number_or("height", 2.0)?)
    };
    let background = f.vec3("background")?.unwrap_or(Vec3::ZERO);
    CameraDesc::new(eye, look_at, up, projection.map_err(|e| f.named(e))?, background).map_err(|e| f.named(e))
}

/// A colour: three non-negative numbers.
pub(super) fn colour(f: &Fields, key: &'static str, default: Vec3) -> Result<Vec3> {
    super::build::check_colour(key, f.vec3(key)?.unwrap_or(default)).map_err(|e| f.named(e))
}

/// A light and how it casts shadows; a spot light's slide is loaded onto `slides`.
fn parse_light(
    path: &str,
    v: &Value,
    base: &Path,
    slides: &mut Vec<FilteredTexture>,
) -> Result<(Light, ShadowSettings)> {
    let f = Fields::new(
        path,
        v,
        &[
            "type",
            "direction",
            "position",
            "color",
            "intensity",
            "angle",
            "falloff",
            "up",
            "texture",
            "shadow",
            "shadow_size",
            "shadow_bias",
        ],
    )?;
    let radiance = colour(&f, "color", Vec3::ONE)?
        * f.number_where("intensity", Some(1.0), non_negative, "a non-negative intensity")?;
    let kind = f.required("type", f.string("type")?)?;
    const SHADOW: [&str; 3] = ["shadow", "shadow_size", "shadow_bias"];
    let allowed: &[&str] = match kind {
        "directional" => &["direction", SHADOW[0], SHADOW[1], SHADOW[2]],
        "point" => &["position", SHADOW[0], SHADOW[1], SHADOW[2]],
        "spot" => &["position", "direction", "angle", "falloff", "up", "texture", SHADOW[0], SHADOW[1], SHADOW[2]],
        _ => &[],
    };
    f.only_of_kind(
        &["direction", "position", "angle", "falloff", "up", "texture", SHADOW[0], SHADOW[1], SHADOW[2]],
        allowed,
        &format!("lights of type {}", quoted(kind)),
    )?;
    let shadow = ShadowSettings {
        enabled: f.boolean("shadow", true)?,
        size: f.get("shadow_size").map(|_| f.integer_where("shadow_size", 0, 16, 8192)).transpose()?,
        bias: f.number_where("shadow_bias", Some(1.0), |b| (0.0..=100.0).contains(&b), "a bias scale from 0 to 100")?,
    };
    let direction = || -> Result<Vec3> { f.required("direction", f.vec3("direction")?) };
    let position = || -> Result<Vec3> { f.required("position", f.vec3("position")?) };
    let light = match kind {
        "directional" => Light::directional(direction()?, radiance),
        "point" => Light::point(position()?, radiance),
        "spot" => {
            let angle = f.number_or("angle", 30.0)?;
            let falloff = f.number_or("falloff", 5.0)?;
            let up = f.vec3("up")?.unwrap_or(Vec3::Y);
            let mut spot = Light::spot(position()?, direction()?, up, angle, falloff, radiance);
            if let (Ok(Light::Spot(spot)), Some(name)) = (&mut spot, f.string("texture")?) {
                let file = resolve(base, &f.at("texture"), name)?;
                let options = TextureOptions { wrap: [Wrap::Border; 2], ..TextureOptions::default() };
                slides.push(load_texture(&file, true, options)?.0);
                spot.slide = Some(slides.len() - 1);
            }
            spot
        }
        "ambient" => Light::ambient(radiance),
        "environment" => Ok(Light::Environment { radiance }),
        other => {
            return Err(Error::scene(
                f.at("type"),
                format!(
                    "expected one of \"directional\", \"point\", \"spot\", \"ambient\", \"environment\", got {}",
                    quoted(other)
                ),
            ))
        }
    };
    Ok((light.map_err(|e| f.named(e))?, shadow))
}

const SHAPE_FIELDS: &[&str] = &[
    "shape",
    "transform",
    "material",
    "file",
    "two_sided",
    "interp",
    "radius",
    "height",
    "major_radius",
    "minor_radius",
    "corners",
    "uv_corners",
    "points",
    "size",
    "width",
    "align",
    "axis",
];

/// An object, its material and (for a model file) its meshes' materials, pushed onto `materials`.
fn parse_object(path: &str, v: &Value, base: &Path, materials: &mut Vec<Material>) -> Result<Object> {
    let f = Fields::new(path, v, SHAPE_FIELDS)?;
    let kind = f.required("shape", f.string("shape")?)?;
    let transform = match f.get("transform") {
        Some(t) => parse_transform(&f.at("transform"), t)?,
        None => Transform::default(),
    };
    if kind == "mesh" {
        f.only_of_kind(&SHAPE_FIELDS[3..], &["file", "two_sided"], "shape \"mesh\"")?;
        let shape = parse_mesh(&f, base, materials)?;
        return Ok(Object { shape, transform, material: materials.len() - 1, affine: false });
    }
    let affine = f.choice("interp", false, &[("perspective", false), ("affine", true)])?;
    if let Some(key) = ["file", "two_sided"].into_iter().find(|k| f.get(k).is_some()) {
        return Err(Error::scene(f.at(key), "only for shape = \"mesh\""));
    }
    let allowed: &[&str] = match kind {
        "sphere" => &["radius"],
        "cylinder" => &["radius", "height"],
        "torus" => &["major_radius", "minor_radius"],
        "patch" => &["corners", "uv_corners"],
        "bicubic" => &["points"],
        "box" => &["size"],
        "billboard" => &["width", "height", "align", "axis"],
        other => {
            return Err(Error::scene(
                f.at("shape"),
                format!(
                    "unknown shape {} (expected one of sphere, cylinder, torus, patch, bicubic, box, mesh, billboard)",
                    quoted(other)
                ),
            ))
        }
    };
    f.only_of_kind(&SHAPE_FIELDS[6..], allowed, &format!("shape \"{kind}\""))?;
    let len = |key: &str, default: f32| f.number_or(key, default);
    let shape = match kind {
        "sphere" => Shape::Surface(Surface::Sphere { radius: len("radius", 1.0)? }),
        "cylinder" => Shape::Surface(Surface::Cylinder { radius: len("radius", 1.0)?, height: len("height", 2.0)? }),
        "torus" => {
            let major_radius = len("major_radius", 1.0)?;
            let minor_radius = len("minor_radius", 0.25)?;
            Shape::Surface(Surface::Torus { major_radius, minor_radius })
        }
        "patch" => {
            let v = f.required("corners", f.get("corners"))?;
            let c = points(&f.at("corners"), v, 4)?;
            Shape::Surface(Surface::Patch { corners: [c[0], c[1], c[2], c[3]] })
        }
        "billboard" => {
            if transform.rotate != Vec3::ZERO || transform.scale != Vec3::ONE {
                return Err(Error::scene(
                    f.at("transform"),
                    "a billboard turns towards the camera and takes its size from width and height: give it only translate",
                ));
            }
            let axis = f.vec3("axis")?.unwrap_or(Vec3::Y);
            let align = f.choice("align", Align::Screen, &Align::NAMES)?;
            if f.get("axis").is_some() && align == Align::Screen {
                return Err(Error::scene(f.at("axis"), "only for align = \"world\" or \"axis\""));
            }
            Shape::Billboard(Billboard { width: len("width", 1.0)?, height: len("height", 1.0)?, align, axis })
        }
        "bicubic" => {
            let v = f.required("points", f.get("points"))?;
            let p = points(&f.at("points"), v, 16)?;
            Shape::Surface(Surface::Bicubic { points: std::array::from_fn(|k| p[k]) })
        }
        _ => Shape::Box { size: f.vec3("size")?.unwrap_or(Vec3::ONE) },
    };
    let shape = shape.validated().map_err(|e| f.named(e))?;
    let mut material = match f.get("material") {
        Some(m) => parse_material(&f.at("material"), m, base, Material::default())?,
        None => Material::default(),
    };
    if let (Some(uv), Shape::Surface(Surface::Patch { corners })) = (f.get("uv_corners"), &shape) {
        quad_mapped(&mut material, *corners, &uv_list(&f.at("uv_corners"), uv, 4)?);
    }
    if material.reads_second_uv() {
        return Err(Error::scene(
            f.at("material"),
            format!("a mapping reads texture coordinate set 1, which only meshes carry (shape \"{kind}\")"),
        ));
    }
    materials.push(material);
    Ok(Object { shape, transform, material: materials.len() - 1, affine })
}

/// A patch's `uv_corners`: every texture the material reads through the patch's own (u,v) reads instead
/// the corners' texture coordinates, by inverse bilinear interpolation in the patch.
fn quad_mapped(material: &mut Material, corners: [Vec3; 4], uv: &[Vec2]) {
    let quad =
        MapProjection::Quad(QuadMapping { corners: corners.map(|c| c.as_dvec3()), uv: std::array::from_fn(|k| uv[k]) });
    for m in material.mappings_mut().filter(|m| m.projection == MapProjection::Uv) {
        m.projection = quad;
    }
}

/// A model file's meshes, each with the file's material under the fields of the scene's `material`.
fn parse_mesh(f: &Fields, base: &Path, materials: &mut Vec<Material>) -> Result<Shape> {
    let file = resolve(base, &f.at("file"), f.required("file", f.string("file")?)?)?;
    let two_sided = match f.get("two_sided") {
        Some(_) => Some(f.boolean("two_sided", true)?),
        None => None,
    };
    let mut parts = Vec::new();
    for part in super::model::load(&file)? {
        let material = match f.get("material") {
            Some(m) => parse_material(&f.at("material"), m, base, part.material)?,
            None => part.material,
        };
        let mut mesh = part.mesh;
        if material.reads_second_uv() && mesh.uvs(1).is_none() {
            return Err(Error::read(&file, "has no texture coordinate set 1 (TEXCOORD_1), which its material reads"));
        }
        // Normal maps need tangents, along the set the map is laid with; MikkTSpace makes them where the
        // file has none (contained: a third-party crate indexing out of bounds on a mesh it did not expect
        // is still one line).
        if let (Some(map), true) = (&material.normal_map, mesh.tangents.is_empty()) {
            let set = usize::from(matches!(map.texture.mapping.projection, MapProjection::SecondUv));
            let made = contain_panics(|| mesh.generate_tangents(set))
                .map_err(|why| Error::read(&file, format!("MikkTSpace failed on its triangles: {why}")))?;
            if !made {
                return Err(Error::read(&file, "has a normal map but no texture coordinates to lay it with"));
            }
        }
        materials.push(material);
        parts.push(MeshPart {
            mesh: Arc::new(mesh),
            material: materials.len() - 1,
            two_sided: two_sided.unwrap_or(part.two_sided),
        });
    }
    Ok(Shape::Mesh(parts))
}

pub(super) fn parse_transform(path: &str, v: &Value) -> Result<Transform> {
    let f = Fields::new(path, v, &["translate", "rotate", "scale"])?;
    let scale = match f.get("scale") {
        // A single number scales uniformly.
        Some(s @ (Value::Float(_) | Value::Integer(_))) => Vec3::splat(number_value(&f.at("scale"), s)?),
        Some(s) => vec3_value(&f.at("scale"), s)?,
        None => Vec3::ONE,
    };
    let translate = f.vec3("translate")?.unwrap_or(Vec3::ZERO);
    let rotate = f.vec3("rotate")?.unwrap_or(Vec3::ZERO);
    Transform { translate, rotate, scale }.validated().map_err(|e| f.named(e))
}

const MATERIAL_FIELDS: &[&str] = &[
    "color",
    "texture",
    "filter",
    "specular",
    "shininess",
    "bump",
    "normal_map",
    "specular_map",
    "layer",
    "opacity",
    "emission",
    "alpha_mode",
    "alpha_cutoff",
    "displacement",
    "reflect",
    "fresnel",
    "reflect_views",
    "chrome",
];

/// A material table; the fields it gives replace those of `under` (the default material, or the one a
/// model file gives its mesh). `texture` replaces the layers on kd, `specular_map` those on ks, and a
/// `layer` array all of them (after the scene's own `texture` and `specular_map`).
fn parse_material(path: &str, v: &Value, base: &Path, under: Material) -> Result<Material> {
    let f = Fields::new(path, v, MATERIAL_FIELDS)?;
    let mut material = Material { layers: Vec::new(), ..under };
    if f.get("layer").is_none() {
        material.layers = under.layers;
    }
    match f.get("texture") {
        Some(t) => {
            let source = parse_texture(&f.at("texture"), t, &f, base, Role::Colour)?;
            material.set_colour_texture(source.mapped, source.rgba);
        }
        None if f.get("filter").is_some() => return Err(Error::scene(f.at("filter"), "only with a texture")),
        None => {}
    }
    if let Some(t) = f.get("specular_map") {
        let source = parse_texture(&f.at("specular_map"), t, &f, base, Role::Data)?;
        material.layers.retain(|l| l.target != Target::Ks);
        material.layers.push(Layer::modulate(source.mapped, Target::Ks, source.rgba));
    }
    material.layers.extend(parse_layers(&f, base)?);
    match (f.get("bump"), f.get("normal_map")) {
        (Some(_), Some(_)) => return Err(Error::scene(f.at("normal_map"), "give bump or normal_map, not both")),
        (Some(b), None) => (material.bump, material.normal_map) = (Some(parse_bump(&f.at("bump"), b, base)?), None),
        (None, Some(n)) => {
            (material.bump, material.normal_map) = (None, Some(parse_normal_map(&f.at("normal_map"), n, &f, base)?))
        }
        (None, None) => {}
    }
    if let Some(d) = f.get("displacement") {
        material.displacement = Some(parse_displacement(&f.at("displacement"), d, base)?);
    }
    if material.displacement.is_some() {
        if material.normal_map.is_some() {
            return Err(Error::scene(f.at("displacement"), "a normal map over a displaced surface is not built: give a bump (its F is added to the displacement's) or neither"));
        }
        if material.bump.as_ref().is_some_and(|b| b.parallax.is_some()) {
            return Err(Error::scene(
                f.at("bump.parallax"),
                "marches a flat surface's height field: not with a displacement",
            ));
        }
    }
    material.color = colour(&f, "color", material.color)?;
    material.emission = colour(&f, "emission", material.emission)?;
    material.opacity =
        f.number_where("opacity", Some(material.opacity), |x| (0.0..=1.0).contains(&x), "a number from 0 to 1")?;
    material.phong = Phong::new(
        f.number_where("specular", Some(material.phong.specular), non_negative, "a non-negative number")?,
        f.number_where("shininess", Some(material.phong.shininess), positive, "a positive exponent")?,
    );
    material.reflect = colour(&f, "reflect", material.reflect)?;
    material.fresnel = f.boolean("fresnel", material.fresnel)?;
    material.reflect_views = f.integer_where("reflect_views", material.reflect_views, 0, 4096)?;
    if material.reflect_views > 0 && !material.reflects() {
        return Err(Error::scene(
            f.at("reflect_views"),
            "mirrors the scene for a material that reflects: give reflect too",
        ));
    }
    if let Some(c) = f.get("chrome") {
        material.chrome = Some(parse_chrome(&f.at("chrome"), c, base)?);
    }
    material.alpha_mode = parse_alpha_mode(&f, material.alpha_mode)?;
    Ok(material)
}

/// The file a scene's file field (at `field`) names, resolved against the scene file's folder `base`. An
/// empty name (which would name the folder) and one longer than any path the system takes are errors.
pub(super) fn resolve(base: &Path, field: &str, name: &str) -> Result<PathBuf> {
    if name.is_empty() {
        return Err(Error::scene(field, "empty file name"));
    }
    if name.len() > LONGEST_PATH {
        return Err(Error::scene(
            field,
            format!("file name {} is longer than any path ({LONGEST_PATH} bytes)", quoted(name)),
        ));
    }
    let p = Path::new(name);
    Ok(if p.is_absolute() { p.to_path_buf() } else { base.join(p) })
}

/// The longest path Linux takes (PATH_MAX).
const LONGEST_PATH: usize = 4096;

/// The placement of a texture or bump table in (u,v): `repeat` (a positive count per axis, default
/// [1, 1]), then `rotate` (degrees counter-clockwise), then `offset`.
pub(super) fn uv_transform(f: &Fields) -> Result<UvTransform> {
    let r = f.vec2("repeat")?.unwrap_or(Vec2::ONE);
    if r.min_element() <= 0.0 {
        return Err(Error::scene(f.at("repeat"), format!("expected positive counts, got [{}, {}]", r.x, r.y)));
    }
    let offset = f.vec2("offset")?.unwrap_or(Vec2::ZERO);
    Ok(UvTransform::new(offset, f.number_or("rotate", 0.0)?, r))
}

/// The fields of a bump table that say what F is and where it lies (a displacement's too).
const BUMP_SOURCE_FIELDS: &[&str] =
    &["map", "generator", "procedural", "scale", "repeat", "offset", "rotate", "mapping", "interp", "filter"];

/// What a bump adds to its source: offset maps, the formula and parallax.
const BUMP_ONLY_FIELDS: &[&str] = &["offsets", "invariant", "formula", "parallax"];

/// What a displacement adds to the source of its F.
const DISPLACEMENT_FIELDS: &[&str] = &["mode", "threshold", "edge_px"];

fn parse_bump(path: &str, v: &Value, base: &Path) -> Result<BumpMap> {
    let f = Fields::new(path, v, &[BUMP_SOURCE_FIELDS, BUMP_ONLY_FIELDS].concat())?;
    // A table's image, the procedural pattern's fields, or an offset map's file.
    enum Source<'a> {
        Image(crate::image::GreyImage),
        Procedural(&'a Value),
        Offsets(PathBuf),
    }
    let given: Vec<&str> =
        ["map", "generator", "procedural", "offsets"].into_iter().filter(|k| f.get(k).is_some()).collect();
    let image = match given[..] {
        [] => return Err(Error::scene(f.at("map"), "missing field (or give a generator, procedural or offsets)")),
        [_, second, ..] => return Err(Error::scene(f.at(second), "give one of map, generator, procedural, offsets")),
        [one] => match one {
            "map" => Source::Image(io::load_grey(&resolve(base, &f.at(one), f.required(one, f.string(one)?)?)?)?),
            "generator" => Source::Image(parse_generator(&f.at(one), &v[one])?),
            "procedural" => Source::Procedural(&v[one]),
            _ => Source::Offsets(resolve(base, &f.at(one), f.required(one, f.string(one)?)?)?),
        },
    };
    let invariant = f.boolean("invariant", false)?;
    let full = f.choice("formula", false, &[("blinn", false), ("full", true)])?;
    let formula = match (full, invariant) {
        (false, false) => BumpFormula::Blinn,
        (false, true) => BumpFormula::Invariant,
        (true, false) => BumpFormula::Full,
        (true, true) => return Err(Error::scene(f.at("invariant"), "applies to formula = \"blinn\" only")),
    };
    let source = match image {
        Source::Image(image) => BumpSource::Table(Arc::new(BumpTable::new(&image))),
        Source::Procedural(p) => {
            let pattern = procedural::parse_bump(&f.at("procedural"), p)?;
            // A pattern has its gradient, not a table to read or filter (only the spread of its normals:
            // filter = "lean" or "toksvig"); a solid one no (u,v) to place.
            if f.get("interp").is_some() {
                return Err(Error::scene(f.at("interp"), "applies to bump tables (map or generator) only"));
            }
            if let Some(name) = f.string("filter")?.filter(|n| !["lean", "toksvig"].contains(n)) {
                return Err(Error::scene(
                    f.at("filter"),
                    format!(
                        "a procedural bump filters its own octaves: only \"lean\" or \"toksvig\" apply, got \"{name}\""
                    ),
                ));
            }
            let placed = ["repeat", "offset", "rotate", "mapping"];
            if let Some(key) = placed.into_iter().find(|k| pattern.space == Space::Object && f.get(k).is_some()) {
                return Err(Error::scene(f.at(key), "applies to tables and space = \"uv\" patterns only"));
            }
            BumpSource::Procedural(Arc::new(pattern))
        }
        Source::Offsets(file) => {
            if formula == BumpFormula::Full {
                return Err(Error::scene(f.at("formula"), "an offset map stores Fu and Fv, not F: use \"blinn\""));
            }
            let filter = FilterOptions { filter: bump_filter(&f)?.texture, ..FilterOptions::default() };
            let (texture, _) = load_texture(&file, false, TextureOptions { filter, ..TextureOptions::default() })?;
            BumpSource::Offsets(Arc::new(OffsetMap::new(texture)))
        }
    };
    let parallax = match f.get("parallax") {
        Some(p) => {
            if !matches!(source, BumpSource::Table(_)) {
                return Err(Error::scene(f.at("parallax"), "marches a height table (map or generator) only"));
            }
            Some(parse_parallax(&f.at("parallax"), p)?)
        }
        None => None,
    };
    let chosen = bump_filter(&f)?;
    Ok(BumpMap {
        mapping: parse_mapping(&f.at("mapping"), f.get("mapping"), uv_transform(&f)?)?,
        formula,
        filter: FilterOptions { filter: chosen.texture, ..FilterOptions::default() },
        slopes: chosen.slopes,
        parallax,
        ..BumpMap::new(source, f.number_or("scale", 0.05)?).map_err(|e| f.named(e))?
    })
}

/// `displacement = { map | generator | procedural, scale, repeat, ..., mode = "full" | "silhouette",
/// threshold, edge_px }`: F as a bump's, the surface moved by it, shaded with the full formula.
fn parse_displacement(path: &str, v: &Value, base: &Path) -> Result<Displacement> {
    let f = Fields::new(path, v, &[BUMP_SOURCE_FIELDS, DISPLACEMENT_FIELDS].concat())?;
    let mut source = v.as_table().expect("Fields::new checked it is a table").clone();
    for key in DISPLACEMENT_FIELDS {
        source.remove(*key);
    }
    let mut map = parse_bump(path, &Value::Table(source), base)?;
    if map.slopes != SlopeFilter::Plain {
        // The displaced surface has its own normals: there is no spread of bump normals to filter.
        return Err(Error::scene(f.at("filter"), "LEAN and Toksvig filter bumps, not displacements"));
    }
    map.formula = BumpFormula::Full;
    let silhouette = f.choice("mode", false, &[("full", false), ("silhouette", true)])?;
    let in_unit = |x: f32| x > 0.0 && x <= 1.0;
    let mode = match silhouette {
        true => DisplacementMode::Silhouette {
            threshold: match f.get("threshold") {
                Some(_) => Some(f.number_where("threshold", None, in_unit, "a number above 0, at most 1")?),
                None => None,
            },
        },
        false if f.get("threshold").is_some() => {
            return Err(Error::scene(f.at("threshold"), "applies to mode = \"silhouette\" only"))
        }
        false => DisplacementMode::Full,
    };
    let (finest, coarsest) = Displacement::EDGE_PX;
    let edge_px = f.number_or("edge_px", 1.0)?;
    if !(finest..=coarsest).contains(&edge_px) {
        return Err(Error::scene(
            f.at("edge_px"),
            format!("expected pixels from {finest} to {coarsest}, got {edge_px}"),
        ));
    }
    Ok(Displacement { map, mode, edge_px })
}

/// `parallax = { steps = 32, depth_replace = false }`: the march of parallax occlusion mapping.
fn parse_parallax(path: &str, v: &Value) -> Result<Parallax> {
    let f = Fields::new(path, v, &["steps", "depth_replace"])?;
    let steps = f.integer_where("steps", 32, 1, Parallax::MAX_STEPS as usize)? as u32;
    Ok(Parallax { steps, depth_replace: f.boolean("depth_replace", false)? })
}

/// A bump table's filter: `filter` names any bump filter (`BumpFilter::parse`): `"none"` (the
/// full-resolution table read as `interp` says: Blinn's nearest or bilinear FVAL), `"mip"` (another name of
/// `"trilinear"`, Blinn's MIP-mapped table of section 5), a texture filter, or LEAN and Toksvig filtering
/// of the normals. `interp` belongs to `"none"` alone: every MIP filter reads its levels bilinearly.
fn bump_filter(f: &Fields) -> Result<BumpFilter> {
    let kernels = [("nearest", Kernel::Nearest), ("bilinear", Kernel::Bilinear)];
    match (f.string("filter")?, f.get("interp")) {
        (None | Some("none"), _) => Ok(BumpFilter {
            texture: Filter::Reconstruct(f.choice("interp", Kernel::Bilinear, &kernels)?),
            slopes: SlopeFilter::Plain,
        }),
        (Some(_), Some(_)) => Err(Error::scene(f.at("interp"), "applies to filter = \"none\" only")),
        (Some(name), None) => BumpFilter::parse(name).ok_or_else(|| {
            Error::scene(f.at("filter"), format!("expected one of {}, got \"{name}\"", BumpFilter::names()))
        }),
    }
}

/// The fields of a generator table: its kind, its size, then the parameters of every kind.
const GENERATOR_FIELDS: &[&str] = &[
    "kind",
    "size",
    "cells",
    "line_width",
    "soft",
    "text",
    "count",
    "radius",
    "rows",
    "bricks_per_row",
    "mortar",
    "bevel",
];

fn parse_generator(path: &str, v: &Value) -> Result<crate::image::GreyImage> {
    let f = Fields::new(path, v, GENERATOR_FIELDS)?;
    let size = f.integer_where("size", 256, 1, 8192)?;
    let kind = f.required("kind", f.string("kind")?)?;
    let own: &[&str] = match kind {
        "grid" => &["cells", "line_width", "soft"],
        "text" => &["text", "soft"],
        "rivets" => &["count", "radius"],
        "bricks" => &["rows", "bricks_per_row", "mortar", "bevel"],
        _ => &[],
    };
    if !own.is_empty() {
        f.only_of_kind(&GENERATOR_FIELDS[2..], own, &format!("generator kind \"{kind}\""))?;
    }
    let fraction = |x: f32| (0.0..=1.0).contains(&x);
    let generator = match kind {
        "grid" => {
            let d = GridParams::default();
            Generator::Grid(GridParams {
                cells: f.integer_where("cells", d.cells, 1, 4096)?,
                line_width: f.number_where(
                    "line_width",
                    Some(d.line_width),
                    fraction,
                    "a fraction of a cell from 0 to 1",
                )?,
                soft: f.number_where("soft", Some(d.soft), fraction, "a fraction of a cell from 0 to 1")?,
            })
        }
        "text" => {
            let d = TextParams::default();
            let text = f.string("text")?.map(str::to_string).unwrap_or(d.text);
            Generator::Text(TextParams {
                text,
                soft: f.number_where("soft", Some(d.soft), fraction, "a fraction from 0 to 1")?,
            })
        }
        "rivets" => {
            let d = RivetParams::default();
            Generator::Rivets(RivetParams {
                count: f.integer_where("count", d.count, 1, 4096)?,
                radius: f.number_where(
                    "radius",
                    Some(d.radius),
                    |r| r > 0.0 && r <= 0.5,
                    "a radius from 0 to 0.5 cells",
                )?,
            })
        }
        "bricks" => {
            let d = BrickParams::default();
            Generator::Bricks(BrickParams {
                rows: f.integer_where("rows", d.rows, 1, 4096)?,
                bricks_per_row: f.integer_where("bricks_per_row", d.bricks_per_row, 1, 4096)?,
                mortar: f.number_where("mortar", Some(d.mortar), fraction, "a fraction from 0 to 1")?,
                bevel: f.number_where("bevel", Some(d.bevel), fraction, "a fraction from 0 to 1")?,
            })
        }
        other => {
            return Err(Error::scene(
                f.at("kind"),
                format!("expected one of \"grid\", \"text\", \"rivets\", \"bricks\", got {}", quoted(other)),
            ))
        }
    };
    // The generators name their parameters by the fields' own names.
    generator.generate(size).map_err(|e| f.named(e))
}
