//! A texture's or bump's `mapping = { type = "...", ... }` (docs/scene-format.md, "Mappings"): which
//! projection gives the texture coordinates, and where it sits on the object (`placement`).

use super::fields::{numbers, points, quoted, Fields};
use super::load::parse_transform;
use crate::mapping::polygon::{QuadMapping, TriangleMapping};
use crate::mapping::projection::{Projector, SphereRange, Surface};
use crate::mapping::{Mapping, Projection, UvTransform};
use crate::{Error, Result};
use glam::{Affine3A, Vec4};
use toml::Value;

const FIELDS: &[&str] =
    &["type", "set", "placement", "longitude", "latitude", "surface", "projector", "flip", "s", "t", "points", "uv"];
const TYPES: &[(&str, &[&str])] = &[
    ("uv", &["set"]),
    ("planar", &["placement"]),
    ("cylindrical", &["placement"]),
    ("spherical", &["placement", "longitude", "latitude"]),
    ("box", &["placement"]),
    ("two_part", &["placement", "surface", "projector", "flip", "longitude", "latitude"]),
    ("object_linear", &["s", "t"]),
    ("eye_linear", &["s", "t"]),
    ("sphere_map", &[]),
    ("triangle", &["points", "uv"]),
    ("quad", &["points", "uv"]),
];

/// A mapping written as a scene writes it, `{ type = "cylindrical", placement = { ... } }`, for front ends
/// that choose mappings without a scene file; errors name its fields under `mapping`.
pub fn parse_mapping_text(text: &str) -> Result<Mapping> {
    let table: toml::Table = toml::from_str(&format!("mapping = {text}"))
        .map_err(|e| Error::scene("mapping", format!("malformed TOML: {}", e.message().trim())))?;
    parse_mapping("mapping", table.get("mapping"), UvTransform::IDENTITY)
}

/// The mapping at `path` (absent: the surface's (u,v)), placed in (u,v) by `transform`.
pub fn parse_mapping(path: &str, v: Option<&Value>, transform: UvTransform) -> Result<Mapping> {
    let Some(v) = v else { return Ok(Mapping::uv(transform)) };
    let f = Fields::new(path, v, FIELDS)?;
    let kind = f.required("type", f.string("type")?)?;
    let Some(&(_, own)) = TYPES.iter().find(|(name, _)| *name == kind) else {
        let names = TYPES.iter().map(|(n, _)| format!("\"{n}\"")).collect::<Vec<_>>().join(", ");
        return Err(Error::scene(f.at("type"), format!("expected one of {names}, got {}", quoted(kind))));
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
        // glTF asks viewers to draw two sets; a mesh's loader keeps both.
        "uv" => match f.integer_where("set", 0, 0, 1)? {
            0 => Projection::Uv,
            _ => Projection::SecondUv,
        },
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
        "triangle" => {
            let (points, uv) = (corner_points(&f, 3)?, corner_uvs(&f, 3)?);
            let m = TriangleMapping::new([points[0], points[1], points[2]], [uv[0], uv[1], uv[2]])
                .ok_or_else(|| Error::scene(f.at("points"), "the three points must span a triangle"))?;
            Projection::Triangle(m)
        }
        "quad" => {
            let (points, uv) = (corner_points(&f, 4)?, corner_uvs(&f, 4)?);
            let corners = std::array::from_fn(|k| points[k].as_dvec3());
            Projection::Quad(QuadMapping { corners, uv: std::array::from_fn(|k| uv[k]) })
        }
        _ => Projection::SphereMap,
    };
    let to_mapping = match f.get("placement") {
        Some(p) => parse_transform(&f.at("placement"), p)?.matrix().inverse(),
        None => Affine3A::IDENTITY,
    };
    Ok(Mapping { projection, to_mapping, transform })
}

/// `points`: `n` points in object space, P00, P10, P11, P01 for a quad.
fn corner_points(f: &Fields, n: usize) -> Result<Vec<glam::Vec3>> {
    let v = f.required("points", f.get("points"))?;
    points(&f.at("points"), v, n)
}

/// `uv`: the texture coordinates at the `n` points.
fn corner_uvs(f: &Fields, n: usize) -> Result<Vec<glam::Vec2>> {
    uv_list(&f.at("uv"), f.required("uv", f.get("uv"))?, n)
}

/// An array of `n` [u, v] pairs.
pub(super) fn uv_list(path: &str, v: &Value, n: usize) -> Result<Vec<glam::Vec2>> {
    match v {
        Value::Array(a) if a.len() == n => a
            .iter()
            .enumerate()
            .map(|(k, x)| numbers(&format!("{path}[{k}]"), x, 2).map(|c| glam::Vec2::new(c[0], c[1])))
            .collect(),
        _ => Err(Error::scene(path, format!("expected an array of {n} [u, v] pairs"))),
    }
}
