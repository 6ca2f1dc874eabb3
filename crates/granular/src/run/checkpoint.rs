//! The checkpoint file: a header that names the file as a granular checkpoint, its format,
//! the payload's length and CRC-32, then the MessagePack payload. Each way the file can be
//! damaged (truncated, a flipped bit, not a checkpoint, another format) is named on reading,
//! with what to do; a failed write leaves the previous checkpoint intact and no temporary
//! file behind.

use super::{CHECKPOINT_FORMAT, RunError};
use std::io::Write;
use std::path::{Path, PathBuf};

/// The first bytes of every checkpoint since format 8.
pub const MAGIC: &[u8; 8] = b"GRANCKPT";

/// Magic, format (u32), payload length (u64), CRC-32 of the payload (u32), little-endian.
const HEADER_LEN: usize = 8 + 4 + 8 + 4;

/// The checkpoint file of the run directory `dir`.
pub(crate) fn path(dir: &Path) -> PathBuf {
    super::RunDir::new(dir).file(super::RunFile::Checkpoint)
}

/// The header and payload of a checkpoint.
pub(crate) fn encode(payload: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(HEADER_LEN + payload.len());
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&CHECKPOINT_FORMAT.to_le_bytes());
    out.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    out.extend_from_slice(&crc32fast::hash(payload).to_le_bytes());
    out.extend_from_slice(payload);
    out
}

fn damaged(path: &Path, what: String) -> RunError {
    let dir = path.parent().unwrap_or(Path::new("."));
    RunError::Checkpoint {
        path: path.to_path_buf(),
        message: format!(
            "{what}. The run cannot continue from it; rerun the scenario: \
             `granular run {} --out {} --replace`",
            super::RunDir::new(dir)
                .file(super::RunFile::Scenario)
                .display(),
            dir.display()
        ),
    }
}

/// The payload of the checkpoint `bytes` read from `path`, checked against its header.
pub(crate) fn decode<'a>(path: &Path, bytes: &'a [u8]) -> Result<&'a [u8], RunError> {
    if !bytes.starts_with(MAGIC) {
        // Formats up to 7 were a bare MessagePack map that began with its format number.
        #[derive(serde::Deserialize)]
        struct Header {
            format: u32,
        }
        if let Ok(Header { format }) = rmp_serde::from_slice::<Header>(bytes) {
            return Err(RunError::Checkpoint {
                path: path.to_path_buf(),
                message: format!(
                    "checkpoint format {format} was written by another version of granular; \
                     this one reads format {CHECKPOINT_FORMAT}. Resume with the version that \
                     wrote it, or rerun the scenario (DIR/scenario.toml) with --replace"
                ),
            });
        }
        return Err(damaged(
            path,
            format!(
                "is not a granular checkpoint ({} bytes that do not begin with `GRANCKPT`)",
                bytes.len()
            ),
        ));
    }
    if bytes.len() < HEADER_LEN {
        return Err(damaged(
            path,
            format!(
                "is truncated: {} bytes, shorter than the {HEADER_LEN}-byte header",
                bytes.len()
            ),
        ));
    }
    let word = |at: usize, n: usize| -> u64 {
        bytes[at..at + n]
            .iter()
            .rev()
            .fold(0u64, |acc, &b| (acc << 8) | u64::from(b))
    };
    let format = word(8, 4) as u32;
    if format != CHECKPOINT_FORMAT {
        return Err(RunError::Checkpoint {
            path: path.to_path_buf(),
            message: format!(
                "checkpoint format {format} was written by another version of granular; \
                 this one reads format {CHECKPOINT_FORMAT}. Resume with the version that \
                 wrote it, or rerun the scenario (DIR/scenario.toml) with --replace"
            ),
        });
    }
    let length = word(12, 8);
    let crc = word(20, 4) as u32;
    let payload = &bytes[HEADER_LEN..];
    if (payload.len() as u64) < length {
        return Err(damaged(
            path,
            format!(
                "is truncated: {} of its {length} bytes of state are present (a full disk or \
                 an interrupted copy?)",
                payload.len()
            ),
        ));
    }
    if payload.len() as u64 > length {
        return Err(damaged(
            path,
            format!(
                "has {} bytes after its {length} bytes of state (two files joined, or an \
                 interrupted copy?)",
                payload.len() as u64 - length
            ),
        ));
    }
    let actual = crc32fast::hash(payload);
    if actual != crc {
        return Err(damaged(
            path,
            format!(
                "is corrupt: the CRC-32 of its state is {actual:08x}, the header says \
                 {crc:08x} (a damaged disk, memory or copy)"
            ),
        ));
    }
    Ok(payload)
}

/// Writes `bytes` to `path` atomically: to `path.tmp`, flushed to the disk, then renamed.
/// On failure the temporary file is removed and `path` is as it was.
pub(crate) fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), RunError> {
    let mut tmp_name = path.as_os_str().to_owned();
    tmp_name.push(".tmp");
    let tmp = PathBuf::from(tmp_name);
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    result.map_err(|source| {
        if tmp.is_file() {
            let _ = std::fs::remove_file(&tmp);
        }
        let dir = path.parent().unwrap_or(Path::new("."));
        let kept = if path.is_file() {
            "the previous checkpoint is intact"
        } else {
            "there is no earlier checkpoint"
        };
        RunError::CheckpointWrite {
            path: path.to_path_buf(),
            message: format!(
                "{source} ({} bytes); {kept}. Free space on the disk (or fix its permissions), \
                 then continue with `granular resume {}`",
                bytes.len(),
                dir.display()
            ),
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bytes() -> Vec<u8> {
        encode(&rmp_serde::to_vec_named(&[1.5f64, 2.5, 3.5]).unwrap())
    }

    fn err(b: &[u8]) -> String {
        decode(Path::new("d/checkpoint.msgpack"), b)
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn a_sound_checkpoint_decodes() {
        let b = bytes();
        let payload = decode(Path::new("c"), &b).unwrap();
        let v: Vec<f64> = rmp_serde::from_slice(payload).unwrap();
        assert_eq!(v, [1.5, 2.5, 3.5]);
    }

    #[test]
    fn every_flipped_bit_is_caught() {
        let b = bytes();
        for i in 0..b.len() * 8 {
            let mut c = b.clone();
            c[i / 8] ^= 1 << (i % 8);
            assert!(decode(Path::new("c"), &c).is_err(), "bit {i} not caught");
        }
        let mut c = b.clone();
        c[HEADER_LEN + 3] ^= 4;
        assert!(err(&c).contains("corrupt") && err(&c).contains("--replace"));
    }

    #[test]
    fn damage_is_named() {
        let b = bytes();
        assert!(err(&b[..b.len() - 1]).contains("truncated"));
        assert!(err(&b[..10]).contains("truncated"));
        let mut longer = b.clone();
        longer.push(0);
        assert!(err(&longer).contains("after its"));
        assert!(err(b"hello world").contains("not a granular checkpoint"));
        assert!(err(b"").contains("not a granular checkpoint"));
        let old = rmp_serde::to_vec_named(&serde_json::json!({"format": 7, "x": 1})).unwrap();
        assert!(err(&old).contains("format 7"), "{}", err(&old));
        let mut other = b.clone();
        other[8] = 99;
        assert!(err(&other).contains("format 99"));
    }

    #[test]
    fn a_failed_write_keeps_the_previous_checkpoint_and_no_tmp() {
        let dir = tempfile::tempdir().unwrap();
        let path = crate::run::RunDir::new(dir.path()).file(crate::run::RunFile::Checkpoint);
        write_atomic(&path, b"first").unwrap();
        // A directory where the temporary file would go (`write_atomic`'s `PATH.tmp`): the
        // write fails.
        let mut tmp = path.as_os_str().to_owned();
        tmp.push(".tmp");
        let tmp = PathBuf::from(tmp);
        std::fs::create_dir(&tmp).unwrap();
        std::fs::write(tmp.join("x"), b"occupied").unwrap();
        let e = write_atomic(&path, b"second").unwrap_err().to_string();
        assert!(
            e.contains("previous checkpoint is intact") && e.contains("granular resume"),
            "{e}"
        );
        assert_eq!(std::fs::read(&path).unwrap(), b"first");
    }
}
