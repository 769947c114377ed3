//! The frame's displaced geometry: each object whose material displaces is diced where it is seen
//! (geometry/dice.rs) over one base for all of its displaced primitives, welded where they meet, so that
//! patches and faces stay joined; then every primitive gets its own triangles back.
//!
//! The base of a parametric surface is its usual grid (segments of at most 16 px, sagging at most a quarter
//! pixel); the primitives of one object share one segment count, so the sides of a box's faces or of
//! patches that meet are cut at the same points. A mesh's base is its own triangles.

use super::{SAG_PX, SEGMENT_PX};
use crate::bump::{BumpSource, Displacement};
use crate::geometry::dice::{dice, interpolate, weld, Base, BasePoint, DiceSample, DiceSurface, Diced, Face, Skip};
use crate::geometry::tessellate::{grid, segments_for, Mesh};
use crate::geometry::{Instance, Primitive, Surface, TriangleMesh};
use crate::lanes::{CmpGt, CmpLe, F8, LANES, V3};
use crate::limits::Limit;
use crate::raster::camera::NEAR;
use crate::raster::Camera;
use crate::shade::Material;
use crate::texture::filter::Filter;
use crate::texture::reconstruct::Kernel;
use crate::texture::{Footprint, Footprint8, LookupContext, LookupContext8, SurfaceLanes};
use crate::{Error, Result};
use glam::{Affine3A, Mat3, Vec2, Vec3, Vec4};
use rayon::prelude::*;
use std::sync::Arc;

/// Dices every displaced object of the frame. A displaced mesh's instance gets its diced mesh as its
/// primitive; a displaced parametric surface keeps its primitive (the shader evaluates it exactly at each
/// sample's (u,v)) and its diced triangles are returned at its index.
pub fn displace(instances: &mut [Instance], materials: &[Material], camera: &Camera) -> Result<Vec<Option<Mesh>>> {
    let mut grids: Vec<Option<Mesh>> = (0..instances.len()).map(|_| None).collect();
    let mut start = 0;
    while start < instances.len() {
        let object = instances[start].object;
        let end = start + instances[start..].iter().take_while(|i| i.object == object).count();
        let members: Vec<usize> =
            (start..end).filter(|&i| materials[instances[i].material].displacement.is_some()).collect();
        if !members.is_empty() {
            displace_object(instances, &members, materials, camera, &mut grids)?;
        }
        start = end;
    }
    Ok(grids)
}

/// One displaced primitive's part of the object's base.
struct Part<'a> {
    displacement: &'a Displacement,
    surface: Option<Surface>,
    /// The mesh of a mesh primitive (its normals, texture coordinates and tangents).
    mesh: Option<Arc<TriangleMesh>>,
    /// Its first vertex in the base.
    first_vertex: u32,
    /// Whether its faces turned away are culled (closed or one-sided).
    culled: bool,
    /// Silhouette mode's threshold where it is the same all over (given, or the curvature is): worked
    /// out once instead of at every sample.
    threshold: Option<f32>,
}

/// The displaced primitives of one object over one base.
struct Displacing<'a> {
    parts: Vec<Part<'a>>,
    part_of: Vec<u32>,
    positions: Vec<Vec3>,
    uvs: Vec<Vec2>,
    normals: Vec<Vec3>,
    triangles: Vec<[u32; 3]>,
    /// What is diced: a surface's grid cells as quads, a mesh's triangles.
    faces: Vec<Face>,
    camera: &'a Camera,
    object_to_world: Affine3A,
    normal_matrix: Mat3,
    /// How long an object-space unit is in the world (the transform's largest stretch).
    stretch: f32,
}

fn displace_object(
    instances: &mut [Instance],
    members: &[usize],
    materials: &[Material],
    camera: &Camera,
    grids: &mut [Option<Mesh>],
) -> Result<()> {
    let first = &instances[members[0]];
    let (object_to_world, normal_matrix) = (first.object_to_world, first.normal_matrix);
    let m = object_to_world.matrix3;
    let stretch = m.x_axis.length().max(m.y_axis.length()).max(m.z_axis.length());
    let ppu = |p: Vec3| camera.pixels_per_unit(object_to_world.transform_point3(p)) * stretch;
    // One segment count for all the surfaces of the object, so that where they meet they are cut alike.
    let surfaces: Vec<Option<&Surface>> = members
        .iter()
        .map(|&i| match &instances[i].primitive {
            Primitive::Parametric(s) => Some(s),
            Primitive::Mesh(_) => None,
        })
        .collect();
    let counts: Vec<(usize, usize)> =
        surfaces.iter().flatten().map(|s| segments_for(s, SEGMENT_PX, SAG_PX, ppu)).collect();
    let shared = counts.iter().map(|&(u, v)| u.max(v)).max().unwrap_or(1);
    let mut d = Displacing {
        parts: Vec::new(),
        part_of: Vec::new(),
        positions: Vec::new(),
        uvs: Vec::new(),
        normals: Vec::new(),
        triangles: Vec::new(),
        faces: Vec::new(),
        camera,
        object_to_world,
        normal_matrix,
        stretch,
    };
    let mut counts = counts.into_iter();
    for (&i, surface) in members.iter().zip(&surfaces) {
        let displacement = materials[instances[i].material].displacement.as_ref().expect("a displaced member");
        let part = Part {
            displacement,
            surface: surface.cloned(),
            mesh: None,
            first_vertex: d.positions.len() as u32,
            culled: !instances[i].two_sided,
            threshold: displacement.constant_threshold(surface.and_then(|s| s.constant_curvature())),
        };
        let offset = part.first_vertex;
        let (positions, uvs, normals, triangles, mesh) = match (&instances[i].primitive, surface) {
            (_, Some(s)) => {
                let (nu, nv) = counts.next().expect("one count per surface");
                let g = if members.len() > 1 { grid(s, shared, shared) } else { grid(s, nu, nv) };
                let normals = vec![Vec3::ZERO; g.positions.len()];
                (g.positions, g.uvs, normals, g.triangles, None)
            }
            (Primitive::Mesh(mesh), None) => {
                let uvs = mesh.uvs(0).map_or_else(|| vec![Vec2::ZERO; mesh.positions.len()], <[Vec2]>::to_vec);
                (mesh.positions.clone(), uvs, mesh.normals.clone(), mesh.triangles.clone(), Some(mesh.clone()))
            }
            (Primitive::Parametric(_), None) => unreachable!("surfaces are listed by primitive"),
        };
        let first = d.triangles.len() as u32;
        match part.surface {
            // Grid cell q is triangles 2q = [a, b, c] and 2q + 1 = [a, c, d].
            Some(_) => d.faces.extend(triangles.chunks(2).enumerate().map(|(q, pair)| {
                let ([a, b, c], [_, _, d]) = (pair[0], pair[1]);
                Face::quad([a, b, c, d].map(|v| v + offset), first + 2 * q as u32)
            })),
            None => d.faces.extend(
                triangles.iter().enumerate().map(|(t, c)| Face::triangle(c.map(|v| v + offset), first + t as u32)),
            ),
        }
        d.part_of.extend(std::iter::repeat_n(d.parts.len() as u32, triangles.len()));
        d.triangles.extend(triangles.into_iter().map(|t| t.map(|v| v + offset)));
        d.positions.extend(positions);
        d.uvs.extend(uvs);
        d.normals.extend(normals);
        d.parts.push(Part { mesh, ..part });
    }
    // One primitive's seams and poles repeat positions exactly; where primitives meet they agree to rounding.
    let tolerance = match d.parts.len() {
        1 => 0.0,
        _ => {
            let (lo, hi) =
                d.positions.iter().fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &p| (lo.min(p), hi.max(p)));
            1e-5 * (hi - lo).length()
        }
    };
    let (weld_of, welded) = weld(&d.positions, tolerance);
    let base = Base { faces: &d.faces, weld: &weld_of, welded };
    let edge_px = d.parts.iter().map(|p| p.displacement.edge_px).fold(f32::INFINITY, f32::min);
    let most = Limit::Triangles.count();
    let diced = dice(&base, &d, edge_px, most).map_err(|count| {
        Error::Invalid(format!(
            "displacing object {} would make {count} triangles, more than the limit of {most} ({}); raise edge_px",
            first.object,
            Limit::Triangles.hint()
        ))
    })?;
    for (k, part) in d.split(diced).into_iter().enumerate() {
        let i = members[k];
        match (&d.parts[k].surface, part) {
            (Some(_), Split::Grid(g)) => grids[i] = Some(g),
            (None, Split::Mesh(m)) => instances[i].primitive = Primitive::Mesh(Arc::new(m)),
            _ => unreachable!("a part is split as what it is"),
        }
    }
    Ok(())
}

/// One primitive's diced triangles.
enum Split {
    Grid(Mesh),
    Mesh(TriangleMesh),
}

impl Displacing<'_> {
    /// The diced surface cut back into its primitives, each with its vertices' attributes interpolated
    /// from its base.
    fn split(&self, diced: Diced) -> Vec<Split> {
        if let [part] = &self.parts[..] {
            return vec![self.part(part, diced.positions, diced.sources, diced.triangles)];
        }
        let part_of_vertex: Vec<u32> = diced.sources.iter().map(|s| self.part_of[s.triangle as usize]).collect();
        let mut local = vec![0u32; diced.positions.len()];
        let mut vertices: Vec<Vec<u32>> = vec![Vec::new(); self.parts.len()];
        for (v, &p) in part_of_vertex.iter().enumerate() {
            local[v] = vertices[p as usize].len() as u32;
            vertices[p as usize].push(v as u32);
        }
        let mut triangles: Vec<Vec<[u32; 3]>> = vec![Vec::new(); self.parts.len()];
        for (t, &origin) in diced.triangles.iter().zip(&diced.origins) {
            let part = self.part_of[self.faces[origin as usize].triangle as usize];
            triangles[part as usize].push(t.map(|v| local[v as usize]));
        }
        self.parts
            .iter()
            .zip(vertices)
            .zip(triangles)
            .map(|((part, vertices), triangles)| {
                let positions = vertices.iter().map(|&v| diced.positions[v as usize]).collect();
                let sources = vertices.iter().map(|&v| diced.sources[v as usize]).collect();
                self.part(part, positions, sources, triangles)
            })
            .collect()
    }

    /// One primitive's diced triangles over its vertices, with the base points they come from.
    fn part(&self, part: &Part, positions: Vec<Vec3>, sources: Vec<BasePoint>, triangles: Vec<[u32; 3]>) -> Split {
        match &part.mesh {
            None => Split::Grid(Mesh {
                segments: (0, 0),
                wraps: (false, false),
                positions,
                uvs: sources.par_iter().map(|&s| interpolate(self.corners(s, &self.uvs), s.bary)).collect(),
                triangles,
            }),
            Some(mesh) => Split::Mesh(self.mesh_part(mesh, part, positions, sources, triangles)),
        }
    }

    /// A diced mesh: displaced positions, and normals, texture coordinates and tangents interpolated on the
    /// base (what shading reads; the displacement's own slopes come in as a bump).
    fn mesh_part(
        &self,
        mesh: &TriangleMesh,
        part: &Part,
        positions: Vec<Vec3>,
        sources: Vec<BasePoint>,
        triangles: Vec<[u32; 3]>,
    ) -> TriangleMesh {
        let own = |s: &BasePoint| self.triangles[s.triangle as usize].map(|v| (v - part.first_vertex) as usize);
        let normals =
            sources.iter().map(|s| interpolate(own(s).map(|v| mesh.normals[v]), s.bary).normalize_or_zero()).collect();
        let uv_sets = mesh
            .uv_sets
            .iter()
            .map(|set| sources.iter().map(|s| interpolate(own(s).map(|v| set[v]), s.bary)).collect())
            .collect();
        let tangents = match mesh.tangents.is_empty() {
            true => Vec::new(),
            false => sources
                .iter()
                .map(|s| {
                    let c = own(s).map(|v| mesh.tangents[v]);
                    interpolate(c.map(|t| t.truncate()), s.bary).normalize_or_zero().extend(c[0].w)
                })
                .collect::<Vec<Vec4>>(),
        };
        TriangleMesh { positions, normals, uv_sets, tangents, triangles }
    }

    fn corners<T: Copy>(&self, at: BasePoint, data: &[T]) -> [T; 3] {
        self.triangles[at.triangle as usize].map(|v| data[v as usize])
    }
}

impl DiceSurface for Displacing<'_> {
    fn sample(&self, at: BasePoint) -> DiceSample {
        let part = &self.parts[self.part_of[at.triangle as usize] as usize];
        let uv = interpolate(self.corners(at, &self.uvs), at.bary);
        let displacement = part.displacement;
        let (p, normal, pu, pv, threshold) = match &part.surface {
            Some(surface) => {
                let f = surface.frame(uv.x, uv.y);
                let threshold = part.threshold.unwrap_or_else(|| displacement.threshold_at(f.max_curvature()));
                (f.p, f.limit_normal(), f.pu, f.pv, threshold)
            }
            None => {
                let [a, b, c] = self.corners(at, &self.positions);
                let n = interpolate(self.corners(at, &self.normals), at.bary).normalize_or_zero();
                let (pu, pv) = uv_tangents([a, b, c], self.corners(at, &self.uvs));
                let threshold = part.threshold.unwrap_or_else(|| displacement.threshold_at(f32::INFINITY));
                (interpolate([a, b, c], at.bary), n, pu, pv, threshold)
            }
        };
        // Where the point is in the world and on the screen, worked out once for all that follows.
        let world = self.object_to_world.transform_point3(p);
        let seen = self.camera.world_to_camera.transform_point3(world);
        let ppu = self.camera.pixels_per_unit_at(seen) * self.stretch;
        let facing = self.facing(world, normal);
        let w = displacement.weight(facing.abs(), threshold);
        let height = match w {
            0.0 => 0.0,
            // F filtered to what one diced edge can show.
            _ => {
                let size = displacement.edge_px / ppu;
                let step = |d: Vec3| (size / d.length()).min(1.0);
                let footprint = Footprint { dudx: step(pu), dvdx: 0.0, dudy: 0.0, dvdy: step(pv) };
                let ctx = LookupContext::on_surface(p, pu, pv, uv, footprint);
                w * displacement.map.height(&ctx, &displacement.map.filter)
            }
        };
        self.finish(part, p, normal, seen, ppu, facing, threshold, height)
    }

    /// Eight points at a time where they lie on one parametric surface: its frames, facing, weights and F
    /// on lanes.
    fn sample_into(&self, at: &[BasePoint], out: &mut [DiceSample]) {
        for (at, out) in at.chunks(LANES).zip(out.chunks_mut(LANES)) {
            let part = self.part_of[at[0].triangle as usize];
            match &self.parts[part as usize].surface {
                Some(surface) if at.iter().all(|a| self.part_of[a.triangle as usize] == part) => {
                    self.sample8(&self.parts[part as usize], surface, at, out)
                }
                _ => out.iter_mut().zip(at).for_each(|(out, &at)| *out = self.sample(at)),
            }
        }
    }

    fn screen(&self, p: Vec3) -> Option<Vec2> {
        self.on_screen(self.camera.world_to_camera.transform_point3(self.object_to_world.transform_point3(p)))
    }

    fn pixels_per_unit(&self, p: Vec3) -> f32 {
        self.camera.pixels_per_unit(self.object_to_world.transform_point3(p)) * self.stretch
    }

    /// Told by a table read on its own (u,v) (the uv transform is affine, so the table coordinates of the
    /// base between the points lie within their box) by nearest or bilinear lookups, whose every tap
    /// within the box holds one value.
    fn uniform(&self, points: &[BasePoint]) -> bool {
        let part = &self.parts[self.part_of[points[0].triangle as usize] as usize];
        let map = &part.displacement.map;
        let (BumpSource::Table(table), Some(_), Filter::Reconstruct(Kernel::Nearest | Kernel::Bilinear)) =
            (&map.source, map.mapping.constant_jacobian(), map.filter.filter)
        else {
            return false;
        };
        let (lo, hi) = points
            .iter()
            .map(|at| map.mapping.transform.point(interpolate(self.corners(*at, &self.uvs), at.bary)))
            .fold((Vec2::INFINITY, Vec2::NEG_INFINITY), |(lo, hi), st| (lo.min(st), hi.max(st)));
        table.is_constant_over(lo, hi)
    }
}

/// Below this N.V a point of a culled surface is taken to be hidden, displaced or not: 30 degrees past the
/// outline, where a height of 15% of the radius of curvature would be needed to reach it.
const FACING_AWAY: f32 = -0.5;

/// How far off the screen (pixels, besides the height) a point still counts as on it.
const SCREEN_MARGIN_PX: f32 = 16.0;

impl Displacing<'_> {
    /// `sample` of up to eight points of `part`'s parametric `surface`, on lanes.
    fn sample8(&self, part: &Part, surface: &Surface, at: &[BasePoint], out: &mut [DiceSample]) {
        let displacement = part.displacement;
        // Lanes past the end repeat the last point.
        let uv: [Vec2; LANES] = std::array::from_fn(|i| {
            let at = at[i.min(at.len() - 1)];
            interpolate(self.corners(at, &self.uvs), at.bary)
        });
        let (u, v) = (F8::new(uv.map(|t| t.x)), F8::new(uv.map(|t| t.y)));
        let f = surface.frame8(u, v);
        // Pu x Pv, or where it vanishes (a pole) the scalar frame's limit along the edge drawn together.
        let mut normal = f.pu.cross(f.pv);
        let (size, scale) = (normal.dot(normal), f.pu.dot(f.pu).max(f.pv.dot(f.pv)));
        let degenerate = size.cmp_le(F8::splat(1e-12) * scale * scale).move_mask();
        normal = normal.normalize_or_zero();
        for i in (0..LANES).filter(|i| degenerate & (1 << i) != 0) {
            normal.set_lane(i, surface.frame(uv[i].x, uv[i].y).limit_normal());
        }
        let threshold = match part.threshold {
            Some(t) => F8::splat(t),
            None => displacement.threshold8(f.max_curvature8()),
        };
        let world = V3::transform_point(&self.object_to_world, f.p);
        let seen = V3::transform_point(&self.camera.world_to_camera, world);
        let ppu = F8::new(std::array::from_fn(|i| self.camera.pixels_per_unit_at(seen.lane(i)) * self.stretch));
        let to_eye = match self.camera.is_perspective() {
            true => V3::splat(self.camera.eye) - world,
            false => V3::splat(self.camera.camera_to_world.transform_vector3(Vec3::Z)),
        };
        let facing = V3::mul_mat3(&self.normal_matrix, normal).normalize_or_zero().dot(to_eye.normalize_or_zero());
        let w = displacement.weight8(facing.abs(), threshold);
        // F filtered to what one diced edge can show, where any lane moves.
        let height = match w.cmp_gt(F8::ZERO).any() {
            true => {
                let size = F8::splat(displacement.edge_px) / ppu;
                let step = |d: V3| (size / d.length()).min(F8::ONE);
                let footprint = Footprint8 { dudx: step(f.pu), dvdx: F8::ZERO, dudy: F8::ZERO, dvdy: step(f.pv) };
                let lanes = SurfaceLanes::new(f.p, f.pu, f.pv, &footprint, 0, [0; LANES]);
                let ctx = LookupContext8 { surface: &lanes, u, v, footprint };
                w * displacement.map.height8(&ctx, &displacement.map.filter)
            }
            false => F8::ZERO,
        };
        let (facing, threshold, height, ppu) =
            (facing.to_array(), threshold.to_array(), height.to_array(), ppu.to_array());
        for (i, out) in out.iter_mut().enumerate() {
            let (p, normal, seen) = (f.p.lane(i), normal.lane(i), seen.lane(i));
            *out = self.finish(part, p, normal, seen, ppu[i], facing[i], threshold[i], height[i]);
        }
    }

    /// The sample at object-space point `p` with unit normal `normal`, camera-space point `seen`, `ppu`
    /// pixels per object unit, N.V `facing`, silhouette mode's `threshold` and the `height` it moves by:
    /// why it needs no dicing, and how surely.
    #[allow(clippy::too_many_arguments)]
    fn finish(
        &self,
        part: &Part,
        p: Vec3,
        normal: Vec3,
        seen: Vec3,
        ppu: f32,
        facing: f32,
        threshold: f32,
        height: f32,
    ) -> DiceSample {
        let (mut skip, mut clearance) = (0, f32::INFINITY);
        if part.culled && facing < FACING_AWAY {
            skip |= Skip::FACING_AWAY;
            clearance = FACING_AWAY - facing;
        }
        if part.displacement.weight(facing.abs(), threshold) == 0.0 {
            skip |= Skip::FLAT;
            clearance = clearance.min(facing.abs() - threshold);
        }
        skip |= self.off_screen(seen, height.abs() * ppu);
        let clearance = if skip & Skip::FACING != 0 { clearance } else { 0.0 };
        DiceSample { p, normal, height, skip, clearance }
    }

    /// N.V at a world point whose object-space unit normal is `n`.
    fn facing(&self, world: Vec3, n: Vec3) -> f32 {
        let n = (self.normal_matrix * n).normalize_or_zero();
        let to_eye = match self.camera.is_perspective() {
            true => self.camera.eye - world,
            false => self.camera.camera_to_world.transform_vector3(Vec3::Z),
        };
        n.dot(to_eye.normalize_or_zero())
    }

    /// Where a camera-space point lands on the screen (pixels), if it is in front of the eye.
    fn on_screen(&self, seen: Vec3) -> Option<Vec2> {
        (!self.camera.is_perspective() || -seen.z > NEAR).then(|| self.camera.project(seen).0)
    }

    /// Which sides of the screen a camera-space point lies beyond, by more than a margin and its height
    /// (`height_px`, pixels); none behind the eye.
    fn off_screen(&self, seen: Vec3, height_px: f32) -> u8 {
        let Some(at) = self.on_screen(seen) else { return 0 };
        let margin = SCREEN_MARGIN_PX + height_px;
        let (w, h) = (self.camera.width as f32, self.camera.height as f32);
        let side = |out: bool, bit: u8| if out { bit } else { 0 };
        side(at.x < -margin, Skip::LEFT)
            | side(at.x > w + margin, Skip::RIGHT)
            | side(at.y < -margin, Skip::TOP)
            | side(at.y > h + margin, Skip::BOTTOM)
    }
}

/// dP/du and dP/dv of a flat triangle from its corners' positions and (u,v); zero where the (u,v) are
/// degenerate.
fn uv_tangents(p: [Vec3; 3], uv: [Vec2; 3]) -> (Vec3, Vec3) {
    let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
    let (d1, d2) = (uv[1] - uv[0], uv[2] - uv[0]);
    let det = d1.perp_dot(d2);
    if det.abs() < 1e-20 {
        return (Vec3::ZERO, Vec3::ZERO);
    }
    ((e1 * d2.y - e2 * d1.y) / det, (e2 * d1.x - e1 * d2.x) / det)
}
