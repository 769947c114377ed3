//! Model files: OBJ (with its .mtl) and glTF 2.0 (.gltf, .glb), by their extension.

use crate::geometry::TriangleMesh;
use crate::shade::Material;
use crate::{Error, Result};
use std::path::Path;

/// One mesh of a model file with the material the file gives it.
pub struct ModelPart {
    pub mesh: TriangleMesh,
    pub material: Material,
    /// Drawn from both sides, else back faces are culled.
    pub two_sided: bool,
}

/// The meshes of a model file, in object space.
pub fn load(path: &Path) -> Result<Vec<ModelPart>> {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("obj") => super::obj::load(path),
        Some("gltf" | "glb") => super::gltf::load(path),
        _ => Err(Error::read(path, "expected a model file ending in .obj, .gltf or .glb")),
    }
}
