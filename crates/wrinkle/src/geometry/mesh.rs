//! Triangle meshes brought by the user (OBJ, glTF): positions, unit vertex normals, texture coordinates and
//! tangents, in object space. Missing normals are computed (each face's normal weighted by its angle at the
//! vertex); missing tangents by MikkTSpace, so normal maps baked by Blender or Substance shade as they do
//! there.
//!
//! Texture coordinates follow the project's convention, v up: loaders of v-down formats (glTF) flip them.

use crate::limits::Limit;
use glam::{Affine3A, Mat3, Vec2, Vec3, Vec4};

#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriangleMesh {
    pub positions: Vec<Vec3>,
    /// Unit normals, one per vertex.
    pub normals: Vec<Vec3>,
    /// Texture coordinate sets (TEXCOORD_0, TEXCOORD_1, ...), one entry per vertex each.
    pub uv_sets: Vec<Vec<Vec2>>,
    /// Unit tangents along +u of the set the normal map reads, w = +1 or -1: the bitangent is w (N x T).
    /// Empty until a normal map needs them.
    pub tangents: Vec<Vec4>,
    /// Counter-clockwise seen from the front.
    pub triangles: Vec<[u32; 3]>,
}

impl TriangleMesh {
    /// Checks what a loader read: at least one triangle, every index in range, finite positions, texture
    /// coordinates and normals matching the vertex count. The message names what is wrong.
    pub fn validate(&self) -> Result<(), String> {
        let n = self.positions.len();
        if self.triangles.is_empty() {
            return Err("has no triangles".into());
        }
        let most = Limit::Triangles.count();
        if self.triangles.len() > most {
            return Err(format!(
                "has {} triangles, more than the {most} allowed ({})",
                self.triangles.len(),
                Limit::Triangles.hint()
            ));
        }
        if let Some((t, tri)) = self.triangles.iter().enumerate().find(|(_, t)| t.iter().any(|&k| k as usize >= n)) {
            return Err(format!("triangle {t} has a vertex index out of range ({tri:?}, {n} vertices)"));
        }
        if let Some(k) = self.positions.iter().position(|p| !p.is_finite()) {
            return Err(format!("vertex {k} has a position that is not a finite number"));
        }
        for (name, len) in [("normals", self.normals.len()), ("tangents", self.tangents.len())] {
            if len != 0 && len != n {
                return Err(format!("has {len} {name} for {n} vertices"));
            }
        }
        if let Some((set, uvs)) = self.uv_sets.iter().enumerate().find(|(_, s)| s.len() != n) {
            return Err(format!("texture coordinate set {set} has {} entries for {n} vertices", uvs.len()));
        }
        if self.uv_sets.iter().flatten().any(|uv| !uv.is_finite()) {
            return Err("has texture coordinates that are not finite numbers".into());
        }
        Ok(())
    }

    /// Unit vertex normals from the faces around each vertex, each face's unit normal weighted by its angle
    /// at the vertex (Thürmer and Wüthrich 1998): independent of how the faces around a vertex are split.
    pub fn compute_normals(&mut self) {
        let mut sum = vec![Vec3::ZERO; self.positions.len()];
        for t in &self.triangles {
            let p = t.map(|k| self.positions[k as usize]);
            let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
            for c in 0..3 {
                let (a, b) = (p[(c + 1) % 3] - p[c], p[(c + 2) % 3] - p[c]);
                sum[t[c] as usize] += n * a.angle_between(b);
            }
        }
        self.normals = sum.into_iter().map(|n| n.try_normalize().unwrap_or(Vec3::Z)).collect();
    }

    /// The normals a loader needs: computed from the faces where the file has none, else `repair_normals`.
    pub fn complete_normals(&mut self) {
        if self.normals.is_empty() {
            self.compute_normals();
        } else {
            self.repair_normals();
        }
    }

    /// Replaces non-unit and non-finite normals from a file: they are normalised, and zero or NaN ones
    /// are recomputed from the faces.
    fn repair_normals(&mut self) {
        if self.normals.iter().any(|n| n.try_normalize().is_none()) {
            let given = std::mem::take(&mut self.normals);
            self.compute_normals();
            for (n, g) in self.normals.iter_mut().zip(given) {
                if let Some(g) = g.try_normalize() {
                    *n = g;
                }
            }
        } else {
            self.normals.iter_mut().for_each(|n| *n = n.normalize());
        }
    }

    /// MikkTSpace tangents for the texture coordinates of set `uv_set`. MikkTSpace gives each corner of a
    /// triangle its own tangent, so the mesh is split into three vertices per triangle first (the tangents
    /// of corners that share a vertex may differ across a uv seam or a mirror). False when the mesh has no
    /// such coordinates.
    ///
    /// mikktspace 0.3 is C translated to Rust and trusts its input as the C did: it reads freed memory
    /// when every triangle is degenerate (a count of the others runs below zero) and indexes past its cell
    /// table when the mesh's box is flat in every direction or wider than f32 holds. So it only sees the
    /// triangles with three distinct corners (the others cover no pixel and keep the default tangent), a
    /// huge mesh scaled down exactly by a power of two.
    pub fn generate_tangents(&mut self, uv_set: usize) -> bool {
        if uv_set >= self.uv_sets.len() {
            return false;
        }
        let original: Vec<u32> = self.triangles.iter().flatten().copied().collect();
        self.split_corners();
        let (min, max) = self.bounds();
        let extent = (max.as_dvec3() - min.as_dvec3()).max_element();
        // Beyond 2^30 its squared cross products overflow f32.
        let scale = if extent > (1u64 << 30) as f64 { 0.5f32.powi(extent.log2().ceil() as i32) } else { 1.0 };
        let faces: Vec<usize> = (0..self.triangles.len())
            .filter(|&t| {
                let [a, b, c] = [0, 1, 2].map(|k| self.positions[3 * t + k] * scale);
                a != b && a != c && b != c
            })
            .collect();
        let mut tangents = vec![Vec4::new(1.0, 0.0, 0.0, 1.0); self.positions.len()];
        if !faces.is_empty() {
            let mut corners = Corners { mesh: self, faces, uv_set, scale, tangents };
            if !mikktspace::generate_tangents(&mut corners) {
                return false;
            }
            tangents = corners.tangents;
        }
        self.tangents = tangents;
        self.weld(&original);
        true
    }

    /// Merges the corners of each vertex of the mesh before `split_corners` (`original`, per corner) that
    /// MikkTSpace gave the same tangent, bit for bit, so a smooth mesh is back to one vertex per corner
    /// shared by its triangles: fewer to project per frame. The corners of one vertex differ only in their
    /// tangents, so those alone are compared, along a short list per vertex: no hashing of whole vertices
    /// (BENCHMARKS.md, "Meshes").
    fn weld(&mut self, original: &[u32]) {
        const NONE: u32 = u32::MAX;
        let vertices = original.iter().map(|&o| o as usize + 1).max().unwrap_or(0);
        let (mut first, mut next, mut keep) = (vec![NONE; vertices], Vec::new(), Vec::<usize>::new());
        let bits = |t: Vec4| t.to_array().map(f32::to_bits);
        let remap: Vec<u32> = (0..self.positions.len())
            .map(|k| {
                let o = original[k] as usize;
                let mut at = first[o];
                while at != NONE {
                    if bits(self.tangents[keep[at as usize]]) == bits(self.tangents[k]) {
                        return at;
                    }
                    at = next[at as usize];
                }
                let made = keep.len() as u32;
                keep.push(k);
                next.push(first[o]);
                first[o] = made;
                made
            })
            .collect();
        let pick = |v: &Vec<Vec3>| keep.iter().map(|&k| v[k]).collect::<Vec<_>>();
        self.positions = pick(&self.positions);
        self.normals = pick(&self.normals);
        for set in &mut self.uv_sets {
            *set = keep.iter().map(|&k| set[k]).collect();
        }
        self.tangents = keep.iter().map(|&k| self.tangents[k]).collect();
        for t in &mut self.triangles {
            *t = t.map(|k| remap[k as usize]);
        }
    }

    /// Three vertices of its own for every triangle.
    fn split_corners(&mut self) {
        let order: Vec<usize> = self.triangles.iter().flatten().map(|&k| k as usize).collect();
        let pick = |v: &Vec<Vec3>| order.iter().map(|&k| v[k]).collect::<Vec<_>>();
        self.positions = pick(&self.positions);
        self.normals = pick(&self.normals);
        for set in &mut self.uv_sets {
            *set = order.iter().map(|&k| set[k]).collect();
        }
        if !self.tangents.is_empty() {
            self.tangents = order.iter().map(|&k| self.tangents[k]).collect();
        }
        self.triangles = (0..self.triangles.len() as u32).map(|t| [3 * t, 3 * t + 1, 3 * t + 2]).collect();
    }

    /// The mesh carried by `m` (a node's transform baked into its vertices): normals by the inverse
    /// transpose, tangents by `m` itself; a mirroring transform reverses the winding so fronts stay fronts.
    pub fn transformed(&self, m: &Affine3A) -> TriangleMesh {
        let linear = Mat3::from(m.matrix3);
        let normal_matrix = linear.inverse().transpose();
        let mirrored = linear.determinant() < 0.0;
        TriangleMesh {
            positions: self.positions.iter().map(|&p| m.transform_point3(p)).collect(),
            normals: self.normals.iter().map(|&n| (normal_matrix * n).normalize_or_zero()).collect(),
            uv_sets: self.uv_sets.clone(),
            tangents: self
                .tangents
                .iter()
                .map(|t| (linear * t.truncate()).normalize_or_zero().extend(if mirrored { -t.w } else { t.w }))
                .collect(),
            triangles: if mirrored {
                self.triangles.iter().map(|&[a, b, c]| [a, c, b]).collect()
            } else {
                self.triangles.clone()
            },
        }
    }

    /// The corners of the box around the positions (infinite and inverted for a mesh without any).
    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.positions.iter().fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &p| (lo.min(p), hi.max(p)))
    }

    /// `other`'s triangles added to this mesh (one model of several parts). Vertex data the two do not
    /// both have (normals, tangents, texture coordinate sets) are dropped.
    pub fn append(&mut self, other: &TriangleMesh) {
        if self.positions.is_empty() {
            *self = other.clone();
            return;
        }
        let base = self.positions.len() as u32;
        join(&mut self.normals, &other.normals);
        join(&mut self.tangents, &other.tangents);
        self.uv_sets.truncate(other.uv_sets.len());
        for (set, theirs) in self.uv_sets.iter_mut().zip(&other.uv_sets) {
            set.extend_from_slice(theirs);
        }
        self.positions.extend_from_slice(&other.positions);
        self.triangles.extend(other.triangles.iter().map(|t| t.map(|k| k + base)));
    }

    /// The texture coordinates of set `k`, if the mesh has them.
    pub fn uvs(&self, k: usize) -> Option<&[Vec2]> {
        self.uv_sets.get(k).map(Vec::as_slice)
    }
}

/// Per-vertex data of two meshes joined: `theirs` after `mine`, or none where either has none.
fn join<T: Clone>(mine: &mut Vec<T>, theirs: &[T]) {
    if mine.is_empty() || theirs.is_empty() {
        mine.clear();
    } else {
        mine.extend_from_slice(theirs);
    }
}

/// The mesh as MikkTSpace reads it: every face a triangle with three distinct corners, every corner its
/// own vertex.
struct Corners<'a> {
    mesh: &'a TriangleMesh,
    /// The triangles it is given, by index.
    faces: Vec<usize>,
    uv_set: usize,
    /// What positions are multiplied by: 1, or a power of two that brings a huge mesh to about a unit.
    scale: f32,
    tangents: Vec<Vec4>,
}

impl Corners<'_> {
    fn corner(&self, face: usize, vert: usize) -> usize {
        3 * self.faces[face] + vert
    }
}

impl mikktspace::Geometry for Corners<'_> {
    fn num_faces(&self) -> usize {
        self.faces.len()
    }
    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }
    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        (self.mesh.positions[self.corner(face, vert)] * self.scale).to_array()
    }
    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        self.mesh.normals[self.corner(face, vert)].to_array()
    }
    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        self.mesh.uv_sets[self.uv_set][self.corner(face, vert)].to_array()
    }
    fn set_tangent_encoded(&mut self, tangent: [f32; 4], face: usize, vert: usize) {
        let k = self.corner(face, vert);
        self.tangents[k] = Vec4::from_array(tangent);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit square in z = 0 of two triangles, u along +x and v along +y.
    fn square() -> TriangleMesh {
        let positions = vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y];
        TriangleMesh {
            uv_sets: vec![positions.iter().map(|p| p.truncate()).collect()],
            positions,
            triangles: vec![[0, 1, 2], [0, 2, 3]],
            ..TriangleMesh::default()
        }
    }

    #[test]
    fn normals_are_angle_weighted() {
        // A corner of a cube: three faces meet at the origin at right angles, with one face split in two.
        // Weighting by angle gives the diagonal whatever the split; weighting by count or area would not.
        let p = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z, Vec3::new(1.0, 1.0, 0.0)];
        let mut m = TriangleMesh {
            positions: p,
            triangles: vec![[0, 1, 4], [0, 4, 2], [0, 2, 3], [0, 3, 1]],
            ..TriangleMesh::default()
        };
        m.compute_normals();
        // The faces point along +z (both halves), +x and +y: the normal is (1,1,1)/sqrt 3.
        let want = Vec3::ONE.normalize();
        assert!((m.normals[0] - want).length() < 1e-6, "{}", m.normals[0]);
    }

    #[test]
    fn mikktspace_tangents_of_a_plain_square_run_along_u() {
        let mut m = square();
        m.compute_normals();
        assert!(m.generate_tangents(0));
        // Split into corners for MikkTSpace, then welded back: the shared corners have the same tangent.
        assert_eq!(m.positions.len(), 4);
        for t in &m.tangents {
            assert!((t.truncate() - Vec3::X).length() < 1e-5 && t.w == 1.0, "{t}");
        }
        // Mirrored in u: the tangent turns round and the bitangent keeps pointing along +v.
        let mut m = square();
        m.uv_sets[0].iter_mut().for_each(|uv| uv.x = 1.0 - uv.x);
        m.compute_normals();
        assert!(m.generate_tangents(0));
        for t in &m.tangents {
            let bitangent = t.w * Vec3::Z.cross(t.truncate());
            assert!((t.truncate() + Vec3::X).length() < 1e-5 && (bitangent - Vec3::Y).length() < 1e-5, "{t}");
        }
    }

    /// Meshes mikktspace 0.3 reads out of bounds on (found by fuzzing): all triangles degenerate, one
    /// point, wider than f32 holds. Degenerate triangles keep the default tangent, the others get
    /// MikkTSpace's, of the mesh scaled down where it is huge.
    #[test]
    fn tangents_of_degenerate_and_huge_meshes() {
        let mut point = square();
        point.positions.iter_mut().for_each(|p| *p = Vec3::splat(0.5));
        point.normals = vec![Vec3::Z; 4];
        assert!(point.generate_tangents(0));
        assert!(point.tangents.iter().all(|&t| t == Vec4::new(1.0, 0.0, 0.0, 1.0)));
        let mut lines = square();
        lines.positions[2] = lines.positions[0];
        lines.normals = vec![Vec3::Z; 4];
        assert!(lines.generate_tangents(0));
        assert!(lines.tangents.iter().all(|&t| t == Vec4::new(1.0, 0.0, 0.0, 1.0)));
        let mut huge = square();
        huge.positions.iter_mut().for_each(|p| *p = (*p * 2.0 - Vec3::ONE) * 3.0e38 * Vec3::new(1.0, 1.0, 0.0));
        huge.normals = vec![Vec3::Z; 4];
        assert!(huge.generate_tangents(0));
        for t in &huge.tangents {
            assert!((t.truncate() - Vec3::X).length() < 1e-5 && t.w == 1.0, "{t}");
        }
    }

    #[test]
    fn validation_names_what_is_wrong() {
        let mut m = square();
        assert_eq!(m.validate(), Ok(()));
        m.triangles.push([0, 1, 9]);
        assert!(m.validate().unwrap_err().contains("triangle 2 has a vertex index out of range"));
        let mut m = square();
        m.positions[2].y = f32::NAN;
        assert!(m.validate().unwrap_err().contains("vertex 2"));
        let mut m = square();
        m.triangles.clear();
        assert!(m.validate().unwrap_err().contains("no triangles"));
        let mut m = square();
        m.uv_sets[0].pop();
        assert!(m.validate().unwrap_err().contains("texture coordinate set 0"));
    }

    #[test]
    fn a_mirroring_transform_keeps_fronts_in_front() {
        let mut m = square();
        m.compute_normals();
        let flipped = m.transformed(&Affine3A::from_scale(Vec3::new(-1.0, 1.0, 1.0)));
        let t = flipped.triangles[0].map(|k| flipped.positions[k as usize]);
        let n = (t[1] - t[0]).cross(t[2] - t[0]);
        assert!(n.z > 0.0 && flipped.normals[0] == Vec3::Z);
    }
}
