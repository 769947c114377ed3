//! Scenes from TOML text, files or Python dictionaries, rendered to arrays with progress and interrupts.

use crate::arrays::{flatten, output};
use crate::errors::{invalid, to_py, IntoPy};
use pyo3::exceptions::{PyRuntimeError, PyTypeError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::mpsc;
use std::time::Duration;
use wrinkle::bump::BumpFilter;
use wrinkle::render::{Aovs, Transparency};
use wrinkle::texture::TexelLocation;
use wrinkle::{Crop, PixelFilter, RenderOptions, Sampler, ShadingRate};

/// How often a render in progress looks up from its work: for Ctrl-C, and to report progress.
const POLL: Duration = Duration::from_millis(20);

#[pyclass(frozen, module = "wrinkle._wrinkle")]
pub struct Scene {
    scene: wrinkle::Scene,
}

#[pymethods]
impl Scene {
    /// Parses scene text; relative file names resolve against `base`.
    #[staticmethod]
    fn parse(py: Python<'_>, text: &str, base: PathBuf) -> PyResult<Scene> {
        let scene = py.detach(|| wrinkle::Scene::parse(text, &base)).py_err()?;
        Ok(Scene { scene })
    }

    /// Reads a scene file.
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Scene> {
        let scene = py.detach(|| wrinkle::Scene::load(&path)).py_err()?;
        Ok(Scene { scene })
    }

    /// The scene a dictionary describes, with the scene file's tables and fields.
    #[staticmethod]
    fn from_dict(py: Python<'_>, tables: &Bound<'_, PyDict>, base: PathBuf) -> PyResult<Scene> {
        let toml::Value::Table(table) = to_toml(tables.as_any(), "")? else { unreachable!("a dict is a table") };
        let text = toml::to_string(&table).map_err(|e| invalid(format!("scene: {e}")))?;
        let scene = py.detach(|| wrinkle::Scene::parse(&text, &base)).py_err()?;
        Ok(Scene { scene })
    }

    /// The embedded default scene.
    #[staticmethod]
    fn default(py: Python<'_>) -> Scene {
        Scene { scene: py.detach(wrinkle::Scene::default_scene) }
    }

    /// The number of objects.
    #[getter]
    fn objects(&self) -> usize {
        self.scene.objects.len()
    }

    /// The time of the animation's last key in seconds, or None for a scene without [[animation]] tracks.
    #[getter]
    fn animation_end(&self) -> Option<f64> {
        self.scene.animation.as_ref().map(|a| a.end())
    }

    /// The scene at `time` seconds of its animation.
    fn at(&self, py: Python<'_>, time: f64) -> PyResult<Scene> {
        let Some(animation) = self.scene.animation.clone() else {
            return Err(invalid("at: the scene has no [[animation]] tracks"));
        };
        let scene = py.detach(|| animation.scene_at(time)).py_err()?;
        Ok(Scene { scene })
    }

    /// Renders a frame: "color" (H, W, 3) linear RGB and each AOV named in `aovs`, as arrays. `progress`,
    /// when given, is called with (done, total) from the calling thread as bands finish.
    #[pyo3(signature = (width, height, spp, aovs, bump, bump_filter, transparent, transparency, turntable, progress, crop=None, sampler="stratified", pixel_filter="box", seed=0, texel_location="centre", shading_rate="sample"))]
    #[allow(clippy::too_many_arguments)]
    fn render<'py>(
        &self,
        py: Python<'py>,
        width: usize,
        height: usize,
        spp: usize,
        aovs: Vec<String>,
        bump: bool,
        bump_filter: Option<&str>,
        transparent: bool,
        transparency: &str,
        turntable: f32,
        progress: Option<Bound<'py, PyAny>>,
        crop: Option<(usize, usize, usize, usize)>,
        sampler: &str,
        pixel_filter: &str,
        seed: u32,
        texel_location: &str,
        shading_rate: &str,
    ) -> PyResult<Bound<'py, PyDict>> {
        let mut kinds = Aovs::default();
        for name in &aovs {
            let flag = match name.as_str() {
                "normal" => &mut kinds.normal,
                "uv" => &mut kinds.uv,
                "depth" => &mut kinds.depth,
                "id" => &mut kinds.id,
                "primitive" => &mut kinds.primitive,
                "alpha" => &mut kinds.alpha,
                _ => {
                    return Err(invalid(format!(
                        "aovs: unknown AOV \"{name}\" (expected normal, uv, depth, id, primitive, alpha)"
                    )))
                }
            };
            *flag = true;
        }
        let options = RenderOptions {
            width,
            height,
            spp,
            sampler: Sampler::parse(sampler).ok_or_else(|| {
                invalid(format!("sampler: expected one of {}, got \"{sampler}\"", Sampler::NAMES.join(", ")))
            })?,
            pixel_filter: PixelFilter::parse(pixel_filter).py_err()?,
            texel_location: TexelLocation::parse(texel_location).ok_or_else(|| {
                let names = TexelLocation::NAMES.map(|(n, _)| n).join(", ");
                invalid(format!("texel_location: expected one of {names}, got \"{texel_location}\""))
            })?,
            shading_rate: ShadingRate::parse(shading_rate).ok_or_else(|| {
                let names = ShadingRate::NAMES.join(", ");
                invalid(format!("shading_rate: expected one of {names}, got \"{shading_rate}\""))
            })?,
            seed,
            bump,
            bump_filter: bump_filter
                .map(|f| {
                    BumpFilter::parse(f).ok_or_else(|| {
                        invalid(format!("bump_filter: expected one of {}, got \"{f}\"", BumpFilter::names()))
                    })
                })
                .transpose()?,
            turntable_degrees: turntable,
            aovs: kinds,
            transparent,
            transparency: match transparency {
                "sorted" => Transparency::Sorted,
                "exact" => Transparency::Exact,
                _ => {
                    return Err(invalid(format!(
                        "transparency: expected \"sorted\" or \"exact\", got \"{transparency}\""
                    )))
                }
            },
            crop: crop.map(|(x0, y0, x1, y1)| Crop { x0, y0, x1, y1 }),
        };
        options.validate().py_err()?;
        let frame = render_interruptibly(py, &self.scene, &options, progress.as_ref())?;
        let out = PyDict::new(py);
        let (w, h) = (frame.width, frame.height);
        out.set_item("color", output(py, &[h, w, 3], flatten(frame.color)))?;
        if let Some(v) = frame.normal {
            out.set_item("normal", output(py, &[h, w, 3], flatten(v)))?;
        }
        if let Some(v) = frame.uv {
            out.set_item("uv", output(py, &[h, w, 2], flatten(v)))?;
        }
        if let Some(v) = frame.depth {
            out.set_item("depth", output(py, &[h, w], v))?;
        }
        if let Some(v) = frame.id {
            out.set_item("id", output(py, &[h, w], v))?;
        }
        if let Some(v) = frame.primitive {
            out.set_item("primitive", output(py, &[h, w, 2], v.into_iter().flatten().collect()))?;
        }
        if let Some(v) = frame.alpha {
            out.set_item("alpha", output(py, &[h, w], v))?;
        }
        Ok(out)
    }
}

/// Renders on a worker thread while the calling thread, the GIL released between looks, reports progress
/// and checks for signals: Ctrl-C (or an exception from the callback) stops the render within a band.
fn render_interruptibly(
    py: Python<'_>,
    scene: &wrinkle::Scene,
    options: &RenderOptions,
    progress: Option<&Bound<'_, PyAny>>,
) -> PyResult<wrinkle::Frame> {
    let stop = AtomicBool::new(false);
    let (done, total) = (AtomicUsize::new(0), AtomicUsize::new(0));
    let report = |d: usize, t: usize| {
        done.fetch_max(d, Ordering::Relaxed);
        total.store(t, Ordering::Relaxed);
    };
    std::thread::scope(|s| {
        let (tx, rx) = mpsc::channel();
        let (report, stop) = (&report, &stop);
        s.spawn(move || {
            let _ = tx.send(wrinkle::render_until(scene, options, report, stop));
        });
        let mut failure: Option<PyErr> = None;
        let (mut rx, mut told) = (rx, 0);
        // Tells the callback how far the render is, when it has moved on since the last time.
        let tell = |told: &mut usize| -> PyResult<()> {
            let d = done.load(Ordering::Relaxed);
            if let (Some(callback), true) = (progress, d > *told) {
                *told = d;
                callback.call1((d, total.load(Ordering::Relaxed)))?;
            }
            Ok(())
        };
        loop {
            // The receiver goes to the detached closure and comes back (it may move between threads, not be shared).
            let (back, result) = py.detach(move || {
                let r = rx.recv_timeout(POLL);
                (rx, r)
            });
            rx = back;
            if let Err(mpsc::RecvTimeoutError::Disconnected) = result {
                // The render thread ended without a result: it panicked, which the scope's end reports.
                return Err(PyRuntimeError::new_err("the render stopped without a result"));
            }
            if let Ok(result) = result {
                if let Some(e) = failure {
                    return Err(e);
                }
                let frame = result.map_err(to_py)?;
                // The last report, which a render faster than one look never gave.
                tell(&mut told)?;
                return Ok(frame);
            }
            if failure.is_some() {
                continue;
            }
            if let Err(e) = py.check_signals().and_then(|()| tell(&mut told)) {
                stop.store(true, Ordering::Relaxed);
                failure = Some(e);
            }
        }
    })
}

/// Tables and arrays nested deeper than this are refused (a dictionary that holds itself would recurse forever).
const MAX_DEPTH: usize = 32;

/// A Python value as TOML: dicts are tables, lists and tuples arrays; `at` names it in errors.
fn to_toml(v: &Bound<'_, PyAny>, at: &str) -> PyResult<toml::Value> {
    if at.matches(['.', '[']).count() > MAX_DEPTH {
        return Err(invalid(format!("{at}: tables nested more than {MAX_DEPTH} deep")));
    }
    let here = |k: &str| if at.is_empty() { k.to_string() } else { format!("{at}.{k}") };
    if v.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(v.extract()?));
    }
    if v.is_instance_of::<PyInt>() {
        return Ok(toml::Value::Integer(v.extract()?));
    }
    if v.is_instance_of::<PyFloat>() {
        return Ok(toml::Value::Float(v.extract()?));
    }
    if v.is_instance_of::<PyString>() {
        return Ok(toml::Value::String(v.extract()?));
    }
    if let Ok(d) = v.cast::<PyDict>() {
        let mut table = toml::Table::new();
        for (k, item) in d.iter() {
            let key: String = k.extract().map_err(|_| PyTypeError::new_err(format!("{at}: keys must be strings")))?;
            table.insert(key.clone(), to_toml(&item, &here(&key))?);
        }
        return Ok(toml::Value::Table(table));
    }
    if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() {
        let items: Vec<Bound<'_, PyAny>> = v.try_iter()?.collect::<PyResult<_>>()?;
        let values =
            items.iter().enumerate().map(|(i, x)| to_toml(x, &format!("{at}[{i}]"))).collect::<PyResult<_>>()?;
        return Ok(toml::Value::Array(values));
    }
    // NumPy scalars and anything else with a float value (but not strings, handled above).
    if let Ok(f) = v.extract::<f64>() {
        return Ok(toml::Value::Float(f));
    }
    let what = v.get_type().name().map(|n| n.to_string()).unwrap_or_default();
    Err(PyTypeError::new_err(format!("{}: a {what} has no place in a scene", if at.is_empty() { "scene" } else { at })))
}
