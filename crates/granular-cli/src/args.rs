//! The numbers of the command line's flags, read in words a user knows. Every numeric flag
//! is declared with `allow_hyphen_values`, so that a negative number reaches its parser
//! (clap alone takes `-1` for a flag and answers "unexpected argument"): a quantity that
//! may be negative (`--gravity`) accepts it, the others are refused with their allowed
//! range, here or in the command's own checks (which name the flag and the reason).

/// `Err` saying what the flag takes and what was given.
fn refuse<T>(what: &str, s: &str) -> Result<T, String> {
    Err(format!("{what} (got `{s}`)"))
}

/// A whole number `>= 0`, also written as `1e6`.
fn whole(s: &str) -> Option<u64> {
    let t = s.trim();
    t.parse::<u64>().ok().or_else(|| {
        t.parse::<f64>()
            .ok()
            .filter(|x| *x >= 0.0 && x.fract() == 0.0 && *x < u64::MAX as f64)
            .map(|x| x as u64)
    })
}

/// `--threads`: a number of worker threads (0 is refused by the command, with the number
/// of cores).
pub(crate) fn threads(s: &str) -> Result<usize, String> {
    whole(s).map_or_else(
        || refuse("a number of worker threads is a whole number, 1 or more", s),
        |n| Ok(n as usize),
    )
}

/// `--dimension`: 2 or 3.
pub(crate) fn dimension(s: &str) -> Result<usize, String> {
    match s.trim() {
        "2" => Ok(2),
        "3" => Ok(3),
        _ => refuse("the dimension is 2 or 3", s),
    }
}

/// `--collisions`, `--steps`, `--segments`: a whole number, 1 or more.
pub(crate) fn count(s: &str) -> Result<u64, String> {
    match whole(s) {
        Some(n) if n >= 1 => Ok(n),
        _ => refuse(
            "a count is a whole number, 1 or more (`1e6` is read as 1000000)",
            s,
        ),
    }
}

/// A number flag: any number that reads as one (`1`, `-2.5`, `3e-4`); the command checks
/// its range and says it.
pub(crate) fn number(s: &str) -> Result<f64, String> {
    s.trim()
        .parse::<f64>()
        .or_else(|_| refuse("a number, e.g. 1, -2.5 or 3e-4", s))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parsers_read_negative_numbers_and_name_the_range() {
        assert_eq!(number("-1"), Ok(-1.0));
        assert_eq!(threads("2"), Ok(2));
        assert_eq!(count("1e6"), Ok(1_000_000));
        assert!(threads("-1").unwrap_err().contains("1 or more"));
        assert!(dimension("4").unwrap_err().contains("2 or 3"));
        assert!(count("0").unwrap_err().contains("(got `0`)"));
        assert!(number("x").unwrap_err().contains("a number"));
        for e in [
            threads("x").unwrap_err(),
            count("-3").unwrap_err(),
            dimension("two").unwrap_err(),
        ] {
            assert!(!e.contains("usize") && !e.contains("digit"), "{e}");
        }
    }
}
