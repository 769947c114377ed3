//! glTF 2.0 models (.gltf with its buffers and images, or one .glb) through the `gltf` crate: the default
//! scene's node hierarchy with every node's transform baked into its meshes, each primitive with its
//! material: baseColorFactor and baseColorTexture, normalTexture with its scale, the samplers' wrap and
//! filter modes, KHR_texture_transform (on the base colour and the normal texture), doubleSided. Texture coordinates are flipped into the project's
//! convention (v up): glTF's v runs down the image.

use super::contain::contain_panics;
use super::model::ModelPart;
use super::texture::Source;
use crate::bump::normal_map::Convention;
use crate::bump::TangentNormalMap;
use crate::geometry::TriangleMesh;
use crate::image::color::srgb_to_linear;
use crate::image::Image;
use crate::mapping::{MappedTexture, Mapping, Projection, UvTransform};
use crate::shade::{AlphaMode, Layer, Material, Phong, Target};
use crate::texture::reconstruct::Kernel;
use crate::texture::{Filter, FilterOptions, FilteredTexture, Texture, TextureOptions, Wrap};
use crate::{Error, Result};
use glam::{Affine3A, Mat4, Vec2, Vec3, Vec4};
use gltf::image::Format;
use gltf::mesh::Mode;
use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

/// Every primitive of the file's default scene (or its first), placed by its node's world transform.
pub fn load(path: &Path) -> Result<Vec<ModelPart>> {
    contain_panics(|| load_checked(path))
        .unwrap_or_else(|panic| Err(Error::read(path, format!("malformed glTF: the gltf crate failed on it: {panic}"))))
}

fn load_checked(path: &Path) -> Result<Vec<ModelPart>> {
    let (document, buffers, images) = import(path)?;
    let fail = |m: String| Error::read(path, m);
    let scene =
        document.default_scene().or_else(|| document.scenes().next()).ok_or_else(|| fail("has no scene".into()))?;
    let mut textures = Textures { images: &images, cache: HashMap::new() };
    let mut parts = Vec::new();
    let mut stack: Vec<(gltf::Node, Mat4)> = scene.nodes().map(|n| (n, Mat4::IDENTITY)).collect();
    while let Some((node, parent)) = stack.pop() {
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        stack.extend(node.children().map(|c| (c, world)));
        let Some(mesh) = node.mesh() else { continue };
        let name = mesh.name().map_or_else(|| format!("mesh {}", mesh.index()), |n| format!("mesh \"{n}\""));
        for primitive in mesh.primitives() {
            let what = format!("{name}, primitive {}", primitive.index());
            if primitive.mode() != Mode::Triangles {
                return Err(fail(format!("{what}: only triangle lists are drawn, not {:?}", primitive.mode())));
            }
            let reader = primitive.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
            let positions: Vec<Vec3> = reader
                .read_positions()
                .ok_or_else(|| fail(format!("{what} has no POSITION")))?
                .map(Vec3::from_array)
                .collect();
            let triangles: Vec<[u32; 3]> = match reader.read_indices() {
                Some(indices) => {
                    let flat: Vec<u32> = indices.into_u32().collect();
                    if !flat.len().is_multiple_of(3) {
                        return Err(fail(format!("{what}: {} indices are not whole triangles", flat.len())));
                    }
                    flat.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect()
                }
                None => (0..positions.len() as u32 / 3).map(|t| [3 * t, 3 * t + 1, 3 * t + 2]).collect(),
            };
            let flip = |uv: [f32; 2]| Vec2::new(uv[0], 1.0 - uv[1]);
            let uv_sets: Vec<Vec<Vec2>> =
                (0..2).map_while(|set| reader.read_tex_coords(set).map(|t| t.into_f32().map(flip).collect())).collect();
            let mut m = TriangleMesh {
                positions,
                normals: reader.read_normals().map_or_else(Vec::new, |n| n.map(Vec3::from_array).collect()),
                uv_sets,
                tangents: reader.read_tangents().map_or_else(Vec::new, |t| t.map(Vec4::from_array).collect()),
                triangles,
            };
            m.validate().map_err(|e| fail(format!("{what} {e}")))?;
            m.complete_normals();
            let gm = primitive.material();
            let material = material(&gm, &mut textures).map_err(|e| fail(format!("{what}: {e}")))?;
            let transform = Affine3A::from_mat4(world);
            parts.push(ModelPart { mesh: m.transformed(&transform), material, two_sided: gm.double_sided() });
        }
    }
    if parts.is_empty() {
        return Err(fail("has no meshes in its scene".into()));
    }
    Ok(parts)
}

/// `gltf::import` with what it does not check first: the file and every file it names must be regular files
/// (a buffer at /dev/zero would be read forever), and every primitive's attributes must name accessors that
/// exist (gltf-json's validation indexes POSITION's accessor unchecked).
fn import(path: &Path) -> Result<(gltf::Document, Vec<gltf::buffer::Data>, Vec<gltf::image::Data>)> {
    use gltf::json::accessor::ComponentType;
    use gltf::json::mesh::Semantic;
    use gltf::json::validation::{Checked, Validate};
    crate::image::io::check_input(path)?;
    let bytes = std::fs::read(path).map_err(|e| Error::read(path, crate::image::io::open_message(&e)))?;
    let fail = |m: String| Error::read(path, m);
    let gltf = gltf::Gltf::from_slice_without_validation(&bytes).map_err(|e| fail(gltf_error(&e)))?;
    let root = gltf.document.as_json();
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            if let Some((_, index)) = primitive.attributes.iter().find(|(_, a)| a.value() >= root.accessors.len()) {
                return Err(fail(format!(
                    "malformed glTF: meshes[{m}].primitives[{p}] names accessor {}, of {}",
                    index.value(),
                    root.accessors.len()
                )));
            }
            // The reader reaches `unreachable!` on component types the specification does not allow here.
            let component = |a: usize| match root.accessors.get(a).map(|a| &a.component_type) {
                Some(Checked::Valid(t)) => Some(t.0),
                _ => None,
            };
            let allowed = |a: usize, kinds: &[ComponentType]| component(a).is_none_or(|t| kinds.contains(&t));
            for (semantic, index) in &primitive.attributes {
                if let Checked::Valid(Semantic::TexCoords(set)) = semantic {
                    if !allowed(index.value(), &[ComponentType::U8, ComponentType::U16, ComponentType::F32]) {
                        return Err(fail(format!(
                            "malformed glTF: meshes[{m}].primitives[{p}]: TEXCOORD_{set} must be unsigned bytes, shorts or floats"
                        )));
                    }
                }
            }
            if let Some(indices) = &primitive.indices {
                if !allowed(indices.value(), &[ComponentType::U8, ComponentType::U16, ComponentType::U32]) {
                    return Err(fail(format!(
                        "malformed glTF: meshes[{m}].primitives[{p}]: indices must be unsigned bytes, shorts or ints"
                    )));
                }
            }
        }
    }
    // The specification's rule the gltf crate unwraps unchecked: an image is a bufferView with a mimeType,
    // or a uri.
    for (k, image) in root.images.iter().enumerate() {
        let complete = if image.buffer_view.is_some() { image.mime_type.is_some() } else { image.uri.is_some() };
        if !complete {
            return Err(fail(format!("malformed glTF: images[{k}] needs a uri, or a bufferView and a mimeType")));
        }
    }
    let mut problem = None;
    root.validate(root, gltf::json::Path::new, &mut |at, error| {
        problem.get_or_insert_with(|| format!("malformed glTF: {}: {error}", at()));
    });
    if let Some(problem) = problem {
        return Err(fail(problem));
    }
    let base = path.parent().unwrap_or(Path::new("."));
    let uris =
        root.buffers.iter().filter_map(|b| b.uri.as_deref()).chain(root.images.iter().filter_map(|i| i.uri.as_deref()));
    for uri in uris.filter(|u| !u.starts_with("data:") && !u.contains("://")) {
        let file = base.join(uri);
        if file.exists() {
            crate::image::io::check_input(&file).map_err(|e| fail(format!("the file it names: {e}")))?;
        }
    }
    let gltf::Gltf { document, blob } = gltf;
    let buffers = gltf::import_buffers(&document, Some(base), blob).map_err(|e| fail(gltf_error(&e)))?;
    let images = gltf::import_images(&document, Some(base), &buffers).map_err(|e| fail(gltf_error(&e)))?;
    Ok((document, buffers, images))
}

fn gltf_error(e: &gltf::Error) -> String {
    match e {
        gltf::Error::Io(io) if io.kind() == std::io::ErrorKind::NotFound => "no such file (or one it refers to)".into(),
        other => format!("malformed glTF: {other}"),
    }
}

/// The file's images as textures, each built once per colour space and sampler.
struct Textures<'a> {
    images: &'a [gltf::image::Data],
    cache: HashMap<(usize, bool, Option<usize>), Arc<dyn Texture>>,
}

impl Textures<'_> {
    /// The texture of `info` with its sampler and texture transform; `srgb` for colour.
    fn get(
        &mut self,
        texture: gltf::Texture,
        tex_coord: u32,
        transform: Option<TextureTransform>,
        srgb: bool,
    ) -> std::result::Result<Source, String> {
        let set = transform.as_ref().and_then(|t| t.tex_coord).unwrap_or(tex_coord);
        if set > 1 {
            return Err(format!(
                "texture {} reads TEXCOORD_{set}; TEXCOORD_0 and TEXCOORD_1 are drawn",
                texture.index()
            ));
        }
        let sampler = texture.sampler();
        let image = texture.source().index();
        let data = self.images.get(image).ok_or_else(|| format!("image {image} is missing"))?;
        let rgba = matches!(
            data.format,
            Format::R8G8 | Format::R16G16 | Format::R8G8B8A8 | Format::R16G16B16A16 | Format::R32G32B32A32FLOAT
        );
        let key = (image, srgb, sampler.index());
        let built = match self.cache.get(&key) {
            Some(t) => t.clone(),
            None => {
                let options = TextureOptions {
                    wrap: [wrap(sampler.wrap_s()), wrap(sampler.wrap_t())],
                    filter: FilterOptions { filter: filter(sampler.min_filter()), ..FilterOptions::default() },
                    ..TextureOptions::default()
                };
                let t: Arc<dyn Texture> = Arc::new(texture_of(data, srgb, options)?);
                self.cache.insert(key, t.clone());
                t
            }
        };
        let uv = transform.map_or(UvTransform::IDENTITY, |t| t.uv_transform());
        let projection = if set == 1 { Projection::SecondUv } else { Projection::Uv };
        Ok(Source {
            mapped: MappedTexture { texture: built, mapping: Mapping { projection, ..Mapping::uv(uv) } },
            rgba,
        })
    }
}

/// A texture reference's KHR_texture_transform: the gltf crate reads it on `textureInfo`s, wrinkle reads
/// it from the JSON on the normal texture, where the crate does not.
struct TextureTransform {
    offset: [f32; 2],
    rotation: f32,
    scale: [f32; 2],
    tex_coord: Option<u32>,
}

impl TextureTransform {
    fn of_info(t: gltf::texture::TextureTransform) -> TextureTransform {
        TextureTransform { offset: t.offset(), rotation: t.rotation(), scale: t.scale(), tex_coord: t.tex_coord() }
    }

    /// The extension's JSON object; its members as the specification types them, with its defaults.
    fn of_json(v: &gltf::json::Value) -> std::result::Result<TextureTransform, String> {
        let bad = |member: &str| format!("normalTexture's KHR_texture_transform has a malformed {member}");
        let object = v.as_object().ok_or_else(|| bad("object"))?;
        let pair = |member: &str, default: [f32; 2]| match object.get(member) {
            None => Ok(default),
            Some(v) => match v.as_array().map(|a| a.iter().map(|x| x.as_f64()).collect::<Vec<_>>()).as_deref() {
                Some([Some(a), Some(b)]) => Ok([*a as f32, *b as f32]),
                _ => Err(bad(member)),
            },
        };
        let rotation = match object.get("rotation") {
            None => 0.0,
            Some(v) => v.as_f64().ok_or_else(|| bad("rotation"))? as f32,
        };
        let tex_coord = match object.get("texCoord") {
            None => None,
            Some(v) => Some(v.as_u64().and_then(|k| u32::try_from(k).ok()).ok_or_else(|| bad("texCoord"))?),
        };
        let t = TextureTransform {
            offset: pair("offset", [0.0; 2])?,
            rotation,
            scale: pair("scale", [1.0; 2])?,
            tex_coord,
        };
        if t.offset.iter().chain(&t.scale).chain([&t.rotation]).any(|x| !x.is_finite()) {
            return Err(bad("number (out of range)"));
        }
        Ok(t)
    }

    /// st = T R S uv in glTF's coordinates (v down, rotation clockwise on the image), carried into the
    /// project's (v up): s = x + sin(r) sy + cos(r) sx u - sin(r) sy v,
    /// t = 1 - y - cos(r) sy + sin(r) sx u + cos(r) sy v, a counter-clockwise rotation by r.
    fn uv_transform(&self) -> UvTransform {
        let (sin, cos) = self.rotation.sin_cos();
        let o = Vec2::new(self.offset[0] + sin * self.scale[1], 1.0 - self.offset[1] - cos * self.scale[1]);
        UvTransform::new(o, self.rotation.to_degrees(), Vec2::from_array(self.scale))
    }
}

fn wrap(w: gltf::texture::WrappingMode) -> Wrap {
    match w {
        gltf::texture::WrappingMode::ClampToEdge => Wrap::Clamp,
        gltf::texture::WrappingMode::MirroredRepeat => Wrap::Mirror,
        gltf::texture::WrappingMode::Repeat => Wrap::Repeat,
    }
}

/// The sampler's minification filter as one of ours: no MIP maps reconstruct, a MIP filter is trilinear
/// (the best a viewer without anisotropy draws; `filter` in the scene picks any other).
fn filter(min: Option<gltf::texture::MinFilter>) -> Filter {
    use gltf::texture::MinFilter as M;
    match min {
        Some(M::Nearest) => Filter::Reconstruct(Kernel::Nearest),
        Some(M::Linear) => Filter::Reconstruct(Kernel::Bilinear),
        Some(M::NearestMipmapNearest | M::LinearMipmapNearest) => Filter::MipNearest,
        _ => Filter::Trilinear,
    }
}

/// A decoded image as a texture: 8-bit formats stay 8-bit, 16-bit and float ones become linear f32.
fn texture_of(
    data: &gltf::image::Data,
    srgb: bool,
    options: TextureOptions,
) -> std::result::Result<FilteredTexture, String> {
    let (w, h) = (data.width as usize, data.height as usize);
    let channels = match data.format {
        Format::R8 | Format::R16 => 1,
        Format::R8G8 | Format::R16G16 => 2,
        Format::R8G8B8 | Format::R16G16B16 | Format::R32G32B32FLOAT => 3,
        Format::R8G8B8A8 | Format::R16G16B16A16 | Format::R32G32B32A32FLOAT => 4,
    };
    // Grey is spread to RGB; grey and alpha keeps its alpha.
    let rgba = |c: &[f32], one: f32| match channels {
        1 => [c[0], c[0], c[0], one],
        2 => [c[0], c[0], c[0], c[1]],
        3 => [c[0], c[1], c[2], one],
        _ => [c[0], c[1], c[2], c[3]],
    };
    match data.format {
        Format::R8 | Format::R8G8 | Format::R8G8B8 | Format::R8G8B8A8 => {
            let px: Vec<[u8; 4]> = data
                .pixels
                .chunks_exact(channels)
                .map(|c| {
                    let f: Vec<f32> = c.iter().map(|&b| b as f32).collect();
                    rgba(&f, 255.0).map(|x| x as u8)
                })
                .collect();
            check_size(&px, w, h)?;
            Ok(FilteredTexture::from_rgba8(&Image { width: w, height: h, pixels: px }, srgb, options))
        }
        _ => {
            let values: Vec<f32> = match data.format {
                Format::R32G32B32FLOAT | Format::R32G32B32A32FLOAT => {
                    data.pixels.chunks_exact(4).map(|b| f32::from_ne_bytes([b[0], b[1], b[2], b[3]])).collect()
                }
                _ => data.pixels.chunks_exact(2).map(|b| u16::from_ne_bytes([b[0], b[1]]) as f32 / 65535.0).collect(),
            };
            let px: Vec<[f32; 4]> = values
                .chunks_exact(channels)
                .map(|c| {
                    let [r, g, b, a] = rgba(c, 1.0);
                    let decode = |x: f32| if srgb { srgb_to_linear(x) } else { x };
                    [decode(r), decode(g), decode(b), a]
                })
                .collect();
            check_size(&px, w, h)?;
            Ok(FilteredTexture::new(&Image { width: w, height: h, pixels: px }, options))
        }
    }
}

fn check_size<T>(px: &[T], w: usize, h: usize) -> std::result::Result<(), String> {
    if w == 0 || h == 0 || px.len() != w * h {
        return Err(format!("an image of {w}x{h} pixels holds {} pixels", px.len()));
    }
    Ok(())
}

/// A glTF material as Blinn-Phong: the base colour (factor times texture, alpha too) with its alpha mode
/// and cutoff, the normal map with its scale; metallic-roughness has no Blinn-Phong counterpart and is left
/// out.
fn material(m: &gltf::Material, textures: &mut Textures) -> std::result::Result<Material, String> {
    let pbr = m.pbr_metallic_roughness();
    let [r, g, b, a] = pbr.base_color_factor();
    let mut layers = Vec::new();
    if let Some(info) = pbr.base_color_texture() {
        let transform = info.texture_transform().map(TextureTransform::of_info);
        let source = textures.get(info.texture(), info.tex_coord(), transform, true)?;
        layers.push(Layer::modulate(source.mapped, Target::Kd, source.rgba));
    }
    // Emission: emissiveFactor x emissiveTexture (sRGB, its alpha unused) x KHR_materials_emissive_strength.
    if let Some(info) = m.emissive_texture() {
        let transform = info.texture_transform().map(TextureTransform::of_info);
        let source = textures.get(info.texture(), info.tex_coord(), transform, true)?;
        layers.push(Layer::modulate(source.mapped, Target::Emission, false));
    }
    let strength = match m.extension_value("KHR_materials_emissive_strength") {
        None => 1.0,
        Some(v) => v
            .get("emissiveStrength")
            .map_or(Some(1.0), |s| s.as_f64().filter(|s| s.is_finite() && *s >= 0.0))
            .ok_or("KHR_materials_emissive_strength has a malformed emissiveStrength")? as f32,
    };
    let normal_map = match m.normal_texture() {
        Some(n) => {
            let transform = n.extension_value("KHR_texture_transform").map(TextureTransform::of_json).transpose()?;
            let texture = textures.get(n.texture(), n.tex_coord(), transform, false)?.mapped;
            Some(TangentNormalMap::new(texture, n.scale(), Convention::OpenGl))
        }
        None => None,
    };
    let alpha_mode = match m.alpha_mode() {
        gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
        gltf::material::AlphaMode::Mask => AlphaMode::Mask { cutoff: m.alpha_cutoff().unwrap_or(0.5) },
        gltf::material::AlphaMode::Blend => AlphaMode::Blend,
    };
    Ok(Material {
        color: Vec3::new(r, g, b),
        opacity: a,
        emission: (Vec3::from_array(m.emissive_factor()) * strength).max(Vec3::ZERO),
        layers,
        alpha_mode,
        phong: Phong::new(0.04, 40.0),
        normal_map,
        ..Material::default()
    })
}
