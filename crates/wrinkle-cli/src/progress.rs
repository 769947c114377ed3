//! Progress of long work: a bar on a terminal; elsewhere (CI logs, batch systems, a pipe) one line every
//! few seconds with the share done, the time so far and the time left, so that logs show it.

use indicatif::{ProgressBar, ProgressStyle};
use std::io::{IsTerminal, Write};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// Seconds between the lines written where stderr is not a terminal; `WRINKLE_PROGRESS_SECONDS` overrides it.
const LINE_EVERY: f64 = 5.0;

/// A bar or a log of `len` steps of `unit` (rows, bands, frames, panels).
pub struct Progress {
    bar: Option<ProgressBar>,
    log: Option<Log>,
}

struct Log {
    what: String,
    unit: &'static str,
    start: Instant,
    every: Duration,
    /// When the last line was written (None: none yet).
    last: Mutex<Option<Instant>>,
    len: AtomicU64,
    pos: AtomicU64,
    message: Mutex<String>,
}

impl Progress {
    /// Progress of `what` (the command) over `len` steps of `unit`; `shown` is what the bar shows after it
    /// (an indicatif template: `{pos}/{len} rows`).
    pub fn new(what: &str, len: u64, unit: &'static str, shown: &str) -> Progress {
        if std::io::stderr().is_terminal() {
            let bar = ProgressBar::new(len);
            let template = format!("{{bar:40}} {shown}  {{elapsed}} (eta {{eta}})");
            bar.set_style(ProgressStyle::with_template(&template).expect("a valid template"));
            return Progress { bar: Some(bar), log: None };
        }
        let every = std::env::var("WRINKLE_PROGRESS_SECONDS").ok().and_then(|s| s.parse::<f64>().ok());
        let every = Duration::from_secs_f64(every.filter(|s| s.is_finite() && *s >= 0.0).unwrap_or(LINE_EVERY));
        let log = Log {
            what: what.to_string(),
            unit,
            start: Instant::now(),
            every,
            last: Mutex::new(None),
            len: AtomicU64::new(len),
            pos: AtomicU64::new(0),
            message: Mutex::new(String::new()),
        };
        Progress { bar: None, log: Some(log) }
    }

    /// No progress at all (short work).
    pub fn hidden() -> Progress {
        Progress { bar: None, log: None }
    }

    pub fn set_length(&self, len: u64) {
        if let Some(b) = &self.bar {
            b.set_length(len);
        }
        if let Some(l) = &self.log {
            l.len.store(len, Ordering::Relaxed);
        }
    }

    pub fn set_position(&self, pos: u64) {
        if let Some(b) = &self.bar {
            b.set_position(pos);
        }
        if let Some(l) = &self.log {
            l.pos.fetch_max(pos, Ordering::Relaxed);
            l.tell(false);
        }
    }

    pub fn inc(&self, steps: u64) {
        if let Some(b) = &self.bar {
            b.inc(steps);
        }
        if let Some(l) = &self.log {
            l.pos.fetch_add(steps, Ordering::Relaxed);
            l.tell(false);
        }
    }

    /// What is being done now (a panel's name).
    pub fn set_message(&self, message: impl Into<String>) {
        let message = message.into();
        if let Some(b) = &self.bar {
            b.set_message(message.clone());
        }
        if let Some(l) = &self.log {
            *l.message.lock().expect("the message lock") = message;
        }
    }

    /// The work is done: the bar goes; a log that has written lines ends with one for the whole.
    pub fn finish(&self) {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
        if let Some(l) = &self.log {
            l.tell(true);
        }
    }
}

impl Log {
    /// Writes a line when the last is `every` old (or, with `done`, when any was written before).
    fn tell(&self, done: bool) {
        let now = Instant::now();
        let mut last = self.last.lock().expect("the progress lock");
        let due = match (*last, done) {
            (None, true) => false,
            (Some(_), true) => true,
            (None, false) => now - self.start >= self.every,
            (Some(t), false) => now - t >= self.every,
        };
        if !due {
            return;
        }
        *last = Some(now);
        let (pos, len) = (self.pos.load(Ordering::Relaxed), self.len.load(Ordering::Relaxed));
        let elapsed = (now - self.start).as_secs_f64();
        let message = self.message.lock().expect("the message lock");
        let about = if message.is_empty() { String::new() } else { format!(", {message}") };
        let line = if done {
            format!("{}: done, {pos} {} in {elapsed:.1} s\n", self.what, self.unit)
        } else {
            let share = if len > 0 { pos as f64 / len as f64 } else { 0.0 };
            let left = if share > 0.0 { format!("{:.1} s", elapsed * (1.0 - share) / share) } else { "?".into() };
            format!(
                "{}: {:.0}% ({pos}/{len} {}{about}), {elapsed:.1} s elapsed, about {left} left\n",
                self.what,
                share * 100.0,
                self.unit
            )
        };
        let _ = std::io::stderr().write_all(line.as_bytes());
    }
}
