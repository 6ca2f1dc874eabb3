//! What the machine says about itself (Linux `/proc`): the memory it can give and the
//! memory this process holds. Read once here for the pre-flight estimate of a scenario
//! and for the benchmarks.

/// `MemAvailable` of `/proc/meminfo` in bytes: the memory the system can give without
/// swapping; `None` where the system does not say.
pub(crate) fn available_memory() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    kilobytes(&text, "MemAvailable:")
}

/// `VmRSS` and `VmHWM` of this process in bytes (the resident memory now and at its
/// peak), NaN where the system does not say.
pub(crate) fn resident_memory() -> (f64, f64) {
    let text = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let field = |key: &str| kilobytes(&text, key).unwrap_or(f64::NAN);
    (field("VmRSS:"), field("VmHWM:"))
}

/// The value of the line `key  N kB` of a `/proc` file, in bytes.
fn kilobytes(text: &str, key: &str) -> Option<f64> {
    let line = text.lines().find(|l| l.starts_with(key))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024.0)
}

#[cfg(test)]
mod tests {
    use super::kilobytes;

    #[test]
    fn reads_a_proc_line() {
        let text = "MemTotal:       16000000 kB\nMemAvailable:    8000000 kB\n";
        assert_eq!(kilobytes(text, "MemAvailable:"), Some(8_000_000.0 * 1024.0));
        assert_eq!(kilobytes(text, "VmRSS:"), None);
    }
}
