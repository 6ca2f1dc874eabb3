//! The intruder's lines of the end-of-run report of `granular run` (`engine = "intruder"`):
//! `T/T_B` and kurtosis with their errors and the theory value with its z-score (1D), or
//! the needle's temperatures and `R`.

use granular::run::Summary;

/// One or two lines on the intruder's result for the end of `granular run`.
pub fn print(summary: &Summary) {
    let Some(b) = &summary.intruder else {
        return;
    };
    let f = |k: &str| b.value(k).unwrap_or(f64::NAN);
    if b.value("temperature_ratio").is_some() {
        eprint!(
            "  T/T_B = {:.5} ± {:.5}, kurtosis = {:.4} ± {:.4}",
            f("temperature_ratio"),
            f("temperature_ratio_error"),
            f("kurtosis"),
            f("kurtosis_error")
        );
        match b.theory_temperature_ratio {
            Some(_) => eprintln!(
                "; theory {:.5} (z = {:.2})",
                f("theory_temperature_ratio"),
                f("temperature_ratio_z")
            ),
            None => eprintln!(),
        }
    } else {
        eprintln!(
            "  T_tr/T_B = {:.5} ± {:.5}, T_rot/T_B = {:.5} ± {:.5}, R = {:.5} ± {:.5}",
            f("translational_temperature_ratio"),
            f("translational_temperature_ratio_error"),
            f("rotational_temperature_ratio"),
            f("rotational_temperature_ratio_error"),
            f("correlation_r"),
            f("correlation_r_error")
        );
    }
}
