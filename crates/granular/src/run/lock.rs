//! The run directory's lock, `DIR/.lock`: a file holding the process id of the run, with
//! an exclusive advisory lock of the operating system on it (`File::try_lock`) for as long
//! as the run lives, so that a second `run` or `resume` on the same directory refuses
//! instead of interleaving its files. The operating system releases that lock when the
//! process ends in any way (`kill -9`, a crash), so a lock file left behind is told apart
//! from a live one without guessing from process ids: it is stale, taken over atomically
//! (only one process can take the system lock), and the log says so. Where the file
//! system has no such locks, the process id decides (`/proc`).

use super::RunError;
use std::fs::{File, OpenOptions, TryLockError};
use std::io::{Read, Seek, Write};
use std::path::{Path, PathBuf};

/// The lock of a run directory; removed on drop.
#[derive(Debug)]
pub(crate) struct Lock {
    path: PathBuf,
    /// The open lock file holding the system lock (released when it closes).
    _file: File,
}

/// Whether process `pid` is running, where the system says (`/proc`); `None` elsewhere.
fn process_alive(pid: u32) -> Option<bool> {
    let proc = Path::new("/proc");
    proc.join("self")
        .exists()
        .then(|| proc.join(pid.to_string()).exists())
}

/// Whether the open `file` is still the one at `path` (a run that ended may have removed
/// its lock file between our opening and locking it).
#[cfg(unix)]
fn still_at(file: &File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (file.metadata(), std::fs::metadata(path)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

#[cfg(not(unix))]
fn still_at(_file: &File, path: &Path) -> bool {
    path.exists()
}

fn in_use(dir: &Path, path: &Path, holder: &str) -> RunError {
    let pid = holder.trim();
    let who = if pid.parse::<u32>().is_ok() {
        format!("process {pid} is running in it")
    } else {
        "another process is running in it".to_string()
    };
    RunError::Locked {
        dir: dir.to_path_buf(),
        message: format!(
            "{who} (its lock: {}). Wait for it to finish or stop it (Ctrl-C or `kill {}`: it \
             then saves a checkpoint), or choose another --out",
            path.display(),
            if pid.is_empty() { "PID" } else { pid }
        ),
    }
}

impl Lock {
    /// Takes the lock of `dir` (which exists). Returns the lock and, when a stale lock
    /// (left by a run that no longer runs) was taken over, a line for the log.
    pub(crate) fn acquire(dir: &Path) -> Result<(Lock, Option<String>), RunError> {
        let path = dir.join(crate::run::RunFile::Lock.name());
        let io = |source| RunError::Io {
            path: path.clone(),
            source,
        };
        for _ in 0..3 {
            let mut file = OpenOptions::new()
                .read(true)
                .write(true)
                .create(true)
                .truncate(false)
                .open(&path)
                .map_err(io)?;
            let mut before = String::new();
            match file.try_lock() {
                Ok(()) => {}
                Err(TryLockError::WouldBlock) => {
                    let _ = file.read_to_string(&mut before);
                    return Err(in_use(dir, &path, &before));
                }
                Err(TryLockError::Error(e)) if e.kind() == std::io::ErrorKind::Unsupported => {
                    let _ = file.read_to_string(&mut before);
                    if let Some(p) = before.trim().parse::<u32>().ok()
                        && p != std::process::id()
                        && process_alive(p) != Some(false)
                    {
                        return Err(in_use(dir, &path, &before));
                    }
                }
                Err(TryLockError::Error(e)) => return Err(io(e)),
            }
            if !still_at(&file, &path) {
                continue; // removed by the run that just ended: open the new one
            }
            file.read_to_string(&mut before).map_err(io)?;
            file.set_len(0).map_err(io)?;
            file.rewind().map_err(io)?;
            writeln!(file, "{}", std::process::id()).map_err(io)?;
            file.flush().map_err(io)?;
            let before = before.trim();
            let note = (!before.is_empty()).then(|| {
                let holder = match before.parse::<u32>() {
                    Ok(p) => format!("process {p}"),
                    Err(_) => format!("an unknown process ({before:?})"),
                };
                format!(
                    "took over the stale lock {} of {holder}, which is no longer running \
                     (killed or crashed; its last checkpoint is intact)",
                    path.display()
                )
            });
            return Ok((Lock { path, _file: file }, note));
        }
        Err(RunError::Locked {
            dir: dir.to_path_buf(),
            message: format!(
                "its lock {} changed hands three times while this process tried to take it; \
                 another run is starting in it: choose another --out or retry",
                path.display()
            ),
        })
    }
}

impl Drop for Lock {
    /// Removes the lock file, then (as the file closes) releases the system lock.
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.path);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_second_lock_is_refused_and_released_on_drop() {
        let dir = tempfile::tempdir().unwrap();
        let (lock, note) = Lock::acquire(dir.path()).unwrap();
        assert!(note.is_none());
        let e = Lock::acquire(dir.path()).unwrap_err().to_string();
        assert!(
            e.contains(&std::process::id().to_string()) && e.contains("is running in it"),
            "{e}"
        );
        drop(lock);
        assert!(!dir.path().join(".lock").exists());
        assert!(Lock::acquire(dir.path()).is_ok());
    }

    /// A lock file without a live holder (what `kill -9` leaves) is taken over and named,
    /// whatever it holds.
    #[test]
    fn a_stale_lock_is_taken_over_and_named() {
        let dir = tempfile::tempdir().unwrap();
        for (text, named) in [("4294967\n", "process 4294967"), ("garbage", "\"garbage\"")] {
            std::fs::write(dir.path().join(".lock"), text).unwrap();
            let (lock, note) = Lock::acquire(dir.path()).unwrap();
            let note = note.unwrap();
            assert!(
                note.contains(named) && note.contains("no longer running"),
                "{note}"
            );
            let held = std::fs::read_to_string(dir.path().join(".lock")).unwrap();
            assert_eq!(held.trim(), std::process::id().to_string());
            drop(lock);
        }
    }

    /// A lock whose file was removed between opening and locking (its run just ended) is
    /// not taken on the removed file: the new file is locked.
    #[test]
    fn a_lock_file_removed_under_us_is_not_kept() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(".lock");
        let old = OpenOptions::new()
            .create(true)
            .truncate(false)
            .write(true)
            .open(&path)
            .unwrap();
        std::fs::remove_file(&path).unwrap();
        assert!(!still_at(&old, &path));
        let (_lock, _) = Lock::acquire(dir.path()).unwrap();
        assert!(path.is_file());
    }
}
