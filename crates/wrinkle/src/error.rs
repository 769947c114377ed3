//! The library's error type: every variant names what failed and why.

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A scene field is missing, of the wrong type, or out of range. `path` is like `objects[2].material.bump.scale`.
    #[error("{path}: {message}")]
    Scene { path: String, message: String },
    /// A scene or image file could not be read or decoded.
    #[error("{}: {message}", path.display())]
    Read { path: PathBuf, message: String },
    /// An output file could not be written.
    #[error("{}: cannot write: {message}", path.display())]
    Write { path: PathBuf, message: String },
    /// A parameter given by the caller is out of range, by its own name (`spp`, `line_width`); `message`
    /// follows the name ("must be between 1 and 4096, got 0"). Each front end words the name its way: `--spp` on the
    /// command line, the field's path in a scene, `spp=` in Python.
    #[error("{name} {message}")]
    Parameter { name: &'static str, message: String },
    /// A request that cannot be carried out, not tied to one parameter.
    #[error("{0}")]
    Invalid(String),
    /// The caller asked the work to stop before it was done.
    #[error("interrupted")]
    Interrupted,
}

pub type Result<T> = std::result::Result<T, Error>;

impl Error {
    pub fn scene(path: impl Into<String>, message: impl Into<String>) -> Self {
        Error::Scene { path: path.into(), message: message.into() }
    }
    pub fn read(path: impl Into<PathBuf>, message: impl std::fmt::Display) -> Self {
        Error::Read { path: path.into(), message: message.to_string() }
    }
    pub fn write(path: impl Into<PathBuf>, message: impl std::fmt::Display) -> Self {
        Error::Write { path: path.into(), message: message.to_string() }
    }
    pub fn parameter(name: &'static str, message: impl Into<String>) -> Self {
        Error::Parameter { name, message: message.into() }
    }
}
