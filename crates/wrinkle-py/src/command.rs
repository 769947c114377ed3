//! The `wrinkle` command's own code from Python: its commands run in-process (the farm's workers run
//! `normalmap`, `emboss`, ... with the options the command takes), and rendered frames written exactly as
//! `wrinkle render` writes them.

use crate::arrays::{shape, slice};
use numpy::PyReadonlyArrayDyn;
use pyo3::create_exception;
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use std::ffi::OsString;
use std::path::PathBuf;
use wrinkle::image::io::Placement;
use wrinkle::render::Stats;
use wrinkle::Frame;

create_exception!(
    _wrinkle,
    CommandError,
    PyRuntimeError,
    "A `wrinkle` command that failed: args are its one-line message and its exit code (2: the request, 1: the job)."
);

/// Runs `wrinkle ARGS...` in this process.
#[pyfunction]
fn run_command(py: Python<'_>, args: Vec<String>) -> PyResult<()> {
    let argv: Vec<OsString> = std::iter::once("wrinkle".to_string()).chain(args).map(OsString::from).collect();
    py.detach(|| wrinkle_cli::execute(argv)).map_err(|f| CommandError::new_err((f.message, f.code)))
}

/// Pixels of an (H, W, N) array as rows of N.
fn pixels<const N: usize>(
    name: &str,
    a: &PyReadonlyArrayDyn<'_, f32>,
    (h, w): (usize, usize),
) -> PyResult<Vec<[f32; N]>> {
    shape(name, a, &[Some(h), Some(w), Some(N)])?;
    Ok(slice(name, a)?.chunks_exact(N).map(|c| std::array::from_fn(|k| c[k])).collect())
}

/// Writes a rendered frame as `wrinkle render -o PATH` writes it: PNG (RGBA where `alpha` is given) or EXR
/// by the extension, and each AOV given as PATH.<name>.exr. Arrays as `Scene.render` returns them.
#[pyfunction]
#[pyo3(signature = (path, color, alpha=None, normal=None, uv=None, depth=None, id=None, primitive=None))]
#[allow(clippy::too_many_arguments)]
fn write_frame(
    py: Python<'_>,
    path: PathBuf,
    color: PyReadonlyArrayDyn<'_, f32>,
    alpha: Option<PyReadonlyArrayDyn<'_, f32>>,
    normal: Option<PyReadonlyArrayDyn<'_, f32>>,
    uv: Option<PyReadonlyArrayDyn<'_, f32>>,
    depth: Option<PyReadonlyArrayDyn<'_, f32>>,
    id: Option<PyReadonlyArrayDyn<'_, f32>>,
    primitive: Option<PyReadonlyArrayDyn<'_, u32>>,
) -> PyResult<()> {
    let s = shape("color", &color, &[None, None, Some(3)])?;
    let size = (s[0], s[1]);
    let grey = |name: &str, a: &PyReadonlyArrayDyn<'_, f32>| -> PyResult<Vec<f32>> {
        shape(name, a, &[Some(size.0), Some(size.1)])?;
        Ok(slice(name, a)?.to_vec())
    };
    // Built from the arrays directly: Frame::new would fill a whole frame of background first.
    let frame = Frame {
        width: size.1,
        height: size.0,
        color: pixels::<3>("color", &color, size)?,
        alpha: alpha.as_ref().map(|a| grey("alpha", a)).transpose()?,
        normal: normal.as_ref().map(|a| pixels::<3>("normal", a, size)).transpose()?,
        uv: uv.as_ref().map(|a| pixels::<2>("uv", a, size)).transpose()?,
        depth: depth.as_ref().map(|a| grey("depth", a)).transpose()?,
        id: id.as_ref().map(|a| grey("id", a)).transpose()?,
        primitive: match &primitive {
            Some(a) => {
                shape("primitive", a, &[Some(size.0), Some(size.1), Some(2)])?;
                Some(slice("primitive", a)?.chunks_exact(2).map(|c| [c[0], c[1]]).collect())
            }
            None => None,
        },
        placement: Placement::whole(size.1, size.0),
        stats: Stats::default(),
    };
    py.detach(|| wrinkle_cli::write_frame(&path, &frame)).map_err(crate::errors::to_py)
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("CommandError", m.py().get_type::<CommandError>())?;
    m.add_function(wrap_pyfunction!(run_command, m)?)?;
    m.add_function(wrap_pyfunction!(write_frame, m)?)?;
    Ok(())
}
