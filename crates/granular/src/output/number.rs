//! Numbers as people read them, for the terminal and `log.txt`: six significant digits
//! without trailing zeros, in exponent notation (`2.25e6`, `1e-9`) outside
//! `1e-4 <= |x| < 1e6`; `NaN`, `inf` and `-inf` spelt out.

/// Significant digits of [`format_number`].
pub(crate) const SIGNIFICANT_DIGITS: usize = 6;

/// `x` with `SIGNIFICANT_DIGITS` significant digits: `0.83` (not
/// `0.8300000000000001`), `28000`, `2.25e6`, `1.5e-7`, `0`, `NaN`, `inf`.
pub fn format_number(x: f64) -> String {
    if x.is_nan() {
        return "NaN".into();
    }
    if x.is_infinite() {
        return if x > 0.0 { "inf" } else { "-inf" }.into();
    }
    if x == 0.0 {
        return "0".into();
    }
    // The exponent after rounding to the significant digits (999999.7 is 1e6).
    let sci = format!("{:.*e}", SIGNIFICANT_DIGITS - 1, x);
    let (mantissa, exponent) = sci.split_once('e').unwrap_or((&sci, "0"));
    let exponent: i32 = exponent.parse().unwrap_or(0);
    if (-4..6).contains(&exponent) {
        let decimals = (SIGNIFICANT_DIGITS as i32 - 1 - exponent).max(0) as usize;
        trim_zeros(&format!("{x:.decimals$}"))
    } else {
        format!("{}e{exponent}", trim_zeros(mantissa))
    }
}

/// `1.50000` → `1.5`, `2.00000` → `2`, `28000` unchanged.
fn trim_zeros(s: &str) -> String {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_at_every_magnitude() {
        let cases = [
            (0.8300000000000001, "0.83"),
            (2.25e6, "2.25e6"),
            (4.5e7, "4.5e7"),
            (28000.0, "28000"),
            (225000.0, "225000"),
            (999999.0, "999999"),
            (999999.7, "1e6"),
            (1e12, "1e12"),
            (1.234567e12, "1.23457e12"),
            (1e-9, "1e-9"),
            (-3.25e-9, "-3.25e-9"),
            (1e-4, "0.0001"),
            (9.99e-5, "9.99e-5"),
            (0.1 + 0.2, "0.3"),
            (1.0, "1"),
            (-2.5, "-2.5"),
            (123.456789, "123.457"),
            (0.0, "0"),
            (-0.0, "0"),
            (f64::NAN, "NaN"),
            (f64::INFINITY, "inf"),
            (f64::NEG_INFINITY, "-inf"),
            (f64::MAX, "1.79769e308"),
            (f64::MIN_POSITIVE, "2.22507e-308"),
        ];
        for (x, want) in cases {
            assert_eq!(format_number(x), want, "{x:e}");
        }
    }

    #[test]
    fn every_decade_reads_back_to_six_digits() {
        for k in -9..=12 {
            for m in [1.0, 1.5, 4.567_891, 9.999_994] {
                let x = m * 10f64.powi(k);
                let s = format_number(x);
                let back: f64 = s.parse().unwrap();
                assert!((back - x).abs() <= 5e-6 * x.abs(), "{x:e} -> {s}");
                assert!(s.len() <= 12, "{x:e} -> {s}");
                assert_eq!(s.contains('e'), !(1e-4..1e6).contains(&back), "{s}");
            }
        }
    }
}
