//! The brush and the stroke it lays: what it deposits, its falloff, and how dabs of one stroke combine (the
//! most of them, not their sum, so a stroke never deposits more than its opacity, as in Blender and
//! Photoshop).

use crate::channels::{Atlas, Channel};
use glam::Vec3;
use serde::Deserialize;
use std::collections::HashMap;

/// The brush of a stroke, as the page and the HTTP API send it.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Brush {
    /// Pixels of the view, or object units with `space = "object"`.
    pub radius: f32,
    #[serde(default)]
    pub space: RadiusSpace,
    /// The share of the radius painted at full strength; the rest falls off smoothly to 0.
    #[serde(default = "half")]
    pub hardness: f32,
    /// The most one stroke deposits.
    #[serde(default = "one")]
    pub opacity: f32,
    /// Dab spacing along the stroke as a share of the radius.
    #[serde(default = "quarter")]
    pub spacing: f32,
    #[serde(default = "colour_channel", deserialize_with = "channel_by_name")]
    pub channel: Channel,
    /// Linear RGB for the colour channel.
    #[serde(default)]
    pub color: Option<[f32; 3]>,
    /// The value for a scalar channel.
    #[serde(default)]
    pub value: Option<f32>,
    /// Paint back what the channel held when it was loaded.
    #[serde(default)]
    pub erase: bool,
    /// A second dab at the object-space mirror image (x -> -x).
    #[serde(default)]
    pub mirror_x: bool,
}

#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum RadiusSpace {
    #[default]
    Screen,
    Object,
}

fn half() -> f32 {
    0.5
}
fn one() -> f32 {
    1.0
}
fn quarter() -> f32 {
    0.25
}
fn colour_channel() -> Channel {
    Channel::Color
}

fn channel_by_name<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Channel, D::Error> {
    let name = String::deserialize(d)?;
    Channel::parse(&name).ok_or_else(|| {
        let names: Vec<&str> = Channel::ALL.iter().map(|c| c.name()).collect();
        serde::de::Error::custom(format!("unknown channel \"{name}\" (one of {})", names.join(", ")))
    })
}

/// The largest brush radius in pixels (a screen-sized brush paints everything in view already).
pub const MAX_RADIUS_PX: f32 = 4096.0;

impl Brush {
    /// Checks every field; the message names the field.
    pub fn validate(&self) -> Result<(), String> {
        let finite = |name: &str, v: f32, lo: f32, hi: f32| {
            if v.is_finite() && (lo..=hi).contains(&v) {
                Ok(())
            } else {
                Err(format!("{name} must be a number from {lo} to {hi}, got {v}"))
            }
        };
        match self.space {
            RadiusSpace::Screen => finite("radius", self.radius, 0.5, MAX_RADIUS_PX)?,
            RadiusSpace::Object => finite("radius", self.radius, 1e-6, 1e6)?,
        }
        finite("hardness", self.hardness, 0.0, 1.0)?;
        finite("opacity", self.opacity, 0.0, 1.0)?;
        finite("spacing", self.spacing, 0.01, 10.0)?;
        if self.erase {
            return Ok(());
        }
        match (self.channel.is_colour(), self.color, self.value) {
            (true, Some(c), _) => {
                if c.iter().any(|v| !v.is_finite() || *v < 0.0) {
                    return Err(format!("color must be three finite non-negative numbers, got {c:?}"));
                }
            }
            (true, None, _) => return Err("the color channel needs a color [r, g, b]".into()),
            (false, _, Some(v)) => finite("value", v, 0.0, 1.0)?,
            (false, _, None) => return Err(format!("the {} channel needs a value", self.channel.name())),
        }
        Ok(())
    }

    /// The strength at `distance` from the centre of a dab of `radius`: 1 inside the hard core, then a
    /// smoothstep down to 0 at the rim, times the opacity.
    pub fn weight(&self, distance: f32, radius: f32) -> f32 {
        let x = distance / radius;
        let core = self.hardness.min(0.9999);
        let w = if x <= core {
            1.0
        } else if x >= 1.0 {
            0.0
        } else {
            let t = (x - core) / (1.0 - core);
            1.0 - t * t * (3.0 - 2.0 * t)
        };
        w * self.opacity
    }

    /// What the brush deposits on a texel that held `loaded` when the atlas was loaded.
    fn target(&self, loaded: Vec3) -> Vec3 {
        if self.erase {
            return loaded;
        }
        match (self.color, self.value) {
            (Some(c), _) if self.channel.is_colour() => Vec3::from(c),
            (_, Some(v)) => Vec3::splat(v),
            _ => loaded,
        }
    }
}

/// A stroke under way: the strongest weight each texel has received and what it held before.
pub struct Stroke {
    pub brush: Brush,
    touched: HashMap<u32, (f32, u32)>,
    /// Where the last dab was laid (view pixels): the next is `spacing` radii along.
    pub last_dab: Option<glam::Vec2>,
    /// The object-space point of the last dab that met the surface: the next dab sweeps the brush from it,
    /// so the stroke's edge is straight rather than scalloped by its dabs.
    pub last_centre: Option<Vec3>,
}

/// One stroke's change of the atlas: enough to undo and redo it exactly.
pub struct Edit {
    pub channel: Channel,
    pub texels: Vec<u32>,
    pub before: Vec<u32>,
    pub after: Vec<u32>,
}

impl Stroke {
    pub fn new(brush: Brush) -> Stroke {
        Stroke { brush, touched: HashMap::new(), last_dab: None, last_centre: None }
    }

    /// Raises texel `texel`'s weight to `weight` if that is more than it had this stroke, and writes it.
    pub fn deposit(&mut self, atlas: &mut Atlas, texel: u32, weight: f32) {
        if weight <= 0.0 {
            return;
        }
        let channel = self.brush.channel;
        let codes = atlas.codes(channel);
        let entry = self.touched.entry(texel).or_insert((0.0, codes[texel as usize]));
        if weight <= entry.0 {
            return;
        }
        entry.0 = weight;
        let before = channel.decode(entry.1);
        let target = self.brush.target(channel.decode(atlas.loaded(channel, texel)));
        atlas.set(channel, texel, channel.encode(before.lerp(target, weight)));
    }

    /// The stroke's change: the texels whose code differs from before it.
    pub fn finish(self, atlas: &Atlas) -> Edit {
        let channel = self.brush.channel;
        let codes = atlas.codes(channel);
        let mut changed: Vec<(u32, u32)> =
            self.touched.into_iter().filter(|(t, (_, b))| codes[*t as usize] != *b).map(|(t, (_, b))| (t, b)).collect();
        changed.sort_unstable();
        Edit {
            channel,
            texels: changed.iter().map(|c| c.0).collect(),
            before: changed.iter().map(|c| c.1).collect(),
            after: changed.iter().map(|c| codes[c.0 as usize]).collect(),
        }
    }
}

impl Edit {
    /// Puts the texels back as they were before (`undo`) or after the stroke.
    pub fn apply(&self, atlas: &mut Atlas, undo: bool) {
        let values = if undo { &self.before } else { &self.after };
        for (&t, &v) in self.texels.iter().zip(values) {
            atlas.set(self.channel, t, v);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn brush(json: &str) -> Brush {
        serde_json::from_str(json).unwrap()
    }

    #[test]
    fn falloff_is_hard_in_the_core_and_zero_at_the_rim() {
        let b = brush(r#"{"radius": 10, "hardness": 0.5, "opacity": 0.8, "color": [1, 0, 0]}"#);
        assert_eq!(b.weight(0.0, 10.0), 0.8);
        assert_eq!(b.weight(5.0, 10.0), 0.8);
        assert!((b.weight(7.5, 10.0) - 0.4).abs() < 1e-6); // the smoothstep's middle
        assert_eq!(b.weight(10.0, 10.0), 0.0);
    }

    #[test]
    fn dabs_of_a_stroke_do_not_build_up_and_undo_is_exact() {
        let mut atlas = Atlas::new(4, |_| Vec3::splat(0.5), Vec::new());
        let b = brush(r#"{"radius": 3, "channel": "specular", "value": 1.0, "opacity": 0.5}"#);
        let mut stroke = Stroke::new(b);
        for _ in 0..5 {
            stroke.deposit(&mut atlas, 2, 0.5);
        }
        // Code 128 (0.5 rounded up) halfway to 255, once: 191.5, rounded to 192; not 255.
        assert_eq!(atlas.codes(Channel::Specular)[2], 192);
        let edit = stroke.finish(&atlas);
        assert_eq!(edit.texels, vec![2]);
        edit.apply(&mut atlas, true);
        assert_eq!(atlas.codes(Channel::Specular)[2], Channel::Specular.encode(Vec3::splat(0.5)));
    }

    #[test]
    fn bad_brushes_name_their_field() {
        let bad = [
            (r#"{"radius": -1, "color": [1, 0, 0]}"#, "radius"),
            (r#"{"radius": 5, "hardness": 2, "color": [1, 0, 0]}"#, "hardness"),
            (r#"{"radius": 5}"#, "color"),
            (r#"{"radius": 5, "channel": "height"}"#, "value"),
        ];
        for (json, field) in bad {
            let e = brush(json).validate().unwrap_err();
            assert!(e.contains(field), "{json}: {e}");
        }
        let e = serde_json::from_str::<Brush>(r#"{"radius": 5, "channel": "gloss"}"#).unwrap_err().to_string();
        assert!(e.contains("unknown channel \"gloss\""), "{e}");
    }
}
