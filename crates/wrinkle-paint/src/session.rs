//! One painting session: the model, its atlas, the painter's orbiting camera, the current frame with its
//! item buffer, the stroke under way and the undo history. Everything the page and the HTTP API do goes
//! through here; the server only carries messages.

use crate::brush::{Brush, Edit, RadiusSpace, Stroke};
use crate::channels::{Atlas, Channel};
use crate::model::Model;
use glam::{Affine3A, Vec2, Vec3};
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::Instant;
use wrinkle::image::output::OutputSet;
use wrinkle::render::Aovs;
use wrinkle::{Camera, CameraDesc, Error, Frame, RenderOptions, Result};

/// Undo keeps this many strokes.
pub const UNDO_STEPS: usize = 100;
/// The largest view the page may ask for.
const MAX_VIEW: usize = 4096;

/// The painter's camera: it orbits `target` at `distance`, `yaw` about +y from +z, `pitch` above the
/// horizon, both in degrees.
#[derive(Clone, Copy, Debug, Serialize, serde::Deserialize, PartialEq)]
pub struct Orbit {
    pub yaw: f32,
    pub pitch: f32,
    pub distance: f32,
    pub target: [f32; 3],
}

impl Orbit {
    pub fn eye(&self) -> Vec3 {
        let (yaw, pitch) = (self.yaw.to_radians(), self.pitch.to_radians());
        Vec3::from(self.target)
            + self.distance * Vec3::new(pitch.cos() * yaw.sin(), pitch.sin(), pitch.cos() * yaw.cos())
    }

    fn validate(&self) -> std::result::Result<(), String> {
        if !(self.yaw.is_finite() && self.pitch.is_finite()) {
            return Err("yaw and pitch must be finite numbers of degrees".into());
        }
        if !(self.distance.is_finite() && self.distance > 1e-4 && self.distance < 1e6) {
            return Err(format!("distance must be a number from 0.0001 to 1000000, got {}", self.distance));
        }
        if self.target.iter().any(|v| !v.is_finite()) {
            return Err("target must be three finite numbers".into());
        }
        Ok(())
    }
}

/// How a model is opened for painting.
#[derive(Clone, Copy, Debug)]
pub struct Opening {
    /// Which object of a scene file.
    pub object: usize,
    /// The side of the square atlas (a saved scene's channels keep theirs).
    pub atlas_size: usize,
    /// The view's width and height in pixels.
    pub view: (usize, usize),
    /// Lay out a new atlas for a mesh even where it has texture coordinates (overlapping or mirrored ones).
    pub new_atlas: bool,
}

impl Default for Opening {
    fn default() -> Self {
        Opening { object: 0, atlas_size: 1024, view: (960, 540), new_atlas: false }
    }
}

/// What `GET /api/state` answers.
#[derive(Serialize)]
pub struct State {
    pub width: usize,
    pub height: usize,
    pub channels: Vec<&'static str>,
    pub atlas_size: usize,
    pub camera: Orbit,
    pub fov_y: Option<f32>,
    pub undo: usize,
    pub redo: usize,
    pub model: String,
    /// The atlas laid out for a mesh without texture coordinates: its charts, utilisation and stretch.
    pub unwrapped: Option<Unwrapped>,
}

#[derive(Serialize)]
pub struct Unwrapped {
    pub charts: usize,
    pub utilisation: f32,
    pub stretch_mean: f32,
    pub stretch_max: f32,
}

/// What saving wrote.
#[derive(Serialize)]
pub struct Saved {
    pub scene: PathBuf,
    pub files: Vec<PathBuf>,
}

pub struct Session {
    model: Model,
    atlas: Atlas,
    orbit: Orbit,
    width: usize,
    height: usize,
    /// The frame of the current camera and atlas, with its depth and item buffer; `None` when stale.
    frame: Option<Frame>,
    stroke: Option<Stroke>,
    undo: Vec<Edit>,
    redo: Vec<Edit>,
    /// Where saving writes by default.
    pub save_dir: PathBuf,
    /// Whether the atlas changed since the last save or recovery copy.
    unsaved: bool,
    /// How long the last frame took to render, milliseconds.
    pub render_ms: f64,
}

impl Session {
    /// Opens a scene or model (see [`Model::open`]).
    pub fn open(path: &Path, opening: &Opening) -> Result<Session> {
        let Opening { object, atlas_size, view: (width, height), new_atlas } = *opening;
        if !(16..=8192).contains(&atlas_size) {
            return Err(Error::parameter("atlas_size", format!("must be from 16 to 8192, got {atlas_size}")));
        }
        let (model, atlas) = Model::open(path, object, atlas_size, new_atlas)?;
        let save_dir = model.base.join(format!("{}-painted", model.stem));
        // The camera starts where the scene's looks from, orbiting what it looks at.
        let cam = &model.scene.camera;
        let offset = cam.eye - cam.look_at;
        let distance = offset.length();
        let orbit = Orbit {
            yaw: offset.x.atan2(offset.z).to_degrees(),
            pitch: (offset.y / distance).clamp(-1.0, 1.0).asin().to_degrees().clamp(-89.0, 89.0),
            distance,
            target: cam.look_at.to_array(),
        };
        let mut session = Session {
            model,
            atlas,
            orbit,
            width,
            height,
            frame: None,
            stroke: None,
            undo: Vec::new(),
            redo: Vec::new(),
            save_dir,
            unsaved: false,
            render_ms: 0.0,
        };
        session.resize(width, height)?;
        if !is_scene_file(path) {
            session.fit_camera_to_model()?;
        }
        Ok(session)
    }

    /// The orbit centred on the model, far enough to see all of it.
    fn fit_camera_to_model(&mut self) -> Result<()> {
        let m = self.model.object_to_world();
        let (lo, hi) = self.model.points.bounds();
        let centre = m.transform_point3((lo + hi) * 0.5);
        let radius = self.model.points.points().map(|p| m.transform_point3(p).distance(centre)).fold(0.0, f32::max);
        let fov = match self.model.scene.camera.projection {
            wrinkle::Projection::Perspective { fov_y } => fov_y,
            _ => 40.0,
        };
        self.orbit.target = centre.to_array();
        self.orbit.distance = (radius.max(1e-3) / (0.5 * fov.to_radians()).sin() * 1.15).max(1e-3);
        self.set_camera(self.orbit)
    }

    pub fn state(&self) -> State {
        State {
            width: self.width,
            height: self.height,
            channels: Channel::ALL.iter().map(|c| c.name()).collect(),
            atlas_size: self.atlas.size,
            camera: self.orbit,
            fov_y: match self.model.scene.camera.projection {
                wrinkle::Projection::Perspective { fov_y } => Some(fov_y),
                _ => None,
            },
            undo: self.undo.len(),
            redo: self.redo.len(),
            model: self.model.stem.clone(),
            unwrapped: self.model.unwrapped.map(|r| Unwrapped {
                charts: r.charts,
                utilisation: r.utilisation,
                stretch_mean: r.stretch_mean,
                stretch_max: r.stretch_max,
            }),
        }
    }

    pub fn set_camera(&mut self, orbit: Orbit) -> Result<()> {
        orbit.validate().map_err(Error::Invalid)?;
        let orbit = Orbit { pitch: orbit.pitch.clamp(-89.0, 89.0), ..orbit };
        let cam = &self.model.scene.camera;
        let camera = CameraDesc::new(orbit.eye(), Vec3::from(orbit.target), Vec3::Y, cam.projection, cam.background)?;
        self.model.scene.camera = camera;
        self.orbit = orbit;
        self.frame = None;
        Ok(())
    }

    pub fn resize(&mut self, width: usize, height: usize) -> Result<()> {
        for (name, v) in [("width", width), ("height", height)] {
            if !(1..=MAX_VIEW).contains(&v) {
                return Err(Error::parameter(name, format!("must be from 1 to {MAX_VIEW}, got {v}")));
            }
        }
        (self.width, self.height, self.frame) = (width, height, None);
        Ok(())
    }

    /// The frame of the current camera and atlas, rendered where stale.
    pub fn frame(&mut self) -> Result<&Frame> {
        if self.frame.is_none() {
            let options = RenderOptions {
                width: self.width,
                height: self.height,
                aovs: Aovs { depth: true, primitive: true, ..Aovs::default() },
                ..RenderOptions::default()
            };
            let start = Instant::now();
            self.frame = Some(wrinkle::render(&self.model.scene, &options)?);
            self.render_ms = start.elapsed().as_secs_f64() * 1e3;
        }
        Ok(self.frame.as_ref().expect("rendered"))
    }

    /// Starts a stroke (ending one under way).
    pub fn begin_stroke(&mut self, brush: Brush) -> Result<()> {
        brush.validate().map_err(Error::Invalid)?;
        self.end_stroke();
        self.stroke = Some(Stroke::new(brush));
        Ok(())
    }

    /// Carries the stroke to `(x, y)` (view pixels, row 0 at the top), laying dabs `spacing` radii apart.
    pub fn stroke_to(&mut self, x: f32, y: f32) -> Result<()> {
        if !(x.is_finite() && y.is_finite()) {
            return Err(Error::Invalid(format!("a stroke point must be two finite numbers, got [{x}, {y}]")));
        }
        let Some(stroke) = &self.stroke else {
            return Err(Error::Invalid("no stroke under way: begin one first".into()));
        };
        let to = Vec2::new(x, y);
        let step = (stroke.brush.spacing * self.radius_px(&stroke.brush)).max(1.0);
        let mut dabs = Vec::new();
        match stroke.last_dab {
            None => dabs.push(to),
            Some(from) => {
                let length = from.distance(to);
                let n = (length / step).floor() as usize;
                dabs.extend((1..=n.min(10_000)).map(|k| from + (to - from) * (k as f32 * step / length)));
            }
        }
        if dabs.is_empty() {
            return Ok(());
        }
        self.frame()?;
        for &at in &dabs {
            self.dab(at);
        }
        if let Some(stroke) = &mut self.stroke {
            stroke.last_dab = dabs.last().copied();
            let channel = stroke.brush.channel;
            self.model.repaint(&mut self.atlas, channel);
        }
        self.frame = None;
        Ok(())
    }

    /// Ends the stroke under way: its change goes onto the undo history. The number of texels it changed.
    pub fn end_stroke(&mut self) -> usize {
        let Some(stroke) = self.stroke.take() else { return 0 };
        let edit = stroke.finish(&self.atlas);
        let changed = edit.texels.len();
        if changed > 0 {
            self.undo.push(edit);
            if self.undo.len() > UNDO_STEPS {
                self.undo.remove(0);
            }
            self.redo.clear();
            self.unsaved = true;
        }
        changed
    }

    /// A whole stroke through `points`: the number of texels it changed.
    pub fn stroke(&mut self, brush: Brush, points: &[[f32; 2]]) -> Result<usize> {
        if points.is_empty() {
            return Err(Error::Invalid("points must hold at least one [x, y]".into()));
        }
        self.begin_stroke(brush)?;
        for &[x, y] in points {
            if let Err(e) = self.stroke_to(x, y) {
                self.end_stroke();
                return Err(e);
            }
        }
        Ok(self.end_stroke())
    }

    /// Undoes (or with `redo` redoes) one stroke: the number of texels it changed back.
    pub fn undo(&mut self, redo: bool) -> usize {
        self.end_stroke();
        let (from, to) = if redo { (&mut self.redo, &mut self.undo) } else { (&mut self.undo, &mut self.redo) };
        let Some(edit) = from.pop() else { return 0 };
        edit.apply(&mut self.atlas, !redo);
        let (channel, changed) = (edit.channel, edit.texels.len());
        to.push(edit);
        self.model.repaint(&mut self.atlas, channel);
        self.frame = None;
        self.unsaved = true;
        changed
    }

    /// The brush radius in view pixels (an object-space radius measured at the orbit's target).
    fn radius_px(&self, brush: &Brush) -> f32 {
        match brush.space {
            RadiusSpace::Screen => brush.radius,
            RadiusSpace::Object => {
                let camera = self.camera();
                let scale = self.model.object_to_world().matrix3.x_axis.length();
                brush.radius * scale * camera.pixels_per_unit(Vec3::from(self.orbit.target))
            }
        }
    }

    fn camera(&self) -> Camera {
        self.model.scene.camera.screen(self.width, self.height)
    }

    /// One dab at view position `at`: the texels whose points lie within the brush's radius of the point seen
    /// there (or of the segment swept from the last dab's point, where that is within two radii), and are
    /// seen themselves, receive the brush's weight (and their mirror images with `mirror_x`).
    fn dab(&mut self, at: Vec2) {
        let Some(frame) = &self.frame else { return };
        let Some(stroke) = &mut self.stroke else { return };
        let camera = self.model.scene.camera.screen(self.width, self.height);
        let object_to_world = self.model.object_to_world();
        let seen = Seen { frame, camera: &camera, object: self.model.object as u32, object_to_world };
        let Some(world) = seen.point_under(at) else {
            stroke.last_centre = None;
            return;
        };
        let centre = object_to_world.inverse().transform_point3(world);
        let scale = object_to_world.matrix3.x_axis.length();
        let radius = match stroke.brush.space {
            RadiusSpace::Screen => stroke.brush.radius / camera.pixels_per_unit(world).max(1e-12) / scale,
            RadiusSpace::Object => stroke.brush.radius,
        };
        let from = stroke.last_centre.filter(|c| c.distance(centre) < 2.0 * radius).unwrap_or(centre);
        stroke.last_centre = Some(centre);
        let mirror = |p: Vec3| Vec3::new(-p.x, p.y, p.z);
        let mut hits: Vec<(u32, f32)> = Vec::new();
        let mirrors: &[bool] = if stroke.brush.mirror_x { &[false, true] } else { &[false] };
        for &mirrored in mirrors {
            let (a, b) = if mirrored { (mirror(from), mirror(centre)) } else { (from, centre) };
            let reach = radius + 0.5 * a.distance(b);
            self.model.points.within((a + b) * 0.5, reach, |texel, p, _| {
                let d = distance_to_segment(p, a, b);
                let q = if mirrored { mirror(p) } else { p };
                if d < radius && seen.visible(q) {
                    hits.push((texel, stroke.brush.weight(d, radius)));
                }
            });
        }
        for (texel, weight) in hits {
            stroke.deposit(&mut self.atlas, texel, weight);
        }
    }

    pub fn atlas(&self) -> &Atlas {
        &self.atlas
    }

    /// Writes the channels and a scene that renders the painted model into `dir`.
    pub fn save(&mut self, dir: Option<&Path>) -> Result<Saved> {
        let dir = dir.map_or_else(|| self.save_dir.clone(), Path::to_path_buf);
        let saved = self.write_to(&dir)?;
        self.unsaved = false;
        Ok(saved)
    }

    /// Writes a recovery copy (a saved scene in `.wrinkle-paint-recovery/` of the save folder) where the atlas
    /// changed since the last save or copy: where it went, if anywhere.
    pub fn write_recovery(&mut self) -> Result<Option<PathBuf>> {
        if !self.unsaved {
            return Ok(None);
        }
        let dir = self.save_dir.join(".wrinkle-paint-recovery");
        let saved = self.write_to(&dir)?;
        self.unsaved = false;
        Ok(Some(saved.scene))
    }

    /// The channels, the model (where its atlas was laid out here) and the scene, placed together: a save
    /// that fails leaves the folder as it was.
    fn write_to(&self, dir: &Path) -> Result<Saved> {
        std::fs::create_dir_all(dir).map_err(|e| Error::write(dir, e.to_string()))?;
        let mut contents = Vec::new();
        for channel in Channel::ALL {
            contents.push((dir.join(channel.file_name()), self.atlas.png(channel)?));
        }
        if let Some(obj) = self.model.unwrapped_obj() {
            contents.push((dir.join("model.obj"), obj.into_bytes()));
        }
        let scene = dir.join("scene.toml");
        contents.push((scene.clone(), self.model.saved_document(dir).into_bytes()));
        let mut set = OutputSet::new();
        for (path, bytes) in &contents {
            set.stage(path, |staged| std::fs::write(staged, bytes).map_err(|e| Error::write(path, e.to_string())))?;
        }
        set.commit()?;
        Ok(Saved { scene, files: contents.into_iter().map(|(path, _)| path).collect() })
    }
}

/// The distance from `p` to the segment from `a` to `b`.
fn distance_to_segment(p: Vec3, a: Vec3, b: Vec3) -> f32 {
    let ab = b - a;
    let t = if ab.length_squared() > 0.0 { ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0) } else { 0.0 };
    p.distance(a + ab * t)
}

pub fn is_scene_file(path: &Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("toml"))
}

/// What the current frame shows: the item buffer and depth under a pixel, to find the painted point under
/// the brush and whether a point of the surface is in view.
struct Seen<'a> {
    frame: &'a Frame,
    camera: &'a Camera,
    object: u32,
    object_to_world: Affine3A,
}

impl Seen<'_> {
    /// The pixel at view position `at`, where it shows the painted object: its index.
    fn pixel(&self, at: Vec2) -> Option<usize> {
        let (x, y) = (at.x.floor(), at.y.floor());
        if x < 0.0 || y < 0.0 || x >= self.frame.width as f32 || y >= self.frame.height as f32 {
            return None;
        }
        let k = y as usize * self.frame.width + x as usize;
        (self.frame.primitive.as_ref()?[k][0] == self.object).then_some(k)
    }

    /// The world point the painted object shows at view position `at`.
    fn point_under(&self, at: Vec2) -> Option<Vec3> {
        let k = self.pixel(at)?;
        let depth = self.frame.depth.as_ref()?[k];
        let centre = Vec2::new((k % self.frame.width) as f32 + 0.5, (k / self.frame.width) as f32 + 0.5);
        let (origin, dir) = self.camera.ray(centre);
        depth.is_finite().then(|| origin + dir * depth)
    }

    /// Whether object-space point `p` is in view: its pixel, or one beside it, shows the painted object at a
    /// depth around the point's (within a pixel's width and 1%).
    fn visible(&self, p: Vec3) -> bool {
        let world = self.object_to_world.transform_point3(p);
        let in_camera = self.camera.world_to_camera.transform_point3(world);
        if in_camera.z >= -1e-3 && self.camera.is_perspective() {
            return false;
        }
        let (screen, _) = self.camera.project(in_camera);
        let depth = if self.camera.is_perspective() { world.distance(self.camera.eye) } else { -in_camera.z };
        let tolerance = 0.01 * depth + 1.5 / self.camera.pixels_per_unit(world).max(1e-12);
        let (Some(depths), Some(items)) = (&self.frame.depth, &self.frame.primitive) else { return false };
        let (w, h) = (self.frame.width as i64, self.frame.height as i64);
        let (cx, cy) = (screen.x.floor() as i64, screen.y.floor() as i64);
        let (mut lo, mut hi) = (f32::INFINITY, f32::NEG_INFINITY);
        for y in (cy - 1).max(0)..=(cy + 1).min(h - 1) {
            for x in (cx - 1).max(0)..=(cx + 1).min(w - 1) {
                let k = (y * w + x) as usize;
                if items[k][0] == self.object {
                    (lo, hi) = (lo.min(depths[k]), hi.max(depths[k]));
                }
            }
        }
        lo <= hi && depth >= lo - tolerance && depth <= hi + tolerance
    }
}
