//! Shadow maps rendered by the same rasterizer as the frame: the frame's objects seen from each light that
//! casts shadows, one sample per texel, with the exact outline test of curved surfaces and the alpha test
//! of cut-out ones, keeping each texel's distance. Billboards turn towards the light for its maps, as they
//! turn towards the eye for the frame, so a billboard tree's shadow has the tree's shape whatever the
//! light's angle to the view.

use super::{displace, Binning, Drawn, TileJob, TileScratch};
use crate::bump::DisplacementMode;
use crate::envmap::chart::Face;
use crate::geometry::Instance;
use crate::light::shadow::{depth_of_key, ShadowView, CUBE_MARGIN};
use crate::light::{Light, ShadowMap, ShadowSettings, Shadows, Spot};
use crate::raster::visibility::EMPTY;
use crate::raster::{Camera, Projection, SamplePattern};
use crate::scene::Scene;
use crate::shade::ShadeContext;
use crate::Result;
use glam::Vec3;
use rayon::prelude::*;

/// Spots narrower than this (half-angle, degrees) get one map; wider ones a cube, like a point light.
const ONE_VIEW_SPOT_DEGREES: f32 = 60.0;
const TILE: usize = 64;

/// Every light's shadow map, or `None` where no light casts a shadow or no object can shadow anything
/// (one object that cannot shadow itself). `instances` and `drawn`: the frame's; `placed_for`: the
/// instances as a camera sees them (in the same order); `frame_side`: the frame's larger side, which sizes
/// the maps that do not set their size; `casting`: per instance, whether it casts shadows (translucent
/// surfaces do not).
#[allow(clippy::too_many_arguments)]
pub(super) fn shadows(
    scene: &Scene,
    instances: &[Instance],
    drawn: &Drawn,
    placed_for: &dyn Fn(&Camera) -> Vec<Instance>,
    shade: &ShadeContext,
    cutoffs: &[Option<f32>],
    casting: &[bool],
    frame_side: usize,
) -> Result<Option<Shadows>> {
    let mut self_shadowless: Vec<bool> = scene.objects.iter().map(|o| o.shape.cannot_shadow_itself()).collect();
    // Fully displaced surfaces shadow themselves; silhouette mode bump-maps all but the outline, so it
    // shadows itself as its smooth base does, as bump mapping does (its outline still shapes the shadows
    // it casts on others).
    let displaced_fully = |i: &&Instance| {
        scene.materials[i.material].displacement.as_ref().is_some_and(|d| d.mode == DisplacementMode::Full)
    };
    for inst in instances.iter().filter(displaced_fully) {
        self_shadowless[inst.object as usize] = false;
    }
    let mut objects: Vec<u32> = instances.iter().map(|i| i.object).collect();
    objects.dedup();
    let shadowing = |(light, settings): (&Light, &ShadowSettings)| {
        settings.enabled && matches!(light, Light::Directional { .. } | Light::Point { .. } | Light::Spot(_))
    };
    let alone = objects.len() <= 1 && objects.iter().all(|&o| self_shadowless[o as usize]);
    if alone || !scene.lights.iter().zip(&scene.shadows).any(shadowing) {
        return Ok(None);
    }
    let bounds = world_bounds(instances, drawn);
    // About one texel per two pixels across a frame that the scene fills.
    let auto = (frame_side / 2).next_power_of_two().clamp(256, 4096);
    let mut maps = Vec::with_capacity(scene.lights.len());
    for (light, settings) in scene.lights.iter().zip(&scene.shadows) {
        if !shadowing((light, settings)) {
            maps.push(None);
            continue;
        }
        let (origin, cameras) = match *light {
            Light::Directional { direction, .. } => {
                (Vec3::ZERO, vec![directional_camera(direction, bounds, settings.size.unwrap_or(auto))])
            }
            Light::Spot(spot) if spot.tan_half <= ONE_VIEW_SPOT_DEGREES.to_radians().tan() => {
                (spot.position, vec![spot_camera(&spot, settings.size.unwrap_or(auto))])
            }
            Light::Point { position, .. } | Light::Spot(Spot { position, .. }) => {
                (position, cube_cameras(position, settings.size.unwrap_or(auto / 2)))
            }
            Light::Ambient { .. } | Light::Environment { .. } => unreachable!("only casting lights have maps"),
        };
        let views = cameras
            .into_iter()
            .map(|c| depth_view(c, scene, placed_for, shade, cutoffs, casting))
            .collect::<Result<_>>()?;
        maps.push(Some(ShadowMap { views, origin, bias: settings.bias }));
    }
    Ok(Some(Shadows { maps, self_shadowless }))
}

/// The world-space box around every triangle drawn.
fn world_bounds(instances: &[Instance], drawn: &Drawn) -> (Vec3, Vec3) {
    instances
        .par_iter()
        .zip(&drawn.meshes)
        .map(|(inst, mesh)| {
            mesh.positions()
                .iter()
                .map(|&p| inst.object_to_world.transform_point3(p))
                .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), p| (lo.min(p), hi.max(p)))
        })
        .reduce(|| (Vec3::INFINITY, Vec3::NEG_INFINITY), |a, b| (a.0.min(b.0), a.1.max(b.1)))
}

/// An up vector not along `d`.
fn up_for(d: Vec3) -> Vec3 {
    if d.y.abs() < 0.99 {
        Vec3::Y
    } else {
        Vec3::Z
    }
}

/// The orthographic view along `direction` that holds the box `bounds`, `size` texels along its longer
/// side (and a texel of border all round), from in front of all of it.
fn directional_camera(direction: Vec3, (lo, hi): (Vec3, Vec3), size: usize) -> Camera {
    let up = up_for(direction);
    let centre = 0.5 * (lo + hi);
    let probe = Camera::new(centre - direction, centre, up, Projection::Orthographic { height: 1.0 }, 1, 1);
    let corners = (0..8).map(|k| {
        let pick = |bit: usize, a: f32, b: f32| if k >> bit & 1 == 0 { a } else { b };
        probe.world_to_camera.transform_point3(Vec3::new(pick(0, lo.x, hi.x), pick(1, lo.y, hi.y), pick(2, lo.z, hi.z)))
    });
    let (min, max) = corners.fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(a, b), p| (a.min(p), b.max(p)));
    let extent = (max - min).max(Vec3::splat(1e-6));
    let scale = size as f32 / extent.x.max(extent.y);
    let (w, h) = ((extent.x * scale).ceil() as u32 + 2, (extent.y * scale).ceil() as u32 + 2);
    let eye_local = Vec3::new(0.5 * (min.x + max.x), 0.5 * (min.y + max.y), max.z + 0.01 * extent.z + 1e-3);
    let eye = probe.camera_to_world.transform_point3(eye_local);
    Camera::new(eye, eye + direction, up, Projection::Orthographic { height: h as f32 / scale }, w, h)
}

/// A perspective view of `size` texels across, plus the cube margin all round, spanning `tan_half` of
/// the axis each way within the size.
fn square_perspective(eye: Vec3, forward: Vec3, up: Vec3, tan_half: f32, size: usize) -> Camera {
    let side = size + 2 * CUBE_MARGIN;
    let tan = tan_half * side as f32 / size as f32;
    let fov_y = 2.0 * tan.atan().to_degrees();
    Camera::new(eye, eye + forward, up, Projection::Perspective { fov_y }, side as u32, side as u32)
}

fn spot_camera(spot: &Spot, size: usize) -> Camera {
    square_perspective(spot.position, spot.forward, spot.up, spot.tan_half, size)
}

/// The six 90-degree views from `position`, one per cube face, in the order of `ShadowMap::views`.
fn cube_cameras(position: Vec3, size: usize) -> Vec<Camera> {
    Face::ALL
        .into_iter()
        .map(|face| {
            let (outward, _, up) = face.axes();
            square_perspective(position, outward, up, 1.0, size)
        })
        .collect()
}

/// The scene seen through `camera`: each texel's nearest surface's distance along the axis and its object.
fn depth_view(
    camera: Camera,
    scene: &Scene,
    placed_for: &dyn Fn(&Camera) -> Vec<Instance>,
    shade: &ShadeContext,
    cutoffs: &[Option<f32>],
    casting: &[bool],
) -> Result<ShadowView> {
    let (w, h) = (camera.width as usize, camera.height as usize);
    crate::limits::reserve((w * h * 8) as u64, || format!("a {w}x{h} shadow map"))?;
    let mut seen = placed_for(&camera);
    let diced = displace::displace(&mut seen, &scene.materials, &camera)?;
    let binning = Binning { tile_size: TILE, surfaces: casting };
    let pattern = SamplePattern::centre();
    let drawn = Drawn::new(&seen, diced, &camera, &pattern, binning, &mut Default::default());
    let bins = &drawn.bins;
    // A parallax crossing's depth is the eye's, not the light's: shadows see the surface itself.
    let not_replacing = vec![false; seen.len()];
    let job = TileJob {
        exact_depth: true,
        ..TileJob::visibility(&drawn, bins, &camera, &pattern, &seen, shade, cutoffs, &not_replacing)
    };
    let (mut depth, mut object) = (vec![f32::INFINITY; w * h], vec![EMPTY.to_le_bytes(); w * h]);
    depth.par_chunks_mut(TILE * w).zip(object.par_chunks_mut(TILE * w)).enumerate().for_each_init(
        || TileScratch::new(TILE, 1),
        |scratch, (ty, (depth, object))| {
            for tx in 0..bins.tiles_x {
                if bins.bin((tx, ty)).is_empty() {
                    continue;
                }
                scratch.vis.render_tile(bins, (tx, ty), (w, h), &drawn.triangles, &pattern);
                if job.any_masked || scratch.vis.outline {
                    job.fix_visibility(scratch, (tx, ty));
                }
                let vis = &scratch.vis;
                for y in 0..vis.height {
                    for x in 0..vis.width {
                        let t = vis.triangle[y * vis.width + x];
                        if t != EMPTY {
                            let i = y * w + vis.x0 + x;
                            depth[i] = depth_of_key(&camera, vis.depth[y * vis.width + x]);
                            object[i] = seen[drawn.triangles[t as usize].surface as usize].object.to_le_bytes();
                        }
                    }
                }
            }
        },
    );
    Ok(ShadowView::new(camera, depth, object))
}
