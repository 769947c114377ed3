//! How output files reach their place, all or nothing (docs/reliability.md states the policy):
//!
//! - a regular file (or a new name) is written to a hidden temporary beside it and renamed into place when
//!   complete, so a reader never sees half a file and a failure leaves the old file as it was;
//! - a symlink is followed: its final target is replaced the same way and the link stays;
//! - a device, FIFO or socket (`/dev/null`, `/dev/stdout`, a pipe) is written directly, as a stream can
//!   only be; its write errors (`/dev/full`) fail the job;
//! - a folder in the way, or a symlink to nothing, is an error before anything is written.
//!
//! Every temporary is recorded while it exists, so that a signal handler ([`remove_temporaries`]) can take
//! them away when the job is interrupted. [`OutputSet`] extends this to several files (a frame and its
//! AOVs, the levels of a pyramid, the frames of an animation): none is placed until all are written.

use std::fs::{self, File, OpenOptions};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

use crate::error::{Error, Result};

/// Where the bytes for an output path go.
enum Target {
    /// A regular file, or nothing yet: written beside it and renamed.
    File(PathBuf),
    /// A device, FIFO or socket: written directly.
    Stream(PathBuf),
}

/// The temporaries that exist now, for [`remove_temporaries`].
static TEMPORARIES: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Removes every temporary file this process is writing or has staged: what a signal handler calls before
/// the process exits, so that an interrupted job leaves nothing behind.
pub fn remove_temporaries() {
    remove_temporaries_where(|_| true);
}

fn remove_temporaries_where(chosen: impl Fn(&Path) -> bool) {
    let mut list = TEMPORARIES.lock().unwrap_or_else(|e| e.into_inner());
    list.retain(|path| {
        let remove = chosen(path);
        if remove {
            let _ = fs::remove_file(path);
        }
        !remove
    });
}

fn record(path: &Path) {
    TEMPORARIES.lock().unwrap_or_else(|e| e.into_inner()).push(path.to_path_buf());
}

fn forget(path: &Path) {
    TEMPORARIES.lock().unwrap_or_else(|e| e.into_inner()).retain(|p| p != path);
}

/// Writes a file atomically as the module says: `write` fills a buffered temporary
/// `.{name}.{pid}.{n}.tmp` beside the target, renamed onto it when complete; on any error the temporary
/// is removed and the target left as it was. Devices and FIFOs are written directly.
pub fn write_atomic(path: &Path, write: impl FnOnce(&mut dyn Write) -> Result<()>) -> Result<()> {
    match resolve(path)? {
        Target::Stream(device) => {
            let file = OpenOptions::new().write(true).open(&device).map_err(|e| Error::write(path, e))?;
            fill(file, path, write)
        }
        Target::File(target) => {
            let tmp = hidden_beside(&target, "tmp")?;
            record(&tmp);
            let result = File::create(&tmp)
                .map_err(|e| Error::write(path, create_message(&target, &e)))
                .and_then(|file| fill(file, path, write))
                .and_then(|()| fs::rename(&tmp, &target).map_err(|e| Error::write(path, e)));
            if result.is_err() {
                // The temporary may not exist (creating it failed); there is nothing else to do.
                let _ = fs::remove_file(&tmp);
            }
            forget(&tmp);
            result
        }
    }
}

/// Several output files placed together: each is written under a hidden staging name beside its target,
/// and [`OutputSet::commit`] renames them all into place. Dropped uncommitted (an error, a panic), it
/// removes what it staged; a failure while committing removes what it had placed too.
#[derive(Default)]
pub struct OutputSet {
    /// (staging name, target, the path as asked, for errors).
    staged: Vec<(PathBuf, PathBuf, PathBuf)>,
}

impl OutputSet {
    pub fn new() -> Self {
        OutputSet::default()
    }

    /// Writes one file of the set: `write` is given the path to write (a staging name, or the device itself
    /// for a stream, which cannot wait for the others). Errors name `path`.
    pub fn stage(&mut self, path: &Path, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
        match resolve(path)? {
            Target::Stream(device) => write(&device).map_err(|e| renamed(e, path)),
            Target::File(target) => {
                if self.staged.iter().any(|(_, t, _)| *t == target) {
                    return Err(Error::write(path, "is named twice in one set of outputs"));
                }
                let staging = hidden_beside(&target, "staged")?;
                record(&staging);
                self.staged.push((staging.clone(), target, path.to_path_buf()));
                write(&staging).map_err(|e| renamed(e, path))
            }
        }
    }

    /// Renames every staged file into place.
    pub fn commit(mut self) -> Result<()> {
        let staged = std::mem::take(&mut self.staged);
        // A folder that appeared in the way is the one common reason a rename fails: look before renaming.
        if let Some((_, _, asked)) = staged.iter().find(|(_, target, _)| target.is_dir()) {
            let error = Error::write(asked, "a folder of that name is in the way");
            self.staged = staged;
            return Err(error);
        }
        for (k, (staging, target, asked)) in staged.iter().enumerate() {
            if let Err(e) = fs::rename(staging, target) {
                for (_, placed, _) in &staged[..k] {
                    let _ = fs::remove_file(placed);
                }
                let error = Error::write(asked, e);
                self.staged = staged[k..].to_vec();
                return Err(error);
            }
            forget(staging);
        }
        Ok(())
    }
}

impl Drop for OutputSet {
    fn drop(&mut self) {
        for (staging, _, _) in &self.staged {
            let _ = fs::remove_file(staging);
            forget(staging);
        }
    }
}

/// What an output path stands for, by the policy of the module.
fn resolve(path: &Path) -> Result<Target> {
    let meta = match fs::symlink_metadata(path) {
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(Target::File(path.to_path_buf())),
        Err(e) => return Err(Error::write(path, e)),
        Ok(meta) => meta,
    };
    let (target, meta) = if meta.file_type().is_symlink() {
        let target = fs::canonicalize(path)
            .map_err(|_| Error::write(path, "is a symlink to nothing; write to a real file or fix the link"))?;
        let meta = fs::metadata(&target).map_err(|e| Error::write(path, e))?;
        (target, meta)
    } else {
        (path.to_path_buf(), meta)
    };
    if meta.is_dir() {
        Err(Error::write(path, "a folder of that name is in the way"))
    } else if meta.is_file() {
        Ok(Target::File(target))
    } else {
        Ok(Target::Stream(target))
    }
}

/// `.{file name}.{pid}.{n}.{kind}` beside `target`; `n` keeps concurrent writers in one process apart.
fn hidden_beside(target: &Path, kind: &str) -> Result<PathBuf> {
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let name = target.file_name().ok_or_else(|| Error::write(target, "not a file name"))?;
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    Ok(target.with_file_name(format!(".{}.{}.{n}.{kind}", name.to_string_lossy(), std::process::id())))
}

/// Lets `write` fill `file` through a buffer and flushes it; errors name `path`.
fn fill(file: File, path: &Path, write: impl FnOnce(&mut dyn Write) -> Result<()>) -> Result<()> {
    let mut out = BufWriter::new(file);
    write(&mut out)?;
    out.flush().map_err(|e| Error::write(path, e))
}

fn create_message(path: &Path, e: &io::Error) -> String {
    match path.parent() {
        Some(dir) if e.kind() == io::ErrorKind::NotFound && !dir.as_os_str().is_empty() => {
            format!("directory {} does not exist", dir.display())
        }
        _ => e.to_string(),
    }
}

/// An error of writing a staged file, told of the file the user asked for.
fn renamed(e: Error, path: &Path) -> Error {
    match e {
        Error::Write { message, .. } => Error::Write { path: path.to_path_buf(), message },
        other => other,
    }
}

#[cfg(test)]
mod tests {
    use super::super::scratch::Scratch;
    use super::*;
    use std::os::unix::fs::symlink;

    fn write_text(path: &Path, contents: &'static str) -> Result<()> {
        write_atomic(path, |w| w.write_all(contents.as_bytes()).map_err(|e| Error::write(path, e)))
    }

    #[test]
    fn into_a_missing_directory_fails_and_leaves_nothing() {
        let dir = Scratch::new("nodir");
        let path = dir.path("missing").join("out.png");
        match write_text(&path, "data") {
            Err(Error::Write { path: p, message }) => {
                assert_eq!(p, path);
                assert!(message.contains("does not exist"), "{message}");
            }
            other => panic!("expected a write error, got {other:?}"),
        }
        assert!(dir.entries().is_empty());
    }

    #[test]
    fn a_failing_writer_leaves_no_file_and_keeps_the_old_one() {
        let dir = Scratch::new("failing");
        let fail = |w: &mut dyn Write| {
            w.write_all(b"partial").unwrap();
            Err(Error::Invalid("boom".into()))
        };
        let new = dir.path("new.bin");
        assert!(matches!(write_atomic(&new, fail), Err(Error::Invalid(m)) if m == "boom"));
        assert!(dir.entries().is_empty());
        let old = dir.path("old.bin");
        fs::write(&old, "old").unwrap();
        assert!(matches!(write_atomic(&old, fail), Err(Error::Invalid(m)) if m == "boom"));
        assert_eq!(fs::read_to_string(&old).unwrap(), "old");
        assert_eq!(dir.entries(), ["old.bin"]);
        assert!(TEMPORARIES.lock().unwrap().iter().all(|p| !p.starts_with(&dir.0)));
    }

    #[test]
    fn a_file_is_replaced_whole() {
        let dir = Scratch::new("replace");
        let path = dir.path("out.txt");
        fs::write(&path, "old contents").unwrap();
        write_text(&path, "new").unwrap();
        assert_eq!(fs::read_to_string(&path).unwrap(), "new");
        assert_eq!(dir.entries(), ["out.txt"]);
    }

    #[test]
    fn a_symlink_is_followed_its_target_replaced_and_the_link_kept() {
        let dir = Scratch::new("symlink");
        fs::create_dir(dir.path("real")).unwrap();
        let target = dir.path("real/picture.png");
        fs::write(&target, "old").unwrap();
        let link = dir.path("link.png");
        symlink("real/picture.png", &link).unwrap();
        write_text(&link, "new").unwrap();
        assert!(fs::symlink_metadata(&link).unwrap().file_type().is_symlink());
        assert_eq!(fs::read_to_string(&target).unwrap(), "new");
        assert_eq!(dir.entries(), ["link.png", "real"]);
        let dangling = dir.path("dangling.png");
        symlink("nowhere/x.png", &dangling).unwrap();
        let err = write_text(&dangling, "x").unwrap_err().to_string();
        assert!(err.contains("dangling.png: cannot write: is a symlink to nothing"), "{err}");
    }

    #[test]
    fn devices_are_written_directly_and_their_errors_fail_the_job() {
        write_text(Path::new("/dev/null"), "discarded").unwrap();
        let dir = Scratch::new("devices");
        let link = dir.path("full.png");
        symlink("/dev/full", &link).unwrap();
        let err = write_text(&link, "x").unwrap_err();
        assert!(matches!(&err, Error::Write { path, .. } if *path == link), "{err:?}");
        assert!(err.to_string().contains("No space left on device"), "{err}");
        assert!(fs::symlink_metadata(&link).unwrap().file_type().is_symlink());
        assert!(Path::new("/dev/full").exists());
        let folder = dir.path("folder.png");
        fs::create_dir(&folder).unwrap();
        assert!(write_text(&folder, "x").unwrap_err().to_string().contains("a folder of that name is in the way"));
    }

    #[test]
    fn a_set_places_all_its_files_or_none() {
        let dir = Scratch::new("set");
        let write = |p: &Path, s: &'static str| write_text(p, s);
        let mut set = OutputSet::new();
        set.stage(&dir.path("a.txt"), |p| write(p, "a")).unwrap();
        set.stage(&dir.path("b.txt"), |p| write(p, "b")).unwrap();
        assert_eq!(dir.entries().iter().filter(|n| n.starts_with('.')).count(), 2);
        set.commit().unwrap();
        assert_eq!(dir.entries(), ["a.txt", "b.txt"]);

        // The second file fails: the first is not placed, the old files stay.
        let mut set = OutputSet::new();
        set.stage(&dir.path("a.txt"), |p| write(p, "A")).unwrap();
        let err = set.stage(&dir.path("c.txt"), |_| Err(Error::write("staging name", "disk full"))).unwrap_err();
        assert_eq!(err.to_string(), format!("{}: cannot write: disk full", dir.path("c.txt").display()));
        drop(set);
        assert_eq!(dir.entries(), ["a.txt", "b.txt"]);
        assert_eq!(fs::read_to_string(dir.path("a.txt")).unwrap(), "a");

        // A folder appears where one of them goes: nothing is placed.
        let mut set = OutputSet::new();
        set.stage(&dir.path("a.txt"), |p| write(p, "A")).unwrap();
        set.stage(&dir.path("d.txt"), |p| write(p, "D")).unwrap();
        fs::create_dir(dir.path("d.txt")).unwrap();
        assert!(set.commit().unwrap_err().to_string().contains("d.txt: cannot write: a folder of that name"));
        assert_eq!(dir.entries(), ["a.txt", "b.txt", "d.txt"]);
        assert_eq!(fs::read_to_string(dir.path("a.txt")).unwrap(), "a");

        let mut set = OutputSet::new();
        set.stage(&dir.path("e.txt"), |p| write(p, "e")).unwrap();
        assert!(set.stage(&dir.path("e.txt"), |p| write(p, "e")).unwrap_err().to_string().contains("named twice"));
    }

    #[test]
    fn removing_temporaries_takes_away_what_is_being_written() {
        let dir = Scratch::new("signal");
        let mut set = OutputSet::new();
        set.stage(&dir.path("frame.png"), |p| write_text(p, "pixels")).unwrap();
        write_atomic(&dir.path("single.png"), |w| {
            w.write_all(b"half").unwrap();
            w.flush().unwrap();
            assert_eq!(dir.entries().len(), 2);
            // What remove_temporaries does, kept to this test's folder (other tests write at the same time).
            remove_temporaries_where(|p| p.starts_with(&dir.0));
            assert!(dir.entries().is_empty());
            Err(Error::Invalid("interrupted".into()))
        })
        .unwrap_err();
        assert!(dir.entries().is_empty());
        drop(set);
    }
}
