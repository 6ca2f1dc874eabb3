//! [`HeatMaps`]: panels of scalar fields on regular grids (e.g. density maps), side by side
//! on one shared *viridis* colour scale, with a colour bar.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::colour::viridis;
use super::{Draw, Metrics, PlotError, font, format_tick, save_both, save_figure};

/// One panel: a field of `nx x ny` values, `x` (axis 0) fastest, row `y = 0` at the bottom.
#[derive(Clone, Debug)]
pub struct HeatPanel {
    /// Panel title.
    pub title: String,
    /// Bins along x.
    pub nx: usize,
    /// Bins along y.
    pub ny: usize,
    /// `nx * ny` values, x fastest.
    pub values: Vec<f64>,
}

/// Several heat maps in a grid of `columns` panels per row, sharing the colour range.
///
/// ```no_run
/// # use granular_report::plot::{HeatMaps, HeatPanel};
/// # fn demo(values: Vec<f64>) -> Result<(), granular_report::plot::PlotError> {
/// HeatMaps::new("Density / mean density", 2)
///     .panel(HeatPanel { title: "EDMD t = 1".into(), nx: 64, ny: 64, values })
///     .save("density.png")?;
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug)]
pub struct HeatMaps {
    title: String,
    columns: usize,
    range: Option<(f64, f64)>,
    panels: Vec<HeatPanel>,
    panel_size: u32,
    log: bool,
}

impl HeatMaps {
    /// An empty figure with a title (shown above the colour bar), `columns` panels per row.
    pub fn new(title: impl Into<String>, columns: usize) -> Self {
        Self {
            title: title.into(),
            columns: columns.max(1),
            range: None,
            panels: Vec::new(),
            panel_size: 420,
            log: false,
        }
    }

    /// A logarithmic colour scale (base 10), so that a few very dense cells do not flatten
    /// the rest; values `<= 0` take the bottom colour. The default range then runs from the
    /// smallest positive value to the largest.
    pub fn log_scale(mut self, log: bool) -> Self {
        self.log = log;
        self
    }

    /// Adds a panel.
    pub fn panel(mut self, panel: HeatPanel) -> Self {
        self.panels.push(panel);
        self
    }

    /// Fixes the colour range (default: minimum and maximum over all panels).
    pub fn range(mut self, min: f64, max: f64) -> Self {
        self.range = Some((min, max));
        self
    }

    /// Writes the figure as PNG or SVG, by the extension of `path`.
    ///
    /// # Errors
    /// As [`super::LinePlot::save`].
    pub fn save(&self, path: impl AsRef<Path>) -> Result<(), PlotError> {
        save_figure(self, path.as_ref())
    }

    /// Writes `stem.png` and `stem.svg`; returns their paths.
    ///
    /// # Errors
    /// As [`HeatMaps::save`].
    pub fn save_png_and_svg(&self, stem: impl AsRef<Path>) -> Result<[PathBuf; 2], PlotError> {
        save_both(self, stem.as_ref())
    }

    fn rows(&self) -> usize {
        self.panels.len().div_ceil(self.columns).max(1)
    }

    fn colour_range(&self) -> (f64, f64) {
        if let Some(r) = self.range {
            return r;
        }
        let values = self
            .panels
            .iter()
            .flat_map(|p| &p.values)
            .filter(|v| v.is_finite() && (!self.log || **v > 0.0));
        let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
        if lo < hi {
            (lo, hi)
        } else if self.log && lo > 0.0 && lo.is_finite() {
            (lo / 2.0, lo * 2.0)
        } else if self.log {
            (0.1, 10.0)
        } else {
            (lo - 0.5, lo + 0.5)
        }
    }

    /// Position of `v` on the colour scale, 0 at `lo` and 1 at `hi`.
    fn unit(&self, v: f64, (lo, hi): (f64, f64)) -> f64 {
        if self.log {
            if v > 0.0 {
                (v.ln() - lo.ln()) / (hi.ln() - lo.ln())
            } else {
                0.0
            }
        } else {
            (v - lo) / (hi - lo)
        }
    }

    /// Tick values on the colour bar: decades (with 2 and 5 when fewer than three) on a log
    /// scale, about five round numbers on a linear one.
    fn ticks(&self, (lo, hi): (f64, f64)) -> Vec<f64> {
        let inside = |v: &f64| *v >= lo * (1.0 - 1e-9) && *v <= hi * (1.0 + 1e-9);
        if self.log {
            let (a, b) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
            let decades: Vec<f64> = (a..=b).map(|e| 10f64.powi(e)).filter(inside).collect();
            if decades.len() >= 3 {
                return decades;
            }
            (a..=b)
                .flat_map(|e| [1.0, 2.0, 5.0].map(|m| m * 10f64.powi(e)))
                .filter(inside)
                .collect()
        } else {
            let raw = (hi - lo) / 5.0;
            let magnitude = 10f64.powf(raw.log10().floor());
            let step = [1.0, 2.0, 5.0, 10.0]
                .iter()
                .map(|m| m * magnitude)
                .find(|s| *s >= raw)
                .unwrap_or(raw);
            let first = (lo / step).ceil() as i64;
            let last = (hi / step).floor() as i64;
            (first..=last).map(|i| i as f64 * step).collect()
        }
    }
}

impl Draw for HeatMaps {
    fn size(&self) -> (u32, u32) {
        let cols = self.columns.min(self.panels.len().max(1)) as u32;
        // Panels plus a strip for the colour bar and its title.
        (
            self.panel_size * cols,
            self.panel_size * self.rows() as u32 + 110,
        )
    }

    fn check(&self) -> Result<(), PlotError> {
        if self.panels.is_empty() {
            return Err(PlotError::Data(
                "a heat-map figure needs at least one panel".into(),
            ));
        }
        for p in &self.panels {
            if p.nx == 0 || p.ny == 0 || p.values.len() != p.nx * p.ny {
                return Err(PlotError::Data(format!(
                    "panel `{}`: {} values for a {} x {} grid",
                    p.title,
                    p.values.len(),
                    p.nx,
                    p.ny
                )));
            }
        }
        Ok(())
    }

    fn draw_on<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        _vector: bool,
    ) -> Result<(), PlotError> {
        let m = Metrics::for_size((self.panel_size, self.panel_size));
        // Text sizes in pixels, readable at the panel size (not scaled down with it).
        let (title_px, tick_px) = (22.0, 20.0);
        let (w, h) = area.dim_in_pixel();
        let (grid, bar) = area.split_vertically(h - 110);
        let (lo, hi) = self.colour_range();
        let cols = self.columns.min(self.panels.len());
        let cells = grid.split_evenly((self.rows(), cols));
        for (p, cell) in self.panels.iter().zip(&cells) {
            let (cw, ch) = cell.dim_in_pixel();
            let title_h = (title_px * 1.6) as u32;
            let cell = cell.titled(&p.title, font(title_px))?;
            let side = (cw.min(ch.saturating_sub(title_h)) as i32 - 2 * m.margin as i32).max(10);
            let x0 = (cw as i32 - side) / 2;
            let y0 = m.margin as i32 / 2;
            let dx = side as f64 / p.nx as f64;
            let dy = side as f64 / p.ny as f64;
            for iy in 0..p.ny {
                for ix in 0..p.nx {
                    let v = p.values[iy * p.nx + ix];
                    let c = viridis(self.unit(v, (lo, hi)));
                    // Row iy = 0 at the bottom (y axis up).
                    let top = y0 + (side as f64 - (iy + 1) as f64 * dy).round() as i32;
                    let bottom = y0 + (side as f64 - iy as f64 * dy).round() as i32;
                    let left = x0 + (ix as f64 * dx).round() as i32;
                    let right = x0 + ((ix + 1) as f64 * dx).round() as i32;
                    cell.draw(&Rectangle::new([(left, top), (right, bottom)], c.filled()))?;
                }
            }
            cell.draw(&Rectangle::new(
                [(x0, y0), (x0 + side, y0 + side)],
                BLACK.stroke_width(1),
            ))?;
        }
        // Colour bar: 60 % of the width, centred, with end labels and the title.
        let bar_w = (w as f64 * 0.6) as i32;
        let bx = (w as i32 - bar_w) / 2;
        let (by, bh) = (14, 22);
        let steps = 200;
        for i in 0..steps {
            let l = bx + (i * bar_w) / steps;
            let r = bx + ((i + 1) * bar_w) / steps;
            let c = viridis((i as f64 + 0.5) / steps as f64);
            bar.draw(&Rectangle::new([(l, by), (r, by + bh)], c.filled()))?;
        }
        bar.draw(&Rectangle::new(
            [(bx, by), (bx + bar_w, by + bh)],
            BLACK.stroke_width(1),
        ))?;
        // Ticks below the bar, labelled; the title under them.
        let f = font(tick_px).pos(Pos::new(HPos::Center, VPos::Top));
        for t in self.ticks((lo, hi)) {
            let x = bx + (self.unit(t, (lo, hi)) * f64::from(bar_w)).round() as i32;
            bar.draw(&PathElement::new(
                vec![(x, by + bh), (x, by + bh + 6)],
                BLACK.stroke_width(1),
            ))?;
            let label = format_tick(t);
            bar.draw(&Text::new(label, (x, by + bh + 8), f.clone()))?;
        }
        let scale = if self.log { " (logarithmic scale)" } else { "" };
        bar.draw(&Text::new(
            format!("{}{scale}", self.title),
            (w as i32 / 2, by + bh + 8 + (tick_px * 1.4) as i32),
            font(title_px).pos(Pos::new(HPos::Center, VPos::Top)),
        ))?;
        Ok(())
    }
}
