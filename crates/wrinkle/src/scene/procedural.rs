//! Procedural patterns in scene files (docs/scene-format.md):
//!     texture = { procedural = "marble", scale = 3, octaves = 6, colors = [[...], [...]] }
//!     [object.material.bump]
//!     procedural = { pattern = "fbm", scale = 8, octaves = 4 }
//! Every field of the pattern is optional; the default space is "object" (a solid texture).
//! And hypertextures: `[[volume]]` tables with their `[[volume.modulate]]` functions.

use super::build::check_colour;
use super::fields::{quoted, vec3_value, Fields};
use crate::procedural::effects::{Kind, Params, Pattern};
use crate::procedural::fbm::Sum;
use crate::procedural::hypertexture::{Hypertexture, Modulation, Shading};
use crate::procedural::solid::{Procedural, Space};
use crate::procedural::Variant;
use crate::{Error, Result};
use glam::Vec3;
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

/// The noise's fields (`seed`, `variant`), then its sums' (`octaves`, `lacunarity`, `gain`).
const NOISE_FIELDS: &[&str] = &["seed", "variant", "octaves", "lacunarity", "gain"];

/// The fields a pattern reads (`Kind::describe`): `space`, `scale` and `colors`, those of its noise and
/// sums, and its own.
fn pattern_fields(kind: Kind) -> Vec<&'static str> {
    let (noise, own): (&[&str], &[&str]) = match kind {
        Kind::Noise => (&NOISE_FIELDS[..2], &[]),
        Kind::Fbm | Kind::Turbulence => (NOISE_FIELDS, &[]),
        Kind::Marble => (NOISE_FIELDS, &["strength"]),
        Kind::Wood => (NOISE_FIELDS, &["rings", "strength"]),
        Kind::Fire => (NOISE_FIELDS, &["strength", "time"]),
        Kind::Clouds => (NOISE_FIELDS, &["time"]),
        Kind::Bricks => (&[], &["mortar"]),
        Kind::Checker => (&[], &[]),
        Kind::Grid => (&[], &["line_width"]),
    };
    ["space", "scale", "colors"].iter().chain(noise).chain(own).copied().collect()
}

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
    let f = pattern_table(path, v)?;
    if f.get("colors").is_some() {
        return Err(Error::scene(f.at("colors"), "applies to textures only (a bump reads the pattern's value)"));
    }
    parse_pattern(&f, "pattern")
}

/// `procedural = { pattern = "marble", ... }` as a texture layer's source.
pub fn parse_layer(path: &str, v: &Value) -> Result<Procedural> {
    parse_pattern(&pattern_table(path, v)?, "pattern")
}

fn pattern_table<'a>(path: &str, v: &'a Value) -> Result<Fields<'a>> {
    let known: Vec<&str> = std::iter::once("pattern").chain(PATTERN_FIELDS.iter().copied()).collect();
    Fields::new(path, v, &known)
}

fn parse_pattern(f: &Fields, name_key: &str) -> Result<Procedural> {
    let name = f.required(name_key, f.string(name_key)?)?;
    let kind = Kind::from_name(name).ok_or_else(|| {
        let names: Vec<String> = Kind::ALL.iter().map(|k| format!("\"{}\"", k.name())).collect();
        Error::scene(f.at(name_key), format!("expected one of {}, got {}", names.join(", "), quoted(name)))
    })?;
    f.only_of_kind(PATTERN_FIELDS, &pattern_fields(kind), &format!("pattern \"{name}\""))?;
    let space = f.choice("space", Space::Object, &[("object", Space::Object), ("uv", Space::Uv)])?;
    let mut p = Params::new(kind);
    p.scale = f.number_or("scale", p.scale)?;
    p.seed = f.integer_where("seed", 0, 0, u32::MAX as usize)? as u64;
    p.variant = f.choice("variant", p.variant, &Variant::NAMES)?;
    p.octaves.count = f.integer_where("octaves", p.octaves.count as usize, 1, 24)? as u32;
    p.octaves.lacunarity = f.number_or("lacunarity", p.octaves.lacunarity)?;
    p.octaves.gain = f.number_or("gain", p.octaves.gain)?;
    p.strength = f.number_or("strength", p.strength)?;
    p.rings = f.number_or("rings", p.rings)?;
    p.time = f.number_or("time", p.time)?;
    p.mortar = f.number_or("mortar", p.mortar)?;
    p.line_width = f.number_or("line_width", p.line_width)?;
    if let Some(c) = f.get("colors") {
        p.colors = colors(&f.at("colors"), c)?;
    }
    // Parameter errors name the field by its path.
    let dims = if space == Space::Object { 3 } else { 2 };
    let pattern = Pattern::new(p, dims, false).map_err(|e| f.named(e))?;
    Ok(Procedural { pattern, space })
}

const VOLUME_FIELDS: &[&str] =
    &["center", "radius", "radii", "soft", "density", "step", "shading", "color", "colors", "emission", "modulate"];

/// A `[[volume]]` table: a hypertextured ellipsoid.
pub fn parse_volume(path: &str, v: &Value) -> Result<Hypertexture> {
    let f = Fields::new(path, v, VOLUME_FIELDS)?;
    let positive = |x: f32| x > 0.0;
    let radii = match (f.get("radius"), f.vec3("radii")?) {
        (Some(_), Some(_)) => return Err(Error::scene(f.at("radii"), "give either radius or radii, not both")),
        (_, Some(r)) if r.min_element() <= 0.0 => {
            return Err(Error::scene(
                f.at("radii"),
                format!("expected positive radii, got [{}, {}, {}]", r.x, r.y, r.z),
            ))
        }
        (_, Some(r)) => r,
        _ => Vec3::splat(f.number_where("radius", Some(1.0), positive, "a positive radius")?),
    };
    let mode = f.choice("shading", "lit", &[("lit", "lit"), ("emissive", "emissive")])?;
    // The fields of the other shading.
    let (other, owner) =
        if mode == "lit" { (["colors", "emission"].as_slice(), "emissive") } else { (&["color"][..], "lit") };
    if let Some(key) = other.iter().find(|k| f.get(k).is_some()) {
        return Err(Error::scene(f.at(key), format!("applies to shading = \"{owner}\" only")));
    }
    let shading = match mode {
        "lit" => Shading::Lit { albedo: super::load::colour(&f, "color", Vec3::splat(0.8))? },
        _ => Shading::Emissive {
            colors: match f.get("colors") {
                Some(c) => colors(&f.at("colors"), c)?,
                None => Kind::Fire.default_colors(),
            },
            emission: f.number_where("emission", Some(2.0), |x| x >= 0.0, "a non-negative number")?,
        },
    };
    let modulations = f
        .tables("modulate")?
        .iter()
        .enumerate()
        .map(|(i, m)| parse_modulation(&format!("{}[{i}]", f.at("modulate")), m))
        .collect::<Result<_>>()?;
    Ok(Hypertexture {
        center: f.vec3("center")?.unwrap_or(Vec3::ZERO),
        radii,
        soft: f.number_where("soft", Some(0.5), |x| x > 0.0 && x <= 1.0, "a fraction above 0, at most 1")?,
        density: f.number_where("density", Some(10.0), positive, "a positive extinction per unit length")?,
        step: f.number_where("step", Some(0.01), |x| x >= 1e-4, "a march step of at least 0.0001")?,
        modulations,
        shading,
    })
}

/// The fields of a modulation table: its kind, then the parameters of every kind.
const MODULATION_FIELDS: &[&str] = &["kind", "value", "amplitude", "frequency", "octaves", "seed", "drift"];

fn parse_modulation(path: &str, v: &Value) -> Result<Modulation> {
    let f = Fields::new(path, v, MODULATION_FIELDS)?;
    let kind = f.required("kind", f.string("kind")?)?;
    let own: &[&str] = match kind {
        "bias" | "gain" => &["value"],
        // Noise is one octave.
        "noise" => &["amplitude", "frequency", "seed", "drift"],
        "fbm" | "turbulence" => &MODULATION_FIELDS[2..],
        _ => &[],
    };
    if !own.is_empty() {
        f.only_of_kind(&MODULATION_FIELDS[1..], own, &format!("kind \"{kind}\""))?;
    }
    let fraction = |x: f32| x > 0.0 && x < 1.0;
    match kind {
        "bias" | "gain" => {
            let b = f.number_where("value", None, fraction, "a number between 0 and 1")?;
            Ok(if kind == "bias" { Modulation::Bias(b) } else { Modulation::Gain(b) })
        }
        "noise" | "fbm" | "turbulence" => {
            let sum = if kind == "turbulence" { Sum::Turbulence } else { Sum::Fbm };
            let octaves = if kind == "noise" { 1 } else { f.integer_where("octaves", 5, 1, 24)? as u32 };
            Ok(Modulation::noise(
                sum,
                // H is clamped to [0, 1]: a larger amplitude only pushes the volume's bound (and its march) out.
                f.number_where("amplitude", Some(0.5), |x| x.abs() <= 16.0, "an amplitude between -16 and 16")?,
                f.number_where("frequency", Some(2.0), |x| x > 0.0, "a positive frequency")?,
                octaves,
                f.integer_where("seed", 0, 0, u32::MAX as usize)? as u64,
                f.vec3("drift")?.unwrap_or(Vec3::ZERO),
            ))
        }
        other => Err(Error::scene(
            f.at("kind"),
            format!("expected one of \"bias\", \"gain\", \"noise\", \"fbm\", \"turbulence\", got {}", quoted(other)),
        )),
    }
}

fn colors(path: &str, v: &Value) -> Result<Vec<[f32; 3]>> {
    let Value::Array(list) = v else {
        return Err(Error::scene(path, "expected an array of colours [r, g, b]"));
    };
    if list.is_empty() {
        return Err(Error::scene(path, "expected at least one colour"));
    }
    list.iter()
        .enumerate()
        .map(|(i, c)| {
            let at = format!("{path}[{i}]");
            let colour = vec3_value(&at, c)?;
            check_colour("colour", colour).map(|c| c.to_array()).map_err(|e| match e {
                Error::Parameter { message, .. } => Error::scene(at, message),
                other => other,
            })
        })
        .collect()
}
