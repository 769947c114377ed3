//! The core's errors as Python exceptions, with the core's message.

use pyo3::create_exception;
use pyo3::exceptions::{PyFileNotFoundError, PyKeyboardInterrupt, PyOSError, PyValueError};
use pyo3::PyErr;
use wrinkle::Error;

create_exception!(
    _wrinkle,
    SceneError,
    PyValueError,
    "A scene that cannot be used: a missing, mistyped or out-of-range field, named by its path."
);

/// ValueError for bad arguments, FileNotFoundError for a file that is not there, OSError for one that
/// cannot be read or written, SceneError for scene problems, KeyboardInterrupt for an interrupted call.
pub fn to_py(e: Error) -> PyErr {
    let message = e.to_string();
    match e {
        Error::Scene { .. } => SceneError::new_err(message),
        Error::Read { path, .. } if !path.exists() => PyFileNotFoundError::new_err(message),
        Error::Read { .. } | Error::Write { .. } => PyOSError::new_err(message),
        // A parameter in Python's words: the keyword argument.
        Error::Parameter { name, message } => PyValueError::new_err(format!("{name}= {message}")),
        Error::Invalid(_) => PyValueError::new_err(message),
        Error::Interrupted => PyKeyboardInterrupt::new_err(message),
    }
}

/// `Result` of the core, as a `PyResult`.
pub trait IntoPy<T> {
    fn py_err(self) -> pyo3::PyResult<T>;
}

impl<T> IntoPy<T> for wrinkle::Result<T> {
    fn py_err(self) -> pyo3::PyResult<T> {
        self.map_err(to_py)
    }
}

/// A ValueError naming the argument.
pub fn invalid(message: impl Into<String>) -> PyErr {
    PyValueError::new_err(message.into())
}
