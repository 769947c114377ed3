//! Every example the project shows runs: the embedded default scene, the scenes in scenes/, the canonical
//! benchmark scene (bench/canonical) and the complete example of docs/scene-format.md. Each renders small,
//! and must show objects in front of the background.

use std::path::{Path, PathBuf};
use wrinkle::bump::generators::{BrickParams, Generator};
use wrinkle::image::io::write_png_grey16;
use wrinkle::{render, RenderOptions, Scene};

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Renders at 96x54 and returns the share of pixels that differ from the background.
fn covered_share(scene: &Scene) -> f32 {
    let frame = render(scene, &RenderOptions { width: 96, height: 54, ..RenderOptions::default() }).unwrap();
    let bg = scene.camera.background.to_array();
    frame.color.iter().filter(|c| **c != bg).count() as f32 / frame.color.len() as f32
}

#[test]
fn default_scene_renders() {
    assert!(covered_share(&Scene::default_scene()) > 0.15);
}

#[test]
fn example_scenes_render() {
    let dir = repo().join("scenes");
    let mut seen = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let scene = Scene::load(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            let share = covered_share(&scene);
            assert!(share > 0.05, "{}: only {share} of the image shows an object", path.display());
            seen += 1;
        }
    }
    assert!(seen >= 4, "expected the example scenes of figures 5, 9 (twice) and 11, found {seen}");
}

#[test]
fn the_canonical_benchmark_scene_renders() {
    // bench/canonical.sh and BENCHMARKS.md time it; the sphere covers about 0.23 of the 16:9 frame.
    let scene = Scene::load(&repo().join("bench/canonical/sphere.toml")).unwrap();
    assert!(covered_share(&scene) > 0.15);
}

#[test]
fn scene_format_example_renders() {
    let doc = std::fs::read_to_string(repo().join("docs/scene-format.md")).unwrap();
    let start = doc.find("```toml\n").expect("a TOML example") + "```toml\n".len();
    let example = &doc[start..start + doc[start..].find("```").unwrap()];
    // The example's one file: a brick height map beside it, made as `wrinkle bumpgen bricks` would.
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("doc-example-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("maps")).unwrap();
    let bricks = Generator::Bricks(BrickParams::default()).generate(128).unwrap();
    write_png_grey16(&dir.join("maps/bricks.png"), &bricks).unwrap();
    std::fs::write(dir.join("example.toml"), example).unwrap();
    let scene = Scene::load(&dir.join("example.toml")).unwrap();
    assert!(covered_share(&scene) > 0.1);
    std::fs::remove_dir_all(&dir).unwrap();
}
