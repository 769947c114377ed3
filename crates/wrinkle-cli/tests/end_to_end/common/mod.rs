//! Helpers shared by the end-to-end tests: a scratch folder per test, running the built binary, and the
//! checks of a successful run and of a one-line error that leaves nothing behind.
// Each test file uses its own subset of these.
#![allow(dead_code)]

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::atomic::{AtomicUsize, Ordering};

/// A fresh folder under the system temp dir, removed when dropped. Inputs (scenes, textures) go in
/// `in/`, outputs in `out/`, so that "nothing left behind" means `out/` holds exactly what it should.
pub struct Scratch(PathBuf);

impl Scratch {
    pub fn new(name: &str) -> Self {
        static COUNTER: AtomicUsize = AtomicUsize::new(0);
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let dir = std::env::temp_dir().join(format!("wrinkle-cli-test-{}-{n}-{name}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(dir.join("in")).unwrap();
        fs::create_dir_all(dir.join("out")).unwrap();
        Scratch(dir)
    }

    /// `in/{name}` as a string argument.
    pub fn input(&self, name: &str) -> String {
        path_arg(&self.0.join("in").join(name))
    }

    /// Writes `in/{name}` and returns its path.
    pub fn write_input(&self, name: &str, contents: impl AsRef<[u8]>) -> String {
        let path = self.input(name);
        fs::write(&path, contents).unwrap();
        path
    }

    /// `out/{name}` as a string argument.
    pub fn out(&self, name: &str) -> String {
        path_arg(&self.0.join("out").join(name))
    }

    /// The sorted names in `out/`, hidden (temporary) files included.
    pub fn out_entries(&self) -> Vec<String> {
        let mut names: Vec<String> = fs::read_dir(self.0.join("out"))
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = fs::remove_dir_all(&self.0);
    }
}

pub fn path_arg(p: &Path) -> String {
    p.to_str().expect("temp paths are UTF-8").to_string()
}

/// What one run of the binary gave back.
#[derive(Debug)]
pub struct Run {
    pub code: i32,
    pub stdout: String,
    pub stderr: String,
}

/// Runs `wrinkle` with `args` and captures its exit code, stdout and stderr.
pub fn wrinkle<S: AsRef<std::ffi::OsStr>>(args: &[S]) -> Run {
    let out = Command::new(env!("CARGO_BIN_EXE_wrinkle")).args(args).output().expect("run wrinkle");
    Run {
        // A run killed by a signal has no code; -1 fails every comparison below.
        code: out.status.code().unwrap_or(-1),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
    }
}

/// Asserts a successful run.
pub fn assert_ok(run: &Run) {
    assert_eq!(run.code, 0, "expected success: {run:#?}");
}

/// Asserts a failed run: exit `code`, stderr exactly one line `error: ...` that contains every one of
/// `names`, and nothing at all in the scratch output folder (no output file, no temporary file).
pub fn assert_one_error(run: &Run, code: i32, names: &[&str], scratch: &Scratch) {
    assert_eq!(run.code, code, "exit code: {run:#?}");
    let lines: Vec<&str> = run.stderr.lines().collect();
    assert_eq!(lines.len(), 1, "stderr must be one line: {:?}", run.stderr);
    assert!(lines[0].starts_with("error: "), "stderr must start with `error: `: {:?}", run.stderr);
    for name in names {
        assert!(lines[0].contains(name), "stderr must name {name:?}: {:?}", run.stderr);
    }
    assert_eq!(scratch.out_entries(), Vec::<String>::new(), "output folder must stay empty");
}
