//! One finished `edmd` or `dsmc` run as read back from its directory (scenario and time
//! series), with the theory the figures put next to it (Haff's time `t0`).

use crate::plot::LinePlot;
use granular::boundary::AxisKind;
use granular::output::npz::NpzArray;
use granular::run::{RunDir, RunFile};
use granular::scenario::{EngineKind, Scenario};
use std::path::{Path, PathBuf};

/// One finished run, as read back from its directory.
pub(crate) struct RunFiles {
    pub dir: PathBuf,
    pub label: String,
    pub scenario: Scenario,
    pub time: Vec<f64>,
    pub energy: Vec<f64>,
    pub temperature: Vec<f64>,
}

pub(crate) type Arrays = Vec<(String, NpzArray)>;

pub(crate) fn get<'a>(arrays: &'a Arrays, name: &str, file: &Path) -> Result<&'a NpzArray, String> {
    arrays
        .iter()
        .find(|(n, _)| n == name)
        .map(|(_, a)| a)
        .ok_or_else(|| format!("{}: no array `{name}`", file.display()))
}

pub(crate) fn floats<'a>(arrays: &'a Arrays, name: &str, file: &Path) -> Result<&'a [f64], String> {
    get(arrays, name, file)?
        .as_f64()
        .ok_or_else(|| format!("{}: array `{name}` is not float64", file.display()))
}

pub(crate) fn load(dir: &Path) -> Result<RunFiles, String> {
    let run = RunDir::new(dir);
    let scenario = run.scenario().map_err(|e| e.to_string())?;
    let ts = crate::table::read_run_csv(dir, RunFile::TimeSeries)?;
    let col = |name: &str| {
        crate::table::column(&ts, name).ok_or_else(|| {
            format!(
                "{}: no column `{name}`",
                run.file(RunFile::TimeSeries).display()
            )
        })
    };
    let engine = match scenario.kind() {
        EngineKind::Edmd => "EDMD",
        EngineKind::Dsmc => "DSMC",
        EngineKind::Intruder => {
            return Err(format!(
                "{}: `granular compare` overlays cooling runs of the edmd and dsmc engines; \
                 this is an intruder run (use `granular plot` for it)",
                dir.display()
            ));
        }
    };
    let name = dir
        .file_name()
        .map_or(String::new(), |s| s.to_string_lossy().to_string());
    Ok(RunFiles {
        dir: dir.to_path_buf(),
        label: format!("{engine} ({name})"),
        time: col("time")?,
        energy: col("kinetic_energy")?,
        temperature: col("temperature")?,
        scenario,
    })
}

/// Haff's time of a run from kinetic theory, with the contact value `χ` it uses, as the
/// library resolves the run's scenario at the initial temperature of `timeseries.csv`
/// (`Resolved::at_temperature`, KT-9): the contact value of the collision rate the run
/// uses (Enskog's at the run's packing fraction for the event-driven engine and for DSMC
/// with `dsmc.enskog = true`; 1, Boltzmann's, for DSMC without it), first Sonine
/// correction. `None` for an elastic gas, one at rest, or rough grains (they cool at RS-5,
/// not at Haff's rate of smooth grains: the rough figure).
pub(crate) fn haff_theory(run: &RunFiles) -> Option<(f64, f64)> {
    let t0 = *run.temperature.first().filter(|t| **t > 0.0)?;
    let resolved = run.scenario.resolve().at_temperature(&run.scenario, t0);
    let g = resolved.grains?;
    Some((g.cooling?.haff_time, g.chi))
}

/// The critical size `L_c` of the homogeneous cooling state of a run's gas (HCS-2,
/// `theory::stability::critical_length`: Haff's law holds only in a periodic box smaller
/// than it), from the library's resolved values of the run's scenario (density, radius,
/// restitution, the cooling state's first `a2` and the contact value of the run's
/// collision rate). `None` for the intruder engines.
pub(crate) fn critical_length(scenario: &Scenario) -> Option<f64> {
    let g = scenario.resolve().grains?;
    Some(granular::theory::stability::critical_length(
        scenario.dimension,
        g.number_density,
        g.radius,
        g.restitution,
        g.hcs_a2[0],
        g.chi,
    ))
}

/// Haff's time of a run from kinetic theory ([`haff_theory`]), for a set-up where Haff's law
/// can hold (`None` where [`haff_excluded`] gives a reason: no curve or `t/t0` axis then).
pub(crate) fn haff_time(run: &RunFiles) -> Option<f64> {
    if haff_excluded(&run.scenario).is_some() {
        return None;
    }
    haff_theory(run).map(|(t0, _)| t0)
}

/// Why Haff's law does not apply to a run's set-up at all (`None`: it may apply): the
/// report's Haff row says so instead of comparing, and `plot` and `compare` draw no Haff
/// curve.
pub(crate) fn haff_excluded(sc: &Scenario) -> Option<String> {
    if sc.species().len() != 1 {
        return Some("a mixture: Haff's law is the one-species cooling state".into());
    }
    if sc.gravity().iter().any(|g| *g != 0.0) {
        return Some("gravity makes the gas inhomogeneous".into());
    }
    if sc.driving().is_some() {
        return Some("a driven gas does not cool freely (steady-state rows)".into());
    }
    if sc.axes().contains(&AxisKind::Wall) {
        return Some(
            "the box has walls; Haff's law is the homogeneous state of a periodic box".into(),
        );
    }
    if sc.collisions().law().is_rough() {
        return Some(
            "rough grains cool at the rate of RS-5, not at Haff's rate of smooth grains (the \
             rough grains' rows)"
                .into(),
        );
    }
    None
}

/// How [`haff_time`] was computed, for legends: `Enskog + Sonine` or `Boltzmann + Sonine`.
pub(crate) fn haff_model(run: &RunFiles) -> &'static str {
    let enskog = run.scenario.resolve().grains.is_none_or(|g| g.enskog);
    if enskog {
        "Enskog + Sonine"
    } else {
        "Boltzmann + Sonine"
    }
}

/// Records the two files of a figure saved as PNG and SVG (`stem`: for the error message).
pub(crate) fn save_both(
    stem: &Path,
    r: Result<[PathBuf; 2], crate::plot::PlotError>,
    made: &mut Vec<PathBuf>,
) -> Result<(), String> {
    let files = r.map_err(|e| format!("{}: {e}", stem.display()))?;
    made.extend(files);
    Ok(())
}

/// Saves a line plot as PNG and SVG at `stem` and records the files.
pub(crate) fn save(plot: &LinePlot, stem: PathBuf, made: &mut Vec<PathBuf>) -> Result<(), String> {
    save_both(&stem, plot.save_png_and_svg(&stem), made)
}

/// A file-name-safe tag of a run.
pub(crate) fn tag(run: &RunFiles) -> String {
    run.dir
        .file_name()
        .map_or("run".into(), |s| s.to_string_lossy().to_string())
        .replace(
            |c: char| !c.is_ascii_alphanumeric() && c != '-' && c != '_',
            "_",
        )
}
