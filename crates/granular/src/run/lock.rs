//! The run directory's lock, `DIR/.lock`: created with `create_new` and holding the
//! process id, removed when the run ends (its [`Drop`]), so that a second `run` or `resume`
//! on the same directory refuses instead of interleaving its files. A lock left by a process
//! that no longer runs (killed with `kill -9`, a crashed machine) is stale: it is taken over,
//! and the log says so.

use super::RunError;
use std::io::Write;
use std::path::{Path, PathBuf};

/// The lock of a run directory; removed on drop.
#[derive(Debug)]
pub struct Lock {
    path: PathBuf,
}

/// Whether process `pid` is running, where the system says (`/proc`); `None` elsewhere.
fn process_alive(pid: u32) -> Option<bool> {
    let proc = Path::new("/proc");
    proc.join("self")
        .exists()
        .then(|| proc.join(pid.to_string()).exists())
}

impl Lock {
    /// Takes the lock of `dir` (which exists). Returns the lock and, when a stale lock
    /// was taken over, a line for the log.
    pub fn acquire(dir: &Path) -> Result<(Lock, Option<String>), RunError> {
        let path = dir.join(".lock");
        let mut note = None;
        for _ in 0..2 {
            match std::fs::OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(&path)
            {
                Ok(mut f) => {
                    let _ = writeln!(f, "{}", std::process::id());
                    return Ok((Lock { path }, note));
                }
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                    let text = std::fs::read_to_string(&path).unwrap_or_default();
                    let pid = text.trim().parse::<u32>().ok();
                    match pid.map(|p| (p, process_alive(p))) {
                        Some((p, Some(false))) => {
                            let _ = std::fs::remove_file(&path);
                            note = Some(format!(
                                "took over the stale lock {} of process {p}, which is no \
                                 longer running",
                                path.display()
                            ));
                        }
                        Some((p, _)) => {
                            return Err(RunError::Locked {
                                dir: dir.to_path_buf(),
                                message: format!(
                                    "process {p} is running in it (its lock: {}). Wait for \
                                     it to finish or stop it (Ctrl-C or `kill {p}`: it then \
                                     saves a checkpoint), or choose another --out",
                                    path.display()
                                ),
                            });
                        }
                        None => {
                            return Err(RunError::Locked {
                                dir: dir.to_path_buf(),
                                message: format!(
                                    "its lock {} does not name a process ({:?}). If no run \
                                     is using the directory, remove the lock and retry",
                                    path.display(),
                                    text.trim()
                                ),
                            });
                        }
                    }
                }
                Err(source) => return Err(RunError::Io { path, source }),
            }
        }
        Err(RunError::Locked {
            dir: dir.to_path_buf(),
            message: format!(
                "another process took its lock {} as this one removed a stale one; retry",
                path.display()
            ),
        })
    }
}

impl Drop for Lock {
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
        assert!(e.contains(&std::process::id().to_string()), "{e}");
        drop(lock);
        assert!(!dir.path().join(".lock").exists());
        assert!(Lock::acquire(dir.path()).is_ok());
    }

    #[test]
    fn a_stale_lock_is_taken_over_and_named() {
        let dir = tempfile::tempdir().unwrap();
        if process_alive(1).is_none() {
            return; // no /proc: liveness cannot be told here
        }
        // Process ids are below 2^22 on Linux: this one is not running.
        std::fs::write(dir.path().join(".lock"), "4294967\n").unwrap();
        let (_lock, note) = Lock::acquire(dir.path()).unwrap();
        assert!(note.unwrap().contains("4294967"));
    }

    #[test]
    fn a_garbled_lock_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join(".lock"), "garbage").unwrap();
        let e = Lock::acquire(dir.path()).unwrap_err().to_string();
        assert!(
            e.contains("garbage") && e.contains("remove the lock"),
            "{e}"
        );
    }
}
