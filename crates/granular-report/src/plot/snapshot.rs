//! [`SnapshotPicture`]: the grains of a [`Snapshot`] drawn as true-size disks in data units
//! (not scatter markers, whose size is in pixels), with equal aspect ratio, the box outline
//! (walls solid, periodic faces dashed, periodic images drawn), and colours by species (with
//! a legend) or by speed (with a colour bar).

use std::path::{Path, PathBuf};

use granular::engine::Snapshot;
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;

use super::colour::{darken, palette, viridis};
use super::{Draw, Metrics, PlotError, font, format_tick, save_both, save_figure};

/// How grains are coloured.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ColourBy {
    /// A distinct palette colour per species, with a legend of species names.
    Species,
    /// Speed `|v|` on the *viridis* map from 0 to `max` (default: the fastest grain; fix it
    /// for animations so colours mean the same in every frame), with a colour bar.
    Speed {
        /// Speed mapped to the top of the colour bar.
        max: Option<f64>,
    },
}

/// Settings shared by [`SnapshotPicture`] and [`super::Animation`].
#[derive(Clone, Debug)]
pub struct PictureStyle {
    pub(crate) box_lengths: [f64; 2],
    pub(crate) periodic: [bool; 2],
    pub(crate) colour_by: ColourBy,
    pub(crate) title: String,
    pub(crate) show_time: bool,
    pub(crate) slab: Option<(f64, f64)>,
    pub(crate) x_label: String,
    pub(crate) y_label: String,
    pub(crate) speed_label: String,
    pub(crate) size: Option<(u32, u32)>,
}

impl PictureStyle {
    /// A picture of the box `[0, lx] x [0, ly]` (the x-y face of a 3D box), hard walls,
    /// coloured by species, 1000 pixels wide and as high as the box's aspect ratio needs.
    pub fn new(lx: f64, ly: f64) -> Self {
        Self {
            box_lengths: [lx, ly],
            periodic: [false, false],
            colour_by: ColourBy::Species,
            title: String::new(),
            show_time: true,
            slab: None,
            x_label: "x [L]".into(),
            y_label: "y [L]".into(),
            speed_label: "speed |v| [L/τ]".into(),
            size: None,
        }
    }

    /// A picture of the x-y face of a simulation box, with its periodic axes.
    pub fn from_box<const D: usize>(simulation_box: &granular::SimulationBox<D>) -> Self {
        let length = |k: usize| {
            if k < D {
                simulation_box.lengths[k]
            } else {
                1.0
            }
        };
        let periodic = |k: usize| k < D && simulation_box.is_periodic(k);
        Self::new(length(0), length(1)).periodic(periodic(0), periodic(1))
    }

    /// Which of the x and y faces are periodic (drawn dashed; grains crossing them are
    /// drawn on both sides).
    pub fn periodic(mut self, x: bool, y: bool) -> Self {
        self.periodic = [x, y];
        self
    }

    /// How grains are coloured.
    pub fn colour_by(mut self, colour_by: ColourBy) -> Self {
        self.colour_by = colour_by;
        self
    }

    /// Title; the snapshot time is appended unless [`PictureStyle::show_time`] is off.
    pub fn title(mut self, title: impl Into<String>) -> Self {
        self.title = title.into();
        self
    }

    /// Whether `t = …` is printed in the title line (default on).
    pub fn show_time(mut self, show: bool) -> Self {
        self.show_time = show;
        self
    }

    /// For 3D snapshots: draw only grains whose centre has `z0 <= z < z1` (default: all,
    /// projected onto the x-y plane, nearer grains (larger z) on top).
    pub fn slab(mut self, z0: f64, z1: f64) -> Self {
        self.slab = Some((z0, z1));
        self
    }

    /// Axis labels with units (default `x [L]`, `y [L]`) and the colour-bar label.
    pub fn labels(
        mut self,
        x: impl Into<String>,
        y: impl Into<String>,
        speed: impl Into<String>,
    ) -> Self {
        self.x_label = x.into();
        self.y_label = y.into();
        self.speed_label = speed.into();
        self
    }

    /// Figure size in pixels; the box keeps its aspect ratio inside it (centred).
    pub fn size(mut self, width: u32, height: u32) -> Self {
        self.size = Some((width, height));
        self
    }

    /// Font sizes and lines: those of a 4:3 figure of the same width.
    pub(crate) fn metrics(&self) -> Metrics {
        let w = self.size.map_or(1000, |s| s.0);
        let h = self.size.map_or(750, |s| s.1.max(w * 3 / 4));
        Metrics::for_size((w, h))
    }

    /// The figure size: the one set, or 1000 pixels wide and as high as the box needs.
    pub(crate) fn figure_size(&self, panel_w: u32) -> (u32, u32) {
        if let Some(size) = self.size {
            return size;
        }
        let m = self.metrics();
        let w = 1000u32;
        let [lx, ly] = self.box_lengths;
        let aspect = if lx > 0.0 && ly > 0.0 && (ly / lx).is_finite() {
            ly / lx
        } else {
            1.0
        };
        let plot_w = f64::from(w)
            - f64::from(panel_w)
            - m.tick * 2.4
            - m.label * 1.5
            - 2.0 * f64::from(m.margin);
        let h = plot_w * aspect
            + m.tick * 1.3
            + m.label * 1.9
            + 2.0 * f64::from(m.margin)
            + m.title * 1.6;
        (w, h.clamp(300.0, 1600.0).round() as u32)
    }
}

/// A picture of one snapshot.
///
/// ```no_run
/// # use granular_report::plot::{ColourBy, PictureStyle, SnapshotPicture};
/// # fn demo(snapshot: &granular::engine::Snapshot) -> Result<(), granular_report::plot::PlotError> {
/// let style = PictureStyle::new(1.0, 1.0).periodic(true, true)
///     .colour_by(ColourBy::Speed { max: None }).title("Clustering, e = 0.8");
/// SnapshotPicture::new(snapshot, style).save("clusters.png")?;
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug)]
pub struct SnapshotPicture<'a> {
    snapshot: &'a Snapshot,
    style: PictureStyle,
}

/// One grain ready to draw: centre, radius, colour key (species index or speed).
struct Grain {
    x: f64,
    y: f64,
    z: f64,
    r: f64,
    species: usize,
    speed: f64,
}

impl<'a> SnapshotPicture<'a> {
    /// A picture of `snapshot` drawn with `style`.
    pub fn new(snapshot: &'a Snapshot, style: PictureStyle) -> Self {
        Self { snapshot, style }
    }

    /// Writes the picture as PNG or SVG, by the extension of `path`.
    ///
    /// # Errors
    /// [`PlotError::Data`] for an inconsistent snapshot or box, otherwise as
    /// [`super::LinePlot::save`].
    pub fn save(&self, path: impl AsRef<Path>) -> Result<(), PlotError> {
        save_figure(self, path.as_ref())
    }

    /// Writes `stem.png` and `stem.svg`; returns their paths.
    ///
    /// # Errors
    /// As [`SnapshotPicture::save`].
    pub fn save_png_and_svg(&self, stem: impl AsRef<Path>) -> Result<[PathBuf; 2], PlotError> {
        save_both(self, stem.as_ref())
    }

    fn grains(&self) -> Vec<Grain> {
        let s = self.snapshot;
        let d = s.dimension;
        let mut grains: Vec<Grain> = (0..s.radii.len())
            .map(|i| {
                let p = &s.positions[i * d..(i + 1) * d];
                let v = &s.velocities[i * d..(i + 1) * d];
                Grain {
                    x: p[0],
                    y: p[1],
                    z: if d > 2 { p[2] } else { 0.0 },
                    r: s.radii[i],
                    species: s.species.get(i).map_or(0, |&k| k as usize),
                    speed: v.iter().map(|c| c * c).sum::<f64>().sqrt(),
                }
            })
            .filter(|g| g.x.is_finite() && g.y.is_finite() && g.r.is_finite() && g.r >= 0.0)
            .filter(|g| match (d > 2, self.style.slab) {
                (true, Some((z0, z1))) => g.z >= z0 && g.z < z1,
                _ => true,
            })
            .collect();
        grains.sort_by(|a, b| a.z.total_cmp(&b.z));
        grains
    }

    pub(crate) fn max_speed(&self) -> f64 {
        self.grains()
            .iter()
            .map(|g| g.speed)
            .filter(|v| v.is_finite())
            .fold(0.0, f64::max)
    }

    fn title_text(&self) -> String {
        let time = format_time(self.snapshot.time);
        match (self.style.title.is_empty(), self.style.show_time) {
            (true, true) => format!("t = {time}"),
            (false, true) => format!("{}    t = {time}", self.style.title),
            (_, false) => self.style.title.clone(),
        }
    }

    fn species_present(&self) -> Vec<usize> {
        let mut species: Vec<usize> = self.grains().iter().map(|g| g.species).collect();
        species.sort_unstable();
        species.dedup();
        species
    }

    /// Width of the legend / colour-bar panel on the right.
    fn panel_width(&self, m: &Metrics) -> u32 {
        match self.style.colour_by {
            ColourBy::Species => {
                let chars = self
                    .species_present()
                    .iter()
                    .map(|&k| self.species_name(k).chars().count())
                    .max()
                    .unwrap_or(0);
                (chars as f64 * 0.62 * m.legend + m.legend * 2.0 + f64::from(m.margin) * 2.0) as u32
            }
            ColourBy::Speed { .. } => {
                (m.tick * 2.4 + m.label * 1.5 + m.legend * 1.3 + f64::from(m.margin) * 3.0) as u32
            }
        }
    }

    fn species_name(&self, k: usize) -> String {
        self.snapshot
            .species_names
            .get(k)
            .filter(|n| !n.is_empty())
            .cloned()
            .unwrap_or_else(|| format!("species {k}"))
    }

    /// Draws the legend (species) or colour bar (speed) into the side panel.
    fn draw_side_panel<DB: DrawingBackend>(
        &self,
        panel: &DrawingArea<DB, Shift>,
        m: &Metrics,
        top: u32,
        plot_height: u32,
        vmax: f64,
        species: &[usize],
    ) -> Result<(), PlotError> {
        match self.style.colour_by {
            ColourBy::Species => {
                let line = (m.legend * 1.6) as i32;
                let r = (m.legend * 0.4) as i32;
                for (row, &k) in species.iter().enumerate() {
                    let y = top as i32 + line / 2 + row as i32 * line;
                    let x = m.margin as i32;
                    panel.draw(&Circle::new((x + r, y), r, palette(k).filled()))?;
                    panel.draw(&Circle::new((x + r, y), r, darken(palette(k), 0.4)))?;
                    let text = font(m.legend).pos(plotters::style::text_anchor::Pos::new(
                        plotters::style::text_anchor::HPos::Left,
                        plotters::style::text_anchor::VPos::Center,
                    ));
                    panel.draw_text(&self.species_name(k), &text, (x + 3 * r, y))?;
                }
            }
            ColourBy::Speed { .. } => {
                let (_, h) = panel.dim_in_pixel();
                let bottom = h.saturating_sub(top + plot_height);
                let mut chart = ChartBuilder::on(panel)
                    .margin_top(top)
                    .margin_bottom(bottom)
                    .margin_left(m.margin)
                    .margin_right(m.margin * 2)
                    .y_label_area_size(m.tick * 2.4 + m.label * 1.5)
                    .build_cartesian_2d(0.0..1.0, 0.0..vmax)?;
                let steps = 256;
                chart.draw_series((0..steps).map(|i| {
                    let a = vmax * i as f64 / steps as f64;
                    let b = vmax * (i + 1) as f64 / steps as f64;
                    Rectangle::new(
                        [(0.0, a), (1.0, b)],
                        viridis((a + b) / (2.0 * vmax)).filled(),
                    )
                }))?;
                let fmt = |v: &f64| format_tick(*v);
                chart
                    .configure_mesh()
                    .disable_mesh()
                    .disable_x_axis()
                    .y_desc(self.style.speed_label.as_str())
                    .axis_desc_style(font(m.label))
                    .label_style(font(m.tick))
                    .y_label_formatter(&fmt)
                    .y_labels(6)
                    .set_all_tick_mark_size(m.marker)
                    .draw()?;
                chart.draw_series(std::iter::once(Rectangle::new(
                    [(0.0, 0.0), (1.0, vmax)],
                    BLACK.stroke_width(1),
                )))?;
            }
        }
        Ok(())
    }
}

/// Time as printed on pictures: four significant digits.
pub(crate) fn format_time(t: f64) -> String {
    if t == 0.0 || !t.is_finite() {
        return format!("{t}");
    }
    let digits = (3 - t.abs().log10().floor() as i32).clamp(0, 12) as usize;
    if t.abs() >= 1e5 || t.abs() < 1e-3 {
        format!("{t:.3e}")
    } else {
        format!("{t:.digits$}")
    }
}

/// Vertices of a circle in data units, with enough sides to look round at `r_px` pixels.
fn circle_polygon(x: f64, y: f64, r: f64, r_px: f64) -> Vec<(f64, f64)> {
    let sides = ((std::f64::consts::TAU * r_px / 2.0).ceil() as usize).clamp(16, 360);
    (0..sides)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / sides as f64;
            (x + r * a.cos(), y + r * a.sin())
        })
        .collect()
}

impl Draw for SnapshotPicture<'_> {
    fn size(&self) -> (u32, u32) {
        self.style
            .figure_size(self.panel_width(&self.style.metrics()))
    }

    fn check(&self) -> Result<(), PlotError> {
        let s = self.snapshot;
        let d = s.dimension;
        let n = s.radii.len();
        if d < 2 {
            return Err(PlotError::Data(format!(
                "cannot draw a {d}-dimensional snapshot"
            )));
        }
        if s.positions.len() != n * d || s.velocities.len() != n * d {
            return Err(PlotError::Data(format!(
                "snapshot positions/velocities do not hold {n} x {d} values"
            )));
        }
        let [lx, ly] = self.style.box_lengths;
        if !(lx.is_finite() && ly.is_finite() && lx > 0.0 && ly > 0.0) {
            return Err(PlotError::Data(format!("invalid box {lx} x {ly}")));
        }
        if let ColourBy::Speed { max: Some(v) } = self.style.colour_by
            && !(v.is_finite() && v > 0.0)
        {
            return Err(PlotError::Data(format!("invalid colour-bar maximum {v}")));
        }
        Ok(())
    }

    fn draw_on<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        vector: bool,
    ) -> Result<(), PlotError> {
        self.check()?;
        let style = &self.style;
        let m = style.metrics();
        let grains = self.grains();
        let species = self.species_present();

        let title = self.title_text();
        let area = if title.is_empty() {
            root.clone()
        } else {
            root.titled(&title, font(m.title))?
        };
        let (w, _) = area.dim_in_pixel();
        let panel_w = self.panel_width(&m).min(w / 3);
        let (main, panel) = area.split_horizontally(w - panel_w);

        // Equal aspect ratio: shrink the main area so the plotting area has the box's shape.
        let [lx, ly] = style.box_lengths;
        let x_lab = m.tick * 1.3 + m.label * 1.9;
        let y_lab = m.tick * 2.4 + m.label * 1.5;
        let (mw, mh) = main.dim_in_pixel();
        let avail_w = (f64::from(mw) - y_lab - 2.0 * f64::from(m.margin)).max(10.0);
        let avail_h = (f64::from(mh) - x_lab - 2.0 * f64::from(m.margin)).max(10.0);
        let scale = (avail_w / lx).min(avail_h / ly);
        let extra_w = (avail_w - lx * scale).max(0.0).round() as u32;
        let extra_h = (avail_h - ly * scale).max(0.0).round() as u32;
        let main = main.margin(
            extra_h / 2,
            extra_h - extra_h / 2,
            extra_w / 2,
            extra_w - extra_w / 2,
        );
        let mut chart = ChartBuilder::on(&main)
            .margin(m.margin)
            .x_label_area_size(x_lab)
            .y_label_area_size(y_lab)
            .build_cartesian_2d(0.0..lx, 0.0..ly)?;
        let fmt = |v: &f64| format_tick(*v);
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc(style.x_label.as_str())
            .y_desc(style.y_label.as_str())
            .axis_desc_style(font(m.label))
            .label_style(font(m.tick))
            .x_label_formatter(&fmt)
            .y_label_formatter(&fmt)
            .x_labels(6)
            .y_labels(6)
            .set_all_tick_mark_size(m.marker)
            .draw()?;

        // Pixels per length unit (equal on both axes by construction).
        let (pw, _) = chart.plotting_area().dim_in_pixel();
        let px = f64::from(pw) / lx;
        let vmax = match style.colour_by {
            ColourBy::Speed { max: Some(v) } => v,
            _ => self.max_speed().max(f64::MIN_POSITIVE),
        };
        let colour_of = |g: &Grain| match style.colour_by {
            ColourBy::Species => palette(g.species),
            ColourBy::Speed { .. } => viridis(g.speed / vmax),
        };
        for g in &grains {
            let r_px = g.r * px;
            let colour = colour_of(g);
            let outline = r_px >= 4.0;
            let shifts = |k: usize, c: f64, l: f64| -> Vec<f64> {
                let mut v = vec![0.0];
                if style.periodic[k] {
                    if c - g.r < 0.0 {
                        v.push(l);
                    }
                    if c + g.r > l {
                        v.push(-l);
                    }
                }
                v
            };
            for dx in shifts(0, g.x, lx) {
                for dy in shifts(1, g.y, ly) {
                    let (cx, cy) = (g.x + dx, g.y + dy);
                    if !vector && r_px < 12.0 {
                        // Small disks in bitmaps: plotters' anti-aliased circle, radius
                        // rounded to the pixel (a polygon this small would be ragged).
                        let r_int = r_px.round().max(1.0) as i32;
                        chart.draw_series(std::iter::once(Circle::new(
                            (cx, cy),
                            r_int,
                            colour.filled(),
                        )))?;
                        if outline {
                            chart.draw_series(std::iter::once(Circle::new(
                                (cx, cy),
                                r_int,
                                darken(colour, 0.45).stroke_width(1),
                            )))?;
                        }
                        continue;
                    }
                    let poly = circle_polygon(cx, cy, g.r, r_px);
                    if outline {
                        let mut closed = poly.clone();
                        closed.push(poly[0]);
                        chart.draw_series(std::iter::once(Polygon::new(poly, colour.filled())))?;
                        chart.draw_series(std::iter::once(PathElement::new(
                            closed,
                            darken(colour, 0.45).stroke_width(1),
                        )))?;
                    } else {
                        chart.draw_series(std::iter::once(Polygon::new(poly, colour.filled())))?;
                    }
                }
            }
        }
        // Box: walls solid and thick, periodic faces dashed.
        let wall = BLACK.stroke_width(m.line);
        let open = BLACK.mix(0.6).stroke_width(m.line.max(2) - 1);
        let faces = [
            ([(0.0, 0.0), (0.0, ly)], style.periodic[0]),
            ([(lx, 0.0), (lx, ly)], style.periodic[0]),
            ([(0.0, 0.0), (lx, 0.0)], style.periodic[1]),
            ([(0.0, ly), (lx, ly)], style.periodic[1]),
        ];
        for (segment, periodic) in faces {
            if periodic {
                chart.draw_series(std::iter::once(DashedPathElement::new(
                    segment,
                    4 * m.line,
                    3 * m.line,
                    open,
                )))?;
            } else {
                chart.draw_series(std::iter::once(PathElement::new(segment.to_vec(), wall)))?;
            }
        }
        let (_, py) = chart.plotting_area().get_pixel_range();
        let (_, panel_y) = panel.get_pixel_range();
        let top = (py.start - panel_y.start).max(0) as u32;
        let plot_height = (py.end - py.start).max(0) as u32;
        self.draw_side_panel(&panel, &m, top, plot_height, vmax, &species)?;
        Ok(())
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::super::test_support::{decode_png, temp_dir};
    use super::*;

    /// A lattice of small grains with a few large intruders, in a 2:1 box.
    pub(crate) fn demo_snapshot(time: f64) -> Snapshot {
        let (mut positions, mut velocities, mut radii, mut masses, mut species) =
            (vec![], vec![], vec![], vec![], vec![]);
        for i in 0..20 {
            for j in 0..10 {
                let (x, y) = (0.05 + 0.1 * i as f64, 0.05 + 0.1 * j as f64);
                let phase = (i * 7 + j * 3) as f64 + time;
                positions.extend([x + 0.02 * phase.sin(), y + 0.02 * phase.cos()]);
                velocities.extend([phase.cos() * (1.0 + 0.1 * i as f64), phase.sin()]);
                let big = (i + j) % 17 == 0;
                radii.push(if big { 0.045 } else { 0.025 });
                masses.push(if big { 4.0 } else { 1.0 });
                species.push(u32::from(big));
            }
        }
        // A grain crossing the periodic x face.
        positions.extend([1.99, 0.5]);
        velocities.extend([0.0, 0.0]);
        radii.push(0.04);
        masses.push(1.0);
        species.push(2);
        Snapshot {
            time,
            dimension: 2,
            positions,
            velocities,
            radii,
            masses,
            species,
            species_names: vec!["bath".into(), "intruder".into(), "tracer".into()],
            ..Default::default()
        }
    }

    #[test]
    fn species_picture_has_true_size_disks() {
        let dir = temp_dir("snapshot_species");
        let snap = demo_snapshot(0.0);
        let style = PictureStyle::new(2.0, 1.0)
            .periodic(true, false)
            .title("Bidisperse gas");
        let path = dir.join("species.png");
        SnapshotPicture::new(&snap, style.clone())
            .save(&path)
            .expect("save");
        let (w, h, pixels) = decode_png(&path);
        assert_eq!(w, 1000);
        assert!(
            (450..650).contains(&h),
            "height {h} does not follow the 2:1 box"
        );
        // Measure the intruder at (0.05, 0.05) + offset: find its colour's extent in a row.
        let target = palette(1);
        let hits: Vec<(u32, u32)> = pixels
            .iter()
            .enumerate()
            .filter(|(_, p)| **p == [target.0, target.1, target.2])
            .map(|(i, _)| (i as u32 % w, i as u32 / w))
            .collect();
        assert!(!hits.is_empty(), "no intruder pixels");
        let svg = dir.join("species.svg");
        SnapshotPicture::new(&snap, style).save(&svg).expect("svg");
        let text = std::fs::read_to_string(svg).expect("svg text");
        assert!(text.contains("intruder") && text.contains("x [L]") && text.contains("t = 0"));
    }

    #[test]
    fn disks_are_round_and_true_size() {
        // One grain of radius 0.25 in a unit box: its pixel extent must be the same in x and
        // y and equal to 2 r times the axis scale.
        let snap = Snapshot {
            time: 1.0,
            dimension: 2,
            positions: vec![0.5, 0.5],
            velocities: vec![0.0, 0.0],
            radii: vec![0.25],
            masses: vec![1.0],
            species: vec![0],
            species_names: vec!["a".into()],
            ..Default::default()
        };
        let dir = temp_dir("snapshot_round");
        let path = dir.join("one.png");
        SnapshotPicture::new(&snap, PictureStyle::new(1.0, 1.0).size(900, 700))
            .save(&path)
            .expect("save");
        let (w, _, pixels) = decode_png(&path);
        let target = palette(0);
        let is_fill = |p: &[u8; 3]| {
            (i32::from(p[0]) - i32::from(target.0)).abs() < 8
                && (i32::from(p[1]) - i32::from(target.1)).abs() < 8
                && (i32::from(p[2]) - i32::from(target.2)).abs() < 8
        };
        let coords: Vec<(u32, u32)> = pixels
            .iter()
            .enumerate()
            .filter(|(_, p)| is_fill(p))
            .map(|(i, _)| (i as u32 % w, i as u32 / w))
            // Leave out the legend on the right.
            .filter(|&(x, _)| x < w * 5 / 6)
            .collect();
        let xs = coords.iter().map(|c| c.0);
        let ys = coords.iter().map(|c| c.1);
        let width = xs.clone().max().unwrap_or(0) - xs.min().unwrap_or(0);
        let height = ys.clone().max().unwrap_or(0) - ys.min().unwrap_or(0);
        assert!(width > 100, "disk too small: {width}");
        assert!(
            (i64::from(width) - i64::from(height)).abs() <= 3,
            "not round: {width} x {height}"
        );
        // Axis frame: find the black box outline columns on the disk's centre row to get
        // pixels per unit; the disk spans half the box.
        let row = (coords.iter().map(|c| c.1).sum::<u32>() / coords.len() as u32) as usize;
        let dark: Vec<usize> = (0..w as usize)
            .filter(|&x| pixels[row * w as usize + x].iter().all(|&c| c < 60))
            .collect();
        let box_px = dark.last().copied().unwrap_or(0) - dark.first().copied().unwrap_or(0);
        let ratio = f64::from(width) / box_px as f64;
        assert!((ratio - 0.5).abs() < 0.02, "disk / box = {ratio}");
    }

    #[test]
    fn speed_colouring_and_3d_projection() {
        let dir = temp_dir("snapshot_speed");
        let snap = demo_snapshot(2.0);
        let style = PictureStyle::new(2.0, 1.0)
            .periodic(true, true)
            .colour_by(ColourBy::Speed { max: None })
            .title("Speeds");
        SnapshotPicture::new(&snap, style)
            .save_png_and_svg(dir.join("speed"))
            .expect("save");
        // A 3D snapshot: x-y projection, and a slab.
        let snap3 = Snapshot {
            time: 0.5,
            dimension: 3,
            positions: vec![0.3, 0.3, 0.1, 0.35, 0.3, 0.9, 0.7, 0.7, 0.5],
            velocities: vec![0.0; 9],
            radii: vec![0.1, 0.1, 0.15],
            masses: vec![1.0; 3],
            species: vec![0, 1, 0],
            species_names: vec!["a".into(), "b".into()],
            ..Default::default()
        };
        SnapshotPicture::new(&snap3, PictureStyle::new(1.0, 1.0))
            .save(dir.join("projection.png"))
            .expect("3d");
        SnapshotPicture::new(&snap3, PictureStyle::new(1.0, 1.0).slab(0.0, 0.5))
            .save(dir.join("slab.png"))
            .expect("slab");
        let bad = Snapshot {
            dimension: 1,
            ..snap3.clone()
        };
        assert!(
            SnapshotPicture::new(&bad, PictureStyle::new(1.0, 1.0))
                .save(dir.join("bad.png"))
                .is_err()
        );
    }

    #[test]
    fn style_from_box() {
        use granular::{AxisKind, SimulationBox, Vector};
        let b = SimulationBox::<3> {
            lengths: Vector([2.0, 3.0, 4.0]),
            axes: [AxisKind::Periodic, AxisKind::Wall, AxisKind::Periodic],
        };
        let style = PictureStyle::from_box(&b);
        assert_eq!(style.box_lengths, [2.0, 3.0]);
        assert_eq!(style.periodic, [true, false]);
    }

    #[test]
    fn time_format() {
        assert_eq!(format_time(0.0), "0");
        assert_eq!(format_time(12.3456), "12.35");
        assert_eq!(format_time(0.5), "0.5000");
        assert_eq!(format_time(123456.0), "1.235e5");
    }
}
