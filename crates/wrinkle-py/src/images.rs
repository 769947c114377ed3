//! Image tools over arrays: Schlag's emboss, normal maps, heights from normals, Blinn's bump-table
//! generators, and image files read with the core's own decoders.

use crate::arrays::{flatten, output, shape, slice};
use crate::errors::{invalid, IntoPy};
use numpy::{PyArrayDyn, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;
use wrinkle::bump::generators::{BrickParams, Generator, GridParams, RivetParams, TextParams};
use wrinkle::bump::integrate::{check_strength, frankot_chellappa, gradient_of_normal, settle_heights};
use wrinkle::bump::normal_map::{Convention, Kernel, NormalMap};
use wrinkle::bump::schlag::{emboss_image, modulate_rgb8, Emboss};
use wrinkle::image::color::SrgbEncoder;
use wrinkle::image::io;
use wrinkle::image::strips::Edges;
use wrinkle::ImageRef;

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(emboss, m)?)?;
    m.add_function(wrap_pyfunction!(modulate, m)?)?;
    m.add_function(wrap_pyfunction!(normal_map, m)?)?;
    m.add_function(wrap_pyfunction!(height_from_normals, m)?)?;
    m.add_function(wrap_pyfunction!(bumpgen, m)?)?;
    m.add_function(wrap_pyfunction!(read_image, m)?)?;
    m.add_function(wrap_pyfunction!(read_exr, m)?)?;
    m.add_function(wrap_pyfunction!(encode_srgb8, m)?)?;
    m.add_function(wrap_pyfunction!(write_png8, m)?)?;
    m.add_function(wrap_pyfunction!(write_png16, m)?)?;
    m.add_function(wrap_pyfunction!(write_exr, m)?)?;
    Ok(())
}

/// The shade of every pixel of a grey height image in [0, 1] (H, W).
#[pyfunction]
fn emboss<'py>(
    py: Python<'py>,
    height: PyReadonlyArrayDyn<'py, f32>,
    azimuth: f32,
    elevation: f32,
    width: f32,
) -> PyResult<Bound<'py, PyArrayDyn<f32>>> {
    let s = shape("height", &height, &[None, None])?;
    let emboss = Emboss::new(azimuth, elevation, width).py_err()?;
    // The core's intensities run 0..255, as 8-bit files decode.
    let intensities: Vec<f32> = slice("height", &height)?.iter().map(|&v| v * 255.0).collect();
    let image = ImageRef::new(s[1], s[0], &intensities).map_err(|e| invalid(format!("height: {e}")))?;
    let shade = py.detach(|| emboss_image(image, &emboss));
    Ok(output(py, &s, shade.pixels))
}

/// An 8-bit RGB texture (H, W, 3) times the shade (H, W), rounded as `wrinkle emboss --texture` rounds.
#[pyfunction]
fn modulate<'py>(
    py: Python<'py>,
    shade: PyReadonlyArrayDyn<'py, f32>,
    texture: PyReadonlyArrayDyn<'py, u8>,
) -> PyResult<Bound<'py, PyArrayDyn<u8>>> {
    let s = shape("shade", &shade, &[None, None])?;
    let t = shape("texture", &texture, &[Some(s[0]), Some(s[1]), Some(3)])?;
    let mut out = vec![0u8; s[0] * s[1] * 3];
    modulate_rgb8(slice("shade", &shade)?, slice("texture", &texture)?, &mut out);
    Ok(output(py, &t, out))
}

fn convention(name: &str) -> PyResult<Convention> {
    match name {
        "opengl" => Ok(Convention::OpenGl),
        "directx" => Ok(Convention::DirectX),
        _ => Err(invalid(format!("convention: expected \"opengl\" or \"directx\", got \"{name}\""))),
    }
}

fn edges(wrap: bool) -> Edges {
    if wrap {
        Edges::Wrap
    } else {
        Edges::Clamp
    }
}

/// Unit normals (H, W, 3), or with `offset` the slopes (H, W, 2), of z = strength * height.
#[pyfunction]
fn normal_map<'py>(
    py: Python<'py>,
    height: PyReadonlyArrayDyn<'py, f32>,
    strength: f32,
    convention: &str,
    kernel: &str,
    wrap: bool,
    offset: bool,
) -> PyResult<Bound<'py, PyArrayDyn<f32>>> {
    let s = shape("height", &height, &[None, None])?;
    let kernel = match kernel {
        "central" => Kernel::Central,
        "sobel" => Kernel::Sobel,
        "scharr" => Kernel::Scharr,
        _ => return Err(invalid(format!("kernel: expected \"central\", \"sobel\" or \"scharr\", got \"{kernel}\""))),
    };
    let map = NormalMap::new(kernel, strength, self::convention(convention)?).py_err()?;
    // Read in place: a view of the array's buffer.
    let heights = ImageRef::new(s[1], s[0], slice("height", &height)?).map_err(|e| invalid(format!("height: {e}")))?;
    Ok(if offset {
        let slopes = py.detach(|| flatten(map.slopes_image(heights, edges(wrap)).pixels));
        output(py, &[s[0], s[1], 2], slopes)
    } else {
        let normals = py.detach(|| flatten(map.normals_image(heights, edges(wrap)).pixels));
        output(py, &[s[0], s[1], 3], normals)
    })
}

/// Heights in [0, 1] (H, W) whose normal map is nearest to `normals` (H, W, 3, components in [-1, 1]), and
/// the span of the heights before `normalize`.
#[pyfunction]
fn height_from_normals<'py>(
    py: Python<'py>,
    normals: PyReadonlyArrayDyn<'py, f32>,
    strength: f32,
    convention: &str,
    wrap: bool,
    normalize: bool,
) -> PyResult<(Bound<'py, PyArrayDyn<f32>>, f32)> {
    let s = shape("normals", &normals, &[None, None, Some(3)])?;
    check_strength(strength).py_err()?;
    let flip = if self::convention(convention)? == Convention::DirectX { -1.0 } else { 1.0 };
    let (w, h) = (s[1], s[0]);
    let n = slice("normals", &normals)?;
    let field = wrinkle::bump::integrate::field_size(w, h, wrap);
    wrinkle::limits::reserve((field.0 * field.1 * wrinkle::bump::integrate::BYTES_PER_FIELD_PIXEL) as u64, || {
        format!("integrating a {w}x{h} map")
    })
    .py_err()?;
    let (heights, span) = py.detach(|| {
        let (p, q): (Vec<f32>, Vec<f32>) =
            n.chunks_exact(3).map(|c| gradient_of_normal([c[0], flip * c[1], c[2]], strength)).unzip();
        let mut heights = frankot_chellappa(&p, &q, w, h, wrap);
        let span = settle_heights(&mut heights, normalize);
        (heights, span)
    });
    Ok((output(py, &[h, w], heights), span))
}

/// One of Blinn's bump tables (grid, text, rivets, bricks), heights in [0, 1]; `params` holds the
/// generator's own options by name, the rest keep their defaults.
#[pyfunction]
#[pyo3(signature = (kind, size, params=None))]
fn bumpgen<'py>(
    py: Python<'py>,
    kind: &str,
    size: usize,
    params: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyArrayDyn<f32>>> {
    let mut options = Options::new(kind, params)?;
    let generator = match kind {
        "grid" => {
            let d = GridParams::default();
            Generator::Grid(GridParams {
                cells: options.take("cells", d.cells)?,
                line_width: options.take("line_width", d.line_width)?,
                soft: options.take("soft", d.soft)?,
            })
        }
        "text" => {
            let d = TextParams::default();
            Generator::Text(TextParams { text: options.take("text", d.text)?, soft: options.take("soft", d.soft)? })
        }
        "rivets" => {
            let d = RivetParams::default();
            Generator::Rivets(RivetParams {
                count: options.take("count", d.count)?,
                radius: options.take("radius", d.radius)?,
            })
        }
        "bricks" => {
            let d = BrickParams::default();
            Generator::Bricks(BrickParams {
                rows: options.take("rows", d.rows)?,
                bricks_per_row: options.take("bricks_per_row", d.bricks_per_row)?,
                mortar: options.take("mortar", d.mortar)?,
                bevel: options.take("bevel", d.bevel)?,
            })
        }
        _ => return Err(invalid(format!("kind: expected grid, text, rivets or bricks, got \"{kind}\""))),
    };
    options.finish()?;
    let table = py.detach(|| generator.generate(size)).py_err()?;
    Ok(output(py, &[table.height, table.width], table.pixels))
}

/// Keyword options of one kind: each taken by name with its default; any left over is an error that names it.
pub struct Options<'py> {
    what: String,
    left: Vec<(String, Bound<'py, PyAny>)>,
}

impl<'py> Options<'py> {
    pub fn new(what: &str, params: Option<&Bound<'py, PyDict>>) -> PyResult<Self> {
        let left = match params {
            Some(d) => d.iter().map(|(k, v)| Ok((k.extract::<String>()?, v))).collect::<PyResult<_>>()?,
            None => Vec::new(),
        };
        Ok(Options { what: what.to_string(), left })
    }

    pub fn take<T: for<'a> FromPyObject<'a, 'py>>(&mut self, name: &str, default: T) -> PyResult<T> {
        match self.left.iter().position(|(k, _)| k == name) {
            Some(i) => {
                let (_, v) = self.left.remove(i);
                v.extract::<T>().map_err(|e| invalid(format!("{name}: {}", e.into())))
            }
            None => Ok(default),
        }
    }

    pub fn finish(self) -> PyResult<()> {
        match self.left.first() {
            Some((k, _)) => Err(invalid(format!("{}: unknown option \"{k}\"", self.what))),
            None => Ok(()),
        }
    }
}

/// An image file as RGBA float32 (H, W, 4): 8- and 16-bit samples over their full scale, decoded from sRGB
/// when `srgb`; float files (EXR, HDR) as stored.
#[pyfunction]
fn read_image<'py>(py: Python<'py>, path: PathBuf, srgb: bool) -> PyResult<Bound<'py, PyArrayDyn<f32>>> {
    let image = py.detach(|| io::load_rgba_linear(&path, srgb)).py_err()?;
    Ok(output(py, &[image.height, image.width, 4], flatten(image.pixels)))
}

/// Every channel of an OpenEXR file by name, each (H, W) float32.
#[pyfunction]
fn read_exr<'py>(py: Python<'py>, path: PathBuf) -> PyResult<Bound<'py, PyDict>> {
    let (w, h, channels) = py.detach(|| io::read_exr_channels(&path)).py_err()?;
    let out = PyDict::new(py);
    for (name, values) in channels {
        out.set_item(name, output(py, &[h, w], values))?;
    }
    Ok(out)
}

/// The (height, width, channels) of an image array (H, W) or (H, W, C).
fn image_shape(a: &PyReadonlyArrayDyn<'_, impl numpy::Element>) -> PyResult<(usize, usize, usize)> {
    match *a.shape() {
        [h, w] if h > 0 && w > 0 => Ok((h, w, 1)),
        [h, w, c] if h > 0 && w > 0 => Ok((h, w, c)),
        ref s => Err(invalid(format!("image: expected shape (H, W) or (H, W, C), got {s:?}"))),
    }
}

/// Writes 8-bit samples as stored to a PNG (1 to 4 channels), whole or not at all.
#[pyfunction]
fn write_png8(py: Python<'_>, path: PathBuf, samples: PyReadonlyArrayDyn<'_, u8>) -> PyResult<()> {
    let (h, w, c) = image_shape(&samples)?;
    let data = slice("image", &samples)?;
    py.detach(|| io::write_png8(&path, w, h, c, data)).py_err()
}

/// Writes 16-bit samples as stored to a PNG (1 to 4 channels), whole or not at all.
#[pyfunction]
fn write_png16(py: Python<'_>, path: PathBuf, samples: PyReadonlyArrayDyn<'_, u16>) -> PyResult<()> {
    let (h, w, c) = image_shape(&samples)?;
    let data = slice("image", &samples)?;
    py.detach(|| io::write_png16(&path, w, h, c, data)).py_err()
}

/// Writes named float32 channels, each (H, W), to a linear OpenEXR file (lossless).
#[pyfunction]
fn write_exr(py: Python<'_>, path: PathBuf, channels: Vec<(String, PyReadonlyArrayDyn<'_, f32>)>) -> PyResult<()> {
    let first = channels.first().ok_or_else(|| invalid("channels: give at least one"))?;
    let s = shape("channels", &first.1, &[None, None])?;
    let data = channels
        .iter()
        .map(|(name, a)| {
            shape(name, a, &[Some(s[0]), Some(s[1])])?;
            Ok((name.as_str(), slice(name, a)?))
        })
        .collect::<PyResult<Vec<(&str, &[f32])>>>()?;
    py.detach(|| io::write_exr(&path, s[1], s[0], &data)).py_err()
}

/// Linear values to 8-bit sRGB codes, as the renderer encodes PNG frames (any shape).
#[pyfunction]
fn encode_srgb8<'py>(py: Python<'py>, linear: PyReadonlyArrayDyn<'py, f32>) -> PyResult<Bound<'py, PyArrayDyn<u8>>> {
    let s = linear.shape().to_vec();
    let values = slice("linear", &linear)?;
    let codes = py.detach(|| {
        let enc = SrgbEncoder::new();
        values.iter().map(|&v| enc.encode(v)).collect()
    });
    Ok(output(py, &s, codes))
}
