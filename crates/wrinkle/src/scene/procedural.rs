//! Procedural patterns in scene files (docs/scene-format.md):
//!     texture = { procedural = "marble", scale = 3, octaves = 6, colors = [[...], [...]] }
//!     [object.material.bump]
//!     procedural = { pattern = "fbm", scale = 8, octaves = 4 }
//! Every field of the pattern is optional; the default space is "object" (a solid texture).

use super::fields::{vec3_value, Fields};
use crate::procedural::effects::{Kind, Params, Pattern};
use crate::procedural::solid::{Procedural, Space};
use crate::procedural::Variant;
use crate::{Error, Result};
use toml::Value;

/// The pattern fields, besides the one that names the pattern.
const PATTERN_FIELDS: &[&str] = &[
    "space",
    "scale",
    "seed",
    "variant",
    "octaves",
    "lacunarity",
    "gain",
    "strength",
    "rings",
    "time",
    "mortar",
    "line_width",
    "colors",
];

/// Whether a texture table names a procedural pattern.
pub fn is_procedural(v: &Value) -> bool {
    v.as_table().is_some_and(|t| t.contains_key("procedural"))
}

/// `texture = { procedural = "marble", ... }`.
pub fn parse_texture(path: &str, v: &Value) -> Result<Procedural> {
    let known: Vec<&str> = std::iter::once("procedural").chain(PATTERN_FIELDS.iter().copied()).collect();
    let f = Fields::new(path, v, &known)?;
    parse_pattern(&f, "procedural")
}

/// `procedural = { pattern = "fbm", ... }` inside a bump table.
pub fn parse_bump(path: &str, v: &Value) -> Result<Procedural> {
    let known: Vec<&str> = std::iter::once("pattern").chain(PATTERN_FIELDS.iter().copied()).collect();
    let f = Fields::new(path, v, &known)?;
    parse_pattern(&f, "pattern")
}

fn parse_pattern(f: &Fields, name_key: &str) -> Result<Procedural> {
    let name = f.required(name_key, f.string(name_key)?)?;
    let kind = Kind::from_name(name).ok_or_else(|| {
        let names: Vec<String> = Kind::ALL.iter().map(|k| format!("\"{}\"", k.name())).collect();
        Error::scene(f.at(name_key), format!("expected one of {}, got \"{name}\"", names.join(", ")))
    })?;
    let space = f.choice("space", Space::Object, &[("object", Space::Object), ("uv", Space::Uv)])?;
    let mut p = Params::new(kind);
    p.scale = f.number_or("scale", p.scale)?;
    p.seed = f.integer_where("seed", 0, 0, u32::MAX as usize)? as u64;
    p.variant =
        f.choice("variant", Variant::Improved, &[("improved", Variant::Improved), ("classic", Variant::Classic)])?;
    p.octaves.count = f.integer_where("octaves", p.octaves.count as usize, 1, 24)? as u32;
    p.octaves.lacunarity = f.number_or("lacunarity", p.octaves.lacunarity)?;
    p.octaves.gain = f.number_or("gain", p.octaves.gain)?;
    p.strength = f.number_or("strength", p.strength)?;
    p.rings = f.number_or("rings", p.rings)?;
    p.time = f.number_or("time", p.time)?;
    p.mortar = f.number_or("mortar", p.mortar)?;
    p.line_width = f.number_or("line_width", p.line_width)?;
    if let Some(c) = f.get("colors") {
        let Value::Array(list) = c else {
            return Err(Error::scene(f.at("colors"), "expected an array of colours [r, g, b]"));
        };
        p.colors = list
            .iter()
            .enumerate()
            .map(|(i, c)| vec3_value(&format!("{}[{i}]", f.at("colors")), c).map(|v| v.to_array()))
            .collect::<Result<_>>()?;
    }
    // Parameter errors name the field: "scale: expected ..." -> "objects[0].material.texture.scale: expected ...".
    let dims = if space == Space::Object { 3 } else { 2 };
    let pattern = Pattern::new(p, dims, false).map_err(|e| match e {
        Error::Invalid(m) => match m.split_once(": ") {
            Some((field, rest)) => Error::scene(f.at(field), rest),
            None => Error::scene(&f.path, m),
        },
        other => other,
    })?;
    Ok(Procedural { pattern, space })
}
