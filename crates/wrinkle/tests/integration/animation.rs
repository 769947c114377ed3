//! Keyframed animation against scenes written out by hand: the frame of an animated scene at a time is,
//! bit for bit, the render of the static scene whose fields hold the tracks' values at that time (computed
//! here from the keys: linear halfway, smooth at a key and halfway, step), and a track that drives a field
//! out of range is refused with the time named.

use std::path::Path;
use std::sync::Arc;
use wrinkle::{render, Error, RenderOptions, Scene};

/// A scene with `{eye}`, `{rotate}`, `{direction}`, `{color}`, `{time}` and `{octaves}` to fill in.
const TEMPLATE: &str = r#"
[camera]
eye = {eye}
look_at = [0.0, 0.0, 0.0]
fov_y = 40.0

[[light]]
type = "directional"
direction = {direction}

[[object]]
shape = "sphere"
transform = { rotate = {rotate} }

[object.material]
color = {color}
texture = { procedural = "clouds", scale = 2.0, octaves = {octaves}, time = {time} }
"#;

fn fill(eye: &str, rotate: &str, direction: &str, color: &str, time: &str, octaves: &str) -> String {
    TEMPLATE
        .replace("{eye}", eye)
        .replace("{rotate}", rotate)
        .replace("{direction}", direction)
        .replace("{color}", color)
        .replace("{time}", time)
        .replace("{octaves}", octaves)
}

const TRACKS: &str = r#"
[[animation]]
target = "camera.eye"
interpolation = "smooth"
keys = [{ time = 0.0, value = [0.0, 0.0, 4.0] }, { time = 1.0, value = [2.0, 1.0, 3.0] }, { time = 2.0, value = [0.0, 2.0, 4.0] }]

[[animation]]
target = "objects[0].transform.rotate"
keys = [{ time = 0.0, value = [0.0, 0.0, 0.0] }, { time = 2.0, value = [0.0, 90.0, 30.0] }]

[[animation]]
target = "lights[0].direction"
keys = [{ time = 0.0, value = [0.5, -0.5, -1.0] }, { time = 2.0, value = [-0.5, -0.25, -1.0] }]

[[animation]]
target = "objects[0].material.color"
interpolation = "step"
keys = [{ time = 0.0, value = [0.9, 0.5, 0.2] }, { time = 1.5, value = [0.2, 0.6, 0.9] }]

[[animation]]
target = "objects[0].material.texture.time"
keys = [{ time = 0.0, value = 0.0 }, { time = 2.0, value = 3.0 }]

[[animation]]
target = "objects[0].material.texture.octaves"
keys = [{ time = 0.0, value = 1 }, { time = 2.0, value = 7 }]
"#;

fn colour(scene: &Scene) -> Vec<[f32; 3]> {
    render(scene, &RenderOptions { width: 80, height: 60, ..Default::default() }).unwrap().color
}

#[test]
fn a_frame_is_the_static_scene_of_the_tracks_values() {
    let start = fill("[0.0, 0.0, 4.0]", "[0.0, 0.0, 0.0]", "[0.5, -0.5, -1.0]", "[0.9, 0.5, 0.2]", "0.0", "1");
    let animated = Scene::parse(&format!("{start}{TRACKS}"), Path::new(".")).unwrap();
    let animation = Arc::clone(animated.animation.as_ref().expect("the scene is animated"));
    assert_eq!(animation.end(), 2.0);
    // Smooth at t = 1 is the middle key; the Hermite cubic halfway from the first key (slope 0) to it
    // (slope (p2 - p0) / 2): p0 + (p1 - p0) / 2 + (1/8) (0 - m1) with m1 = (p2 - p0) / 2 for the unit span.
    let halfway = |p0: f64, p1: f64, p2: f64| 0.5 * p0 + 0.5 * p1 - 0.125 * (p2 - p0) / 2.0;
    let eye_half =
        format!("[{:?}, {:?}, {:?}]", halfway(0.0, 2.0, 0.0), halfway(0.0, 1.0, 2.0), halfway(4.0, 3.0, 4.0));
    let cases = [
        (0.0, start.clone()),
        (0.5, fill(&eye_half, "[0.0, 22.5, 7.5]", "[0.25, -0.4375, -1.0]", "[0.9, 0.5, 0.2]", "0.75", "3")),
        (1.0, fill("[2.0, 1.0, 3.0]", "[0.0, 45.0, 15.0]", "[0.0, -0.375, -1.0]", "[0.9, 0.5, 0.2]", "1.5", "4")),
        (2.0, fill("[0.0, 2.0, 4.0]", "[0.0, 90.0, 30.0]", "[-0.5, -0.25, -1.0]", "[0.2, 0.6, 0.9]", "3.0", "7")),
        // After the last key every track holds.
        (9.0, fill("[0.0, 2.0, 4.0]", "[0.0, 90.0, 30.0]", "[-0.5, -0.25, -1.0]", "[0.2, 0.6, 0.9]", "3.0", "7")),
    ];
    let mut frames = Vec::new();
    for (time, text) in &cases {
        let expected = Scene::parse(text, Path::new(".")).unwrap();
        let got = animation.scene_at(*time).unwrap();
        assert_eq!(got.camera, expected.camera, "the camera at {time} s");
        let frame = colour(&got);
        assert!(frame == colour(&expected), "the frame at {time} s differs from its static scene");
        frames.push(frame);
    }
    // The frame at time 0 is what parsing the animated scene gives, and the frames move.
    assert!(colour(&animated) == frames[0]);
    assert!(frames.windows(2).take(3).all(|w| w[0] != w[1]), "consecutive frames do not change");
}

#[test]
fn bad_tracks_are_refused_with_their_field() {
    let base = fill("[0.0, 0.0, 4.0]", "[0.0, 0.0, 0.0]", "[0.5, -0.5, -1.0]", "[0.9, 0.5, 0.2]", "0.0", "2");
    let track = |t: &str| format!("{base}\n[[animation]]\n{t}\n");
    let cases = [
        ("target = \"objects[3].radius\"\nkeys = [{ time = 0.0, value = 1.0 }]", "animation[0].target", "past the 1"),
        ("target = \"objects[0].\"\nkeys = [{ time = 0.0, value = 1.0 }]", "animation[0].target", "field path"),
        (
            "target = \"objects[0].radius\"\nkeys = [{ time = 1.0, value = 1.0 }, { time = 1.0, value = 2.0 }]",
            "animation[0].keys[1].time",
            "increase",
        ),
        (
            "target = \"camera.eye\"\nkeys = [{ time = 0.0, value = [0.0, 0.0, 4.0] }, { time = 1.0, value = [1.0, 2.0] }]",
            "animation[0].keys[1].value",
            "shape",
        ),
        (
            "target = \"camera.projection\"\nkeys = [{ time = 0.0, value = \"perspective\" }]",
            "animation[0].keys[0].value",
            "step",
        ),
        ("target = \"camera.eye\"\nkeys = []", "animation[0].keys", "at least one"),
        ("target = \"camera.eye\"\nkeys = [{ time = 0.0, value = [0.0, 0.0, 4.0] }]\nspeed = 2", "animation[0].speed", ""),
    ];
    for (text, field, words) in cases {
        match Scene::parse(&track(text), Path::new(".")) {
            Err(Error::Scene { path, message }) => {
                assert_eq!(path, field, "{text}: {message}");
                assert!(message.contains(words), "{text}: {message}");
            }
            Err(e) => panic!("{text}: not a scene error: {e}"),
            Ok(_) => panic!("{text}: accepted"),
        }
    }
    // A radius that turns negative after t = 1: fine at 0.5, refused at 1.5 with the time named.
    let shrinking =
        track("target = \"objects[0].radius\"\nkeys = [{ time = 0.0, value = 1.0 }, { time = 2.0, value = -1.0 }]");
    let scene = Scene::parse(&shrinking, Path::new(".")).unwrap();
    let animation = scene.animation.as_ref().unwrap();
    assert!(animation.scene_at(0.5).is_ok());
    let e = animation.scene_at(1.5).err().expect("a negative radius").to_string();
    assert!(e.contains("objects[0].radius") && e.contains("at time 1.5 s"), "{e}");
    assert!(animation.scene_at(f64::NAN).is_err());
}
