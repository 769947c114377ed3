//! Regression tests of issue 19, end to end: every defect found by the hostile-input run, reproduced
//! through the built binary. Each asserts the exit code, the one-line error naming what is wrong, and what
//! is (or is not) left in the output folder.

use crate::common::*;
use std::fs;
use std::os::unix::fs::symlink;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// A flat grey PNG of `side` x `side`: a few kilobytes however large it claims to be.
fn flat_png(scratch: &Scratch, name: &str, side: usize) -> String {
    let path = scratch.input(name);
    let grey = wrinkle::image::Image::new(side, side, 0.5);
    wrinkle::image::io::write_png_grey8(Path::new(&path), &grey).unwrap();
    path
}

/// A scene of one textured sphere reading `texture`.
fn textured_scene(scratch: &Scratch, texture: &str) -> String {
    scratch.write_input(
        "scene.toml",
        format!(
            "[camera]\neye = [0.0, 0.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\nfov_y = 40.0\n\n\
             [[light]]\ntype = \"directional\"\ndirection = [-1.0, -1.0, -1.0]\n\n\
             [[object]]\nshape = \"sphere\"\nradius = 1.0\n[object.material]\ntexture = \"{texture}\"\n"
        ),
    )
}

#[test]
fn work_beyond_the_memory_budget_is_refused_up_front_and_the_flag_raises_it() {
    let s = Scratch::new("budget");
    // 4096^2 decodes to 64 MB of grey and 256 MB of linear RGBA: far beyond a 100 MB budget.
    let big = flat_png(&s, "big.png", 4096);
    let out = s.out("mips.png");
    let run = wrinkle(&["--limit", "memory=100M", "mipmap", &big, "-o", &out]);
    assert_one_error(&run, 2, &["big.png", "4096x4096", "needs", "budget", "--limit memory=SIZE"], &s);
    // The same job as a scene texture.
    let scene = textured_scene(&s, &big);
    let run = wrinkle(&["render", &scene, "-o", &out, "--width", "32", "--height", "24", "--limit", "memory=100M"]);
    assert_one_error(&run, 2, &["big.png", "needs", "--limit memory=SIZE"], &s);
    // Raised, it runs.
    assert_ok(&wrinkle(&["--limit", "memory=4G", "mipmap", &big, "-o", &out]));
    assert_eq!(s.out_entries(), ["mips.png"]);
    let run = wrinkle(&["--limit", "memory=lots", "mipmap", &big, "-o", &out]);
    assert_eq!((run.code, run.stderr.trim()), (2, "error: --limit memory=lots: not a positive number"));
}

#[test]
fn many_large_bump_tables_stop_at_the_budget_naming_the_object() {
    let s = Scratch::new("tables");
    let object =
        "[[object]]\nshape = \"sphere\"\n[object.material.bump]\ngenerator = { kind = \"bricks\", size = 4096 }\n";
    let scene = format!("[camera]\neye = [0.0, 0.0, 5.0]\nlook_at = [0.0, 0.0, 0.0]\n{}", object.repeat(40));
    let scene = s.write_input("tables.toml", scene);
    let t = Instant::now();
    let run = wrinkle(&[
        "render",
        &scene,
        "-o",
        &s.out("r.png"),
        "--width",
        "32",
        "--height",
        "24",
        "--limit",
        "memory=600M",
    ]);
    assert_one_error(&run, 2, &["].material.bump.generator", "4096-texel bump table needs", "--limit memory=SIZE"], &s);
    // Each table holds about 150 MB: the budget stops the scene after a few of its forty.
    let object: usize = run.stderr["error: objects[".len()..].split(']').next().unwrap().parse().unwrap();
    assert!((1..10).contains(&object), "stopped at object {object}: {}", run.stderr);
    assert!(t.elapsed() < Duration::from_secs(60), "{:?}", t.elapsed());
}

#[test]
fn the_image_and_frame_limits_are_errors_that_name_their_flag_and_can_be_raised() {
    let s = Scratch::new("limits");
    let png = flat_png(&s, "wide.png", 600);
    let out = s.out("e.png");
    let run = wrinkle(&["emboss", &png, "-o", &out, "--limit", "image-side=512"]);
    assert_one_error(&run, 2, &["wide.png", "600x600", "512 limit", "--limit image-side=N"], &s);
    // Streamed rows need no pixel-count limit; a pyramid, held whole, does.
    let run = wrinkle(&["mipmap", &png, "-o", &out, "--limit", "image-pixels=100000"]);
    assert_one_error(&run, 2, &["wide.png", "100000 pixel limit", "--limit image-pixels=N"], &s);
    let run = wrinkle(&["render", "-o", &out, "--width", "640", "--height", "480", "--limit", "frame-pixels=300000"]);
    assert_one_error(&run, 2, &["640x480", "--limit frame-pixels=N"], &s);
    assert_ok(&wrinkle(&["emboss", &png, "-o", &out, "--limit", "image-side=600"]));
}

/// A baseline JPEG of `w` x `h` (multiples of 16), then the same file with its SOF0 claiming 16000x16000
/// and cut inside its scan: the decoder would fill in 256 megapixels from a few hundred bytes.
fn lying_jpeg(scratch: &Scratch) -> String {
    let path = scratch.input("liar.jpg");
    let pixels: Vec<u8> = (0..64 * 64).map(|i| (i * 37 % 251) as u8).collect();
    image::save_buffer_with_format(&path, &pixels, 64, 64, image::ExtendedColorType::L8, image::ImageFormat::Jpeg)
        .unwrap();
    let mut bytes = fs::read(&path).unwrap();
    let sof = bytes.windows(2).position(|m| m == [0xFF, 0xC0]).expect("a baseline JPEG has SOF0");
    // SOF0: marker, length (2), precision (1), height (2), width (2).
    bytes[sof + 5..sof + 7].copy_from_slice(&16000u16.to_be_bytes());
    bytes[sof + 7..sof + 9].copy_from_slice(&16000u16.to_be_bytes());
    let sos = bytes.windows(2).position(|m| m == [0xFF, 0xDA]).expect("a scan");
    bytes.truncate(sos + 40);
    fs::write(&path, &bytes).unwrap();
    path
}

#[test]
fn a_truncated_jpeg_that_claims_a_huge_size_is_refused() {
    let s = Scratch::new("jpeg");
    let liar = lying_jpeg(&s);
    let t = Instant::now();
    let run = wrinkle(&["emboss", &liar, "-o", &s.out("e.png")]);
    assert_one_error(&run, 2, &["liar.jpg", "truncated or corrupt JPEG", "end-of-image"], &s);
    let scene = textured_scene(&s, &liar);
    let run = wrinkle(&["render", &scene, "-o", &s.out("r.png"), "--width", "32", "--height", "24"]);
    assert_one_error(&run, 2, &["liar.jpg", "truncated or corrupt JPEG"], &s);
    assert!(t.elapsed() < Duration::from_secs(10), "refusing took {:?}", t.elapsed());
}

/// Waits until `dir` holds a hidden (temporary or staged) file, for at most `limit`.
fn wait_for_hidden_file(dir: &Path, limit: Duration) -> bool {
    let start = Instant::now();
    while start.elapsed() < limit {
        let hidden = fs::read_dir(dir).unwrap().any(|e| e.unwrap().file_name().to_string_lossy().starts_with('.'));
        if hidden {
            return true;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    false
}

#[test]
fn an_interrupted_job_leaves_no_temporary_file() {
    for signal in ["TERM", "INT", "HUP"] {
        let s = Scratch::new("signals");
        let out = s.out("spin.png");
        let mut child = Command::new(env!("CARGO_BIN_EXE_wrinkle"))
            .args(["render", "-o", &out, "--turntable", "--frames", "400", "--width", "320", "--height", "240"])
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let out_dir = Path::new(&out).parent().unwrap().to_path_buf();
        assert!(wait_for_hidden_file(&out_dir, Duration::from_secs(60)), "no frame was staged");
        let sent = Command::new("kill").args([format!("-{signal}"), child.id().to_string()]).status().unwrap();
        assert!(sent.success());
        let status = child.wait().unwrap();
        let number = match signal {
            "TERM" => 15,
            "INT" => 2,
            _ => 1,
        };
        assert_eq!(status.code(), Some(128 + number), "SIG{signal}: {status:?}");
        assert_eq!(s.out_entries(), Vec::<String>::new(), "SIG{signal} left files behind");
    }
}

#[test]
fn outputs_through_symlinks_replace_the_target_and_devices_are_streamed_to() {
    let s = Scratch::new("links");
    let real = s.out("real.png");
    fs::write(&real, "not yet a picture").unwrap();
    let link = s.out("link.png");
    symlink(&real, &link).unwrap();
    assert_ok(&wrinkle(&["render", "-o", &link, "--width", "32", "--height", "24"]));
    assert!(fs::symlink_metadata(&link).unwrap().file_type().is_symlink(), "the link must stay a link");
    assert_eq!(&fs::read(&real).unwrap()[..4], b"\x89PNG", "the link's target must hold the picture");
    assert_eq!(s.out_entries(), ["link.png", "real.png"]);

    let full = s.out("full.png");
    symlink("/dev/full", &full).unwrap();
    let run = wrinkle(&["render", "-o", &full, "--width", "32", "--height", "24"]);
    assert_eq!(run.code, 1, "{run:#?}");
    assert!(run.stderr.contains("full.png: cannot write") && run.stderr.contains("No space left"), "{run:#?}");
    assert!(fs::symlink_metadata(&full).unwrap().file_type().is_symlink());
    let null = s.out("null.png");
    symlink("/dev/null", &null).unwrap();
    assert_ok(&wrinkle(&["render", "-o", &null, "--width", "32", "--height", "24"]));
    assert!(fs::symlink_metadata(&null).unwrap().file_type().is_symlink());
}

#[test]
fn a_failed_output_set_leaves_none_of_its_files() {
    let s = Scratch::new("sets");
    let png = flat_png(&s, "tile.png", 64);
    // Level 3 of 7 cannot be placed: a folder is in the way. Levels 0 to 2 must not stay either.
    fs::create_dir(s.out("mips_3.png")).unwrap();
    let run = wrinkle(&["mipmap", &png, "-o", &s.out("mips.png"), "--levels"]);
    assert_eq!(run.code, 1, "{run:#?}");
    assert!(run.stderr.contains("mips_3.png: cannot write: a folder of that name is in the way"), "{run:#?}");
    assert_eq!(s.out_entries(), ["mips_3.png"]);
    fs::remove_dir(s.out("mips_3.png")).unwrap();
    assert_ok(&wrinkle(&["mipmap", &png, "-o", &s.out("mips.png"), "--levels"]));
    assert_eq!(s.out_entries().len(), 7);

    let s = Scratch::new("frames");
    fs::create_dir(s.out("spin_0002.png")).unwrap();
    let args = ["render", "-o", &s.out("spin.png"), "--turntable", "--frames", "4", "--width", "32", "--height", "24"];
    let run = wrinkle(&args);
    assert_eq!(run.code, 1, "{run:#?}");
    assert_eq!(s.out_entries(), ["spin_0002.png"]);
}

#[test]
fn every_output_must_be_named_for_its_format() {
    let s = Scratch::new("extensions");
    let run = wrinkle(&["bumpgen", "bricks", "-o", &s.out("o.jpg"), "--size", "64"]);
    assert_one_error(&run, 2, &["o.jpg", "must end in .png"], &s);
    let png = flat_png(&s, "h.png", 16);
    for (command, allowed) in [("emboss", ".png"), ("normalmap", ".png"), ("heightmap", ".png"), ("mipmap", ".png")] {
        let run = wrinkle(&[command, &png, "-o", &s.out("o.jpg")]);
        assert_one_error(&run, 2, &["o.jpg", allowed], &s);
    }
    let run = wrinkle(&["texture", "marble", "-o", &s.out("o.tif"), "--size", "16x16"]);
    assert_one_error(&run, 2, &["o.tif", ".png or .exr"], &s);
    let run = wrinkle(&["render", "-o", &s.out("o.bmp")]);
    assert_one_error(&run, 2, &["o.bmp", ".png or .exr"], &s);
}

#[test]
fn a_fifo_as_a_texture_is_refused_instead_of_waited_on() {
    let s = Scratch::new("fifo");
    let fifo = s.input("pipe.png");
    assert!(Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    let scene = textured_scene(&s, &fifo);
    let t = Instant::now();
    let run = wrinkle(&["render", &scene, "-o", &s.out("r.png"), "--width", "32", "--height", "24"]);
    assert_one_error(&run, 2, &["pipe.png", "not a regular file"], &s);
    let run = wrinkle(&["emboss", &fifo, "-o", &s.out("e.png")]);
    assert_one_error(&run, 2, &["pipe.png", "not a regular file"], &s);
    assert!(t.elapsed() < Duration::from_secs(10));
}
