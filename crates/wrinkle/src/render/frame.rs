//! A rendered frame: linear RGB and the optional AOVs (normal, uv, depth, id, primitive), with stage
//! timings.

use crate::image::color::SrgbEncoder;
use crate::image::io::Placement;
use crate::shade::ShadedSample;
use glam::{Vec2, Vec3};
use rayon::prelude::*;

/// Which AOVs to keep. Background pixels hold NaN in every AOV (alpha: 0).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Aovs {
    pub normal: bool,
    pub uv: bool,
    pub depth: bool,
    pub id: bool,
    pub primitive: bool,
    /// Coverage: the share of the pixel's samples that see an object.
    pub alpha: bool,
}

impl Aovs {
    /// Bytes a frame with these AOVs holds per pixel, doubled for the copies that encoding and writing make.
    pub fn bytes_per_pixel(&self) -> u64 {
        let aov = |on: bool, bytes: u64| if on { bytes } else { 0 };
        2 * (12
            + aov(self.normal, 12)
            + aov(self.uv, 8)
            + aov(self.depth, 4)
            + aov(self.id, 4)
            + aov(self.primitive, 8)
            + aov(self.alpha, 4))
    }

    pub fn any(&self) -> bool {
        self.normal || self.uv || self.depth || self.id || self.primitive || self.alpha
    }
}

/// What the primitive AOV holds where no object is seen.
pub const NO_PRIMITIVE: [u32; 2] = [u32::MAX; 2];

/// Wall time of each stage of one frame, milliseconds (raster, shade and resolve run together, in parallel).
#[derive(Clone, Copy, Debug, Default)]
pub struct Stats {
    pub tessellate_ms: f64,
    pub setup_ms: f64,
    pub bin_ms: f64,
    pub raster_shade_ms: f64,
    /// Rendering the lights' shadow maps.
    pub shadow_ms: f64,
    pub triangles: usize,
}

pub struct Frame {
    pub width: usize,
    pub height: usize,
    /// Linear RGB, row 0 at the top.
    pub color: Vec<[f32; 3]>,
    /// Unit shading normal N' in world space (the mean of the pixel's covered samples, made unit).
    pub normal: Option<Vec<[f32; 3]>>,
    /// (u,v) before replication.
    pub uv: Option<Vec<[f32; 2]>>,
    /// Distance from the eye.
    pub depth: Option<Vec<f32>>,
    /// The index in the scene file of the object that covers most of the pixel's samples.
    pub id: Option<Vec<f32>>,
    /// The item buffer: (object, triangle within the object) of the object that covers most of the pixel's
    /// samples, the triangle of its first covered sample; `NO_PRIMITIVE` where none is.
    pub primitive: Option<Vec<[u32; 2]>>,
    /// Coverage, 0 to 1 (where asked: a transparent background); the colour is premultiplied by it.
    pub alpha: Option<Vec<f32>>,
    /// Where the pixels lie in the whole frame: all of it, or the crop.
    pub placement: Placement,
    pub stats: Stats,
}

impl Frame {
    /// A frame of `background`, filled by all workers: one thread's fill (calloc's memset, as the allocator
    /// hands back the last frame's memory) was a few milliseconds of every frame's serial time.
    pub fn new(width: usize, height: usize, aovs: Aovs, background: Vec3) -> Frame {
        let mut color = Vec::with_capacity(width * height);
        color.par_extend(rayon::iter::repeat_n(background.to_array(), width * height));
        Frame::with_color(width, height, aovs, color)
    }

    /// A frame of the pixels `color` (row by row, `width` x `height` of them), its AOVs still empty.
    pub fn with_color(width: usize, height: usize, aovs: Aovs, color: Vec<[f32; 3]>) -> Frame {
        let n = width * height;
        assert_eq!(color.len(), n, "a frame's colour has a pixel for each of its width x height");
        Frame {
            width,
            height,
            color,
            normal: aovs.normal.then(|| vec![[f32::NAN; 3]; n]),
            uv: aovs.uv.then(|| vec![[f32::NAN; 2]; n]),
            depth: aovs.depth.then(|| vec![f32::NAN; n]),
            id: aovs.id.then(|| vec![f32::NAN; n]),
            primitive: aovs.primitive.then(|| vec![NO_PRIMITIVE; n]),
            alpha: aovs.alpha.then(|| vec![0.0; n]),
            placement: Placement::whole(width, height),
            stats: Stats::default(),
        }
    }

    /// The linear RGB as 8-bit sRGB bytes, three a pixel, row 0 at the top (what a PNG of the frame holds).
    pub fn srgb8(&self) -> Vec<u8> {
        let enc = SrgbEncoder::new();
        let mut out = vec![0u8; self.width * self.height * 3];
        out.par_chunks_mut(self.width * 3).zip(self.color.par_chunks(self.width)).for_each(|(dst, src)| {
            for (d, s) in dst.chunks_exact_mut(3).zip(src) {
                d[0] = enc.encode(s[0]);
                d[1] = enc.encode(s[1]);
                d[2] = enc.encode(s[2]);
            }
        });
        out
    }

    /// The AOVs the frame holds.
    pub fn aovs(&self) -> Aovs {
        Aovs {
            normal: self.normal.is_some(),
            uv: self.uv.is_some(),
            depth: self.depth.is_some(),
            id: self.id.is_some(),
            primitive: self.primitive.is_some(),
            alpha: self.alpha.is_some(),
        }
    }

    /// Copies `part`'s pixels, its colour and every AOV both frames hold, into this frame with its top left
    /// at (x0, y0): how the tiles of a frame rendered in parts (crops) are assembled.
    pub fn paste(&mut self, part: &Frame, x0: usize, y0: usize) {
        assert!(x0 + part.width <= self.width && y0 + part.height <= self.height, "the part lies outside the frame");
        // Row by row, for buffers of any pixel type; an AOV only where both frames hold it.
        struct At {
            width: usize,
            part_width: usize,
            x0: usize,
            y0: usize,
        }
        impl At {
            fn paste<T: Copy>(&self, dst: &mut [T], src: &[T]) {
                for (r, row) in src.chunks_exact(self.part_width).enumerate() {
                    let start = (self.y0 + r) * self.width + self.x0;
                    dst[start..start + self.part_width].copy_from_slice(row);
                }
            }
            fn paste_aov<T: Copy>(&self, dst: &mut Option<Vec<T>>, src: &Option<Vec<T>>) {
                if let (Some(d), Some(s)) = (dst, src) {
                    self.paste(d, s);
                }
            }
        }
        let at = At { width: self.width, part_width: part.width, x0, y0 };
        at.paste(&mut self.color, &part.color);
        at.paste_aov(&mut self.normal, &part.normal);
        at.paste_aov(&mut self.uv, &part.uv);
        at.paste_aov(&mut self.depth, &part.depth);
        at.paste_aov(&mut self.id, &part.id);
        at.paste_aov(&mut self.primitive, &part.primitive);
        at.paste_aov(&mut self.alpha, &part.alpha);
    }

    /// Copies the bands' AOVs (in band order) into the frame.
    pub(super) fn gather_aovs(&mut self, bands: Vec<AovBand>) {
        fn gather<T: Copy>(dst: &mut Option<Vec<T>>, parts: impl Iterator<Item = Vec<T>>) {
            if let Some(d) = dst {
                let mut at = 0;
                for p in parts {
                    d[at..at + p.len()].copy_from_slice(&p);
                    at += p.len();
                }
            }
        }
        if !bands.iter().any(|b| b.kinds.any()) {
            return;
        }
        let mut bands = bands;
        gather(&mut self.normal, bands.iter_mut().map(|b| std::mem::take(&mut b.normal)));
        gather(&mut self.uv, bands.iter_mut().map(|b| std::mem::take(&mut b.uv)));
        gather(&mut self.depth, bands.iter_mut().map(|b| std::mem::take(&mut b.depth)));
        gather(&mut self.id, bands.iter_mut().map(|b| std::mem::take(&mut b.id)));
        gather(&mut self.primitive, bands.iter_mut().map(|b| std::mem::take(&mut b.primitive)));
        gather(&mut self.alpha, bands.iter_mut().map(|b| std::mem::take(&mut b.alpha)));
    }
}

/// The covered samples of one pixel, for the AOVs.
#[derive(Default)]
pub(super) struct AovSample {
    count: u32,
    /// The samples' alpha summed, each by its weight: 1 for each covered one, what translucent surfaces
    /// cover of the others; and the same unweighted.
    coverage: f32,
    coverage_unweighted: f32,
    normal: Vec3,
    uv: Vec2,
    depth: f32,
    /// (object, samples, first triangle) of the objects seen, so the pixel's id is one of them, not a blend.
    objects: Vec<(u32, u32, u32)>,
}

impl AovSample {
    pub fn clear(&mut self) {
        self.count = 0;
        self.coverage = 0.0;
        self.coverage_unweighted = 0.0;
        self.normal = Vec3::ZERO;
        self.uv = Vec2::ZERO;
        self.depth = 0.0;
        self.objects.clear();
    }

    /// Adds a covered sample of weight `weight` (the pixel filter's sign there).
    pub fn add(&mut self, s: &ShadedSample, uv: Vec2, object: u32, triangle: u32, weight: f32) {
        self.count += 1;
        self.coverage += weight;
        self.coverage_unweighted += 1.0;
        self.normal += s.normal;
        self.uv += uv;
        self.depth += s.depth;
        match self.objects.iter_mut().find(|(o, _, _)| *o == object) {
            Some((_, n, _)) => *n += 1,
            None => self.objects.push((object, 1, triangle)),
        }
    }

    /// Adds what translucent surfaces cover of a sample no opaque surface covers, times its weight.
    pub fn cover(&mut self, alpha: f32, weight: f32) {
        self.coverage += alpha * weight;
        self.coverage_unweighted += alpha;
    }

    /// The object covering most of the pixel's samples (the lower index on a tie) and its first triangle.
    fn primitive(&self) -> [u32; 2] {
        self.objects.iter().max_by_key(|&&(o, n, _)| (n, std::cmp::Reverse(o))).map_or([0, 0], |&(o, _, t)| [o, t])
    }
}

/// The AOVs of one band of tiles.
pub(super) struct AovBand {
    kinds: Aovs,
    normal: Vec<[f32; 3]>,
    uv: Vec<[f32; 2]>,
    depth: Vec<f32>,
    id: Vec<f32>,
    primitive: Vec<[u32; 2]>,
    alpha: Vec<f32>,
}

impl AovBand {
    pub fn new(kinds: Aovs, n: usize) -> AovBand {
        let sized = |on: bool, n: usize| if on { n } else { 0 };
        AovBand {
            kinds,
            normal: vec![[f32::NAN; 3]; sized(kinds.normal, n)],
            uv: vec![[f32::NAN; 2]; sized(kinds.uv, n)],
            depth: vec![f32::NAN; sized(kinds.depth, n)],
            id: vec![f32::NAN; sized(kinds.id, n)],
            primitive: vec![NO_PRIMITIVE; sized(kinds.primitive, n)],
            alpha: vec![0.0; sized(kinds.alpha, n)],
        }
    }

    /// The AOVs of rows `rows` and columns `x0..x0 + width` of this band, `band_width` pixels wide.
    pub fn cropped(&self, rows: std::ops::Range<usize>, x0: usize, width: usize, band_width: usize) -> AovBand {
        fn cut<T: Copy>(v: &[T], rows: &std::ops::Range<usize>, x0: usize, width: usize, band_width: usize) -> Vec<T> {
            match v.is_empty() {
                true => Vec::new(),
                false => {
                    rows.clone().flat_map(|r| &v[r * band_width + x0..r * band_width + x0 + width]).copied().collect()
                }
            }
        }
        AovBand {
            kinds: self.kinds,
            normal: cut(&self.normal, &rows, x0, width, band_width),
            uv: cut(&self.uv, &rows, x0, width, band_width),
            depth: cut(&self.depth, &rows, x0, width, band_width),
            id: cut(&self.id, &rows, x0, width, band_width),
            primitive: cut(&self.primitive, &rows, x0, width, band_width),
            alpha: cut(&self.alpha, &rows, x0, width, band_width),
        }
    }

    /// Stores the pixel's AOVs from its covered samples (NaN stays where none was covered): the mean uv and
    /// depth, the mean normal made unit again, and the id of the object that covers most samples. Alpha is
    /// the coverage weighted (`weighted`) or not, times `share`: 1 / the weights' sum, or 1 / the samples.
    pub fn set(&mut self, i: usize, s: &AovSample, share: f32, weighted: bool) {
        if self.kinds.alpha {
            self.alpha[i] = if weighted { s.coverage } else { s.coverage_unweighted } * share;
        }
        if s.count == 0 {
            return;
        }
        let k = 1.0 / s.count as f32;
        if self.kinds.normal {
            self.normal[i] = s.normal.normalize_or_zero().to_array();
        }
        if self.kinds.uv {
            self.uv[i] = (s.uv * k).to_array();
        }
        if self.kinds.depth {
            self.depth[i] = s.depth * k;
        }
        if self.kinds.id {
            self.id[i] = s.primitive()[0] as f32;
        }
        if self.kinds.primitive {
            self.primitive[i] = s.primitive();
        }
    }
}
