//! Issue 19: scenes that hung the renderer or were read wrongly. EWA on a texture repeated 1e5 times never
//! finished; fields of another variant (a lit volume's `emission`) were accepted silently; an empty file
//! name said ": no such file"; and errors echoed a bad value whole, however long.

use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::{Duration, Instant};
use wrinkle::{render, RenderOptions, Scene};

fn scenes() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

const CAMERA: &str = "[camera]\neye = [0.0, 0.8, 4.2]\nlook_at = [0.0, 0.0, 0.0]\nfov_y = 38.0\n\n\
                      [[light]]\ntype = \"directional\"\ndirection = [0.6, -0.6, -0.55]\n\n";

/// The error that loading `body` after a camera and a light gives, as the command line prints it.
fn error_of(body: &str) -> String {
    match Scene::parse(&format!("{CAMERA}{body}"), &scenes()) {
        Ok(_) => panic!("parsed: {body}"),
        Err(e) => e.to_string(),
    }
}

fn parses(body: &str) {
    if let Err(e) = Scene::parse(&format!("{CAMERA}{body}"), &scenes()) {
        panic!("{body}: {e}");
    }
}

/// A sphere whose colour texture and bump table repeat 1e5 times across it, filtered by `filter`.
fn repeated_sphere(filter: &str) -> String {
    format!(
        "{CAMERA}[[object]]\nshape = \"sphere\"\nradius = 1.2\n\n[object.material]\n\
         texture = {{ path = \"tiles_color.png\", repeat = [1e5, 1e5], filter = \"{filter}\" }}\n\n\
         [object.material.bump]\ngenerator = {{ kind = \"grid\", size = 64 }}\nrepeat = [1e5, 1e5]\n\
         filter = \"{filter}\"\nscale = 0.01\n"
    )
}

/// The frame of `scene` at 32 x 24, and how long it took; a failure if it takes longer than `limit`.
fn render_within(scene: String, limit: Duration) -> (Vec<[f32; 3]>, Duration) {
    let (send, receive) = mpsc::channel();
    // On a thread, so that a render that never ends fails the test instead of hanging it.
    std::thread::spawn(move || {
        let scene = Scene::parse(&scene, &scenes()).unwrap();
        let start = Instant::now();
        let frame = render(&scene, &RenderOptions { width: 32, height: 24, ..RenderOptions::default() }).unwrap();
        send.send((frame.color, start.elapsed())).unwrap();
    });
    receive.recv_timeout(limit).unwrap_or_else(|_| panic!("the frame took longer than {limit:?}"))
}

/// Every pixel's footprint covers thousands of periods, so every MIP filter reads the texture's mean (the
/// 1 x 1 level) and the bump table's flat mean: EWA renders the trilinear frame, as fast.
#[test]
fn ewa_on_a_texture_repeated_1e5_times_renders_the_mean_quickly() {
    let (ewa, took) = render_within(repeated_sphere("ewa"), Duration::from_secs(5));
    let (trilinear, _) = render_within(repeated_sphere("trilinear"), Duration::from_secs(5));
    eprintln!("EWA, 1e5 repeats, 32 x 24: {took:?}");
    let lit = ewa.iter().filter(|c| c.iter().any(|&x| x > 0.0)).count();
    assert!(lit > 100, "only {lit} pixels show the sphere");
    let worst =
        ewa.iter().zip(&trilinear).flat_map(|(a, b)| (0..3).map(move |c| (a[c] - b[c]).abs())).fold(0.0, f32::max);
    assert!(worst < 1e-3, "EWA differs from trilinear by {worst}");
}

#[test]
fn volume_fields_of_the_other_shading_are_errors() {
    let volume = "[[volume]]\nradius = 1.0\n";
    for (fields, want) in [
        ("emission = 3.0", "volumes[0].emission: applies to shading = \"emissive\" only"),
        ("shading = \"lit\"\ncolors = [[1.0, 0.5, 0.0]]", "volumes[0].colors: applies to shading = \"emissive\" only"),
        ("shading = \"emissive\"\ncolor = [1.0, 1.0, 1.0]", "volumes[0].color: applies to shading = \"lit\" only"),
    ] {
        assert_eq!(error_of(&format!("{volume}{fields}\n")), want);
    }
    let modulated = |m: &str| error_of(&format!("{volume}\n[[volume.modulate]]\n{m}\n"));
    assert_eq!(
        modulated("kind = \"noise\"\noctaves = 4"),
        "volumes[0].modulate[0].octaves: not a field of kind \"noise\" (it has: amplitude, frequency, seed, drift)"
    );
    assert_eq!(
        modulated("kind = \"bias\"\nvalue = 0.3\namplitude = 0.5"),
        "volumes[0].modulate[0].amplitude: not a field of kind \"bias\" (it has: value)"
    );
    // An amplitude far beyond H's [0, 1] only pushed the volume's bound out: billions of march steps a ray.
    let amplitude = modulated("kind = \"turbulence\"\namplitude = -3e9");
    assert!(amplitude.starts_with("volumes[0].modulate[0].amplitude: "), "{amplitude}");
    assert!(amplitude.contains("between -16 and 16"), "{amplitude}");
    // What each one does take still parses.
    parses(&format!("{volume}shading = \"emissive\"\nemission = 3.0\ncolors = [[1.0, 0.5, 0.0]]\n"));
    parses(&format!("{volume}color = [1.0, 1.0, 1.0]\n[[volume.modulate]]\nkind = \"fbm\"\noctaves = 4\n"));
}

/// The same pattern elsewhere in the format: pattern parameters of another pattern, a procedural bump's
/// table fields, a filter beside a procedural texture, a border colour without the border wrap.
#[test]
fn fields_of_another_variant_are_errors_everywhere() {
    let object = |material: &str| format!("[[object]]\nshape = \"sphere\"\nmaterial = {material}\n");
    for (material, want) in [
        (
            "{ texture = { procedural = \"marble\", rings = 8 } }",
            "objects[0].material.texture.rings: not a field of pattern \"marble\" (it has: space, scale, colors, \
             seed, variant, octaves, lacunarity, gain, strength)",
        ),
        (
            "{ texture = { procedural = \"checker\", octaves = 3 } }",
            "objects[0].material.texture.octaves: not a field of pattern \"checker\" (it has: space, scale, colors)",
        ),
        (
            "{ texture = { procedural = \"marble\" }, filter = \"ewa\" }",
            "objects[0].material.filter: applies to image textures only, not to a procedural one",
        ),
        (
            "{ texture = { path = \"tiles_color.png\", border = [1, 0, 0] } }",
            "objects[0].material.texture.border: applies to wrap = \"border\" only",
        ),
        (
            "{ bump = { procedural = { pattern = \"fbm\", colors = [[1, 1, 1]] } } }",
            "objects[0].material.bump.procedural.colors: applies to textures only (a bump reads the pattern's value)",
        ),
        (
            "{ bump = { procedural = { pattern = \"fbm\" }, filter = \"ewa\" } }",
            "objects[0].material.bump.filter: a procedural bump filters its own octaves: only \"lean\" or \"toksvig\" \
             apply, got \"ewa\"",
        ),
        (
            "{ bump = { generator = { kind = \"grid\" }, filter = \"lean:fancy\" } }",
            "objects[0].material.bump.filter: expected one of none, mip, nearest, bilinear, bicubic, bspline, gaussian, \
             lanczos, mip-nearest, trilinear, ripmap, sat, aniso, ewa, reference, catmull-rom, lean, toksvig, \
             lean:FILTER, toksvig:FILTER, got \"lean:fancy\"",
        ),
        (
            "{ displacement = { generator = { kind = \"grid\" }, filter = \"lean\" } }",
            "objects[0].material.displacement.filter: LEAN and Toksvig filter bumps, not displacements",
        ),
        (
            "{ texture = { path = \"tiles_color.png\", levels = \"tiles_color.png\" } }",
            "objects[0].material.texture.levels: expected a list of file names (level 1 first), got \"tiles_color.png\"",
        ),
        (
            "{ bump = { procedural = { pattern = \"fbm\" }, interp = \"nearest\" } }",
            "objects[0].material.bump.interp: applies to bump tables (map or generator) only",
        ),
        (
            "{ bump = { procedural = { pattern = \"fbm\" }, repeat = [4, 4] } }",
            "objects[0].material.bump.repeat: applies to tables and space = \"uv\" patterns only",
        ),
    ] {
        assert_eq!(error_of(&object(material)), want, "{material}");
    }
    parses(&object("{ bump = { procedural = { pattern = \"fbm\", space = \"uv\" }, repeat = [4, 4] } }"));
    parses(&object("{ bump = { procedural = { pattern = \"fbm\" }, filter = \"toksvig\" } }"));
    parses(&object("{ texture = { procedural = \"wood\", rings = 8, strength = 0.2, seed = 3 } }"));
}

#[test]
fn empty_file_names_are_errors_naming_the_field() {
    let object = |fields: &str| format!("[[object]]\n{fields}\n");
    for (fields, want) in [
        ("shape = \"sphere\"\nmaterial = { texture = \"\" }", "objects[0].material.texture"),
        ("shape = \"sphere\"\nmaterial = { texture = { path = \"\" } }", "objects[0].material.texture.path"),
        ("shape = \"sphere\"\nmaterial = { bump = { map = \"\" } }", "objects[0].material.bump.map"),
        ("shape = \"sphere\"\nmaterial = { normal_map = \"\" }", "objects[0].material.normal_map"),
        ("shape = \"sphere\"\nmaterial = { specular_map = \"\" }", "objects[0].material.specular_map"),
        ("shape = \"mesh\"\nfile = \"\"", "objects[0].file"),
    ] {
        assert_eq!(error_of(&object(fields)), format!("{want}: empty file name"));
    }
}

/// 50 MB of `x`, as a value or a key.
fn long() -> String {
    "x".repeat(50 << 20)
}

/// The message is one line, short, and shows the value's start and its length.
fn shortened(message: &str, what: &str) {
    assert!(message.len() < 400, "{what}: {} characters: {:.200}", message.len(), message);
    assert!(!message.contains('\n'), "{what}: {message}");
    assert!(message.contains(&format!("\"{}…\" (52428800 characters)", "x".repeat(60))), "{what}: {message}");
}

#[test]
fn errors_echo_at_most_sixty_characters_of_a_value() {
    let x = long();
    let started = Instant::now();
    shortened(&error_of(&format!("[[object]]\nshape = \"{x}\"\n")), "a shape");
    shortened(&error_of(&format!("[[light]]\ntype = \"{x}\"\n")), "a light type");
    shortened(&error_of(&format!("[[object]]\nshape = \"sphere\"\n{x} = 1\n")), "an unknown key");
    shortened(&error_of(&format!("[[object]]\nshape = \"sphere\"\nradius = \"{x}\"\n")), "a string for a number");
    let interp = format!("[[object]]\nshape = \"sphere\"\ninterp = \"{x}\"\n");
    shortened(&error_of(&interp), "a choice");
    let texture = format!("[[object]]\nshape = \"sphere\"\nmaterial = {{ texture = \"{x}\" }}\n");
    shortened(&error_of(&texture), "a file name");
    let wrap =
        format!("[[object]]\nshape = \"sphere\"\nmaterial = {{ texture = {{ path = \"t.png\", wrap = \"{x}\" }} }}\n");
    shortened(&error_of(&wrap), "a wrap mode");
    // Parsing and checking 50 MB takes a fraction of a second per scene, not the echo's megabytes.
    assert!(started.elapsed() < Duration::from_secs(30), "{:?}", started.elapsed());
    // Newlines and quotes are escaped, so the message stays one line.
    assert_eq!(
        error_of("[[object]]\nshape = \"cube\\nor \\\"box\\\"\"\n"),
        "objects[0].shape: unknown shape \"cube\\nor \\\"box\\\"\" (expected one of sphere, cylinder, torus, patch, \
         bicubic, box, mesh, billboard)"
    );
    assert_eq!(
        error_of("[[object]]\nshape = \"sphere\"\n\"rad\\nius\" = 1\n"),
        "objects[0].\"rad\\nius\": unknown field (expected one of: shape, transform, material, file, two_sided, \
         interp, radius, height, major_radius, minor_radius, corners, uv_corners, points, size, width, align, axis)"
    );
}

/// A TOML syntax error in a 50 MB file: one short line with the position, and a key the parser quotes
/// cut like an echoed value.
#[test]
fn syntax_errors_in_huge_files_are_one_short_line() {
    let x = long();
    let file = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("huge-{}.toml", std::process::id()));
    for (text, want) in [
        (format!("{CAMERA}[[object]]\nshape = \"{x}\" junk\n"), "column 52428812: expected newline, `#`".into()),
        (format!("{CAMERA}[[object]]\nshape = \"{x}\n"), "column 52428810: invalid basic string".into()),
        (
            format!("{CAMERA}{x} = 1\n{x} = 2\n"),
            format!("column 1: duplicate key `{}…` (52428800 characters) in table `light`", &x[..60]),
        ),
    ] {
        std::fs::write(&file, text).unwrap();
        let message = Scene::load(&file).err().expect("a syntax error").to_string();
        assert_eq!(message, format!("{}: malformed TOML at line 11, {want}", file.display()));
    }
    std::fs::remove_file(&file).unwrap();
}

/// Billboards, environments and shadows: what does not apply, or cannot be, is named.
#[test]
fn billboard_and_environment_mistakes_are_named() {
    for (body, want) in [
        (
            "[[object]]\nshape = \"billboard\"\ntransform = { rotate = [0.0, 30.0, 0.0] }",
            "objects[0].transform: a billboard turns towards the camera and takes its size from width and height: give it only translate",
        ),
        ("[[object]]\nshape = \"billboard\"\naxis = [0.0, 0.0, 0.0]\nalign = \"axis\"", "objects[0].axis: must be a direction, not [0, 0, 0]"),
        ("[[object]]\nshape = \"billboard\"\naxis = [0.0, 1.0, 0.0]", "objects[0].axis: only for align = \"world\" or \"axis\""),
        ("[[object]]\nshape = \"billboard\"\nradius = 2.0", "objects[0].radius: not a field of shape \"billboard\" (it has: width, height, align, axis)"),
        ("[[object]]\nshape = \"sphere\"\nalign = \"axis\"", "objects[0].align: not a field of shape \"sphere\""),
        ("[[light]]\ntype = \"environment\"", "lights[1].type: \"environment\" lights the scene with its [environment] map: add one"),
        ("[environment]\nlayout = \"latlong\"", "environment.map: missing"),
        ("[environment]\nmap = \"maps/sky.hdr\"\nintensity = -1.0", "environment.intensity"),
        ("[[object]]\nshape = \"sphere\"\nmaterial = { chrome = { blur = 0.5 } }", "objects[0].material.chrome.blur"),
        ("[[light]]\ntype = \"ambient\"\nshadow = false", "lights[1].shadow: not a field of lights of type \"ambient\""),
        ("[[light]]\ntype = \"point\"\nposition = [0.0, 2.0, 0.0]\nshadow = \"yes\"", "lights[1].shadow: expected true or false, got"),
        ("[[light]]\ntype = \"point\"\nposition = [0.0, 2.0, 0.0]\nshadow_size = 8", "lights[1].shadow_size: expected an integer from 16 to 8192, got 8"),
        ("[[light]]\ntype = \"point\"\nposition = [0.0, 2.0, 0.0]\nshadow_size = 1e9", "lights[1].shadow_size: expected an integer from 16 to 8192"),
        ("[[light]]\ntype = \"point\"\nposition = [0.0, 2.0, 0.0]\nshadow_bias = -1.0", "lights[1].shadow_bias: expected a bias scale from 0 to 100"),
        ("[[light]]\ntype = \"point\"\nposition = [0.0, 2.0, 0.0]\nshadow_bias = nan", "lights[1].shadow_bias: expected a finite number, got NaN"),
    ] {
        let got = error_of(body);
        assert!(got.starts_with(want), "{body}: {got}");
    }
    parses("[[object]]\nshape = \"billboard\"\nalign = \"axis\"\naxis = [0.0, 0.0, 1.0]\ntransform = { translate = [1.0, 0.0, 0.0] }");
}
