//! The page of `wrinkle paint` (web/): its committed build (web/dist, embedded in the binary) is the build of
//! its source, and in headless Chromium it paints the sphere under a drag (web/tests/paint.test.mjs against a
//! running `wrinkle paint scenes/paint_sphere.toml`). Both need node and npm (and the second Chromium): without
//! them the tests say why and pass, except under CI, which must have them (.ci/run installs Chromium).

use std::fs::{self, File};
use std::io::{Read, Write};
use std::net::{TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant, SystemTime};

/// The files the binary embeds (src/page.rs).
const BUILT: [&str; 3] = ["index.html", "assets/app.js", "assets/app.css"];

fn web() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("web")
}

/// The repository, where the scenes' relative paths start.
fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..").canonicalize().expect("the repository")
}

/// target/<profile>: the test binary runs from target/<profile>/deps.
fn profile_dir() -> PathBuf {
    let exe = std::env::current_exe().expect("the test binary's path");
    exe.parent().and_then(Path::parent).expect("target/<profile>/deps").to_path_buf()
}

/// Whether `program --version` runs; if not, the test is skipped, or fails under CI (the project's rule).
fn have(program: &str, what: &str) -> bool {
    if Command::new(program).arg("--version").stdout(Stdio::null()).stderr(Stdio::null()).status().is_ok() {
        return true;
    }
    assert!(std::env::var_os("CI").is_none(), "CI must have {program} for this test");
    eprintln!("{program} not found: skipping {what}");
    false
}

/// Debian's Chromium, or one on PATH.
fn chromium() -> Option<PathBuf> {
    let path = std::env::var_os("PATH").unwrap_or_default();
    let on_path = std::env::split_paths(&path).map(|dir| dir.join("chromium"));
    std::iter::once(PathBuf::from("/usr/bin/chromium")).chain(on_path).find(|p| p.is_file())
}

fn run(cmd: &mut Command, what: &str) {
    let status = cmd.status().unwrap_or_else(|e| panic!("{what}: cannot start: {e}"));
    assert!(status.success(), "{what} failed ({status})");
}

/// The page's source copied to target/paint-page-build with its node_modules, made by `npm ci` only when
/// package-lock.json changed. The returned file holds a lock on the folder: the two tests, and other test
/// runs on the same target folder, take turns.
fn page_build() -> (File, PathBuf) {
    let dir = profile_dir().parent().expect("target/").join("paint-page-build");
    fs::create_dir_all(&dir).expect("the page's build folder");
    let lock = File::create(dir.with_extension("lock")).expect("the build folder's lock file");
    lock.lock().expect("locking the page's build folder");
    for entry in fs::read_dir(&dir).expect("the page's build folder") {
        let path = entry.expect("a build file").path();
        if path.file_name().is_some_and(|n| n != "node_modules") {
            let gone = if path.is_dir() { fs::remove_dir_all(&path) } else { fs::remove_file(&path) };
            gone.expect("clearing the page's build folder");
        }
    }
    copy_tree(&web(), &dir, &["node_modules", "dist"]);
    let wanted = fs::read(dir.join("package-lock.json")).expect("package-lock.json");
    let stamp = dir.join("node_modules/.wrinkle-package-lock.json");
    if fs::read(&stamp).ok().as_ref() != Some(&wanted) {
        run(Command::new("npm").args(["ci", "--no-audit", "--no-fund"]).current_dir(&dir), "npm ci");
        fs::write(&stamp, wanted).expect("node_modules' stamp");
    }
    (lock, dir)
}

/// Copies the folder `from` into `to`, less the entries of `from` named in `skip`.
fn copy_tree(from: &Path, to: &Path, skip: &[&str]) {
    fs::create_dir_all(to).expect("a build folder");
    for entry in fs::read_dir(from).expect("a page folder") {
        let entry = entry.expect("a page file");
        if skip.iter().any(|s| entry.file_name() == *s) {
            continue;
        }
        let target = to.join(entry.file_name());
        if entry.file_type().expect("a page file's type").is_dir() {
            copy_tree(&entry.path(), &target, &[]);
        } else {
            fs::copy(entry.path(), &target).expect("copying a page file");
        }
    }
}

#[test]
fn committed_page_matches_its_source() {
    if !have("node", "the page's build check") || !have("npm", "the page's build check") {
        return;
    }
    let (_lock, dir) = page_build();
    run(Command::new("npm").args(["run", "build"]).current_dir(&dir), "npm run build");
    for file in BUILT {
        let built = fs::read(dir.join("dist").join(file)).expect("a built page file");
        let committed = fs::read(web().join("dist").join(file)).expect("a committed page file");
        assert!(
            built == committed,
            "dist/{file}: the committed page (crates/wrinkle-paint/web/dist) is not the build of its source: \
             run npm run build in crates/wrinkle-paint/web and commit dist"
        );
    }
}

/// The newest modification time of the files under `path`.
fn newest(path: &Path) -> SystemTime {
    let Ok(meta) = fs::metadata(path) else { return SystemTime::UNIX_EPOCH };
    if !meta.is_dir() {
        return meta.modified().expect("a file's modification time");
    }
    let entries = fs::read_dir(path).expect("a source folder");
    entries.map(|e| newest(&e.expect("a source file").path())).max().unwrap_or(SystemTime::UNIX_EPOCH)
}

/// The `wrinkle` binary of this profile (wrinkle-cli's, so no CARGO_BIN_EXE here), built when missing or
/// older than its sources. `cargo test --workspace` has just built it: building it again there with other
/// features would replace it under the CLI's own tests.
fn wrinkle_binary() -> PathBuf {
    let profile = profile_dir();
    let binary = profile.join("wrinkle");
    let repo = repo();
    let sources = ["Cargo.toml", "Cargo.lock", "crates/wrinkle-paint/web/dist"].into_iter().map(String::from).chain(
        ["wrinkle", "wrinkle-cli", "wrinkle-paint"]
            .into_iter()
            .flat_map(|c| [format!("crates/{c}/Cargo.toml"), format!("crates/{c}/src")]),
    );
    let source_time = sources.map(|s| newest(&repo.join(s))).max().expect("sources");
    if fs::metadata(&binary).and_then(|m| m.modified()).is_ok_and(|t| t >= source_time) {
        return binary;
    }
    let mut cargo = Command::new(std::env::var_os("CARGO").unwrap_or("cargo".into()));
    cargo.args(["build", "-p", "wrinkle-cli", "--target-dir"]).arg(profile.parent().expect("target/"));
    if profile.ends_with("release") {
        cargo.arg("--release");
    }
    run(&mut cargo, "building the wrinkle binary");
    binary
}

/// A running `wrinkle paint`, killed when dropped (a failing test too), with its scratch folder.
struct Server {
    child: Child,
    dir: PathBuf,
    port: u16,
}

impl Server {
    fn start(binary: &Path) -> Server {
        // A port that was free a moment ago: the server is told it, and fails loudly if it was taken since.
        let port = TcpListener::bind("127.0.0.1:0").and_then(|l| l.local_addr()).expect("a free port").port();
        let dir = profile_dir().parent().expect("target/").join(format!("paint-page-run-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).expect("the server's scratch folder");
        // Its output goes to a file: a pipe nobody reads could fill and stall it.
        let log = File::create(dir.join("server.log")).expect("the server's log");
        let child = Command::new(binary)
            .args(["paint", "scenes/paint_sphere.toml", "--port", &port.to_string(), "--save-dir"])
            .arg(dir.join("saved"))
            .current_dir(repo())
            .stdin(Stdio::null())
            .stdout(log.try_clone().expect("the server's log"))
            .stderr(log)
            .spawn()
            .unwrap_or_else(|e| panic!("cannot start {}: {e}", binary.display()));
        Server { child, dir, port }
    }

    fn log(&self) -> String {
        fs::read_to_string(self.dir.join("server.log")).unwrap_or_default()
    }

    /// Whether GET /api/state answers 200.
    fn answers(&self) -> bool {
        let Ok(mut stream) = TcpStream::connect(("127.0.0.1", self.port)) else { return false };
        let _ = stream.set_read_timeout(Some(Duration::from_secs(5)));
        let request = format!("GET /api/state HTTP/1.1\r\nHost: 127.0.0.1:{}\r\nConnection: close\r\n\r\n", self.port);
        let mut status = [0u8; 12];
        stream.write_all(request.as_bytes()).is_ok()
            && stream.read_exact(&mut status).is_ok()
            && status.starts_with(b"HTTP/1.1 200")
    }

    fn wait_until_it_answers(&mut self) {
        let start = Instant::now();
        while !self.answers() {
            if let Ok(Some(status)) = self.child.try_wait() {
                panic!("wrinkle paint exited ({status}) before answering:\n{}", self.log());
            }
            assert!(start.elapsed() < Duration::from_secs(30), "wrinkle paint did not answer in 30 s:\n{}", self.log());
            std::thread::sleep(Duration::from_millis(100));
        }
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
        let _ = fs::remove_dir_all(&self.dir);
    }
}

#[test]
fn page_paints_the_sphere_under_a_drag() {
    if !have("node", "the page's browser test") || !have("npm", "the page's browser test") {
        return;
    }
    let Some(chromium) = chromium() else {
        assert!(std::env::var_os("CI").is_none(), "CI must have Chromium (/usr/bin/chromium) for this test");
        eprintln!("chromium not found: skipping the page's browser test");
        return;
    };
    let mut server = Server::start(&wrinkle_binary());
    server.wait_until_it_answers();
    // The script and its node_modules (playwright-core, pngjs) from the shared build folder.
    let (_lock, dir) = page_build();
    let out = Command::new("node")
        .arg("tests/paint.test.mjs")
        .env("WRINKLE_PAINT_URL", format!("http://127.0.0.1:{}", server.port))
        .env("CHROMIUM", &chromium)
        .current_dir(&dir)
        .output()
        .expect("node tests/paint.test.mjs");
    print!("{}", String::from_utf8_lossy(&out.stdout));
    assert!(
        out.status.success(),
        "node tests/paint.test.mjs failed ({}):\n{}\nserver log:\n{}",
        out.status,
        String::from_utf8_lossy(&out.stderr),
        server.log()
    );
}
