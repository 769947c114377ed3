//! Triangle meshes brought by the user (OBJ, glTF): positions, unit vertex normals, texture coordinates and
//! tangents, in object space. Missing normals are computed (each face's normal weighted by its angle at the
//! vertex); missing tangents by MikkTSpace, so normal maps baked by Blender or Substance shade as they do
//! there.
//!
//! Texture coordinates follow the project's convention, v up: loaders of v-down formats (glTF) flip them.

use crate::limits::Limit;
use glam::{Affine3A, Mat3, Vec2, Vec3, Vec4};
use rayon::prelude::*;
use rustc_hash::FxHashMap;

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
        let parts = if faces.len() >= PARALLEL_MIKKTSPACE_FROM { rayon::current_num_threads() } else { 1 };
        let Some(tangents) = self.mikktspace_in_parts(&faces, &original, uv_set, scale, parts) else { return false };
        self.tangents = tangents;
        self.weld(&original);
        true
    }

    /// MikkTSpace's tangent for every corner of the split mesh (the default +x where `faces` leaves a
    /// triangle out), run on `parts` runs of `faces` at once, each with its halo: every triangle that shares
    /// a vertex with the run, a vertex being what MikkTSpace welds (equal position, normal and coordinates).
    /// A corner's tangent depends only on the triangles around its vertex (their groups, subgroups and the
    /// order they come in), so each run's own corners come out bit for bit as one run over all the faces
    /// gives them (tested). `original` is each corner's vertex before the split. None where MikkTSpace fails.
    fn mikktspace_in_parts(
        &self,
        faces: &[usize],
        original: &[u32],
        uv_set: usize,
        scale: f32,
        parts: usize,
    ) -> Option<Vec<Vec4>> {
        let mut tangents = vec![Vec4::new(1.0, 0.0, 0.0, 1.0); self.positions.len()];
        if faces.is_empty() {
            return Some(tangents);
        }
        let parts = parts.clamp(1, faces.len());
        // The runs as positions in `faces`: each run's own, then its halo's, in the order of `faces`.
        let runs: Vec<(std::ops::Range<usize>, Vec<usize>)> = if parts == 1 {
            vec![(0..faces.len(), (0..faces.len()).collect())]
        } else {
            let around = FacesAroundVertices::of(self, faces, original, uv_set, scale);
            (0..parts)
                .into_par_iter()
                .map(|p| {
                    let own = p * faces.len() / parts..(p + 1) * faces.len() / parts;
                    let mut marked = vec![false; faces.len()];
                    own.clone().flat_map(|f| around.of_face(f)).for_each(|g| marked[g] = true);
                    let with_halo = (0..faces.len()).filter(|&g| marked[g]).collect();
                    (own, with_halo)
                })
                .collect()
        };
        let results: Vec<Option<Vec<Vec4>>> = runs
            .par_iter()
            .map(|(_, with_halo)| {
                let faces = with_halo.iter().map(|&f| faces[f]).collect();
                let mut corners =
                    Corners { mesh: self, faces, uv_set, scale, tangents: vec![Vec4::ZERO; 3 * with_halo.len()] };
                mikktspace::generate_tangents(&mut corners).then_some(corners.tangents)
            })
            .collect();
        for ((own, with_halo), run_tangents) in runs.iter().zip(results) {
            let run_tangents = run_tangents?;
            for (k, &f) in with_halo.iter().enumerate().filter(|(_, f)| own.contains(f)) {
                let t = 3 * faces[f];
                tangents[t..t + 3].copy_from_slice(&run_tangents[3 * k..3 * k + 3]);
            }
        }
        Some(tangents)
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

/// Faces from which MikkTSpace runs in parts (below, one run is quicker than finding the halos).
const PARALLEL_MIKKTSPACE_FROM: usize = 20_000;

/// The faces around each vertex of a split mesh, a vertex being what MikkTSpace welds: corners with equal
/// position (as scaled), normal and coordinates (compared as numbers: 0 and -0 are one value).
struct FacesAroundVertices {
    /// Per corner of the faces given (3 per face, in their order), its vertex.
    vertex: Vec<u32>,
    /// Per vertex, its range in `faces`; `faces` holds positions in the faces given, ascending.
    starts: Vec<u32>,
    faces: Vec<u32>,
}

impl FacesAroundVertices {
    /// `original` is each corner's vertex before the split: corners of one such vertex are equal, so each is
    /// looked up once (a sixth of the corners of a smooth mesh).
    fn of(mesh: &TriangleMesh, faces: &[usize], original: &[u32], uv_set: usize, scale: f32) -> FacesAroundVertices {
        let key = |c: usize| -> Option<[u32; 8]> {
            let (p, n, uv) = (mesh.positions[c] * scale, mesh.normals[c], mesh.uv_sets[uv_set][c]);
            let v = [p.x, p.y, p.z, n.x, n.y, n.z, uv.x, uv.y];
            // NaN equals nothing in MikkTSpace's comparison: such a corner is a vertex of its own.
            v.iter().all(|x| !x.is_nan()).then(|| v.map(|x| (x + 0.0).to_bits()))
        };
        const NONE: u32 = u32::MAX;
        let mut index: FxHashMap<[u32; 8], u32> = FxHashMap::default();
        let mut of_original = vec![NONE; original.iter().map(|&o| o as usize + 1).max().unwrap_or(0)];
        let mut count = 0u32;
        let mut vertex = Vec::with_capacity(3 * faces.len());
        for c in faces.iter().flat_map(|&f| (0..3).map(move |k| 3 * f + k)) {
            let o = original[c] as usize;
            if of_original[o] == NONE {
                let mut fresh = || {
                    count += 1;
                    count - 1
                };
                of_original[o] = match key(c) {
                    Some(k) => *index.entry(k).or_insert_with(&mut fresh),
                    None => fresh(),
                };
            }
            vertex.push(of_original[o]);
        }
        let mut starts = vec![0u32; count as usize + 1];
        for &v in &vertex {
            starts[v as usize + 1] += 1;
        }
        for v in 0..count as usize {
            starts[v + 1] += starts[v];
        }
        let mut next = starts.clone();
        let mut around = vec![0u32; vertex.len()];
        // Corners in face order, so each vertex's faces come out ascending.
        for (c, &v) in vertex.iter().enumerate() {
            around[next[v as usize] as usize] = (c / 3) as u32;
            next[v as usize] += 1;
        }
        FacesAroundVertices { vertex, starts, faces: around }
    }

    /// The faces (positions in the faces given) that share a vertex with face `f`, `f` among them.
    fn of_face(&self, f: usize) -> impl Iterator<Item = usize> + '_ {
        self.vertex[3 * f..3 * f + 3].iter().flat_map(move |&v| {
            let (a, b) = (self.starts[v as usize] as usize, self.starts[v as usize + 1] as usize);
            self.faces[a..b].iter().map(|&g| g as usize)
        })
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
    /// Per corner of the faces given (3 per face, in their order).
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
        self.tangents[3 * face + vert] = Vec4::from_array(tangent);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// MikkTSpace in parts, each with the faces around its vertices, gives every corner the bits of one
    /// run over the whole mesh: on a bumpy grid with a uv seam (vertices doubled with other coordinates),
    /// a mirrored half, vertices repeated by value under other indices, a sliver of no area, a face turned
    /// over, an edge three faces share, and -0 beside 0.
    #[test]
    fn mikktspace_in_parts_equals_one_run() {
        let (nx, ny) = (24usize, 17usize);
        let mut mesh = TriangleMesh::default();
        let jitter = |k: usize| ((k * 2654435761) % 1000) as f32 / 1000.0 - 0.5;
        for j in 0..=ny {
            for i in 0..=nx {
                let k = j * (nx + 1) + i;
                let (x, y) = (i as f32 / nx as f32, j as f32 / ny as f32);
                mesh.positions.push(Vec3::new(x, y, 0.05 * jitter(k)));
                mesh.normals.push(Vec3::new(0.2 * jitter(k + 7), 0.2 * jitter(k + 11), 1.0).normalize());
                // The right half mirrored in u; at y = 0, -0 for the first column.
                let u = if x > 0.5 { 1.0 - x } else { x };
                mesh.positions[k].x = if i == 0 && j == 0 { -0.0 } else { mesh.positions[k].x };
                mesh.uv_sets.resize(1, Vec::new());
                mesh.uv_sets[0].push(Vec2::new(u, y + 0.01 * jitter(k + 3)));
            }
        }
        let at = |i: usize, j: usize| (j * (nx + 1) + i) as u32;
        for j in 0..ny {
            for i in 0..nx {
                mesh.triangles.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                mesh.triangles.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
        // A uv seam: the vertices of column 5 again, with other u, used by the faces right of it.
        let seam: Vec<u32> = (0..=ny)
            .map(|j| {
                let k = at(5, j) as usize;
                mesh.positions.push(mesh.positions[k]);
                mesh.normals.push(mesh.normals[k]);
                let uv = mesh.uv_sets[0][k] + Vec2::new(0.3, 0.0);
                mesh.uv_sets[0].push(uv);
                (mesh.positions.len() - 1) as u32
            })
            .collect();
        for t in &mut mesh.triangles {
            let right = t.iter().any(|&v| v as usize % (nx + 1) == 6);
            for v in t.iter_mut().filter(|v| right && **v as usize % (nx + 1) == 5) {
                *v = seam[*v as usize / (nx + 1)];
            }
        }
        // A repeat of vertex 40 by value under another index, used by the faces that used 40.
        mesh.positions.push(mesh.positions[40]);
        mesh.normals.push(mesh.normals[40]);
        let uv = mesh.uv_sets[0][40];
        mesh.uv_sets[0].push(uv);
        let twin = (mesh.positions.len() - 1) as u32;
        for t in mesh.triangles.iter_mut().step_by(2) {
            t.iter_mut().filter(|v| **v == 40).for_each(|v| *v = twin);
        }
        // A sliver (three corners in a line), a face turned over, a third face on an edge.
        mesh.triangles.push([at(2, 2), at(3, 2), at(4, 2)]);
        mesh.triangles.push([at(8, 8), at(9, 9), at(9, 8)]);
        mesh.triangles.push([at(10, 10), at(11, 11), at(12, 3)]);
        // Far down the list, a face on the edge from vertex 0 (x = -0) to the one above it (x = +0) through
        // copies with the zeros' signs swapped, which MikkTSpace welds to them (0 == -0).
        let copy = |mesh: &mut TriangleMesh, k: usize, x: f32| {
            mesh.positions.push(Vec3 { x, ..mesh.positions[k] });
            mesh.normals.push(mesh.normals[k]);
            let uv = mesh.uv_sets[0][k];
            mesh.uv_sets[0].push(uv);
            (mesh.positions.len() - 1) as u32
        };
        let (zero, above) = (copy(&mut mesh, 0, 0.0), copy(&mut mesh, at(0, 1) as usize, -0.0));
        // Its third corner left of the edge, wound as the faces right of it in uv, so that MikkTSpace groups
        // it with them at both corners.
        mesh.positions.push(Vec3::new(-0.04, 0.03, 0.0));
        mesh.normals.push(Vec3::Z);
        mesh.uv_sets[0].push(Vec2::new(-0.04, 0.03));
        mesh.triangles.push([zero, above, (mesh.positions.len() - 1) as u32]);
        mesh.validate().unwrap();

        let original: Vec<u32> = mesh.triangles.iter().flatten().copied().collect();
        mesh.split_corners();
        let faces: Vec<usize> = (0..mesh.triangles.len()).collect();
        let one = mesh.mikktspace_in_parts(&faces, &original, 0, 1.0, 1).unwrap();
        assert!(one.iter().any(|t| t.w < 0.0) && one.iter().any(|t| t.w > 0.0), "the mirror flips the sign");
        for parts in [2, 3, 7, 64] {
            let split = mesh.mikktspace_in_parts(&faces, &original, 0, 1.0, parts).unwrap();
            let bits = |v: &[Vec4]| v.iter().map(|t| t.to_array().map(f32::to_bits)).collect::<Vec<_>>();
            assert_eq!(bits(&split), bits(&one), "{parts} parts");
        }
    }

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
