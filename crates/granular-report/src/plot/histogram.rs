//! [`HistogramPlot`]: a normalised histogram (probability density per bin) with optional
//! error bars and theory densities overlaid.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::coord::ranged1d::Ranged;
use plotters::prelude::*;

use super::chart::{ChartBody, Frame, LegendPosition, Ranges, along, draw_chart, padded_range};
use super::colour::{Colour, darken, lighten, palette};
use super::line::{Series, check_range, draw_error_bars, draw_line, draw_notes, sample_points};
use super::{DEFAULT_SIZE, Draw, Metrics, PlotError, save_both, save_figure};

/// A normalised histogram with theory curves.
///
/// ```no_run
/// # use granular_report::plot::HistogramPlot;
/// # use granular::theory::equilibrium::speed_density;
/// # fn demo(speeds: &[f64]) -> Result<(), granular_report::plot::PlotError> {
/// HistogramPlot::from_samples("Speed distribution", speeds, 40, None)
///     .x_label("speed v [L/τ]").y_label("probability density p(v) [τ/L]")
///     .theory("Maxwell–Boltzmann, T = 1", |v| speed_density(2, v, 1.0, 1.0))
///     .save("speeds.png")?;
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug)]
pub struct HistogramPlot {
    title: String,
    x_label: String,
    y_label: String,
    data_name: String,
    edges: Vec<f64>,
    densities: Vec<f64>,
    errors: Option<Vec<f64>>,
    theories: Vec<Series>,
    log_y: bool,
    legend: LegendPosition,
    size: (u32, u32),
    colour: Colour,
    notes: Vec<String>,
}

impl HistogramPlot {
    /// A histogram from `edges` (`k + 1` increasing values) and `densities` (`k` values,
    /// already normalised so that `Σ density·width = 1`).
    pub fn new(title: impl Into<String>, edges: Vec<f64>, densities: Vec<f64>) -> Self {
        Self {
            title: title.into(),
            x_label: String::new(),
            y_label: "probability density".into(),
            data_name: "simulation".into(),
            edges,
            densities,
            errors: None,
            theories: Vec::new(),
            log_y: false,
            legend: LegendPosition::Auto,
            size: DEFAULT_SIZE,
            colour: palette(0),
            notes: Vec::new(),
        }
    }

    /// Adds a line of text to the legend box, e.g. the goodness of fit
    /// (see [`HistogramPlot::goodness_of_fit`]).
    pub fn note(mut self, text: impl Into<String>) -> Self {
        self.notes.push(text.into());
        self
    }

    /// Prints Pearson's test of the histogram against its theory curve in the legend:
    /// `χ² = …, dof = …, p = …`.
    pub fn goodness_of_fit(self, chi_square: f64, degrees_of_freedom: usize, p: f64) -> Self {
        self.note(fit_text(chi_square, degrees_of_freedom, p))
    }

    /// Bins `samples` into `bins` equal bins over `range` (default: the finite samples'
    /// extent) and normalises to a density, with Poisson error bars `√count / (N·width)`.
    /// Samples outside the range count in the normalisation but are not drawn.
    pub fn from_samples(
        title: impl Into<String>,
        samples: &[f64],
        bins: usize,
        range: Option<(f64, f64)>,
    ) -> Self {
        let finite: Vec<f64> = samples.iter().copied().filter(|v| v.is_finite()).collect();
        let bins = bins.max(1);
        let (lo, hi) = range.unwrap_or_else(|| {
            let lo = finite.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = finite.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            if lo < hi {
                (lo, hi)
            } else {
                (lo - 0.5, lo + 0.5)
            }
        });
        let width = (hi - lo) / bins as f64;
        let edges: Vec<f64> = (0..=bins).map(|i| lo + width * i as f64).collect();
        let mut counts = vec![0u64; bins];
        for &v in &finite {
            if v >= lo && v <= hi && width > 0.0 {
                let i = (((v - lo) / width) as usize).min(bins - 1);
                counts[i] += 1;
            }
        }
        let norm = finite.len().max(1) as f64 * width;
        let densities = counts.iter().map(|&c| c as f64 / norm).collect();
        let errors = counts.iter().map(|&c| (c as f64).sqrt() / norm).collect();
        Self::new(title, edges, densities).with_errors(errors)
    }

    /// Error bar half-widths, one per bin.
    pub fn with_errors(mut self, errors: Vec<f64>) -> Self {
        self.errors = Some(errors);
        self
    }

    /// Legend entry of the histogram (default `"simulation"`).
    pub fn data_label(mut self, name: impl Into<String>) -> Self {
        self.data_name = name.into();
        self
    }

    /// The x-axis label, with units.
    pub fn x_label(mut self, label: impl Into<String>) -> Self {
        self.x_label = label.into();
        self
    }

    /// The y-axis label, with units (default `"probability density"`).
    pub fn y_label(mut self, label: impl Into<String>) -> Self {
        self.y_label = label.into();
        self
    }

    /// Overlays a theory density `f`, sampled finely over the histogram's range.
    pub fn theory(mut self, name: impl Into<String>, f: impl Fn(f64) -> f64) -> Self {
        let (a, b) = match (self.edges.first(), self.edges.last()) {
            (Some(&a), Some(&b)) => (a, b),
            _ => (0.0, 1.0),
        };
        let x = sample_points(a, b, 400, false);
        let y = x.iter().map(|&v| f(v)).collect();
        self.theories.push(Series::theory(name, x, y));
        self
    }

    /// Overlays a theory curve given as points.
    pub fn theory_points(mut self, name: impl Into<String>, x: Vec<f64>, y: Vec<f64>) -> Self {
        self.theories.push(Series::theory(name, x, y));
        self
    }

    /// Overlays a theory curve given as points, drawn only over the range of the bins that
    /// hold data (so a log-scale tail is not extrapolated past the data).
    pub fn theory_points_over_data(
        self,
        name: impl Into<String>,
        x: Vec<f64>,
        y: Vec<f64>,
    ) -> Self {
        let used: Vec<usize> = (0..self.densities.len())
            .filter(|&i| self.densities[i] > 0.0)
            .collect();
        let (lo, hi) = match (used.first(), used.last()) {
            (Some(&a), Some(&b)) => (self.edges[a], self.edges[b + 1]),
            _ => (f64::NEG_INFINITY, f64::INFINITY),
        };
        let (x, y) = x
            .into_iter()
            .zip(y)
            .filter(|(x, _)| *x >= lo && *x <= hi)
            .unzip();
        self.theory_points(name, x, y)
    }

    /// Logarithmic density axis (to show the tails); empty bins are not drawn.
    pub fn log_y(mut self, log: bool) -> Self {
        self.log_y = log;
        self
    }

    /// Where the legend goes (default: the emptiest corner).
    pub fn legend(mut self, position: LegendPosition) -> Self {
        self.legend = position;
        self
    }

    /// Bar colour (default: the first palette colour).
    pub fn colour(mut self, colour: Colour) -> Self {
        self.colour = colour;
        self
    }

    /// Figure size in pixels.
    pub fn size(mut self, width: u32, height: u32) -> Self {
        self.size = (width, height);
        self
    }

    /// Writes the plot as PNG or SVG, by the extension of `path`.
    ///
    /// # Errors
    /// [`PlotError::UnknownFormat`], [`PlotError::Data`] for inconsistent bins,
    /// [`PlotError::Draw`] if the file cannot be written.
    pub fn save(&self, path: impl AsRef<Path>) -> Result<(), PlotError> {
        save_figure(self, path.as_ref())
    }

    /// Writes `stem.png` and `stem.svg`; returns their paths.
    ///
    /// # Errors
    /// As [`HistogramPlot::save`].
    pub fn save_png_and_svg(&self, stem: impl AsRef<Path>) -> Result<[PathBuf; 2], PlotError> {
        save_both(self, stem.as_ref())
    }

    fn bars(&self) -> Vec<(f64, f64, f64, f64)> {
        (0..self.densities.len())
            .map(|i| {
                let e = self.errors.as_ref().map_or(0.0, |e| e[i]);
                (self.edges[i], self.edges[i + 1], self.densities[i], e)
            })
            .filter(|&(_, _, d, _)| d.is_finite() && (!self.log_y || d > 0.0))
            .collect()
    }

    fn ranges(&self) -> Result<Ranges, PlotError> {
        let x = (self.edges[0], self.edges[self.edges.len() - 1]);
        let theory_y = self
            .theories
            .iter()
            .flat_map(|s| s.x.iter().zip(&s.y))
            .filter(|&(&x0, _)| x0 >= x.0 && x0 <= x.1)
            .map(|(_, &y)| y);
        let bar_y = self.bars().into_iter().map(|(_, _, d, e)| d + e);
        let y = if self.log_y {
            let lows = self.bars().into_iter().map(|(_, _, d, _)| d);
            padded_range(bar_y.chain(theory_y).chain(lows), true, 0.05)?
        } else {
            let top = bar_y
                .chain(theory_y)
                .filter(|v| v.is_finite())
                .fold(0.0, f64::max);
            (0.0, if top > 0.0 { top * 1.08 } else { 1.0 })
        };
        check_range(x, false, "x")?;
        check_range(y, self.log_y, "y")?;
        Ok((x, y))
    }
}

impl ChartBody for HistogramPlot {
    fn draw_body<'a, DB, X, Y>(
        &self,
        chart: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
        m: &Metrics,
    ) -> Result<(), PlotError>
    where
        DB: DrawingBackend + 'a,
        X: Ranged<ValueType = f64>,
        Y: Ranged<ValueType = f64>,
    {
        let floor = chart.y_range().start;
        let fill = lighten(self.colour, 0.45).filled();
        let edge = darken(self.colour, 0.3).stroke_width(m.line.max(2) - 1);
        let bars = self.bars();
        if self.log_y {
            // On a log axis bars would need an arbitrary floor: draw the histogram as steps,
            // one polyline per run of adjacent non-empty bins, not dropped to the axis
            // (an empty bin has no logarithm: it is left blank).
            let mut runs: Vec<Vec<(f64, f64)>> = Vec::new();
            let mut last_end = f64::NAN;
            for &(a, b, d, _) in &bars {
                if a != last_end || runs.is_empty() {
                    runs.push(Vec::new());
                }
                if let Some(run) = runs.last_mut() {
                    run.push((a, d));
                    run.push((b, d));
                }
                last_end = b;
            }
            let style = darken(self.colour, 0.1).stroke_width(m.line);
            let anno =
                chart.draw_series(runs.into_iter().map(|run| PathElement::new(run, style)))?;
            if !self.data_name.is_empty() {
                let w = (m.legend * 1.8) as i32;
                anno.label(self.data_name.as_str())
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + w, y)], style));
            }
        } else {
            let anno = chart.draw_series(
                bars.iter()
                    .map(|&(a, b, d, _)| Rectangle::new([(a, floor), (b, d)], fill)),
            )?;
            if !self.data_name.is_empty() {
                let h = (m.legend * 0.4) as i32;
                let w = (m.legend * 1.8) as i32;
                anno.label(self.data_name.as_str())
                    .legend(move |(x, y)| Rectangle::new([(x, y - h), (x + w, y + h)], fill));
            }
            chart.draw_series(
                bars.iter()
                    .map(|&(a, b, d, _)| Rectangle::new([(a, floor), (b, d)], edge)),
            )?;
        }
        let centres: Vec<(f64, f64, f64)> = bars
            .iter()
            .map(|&(a, b, d, e)| (0.5 * (a + b), d, e))
            .collect();
        draw_error_bars(chart, &centres, RGBColor(64, 64, 64), floor, m)?;
        for (k, s) in self.theories.iter().enumerate() {
            let colour = s.colour.unwrap_or_else(|| palette(k + 1));
            let pts: Vec<(f64, f64)> =
                s.x.iter()
                    .zip(&s.y)
                    .map(|(&x, &y)| (x, y))
                    .filter(|&(x, y)| x.is_finite() && y.is_finite() && (!self.log_y || y > 0.0))
                    .collect();
            let w = m.line + 1;
            let dash = match k % 3 {
                0 => None,
                1 => Some((6 * w, 4 * w)),
                _ => Some((2 * w, 3 * w)),
            };
            draw_line(chart, &pts, colour, w, dash, &s.name, m)?;
        }
        draw_notes(chart, &self.notes)
    }

    fn points(&self) -> Vec<(f64, f64)> {
        let mut pts = Vec::new();
        for (a, b, d, e) in self.bars() {
            // Bars are filled down to the axis: a corner box over a bar's x range is covered
            // from the bottom, and from the top if the bar is tall.
            for x in [a, 0.5 * (a + b), b] {
                pts.push((x, d + e));
                if !self.log_y {
                    pts.push((x, 0.0));
                }
            }
        }
        for s in &self.theories {
            let xy: Vec<(f64, f64)> = s.x.iter().copied().zip(s.y.iter().copied()).collect();
            pts.extend(along(&xy, false, self.log_y));
        }
        pts
    }
}

impl Draw for HistogramPlot {
    fn size(&self) -> (u32, u32) {
        self.size
    }

    fn check(&self) -> Result<(), PlotError> {
        let k = self.densities.len();
        if k == 0 || self.edges.len() != k + 1 {
            return Err(PlotError::Data(format!(
                "a histogram needs k + 1 bin edges for k > 0 densities (got {} edges, {k} densities)",
                self.edges.len()
            )));
        }
        if self
            .edges
            .windows(2)
            .any(|w| !(w[0].is_finite() && w[1].is_finite() && w[0] < w[1]))
        {
            return Err(PlotError::Data(
                "histogram bin edges must be finite and increasing".into(),
            ));
        }
        if let Some(e) = &self.errors
            && e.len() != k
        {
            return Err(PlotError::Data(format!(
                "{} error bars for {k} bins",
                e.len()
            )));
        }
        for s in &self.theories {
            s.validate()?;
        }
        self.ranges().map(|_| ())
    }

    fn draw_on<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        _vector: bool,
    ) -> Result<(), PlotError> {
        self.check()?;
        let (x_range, y_range) = self.ranges()?;
        let names: Vec<&str> = std::iter::once(self.data_name.as_str())
            .chain(self.theories.iter().map(|s| s.name.as_str()))
            .chain(self.notes.iter().map(String::as_str))
            .filter(|n| !n.is_empty())
            .collect();
        let frame = Frame {
            title: &self.title,
            x_label: &self.x_label,
            y_label: &self.y_label,
            x_range,
            y_range,
            log_x: false,
            log_y: self.log_y,
            legend: self.legend,
            legend_extent: (
                names.iter().map(|n| n.chars().count()).max().unwrap_or(0),
                names.len(),
            ),
            y_fixed: false,
            metrics: Metrics::for_size(self.size),
        };
        draw_chart(area, &frame, self)
    }
}

/// The goodness-of-fit line printed on histograms: `χ² = 40.0, dof = 48, p = 0.787`.
/// A `p` that underflowed to 0 (`χ²` of thousands) is printed from the logarithm of the
/// survival function (`granular::stats::chi_square_log10_p`), e.g. `p = 3.2e-1234`.
pub fn fit_text(chi_square: f64, degrees_of_freedom: usize, p: f64) -> String {
    format!(
        "χ² = {chi_square:.1}, dof = {degrees_of_freedom}, p = {}",
        p_text(chi_square, degrees_of_freedom, p)
    )
}

/// `p` with three decimals, or in scientific notation below 1e-3; below the smallest
/// `f64` (where `p` is 0 or subnormal) mantissa and exponent come from `log10 p`.
fn p_text(chi_square: f64, degrees_of_freedom: usize, p: f64) -> String {
    if p >= 1e-3 {
        return format!("{p:.3}");
    }
    if p >= f64::MIN_POSITIVE {
        return format!("{p:.1e}");
    }
    let log10_p = granular::stats::chi_square_log10_p(chi_square, degrees_of_freedom);
    if !log10_p.is_finite() {
        return format!("{p:.1e}");
    }
    let mut exponent = log10_p.floor();
    let mut mantissa = 10f64.powf(log10_p - exponent);
    // 9.96 would print as "10.0".
    if mantissa >= 9.95 {
        mantissa = 1.0;
        exponent += 1.0;
    }
    format!("{mantissa:.1}e{exponent:.0}")
}

#[cfg(test)]
mod tests {
    use super::super::test_support::{decode_png, ink, temp_dir};
    use super::*;
    use granular::theory::equilibrium::speed_density;

    /// Deterministic 2D Maxwellian speeds (inverse-CDF of a quasi-random sequence).
    fn speeds(n: usize, mass: f64, temperature: f64) -> Vec<f64> {
        (0..n)
            .map(|i| {
                let u = ((i as f64 + 0.5) * 0.618_033_988_749_895).fract();
                (-2.0 * temperature / mass * (1.0 - u).ln()).sqrt()
            })
            .collect()
    }

    /// Ordinary p-values keep their format; one that underflows (Fig. 8's χ² against the
    /// fitted Gaussian) is printed from its logarithm instead of as "0.0e0". For 2 degrees
    /// of freedom `p = exp(-χ²/2)` exactly: χ² = 5000 gives `log10 p = -1085.74`, i.e.
    /// `1.8e-1086`.
    #[test]
    fn fit_text_prints_an_underflowed_p_value() {
        assert_eq!(fit_text(40.04, 48, 0.787), "χ² = 40.0, dof = 48, p = 0.787");
        assert_eq!(
            fit_text(80.0, 48, 2.5e-4),
            "χ² = 80.0, dof = 48, p = 2.5e-4"
        );
        let p = (-2500f64).exp();
        assert_eq!(p, 0.0);
        let text = fit_text(5000.0, 2, p);
        assert_eq!(text, "χ² = 5000.0, dof = 2, p = 1.8e-1086");
        assert!(!text.contains("0.0e0"), "{text}");
        assert_eq!(p_text(f64::INFINITY, 3, 0.0), "0.0e0");
    }

    #[test]
    fn histogram_from_samples_is_normalised() {
        let h = HistogramPlot::from_samples("", &speeds(10_000, 1.0, 1.0), 30, None);
        let total: f64 = h
            .densities
            .iter()
            .zip(h.edges.windows(2))
            .map(|(d, w)| d * (w[1] - w[0]))
            .sum();
        assert!((total - 1.0).abs() < 1e-12);
    }

    #[test]
    fn writes_png_and_svg_with_theory() {
        let dir = temp_dir("histogram");
        let plot =
            HistogramPlot::from_samples("Speed distribution", &speeds(20_000, 1.0, 1.0), 40, None)
                .data_label("EDMD, N = 20000")
                .x_label("speed v [L/τ]")
                .y_label("probability density p(v) [τ/L]")
                .theory("Maxwell–Boltzmann, T = 1", |v| {
                    speed_density(2, v, 1.0, 1.0)
                })
                .theory("Maxwell–Boltzmann, T = 1.3", |v| {
                    speed_density(2, v, 1.0, 1.3)
                });
        let [png, svg] = plot.save_png_and_svg(dir.join("speeds")).expect("save");
        let (w, h, pixels) = decode_png(&png);
        assert_eq!((w, h), (1000, 750));
        assert!(ink(&pixels) > 20_000);
        let text = std::fs::read_to_string(svg).expect("svg");
        assert!(text.contains("speed v [L/τ]") && text.contains("Maxwell–Boltzmann, T = 1"));
        plot.clone()
            .log_y(true)
            .save(dir.join("speeds_log.png"))
            .expect("log");
        assert!(
            HistogramPlot::new("", vec![0.0, 1.0], vec![1.0, 2.0])
                .save(dir.join("bad.png"))
                .is_err()
        );
    }
}
