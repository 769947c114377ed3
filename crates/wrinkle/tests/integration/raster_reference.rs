//! The rasterizer and the AOVs against independent references: analytic ray-plane and ray-sphere
//! intersections through an f64 camera written from the scene format's definition, and the exact
//! outline (convex hull of the projected vertices) of the tessellated geometry.
//!
//! Run with `cargo test --release -p wrinkle --test integration raster_reference -- --nocapture` to see the measured figures.

use crate::common::*;
use glam::{Affine3A, DVec3, Quat, Vec3};
use std::path::Path;
use wrinkle::internals::{cover, grid, Cull, Mesh, ProjectedMesh, SamplePattern, TileOffsets, TriangleSetup};
use wrinkle::Camera;
use wrinkle::{render, Aovs, PixelFilter, Projection, RenderOptions, Sampler, Scene, Surface};

// ---------------------------------------------------------------------------------------------
// 4. Perspective-correct (u,v).
// ---------------------------------------------------------------------------------------------

/// A flat parallelogram seen at a grazing angle (rotated 68 degrees about x, receding) through a wide
/// perspective camera, 1 sample per pixel: at every covered pixel the uv AOV equals (u,v) of the analytic
/// intersection of the ray through the pixel centre with the parallelogram, within 1e-4. Screen-affine
/// interpolation over the same two triangles misses by far more, so the bound does discriminate.
#[test]
fn oblique_plane_uv_is_perspective_correct() {
    let (w, h) = (240, 180);
    let (eye, look_at, fov) = ([0.2, 0.6, 3.0], [0.0, -0.2, -0.5], 55.0);
    // P(0,0), P(1,0), P(1,1), P(0,1): a parallelogram (P00 + P11 = P10 + P01).
    let corners = [[-1.8, -1.35, 0.0], [1.95, -1.65, 0.0], [2.55, 1.2, 0.0], [-1.2, 1.5, 0.0]];
    let transform = RefTransform { translate: [0.2, -0.3, -1.0], rotate: [-68.0, 20.0, 5.0], scale: 1.0 };
    let scene = format!(
        "{}[[object]]\nshape = \"patch\"\ncorners = [{}]\ntransform = {}\n",
        camera_toml(eye, look_at, fov),
        corners.map(arr).join(", "),
        transform.toml()
    );
    let frame = render_all_aovs(&scene, std::path::Path::new("."), w, h, 1);
    let uvs = frame.uv.as_ref().expect("uv AOV");
    let cam = RefCamera::perspective(eye, look_at, [0.0, 1.0, 0.0], fov, w, h);

    let world = corners.map(|c| transform.point(DVec3::from(c)));
    let (p00, e1, e2) = (world[0], world[1] - world[0], world[3] - world[0]);
    let normal = e1.cross(e2);
    // The two triangles of the 1 x 1 grid, (0,0) (1,0) (1,1) and (0,0) (1,1) (0,1), projected exactly.
    let screen = world.map(|p| cam.project(p));
    let tri_uv = [[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]], [[0.0, 0.0], [1.0, 1.0], [0.0, 1.0]]];
    let tri_screen = [[screen[0], screen[1], screen[2]], [screen[0], screen[2], screen[3]]];

    let (mut err, mut affine_err, mut mismatches) = (MaxErr::default(), 0.0f64, 0usize);
    for j in 0..h {
        for i in 0..w {
            let got = uvs[j * w + i];
            let (o, d) = cam.pixel_ray(i, j);
            let exact = ray_plane(o, d, p00, normal).map(|t| parallelogram_uv(o + t * d, p00, e1, e2));
            let margin = 1e-3;
            let inside = exact.is_some_and(|(u, v)| [u, v].iter().all(|&x| x > margin && x < 1.0 - margin));
            let outside = exact.is_none_or(|(u, v)| [u, v].iter().any(|&x| x < -margin || x > 1.0 + margin));
            if got[0].is_nan() {
                mismatches += usize::from(inside);
                continue;
            }
            mismatches += usize::from(outside);
            let Some((u, v)) = exact else { continue };
            let e = (got[0] as f64 - u).abs().max((got[1] as f64 - v).abs());
            err.add(e, || format!("pixel ({i},{j}): got {got:?}, exact ({u:.6}, {v:.6})"));

            // What screen-affine interpolation of (u,v) would give here.
            let p = [i as f64 + 0.5, j as f64 + 0.5];
            let bary = |t: &[[f64; 2]; 3]| {
                let area = (t[1][0] - t[0][0]) * (t[2][1] - t[0][1]) - (t[1][1] - t[0][1]) * (t[2][0] - t[0][0]);
                let b1 = ((p[0] - t[0][0]) * (t[2][1] - t[0][1]) - (p[1] - t[0][1]) * (t[2][0] - t[0][0])) / area;
                let b2 = ((t[1][0] - t[0][0]) * (p[1] - t[0][1]) - (t[1][1] - t[0][1]) * (p[0] - t[0][0])) / area;
                [1.0 - b1 - b2, b1, b2]
            };
            let (b, k) = {
                let b0 = bary(&tri_screen[0]);
                if b0.iter().all(|&x| x >= -1e-9) {
                    (b0, 0)
                } else {
                    (bary(&tri_screen[1]), 1)
                }
            };
            let affine = [0, 1].map(|c| (0..3).map(|m| b[m] * tri_uv[k][m][c]).sum::<f64>());
            affine_err = affine_err.max((affine[0] - u).abs().max((affine[1] - v).abs()));
        }
    }
    println!(
        "oblique plane: {} covered pixels, max |uv - exact| {:.3e} (bound 1e-4) at {}; screen-affine would be off by {:.3e}",
        err.count, err.max, err.at, affine_err
    );
    assert!(err.count > w * h / 5, "only {} pixels covered", err.count);
    assert_eq!(mismatches, 0, "pixels covered (or not) against the analytic outline");
    assert!(err.max < 1e-4, "uv off by {} at {}", err.max, err.at);
    assert!(affine_err > 100.0 * 1e-4, "the view is not oblique enough to tell perspective from affine: {affine_err}");
}

// ---------------------------------------------------------------------------------------------
// 5. Watertightness.
// ---------------------------------------------------------------------------------------------

/// `spp` stratified samples a pixel, box-filtered.
fn stratified(spp: usize) -> SamplePattern {
    SamplePattern::new(spp, Sampler::Stratified, PixelFilter::default()).expect("a stratified pattern")
}

/// Sets up a mesh's triangles for `camera` and counts, per sample, how many of them cover it
/// (`(y * w + x) * spp + s`), through the rasterizer's own coverage function over the whole screen.
fn coverage(camera: &Camera, mesh: &Mesh, object_to_world: Affine3A, cull: bool, pattern: &SamplePattern) -> Vec<u16> {
    let (w, h, spp) = (camera.width as usize, camera.height as usize, pattern.count());
    let mut setup = TriangleSetup::new(camera, pattern);
    let vertices =
        setup.project_vertices(&mesh.positions, Some(&mesh.uvs), &(camera.world_to_camera * object_to_world));
    let cull = if cull { Cull::FacingAway { mirrored: false } } else { Cull::Nothing };
    let part =
        ProjectedMesh { vertices: &vertices, triangles: &mesh.triangles, surface: 0, first: 0, cull, outline: None };
    let triangles = setup.triangles_of(part);
    let samples = TileOffsets::of(pattern, (0, 0, w, h));
    let mut count = vec![0u16; w * h * spp];
    for t in &triangles {
        cover(t, &samples, (0, 0, w, h), |x, y, s, _, _| count[(y * w + x) * spp + s] += 1);
    }
    count
}

/// Screen positions of every sample of the pattern, in the order of `coverage`.
fn sample_positions(w: usize, h: usize, pattern: &SamplePattern) -> Vec<[f64; 2]> {
    let samples = TileOffsets::of(pattern, (0, 0, w, h));
    let mut out = Vec::with_capacity(w * h * pattern.count());
    for y in 0..h {
        for x in 0..w {
            for s in 0..pattern.count() {
                let (ox, oy) = samples.offset(x, y, s);
                out.push([x as f64 + ox as f64, y as f64 + oy as f64]);
            }
        }
    }
    out
}

/// The convex hull of points (Andrew's monotone chain), ordered so that interior points lie to the left.
fn convex_hull(mut pts: Vec<[f64; 2]>) -> Vec<[f64; 2]> {
    pts.sort_by(|a, b| a.partial_cmp(b).expect("finite points"));
    pts.dedup();
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
    let mut hull: Vec<[f64; 2]> = Vec::new();
    for pass in 0..2 {
        let start = hull.len();
        let ordered: Box<dyn Iterator<Item = &[f64; 2]>> =
            if pass == 0 { Box::new(pts.iter()) } else { Box::new(pts.iter().rev()) };
        for &p in ordered {
            while hull.len() >= start + 2 && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0 {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    hull
}

/// Signed distance from p to the boundary of a convex polygon from `convex_hull`: positive inside.
fn depth_inside(hull: &[[f64; 2]], p: [f64; 2]) -> f64 {
    (0..hull.len())
        .map(|k| {
            let (a, b) = (hull[k], hull[(k + 1) % hull.len()]);
            ((b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])) / (b[0] - a[0]).hypot(b[1] - a[1])
        })
        .fold(f64::INFINITY, f64::min)
}

/// How far (pixels) from the reference outline a sample must be to count as inside or outside:
/// snapping moves vertices by at most 1/512 pixel per axis.
const OUTLINE_MARGIN: f64 = 0.02;

/// Coverage counts against a convex outline: (samples inside, largest count, inside samples not covered
/// exactly once, outside samples covered).
fn check_against_outline(count: &[u16], samples: &[[f64; 2]], hull: &[[f64; 2]]) -> (usize, u16, usize, usize) {
    let (mut inside, mut holes, mut spill) = (0, 0, 0);
    for (&c, &p) in count.iter().zip(samples) {
        let d = depth_inside(hull, p);
        if d >= OUTLINE_MARGIN {
            inside += 1;
            holes += usize::from(c != 1);
        } else if d <= -OUTLINE_MARGIN {
            spill += usize::from(c != 0);
        }
    }
    (inside, count.iter().copied().max().unwrap_or(0), holes, spill)
}

#[derive(Clone, Copy)]
struct SphereView {
    name: &'static str,
    eye: [f64; 3],
    look_at: [f64; 3],
    /// Some(fov_y) for perspective, None for orthographic with `ORTHO_HEIGHT`.
    fov: Option<f64>,
    size: (usize, usize),
    segments: (usize, usize),
    rotate: [f32; 3],
    translate: [f32; 3],
    spp: usize,
    /// Sobol samples spread over this pixel filter (reaching past the pixel), where given; else stratified.
    sobol_filter: Option<&'static str>,
}

const ORTHO_HEIGHT: f64 = 2.6;

/// A closed tessellated sphere, drawn with back faces culled, at awkward angles, from off-centre
/// cameras, with odd tessellation counts and 1, 4 and 16 samples per pixel (and 8 Sobol samples spread over
/// a Lanczos filter, which reach three pixels past their own, also past the frame): no sample is covered twice
/// by front faces, and every sample inside the exact outline of the polyhedron (the convex hull of its
/// projected vertices, computed here in f64) by more than 0.02 pixel is covered exactly once (nothing
/// outside it is covered). The tessellation is checked to be convex first, so that this reference holds.
#[test]
fn tessellated_sphere_is_watertight() {
    let off_centre = SphereView {
        name: "off-centre and cut by the border, 61 x 29, spp 1",
        eye: [-0.4, 0.9, 3.5],
        look_at: [1.3, -0.8, 0.0],
        fov: Some(40.0),
        size: (200, 150),
        segments: (61, 29),
        rotate: [13.7, 71.3, -42.1],
        translate: [0.05, 0.1, -0.2],
        spp: 1,
        sobol_filter: None,
    };
    let views = [
        SphereView {
            name: "tilted, 32 x 16, spp 16",
            eye: [0.3, 0.2, 4.0],
            look_at: [0.0; 3],
            fov: Some(40.0),
            size: (160, 120),
            segments: (32, 16),
            rotate: [37.0, 23.0, 11.0],
            translate: [0.0; 3],
            spp: 16,
            sobol_filter: None,
        },
        SphereView {
            name: "pole towards the eye, 13 x 7, spp 16",
            eye: [0.0, 0.0, 3.2],
            look_at: [0.0; 3],
            fov: Some(40.0),
            size: (128, 128),
            segments: (13, 7),
            rotate: [90.0, 0.0, 0.0],
            translate: [0.0; 3],
            spp: 16,
            sobol_filter: None,
        },
        off_centre,
        SphereView {
            name: "close up, wide angle, odd image, 45 x 23, spp 4",
            eye: [0.2, -0.3, 1.9],
            look_at: [0.0; 3],
            fov: Some(60.0),
            size: (97, 131),
            segments: (45, 23),
            rotate: [-20.0, 110.0, 5.0],
            translate: [0.0; 3],
            spp: 4,
            sobol_filter: None,
        },
        SphereView {
            name: "orthographic, 17 x 9, spp 16",
            eye: [1.0, 2.0, 3.0],
            look_at: [0.0; 3],
            fov: None,
            size: (150, 110),
            segments: (17, 9),
            rotate: [0.0, 0.0, 33.0],
            translate: [0.0; 3],
            spp: 16,
            sobol_filter: None,
        },
        SphereView {
            name: "fine, 100 x 51, spp 1",
            eye: [0.7, -0.4, 3.0],
            look_at: [0.1, 0.05, 0.0],
            fov: Some(45.0),
            size: (240, 200),
            segments: (100, 51),
            rotate: [5.0, 5.0, 5.0],
            translate: [0.0; 3],
            spp: 1,
            sobol_filter: None,
        },
        SphereView {
            name: "off-centre, cut by the border, 8 Sobol samples over a Lanczos filter",
            spp: 8,
            sobol_filter: Some("lanczos"),
            ..off_centre
        },
    ];
    for view in &views {
        let (w, h) = view.size;
        let mesh = grid(&Surface::Sphere { radius: 1.0 }, view.segments.0, view.segments.1);
        assert_convex(&mesh, view.name);
        let r = view.rotate.map(f32::to_radians);
        let rotation = Quat::from_rotation_z(r[2]) * Quat::from_rotation_y(r[1]) * Quat::from_rotation_x(r[0]);
        let to_world = Affine3A::from_rotation_translation(rotation, Vec3::from(view.translate));
        let up = [0.0, 1.0, 0.0];
        let (camera, reference) = match view.fov {
            Some(fov) => (
                Camera::new(
                    f3(view.eye),
                    f3(view.look_at),
                    Vec3::Y,
                    Projection::Perspective { fov_y: fov as f32 },
                    w as u32,
                    h as u32,
                ),
                RefCamera::perspective(view.eye, view.look_at, up, fov, w, h),
            ),
            None => (
                Camera::new(
                    f3(view.eye),
                    f3(view.look_at),
                    Vec3::Y,
                    Projection::Orthographic { height: ORTHO_HEIGHT as f32 },
                    w as u32,
                    h as u32,
                ),
                RefCamera::orthographic(view.eye, view.look_at, up, ORTHO_HEIGHT, w, h),
            ),
        };
        let pattern = match view.sobol_filter {
            None => stratified(view.spp),
            Some(f) => SamplePattern::new(view.spp, Sampler::Sobol, PixelFilter::parse(f).unwrap()).unwrap(),
        };
        let count = coverage(&camera, &mesh, to_world, true, &pattern);
        let hull =
            convex_hull(mesh.positions.iter().map(|&p| reference.project(d3(to_world.transform_point3(p)))).collect());
        let (inside, max, holes, spill) = check_against_outline(&count, &sample_positions(w, h, &pattern), &hull);
        println!(
            "sphere [{}]: {inside} samples inside the outline, max coverage {max} (bound 1), {holes} inside not covered once, \
             {spill} outside covered (bound 0 each)",
            view.name
        );
        assert!(inside > w * h * view.spp / 10, "[{}] the sphere covers too little of the screen: {inside}", view.name);
        assert!(max <= 1, "[{}] a sample is covered {max} times by front faces", view.name);
        assert_eq!(holes, 0, "[{}] samples inside the silhouette not covered exactly once", view.name);
        assert_eq!(spill, 0, "[{}] samples outside the silhouette covered", view.name);
    }
}

fn f3(v: [f64; 3]) -> Vec3 {
    DVec3::from(v).as_vec3()
}

/// Every vertex lies behind (or on) the plane of every face: the mesh is a convex polyhedron, so a ray
/// through its outline crosses exactly one front face.
fn assert_convex(mesh: &Mesh, name: &str) {
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|k| d3(mesh.positions[k as usize]));
        let n = (b - a).cross(c - a);
        if n.length() < 1e-9 {
            continue;
        }
        let n = n.normalize();
        let worst = mesh.positions.iter().map(|&p| n.dot(d3(p) - a)).fold(f64::NEG_INFINITY, f64::max);
        assert!(worst < 1e-6, "[{name}] the tessellation is not convex (a vertex {worst} in front of a face)");
    }
}

/// Vertices that land exactly on sample positions exercise the fill rule: a patch grid seen head-on
/// through an orthographic camera of one world unit per pixel, its vertices on pixel centres (grids of
/// 4 x 4, 4 x 5 and 1 x 1 pixels: with 1 x 1 every sample is a vertex and every edge runs through samples),
/// from the front and from behind, culling off. Samples strictly inside the patch are covered exactly once,
/// samples outside never, samples on its border at most once.
#[test]
fn fill_rule_with_vertices_on_samples() {
    let (w, h) = (64, 64);
    // World x = pixel x - 32 and y = 32 - pixel y: the corners (-20.5, -19.5) and (19.5, 20.5) are pixel centres.
    let corners = [[-20.5, -19.5, 0.0], [19.5, -19.5, 0.0], [19.5, 20.5, 0.0], [-20.5, 20.5, 0.0]];
    let patch = Surface::Patch { corners: corners.map(f3) };
    for (nu, nv) in [(10, 10), (10, 8), (40, 40)] {
        let mesh = grid(&patch, nu, nv);
        for eye in [[0.0, 0.0, 10.0], [0.0, 0.0, -10.0]] {
            for spp in [1, 16] {
                let camera = Camera::new(
                    f3(eye),
                    Vec3::ZERO,
                    Vec3::Y,
                    Projection::Orthographic { height: h as f32 },
                    w as u32,
                    h as u32,
                );
                let reference = RefCamera::orthographic(eye, [0.0; 3], [0.0, 1.0, 0.0], h as f64, w, h);
                let count = coverage(&camera, &mesh, Affine3A::IDENTITY, false, &stratified(spp));
                let screen = corners.map(|c| reference.project(DVec3::from(c)));
                let (x0, x1) = (
                    screen.iter().map(|p| p[0]).fold(f64::INFINITY, f64::min),
                    screen.iter().map(|p| p[0]).fold(f64::NEG_INFINITY, f64::max),
                );
                let (y0, y1) = (
                    screen.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min),
                    screen.iter().map(|p| p[1]).fold(f64::NEG_INFINITY, f64::max),
                );
                assert_eq!((x0.fract(), y0.fract()), (0.5, 0.5), "corners must project to pixel centres");
                let (mut inside, mut bad) = (0, Vec::new());
                for (&c, p) in count.iter().zip(sample_positions(w, h, &stratified(spp))) {
                    let strictly_inside = p[0] > x0 && p[0] < x1 && p[1] > y0 && p[1] < y1;
                    let strictly_outside = p[0] < x0 || p[0] > x1 || p[1] < y0 || p[1] > y1;
                    inside += usize::from(strictly_inside);
                    let ok = if strictly_inside {
                        c == 1
                    } else if strictly_outside {
                        c == 0
                    } else {
                        c <= 1
                    };
                    if !ok {
                        bad.push((p, c));
                    }
                }
                println!(
                    "fill rule: grid {nu} x {nv}, eye z {}, spp {spp}: {inside} inside samples, {} wrong",
                    eye[2],
                    bad.len()
                );
                assert!(inside > 1000);
                assert!(
                    bad.is_empty(),
                    "grid {nu} x {nv}, eye {eye:?}, spp {spp}: (sample, count) {:?}",
                    &bad[..bad.len().min(10)]
                );
            }
        }
    }
}

/// An open quad of two triangles (a flat parallelogram) seen in perspective from the front and from
/// behind, culling off: every sample inside its projected outline (a convex quadrilateral computed here)
/// is covered exactly once, including those along the shared diagonal, and nothing outside is covered.
#[test]
fn open_quad_from_both_sides() {
    let (w, h) = (151, 113);
    let corners = [[-1.0, -0.7, 0.2], [1.1, -0.9, -0.1], [0.9, 1.0, -0.3], [-1.2, 1.2, 0.0]];
    let patch = Surface::Patch { corners: corners.map(f3) };
    let mesh = grid(&patch, 1, 1);
    assert_eq!(mesh.triangles.len(), 2);
    for eye in [[0.4, -0.3, 3.0], [-0.5, 0.6, -2.8]] {
        for spp in [1, 16] {
            let camera =
                Camera::new(f3(eye), Vec3::ZERO, Vec3::Y, Projection::Perspective { fov_y: 50.0 }, w as u32, h as u32);
            let reference = RefCamera::perspective(eye, [0.0; 3], [0.0, 1.0, 0.0], 50.0, w, h);
            let count = coverage(&camera, &mesh, Affine3A::IDENTITY, false, &stratified(spp));
            let hull = convex_hull(corners.iter().map(|&c| reference.project(DVec3::from(c))).collect());
            assert_eq!(hull.len(), 4);
            let (inside, max, holes, spill) =
                check_against_outline(&count, &sample_positions(w, h, &stratified(spp)), &hull);
            println!("open quad, eye {eye:?}, spp {spp}: {inside} inside samples, max coverage {max}, {holes} holes, {spill} spilled");
            assert!(inside > w * h * spp / 10);
            assert!(max <= 1, "a sample covered {max} times");
            assert_eq!((holes, spill), (0, 0), "eye {eye:?} spp {spp}");
        }
    }
}

/// A large floor grid that passes under and behind the eye, so that its triangles are cut by the near
/// plane and the guard band: every sample whose ray meets the floor inside the patch (analytic ray-plane
/// intersection) is covered exactly once, every sample whose ray misses it is not covered.
#[test]
fn clipped_floor_is_watertight() {
    let (w, h) = (160, 120);
    let corners = [[-30.0, -1.0, 30.0], [30.0, -1.0, 30.0], [30.0, -1.0, -30.0], [-30.0, -1.0, -30.0]];
    let mesh = grid(&Surface::Patch { corners: corners.map(f3) }, 9, 7);
    let (eye, look_at) = ([0.3, 0.0, 0.2], [0.0, -0.45, -1.0]);
    let camera =
        Camera::new(f3(eye), f3(look_at), Vec3::Y, Projection::Perspective { fov_y: 70.0 }, w as u32, h as u32);
    let reference = RefCamera::perspective(eye, look_at, [0.0, 1.0, 0.0], 70.0, w, h);
    let spp = 4;
    let count = coverage(&camera, &mesh, Affine3A::IDENTITY, false, &stratified(spp));
    let [p00, p10, _, p01] = corners.map(DVec3::from);
    let (e1, e2) = (p10 - p00, p01 - p00);
    let (mut inside, mut outside, mut bad) = (0, 0, Vec::new());
    for (&c, p) in count.iter().zip(sample_positions(w, h, &stratified(spp))) {
        let (o, d) = reference.ray(p[0], p[1]);
        let uv = ray_plane(o, d, p00, e1.cross(e2)).map(|t| parallelogram_uv(o + t * d, p00, e1, e2));
        let margin = 1e-3;
        let is_in = uv.is_some_and(|(u, v)| [u, v].iter().all(|&x| x > margin && x < 1.0 - margin));
        let is_out = uv.is_none_or(|(u, v)| [u, v].iter().any(|&x| x < -margin || x > 1.0 + margin));
        inside += usize::from(is_in);
        outside += usize::from(is_out);
        if (is_in && c != 1) || (is_out && c != 0) || c > 1 {
            bad.push((p, c));
        }
    }
    println!("clipped floor: {inside} samples on the floor, {outside} off it, {} wrong", bad.len());
    assert!(inside > w * h * spp / 3 && outside > w * h * spp / 10, "{inside} on, {outside} off");
    assert!(bad.is_empty(), "(sample, count) {:?}", &bad[..bad.len().min(10)]);
}

// ---------------------------------------------------------------------------------------------
// 6. AOVs: depth, id, background.
// ---------------------------------------------------------------------------------------------

/// Two spheres (the second rotated, to check the documented transform) in front of a tilted flat patch,
/// rendered at 1 spp with every AOV, and the analytic scene to compare it with.
struct AovScene {
    w: usize,
    h: usize,
    frame: wrinkle::Frame,
    cam: RefCamera,
    /// Centre, radius and transform of each sphere (objects 0 and 1).
    spheres: [(RefTransform, f64); 2],
    /// The patch (object 2): P00 and its two edges.
    patch: (DVec3, DVec3, DVec3),
}

/// What the ray through a screen position sees first: object index, distance, cosine of the incidence angle.
type Hit = Option<(usize, f64, f64)>;

impl AovScene {
    fn render() -> AovScene {
        let (w, h) = (200, 160);
        let (eye, look_at, fov) = ([0.4, 0.5, 5.0], [0.2, 0.0, 0.0], 45.0);
        let spheres = [
            (RefTransform { translate: [-0.8, 0.0, 0.0], ..RefTransform::IDENTITY }, 1.0),
            (RefTransform { translate: [1.2, 0.4, 0.8], rotate: [30.0, 40.0, 0.0], scale: 1.0 }, 0.6),
        ];
        // A parallelogram: P00 + P11 = P10 + P01.
        let corners = [[-3.0, -2.0, -2.0], [3.0, -2.0, -2.0], [3.0, 2.0, -3.0], [-3.0, 2.0, -3.0]];
        let scene = format!(
            "{}[[object]]\nshape = \"sphere\"\nradius = {:?}\ntransform = {}\n\n\
             [[object]]\nshape = \"sphere\"\nradius = {:?}\ntransform = {}\n\n\
             [[object]]\nshape = \"patch\"\ncorners = [{}]\n",
            camera_toml(eye, look_at, fov),
            spheres[0].1,
            spheres[0].0.toml(),
            spheres[1].1,
            spheres[1].0.toml(),
            corners.map(arr).join(", ")
        );
        let frame = render_all_aovs(&scene, std::path::Path::new("."), w, h, 1);
        let [q00, q10, _, q01] = corners.map(DVec3::from);
        let cam = RefCamera::perspective(eye, look_at, [0.0, 1.0, 0.0], fov, w, h);
        AovScene { w, h, frame, cam, spheres, patch: (q00, q10 - q00, q01 - q00) }
    }

    fn nearest(&self, x: f64, y: f64) -> Hit {
        let (o, d) = self.cam.ray(x, y);
        let mut best: Hit = None;
        for (k, (tr, r)) in self.spheres.iter().enumerate() {
            let c = DVec3::from(tr.translate);
            if let Some(t) = ray_sphere(o, d, c, *r) {
                let n = (o + t * d - c) / *r;
                if best.is_none_or(|b| t < b.1) {
                    best = Some((k, t, -n.dot(d)));
                }
            }
        }
        let (q00, e1, e2) = self.patch;
        let n = e1.cross(e2).normalize();
        if let Some(t) = ray_plane(o, d, q00, n) {
            let (u, v) = parallelogram_uv(o + t * d, q00, e1, e2);
            if (0.0..=1.0).contains(&u) && (0.0..=1.0).contains(&v) && best.is_none_or(|b| t < b.1) {
                best = Some((2, t, n.dot(d).abs()));
            }
        }
        best
    }

    /// Calls `f(i, j, hit)` for every pixel whose centre ray and the rays 0.75 pixel diagonally around
    /// it see the same object (or nothing): pixels well clear of every silhouette.
    fn for_clear_pixels(&self, mut f: impl FnMut(usize, usize, Hit)) {
        for j in 0..self.h {
            for i in 0..self.w {
                let (x, y) = (i as f64 + 0.5, j as f64 + 0.5);
                let here = self.nearest(x, y);
                let around = [(-0.75, -0.75), (0.75, -0.75), (-0.75, 0.75), (0.75, 0.75)];
                if around.iter().all(|&(dx, dy)| self.nearest(x + dx, y + dy).map(|b| b.0) == here.map(|b| b.0)) {
                    f(i, j, here);
                }
            }
        }
    }

    /// The exact sphere point at the (u,v) the renderer shaded at pixel index k (documented mapping and
    /// transform, in f64).
    fn shaded_sphere_point(&self, id: usize, k: usize) -> DVec3 {
        let uv = self.frame.uv.as_ref().expect("uv")[k];
        let (tr, r) = self.spheres[id];
        tr.point(sphere_point(r, uv[0] as f64, uv[1] as f64))
    }
}

/// At every pixel well clear of silhouettes (its centre ray and rays 0.75 pixel diagonally around it see
/// the same object analytically): the id AOV is the object's index in the scene file; pixels that see
/// nothing hold NaN in every AOV; on the flat patch the depth AOV is the analytic ray-plane distance
/// (within 1e-4 relative); on the spheres it is the distance from the eye to the exact sphere point at
/// the pixel's own uv AOV (within 1e-5 relative: depth and uv describe the same surface point).
#[test]
fn depth_id_and_background_aovs() {
    let sc = AovScene::render();
    let f = &sc.frame;
    let (ids, depths) = (f.id.as_ref().expect("id"), f.depth.as_ref().expect("depth"));
    let (normals, uvs) = (f.normal.as_ref().expect("normal"), f.uv.as_ref().expect("uv"));
    let (mut seen, mut background) = ([0usize; 3], 0usize);
    let (mut patch_depth, mut sphere_consistency) = (MaxErr::default(), MaxErr::default());
    sc.for_clear_pixels(|i, j, hit| {
        let k = j * sc.w + i;
        let Some((id, t, _)) = hit else {
            background += 1;
            let all_nan = normals[k].iter().chain(&uvs[k]).all(|v| v.is_nan()) && depths[k].is_nan() && ids[k].is_nan();
            assert!(all_nan, "pixel ({i},{j}) sees nothing but holds id {} depth {}", ids[k], depths[k]);
            return;
        };
        seen[id] += 1;
        assert_eq!(ids[k], id as f32, "pixel ({i},{j})");
        assert!(normals[k].iter().chain(&uvs[k]).all(|v| v.is_finite()), "pixel ({i},{j}) has NaN AOVs");
        let depth = depths[k] as f64;
        if id == 2 {
            patch_depth.add((depth - t).abs() / t, || format!("pixel ({i},{j}): depth {depth} vs {t:.6}"));
        } else {
            let p = sc.shaded_sphere_point(id, k);
            let want = (p - sc.cam.eye).length();
            sphere_consistency
                .add((depth - want).abs() / want, || format!("pixel ({i},{j}) object {id}: {depth} vs {want:.6}"));
        }
    });
    println!(
        "AOVs: clear pixels per object {seen:?}, background {background}; patch depth vs ray-plane {:.3e} (bound 1e-4); \
         sphere depth vs |P(uv) - eye| {:.3e} (bound 1e-5)",
        patch_depth.max, sphere_consistency.max
    );
    assert!(seen.iter().all(|&n| n > 500) && background > 500, "the scene does not show every object and background");
    assert!(patch_depth.max < 1e-4, "patch depth off: {}", patch_depth.at);
    assert!(
        sphere_consistency.max < 1e-5,
        "sphere depth is not the distance to the point at its uv: {}",
        sphere_consistency.at
    );
}

/// The depth AOV on a sphere against the analytic ray-sphere distance, wherever the view is not grazing
/// (cos of incidence > 0.5). The tessellation alone puts the shaded point up to its sag (a fraction of a
/// pixel) off the pixel's ray; the shader's Newton step (src/raster/refine.rs) moves it onto the ray.
/// Measured: 9.9e-5 relative, 0.02 px off the pixel centre (without the step: 7.6e-4 and 0.11 px with
/// 0.05 px sag, 7.8e-3 and 1.08 px with plain 12 px segments).
#[test]
fn sphere_depth_matches_the_ray_intersection() {
    let sc = AovScene::render();
    let depths = sc.frame.depth.as_ref().expect("depth");
    let (mut depth_err, mut offset, mut offset_all) = (MaxErr::default(), 0.0f64, 0.0f64);
    sc.for_clear_pixels(|i, j, hit| {
        let Some((id @ (0 | 1), t, cos)) = hit else { return };
        let k = j * sc.w + i;
        // Where the shaded point lies on screen, against the pixel centre its ray goes through.
        let s = sc.cam.project(sc.shaded_sphere_point(id, k));
        let off = (s[0] - (i as f64 + 0.5)).hypot(s[1] - (j as f64 + 0.5));
        offset_all = offset_all.max(off);
        if cos > 0.5 {
            offset = offset.max(off);
            let depth = depths[k] as f64;
            depth_err.add((depth - t).abs() / t, || {
                format!("pixel ({i},{j}) object {id}: depth {depth} vs {t:.6}, cos {cos:.3}")
            });
        }
    });
    println!(
        "sphere depth vs ray-sphere distance (cos > 0.5): max relative error {:.3e} (bound 3e-4) at {}; \
         shaded point off its pixel centre by up to {offset:.2} px (cos > 0.5), {offset_all:.2} px (all clear pixels)",
        depth_err.max, depth_err.at
    );
    assert!(depth_err.count > 1000);
    assert!(
        depth_err.max < 3e-4 && offset < 0.05,
        "depth is not the distance along the pixel's ray ({offset:.2} px off): {}",
        depth_err.at
    );
}

/// A mirroring transform (negative determinant) turns the tessellation's winding over: the renderer must
/// still cull the far side of a closed shape, not the near one. Reference: the same sphere unmirrored covers
/// the same pixels, and every shading normal faces the eye.
#[test]
fn mirrored_closed_shapes_show_their_outside() {
    let scene_with = |scale: &str| {
        format!(
            "[camera]\neye = [0.0, 0.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\n\n[[light]]\ntype = \"ambient\"\n\n\
             [[object]]\nshape = \"sphere\"\ntransform = {{ scale = {scale} }}\n"
        )
    };
    let options =
        RenderOptions { width: 96, height: 72, aovs: Aovs { normal: true, ..Aovs::default() }, ..Default::default() };
    let render_normals = |scale: &str| {
        let scene = Scene::parse(&scene_with(scale), Path::new(".")).unwrap();
        render(&scene, &options).unwrap().normal.unwrap()
    };
    let plain = render_normals("[1.0, 1.0, 1.0]");
    let mirrored = render_normals("[-1.0, 1.0, 1.0]");
    let covered = |n: &[[f32; 3]]| n.iter().filter(|v| !v[0].is_nan()).count();
    assert!(covered(&plain) > 1000);
    assert_eq!(covered(&plain), covered(&mirrored));
    // The eye looks down -z: a normal of the visible outside has a positive z.
    let min_z = mirrored.iter().filter(|v| !v[0].is_nan()).map(|v| v[2]).fold(f32::INFINITY, f32::min);
    assert!(min_z > 0.0, "a normal faces away from the eye: z = {min_z}");
}

// ---------------------------------------------------------------------------------------------
// 7. Exact silhouettes of curved surfaces.
// ---------------------------------------------------------------------------------------------

/// The pixels (1 spp, centre samples) whose ray meets a sphere, against the analytic disc: every sphere
/// from a few pixels to hundreds across, seen in perspective from off-axis (its poles near the outline)
/// and orthographically, scaled, rotated and off-centre. A pixel centre counts where the ray through it
/// and the rays 1e-3 px to either side in x and y agree (it is not within 1e-3 px of the outline); the
/// covered set (the id AOV) must then equal the analytic set exactly. The inscribed tessellation alone
/// misses pixel centres up to its quarter-pixel sag inside the outline.
#[test]
fn sphere_outline_matches_the_analytic_disc() {
    let (w, h) = (240, 180);
    let views: [(&str, RefCamera, String); 2] = [
        (
            "perspective",
            RefCamera::perspective([3.5, 0.4, 4.0], [0.1, 0.0, 0.0], [0.0, 1.0, 0.0], 40.0, w, h),
            camera_toml([3.5, 0.4, 4.0], [0.1, 0.0, 0.0], 40.0),
        ),
        (
            "orthographic",
            RefCamera::orthographic([0.2, 5.0, 3.0], [0.0, 0.0, 0.0], [0.0, 1.0, 0.0], 5.0, w, h),
            "[camera]\nprojection = \"orthographic\"\neye = [0.2, 5.0, 3.0]\nlook_at = [0.0, 0.0, 0.0]\n\
             height = 5.0\nbackground = [0.0, 0.0, 0.0]\n\n[[light]]\ntype = \"ambient\"\n\n"
                .to_string(),
        ),
    ];
    let spheres = [
        (RefTransform { translate: [-0.9, 0.2, 0.0], rotate: [20.0, 0.0, 10.0], scale: 1.0 }, 0.9),
        (RefTransform { translate: [1.1, -0.3, 0.4], rotate: [0.0, 35.0, 0.0], scale: 0.5 }, 0.7),
        (RefTransform { translate: [0.6, 0.9, 1.2], ..RefTransform::IDENTITY }, 0.04),
        (RefTransform { translate: [-0.2, -1.0, 1.5], ..RefTransform::IDENTITY }, 0.12),
    ];
    for (name, cam, head) in views {
        let mut scene = head;
        for (tr, r) in &spheres {
            scene += &format!("[[object]]\nshape = \"sphere\"\nradius = {r:?}\ntransform = {}\n\n", tr.toml());
        }
        let frame = render_all_aovs(&scene, Path::new("."), w, h, 1);
        let ids = frame.id.as_ref().expect("id");
        let hits = |x: f64, y: f64| {
            let (o, d) = cam.ray(x, y);
            spheres.iter().any(|(tr, r)| ray_sphere(o, d, DVec3::from(tr.translate), r * tr.scale).is_some())
        };
        let (covered, open, wrong) = compare_coverage(ids, w, h, hits);
        println!(
            "{name}: {covered} pixel centres on a sphere, {open} within 1e-3 px of an outline, {} wrong",
            wrong.len()
        );
        assert!(covered > 3000, "{name}: the spheres cover only {covered} pixels");
        assert!(wrong.is_empty(), "{name}: (pixel, on the sphere) {:?}", &wrong[..wrong.len().min(12)]);
    }
}

/// The same exactness where Newton's method decides (raster/exact.rs): a torus, whose inner outline folds
/// over its far side, and an open cylinder seen from above, whose rims are curved open edges. The
/// references are an implicit-function search along each ray (torus) and the quadratic with the tube's
/// height range (cylinder), in f64.
#[test]
fn torus_and_tube_outlines_match_their_ray_tests() {
    let (w, h) = (240, 180);
    let (eye, look_at) = ([0.5, 3.2, 4.0], [0.2, 0.0, 0.0]);
    let cam = RefCamera::perspective(eye, look_at, [0.0, 1.0, 0.0], 40.0, w, h);
    let (torus_at, big_r, small_r) = (DVec3::new(-0.9, 0.0, 0.0), 0.8, 0.3);
    let (tube_at, tube_r, tube_h) = (DVec3::new(1.3, 0.0, 0.3), 0.5, 1.2);
    let scene = format!(
        "{}[[object]]\nshape = \"torus\"\nmajor_radius = {big_r:?}\nminor_radius = {small_r:?}\n\
         transform = {{ translate = {} }}\n\n[[object]]\nshape = \"cylinder\"\nradius = {tube_r:?}\n\
         height = {tube_h:?}\ntransform = {{ translate = {} }}\n",
        camera_toml(eye, look_at, 40.0),
        arr(torus_at.to_array()),
        arr(tube_at.to_array())
    );
    let frame = render_all_aovs(&scene, Path::new("."), w, h, 1);
    let ids = frame.id.as_ref().expect("id");
    let torus_hit = |o: DVec3, d: DVec3| {
        let o = o - torus_at;
        let f = |t: f64| {
            let p = o + t * d;
            (p.x.hypot(p.z) - big_r).powi(2) + p.y * p.y - small_r * small_r
        };
        // The stretch of the ray inside the torus's bounding sphere, searched in fine steps, and each dip
        // refined by golden-section search.
        let b = o.dot(d);
        let disc = b * b - (o.length_squared() - (big_r + small_r).powi(2));
        if disc < 0.0 {
            return false;
        }
        let (t0, t1) = (-b - disc.sqrt(), -b + disc.sqrt());
        let n = 400;
        let step = (t1 - t0) / n as f64;
        (0..=n).any(|k| {
            let t = t0 + k as f64 * step;
            if f(t) <= 0.0 {
                return true;
            }
            let (mut a, mut c) = (t - step, t + step);
            if !(f(t) <= f(a) && f(t) <= f(c)) {
                return false;
            }
            for _ in 0..60 {
                let (m1, m2) = (c - (c - a) * 0.618, a + (c - a) * 0.618);
                if f(m1) < f(m2) {
                    c = m2;
                } else {
                    a = m1;
                }
            }
            f(0.5 * (a + c)) <= 0.0
        })
    };
    let tube_hit = |o: DVec3, d: DVec3| {
        let o = o - tube_at;
        let (a, b, c) = (d.x * d.x + d.z * d.z, o.x * d.x + o.z * d.z, o.x * o.x + o.z * o.z - tube_r * tube_r);
        let disc = b * b - a * c;
        disc >= 0.0
            && [(-b - disc.sqrt()) / a, (-b + disc.sqrt()) / a]
                .iter()
                .any(|&t| t > 0.0 && (o.y + t * d.y).abs() <= 0.5 * tube_h)
    };
    let seen = |x: f64, y: f64| {
        let (o, d) = cam.ray(x, y);
        torus_hit(o, d) || tube_hit(o, d)
    };
    let (covered, open, wrong) = compare_coverage(ids, w, h, seen);
    println!(
        "torus and tube: {covered} pixel centres covered, {open} within 1e-3 px of an outline, {} wrong",
        wrong.len()
    );
    assert!(covered > 5000, "the shapes cover only {covered} pixels");
    assert!(wrong.is_empty(), "(pixel, on a shape) {:?}", &wrong[..wrong.len().min(12)]);
}

/// The rendered coverage (the id AOV of a `w` x `h` frame at 1 spp) against `seen(x, y)`, whether the ray
/// through a screen position meets the shapes, at every pixel centre not within 1e-3 px of an outline (where
/// the rays 1e-3 px to either side in x and y agree with it): the centres covered, those left open, and the
/// pixels that differ, with what they should show.
fn compare_coverage(
    ids: &[f32],
    w: usize,
    h: usize,
    seen: impl Fn(f64, f64) -> bool,
) -> (usize, usize, Vec<(usize, usize, bool)>) {
    let (mut covered, mut open, mut wrong) = (0, 0, Vec::new());
    for j in 0..h {
        for i in 0..w {
            let (x, y) = (i as f64 + 0.5, j as f64 + 0.5);
            let want = seen(x, y);
            let e = 1e-3;
            if [(e, 0.0), (-e, 0.0), (0.0, e), (0.0, -e)].iter().any(|&(dx, dy)| seen(x + dx, y + dy) != want) {
                open += 1;
                continue;
            }
            covered += usize::from(want);
            if want == ids[j * w + i].is_nan() {
                wrong.push((i, j, want));
            }
        }
    }
    (covered, open, wrong)
}
