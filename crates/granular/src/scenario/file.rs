//! Reading a scenario file (or a file it names, such as a tabulated bath): a path that is
//! not a regular file, or one larger than such a file can reasonably be, is refused before
//! anything is read (`granular run /dev/zero` would otherwise read until memory runs out).

use std::io::{Error, ErrorKind, Read};
use std::path::Path;

/// The largest scenario (or bath table) file read: 64 MiB, room for explicit positions of
/// about a million grains. Larger inputs belong in NumPy arrays (`docs/python.md`).
pub(crate) const MAX_FILE_BYTES: u64 = 64 << 20;

/// What kind of file system object `meta` is, in words.
fn kind(meta: &std::fs::Metadata) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        let t = meta.file_type();
        if t.is_char_device() {
            return "a character device";
        }
        if t.is_block_device() {
            return "a block device";
        }
        if t.is_fifo() {
            return "a named pipe";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    if meta.is_dir() {
        "a directory"
    } else {
        "not a regular file"
    }
}

/// The text of the file at `path`, refused (`ErrorKind::InvalidInput`, the message naming
/// what the path is) when it is not a regular file, is larger than `MAX_FILE_BYTES` or
/// is not UTF-8 text; other errors (not found, no permission) as the system gives them.
pub fn read_text_file(path: &Path) -> Result<String, Error> {
    let meta = std::fs::metadata(path)?;
    if !meta.is_file() {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            format!("{} is {}, not a file", path.display(), kind(&meta)),
        ));
    }
    let too_large = |size: &str| {
        Error::new(
            ErrorKind::InvalidInput,
            format!(
                "{} is {size}, larger than a scenario file can reasonably be (at most {} MiB); \
                 give grains' positions as NumPy arrays instead (docs/python.md)",
                path.display(),
                MAX_FILE_BYTES >> 20
            ),
        )
    };
    if meta.len() > MAX_FILE_BYTES {
        return Err(too_large(&format!("{} MiB", meta.len() >> 20)));
    }
    // A file that grows while it is read (or a special file posing as a regular one) is
    // cut at the limit.
    let mut bytes = Vec::new();
    std::fs::File::open(path)?
        .take(MAX_FILE_BYTES + 1)
        .read_to_end(&mut bytes)?;
    if bytes.len() as u64 > MAX_FILE_BYTES {
        return Err(too_large(&format!("over {} MiB", MAX_FILE_BYTES >> 20)));
    }
    String::from_utf8(bytes).map_err(|e| {
        Error::new(
            ErrorKind::InvalidData,
            format!(
                "{} is not text (UTF-8): byte {} is not",
                path.display(),
                e.utf8_error().valid_up_to() + 1
            ),
        )
    })
}

/// The `--set` overrides that make the scenario's relative file paths absolute, relative
/// to the directory of the scenario file `scenario_file`: a tabulated intruder bath's
/// `file` (`intruder.bath.file="/abs/path"`) and the `.npz` files of per-grain arrays
/// (`species[0].positions.npz="/abs/path"`), so that validation reads them and run
/// directories, sweeps and resumes find them from any working directory; empty when there
/// is nothing to make absolute. The command line and the Python package both apply them.
pub fn file_overrides(scenario_file: &Path, sc: &super::Scenario) -> Vec<String> {
    let base = scenario_file
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let base = std::path::absolute(base).unwrap_or_else(|_| base.to_path_buf());
    let absolute = |key: &str, f: &str| {
        (!Path::new(f).is_absolute()).then(|| {
            let full = base.join(f).to_string_lossy().into_owned();
            format!("{key}={}", toml::Value::String(full))
        })
    };
    let mut out = Vec::new();
    if let Some(super::BathTable::Tabulated { file: Some(f), .. }) =
        sc.intruder().and_then(|i| i.bath())
    {
        out.extend(absolute("intruder.bath.file", f));
    }
    for (key, v) in sc.without_arrays().1 {
        if let super::VectorSource::Npz { npz, .. } = v.source() {
            out.extend(absolute(&format!("{key}.npz"), npz));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn special_files_and_directories_are_refused_before_reading() {
        let e = read_text_file(Path::new("/dev/zero")).unwrap_err();
        assert_eq!(e.kind(), ErrorKind::InvalidInput);
        assert!(e.to_string().contains("a character device"), "{e}");
        let e = read_text_file(Path::new("/")).unwrap_err();
        assert!(e.to_string().contains("a directory"), "{e}");
        let e = read_text_file(Path::new("/no/such/scenario.toml")).unwrap_err();
        assert_eq!(e.kind(), ErrorKind::NotFound);
    }
}
