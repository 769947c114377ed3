//! Wavefront OBJ models through `tobj`, with their .mtl materials: Kd, Ks, Ns, d, map_Kd (colour), map_Ks
//! (specular), map_Ns (the exponent), map_d (dissolve: a cutout under the alpha test), Ke and map_Ke
//! (emission), bump / map_Bump with
//! `-bm` (a height map for Blinn's bump mapping), norm (a tangent-space normal map). Texture options `-bm`, `-o`, `-s` and `-clamp` are read; the other standard options are
//! accepted and ignored.

use super::model::ModelPart;
use super::texture::load_texture;
use crate::bump::normal_map::Convention;
use crate::bump::{BumpFormula, BumpMap, BumpSource, BumpTable, SlopeFilter, TangentNormalMap};
use crate::geometry::TriangleMesh;
use crate::image::io;
use crate::mapping::{MappedTexture, Mapping, UvTransform};
use crate::shade::{AlphaMode, Layer, Material, Phong, Target};
use crate::texture::{Filter, FilterOptions, TextureOptions, Wrap};
use crate::{Error, Result};
use glam::{Vec2, Vec3};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A .mtl file for tobj, with what tobj does not check first: it must be a regular file (a library at
/// /dev/zero would be read forever), and Ka, Kd, Ks and Ke need three numbers (tobj panics on fewer).
fn read_library(file: &Path) -> std::result::Result<tobj::MTLLoadResult, LibraryProblem> {
    let missing = |message: String| LibraryProblem { message, malformed: false };
    io::check_input(file).map_err(|e| missing(e.to_string()))?;
    let text = std::fs::read_to_string(file).map_err(|e| missing(format!("{}: {e}", file.display())))?;
    for (n, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        if let Some(key @ ("Ka" | "Kd" | "Ks" | "Ke")) = words.next() {
            if words.count() < 3 {
                let message = format!("{}: line {}: {key} needs three numbers", file.display(), n + 1);
                return Err(LibraryProblem { message, malformed: true });
            }
        }
    }
    Ok(tobj::load_mtl_buf(&mut text.as_bytes()))
}

/// Why a material library was refused: missing or unreadable (an error only where a face needs it), or
/// malformed (always an error).
struct LibraryProblem {
    message: String,
    malformed: bool,
}

/// The meshes of an OBJ file, one per object and material, with the materials of its .mtl.
pub fn load(path: &Path) -> Result<Vec<ModelPart>> {
    let options = tobj::LoadOptions { single_index: true, triangulate: true, ..tobj::LoadOptions::default() };
    let dir = path.parent().unwrap_or(Path::new("."));
    let mut reader = std::io::BufReader::new(io::open_input(path)?);
    // Why the material library was refused, when it was for a reason tobj's errors cannot carry.
    let library_problem = std::cell::RefCell::new(None);
    let (models, materials) = tobj::load_obj_buf(&mut reader, &options, |name| {
        read_library(&dir.join(name)).map_err(|problem| {
            *library_problem.borrow_mut() = Some(problem);
            tobj::LoadError::OpenFileFailed
        })?
    })
    .map_err(|e| Error::read(path, obj_error(&e)))?;
    // A malformed .mtl is always an error: tobj then leaves every face without its material, which would
    // render silently grey.
    let malformed = library_problem.borrow().as_ref().is_some_and(|p: &LibraryProblem| p.malformed);
    let materials = match materials {
        Ok(m) => m,
        // A missing .mtl is an error only when a face asks for one of its materials.
        Err(tobj::LoadError::OpenFileFailed) if !malformed && models.iter().all(|m| m.mesh.material_id.is_none()) => {
            Vec::new()
        }
        Err(e) => {
            let why = library_problem.take().map_or_else(|| obj_error(&e), |p| p.message);
            return Err(Error::read(path, format!("its material library: {why}")));
        }
    };
    let materials = materials
        .iter()
        .map(|m| {
            let named = |e: Error| Error::read(path, format!("material \"{}\": {e}", m.name));
            material(m, dir).map(Arc::new).map_err(named)
        })
        .collect::<Result<Vec<Arc<ObjMaterial>>>>()?;
    let mut parts = Vec::new();
    for model in &models {
        let m = &model.mesh;
        if m.indices.is_empty() {
            continue;
        }
        let positions = m.positions.chunks_exact(3).map(|p| Vec3::new(p[0], p[1], p[2])).collect();
        let normals = m.normals.chunks_exact(3).map(|n| Vec3::new(n[0], n[1], n[2])).collect();
        let uvs: Vec<Vec2> = m.texcoords.chunks_exact(2).map(|t| Vec2::new(t[0], t[1])).collect();
        let mut mesh = TriangleMesh {
            positions,
            normals,
            uv_sets: if uvs.is_empty() { vec![] } else { vec![uvs] },
            tangents: vec![],
            triangles: m.indices.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect(),
        };
        mesh.validate().map_err(|e| Error::read(path, format!("object \"{}\" {e}", model.name)))?;
        mesh.complete_normals();
        let material = match m.material_id {
            Some(k) => {
                let mtl = materials.get(k).ok_or_else(|| {
                    Error::read(path, format!("object \"{}\" names material {k}, which its .mtl lacks", model.name))
                })?;
                mtl.material()
            }
            None => Material::default(),
        };
        parts.push(ModelPart { mesh, material, two_sided: true });
    }
    if parts.is_empty() {
        return Err(Error::read(path, "has no triangles"));
    }
    Ok(parts)
}

fn obj_error(e: &tobj::LoadError) -> String {
    match e {
        tobj::LoadError::OpenFileFailed => "no such file, or it cannot be opened".into(),
        other => format!("malformed OBJ: {other}"),
    }
}

/// An .mtl material with its textures loaded once, however many meshes use it.
struct ObjMaterial {
    color: Vec3,
    specular: f32,
    shininess: f32,
    opacity: f32,
    emission: Vec3,
    /// map_Kd, map_Ks, map_Ns, map_d and map_Ke as texture layers.
    layers: Vec<Layer>,
    bump: Option<(Arc<BumpTable>, f32, UvTransform)>,
    normal_map: Option<MappedTexture>,
}

impl ObjMaterial {
    fn material(&self) -> Material {
        let cutout = self.layers.iter().any(|l| l.target == Target::Opacity);
        Material {
            color: self.color,
            opacity: self.opacity,
            emission: self.emission,
            layers: self.layers.clone(),
            // A dissolve map cuts leaves and fences out (the alpha test); a dissolve below 1 alone is glass.
            alpha_mode: match (cutout, self.opacity < 1.0) {
                (true, _) => AlphaMode::Mask { cutoff: 0.5 },
                (false, true) => AlphaMode::Blend,
                (false, false) => AlphaMode::Opaque,
            },
            phong: Phong::new(self.specular, self.shininess),
            bump: self.bump.as_ref().map(|(table, scale, transform)| BumpMap {
                source: BumpSource::Table(table.clone()),
                scale: *scale,
                mapping: Mapping::uv(*transform),
                formula: BumpFormula::Blinn,
                filter: FilterOptions { filter: Filter::Trilinear, ..FilterOptions::default() },
                slopes: SlopeFilter::Plain,
                parallax: None,
            }),
            normal_map: self
                .normal_map
                .as_ref()
                .map(|texture| TangentNormalMap::new(texture.clone(), 1.0, Convention::OpenGl)),
            ..Material::default()
        }
    }
}

fn material(m: &tobj::Material, dir: &Path) -> Result<ObjMaterial> {
    let mean = |c: [f32; 3]| (c[0] + c[1] + c[2]) / 3.0;
    let parse = |spec: &str| MapSpec::parse(spec, dir).map_err(|e| Error::read(dir.join(spec), e));
    let map = |spec: &Option<String>, srgb: bool| -> Result<Option<(MappedTexture, bool)>> {
        let Some(spec) = spec else { return Ok(None) };
        let map = parse(spec)?;
        let wrap = if map.clamp { Wrap::Clamp } else { Wrap::Repeat };
        let options = TextureOptions { wrap: [wrap; 2], ..TextureOptions::default() };
        let (texture, alpha) = load_texture(&map.file, srgb, options)?;
        Ok(Some((MappedTexture { texture: Arc::new(texture), mapping: Mapping::uv(map.transform) }, alpha)))
    };
    // Each map multiplies its value (map_Ns the exponent, map_d the dissolve), as the MTL format says.
    let mut layers = Vec::new();
    for (spec, target, srgb) in [
        (&m.diffuse_texture, Target::Kd, true),
        (&m.specular_texture, Target::Ks, false),
        (&m.shininess_texture, Target::Shininess, false),
        (&m.dissolve_texture, Target::Opacity, false),
        (&m.unknown_param.get("map_Ke").cloned(), Target::Emission, true),
    ] {
        if let Some((source, rgba)) = map(spec, srgb)? {
            layers.push(Layer::modulate(source, target, rgba));
        }
    }
    let bump = match &m.normal_texture {
        // tobj reads both bump and map_Bump into `normal_texture`: a height map.
        Some(spec) => {
            let map = parse(spec)?;
            let table = Arc::new(BumpTable::new(&io::load_grey(&map.file)?));
            Some((table, 0.01 * map.bump_multiplier, map.transform))
        }
        None => None,
    };
    Ok(ObjMaterial {
        color: m.diffuse.map_or(Vec3::splat(0.8), Vec3::from_array),
        specular: m.specular.map_or(0.0, mean),
        // Ns runs 0..1000; Blinn-Phong needs a positive exponent.
        shininess: m.shininess.map_or(20.0, |n| n.max(1.0)),
        opacity: m.dissolve.map_or(1.0, |d| if d.is_finite() { d.clamp(0.0, 1.0) } else { 1.0 }),
        emission: m.emissive.map_or(Vec3::ZERO, |e| Vec3::from_array(e).max(Vec3::ZERO)),
        layers,
        bump,
        normal_map: map(&m.unknown_param.get("norm").cloned(), false)?.map(|(texture, _)| texture),
    })
}

/// A texture statement of an .mtl: `[options] file`.
#[derive(Debug)]
struct MapSpec {
    file: PathBuf,
    /// `-bm`: the bump multiplier.
    bump_multiplier: f32,
    /// `-o` and `-s`: offset and scale of (u, v).
    transform: UvTransform,
    /// `-clamp on`.
    clamp: bool,
}

impl MapSpec {
    fn parse(spec: &str, dir: &Path) -> std::result::Result<MapSpec, String> {
        let words: Vec<&str> = spec.split_whitespace().collect();
        let (mut bump_multiplier, mut offset, mut scale, mut clamp) = (1.0, Vec2::ZERO, Vec2::ONE, false);
        let mut k = 0;
        let number = |w: Option<&&str>, option: &str| -> std::result::Result<f32, String> {
            w.and_then(|w| w.parse::<f32>().ok())
                .filter(|x| x.is_finite())
                .ok_or_else(|| format!("texture option {option} needs a number"))
        };
        while k + 1 < words.len() && words[k].starts_with('-') {
            let option = words[k];
            // Up to three numbers follow -o and -s; the others take a fixed count.
            let numbers = |k: usize| {
                (1..=3)
                    .take_while(|&i| {
                        words.get(k + i).is_some_and(|w| w.parse::<f32>().is_ok()) && k + i + 1 < words.len()
                    })
                    .count()
            };
            match option {
                "-bm" => {
                    bump_multiplier = number(words.get(k + 1), option)?;
                    k += 2;
                }
                "-o" | "-s" => {
                    let n = numbers(k);
                    if n == 0 {
                        return Err(format!("texture option {option} needs numbers"));
                    }
                    let x = number(words.get(k + 1), option)?;
                    let y = if n >= 2 { number(words.get(k + 2), option)? } else { x };
                    if option == "-o" {
                        offset = Vec2::new(x, y);
                    } else {
                        scale = Vec2::new(x, y);
                    }
                    k += 1 + n;
                }
                "-clamp" => {
                    clamp = words[k + 1] == "on";
                    k += 2;
                }
                "-blendu" | "-blendv" | "-cc" | "-imfchan" | "-type" | "-texres" | "-boost" => k += 2,
                "-mm" => k += 3,
                "-t" => k += 1 + numbers(k),
                other => return Err(format!("unknown texture option {other}")),
            }
        }
        // An option's arguments may run past the end (`-mm 0` with nothing after it).
        let file = words.get(k..).map_or_else(String::new, |rest| rest.join(" "));
        if file.is_empty() {
            return Err("a texture statement names no file".into());
        }
        if scale.min_element() <= 0.0 {
            return Err("texture option -s needs positive scales".into());
        }
        Ok(MapSpec { file: dir.join(file), bump_multiplier, transform: UvTransform::new(offset, 0.0, scale), clamp })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn texture_statements_with_options() {
        let d = Path::new("/m");
        let s = MapSpec::parse("-bm 0.5 bricks.png", d).unwrap();
        assert_eq!((s.file, s.bump_multiplier, s.clamp), (PathBuf::from("/m/bricks.png"), 0.5, false));
        let s = MapSpec::parse("-s 2 3 1 -o 0.5 -clamp on my map.png", d).unwrap();
        assert_eq!(s.file, PathBuf::from("/m/my map.png"));
        assert_eq!(s.transform, UvTransform::new(Vec2::new(0.5, 0.5), 0.0, Vec2::new(2.0, 3.0)));
        assert!(s.clamp);
        assert!(MapSpec::parse("-bogus 1 a.png", d).unwrap_err().contains("-bogus"));
        assert!(MapSpec::parse("-bm x a.png", d).unwrap_err().contains("-bm"));
    }
}
