//! Perlin noise, its fractal sums and the procedural patterns over arrays of points, and patterns baked to
//! images.

use crate::arrays::{output, shape, slice};
use crate::errors::{invalid, IntoPy};
use crate::images::Options;
use numpy::{PyArrayDyn, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};
use wrinkle::procedural::bake::bake_rows;
use wrinkle::procedural::effects::{spline, Kind, Params, Pattern};
use wrinkle::procedural::fbm::{Fractal, Octaves, Sum};
use wrinkle::procedural::{Perlin, Variant};

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(perlin, m)?)?;
    m.add_function(wrap_pyfunction!(fractal, m)?)?;
    m.add_function(wrap_pyfunction!(pattern, m)?)?;
    m.add_function(wrap_pyfunction!(bake, m)?)?;
    m.add_function(wrap_pyfunction!(pattern_kinds, m)?)?;
    Ok(())
}

/// Points per parallel task: large enough that the task costs little beside it.
const CHUNK: usize = 4096;

/// The variant called `name`; the core's default where none is given.
fn variant(name: Option<&str>) -> PyResult<Variant> {
    name.map_or(Ok(Variant::default()), |name| {
        Variant::from_name(name)
            .ok_or_else(|| invalid(format!("variant: expected {}, got \"{name}\"", Variant::name_list("\""))))
    })
}

/// The points (N, 2) or (N, 3) and their dimension.
fn points<'a>(p: &'a PyReadonlyArrayDyn<'_, f32>) -> PyResult<(&'a [f32], usize)> {
    let s = p.shape();
    let dims = if s.len() == 2 { s[1] } else { 0 };
    if dims != 2 && dims != 3 {
        return Err(invalid(format!("points: expected shape (N, 2) or (N, 3), got {s:?}")));
    }
    shape("points", p, &[None, Some(dims)])?;
    Ok((slice("points", p)?, dims))
}

/// `f` over every point, in parallel chunks, the GIL released, into `per` values a point (row by row, the
/// array handed to NumPy as it is). Points with NaN or infinite coordinates are refused.
fn per_point(
    py: Python<'_>,
    pts: &[f32],
    dims: usize,
    per: usize,
    f: impl Fn(&[f32], &mut [f32]) + Sync,
) -> PyResult<Vec<f32>> {
    let mut out = vec![0.0; pts.len() / dims * per];
    let bad = AtomicBool::new(false);
    py.detach(|| {
        out.par_chunks_mut(CHUNK * per).zip(pts.par_chunks(CHUNK * dims)).for_each(|(o, p)| {
            if p.iter().all(|v| v.is_finite()) {
                f(p, o)
            } else {
                bad.store(true, Ordering::Relaxed)
            }
        })
    });
    match bad.into_inner() {
        true => Err(invalid("points: contains NaN or infinite values")),
        false => Ok(out),
    }
}

/// Deinterleaves a chunk of points into x, y, z (z = 0 for 2D points).
fn axes(p: &[f32], dims: usize) -> [Vec<f32>; 3] {
    std::array::from_fn(|a| {
        if a < dims {
            p.iter().skip(a).step_by(dims).copied().collect()
        } else {
            vec![0.0; p.len() / dims]
        }
    })
}

/// Perlin's noise (in about [-1, 1]) at every point.
#[pyfunction]
fn perlin<'py>(
    py: Python<'py>,
    points: PyReadonlyArrayDyn<'py, f32>,
    seed: u64,
    variant: Option<&str>,
) -> PyResult<Bound<'py, PyArrayDyn<f32>>> {
    let (pts, dims) = self::points(&points)?;
    let noise = Perlin::new(self::variant(variant)?, seed);
    let out = per_point(py, pts, dims, 1, |p, o| {
        let [x, y, z] = axes(p, dims);
        if dims == 3 {
            noise.noise3_many(&x, &y, &z, o);
        } else {
            o.iter_mut().enumerate().for_each(|(i, v)| *v = noise.noise2(x[i], y[i]));
        }
    })?;
    Ok(output(py, &[out.len()], out))
}

/// A fractal sum of Perlin noise over octaves (fBm: sum noise / f; turbulence: sum |noise| / f).
#[pyfunction]
#[allow(clippy::too_many_arguments)]
fn fractal<'py>(
    py: Python<'py>,
    points: PyReadonlyArrayDyn<'py, f32>,
    sum: &str,
    octaves: u32,
    lacunarity: f32,
    gain: f32,
    seed: u64,
    variant: Option<&str>,
) -> PyResult<Bound<'py, PyArrayDyn<f32>>> {
    let (pts, dims) = self::points(&points)?;
    let sum = match sum {
        "fbm" => Sum::Fbm,
        "turbulence" => Sum::Turbulence,
        _ => return Err(invalid(format!("sum: expected \"fbm\" or \"turbulence\", got \"{sum}\""))),
    };
    // The octave limits are the patterns' own: checked once, by the same rules.
    let mut check = Params::new(Kind::Fbm);
    check.octaves = Octaves { count: octaves, lacunarity, gain };
    check.validate().py_err()?;
    let fractal = Fractal::new(Perlin::new(self::variant(variant)?, seed), sum, check.octaves);
    let out = per_point(py, pts, dims, 1, |p, o| {
        let [x, y, z] = axes(p, dims);
        if dims == 3 {
            fractal.eval3_many(&x, &y, &z, o);
        } else {
            fractal.eval2_many(&x, &y, o);
        }
    })?;
    Ok(output(py, &[out.len()], out))
}

/// The parameters of a pattern kind from keyword options (the scene's and `wrinkle texture`'s names).
fn pattern_params(kind: &str, params: Option<&Bound<'_, PyDict>>) -> PyResult<Params> {
    let kind = Kind::from_name(kind).ok_or_else(|| {
        let names: Vec<&str> = Kind::ALL.iter().map(|k| k.name()).collect();
        invalid(format!("kind: expected one of {}, got \"{kind}\"", names.join(", ")))
    })?;
    let mut o = Options::new(kind.name(), params)?;
    let d = Params::new(kind);
    let p = Params {
        kind,
        scale: o.take("scale", d.scale)?,
        seed: o.take("seed", d.seed)?,
        variant: variant(o.take::<Option<String>>("variant", None)?.as_deref())?,
        octaves: Octaves {
            count: o.take("octaves", d.octaves.count)?,
            lacunarity: o.take("lacunarity", d.octaves.lacunarity)?,
            gain: o.take("gain", d.octaves.gain)?,
        },
        strength: o.take("strength", d.strength)?,
        rings: o.take("rings", d.rings)?,
        time: o.take("time", d.time)?,
        mortar: o.take("mortar", d.mortar)?,
        line_width: o.take("line_width", d.line_width)?,
        colors: o.take("colors", d.colors)?,
    };
    o.finish()?;
    Ok(p)
}

/// A procedural pattern at every point: t in [0, 1] (N,) and its colour (N, 3); `width` is the footprint
/// (the pattern is filtered over it, 0: a point sample).
#[pyfunction]
#[pyo3(signature = (kind, points, width, params=None))]
#[allow(clippy::type_complexity)]
fn pattern<'py>(
    py: Python<'py>,
    kind: &str,
    points: PyReadonlyArrayDyn<'py, f32>,
    width: f32,
    params: Option<&Bound<'py, PyDict>>,
) -> PyResult<(Bound<'py, PyArrayDyn<f32>>, Bound<'py, PyArrayDyn<f32>>)> {
    let (pts, dims) = self::points(&points)?;
    if !(width.is_finite() && width >= 0.0) {
        return Err(invalid(format!("width: expected a finite non-negative number, got {width}")));
    }
    let pattern = Pattern::new(pattern_params(kind, params)?, dims, false).py_err()?;
    let out = per_point(py, pts, dims, 4, |p, o| {
        for (o, q) in o.chunks_exact_mut(4).zip(p.chunks_exact(dims)) {
            let t = pattern.eval([q[0], q[1], if dims == 3 { q[2] } else { 0.0 }], width);
            let [r, g, b] = spline(&pattern.params.colors, t);
            o.copy_from_slice(&[t, r, g, b]);
        }
    })?;
    let n = out.len() / 4;
    let t = out.iter().step_by(4).copied().collect();
    let rgb = out.chunks_exact(4).flat_map(|v| [v[1], v[2], v[3]]).collect();
    Ok((output(py, &[n], t), output(py, &[n, 3], rgb)))
}

/// A pattern baked into a `width` x `height` image as `wrinkle texture` bakes it: t (H, W) and the
/// colour (H, W, 3), linear.
#[pyfunction]
#[pyo3(signature = (kind, width, height, tileable, params=None))]
#[allow(clippy::type_complexity)]
fn bake<'py>(
    py: Python<'py>,
    kind: &str,
    width: usize,
    height: usize,
    tileable: bool,
    params: Option<&Bound<'py, PyDict>>,
) -> PyResult<(Bound<'py, PyArrayDyn<f32>>, Bound<'py, PyArrayDyn<f32>>)> {
    wrinkle::image::io::check_size(width, height).map_err(|m| invalid(format!("size: {m}")))?;
    let pattern = Pattern::new(pattern_params(kind, params)?, 2, tileable).py_err()?;
    wrinkle::limits::reserve((width * height * 16) as u64, || format!("a {width}x{height} pattern")).py_err()?;
    let (t, rgb) = py.detach(|| {
        let mut t = vec![0.0f32; width * height];
        bake_rows(&pattern, width, height, 0, &mut t);
        let rgb: Vec<f32> = t.par_iter().flat_map_iter(|&t| spline(&pattern.params.colors, t)).collect();
        (t, rgb)
    });
    Ok((output(py, &[height, width], t), output(py, &[height, width, 3], rgb)))
}

/// Every pattern kind with its one-line description.
#[pyfunction]
fn pattern_kinds() -> Vec<(&'static str, &'static str)> {
    Kind::ALL.iter().map(|k| (k.name(), k.describe())).collect()
}
