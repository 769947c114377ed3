//! A material's texture layers and alpha (docs/scene-format.md):
//!     [[objects.material.layer]]
//!     texture = { path = "leaf.png" }      # or procedural = { pattern = "marble", ... }
//!     target = "kd"                        # kd, ks, shininess, opacity, emission
//!     mode = "decal"                       # replace, modulate, decal, blend (with blend_color), add
//! and `alpha_mode = "opaque" | "mask" | "blend"` with `alpha_cutoff` in the material.

use super::fields::Fields;
use super::load::colour;
use super::texture::{parse_texture, Role, Source};
use crate::mapping::{MappedTexture, Mapping};
use crate::shade::{AlphaMode, Layer, Mode, Target};
use crate::{Error, Result};
use glam::Vec3;
use std::path::Path;
use std::sync::Arc;
use toml::Value;

const LAYER_FIELDS: &[&str] = &["texture", "procedural", "target", "mode", "blend_color"];

/// The material's `layer` array, in order.
pub fn parse_layers(material: &Fields, base: &Path) -> Result<Vec<Layer>> {
    let Some(v) = material.get("layer") else { return Ok(Vec::new()) };
    let Some(tables) = v.as_array() else {
        return Err(Error::scene(material.at("layer"), "expected an array of tables ([[...material.layer]])"));
    };
    (0..tables.len()).map(|i| parse_layer(&format!("{}[{i}]", material.at("layer")), &tables[i], base)).collect()
}

fn parse_layer(path: &str, v: &Value, base: &Path) -> Result<Layer> {
    let f = Fields::new(path, v, LAYER_FIELDS)?;
    let target = f.choice("target", Target::Kd, &Target::NAMES)?;
    // Colours are pictures, sRGB-encoded unless `srgb = false`; reflection properties and coverage are data.
    let role = if target.is_colour() { Role::Colour } else { Role::Data };
    let source = match (f.get("texture"), f.get("procedural")) {
        (Some(_), Some(_)) => return Err(Error::scene(f.at("procedural"), "give texture or procedural, not both")),
        (Some(t), None) => parse_texture(&f.at("texture"), t, &f, base, role)?,
        (None, Some(p)) => {
            let texture = Arc::new(super::procedural::parse_layer(&f.at("procedural"), p)?);
            Source { mapped: MappedTexture { texture, mapping: Mapping::default() }, rgba: false }
        }
        (None, None) => return Err(Error::scene(f.at("texture"), "missing field (or give procedural)")),
    };
    let mode = match f.string("mode")?.unwrap_or("modulate") {
        "replace" => Mode::Replace,
        "modulate" => Mode::Modulate,
        "decal" if target.is_colour() => Mode::Decal,
        "decal" => {
            return Err(Error::scene(f.at("mode"), "\"decal\" applies to colour targets (kd, emission) only"));
        }
        "blend" => Mode::Blend(colour(&f, "blend_color", Vec3::ZERO)?),
        "add" => Mode::Add,
        other => {
            let names: Vec<String> = Mode::NAMES.iter().map(|n| format!("\"{n}\"")).collect();
            let got = super::fields::quoted(other);
            return Err(Error::scene(f.at("mode"), format!("expected one of {}, got {got}", names.join(", "))));
        }
    };
    if f.get("blend_color").is_some() && !matches!(mode, Mode::Blend(_)) {
        return Err(Error::scene(f.at("blend_color"), "applies to mode = \"blend\" only"));
    }
    Ok(Layer { source: source.mapped, target, mode, rgba: source.rgba })
}

/// `alpha_mode` and `alpha_cutoff` (default 0.5, or the model file's, in [0, 1]); `under` is the mode
/// without the fields (the default's or the model file's).
pub fn parse_alpha_mode(f: &Fields, under: AlphaMode) -> Result<AlphaMode> {
    let under_cutoff = match under {
        AlphaMode::Mask { cutoff } => cutoff,
        _ => 0.5,
    };
    let modes = [
        ("opaque", AlphaMode::Opaque),
        ("mask", AlphaMode::Mask { cutoff: under_cutoff }),
        ("blend", AlphaMode::Blend),
    ];
    match f.choice("alpha_mode", under, &modes)? {
        AlphaMode::Mask { cutoff } => {
            let in_unit = |x: f32| (0.0..=1.0).contains(&x);
            Ok(AlphaMode::Mask {
                cutoff: f.number_where("alpha_cutoff", Some(cutoff), in_unit, "a number from 0 to 1")?,
            })
        }
        _ if f.get("alpha_cutoff").is_some() => {
            Err(Error::scene(f.at("alpha_cutoff"), "applies to alpha_mode = \"mask\" only"))
        }
        other => Ok(other),
    }
}
