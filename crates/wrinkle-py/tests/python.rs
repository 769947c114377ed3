//! Runs the Python package's tests (tests/*.py, with pytest) and its examples against the extension module
//! this build made, in a virtual environment made here from requirements-test.txt (nothing installed by
//! hand): `cargo test --release --workspace` is the one command that tests every front end.

use std::path::{Path, PathBuf};
use std::process::Command;

/// target/<profile>: the test binary runs from target/<profile>/deps.
fn profile_dir() -> PathBuf {
    let exe = std::env::current_exe().expect("the test binary's path");
    exe.parent().and_then(Path::parent).expect("target/<profile>/deps").to_path_buf()
}

fn run(cmd: &mut Command, what: &str) {
    let status = cmd.status().unwrap_or_else(|e| panic!("{what}: cannot start: {e}"));
    assert!(status.success(), "{what} failed ({status})");
}

/// The venv with the test requirements, made again when they change.
fn venv(target: &Path, crate_dir: &Path) -> PathBuf {
    let venv = target.join("py-venv");
    let python = venv.join("bin/python");
    let wanted = std::fs::read_to_string(crate_dir.join("requirements-test.txt")).expect("requirements-test.txt");
    let stamp = venv.join("wrinkle-requirements.txt");
    if python.exists() && std::fs::read_to_string(&stamp).is_ok_and(|s| s == wanted) {
        return python;
    }
    let _ = std::fs::remove_dir_all(&venv);
    run(Command::new("python3").args(["-m", "venv"]).arg(&venv), "python3 -m venv");
    run(
        Command::new(&python)
            .args(["-m", "pip", "install", "--quiet", "--disable-pip-version-check", "-r"])
            .arg(crate_dir.join("requirements-test.txt")),
        "pip install -r requirements-test.txt",
    );
    std::fs::write(&stamp, wanted).expect("the venv's stamp");
    python
}

#[path = "../../wrinkle-cli/tests/end_to_end/portable_build.rs"]
mod portable_build;

/// The extension module built for baseline x86-64 (with the CLI, as the CLI's tests build them), or None off
/// x86-64.
fn portable_module(target: &Path) -> Option<PathBuf> {
    cfg!(target_arch = "x86_64").then(|| portable_build::build_portable(target).join("lib_wrinkle.so"))
}

/// Copies the Python files of the folder `from` into `to`.
fn copy_python_files(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).expect("the staging folder");
    for entry in std::fs::read_dir(from).expect("a package folder") {
        let path = entry.expect("a package file").path();
        if path.is_file() && path.extension().is_some_and(|e| e == "py" || e == "pyi" || e == "typed") {
            std::fs::copy(&path, to.join(path.file_name().unwrap())).expect("copying a package file");
        }
    }
}

/// The package as it would be installed: its Python files, the extension under its module name and the
/// portable one where there is one.
fn stage(profile: &Path, crate_dir: &Path, portable: Option<&Path>) -> PathBuf {
    let stage = profile.join("py-stage");
    let package = stage.join("wrinkle");
    let _ = std::fs::remove_dir_all(&stage);
    copy_python_files(&crate_dir.join("python/wrinkle"), &package);
    if let Some(module) = portable {
        std::fs::copy(module, package.join("_wrinkle_portable.abi3.so")).expect("copying the portable module");
    }
    // Cargo writes the cdylib into deps/ in every build of the package (uplifted beside it only by `cargo build`).
    let built = profile.join("deps/lib_wrinkle.so");
    assert!(built.exists(), "{} is missing: the extension module was not built", built.display());
    std::fs::copy(&built, package.join("_wrinkle.abi3.so")).expect("copying the extension module");
    stage
}

#[test]
fn python_package_tests_and_examples() {
    if Command::new("python3").arg("--version").output().is_err() {
        assert!(std::env::var_os("CI").is_none(), "CI must have python3");
        eprintln!("python3 not found: skipping the Python package's tests");
        return;
    }
    let crate_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let repo = crate_dir.join("../..").canonicalize().expect("the repository");
    let profile = profile_dir();
    let python = venv(profile.parent().expect("target/"), crate_dir);
    let portable = portable_module(profile.parent().expect("target/"));
    let stage = stage(&profile, crate_dir, portable.as_deref());
    let cli = profile.join("wrinkle");
    if std::env::var_os("CI").is_some() {
        assert!(cli.exists(), "{} is missing: run the workspace's tests (--workspace)", cli.display());
    }
    let mut pytest = Command::new(&python);
    pytest
        .args(["-m", "pytest", "-q", "-p", "no:cacheprovider"])
        .arg(crate_dir.join("tests"))
        .env("PYTHONPATH", &stage)
        .env("WRINKLE_REPO", &repo)
        .env("MPLBACKEND", "Agg")
        // pytest's report reaches the log even where an interpreter dies (Ray's driver aborting).
        .env("PYTHONUNBUFFERED", "1")
        .env("WRINKLE_PORTABLE_STAGED", if portable.is_some() { "1" } else { "0" })
        .current_dir(&repo);
    if cli.exists() {
        pytest.env("WRINKLE_CLI", &cli);
    }
    run(&mut pytest, "pytest");
}
