//! Meshes from model files against what their formats' specifications imply: glTF normal maps with and
//! without tangents (MikkTSpace), mirrored texture coordinates, node transforms, every loader path (glTF
//! embedded, with a .bin, GLB; OBJ with its .mtl), and one clear error for every broken file.

use crate::common::gltf::{png_of, File, Layout, Primitive};
use crate::common::{angle_deg, d3, render_all_aovs, scratch_dir};
use glam::{DVec3, Vec3};
use std::path::Path;
use wrinkle::Scene;

/// A 2x2 quad in z = 0 facing +z, u along +x (flipped when `mirrored`), glTF's v down the image.
fn quad(tangents: Option<[f32; 4]>, mirrored: bool) -> Primitive {
    let u = |x: f32| if mirrored { 1.0 - x } else { x };
    Primitive {
        positions: vec![[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]],
        normals: Some(vec![[0.0, 0.0, 1.0]; 4]),
        uvs: Some(vec![[u(0.0), 1.0], [u(1.0), 1.0], [u(1.0), 0.0], [u(0.0), 0.0]]),
        tangents: tangents.map(|t| vec![t; 4]),
        indices: vec![0, 1, 2, 0, 2, 3],
        ..Primitive::default()
    }
}

/// q.obj in `dir`: the 2x2 quad of `quad` (u along +x, v up) with material `m` of q.mtl.
fn write_obj_quad(dir: &Path) {
    std::fs::write(
        dir.join("q.obj"),
        "mtllib q.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n\
         usemtl m\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n",
    )
    .unwrap();
}

/// The scene: the model `file` seen head-on from +z, its centre pixel's world normal.
fn centre_normal(dir: &Path, file: &str) -> DVec3 {
    let text = format!(
        "[camera]\neye = [0.0, 0.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\n\n[[light]]\ntype = \"ambient\"\n\n\
         [[object]]\nshape = \"mesh\"\nfile = \"{file}\"\n"
    );
    let frame = render_all_aovs(&text, dir, 33, 33, 1);
    d3(Vec3::from(frame.normal.as_ref().unwrap()[16 * 33 + 16]))
}

/// An 8-bit normal-map texel of the unit vector `n` (each component stored as (c + 1) / 2).
fn texel_of(n: DVec3) -> [u8; 3] {
    n.normalize().to_array().map(|c| ((c + 1.0) * 0.5 * 255.0).round() as u8)
}

/// The vector an 8-bit texel stores.
fn decoded(t: [u8; 3]) -> DVec3 {
    DVec3::from_array(t.map(|c| c as f64 / 255.0 * 2.0 - 1.0)).normalize()
}

/// glTF: N' = normalize(x T + y B + z N) with B = w (N x T). For the quad, T = +x (or -x mirrored) and
/// B = +y (up the image) whether the tangents come with the file or from MikkTSpace.
#[test]
fn gltf_normal_maps_shade_with_the_normal_the_specification_implies() {
    let dir = scratch_dir("gltf-normal-map");
    let tilt = DVec3::new(0.35, -0.45, 0.82);
    let texel = texel_of(tilt);
    let png = png_of(&dir, texel);
    let material = "{\"normalTexture\": {\"index\": 0}}".to_string();
    let cases = [
        ("given tangents", Some([1.0, 0.0, 0.0, 1.0]), false),
        ("MikkTSpace", None, false),
        ("mirrored, given tangents", Some([-1.0, 0.0, 0.0, -1.0]), true),
        ("mirrored, MikkTSpace", None, true),
        // Tangents the file gives are used as given, even where MikkTSpace would choose others.
        ("tangents along +y", Some([0.0, 1.0, 0.0, 1.0]), false),
    ];
    for (k, (name, tangents, mirrored)) in cases.into_iter().enumerate() {
        let file = File {
            primitive: quad(tangents, mirrored),
            matrix: None,
            material: material.clone(),
            png: Some(png.clone()),
        };
        let (bytes, _) = file.write(Layout::Binary, "");
        std::fs::write(dir.join(format!("q{k}.glb")), bytes).unwrap();
        let got = centre_normal(&dir, &format!("q{k}.glb"));
        let t = decoded(texel);
        // Mirrored in u: the tangent runs along -x, the bitangent still along +y. With T = +y the
        // bitangent N x T is -x.
        let want = match (mirrored, tangents) {
            (true, _) => DVec3::new(-t.x, t.y, t.z),
            (false, Some([_, 1.0, _, _])) => DVec3::new(-t.y, t.x, t.z),
            _ => t,
        };
        let err = angle_deg(got, want);
        assert!(err < 0.5, "{name}: normal {got} against {want}: {err} degrees");
    }
    // The normal map read as sRGB colour would be off by several degrees: the test can tell.
    assert!(angle_deg(decoded(texel), DVec3::new(0.0, 0.0, 1.0)) > 20.0);
}

/// A node's matrix carries the mesh, its normals and its tangents.
#[test]
fn gltf_node_transforms_carry_the_normal_map_frame() {
    let dir = scratch_dir("gltf-node");
    let tilt = DVec3::new(0.3, 0.2, 0.93);
    let texel = texel_of(tilt);
    // A quarter turn about z (column-major): +x goes to +y, +y to -x.
    let matrix = [0.0, 1.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0];
    for (k, tangents) in [Some([1.0, 0.0, 0.0, 1.0]), None].into_iter().enumerate() {
        let file = File {
            primitive: quad(tangents, false),
            matrix: Some(matrix),
            material: "{\"normalTexture\": {\"index\": 0}}".into(),
            png: Some(png_of(&dir, texel)),
        };
        std::fs::write(dir.join(format!("n{k}.glb")), file.write(Layout::Binary, "").0).unwrap();
        let got = centre_normal(&dir, &format!("n{k}.glb"));
        let t = decoded(texel);
        let want = DVec3::new(-t.y, t.x, t.z);
        assert!(angle_deg(got, want) < 0.5, "tangents {tangents:?}: {got} against {want}");
    }
}

/// The same model through every glTF layout, and as OBJ with its .mtl: the same colour at the centre.
#[test]
fn every_loader_path_gives_the_same_picture() {
    let dir = scratch_dir("loaders");
    let png = png_of(&dir, [200, 100, 50]);
    std::fs::write(dir.join("colour.png"), &png).unwrap();
    let material =
        "{\"pbrMetallicRoughness\": {\"baseColorFactor\": [0.5, 1.0, 1.0, 1.0], \"baseColorTexture\": {\"index\": 0}}}";
    let file = File { primitive: quad(None, false), matrix: None, material: material.into(), png: Some(png) };
    let (embedded, _) = file.write(Layout::Embedded, "");
    std::fs::write(dir.join("e.gltf"), embedded).unwrap();
    let (separate, bin) = file.write(Layout::Separate, "s.bin");
    std::fs::write(dir.join("s.gltf"), separate).unwrap();
    std::fs::write(dir.join("s.bin"), bin).unwrap();
    std::fs::write(dir.join("b.glb"), file.write(Layout::Binary, "").0).unwrap();
    write_obj_quad(&dir);
    std::fs::write(dir.join("q.mtl"), "newmtl m\nKd 0.5 1 1\nmap_Kd colour.png\n").unwrap();
    // Lit by an ambient light of 1: the colour is the albedo, base colour factor times the texel.
    let srgb = |c: f64| if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) };
    let want = DVec3::new(0.5 * srgb(200.0 / 255.0), srgb(100.0 / 255.0), srgb(50.0 / 255.0));
    for name in ["e.gltf", "s.gltf", "b.glb", "q.obj"] {
        let text = format!(
            "[camera]\neye = [0.0, 0.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\n\n[[light]]\ntype = \"ambient\"\n\n\
             [[object]]\nshape = \"mesh\"\nfile = \"{name}\"\n"
        );
        let frame = render_all_aovs(&text, &dir, 17, 17, 1);
        let got = d3(Vec3::from(frame.color[8 * 17 + 8]));
        assert!((got - want).abs().max_element() < 2e-3, "{name}: {got} against {want}");
        assert_eq!(frame.id.as_ref().unwrap()[8 * 17 + 8], 0.0, "{name}");
    }
}

/// A broken model file, or a scene asking for one wrongly: one line naming the file and what is wrong.
#[test]
fn broken_models_give_one_clear_line() {
    let dir = scratch_dir("broken");
    let obj = |name: &str, text: &str| std::fs::write(dir.join(name), text).unwrap();
    obj("out_of_range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
    obj("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
    obj("empty.obj", "v 0 0 0\nv 1 0 0\n");
    obj("garbage.obj", "v 0 0 zero\nf 1 2 3\n");
    obj("missing_texture.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nusemtl a\nf 1/1 2/1 3/1\n");
    obj("m.mtl", "newmtl a\nmap_Kd nowhere.png\n");
    obj("short_ks.obj", "mtllib k.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl k\nf 1 2 3\n");
    obj("k.mtl", "newmtl k\nKd 0.5 0.5 0.5\nKs 0.8\n");
    let png = png_of(&dir, [128, 128, 255]);
    let file = File { primitive: quad(None, false), matrix: None, material: "{}".into(), png: Some(png) };
    let glb = file.write(Layout::Binary, "").0;
    std::fs::write(dir.join("truncated.glb"), &glb[..glb.len() / 2]).unwrap();
    std::fs::write(dir.join("not_json.gltf"), "{ this is not json").unwrap();
    let mut bad_index = quad(None, false);
    bad_index.indices[4] = 77;
    let file = File { primitive: bad_index, matrix: None, material: "{}".into(), png: None };
    std::fs::write(dir.join("bad_index.glb"), file.write(Layout::Binary, "").0).unwrap();
    let cases = [
        ("out_of_range.obj", "out_of_range.obj"),
        ("nan.obj", "not a finite number"),
        ("empty.obj", "no triangles"),
        ("garbage.obj", "malformed OBJ"),
        ("missing_texture.obj", "nowhere.png"),
        ("short_ks.obj", "line 3: Ks needs three numbers"),
        ("truncated.glb", "malformed glTF"),
        ("not_json.gltf", "malformed glTF"),
        ("bad_index.glb", "out of range"),
        ("absent.glb", "no such file"),
        ("model.stl", "expected a model file"),
    ];
    for (file, expect) in cases {
        let text = format!(
            "[camera]\neye = [0.0, 0.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\n\n[[object]]\nshape = \"mesh\"\nfile = \"{file}\"\n"
        );
        let err = match Scene::parse(&text, &dir) {
            Ok(_) => panic!("{file}: loaded"),
            Err(e) => e.to_string(),
        };
        assert!(err.contains(expect) && err.contains(file.trim_end_matches(".obj")), "{file}: {err}");
        assert!(!err.contains('\n'), "{file}: more than one line: {err}");
    }
    // Fields of meshes on other shapes, and of other shapes on meshes.
    for (object, expect) in [
        ("shape = \"sphere\"\nfile = \"q.obj\"", "objects[0].file: only for shape = \"mesh\""),
        ("shape = \"mesh\"\nfile = \"q.obj\"\nradius = 2.0", "objects[0].radius: not a field of shape \"mesh\""),
        ("shape = \"mesh\"", "objects[0].file: missing"),
    ] {
        let text = format!("[camera]\neye = [0.0, 0.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\n\n[[object]]\n{object}\n");
        let err = Scene::parse(&text, &dir).err().map(|e| e.to_string()).unwrap_or_default();
        assert!(err.contains(expect), "{object}: {err}");
    }
}

/// The item buffer: each pixel's object and triangle, against the triangle its ray meets (the quad's
/// diagonal from (-1, -1) to (1, 1) splits it into triangle 0 below and triangle 1 above), and nothing on
/// the background.
#[test]
fn primitive_aov_names_the_triangle_each_pixel_sees() {
    let dir = scratch_dir("item-buffer");
    std::fs::write(dir.join("q.obj"), "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3\nf 1 3 4\n").unwrap();
    let text = "[camera]\neye = [0.0, 0.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\nfov_y = 40.0\n\n\
                [[light]]\ntype = \"ambient\"\n\n\
                [[object]]\nshape = \"sphere\"\nradius = 0.3\ntransform = { translate = [1.2, 1.0, 0.5] }\n\n\
                [[object]]\nshape = \"mesh\"\nfile = \"q.obj\"\n";
    let (w, h) = (64, 48);
    let frame = render_all_aovs(text, &dir, w, h, 1);
    let ids = frame.primitive.as_ref().unwrap();
    let camera = crate::common::RefCamera::perspective([0.0, 0.0, 4.0], [0.0; 3], [0.0, 1.0, 0.0], 40.0, w, h);
    let (mut checked, mut background) = (0, 0);
    for j in 0..h {
        for i in 0..w {
            let (o, d) = camera.pixel_ray(i, j);
            // Within a sphere a little smaller (its silhouette is tessellated), and beside one a little larger.
            let centre = DVec3::new(1.2, 1.0, 0.5);
            let (sphere, near_sphere) =
                (crate::common::ray_sphere(o, d, centre, 0.28), crate::common::ray_sphere(o, d, centre, 0.32));
            let plane = crate::common::ray_plane(o, d, DVec3::ZERO, DVec3::Z);
            let got = ids[j * w + i];
            match (sphere, plane) {
                (Some(_), _) => assert_eq!(got[0], 0, "pixel ({i}, {j}): the sphere"),
                _ if near_sphere.is_some() => continue,
                (None, Some(t)) => {
                    let p = o + t * d;
                    if p.x.abs() > 1.02 || p.y.abs() > 1.02 {
                        assert_eq!(got, wrinkle::render::NO_PRIMITIVE, "pixel ({i}, {j}) sees nothing");
                        background += 1;
                        continue;
                    }
                    if p.x.abs() > 0.98 || p.y.abs() > 0.98 || (p.x - p.y).abs() < 0.03 {
                        continue; // edges, where the pixel's sample may fall either side
                    }
                    let triangle = if p.x > p.y { 0 } else { 1 };
                    assert_eq!(got, [1, triangle], "pixel ({i}, {j}) at {p}");
                    checked += 1;
                }
                (None, None) => {}
            }
        }
    }
    assert!(checked > 500 && background > 100, "{checked} quad pixels, {background} background");
}

/// The teapot's mesh in scenes/models/teapot.obj is what `wrinkle tessellate` makes of the 32 patches, and
/// it renders as they do: the same pixels covered (no pinholes where patches meet, silhouettes within a
/// pixel), the same colours and normals inside, Blinn's bumps from the triangles' uv gradients included.
#[test]
fn the_teapot_mesh_is_the_patches_exported_and_renders_like_them() {
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let patches = Scene::load(&scenes.join("teapot.toml")).unwrap();
    let committed = std::fs::read_to_string(scenes.join("models/teapot.obj")).unwrap();
    assert!(committed == patches.to_obj(10).unwrap(), "teapot.obj differs from `wrinkle tessellate --segments 10`");

    let (w, h) = (240, 160);
    let read = |name: &str| std::fs::read_to_string(scenes.join(name)).unwrap();
    let exact = render_all_aovs(&read("teapot.toml"), &scenes, w, h, 1);
    let mesh = render_all_aovs(&read("teapot_mesh.toml"), &scenes, w, h, 1);
    let covered = |f: &wrinkle::Frame, i: usize, j: usize| f.depth.as_ref().unwrap()[j * w + i].is_finite();
    let (mut inside, mut holes, mut silhouette, mut shared) = (0, 0, 0, 0);
    let (mut colour_err, mut normal_err) = (0.0f64, 0.0f64);
    for j in 1..h - 1 {
        for i in 1..w - 1 {
            let interior = (0..9).all(|k| covered(&exact, i + k % 3 - 1, j + k / 3 - 1));
            if interior {
                inside += 1;
                if !covered(&mesh, i, j) {
                    holes += 1;
                }
            } else if covered(&exact, i, j) != covered(&mesh, i, j) {
                silhouette += 1;
            }
            if interior && covered(&mesh, i, j) {
                shared += 1;
                let (a, b) = (exact.color[j * w + i], mesh.color[j * w + i]);
                colour_err += (0..3).map(|c| (a[c] - b[c]).abs() as f64).sum::<f64>() / 3.0;
                let (na, nb) = (exact.normal.as_ref().unwrap()[j * w + i], mesh.normal.as_ref().unwrap()[j * w + i]);
                normal_err += angle_deg(d3(Vec3::from(na)), d3(Vec3::from(nb)));
            }
        }
    }
    let (colour_err, normal_err) = (colour_err / shared as f64, normal_err / shared as f64);
    assert!(inside > 8000 && holes == 0, "{holes} of {inside} interior pixels show the background");
    assert!(silhouette < inside / 100, "{silhouette} silhouette pixels differ");
    assert!(
        colour_err < 0.006 && normal_err < 1.0,
        "mean |colour| {colour_err:.4}, mean normal {normal_err:.3} degrees"
    );
}

/// KHR_texture_transform on the normal texture (which the gltf crate leaves to the reader): a 4x4 map of
/// four quadrants of different normals, the quad's centre (uv 0.5, 0.5) scaled by 1/2 onto a quadrant's
/// corner texel and moved by the offset, or turned by the rotation, into another.
#[test]
fn gltf_normal_texture_transform_picks_the_quadrant_the_specification_implies() {
    let dir = scratch_dir("gltf-normal-transform");
    let tilts = [
        DVec3::new(0.5, 0.0, 0.85),
        DVec3::new(0.0, 0.5, 0.85),
        DVec3::new(-0.5, 0.0, 0.85),
        DVec3::new(0.0, -0.5, 0.85),
    ];
    // Quadrant k = column + 2 row, row 0 at the top of the image (glTF's v = 0).
    let texels: Vec<u8> = (0..16).flat_map(|i| texel_of(tilts[(i % 4) / 2 + 2 * ((i / 4) / 2)])).collect();
    let path = dir.join("quadrants.png");
    wrinkle::image::io::write_png_rgb8(&path, 4, 4, &texels).unwrap();
    let png = std::fs::read(&path).unwrap();
    let half_pi = std::f64::consts::FRAC_PI_2;
    let cases = [
        ("scale", "\"scale\": [0.5, 0.5]".to_string(), 0),
        ("offset in u", "\"offset\": [0.5, 0.0], \"scale\": [0.5, 0.5]".to_string(), 1),
        ("offset in v", "\"offset\": [0.0, 0.5], \"scale\": [0.5, 0.5]".to_string(), 2),
        // (0.25, 0.25) turned by R = [cos sin; -sin cos] is (0.25, -0.25); with the offset, (0.75, 0.25).
        ("rotation", format!("\"offset\": [0.5, 0.5], \"rotation\": {half_pi}, \"scale\": [0.5, 0.5]"), 1),
    ];
    for (k, (name, transform, quadrant)) in cases.into_iter().enumerate() {
        let material = format!(
            "{{\"normalTexture\": {{\"index\": 0, \"extensions\": {{\"KHR_texture_transform\": {{{transform}}}}}}}}}"
        );
        let file = File { primitive: quad(None, false), matrix: None, material, png: Some(png.clone()) };
        let (bytes, _) = file.write(Layout::Binary, "");
        std::fs::write(dir.join(format!("t{k}.glb")), bytes).unwrap();
        let got = centre_normal(&dir, &format!("t{k}.glb"));
        let want = decoded(texel_of(tilts[quadrant]));
        let err = angle_deg(got, want);
        assert!(err < 0.5, "{name}: normal {got} against quadrant {quadrant}'s {want}: {err} degrees");
    }
    // A malformed transform is one line naming it.
    let material = "{\"normalTexture\": {\"index\": 0, \"extensions\": {\"KHR_texture_transform\": {\"scale\": 2}}}}";
    let file = File { primitive: quad(None, false), matrix: None, material: material.into(), png: Some(png) };
    std::fs::write(dir.join("bad.glb"), file.write(Layout::Binary, "").0).unwrap();
    let text = "[camera]\neye = [0.0, 0.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\n\n[[object]]\nshape = \"mesh\"\nfile = \"bad.glb\"\n";
    let err = Scene::parse(text, &dir).err().expect("a malformed transform is refused").to_string();
    assert!(err.contains("bad.glb") && err.contains("KHR_texture_transform") && err.contains("scale"), "{err}");
}

/// The quad with set 1 = set 0 mirrored in u (and a texel column per quarter of the quad in the images).
fn quad_with_mirrored_set_1() -> Primitive {
    let mut q = quad(None, false);
    q.uvs1 = q.uvs.as_ref().map(|uvs| uvs.iter().map(|[u, v]| [1.0 - u, *v]).collect());
    q
}

/// TEXCOORD_1: a texture that reads set 1 (by its `texCoord`, or KHR_texture_transform's) is laid with
/// it; a normal map on set 1 gets MikkTSpace tangents along set 1, so the mirrored set turns the tangent
/// as the mirrored quad did; a bump on set 1 = 2 set 0 is the bump repeated twice on set 0.
#[test]
fn gltf_second_texture_coordinate_set_lays_textures_normal_maps_and_bumps() {
    let dir = scratch_dir("gltf-texcoord-1");
    // Red in the left half of the image, green in the right: two texels each, so the quarters' centres
    // read one colour under bilinear magnification.
    let path = dir.join("halves.png");
    let texels: Vec<u8> = [[255, 0, 0], [255, 0, 0], [0, 255, 0], [0, 255, 0]].concat();
    wrinkle::image::io::write_png_rgb8(&path, 4, 1, &texels).unwrap();
    let halves = std::fs::read(&path).unwrap();
    let scene = |file: &str, material: &str| {
        format!(
            "[camera]\neye = [0.0, 0.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\n\n[[light]]\ntype = \"ambient\"\n\n\
             [[object]]\nshape = \"mesh\"\nfile = \"{file}\"\n{material}"
        )
    };
    let cases = [
        ("set 0", "{\"index\": 0}", false),
        ("set 1", "{\"index\": 0, \"texCoord\": 1}", true),
        (
            "set 1 by KHR_texture_transform",
            "{\"index\": 0, \"extensions\": {\"KHR_texture_transform\": {\"texCoord\": 1}}}",
            true,
        ),
    ];
    for (k, (name, info, mirrored)) in cases.into_iter().enumerate() {
        let material = format!("{{\"pbrMetallicRoughness\": {{\"baseColorTexture\": {info}}}}}");
        let file = File { primitive: quad_with_mirrored_set_1(), matrix: None, material, png: Some(halves.clone()) };
        std::fs::write(dir.join(format!("c{k}.glb")), file.write(Layout::Binary, "").0).unwrap();
        let frame = render_all_aovs(&scene(&format!("c{k}.glb"), ""), &dir, 33, 33, 1);
        // The quad spans about pixels 6 to 27: pixels 10 and 22 lie in its left and right quarters.
        let [left, right] = [10, 22].map(|x| d3(Vec3::from(frame.color[16 * 33 + x])));
        let (red, green) = (DVec3::new(1.0, 0.0, 0.0), DVec3::new(0.0, 1.0, 0.0));
        let want = if mirrored { [green, red] } else { [red, green] };
        for (got, want) in [left, right].into_iter().zip(want) {
            assert!((got - want).abs().max_element() < 0.02, "{name}: {got} against {want}");
        }
        // The uv AOV shows the set the colour texture read.
        let u = frame.uv.as_ref().unwrap()[16 * 33 + 10][0];
        assert!(if mirrored { u > 0.7 } else { u < 0.3 }, "{name}: u = {u}");
    }

    let tilt = DVec3::new(0.35, -0.45, 0.82);
    let texel = texel_of(tilt);
    let t = decoded(texel);
    let material = "{\"normalTexture\": {\"index\": 0, \"texCoord\": 1}}".to_string();
    let file = File { primitive: quad_with_mirrored_set_1(), matrix: None, material, png: Some(png_of(&dir, texel)) };
    std::fs::write(dir.join("n.glb"), file.write(Layout::Binary, "").0).unwrap();
    let got = centre_normal(&dir, "n.glb");
    let want = DVec3::new(-t.x, t.y, t.z);
    assert!(angle_deg(got, want) < 0.5, "normal map on set 1: {got} against {want}");

    // Set 1 = 2 set 0: a bump on set 1 against the same bump repeated twice on set 0 (normals within
    // float rounding of the two chains).
    let mut primitive = quad(None, false);
    primitive.uvs1 = primitive.uvs.as_ref().map(|uvs| uvs.iter().map(|[u, v]| [2.0 * u, 2.0 * v - 1.0]).collect());
    let file = File { primitive, matrix: None, material: "{}".into(), png: None };
    std::fs::write(dir.join("b.glb"), file.write(Layout::Binary, "").0).unwrap();
    let bump = |mapping: &str| {
        format!(
            "[object.material.bump]\ngenerator = {{ kind = \"rivets\", size = 128, count = 2, radius = 0.3 }}\n\
             scale = 0.05\n{mapping}\n"
        )
    };
    let normals = |mapping: &str| render_all_aovs(&scene("b.glb", &bump(mapping)), &dir, 48, 48, 1).normal.unwrap();
    let (set1, repeated) = (normals("mapping = { type = \"uv\", set = 1 }"), normals("repeat = [2.0, 2.0]"));
    let flat = normals("repeat = [0.0001, 0.0001]");
    let (mut worst, mut bumped) = (0.0f64, 0usize);
    for ((a, b), f) in set1.iter().zip(&repeated).zip(&flat) {
        worst = worst.max(angle_deg(d3(Vec3::from(*a)), d3(Vec3::from(*b))));
        bumped += usize::from(angle_deg(d3(Vec3::from(*b)), d3(Vec3::from(*f))) > 2.0);
    }
    assert!(worst < 0.05, "bump on set 1 against repeat 2 on set 0: {worst} degrees apart");
    assert!(bumped > 100, "the rivets must show: {bumped} pixels bumped");

    // A material that reads set 1 on a primitive without it, a texture on set 2, set 1 on a parametric
    // surface: one line each.
    let material = "{\"pbrMetallicRoughness\": {\"baseColorTexture\": {\"index\": 0, \"texCoord\": 1}}}";
    let file =
        File { primitive: quad(None, false), matrix: None, material: material.into(), png: Some(halves.clone()) };
    std::fs::write(dir.join("no1.glb"), file.write(Layout::Binary, "").0).unwrap();
    let err = Scene::parse(&scene("no1.glb", ""), &dir).err().expect("set 1 missing").to_string();
    assert!(err.contains("no1.glb") && err.contains("TEXCOORD_1"), "{err}");
    let material = "{\"pbrMetallicRoughness\": {\"baseColorTexture\": {\"index\": 0, \"texCoord\": 2}}}";
    let file =
        File { primitive: quad_with_mirrored_set_1(), matrix: None, material: material.into(), png: Some(halves) };
    std::fs::write(dir.join("set2.glb"), file.write(Layout::Binary, "").0).unwrap();
    let err = Scene::parse(&scene("set2.glb", ""), &dir).err().expect("set 2").to_string();
    assert!(err.contains("set2.glb") && err.contains("TEXCOORD_2"), "{err}");
    let sphere = "[camera]\neye = [0.0, 0.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\n\n[[object]]\nshape = \"sphere\"\n[object.material.bump]\ngenerator = { kind = \"rivets\" }\n\
                  mapping = { type = \"uv\", set = 1 }\n";
    let err = Scene::parse(sphere, &dir).err().expect("set 1 on a sphere").to_string();
    assert!(err.contains("set 1") && err.contains("sphere"), "{err}");
    let bad_set = sphere.replace("set = 1", "set = 2");
    let err = Scene::parse(&bad_set, &dir).err().expect("set 2 in a scene").to_string();
    assert!(err.contains("set") && err.contains("0 to 1"), "{err}");
}

/// Alpha from model files: a glTF base colour texture's alpha under alphaMode MASK with its alphaCutoff,
/// and an OBJ's map_d (a grey mask), cut the quad where the specifications say; OPAQUE ignores alpha; BLEND
/// composites by it, and the scene's `alpha_mode` overrides the file's.
#[test]
fn model_files_cut_by_their_alpha() {
    let dir = scratch_dir("model-alpha");
    let background = [0.1f32, 0.2, 0.3];
    let scene = |file: &str, material: &str| {
        format!(
            "[camera]\neye = [0.0, 0.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\nprojection = \"orthographic\"\nheight = 2.0\n\
             background = [0.1, 0.2, 0.3]\n\n[[light]]\ntype = \"ambient\"\n\n\
             [[object]]\nshape = \"mesh\"\nfile = \"{file}\"\n{material}"
        )
    };
    // Which of the 32 columns show the background, on the middle row (away from the texture's wrap and its
    // blended middle: columns 2-12 and 20-30 only).
    let cut = |text: &str| -> [bool; 2] {
        let frame = render_all_aovs(text, &dir, 32, 32, 1);
        let row = |x: usize| frame.color[16 * 32 + x] == background;
        let left = (2..=12).map(row).collect::<Vec<_>>();
        let right = (20..=30).map(row).collect::<Vec<_>>();
        assert!(left.iter().all(|&b| b == left[0]) && right.iter().all(|&b| b == right[0]), "{left:?} {right:?}");
        [left[0], right[0]]
    };
    // 8x1 RGBA: the left half transparent, the right opaque.
    let png_path = dir.join("halves.png");
    let pixels: Vec<u8> = (0..8).flat_map(|x| [200, 180, 40, if x < 4 { 0 } else { 255 }]).collect();
    wrinkle::image::io::write_png_rgba8(&png_path, 8, 1, &pixels).unwrap();
    let png = std::fs::read(&png_path).unwrap();
    for (name, mode, want) in [
        ("mask.glb", ", \"alphaMode\": \"MASK\", \"alphaCutoff\": 0.6", [true, false]),
        ("opaque.glb", "", [false, false]),
    ] {
        let material = format!("{{\"pbrMetallicRoughness\": {{\"baseColorTexture\": {{\"index\": 0}}}}{mode}}}");
        let file = File { primitive: quad(None, false), matrix: None, material, png: Some(png.clone()) };
        std::fs::write(dir.join(name), file.write(Layout::Binary, "").0).unwrap();
        assert_eq!(cut(&scene(name, "")), want, "{name}");
    }
    // The base colour factor's alpha multiplies the texture's: 0.5 x 1 is below a cutoff of 0.6 everywhere.
    let material = "{\"pbrMetallicRoughness\": {\"baseColorTexture\": {\"index\": 0}, \"baseColorFactor\": \
                    [1, 1, 1, 0.5]}, \"alphaMode\": \"MASK\", \"alphaCutoff\": 0.6}";
    let file = File { primitive: quad(None, false), matrix: None, material: material.into(), png: Some(png.clone()) };
    std::fs::write(dir.join("faded.glb"), file.write(Layout::Binary, "").0).unwrap();
    assert_eq!(cut(&scene("faded.glb", "")), [true, true]);
    // BLEND: composited by its alpha (the transparent pass): alpha 0 shows the background exactly, alpha 1 the
    // texture; the scene's alpha_mode overrides it.
    let material = "{\"pbrMetallicRoughness\": {\"baseColorTexture\": {\"index\": 0}}, \"alphaMode\": \"BLEND\"}";
    let file = File { primitive: quad(None, false), matrix: None, material: material.into(), png: Some(png) };
    std::fs::write(dir.join("blend.glb"), file.write(Layout::Binary, "").0).unwrap();
    assert_eq!(cut(&scene("blend.glb", "")), [true, false]);
    assert_eq!(cut(&scene("blend.glb", "[object.material]\nalpha_mode = \"opaque\"\n")), [false, false]);
    assert_eq!(cut(&scene("blend.glb", "[object.material]\nalpha_mode = \"mask\"\n")), [true, false]);

    // OBJ: map_d is a grey mask (black left, white right) under the alpha test.
    wrinkle::image::io::write_png_rgb8(
        &dir.join("d.png"),
        8,
        1,
        &(0..8).flat_map(|x| [if x < 4 { 0 } else { 255 }; 3]).collect::<Vec<u8>>(),
    )
    .unwrap();
    write_obj_quad(&dir);
    std::fs::write(dir.join("q.mtl"), "newmtl m\nKd 0.5 1 1\nmap_d d.png\n").unwrap();
    assert_eq!(cut(&scene("q.obj", "")), [true, false]);
    // d = 0.4 scales the mask below the cutoff everywhere.
    std::fs::write(dir.join("q.mtl"), "newmtl m\nKd 0.5 1 1\nd 0.4\nmap_d d.png\n").unwrap();
    assert_eq!(cut(&scene("q.obj", "")), [true, true]);
}

/// Emission from model files: glTF's emissiveFactor x emissiveTexture (sRGB) x KHR_materials_emissive_strength,
/// and an OBJ's Ke, seen with no light at all.
#[test]
fn model_files_emit_what_their_materials_say() {
    let dir = scratch_dir("model-emission");
    let centre = |file: &str| {
        let text = format!(
            "[camera]\neye = [0.0, 0.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\nprojection = \"orthographic\"\nheight = 2.0\n\n\
             [[light]]\ntype = \"ambient\"\nintensity = 0.0\n\n[[object]]\nshape = \"mesh\"\nfile = \"{file}\"\n"
        );
        render_all_aovs(&text, &dir, 9, 9, 1).color[4 * 9 + 4]
    };
    let material = "{\"emissiveFactor\": [0.5, 0.25, 1.0], \"emissiveTexture\": {\"index\": 0}, \
                    \"extensions\": {\"KHR_materials_emissive_strength\": {\"emissiveStrength\": 2.0}}}";
    let file = File {
        primitive: quad(None, false),
        matrix: None,
        material: material.into(),
        png: Some(png_of(&dir, [255, 128, 0])),
    };
    std::fs::write(dir.join("glow.glb"), file.write(Layout::Binary, "").0).unwrap();
    let srgb = |c: f64| if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) };
    let want = [2.0 * 0.5, 2.0 * 0.25 * srgb(128.0 / 255.0), 0.0];
    let got = centre("glow.glb");
    assert!(got.iter().zip(want).all(|(&g, w)| (g as f64 - w).abs() < 1e-5), "glTF emission {got:?} != {want:?}");

    write_obj_quad(&dir);
    std::fs::write(dir.join("q.mtl"), "newmtl m\nKd 0.5 1 1\nKe 0.2 0.4 0.6\n").unwrap();
    assert_eq!(centre("q.obj"), [0.2, 0.4, 0.6]);
}
