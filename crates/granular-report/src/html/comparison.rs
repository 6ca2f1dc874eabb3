//! One comparison of a measured number with its theory ([`Comparison`]): the deviation
//! in the combined uncertainty `sqrt(error² + accuracy²)` of the run's standard error and
//! the theory's stated accuracy, and the table that shows the rows ([`render`]), coloured
//! only where the theory applies and the disagreement is real. The rows themselves come
//! from `numbers` (equilibrium, intruder), `cooling` (Haff's law) and `steady` (driven
//! states).

use super::page::{escape, number, table};

/// One measured number, its standard error, its theory value with the theory's stated
/// accuracy, and where that comes from (`NaN` where there is none).
pub(crate) struct Comparison {
    pub quantity: String,
    pub measured: f64,
    /// The run's standard error of `measured`.
    pub error: f64,
    pub theory: f64,
    /// The stated accuracy of `theory` (absolute; 0 for an exact result).
    pub accuracy: f64,
    pub source: String,
    /// Whether `measured / theory - 1` means something (not for a chi-square).
    pub relative: bool,
    /// Why the theory does not apply to this run (the row is then not compared).
    pub not_applicable: Option<String>,
}

impl Comparison {
    pub(crate) fn new(quantity: impl Into<String>, measured: f64, error: f64, theory: f64) -> Self {
        Self {
            quantity: quantity.into(),
            measured,
            error,
            theory,
            accuracy: 0.0,
            source: String::new(),
            relative: true,
            not_applicable: None,
        }
    }

    /// A row with nothing measured (the theory does not apply).
    pub(crate) fn unmeasured(quantity: impl Into<String>) -> Self {
        Self::new(quantity, f64::NAN, f64::NAN, f64::NAN)
    }

    pub(crate) fn absolute(mut self) -> Self {
        self.relative = false;
        self
    }

    pub(crate) fn source(mut self, source: impl Into<String>) -> Self {
        self.source = source.into();
        self
    }

    /// Sets the theory's stated accuracy (absolute).
    pub(crate) fn accuracy(mut self, accuracy: f64) -> Self {
        self.accuracy = accuracy;
        self
    }

    /// Marks the theory as not applying to this run, saying why.
    pub(crate) fn not_applicable(mut self, why: impl Into<String>) -> Self {
        self.not_applicable = Some(why.into());
        self
    }

    /// The combined uncertainty `sqrt(error² + accuracy²)` (`NaN` without an error).
    pub(crate) fn uncertainty(&self) -> f64 {
        let accuracy = if self.accuracy.is_finite() {
            self.accuracy
        } else {
            0.0
        };
        (self.error * self.error + accuracy * accuracy).sqrt()
    }

    /// `(measured - theory) / uncertainty`; `NaN` when any is missing or the theory does
    /// not apply.
    pub(crate) fn deviation(&self) -> f64 {
        let u = self.uncertainty();
        if self.not_applicable.is_none() && u > 0.0 {
            (self.measured - self.theory) / u
        } else {
            f64::NAN
        }
    }
}

/// The comparison table, the deviation in combined standard uncertainties coloured by its
/// size (`ok` below 2, `warn` below 3, `bad` from 3; `none`, neutral, where nothing is
/// compared).
pub(crate) fn render(rows: &[Comparison]) -> String {
    if rows.is_empty() {
        return "<p>This run has no quantity with an exact theory to compare with \
                (see the final observables below).</p>"
            .into();
    }
    let body: Vec<Vec<String>> = rows
        .iter()
        .map(|c| {
            let z = c.deviation();
            let class = if !z.is_finite() {
                "none"
            } else if z.abs() < 2.0 {
                "ok"
            } else if z.abs() < 3.0 {
                "warn"
            } else {
                "bad"
            };
            let measured = if c.error.is_finite() {
                format!("{} ± {}", number(c.measured), number(c.error))
            } else {
                number(c.measured)
            };
            let theory = if c.accuracy > 0.0 && c.theory.is_finite() {
                format!("{} ± {}", number(c.theory), number(c.accuracy))
            } else {
                number(c.theory)
            };
            let deviation = if z.is_finite() {
                format!("{z:+.2} σ")
            } else if c.not_applicable.is_some() {
                "not compared".into()
            } else {
                "—".into()
            };
            let relative = c.measured / c.theory - 1.0;
            let relative = if c.relative && relative.is_finite() && c.theory != 0.0 {
                format!("{:+.2} %", 100.0 * relative)
            } else {
                "—".into()
            };
            let notes = match &c.not_applicable {
                Some(why) if c.source.is_empty() => format!("Not compared: {why}."),
                Some(why) => format!("Not compared: {why}. {}", c.source),
                None => c.source.clone(),
            };
            vec![
                escape(&c.quantity),
                measured,
                theory,
                format!("<span class=\"z {class}\">{deviation}</span>"),
                relative,
                escape(&notes),
            ]
        })
        .collect();
    let mut out = String::from(
        "<p>Deviation: (measured − theory) / √(error² + accuracy²), the run's standard error \
         combined with the theory's stated accuracy; green below 2, amber below 3, red from 3. \
         A theory whose conditions the run does not meet is not compared, and the row says why.</p>",
    );
    out.push_str(&table(
        "numbers",
        &[
            "quantity",
            "measured ± standard error",
            "theory ± stated accuracy",
            "deviation",
            "relative",
            "theory and notes",
        ],
        &body,
    ));
    out
}
