//! Keyframed animation: `[[animation]]` tracks, each setting one field of the scene over time from its
//! keys. A frame's scene is the scene file with every track's value at that time written into its field,
//! built as any scene is: every field can move (the camera, transforms, lights, material and procedural
//! parameters), and each frame's values are checked as a static scene's are.

use super::fields::Fields;
use super::Scene;
use crate::{Error, Result};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use toml::Value;

/// The scene file's animation: its tracks and the document they write into.
#[derive(Debug)]
pub struct Animation {
    /// The scene file without its `[[animation]]` tables.
    document: Value,
    base: PathBuf,
    tracks: Vec<Track>,
}

/// How a track moves between its keys.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interpolation {
    /// Straight from key to key.
    Linear,
    /// A cubic through the keys with Catmull-Rom slopes inside and zero slopes at the first and last key
    /// (easing in and out), C1 everywhere.
    Smooth,
    /// Each key's value until the next key (the only choice for strings and booleans).
    Step,
}

#[derive(Debug)]
struct Track {
    /// The field's path, as the scene's messages name it (`objects[0].transform.rotate`), step by step.
    steps: Vec<Step>,
    /// Times in seconds, increasing, with their values (all of one shape).
    keys: Vec<(f64, Value)>,
    interpolation: Interpolation,
}

/// One step of a path: a table's key, or an array's element.
#[derive(Clone, Debug)]
enum Step {
    Key(String),
    Index(usize),
}

impl Animation {
    /// The animation of a scene document (`[[animation]]` tables), if it has one.
    pub(super) fn of(root: &Value, base: &Path) -> Result<Option<Animation>> {
        let Some(tables) = root.get("animation") else { return Ok(None) };
        let Value::Array(tables) = tables else {
            return Err(Error::scene("animation", "must be an array of tables ([[animation]])"));
        };
        let mut document = root.clone();
        if let Value::Table(t) = &mut document {
            t.remove("animation");
        }
        let tracks = tables
            .iter()
            .enumerate()
            .map(|(i, v)| Track::parse(&format!("animation[{i}]"), v, &document))
            .collect::<Result<Vec<_>>>()?;
        if tracks.is_empty() {
            return Err(Error::scene("animation", "has no tracks"));
        }
        Ok(Some(Animation { document, base: base.to_path_buf(), tracks }))
    }

    /// The time of the last key of any track, in seconds: where the animation holds still.
    pub fn end(&self) -> f64 {
        self.tracks.iter().map(|t| t.keys.last().map_or(0.0, |k| k.0)).fold(0.0, f64::max)
    }

    /// The scene at `time` seconds (before the first key a track holds its first value, after its last its
    /// last). A value a track reaches that the scene refuses is named with the time.
    pub fn scene_at(self: &Arc<Self>, time: f64) -> Result<Scene> {
        if !time.is_finite() {
            return Err(Error::parameter("time", format!("must be finite, got {time}")));
        }
        let mut document = self.document.clone();
        for track in &self.tracks {
            let slot = field_mut(&mut document, &track.steps).expect("the track's path was checked");
            *slot = track.value_at(time);
        }
        let mut scene = Scene::build(&document, &self.base).map_err(|e| match e {
            Error::Scene { path, message } => Error::Scene { path, message: format!("{message} (at time {time} s)") },
            other => other,
        })?;
        scene.animation = Some(self.clone());
        Ok(scene)
    }
}

impl Track {
    fn parse(path: &str, v: &Value, document: &Value) -> Result<Track> {
        let f = Fields::new(path, v, &["target", "keys", "interpolation"])?;
        let target = f.required("target", f.string("target")?)?;
        let steps = parse_steps(target).ok_or_else(|| {
            Error::scene(f.at("target"), format!("\"{target}\" is not a field path like objects[0].transform.rotate"))
        })?;
        let mut probe = document.clone();
        if let Err(message) = field_mut(&mut probe, &steps) {
            return Err(Error::scene(f.at("target"), format!("\"{target}\": {message}")));
        }
        let interpolation = match f.choice(
            "interpolation",
            "linear",
            &[("linear", "linear"), ("smooth", "smooth"), ("step", "step")],
        )? {
            "smooth" => Interpolation::Smooth,
            "step" => Interpolation::Step,
            _ => Interpolation::Linear,
        };
        let Some(Value::Array(list)) = f.get("keys") else {
            return Err(Error::scene(f.at("keys"), "must be an array of keys: [{ time = 0.0, value = ... }, ...]"));
        };
        let mut keys: Vec<(f64, Value)> = Vec::with_capacity(list.len());
        for (k, key) in list.iter().enumerate() {
            let at = format!("{}[{k}]", f.at("keys"));
            let kf = Fields::new(&at, key, &["time", "value"])?;
            let time = kf.required("time", kf.number("time")?)? as f64;
            let value = kf.get("value").ok_or_else(|| Error::scene(kf.at("value"), "missing"))?.clone();
            if !time.is_finite() || keys.last().is_some_and(|(t, _)| time <= *t) {
                return Err(Error::scene(kf.at("time"), "times must be finite and increase from key to key"));
            }
            if let Some((_, first)) = keys.first() {
                if !same_shape(first, &value) {
                    return Err(Error::scene(kf.at("value"), "must have the shape and type of the first key's value"));
                }
            }
            if interpolation != Interpolation::Step && !numeric(&value) {
                return Err(Error::scene(
                    kf.at("value"),
                    "only numbers and arrays of numbers interpolate: use interpolation = \"step\"",
                ));
            }
            keys.push((time, value));
        }
        if keys.is_empty() {
            return Err(Error::scene(f.at("keys"), "needs at least one key"));
        }
        Ok(Track { steps, keys, interpolation })
    }

    /// The track's value at `time`.
    fn value_at(&self, time: f64) -> Value {
        let keys = &self.keys;
        let last = keys.len() - 1;
        if time <= keys[0].0 {
            return keys[0].1.clone();
        }
        if time >= keys[last].0 {
            return keys[last].1.clone();
        }
        let k = keys.partition_point(|(t, _)| *t <= time) - 1;
        let (t0, t1) = (keys[k].0, keys[k + 1].0);
        let s = (time - t0) / (t1 - t0);
        match self.interpolation {
            Interpolation::Step => keys[k].1.clone(),
            Interpolation::Linear => blend(&[&keys[k].1, &keys[k + 1].1], &[1.0 - s, s]),
            Interpolation::Smooth => {
                // Hermite basis on [t0, t1]; slopes (per second) from the neighbouring keys, zero at the ends.
                let slope = |i: usize| match i {
                    0 => None,
                    i if i == last => None,
                    i => Some((i - 1, i + 1, 1.0 / (keys[i + 1].0 - keys[i - 1].0))),
                };
                let (h00, h10, h01, h11) = (
                    2.0 * s * s * s - 3.0 * s * s + 1.0,
                    s * s * s - 2.0 * s * s + s,
                    -2.0 * s * s * s + 3.0 * s * s,
                    s * s * s - s * s,
                );
                let span = t1 - t0;
                let mut values = vec![&keys[k].1, &keys[k + 1].1];
                let mut weights = vec![h00, h01];
                for (i, h) in [(k, h10), (k + 1, h11)] {
                    if let Some((a, b, inv)) = slope(i) {
                        // m = (p_b - p_a) / (t_b - t_a), times the span for the unit interval.
                        values.extend([&keys[b].1, &keys[a].1]);
                        weights.extend([h * span * inv, -h * span * inv]);
                    }
                }
                blend(&values, &weights)
            }
        }
    }
}

/// The weighted sum of values of one shape (numbers, or arrays of them); integers stay integers (rounded).
fn blend(values: &[&Value], weights: &[f64]) -> Value {
    match values[0] {
        Value::Array(first) => Value::Array(
            (0..first.len())
                .map(|i| {
                    let parts: Vec<&Value> = values.iter().map(|v| &v.as_array().expect("one shape")[i]).collect();
                    blend(&parts, weights)
                })
                .collect(),
        ),
        Value::Integer(_) => {
            let sum: f64 = values.iter().zip(weights).map(|(v, w)| v.as_integer().expect("one shape") as f64 * w).sum();
            Value::Integer(sum.round() as i64)
        }
        _ => Value::Float(values.iter().zip(weights).map(|(v, w)| number(v) * w).sum()),
    }
}

fn number(v: &Value) -> f64 {
    match v {
        Value::Integer(i) => *i as f64,
        Value::Float(x) => *x,
        _ => unreachable!("checked numeric"),
    }
}

fn numeric(v: &Value) -> bool {
    match v {
        Value::Integer(_) | Value::Float(_) => true,
        Value::Array(a) => !a.is_empty() && a.iter().all(numeric),
        _ => false,
    }
}

/// Whether two key values can be blended: numbers with numbers (integers only with integers), arrays of the
/// same length element by element; any other value with a value of its own type.
fn same_shape(a: &Value, b: &Value) -> bool {
    match (a, b) {
        (Value::Array(x), Value::Array(y)) => x.len() == y.len() && x.iter().zip(y).all(|(p, q)| same_shape(p, q)),
        (Value::Float(_), Value::Float(_) | Value::Integer(_)) | (Value::Integer(_), Value::Float(_)) => true,
        _ => std::mem::discriminant(a) == std::mem::discriminant(b),
    }
}

/// `objects[0].material.layer[1].time` as steps; the scene's plural names of its top-level arrays (objects,
/// lights, volumes) are the file's `object`, `light` and `volume`.
fn parse_steps(path: &str) -> Option<Vec<Step>> {
    let mut steps = Vec::new();
    for (n, part) in path.split('.').enumerate() {
        let (name, mut rest) = part.split_once('[').map_or((part, ""), |(a, b)| (a, b));
        let valid = |c: char| c.is_ascii_alphanumeric() || c == '_';
        if name.is_empty() || !name.chars().all(valid) {
            return None;
        }
        let name = match (n, name) {
            (0, "objects") => "object",
            (0, "lights") => "light",
            (0, "volumes") => "volume",
            _ => name,
        };
        steps.push(Step::Key(name.to_string()));
        while !rest.is_empty() {
            let (index, after) = rest.split_once(']')?;
            steps.push(Step::Index(index.parse().ok()?));
            rest = match after {
                "" => "",
                a => a.strip_prefix('[')?,
            };
        }
    }
    Some(steps)
}

/// The field at `steps` in `doc`, created (with the tables above it) where a table lacks it; arrays must
/// hold the element named.
fn field_mut<'a>(doc: &'a mut Value, steps: &[Step]) -> std::result::Result<&'a mut Value, String> {
    let mut at = doc;
    for (i, step) in steps.iter().enumerate() {
        let leaf = i + 1 == steps.len();
        at = match (step, at) {
            (Step::Key(k), Value::Table(t)) => {
                let next_is_index = matches!(steps.get(i + 1), Some(Step::Index(_)));
                if !t.contains_key(k) {
                    if next_is_index {
                        return Err(format!("the scene has no \"{k}\" array"));
                    }
                    let fresh = if leaf { Value::Float(0.0) } else { Value::Table(Default::default()) };
                    t.insert(k.clone(), fresh);
                }
                t.get_mut(k).expect("present")
            }
            (Step::Index(n), Value::Array(a)) => {
                let len = a.len();
                a.get_mut(*n).ok_or_else(|| format!("index {n} is past the {len} there"))?
            }
            (Step::Key(k), _) => return Err(format!("\"{k}\" is not inside a table")),
            (Step::Index(n), _) => return Err(format!("[{n}] is not inside an array")),
        };
    }
    Ok(at)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn track(interpolation: Interpolation, keys: &[(f64, f64)]) -> Track {
        Track {
            steps: vec![Step::Key("x".into())],
            keys: keys.iter().map(|&(t, v)| (t, Value::Float(v))).collect(),
            interpolation,
        }
    }

    fn at(t: &Track, time: f64) -> f64 {
        number(&t.value_at(time))
    }

    #[test]
    fn linear_step_and_smooth_pass_through_their_keys() {
        let keys = [(0.0, 1.0), (1.0, 3.0), (3.0, -1.0)];
        for kind in [Interpolation::Linear, Interpolation::Smooth, Interpolation::Step] {
            let t = track(kind, &keys);
            for &(time, v) in &keys {
                assert!((at(&t, time) - v).abs() < 1e-12, "{kind:?} at {time}");
            }
            assert_eq!(at(&t, -5.0), 1.0);
            assert_eq!(at(&t, 9.0), -1.0);
        }
        let linear = track(Interpolation::Linear, &keys);
        assert!((at(&linear, 0.25) - 1.5).abs() < 1e-12 && (at(&linear, 2.0) - 1.0).abs() < 1e-12);
        assert_eq!(at(&track(Interpolation::Step, &keys), 2.9), 3.0);
    }

    /// Smooth: zero slope at the first and last key, the Catmull-Rom slope (p2 - p0) / (t2 - t0) at an inner
    /// key, and the same slope from both sides (C1), by finite differences.
    #[test]
    fn smooth_eases_at_the_ends_and_is_c1_inside() {
        let t = track(Interpolation::Smooth, &[(0.0, 1.0), (1.0, 3.0), (3.0, -1.0)]);
        let h = 1e-6;
        let d = |time: f64| (at(&t, time + h) - at(&t, time - h)) / (2.0 * h);
        assert!(((at(&t, h) - at(&t, 0.0)) / h).abs() < 1e-4, "eases out of the first key");
        assert!(((at(&t, 3.0) - at(&t, 3.0 - h)) / h).abs() < 1e-4, "eases into the last key");
        let inner = (-1.0 - 1.0) / 3.0;
        let (left, right) = ((at(&t, 1.0) - at(&t, 1.0 - h)) / h, (at(&t, 1.0 + h) - at(&t, 1.0)) / h);
        assert!((left - inner).abs() < 1e-4 && (right - inner).abs() < 1e-4, "{left} {right} vs {inner}");
        assert!(d(0.5) > 0.0 && d(2.0) < 0.0);
    }

    #[test]
    fn arrays_blend_per_element_and_integers_stay_integers() {
        let v = |x: &str| -> Value { toml::from_str::<toml::Table>(&format!("v = {x}")).unwrap()["v"].clone() };
        let (a, b) = (v("[[0.0, 1], 2]"), v("[[4.0, 3], 6]"));
        assert!(same_shape(&a, &b) && !same_shape(&a, &v("[1.0, 2.0]")) && !same_shape(&v("1"), &v("\"x\"")));
        assert_eq!(blend(&[&a, &b], &[0.75, 0.25]), v("[[1.0, 2], 3]"));
    }

    #[test]
    fn paths_name_fields_as_the_scene_messages_do() {
        let mut doc: Value = toml::from_str::<toml::Table>(
            "[camera]\neye = [0, 0, 4]\n[[object]]\nshape = \"sphere\"\n[[object.material.layer]]\nmode = \"add\"\n",
        )
        .map(Value::Table)
        .unwrap();
        let path = |p: &str| parse_steps(p).unwrap();
        assert!(field_mut(&mut doc, &path("camera.eye[2]")).unwrap().is_integer());
        assert!(field_mut(&mut doc, &path("objects[0].transform.rotate")).is_ok(), "missing tables are made");
        assert!(field_mut(&mut doc, &path("objects[0].material.layer[0].texture.time")).is_ok());
        assert!(field_mut(&mut doc, &path("objects[1].radius")).unwrap_err().contains("past the 1"));
        assert!(field_mut(&mut doc, &path("lights[0].intensity")).unwrap_err().contains("no \"light\" array"));
        for bad in ["", "a..b", "a[x]", "a[1", "a[1]b", "a b"] {
            assert!(parse_steps(bad).is_none(), "{bad}");
        }
    }
}
