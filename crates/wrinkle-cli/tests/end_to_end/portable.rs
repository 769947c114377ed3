//! The portable build (baseline x86-64, built here as scripts/build-portable.sh builds it) writes the same
//! bytes as the default x86-64-v3 build, and on a CPU without AVX2 (qemu-user emulating a Westmere) the
//! default build hands the command over to it, or says what is missing, instead of dying of SIGILL.

use crate::common::*;
use crate::portable_build::build_portable;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;

/// The repository, where the scenes' relative paths start.
fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..").canonicalize().unwrap()
}

/// The portable CLI, built once for the whole file in its own target folder.
fn portable() -> &'static Path {
    static BUILT: OnceLock<PathBuf> = OnceLock::new();
    BUILT.get_or_init(|| {
        let default = Path::new(env!("CARGO_BIN_EXE_wrinkle"));
        let target = default.parent().and_then(Path::parent).expect("target/<profile>/wrinkle");
        build_portable(target).join("wrinkle")
    })
}

fn run_in_repo(program: &[&str], args: &[String]) -> Output {
    let out = Command::new(program[0]).args(&program[1..]).args(args).current_dir(repo()).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{program:?} {args:?}: {stderr}");
    out
}

/// Every file the commands wrote into `dir`, by name.
fn files(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut all: Vec<_> = fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let e = e.unwrap();
            (e.file_name().to_string_lossy().into_owned(), fs::read(e.path()).unwrap())
        })
        .collect();
    all.sort();
    all
}

#[cfg(target_arch = "x86_64")]
#[test]
fn the_portable_build_writes_the_same_bytes() {
    // Renders touch every lane kernel: bump tables, textures and their filters, environment charts
    // (atan2, asin), Phong powers, displacement, meshes, solid noise; then the image tools.
    let cases: Vec<Vec<&str>> = vec![
        vec!["render", "-o", "OUT/default.exr", "--aov", "normal,uv,depth,id"],
        vec!["render", "scenes/environment_chrome.toml", "-o", "OUT/chrome.exr"],
        vec!["render", "scenes/parallax.toml", "-o", "OUT/parallax.exr", "--aov", "normal"],
        vec!["render", "scenes/mesh.toml", "-o", "OUT/mesh.exr"],
        vec!["render", "scenes/solid_marble.toml", "-o", "OUT/marble.exr"],
        vec!["render", "scenes/displacement_silhouette.toml", "-o", "OUT/silhouette.exr"],
        vec!["render", "scenes/layers.toml", "-o", "OUT/layers.png", "--filter", "ewa"],
        vec!["emboss", "scenes/maps/emblem.png", "-o", "OUT/emboss.png"],
        vec!["normalmap", "scenes/maps/bricks_height.png", "-o", "OUT/normals.png"],
        vec!["texture", "fbm", "-o", "OUT/fbm.exr", "--size", "96x64"],
        vec!["texture", "wood", "-o", "OUT/wood.exr", "--size", "96x64"],
        vec!["filters", "-o", "OUT/filters.png"],
    ];
    let (default_out, portable_out) = (Scratch::new("default"), Scratch::new("portable"));
    let size = ["--width", "120", "--height", "90", "--spp", "4"];
    for case in &cases {
        for (binary, scratch) in
            [(env!("CARGO_BIN_EXE_wrinkle"), &default_out), (portable().to_str().unwrap(), &portable_out)]
        {
            let out_dir = scratch.out("");
            let mut args: Vec<String> = case.iter().map(|a| a.replace("OUT/", &out_dir)).collect();
            if case[0] == "render" {
                args.extend(size.iter().map(|s| s.to_string()));
            }
            run_in_repo(&[binary], &args);
        }
    }
    let (a, b) = (files(Path::new(&default_out.out(""))), files(Path::new(&portable_out.out(""))));
    assert!(a.len() >= cases.len(), "{} outputs", a.len());
    assert_eq!(a.iter().map(|f| &f.0).collect::<Vec<_>>(), b.iter().map(|f| &f.0).collect::<Vec<_>>());
    for ((name, x), (_, y)) in a.iter().zip(&b) {
        assert!(x == y, "{name}: the portable build's bytes differ");
    }
}

/// Runs `binary ARGS` on qemu-user's emulation of `cpu`, in the repository.
fn emulated(cpu: &str, binary: &Path, args: &[&str]) -> (Option<i32>, Vec<u8>, Vec<String>) {
    let out = Command::new("qemu-x86_64").args(["-cpu", cpu]).arg(binary).args(args).current_dir(repo()).output();
    let out = out.expect("qemu-x86_64");
    let stderr = String::from_utf8_lossy(&out.stderr);
    let ours = stderr.lines().filter(|l| !l.starts_with("qemu-x86_64: warning")).map(str::to_string).collect();
    (out.status.code(), out.stdout, ours)
}

#[cfg(target_arch = "x86_64")]
#[test]
fn on_a_cpu_without_avx2_the_portable_build_takes_over() {
    // qemu-user emulates older CPUs (.ci/run installs it); without it the check cannot run here.
    if Command::new("qemu-x86_64").arg("--version").output().is_err() {
        assert!(std::env::var_os("CI").is_none(), "CI must install qemu-user for this test");
        eprintln!("qemu-x86_64 not found: skipping the emulated old-CPU runs");
        return;
    }
    let s = Scratch::new("handover");
    let bin = PathBuf::from(s.input(""));
    let (default, beside) = (bin.join("wrinkle"), bin.join("wrinkle-portable"));
    fs::copy(env!("CARGO_BIN_EXE_wrinkle"), &default).unwrap();

    // Alone, on CPUs without AVX2: one line saying what is missing and how to build it.
    for cpu in ["Westmere", "SandyBridge"] {
        let (code, _, err) = emulated(cpu, &default, &["--version"]);
        assert_eq!((code, err.len()), (Some(1), 1), "{cpu}: {err:?}");
        assert!(err[0].starts_with("error: this build of wrinkle needs an x86-64-v3 CPU"), "{err:?}");
        assert!(err[0].ends_with(
            "there is no wrinkle-portable beside it: build the portable one with scripts/build-portable.sh"
        ));
    }
    let (code, stdout, _) = emulated("Haswell", &default, &["--version"]);
    assert_eq!(code, Some(0));
    assert!(String::from_utf8_lossy(&stdout).starts_with("wrinkle "));

    // A copy of the default build installed under the portable name does not start itself again.
    fs::copy(&default, &beside).unwrap();
    let (code, _, err) = emulated("Westmere", &beside, &["--version"]);
    assert_eq!(code, Some(1));
    assert!(err[0].ends_with(
        "and it is itself installed as the portable build: build the portable one with scripts/build-portable.sh"
    ));

    // With the portable build beside it, the command runs there, as typed; the portable build itself runs
    // on the emulated CPU; both write what the default build writes here.
    fs::copy(portable(), &beside).unwrap();
    let render = |binary: &Path, prefix: &[&str], name: &str| {
        let out = s.out(name);
        let args = ["render", "-o", out.as_str(), "--width", "64", "--height", "48", "--spp", "4"];
        let (code, _, err) = if prefix.is_empty() {
            let o = run_in_repo(&[binary.to_str().unwrap()], &args.map(String::from));
            (o.status.code(), o.stdout, vec![])
        } else {
            emulated(prefix[0], binary, &args)
        };
        assert_eq!(code, Some(0), "{name}: {err:?}");
        fs::read(out).unwrap()
    };
    let native = render(Path::new(env!("CARGO_BIN_EXE_wrinkle")), &[], "native.png");
    assert!(render(&default, &["Westmere"], "handed_over.png") == native, "the handed-over render differs");
    assert!(render(&beside, &["Westmere"], "portable.png") == native, "the emulated portable render differs");
}
