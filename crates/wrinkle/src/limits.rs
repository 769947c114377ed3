//! The limits every command and library call is held to, in one place (docs/reliability.md lists them):
//! image side and pixel count for files, frame pixels for renders, triangles per mesh, and a memory budget
//! checked before every large allocation. Each is process-wide, has a default that a small hostile file
//! cannot push a machine past, and can be raised (`--limit NAME=VALUE` on the command line, [`set`] here).

use crate::{Error, Result};
use std::sync::atomic::{AtomicU64, Ordering};

/// One limit: its name on the command line, what it bounds, and its default.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Limit {
    /// Bytes of memory the process may hold (default: three quarters of the machine's memory).
    Memory,
    /// Width or height of an image file read or written.
    ImageSide,
    /// Pixels of an image file read or written.
    ImagePixels,
    /// Width or height of a rendered frame.
    FrameSide,
    /// Pixels of a rendered frame.
    FramePixels,
    /// Triangles of one mesh.
    Triangles,
}

impl Limit {
    pub const ALL: [Limit; 6] =
        [Limit::Memory, Limit::ImageSide, Limit::ImagePixels, Limit::FrameSide, Limit::FramePixels, Limit::Triangles];

    pub fn name(self) -> &'static str {
        match self {
            Limit::Memory => "memory",
            Limit::ImageSide => "image-side",
            Limit::ImagePixels => "image-pixels",
            Limit::FrameSide => "frame-side",
            Limit::FramePixels => "frame-pixels",
            Limit::Triangles => "triangles",
        }
    }

    fn default_value(self) -> u64 {
        // The machine's memory is read once, not at every reservation.
        static MEMORY: std::sync::OnceLock<u64> = std::sync::OnceLock::new();
        match self {
            Limit::Memory => *MEMORY.get_or_init(default_memory),
            Limit::ImageSide => 32768,
            Limit::ImagePixels => 16384 * 16384,
            Limit::FrameSide => 16384,
            Limit::FramePixels => 8192 * 8192,
            Limit::Triangles => 1 << 28,
        }
    }

    /// The hard ceiling: what the data structures themselves allow (indices are u32, sides fit in u32).
    fn ceiling(self) -> u64 {
        match self {
            Limit::Memory => u64::MAX,
            Limit::ImageSide => 1 << 20,
            // A screen triangle's edge slopes are 32-bit: sides within the clip planes' guard band of
            // 4.5 frames, in 1/256 pixel, fit for frames up to 2^18 on a side; a whole frame rendered in
            // parts is at most 2^16.
            Limit::FrameSide => 1 << 16,
            Limit::ImagePixels | Limit::FramePixels => 1 << 36,
            // Four of every vertex index's 2^32 must fit: 3 per triangle plus the welded copies.
            Limit::Triangles => 1 << 30,
        }
    }

    fn slot(self) -> &'static AtomicU64 {
        static SLOTS: [AtomicU64; 6] = [const { AtomicU64::new(0) }; 6];
        &SLOTS[self as usize]
    }

    /// The limit's value now (its default until [`set`] changes it).
    pub fn get(self) -> u64 {
        match self.slot().load(Ordering::Relaxed) {
            0 => self.default_value(),
            v => v,
        }
    }

    /// The value as a usize, for limits on counts (saturating on 32-bit targets).
    pub fn count(self) -> usize {
        usize::try_from(self.get()).unwrap_or(usize::MAX)
    }

    /// How to raise it, for error messages.
    pub fn hint(self) -> String {
        format!("raise it with --limit {}=N", self.name())
    }
}

/// Sets one limit for the whole process.
pub fn set(limit: Limit, value: u64) -> Result<()> {
    if value == 0 || value > limit.ceiling() {
        return Err(Error::Invalid(format!(
            "--limit {}: {value} is out of range (1 to {})",
            limit.name(),
            limit.ceiling()
        )));
    }
    limit.slot().store(value, Ordering::Relaxed);
    Ok(())
}

/// Parses `NAME=VALUE` (sizes take K, M, G, T suffixes in powers of 1024; counts take them in powers of 1000
/// only as `k`, `M`, `G`) and sets it.
pub fn set_from_arg(arg: &str) -> Result<()> {
    let bad = |why: String| Error::Invalid(format!("--limit {arg:.60}: {why}"));
    let (name, value) = arg.split_once('=').ok_or_else(|| bad("expected NAME=VALUE".into()))?;
    let limit = Limit::ALL.into_iter().find(|l| l.name() == name.trim()).ok_or_else(|| {
        let names: Vec<&str> = Limit::ALL.iter().map(|l| l.name()).collect();
        bad(format!("unknown limit (one of {})", names.join(", ")))
    })?;
    let value = parse_size(value.trim(), limit == Limit::Memory).ok_or_else(|| bad("not a positive number".into()))?;
    set(limit, value)
}

/// `12G` -> 12 * 2^30 for bytes, `2M` -> 2 000 000 for counts; plain integers as they are.
fn parse_size(text: &str, bytes: bool) -> Option<u64> {
    let split = text.find(|c: char| !(c.is_ascii_digit() || c == '.')).unwrap_or(text.len());
    let (number, suffix) = text.split_at(split);
    let number: f64 = number.parse().ok()?;
    let unit: f64 = match (suffix.trim().to_ascii_uppercase().trim_end_matches(['B', 'I']), bytes) {
        ("", _) => 1.0,
        ("K", true) => 1024.0,
        ("M", true) => 1024.0 * 1024.0,
        ("G", true) => 1024.0 * 1024.0 * 1024.0,
        ("T", true) => 1024.0 * 1024.0 * 1024.0 * 1024.0,
        ("K", false) => 1e3,
        ("M", false) => 1e6,
        ("G", false) => 1e9,
        _ => return None,
    };
    let value = number * unit;
    (1.0..1.8e19).contains(&value).then_some(value as u64)
}

/// Checks that `bytes` more can be allocated within the memory budget, given what the process holds now;
/// `what` names the allocation in the error ("a 16384x16384 texture's MIP pyramid").
pub fn reserve(bytes: u64, what: impl FnOnce() -> String) -> Result<()> {
    let budget = Limit::Memory.get();
    let held = resident_bytes();
    if held.saturating_add(bytes) <= budget {
        return Ok(());
    }
    Err(Error::Invalid(format!(
        "{} needs {} of memory, and {} of the {} budget is in use ({})",
        what(),
        show_bytes(bytes),
        show_bytes(held),
        show_bytes(budget),
        Limit::Memory.hint().replace("=N", "=SIZE")
    )))
}

/// Bytes as people read them: `1.5 GB`, `640 MB`.
pub fn show_bytes(bytes: u64) -> String {
    let b = bytes as f64;
    if b >= (1u64 << 30) as f64 {
        format!("{:.1} GB", b / (1u64 << 30) as f64)
    } else if b >= (1u64 << 20) as f64 {
        format!("{:.0} MB", b / (1u64 << 20) as f64)
    } else {
        format!("{:.0} KB", (b / 1024.0).ceil())
    }
}

/// Three quarters of the memory this process may use (the machine's, or its cgroup's when smaller), leaving
/// room for the rest of the system; 8 GB where neither can be read.
fn default_memory() -> u64 {
    let machine = std::fs::read_to_string("/proc/meminfo").ok().and_then(|text| {
        let line = text.lines().find(|l| l.starts_with("MemTotal:"))?;
        line.split_whitespace().nth(1)?.parse::<u64>().ok().map(|kb| kb * 1024)
    });
    let cgroup = std::fs::read_to_string("/sys/fs/cgroup/memory.max").ok().and_then(|t| t.trim().parse::<u64>().ok());
    match (machine, cgroup) {
        (Some(m), Some(c)) => m.min(c) / 4 * 3,
        (Some(m), None) => m / 4 * 3,
        (None, Some(c)) => c / 4 * 3,
        (None, None) => 8 << 30,
    }
}

/// The process's resident memory (Linux: VmRSS); 0 where the system does not say.
fn resident_bytes() -> u64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|text| {
            let line = text.lines().find(|l| l.starts_with("VmRSS:"))?;
            line.split_whitespace().nth(1)?.parse::<u64>().ok().map(|kb| kb * 1024)
        })
        .unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_with_binary_units_for_bytes_and_decimal_for_counts() {
        assert_eq!(parse_size("12G", true), Some(12 << 30));
        assert_eq!(parse_size("512MiB", true), Some(512 << 20));
        assert_eq!(parse_size("1.5g", true), Some(3 << 29));
        assert_eq!(parse_size("2M", false), Some(2_000_000));
        assert_eq!(parse_size("4096", false), Some(4096));
        for bad in ["", "G", "-1", "0", "1X", "nan", "1e400"] {
            assert_eq!(parse_size(bad, true), None, "{bad}");
        }
    }

    #[test]
    fn bad_limit_arguments_say_what_is_wrong() {
        let message = |arg: &str| set_from_arg(arg).unwrap_err().to_string();
        assert!(message("memory").contains("expected NAME=VALUE"));
        assert!(message("speed=3").contains("unknown limit (one of memory, image-side"));
        assert!(message("memory=lots").contains("not a positive number"));
        assert!(message("image-side=2000000").contains("out of range (1 to 1048576)"));
    }

    #[test]
    fn a_reservation_beyond_the_budget_names_its_need_and_the_flag() {
        // The budget is the machine's by default: far below u64::MAX / 2.
        let err = reserve(u64::MAX / 2, || "a test allocation".into()).unwrap_err().to_string();
        assert!(err.starts_with("a test allocation needs "), "{err}");
        assert!(err.contains("--limit memory=SIZE"), "{err}");
        assert!(reserve(1 << 20, || unreachable!()).is_ok());
        assert!(resident_bytes() > 0);
    }
}
