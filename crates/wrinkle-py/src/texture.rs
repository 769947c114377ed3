//! A filtered colour texture over arrays of lookups: every filter of the course by name.

use crate::arrays::{flatten, output, shape, slice};
use crate::errors::invalid;
use glam::{Vec2, Vec4};
use numpy::{PyArrayDyn, PyReadonlyArrayDyn};
use pyo3::prelude::*;
use rayon::prelude::*;
use wrinkle::{Filter, FilterOptions, FilteredTexture, Footprint, ImageRef, MipFilter, TextureOptions, Wrap};

/// Lookups below this many run on the calling thread, the GIL held: a thread hand-off costs more.
const PARALLEL_FROM: usize = 16384;
/// Lookups per parallel task.
const CHUNK: usize = 4096;

#[pyclass(frozen, module = "wrinkle._wrinkle")]
pub struct Texture {
    texture: FilteredTexture,
}

fn parse<T: Copy>(what: &str, name: &str, names: &[(&str, T)]) -> PyResult<T> {
    names.iter().find(|(n, _)| *n == name).map(|&(_, v)| v).ok_or_else(|| {
        let all: Vec<&str> = names.iter().map(|(n, _)| *n).collect();
        invalid(format!("{what}: expected one of {}, got \"{name}\"", all.join(", ")))
    })
}

fn filter(name: &str) -> PyResult<Filter> {
    Filter::parse(name).ok_or_else(|| invalid(format!("filter: expected one of {}, got \"{name}\"", Filter::names())))
}

fn filter_options(name: &str, max_aniso: f32) -> PyResult<FilterOptions> {
    if !(max_aniso.is_finite() && (1.0..=64.0).contains(&max_aniso)) {
        return Err(invalid(format!("max_aniso: expected a number from 1 to 64, got {max_aniso}")));
    }
    Ok(FilterOptions { filter: filter(name)?, max_aniso, ..FilterOptions::default() })
}

/// An (H, W, 4) array as a view of RGBA pixels, checked for a size the core can hold.
fn view<'a, T: numpy::Element>(a: &'a PyReadonlyArrayDyn<'_, T>) -> PyResult<ImageRef<'a, [T; 4]>> {
    let s = shape("pixels", a, &[None, None, Some(4)])?;
    wrinkle::image::io::check_size(s[1], s[0]).map_err(|m| invalid(format!("pixels: {m}")))?;
    let (pixels, _) = slice("pixels", a)?.as_chunks::<4>();
    ImageRef::new(s[1], s[0], pixels).map_err(|e| invalid(format!("pixels: {e}")))
}

#[pymethods]
impl Texture {
    /// `rgba8` (H, W, 4) uint8, sRGB-encoded when `srgb`, or `rgba` (H, W, 4) float32 linear: exactly one.
    #[new]
    #[pyo3(signature = (rgba8, rgba, srgb, wrap, mip_filter, filter, max_aniso, border, lod_bias))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        rgba8: Option<PyReadonlyArrayDyn<'_, u8>>,
        rgba: Option<PyReadonlyArrayDyn<'_, f32>>,
        srgb: bool,
        wrap: (String, String),
        mip_filter: &str,
        filter: &str,
        max_aniso: f32,
        border: [f32; 4],
        lod_bias: f32,
    ) -> PyResult<Texture> {
        if !(-4.0..=4.0).contains(&lod_bias) {
            return Err(invalid(format!("lod_bias: expected a number of levels from -4 to 4, got {lod_bias}")));
        }
        let options = TextureOptions {
            wrap: [parse("wrap", &wrap.0, &Wrap::NAMES)?, parse("wrap", &wrap.1, &Wrap::NAMES)?],
            border: Vec4::from(border),
            mip_filter: parse("mip_filter", mip_filter, &MipFilter::NAMES)?,
            filter: filter_options(filter, max_aniso)?,
            lod_bias,
        };
        // The texture reads the array in place (a view of its buffer), without a copy into an image.
        let texture = match (rgba8, rgba) {
            (Some(a), None) => {
                let image = view(&a)?;
                py.detach(|| FilteredTexture::from_rgba8(image, srgb, options))
            }
            (None, Some(a)) => {
                let image = view(&a)?;
                if image.pixels().as_flattened().iter().any(|v| !v.is_finite()) {
                    return Err(invalid("pixels: NaN or infinite values"));
                }
                py.detach(|| FilteredTexture::new(image, options))
            }
            _ => return Err(invalid("give the pixels as uint8 or float32")),
        };
        Ok(Texture { texture })
    }

    /// (width, height) in texels.
    #[getter]
    fn size(&self) -> (usize, usize) {
        self.texture.size()
    }

    /// The filtered texture at each (s, t) of `uv` (N, 2), one period per unit, t up the image, with the
    /// footprint (N, 4) = (ds/dx, dt/dx, ds/dy, dt/dy) per lookup (None: a point), as RGBA (N, 4).
    #[pyo3(signature = (uv, footprint, filter, max_aniso))]
    fn sample<'py>(
        &self,
        py: Python<'py>,
        uv: PyReadonlyArrayDyn<'py, f32>,
        footprint: Option<PyReadonlyArrayDyn<'py, f32>>,
        filter: Option<&str>,
        max_aniso: Option<f32>,
    ) -> PyResult<Bound<'py, PyArrayDyn<f32>>> {
        let n = shape("uv", &uv, &[None, Some(2)])?[0];
        let uv = slice("uv", &uv)?;
        let fp = match &footprint {
            Some(f) => {
                shape("footprint", f, &[Some(n), Some(4)])?;
                Some(slice("footprint", f)?)
            }
            None => None,
        };
        let current = self.texture.options().filter;
        let texture = match (filter, max_aniso) {
            (None, None) => None,
            (f, a) => Some(
                self.texture
                    .with_options(filter_options(f.unwrap_or(current.filter.name()), a.unwrap_or(current.max_aniso))?),
            ),
        };
        let texture = texture.as_ref().unwrap_or(&self.texture);
        // Lookups `first..` into `out` (4 values each), as one batch (whose lookups overlap their cache
        // misses); false where a value is NaN or infinite.
        let fill = |first: usize, out: &mut [f32]| -> bool {
            let (count, mut ok) = (out.len() / 4, true);
            let (st, footprints): (Vec<Vec2>, Vec<Footprint>) = (first..first + count)
                .map(|i| {
                    let (s, t) = (uv[2 * i], uv[2 * i + 1]);
                    let f = fp.map_or([0.0; 4], |f| [f[4 * i], f[4 * i + 1], f[4 * i + 2], f[4 * i + 3]]);
                    ok &= s.is_finite() && t.is_finite() && f.iter().all(|v| v.is_finite());
                    (Vec2::new(s, t), Footprint { dudx: f[0], dvdx: f[1], dudy: f[2], dvdy: f[3] })
                })
                .unzip();
            let mut values = vec![Vec4::ZERO; count];
            texture.lookup_batch(&st, &footprints, &mut values);
            for (o, v) in out.chunks_exact_mut(4).zip(&values) {
                o.copy_from_slice(&v.to_array());
            }
            ok
        };
        let mut values = vec![0.0f32; 4 * n];
        let ok = if n < PARALLEL_FROM {
            fill(0, &mut values)
        } else {
            py.detach(|| {
                values
                    .par_chunks_mut(4 * CHUNK)
                    .enumerate()
                    .map(|(c, o)| fill(c * CHUNK, o))
                    .reduce(|| true, |a, b| a && b)
            })
        };
        if !ok {
            return Err(invalid("uv or footprint: contains NaN or infinite values"));
        }
        Ok(output(py, &[n, 4], values))
    }

    /// One lookup at (s, t) with the footprint (ds/dx, dt/dx, ds/dy, dt/dy) (None: a point), as an RGBA
    /// tuple: the per-point form of `sample`, which makes no arrays.
    #[pyo3(signature = (s, t, footprint=None))]
    fn lookup(&self, s: f32, t: f32, footprint: Option<(f32, f32, f32, f32)>) -> PyResult<(f32, f32, f32, f32)> {
        let (dudx, dvdx, dudy, dvdy) = footprint.unwrap_or_default();
        if ![s, t, dudx, dvdx, dudy, dvdy].iter().all(|v| v.is_finite()) {
            return Err(invalid("lookup: NaN or infinite coordinates"));
        }
        let [r, g, b, a] = self.texture.lookup(s, t, &Footprint { dudx, dvdx, dudy, dvdy }).to_array();
        Ok((r, g, b, a))
    }

    /// The MIP pyramid in linear light, level 0 first, each (H, W, 4) float32 (row 0 at the top).
    fn mipmap<'py>(&self, py: Python<'py>) -> Vec<Bound<'py, PyArrayDyn<f32>>> {
        let levels = py.detach(|| self.texture.pyramid());
        levels.into_iter().map(|l| output(py, &[l.height, l.width, 4], flatten(l.pixels))).collect()
    }
}
