//! The common frame of x-y charts: title, labelled axes (linear or logarithmic), a light
//! grid, and a legend placed where it covers the fewest data points.

use plotters::coord::Shift;
use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint, Ranged, ValueFormatter};
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use super::{Metrics, PlotError, font, format_log_tick, format_tick, format_tick_at};

/// Where the legend goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum LegendPosition {
    /// The corner of the plot that covers the fewest data points.
    #[default]
    Auto,
    /// Upper left corner.
    UpperLeft,
    /// Upper right corner.
    UpperRight,
    /// Lower left corner.
    LowerLeft,
    /// Lower right corner.
    LowerRight,
    /// No legend.
    None,
}

/// A logarithmic axis whose ticks are the decades, with 2 and 5 times them (and 3 on a range
/// of about a decade) when it spans fewer than three decades: plotters' own log axis puts
/// a single tick, or none, on such a range.
pub(crate) struct LogAxis(LogCoord<f64>);

impl Ranged for LogAxis {
    type FormatOption = DefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        self.0.map(value, limit)
    }

    fn key_points<H: KeyPointHint>(&self, hint: H) -> Vec<f64> {
        let r = self.0.range();
        let (a, b) = (r.start.min(r.end), r.start.max(r.end));
        let decades = (b / a).log10();
        if !(a > 0.0 && decades.is_finite()) || decades >= 3.0 {
            return self.0.key_points(hint);
        }
        let multiples: &[f64] = if decades < 1.3 {
            &[1.0, 2.0, 3.0, 5.0]
        } else {
            &[1.0, 2.0, 5.0]
        };
        let mut ticks = Vec::new();
        for e in (a.log10().floor() as i32)..=(b.log10().ceil() as i32) {
            for m in multiples {
                let v = m * 10f64.powi(e);
                if v >= a * (1.0 - 1e-12) && v <= b * (1.0 + 1e-12) {
                    ticks.push(v);
                }
            }
        }
        ticks
    }

    fn range(&self) -> std::ops::Range<f64> {
        self.0.range()
    }
}

/// Axes, titles and legend placement for one chart.
pub(crate) struct Frame<'a> {
    pub title: &'a str,
    pub x_label: &'a str,
    pub y_label: &'a str,
    pub x_range: (f64, f64),
    pub y_range: (f64, f64),
    pub log_x: bool,
    pub log_y: bool,
    pub legend: LegendPosition,
    /// Longest legend entry in characters and number of entries (for auto placement).
    pub legend_extent: (usize, usize),
    /// The y range was fixed by the caller: no headroom is added for the legend.
    pub y_fixed: bool,
    pub metrics: Metrics,
}

/// What is drawn inside the frame.
pub(crate) trait ChartBody {
    /// Draws the data; series given a label appear in the legend.
    fn draw_body<'a, DB, X, Y>(
        &self,
        chart: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
        metrics: &Metrics,
    ) -> Result<(), PlotError>
    where
        DB: DrawingBackend + 'a,
        X: Ranged<ValueType = f64>,
        Y: Ranged<ValueType = f64>;

    /// All plotted points, for legend placement.
    fn points(&self) -> Vec<(f64, f64)>;
}

/// Draws `body` inside `frame` on `area`.
pub(crate) fn draw_chart<DB: DrawingBackend, B: ChartBody>(
    area: &DrawingArea<DB, Shift>,
    frame: &Frame<'_>,
    body: &B,
) -> Result<(), PlotError> {
    let (x0, x1) = frame.x_range;
    let (y0, y1) = legend_headroom(frame, area, &body.points());
    let frame = &Frame {
        y_range: (y0, y1),
        ..*frame
    };
    match (frame.log_x, frame.log_y) {
        (false, false) => draw_in(
            area,
            frame,
            body,
            RangedCoordf64::from(x0..x1),
            RangedCoordf64::from(y0..y1),
        ),
        (true, false) => draw_in(
            area,
            frame,
            body,
            LogAxis(LogCoord::from((x0..x1).log_scale())),
            RangedCoordf64::from(y0..y1),
        ),
        (false, true) => draw_in(
            area,
            frame,
            body,
            RangedCoordf64::from(x0..x1),
            LogAxis(LogCoord::from((y0..y1).log_scale())),
        ),
        (true, true) => draw_in(
            area,
            frame,
            body,
            LogAxis(LogCoord::from((x0..x1).log_scale())),
            LogAxis(LogCoord::from((y0..y1).log_scale())),
        ),
    }
}

fn draw_in<DB, X, Y, B>(
    area: &DrawingArea<DB, Shift>,
    frame: &Frame<'_>,
    body: &B,
    x: X,
    y: Y,
) -> Result<(), PlotError>
where
    DB: DrawingBackend,
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
    B: ChartBody,
{
    let m = &frame.metrics;
    let mut builder = ChartBuilder::on(area);
    builder
        .margin(m.margin)
        .margin_right(m.margin * 2)
        .x_label_area_size(m.tick * 1.3 + m.label * 1.9)
        .y_label_area_size(m.tick * 3.4 + m.label * 1.6);
    if !frame.title.is_empty() {
        builder.caption(frame.title, font(title_size(frame.title, area, m)));
    }
    let mut chart = builder.build_cartesian_2d(x, y)?;
    // Powers of ten on a log axis of three decades or more; plain numbers on a shorter one,
    // whose ticks are 1, 2 and 5 times the decades (`LogAxis`). A linear axis has at most 7
    // labels, so its ticks are at least a seventh of the range apart: labels within a
    // twentieth of their values are all different.
    let tick = |log: bool, (a, b): (f64, f64)| {
        let powers = log && (b / a).log10().abs() >= 3.0;
        let resolution = if log { f64::NAN } else { (b - a).abs() / 10.0 };
        move |v: &f64| {
            if powers {
                format_log_tick(*v)
            } else if log {
                format_tick(*v)
            } else {
                format_tick_at(*v, resolution)
            }
        }
    };
    let (x_fmt, y_fmt) = (
        tick(frame.log_x, frame.x_range),
        tick(frame.log_y, frame.y_range),
    );
    chart
        .configure_mesh()
        .x_desc(frame.x_label)
        .y_desc(frame.y_label)
        .axis_desc_style(font(m.label))
        .label_style(font(m.tick))
        .x_label_formatter(&x_fmt)
        .y_label_formatter(&y_fmt)
        .x_labels(7)
        .y_labels(7)
        .bold_line_style(BLACK.mix(0.12))
        .light_line_style(TRANSPARENT)
        .axis_style(BLACK.stroke_width(m.line.max(2) - 1))
        .set_all_tick_mark_size(m.marker)
        .draw()?;
    body.draw_body(&mut chart, m)?;
    // A closed frame around the plot area.
    let (xr, yr) = (chart.x_range(), chart.y_range());
    chart.draw_series(std::iter::once(Rectangle::new(
        [(xr.start, yr.start), (xr.end, yr.end)],
        BLACK.stroke_width(m.line.max(2) - 1),
    )))?;
    let position = match frame.legend {
        LegendPosition::None => None,
        LegendPosition::UpperLeft => Some(SeriesLabelPosition::UpperLeft),
        LegendPosition::UpperRight => Some(SeriesLabelPosition::UpperRight),
        LegendPosition::LowerLeft => Some(SeriesLabelPosition::LowerLeft),
        LegendPosition::LowerRight => Some(SeriesLabelPosition::LowerRight),
        LegendPosition::Auto => Some(auto_legend_position(frame, &body.points(), area).0),
    };
    if let Some(position) = position
        && frame.legend_extent.1 > 0
    {
        chart
            .configure_series_labels()
            .position(position)
            .margin(m.margin / 2)
            .legend_area_size((m.legend * 2.2) as u32)
            .label_font(font(m.legend))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK.mix(0.6))
            .draw()?;
    }
    Ok(())
}

/// The title's font size: the figure's, shrunk so that the title fits the width.
fn title_size<DB: DrawingBackend>(title: &str, area: &DrawingArea<DB, Shift>, m: &Metrics) -> f64 {
    let width = f64::from(area.dim_in_pixel().0) - 2.0 * f64::from(m.margin);
    // DejaVu Sans averages about 0.56 em per character; 0.62 leaves a margin.
    let fits = width / (0.62 * title.chars().count().max(1) as f64);
    m.title.min(fits).max(0.45 * m.title)
}

/// The legend box as fractions of the plot area (width, height).
fn legend_box<DB: DrawingBackend>(frame: &Frame<'_>, area: &DrawingArea<DB, Shift>) -> (f64, f64) {
    let (w, h) = area.dim_in_pixel();
    let m = &frame.metrics;
    // Rough plot-area size and legend-box size in pixels (generous, so that the legend
    // never ends up on data).
    let plot_w = (f64::from(w) - m.tick * 3.4 - m.label * 1.6 - 3.0 * f64::from(m.margin)).max(1.0);
    let plot_h = (f64::from(h) - m.title * 1.5 - m.tick * 1.3 - m.label * 1.9).max(1.0);
    let (chars, entries) = frame.legend_extent;
    let box_w = ((chars as f64 * 0.62 * m.legend + m.legend * 4.0) / plot_w).min(1.0);
    let box_h = ((entries as f64 * m.legend * 1.45 + m.legend * 1.2) / plot_h).min(1.0);
    (box_w, box_h)
}

/// The y range, raised at the top so that an automatically placed legend covers no data
/// when every corner of the original range holds some (not for a fixed range).
fn legend_headroom<DB: DrawingBackend>(
    frame: &Frame<'_>,
    area: &DrawingArea<DB, Shift>,
    points: &[(f64, f64)],
) -> (f64, f64) {
    let (lo, hi) = frame.y_range;
    if frame.legend != LegendPosition::Auto || frame.y_fixed || frame.legend_extent.1 == 0 {
        return (lo, hi);
    }
    if auto_legend_position(frame, points, area).1 == 0 {
        return (lo, hi);
    }
    let (_, box_h) = legend_box(frame, area);
    if box_h > 0.6 {
        return (lo, hi);
    }
    // The data keep the lower `1 - box_h - 3 %` of the plot.
    let keep = 1.0 - box_h - 0.03;
    if frame.log_y {
        let (a, b) = (lo.ln(), hi.ln());
        (lo, (a + (b - a) / keep).exp())
    } else {
        (lo, lo + (hi - lo) / keep)
    }
}

/// The corner whose legend box would cover the fewest points (ties: upper right first),
/// and how many it covers.
fn auto_legend_position<DB: DrawingBackend>(
    frame: &Frame<'_>,
    points: &[(f64, f64)],
    area: &DrawingArea<DB, Shift>,
) -> (SeriesLabelPosition, usize) {
    let (box_w, box_h) = legend_box(frame, area);
    let unit = |v: f64, (a, b): (f64, f64), log: bool| {
        if log {
            (v.ln() - a.ln()) / (b.ln() - a.ln())
        } else {
            (v - a) / (b - a)
        }
    };
    let normalised: Vec<(f64, f64)> = points
        .iter()
        .map(|&(x, y)| {
            (
                unit(x, frame.x_range, frame.log_x),
                unit(y, frame.y_range, frame.log_y),
            )
        })
        .filter(|(u, v)| u.is_finite() && v.is_finite())
        .collect();
    let count = |left: bool, top: bool| {
        normalised
            .iter()
            .filter(|&&(u, v)| {
                let in_x = if left { u <= box_w } else { u >= 1.0 - box_w };
                let in_y = if top { v >= 1.0 - box_h } else { v <= box_h };
                in_x && in_y
            })
            .count()
    };
    let candidates = [
        (SeriesLabelPosition::UpperRight, count(false, true)),
        (SeriesLabelPosition::UpperLeft, count(true, true)),
        (SeriesLabelPosition::LowerRight, count(false, false)),
        (SeriesLabelPosition::LowerLeft, count(true, false)),
    ];
    candidates
        .iter()
        .min_by_key(|(_, n)| *n)
        .cloned()
        .unwrap_or((SeriesLabelPosition::UpperRight, 0))
}

/// Points along a polyline (each segment cut into eight, geometrically on a log axis), so
/// that legend placement sees lines, not only their vertices.
pub(crate) fn along(points: &[(f64, f64)], log_x: bool, log_y: bool) -> Vec<(f64, f64)> {
    let mix = |a: f64, b: f64, t: f64, log: bool| {
        if log && a > 0.0 && b > 0.0 {
            (a.ln() + t * (b.ln() - a.ln())).exp()
        } else {
            a + t * (b - a)
        }
    };
    let mut out: Vec<(f64, f64)> = points.first().copied().into_iter().collect();
    for w in points.windows(2) {
        for k in 1..=8 {
            let t = f64::from(k) / 8.0;
            out.push((mix(w[0].0, w[1].0, t, log_x), mix(w[0].1, w[1].1, t, log_y)));
        }
    }
    out
}

/// The x and y ranges of a chart.
pub(crate) type Ranges = ((f64, f64), (f64, f64));

/// A padded axis range covering `values` (positive values only for a log axis).
pub(crate) fn padded_range(
    values: impl IntoIterator<Item = f64>,
    log: bool,
    pad: f64,
) -> Result<(f64, f64), PlotError> {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values {
        if v.is_finite() && (!log || v > 0.0) {
            lo = lo.min(v);
            hi = hi.max(v);
        }
    }
    if !lo.is_finite() {
        return Err(PlotError::Data(if log {
            "no positive finite values for a logarithmic axis".into()
        } else {
            "no finite values to plot".into()
        }));
    }
    if log {
        let (a, b) = (lo.log10(), hi.log10());
        let span = (b - a).max(0.5);
        let mid = 0.5 * (a + b);
        let (a, b) = (mid.min(a) - span * pad, mid.max(b) + span * pad);
        let (a, b) = if b - a < 1.0 {
            (mid - 0.5, mid + 0.5)
        } else {
            (a, b)
        };
        Ok((10f64.powf(a), 10f64.powf(b)))
    } else {
        let span = hi - lo;
        // A quantity constant to round-off (a spread below 10⁻⁹ of its size) is drawn on a
        // fixed range of ±20 % around it, not zoomed onto the noise of its last digits.
        let span = if span > 1e-9 * lo.abs().max(hi.abs()) {
            span
        } else if lo != 0.0 {
            lo.abs() * 0.2
        } else {
            1.0
        };
        Ok((lo - span * pad, hi + span * pad))
    }
}
