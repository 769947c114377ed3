//! The Python extension module `wrinkle._wrinkle`: the core crate's functions over NumPy arrays. The
//! package's Python layer (python/wrinkle) gives them their documented names, defaults and dtype rules;
//! here every array arrives as C-contiguous float32 (or uint8 where named), and every long call releases
//! the GIL and runs on all cores.

use pyo3::prelude::*;

mod arrays;
mod command;
mod errors;
mod images;
mod noise;
mod scene;
mod texture;

/// Whether this CPU runs x86-64-v3 code: the portable module answers before the package loads the other.
#[pyfunction]
fn cpu_runs_x86_64_v3() -> bool {
    wrinkle::cpu::runs_x86_64_v3()
}

// The portable build is `wrinkle._wrinkle_portable`, beside this one in the same package (maturin leaves out
// of a wheel any other file named as the module).
#[pymodule]
#[cfg_attr(not(all(target_arch = "x86_64", target_feature = "avx2")), pyo3(name = "_wrinkle_portable"))]
fn _wrinkle(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("BUILD_LEVEL", wrinkle::cpu::BUILD_LEVEL)?;
    m.add_function(wrap_pyfunction!(cpu_runs_x86_64_v3, m)?)?;
    m.add("SceneError", m.py().get_type::<errors::SceneError>())?;
    m.add_class::<scene::Scene>()?;
    m.add_class::<texture::Texture>()?;
    command::register(m)?;
    images::register(m)?;
    noise::register(m)?;
    Ok(())
}
