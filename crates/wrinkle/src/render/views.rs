//! Cube maps rendered by the renderer (the slides' "create six views from the shiny object's centroid"):
//! an object whose material has `reflect_views` sees the rest of the scene in six 90-degree views from its
//! centroid, rendered each frame, and reflects those instead of the scene's environment.
//!
//! The approximation is the slides': reflection is about the centroid. A reflected ray leaving the surface
//! at P in direction R is looked up as if it left the centroid; what lies far away (compared with the
//! object's size) is where it should be, what lies close is displaced, and the object never reflects
//! itself.

use super::{instances, render_view, RenderOptions, View};
use crate::envmap::{Environment, EnvironmentOptions, Face, Layout};
use crate::geometry::{Instance, Primitive};
use crate::image::Image;
use crate::raster::{Camera, Projection};
use crate::scene::{CameraDesc, Scene};
use crate::Result;
use glam::Vec3;

/// Per object, its rendered cube map where its material asks for one.
pub fn object_views(scene: &Scene, options: &RenderOptions, camera: &Camera) -> Result<Vec<Option<Environment>>> {
    let placed = instances(scene, camera, options.turntable_degrees);
    let mut views = Vec::with_capacity(scene.objects.len());
    for (k, object) in scene.objects.iter().enumerate() {
        let size = scene.materials[object.material].reflect_views;
        if size == 0 {
            views.push(None);
            continue;
        }
        let centre = centroid(placed.iter().filter(|i| i.object == k as u32));
        let face_options = RenderOptions {
            width: size,
            height: size,
            spp: 1,
            aovs: Default::default(),
            transparent: false,
            // The six views are whole: a crop is the frame's, not theirs.
            crop: None,
            ..options.clone()
        };
        let faces = Face::ALL
            .iter()
            .map(|&face| {
                let (ma, _, up) = face.axes();
                let view_camera = CameraDesc {
                    eye: centre,
                    look_at: centre + ma,
                    up,
                    projection: Projection::Perspective { fov_y: 90.0 },
                    background: scene.camera.background,
                };
                let view = View { camera: &view_camera, hidden: Some(k as u32), object_views: false, stop: None };
                let frame = render_view(scene, &view, &face_options, &|_, _| {})?;
                // OpenGL's faces are seen from inside a left-handed cube: s runs along -Z on +X, where a
                // right-handed camera looking down +X has +Z on its right. Each row is mirrored.
                Ok(Image::from_fn(size, size, |x, y| {
                    let c = frame.color[y * size + (size - 1 - x)];
                    [c[0], c[1], c[2], 1.0]
                }))
            })
            .collect::<Result<Vec<_>>>()?;
        let map = Environment::new(Layout::Cube, &faces, EnvironmentOptions::default()).expect("six square faces");
        views.push(Some(map));
    }
    Ok(views)
}

/// The mean of an object's surface points: a parametric surface's on a 9 x 9 grid of (u,v), a mesh's
/// vertices, in the world.
fn centroid<'a>(parts: impl Iterator<Item = &'a Instance>) -> Vec3 {
    let (mut sum, mut count) = (Vec3::ZERO, 0.0);
    for inst in parts {
        let to_world = |p: Vec3| inst.object_to_world.transform_point3(p);
        match &inst.primitive {
            Primitive::Parametric(surface) => {
                for j in 0..9 {
                    for i in 0..9 {
                        sum += to_world(surface.frame(i as f32 / 8.0, j as f32 / 8.0).p);
                        count += 1.0;
                    }
                }
            }
            Primitive::Mesh(mesh) => {
                sum += mesh.positions.iter().map(|&p| to_world(p)).sum::<Vec3>();
                count += mesh.positions.len() as f32;
            }
        }
    }
    sum / count.max(1.0)
}
