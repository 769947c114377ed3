//! The scene's `[environment]`: an environment map in one of the slides' layouts, seen in reflections and
//! (unless `background = false`) where the camera sees no object.
//!
//!     [environment]
//!     map = "sky.hdr"                 # or six cube faces: ["px.png", "nx.png", "py.png", "ny.png", "pz.png", "nz.png"]
//!     layout = "latlong"              # cube, sphere, paraboloid; guessed from the files when left out
//!     intensity = 1.0
//!     rotate = 0.0                    # degrees about +Y
//!     filter = "trilinear"            # any texture filter
//!     background = true

use super::fields::{describe, Fields};
use super::load::resolve;
use super::SceneEnvironment;
use crate::envmap::{files, Environment, EnvironmentOptions, Layout};
use crate::texture::{Filter, FilterOptions};
use crate::{Error, Result};
use std::path::Path;
use toml::Value;

const FIELDS: &[&str] = &["map", "layout", "intensity", "rotate", "filter", "max_aniso", "background"];

pub fn parse_environment(v: &Value, base: &Path) -> Result<SceneEnvironment> {
    let f = Fields::new("environment", v, FIELDS)?;
    let names: Vec<&str> = match f.get("map") {
        Some(Value::String(s)) => vec![s.as_str()],
        Some(Value::Array(items)) => items
            .iter()
            .map(|i| {
                i.as_str().ok_or_else(|| Error::scene(f.at("map"), format!("expected file names, got {}", describe(i))))
            })
            .collect::<Result<_>>()?,
        Some(other) => {
            return Err(Error::scene(
                f.at("map"),
                format!("expected a file name or a list of them, got {}", describe(other)),
            ))
        }
        None => return Err(Error::scene(f.at("map"), "missing: the environment map's file (or six cube faces)")),
    };
    let paths = names.iter().map(|n| resolve(base, &f.at("map"), n)).collect::<Result<Vec<_>>>()?;
    let layouts: Vec<(&str, Option<Layout>)> = Layout::ALL.iter().map(|&(n, l)| (n, Some(l))).collect();
    let layout = f.choice("layout", None, &layouts)?;
    let filters: Vec<(&str, Filter)> = Filter::ALL.to_vec();
    let filter = FilterOptions {
        filter: f.choice("filter", Filter::Trilinear, &filters)?,
        max_aniso: f.number_where("max_aniso", Some(16.0), |x| (1.0..=64.0).contains(&x), "a ratio from 1 to 64")?,
        ..FilterOptions::default()
    };
    let options = EnvironmentOptions {
        intensity: f.number_where("intensity", Some(1.0), |x| x >= 0.0 && x.is_finite(), "a non-negative number")?,
        rotate: f.number_where("rotate", Some(0.0), f32::is_finite, "degrees")?,
        filter,
    };
    let (layout, images) = files::load(&paths, layout).map_err(|e| match e {
        Error::Invalid(m) => Error::scene(f.at("map"), m),
        other => other,
    })?;
    let map = Environment::new(layout, &images, options).map_err(|m| Error::read(&paths[0], m))?;
    Ok(SceneEnvironment { map, background: f.boolean("background", true)? })
}
