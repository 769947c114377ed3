//! The paint session and its HTTP API against independent references: the sphere's analytic (u,v) under
//! the brush, exact undo, the saved scene rendered by the renderer's own loader, a stroke across a mesh's
//! atlas seam, and clear refusals of malformed requests.

use axum::body::Body;
use axum::http::{Request, StatusCode};
use glam::Vec3;
use http_body_util::BodyExt;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use tower::ServiceExt;
use wrinkle::{RenderOptions, Scene, Surface};
use wrinkle_paint::{Brush, Channel, Opening, Orbit, Session};

const VIEW: (usize, usize) = (320, 240);

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("wrinkle-paint-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn opening(object: usize, atlas_size: usize) -> Opening {
    Opening { object, atlas_size, view: VIEW, new_atlas: false }
}

fn sphere_session(atlas: usize) -> Session {
    let mut s = Session::open(&repo().join("scenes/paint_sphere.toml"), &opening(0, atlas)).unwrap();
    s.set_camera(Orbit { yaw: 0.0, pitch: 0.0, distance: 4.0, target: [0.0; 3] }).unwrap();
    s
}

/// What the sphere session's view shows at pixel (x, y): the point where the ray through the pixel's centre
/// (the eye at z = 4, fov 35 degrees) meets the unit sphere, and the world size of `radius_px` pixels there.
fn seen_on_sphere(x: f32, y: f32, radius_px: f32) -> (Vec3, f32) {
    let (w, h) = (VIEW.0 as f32, VIEW.1 as f32);
    let scale = 0.5 * h / (17.5f32).to_radians().tan();
    let eye = Vec3::new(0.0, 0.0, 4.0);
    let dir = Vec3::new((x + 0.5 - w / 2.0) / scale, -(y + 0.5 - h / 2.0) / scale, -1.0).normalize();
    let b = eye.dot(dir);
    let hit = eye + dir * (-b - (b * b - eye.length_squared() + 1.0).sqrt());
    (hit, radius_px * (eye.z - hit.z) / scale)
}

fn brush(json: &str) -> Brush {
    serde_json::from_str(json).unwrap()
}

/// The texel (row 0 at v = 1) of (u,v).
fn texel_uv(k: usize, size: usize) -> (f32, f32) {
    ((k % size) as f32 / size as f32 + 0.5 / size as f32, 1.0 - ((k / size) as f32 + 0.5) / size as f32)
}

/// A hard brush of radius R pixels at the view's centre paints exactly the texels whose point P(u,v) lies
/// within R pixels' worth of world units of the point seen there, (0, 0, 1) on the unit sphere.
#[test]
fn a_dab_paints_the_texels_within_the_brush_sphere() {
    let size = 512;
    let mut s = sphere_session(size);
    let before = s.atlas().codes(Channel::Color).to_vec();
    let (w, h) = VIEW;
    let texels = s
        .stroke(brush(r#"{"radius": 24, "hardness": 1, "color": [1, 0, 0]}"#), &[[w as f32 / 2.0, h as f32 / 2.0]])
        .unwrap();
    // The point seen at the centre pixel; the brush's radius in the world is 24 pixels at its depth.
    let (hit, radius) = seen_on_sphere(w as f32 / 2.0, h as f32 / 2.0, 24.0);
    let sphere = Surface::Sphere { radius: 1.0 };
    let after = s.atlas().codes(Channel::Color);
    let (mut expected, mut wrong) = (0, 0);
    for k in 0..size * size {
        let (u, v) = texel_uv(k, size);
        let d = sphere.position(u, v).distance(hit);
        let painted = after[k] != before[k];
        // Texels on the rim (within 0.5% of the radius) may fall either way with the depth's rounding.
        if (d - radius).abs() < 0.005 * radius {
            continue;
        }
        expected += usize::from(d < radius);
        wrong += usize::from(painted != (d < radius));
    }
    assert!(expected > 1000, "the brush covers {expected} texels");
    assert_eq!(wrong, 0, "{wrong} texels painted or left against the analytic sphere ({expected} expected)");
    assert!(texels >= expected && texels <= expected * 11 / 10, "{texels} changed, {expected} expected");
    // Full strength in the hard core: pure red at u = 0.75, v = 0.5.
    let centre = (size / 2) * size + size * 3 / 4;
    assert_eq!(after[centre].to_le_bytes(), [255, 0, 0, 255]);
}

#[test]
fn the_back_of_the_sphere_is_not_painted_through_it() {
    let size = 128;
    let mut s = sphere_session(size);
    // A brush far larger than the sphere: only the half in view is painted.
    s.stroke(brush(r#"{"radius": 2000, "hardness": 1, "color": [0, 0, 1]}"#), &[[160.0, 120.0]]).unwrap();
    let codes = s.atlas().codes(Channel::Color);
    let blue = |k: usize| codes[k].to_le_bytes()[2] == 255 && codes[k].to_le_bytes()[0] == 0;
    let sphere = Surface::Sphere { radius: 1.0 };
    let eye = Vec3::new(0.0, 0.0, 4.0);
    for k in 0..size * size {
        let (u, v) = texel_uv(k, size);
        let p = sphere.position(u, v);
        // The cosine between the normal (the point) and the way to the eye; the rim may fall either way.
        let facing = p.dot((eye - p).normalize());
        if facing > 0.1 {
            assert!(blue(k), "texel {k} at ({u}, {v}) faces the eye but is not painted");
        } else if facing < -0.1 {
            assert!(!blue(k), "texel {k} at ({u}, {v}) is behind the sphere but painted");
        }
    }
}

#[test]
fn undo_and_redo_restore_the_atlas_exactly() {
    let mut s = sphere_session(128);
    let start = s.atlas().codes(Channel::Specular).to_vec();
    let stroke = brush(r#"{"radius": 30, "hardness": 0.3, "opacity": 0.7, "channel": "specular", "value": 1.0}"#);
    s.stroke(stroke, &[[100.0, 120.0], [220.0, 130.0]]).unwrap();
    let painted = s.atlas().codes(Channel::Specular).to_vec();
    assert_ne!(painted, start);
    assert!(s.undo(false) > 0);
    assert_eq!(s.atlas().codes(Channel::Specular), start.as_slice());
    assert!(s.undo(true) > 0);
    assert_eq!(s.atlas().codes(Channel::Specular), painted.as_slice());
    // The eraser paints back what was loaded.
    s.stroke(brush(r#"{"radius": 300, "hardness": 1, "channel": "specular", "erase": true}"#), &[[160.0, 120.0]])
        .unwrap();
    assert_eq!(s.atlas().codes(Channel::Specular), start.as_slice());
    // Sixty strokes across the sphere (opacity above the alpha cutoff: no holes), all undone, and the two
    // before them.
    for k in 0..60 {
        let b = brush(&format!(r#"{{"radius": 16, "channel": "opacity", "value": {}}}"#, 0.6 + 0.005 * k as f32));
        let x = 70.0 + 3.0 * k as f32;
        assert!(s.stroke(b, &[[x, 120.0]]).unwrap() > 0, "the stroke at x = {x}");
    }
    assert_eq!(s.state().undo, 62);
    for _ in 0..62 {
        assert!(s.undo(false) > 0);
    }
    assert_eq!(s.undo(false), 0);
    assert_eq!(s.atlas().codes(Channel::Opacity), vec![255; 128 * 128].as_slice());
}

/// What the page shows is what `wrinkle render` shows of the saved scene, and opening the saved scene
/// resumes with the same channels.
#[test]
fn the_saved_scene_renders_what_was_painted_and_resumes() {
    let dir = temp_dir("save");
    let mut s = sphere_session(256);
    s.stroke(brush(r#"{"radius": 25, "color": [0.1, 0.8, 0.2]}"#), &[[120.0, 100.0], [200.0, 140.0]]).unwrap();
    s.stroke(brush(r#"{"radius": 20, "channel": "height", "value": 1.0}"#), &[[160.0, 80.0]]).unwrap();
    s.stroke(brush(r#"{"radius": 15, "channel": "opacity", "value": 0.0, "hardness": 1}"#), &[[190.0, 170.0]]).unwrap();
    s.stroke(brush(r#"{"radius": 20, "channel": "specular", "value": 0.0}"#), &[[140.0, 150.0]]).unwrap();
    let shown = s.frame().unwrap().srgb8();
    let saved = s.save(Some(&dir)).unwrap();
    assert_eq!(saved.files.len(), 5);
    let scene = Scene::load(&saved.scene).unwrap();
    let (w, h) = VIEW;
    let rendered = wrinkle::render(&scene, &RenderOptions { width: w, height: h, ..RenderOptions::default() }).unwrap();
    let differing = shown.iter().zip(rendered.srgb8()).filter(|(a, b)| **a != *b).count();
    assert_eq!(differing, 0, "{differing} of {} channels differ between the page and the saved scene", shown.len());
    // The hole cut by the opacity channel shows the background.
    let resumed = Session::open(&saved.scene, &opening(0, 64)).unwrap();
    assert_eq!(resumed.atlas().size, 256, "the saved channels keep their size");
    for channel in Channel::ALL {
        assert_eq!(resumed.atlas().codes(channel), s.atlas().codes(channel), "{channel:?} resumed");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Two (u,v) islands that meet in 3D along x = 0 (a flat square whose halves lie apart in the atlas): a dab
/// on the seam paints both islands up to their borders and past them into the gutter.
#[test]
fn a_stroke_across_an_atlas_seam_leaves_no_gap() {
    let dir = temp_dir("seam");
    std::fs::write(
        dir.join("halves.obj"),
        "v -1 -1 0\nv 0 -1 0\nv 0 1 0\nv -1 1 0\nv 0 -1 0\nv 1 -1 0\nv 1 1 0\nv 0 1 0\n\
         vt 0.1 0.3\nvt 0.4 0.3\nvt 0.4 0.7\nvt 0.1 0.7\nvt 0.6 0.3\nvt 0.9 0.3\nvt 0.9 0.7\nvt 0.6 0.7\n\
         f 1/1 2/2 3/3\nf 1/1 3/3 4/4\nf 5/5 6/6 7/7\nf 5/5 7/7 8/8\n",
    )
    .unwrap();
    let size = 200;
    let mut s = Session::open(&dir.join("halves.obj"), &opening(0, size)).unwrap();
    s.set_camera(Orbit { yaw: 0.0, pitch: 0.0, distance: 4.0, target: [0.0; 3] }).unwrap();
    s.stroke(brush(r#"{"radius": 0.3, "space": "object", "hardness": 1, "color": [1, 1, 0]}"#), &[[160.0, 120.0]])
        .unwrap();
    let codes = s.atlas().codes(Channel::Color);
    let yellow = |u: f32, v: f32| {
        let k = ((1.0 - v) * size as f32) as usize * size + (u * size as f32) as usize;
        codes[k].to_le_bytes()[..3] == [255, 255, 0]
    };
    // Along the seam's rows within the brush (y from -0.25 to 0.25: v from 0.4375 to 0.5625), both islands'
    // border columns and the gutter's first texels past them.
    for row in 0..20 {
        let v = 0.445 + row as f32 * 0.0055;
        for u in [0.398, 0.402, 0.41, 0.59, 0.598, 0.602] {
            assert!(yellow(u, v), "texel at ({u}, {v}) by the seam is not painted");
        }
        // Beyond the brush (0.3 in x is 0.09 in u) and beyond the gutter: untouched.
        for u in [0.28, 0.72, 0.45, 0.55] {
            assert!(!yellow(u, v), "texel at ({u}, {v}) is painted");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

async fn call(router: axum::Router, method: &str, uri: &str, body: &str) -> (StatusCode, String) {
    let request = Request::builder().method(method).uri(uri).body(Body::from(body.to_owned())).unwrap();
    let response = router.oneshot(request).await.unwrap();
    let status = response.status();
    let bytes = response.into_body().collect().await.unwrap().to_bytes();
    (status, String::from_utf8_lossy(&bytes).into_owned())
}

#[tokio::test]
async fn malformed_requests_are_refused_with_their_reason() {
    let session = tokio::task::spawn_blocking(|| sphere_session(64)).await.unwrap();
    let router = wrinkle_paint::router(Arc::new(Mutex::new(session)));
    let refused = [
        ("/api/stroke", r#"{"points": [[10, 10]], "radius": 1e9, "color": [1, 0, 0]}"#, "radius"),
        ("/api/stroke", r#"{"points": [[10, 10]], "radius": 5, "channel": "gloss", "value": 1}"#, "unknown channel"),
        ("/api/stroke", r#"{"radius": 5, "color": [1, 0, 0]}"#, "points"),
        ("/api/stroke", r#"{"points": [], "radius": 5, "color": [1, 0, 0]}"#, "points"),
        ("/api/stroke", r#"{"points": [[1, 2]], "radius": 5, "color": [1, 0, 0], "size": 3}"#, "size"),
        ("/api/stroke", r#"{"points": [[1, 2]], "radius": 5, "channel": "height"}"#, "value"),
        ("/api/stroke", "not json", "malformed"),
        ("/api/camera", r#"{"yaw": 0, "pitch": 0, "distance": -1}"#, "distance"),
        ("/api/camera", r#"{"yaw": 0, "pitch": 0, "distance": 3, "zoom": 2}"#, "zoom"),
        ("/api/camera", r#"{"yaw": 0, "pitch": 0, "distance": 3, "width": 100000}"#, "width"),
    ];
    for (uri, body, reason) in refused {
        let (status, text) = call(router.clone(), "POST", uri, body).await;
        assert_eq!(status, StatusCode::BAD_REQUEST, "{uri} {body}: {text}");
        assert!(text.contains("\"error\"") && text.contains(reason), "{uri} {body}: {text}");
    }
    // The server goes on: a stroke off the model changes nothing, one on it something.
    let (status, text) =
        call(router.clone(), "POST", "/api/stroke", r#"{"points": [[2, 2]], "radius": 3, "color": [1, 0, 0]}"#).await;
    assert_eq!((status, text.as_str()), (StatusCode::OK, r#"{"texels":0}"#));
    let (status, text) =
        call(router.clone(), "POST", "/api/stroke", r#"{"points": [[160, 120]], "radius": 30, "color": [1, 0, 0]}"#)
            .await;
    assert_eq!(status, StatusCode::OK);
    assert_ne!(text, r#"{"texels":0}"#);
    let (status, text) = call(router.clone(), "GET", "/api/state", "").await;
    assert_eq!(status, StatusCode::OK);
    let state: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(
        (state["width"].as_u64(), state["atlas_size"].as_u64(), state["undo"].as_u64()),
        (Some(320), Some(64), Some(1))
    );
    let (status, _) = call(router.clone(), "GET", "/api/atlas/gloss.png", "").await;
    assert_eq!(status, StatusCode::NOT_FOUND);
    let (status, text) = call(router, "GET", "/api/frame.png", "").await;
    assert_eq!(status, StatusCode::OK);
    assert!(text.as_bytes().starts_with(b"\x89PNG") || text.starts_with("\u{FFFD}PNG"));
}

#[test]
fn models_that_cannot_be_painted_are_refused_clearly() {
    let missing = Session::open(Path::new("no/such/model.obj"), &opening(0, 64)).err().unwrap().to_string();
    assert!(missing.contains("model.obj"), "{missing}");
    let beyond = Session::open(&repo().join("scenes/paint_sphere.toml"), &opening(3, 64)).err().unwrap().to_string();
    assert!(beyond.contains("object") && beyond.contains('1'), "{beyond}");
    let huge = Session::open(&repo().join("scenes/paint_sphere.toml"), &opening(0, 100_000)).err().unwrap().to_string();
    assert!(huge.contains("atlas_size"), "{huge}");
}

/// A cube without texture coordinates gets an atlas of six charts; a stroke on its edge paints both faces
/// up to the edge (the seam between their charts shows no gap in the frame); the saved scene (its model
/// written with the atlas's (u,v)) renders what was shown and resumes.
#[test]
fn a_model_without_texture_coordinates_gets_an_atlas_and_paints_across_its_seams() {
    let dir = temp_dir("unwrap");
    let mut obj = String::from("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n");
    for [a, b, c, d] in [[1, 3, 4, 2], [5, 6, 8, 7], [1, 2, 6, 5], [3, 7, 8, 4], [1, 5, 7, 3], [2, 4, 8, 6]] {
        obj += &format!("f {a} {b} {c}\nf {a} {c} {d}\n");
    }
    std::fs::write(dir.join("cube.obj"), obj).unwrap();
    let mut s = Session::open(&dir.join("cube.obj"), &opening(0, 256)).unwrap();
    let unwrapped = s.state().unwrapped.expect("an atlas is laid out");
    assert_eq!(unwrapped.charts, 6);
    assert!(unwrapped.stretch_max < 1.001 && unwrapped.utilisation > 0.3);
    let orbit = Orbit { yaw: 45.0, pitch: 30.0, distance: 4.0, target: [0.5; 3] };
    s.set_camera(orbit).unwrap();
    let before = s.frame().unwrap().srgb8();
    // The view's centre sees the edge x = 1, z = 1 (at y = 0.91).
    s.stroke(brush(r#"{"radius": 0.2, "space": "object", "hardness": 1, "color": [1, 1, 0]}"#), &[[160.0, 120.0]])
        .unwrap();
    let after = s.frame().unwrap().srgb8();
    let camera = wrinkle::CameraDesc::looking_at(orbit.eye(), Vec3::splat(0.5)).unwrap();
    let camera = wrinkle::CameraDesc { projection: wrinkle::Projection::Perspective { fov_y: 35.0 }, ..camera };
    let screen = camera.screen(VIEW.0, VIEW.1);
    for p in
        [Vec3::new(1.0, 0.85, 0.97), Vec3::new(0.97, 0.85, 1.0), Vec3::new(1.0, 0.85, 0.9), Vec3::new(0.9, 0.85, 1.0)]
    {
        let (at, _) = screen.project(screen.world_to_camera.transform_point3(p));
        let k = 3 * (at.y as usize * VIEW.0 + at.x as usize);
        assert!(
            after[k + 2] + 40 < before[k + 2],
            "the point {p} by the edge is not painted (blue {} -> {})",
            before[k + 2],
            after[k + 2]
        );
    }
    let saved = s.save(Some(&dir.join("saved"))).unwrap();
    assert!(saved.files.iter().any(|f| f.ends_with("model.obj")));
    let scene = Scene::load(&saved.scene).unwrap();
    let mut shown = scene;
    (shown.camera.eye, shown.camera.look_at, shown.camera.up) = (orbit.eye(), Vec3::splat(0.5), Vec3::Y);
    let rendered =
        wrinkle::render(&shown, &RenderOptions { width: VIEW.0, height: VIEW.1, ..RenderOptions::default() });
    let differing = after.iter().zip(rendered.unwrap().srgb8()).filter(|(a, b)| **a != *b).count();
    assert_eq!(differing, 0, "{differing} channels differ between the page and the saved scene");
    let resumed = Session::open(&saved.scene, &opening(0, 64)).unwrap();
    assert!(resumed.state().unwrapped.is_none(), "the saved model has its atlas's coordinates");
    assert_eq!(resumed.atlas().codes(Channel::Color), s.atlas().codes(Channel::Color));
    let _ = std::fs::remove_dir_all(&dir);
}

/// A stroke is the brush swept between its dabs' points: each texel takes the falloff of its distance to the
/// segment between them, not to the nearer dab (whose envelope scallops the stroke's edge, and shows as
/// beads in the bumps of a height stroke).
#[test]
fn a_stroke_sweeps_the_brush_between_its_dabs() {
    let size = 512;
    let mut s = sphere_session(size);
    // Two dabs exactly (spacing one radius: 20 pixels), symmetric about the view's centre.
    let stroke = brush(r#"{"radius": 20, "spacing": 1, "hardness": 0, "channel": "specular", "value": 1.0}"#);
    s.stroke(stroke.clone(), &[[150.0, 120.0], [170.0, 120.0]]).unwrap();
    let ((a, _), (b, radius)) = (seen_on_sphere(150.0, 120.0, 20.0), seen_on_sphere(170.0, 120.0, 20.0));
    let sphere = Surface::Sphere { radius: 1.0 };
    let codes = s.atlas().codes(Channel::Specular);
    let mut checked = 0;
    for (k, &code) in codes.iter().enumerate() {
        let (u, v) = texel_uv(k, size);
        let p = sphere.position(u, v);
        let ab = b - a;
        let t = ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
        let d = p.distance(a + ab * t);
        if d > 0.97 * radius {
            continue;
        }
        let expected = Channel::Specular.encode(Vec3::splat(0.3).lerp(Vec3::ONE, stroke.weight(d, radius)));
        assert!(code.abs_diff(expected) <= 2, "texel at ({u}, {v}): {code} against {expected}");
        checked += 1;
    }
    assert!(checked > 1000, "{checked}");
}

/// With x-mirror symmetry a dab on the sphere's right paints its mirror image on the left (x -> -x in
/// object space), and nothing else.
#[test]
fn x_mirror_paints_the_mirror_image_too() {
    let size = 256;
    let mut s = sphere_session(size);
    let before = s.atlas().codes(Channel::Color).to_vec();
    s.stroke(brush(r#"{"radius": 15, "hardness": 1, "color": [0, 1, 1], "mirror_x": true}"#), &[[200.0, 110.0]])
        .unwrap();
    let (hit, radius) = seen_on_sphere(200.0, 110.0, 15.0);
    let mirrored = Vec3::new(-hit.x, hit.y, hit.z);
    let sphere = Surface::Sphere { radius: 1.0 };
    let after = s.atlas().codes(Channel::Color);
    let (mut left, mut right) = (0usize, 0usize);
    for k in 0..size * size {
        let (u, v) = texel_uv(k, size);
        let p = sphere.position(u, v);
        let painted = after[k] != before[k];
        let near = p.distance(hit).min(p.distance(mirrored));
        if near < 0.97 * radius {
            assert!(painted, "texel at ({u}, {v}) within the brush or its mirror image is not painted");
            *(if p.x < 0.0 { &mut left } else { &mut right }) += 1;
        } else if near > 1.03 * radius {
            assert!(!painted, "texel at ({u}, {v}) outside both is painted");
        }
    }
    assert!(left > 50 && left.abs_diff(right) * 10 < right, "left {left}, right {right}");
}

/// The recovery copy: written once the atlas changes (not before), a scene that resumes what was painted.
#[test]
fn a_recovery_copy_keeps_what_was_painted() {
    let dir = temp_dir("recovery");
    let mut s = sphere_session(64);
    s.save_dir = dir.clone();
    assert_eq!(s.write_recovery().unwrap(), None, "nothing painted, nothing written");
    s.stroke(brush(r#"{"radius": 40, "color": [1, 0, 1]}"#), &[[160.0, 120.0]]).unwrap();
    let scene = s.write_recovery().unwrap().expect("a copy after a stroke");
    assert!(scene.starts_with(dir.join(".wrinkle-paint-recovery")));
    assert_eq!(s.write_recovery().unwrap(), None, "unchanged since the copy");
    let resumed = Session::open(&scene, &opening(0, 64)).unwrap();
    assert_eq!(resumed.atlas().codes(Channel::Color), s.atlas().codes(Channel::Color));
    let _ = std::fs::remove_dir_all(&dir);
}
