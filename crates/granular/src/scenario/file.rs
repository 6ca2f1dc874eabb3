//! Reading a scenario file (or a file it names, such as a tabulated bath): a path that is
//! not a regular file, or one larger than such a file can reasonably be, is refused before
//! anything is read (`granular run /dev/zero` would otherwise read until memory runs out).

use std::io::{Error, ErrorKind, Read};
use std::path::Path;

/// The largest scenario (or bath table) file read: 64 MiB, room for explicit positions of
/// about a million grains. Larger inputs belong in NumPy arrays (`docs/python.md`).
pub const MAX_FILE_BYTES: u64 = 64 << 20;

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
/// what the path is) when it is not a regular file, is larger than [`MAX_FILE_BYTES`] or
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

/// The `--set` override (`intruder.bath.file="/abs/path"`) that makes a tabulated intruder
/// bath's relative `file` absolute, relative to the directory of the scenario file
/// `scenario_file`, so that validation reads it and run directories, sweeps and resumes
/// find it from any working directory; `None` when there is nothing to make absolute. The
/// command line and the Python package both apply it.
pub fn bath_file_override(scenario_file: &Path, sc: &super::Scenario) -> Option<String> {
    let super::BathTable::Tabulated { file: Some(f), .. } = sc.intruder()?.bath()? else {
        return None;
    };
    if Path::new(f).is_absolute() {
        return None;
    }
    let base = scenario_file
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let base = std::path::absolute(base).unwrap_or_else(|_| base.to_path_buf());
    let full = base.join(f).to_string_lossy().into_owned();
    Some(format!("intruder.bath.file={}", toml::Value::String(full)))
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
