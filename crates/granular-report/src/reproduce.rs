//! `granular reproduce FIGURE...`: the figures of the Gillespie intruder paper
//! (`docs/intruder.md`), each as `figN.png`, `figN.svg` and the data table `figN.csv`,
//! with the theory overlaid where it exists; and two figures beyond the paper, its Figs. 3
//! and 4 for disks and spheres: `fig3d` (`T/T_B` against `alpha` in 1, 2 and 3 dimensions
//! on the Martin-Piasecki curve, G-40) and `fig4d` (disk and sphere in the power-law bath
//! G-43: Gillespie against the DSMC twin).
//!
//! Statistics: by default the paper's (5e5 collisions per point in 1D, 5e6 for the
//! needle); `--quick` uses ten times fewer. Sweep points run in parallel (rayon) and every
//! point `i` of figure `N` uses the stream `(derive_key(seed, [N]), [MEMBER, i])`, so the
//! tables do not depend on the number of threads.

use std::path::{Path, PathBuf};
use std::time::Instant;

use granular::intruder::ball::figures as balls;
use granular::intruder::figures as paper;
use granular::intruder::observables::Table;
use granular::intruder::theory::{GAUSSIAN_KURTOSIS, martin_piasecki_ratio};
use granular::random::derive_key;
use granular::theory::intruder::maxwellian_kurtosis;

use crate::ReportError;
use crate::figures::{binned_cdf, chi_square_of_bins};
use crate::plot::{HistogramPlot, LinePlot, PALETTE, Panels, PlotError, Series, fit_text};

/// The figures that can be reproduced (Fig. 6 of the paper is a sketch of the needle;
/// `fig3d` and `fig4d` carry Figs. 3 and 4 to disks and spheres).
pub const FIGURES: [&str; 9] = [
    "fig1", "fig2", "fig3", "fig4", "fig5", "fig7", "fig8", "fig3d", "fig4d",
];

/// What `granular reproduce` makes, besides the figures' names.
#[derive(Clone, Debug)]
pub struct Options {
    /// Output directory (created).
    pub out: PathBuf,
    /// Ten times fewer collisions than the paper (for tests and previews).
    pub quick: bool,
    /// Worker threads (0: all cores); results do not depend on it.
    pub threads: usize,
    /// Seed of all random streams.
    pub seed: u64,
}

/// One finished figure: its name (`fig3`), the files written (PNG, SVG, CSV) and the wall
/// time it took.
#[derive(Clone, Debug)]
pub struct FigureDone {
    /// The figure's name.
    pub name: &'static str,
    /// The files written.
    pub files: Vec<PathBuf>,
    /// Wall-clock seconds.
    pub seconds: f64,
}

/// Collisions (or samples) per point.
#[derive(Clone, Copy, Debug)]
struct Statistics {
    /// 1D intruder collisions per point (paper: 5e5).
    one_d: u64,
    /// Needle collisions per point (paper: 5e6).
    needle: u64,
    /// Thinning candidates per `v1` (Fig. 1) and sampler draws per `v1` (Fig. 2).
    samples: u64,
    /// Disk and sphere collisions per point (`fig3d`, `fig4d`; as the 1D intruder's).
    ball: u64,
    /// Stored bath velocities of the DSMC twin (`fig4d`).
    twin_bath: usize,
}

impl Statistics {
    fn new(quick: bool) -> Self {
        let k = if quick { 10 } else { 1 };
        Self {
            one_d: 500_000 / k,
            needle: 5_000_000 / k,
            samples: 500_000 / k,
            ball: 500_000 / k,
            twin_bath: 10_000,
        }
    }
}

/// The figures named in `requested` (each one of [`FIGURES`] or `all`), in order, without
/// repeats.
pub fn select(requested: &[String]) -> Result<Vec<&'static str>, ReportError> {
    let mut wanted: Vec<&'static str> = Vec::new();
    for f in requested {
        let names: Vec<&'static str> = if f == "all" {
            FIGURES.to_vec()
        } else if let Some(name) = FIGURES.iter().find(|n| **n == f.as_str()) {
            vec![*name]
        } else {
            return Err(ReportError::new(format!(
                "unknown figure `{f}`; use one or more of {} or all",
                FIGURES.join(" ")
            )));
        };
        for n in names {
            if !wanted.contains(&n) {
                wanted.push(n);
            }
        }
    }
    Ok(wanted)
}

/// Makes the figures named in `requested` (see [`select`]) one after the other (each in
/// parallel), calling `done` after each.
pub fn run(
    requested: &[String],
    options: &Options,
    done: &(dyn Fn(&FigureDone) + Sync),
) -> Result<(), ReportError> {
    let wanted = select(requested)?;
    std::fs::create_dir_all(&options.out).map_err(|e| format!("{}: {e}", options.out.display()))?;
    let stats = Statistics::new(options.quick);
    let work = || -> Result<(), String> {
        for name in &wanted {
            let start = Instant::now();
            let files = figure(name, &options.out, stats, options.seed)?;
            done(&FigureDone {
                name,
                files,
                seconds: start.elapsed().as_secs_f64(),
            });
        }
        Ok(())
    };
    if options.threads == 0 {
        work()?;
    } else {
        rayon::ThreadPoolBuilder::new()
            .num_threads(options.threads)
            .build()
            .map_err(|e| format!("--threads {}: {e}", options.threads))?
            .install(work)?;
    }
    Ok(())
}

fn write_csv(table: &Table, path: &Path) -> Result<(), String> {
    let text = format!("# {}\n{}", table.title, table.to_csv());
    std::fs::write(path, text).map_err(|e| format!("{}: {e}", path.display()))
}

fn col(t: &Table, name: &str) -> Vec<f64> {
    t.column(name).map(<[f64]>::to_vec).unwrap_or_default()
}

/// Finite points of `(x, y)` only.
fn finite(x: &[f64], y: &[f64]) -> (Vec<f64>, Vec<f64>) {
    x.iter()
        .zip(y)
        .filter(|(a, b)| a.is_finite() && b.is_finite())
        .map(|(a, b)| (*a, *b))
        .unzip()
}

const HALF: (u32, u32) = (800, 700);

fn figure(name: &str, out: &Path, st: Statistics, seed: u64) -> Result<Vec<PathBuf>, String> {
    let number: u64 = match name {
        "fig3d" => 31,
        "fig4d" => 41,
        _ => name.trim_start_matches("fig").parse().unwrap_or(0),
    };
    let fseed = derive_key(seed, &[number]);
    let stem = out.join(name);
    let table = match name {
        "fig1" => paper::fig1_flux(61, st.samples / 5, fseed),
        "fig2" => paper::fig2_colliding_velocities(st.samples, fseed),
        "fig3" => paper::fig3_temperature_ratio(&paper::alpha_grid(), st.one_d, fseed),
        "fig4" => paper::fig4_power_law_ratio(&paper::alpha_grid(), st.one_d, fseed),
        "fig5" => paper::fig5_power_law_distributions(st.one_d, fseed),
        "fig7" => paper::fig7_correlation(&paper::alpha_grid(), st.needle, fseed),
        "fig3d" => balls::temperature_ratio_by_dimension(&paper::alpha_grid(), st.ball, fseed),
        "fig4d" => balls::power_law_by_dimension(
            &paper::linspace(0.0, 1.0, 6),
            st.ball,
            st.twin_bath,
            fseed,
        ),
        _ => paper::fig8_angular_distribution(st.needle, fseed),
    };
    write_csv(&table, &stem.with_extension("csv"))?;
    let r: Result<[PathBuf; 2], PlotError> = match name {
        "fig1" => plot_fig1(&table).save_png_and_svg(&stem),
        "fig2" => plot_fig2(&table).save_png_and_svg(&stem),
        "fig3" => plot_fig3(&table).save_png_and_svg(&stem),
        "fig4" => plot_fig4(&table).save_png_and_svg(&stem),
        "fig5" => plot_fig5(&table).save_png_and_svg(&stem),
        "fig7" => plot_fig7(&table).save_png_and_svg(&stem),
        "fig3d" => plot_fig3d(&table).save_png_and_svg(&stem),
        "fig4d" => plot_fig4d(&table).save_png_and_svg(&stem),
        _ => plot_fig8(&table).save_png_and_svg(&stem),
    };
    let [png, svg] = r.map_err(|e| format!("{}: {e}", stem.display()))?;
    Ok(vec![png, svg, stem.with_extension("csv")])
}

fn plot_fig1(t: &Table) -> LinePlot {
    let v = col(t, "v1");
    let mut p = LinePlot::new("Fig. 1: collision rate of a Gaussian bath (Eq. 16)")
        .x_label("intruder velocity v₁ [√(T_B/m)]")
        .y_label("collision rate per bath density φ(v₁)/ρ [√(T_B/m)]");
    // One colour per `a`: its Monte Carlo markers and its Eq. 16 line.
    for (j, a) in ["0.5", "1", "2", "4"].iter().enumerate() {
        // Every third point, so the Monte Carlo markers do not hide the curves.
        let (x, y): (Vec<f64>, Vec<f64>) = v
            .iter()
            .zip(col(t, &format!("phi_mc_a{a}")))
            .step_by(3)
            .map(|(x, y)| (*x, y))
            .unzip();
        p = p
            .series(Series::markers(format!("Monte Carlo, a = {a}"), x, y).with_colour(PALETTE[j]));
    }
    for (j, a) in ["0.5", "1", "2", "4"].iter().enumerate() {
        p = p.series(
            Series::theory(
                format!("Eq. 16, a = {a}"),
                v.clone(),
                col(t, &format!("phi_a{a}")),
            )
            .dashed(false)
            .with_colour(PALETTE[j]),
        );
    }
    p
}

fn plot_fig2(t: &Table) -> LinePlot {
    let v = col(t, "v");
    let mut p = LinePlot::new("Fig. 2: colliding bath velocities g₊(v, v₁) (Eq. 12)")
        .x_label("bath velocity v [√(T_B/m)]")
        .y_label("density of colliding velocities g₊(v, v₁) [√(m/T_B)]");
    // One colour per v₁: its sampled markers and its Eq. 12 line.
    for (j, v1) in ["-2", "-1", "0", "1", "2"].iter().enumerate() {
        let (x, y) = finite(&v, &col(t, &format!("g_sampled_v1={v1}")));
        let (x, y): (Vec<f64>, Vec<f64>) = x.into_iter().zip(y).step_by(2).unzip();
        p = p.series(Series::markers(format!("sampled, v₁ = {v1}"), x, y).with_colour(PALETTE[j]));
    }
    for (j, v1) in ["-2", "-1", "0", "1", "2"].iter().enumerate() {
        p = p.series(
            Series::theory(
                format!("Eq. 12, v₁ = {v1}"),
                v.clone(),
                col(t, &format!("g_theory_v1={v1}")),
            )
            .dashed(false)
            .with_colour(PALETTE[j]),
        );
    }
    p
}

fn plot_fig3(t: &Table) -> Panels<LinePlot, LinePlot> {
    let alpha = col(t, "alpha");
    let left = LinePlot::new("Fig. 3: T/T_B, M = m, Gaussian bath")
        .size(HALF.0, HALF.1)
        .x_label("restitution α (dimensionless)")
        .y_label("temperature ratio T/T_B")
        .series(
            Series::markers("simulation", alpha.clone(), col(t, "T_over_TB"))
                .with_errors(col(t, "T_over_TB_error")),
        )
        .series(Series::theory_fn(
            "Martin–Piasecki, Eq. 18",
            (0.0, 1.0),
            101,
            false,
            |a| martin_piasecki_ratio(a, 1.0, 1.0),
        ));
    let right = LinePlot::new("Kurtosis ⟨v⁴⟩/⟨v²⟩²")
        .size(HALF.0, HALF.1)
        .x_label("restitution α (dimensionless)")
        .y_label("kurtosis ⟨v⁴⟩/⟨v²⟩²")
        .y_range(2.8, 3.2)
        .series(
            Series::markers("simulation", alpha.clone(), col(t, "kurtosis"))
                .with_errors(col(t, "kurtosis_error")),
        )
        .series(Series::theory(
            "Gaussian: 3",
            vec![0.0, 1.0],
            vec![GAUSSIAN_KURTOSIS, GAUSSIAN_KURTOSIS],
        ));
    Panels::new(left, right)
}

/// `fig3d`: `T/T_B` against `alpha` for `d = 1, 2, 3` on the Martin-Piasecki curve (left),
/// the kurtosis against `(d + 2)/d` (right).
fn plot_fig3d(t: &Table) -> Panels<LinePlot, LinePlot> {
    let alpha = col(t, "alpha");
    let names = ["1D intruder", "disk (2D)", "sphere (3D)"];
    let mut left = LinePlot::new("T/T_B, M = m, Gaussian bath, d = 1, 2, 3")
        .size(HALF.0, HALF.1)
        .x_label("restitution α (dimensionless)")
        .y_label("temperature ratio T/T_B");
    let mut right = LinePlot::new("Kurtosis ⟨|V|⁴⟩/⟨|V|²⟩²")
        .size(HALF.0, HALF.1)
        .x_label("restitution α (dimensionless)")
        .y_label("kurtosis ⟨|V|⁴⟩/⟨|V|²⟩²")
        .y_range(1.4, 3.4);
    for (j, name) in names.iter().enumerate() {
        let d = j + 1;
        left = left.series(
            Series::markers(
                format!("{name}, simulation"),
                alpha.clone(),
                col(t, &format!("T_over_TB_d{d}")),
            )
            .with_errors(col(t, &format!("T_over_TB_d{d}_error")))
            .with_colour(PALETTE[j]),
        );
        right = right
            .series(
                Series::markers(
                    format!("{name}, simulation"),
                    alpha.clone(),
                    col(t, &format!("kurtosis_d{d}")),
                )
                .with_errors(col(t, &format!("kurtosis_d{d}_error")))
                .with_colour(PALETTE[j]),
            )
            .series(
                Series::theory(
                    format!("Maxwellian, (d + 2)/d = {:.3}", maxwellian_kurtosis(d)),
                    vec![0.0, 1.0],
                    vec![maxwellian_kurtosis(d); 2],
                )
                .with_colour(PALETTE[j]),
            );
    }
    left = left.series(Series::theory_fn(
        "Martin–Piasecki, G-18/G-40 (any d)",
        (0.0, 1.0),
        101,
        false,
        |a| martin_piasecki_ratio(a, 1.0, 1.0),
    ));
    Panels::new(left, right)
}

/// `fig4d`: `T/T_B` of the disk and the sphere in the power-law bath, Gillespie against
/// the DSMC twin (one colour each), with the Gaussian bath's G-40 for reference (left); the
/// truncated temperature ratio, whose errors hold in the heavy tail (right).
fn plot_fig4d(t: &Table) -> Panels<LinePlot, LinePlot> {
    let alpha = col(t, "alpha");
    let mut left = LinePlot::new("T/T_B, power-law bath (G-43), M = m")
        .size(HALF.0, HALF.1)
        .x_label("restitution α (dimensionless)")
        .y_label("temperature ratio T/T_B");
    let mut right = LinePlot::new("Truncated: T_h = M⟨min(|V|², h²)⟩/d, h = 6√(T_B/M)")
        .size(HALF.0, HALF.1)
        .x_label("restitution α (dimensionless)")
        .y_label("truncated temperature ratio T_h/T_B");
    for (j, (d, body)) in [(2, "disk"), (3, "sphere")].iter().enumerate() {
        for (method, label) in [("gillespie", "Gillespie"), ("twin", "DSMC twin")] {
            let series = |key: &str| {
                Series::markers(
                    format!("{body} ({d}D), {label}"),
                    alpha.clone(),
                    col(t, &format!("{method}_{key}_d{d}")),
                )
                .with_errors(col(t, &format!("{method}_{key}_d{d}_error")))
                .with_colour(PALETTE[2 * j + usize::from(method == "twin")])
            };
            left = left.series(series("T_over_TB"));
            right = right.series(series("truncated"));
        }
    }
    left = left.series(
        Series::theory_fn(
            "Gaussian bath, G-40 (reference)",
            (0.0, 1.0),
            101,
            false,
            |a| martin_piasecki_ratio(a, 1.0, 1.0),
        )
        .dashed(true),
    );
    Panels::new(left, right)
}

fn plot_fig4(t: &Table) -> LinePlot {
    let alpha = col(t, "alpha");
    let mut p = LinePlot::new("Fig. 4: T/T_B, power-law bath (Eq. 19)")
        .x_label("restitution α (dimensionless)")
        .y_label("temperature ratio T/T_B");
    // One colour per mass: its simulation markers and its Eq. 18 line.
    for (j, m) in ["1", "0.5"].iter().enumerate() {
        p = p.series(
            Series::markers(
                format!("simulation, M = {m}"),
                alpha.clone(),
                col(t, &format!("T_over_TB_M{m}")),
            )
            .with_errors(col(t, &format!("T_over_TB_M{m}_error")))
            .with_colour(PALETTE[j]),
        );
    }
    for (j, m) in ["1", "0.5"].iter().enumerate() {
        let mass: f64 = m.parse().unwrap_or(1.0);
        p = p.series(
            Series::theory_fn(
                format!("Gaussian bath, Eq. 18, M = {m}"),
                (0.0, 1.0),
                101,
                false,
                move |a| martin_piasecki_ratio(a, mass, 1.0),
            )
            .dashed(true)
            .with_colour(PALETTE[j]),
        );
    }
    let (mut ex, mut ey) = (Vec::new(), Vec::new());
    for m in ["1", "0.5"] {
        let (x, y) = finite(&alpha, &col(t, &format!("exact_M{m}")));
        ex.extend(x);
        ey.extend(y);
    }
    p.series(Series::markers("exact, M/m = α", ex, ey).with_colour(PALETTE[6]))
}

fn plot_fig5(t: &Table) -> Panels<LinePlot, LinePlot> {
    let v = col(t, "v");
    let shown = ["0", "0.2", "0.5", "0.8", "1"];
    let mut left = LinePlot::new("Fig. 5: F(v₁), power-law bath, M = 1/2")
        .size(HALF.0, HALF.1)
        .x_label("intruder velocity v₁ [√(T_B/m)]")
        .y_label("velocity distribution F(v₁) [√(m/T_B)]")
        .log_y(true);
    let mut right = LinePlot::new("Tail, v₁ > 0 (log-log)")
        .size(HALF.0, HALF.1)
        .x_label("intruder velocity v₁ [√(T_B/m)]")
        .y_label("velocity distribution F(v₁) [√(m/T_B)]")
        .log_x(true)
        .log_y(true);
    let positive = |y: &[f64]| -> (Vec<f64>, Vec<f64>) {
        v.iter()
            .zip(y)
            .filter(|(x, y)| **x > 0.3 && **y > 0.0)
            .map(|(x, y)| (*x, *y))
            .unzip()
    };
    for a in shown {
        let y = col(t, &format!("F_alpha{a}"));
        left = left.series(Series::line(format!("α = {a}"), v.clone(), y.clone()));
        let (x, y) = positive(&y);
        right = right.series(Series::line(format!("α = {a}"), x, y));
    }
    left = left.series(
        Series::theory(
            "exact (α = M/m = 0.5): Eq. 19",
            v.clone(),
            col(t, "eq19_exact_alpha0.5"),
        )
        .dashed(true),
    );
    let (x, y) = positive(&col(t, "eq19_exact_alpha0.5"));
    right = right.series(Series::theory("Eq. 19 (α = 0.5)", x, y).dashed(true));
    // Pearson's test of the α = 0.5 histogram against Eq. 19 over the binned range.
    if let Some(fit) = equal_bin_edges(&v).and_then(|edges| {
        chi_square_of_bins(
            &edges,
            &col(t, "count_alpha0.5"),
            binned_cdf(&edges, &col(t, "eq19_exact_alpha0.5")),
        )
    }) {
        left = left.note(format!(
            "α = 0.5 vs Eq. 19: {}",
            fit_text(fit.statistic, fit.degrees_of_freedom, fit.p_value)
        ));
    }
    let (x, y) = positive(&col(t, "tail_v^-4"));
    let (x, y): (Vec<f64>, Vec<f64>) = x.into_iter().zip(y).filter(|(x, _)| *x > 1.5).unzip();
    right = right.series(Series::theory("√2/(π v⁴)", x, y).dashed(false));
    Panels::new(left, right)
}

fn plot_fig7(t: &Table) -> Panels<LinePlot, LinePlot> {
    let alpha = col(t, "alpha");
    let mut left = LinePlot::new("Fig. 7: needle correlation R (Eq. 30)")
        .size(HALF.0, HALF.1)
        .x_label("restitution α (dimensionless)")
        .y_label("correlation R = ⟨v²ω²⟩/(⟨v²⟩⟨ω²⟩)");
    let mut right = LinePlot::new("Temperatures")
        .size(HALF.0, HALF.1)
        .x_label("restitution α (dimensionless)")
        .y_label("temperature ratio T/T_B");
    // One colour per mass ratio in both panels; translational (solid, circles) and
    // rotational (dashed, squares) temperatures told apart by line style.
    for (j, m) in ["0.1", "0.5", "1"].iter().enumerate() {
        let colour = PALETTE[j];
        left = left.series(
            Series::markers(
                format!("M/m = {m}"),
                alpha.clone(),
                col(t, &format!("R_M{m}")),
            )
            .with_errors(col(t, &format!("R_M{m}_error")))
            .with_colour(colour)
            .with_pattern(0),
        );
        right = right
            .series(
                Series::line_markers(
                    format!("T_tr, M/m = {m}"),
                    alpha.clone(),
                    col(t, &format!("Ttr_over_TB_M{m}")),
                )
                .with_colour(colour)
                .with_pattern(0),
            )
            .series(
                Series::line_markers(
                    format!("T_rot, M/m = {m}"),
                    alpha.clone(),
                    col(t, &format!("Trot_over_TB_M{m}")),
                )
                .with_colour(colour)
                .with_pattern(1),
            );
    }
    left = left.series(
        Series::theory("equilibrium, R = 1", vec![0.0, 1.0], vec![1.0, 1.0])
            .dashed(true)
            .with_colour(PALETTE[6]),
    );
    Panels::new(left, right)
}

/// A histogram from a table of bin centres, cropped to the bins with data; on a log scale
/// the reference curve is cut a decade below the smallest non-zero density.
fn histogram(t: &Table, log: bool, title: &str) -> HistogramPlot {
    let centres = col(t, "omega");
    let dens = col(t, "P_omega");
    let fit = col(t, "gaussian_fit_omega");
    let w = if centres.len() > 1 {
        centres[1] - centres[0]
    } else {
        1.0
    };
    let used: Vec<usize> = (0..dens.len()).filter(|&i| dens[i] > 0.0).collect();
    let (lo, hi) = match (used.first(), used.last()) {
        (Some(&a), Some(&b)) => (a, b + 1),
        _ => (0, dens.len()),
    };
    let mut edges: Vec<f64> = centres[lo..hi].iter().map(|c| c - 0.5 * w).collect();
    edges.push(centres[hi - 1] + 0.5 * w);
    // Pearson's test against the Gaussian whose width was measured from the same
    // samples: one degree of freedom fewer.
    let counts = col(t, "count_omega");
    let gof = chi_square_of_bins(
        &edges,
        counts.get(lo..hi).unwrap_or(&[]),
        binned_cdf(&edges, &fit[lo..hi]),
    )
    .map(|f| f.with_fitted_parameters(1));
    let plot = HistogramPlot::new(title, edges, dens[lo..hi].to_vec())
        .size(HALF.0, HALF.1)
        .x_label("angular velocity ω [√(T_B/m)/L]")
        .y_label("probability density p(ω) [L√(m/T_B)]")
        .log_y(log)
        .theory_points_over_data(
            "best-fit Gaussian",
            centres[lo..hi].to_vec(),
            fit[lo..hi].to_vec(),
        );
    match gof {
        Some(f) => plot.goodness_of_fit(f.statistic, f.degrees_of_freedom, f.p_value),
        None => plot,
    }
}

/// The edges of equal bins given by their centres (`None` for fewer than two).
fn equal_bin_edges(centres: &[f64]) -> Option<Vec<f64>> {
    let w = centres.get(1)? - centres.first()?;
    let mut edges: Vec<f64> = centres.iter().map(|c| c - 0.5 * w).collect();
    edges.push(centres.last()? + 0.5 * w);
    Some(edges)
}

fn plot_fig8(t: &Table) -> Panels<HistogramPlot, HistogramPlot> {
    Panels::new(
        histogram(t, false, "Fig. 8: needle ω, M/m = 0.1, α = 0.1"),
        histogram(t, true, "Fig. 8, logarithmic scale"),
    )
}
