//! The common frame of x-y charts: title, labelled axes (linear or logarithmic), a light
//! grid, and a legend placed where it covers the fewest data points.

use plotters::coord::Shift;
use plotters::coord::ranged1d::{Ranged, ValueFormatter};
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use super::{Metrics, PlotError, font, format_log_tick, format_tick};

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
    let (y0, y1) = frame.y_range;
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
            LogCoord::from((x0..x1).log_scale()),
            RangedCoordf64::from(y0..y1),
        ),
        (false, true) => draw_in(
            area,
            frame,
            body,
            RangedCoordf64::from(x0..x1),
            LogCoord::from((y0..y1).log_scale()),
        ),
        (true, true) => draw_in(
            area,
            frame,
            body,
            LogCoord::from((x0..x1).log_scale()),
            LogCoord::from((y0..y1).log_scale()),
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
        builder.caption(frame.title, font(m.title));
    }
    let mut chart = builder.build_cartesian_2d(x, y)?;
    let tick = |log: bool| {
        move |v: &f64| {
            if log {
                format_log_tick(*v)
            } else {
                format_tick(*v)
            }
        }
    };
    let (x_fmt, y_fmt) = (tick(frame.log_x), tick(frame.log_y));
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
        LegendPosition::Auto => Some(auto_legend_position(frame, &body.points(), area)),
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

/// The corner whose legend box would cover the fewest points (ties: upper right first).
fn auto_legend_position<DB: DrawingBackend>(
    frame: &Frame<'_>,
    points: &[(f64, f64)],
    area: &DrawingArea<DB, Shift>,
) -> SeriesLabelPosition {
    let (w, h) = area.dim_in_pixel();
    let m = &frame.metrics;
    // Rough plot-area size and legend-box size in pixels.
    let plot_w = (f64::from(w) - m.tick * 3.4 - m.label * 1.6 - 3.0 * f64::from(m.margin)).max(1.0);
    let plot_h = (f64::from(h) - m.title * 1.5 - m.tick * 1.3 - m.label * 1.9).max(1.0);
    let (chars, entries) = frame.legend_extent;
    let box_w = ((chars as f64 * 0.6 * m.legend + m.legend * 3.5) / plot_w).min(1.0);
    let box_h = ((entries as f64 * m.legend * 1.3 + m.legend) / plot_h).min(1.0);
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
        .map(|(p, _)| p.clone())
        .unwrap_or(SeriesLabelPosition::UpperRight)
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
        let span = if span > 0.0 {
            span
        } else if lo != 0.0 {
            lo.abs() * 0.2
        } else {
            1.0
        };
        Ok((lo - span * pad, hi + span * pad))
    }
}
