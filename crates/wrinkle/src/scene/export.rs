//! A scene's geometry as a Wavefront OBJ model: every parametric surface tessellated into a grid of
//! triangles with its exact normals and (u,v), every mesh as it was read, each placed by its object's
//! transform into world space. What the teapot's mesh in scenes/models/ was made with.
//!
//! Positions equal bit for bit are written once and shared (OBJ indexes positions, texture coordinates
//! and normals separately), so the edges where Newell's patches meet stay watertight in the model; each
//! patch keeps its own (u,v) and normals. Materials stay in the scene file.

use super::Scene;
use crate::geometry::tessellate::{triangle_mesh, MAX_SEGMENTS};
use crate::geometry::{Primitive, TriangleMesh};
use crate::{Error, Result};
use std::collections::HashMap;
use std::fmt::Write as _;

impl Scene {
    /// The triangle meshes of every object in world space, one per primitive, each named by its object
    /// (`object_3`, `object_3_2` for the third primitive of a box or model). Parametric surfaces become
    /// `segments` x `segments` quads.
    pub fn world_meshes(&self, segments: usize) -> Result<Vec<(String, TriangleMesh)>> {
        if !(1..=MAX_SEGMENTS).contains(&segments) {
            return Err(Error::Invalid(format!("segments must be between 1 and {MAX_SEGMENTS}, got {segments}")));
        }
        let mut meshes = Vec::new();
        for (k, object) in self.objects.iter().enumerate() {
            let primitives = object.shape.primitives();
            let several = primitives.len() > 1;
            for (p, primitive) in primitives.into_iter().enumerate() {
                let mesh = match primitive {
                    Primitive::Parametric(surface) => triangle_mesh(&surface, segments, segments),
                    Primitive::Mesh(mesh) => (*mesh).clone(),
                };
                let name = if several { format!("object_{k}_{p}") } else { format!("object_{k}") };
                meshes.push((name, mesh.transformed(&object.transform.matrix())));
            }
        }
        Ok(meshes)
    }

    /// The scene's geometry as OBJ text (see the module's documentation).
    pub fn to_obj(&self, segments: usize) -> Result<String> {
        Ok(write_obj(&self.world_meshes(segments)?, "wrinkle tessellate"))
    }
}

/// OBJ text of named meshes: shared positions, then per mesh its texture coordinates (set 0), normals
/// and faces. Numbers in Rust's shortest form that reads back to the same f32. The first line names `tool`.
pub fn write_obj(meshes: &[(String, TriangleMesh)], tool: &str) -> String {
    let mut out = format!("# Written by {tool}: positions shared where bit for bit equal.\n");
    let mut index: HashMap<[u32; 3], usize> = HashMap::new();
    let mut position_of = Vec::with_capacity(meshes.len());
    for (_, mesh) in meshes {
        let ids: Vec<usize> = mesh
            .positions
            .iter()
            .map(|p| {
                let next = index.len() + 1;
                *index.entry(p.to_array().map(f32::to_bits)).or_insert_with(|| {
                    let _ = writeln!(out, "v {} {} {}", p.x, p.y, p.z);
                    next
                })
            })
            .collect();
        position_of.push(ids);
    }
    let (mut uv_base, mut normal_base) = (1, 1);
    for ((name, mesh), ids) in meshes.iter().zip(&position_of) {
        let _ = writeln!(out, "o {name}");
        let uvs = mesh.uvs(0).unwrap_or(&[]);
        for uv in uvs {
            let _ = writeln!(out, "vt {} {}", uv.x, uv.y);
        }
        for n in &mesh.normals {
            let _ = writeln!(out, "vn {} {} {}", n.x, n.y, n.z);
        }
        for t in &mesh.triangles {
            out.push('f');
            for &k in t {
                let k = k as usize;
                let _ = match (uvs.is_empty(), mesh.normals.is_empty()) {
                    (false, false) => write!(out, " {}/{}/{}", ids[k], uv_base + k, normal_base + k),
                    (false, true) => write!(out, " {}/{}", ids[k], uv_base + k),
                    (true, false) => write!(out, " {}//{}", ids[k], normal_base + k),
                    (true, true) => write!(out, " {}", ids[k]),
                };
            }
            out.push('\n');
        }
        uv_base += uvs.len();
        normal_base += mesh.normals.len();
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    #[test]
    fn shared_positions_are_written_once_and_faces_index_them() {
        // Two patches meeting along x = 1: their common edge is two positions, written once.
        let text = "[camera]\neye = [0.0, 0.0, 5.0]\nlook_at = [0.0, 0.0, 0.0]\n\
            [[object]]\nshape = \"patch\"\ncorners = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]]\n\
            [[object]]\nshape = \"patch\"\ncorners = [[1.0, 0.0, 0.0], [2.0, 0.0, 0.0], [2.0, 1.0, 0.0], [1.0, 1.0, 0.0]]\n";
        let scene = Scene::parse(text, Path::new(".")).unwrap();
        let obj = scene.to_obj(1).unwrap();
        let count = |prefix: &str| obj.lines().filter(|l| l.starts_with(prefix)).count();
        assert_eq!((count("v "), count("vt "), count("vn "), count("f "), count("o ")), (6, 8, 8, 4, 2), "{obj}");
        assert!(obj.contains("o object_1\n"));
        // The second patch's first triangle starts at (1, 0, 0), the first patch's second position.
        let second = obj.split("o object_1\n").nth(1).unwrap();
        let face = second.lines().find(|l| l.starts_with("f ")).unwrap();
        assert_eq!(face, "f 2/5/5 5/6/6 6/8/8", "{obj}");
        assert!(scene.to_obj(0).is_err() && scene.to_obj(MAX_SEGMENTS + 1).is_err());
    }
}
