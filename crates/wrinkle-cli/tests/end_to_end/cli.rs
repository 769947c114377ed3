//! End-to-end tests of the `wrinkle` command: each test runs the built binary in a fresh scratch
//! folder and checks its exit code, its output files and, for bad input, the one-line error.
//!
//! Conventions checked: every error is one line on stderr starting with `error: ` and naming the
//! file, field or value at fault; exit code 2 for a usage error (arguments, scene or input files),
//! 1 for a failed job (the output cannot be written); no output or temporary file is left behind.

use crate::common::*;
use std::collections::BTreeSet;
use std::fs;
use std::path::Path;

use glam::DVec3;
use wrinkle::image::io::{read_exr_channels, Placement};

/// Small images keep every render fast.
const W: &str = "64";
const H: &str = "48";

/// Width, height, bit depth and colour type from a PNG's signature and IHDR chunk.
fn png_header(path: &str) -> (u32, u32, u8, u8) {
    let b = fs::read(path).unwrap();
    assert!(b.len() > 33, "{path}: too short for a PNG");
    assert_eq!(&b[..8], b"\x89PNG\r\n\x1a\n", "{path}: PNG signature");
    assert_eq!(&b[12..16], b"IHDR", "{path}: first chunk");
    let be = |i: usize| u32::from_be_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]]);
    (be(16), be(20), b[24], b[25])
}

/// A valid scene around one `[[object]]` whose body (fields and sub-tables) is `object`.
fn scene_with(object: &str) -> String {
    format!(
        "[camera]\neye = [0.0, 0.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\nfov_y = 40.0\n\n\
         [[light]]\ntype = \"directional\"\ndirection = [-1.0, -1.0, -1.0]\n\n\
         [[object]]\n{object}\n"
    )
}

/// `wrinkle render SCENE -o out/x.png` at the small size, plus `extra` arguments.
fn render_scene(s: &Scratch, scene: &str, extra: &[&str]) -> Run {
    let out = s.out("x.png");
    let mut args = vec!["render", scene, "-o", &out, "--width", W, "--height", H];
    args.extend_from_slice(extra);
    wrinkle(&args)
}

/// `wrinkle render` of the default scene into out/x.png with `extra` arguments.
fn render_default(s: &Scratch, extra: &[&str]) -> Run {
    let out = s.out("x.png");
    let mut args = vec!["render", "-o", &out];
    args.extend_from_slice(extra);
    wrinkle(&args)
}

/// Writes a bump table made by `wrinkle bumpgen grid` to in/{name}, cut to its first half.
fn truncated_png(s: &Scratch, name: &str) -> String {
    let path = s.input(name);
    assert_ok(&wrinkle(&["bumpgen", "grid", "-o", &path, "--size", "64"]));
    let bytes = fs::read(&path).unwrap();
    fs::write(&path, &bytes[..bytes.len() / 2]).unwrap();
    path
}

// ---------------------------------------------------------------------------------------------
// Help and version

#[test]
fn version_prints_the_version() {
    let run = wrinkle(&["--version"]);
    assert_ok(&run);
    assert_eq!(run.stdout.trim(), format!("wrinkle {}", env!("CARGO_PKG_VERSION")));
}

#[test]
fn help_of_every_command_has_examples() {
    for args in [
        &["--help"][..],
        &["render", "--help"],
        &["bumpgen", "--help"],
        &["bench", "--help"],
        &["filters", "--help"],
        &["mipmap", "--help"],
        &["bench-texture", "--help"],
    ] {
        let run = wrinkle(args);
        assert_ok(&run);
        assert!(run.stdout.contains("Examples"), "{args:?}: {}", run.stdout);
    }
}

// ---------------------------------------------------------------------------------------------
// Rendering

#[test]
fn default_scene_renders_a_png_of_the_asked_size() {
    let s = Scratch::new("default");
    let run = render_default(&s, &["--width", "96", "--height", "54"]);
    assert_ok(&run);
    assert_eq!(png_header(&s.out("x.png")), (96, 54, 8, 2), "8-bit RGB, 96x54");
    assert_eq!(s.out_entries(), ["x.png"], "no temporary file left");
}

#[test]
fn scene_file_with_relative_texture_and_bump_map_renders() {
    let s = Scratch::new("scenefile");
    let tex = s.input("tex.png");
    assert_ok(&wrinkle(&["bumpgen", "bricks", "-o", &tex, "--size", "32"]));
    let scene = s.write_input(
        "scene.toml",
        scene_with(
            "shape = \"sphere\"\nradius = 1.0\n\n[object.material]\ntexture = \"tex.png\"\n\n\
             [object.material.bump]\nmap = \"tex.png\"\nscale = 0.01\nrepeat = [4, 2]\n",
        ),
    );
    assert_ok(&render_scene(&s, &scene, &["--spp", "4"]));
    assert_eq!(png_header(&s.out("x.png")), (64, 48, 8, 2));
    assert_eq!(s.out_entries(), ["x.png"]);
}

#[test]
fn aovs_are_written_beside_the_output() {
    let s = Scratch::new("aov");
    assert_ok(&render_default(&s, &["--width", W, "--height", H, "--aov", "normal,uv,depth,id"]));
    assert_eq!(s.out_entries(), ["x.depth.exr", "x.id.exr", "x.normal.exr", "x.png", "x.uv.exr"]);

    // Each AOV: its channels (alphabetical), and whether each pixel is covered (finite) or not (NaN).
    let mut coverage: Vec<Vec<bool>> = Vec::new();
    let mut read = |name: &str, want: &[&str]| -> Vec<(String, Vec<f32>)> {
        let path = s.out(&format!("x.{name}.exr"));
        assert!(fs::metadata(&path).unwrap().len() > 0, "{path} is empty");
        let (w, h, channels) = read_exr_channels(Path::new(&path)).unwrap();
        assert_eq!((w, h), (64, 48), "{name}");
        let names: Vec<&str> = channels.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, want, "{name} channels");
        for (c, samples) in &channels {
            assert_eq!(samples.len(), 64 * 48, "{name}.{c}");
            // The default scene's top-left and top-right corners show the background.
            for corner in [0, 63] {
                assert!(samples[corner].is_nan(), "{name}.{c} at corner pixel {corner} = {}", samples[corner]);
            }
            coverage.push(samples.iter().map(|v| v.is_finite()).collect());
            // No infinities: a sample is either NaN (background) or finite (covered).
            assert!(samples.iter().all(|v| v.is_nan() || v.is_finite()), "{name}.{c} holds an infinity");
        }
        channels
    };
    let normal = read("normal", &["X", "Y", "Z"]);
    let uv = read("uv", &["U", "V"]);
    let depth = read("depth", &["Z"]);
    let id = read("id", &["id"]);

    // Every AOV covers the same pixels, and the three objects of the default scene are all seen.
    let covered = coverage[0].clone();
    assert!(coverage.iter().all(|c| *c == covered), "AOVs disagree on which pixels are covered");
    let n = covered.iter().filter(|&&c| c).count();
    assert!(n > 64 * 48 / 10 && n < 64 * 48, "{n} covered pixels");
    let ids: BTreeSet<u32> = id[0].1.iter().filter(|v| v.is_finite()).map(|&v| v as u32).collect();
    assert_eq!(ids, BTreeSet::from([0, 1, 2]), "object ids seen");
    for p in (0..64 * 48).filter(|&p| covered[p]) {
        let len = (normal[0].1[p].powi(2) + normal[1].1[p].powi(2) + normal[2].1[p].powi(2)).sqrt();
        assert!((len - 1.0).abs() < 1e-3, "pixel {p}: |normal| = {len}");
        assert!(depth[0].1[p] > 0.0, "pixel {p}: depth {}", depth[0].1[p]);
        for (c, samples) in &uv {
            assert!((-1e-4..=1.0 + 1e-4).contains(&samples[p]), "pixel {p}: {c} = {}", samples[p]);
        }
        assert_eq!(id[0].1[p].fract(), 0.0, "pixel {p}: id {}", id[0].1[p]);
    }
}

/// The item buffer as 32-bit integers: the object agrees with the id AOV, the background is 2^32 - 1.
#[test]
fn primitive_aov_is_the_item_buffer() {
    let s = Scratch::new("aov-primitive");
    assert_ok(&render_default(&s, &["--width", W, "--height", H, "--aov", "id,primitive"]));
    let (_, _, primitive) = read_exr_channels(Path::new(&s.out("x.primitive.exr"))).unwrap();
    let (_, _, id) = read_exr_channels(Path::new(&s.out("x.id.exr"))).unwrap();
    let names: Vec<&str> = primitive.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["object", "triangle"]);
    let (object, triangle) = (&primitive[0].1, &primitive[1].1);
    let mut triangles = BTreeSet::new();
    for p in 0..64 * 48 {
        if id[0].1[p].is_nan() {
            assert_eq!((object[p], triangle[p]), (u32::MAX as f32, u32::MAX as f32), "pixel {p}");
        } else {
            assert_eq!(object[p], id[0].1[p], "pixel {p}");
            triangles.insert(triangle[p] as u32);
        }
    }
    // The tessellated cover scene shows many triangles, each numbered within its object.
    assert!(triangles.len() > 50, "{} triangles seen", triangles.len());
}

#[test]
fn exr_output_is_linear_rgb() {
    let s = Scratch::new("exr");
    let out = s.out("x.exr");
    assert_ok(&wrinkle(&["render", "-o", &out, "--width", W, "--height", H]));
    assert_eq!(s.out_entries(), ["x.exr"]);
    let (w, h, channels) = read_exr_channels(Path::new(&out)).unwrap();
    assert_eq!((w, h), (64, 48));
    let names: Vec<&str> = channels.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["B", "G", "R"]);
    for (c, samples) in &channels {
        assert!(samples.iter().all(|v| v.is_finite() && *v >= 0.0), "channel {c}");
        // The background is a constant, the objects are not: the picture is not flat.
        assert!(samples.iter().any(|v| v != &samples[0]), "channel {c} is constant");
    }
}

#[test]
fn turntable_writes_numbered_frames_that_differ() {
    let s = Scratch::new("turntable");
    assert_ok(&render_default(&s, &["--width", W, "--height", H, "--frames", "3", "--turntable"]));
    let names = ["x_0000.png", "x_0001.png", "x_0002.png"];
    assert_eq!(s.out_entries(), names);
    let frames: Vec<Vec<u8>> = names
        .iter()
        .map(|n| {
            assert_eq!(png_header(&s.out(n)), (64, 48, 8, 2), "{n}");
            fs::read(s.out(n)).unwrap()
        })
        .collect();
    assert_ne!(frames[0], frames[1]);
    assert_ne!(frames[1], frames[2]);
    assert_ne!(frames[0], frames[2]);
}

/// `--frames A..B --fps F` on an animated scene writes frames A to B, each numbered as its frame, frame f
/// the library's scene at time f / F bit for bit.
#[test]
fn an_animated_scene_renders_its_frames_at_their_times() {
    let s = Scratch::new("animation");
    let scene_file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/animation.toml");
    let out = s.out("a.exr");
    let args = ["--frames", "2..4", "--fps", "2", "--width", "64", "--height", "48"];
    assert_ok(&wrinkle(&[&["render", scene_file.to_str().unwrap(), "-o", &out][..], &args].concat()));
    assert_eq!(s.out_entries(), ["a_0002.exr", "a_0003.exr", "a_0004.exr"]);
    let scene = wrinkle::Scene::load(&scene_file).unwrap();
    let animation = scene.animation.clone().expect("animated");
    let options = wrinkle::RenderOptions { width: 64, height: 48, ..Default::default() };
    let red =
        |f: &str| read_exr_channels(Path::new(&s.out(f))).unwrap().2.into_iter().find(|(n, _)| n == "R").unwrap().1;
    let expected = wrinkle::render(&animation.scene_at(1.5).unwrap(), &options).unwrap().color;
    let got = red("a_0003.exr");
    assert!(got.iter().zip(&expected).all(|(g, e)| g.to_bits() == e[0].to_bits()), "frame 3 is not the scene at 1.5 s");
    assert!(red("a_0002.exr") != got && red("a_0004.exr") != got, "the frames do not move");
}

/// A turntable over frames A..B turns from 0 degrees at A: frame 1 of 1..2 is the unturned frame.
#[test]
fn a_turntable_range_starts_unturned() {
    let s = Scratch::new("turnrange");
    assert_ok(&render_default(&s, &["--width", W, "--height", H, "--frames", "1..2", "--turntable"]));
    let plain = s.out("plain.png");
    assert_ok(&wrinkle(&["render", "-o", &plain, "--width", W, "--height", H]));
    assert_eq!(fs::read(s.out("x_0001.png")).unwrap(), fs::read(&plain).unwrap());
    assert_ne!(fs::read(s.out("x_0002.png")).unwrap(), fs::read(&plain).unwrap());
}

#[test]
fn bad_frame_ranges() {
    let s = Scratch::new("frameranges");
    for (frames, words) in [("5..2", "backwards"), ("0", "at least 1"), ("a..3", "A..B"), ("1..", "A..B")] {
        assert_one_error(&render_default(&s, &["--frames", frames, "--turntable"]), 2, &["--frames", words], &s);
    }
    assert_one_error(&render_default(&s, &["--fps", "0", "--width", W, "--height", H]), 2, &["--fps", "0"], &s);
}

// ---------------------------------------------------------------------------------------------
// bumpgen and bench

#[test]
fn bumpgen_writes_16_bit_grey_pngs() {
    let s = Scratch::new("bumpgen");
    for (kind, width) in [("grid", 32), ("text", 32 * "WRINKLE".len() as u32), ("rivets", 32), ("bricks", 32)] {
        let out = s.out(&format!("{kind}.png"));
        let run = wrinkle(&["bumpgen", kind, "-o", &out, "--size", "32"]);
        assert_ok(&run);
        assert!(run.stdout.contains("16-bit"), "{kind}: {}", run.stdout);
        assert_eq!(png_header(&out), (width, 32, 16, 0), "{kind}: 16-bit grey");
    }
    assert_eq!(s.out_entries(), ["bricks.png", "grid.png", "rivets.png", "text.png"]);
}

#[test]
fn bench_prints_one_line_with_the_median() {
    let run = wrinkle(&["bench", "--width", W, "--height", H, "--frames", "2"]);
    assert_ok(&run);
    assert_eq!(run.stdout.lines().count(), 1, "{}", run.stdout);
    assert!(run.stdout.contains("median_ms="), "{}", run.stdout);
}

// ---------------------------------------------------------------------------------------------
// Bad input: one line on stderr, the right exit code, nothing in the output folder

#[test]
fn missing_scene_file() {
    let s = Scratch::new("noscene");
    let scene = s.input("nope.toml");
    assert_one_error(&render_scene(&s, &scene, &[]), 2, &["nope.toml", "no such file"], &s);
}

/// Each malformed scene text must give exit 2 and one line naming the file.
fn check_malformed(name: &str, cases: &[&str]) {
    let s = Scratch::new(name);
    for (i, text) in cases.iter().enumerate() {
        let scene = s.write_input(&format!("bad{i}.toml"), text);
        assert_one_error(&render_scene(&s, &scene, &[]), 2, &[&format!("bad{i}.toml"), "malformed TOML"], &s);
    }
}

#[test]
fn malformed_toml() {
    check_malformed(
        "malformed",
        &[
            "[camera]\neye = \"unterminated\n",
            "[camera]\neye = [0, 0, 4]\neye = [0, 0, 5]\n",
            "[camera]\neye [0, 0, 4]\n",
            "a = 1 2\n",
        ],
    );
}

#[test]
fn malformed_toml_unclosed_header_or_array() {
    check_malformed("malformed2", &["[camera\neye = [0, 0, 4]\n", "[camera]\neye = [0, 0, 4\n"]);
}

#[test]
fn unknown_shape() {
    let s = Scratch::new("shape");
    let scene = s.write_input("scene.toml", scene_with("shape = \"cone\""));
    assert_one_error(&render_scene(&s, &scene, &[]), 2, &["objects[0].shape", "\"cone\""], &s);
}

#[test]
fn negative_radius() {
    let s = Scratch::new("radius");
    let scene = s.write_input("scene.toml", scene_with("shape = \"sphere\"\nradius = -1.0"));
    assert_one_error(&render_scene(&s, &scene, &[]), 2, &["objects[0].radius", "-1"], &s);
}

#[test]
fn nan_in_a_transform() {
    let s = Scratch::new("nan");
    let scene = s.write_input("scene.toml", scene_with("shape = \"sphere\"\ntransform = { translate = [nan, 0, 0] }"));
    assert_one_error(&render_scene(&s, &scene, &[]), 2, &["objects[0].transform.translate[0]", "NaN"], &s);
}

#[test]
fn string_where_a_number_is_expected() {
    let s = Scratch::new("string");
    let scene = s.write_input(
        "scene.toml",
        scene_with("shape = \"sphere\"\n\n[object.material.bump]\ngenerator = { kind = \"grid\" }\nscale = \"big\""),
    );
    let run = render_scene(&s, &scene, &[]);
    assert_one_error(&run, 2, &[], &s);
    assert_eq!(run.stderr, "error: objects[0].material.bump.scale: expected a number, got \"big\"\n");
}

#[test]
fn unknown_field() {
    let s = Scratch::new("typo");
    let scene = s.write_input("scene.toml", scene_with("shape = \"sphere\"\nraduis = 1.0"));
    assert_one_error(&render_scene(&s, &scene, &[]), 2, &["objects[0].raduis", "unknown field"], &s);
}

#[test]
fn missing_texture_file() {
    let s = Scratch::new("notex");
    let scene =
        s.write_input("scene.toml", scene_with("shape = \"sphere\"\n\n[object.material]\ntexture = \"nope.png\""));
    assert_one_error(&render_scene(&s, &scene, &[]), 2, &["nope.png", "no such file"], &s);
}

#[test]
fn corrupt_texture_and_bump_map() {
    let s = Scratch::new("corrupt");
    truncated_png(&s, "cut.png");
    for material in [
        "[object.material]\ntexture = \"cut.png\"",
        "[object.material]\ntexture = { path = \"cut.png\", repeat = [2, 2] }",
        "[object.material.bump]\nmap = \"cut.png\"",
    ] {
        let scene = s.write_input("scene.toml", scene_with(&format!("shape = \"sphere\"\n\n{material}")));
        assert_one_error(&render_scene(&s, &scene, &[]), 2, &["cut.png", "PNG"], &s);
    }
}

#[test]
fn width_zero() {
    let s = Scratch::new("w0");
    assert_one_error(&render_default(&s, &["--width", "0", "--height", H]), 2, &["--width", "0"], &s);
}

#[test]
fn width_a_million() {
    let s = Scratch::new("w1e6");
    assert_one_error(&render_default(&s, &["--width", "1000000", "--height", H]), 2, &["--width", "1000000"], &s);
}

#[test]
fn spp_out_of_range() {
    let s = Scratch::new("spp");
    for spp in ["0", "5000"] {
        assert_one_error(&render_default(&s, &["--width", W, "--height", H, "--spp", spp]), 2, &["--spp", spp], &s);
    }
}

#[test]
fn unknown_pixel_filter() {
    let s = Scratch::new("pixfilter");
    assert_one_error(&render_default(&s, &["--pixel-filter", "sinc"]), 2, &["--pixel-filter", "sinc", "mitchell"], &s);
    assert_one_error(&render_default(&s, &["--pixel-filter", "tent:20"]), 2, &["--pixel-filter", "radius", "20"], &s);
    assert_one_error(&render_default(&s, &["--sampler", "halton"]), 2, &["--sampler", "halton"], &s);
}

/// `--spp`, `--sampler`, `--pixel-filter` and `--seed` reach the renderer: the EXR of the cover scene at 7
/// Sobol samples over a Mitchell filter, seed 5, is bit for bit the library's render with those options, not
/// the render with seed 0, and far from the same samples box-filtered.
#[test]
fn sampling_options_reach_the_renderer() {
    let s = Scratch::new("sampling");
    let size = ["--width", "96", "--height", "64", "--spp", "7", "--sampler", "sobol"];
    let (mitchell, boxed) = (s.out("mitchell.exr"), s.out("box.exr"));
    assert_ok(&wrinkle(
        &[&["render", "-o", &mitchell, "--pixel-filter", "mitchell", "--seed", "5"][..], &size].concat(),
    ));
    assert_ok(&wrinkle(&[&["render", "-o", &boxed][..], &size].concat()));
    let options = wrinkle::RenderOptions {
        width: 96,
        height: 64,
        spp: 7,
        sampler: wrinkle::Sampler::Sobol,
        pixel_filter: wrinkle::PixelFilter::parse("mitchell").unwrap(),
        seed: 5,
        ..Default::default()
    };
    let expected = wrinkle::render(&wrinkle::Scene::default_scene(), &options).unwrap().color;
    let seed_0 = wrinkle::render(&wrinkle::Scene::default_scene(), &wrinkle::RenderOptions { seed: 0, ..options })
        .unwrap()
        .color;
    assert!(seed_0 != expected, "the seed changed nothing");
    let red = |f: &str| read_exr_channels(Path::new(f)).unwrap().2.into_iter().find(|(n, _)| n == "R").unwrap().1;
    let (got, other) = (red(&mitchell), red(&boxed));
    assert!(got.iter().zip(&expected).all(|(g, e)| g.to_bits() == e[0].to_bits()), "the CLI's render differs");
    let apart = got.iter().zip(&other).map(|(a, b)| (a - b).abs()).fold(0.0f32, f32::max);
    assert!(apart > 0.05, "the pixel filter changed the frame by at most {apart}");
}

#[test]
fn unknown_aov() {
    let s = Scratch::new("aovbad");
    let run = render_default(&s, &["--width", W, "--height", H, "--aov", "normal,bogus"]);
    assert_one_error(&run, 2, &["--aov", "bogus"], &s);
}

#[test]
fn unknown_output_extension() {
    let s = Scratch::new("jpg");
    let out = s.out("x.jpg");
    assert_one_error(&wrinkle(&["render", "-o", &out, "--width", W, "--height", H]), 2, &["x.jpg"], &s);
}

#[test]
fn frames_without_turntable() {
    let s = Scratch::new("frames");
    let run = render_default(&s, &["--width", W, "--height", H, "--frames", "2"]);
    assert_one_error(&run, 2, &["--frames", "--turntable", "[[animation]]"], &s);
}

#[test]
fn zero_threads() {
    let s = Scratch::new("threads");
    assert_one_error(&render_default(&s, &["--width", W, "--height", H, "--threads", "0"]), 2, &["--threads"], &s);
}

#[test]
fn output_into_a_missing_directory_is_a_job_failure() {
    let s = Scratch::new("nodir");
    let out = s.out("nope/x.png");
    let run = wrinkle(&["render", "-o", &out, "--width", W, "--height", H, "--aov", "depth"]);
    assert_one_error(&run, 1, &["nope", "x.png", "does not exist"], &s);
    let run = wrinkle(&["bumpgen", "grid", "-o", &out, "--size", "32"]);
    assert_one_error(&run, 1, &["nope", "x.png", "does not exist"], &s);
}

#[test]
fn output_onto_a_directory_is_a_job_failure_and_leaves_no_temp_file() {
    let s = Scratch::new("ontodir");
    // The temporary file is created and written; renaming it onto a folder fails.
    fs::create_dir(s.out("x.png")).unwrap();
    let run = render_default(&s, &["--width", W, "--height", H]);
    assert_eq!(run.code, 1, "{run:#?}");
    assert_eq!(run.stderr.lines().count(), 1, "{:?}", run.stderr);
    assert!(run.stderr.starts_with("error: ") && run.stderr.contains("x.png"), "{:?}", run.stderr);
    assert_eq!(s.out_entries(), ["x.png"], "only the folder that was there");
    assert!(Path::new(&s.out("x.png")).is_dir());
}

#[test]
fn failing_aov_leaves_no_main_output() {
    let s = Scratch::new("aovfail");
    // x.normal.exr cannot be written (a folder of that name is in the way); x.png must not stay.
    fs::create_dir(s.out("x.normal.exr")).unwrap();
    let run = render_default(&s, &["--width", W, "--height", H, "--aov", "normal"]);
    assert_eq!(run.code, 1, "{run:#?}");
    assert_eq!(run.stderr.lines().count(), 1, "{:?}", run.stderr);
    assert!(run.stderr.starts_with("error: ") && run.stderr.contains("x.normal.exr"), "{:?}", run.stderr);
    assert_eq!(s.out_entries(), ["x.normal.exr"], "no output file may be left behind");
}

#[test]
fn bumpgen_bad_options() {
    let s = Scratch::new("bumpgenbad");
    let out = s.out("g.png");
    assert_one_error(&wrinkle(&["bumpgen", "grid", "-o", &out, "--size", "0"]), 2, &["--size"], &s);
    assert_one_error(&wrinkle(&["bumpgen", "rivets", "-o", &out, "--size", "32", "--count", "5"]), 2, &["--count"], &s);
    assert_one_error(&wrinkle(&["bumpgen", "bricks", "-o", &out, "--size", "32", "--rows", "3"]), 2, &["--rows"], &s);
}

#[test]
fn unparsable_arguments_are_one_line() {
    let s = Scratch::new("clap");
    assert_one_error(&render_default(&s, &["--width", "abc"]), 2, &["--width", "abc"], &s);
    assert_one_error(&render_default(&s, &["--spp"]), 2, &["--spp"], &s);
    assert_one_error(&wrinkle(&["bumpgen", "grid"]), 2, &["--output"], &s);
    assert_one_error(&wrinkle(&["frobnicate"]), 2, &["frobnicate"], &s);
}

// ---------------------------------------------------------------------------------------------
// Texture filters: filters, mipmap, bench-texture, --filter

/// The PSNR of the row of `wrinkle filters --json` whose filter is `name`.
fn json_psnr(stdout: &str, name: &str) -> f64 {
    let line = stdout.lines().find(|l| l.contains(&format!("\"{name}\""))).unwrap();
    line.split("\"psnr_db\": ").nth(1).unwrap().trim_end_matches(['}', ',']).parse().unwrap()
}

#[test]
fn filters_writes_a_labelled_sheet_and_a_table_of_errors() {
    let s = Scratch::new("filters");
    let out = s.out("sheet.png");
    let run =
        wrinkle(&["filters", "-o", &out, "--width", "64", "--height", "48", "--filters", "bilinear,ewa", "--json"]);
    assert_ok(&run);
    // Two filters and the ground truth in one row of three 64 px panels with 4 px gaps; a 20 px label strip.
    assert_eq!(png_header(&out), (3 * 68 + 4, 48 + 20 + 8, 8, 2));
    // The two filters, and the ground truth from other samples (another seed) against the ground truth.
    assert_eq!(run.stdout.matches("\"filter\"").count(), 3, "{}", run.stdout);
    // EWA is much closer to the ground truth than bilinear without MIP maps.
    let psnr = |name: &str| json_psnr(&run.stdout, name);
    assert!(psnr("ewa") > psnr("bilinear") + 3.0, "{}", run.stdout);
    // The truth's noise floor lies far above the best filter's error.
    assert!(psnr("truth, seed 1") > 45.0 && psnr("truth, seed 1") > psnr("ewa") + 10.0, "{}", run.stdout);
    assert_eq!(s.out_entries(), ["sheet.png"]);
}

/// The sheet's printed PSNRs against a ground truth computed here, independently of the renderer: each
/// pixel of a textured floor receding in perspective integrated over its square by 16 x 16 rays in f64,
/// each reading the bilinear checker at its own exact (u,v). Every filter's PSNR as `filters` prints it
/// (against its own 256-sample truth) must agree with the PSNR of the same render against this truth.
#[test]
fn filters_psnrs_agree_with_an_independent_ground_truth() {
    let s = Scratch::new("filters_truth");
    // A 64 x 64 checker of 8-texel checks, two sRGB colours.
    let (n, colours) = (64usize, [[230u8, 40, 40], [30, 60, 200]]);
    let check = |x: usize, y: usize| colours[(x / 8 + y / 8) % 2];
    let bytes: Vec<u8> = (0..n * n).flat_map(|k| check(k % n, k / n)).collect();
    let texture = s.input("checks.png");
    wrinkle::image::io::write_png8(Path::new(&texture), n, n, 3, &bytes).unwrap();
    let scene = s.write_input(
        "floor.toml",
        format!(
            "[camera]\neye = [0.0, 0.6, 3.0]\nlook_at = [0.0, 0.0, 0.0]\nfov_y = 40.0\nbackground = [0.0, 0.0, 0.0]\n\n\
             [[light]]\ntype = \"ambient\"\nintensity = 1.0\n\n[[object]]\nshape = \"patch\"\n\
             corners = [[-1.0, -0.5, 1.0], [1.0, -0.5, 1.0], [1.0, -0.5, -9.0], [-1.0, -0.5, -9.0]]\n\
             material = {{ color = [1.0, 1.0, 1.0], texture = {{ path = \"{}\", repeat = [2, 10] }} }}\n",
            texture.replace('\\', "/")
        ),
    );
    let (w, h) = (96usize, 72usize);
    let filters = ["bilinear", "trilinear", "aniso", "ewa"];
    let run = wrinkle(&[
        "filters",
        &scene,
        "-o",
        &s.out("sheet.png"),
        "--width",
        &w.to_string(),
        "--height",
        &h.to_string(),
        "--filters",
        &filters.join(","),
        "--json",
    ]);
    assert_ok(&run);

    // The truth: the camera's rays (y down), the floor y = -0.5 with u along +x, v away from the eye.
    let (eye, target) = (DVec3::new(0.0, 0.6, 3.0), DVec3::ZERO);
    let fwd = (target - eye).normalize();
    let right = fwd.cross(DVec3::Y).normalize();
    let up = right.cross(fwd);
    let scale = 0.5 * h as f64 / (20f64).to_radians().tan();
    let linear = |c: u8| {
        let c = c as f64 / 255.0;
        if c <= 0.04045 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }
    };
    // Texel (i, j), j counted from the bottom (row n - 1 - j of the image), repeating.
    let texel = |i: i64, j: i64| {
        let (i, j) = (i.rem_euclid(n as i64) as usize, j.rem_euclid(n as i64) as usize);
        check(i, n - 1 - j).map(linear)
    };
    let bilinear = |s: f64, t: f64| {
        let (x, y) = (s * n as f64 - 0.5, t * n as f64 - 0.5);
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let (i, j) = (x0 as i64, y0 as i64);
        let mut c = [0.0; 3];
        for (di, dj, wgt) in
            [(0, 0, (1.0 - fx) * (1.0 - fy)), (1, 0, fx * (1.0 - fy)), (0, 1, (1.0 - fx) * fy), (1, 1, fx * fy)]
        {
            let t = texel(i + di, j + dj);
            for k in 0..3 {
                c[k] += wgt * t[k];
            }
        }
        c
    };
    let k = 16;
    let truth: Vec<[f64; 3]> = (0..w * h)
        .map(|p| {
            let (px, py) = ((p % w) as f64, (p / w) as f64);
            let mut sum = [0.0; 3];
            for q in 0..k * k {
                let (x, y) = (px + ((q % k) as f64 + 0.5) / k as f64, py + ((q / k) as f64 + 0.5) / k as f64);
                let dir = fwd + right * ((x - 0.5 * w as f64) / scale) + up * ((0.5 * h as f64 - y) / scale);
                if dir.y >= 0.0 {
                    continue;
                }
                let hit = eye + dir * ((-0.5 - eye.y) / dir.y);
                let (u, v) = ((hit.x + 1.0) / 2.0, (1.0 - hit.z) / 10.0);
                if !(0.0..=1.0).contains(&u) || !(0.0..=1.0).contains(&v) {
                    continue;
                }
                let c = bilinear(2.0 * u, 10.0 * v);
                for c3 in 0..3 {
                    sum[c3] += c[c3] / (k * k) as f64;
                }
            }
            sum
        })
        .collect();

    let mut scene_data = wrinkle::Scene::load(Path::new(&scene)).unwrap();
    for name in filters {
        scene_data.set_texture_filter(wrinkle::texture::Filter::parse(name).unwrap());
        let options = wrinkle::RenderOptions { width: w, height: h, ..Default::default() };
        let frame = wrinkle::render(&scene_data, &options).unwrap();
        let sum: f64 = frame
            .color
            .iter()
            .zip(&truth)
            .map(|(a, b)| (0..3).map(|c| (a[c] as f64 - b[c]).powi(2)).sum::<f64>() / 3.0)
            .sum();
        let independent = -20.0 * (sum / (w * h) as f64).sqrt().log10();
        let printed = json_psnr(&run.stdout, name);
        eprintln!("{name}: printed {printed:.2} dB, independent {independent:.2} dB");
        assert!(
            (printed - independent).abs() < 0.5,
            "{name}: printed {printed:.2} dB, independent {independent:.2} dB"
        );
    }
}

/// `filters --bump`: the bump filters against the supersampled intensities; MIP filtering the table scores
/// below the anisotropic filters on the grazing grooves, and the truth's noise floor is far above both.
#[test]
fn filters_compares_bump_filters_against_the_supersampled_intensities() {
    let s = Scratch::new("filters_bump");
    let out = s.out("sheet.png");
    let args =
        ["filters", "--bump", "-o", &out, "--width", "96", "--height", "72", "--filters", "none,mip,ewa", "--json"];
    let run = wrinkle(&args);
    assert_ok(&run);
    assert_eq!(run.stdout.matches("\"filter\"").count(), 4, "{}", run.stdout);
    let psnr = |name: &str| json_psnr(&run.stdout, name);
    assert!(psnr("ewa") > psnr("mip") + 1.0, "{}", run.stdout);
    assert!(psnr("truth, seed 1") > 45.0 && psnr("truth, seed 1") > psnr("ewa") + 15.0, "{}", run.stdout);
    let plain = Scratch::new("filters_bump_plain");
    let scene = plain.write_input(
        "plain.toml",
        "[camera]\neye = [0.0, 0.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\n[[light]]\ntype = \"ambient\"\n[[object]]\nshape = \"sphere\"\n",
    );
    let run = wrinkle(&["filters", "--bump", &scene, "-o", &plain.out("sheet.png")]);
    assert_one_error(&run, 2, &["no bump map"], &plain);
}

#[test]
fn filters_rejects_unknown_names() {
    let s = Scratch::new("filters_bad");
    let out = s.out("sheet.png");
    let run = wrinkle(&["filters", "-o", &out, "--filters", "bilinear,fancy"]);
    assert_one_error(&run, 2, &["--filters", "fancy", "ewa"], &s);
}

#[test]
fn mipmap_writes_an_atlas_or_every_level() {
    let s = Scratch::new("mipmap");
    let tex = s.input("tex.png");
    assert_ok(&wrinkle(&["bumpgen", "bricks", "-o", &tex, "--size", "32"]));
    let atlas = s.out("atlas.png");
    let run = wrinkle(&["mipmap", &tex, "-o", &atlas, "--filter", "lanczos"]);
    assert_ok(&run);
    assert!(run.stdout.contains("6 levels"), "{}", run.stdout);
    // 32 wide, the 16-wide level to its right; RGBA.
    assert_eq!(png_header(&atlas), (48, 32, 8, 6));
    let levels = s.out("lv.png");
    assert_ok(&wrinkle(&["mipmap", &tex, "-o", &levels, "--levels", "--linear"]));
    for (k, side) in [32, 16, 8, 4, 2, 1].into_iter().enumerate() {
        assert_eq!(png_header(&s.out(&format!("lv_{k}.png"))), (side, side, 8, 6));
    }
}

#[test]
fn mipmap_of_a_missing_file() {
    let s = Scratch::new("mipmap_missing");
    let run = wrinkle(&["mipmap", &s.input("nope.png"), "-o", &s.out("m.png")]);
    assert_one_error(&run, 2, &["nope.png"], &s);
}

#[test]
fn render_filter_overrides_the_scene_and_unknown_names_fail() {
    let s = Scratch::new("render_filter");
    let tex = s.input("tex.png");
    assert_ok(&wrinkle(&["bumpgen", "grid", "-o", &tex, "--size", "32"]));
    let scene = s.write_input(
        "scene.toml",
        scene_with("shape = \"sphere\"\n\n[object.material]\ntexture = { path = \"tex.png\", repeat = [8, 4] }\nfilter = \"sat\"\n"),
    );
    // The table form has no filter: the one beside it applies.
    assert_ok(&render_scene(&s, &scene, &["--filter", "ewa", "--bump-filter", "aniso"]));
    let bad = Scratch::new("render_filter_bad");
    let run = render_scene(&bad, &scene, &["--filter", "fancy"]);
    assert_eq!(run.code, 2, "{run:#?}");
    assert!(run.stderr.contains("fancy"), "{}", run.stderr);
}

/// `--lod-bias` moves every image texture's level of detail as the scene's `lod_bias` does, overriding it;
/// no bias leaves the frame as it was; out-of-range values fail in one line.
#[test]
fn render_lod_bias_is_the_scenes_lod_bias_and_overrides_it() {
    let s = Scratch::new("render_lod_bias");
    let tex = s.input("tex.png");
    assert_ok(&wrinkle(&["bumpgen", "grid", "-o", &tex, "--size", "64"]));
    let scene = |bias: &str| {
        scene_with(&format!(
            "shape = \"sphere\"\n\n[object.material]\ntexture = {{ path = \"tex.png\", repeat = [8, 4]{bias} }}\n"
        ))
    };
    let (plain, biased) =
        (s.write_input("plain.toml", scene("")), s.write_input("biased.toml", scene(", lod_bias = -1")));
    let frame = |scene: &str, extra: &[&str]| {
        let mut args = vec!["--spp", "4"];
        args.extend_from_slice(extra);
        assert_ok(&render_scene(&s, scene, &args));
        std::fs::read(s.out("x.png")).unwrap()
    };
    let none = frame(&plain, &[]);
    assert_eq!(frame(&plain, &["--lod-bias", "0"]), none, "no bias, the same frame");
    let finer = frame(&plain, &["--lod-bias", "-1"]);
    assert_ne!(finer, none, "--lod-bias -1 must change the frame");
    assert_eq!(frame(&biased, &[]), finer, "the scene's lod_bias = -1");
    assert_eq!(frame(&biased, &["--lod-bias", "0"]), none, "--lod-bias overrides the scene");
    let bad = Scratch::new("render_lod_bias_bad");
    let run = render_scene(&bad, &plain, &["--lod-bias", "7"]);
    assert_eq!(run.code, 2, "{run:#?}");
    assert!(run.stderr.contains("--lod-bias") && run.stderr.contains("-4 to 4"), "{}", run.stderr);
}

/// A short run (10^5 lookups on a 512^2 texture, well under a scheduler tick) reports figures a CPU can
/// reach: a trilinear lookup reads eight texels, so no thread does 150 million a second. Read from the
/// scheduler's statistics (brought up to date at its 4 ms ticks), its CPU time came in whole ticks, often
/// none: rates of 248 M/s and infinite ones.
#[test]
fn bench_texture_short_runs_report_plausible_rates() {
    let run = wrinkle(&[
        "bench-texture",
        "--size",
        "512",
        "--lookups",
        "100000",
        "--rounds",
        "3",
        "--filters",
        "trilinear",
        "--threads",
        "1",
    ]);
    assert_ok(&run);
    let figure = |line: &str, name: &str| -> f64 {
        let field = line.split_whitespace().find_map(|w| w.strip_prefix(&format!("{name}="))).unwrap();
        field.parse().unwrap()
    };
    let lines: Vec<&str> = run.stdout.lines().filter(|l| l.starts_with("filter=trilinear")).collect();
    assert_eq!(lines.len(), 4, "{}", run.stdout);
    for line in lines {
        for (wall, cpu) in
            [("mlookups_per_s_1thread", "mlookups_per_cpu_s_1thread"), ("batch_1thread", "batch_per_cpu_s_1thread")]
        {
            let (wall, cpu) = (figure(line, wall), figure(line, cpu));
            assert!(wall > 0.0 && cpu >= 0.95 * wall && cpu < 150.0, "{line}");
        }
    }
}

#[test]
fn bench_texture_prints_rates() {
    let run = wrinkle(&["bench-texture", "--size", "64", "--lookups", "1000", "--rounds", "1", "--filters", "sat"]);
    assert_ok(&run);
    assert!(run.stdout.contains("pyramid size=64x64"), "{}", run.stdout);
    assert_eq!(run.stdout.matches("filter=sat").count(), 4, "{}", run.stdout);
}

#[test]
fn texture_writes_every_kind_and_format() {
    let s = Scratch::new("texture");
    let list = wrinkle(&["texture", "--list"]);
    assert_ok(&list);
    for kind in ["noise", "fbm", "turbulence", "marble", "wood", "fire", "clouds", "bricks", "checker", "grid"] {
        assert!(list.stdout.contains(kind), "--list names {kind}");
        let out = s.out(&format!("{kind}.png"));
        assert_ok(&wrinkle(&["texture", kind, "-o", &out, "--size", "40x24"]));
        assert_eq!(png_header(&out), (40, 24, 8, 2));
    }
    let out16 = s.out("fbm16.png");
    assert_ok(&wrinkle(&[
        "texture",
        "fbm",
        "-o",
        &out16,
        "--size",
        "32x32",
        "--bits",
        "16",
        "--tileable",
        "--seed",
        "9",
    ]));
    assert_eq!(png_header(&out16), (32, 32, 16, 2));
    let exr = s.out("clouds.exr");
    assert_ok(&wrinkle(&["texture", "clouds", "-o", &exr, "--size", "16x8", "--time", "2"]));
    let (w, h, channels) = read_exr_channels(Path::new(&exr)).unwrap();
    assert_eq!((w, h, channels.len()), (16, 8, 3));
}

/// Large bakes are written a band of rows at a time (64 rows at 16384 wide): the rows meet across band
/// boundaries as they do inside a band, and the 16-bit PNG holds the EXR's values.
#[test]
fn texture_bands_join_seamlessly_and_png_matches_exr() {
    let s = Scratch::new("texture-bands");
    let (exr, png) = (s.out("fbm.exr"), s.out("fbm.png"));
    let size = ["--size", "16384x130", "--seed", "4", "--scale", "64"];
    assert_ok(&wrinkle(&[&["texture", "fbm", "-o", &exr][..], &size].concat()));
    assert_ok(&wrinkle(&[&["texture", "fbm", "-o", &png, "--bits", "16"][..], &size].concat()));
    let (w, h, channels) = read_exr_channels(Path::new(&exr)).unwrap();
    assert_eq!((w, h), (16384, 130));
    let r = &channels.iter().find(|(n, _)| n == "R").unwrap().1;
    let step = |y: usize| (0..w).map(|x| (r[(y + 1) * w + x] - r[y * w + x]).abs()).sum::<f32>() / w as f32;
    let (inside, across) = ((step(61) + step(62) + step(65) + step(66)) / 4.0, step(63));
    assert!(inside > 1e-4, "the rows differ at all: {inside}");
    assert!((across - inside).abs() < 0.25 * inside, "band boundary step {across} vs {inside} inside");
    let grey = wrinkle::image::io::load_grey(Path::new(&png)).unwrap();
    let g = &channels.iter().find(|(n, _)| n == "G").unwrap().1;
    let b = &channels.iter().find(|(n, _)| n == "B").unwrap().1;
    for k in (0..w * h).step_by(997) {
        let luma = 0.2126 * r[k].clamp(0.0, 1.0) + 0.7152 * g[k].clamp(0.0, 1.0) + 0.0722 * b[k].clamp(0.0, 1.0);
        assert!((grey.pixels[k] - luma).abs() < 2e-5, "pixel {k}: PNG {} vs EXR {luma}", grey.pixels[k]);
    }
}

#[test]
fn texture_rejects_bad_requests_in_one_line() {
    let s = Scratch::new("texture-bad");
    let out = s.out("x.png");
    assert_one_error(&wrinkle(&["texture", "plaid", "-o", &out]), 2, &["plaid", "marble"], &s);
    assert_one_error(&wrinkle(&["texture", "fbm", "-o", &out, "--size", "0x5"]), 2, &["--size"], &s);
    assert_one_error(&wrinkle(&["texture", "fbm", "-o", &out, "--size", "big"]), 2, &["--size", "big"], &s);
    assert_one_error(&wrinkle(&["texture", "wood", "-o", &out, "--tileable"]), 2, &["wood", "tile"], &s);
    assert_one_error(&wrinkle(&["texture", "fbm", "-o", &out, "--gain", "2"]), 2, &["gain"], &s);
    assert_one_error(&wrinkle(&["texture", "fbm", "-o", &out, "--bits", "12"]), 2, &["--bits"], &s);
    assert_one_error(&wrinkle(&["texture", "marble", "-o", &out, "--colors", "1,0"]), 2, &["--colors"], &s);
}

#[test]
fn procedural_scene_fields_are_checked() {
    let s = Scratch::new("procedural-scene");
    let bad_pattern =
        s.write_input("a.toml", scene_with("shape = \"sphere\"\nmaterial = { texture = { procedural = \"plaid\" } }"));
    assert_one_error(&render_scene(&s, &bad_pattern, &[]), 2, &["objects[0].material.texture.procedural", "plaid"], &s);
    let bad_octaves = s.write_input(
        "b.toml",
        scene_with("shape = \"sphere\"\n[object.material.bump]\nprocedural = { pattern = \"fbm\", octaves = 99 }"),
    );
    assert_one_error(&render_scene(&s, &bad_octaves, &[]), 2, &["objects[0].material.bump.procedural.octaves"], &s);
    let volume = s.write_input(
        "c.toml",
        format!(
            "{}\n[[volume]]\nradius = 0.5\n[[volume.modulate]]\nkind = \"bias\"\nvalue = 1.5\n",
            scene_with("shape = \"sphere\"")
        ),
    );
    assert_one_error(&render_scene(&s, &volume, &[]), 2, &["volumes[0].modulate[0].value"], &s);
}

#[test]
fn bench_noise_reports_throughput() {
    let run = wrinkle(&["bench-noise", "--points", "20000", "--rounds", "1"]);
    assert_ok(&run);
    assert!(run.stdout.contains("perlin3_mpts=") && run.stdout.contains("fbm6_mpts="), "{}", run.stdout);
}

#[test]
fn mappings_sheet_shows_each_mapping_differently() {
    let s = Scratch::new("mappings");
    let out = s.out("sheet.png");
    let (w, h) = (96usize, 60usize);
    assert_ok(&wrinkle(&["mappings", "-o", &out, "--width", "96", "--height", "60", "--spp", "1"]));
    // 14 panels in rows of 4: 4 columns of 96 + 4 px gaps, 4 rows of 60 px under 20 px labels.
    assert_eq!(png_header(&out), (4 * 100 + 4, 4 * (h as u32 + 24) + 4, 8, 2));
    let sheet = wrinkle::image::io::load_rgba8(Path::new(&out)).unwrap();
    let panel = |k: usize| -> Vec<f64> {
        let (x0, y0) = (4 + (k % 4) * (w + 4), 4 + (k / 4) * (h + 24) + 20);
        (0..w * h).flat_map(|i| sheet.get(x0 + i % w, y0 + i / w)[..3].to_vec()).map(f64::from).collect()
    };
    let panels: Vec<Vec<f64>> = (0..14).map(panel).collect();
    // Each mapping lays the checkerboard its own way: every two panels differ, if only on the teapot
    // (spherical and sphere/normal agree on the sphere), by more than rounding does (cylinder/ISN, the
    // same as cylindrical, differed from it by 0.3 levels).
    for a in 0..14 {
        for b in a + 1..14 {
            let mean =
                panels[a].iter().zip(&panels[b]).map(|(x, y)| (x - y).abs()).sum::<f64>() / panels[a].len() as f64;
            assert!(mean > 1.0, "panels {a} and {b} differ by only {mean:.2} levels");
        }
    }
    assert_eq!(s.out_entries(), ["sheet.png"]);
}

#[test]
fn tessellate_writes_the_scene_as_an_obj_with_shared_positions() {
    let s = Scratch::new("tessellate");
    let scene = s.write_input(
        "sphere.toml",
        "[camera]\neye = [0.0, 0.0, 5.0]\nlook_at = [0.0, 0.0, 0.0]\n\n[[object]]\nshape = \"sphere\"\nradius = 2.0\n\
         transform = { translate = [1.0, 0.0, 0.0] }\n",
    );
    let out = s.out("sphere.obj");
    assert_ok(&wrinkle(&["tessellate", &scene, "-o", &out, "--segments", "8"]));
    let obj = fs::read_to_string(&out).unwrap();
    let lines = |prefix: &'static str| obj.lines().filter(move |l| l.starts_with(prefix));
    // 9 x 9 grid vertices, each with its (u,v) and normal; positions shared across the seam (9) and at
    // each pole (8 + 8 collapse onto 2): 81 - 9 - 14 = 58.
    assert_eq!((lines("v ").count(), lines("vt ").count(), lines("vn ").count()), (58, 81, 81));
    assert_eq!(lines("f ").count(), 2 * 8 * 8);
    for v in lines("v ") {
        let p: Vec<f64> = v[2..].split(' ').map(|x| x.parse().unwrap()).collect();
        let r = ((p[0] - 1.0).powi(2) + p[1].powi(2) + p[2].powi(2)).sqrt();
        assert!((r - 2.0).abs() < 1e-5, "{v} is off the sphere");
    }
    for n in lines("vn ") {
        let n: Vec<f64> = n[3..].split(' ').map(|x| x.parse().unwrap()).collect();
        assert!(((n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt() - 1.0).abs() < 1e-5);
    }
    fs::remove_file(&out).unwrap();
    assert_one_error(&wrinkle(&["tessellate", &scene, "-o", &out, "--segments", "0"]), 2, &["segments", "0"], &s);
    assert_one_error(&wrinkle(&["tessellate", &scene, "-o", &s.out("m.png")]), 2, &["m.png"], &s);
}

/// `wrinkle envmap`: a latlong map of a known function of the direction, to a cube cross and back: the
/// cross has the cube's shape and its face centres hold the function at the six axes; the round trip
/// keeps the map within 1%.
#[test]
fn envmap_converts_between_layouts() {
    use wrinkle::envmap::Layout;
    let s = Scratch::new("envmap");
    let f = |d: glam::Vec3| [0.5 + 0.4 * d.x, 0.5 + 0.4 * d.y, 0.5 + 0.4 * d.z];
    let (w, h) = (256, 128);
    let mut channels = vec![Vec::new(); 3];
    for y in 0..h {
        for x in 0..w {
            let d =
                Layout::LatLong.direction(0, (x as f32 + 0.5) / w as f32, 1.0 - (y as f32 + 0.5) / h as f32).unwrap();
            for (c, v) in channels.iter_mut().zip(f(d)) {
                c.push(v);
            }
        }
    }
    let input = s.input("sky.exr");
    wrinkle::image::io::write_exr(
        Path::new(&input),
        w,
        h,
        &[("R", &channels[0]), ("G", &channels[1]), ("B", &channels[2])],
    )
    .unwrap();
    let cross = s.out("cross.exr");
    let run = wrinkle(&["envmap", &input, "-o", &cross, "--to", "cube", "--size", "32"]);
    assert_ok(&run);
    assert!(run.stdout.contains("latlong -> cube 128x96"), "{}", run.stdout);
    let (cw, ch, cube) = read_exr_channels(Path::new(&cross)).unwrap();
    assert_eq!((cw, ch), (128, 96));
    let named =
        |channels: &[(String, Vec<f32>)], name: &str| channels.iter().find(|(n, _)| n == name).unwrap().1.clone();
    let cube = [named(&cube, "R"), named(&cube, "G"), named(&cube, "B")];
    // Face centres in the cross (+X right of +Z, +Y above it, -Z at the end of the row).
    let centre = |col: usize, row: usize| {
        let (x, y) = (col * 32 + 16, row * 32 + 16);
        // The mean of the four texels around the face's centre.
        let at = |c: usize| {
            [(x - 1, y - 1), (x, y - 1), (x - 1, y), (x, y)].iter().map(|&(i, j)| cube[c][j * cw + i]).sum::<f32>()
                / 4.0
        };
        [at(0), at(1), at(2)]
    };
    for ((col, row), axis) in
        [((2, 1), glam::Vec3::X), ((1, 0), glam::Vec3::Y), ((1, 1), glam::Vec3::Z), ((3, 1), -glam::Vec3::Z)]
    {
        let (got, want) = (centre(col, row), f(axis));
        for k in 0..3 {
            assert!((got[k] - want[k]).abs() < 0.01, "face at ({col}, {row}): {got:?} vs {want:?}");
        }
    }
    let back = s.out("back.exr");
    assert_ok(&wrinkle(&["envmap", &cross, "-o", &back, "--to", "latlong", "--size", "128"]));
    let (_, _, round) = read_exr_channels(Path::new(&back)).unwrap();
    let worst = named(&round, "R").iter().zip(&channels[0]).map(|(a, b)| (a - b).abs()).fold(0.0, f32::max);
    assert!(worst < 0.01, "round trip: worst {worst}");
    let bad = Scratch::new("envmap_bad");
    let run = wrinkle(&["envmap", &input, "-o", &bad.out("x.png"), "--to", "cube", "--size", "0"]);
    assert_one_error(&run, 2, &["--size 0"], &bad);
}

/// `--background transparent`: an RGBA PNG whose alpha is the coverage and whose colour is straight (an
/// edge pixel keeps the surface's colour, not a darker blend), and an EXR with a premultiplied A.
#[test]
fn transparent_background_writes_alpha() {
    let s = Scratch::new("transparent");
    let scene = s.write_input(
        "scene.toml",
        "[camera]\neye = [0.0, 0.0, 5.0]\nlook_at = [0.0, 0.0, 0.0]\nprojection = \"orthographic\"\nheight = 2.0\n\
         background = [0.0, 1.0, 0.0]\n\n[[light]]\ntype = \"ambient\"\n\n[[object]]\nshape = \"sphere\"\nradius = 0.7\n\
         [object.material]\ncolor = [0.8, 0.4, 0.1]\n",
    );
    let png = s.out("x.png");
    assert_ok(&wrinkle(&[
        "render",
        &scene,
        "-o",
        &png,
        "--width",
        "32",
        "--height",
        "32",
        "--spp",
        "16",
        "--background",
        "transparent",
    ]));
    assert_eq!(png_header(&png), (32, 32, 8, 6));
    let rgba = image::open(&png).unwrap().to_rgba8();
    let (corner, centre) = (rgba.get_pixel(0, 0).0, rgba.get_pixel(16, 16).0);
    assert_eq!(corner[3], 0, "nothing at the corner: {corner:?}");
    assert_eq!(centre[3], 255);
    let edge = rgba.pixels().find(|p| p[3] > 40 && p[3] < 215).expect("an edge pixel").0;
    for c in 0..3 {
        assert!((i32::from(edge[c]) - i32::from(centre[c])).abs() <= 2, "straight alpha: {edge:?} vs {centre:?}");
    }
    let exr = s.out("x.exr");
    assert_ok(&wrinkle(&[
        "render",
        &scene,
        "-o",
        &exr,
        "--width",
        "32",
        "--height",
        "32",
        "--spp",
        "16",
        "--background",
        "transparent",
    ]));
    let (_, _, channels) = read_exr_channels(Path::new(&exr)).unwrap();
    let named = |name: &str| channels.iter().find(|(n, _)| n == name).unwrap().1.clone();
    let (r, a) = (named("R"), named("A"));
    assert_eq!((a[0], r[0]), (0.0, 0.0));
    let k = a.iter().position(|&x| x > 0.2 && x < 0.8).expect("an edge pixel");
    assert!((r[k] - 0.8 * a[k]).abs() < 1e-5, "premultiplied: R {} at A {}", r[k], a[k]);
}

/// `--transparency`: two translucent squares crossing at x = 0, seen head on over black. `exact` puts each
/// pixel's nearer square in front on both sides of the crossing; `sorted` (the default) one square in front
/// everywhere, so the two differ on one side only; a bad value is one error naming the choices.
#[test]
fn transparency_orders_crossing_panes() {
    let s = Scratch::new("transparency");
    let square = |corners: &str, colour: &str, opacity: f32| {
        format!(
            "[[object]]\nshape = \"patch\"\ncorners = {corners}\n[object.material]\ncolor = [0.0, 0.0, 0.0]\n\
             specular = 0.0\nemission = {colour}\nalpha_mode = \"blend\"\nopacity = {opacity}\n\n"
        )
    };
    let scene = s.write_input(
        "scene.toml",
        format!(
            "[camera]\neye = [0.0, 0.0, 5.0]\nlook_at = [0.0, 0.0, 0.0]\nprojection = \"orthographic\"\nheight = 4.0\n\
             background = [0.0, 0.0, 0.0]\n\n{}{}",
            square("[[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]]", "[1.0, 0.0, 0.0]", 0.3),
            square(
                "[[-1.0, -1.0, -0.5], [1.0, -1.0, 0.5], [1.0, 1.0, 0.5], [-1.0, 1.0, -0.5]]",
                "[0.0, 1.0, 0.0]",
                0.6
            ),
        ),
    );
    let render = |mode: &str| {
        let out = s.out(&format!("{mode}.png"));
        assert_ok(&wrinkle(&["render", &scene, "-o", &out, "--width", "32", "--height", "32", "--transparency", mode]));
        let rgb = image::open(&out).unwrap().to_rgb8();
        (rgb.get_pixel(12, 16).0, rgb.get_pixel(20, 16).0)
    };
    // sRGB bytes of linear (R, G): left red 0.3 over green 0.6 x 0.7, right green 0.6 over red 0.3 x 0.4.
    let byte =
        |v: f32| (255.0 * if v <= 0.0031308 { 12.92 * v } else { 1.055 * v.powf(1.0 / 2.4) - 0.055 }).round() as i32;
    let near =
        |p: [u8; 3], r: f32, g: f32| (i32::from(p[0]) - byte(r)).abs() <= 1 && (i32::from(p[1]) - byte(g)).abs() <= 1;
    let (left, right) = render("exact");
    assert!(near(left, 0.3, 0.42) && near(right, 0.12, 0.6), "exact: {left:?} {right:?}");
    let (left, right) = render("sorted");
    assert!(near(left, 0.3, 0.42) != near(right, 0.12, 0.6), "sorted: {left:?} {right:?}");
    let bad = Scratch::new("transparency_bad");
    let run = wrinkle(&["render", &scene, "-o", &bad.out("x.png"), "--transparency", "painter"]);
    assert_one_error(&run, 2, &["--transparency", "sorted", "exact"], &bad);
}

/// Where stderr is not a terminal, a long render logs its progress as lines (here one per band:
/// WRINKLE_PROGRESS_SECONDS=0), rising to 100% and closed by a "done" line; a short one writes none.
#[test]
fn progress_is_logged_as_lines_where_stderr_is_not_a_terminal() {
    let s = Scratch::new("progress_lines");
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/fractal_egg.toml");
    let out = s.out("egg.png");
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_wrinkle"))
        .args(["render", &path_arg(&scene), "-o", &out, "--width", "128", "--height", "256"])
        .env("WRINKLE_PROGRESS_SECONDS", "0")
        .output()
        .unwrap();
    assert!(run.status.success());
    let stderr = String::from_utf8_lossy(&run.stderr);
    let lines: Vec<&str> = stderr.lines().collect();
    assert!(lines.len() >= 3, "{stderr}");
    assert!(lines.iter().all(|l| l.starts_with("render: ")), "{stderr}");
    let percents: Vec<u32> =
        lines.iter().filter_map(|l| l.strip_prefix("render: ")?.split('%').next()?.parse().ok()).collect();
    assert!(percents.windows(2).all(|p| p[0] <= p[1]) && percents.last() == Some(&100), "{stderr}");
    assert!(lines.last().unwrap().starts_with("render: done, "), "{stderr}");
    // The same render is far shorter than the default five seconds between lines: nothing is written.
    let quiet = wrinkle(&["render", &path_arg(&scene), "-o", &out, "--width", "128", "--height", "256"]);
    assert_ok(&quiet);
    assert_eq!(quiet.stderr, "");
}

/// `-o -` writes the PNG that `-o FILE` writes to the standard output, and refuses what one PNG cannot hold.
#[test]
fn a_frame_goes_to_the_standard_output() {
    let s = Scratch::new("stdout_png");
    let file = s.out("cover.png");
    assert_ok(&wrinkle(&["render", "-o", &file, "--width", "64", "--height", "36"]));
    let piped = std::process::Command::new(env!("CARGO_BIN_EXE_wrinkle"))
        .args(["render", "-o", "-", "--width", "64", "--height", "36"])
        .output()
        .unwrap();
    assert!(piped.status.success(), "{}", String::from_utf8_lossy(&piped.stderr));
    assert_eq!(piped.stdout, fs::read(&file).unwrap());
    for extra in [&["--aov", "depth"][..], &["--frames", "2", "--turntable"][..]] {
        let run = wrinkle(&[&["render", "-o", "-", "--width", "8", "--height", "8"][..], extra].concat());
        assert_eq!(run.code, 2, "{run:#?}");
        assert!(run.stderr.starts_with("error: -o -: the standard output holds one PNG"), "{run:#?}");
        assert!(run.stdout.is_empty());
    }
}

/// `--crop` renders the whole frame's pixels (and AOVs) of the rectangle, into an image of its size.
#[test]
fn a_crop_is_the_whole_frames_pixels() {
    let s = Scratch::new("crop");
    let (whole, part) = (s.out("whole.png"), s.out("part.png"));
    let size = ["--width", "200", "--height", "120", "--spp", "4", "--aov", "depth"];
    assert_ok(&wrinkle(&[&["render", "-o", &whole][..], &size].concat()));
    assert_ok(&wrinkle(&[&["render", "-o", &part, "--crop", "30,70,190,119"][..], &size].concat()));
    let (w, p) = (
        wrinkle::image::io::load_rgba8(Path::new(&whole)).unwrap(),
        wrinkle::image::io::load_rgba8(Path::new(&part)).unwrap(),
    );
    assert_eq!((p.width, p.height), (160, 49));
    for y in 0..49 {
        assert_eq!(p.pixels[y * 160..(y + 1) * 160], w.pixels[(y + 70) * 200 + 30..(y + 70) * 200 + 190], "row {y}");
    }
    let depth = |f: &str| read_exr_channels(Path::new(&f.replace(".png", ".depth.exr"))).unwrap().2[0].1.clone();
    let (dw, dp) = (depth(&whole), depth(&part));
    for y in 0..49 {
        for x in 0..160 {
            assert_eq!(dp[y * 160 + x].to_bits(), dw[(y + 70) * 200 + 30 + x].to_bits());
        }
    }
    let run = wrinkle(&["render", "-o", &part, "--crop", "0,0,300,10", "--width", "200", "--height", "120"]);
    assert_one_error(&run, 2, &["--crop must be X0,Y0,X1,Y1", "300"], &Scratch::new("crop_bad"));
}

/// A crop's EXRs carry its place in the frame: the data window is the crop, the display window the frame
/// (the OpenEXR header's dataWindow and displayWindow, as the exr crate reads them).
#[test]
fn a_cropped_exr_carries_its_data_window() {
    let s = Scratch::new("crop_exr");
    let (whole, part) = (s.out("whole.exr"), s.out("part.exr"));
    let size = ["--width", "120", "--height", "80", "--aov", "primitive"];
    assert_ok(&wrinkle(&[&["render", "-o", &whole][..], &size].concat()));
    assert_ok(&wrinkle(&[&["render", "-o", &part, "--crop", "20,10,100,45"][..], &size].concat()));
    let placed = |f: &str| wrinkle::image::io::read_exr_placement(Path::new(f)).unwrap();
    let expected = Placement { x0: 20, y0: 10, width: 80, height: 35, full_width: 120, full_height: 80 };
    assert_eq!(placed(&part), expected);
    assert_eq!(placed(&part.replace(".exr", ".primitive.exr")), expected);
    assert_eq!(placed(&whole), Placement::whole(120, 80));
    let (_, _, w) = read_exr_channels(Path::new(&whole)).unwrap();
    let (_, _, p) = read_exr_channels(Path::new(&part)).unwrap();
    for ((name, wc), (_, pc)) in w.iter().zip(&p) {
        for y in 0..35 {
            for x in 0..80 {
                assert_eq!(pc[y * 80 + x].to_bits(), wc[(y + 10) * 120 + 20 + x].to_bits(), "{name} at ({x}, {y})");
            }
        }
    }
}

/// `--tile N` renders the frame in parts and assembles them: the same pixels and AOVs as the whole frame,
/// for a PNG streamed band by band, an EXR with AOVs and a transparent PNG; and a frame above the pixel
/// limit of one render renders in tiles.
#[test]
fn a_frame_in_tiles_is_the_whole_frame() {
    let s = Scratch::new("tiles");
    let size = ["--width", "150", "--height", "100", "--spp", "4"];
    for (name, extra) in [
        ("plain.png", &[][..]),
        ("aovs.exr", &["--aov", "depth,uv"][..]),
        ("clear.png", &["--background", "transparent"][..]),
        // Samples over a filter reach three pixels past their own, each pixel with its own scramble.
        ("lanczos.png", &["--sampler", "sobol", "--pixel-filter", "lanczos", "--background", "transparent"][..]),
    ] {
        let (whole, tiled) = (s.out(&format!("whole_{name}")), s.out(&format!("tiled_{name}")));
        assert_ok(&wrinkle(&[&["render", "-o", &whole][..], &size, extra].concat()));
        // 64 does not divide 150 or 100: the last tiles of each row and column are narrower.
        assert_ok(&wrinkle(&[&["render", "-o", &tiled, "--tile", "64"][..], &size, extra].concat()));
        if name.ends_with(".png") {
            let (a, b) = (
                wrinkle::image::io::load_rgba8(Path::new(&whole)).unwrap(),
                wrinkle::image::io::load_rgba8(Path::new(&tiled)).unwrap(),
            );
            assert_eq!((b.width, b.height), (150, 100));
            assert!(a.pixels == b.pixels, "{name}: the tiled frame differs");
        } else {
            for file in [whole.clone(), whole.replace(".exr", ".depth.exr"), whole.replace(".exr", ".uv.exr")] {
                let a = read_exr_channels(Path::new(&file)).unwrap();
                let b = read_exr_channels(Path::new(&file.replace("whole_", "tiled_"))).unwrap();
                assert_eq!((a.0, a.1), (b.0, b.1));
                for ((n, x), (_, y)) in a.2.iter().zip(&b.2) {
                    assert!(
                        x.iter().zip(y).all(|(p, q)| p.to_bits() == q.to_bits()),
                        "{file} {n}: the tiled frame differs"
                    );
                }
            }
        }
    }
    // 15,000 pixels against a limit of 10,000 for one render: refused whole, rendered in 64 x 64 tiles.
    let (whole, tiled) = (s.out("big_whole.png"), s.out("big_tiled.png"));
    let limit = ["--limit", "frame-pixels=10000"];
    let run = wrinkle(&[&limit[..], &["render", "-o", &whole], &size].concat());
    assert_one_error(&run, 2, &["150x100", "10000 pixel limit"], &Scratch::new("tiles_big"));
    assert!(!Path::new(&whole).exists(), "a refused render leaves no file");
    assert_ok(&wrinkle(&[&limit[..], &["render", "-o", &tiled, "--tile", "64"], &size].concat()));
    let a = wrinkle::image::io::load_rgba8(Path::new(&s.out("tiled_plain.png"))).unwrap();
    let b = wrinkle::image::io::load_rgba8(Path::new(&tiled)).unwrap();
    assert!(a.pixels == b.pixels, "the frame above the limit differs");
    let run = wrinkle(&["render", "-o", &tiled, "--tile", "64", "--crop", "0,0,10,10"]);
    assert_one_error(&run, 2, &["--tile", "--crop"], &Scratch::new("tiles_crop"));
    let run = wrinkle(&["render", "-o", &tiled, "--tile", "8"]);
    assert_one_error(&run, 2, &["--tile must be between 16 and 65536, got 8"], &Scratch::new("tiles_small"));
}
