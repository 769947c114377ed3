//! Every texture filter against the ground truth on the classic view: a checkerboard on a plane receding
//! to the horizon. The ground truth of a pixel is the integral of the bilinearly reconstructed texture over
//! the pixel's exact preimage: 32 x 32 stratified samples, each at the (u,v) where its own ray meets the
//! plane (computed here in f64, independently of the renderer). The filters get the pixel centre's (u,v)
//! and its exact screen derivatives.

use glam::{DVec3, Vec4};
use wrinkle::image::color::srgb_to_linear;
use wrinkle::image::Image;
use wrinkle::internals::Axes;
use wrinkle::texture::{Filter, FilterOptions, FilteredTexture, Footprint, LookupContext, TextureOptions};

const W: usize = 192;
const H: usize = 128;
/// Texture periods per world unit along the plane, and the texture's rotation on it (degrees): rotated so
/// the footprints are not aligned with the texture axes (where ripmaps and SATs are at their best).
const PERIOD: f64 = 2.0;
const ROTATION: f64 = 30.0;

/// A 64 x 64 checkerboard of 4-texel checks, brick red and cream, sRGB-encoded colours decoded to linear.
fn checkerboard() -> FilteredTexture {
    let colour = |c: [u8; 3]| {
        [
            srgb_to_linear(c[0] as f32 / 255.0),
            srgb_to_linear(c[1] as f32 / 255.0),
            srgb_to_linear(c[2] as f32 / 255.0),
            1.0,
        ]
    };
    let (a, b) = (colour([200, 50, 30]), colour([245, 240, 220]));
    let image = Image::from_fn(64, 64, |x, y| if (x / 4 + y / 4) % 2 == 0 { a } else { b });
    FilteredTexture::new(&image, TextureOptions::default())
}

/// The camera: 1 unit above the plane y = 0, looking slightly down towards -z, 50 degree vertical field.
struct View {
    eye: DVec3,
    fwd: DVec3,
    right: DVec3,
    up: DVec3,
    scale: f64,
}

impl View {
    fn new() -> View {
        let eye = DVec3::new(0.0, 1.0, 0.0);
        let fwd = DVec3::new(0.0, -0.25, -1.0).normalize();
        let right = fwd.cross(DVec3::Y).normalize();
        let up = right.cross(fwd);
        View { eye, fwd, right, up, scale: 0.5 * H as f64 / 25f64.to_radians().tan() }
    }

    /// (u,v) where the ray through screen point (x, y) (pixels, y down) meets the plane, if it does
    /// within 2000 units.
    fn uv(&self, x: f64, y: f64) -> Option<[f64; 2]> {
        let d = self.fwd + (x - 0.5 * W as f64) / self.scale * self.right + (0.5 * H as f64 - y) / self.scale * self.up;
        if d.y >= 0.0 {
            return None;
        }
        let t = -self.eye.y / d.y;
        let p = self.eye + t * d;
        if (p - self.eye).length() > 2000.0 {
            return None;
        }
        let (c, s) = (ROTATION.to_radians().cos(), ROTATION.to_radians().sin());
        Some([(p.x * c - p.z * s) / PERIOD, (p.x * s + p.z * c) / PERIOD])
    }
}

struct Pixel {
    /// The pixel's centre on the screen.
    centre: [f64; 2],
    uv: [f64; 2],
    footprint: Footprint,
    truth: Vec4,
}

/// The pixels wholly on the plane, with their ground truth.
fn pixels(tex: &FilteredTexture) -> Vec<Pixel> {
    let view = View::new();
    let bilinear = FilterOptions { filter: Filter::parse("bilinear").unwrap(), ..FilterOptions::default() };
    let exact = tex.with_options(bilinear);
    let n = 32;
    let mut out = Vec::new();
    for py in 0..H {
        for px in 0..W {
            let (x, y) = (px as f64 + 0.5, py as f64 + 0.5);
            // The whole pixel must be on the plane: its top corners' rays meet it.
            if view.uv(x - 0.5, y - 0.5).is_none() || view.uv(x + 0.5, y - 0.5).is_none() {
                continue;
            }
            let (uv, footprint) = uv_and_footprint(&view, x, y);
            let mut sum = Vec4::ZERO;
            for b in 0..n {
                for a in 0..n {
                    let sx = px as f64 + (a as f64 + 0.5) / n as f64;
                    let sy = py as f64 + (b as f64 + 0.5) / n as f64;
                    let [u, v] = view.uv(sx, sy).unwrap();
                    sum += exact.lookup(u.rem_euclid(1.0) as f32, v.rem_euclid(1.0) as f32, &Footprint::default());
                }
            }
            out.push(Pixel { centre: [x, y], uv, footprint, truth: sum / (n * n) as f32 });
        }
    }
    out
}

fn rmse(tex: &FilteredTexture, filter: Filter, pixels: &[&Pixel]) -> f64 {
    let t = tex.with_options(FilterOptions { filter, ..FilterOptions::default() });
    let sum: f64 = pixels
        .iter()
        .map(|p| {
            let (s, tt) = (p.uv[0].rem_euclid(1.0) as f32, p.uv[1].rem_euclid(1.0) as f32);
            let d = (t.lookup(s, tt, &p.footprint) - p.truth).truncate();
            d.length_squared() as f64 / 3.0
        })
        .sum();
    (sum / pixels.len() as f64).sqrt()
}

fn psnr(rmse: f64) -> f64 {
    -20.0 * rmse.log10()
}

#[test]
fn every_filter_against_the_ground_truth_on_the_grazing_plane() {
    let tex = checkerboard();
    let all = pixels(&tex);
    let all_refs: Vec<&Pixel> = all.iter().collect();
    // The anisotropic part: footprints more than 4:1.
    let aniso: Vec<&Pixel> = all
        .iter()
        .filter(|p| {
            let a = Axes::of_footprint(&p.footprint, 64, 64);
            a.major > 1.0 && a.major > 4.0 * a.minor
        })
        .collect();
    assert!(all.len() > W * H / 2 && aniso.len() > W * H / 8, "{} pixels, {} anisotropic", all.len(), aniso.len());
    let names = [
        "nearest",
        "bilinear",
        "bicubic",
        "bspline",
        "gaussian",
        "lanczos",
        "mip-nearest",
        "trilinear",
        "ripmap",
        "sat",
        "aniso",
        "ewa",
    ];
    let mut psnr_all = std::collections::HashMap::new();
    let mut psnr_aniso = std::collections::HashMap::new();
    for name in names {
        let f = Filter::parse(name).unwrap();
        let (ea, en) = (rmse(&tex, f, &all_refs), rmse(&tex, f, &aniso));
        eprintln!(
            "{name:12} rmse {ea:.4} psnr {:.2} dB | anisotropic part: rmse {en:.4} psnr {:.2} dB",
            psnr(ea),
            psnr(en)
        );
        psnr_all.insert(name, psnr(ea));
        psnr_aniso.insert(name, psnr(en));
    }
    let (a, n) = (&psnr_all, &psnr_aniso);
    // EWA and anisotropic beat trilinear.
    assert!(a["ewa"] > a["trilinear"] + 1.0 && a["aniso"] > a["trilinear"] + 1.0, "{a:?}");
    // Trilinear beats bilinear without MIP maps by a wide margin (RMSE at least halved: 6 dB).
    assert!(a["trilinear"] > a["bilinear"] + 6.0, "{a:?}");
    // On the anisotropic part, ripmap and SAT sit between trilinear and the anisotropic filters.
    for between in ["ripmap", "sat"] {
        assert!(n[between] > n["trilinear"], "{between}: {n:?}");
        assert!(n[between] < n["aniso"].max(n["ewa"]), "{between}: {n:?}");
    }
    // The floors measured (docs/filtering.md), less 0.3 dB of slack.
    let floors = [
        ("nearest", 13.06),
        ("bilinear", 16.14),
        ("bicubic", 14.74),
        ("bspline", 17.61),
        ("gaussian", 16.99),
        ("lanczos", 14.19),
        ("mip-nearest", 24.36),
        ("trilinear", 25.04),
        ("ripmap", 26.10),
        ("sat", 25.07),
        ("aniso", 40.19),
        ("ewa", 34.28),
    ];
    for (name, floor) in floors {
        assert!(a[name] > floor - 0.3, "{name}: {:.2} dB, floor {floor}", a[name]);
    }
}

/// (u,v) at screen point (x, y) and its exact screen derivatives there.
fn uv_and_footprint(view: &View, x: f64, y: f64) -> ([f64; 2], Footprint) {
    let e = 1e-3;
    let (ax, bx) = (view.uv(x + e, y).unwrap(), view.uv(x - e, y).unwrap());
    let (ay, by) = (view.uv(x, y + e).unwrap(), view.uv(x, y - e).unwrap());
    let d = |a: [f64; 2], b: [f64; 2], k: usize| ((a[k] - b[k]) / (2.0 * e)) as f32;
    (
        view.uv(x, y).unwrap(),
        Footprint { dudx: d(ax, bx, 0), dvdx: d(ax, bx, 1), dudy: d(ay, by, 0), dvdy: d(ay, by, 1) },
    )
}

/// Supersampling with trilinear lookups: each of a pixel's n x n samples reads the texture with its own cell's
/// footprint (the pixel's derivatives over n), and the pixel is their mean. A bilinear tap's tent has twice
/// the variance of the box over the texels it stands for, so half a level finer (lod_bias -0.5) comes closer
/// to the ground truth at every sample count; at 1 sample too, but there the coarser level's blur is the
/// convention that keeps a lone sample from aliasing.
#[test]
fn half_a_level_finer_brings_supersampled_trilinear_closer_to_the_ground_truth() {
    let tex = checkerboard();
    let view = View::new();
    let all = pixels(&tex);
    let rmse_at = |n: usize, lod_bias: f32| {
        let t = tex.with_lookup(tex.options().filter, lod_bias);
        let sum: f64 = all
            .iter()
            .map(|p| {
                let mut mean = Vec4::ZERO;
                for b in 0..n {
                    for a in 0..n {
                        let (dx, dy) = ((a as f64 + 0.5) / n as f64 - 0.5, (b as f64 + 0.5) / n as f64 - 0.5);
                        let (x, y) = (p.centre[0] + dx, p.centre[1] + dy);
                        let ([u, v], fp) = uv_and_footprint(&view, x, y);
                        let cell = fp.scaled(1.0 / n as f32);
                        mean += t.lookup(u.rem_euclid(1.0) as f32, v.rem_euclid(1.0) as f32, &cell);
                    }
                }
                let d = (mean / (n * n) as f32 - p.truth).truncate();
                d.length_squared() as f64 / 3.0
            })
            .sum();
        (sum / all.len() as f64).sqrt()
    };
    for n in [1, 2, 4] {
        let (plain, finer) = (psnr(rmse_at(n, 0.0)), psnr(rmse_at(n, -0.5)));
        eprintln!("{n}x{n} samples: trilinear {plain:.2} dB, lod_bias -0.5 {finer:.2} dB");
        assert!(finer > plain + 0.5, "{n}x{n} samples: lod_bias -0.5 {finer:.2} dB, none {plain:.2} dB");
    }
    // A bias is the footprint scaled by 2^bias: -1 at a footprint is no bias at half of it, bit for bit.
    let (half, coarser) = (tex.with_lookup(tex.options().filter, -1.0), &tex);
    for p in all.iter().step_by(97) {
        let (s, t) = (p.uv[0].rem_euclid(1.0) as f32, p.uv[1].rem_euclid(1.0) as f32);
        assert_eq!(half.lookup(s, t, &p.footprint), coarser.lookup(s, t, &p.footprint.scaled(0.5)));
    }
}

/// A material's texture with its filter, both forms, and the errors that name the field.
#[test]
fn scene_files_choose_the_filter_per_texture() {
    use std::path::Path;
    use wrinkle::Scene;
    let dir = std::env::temp_dir().join(format!("wrinkle_filtering_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let rgb: Vec<u8> = (0..16 * 8 * 3).map(|k| (k * 37 % 256) as u8).collect();
    wrinkle::image::io::write_png_rgb8(&dir.join("t.png"), 16, 8, &rgb).unwrap();
    let scene = |material: &str| {
        format!("[camera]\neye = [0.0, 0.0, 3.0]\nlook_at = [0.0, 0.0, 0.0]\n\n[[object]]\nshape = \"sphere\"\nmaterial = {material}\n")
    };
    let parse = |material: &str| Scene::parse(&scene(material), Path::new(&dir));
    let fp = Footprint { dudx: 0.3, dvdx: 0.05, dudy: 0.0, dvdy: 0.01 };
    let ctx = LookupContext::at_uv(glam::Vec2::new(0.3, 0.6), fp);
    let look = |s: &Scene| s.materials[0].colour_texture().unwrap().eval(&ctx);
    let short = parse("{ texture = \"t.png\", filter = \"ewa\" }").unwrap();
    let table = parse("{ texture = { path = \"t.png\", filter = \"ewa\", wrap = \"repeat\", srgb = true } }").unwrap();
    let trilinear = parse("{ texture = \"t.png\" }").unwrap();
    assert_eq!(look(&short), look(&table));
    assert_ne!(look(&short), look(&trilinear), "the default is trilinear, not EWA");
    // Overriding the scene's filter, as --filter does.
    let mut over = parse("{ texture = \"t.png\" }").unwrap();
    over.set_texture_filter(Filter::parse("ewa").unwrap());
    assert_eq!(look(&over), look(&short));
    // The level-of-detail bias: the footprint scaled by 2^bias, in the scene or overriding it (--lod-bias).
    let biased = parse("{ texture = { path = \"t.png\", lod_bias = -1.0 } }").unwrap();
    let halved = LookupContext::at_uv(ctx.uv, fp.scaled(0.5));
    assert_eq!(look(&biased), trilinear.materials[0].colour_texture().unwrap().eval(&halved));
    assert_ne!(look(&biased), look(&trilinear));
    let mut over = parse("{ texture = \"t.png\" }").unwrap();
    over.set_texture_lod_bias(-1.0);
    assert_eq!(look(&over), look(&biased));
    for (material, message) in [
        ("{ texture = \"t.png\", filter = \"fancy\" }", "objects[0].material.filter: expected one of \"nearest\""),
        (
            "{ texture = { path = \"t.png\", filter = \"ewa\" }, filter = \"sat\" }",
            "objects[0].material.filter: given twice",
        ),
        ("{ filter = \"sat\" }", "objects[0].material.filter: only with a texture"),
        ("{ texture = { path = \"t.png\", wrap = \"wobble\" } }", "objects[0].material.texture.wrap: expected one of"),
        (
            "{ texture = { path = \"t.png\", mipmap = \"tent\" } }",
            "objects[0].material.texture.mipmap: expected one of",
        ),
        (
            "{ texture = { path = \"t.png\", lod_bias = 5 } }",
            "objects[0].material.texture.lod_bias: expected a number of levels from -4 to 4",
        ),
        (
            "{ texture = { path = \"t.png\", wrap = \"border\", border = [2, 0, 0] } }",
            "objects[0].material.texture.border: expected components between 0 and 1",
        ),
    ] {
        let e = parse(material).err().unwrap_or_else(|| panic!("{material} parsed")).to_string();
        assert!(e.starts_with(message), "{material}: {e}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
