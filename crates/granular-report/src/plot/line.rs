//! [`LinePlot`]: several named series, data as markers (with optional error bars) or lines,
//! theory curves as lines drawn over the data.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::coord::ranged1d::Ranged;
use plotters::element::DashedPathElement;
use plotters::prelude::*;

use super::chart::LegendPosition;
use super::chart::{ChartBody, Frame, Ranges, along, draw_chart, padded_range};
use super::colour::{Colour, palette};
use super::{DEFAULT_SIZE, Draw, Metrics, PlotError, save_both, save_figure};

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SeriesStyle {
    /// Data points as markers (shape cycles with the series).
    Markers,
    /// Data joined by a solid line.
    Line,
    /// Data as markers joined by a thin line.
    LineMarkers,
    /// A theory curve: a line (dash pattern cycles) drawn on top of the data.
    Theory,
}

/// One named series of `(x, y)` values with optional symmetric `y` error bars.
#[derive(Clone, Debug)]
pub struct Series {
    /// Legend entry; empty for no legend entry.
    pub name: String,
    /// Abscissae.
    pub x: Vec<f64>,
    /// Ordinates, as many as `x`.
    pub y: Vec<f64>,
    /// Symmetric error bar half-widths on `y`, as many as `y`.
    pub y_err: Option<Vec<f64>>,
    /// Drawing style.
    pub style: SeriesStyle,
    /// Colour; `None` takes the next palette colour.
    pub colour: Option<Colour>,
    /// Theory curves: `Some(true)` dashed, `Some(false)` solid, `None` the cycling pattern.
    pub dashed: Option<bool>,
    /// Line and marker pattern of a data series (the second grouping of a figure whose
    /// colours mark the first): dash pattern `i` (0 solid) and marker shape `i`; `None`
    /// solid lines and markers by position.
    pub pattern: Option<usize>,
}

impl Series {
    fn new(name: impl Into<String>, x: Vec<f64>, y: Vec<f64>, style: SeriesStyle) -> Self {
        Self {
            name: name.into(),
            x,
            y,
            y_err: None,
            style,
            colour: None,
            dashed: None,
            pattern: None,
        }
    }

    /// Data drawn as markers.
    pub fn markers(name: impl Into<String>, x: Vec<f64>, y: Vec<f64>) -> Self {
        Self::new(name, x, y, SeriesStyle::Markers)
    }

    /// Data drawn as a solid line.
    pub fn line(name: impl Into<String>, x: Vec<f64>, y: Vec<f64>) -> Self {
        Self::new(name, x, y, SeriesStyle::Line)
    }

    /// Data drawn as markers joined by a line.
    pub fn line_markers(name: impl Into<String>, x: Vec<f64>, y: Vec<f64>) -> Self {
        Self::new(name, x, y, SeriesStyle::LineMarkers)
    }

    /// A theory curve (drawn as a line over the data).
    pub fn theory(name: impl Into<String>, x: Vec<f64>, y: Vec<f64>) -> Self {
        Self::new(name, x, y, SeriesStyle::Theory)
    }

    /// A theory curve `f` sampled at `samples` points over `[x0, x1]` (log-spaced if `log`).
    pub fn theory_fn(
        name: impl Into<String>,
        (x0, x1): (f64, f64),
        samples: usize,
        log: bool,
        f: impl Fn(f64) -> f64,
    ) -> Self {
        let x = sample_points(x0, x1, samples, log);
        let y = x.iter().map(|&v| f(v)).collect();
        Self::theory(name, x, y)
    }

    /// Sets the line and marker pattern (see [`Series::pattern`]).
    pub fn with_pattern(mut self, pattern: usize) -> Self {
        self.pattern = Some(pattern);
        self
    }

    /// Adds symmetric error bars.
    pub fn with_errors(mut self, y_err: Vec<f64>) -> Self {
        self.y_err = Some(y_err);
        self
    }

    /// Sets the colour.
    pub fn with_colour(mut self, colour: Colour) -> Self {
        self.colour = Some(colour);
        self
    }

    /// Draws a theory curve dashed (`true`) or solid (`false`) instead of the cycling
    /// dash pattern.
    pub fn dashed(mut self, dashed: bool) -> Self {
        self.dashed = Some(dashed);
        self
    }

    pub(crate) fn validate(&self) -> Result<(), PlotError> {
        if self.x.len() != self.y.len() {
            return Err(PlotError::Data(format!(
                "series `{}` has {} x values but {} y values",
                self.name,
                self.x.len(),
                self.y.len()
            )));
        }
        if let Some(e) = &self.y_err
            && e.len() != self.y.len()
        {
            return Err(PlotError::Data(format!(
                "series `{}` has {} error bars for {} points",
                self.name,
                e.len(),
                self.y.len()
            )));
        }
        Ok(())
    }

    /// Finite points (positive ones on log axes) with their error bar.
    fn usable(&self, log_x: bool, log_y: bool) -> Vec<(f64, f64, f64)> {
        (0..self.x.len())
            .map(|i| {
                let e = self.y_err.as_ref().map_or(0.0, |e| e[i]);
                (
                    self.x[i],
                    self.y[i],
                    if e.is_finite() { e.abs() } else { 0.0 },
                )
            })
            .filter(|&(x, y, _)| {
                x.is_finite() && y.is_finite() && (!log_x || x > 0.0) && (!log_y || y > 0.0)
            })
            .collect()
    }
}

/// `n` points from `a` to `b`, evenly or logarithmically spaced.
pub(crate) fn sample_points(a: f64, b: f64, n: usize, log: bool) -> Vec<f64> {
    let n = n.max(2);
    (0..n)
        .map(|i| {
            let t = i as f64 / (n - 1) as f64;
            if log && a > 0.0 && b > 0.0 {
                (a.ln() + t * (b.ln() - a.ln())).exp()
            } else {
                a + t * (b - a)
            }
        })
        .collect()
}

/// Marker shapes, cycled over data series so they differ in grey-scale print.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Marker {
    Circle,
    Square,
    TriangleUp,
    Diamond,
    TriangleDown,
}

impl Marker {
    pub(crate) fn nth(i: usize) -> Self {
        [
            Marker::Circle,
            Marker::Square,
            Marker::TriangleUp,
            Marker::Diamond,
            Marker::TriangleDown,
        ][i % 5]
    }

    /// Polygon vertices around the origin in pixels (`None`: a circle of radius `r`).
    pub(crate) fn vertices(self, r: i32) -> Option<Vec<(i32, i32)>> {
        let s = (f64::from(r) * 0.9).round() as i32;
        let t = (f64::from(r) * 1.2).round() as i32;
        match self {
            Marker::Circle => None,
            Marker::Square => Some(vec![(-s, -s), (s, -s), (s, s), (-s, s)]),
            Marker::TriangleUp => Some(vec![(0, -t), (t, t * 2 / 3), (-t, t * 2 / 3)]),
            Marker::TriangleDown => Some(vec![(0, t), (t, -t * 2 / 3), (-t, -t * 2 / 3)]),
            Marker::Diamond => Some(vec![(0, -t), (t, 0), (0, t), (-t, 0)]),
        }
    }
}

/// Dash pattern (dash, gap) in pixels for the `i`-th theory curve; `None` is solid.
pub(crate) fn dash(i: usize, m: &Metrics) -> Option<(u32, u32)> {
    let w = m.line.max(1);
    match i % 4 {
        0 => None,
        1 => Some((6 * w, 4 * w)),
        2 => Some((2 * w, 3 * w)),
        _ => Some((12 * w, 4 * w)),
    }
}

/// Draws `points` as markers; adds a legend entry if `label` is not empty.
pub(crate) fn draw_markers<'a, DB, X, Y>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    points: &[(f64, f64)],
    marker: Marker,
    colour: Colour,
    label: &str,
    m: &Metrics,
) -> Result<(), PlotError>
where
    DB: DrawingBackend + 'a,
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    let r = m.marker;
    let fill = colour.filled();
    let edge = BLACK.mix(0.7).stroke_width(1);
    let anno = match marker.vertices(r) {
        None => chart.draw_series(points.iter().map(|&p| {
            EmptyElement::at(p) + Circle::new((0, 0), r, fill) + Circle::new((0, 0), r, edge)
        }))?,
        Some(v) => chart.draw_series(points.iter().map(|&p| {
            let mut closed = v.clone();
            closed.push(v[0]);
            EmptyElement::at(p) + Polygon::new(v.clone(), fill) + PathElement::new(closed, edge)
        }))?,
    };
    if !label.is_empty() {
        // Legend entries cannot be composed elements for non-'static backends, so the
        // legend shows the filled marker shape alone.
        let half = (m.legend * 0.9) as i32;
        anno.label(label).legend(move |(x, y)| {
            let (cx, cy) = (x + half, y);
            match marker.vertices(r) {
                None => Circle::new((cx, cy), r, fill).into_dyn(),
                Some(v) => Polygon::new(
                    v.iter().map(|&(a, b)| (cx + a, cy + b)).collect::<Vec<_>>(),
                    fill,
                )
                .into_dyn(),
            }
        });
    }
    Ok(())
}

/// Draws a line (solid or dashed); adds a legend entry if `label` is not empty.
pub(crate) fn draw_line<'a, DB, X, Y>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    points: &[(f64, f64)],
    colour: Colour,
    width: u32,
    dash: Option<(u32, u32)>,
    label: &str,
    m: &Metrics,
) -> Result<(), PlotError>
where
    DB: DrawingBackend + 'a,
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    let style = colour.stroke_width(width);
    let anno = match dash {
        None => chart.draw_series(std::iter::once(PathElement::new(points.to_vec(), style)))?,
        Some((d, g)) => {
            chart.draw_series(DashedLineSeries::new(points.iter().copied(), d, g, style))?
        }
    };
    if !label.is_empty() {
        let len = (m.legend * 1.8) as i32;
        anno.label(label).legend(move |(x, y)| match dash {
            None => PathElement::new(vec![(x, y), (x + len, y)], style).into_dyn(),
            Some((d, g)) => {
                DashedPathElement::new(vec![(x, y), (x + len, y)], d, g, style).into_dyn()
            }
        });
    }
    Ok(())
}

/// Adds `notes` to the legend as lines of text without a symbol.
pub(crate) fn draw_notes<'a, DB, X, Y>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    notes: &[String],
) -> Result<(), PlotError>
where
    DB: DrawingBackend + 'a,
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    for note in notes {
        chart
            .draw_series(std::iter::empty::<PathElement<(f64, f64)>>())?
            .label(note.as_str())
            .legend(|(x, y)| PathElement::new(vec![(x, y)], TRANSPARENT));
    }
    Ok(())
}

/// Draws vertical error bars at `(x, y ± e)`, clipped below at `floor` (for log axes).
pub(crate) fn draw_error_bars<'a, DB, X, Y>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    points: &[(f64, f64, f64)],
    colour: Colour,
    floor: f64,
    m: &Metrics,
) -> Result<(), PlotError>
where
    DB: DrawingBackend + 'a,
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    let style = colour.stroke_width(m.line.max(2) - 1);
    let cap = m.marker;
    let bars: Vec<(f64, f64, f64)> = points
        .iter()
        .filter(|(_, _, e)| *e > 0.0)
        .map(|&(x, y, e)| (x, (y - e).max(floor), y + e))
        .collect();
    chart.draw_series(
        bars.iter()
            .map(|&(x, lo, hi)| PathElement::new(vec![(x, lo), (x, hi)], style)),
    )?;
    chart.draw_series(bars.iter().flat_map(|&(x, lo, hi)| {
        [lo, hi]
            .map(|y| EmptyElement::at((x, y)) + PathElement::new(vec![(-cap, 0), (cap, 0)], style))
    }))?;
    Ok(())
}

/// A line/marker plot of several named series.
///
/// ```no_run
/// # use granular_report::plot::{LinePlot, Series};
/// # fn demo(t: Vec<f64>, temp: Vec<f64>, err: Vec<f64>) -> Result<(), granular_report::plot::PlotError> {
/// LinePlot::new("Haff's law")
///     .x_label("time t [τ₀]").y_label("granular temperature T/T₀")
///     .log_x(true).log_y(true)
///     .series(Series::markers("EDMD, N = 1000", t, temp).with_errors(err))
///     .series(Series::theory_fn("T₀/(1+t/τ)²", (1e-2, 1e3), 200, true, |t| (1.0 + t).powi(-2)))
///     .save("haff.png")?;
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug)]
pub struct LinePlot {
    title: String,
    x_label: String,
    y_label: String,
    log_x: bool,
    log_y: bool,
    x_range: Option<(f64, f64)>,
    y_range: Option<(f64, f64)>,
    legend: LegendPosition,
    size: (u32, u32),
    series: Vec<Series>,
    notes: Vec<String>,
}

impl LinePlot {
    /// An empty plot with a title (may be empty), 1000 x 750 pixels.
    pub fn new(title: impl Into<String>) -> Self {
        Self {
            title: title.into(),
            x_label: String::new(),
            y_label: String::new(),
            log_x: false,
            log_y: false,
            x_range: None,
            y_range: None,
            legend: LegendPosition::Auto,
            size: DEFAULT_SIZE,
            series: Vec::new(),
            notes: Vec::new(),
        }
    }

    /// Adds a line of text to the legend box (e.g. a goodness of fit).
    pub fn note(mut self, text: impl Into<String>) -> Self {
        self.notes.push(text.into());
        self
    }

    /// The x-axis label, with units, e.g. `"time t [τ₀]"`.
    pub fn x_label(mut self, label: impl Into<String>) -> Self {
        self.x_label = label.into();
        self
    }

    /// The y-axis label, with units.
    pub fn y_label(mut self, label: impl Into<String>) -> Self {
        self.y_label = label.into();
        self
    }

    /// Logarithmic x axis (non-positive x values are left out).
    pub fn log_x(mut self, log: bool) -> Self {
        self.log_x = log;
        self
    }

    /// Logarithmic y axis (non-positive y values are left out).
    pub fn log_y(mut self, log: bool) -> Self {
        self.log_y = log;
        self
    }

    /// Fixes the x range (default: the data, padded).
    pub fn x_range(mut self, min: f64, max: f64) -> Self {
        self.x_range = Some((min, max));
        self
    }

    /// Fixes the y range (default: the data and error bars, padded).
    pub fn y_range(mut self, min: f64, max: f64) -> Self {
        self.y_range = Some((min, max));
        self
    }

    /// Where the legend goes (default: the emptiest corner).
    pub fn legend(mut self, position: LegendPosition) -> Self {
        self.legend = position;
        self
    }

    /// Figure size in pixels (fonts and lines scale with the height).
    pub fn size(mut self, width: u32, height: u32) -> Self {
        self.size = (width, height);
        self
    }

    /// Adds a series.
    pub fn series(mut self, series: Series) -> Self {
        self.series.push(series);
        self
    }

    /// Writes the plot as PNG or SVG, by the extension of `path`.
    ///
    /// # Errors
    /// [`PlotError::UnknownFormat`] for other extensions, [`PlotError::Data`] for unusable
    /// data, [`PlotError::Draw`] if the file cannot be written.
    pub fn save(&self, path: impl AsRef<Path>) -> Result<(), PlotError> {
        save_figure(self, path.as_ref())
    }

    /// Writes `stem.png` and `stem.svg`; returns their paths.
    ///
    /// # Errors
    /// As [`LinePlot::save`].
    pub fn save_png_and_svg(&self, stem: impl AsRef<Path>) -> Result<[PathBuf; 2], PlotError> {
        save_both(self, stem.as_ref())
    }

    fn ranges(&self) -> Result<Ranges, PlotError> {
        let points: Vec<(f64, f64, f64)> = self
            .series
            .iter()
            .flat_map(|s| s.usable(self.log_x, self.log_y))
            .collect();
        let x = match self.x_range {
            Some(r) => r,
            None => padded_range(points.iter().map(|p| p.0), self.log_x, 0.03)?,
        };
        let y = match self.y_range {
            Some(r) => r,
            None => padded_range(
                points
                    .iter()
                    .flat_map(|&(_, y, e)| [y - e, y + e])
                    .chain(points.iter().map(|p| p.1)),
                self.log_y,
                0.06,
            )?,
        };
        check_range(x, self.log_x, "x")?;
        check_range(y, self.log_y, "y")?;
        Ok((x, y))
    }
}

pub(crate) fn check_range((a, b): (f64, f64), log: bool, axis: &str) -> Result<(), PlotError> {
    if !(a.is_finite() && b.is_finite() && a < b) || (log && a <= 0.0) {
        return Err(PlotError::Data(format!(
            "invalid {axis} range {a}..{b}{}",
            if log { " for a logarithmic axis" } else { "" }
        )));
    }
    Ok(())
}

impl ChartBody for LinePlot {
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
        let mut data_index = 0;
        let mut theory_index = 0;
        let mut theories = Vec::new();
        // Data first, theory curves on top.
        for (i, s) in self.series.iter().enumerate() {
            let colour = s.colour.unwrap_or_else(|| palette(i));
            let pts = s.usable(self.log_x, self.log_y);
            let xy: Vec<(f64, f64)> = pts.iter().map(|&(x, y, _)| (x, y)).collect();
            match s.style {
                SeriesStyle::Theory => {
                    theories.push((s, colour, xy, theory_index));
                    theory_index += 1;
                    continue;
                }
                SeriesStyle::Line => {
                    draw_error_bars(chart, &pts, colour, floor, m)?;
                    let pattern = s.pattern.and_then(|p| dash(p, m));
                    draw_line(chart, &xy, colour, m.line, pattern, &s.name, m)?;
                }
                SeriesStyle::Markers | SeriesStyle::LineMarkers => {
                    let with_line = s.style == SeriesStyle::LineMarkers;
                    if with_line {
                        let pattern = s.pattern.and_then(|p| dash(p, m));
                        draw_line(chart, &xy, colour, m.line.max(2) - 1, pattern, "", m)?;
                    }
                    draw_error_bars(chart, &pts, colour, floor, m)?;
                    let marker = Marker::nth(s.pattern.unwrap_or(data_index));
                    draw_markers(chart, &xy, marker, colour, &s.name, m)?;
                }
            }
            data_index += 1;
        }
        for (s, colour, xy, k) in theories {
            let pattern = match s.dashed {
                Some(true) => dash(1, m),
                Some(false) => None,
                None => dash(k, m),
            };
            draw_line(chart, &xy, colour, m.line, pattern, &s.name, m)?;
        }
        draw_notes(chart, &self.notes)
    }

    fn points(&self) -> Vec<(f64, f64)> {
        let mut out = Vec::new();
        for s in &self.series {
            let xy: Vec<(f64, f64)> = s
                .usable(self.log_x, self.log_y)
                .into_iter()
                .map(|(x, y, _)| (x, y))
                .collect();
            if s.style == SeriesStyle::Markers {
                out.extend(xy);
            } else {
                out.extend(along(&xy, self.log_x, self.log_y));
            }
        }
        out
    }
}

impl Draw for LinePlot {
    fn size(&self) -> (u32, u32) {
        self.size
    }

    fn check(&self) -> Result<(), PlotError> {
        if self.series.is_empty() {
            return Err(PlotError::Data(
                "a line plot needs at least one series".into(),
            ));
        }
        for s in &self.series {
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
        let named: Vec<&str> = self
            .series
            .iter()
            .map(|s| s.name.as_str())
            .filter(|n| !n.is_empty())
            .chain(self.notes.iter().map(String::as_str))
            .collect();
        let frame = Frame {
            title: &self.title,
            x_label: &self.x_label,
            y_label: &self.y_label,
            x_range,
            y_range,
            log_x: self.log_x,
            log_y: self.log_y,
            legend: self.legend,
            legend_extent: (
                named.iter().map(|n| n.chars().count()).max().unwrap_or(0),
                named.len(),
            ),
            y_fixed: self.y_range.is_some(),
            metrics: Metrics::for_size(self.size),
        };
        draw_chart(area, &frame, self)
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_support::{decode_png, ink, temp_dir};
    use super::*;

    fn demo() -> LinePlot {
        let t: Vec<f64> = (0..30).map(|i| 0.05 * 1.3f64.powi(i)).collect();
        let temp: Vec<f64> = t
            .iter()
            .enumerate()
            .map(|(i, &t)| (1.0 + t / 2.0).powi(-2) * (1.0 + 0.03 * ((i % 5) as f64 - 2.0)))
            .collect();
        let err: Vec<f64> = temp.iter().map(|v| 0.05 * v).collect();
        LinePlot::new("Homogeneous cooling")
            .x_label("time t [τ₀]")
            .y_label("temperature T / T₀")
            .log_x(true)
            .log_y(true)
            .series(Series::markers("EDMD, N = 4096", t.clone(), temp.clone()).with_errors(err))
            .series(Series::line_markers(
                "DSMC",
                t.clone(),
                temp.iter().map(|v| v * 1.1).collect(),
            ))
            .series(Series::theory_fn(
                "Haff: (1 + t/τ)⁻²",
                (0.05, 1000.0),
                200,
                true,
                |t| (1.0 + t / 2.0).powi(-2),
            ))
            .series(Series::theory_fn("t⁻²", (1.0, 1000.0), 50, true, |t| {
                4.0 / (t * t)
            }))
    }

    #[test]
    fn png_has_requested_size_and_ink() {
        let dir = temp_dir("line_png");
        let path = dir.join("haff.png");
        demo().save(&path).expect("save png");
        let (w, h, pixels) = decode_png(&path);
        assert_eq!((w, h), (1000, 750));
        // White background, and a fair amount of drawing (text, markers, lines).
        assert_eq!(pixels[0], [255, 255, 255]);
        assert!(ink(&pixels) > 10_000, "too little drawn: {}", ink(&pixels));
        let small = dir.join("small.png");
        demo().size(400, 300).save(&small).expect("small");
        assert_eq!(decode_png(&small).0, 400);
    }

    #[test]
    fn svg_contains_labels_and_legend() {
        let dir = temp_dir("line_svg");
        let [png, svg] = demo()
            .save_png_and_svg(dir.join("haff"))
            .expect("save both");
        assert!(std::fs::metadata(&png).expect("png").len() > 1000);
        let text = std::fs::read_to_string(&svg).expect("svg");
        for needle in [
            "time t [τ₀]",
            "temperature T / T₀",
            "EDMD, N = 4096",
            "Homogeneous cooling",
        ] {
            assert!(text.contains(needle), "svg lacks {needle}");
        }
    }

    #[test]
    fn linear_axes_and_bad_input() {
        let dir = temp_dir("line_linear");
        LinePlot::new("")
            .x_label("x [m]")
            .y_label("y [m]")
            .series(Series::line("a", vec![0.0, 1.0, 2.0], vec![1.0, -1.0, 0.5]))
            .save(dir.join("linear.svg"))
            .expect("linear");
        let mismatched = LinePlot::new("").series(Series::markers("a", vec![1.0], vec![]));
        assert!(matches!(
            mismatched.save(dir.join("x.png")),
            Err(PlotError::Data(_))
        ));
        let no_positive =
            LinePlot::new("")
                .log_y(true)
                .series(Series::markers("a", vec![1.0], vec![-1.0]));
        assert!(no_positive.save(dir.join("y.png")).is_err());
        assert!(matches!(
            demo().save(dir.join("plot.pdf")),
            Err(PlotError::UnknownFormat(_))
        ));
        assert!(LinePlot::new("").save(dir.join("empty.png")).is_err());
        // Rejected data leave no file behind.
        assert!(!dir.join("x.png").exists() && !dir.join("empty.png").exists());
    }
}
