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
use crate::shade::Chrome;
use crate::texture::{Filter, FilterOptions};
use crate::{Error, Result};
use std::path::Path;
use toml::Value;

const FIELDS: &[&str] = &["map", "layout", "intensity", "rotate", "filter", "max_aniso", "background"];

pub fn parse_environment(v: &Value, base: &Path) -> Result<SceneEnvironment> {
    let f = Fields::new("environment", v, FIELDS)?;
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
    let map = load_map(&f, base, options)?
        .ok_or_else(|| Error::scene(f.at("map"), "missing: the environment map's file (or six cube faces)"))?;
    Ok(SceneEnvironment { map, background: f.boolean("background", true)? })
}

/// A material's chrome map (the slides' "chrome mapping"): a view-independent, heavily blurred picture
/// looked up by the reflected view ray.
///
///     [object.material.chrome]
///     map = "landscape.png"     # any environment map; the slides' landscape when left out
///     layout = "latlong"
///     blur = 4.0                # the Phong exponent of the blur (smaller is blurrier)
///     strength = [1.0, 1.0, 1.0]
pub fn parse_chrome(path: &str, v: &Value, base: &Path) -> Result<Chrome> {
    let f = Fields::new(path, v, &["map", "layout", "blur", "strength"])?;
    let blur =
        f.number_where("blur", Some(4.0), |x| (1.0..=10_000.0).contains(&x), "a Phong exponent from 1 to 10000")?;
    let strength = super::load::colour(&f, "strength", glam::Vec3::ONE)?;
    let map = match load_map(&f, base, EnvironmentOptions::default())? {
        Some(map) => map,
        None => landscape(),
    };
    Ok(Chrome { map: map.lobe(blur), strength })
}

/// The slides' chrome landscape: white to blue above the horizon, brown and green below.
fn landscape() -> Environment {
    let (w, h) = (64, 32);
    let image = crate::image::Image::from_fn(w, h, |x, y| {
        let up = 1.0 - 2.0 * (y as f32 + 0.5) / h as f32;
        let c = if up >= 0.0 {
            glam::Vec3::new(0.85, 0.9, 1.0).lerp(glam::Vec3::new(0.12, 0.3, 0.85), up)
        } else {
            // Fields and earth, a few broad patches round the horizon.
            let field =
                if (x / 8) % 2 == 0 { glam::Vec3::new(0.35, 0.25, 0.12) } else { glam::Vec3::new(0.2, 0.35, 0.12) };
            field.lerp(glam::Vec3::new(0.2, 0.12, 0.06), -up)
        };
        c.extend(1.0).to_array()
    });
    Environment::new(Layout::LatLong, &[image], EnvironmentOptions::default()).expect("a 2:1 latlong map")
}

/// The environment map that `map` (one file or a list) and `layout` name, if `map` is given.
fn load_map(f: &Fields, base: &Path, options: EnvironmentOptions) -> Result<Option<Environment>> {
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
        None => return Ok(None),
    };
    let paths = names.iter().map(|n| resolve(base, &f.at("map"), n)).collect::<Result<Vec<_>>>()?;
    let layouts: Vec<(&str, Option<Layout>)> = Layout::ALL.iter().map(|&(n, l)| (n, Some(l))).collect();
    let layout = f.choice("layout", None, &layouts)?;
    let (layout, images) = files::load(&paths, layout).map_err(|e| match e {
        Error::Invalid(m) => Error::scene(f.at("map"), m),
        other => other,
    })?;
    Environment::new(layout, &images, options).map(Some).map_err(|m| Error::read(&paths[0], m))
}
