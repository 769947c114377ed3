//! The colour texture of a material: `texture = "file.png"` (with `filter = "..."` beside it in the
//! material) or `texture = { path, filter, wrap, border, srgb, repeat, offset, rotate, mipmap, level,
//! max_aniso }`.

use super::fields::{describe, numbers, Fields};
use super::load::{resolve, uv_transform};
use super::mapping::parse_mapping;
use crate::bump::normal_map::Convention;
use crate::bump::{BumpFilter, SlopeFilter, TangentNormalMap};
use crate::image::color::decode_rgba8;
use crate::image::levels::{check_chain, sizes};
use crate::image::{indexed, io};
use crate::limits;
use crate::mapping::{MappedTexture, Mapping};
use crate::texture::colour_table::{IndexedTexture, LutTexture};
use crate::texture::reconstruct::Kernel;
use crate::texture::{Filter, FilterOptions, FilteredTexture, LevelRule, MipFilter, Texture, TextureOptions, Wrap};
use crate::{Error, Result};
use glam::Vec4;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use toml::Value;

const TEXTURE_FIELDS: &[&str] = &[
    "path",
    "filter",
    "wrap",
    "border",
    "srgb",
    "repeat",
    "offset",
    "rotate",
    "mapping",
    "mipmap",
    "level",
    "max_aniso",
    "lod_bias",
    "indexed",
    "palette",
    "lut",
    "levels",
];
/// A normal map's fields beside the texture's.
const NORMAL_MAP_FIELDS: &[&str] = &["strength", "convention"];

/// What a texture is for: a colour is decoded from sRGB unless `srgb = false`; data (specular, normal
/// maps) are read as stored unless `srgb = true`.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Role {
    Colour,
    Data,
}

/// A texture as a layer reads it: through its mapping, and whether it has an alpha channel.
pub struct Source {
    pub mapped: MappedTexture,
    /// OpenGL's RGBA base format (the file has alpha) rather than RGB; procedural patterns are RGB.
    pub rgba: bool,
}

/// The texture at `path` (the material's `texture` field, a layer's, or a data map's); `material` is the
/// table beside it (the material or the layer), whose `filter` applies to the short form.
pub fn parse_texture(path: &str, v: &Value, material: &Fields, base: &Path, role: Role) -> Result<Source> {
    parse_texture_with(path, v, material, base, role, &[])
}

/// A tangent-space normal map: a data texture with `strength` (default 1, glTF's scale) and `convention`
/// (`"opengl"`, the default: green up the picture, or `"directx"`).
pub fn parse_normal_map(path: &str, v: &Value, material: &Fields, base: &Path) -> Result<TangentNormalMap> {
    // `filter = "lean"` (or "toksvig", "lean:FILTER", ...): the texture filter, and the normals' spread.
    let mut v = v.clone();
    let mut slopes = SlopeFilter::Plain;
    if let Some(Value::String(name)) = v.get("filter").cloned() {
        if let Some(chosen) = BumpFilter::parse(&name).filter(|c| c.slopes != SlopeFilter::Plain) {
            slopes = chosen.slopes;
            let table = v.as_table_mut().expect("a table has a filter field");
            table.insert("filter".into(), Value::String(chosen.texture.name().to_string()));
        }
    }
    let v = &v;
    let texture = parse_texture_with(path, v, material, base, Role::Data, NORMAL_MAP_FIELDS)?.mapped;
    let (strength, convention) = match v {
        Value::Table(_) => {
            let f = Fields::new(path, v, &[TEXTURE_FIELDS, NORMAL_MAP_FIELDS].concat())?;
            let finite = |x: f32| x.is_finite();
            let conventions = [("opengl", Convention::OpenGl), ("directx", Convention::DirectX)];
            (
                f.number_where("strength", Some(1.0), finite, "a finite number")?,
                f.choice("convention", Convention::OpenGl, &conventions)?,
            )
        }
        _ => (1.0, Convention::OpenGl),
    };
    let mut map = TangentNormalMap::new(texture, strength, convention);
    map.slopes = slopes;
    Ok(map)
}

fn parse_texture_with(
    path: &str,
    v: &Value,
    material: &Fields,
    base: &Path,
    role: Role,
    extra: &[&str],
) -> Result<Source> {
    if super::procedural::is_procedural(v) {
        if role == Role::Colour && material.get("filter").is_some() {
            // Patterns are band-limited to the footprint by their own sums, not filtered.
            return Err(Error::scene(material.at("filter"), "applies to image textures only, not to a procedural one"));
        }
        let texture = Arc::new(super::procedural::parse_texture(path, v)?);
        return Ok(Source { mapped: MappedTexture { texture, mapping: Mapping::default() }, rgba: false });
    }
    let beside = match role {
        Role::Colour => material.choice("filter", None, &filter_choices())?,
        Role::Data => None,
    };
    let srgb_default = role == Role::Colour;
    let (file, file_field, options, srgb, mapping, levels) = match v {
        Value::String(s) => {
            let filter = FilterOptions { filter: beside.unwrap_or(Filter::Trilinear), ..FilterOptions::default() };
            let options = TextureOptions { filter, ..TextureOptions::default() };
            (s.as_str(), path.to_string(), options, srgb_default, Mapping::default(), Vec::new())
        }
        _ => {
            let f = Fields::new(path, v, &[TEXTURE_FIELDS, extra].concat())?;
            if beside.is_some() && f.get("filter").is_some() {
                return Err(Error::scene(
                    material.at("filter"),
                    format!("given twice: here and in {}", f.at("filter")),
                ));
            }
            let file = f.required("path", f.string("path")?)?;
            let filter = FilterOptions {
                filter: f.choice("filter", beside, &filter_choices())?.unwrap_or(Filter::Trilinear),
                level_rule: f.choice(
                    "level",
                    LevelRule::Longest,
                    &[("longest", LevelRule::Longest), ("area", LevelRule::Area)],
                )?,
                max_aniso: f.number_where(
                    "max_aniso",
                    Some(16.0),
                    |x| (1.0..=64.0).contains(&x),
                    "a ratio from 1 to 64",
                )?,
                ..FilterOptions::default()
            };
            let wrap = wrap(&f)?;
            let options = TextureOptions {
                wrap,
                border: border(&f, wrap)?,
                mip_filter: f.choice("mipmap", MipFilter::Box, &MipFilter::NAMES)?,
                filter,
                lod_bias: lod_bias(&f)?,
            };
            let mapping = parse_mapping(&f.at("mapping"), f.get("mapping"), uv_transform(&f)?)?;
            let srgb = f.boolean("srgb", srgb_default)?;
            let path = resolve(base, &f.at("path"), file)?;
            if let Some(source) = colour_table(&f, &path, base, srgb, &options, &mapping)? {
                if f.get("levels").is_some() {
                    return Err(Error::scene(f.at("levels"), "applies to image textures, not to colour tables"));
                }
                return Ok(source);
            }
            (file, f.at("path"), options, srgb, mapping, level_files(&f, base)?)
        }
    };
    let path = resolve(base, &file_field, file)?;
    let (texture, rgba) = load_texture_levels(&path, &levels, srgb, options)?;
    Ok(Source { mapped: MappedTexture { texture: Arc::new(texture), mapping }, rgba })
}

/// `levels = ["level1.png", "level2.png", ...]`: the texture's levels 1, 2, ... as files.
fn level_files(f: &Fields, base: &Path) -> Result<Vec<PathBuf>> {
    let Some(v) = f.get("levels") else { return Ok(Vec::new()) };
    let names = v.as_array().filter(|a| !a.is_empty()).ok_or_else(|| {
        Error::scene(f.at("levels"), format!("expected a list of file names (level 1 first), got {}", describe(v)))
    })?;
    names
        .iter()
        .enumerate()
        .map(|(k, name)| {
            let at = format!("{}[{k}]", f.at("levels"));
            let name = name
                .as_str()
                .ok_or_else(|| Error::scene(&at, format!("expected a file name, got {}", describe(name))))?;
            resolve(base, &at, name)
        })
        .collect()
}

/// A colour table texture, where the table asks for one: `indexed = true` or a `palette` file (indices
/// looked up by nearest index in the file's own palette or the given one), or a `lut` file (the image
/// filtered as an intensity, then mapped through the LUT's first row). The colours of a palette or LUT are
/// decoded from sRGB with `srgb`; the texture is RGBA when one of them is not opaque.
fn colour_table(
    f: &Fields,
    path: &Path,
    base: &Path,
    srgb: bool,
    options: &TextureOptions,
    mapping: &Mapping,
) -> Result<Option<Source>> {
    let decode = |entries: &[[u8; 4]]| decode_rgba8(entries, srgb).into_iter().map(Vec4::from).collect();
    let opaque = |entries: &[[u8; 4]]| entries.iter().all(|c| c[3] == 255);
    let indexed = f.boolean("indexed", false)? || f.get("palette").is_some();
    let (texture, rgba): (Arc<dyn Texture>, bool) = match (indexed, f.get("lut")) {
        (true, Some(_)) => {
            return Err(Error::scene(f.at("lut"), "give an indexed texture (indexed, palette) or a lut, not both"))
        }
        (true, None) => {
            if options.filter.filter != Filter::Reconstruct(Kernel::Nearest) && f.get("filter").is_some() {
                return Err(Error::scene(
                    f.at("filter"),
                    "an indexed texture is looked up by nearest index: filter = \"nearest\" or none",
                ));
            }
            let image = indexed::load_indices(path)?;
            let palette = match f.get("palette") {
                Some(_) => {
                    let name =
                        f.string("palette")?.ok_or_else(|| Error::scene(f.at("palette"), "expected a file name"))?;
                    indexed::load_palette(&resolve(base, &f.at("palette"), name)?)?
                }
                None => image
                    .palette
                    .ok_or_else(|| Error::read(path, "has no palette (grey indices): give palette = \"file\""))?,
            };
            let texture = IndexedTexture::new(image.indices, decode(&palette), options.wrap, options.border)
                .map_err(|m| Error::read(path, m))?;
            (Arc::new(texture), !opaque(&palette))
        }
        (false, Some(_)) => {
            let name = f.string("lut")?.ok_or_else(|| Error::scene(f.at("lut"), "expected a file name"))?;
            let lut_path = resolve(base, &f.at("lut"), name)?;
            let lut = io::load_rgba8(&lut_path)?;
            let row = &lut.pixels[..lut.width];
            // The intensity is data, filtered as the texture's options say.
            let (intensity, _) = load_texture(path, false, *options)?;
            (Arc::new(LutTexture::new(Arc::new(intensity), decode(row))), !opaque(row))
        }
        (false, None) => return Ok(None),
    };
    Ok(Some(Source { mapped: MappedTexture { texture, mapping: *mapping }, rgba }))
}

/// An image file as a filtered texture, and whether the file has an alpha channel.
pub fn load_texture(file: &Path, srgb: bool, options: TextureOptions) -> Result<(FilteredTexture, bool)> {
    load_texture_levels(file, &[], srgb, options)
}

/// `load_texture` with its levels 1, 2, ... from `level_files` (as `glTexImage2D` takes a level each), or
/// from the file itself where it is MIP-mapped (maketx's tiled TIFF, an OpenEXR MIPMAP or RIPMAP): those
/// levels are used, not rebuilt, and the pyramid is completed from the last one.
pub fn load_texture_levels(
    file: &Path,
    level_files: &[PathBuf],
    srgb: bool,
    options: TextureOptions,
) -> Result<(FilteredTexture, bool)> {
    let io::TextureFile { texels, mut alpha, mut levels } = io::load_texture_file(file, srgb)?;
    if !levels.is_empty() && !level_files.is_empty() {
        return Err(Error::read(file, "is MIP-mapped already: give its levels or the file's own, not both"));
    }
    for level in level_files {
        let given = io::load_texture_file(level, srgb)?;
        if !given.levels.is_empty() {
            return Err(Error::read(level, "a level given on its own must be one image, not MIP-mapped"));
        }
        alpha |= given.alpha;
        levels.push(given.texels.into_linear(srgb));
    }
    if !levels.is_empty() {
        levels.insert(0, texels.into_linear(srgb));
        check_chain(file, &sizes(&levels))?;
        let texels: usize = levels.iter().map(|l| l.width * l.height).sum();
        limits::reserve(texels as u64 * 32, || format!("{}: its {} given levels", file.display(), levels.len()))?;
        return Ok((FilteredTexture::from_levels(&levels, options), alpha));
    }
    let (width, height, bytes8) = match &texels {
        io::Texels::Rgba8(image) => (image.width, image.height, true),
        io::Texels::Linear(image) => (image.width, image.height, false),
    };
    // The pyramid (built in f32 for 8-bit texels too, 4/3 of the base), and what the filter builds on first
    // use beside it: a ripmap (4 times the base) or a summed-area table (four f64 sums a texel).
    let per_texel: u64 = match options.filter.filter {
        Filter::Ripmap => 16 * 4,
        Filter::Sat => 32,
        _ => 0,
    } + if bytes8 { 16 * 4 / 3 + 4 * 4 / 3 } else { 16 * 4 / 3 };
    limits::reserve((width * height) as u64 * per_texel, || {
        format!("{}: a {width}x{height} texture with its {} filter", file.display(), options.filter.filter.name())
    })?;
    let texture = match texels {
        io::Texels::Rgba8(image) => FilteredTexture::from_rgba8(&image, srgb, options),
        io::Texels::Linear(image) => FilteredTexture::new(&image, options),
    };
    Ok((texture, alpha))
}

fn filter_choices() -> Vec<(&'static str, Option<Filter>)> {
    Filter::ALL.iter().map(|&(n, f)| (n, Some(f))).collect()
}

/// One mode for both axes, or `[u, v]`.
fn wrap(f: &Fields) -> Result<[Wrap; 2]> {
    let names = || Wrap::NAMES.iter().map(|(n, _)| format!("\"{n}\"")).collect::<Vec<_>>().join(", ");
    let one = |v: &Value| -> Result<Wrap> {
        v.as_str().and_then(Wrap::parse).ok_or_else(|| {
            let got = describe(v);
            Error::scene(f.at("wrap"), format!("expected one of {} (or two of them as [u, v]), got {got}", names()))
        })
    };
    match f.get("wrap") {
        None => Ok([Wrap::Repeat; 2]),
        Some(Value::Array(a)) if a.len() == 2 => Ok([one(&a[0])?, one(&a[1])?]),
        Some(v) => one(v).map(|w| [w; 2]),
    }
}

/// The level-of-detail bias, in levels: from -4 to 4 (a factor of 16 in the footprint either way).
fn lod_bias(f: &Fields) -> Result<f32> {
    f.number_where("lod_bias", Some(0.0), |x| (-4.0..=4.0).contains(&x), "a number of levels from -4 to 4")
}

/// The border colour, linear RGB or RGBA (alpha 1 when left out), components in [0, 1]; only where an axis
/// wraps to the border.
fn border(f: &Fields, wrap: [Wrap; 2]) -> Result<Vec4> {
    let Some(v) = f.get("border") else { return Ok(Vec4::ZERO) };
    if !wrap.contains(&Wrap::Border) {
        return Err(Error::scene(f.at("border"), "applies to wrap = \"border\" only"));
    }
    let n = v.as_array().map_or(0, |a| a.len());
    let c = numbers(&f.at("border"), v, if n == 4 { 4 } else { 3 })?;
    if c.iter().any(|x| !(0.0..=1.0).contains(x)) {
        return Err(Error::scene(f.at("border"), "expected components between 0 and 1"));
    }
    Ok(Vec4::new(c[0], c[1], c[2], if n == 4 { c[3] } else { 1.0 }))
}

impl crate::Scene {
    /// Every layer's texture that has a choice of filters takes `filter` (`--filter` overriding the scene).
    pub fn set_texture_filter(&mut self, filter: Filter) {
        self.change_texture_lookups(&|o| o.filter.filter = filter);
    }

    /// Every layer's image texture takes the level-of-detail bias `bias` (`--lod-bias` overriding the scene).
    pub fn set_texture_lod_bias(&mut self, bias: f32) {
        self.change_texture_lookups(&|o| o.lod_bias = bias);
    }

    fn change_texture_lookups(&mut self, change: &dyn Fn(&mut TextureOptions)) {
        for layer in self.materials.iter_mut().flat_map(|m| &mut m.layers) {
            if let Some(changed) = layer.source.texture.with_lookup(change) {
                layer.source.texture = changed;
            }
        }
    }
}
