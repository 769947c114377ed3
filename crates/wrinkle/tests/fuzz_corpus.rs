//! The fuzz targets (fuzz/targets.rs, the same bodies cargo-fuzz runs) on stable Rust, in two parts per
//! target:
//!
//! - `replay::<target>`: every file of fuzz/corpus/<target>/ once, and every file of
//!   fuzz/regressions/<target>/ (the minimised inputs of bugs found) once in a child process of its own;
//! - `mutate::<target>`: a bounded-time mutation loop over the corpus (deterministic seed; bit flips,
//!   random bytes, interesting integers, byte insertion and deletion, copies within an input, splices
//!   of two corpus files, numbers in text swapped for extreme ones, tokens of the target's dictionary
//!   fuzz/<target>.dict), for `WRINKLE_FUZZ_SECONDS` seconds per target (default 3; 0 turns it off).
//!   `WRINKLE_FUZZ_SEED` changes the seed.
//!
//! The invariant: every input gives `Ok` or `Err`. A panic fails the test; an input running longer than
//! `WRINKLE_FUZZ_TIMEOUT` seconds (default 10) or asking for memory beyond `WRINKLE_FUZZ_MAX_MB` in all
//! (default 2048; the fuzzer runs with -rss_limit_mb=4096) ends the process. Either way the input is saved under
//! target/tmp/fuzz-failures/<target>/ and its start shown in hex.

#[path = "../../../fuzz/targets.rs"]
mod targets;

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::{Cell, RefCell};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, OnceLock};
use std::time::{Duration, Instant};

// ---------------------------------------------------------------------------------------------------
// Memory: every allocation is counted; one that would take the process past the cap waits for the
// watchdog, which saves the inputs being run and ends the process.

struct CountingAlloc;

static LIVE: AtomicUsize = AtomicUsize::new(0);
/// The most bytes the process may hold; unlimited until the watchdog runs.
static CAP: AtomicUsize = AtomicUsize::new(usize::MAX);
/// The size of a refused request (0: none), and the slot of the thread that made it.
static REFUSED: AtomicUsize = AtomicUsize::new(0);
static REFUSED_SLOT: AtomicUsize = AtomicUsize::new(usize::MAX);

thread_local! {
    /// The harness slot of this thread (usize::MAX: none, e.g. a rayon worker).
    static SLOT: Cell<usize> = const { Cell::new(usize::MAX) };
    /// The message and place of the last panic on this thread.
    static LAST_PANIC: RefCell<Option<String>> = const { RefCell::new(None) };
}

impl CountingAlloc {
    fn admit(&self, size: usize) {
        let live = LIVE.load(Ordering::Relaxed);
        if live.saturating_add(size) > CAP.load(Ordering::Relaxed) {
            REFUSED_SLOT.store(SLOT.try_with(Cell::get).unwrap_or(usize::MAX), Ordering::SeqCst);
            REFUSED.store(size.max(1), Ordering::SeqCst);
            // The watchdog reports and exits; this thread must not allocate meanwhile.
            loop {
                std::thread::sleep(Duration::from_secs(1));
            }
        }
    }
}

unsafe impl GlobalAlloc for CountingAlloc {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        self.admit(layout.size());
        let p = System.alloc(layout);
        if !p.is_null() {
            LIVE.fetch_add(layout.size(), Ordering::Relaxed);
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        self.admit(layout.size());
        let p = System.alloc_zeroed(layout);
        if !p.is_null() {
            LIVE.fetch_add(layout.size(), Ordering::Relaxed);
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout);
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        if new_size > layout.size() {
            self.admit(new_size - layout.size());
        }
        let p = System.realloc(ptr, layout, new_size);
        if !p.is_null() {
            LIVE.fetch_add(new_size, Ordering::Relaxed);
            LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
        }
        p
    }
}

#[global_allocator]
static ALLOC: CountingAlloc = CountingAlloc;

// ---------------------------------------------------------------------------------------------------
// Slots: what each test thread is running, for the watchdog.

struct Slot {
    target: &'static str,
    input: Vec<u8>,
    started: Option<Instant>,
}

static SLOTS: Mutex<Vec<Slot>> = Mutex::new(Vec::new());

fn env_number(name: &str, default: f64) -> f64 {
    match std::env::var(name) {
        Ok(v) => v.trim().parse().unwrap_or_else(|_| panic!("{name}={v} is not a number")),
        Err(_) => default,
    }
}

/// Starts the watchdog and the panic hook once.
fn harness() {
    static STARTED: OnceLock<()> = OnceLock::new();
    STARTED.get_or_init(|| {
        let timeout = Duration::from_secs_f64(env_number("WRINKLE_FUZZ_TIMEOUT", 10.0));
        let cap = (env_number("WRINKLE_FUZZ_MAX_MB", 2048.0) * 1024.0 * 1024.0) as usize;
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            let place =
                info.location().map_or(String::new(), |l| format!(" at {}:{}:{}", l.file(), l.line(), l.column()));
            let message = info.payload_as_str().map_or_else(|| payload_message(info.payload()), str::to_string);
            let _ = LAST_PANIC.try_with(|p| *p.borrow_mut() = Some(format!("{message}{place}")));
            previous(info);
        }));
        std::thread::Builder::new()
            .name("fuzz-watchdog".into())
            .spawn(move || watchdog(timeout))
            .expect("start the fuzz watchdog");
        CAP.store(cap, Ordering::SeqCst);
    });
}

fn watchdog(timeout: Duration) -> ! {
    loop {
        std::thread::sleep(Duration::from_millis(50));
        let refused = REFUSED.load(Ordering::SeqCst);
        let slots = SLOTS.lock().unwrap_or_else(|e| e.into_inner());
        if refused != 0 {
            let slot = REFUSED_SLOT.load(Ordering::SeqCst);
            let live = LIVE.load(Ordering::Relaxed);
            fatal(&format!(
                "fuzz harness: a request for {refused} bytes with {live} held passes the memory cap of {} MB",
                CAP.load(Ordering::Relaxed) >> 20
            ));
            // A rayon worker has no slot: every input being run may be the culprit.
            for (k, s) in slots.iter().enumerate() {
                if s.started.is_some() && (slot == usize::MAX || slot == k) {
                    report_fatal(s, "out of memory");
                }
            }
            std::process::exit(101);
        }
        for s in slots.iter() {
            if s.started.is_some_and(|t| t.elapsed() > timeout) {
                report_fatal(s, &format!("running longer than {} s", timeout.as_secs_f64()));
                std::process::exit(101);
            }
        }
    }
}

fn report_fatal(slot: &Slot, what: &str) {
    let path = save_failure(slot.target, &slot.input);
    fatal(&format!(
        "fuzz harness: {}: an input {what}: saved as {}\n{}",
        slot.target,
        path.display(),
        hex(&slot.input)
    ));
}

/// A line straight to the process's stderr: the watchdog inherits a test's output capture, which is lost
/// when the process exits.
fn fatal(message: &str) {
    use std::io::Write;
    let _ = writeln!(std::io::stderr(), "{message}");
}

fn payload_message(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        s.to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "a panic without a message".into()
    }
}

/// The failing input saved under target/tmp/fuzz-failures/<target>/, named by its hash.
fn save_failure(target: &str, input: &[u8]) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("fuzz-failures").join(target);
    let _ = std::fs::create_dir_all(&dir);
    let hash = input.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &b| (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3));
    let path = dir.join(format!("crash-{hash:016x}"));
    let _ = std::fs::write(&path, input);
    path
}

/// The first 256 bytes of an input as a hex dump.
fn hex(input: &[u8]) -> String {
    let mut out = format!("{} bytes:\n", input.len());
    for (k, row) in input.chunks(16).take(16).enumerate() {
        let bytes: String = row.iter().map(|b| format!("{b:02x} ")).collect();
        let text: String =
            row.iter().map(|&b| if b.is_ascii_graphic() || b == b' ' { b as char } else { '.' }).collect();
        out += &format!("{:08x}  {bytes:<48} {text}\n", 16 * k);
    }
    if input.len() > 256 {
        out += "...\n";
    }
    out
}

/// One test thread's runner: its slot, and the target it runs.
struct Runner {
    slot: usize,
    name: &'static str,
    run: fn(&[u8]),
    slowest: Duration,
    /// The input that took `slowest`.
    slowest_input: Vec<u8>,
}

impl Runner {
    fn new(name: &str) -> Runner {
        harness();
        let &(name, run) =
            targets::TARGETS.iter().find(|(n, _)| *n == name).unwrap_or_else(|| panic!("no target {name}"));
        let mut slots = SLOTS.lock().unwrap();
        slots.push(Slot { target: name, input: Vec::new(), started: None });
        let slot = slots.len() - 1;
        SLOT.with(|s| s.set(slot));
        Runner { slot, name, run, slowest: Duration::ZERO, slowest_input: Vec::new() }
    }

    /// Runs one input: `Err` with the panic's message and place if it panics.
    fn run(&mut self, input: &[u8]) -> Result<(), String> {
        let mut copy = input.to_vec();
        let start = Instant::now();
        {
            let mut slots = SLOTS.lock().unwrap();
            std::mem::swap(&mut slots[self.slot].input, &mut copy);
            slots[self.slot].started = Some(start);
        }
        drop(copy);
        LAST_PANIC.with(|p| p.borrow_mut().take());
        let result = catch_unwind(AssertUnwindSafe(|| (self.run)(input)));
        SLOTS.lock().unwrap()[self.slot].started = None;
        if start.elapsed() > self.slowest {
            self.slowest = start.elapsed();
            self.slowest_input = input.to_vec();
        }
        result
            .map_err(|payload| LAST_PANIC.with(|p| p.borrow_mut().take()).unwrap_or_else(|| payload_message(&*payload)))
    }

    fn failure(&self, input: &[u8], message: &str) -> String {
        let path = save_failure(self.name, input);
        format!("{}: panic: {message}\ninput saved as {}\n{}", self.name, path.display(), hex(input))
    }
}

impl Drop for Runner {
    fn drop(&mut self) {
        SLOT.with(|s| s.set(usize::MAX));
        targets::remove_scratch_dir();
    }
}

fn fuzz_dir() -> PathBuf {
    targets::repo_root().join("fuzz")
}

/// The files of fuzz/<folder>/<target>/ (`corpus` or `regressions`), by name.
fn files_of(folder: &str, name: &str) -> Vec<(PathBuf, Vec<u8>)> {
    let mut files = Vec::new();
    let Ok(entries) = std::fs::read_dir(fuzz_dir().join(folder).join(name)) else { return files };
    for entry in entries {
        let path = entry.expect("read a corpus folder").path();
        if path.is_file() {
            let bytes = std::fs::read(&path).expect("read a corpus file");
            files.push((path, bytes));
        }
    }
    files.sort();
    files
}

/// The corpus in this process; each regression input (a bug the fuzzer found, which may still end the
/// process by running out of memory or time) in a child process of its own, so that every one is reported.
fn replay(name: &'static str) {
    let files = files_of("corpus", name);
    assert!(!files.is_empty(), "fuzz/corpus/{name}/ is empty");
    let mut runner = Runner::new(name);
    let start = Instant::now();
    let mut failures: Vec<String> = files
        .iter()
        .filter_map(|(path, bytes)| {
            runner.run(bytes).err().map(|m| format!("{}\n  from {}", runner.failure(bytes, &m), path.display()))
        })
        .collect();
    let corpus_time = start.elapsed();
    let regressions = files_of("regressions", name);
    failures.extend(regressions.iter().filter_map(|(path, _)| replay_in_child(name, path).err()));
    println!(
        "replay {name}: {} corpus files in {:.2} s (slowest {:.3} s), {} regressions in {:.2} s",
        files.len(),
        corpus_time.as_secs_f64(),
        runner.slowest.as_secs_f64(),
        regressions.len(),
        (start.elapsed() - corpus_time).as_secs_f64()
    );
    assert!(
        failures.is_empty(),
        "{} of {} corpus and regression files fail:\n\n{}",
        failures.len(),
        files.len() + regressions.len(),
        failures.join("\n\n")
    );
}

/// Runs `path` through target `name` in a child process (this test binary's `regression_child`), `Err`
/// with what it said if it panicked, ran out of memory or time, or died.
fn replay_in_child(name: &str, path: &Path) -> Result<(), String> {
    let exe = std::env::current_exe().expect("the test binary's path");
    let out = std::process::Command::new(exe)
        .args(["--exact", "regression_child", "--nocapture", "--test-threads=1"])
        .env(CHILD_ENV, format!("{name}={}", path.display()))
        .output()
        .expect("start a child test process");
    if out.status.success() {
        return Ok(());
    }
    let text = String::from_utf8_lossy(&out.stdout).into_owned() + &String::from_utf8_lossy(&out.stderr);
    // The panic's message and place, or the watchdog's verdict, without the backtraces.
    let lines: Vec<&str> = text.lines().collect();
    let said: Vec<&str> = (0..lines.len())
        .filter(|&k| {
            let l = lines[k];
            l.contains("panicked at") || l.contains("fuzz harness:") || (k > 0 && lines[k - 1].contains("panicked at"))
        })
        .map(|k| lines[k])
        .collect();
    Err(format!("{name}: {} fails ({}):\n  {}", path.display(), out.status, said.join("\n  ")))
}

const CHILD_ENV: &str = "WRINKLE_FUZZ_CHILD";

/// One regression input, `WRINKLE_FUZZ_CHILD=<target>=<path>`, for `replay_in_child`; nothing without it.
#[test]
fn regression_child() {
    let Ok(spec) = std::env::var(CHILD_ENV) else { return };
    let (name, path) = spec.split_once('=').expect("WRINKLE_FUZZ_CHILD is <target>=<path>");
    let bytes = std::fs::read(path).expect("read the regression input");
    let mut runner = Runner::new(name);
    if runner.run(&bytes).is_err() {
        // The panic hook has printed the message and place.
        std::process::exit(101);
    }
}

// ---------------------------------------------------------------------------------------------------
// Mutation.

/// xorshift64*: small, fast and the same everywhere.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    /// Uniform in 0..n (n > 0).
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }

    fn chance(&mut self, one_in: usize) -> bool {
        self.below(one_in) == 0
    }
}

const INTERESTING: &[u64] = &[
    0,
    1,
    2,
    3,
    4,
    7,
    8,
    15,
    16,
    31,
    32,
    63,
    64,
    100,
    127,
    128,
    255,
    256,
    512,
    1000,
    1024,
    4096,
    32767,
    32768,
    65535,
    65536,
    100_000,
    1 << 24,
    0x7fff_ffff,
    0x8000_0000,
    0xffff_fffe,
    0xffff_ffff,
    u64::MAX,
    u64::MAX - 1,
    i64::MAX as u64,
];

const INTERESTING_TEXT: &[&str] = &[
    "0",
    "-0",
    "1",
    "-1",
    "2",
    "3",
    "0.5",
    "-0.5",
    "255",
    "256",
    "65535",
    "65536",
    "4294967295",
    "4294967296",
    "-2147483648",
    "9223372036854775807",
    "18446744073709551616",
    "1e10",
    "1e38",
    "3.5e38",
    "1e-45",
    "-1e38",
    "nan",
    "inf",
    "-inf",
    "1e400",
    "99999999999",
    "0.0000001",
    "8192",
    "8193",
    "16384",
    "32768",
    "1048576",
];

/// The tokens of fuzz/<target>.dict (libFuzzer's format: one quoted string a line, with \\, \" and \xNN).
fn dictionary(name: &str) -> Vec<Vec<u8>> {
    let Ok(text) = std::fs::read_to_string(fuzz_dir().join(format!("{name}.dict"))) else { return Vec::new() };
    let mut tokens = Vec::new();
    for line in text.lines() {
        let line = line.trim();
        if line.starts_with('#') {
            continue;
        }
        let (Some(a), Some(b)) = (line.find('"'), line.rfind('"')) else { continue };
        if b <= a {
            continue;
        }
        let raw = &line.as_bytes()[a + 1..b];
        let mut token = Vec::new();
        let mut k = 0;
        while k < raw.len() {
            if raw[k] == b'\\' && k + 1 < raw.len() {
                if raw[k + 1] == b'x' && k + 3 < raw.len() {
                    let hex = std::str::from_utf8(&raw[k + 2..k + 4]).unwrap_or("00");
                    token.push(u8::from_str_radix(hex, 16).unwrap_or(0));
                    k += 4;
                } else {
                    token.push(raw[k + 1]);
                    k += 2;
                }
            } else {
                token.push(raw[k]);
                k += 1;
            }
        }
        tokens.push(token);
    }
    tokens
}

struct Mutator {
    rng: Rng,
    corpus: Vec<Vec<u8>>,
    dict: Vec<Vec<u8>>,
    max_len: usize,
}

impl Mutator {
    /// A new input: a corpus file with one to eight mutations.
    fn input(&mut self) -> Vec<u8> {
        let mut data = self.corpus[self.rng.below(self.corpus.len())].clone();
        let count = 1 + (self.rng.next().trailing_zeros() as usize).min(7);
        for _ in 0..count {
            self.mutate(&mut data);
        }
        data.truncate(self.max_len);
        data
    }

    fn mutate(&mut self, data: &mut Vec<u8>) {
        let rng = &mut self.rng;
        let len = data.len();
        match rng.below(12) {
            // Flip a bit.
            0 if len > 0 => {
                let k = rng.below(len);
                data[k] ^= 1 << rng.below(8);
            }
            // A random byte.
            1 if len > 0 => {
                let k = rng.below(len);
                data[k] = rng.next() as u8;
            }
            // An interesting integer of 1, 2, 4 or 8 bytes, either endianness.
            2 if len > 0 => {
                let width = [1, 2, 4, 8][rng.below(4)].min(len);
                let value = INTERESTING[rng.below(INTERESTING.len())];
                let value = if rng.chance(2) { value } else { value.wrapping_neg() };
                // The value's low `width` bytes.
                let (le, be) = (value.to_le_bytes(), value.to_be_bytes());
                let bytes = if rng.chance(2) { &le[..width] } else { &be[8 - width..] };
                let k = rng.below(len - width + 1);
                data[k..k + width].copy_from_slice(bytes);
            }
            // Insert random bytes.
            3 => {
                let k = rng.below(len + 1);
                let n = 1 + rng.below(8);
                let bytes: Vec<u8> = (0..n).map(|_| rng.next() as u8).collect();
                data.splice(k..k, bytes);
            }
            // Delete a range.
            4 if len > 0 => {
                let k = rng.below(len);
                let n = 1 + rng.below((len - k).min(64));
                data.drain(k..k + n);
            }
            // Copy a range of the input over or into another place of it.
            5 if len > 1 => {
                let from = rng.below(len);
                let n = 1 + rng.below((len - from).min(128));
                let chunk = data[from..from + n].to_vec();
                let to = rng.below(len);
                if rng.chance(2) {
                    data.splice(to..to, chunk);
                } else {
                    let end = (to + n).min(len);
                    data.splice(to..end, chunk);
                }
            }
            // Splice: this input's start and another corpus file's end.
            6 => {
                let other = &self.corpus[rng.below(self.corpus.len())];
                let cut = rng.below(len + 1);
                let from = rng.below(other.len() + 1);
                data.truncate(cut);
                data.extend_from_slice(&other[from..]);
            }
            // Insert a chunk of another corpus file.
            7 => {
                let other = &self.corpus[rng.below(self.corpus.len())];
                if !other.is_empty() {
                    let from = rng.below(other.len());
                    let n = 1 + rng.below((other.len() - from).min(256));
                    let at = rng.below(len + 1);
                    data.splice(at..at, other[from..from + n].iter().copied());
                }
            }
            // A number in text swapped for an extreme one.
            8 => {
                let digits: Vec<usize> = (0..len).filter(|&k| data[k].is_ascii_digit()).collect();
                if !digits.is_empty() {
                    let mut start = digits[rng.below(digits.len())];
                    while start > 0 && (data[start - 1].is_ascii_digit() || b".-+eE".contains(&data[start - 1])) {
                        start -= 1;
                    }
                    let mut end = start;
                    while end < len && (data[end].is_ascii_digit() || b".-+eE".contains(&data[end])) {
                        end += 1;
                    }
                    let text = INTERESTING_TEXT[rng.below(INTERESTING_TEXT.len())];
                    data.splice(start..end, text.bytes());
                }
            }
            // A dictionary token, inserted or written over.
            9 if !self.dict.is_empty() => {
                let token = &self.dict[rng.below(self.dict.len())];
                let at = rng.below(len + 1);
                if rng.chance(2) {
                    data.splice(at..at, token.iter().copied());
                } else {
                    let end = (at + token.len()).min(len);
                    data.splice(at..end, token.iter().copied());
                }
            }
            // Truncate.
            10 if len > 0 => data.truncate(rng.below(len)),
            // A run of one byte value.
            _ => {
                let k = rng.below(len + 1);
                let n = 1 + rng.below(64);
                let byte = [0u8, 0xff, b' ', b'\n', b'[', b'"', b'0'][rng.below(7)];
                data.splice(k..k, std::iter::repeat_n(byte, n));
            }
        }
    }
}

fn mutate(name: &'static str) {
    let seconds = env_number("WRINKLE_FUZZ_SECONDS", 3.0);
    if seconds <= 0.0 {
        return;
    }
    let seed = env_number("WRINKLE_FUZZ_SEED", 0.0) as u64;
    let name_hash =
        name.bytes().fold(0x9e37_79b9_7f4a_7c15u64, |h, b| (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3));
    // The corpus only: regression inputs may still crash until their bugs are fixed.
    let mut corpus: Vec<Vec<u8>> = files_of("corpus", name).into_iter().map(|(_, bytes)| bytes).collect();
    if corpus.is_empty() {
        corpus.push(Vec::new());
    }
    let max_len = (2 * corpus.iter().map(Vec::len).max().unwrap_or(0)).clamp(4096, 1 << 20);
    let mut mutator = Mutator { rng: Rng(name_hash ^ seed | 1), corpus, dict: dictionary(name), max_len };
    let mut runner = Runner::new(name);
    let budget = Duration::from_secs_f64(seconds);
    let start = Instant::now();
    let mut executions = 0u64;
    while start.elapsed() < budget {
        let input = mutator.input();
        executions += 1;
        if let Err(message) = runner.run(&input) {
            panic!("after {executions} executions:\n{}", runner.failure(&input, &message));
        }
    }
    println!(
        "mutate {name}: {executions} executions in {:.1} s, slowest {:.3} s",
        start.elapsed().as_secs_f64(),
        runner.slowest.as_secs_f64()
    );
    // Not a failure below the timeout, but worth a look: kept beside the failures.
    if runner.slowest > Duration::from_secs(1) {
        let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("fuzz-slow");
        let _ = std::fs::create_dir_all(&dir);
        let path = dir.join(name);
        let _ = std::fs::write(&path, &runner.slowest_input);
        println!("mutate {name}: the slowest input is saved as {}", path.display());
    }
}

macro_rules! fuzz_tests {
    ($($name:ident),* $(,)?) => {
        mod replay {
            $(#[test]
            fn $name() {
                super::replay(stringify!($name));
            })*
        }
        mod mutate {
            $(#[test]
            fn $name() {
                super::mutate(stringify!($name));
            })*
        }
        #[test]
        fn every_target_is_tested() {
            let tested = [$(stringify!($name)),*];
            let names: Vec<&str> = targets::TARGETS.iter().map(|(n, _)| *n).collect();
            assert_eq!(names, tested, "fuzz/targets.rs and this file list the same targets");
        }
    };
}

fuzz_tests!(scene, image_png, image_jpeg, image_bmp, image_tga, image_tiff, image_exr, obj, gltf);
