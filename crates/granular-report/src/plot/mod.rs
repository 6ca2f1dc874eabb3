//! Publication-ready figures: data in, file out. The plotting types know nothing of engines
//! or scenarios; they take numbers (and, for pictures, a [`granular::engine::Snapshot`]).
//!
//! * [`LinePlot`]: named series with optional error bars, log axes, theory curves;
//! * [`HistogramPlot`]: a normalised histogram with theory densities overlaid;
//! * [`SnapshotPicture`]: grains as true-size disks, coloured by species or by speed;
//! * [`Animation`]: a GIF (and, with `ffmpeg`, an MP4) of a sequence of snapshots.
//!
//! Every figure is written as PNG or SVG according to the file extension (`save`), or as
//! both (`save_png_and_svg`). Text is drawn with the embedded DejaVu Sans font (see
//! `assets/DejaVuSans-LICENSE.txt`), so bitmaps render the same on every machine.
//! Colours follow the Okabe–Ito palette (safe for colour-blind readers); series are
//! also told apart by marker shape and dash pattern, so the figures survive grey-scale print.

mod animation;
mod chart;
mod colour;
mod heatmap;
mod histogram;
mod line;
mod snapshot;

pub use animation::Animation;
pub use chart::LegendPosition;
pub use colour::{Colour, PALETTE, viridis};
pub use heatmap::{HeatMaps, HeatPanel};
pub use histogram::{HistogramPlot, fit_text};
pub use line::{LinePlot, Series, SeriesStyle};
pub use snapshot::{ColourBy, PictureStyle, SnapshotPicture};

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use plotters::coord::Shift;
use plotters::prelude::*;

/// The default figure size in pixels (4:3); fonts scale with the height.
pub const DEFAULT_SIZE: (u32, u32) = (1000, 750);

/// Font family name under which the embedded font is registered.
pub(crate) const FONT: &str = "sans-serif";

static FONT_BYTES: &[u8] = include_bytes!("../../assets/DejaVuSans.ttf");

/// Why a figure could not be produced.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// The output path has no extension or one other than `png` / `svg` (`gif` for animations).
    #[error("cannot tell the image format of {0}: use a .png or .svg file name")]
    UnknownFormat(PathBuf),
    /// The input data are unusable (empty, mismatched lengths, not finite, …).
    #[error("{0}")]
    Data(String),
    /// The drawing backend failed (often: the output file could not be written).
    #[error("drawing failed: {0}")]
    Draw(String),
    /// The embedded font could not be registered.
    #[error("the embedded font could not be loaded")]
    Font,
    /// A file or an external program failed.
    #[error("{context}: {source}")]
    Io {
        /// What was being done.
        context: String,
        /// The underlying error.
        source: std::io::Error,
    },
}

impl<E: std::error::Error + Send + Sync> From<DrawingAreaErrorKind<E>> for PlotError {
    fn from(e: DrawingAreaErrorKind<E>) -> Self {
        PlotError::Draw(e.to_string())
    }
}

/// Registers the embedded font once per process; bitmap text is not drawn without it.
pub(crate) fn ensure_font() -> Result<(), PlotError> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| {
        plotters::style::register_font(FONT, FontStyle::Normal, FONT_BYTES).is_ok()
    });
    if ok { Ok(()) } else { Err(PlotError::Font) }
}

/// The output format chosen from a file extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Format {
    Png,
    Svg,
}

pub(crate) fn format_of(path: &Path) -> Result<Format, PlotError> {
    match path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .as_deref()
    {
        Some("png") => Ok(Format::Png),
        Some("svg") => Ok(Format::Svg),
        _ => Err(PlotError::UnknownFormat(path.to_path_buf())),
    }
}

/// Font sizes and line widths for a figure, scaled with its height (reference: 750 px).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Metrics {
    pub title: f64,
    pub label: f64,
    pub tick: f64,
    pub legend: f64,
    pub line: u32,
    pub marker: i32,
    pub margin: u32,
}

impl Metrics {
    pub fn for_size((w, h): (u32, u32)) -> Self {
        let s = (f64::from(h.min(w * 3 / 4)) / 750.0).max(0.4);
        Self {
            title: 32.0 * s,
            label: 28.0 * s,
            tick: 24.0 * s,
            legend: 24.0 * s,
            line: ((3.0 * s).round() as u32).max(1),
            marker: ((7.0 * s).round() as i32).max(2),
            margin: ((24.0 * s).round() as u32).max(4),
        }
    }
}

/// A text style in the embedded font.
pub(crate) fn font(size: f64) -> TextStyle<'static> {
    (FONT, size).into_font().color(&BLACK)
}

/// Something drawn onto a drawing area of any backend.
pub(crate) trait Draw {
    fn size(&self) -> (u32, u32);
    /// Checks the data before any file is created.
    fn check(&self) -> Result<(), PlotError> {
        Ok(())
    }
    /// Draws the figure; `vector` is true for SVG output (exact geometry matters more than
    /// pixel anti-aliasing there).
    fn draw_on<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        vector: bool,
    ) -> Result<(), PlotError>;
}

/// Renders a figure to `path` as PNG or SVG by extension, on a white background.
pub(crate) fn save_figure<F: Draw>(figure: &F, path: &Path) -> Result<(), PlotError> {
    ensure_font()?;
    let format = format_of(path)?;
    figure.check()?;
    let size = figure.size();
    if size.0 < 50 || size.1 < 50 {
        return Err(PlotError::Data(format!(
            "figure size {}x{} is too small",
            size.0, size.1
        )));
    }
    match format {
        Format::Png => {
            let root = BitMapBackend::new(path, size).into_drawing_area();
            root.fill(&WHITE)?;
            figure.draw_on(&root, false)?;
            root.present()?;
        }
        Format::Svg => {
            let root = SVGBackend::new(path, size).into_drawing_area();
            root.fill(&WHITE)?;
            figure.draw_on(&root, true)?;
            root.present()?;
        }
    }
    Ok(())
}

/// Writes `stem.png` and `stem.svg` (any extension of `stem` is replaced).
pub(crate) fn save_both<F: Draw>(figure: &F, stem: &Path) -> Result<[PathBuf; 2], PlotError> {
    let png = stem.with_extension("png");
    let svg = stem.with_extension("svg");
    save_figure(figure, &png)?;
    save_figure(figure, &svg)?;
    Ok([png, svg])
}

/// Two figures side by side in one image (e.g. a distribution and its log-log tail).
/// Each panel keeps its own size; the image is as wide as both and as tall as the taller.
pub(crate) struct Panels<A, B> {
    left: A,
    right: B,
}

impl<A: Draw, B: Draw> Panels<A, B> {
    /// `left` and `right` panels.
    pub fn new(left: A, right: B) -> Self {
        Self { left, right }
    }

    /// Writes `stem.png` and `stem.svg`.
    pub fn save_png_and_svg(&self, stem: impl AsRef<Path>) -> Result<[PathBuf; 2], PlotError> {
        save_both(self, stem.as_ref())
    }
}

impl<A: Draw, B: Draw> Draw for Panels<A, B> {
    fn size(&self) -> (u32, u32) {
        let (a, b) = (self.left.size(), self.right.size());
        (a.0 + b.0, a.1.max(b.1))
    }
    fn check(&self) -> Result<(), PlotError> {
        self.left.check()?;
        self.right.check()
    }
    fn draw_on<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        vector: bool,
    ) -> Result<(), PlotError> {
        let (l, r) = area.split_horizontally(self.left.size().0);
        self.left.draw_on(&l, vector)?;
        self.right.draw_on(&r, vector)
    }
}

/// [`format_tick`], with more digits where needed so that the label is within
/// `resolution / 2` of the value: on a linear axis whose ticks are at least `2 resolution`
/// apart no two labels are equal (a narrow range around a large value, such as 1.5725 to
/// 1.5731, needs more digits than [`format_tick`] gives).
pub(crate) fn format_tick_at(v: f64, resolution: f64) -> String {
    let plain = format_tick(v);
    let half = 0.5 * resolution;
    if !(half > 0.0 && half.is_finite() && v.is_finite())
        || parse_tick(&plain).is_some_and(|x| (x - v).abs() <= half)
    {
        return plain;
    }
    let a = v.abs();
    if (1e-3..1e5).contains(&a) {
        let decimals = (-half.log10()).ceil().clamp(0.0, 17.0) as usize;
        let s = format!("{v:.decimals$}");
        return if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').into()
        } else {
            s
        };
    }
    let exponent = a.log10().floor() as i32;
    let mantissa = v / 10f64.powi(exponent);
    let decimals = (-(half / 10f64.powi(exponent)).log10())
        .ceil()
        .clamp(0.0, 17.0) as usize;
    let m = format!("{mantissa:.decimals$}");
    let m = if m.contains('.') {
        m.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        m
    };
    format!("{m}×10{}", superscript(exponent))
}

/// The number a tick label of [`format_tick`] or [`format_tick_at`] stands for.
pub(crate) fn parse_tick(label: &str) -> Option<f64> {
    let power = |p: &str| -> Option<f64> {
        let digits: String = p
            .chars()
            .map(|c| match c {
                '⁻' => '-',
                '⁰' => '0',
                '¹' => '1',
                '²' => '2',
                '³' => '3',
                '⁴' => '4',
                '⁵' => '5',
                '⁶' => '6',
                '⁷' => '7',
                '⁸' => '8',
                '⁹' => '9',
                other => other,
            })
            .collect();
        Some(10f64.powi(digits.parse().ok()?))
    };
    let label = label.replace('−', "-");
    if let Some((m, p)) = label.split_once("×10") {
        return Some(m.parse::<f64>().ok()? * power(p)?);
    }
    if let Some(p) = label.strip_prefix("-10") {
        return Some(-power(p)?);
    }
    if let Some(p) = label.strip_prefix("10")
        && p.chars()
            .next()
            .is_some_and(|c| !c.is_ascii_digit() && c != '.')
    {
        return power(p);
    }
    label.parse().ok()
}

/// Tick label text: plain decimals for ordinary magnitudes, `a×10ⁿ` otherwise.
pub(crate) fn format_tick(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return if v == 0.0 { "0".into() } else { format!("{v}") };
    }
    let a = v.abs();
    if (1e-3..1e5).contains(&a) {
        let s = format!("{v:.6}");
        let s = s.trim_end_matches('0').trim_end_matches('.');
        // Round away float noise such as 0.30000000000000004 -> 0.3.
        let rounded: f64 = format!("{v:.4e}").parse().unwrap_or(v);
        let r = format!("{rounded:.6}");
        let r = r.trim_end_matches('0').trim_end_matches('.');
        return if r.len() < s.len() {
            r.into()
        } else {
            s.into()
        };
    }
    let exponent = a.log10().floor() as i32;
    let mantissa = v / 10f64.powi(exponent);
    let power = format!("10{}", superscript(exponent));
    if (mantissa.abs() - 1.0).abs() < 1e-9 {
        if mantissa < 0.0 {
            format!("−{power}")
        } else {
            power
        }
    } else {
        let m = format!("{mantissa:.2}");
        let m = m.trim_end_matches('0').trim_end_matches('.');
        format!("{m}×{power}")
    }
}

/// Tick label text on a logarithmic axis: `10ⁿ` at exact decades.
pub(crate) fn format_log_tick(v: f64) -> String {
    if v > 0.0 && v.is_finite() {
        let e = v.log10();
        if (e - e.round()).abs() < 1e-9 {
            return format!("10{}", superscript(e.round() as i32));
        }
    }
    format_tick(v)
}

fn superscript(n: i32) -> String {
    n.to_string()
        .chars()
        .map(|c| match c {
            '-' => '⁻',
            '0' => '⁰',
            '1' => '¹',
            '2' => '²',
            '3' => '³',
            '4' => '⁴',
            '5' => '⁵',
            '6' => '⁶',
            '7' => '⁷',
            '8' => '⁸',
            _ => '⁹',
        })
        .collect()
}

#[cfg(test)]
pub(crate) mod test_support {
    use std::path::PathBuf;

    /// A fresh directory for one test's files.
    pub fn temp_dir(test: &str) -> PathBuf {
        let dir = std::env::temp_dir()
            .join(format!("granular-plot-tests-{}", std::process::id()))
            .join(test);
        std::fs::create_dir_all(&dir).expect("create temp dir");
        dir
    }

    /// Decodes a PNG and returns its size and RGB pixels.
    pub fn decode_png(path: &std::path::Path) -> (u32, u32, Vec<[u8; 3]>) {
        let file = std::fs::File::open(path).expect("open png");
        let mut decoder = png::Decoder::new(std::io::BufReader::new(file));
        decoder.set_transformations(png::Transformations::normalize_to_color8());
        let mut reader = decoder.read_info().expect("png header");
        let mut buf = vec![0; reader.output_buffer_size()];
        let info = reader.next_frame(&mut buf).expect("png frame");
        let channels = info.color_type.samples();
        let pixels = buf[..info.buffer_size()]
            .chunks(channels)
            .map(|c| match channels {
                1 | 2 => [c[0]; 3],
                _ => [c[0], c[1], c[2]],
            })
            .collect();
        (info.width, info.height, pixels)
    }

    /// Number of pixels that are neither white nor nearly white.
    pub fn ink(pixels: &[[u8; 3]]) -> usize {
        pixels.iter().filter(|p| p.iter().any(|&c| c < 200)).count()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tick_labels() {
        // Narrow ranges get the digits that keep neighbouring ticks apart.
        assert_eq!(format_tick_at(1.57255, 1e-5), "1.57255");
        assert_eq!(format_tick_at(1.5725, 1e-5), "1.5725");
        assert_eq!(format_tick_at(0.5, 1e-14), "0.5");
        assert_ne!(format_tick_at(0.5 + 2e-13, 1e-14), "0.5");
        assert_eq!(format_tick_at(123456.5, 0.1), "1.234565×10⁵");
        for label in ["0.3", "−10⁶", "2.5×10⁶", "1.234565×10⁵", "-0.25"] {
            let x = parse_tick(label).unwrap();
            assert_eq!(format_tick_at(x, x.abs() * 1e-9), label);
        }
        assert_eq!(parse_tick("10⁻³"), Some(1e-3));
        assert_eq!(format_tick(0.0), "0");
        assert_eq!(format_tick(0.30000000000000004), "0.3");
        assert_eq!(format_tick(2.5), "2.5");
        assert_eq!(format_tick(100.0), "100");
        assert_eq!(format_tick(1e-5), "10⁻⁵");
        assert_eq!(format_tick(2e6), "2×10⁶");
        assert_eq!(format_tick(-0.001), "-0.001");
        assert_eq!(format_log_tick(1.0), "10⁰");
        assert_eq!(format_log_tick(0.001), "10⁻³");
        assert_eq!(format_log_tick(300.0), "300");
    }

    #[test]
    fn formats_by_extension() {
        assert_eq!(format_of(Path::new("a.PNG")).ok(), Some(Format::Png));
        assert_eq!(format_of(Path::new("a.svg")).ok(), Some(Format::Svg));
        assert!(format_of(Path::new("a")).is_err());
        assert!(format_of(Path::new("a.pdf")).is_err());
    }

    #[test]
    fn font_registers() {
        ensure_font().expect("font");
        ensure_font().expect("font twice");
    }
}

/// A gallery of demonstration figures for looking at by eye:
/// `cargo test -p granular-report plot::gallery -- --ignored` writes them to
/// `$GRANULAR_PLOT_DEMOS` (default `/tmp/granular-plot-demos`).
#[cfg(test)]
mod gallery {
    use super::*;
    use granular::engine::Snapshot;
    use granular::theory::equilibrium;

    /// A small deterministic generator (xorshift) so the gallery needs no `rand`.
    struct Xorshift(u64);
    impl Xorshift {
        fn next(&mut self) -> f64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            (self.0 >> 11) as f64 / (1u64 << 53) as f64
        }
        fn normal(&mut self) -> f64 {
            let (u, v) = (self.next().max(1e-300), self.next());
            (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
        }
    }

    /// A dilute hard-disk gas: 1500 disks of radius 0.006 plus 3 intruders, random
    /// non-overlapping positions, Maxwellian velocities.
    fn dense_snapshot() -> Snapshot {
        let mut rng = Xorshift(0x9E37_79B9_7F4A_7C15);
        let mut s = Snapshot {
            time: 3.25,
            dimension: 2,
            species_names: vec!["bath".into(), "intruder".into()],
            ..Snapshot::default()
        };
        let mut placed: Vec<(f64, f64, f64)> = Vec::new();
        let wanted = [(0.04, 3usize, 1u32), (0.006, 1500, 0)];
        for (r, n, species) in wanted {
            let mut count = 0;
            while count < n {
                let (x, y) = (
                    r + (1.0 - 2.0 * r) * rng.next(),
                    r + (1.0 - 2.0 * r) * rng.next(),
                );
                if placed
                    .iter()
                    .all(|&(a, b, q)| (a - x).powi(2) + (b - y).powi(2) > (q + r).powi(2))
                {
                    placed.push((x, y, r));
                    s.positions.extend([x, y]);
                    let scale = if species == 1 { 0.2 } else { 1.0 };
                    s.velocities
                        .extend([scale * rng.normal(), scale * rng.normal()]);
                    s.radii.push(r);
                    s.masses.push(if species == 1 { 44.0 } else { 1.0 });
                    s.species.push(species);
                    count += 1;
                }
            }
        }
        s
    }

    #[test]
    #[ignore = "writes demonstration images for inspection"]
    fn gallery() {
        let dir = std::env::var_os("GRANULAR_PLOT_DEMOS")
            .map_or_else(|| PathBuf::from("/tmp/granular-plot-demos"), PathBuf::from);
        std::fs::create_dir_all(&dir).expect("demo dir");
        let snap = dense_snapshot();
        let style = PictureStyle::new(1.0, 1.0).title("Hard-disk gas, N = 1503");
        SnapshotPicture::new(&snap, style.clone())
            .save_png_and_svg(dir.join("snapshot_species"))
            .expect("species");
        SnapshotPicture::new(
            &snap,
            style
                .colour_by(ColourBy::Speed { max: None })
                .periodic(true, true),
        )
        .save(dir.join("snapshot_speed.png"))
        .expect("speed");
        let speeds: Vec<f64> = (0..snap.radii.len())
            .filter(|&i| snap.species[i] == 0)
            .map(|i| snap.velocities[2 * i].hypot(snap.velocities[2 * i + 1]))
            .collect();
        HistogramPlot::from_samples("Speed distribution of the bath", &speeds, 25, None)
            .data_label("bath grains, N = 1500")
            .x_label("speed v [L/τ]")
            .y_label("probability density p(v) [τ/L]")
            .theory("Maxwell–Boltzmann, T = 1", |v| {
                equilibrium::speed_density(2, v, 1.0, 1.0)
            })
            .save_png_and_svg(dir.join("speed_histogram"))
            .expect("histogram");
        let t: Vec<f64> = (0..12).map(|i| f64::from(i) * 0.5).collect();
        let msd: Vec<f64> = t
            .iter()
            .map(|&t| 4.0 * 0.3 * t * (1.0 + 0.02 * t.sin()))
            .collect();
        LinePlot::new("Mean-square displacement")
            .x_label("time t [τ]")
            .y_label("⟨|Δr|²⟩ [L²]")
            .series(
                Series::markers("intruder", t.clone(), msd.clone())
                    .with_errors(msd.iter().map(|v| 0.05 * v + 0.02).collect()),
            )
            .series(Series::line_markers(
                "bath",
                t.clone(),
                t.iter().map(|&t| 4.0 * 0.9 * t).collect(),
            ))
            .series(Series::theory_fn(
                "4 D t, D = 0.3",
                (0.0, 5.5),
                50,
                false,
                |t| 1.2 * t,
            ))
            .save_png_and_svg(dir.join("msd"))
            .expect("msd");
    }
}
