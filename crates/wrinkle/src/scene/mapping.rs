//! A texture's or bump's `mapping = { type = "...", ... }` (docs/scene-format.md, "Mappings"): which
//! projection gives the texture coordinates, and where it sits on the object (`placement`).

use super::fields::{numbers, Fields};
use super::load::parse_transform;
use crate::mapping::projection::{Projector, SphereRange, Surface};
use crate::mapping::{Mapping, Projection, UvTransform};
use crate::{Error, Result};
use glam::{Affine3A, Vec4};
use toml::Value;

const FIELDS: &[&str] = &["type", "placement", "longitude", "latitude", "surface", "projector", "flip", "s", "t"];
const TYPES: &[(&str, &[&str])] = &[
    ("uv", &[]),
    ("planar", &["placement"]),
    ("cylindrical", &["placement"]),
    ("spherical", &["placement", "longitude", "latitude"]),
    ("box", &["placement"]),
    ("two_part", &["placement", "surface", "projector", "flip", "longitude", "latitude"]),
    ("object_linear", &["s", "t"]),
    ("eye_linear", &["s", "t"]),
    ("sphere_map", &[]),
];

/// The mapping at `path` (absent: the surface's (u,v)), placed in (u,v) by `transform`.
pub fn parse_mapping(path: &str, v: Option<&Value>, transform: UvTransform) -> Result<Mapping> {
    let Some(v) = v else { return Ok(Mapping::uv(transform)) };
    let f = Fields::new(path, v, FIELDS)?;
    let kind = f.required("type", f.string("type")?)?;
    let Some(&(_, own)) = TYPES.iter().find(|(name, _)| *name == kind) else {
        let names = TYPES.iter().map(|(n, _)| format!("\"{n}\"")).collect::<Vec<_>>().join(", ");
        return Err(Error::scene(f.at("type"), format!("expected one of {names}, got \"{kind}\"")));
    };
    f.only_of_kind(&FIELDS[1..], own, &format!("mapping type \"{kind}\""))?;
    let range = || -> Result<SphereRange> {
        let d = SphereRange::default();
        let pair = |key: &str, default: [f32; 2], lo: f32, hi: f32| -> Result<[f32; 2]> {
            let Some(r) = f.vec2(key)? else { return Ok(default) };
            if r.x == r.y || r.min_element() < lo || r.max_element() > hi {
                return Err(Error::scene(
                    f.at(key),
                    format!("expected two different angles from {lo} to {hi} degrees"),
                ));
            }
            Ok([r.x, r.y])
        };
        Ok(SphereRange {
            longitude: pair("longitude", d.longitude, -360.0, 720.0)?,
            latitude: pair("latitude", d.latitude, -90.0, 90.0)?,
        })
    };
    let plane = |key: &str, default: Vec4| -> Result<Vec4> {
        match f.get(key) {
            Some(v) => Ok(Vec4::from_slice(&numbers(&f.at(key), v, 4)?)),
            None => Ok(default),
        }
    };
    let projection = match kind {
        "uv" => Projection::Uv,
        "planar" => Projection::Planar,
        "cylindrical" => Projection::Cylindrical,
        "spherical" => Projection::Spherical(range()?),
        "box" => Projection::Box,
        "two_part" => {
            let surfaces = [("plane", 0), ("cylinder", 1), ("sphere", 2), ("box", 3)];
            let surface = match f.choice("surface", 1, &surfaces)? {
                0 => Surface::Plane,
                1 => Surface::Cylinder,
                2 => Surface::Sphere(range()?),
                _ => Surface::Box,
            };
            if !matches!(surface, Surface::Sphere(_)) {
                if let Some(key) = ["longitude", "latitude"].into_iter().find(|k| f.get(k).is_some()) {
                    return Err(Error::scene(f.at(key), "only with surface = \"sphere\""));
                }
            }
            let projectors = [("isn", 0), ("normal", 1), ("centroid", 2), ("reflected", 3)];
            let projector = match f.choice("projector", 0, &projectors)? {
                0 => Projector::Isn { flip: f.boolean("flip", true)? },
                1 => Projector::Normal,
                2 => Projector::Centroid,
                _ => Projector::Reflected,
            };
            if f.get("flip").is_some() && !matches!(projector, Projector::Isn { .. }) {
                return Err(Error::scene(f.at("flip"), "only with projector = \"isn\""));
            }
            Projection::TwoPart { surface, projector }
        }
        "object_linear" | "eye_linear" => {
            // glTexGen's defaults: s = x, t = y.
            let (s, t) = (plane("s", Vec4::X)?, plane("t", Vec4::Y)?);
            if kind == "object_linear" {
                Projection::ObjectLinear { s, t }
            } else {
                Projection::EyeLinear { s, t }
            }
        }
        _ => Projection::SphereMap,
    };
    let to_mapping = match f.get("placement") {
        Some(p) => parse_transform(&f.at("placement"), p)?.matrix().inverse(),
        None => Affine3A::IDENTITY,
    };
    Ok(Mapping { projection, to_mapping, transform })
}
