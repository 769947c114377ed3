//! The driver: runs the pipeline for one frame (tessellate, set up, bin, then per tile: rasterize,
//! shade, resolve) and reports the time of each stage.

mod displace;
mod frame;
mod shadows;
mod transparent;
mod views;

pub use frame::{Aovs, Frame, Stats, NO_PRIMITIVE};
pub use transparent::Transparency;

use crate::bump::BumpFilter;
use crate::envmap::Environment;
use crate::geometry::billboard::Viewer;
use crate::geometry::frame_lanes::Frame8;
use crate::geometry::mesh_lanes;
use crate::geometry::tessellate::{grid, segments_for, Mesh};
use crate::geometry::{Instance, Primitive, Shape, Surface, TriangleMesh};
use crate::image::io::Placement;
use crate::lanes::{mask_of, F8, LANES, V3};
use crate::light::Light;
use crate::limits::Limit;
use crate::procedural::hypertexture::Hypertexture;
use crate::raster::exact::{exact8, frames_at, outline_triangles, start_within, tested_lanes, Outline};
use crate::raster::refine::{affine_uv8, refine_uv8};
pub use crate::raster::samples::{PixelFilter, Sampler, ShadingRate, MAX_SPP};
use crate::raster::setup::{
    interpolate8, keep_triangle_buffer, triangle_buffer, Counted, ProjectedMesh, ProjectedVertices,
};
use crate::raster::visibility::{BinPart, EMPTY};
use crate::raster::{Bins, Camera, Cull, SamplePattern, ScreenTriangle, TriangleSetup, VisBuffer, SUBPIXEL};
use crate::scene::{CameraDesc, Scene};
use crate::shade::{AlphaMode, Ibl, MappingNeeds, ShadeContext, ShadedSample, SurfaceSamples8};
use crate::stream;
use crate::texture::{Footprint8, TexelLocation};
use crate::{Error, Result};
use glam::{Affine3A, Quat, Vec2, Vec3};
use rayon::prelude::*;
use std::borrow::Cow;
use std::mem::MaybeUninit;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Instant;

/// The longest a tessellation segment may be on screen, in pixels.
const SEGMENT_PX: f32 = 16.0;
/// How far (in pixels) a flat triangle may sag from the curved surface. The shader's Newton step
/// (raster/refine.rs) then moves each sample's (u,v) onto its ray, leaving an error of about the square of
/// this over the radius of curvature: thousandths of a pixel.
const SAG_PX: f32 = 0.25;
/// The largest side of a screen tile, in pixels (at one sample a pixel).
const MAX_TILE: usize = 64;

#[derive(Clone, Debug)]
pub struct RenderOptions {
    pub width: usize,
    pub height: usize,
    /// Samples per pixel, 1 to [`MAX_SPP`].
    pub spp: usize,
    /// How the samples are placed in each pixel.
    pub sampler: Sampler,
    /// How the samples make the pixel: each is drawn in proportion to the filter's magnitude around the
    /// pixel's centre and weighs its sign (the box over the pixel by default).
    pub pixel_filter: PixelFilter,
    /// Whether every sample is shaded, or each triangle once per pixel.
    pub shading_rate: ShadingRate,
    /// Seeds the Sobol sampler's per-pixel scrambles: renders with different seeds are independent
    /// estimates of the same image (their difference measures the noise).
    pub seed: u32,
    /// Where a pixel reads its textures and bumps: its centre's (u,v) (the default), or the centroid or
    /// diagonal crossing of its projected corners, with their quadrilateral's footprint.
    pub texel_location: TexelLocation,
    pub bump: bool,
    /// Replaces every material's bump filter when set.
    pub bump_filter: Option<BumpFilter>,
    /// Rotation of every object about the vertical axis through the camera's target, degrees (turntables).
    pub turntable_degrees: f32,
    /// Which per-pixel AOVs to keep.
    pub aovs: Aovs,
    /// Nothing behind the objects: the background (colour or environment) is black with alpha 0, the
    /// frame keeps its coverage as alpha and its colour is premultiplied by it.
    pub transparent: bool,
    /// How translucent (`alpha_mode = "blend"`) fragments are put in order.
    pub transparency: Transparency,
    /// Only this part of the frame: pixels x0..x1, y0..y1 (row 0 at the top), exactly as the whole frame
    /// renders them. The frame limits apply to the part.
    pub crop: Option<Crop>,
}

/// A rectangle of the frame's pixels: x0..x1 by y0..y1.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Crop {
    pub x0: usize,
    pub y0: usize,
    pub x1: usize,
    pub y1: usize,
}

impl Crop {
    pub fn width(&self) -> usize {
        self.x1 - self.x0
    }
    pub fn height(&self) -> usize {
        self.y1 - self.y0
    }
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            width: 1280,
            height: 720,
            spp: 1,
            sampler: Sampler::default(),
            pixel_filter: PixelFilter::default(),
            shading_rate: ShadingRate::default(),
            seed: 0,
            texel_location: TexelLocation::Centre,
            bump: true,
            bump_filter: None,
            turntable_degrees: 0.0,
            aovs: Aovs::default(),
            transparent: false,
            transparency: Transparency::default(),
            crop: None,
        }
    }
}

impl RenderOptions {
    /// The size of what is rendered and held: the crop, or the whole frame.
    pub fn output_size(&self) -> (usize, usize) {
        self.crop.map_or((self.width, self.height), |c| (c.width(), c.height()))
    }

    /// Where each pixel's samples lie and what they weigh.
    fn sample_pattern(&self) -> Result<SamplePattern> {
        Ok(SamplePattern::new(self.spp, self.sampler, self.pixel_filter)?.seeded(self.seed))
    }

    /// The side of the square screen tiles: about 4096 samples a tile (64 x 64 at one sample a pixel), at
    /// least 8 pixels so triangles are not binned into too many.
    fn tile_size(&self) -> usize {
        let mut side = MAX_TILE;
        while side > 8 && side * side * self.spp > 4096 {
            side /= 2;
        }
        side
    }

    pub fn validate(&self) -> Result<()> {
        // A frame too large to hold is rendered in parts (crops): the side limit is then the part's, and
        // the whole frame may be up to 65536 on a side (its tile grid, camera and one band per worker).
        let (side, pixels) = (Limit::FrameSide.count(), Limit::FramePixels.count());
        let whole_side = if self.crop.is_some() { 1 << 16 } else { side };
        for (name, v) in [("width", self.width), ("height", self.height)] {
            if v == 0 || v > whole_side {
                let parts =
                    if v > side && self.crop.is_none() { " (a larger frame renders in parts: crop)" } else { "" };
                return Err(Error::parameter(name, format!("must be between 1 and {whole_side}, got {v}{parts}")));
            }
        }
        if let Some(c) = self.crop {
            if !(c.x0 < c.x1 && c.y0 < c.y1 && c.x1 <= self.width && c.y1 <= self.height) {
                return Err(Error::parameter(
                    "crop",
                    format!(
                        "must be X0,Y0,X1,Y1 with X0 < X1 <= {} and Y0 < Y1 <= {}, got {},{},{},{}",
                        self.width, self.height, c.x0, c.y0, c.x1, c.y1
                    ),
                ));
            }
            if c.width() > side || c.height() > side {
                return Err(Error::parameter("crop", format!("must be at most {side} pixels on a side")));
            }
        }
        let (w, h) = self.output_size();
        if w * h > pixels {
            return Err(Error::Invalid(format!(
                "{w}x{h} is more than the {pixels} pixel limit of a frame ({}; or render it in parts with a crop)",
                Limit::FramePixels.hint()
            )));
        }
        // Checked alone: the pattern's tables are built once, by the render.
        SamplePattern::check(self.spp, self.pixel_filter)?;
        if !self.turntable_degrees.is_finite() {
            return Err(Error::Invalid("turntable angle must be finite".into()));
        }
        Ok(())
    }
}

/// Renders one frame of the scene.
pub fn render(scene: &Scene, options: &RenderOptions) -> Result<Frame> {
    render_with_progress(scene, options, &|_, _| {})
}

/// Renders one frame, calling `progress(done, total)` from the worker threads as bands of tiles finish.
pub fn render_with_progress(
    scene: &Scene,
    options: &RenderOptions,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Frame> {
    render_view(scene, &View { camera: &scene.camera, hidden: None, object_views: true, stop: None }, options, progress)
}

/// Renders one frame like [`render_with_progress`], giving up with [`Error::Interrupted`] soon after `stop`
/// is set (from another thread: a front end's interrupt).
pub fn render_until(
    scene: &Scene,
    options: &RenderOptions,
    progress: &(dyn Fn(usize, usize) + Sync),
    stop: &AtomicBool,
) -> Result<Frame> {
    let view = View { camera: &scene.camera, hidden: None, object_views: true, stop: Some(stop) };
    render_view(scene, &view, options, progress)
}

/// What one render sees the scene through.
struct View<'a> {
    camera: &'a CameraDesc,
    /// An object left out (the one whose surroundings a cube map's views show).
    hidden: Option<u32>,
    /// Whether objects with `reflect_views` get their six views rendered (not within those views).
    object_views: bool,
    /// Set from elsewhere to give up: the bands not yet begun are skipped.
    stop: Option<&'a AtomicBool>,
}

/// Renders the frame in parts, each a crop of it (`RenderOptions::crop` is not used), with one setup for
/// them all (tessellation, binning, shadow maps): `each` receives the parts' frames in order, each part's
/// pixels exactly the whole frame's. The whole frame may be larger than one render holds; each part is
/// checked as a crop is.
pub fn render_parts(
    scene: &Scene,
    options: &RenderOptions,
    parts: &[Crop],
    each: &mut dyn FnMut(Frame) -> Result<()>,
) -> Result<()> {
    let view = View { camera: &scene.camera, hidden: None, object_views: true, stop: None };
    let parts: Vec<Option<Crop>> = parts.iter().map(|&c| Some(c)).collect();
    render_view_parts(scene, &view, options, &parts, &|_, _| {}, each)
}

fn render_view(
    scene: &Scene,
    view: &View,
    options: &RenderOptions,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Frame> {
    let mut frame = None;
    render_view_parts(scene, view, options, &[options.crop], progress, &mut |f| {
        frame = Some(f);
        Ok(())
    })?;
    Ok(frame.expect("one part rendered"))
}

/// Renders each of `parts` (a crop, or `None`: the whole frame) of the frame with one setup for all.
fn render_view_parts(
    scene: &Scene,
    view: &View,
    options: &RenderOptions,
    parts: &[Option<Crop>],
    progress: &(dyn Fn(usize, usize) + Sync),
    each: &mut dyn FnMut(Frame) -> Result<()>,
) -> Result<()> {
    let aovs = Aovs { alpha: options.transparent || options.aovs.alpha, ..options.aovs };
    for &crop in parts {
        let part = RenderOptions { crop, ..options.clone() };
        part.validate()?;
        let (ow, oh) = part.output_size();
        crate::limits::reserve((ow * oh) as u64 * aovs.bytes_per_pixel(), || format!("a {ow}x{oh} frame"))?;
    }
    let (w, h) = (options.width, options.height);
    let mut stats = Stats::default();
    let cam = view.camera;
    let camera = cam.screen(w, h);
    let object_views = match view.object_views {
        true => views::object_views(scene, options, &camera)?,
        false => Vec::new(),
    };

    // Every primitive placed for a camera (billboards turned towards it), less the hidden object.
    let placed_for = |camera: &Camera| {
        let mut placed = instances(scene, camera, options.turntable_degrees);
        placed.retain(|i| Some(i.object) != view.hidden);
        placed
    };
    let mut instances = placed_for(&camera);
    let t = Instant::now();
    let diced = displace::displace(&mut instances, &scene.materials, &camera)?;
    stats.tessellate_ms = ms(t);
    let pattern = options.sample_pattern()?;
    let tile_size = options.tile_size();
    // Translucent surfaces stay out of the opaque visibility: the transparent pass composites them over it.
    let blending: Vec<bool> =
        instances.iter().map(|i| scene.materials[i.material].alpha_mode == AlphaMode::Blend).collect();
    let opaque: Vec<bool> = blending.iter().map(|b| !b).collect();
    let binning = Binning { tile_size, surfaces: &opaque };
    let drawn = Drawn::new(&instances, diced, &camera, &pattern, binning, &mut stats);
    let bins = &drawn.bins;
    let t = Instant::now();
    let blend_bins =
        blending.contains(&true).then(|| Bins::of(&drawn.triangles, w, h, tile_size, |t| blending[t.surface as usize]));
    let blend_order = match (&blend_bins, options.transparency) {
        (Some(_), Transparency::Sorted) => transparent::sorted_order(&camera, &instances, &drawn, &blending),
        _ => Vec::new(),
    };
    stats.bin_ms += ms(t);

    let mut shade_ctx = ShadeContext {
        eye: cam.eye,
        ortho_to_eye: (!camera.is_perspective()).then(|| camera.camera_to_world.transform_vector3(Vec3::Z).normalize()),
        lights: &scene.lights,
        materials: &scene.materials,
        needs: scene
            .materials
            .iter()
            .map(|m| MappingNeeds::of(m, scene.environment.is_some() || m.reflect_views > 0))
            .collect(),
        bump_enabled: options.bump,
        bump_filter: options.bump_filter,
        environment: scene.environment.as_ref().map(|e| &e.map),
        object_views: &object_views,
        ibl: ibl(scene),
        slides: &scene.slides,
        shadows: None,
    };
    let cutoffs: Vec<Option<f32>> = instances.iter().map(|i| scene.materials[i.material].alpha_cutoff()).collect();
    let t = Instant::now();
    let casting: Vec<bool> = blending.iter().map(|b| !b).collect();
    let shadows = shadows::shadows(scene, &instances, &drawn, &placed_for, &shade_ctx, &cutoffs, &casting, w.max(h))?;
    shade_ctx.shadows = shadows.as_ref();
    stats.shadow_ms = ms(t);

    let replacing: Vec<bool> =
        instances.iter().map(|i| options.bump && scene.materials[i.material].replaces_depth()).collect();
    // A transparent background: black and alpha 0 where nothing is seen, colour premultiplied by coverage.
    let background = if options.transparent { Vec3::ZERO } else { cam.background };
    let job = TileJob {
        background,
        aovs,
        // Shaded once per pixel, a sample stands for the whole pixel.
        sample_cell: match options.shading_rate {
            ShadingRate::Sample => (1.0 / options.spp as f32).sqrt(),
            ShadingRate::Pixel => 1.0,
        },
        per_pixel: options.shading_rate == ShadingRate::Pixel && options.spp > 1,
        texel_location: options.texel_location,
        volumes: &scene.volumes,
        sky: scene.environment.as_ref().filter(|e| e.background && !options.transparent).map(|e| &e.map),
        lights: &scene.lights,
        blend_bins: blend_bins.as_ref(),
        transparency: options.transparency,
        blend_order: &blend_order,
        ..TileJob::visibility(&drawn, bins, &camera, &pattern, &instances, &shade_ctx, &cutoffs, &replacing)
    };
    for &part in parts {
        let t = Instant::now();
        let (ow, oh) = part.map_or((w, h), |c| (c.width(), c.height()));
        // Every pixel is written once, by the tile it lies in (the background where nothing covers it): a
        // frame filled with the background first wrote it twice (a tenth of the canonical frame on one thread).
        let mut color = Vec::with_capacity(ow * oh);
        let bands = render_bands(&job, &mut color.spare_capacity_mut()[..ow * oh], part, bins, options, view, progress);
        let (Some(bands), false) = (bands, stopped(view)) else {
            return Err(Error::Interrupted);
        };
        // SAFETY: `render_bands` wrote every pixel of the first ow x oh, as it returned bands.
        unsafe { color.set_len(ow * oh) };
        let mut frame = Frame::with_color(ow, oh, aovs, color);
        if let Some(c) = part {
            frame.placement = Placement { x0: c.x0, y0: c.y0, width: ow, height: oh, full_width: w, full_height: h };
        }
        frame.gather_aovs(bands);
        stats.raster_shade_ms = ms(t);
        frame.stats = stats;
        each(frame)?;
    }
    Ok(())
}

/// The colour of the frame's pixels (of the crop, where one is given) into `color`, every one of them written,
/// and their AOVs band by band of tiles, on every worker; `progress` is told as bands finish. None where the
/// view was stopped before every band was drawn (some pixels are then left unwritten).
fn render_bands(
    job: &TileJob,
    color: &mut [MaybeUninit<[f32; 3]>],
    crop: Option<Crop>,
    bins: &Bins,
    options: &RenderOptions,
    view: &View,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Option<Vec<frame::AovBand>> {
    let (w, h, tile_size) = (options.width, options.height, bins.tile_size);
    let band_len = tile_size * w;
    let (bands_done, bands) = (AtomicUsize::new(0), bins.tiles_y);
    let skipped = AtomicBool::new(false);
    // Told once per band, before it is drawn: whether to leave it.
    let stop = || {
        let stop = stopped(view);
        if stop {
            skipped.store(true, Ordering::Relaxed);
        }
        stop
    };
    let aovs = match crop {
        Some(crop) => {
            let bands = crop.y1.div_ceil(tile_size) - crop.y0 / tile_size;
            let done = || progress(bands_done.fetch_add(1, Ordering::Relaxed) + 1, bands);
            crop_bands(job, color, crop, (w, h, options.spp), tile_size, &stop, &done)
        }
        None => color
            .par_chunks_mut(band_len)
            .enumerate()
            .map_init(
                || TileScratch::new(tile_size, options.spp),
                |scratch, (ty, color)| {
                    let mut aov = frame::AovBand::new(job.aovs, color.len());
                    if stop() {
                        return aov;
                    }
                    for tx in 0..bins.tiles_x {
                        job.tile(scratch, (tx, ty), color, &mut aov, w, h);
                    }
                    stream::fence();
                    progress(bands_done.fetch_add(1, Ordering::Relaxed) + 1, bands);
                    aov
                },
            )
            .collect(),
    };
    (!skipped.load(Ordering::Relaxed)).then_some(aovs)
}

/// The environment as a light, with the convolved maps its materials need (made on first use, then kept
/// with the environment).
fn ibl(scene: &Scene) -> Option<Ibl> {
    let env = &scene.environment.as_ref()?.map;
    let lights = scene.lights.iter().filter_map(|l| match l {
        Light::Environment { radiance } => Some(*radiance),
        _ => None,
    });
    let radiance = lights.reduce(|a, b| a + b)?;
    let glossy = scene
        .materials
        .iter()
        .map(|m| (m.phong.specular > 0.0).then(|| env.lobe(Ibl::phong_exponent(m.phong.shininess))))
        .collect();
    Some(Ibl { radiance, diffuse: env.lobe(1.0), glossy })
}

/// The tile rows that meet `crop`, each rendered into a whole-width band of its own (only the tiles that
/// meet the crop) and cut to the crop: the crop's pixels are exactly the whole frame's, every one of them
/// written. `stop` is asked before each band (which is then left unwritten); `done` is told after each.
fn crop_bands(
    job: &TileJob,
    color: &mut [MaybeUninit<[f32; 3]>],
    crop: Crop,
    (w, h, spp): (usize, usize, usize),
    tile_size: usize,
    stop: &(dyn Fn() -> bool + Sync),
    done: &(dyn Fn() + Sync),
) -> Vec<frame::AovBand> {
    let (ty0, ty1) = (crop.y0 / tile_size, crop.y1.div_ceil(tile_size));
    let (tx0, tx1) = (crop.x0 / tile_size, crop.x1.div_ceil(tile_size));
    let cw = crop.width();
    // The crop's rows split by tile row.
    let mut parts = Vec::with_capacity(ty1 - ty0);
    let mut rest = color;
    for ty in ty0..ty1 {
        let rows = (ty * tile_size).max(crop.y0)..((ty + 1) * tile_size).min(crop.y1);
        let (part, tail) = rest.split_at_mut(rows.len() * cw);
        parts.push((ty, rows, part));
        rest = tail;
    }
    parts
        .into_par_iter()
        .map_init(
            || TileScratch::new(tile_size, spp),
            |scratch, (ty, rows, part)| {
                let band_rows = tile_size.min(h - ty * tile_size);
                // Only the tiles that meet the crop are drawn: the band's other pixels hold the background.
                let mut band = vec![MaybeUninit::new(job.background.to_array()); band_rows * w];
                let mut aov = frame::AovBand::new(job.aovs, band.len());
                let local = rows.start - ty * tile_size..rows.end - ty * tile_size;
                if stop() {
                    return aov.cropped(local, crop.x0, cw, w);
                }
                for tx in tx0..tx1 {
                    job.tile(scratch, (tx, ty), &mut band, &mut aov, w, h);
                }
                for (dst, r) in part.chunks_exact_mut(cw).zip(local.clone()) {
                    dst.copy_from_slice(&band[r * w + crop.x0..r * w + crop.x0 + cw]);
                }
                stream::fence();
                done();
                aov.cropped(local, crop.x0, cw, w)
            },
        )
        .collect()
}

fn stopped(view: &View) -> bool {
    view.stop.is_some_and(|s| s.load(Ordering::Relaxed))
}

fn ms(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}

/// Every primitive of every object, placed in the world; billboards turned towards the camera.
fn instances(scene: &Scene, camera: &Camera, turntable_degrees: f32) -> Vec<Instance> {
    let pivot = scene.camera.look_at;
    let spin = Affine3A::from_translation(pivot)
        * Affine3A::from_quat(Quat::from_rotation_y(turntable_degrees.to_radians()))
        * Affine3A::from_translation(-pivot);
    let axes = camera.camera_to_world.matrix3;
    let viewer = Viewer {
        right: axes.x_axis.into(),
        up: axes.y_axis.into(),
        back: axes.z_axis.into(),
        eye: camera.is_perspective().then_some(camera.eye),
    };
    let mut out = Vec::new();
    for (index, object) in scene.objects.iter().enumerate() {
        let object_to_world = spin * object.transform.matrix();
        let (shape, object_to_world) = match &object.shape {
            Shape::Billboard(b) => {
                let corners = b.corners(object_to_world.transform_point3(Vec3::ZERO), &viewer);
                (Cow::Owned(Shape::Surface(Surface::Patch { corners })), Affine3A::IDENTITY)
            }
            shape => (Cow::Borrowed(shape), object_to_world),
        };
        out.extend(Instance::of_shape(
            &shape,
            object_to_world,
            camera.world_to_camera,
            object.material,
            index as u32,
            object.affine,
        ));
    }
    out
}

/// The triangles the rasterizer draws for one instance: a parametric surface's tessellation, a displaced
/// one's diced triangles, or a mesh's own triangles (borrowed, not copied).
enum Triangles<'a> {
    Grid(Mesh),
    Diced(Mesh),
    Mesh(&'a TriangleMesh),
}

impl Triangles<'_> {
    fn positions(&self) -> &[Vec3] {
        match self {
            Triangles::Grid(g) | Triangles::Diced(g) => &g.positions,
            Triangles::Mesh(m) => &m.positions,
        }
    }

    fn uvs(&self) -> Option<&[Vec2]> {
        match self {
            Triangles::Grid(g) | Triangles::Diced(g) => Some(&g.uvs),
            Triangles::Mesh(m) => m.uvs(0),
        }
    }

    fn triangles(&self) -> &[[u32; 3]] {
        match self {
            Triangles::Grid(g) | Triangles::Diced(g) => &g.triangles,
            Triangles::Mesh(m) => &m.triangles,
        }
    }
}

/// What the rasterizer draws of a scene seen through one camera: each instance's triangles, and all of
/// them set up on its screen.
struct Drawn<'a> {
    meshes: Vec<Triangles<'a>>,
    /// Per surface, the longest (u,v) step of the ray-exact refinement: one tessellation segment.
    max_steps: Vec<Vec2>,
    /// Per surface, the number within its object of its first triangle.
    first_triangles: Vec<u32>,
    triangles: Vec<ScreenTriangle>,
    /// The triangles of the surfaces asked for, binned to the screen's tiles as they were set up.
    bins: Bins,
}

/// Which triangles `Drawn::new` bins, and to tiles of what size: those of the surfaces marked true.
struct Binning<'b> {
    tile_size: usize,
    surfaces: &'b [bool],
}

impl Drop for Drawn<'_> {
    fn drop(&mut self) {
        keep_triangle_buffer(std::mem::take(&mut self.triangles));
    }
}

impl<'a> Drawn<'a> {
    /// Tessellates the instances' surfaces for `camera` (or takes their diced or mesh triangles), sets
    /// every triangle up for the samples of `pattern` and bins those of the surfaces `binning` asks for,
    /// timing the stages into `stats`.
    fn new(
        instances: &'a [Instance],
        mut diced: Vec<Option<Mesh>>,
        camera: &Camera,
        pattern: &SamplePattern,
        binning: Binning,
        stats: &mut Stats,
    ) -> Drawn<'a> {
        let t = Instant::now();
        let meshes: Vec<Triangles> = instances
            .par_iter()
            .zip(diced.par_iter_mut())
            .map(|(inst, diced)| match (&inst.primitive, diced.take()) {
                (_, Some(diced)) => Triangles::Diced(diced),
                (Primitive::Parametric(surface), None) => {
                    let (nu, nv) = match surface.is_parallelogram() {
                        true => (1, 1),
                        false => segments_for(surface, SEGMENT_PX, SAG_PX, |p| {
                            camera.pixels_per_unit(inst.object_to_world.transform_point3(p))
                        }),
                    };
                    Triangles::Grid(grid(surface, nu, nv))
                }
                (Primitive::Mesh(mesh), None) => Triangles::Mesh(mesh),
            })
            .collect();
        let max_steps = meshes
            .iter()
            .map(|m| match m {
                Triangles::Grid(g) => Vec2::new(1.0 / g.segments.0 as f32, 1.0 / g.segments.1 as f32),
                Triangles::Mesh(_) | Triangles::Diced(_) => Vec2::ZERO,
            })
            .collect();
        stats.tessellate_ms += ms(t);
        let t = Instant::now();
        let first_triangles = first_triangles(instances, &meshes);
        let (triangles, parts) = setup_triangles(camera, pattern, instances, &meshes, &first_triangles, &binning);
        stats.triangles += triangles.len();
        stats.setup_ms += ms(t);
        let t = Instant::now();
        let bins = Bins::join(camera.width as usize, camera.height as usize, binning.tile_size, &parts);
        stats.bin_ms += ms(t);
        Drawn { meshes, max_steps, first_triangles, triangles, bins }
    }
}

/// Each primitive's first triangle's number within its object: the triangles of the object's earlier
/// primitives come first.
fn first_triangles(instances: &[Instance], meshes: &[Triangles]) -> Vec<u32> {
    let mut first = vec![0u32; instances.len()];
    for s in 1..instances.len() {
        if instances[s].object == instances[s - 1].object {
            first[s] = first[s - 1] + meshes[s - 1].triangles().len() as u32;
        }
    }
    first
}

/// Clips, projects and sets up every triangle, in parallel over chunks, keeping submission order; bins
/// them as `binning` asks while each is at hand (a second pass over a million records read them all from
/// memory again), each chunk's entries a part of the bins.
fn setup_triangles(
    camera: &Camera,
    pattern: &SamplePattern,
    instances: &[Instance],
    meshes: &[Triangles],
    first: &[u32],
    binning: &Binning,
) -> (Vec<ScreenTriangle>, Vec<BinPart>) {
    const CHUNK: usize = 8192;
    let projector = TriangleSetup::new(camera, pattern);
    let projected: Vec<ProjectedVertices> = instances
        .par_iter()
        .zip(meshes)
        .map(|(inst, mesh)| projector.project_vertices(mesh.positions(), mesh.uvs(), &inst.object_to_camera))
        .collect();
    // Curved surfaces' triangles along their outline on screen (not where (u,v) is affine on purpose).
    let outlines: Vec<Option<Vec<Outline>>> = instances
        .par_iter()
        .zip(meshes)
        .zip(&projected)
        .map(|((inst, mesh), vertices)| match (&inst.primitive, mesh) {
            (Primitive::Parametric(surface), Triangles::Grid(grid)) if !inst.affine => Some(outline_triangles(
                surface,
                grid,
                |k| vertices.camera[k as usize].clip.pos,
                camera.is_perspective(),
            )),
            _ => None,
        })
        .collect();
    let jobs: Vec<(usize, usize)> = meshes
        .iter()
        .enumerate()
        .flat_map(|(s, m)| (0..m.triangles().len()).step_by(CHUNK).map(move |start| (s, start)))
        .collect();
    // Each job's triangles are counted first and then written in place, into one vector: a million-triangle
    // mesh's setup writes a hundred megabytes, which collecting pieces and joining them wrote twice.
    let part = |&(s, start): &(usize, usize)| {
        let tris = meshes[s].triangles();
        let end = (start + CHUNK).min(tris.len());
        ProjectedMesh {
            vertices: &projected[s],
            triangles: &tris[start..end],
            surface: s as u32,
            first: first[s] + start as u32,
            cull: cull(&instances[s]),
            outline: outlines[s].as_ref().map(|o| &o[start..end]),
        }
    };
    let setup = || TriangleSetup::new(camera, pattern);
    let counts: Vec<Counted> = jobs.par_iter().map(|j| setup().count_triangles(part(j))).collect();
    let total = counts.iter().map(|c| c.count).sum();
    let mut triangles = triangle_buffer(total);
    let mut rest = &mut triangles.spare_capacity_mut()[..total];
    let mut places = Vec::with_capacity(jobs.len());
    let mut base = 0;
    for counted in &counts {
        let (place, after) = rest.split_at_mut(counted.count);
        places.push((place, base));
        rest = after;
        base += counted.count;
    }
    let width = camera.width as usize;
    let parts = jobs
        .par_iter()
        .zip(places)
        .zip(&counts)
        .map(|((j, (place, base)), counted)| {
            let mut bins = BinPart::new(width, binning.tile_size);
            let binned = binning.surfaces[j.0];
            setup().write_triangles(part(j), counted, place, |k, t| {
                if binned {
                    bins.add(t.bbox, (base + k) as u32);
                }
            });
            bins
        })
        .collect();
    // SAFETY: every job wrote exactly the `count` triangles of its place (`write_triangles` panics
    // otherwise, and a panic ends the frame before this line), and the places tile the first `total` slots.
    unsafe { triangles.set_len(total) };
    (triangles, parts)
}

/// Closed surfaces are never seen from inside: their triangles facing away are dropped.
fn cull(inst: &Instance) -> Cull {
    if inst.two_sided {
        Cull::Nothing
    } else {
        Cull::FacingAway { mirrored: inst.object_to_world.matrix3.determinant() < 0.0 }
    }
}

/// Everything one tile needs, shared by all tiles of a frame.
#[derive(Clone, Copy)]
struct TileJob<'a> {
    bins: &'a Bins,
    camera: &'a Camera,
    /// Per surface, the longest (u,v) step of the ray-exact refinement: one tessellation segment.
    max_steps: &'a [Vec2],
    /// Per surface, the number within its object of its first triangle.
    first_triangles: &'a [u32],
    triangles: &'a [ScreenTriangle],
    pattern: &'a SamplePattern,
    instances: &'a [Instance],
    shade: &'a ShadeContext<'a>,
    background: Vec3,
    aovs: Aovs,
    /// The side of one sample's cell of the pixel (1/sqrt(spp)), which scales its footprint.
    sample_cell: f32,
    /// Whether each triangle is shaded once per pixel (`ShadingRate::Pixel`) rather than every sample.
    per_pixel: bool,
    /// Where the samples read their textures (`RenderOptions::texel_location`).
    texel_location: TexelLocation,
    volumes: &'a [Hypertexture],
    /// The environment, where it is the background.
    sky: Option<&'a Environment>,
    lights: &'a [Light],
    /// Per surface, the alpha cutoff of its material where the alpha test applies.
    cutoffs: &'a [Option<f32>],
    /// Whether any surface is masked (else tiles skip the alpha test).
    any_masked: bool,
    /// Per surface, whether its depth is a parallax crossing's (depth replacement).
    replacing: &'a [bool],
    any_replacing: bool,
    /// Whether samples that the outline test finds on the exact surface take its depth (a shadow map's
    /// texels) or keep their triangle's, widened past the chord (a frame's, whose shading finds the depth).
    exact_depth: bool,
    /// The translucent triangles' bins, where there are any (`bins` holds the opaque ones).
    blend_bins: Option<&'a Bins>,
    transparency: Transparency,
    /// Per triangle, its place in sorted drawing (translucent ones; `Transparency::Sorted`).
    blend_order: &'a [u32],
}

impl<'a> TileJob<'a> {
    /// A job that finds what each sample of `drawn` sees (the outline, alpha and depth-replacement tests
    /// included), over no background, volumes or AOVs: what a shadow map needs; a frame adds the rest.
    #[allow(clippy::too_many_arguments)]
    fn visibility(
        drawn: &'a Drawn,
        bins: &'a Bins,
        camera: &'a Camera,
        pattern: &'a SamplePattern,
        instances: &'a [Instance],
        shade: &'a ShadeContext<'a>,
        cutoffs: &'a [Option<f32>],
        replacing: &'a [bool],
    ) -> TileJob<'a> {
        TileJob {
            bins,
            camera,
            max_steps: &drawn.max_steps,
            first_triangles: &drawn.first_triangles,
            triangles: &drawn.triangles,
            pattern,
            instances,
            shade,
            background: Vec3::ZERO,
            aovs: Aovs::default(),
            sample_cell: 1.0,
            per_pixel: false,
            texel_location: TexelLocation::Centre,
            volumes: &[],
            sky: None,
            lights: &[],
            cutoffs,
            any_masked: cutoffs.iter().any(Option::is_some),
            replacing,
            any_replacing: replacing.contains(&true),
            exact_depth: false,
            blend_bins: None,
            transparency: Transparency::default(),
            blend_order: &[],
        }
    }

    /// What the samples that see no object show, where the environment is the background: the environment
    /// along their rays, filtered over each ray's change across the sample's share of the pixel, eight at
    /// a time, into `sky` (by sample).
    fn sky_samples(&self, env: &Environment, vis: &VisBuffer, sky: &mut Vec<Vec3>) {
        sky.resize(vis.width * vis.height * vis.spp, Vec3::ZERO);
        let empty = (0..sky.len()).filter(|&k| vis.triangle[k] == EMPTY);
        let mut batch = [0usize; LANES];
        let mut len = 0;
        let flush = |batch: &[usize; LANES], len: usize, sky: &mut [Vec3]| {
            let screen = |i: usize| {
                let k = batch[i.min(len - 1)];
                vis.sample_position((k / vis.spp) % vis.width, k / vis.spp / vis.width, k % vis.spp)
            };
            let (sx, sy) =
                (F8::new(std::array::from_fn(|i| screen(i).x)), F8::new(std::array::from_fn(|i| screen(i).y)));
            let rays = self.camera.rays8(sx, sy, self.sample_cell);
            let to_world = &self.camera.camera_to_world;
            let c = V3::transform_vector(to_world, rays.dir);
            let inv = F8::ONE / c.length();
            let d = c * inv;
            // d(c / |c|) = (dc - d (d.dc)) / |c|
            let change = |dc: V3| {
                let dc = V3::transform_vector(to_world, dc);
                (dc - d * d.dot(dc)) * inv
            };
            let radiance = env.radiance8(&d, &change(rays.dx.1), &change(rays.dy.1));
            for i in 0..len {
                sky[batch[i]] = radiance.lane(i);
            }
        };
        for k in empty {
            batch[len] = k;
            len += 1;
            if len == LANES {
                flush(&batch, len, sky);
                len = 0;
            }
        }
        if len > 0 {
            flush(&batch, len, sky);
        }
    }

    /// The volumes in front of an opaque sample `depth` away (its distance along the ray; infinity for
    /// the background), composited over its colour; `screen` gives the sample's position, asked for only
    /// where there are volumes.
    #[inline]
    fn volume_pass(&self, screen: impl FnOnce() -> Vec2, depth: f32, behind: Vec3) -> Vec3 {
        if self.volumes.is_empty() {
            return behind;
        }
        let (origin, dir) = self.camera.ray(screen());
        self.volumes.iter().fold(behind, |c, v| v.composite(origin, dir, depth, c, self.lights))
    }

    /// Rasterizes, shades and resolves one tile into its band of the frame.
    fn tile(
        &self,
        scratch: &mut TileScratch,
        tile: (usize, usize),
        band: &mut [MaybeUninit<[f32; 3]>],
        aov: &mut frame::AovBand,
        w: usize,
        h: usize,
    ) {
        if self.bins.bin(tile).is_empty()
            && self.blend_bins.is_none_or(|b| b.bin(tile).is_empty())
            && self.volumes.is_empty()
            && self.sky.is_none()
        {
            // Nothing here: the background, and the AOVs keep their NaN.
            let x0 = tile.0 * self.bins.tile_size;
            let background = [self.background.to_array(); MAX_TILE];
            let width = self.bins.tile_size.min(w - x0);
            for row in band.chunks_exact_mut(w) {
                stream::copy_row(&mut row[x0..x0 + width], &background[..width]);
            }
            return;
        }
        scratch.vis.render_tile(self.bins, tile, (w, h), self.triangles, self.pattern);
        if self.any_masked || self.any_replacing || scratch.vis.outline {
            self.fix_visibility(scratch, tile);
        }
        let TileScratch { vis, shaded, sky, translucent, fragments, seen, source, nearest, .. } = scratch;
        if let Some(env) = self.sky {
            self.sky_samples(env, vis, sky);
        }
        // Shade every covered sample (or one of each triangle's in each pixel), eight of one surface at a
        // time, into the tile's sample buffer.
        let spp = vis.spp;
        // Only covered samples are read back, and each of them is written first: no clearing needed.
        shaded.resize(vis.width * vis.height * spp, Shaded::default());
        let mut packet = Packet::default();
        if self.per_pixel {
            source.resize(shaded.len(), 0);
            if let Some(offsets) = vis.shared_offsets() {
                nearest_first(offsets, nearest);
            }
        }
        for y in 0..vis.height {
            for x in 0..vis.width {
                let first = (y * vis.width + x) * spp;
                if self.per_pixel {
                    if vis.shared_offsets().is_none() {
                        nearest_first(vis.sample_offsets(x, y), nearest);
                    }
                    pixel_samples(vis, first, nearest, seen, source);
                    for &(t, s) in seen.iter() {
                        self.queue(vis, &mut packet, shaded, (first + s, t), vis.sample_position(x, y, s));
                    }
                    continue;
                }
                for s in 0..spp {
                    let t = vis.triangle[first + s];
                    if t != EMPTY {
                        self.queue(vis, &mut packet, shaded, (first + s, t), vis.sample_position(x, y, s));
                    }
                }
            }
        }
        if packet.len > 0 {
            self.shade_packet(vis, &mut packet, shaded);
        }
        if self.blend_bins.is_some() {
            let layers = translucent.get_or_insert_with(|| Box::new(TileScratch::new(self.bins.tile_size, spp)));
            self.translucent_fragments(layers, tile, (w, h), vis, fragments);
        }
        let samples = Samples {
            vis,
            shaded,
            source: self.per_pixel.then_some(&source[..]),
            sky: self.sky.map(|_| &sky[..]),
            background: self.background,
        };
        let signed = self.pattern.has_negative_weights();
        if !signed && self.volumes.is_empty() && fragments.is_empty() && !self.aovs.any() {
            self.resolve_plain(&samples, band, w);
            return;
        }
        // Resolve: each pixel's samples, weighted by the pixel filter's sign where it has negative lobes (the
        // samples were drawn in proportion to its magnitude).
        let inv_spp = 1.0 / spp as f32;
        let mut acc = frame::AovSample::default();
        let mut next_fragment = 0;
        for y in 0..vis.height {
            for x in 0..vis.width {
                let (mut sum, mut plain, mut weights) = (Vec3::ZERO, Vec3::ZERO, 0.0);
                acc.clear();
                for s in 0..spp {
                    let k = (y * vis.width + x) * spp + s;
                    let screen = || vis.sample_position(x, y, s);
                    let weight = if signed { vis.sample_weight(x, y, s, self.pattern) } else { 1.0 };
                    let covered = vis.triangle[k] != EMPTY;
                    let seen = if covered {
                        let sample = samples.shading(k);
                        if self.aovs.any() {
                            acc.add(&sample.shaded, sample.uv, sample.object, sample.triangle, weight);
                        }
                        self.volume_pass(screen, sample.shaded.depth, sample.shaded.color)
                    } else {
                        self.volume_pass(screen, f32::INFINITY, samples.behind(k))
                    };
                    let (seen, next) =
                        transparent::composite(fragments, next_fragment, k, seen, covered, weight, &mut acc);
                    next_fragment = next;
                    if signed {
                        sum += seen * weight;
                        plain += seen;
                        weights += weight;
                    } else {
                        sum += seen;
                    }
                }
                // Negative samples that cancel the positive ones exactly leave no weight: the plain mean then.
                let (color, share, weighted) = match signed {
                    false => (sum * inv_spp, inv_spp, false),
                    true if weights != 0.0 => (sum / weights, 1.0 / weights, true),
                    true => (plain * inv_spp, inv_spp, false),
                };
                let i = (y * w) + vis.x0 + x;
                band[i].write(color.to_array());
                if self.aovs.any() {
                    aov.set(i, &acc, share, weighted);
                }
            }
        }
    }

    /// The resolve of a tile with nothing but opaque samples to average (no volumes, translucent fragments,
    /// AOVs or negative filter weights): the full resolve's arithmetic on the colours alone, in a loop a
    /// quarter of its length (3% of the canonical frame).
    fn resolve_plain(&self, samples: &Samples<'_>, band: &mut [MaybeUninit<[f32; 3]>], w: usize) {
        let vis = samples.vis;
        let spp = vis.spp;
        let inv_spp = 1.0 / spp as f32;
        let seen = |k: usize| match vis.triangle[k] {
            EMPTY => samples.behind(k),
            _ => samples.shading(k).shaded.color,
        };
        let mut row = [[0.0; 3]; MAX_TILE];
        for y in 0..vis.height {
            for (x, pixel) in row[..vis.width].iter_mut().enumerate() {
                let first = (y * vis.width + x) * spp;
                *pixel = ((first..first + spp).fold(Vec3::ZERO, |sum, k| sum + seen(k)) * inv_spp).to_array();
            }
            stream::copy_row(&mut band[y * w + vis.x0..][..vis.width], &row[..vis.width]);
        }
    }

    /// Interpolates and refines the packet's samples and hands them to `then` with their instance.
    #[inline(always)]
    fn with_samples<R>(
        &self,
        vis: &VisBuffer,
        packet: &Packet,
        then: impl FnOnce(&Instance, &SurfaceSamples8<'_>) -> R,
    ) -> R {
        let inst = &self.instances[packet.surface as usize];
        let (samples, tris, (sx, sy)) = self.lanes_of(packet);
        // Each of the spp stratified samples stands for its own 1/spp of the pixel: the texture filters
        // integrate over that cell, not the whole pixel again.
        let triangles = tris.map(|t| t.triangle);
        // Each primitive's frame stays where it was made; the shader borrows it (one call site, no copies).
        let (parametric, mesh_sample);
        let samples = match &inst.primitive {
            Primitive::Parametric(surface) => {
                let at = interpolate8(&tris, sx, sy);
                let max_step = self.max_steps[packet.surface as usize];
                // Affine (u,v) name the surface off the sample's ray: no step moves them onto it. Nor do
                // diced ones (no steps): the ray meets the displaced surface, not P(u,v).
                let uv = match inst.affine {
                    true => affine_uv8(self.camera, surface, &inst.object_to_camera, &tris, (sx, sy)),
                    false => at.uv,
                };
                let (mut uv, mut frame) = match inst.affine || max_step == Vec2::ZERO {
                    true => (uv, surface.frame8(uv.0, uv.1)),
                    false => refine_uv8(self.camera, surface, &inst.object_to_camera, uv, (sx, sy), max_step),
                };
                let mut duv = at.duv;
                // Along the outline the exact surface's point on the ray replaces the one Newton step.
                let outline = if vis.outline { tested_lanes(tris.map(|t| t.outline), at.bary, packet.len) } else { 0 };
                if outline != 0 {
                    // The outline test (fix_visibility) found these lanes' (u,v).
                    let exact = |c: usize| F8::new(samples.map(|k| vis.exact_uv[k][c]));
                    let mask = mask_of(outline);
                    uv = (mask.blend(exact(0), uv.0), mask.blend(exact(1), uv.1));
                    let (exact_frame, exact_duv) = frames_at(self.camera, surface, &inst.object_to_camera, uv, outline);
                    frame = Frame8::select(mask, &exact_frame, &frame);
                    duv = std::array::from_fn(|k| mask.blend(exact_duv[k], duv[k]));
                }
                let [dudx, dvdx, dudy, dvdy] = duv.map(|d| d * F8::splat(self.sample_cell));
                let mut footprint = Footprint8 { dudx, dvdx, dudy, dvdy };
                if self.texel_location != TexelLocation::Centre {
                    let rays = self.camera.rays8(sx, sy, self.sample_cell).transformed(&inst.camera_to_object);
                    (uv, footprint) = self.texel_location.locate8(&rays, frame.p, frame.pu, frame.pv, uv, footprint);
                }
                parametric = (uv, frame);
                SurfaceSamples8 { frame: &parametric.1, uv: parametric.0, footprint, uv1: None, triangles, mesh: None }
            }
            Primitive::Mesh(mesh) => {
                // The mesh's own triangle numbers: the object's numbering less its earlier primitives'.
                let first = self.first_triangles[packet.surface as usize];
                let local = triangles.map(|t| t - first);
                let rays = self.camera.rays8(sx, sy, self.sample_cell).transformed(&inst.camera_to_object);
                let second_set = self.shade.needs[inst.material].second_uv;
                mesh_sample = mesh_lanes::sample8(mesh, &local, &rays, second_set);
                let m = &mesh_sample;
                let (uv, footprint) =
                    self.texel_location.locate8(&rays, m.frame.p, m.frame.pu, m.frame.pv, m.uv, m.footprint);
                SurfaceSamples8 {
                    frame: &m.frame,
                    uv,
                    footprint,
                    uv1: m.uv1.as_ref(),
                    triangles,
                    mesh: Some(&m.orientation),
                }
            }
        };
        then(inst, &samples)
    }

    /// The packet's samples, triangles and screen positions on lanes; unused lanes repeat the first sample
    /// (their results are dropped).
    #[inline(always)]
    fn lanes_of(&self, packet: &Packet) -> ([usize; LANES], [&ScreenTriangle; LANES], (F8, F8)) {
        let used = |i: usize| if i < packet.len { i } else { 0 };
        let samples = std::array::from_fn(|i| packet.samples[used(i)]);
        let tris = std::array::from_fn(|i| &self.triangles[packet.triangles[used(i)] as usize]);
        let screen = |c: fn(Vec2) -> f32| F8::new(std::array::from_fn(|i| c(packet.screen[used(i)])));
        (samples, tris, (screen(|p| p.x), screen(|p| p.y)))
    }

    /// The outline test of the tile's samples `candidates` that lie on outline triangles: those whose ray
    /// misses the exact surface are pushed onto `missed`; for the others the (u,v) where it meets the
    /// surface is kept in `vis.exact_uv` for the shader.
    fn outline_test(&self, vis: &mut VisBuffer, candidates: &[usize], missed: &mut Vec<usize>) {
        self.packets_of(
            vis,
            candidates,
            &[],
            |t| t.outline != Outline::Inside,
            |vis, packet| {
                let inst = &self.instances[packet.surface as usize];
                let Primitive::Parametric(surface) = &inst.primitive else { unreachable!("outlines are of surfaces") };
                let (_, tris, screen) = self.lanes_of(packet);
                let at = interpolate8(&tris, screen.0, screen.1);
                let max_step = self.max_steps[packet.surface as usize];
                let tested = tested_lanes(tris.map(|t| t.outline), at.bary, packet.len);
                if tested == 0 {
                    return;
                }
                let start = start_within(at.uv, &tris.map(|t| t.uv));
                let (to_camera, to_object) = (&inst.object_to_camera, &inst.camera_to_object);
                let (hits, (u, v)) =
                    exact8(self.camera, surface, to_camera, to_object, start, screen, max_step, tested);
                let key = self.exact_depth.then(|| {
                    let p = V3::transform_point(to_camera, surface.frame8(u, v).p);
                    if self.camera.is_perspective() { F8::ONE / -p.z } else { p.z }.to_array()
                });
                let (u, v) = (u.as_array_ref(), v.as_array_ref());
                for i in 0..packet.len {
                    let k = packet.samples[i];
                    if (tested & !hits) >> i & 1 == 1 {
                        missed.push(k);
                    } else if tested >> i & 1 == 1 {
                        vis.exact_uv[k] = [u[i], v[i]];
                        if let Some(key) = key {
                            vis.depth[k] = key[i];
                        }
                    }
                }
            },
        );
    }

    /// Adds sample `k` (tile index) on triangle `t`, at `screen`, to the packet, shading the packet first
    /// where the sample is of another surface and after it where it is full.
    fn queue(
        &self,
        vis: &mut VisBuffer,
        packet: &mut Packet,
        shaded: &mut [Shaded],
        (k, t): (usize, u32),
        screen: Vec2,
    ) {
        let surface = self.triangles[t as usize].surface;
        if packet.len > 0 && packet.surface != surface {
            self.shade_packet(vis, packet, shaded);
        }
        packet.push(surface, k, t, screen);
        if packet.len == LANES {
            self.shade_packet(vis, packet, shaded);
        }
    }

    /// Interpolates, refines and shades the packet's samples, and empties it.
    fn shade_packet(&self, vis: &mut VisBuffer, packet: &mut Packet, shaded: &mut [Shaded]) {
        let (result, object) = self.with_samples(vis, packet, |inst, at| (self.shade.shade8(inst, at), inst.object));
        let uv = result.uv;
        for i in 0..packet.len {
            let uv = Vec2::new(uv.0.as_array_ref()[i], uv.1.as_array_ref()[i]);
            let triangle = self.triangles[packet.triangles[i] as usize].triangle;
            shaded[packet.samples[i]] = Shaded { shaded: result.lane(i), uv, object, triangle };
        }
        packet.len = 0;
    }

    /// Calls `each` on packets of the samples `candidates` (less those in `skip`, a subsequence of them)
    /// whose fragment's triangle is `wanted`, eight of one surface at a time.
    fn packets_of(
        &self,
        vis: &mut VisBuffer,
        candidates: &[usize],
        skip: &[usize],
        wanted: impl Fn(&ScreenTriangle) -> bool,
        mut each: impl FnMut(&mut VisBuffer, &Packet),
    ) {
        let mut packet = Packet::default();
        let mut flush = |vis: &mut VisBuffer, packet: &mut Packet| {
            each(vis, packet);
            packet.len = 0;
        };
        let (spp, mut skipped) = (vis.spp, skip.iter().peekable());
        for &k in candidates {
            if skipped.next_if_eq(&&k).is_some() {
                continue;
            }
            let t = vis.triangle[k];
            if t == EMPTY || !wanted(&self.triangles[t as usize]) {
                continue;
            }
            let surface = self.triangles[t as usize].surface;
            if packet.len > 0 && packet.surface != surface {
                flush(vis, &mut packet);
            }
            let (x, y) = ((k / spp) % vis.width, k / spp / vis.width);
            packet.push(surface, k, t, vis.sample_position(x, y, k % spp));
            if packet.len == LANES {
                flush(vis, &mut packet);
            }
        }
        if packet.len > 0 {
            flush(vis, &mut packet);
        }
    }

    /// The alpha test of the tile's samples `candidates` (less those in `skip`) whose surfaces are masked:
    /// those whose alpha is below their material's cutoff are pushed onto `refused`.
    fn alpha_test(&self, vis: &mut VisBuffer, candidates: &[usize], skip: &[usize], refused: &mut Vec<usize>) {
        self.packets_of(
            vis,
            candidates,
            skip,
            |t| self.cutoffs[t.surface as usize].is_some(),
            |vis, packet| {
                let cutoff = self.cutoffs[packet.surface as usize].expect("only masked surfaces are queued");
                let alpha = self.with_samples(vis, packet, |inst, at| self.shade.alpha8(inst, at));
                let alpha = alpha.as_array_ref();
                refused.extend((0..packet.len).filter(|&i| alpha[i] < cutoff).map(|i| packet.samples[i]));
            },
        );
    }

    /// Where the samples `candidates` (less the `refused`) lie on surfaces that replace their depth by a
    /// parallax crossing: each such fragment, its key, and the key of the crossing behind it.
    fn replaced_depths(&self, vis: &mut VisBuffer, candidates: &[usize], refused: &[usize], out: &mut Vec<Replaced>) {
        let ortho = !self.camera.is_perspective();
        self.packets_of(
            vis,
            candidates,
            refused,
            |t| self.replacing[t.surface as usize],
            |vis, packet| {
                let found = self.with_samples(vis, packet, |inst, at| {
                    let distance = V3::transform_point(&inst.object_to_camera, at.frame.p).length();
                    self.shade.replaced_depth8(inst, at).map(|travel| (travel, distance))
                });
                let Some((travel, distance)) = found else { return };
                let (travel, distance) = (travel.as_array_ref(), distance.as_array_ref());
                for i in 0..packet.len {
                    let k = packet.samples[i];
                    let key = vis.depth[k];
                    // Depth keys: camera z for orthographic views, 1/w (w in proportion to the distance along
                    // the ray) for perspective ones.
                    let behind = if ortho { key - travel[i] } else { key * distance[i] / (distance[i] + travel[i]) };
                    if travel[i] > 0.0 {
                        out.push(Replaced { sample: k, key, triangle: vis.triangle[k], behind });
                    }
                }
            },
        );
    }

    /// Fixes the tile's visibility where the surface is not the flat triangle: samples whose ray misses the
    /// exact surface along its outline, and samples the alpha test refuses, are peeled back to the next
    /// fragment behind and tested again, until every sample keeps its fragment; samples of depth-replacing
    /// parallax surfaces are peeled too, and keep what lies behind only where it is in front of their
    /// crossing. Out of line: most tiles never call it, and the tile loop keeps its registers.
    #[inline(never)]
    fn fix_visibility(&self, scratch: &mut TileScratch, tile: (usize, usize)) {
        let TileScratch { vis, candidates, missed, refused, replaced, .. } = scratch;
        let fixed = |t: &ScreenTriangle| {
            let s = t.surface as usize;
            t.outline != Outline::Inside || self.cutoffs[s].is_some() || self.replacing[s]
        };
        candidates.clear();
        candidates.extend(
            (0..vis.width * vis.height * vis.spp)
                .filter(|&k| vis.triangle[k] != EMPTY && fixed(&self.triangles[vis.triangle[k] as usize])),
        );
        loop {
            missed.clear();
            refused.clear();
            replaced.clear();
            // In order, so that what each test takes out is a subsequence of the candidates.
            candidates.sort_unstable();
            if vis.outline {
                self.outline_test(vis, candidates, missed);
            }
            self.alpha_test(vis, candidates, missed, refused);
            refused.extend_from_slice(missed);
            refused.sort_unstable();
            if self.any_replacing {
                self.replaced_depths(vis, candidates, refused, replaced);
            }
            if refused.is_empty() && replaced.is_empty() {
                return;
            }
            refused.extend(replaced.iter().map(|r| r.sample));
            vis.peel(self.bins, tile, self.triangles, refused);
            refused.truncate(refused.len() - replaced.len());
            for r in replaced.iter() {
                // Nothing in front of the crossing: the parallax surface keeps the sample, at the crossing.
                if vis.triangle[r.sample] == EMPTY || vis.depth[r.sample] < r.behind {
                    (vis.depth[r.sample], vis.triangle[r.sample]) = (r.key, r.triangle);
                } else {
                    refused.push(r.sample);
                }
            }
            std::mem::swap(candidates, refused);
        }
    }
}

/// A sample of a depth-replacing parallax surface: its fragment (depth key and triangle), and the key of
/// its crossing behind it.
struct Replaced {
    sample: usize,
    key: f32,
    triangle: u32,
    behind: f32,
}

/// One worker's buffers, reused from tile to tile: the visibility buffer, the shaded samples, the
/// background's samples, and the visibility fix-ups' lists of samples.
struct TileScratch {
    vis: VisBuffer,
    shaded: Vec<Shaded>,
    /// The environment behind each sample that sees no object.
    sky: Vec<Vec3>,
    candidates: Vec<usize>,
    missed: Vec<usize>,
    refused: Vec<usize>,
    replaced: Vec<Replaced>,
    /// The transparent pass's own buffers (its layers of fragments), made on first use.
    translucent: Option<Box<TileScratch>>,
    /// The tile's translucent fragments, in compositing order.
    fragments: Vec<transparent::Fragment>,
    /// Per sample, the surface and distance of the transparent pass's last fragment there.
    last: Vec<(u32, f32)>,
    /// Shaded once per pixel: the triangles seen in the pixel at hand, each with its chosen sample.
    seen: Vec<(u32, usize)>,
    /// Shaded once per pixel: per sample, the tile index of the sample whose shading it takes.
    source: Vec<u32>,
    /// Shaded once per pixel: the numbers of a pixel's samples, nearest its centre first.
    nearest: Vec<usize>,
}

impl TileScratch {
    fn new(tile_size: usize, spp: usize) -> TileScratch {
        TileScratch {
            vis: VisBuffer::new(tile_size, spp),
            shaded: Vec::new(),
            sky: Vec::new(),
            candidates: Vec::new(),
            missed: Vec::new(),
            refused: Vec::new(),
            replaced: Vec::new(),
            translucent: None,
            fragments: Vec::new(),
            last: Vec::new(),
            seen: Vec::new(),
            source: Vec::new(),
            nearest: Vec::new(),
        }
    }
}

/// Up to eight covered samples of one surface, waiting to be shaded together.
#[derive(Default)]
struct Packet {
    surface: u32,
    len: usize,
    /// Index of each sample in the tile's buffers.
    samples: [usize; LANES],
    triangles: [u32; LANES],
    screen: [Vec2; LANES],
}

impl Packet {
    fn push(&mut self, surface: u32, k: usize, triangle: u32, screen: Vec2) {
        self.surface = surface;
        (self.samples[self.len], self.triangles[self.len], self.screen[self.len]) = (k, triangle, screen);
        self.len += 1;
    }
}

/// The numbers of a pixel's samples at `offsets` (from its top-left corner), nearest its centre first.
fn nearest_first(offsets: &[[i64; 2]], order: &mut Vec<usize>) {
    let half = SUBPIXEL / 2;
    let distance = |s: usize| (offsets[s][0] - half).pow(2) + (offsets[s][1] - half).pow(2);
    order.clear();
    order.extend(0..offsets.len());
    order.sort_by_key(|&s| (distance(s), s));
}

/// The triangles seen in the tile's pixel whose first sample is `first`, each with its covered sample
/// nearest the pixel's centre (taken in the order `nearest`), into `seen`; and for every covered sample of
/// the pixel, the tile index of its triangle's chosen sample, into `source`.
fn pixel_samples(vis: &VisBuffer, first: usize, nearest: &[usize], seen: &mut Vec<(u32, usize)>, source: &mut [u32]) {
    seen.clear();
    for &s in nearest {
        let t = vis.triangle[first + s];
        if t == EMPTY {
            continue;
        }
        let chosen = match seen.iter().find(|&&(seen, _)| seen == t) {
            Some(&(_, chosen)) => chosen,
            None => {
                seen.push((t, s));
                s
            }
        };
        source[first + s] = (first + chosen) as u32;
    }
}

/// A tile's samples once shaded: which triangle each sees (`vis`), their shading (`shaded`, through
/// `source` where each triangle is shaded once per pixel) and what the empty ones see: the environment
/// along their rays (`sky`, where it is the background), else the background colour.
struct Samples<'a> {
    vis: &'a VisBuffer,
    shaded: &'a [Shaded],
    source: Option<&'a [u32]>,
    sky: Option<&'a [Vec3]>,
    background: Vec3,
}

impl Samples<'_> {
    /// The shading covered sample `k` shows: its own, or shaded once per pixel, its triangle's chosen
    /// sample's.
    #[inline]
    fn shading(&self, k: usize) -> &Shaded {
        &self.shaded[self.source.map_or(k, |source| source[k] as usize)]
    }

    /// What empty sample `k` sees.
    #[inline]
    fn behind(&self, k: usize) -> Vec3 {
        self.sky.map_or(self.background, |sky| sky[k])
    }
}

/// One shaded sample of a tile, kept until its pixel is resolved.
#[derive(Clone, Copy, Default)]
struct Shaded {
    shaded: ShadedSample,
    uv: Vec2,
    object: u32,
    /// The triangle within its object.
    triangle: u32,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The bins made while the triangles are set up are those that binning the set-up triangles afterwards
    /// gives, the surfaces left out included: on the teapot's 32 patches and on its mesh.
    #[test]
    fn bins_made_during_setup_are_those_of_the_triangles_set_up() {
        let scenes = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
        for name in ["teapot.toml", "teapot_mesh.toml"] {
            let scene = Scene::load(&scenes.join(name)).unwrap();
            let (w, h, tile_size) = (301, 203, 16);
            let camera = scene.camera.screen(w, h);
            let instances = instances(&scene, &camera, 0.0);
            let surfaces: Vec<bool> = (0..instances.len()).map(|s| s % 3 != 1).collect();
            let diced = instances.iter().map(|_| None).collect();
            let binning = Binning { tile_size, surfaces: &surfaces };
            let drawn =
                Drawn::new(&instances, diced, &camera, &SamplePattern::centre(), binning, &mut Stats::default());
            assert!(drawn.triangles.len() > 100, "{} triangles", drawn.triangles.len());
            let after = Bins::of(&drawn.triangles, w, h, tile_size, |t| surfaces[t.surface as usize]);
            let (tiles_x, tiles_y) = (after.tiles_x, after.tiles_y);
            assert_eq!((drawn.bins.tiles_x, drawn.bins.tiles_y), (tiles_x, tiles_y));
            for tile in (0..tiles_y).flat_map(|ty| (0..tiles_x).map(move |tx| (tx, ty))) {
                assert_eq!(drawn.bins.bin(tile), after.bin(tile), "tile {tile:?}");
            }
        }
    }
}
