//! Filtering the distribution of normals (LEAN mapping, Toksvig) against Blinn's correct solution: the
//! intensities supersampled with the full-resolution bump table. Shiny bumps seen from afar must keep their
//! glints' average brightness and spread instead of turning into a smooth mirror (MIP-filtered heights) or
//! aliasing (the unfiltered table at 1 spp).

use std::path::Path;
use wrinkle::bump::BumpFilter;
use wrinkle::image::color::linear_to_srgb;
use wrinkle::{render, RenderOptions, Sampler, Scene};

/// A plane receding to the horizon, covered in a grid of shiny grooves, lit from beyond the horizon so
/// every groove glints; in rows of patches that double in depth (a patch is tessellated uniformly).
/// Blinn's scale-invariant D keeps the grooves alike on every row.
fn grooved_plane() -> String {
    let mut text = String::from(
        r#"
[camera]
eye = [0.0, 1.1, 4.0]
look_at = [0.0, 0.55, -4.0]
fov_y = 50.0
background = [0.55, 0.7, 0.9]

[[light]]
type = "ambient"
intensity = 0.15

[[light]]
type = "directional"
direction = [0.15, -0.35, 1.0]
intensity = 1.0
"#,
    );
    for (near, far, half) in [(3.0f32, -1.0f32, 4.0f32), (-1.0, -9.0, 12.0), (-9.0, -25.0, 20.0), (-25.0, -57.0, 44.0)]
    {
        let repeat = [2.0 * half / 4.0, (near - far) / 4.0];
        text += &format!(
            "\n[[object]]\nshape = \"patch\"\ncorners = [[{}, 0.0, {near}], [{half}, 0.0, {near}], [{half}, 0.0, {far}], [{}, 0.0, {far}]]\n\
             [object.material]\ncolor = [0.45, 0.45, 0.5]\nspecular = 0.8\nshininess = 80.0\n\
             bump = {{ generator = {{ kind = \"grid\", size = 64, cells = 2, line_width = 0.25, soft = 0.15 }}, scale = 0.02, invariant = true, repeat = [{:?}, {:?}] }}\n",
            -half, -half, repeat[0], repeat[1]
        );
    }
    text
}

/// A sphere under a fine grid of shiny bumps (Blinn's own formula), a few pixels a cell.
const SPHERE: &str = r#"
[camera]
eye = [0.0, 0.0, 3.2]
look_at = [0.0, 0.0, 0.0]
fov_y = 45.0

[[light]]
type = "directional"
direction = [0.4, -0.5, -0.75]
intensity = 1.0

[[object]]
shape = "sphere"

[object.material]
color = [0.5, 0.5, 0.5]
specular = 0.8
shininess = 60.0

[object.material.bump]
generator = { kind = "grid", size = 64, cells = 2, line_width = 0.3, soft = 0.1 }
scale = 0.006
repeat = [48, 24]
"#;

fn grey(scene: &str, options: &RenderOptions) -> Vec<f32> {
    let scene = Scene::parse(scene, Path::new(".")).unwrap();
    render(&scene, options).unwrap().color.iter().map(|c| (c[0] + c[1] + c[2]) / 3.0).collect()
}

fn rmse(a: &[f32], b: &[f32]) -> f32 {
    (a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum::<f32>() / a.len() as f32).sqrt()
}

/// The error of each bump filter at 1 spp against 64 Sobol samples of the unfiltered table.
fn errors(scene: &str, filters: &[&str]) -> Vec<f32> {
    let base = RenderOptions { width: 200, height: 150, bump_filter: BumpFilter::parse("none"), ..Default::default() };
    let truth = grey(scene, &RenderOptions { spp: 64, sampler: Sampler::Sobol, ..base.clone() });
    filters
        .iter()
        .map(|name| {
            let filter = BumpFilter::parse(name).unwrap();
            rmse(&grey(scene, &RenderOptions { bump_filter: Some(filter), ..base.clone() }), &truth)
        })
        .collect()
}

#[test]
fn lean_comes_closest_to_the_supersampled_intensities() {
    let filters = ["none", "mip", "ewa", "toksvig:ewa", "lean:ewa", "lean"];
    for (what, scene) in [("grooved plane", grooved_plane()), ("bumpy sphere", SPHERE.to_string())] {
        let e = errors(&scene, &filters);
        let line: Vec<String> = filters.iter().zip(&e).map(|(n, e)| format!("{n} {e:.4}")).collect();
        eprintln!("{what}: {}", line.join(", "));
        let [none, mip, ewa, toksvig, lean, lean_trilinear] = e[..] else { unreachable!() };
        // LEAN at least 30% below the MIP-filtered bump and the unfiltered table, and below plain EWA.
        assert!(lean < 0.7 * none.min(mip), "{what}: lean {lean} vs none {none}, mip {mip}");
        assert!(lean < ewa, "{what}: lean {lean} vs ewa {ewa}");
        // Toksvig between LEAN and the filters that ignore the spread.
        assert!(lean <= toksvig && toksvig < none.min(mip), "{what}: toksvig {toksvig}");
        // Through trilinear, LEAN still beats the MIP-filtered heights it costs about as much as.
        assert!(lean_trilinear < mip, "{what}: lean (trilinear) {lean_trilinear} vs mip {mip}");
    }
}

/// Magnified (texels many pixels wide), the slopes under a pixel hardly spread: LEAN renders what the
/// MIP-filtered bump renders, to 8-bit rounding.
#[test]
fn lean_at_magnification_is_plain_bump_mapping() {
    let close = SPHERE
        .replace("eye = [0.0, 0.0, 3.2]", "eye = [0.0, 0.0, 1.25]")
        .replace("repeat = [48, 24]", "repeat = [2, 1]");
    let frame = |name: &str| {
        let options =
            RenderOptions { width: 200, height: 150, bump_filter: BumpFilter::parse(name), ..Default::default() };
        let scene = Scene::parse(&close, Path::new(".")).unwrap();
        let color = render(&scene, &options).unwrap().color;
        color
            .iter()
            .flat_map(|c| *c)
            .map(|c| (linear_to_srgb(c).clamp(0.0, 1.0) * 255.0).round() as u8)
            .collect::<Vec<u8>>()
    };
    let (mip, lean) = (frame("mip"), frame("lean"));
    let worst = mip.iter().zip(&lean).map(|(a, b)| (*a as i32 - *b as i32).abs()).max().unwrap();
    let moved = mip.iter().zip(&lean).filter(|(a, b)| a != b).count();
    eprintln!("magnified: largest difference {worst} codes, {moved} of {} channels differ", mip.len());
    assert!(worst <= 1, "largest difference {worst} codes");
    // The view does show highlights on bumps (the test is not of a dull surface).
    let toksvig = frame("toksvig");
    assert!(toksvig.iter().zip(&lean).all(|(a, b)| (*a as i32 - *b as i32).abs() <= 1));
    assert!(*mip.iter().max().unwrap() > 200, "no highlight in view");
}

/// The grooved plane with its bump given by `material` (a TOML snippet of the patch material's bump or
/// normal map, `{repeat}` replaced by each row's repeat).
fn plane_with(material: &str) -> String {
    grooved_plane()
        .lines()
        .map(|line| match line.strip_prefix("bump = ") {
            Some(bump) => {
                let repeat = &bump[bump.find("repeat = ").unwrap() + 9..bump.rfind(" }").unwrap()];
                material.replace("{repeat}", repeat)
            }
            None => line.to_string(),
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// Grooves two texels of every eight across a 64 x 64 texel tile, as an offset map (Bs in red) and as a
/// tangent-space normal map, both 16-bit PNG.
fn groove_maps(dir: &Path) -> (String, String) {
    let profile = |i: usize| (std::f32::consts::TAU * (i % 8) as f32 / 8.0).sin() * if i % 8 < 4 { 1.0 } else { 0.3 };
    let (n, slope) = (64usize, 0.3f32);
    let mut offsets = Vec::with_capacity(n * n * 3);
    let mut normals = Vec::with_capacity(n * n * 3);
    for _ in 0..n {
        for i in 0..n {
            let b = slope * profile(i);
            offsets.extend([0.5 + 0.5 * b, 0.5, 0.5]);
            let len = (1.0 + b * b).sqrt();
            normals.extend([0.5 + 0.5 * (-b / len), 0.5, 0.5 + 0.5 / len]);
        }
    }
    let (o, m) = (dir.join("offsets.png"), dir.join("normals.png"));
    wrinkle::image::io::write_png_rgb16(&o, n, n, &offsets).unwrap();
    wrinkle::image::io::write_png_rgb16(&m, n, n, &normals).unwrap();
    (o.display().to_string(), m.display().to_string())
}

/// Offset maps, normal maps and procedural bumps take LEAN too: each against its own 64-spp truth
/// (the full-resolution map, bilinear; the procedural pattern's own octaves at each sample's footprint).
#[test]
fn lean_filters_offset_maps_normal_maps_and_procedural_bumps() {
    let dir = crate::common::scratch_dir("lean-maps");
    let (offsets, normals) = groove_maps(&dir);
    let cases = [
        ("offset map", format!("bump = {{ offsets = \"{offsets}\", scale = 0.15, invariant = true, filter = \"FILTER\", repeat = {{repeat}} }}"), ["bilinear", "ewa", "lean:ewa"]),
        ("normal map", format!("normal_map = {{ path = \"{normals}\", filter = \"FILTER\", repeat = {{repeat}} }}"), ["bilinear", "ewa", "lean:ewa"]),
        ("procedural", "bump = { procedural = { pattern = \"fbm\", scale = 6, octaves = 8, space = \"uv\" }, scale = 0.06, FILTER repeat = {repeat} }".to_string(), ["", "", "filter = \"lean\","]),
    ];
    let base = RenderOptions { width: 200, height: 150, ..Default::default() };
    for (what, material, [truth_filter, plain_filter, lean_filter]) in cases {
        let scene = |filter: &str| plane_with(&material.replace("FILTER", filter));
        let truth = grey(&scene(truth_filter), &RenderOptions { spp: 64, sampler: Sampler::Sobol, ..base.clone() });
        let plain = rmse(&grey(&scene(plain_filter), &base), &truth);
        let lean = rmse(&grey(&scene(lean_filter), &base), &truth);
        eprintln!("{what}: plain {plain:.4}, lean {lean:.4}");
        assert!(lean < 0.8 * plain, "{what}: lean {lean} vs plain {plain}");
    }
}

/// On a mesh (an OBJ floor with an .mtl bump map, Pu and Pv from each triangle's uv gradients) as on the
/// parametric patches: LEAN comes closer to the supersampled intensities than the MIP-filtered bump.
#[test]
fn lean_filters_bumps_on_meshes() {
    let dir = crate::common::scratch_dir("lean-mesh");
    // Grooves across u: a raised cosine two texels wide in every eight, 64 x 64, 16-bit grey.
    let n = 64usize;
    let groove = |i: usize| {
        let x = (i % 8) as f32 - 3.5;
        if x.abs() < 2.0 {
            0.5 + 0.5 * (std::f32::consts::PI * x / 2.0).cos()
        } else {
            0.0
        }
    };
    let grey = wrinkle::Image { width: n, height: n, pixels: (0..n * n).map(|k| groove(k % n)).collect::<Vec<f32>>() };
    wrinkle::image::io::write_png_grey16(&dir.join("grooves.png"), &grey).unwrap();
    std::fs::write(
        dir.join("floor.mtl"),
        "newmtl m\nKd 0.45 0.45 0.5\nKs 0.8 0.8 0.8\nNs 80\nbump -bm 1.5 grooves.png\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("floor.obj"),
        "mtllib floor.mtl\nusemtl m\nv -1 -0.5 1\nv 1 -0.5 1\nv 1 -0.5 -9\nv -1 -0.5 -9\n\
         vt 0 0\nvt 4 0\nvt 4 20\nvt 0 20\nvn 0 1 0\nf 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n",
    )
    .unwrap();
    let scene = format!(
        "[camera]\neye = [0.0, 0.6, 3.0]\nlook_at = [0.0, 0.0, 0.0]\nfov_y = 40.0\n\n\
         [[light]]\ntype = \"directional\"\ndirection = [0.1, -0.3, 1.0]\nintensity = 1.0\n\n\
         [[object]]\nshape = \"mesh\"\nfile = \"{}\"\n",
        dir.join("floor.obj").display().to_string().replace('\\', "/")
    );
    let scene = Scene::parse(&scene, &dir).unwrap();
    let image = |filter: &str, spp: usize| {
        let options = RenderOptions {
            width: 200,
            height: 150,
            spp,
            sampler: Sampler::Sobol,
            bump_filter: BumpFilter::parse(filter),
            ..Default::default()
        };
        render(&scene, &options).unwrap().color.iter().map(|c| (c[0] + c[1] + c[2]) / 3.0).collect::<Vec<f32>>()
    };
    let truth = image("none", 64);
    let (mip, lean) = (rmse(&image("mip", 1), &truth), rmse(&image("lean:ewa", 1), &truth));
    eprintln!("mesh: mip {mip:.4}, lean:ewa {lean:.4}");
    assert!(lean < 0.8 * mip, "mesh: lean {lean} vs mip {mip}");
}
