//! Speed and velocity statistics per species: the histograms at `t = 0` and pooled over
//! equilibrium snapshots (`speed_histograms.csv`, `velocity_histograms.csv`), the
//! Maxwell-Boltzmann goodness of fit (HD-12) and the per-species averages of the summary.

use super::Output;
use super::scaled_speeds::{STEADY_TOLERANCE, ScaledSpeeds};
use crate::observation::Observation;
use crate::run::grains::{Grains, add_counts};
use crate::run::summary::{MaxwellBoltzmannFit, SpeciesStatistics};
use crate::run::{RunError, Summary, io_err};
use crate::simulation::Simulation;
use crate::stats::{Histogram, RunningStats, chi_square_test};
use crate::theory::equilibrium;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Pooled speed statistics of a run (part of its checkpoint).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub(crate) struct SpeedStatistics {
    #[serde(skip)]
    dir: PathBuf,
    /// Species names.
    species: Vec<String>,
    /// Mass per species (for the theory curve).
    masses: Vec<f64>,
    /// Initial histograms.
    initial: Vec<Histogram>,
    /// Pooled equilibrium histograms.
    equilibrium: Vec<Histogram>,
    /// Pooled equilibrium histograms of the velocity components (all axes together).
    velocity: Vec<Histogram>,
    /// Σ m v² / D per species over the pooled samples (temperature estimate).
    energy_sum: Vec<f64>,
    /// Speeds of the pooled samples, per species.
    speed_stats: Vec<RunningStats>,
    /// Kinetic energies `m v² / 2` of the pooled samples, per species.
    energy_stats: Vec<RunningStats>,
    /// Number of pooled snapshots.
    samples: u64,
    /// Collisions per grain at the last pooled snapshot.
    last_sample_cpp: f64,
    /// The same snapshots' speeds scaled by their own thermal speed, and the spread of
    /// their temperatures (empty in a checkpoint of an earlier version).
    #[serde(default)]
    scaled: ScaledSpeeds,
}

impl SpeedStatistics {
    /// Statistics written into `dir`; the histogram ranges are fixed at set-up.
    pub(crate) fn new(dir: &Path) -> SpeedStatistics {
        SpeedStatistics {
            dir: dir.to_path_buf(),
            species: Vec::new(),
            masses: Vec::new(),
            initial: Vec::new(),
            equilibrium: Vec::new(),
            velocity: Vec::new(),
            energy_sum: Vec::new(),
            speed_stats: Vec::new(),
            energy_stats: Vec::new(),
            samples: 0,
            last_sample_cpp: f64::NEG_INFINITY,
            scaled: ScaledSpeeds::default(),
        }
    }

    pub(crate) fn relocate(&mut self, dir: &Path) {
        self.dir = dir.to_path_buf();
    }

    /// Temperature of species `s` over the pooled samples (NaN before any).
    fn temperature(&self, s: usize) -> f64 {
        let count = self.equilibrium[s].total();
        if count > 0 {
            self.energy_sum[s] / count as f64
        } else {
            f64::NAN
        }
    }

    fn write_speed_histograms(
        &self,
        d: usize,
    ) -> Result<Vec<Option<MaxwellBoltzmannFit>>, RunError> {
        let path = self.dir.join(crate::run::RunFile::SpeedHistograms.name());
        let mut out = String::from(
            "species,speed_low,speed_high,initial_density,equilibrium_density,equilibrium_count,maxwell_boltzmann_density\n",
        );
        let mut fits = Vec::new();
        for s in 0..self.species.len() {
            let eq = &self.equilibrium[s];
            let count = eq.total();
            let steady = self.steady(s);
            // Not steady: no Maxwell-Boltzmann curve at a mean temperature that no
            // snapshot had.
            let temperature = if steady {
                self.temperature(s)
            } else {
                f64::NAN
            };
            let init_density = self.initial[s].density();
            let eq_density = eq.density();
            let w = eq.bin_width();
            let cdf = |v: f64| equilibrium::speed_cdf(d, v, self.masses[s], temperature);
            for b in 0..eq.counts.len() {
                let lo = eq.min + b as f64 * w;
                let theory = if temperature > 0.0 {
                    (cdf(lo + w) - cdf(lo)) / w
                } else {
                    f64::NAN
                };
                out.push_str(&format!(
                    "{},{:e},{:e},{:e},{:e},{},{:e}\n",
                    self.species[s],
                    lo,
                    lo + w,
                    init_density[b],
                    if count > 0 { eq_density[b] } else { f64::NAN },
                    eq.counts[b],
                    theory
                ));
            }
            fits.push((steady && count > 0 && temperature > 0.0).then(|| {
                let fit = chi_square_test(eq, cdf);
                MaxwellBoltzmannFit {
                    temperature,
                    samples: count,
                    snapshots: self.samples,
                    chi_square: fit.statistic,
                    degrees_of_freedom: fit.degrees_of_freedom,
                    p_value: fit.p_value,
                }
            }));
        }
        std::fs::write(&path, out).map_err(io_err(&path))?;
        Ok(fits)
    }

    /// Velocity components against the Gaussian of variance `T / m`.
    fn write_velocity_histograms(&self) -> Result<(), RunError> {
        let path = self
            .dir
            .join(crate::run::RunFile::VelocityHistograms.name());
        let mut out = String::from(
            "species,velocity_low,velocity_high,equilibrium_density,equilibrium_count,gaussian_density\n",
        );
        for s in 0..self.species.len() {
            let vh = &self.velocity[s];
            let t = if self.steady(s) {
                self.temperature(s)
            } else {
                f64::NAN
            };
            let sd = (t / self.masses[s]).sqrt();
            let cdf = |v: f64| 0.5 * libm::erfc(-v / (sd * std::f64::consts::SQRT_2));
            let dens = vh.density();
            let w = vh.bin_width();
            for (b, &count_b) in vh.counts.iter().enumerate() {
                let lo = vh.min + b as f64 * w;
                let theory = if sd > 0.0 {
                    (cdf(lo + w) - cdf(lo)) / w
                } else {
                    f64::NAN
                };
                let observed = if vh.total() > 0 { dens[b] } else { f64::NAN };
                out.push_str(&format!(
                    "{},{:e},{:e},{:e},{},{:e}\n",
                    self.species[s],
                    lo,
                    lo + w,
                    observed,
                    count_b,
                    theory
                ));
            }
        }
        std::fs::write(&path, out).map_err(io_err(&path))
    }

    /// Whether the pooled snapshots of species `s` had temperatures within
    /// [`STEADY_TOLERANCE`] of their mean (always, for a checkpoint of an earlier version).
    fn steady(&self, s: usize) -> bool {
        !self.scaled.is_set() || self.scaled.steady(s, self.temperature(s))
    }

    /// Pools the speeds of one snapshot (collective under ranks): the histograms from
    /// every rank's counts, the energy sum and running statistics chained in id order.
    fn pool(&mut self, g: &Grains) {
        let snap = &g.snap;
        let d = snap.dimension;
        let ns = self.species.len();
        let empty = |h: &Histogram| Histogram::new(h.min, h.max, h.counts.len());
        let mut speed: Vec<Histogram> = self.equilibrium.iter().map(empty).collect();
        let mut velocity: Vec<Histogram> = self.velocity.iter().map(empty).collect();
        for i in 0..g.len() {
            let s = snap.species[i] as usize;
            speed[s].push(g.speed_squared(i).sqrt());
            for &c in &snap.velocities[i * d..(i + 1) * d] {
                velocity[s].push(c);
            }
        }
        g.sum_histograms(&mut speed);
        g.sum_histograms(&mut velocity);
        for (into, from) in self.equilibrium.iter_mut().zip(&speed) {
            add_counts(into, from);
        }
        for (into, from) in self.velocity.iter_mut().zip(&velocity) {
            add_counts(into, from);
        }
        // [energy sums, speed statistics, energy statistics] per species, in id order.
        let mut init = self.energy_sum.clone();
        init.extend(self.speed_stats.iter().flat_map(RunningStats::to_words));
        init.extend(self.energy_stats.iter().flat_map(RunningStats::to_words));
        let acc = g.chain(init, |mut a| {
            let mut speed_stats: Vec<RunningStats> = (0..ns)
                .map(|s| RunningStats::from_words(&a[ns + 3 * s..]))
                .collect();
            let mut energy_stats: Vec<RunningStats> = (0..ns)
                .map(|s| RunningStats::from_words(&a[4 * ns + 3 * s..]))
                .collect();
            for i in 0..g.len() {
                let v2 = g.speed_squared(i);
                let s = snap.species[i] as usize;
                a[s] += snap.masses[i] * v2 / d as f64;
                speed_stats[s].push(v2.sqrt());
                energy_stats[s].push(0.5 * snap.masses[i] * v2);
            }
            a.truncate(ns);
            a.extend(speed_stats.iter().flat_map(RunningStats::to_words));
            a.extend(energy_stats.iter().flat_map(RunningStats::to_words));
            a
        });
        self.energy_sum = acc[..ns].to_vec();
        self.speed_stats = (0..ns)
            .map(|s| RunningStats::from_words(&acc[ns + 3 * s..]))
            .collect();
        self.energy_stats = (0..ns)
            .map(|s| RunningStats::from_words(&acc[4 * ns + 3 * s..]))
            .collect();
        if self.scaled.is_set() {
            let v2: Vec<f64> = (0..g.len()).map(|i| g.speed_squared(i)).collect();
            self.scaled.push(g, &v2, &self.masses);
        }
    }

    fn species_statistics(&self, d: usize, s: usize) -> Option<SpeciesStatistics> {
        let (sp, en) = (&self.speed_stats[s], &self.energy_stats[s]);
        if sp.count == 0 {
            return None;
        }
        let temperature = 2.0 * en.mean() / d as f64;
        Some(SpeciesStatistics {
            mass: self.masses[s],
            samples: sp.count,
            mean_speed: sp.mean(),
            mean_speed_error: sp.standard_error(),
            mean_kinetic_energy: en.mean(),
            mean_kinetic_energy_error: en.standard_error(),
            temperature,
            maxwell_boltzmann_mean_speed: equilibrium::mean_speed(d, self.masses[s], temperature),
        })
    }
}

impl Output for SpeedStatistics {
    /// Fixes the histogram ranges from the initial state: the upper edge is
    /// `output.histogram_max_speed` times each species' thermal speed at the mean energy.
    /// Under ranks, `Σ m v²` is chained in id order and the counts are summed (see
    /// `run::grains`): no rank holds more than its block of grains.
    fn setup(&mut self, simulation: &Simulation) -> Result<(), RunError> {
        let Some(g) = Grains::of(simulation) else {
            return Ok(());
        };
        let output = &simulation.scenario().output;
        let snap = &g.snap;
        let d = snap.dimension;
        let ns = snap.species_names.len();
        // [Σ m v², Σ m, the mass of each species (the last grain's)], in id order.
        let mut init = vec![0.0, 0.0];
        init.extend(std::iter::repeat_n(1.0, ns));
        let acc = g.chain(init, |mut a| {
            for i in 0..g.len() {
                a[0] += snap.masses[i] * g.speed_squared(i);
                a[1] += snap.masses[i];
                a[2 + snap.species[i] as usize] = snap.masses[i];
            }
            a
        });
        let (mv2, msum) = (acc[0], acc[1]);
        let masses = acc[2..].to_vec();
        let t = mv2 / (d as f64 * g.total as f64);
        let histograms: Vec<Histogram> = (0..ns)
            .map(|s| {
                let v_rms = if t > 0.0 {
                    (d as f64 * t / masses[s]).sqrt()
                } else {
                    (mv2 / msum.max(1e-300)).sqrt().max(1.0)
                };
                let max = output.histogram_max_speed * if v_rms > 0.0 { v_rms } else { 1.0 };
                Histogram::new(0.0, max, output.histogram_bins)
            })
            .collect();
        let mut initial = histograms.clone();
        for i in 0..g.len() {
            initial[snap.species[i] as usize].push(g.speed_squared(i).sqrt());
        }
        g.sum_histograms(&mut initial);
        self.velocity = histograms
            .iter()
            .map(|h| Histogram::new(-h.max, h.max, 2 * h.counts.len()))
            .collect();
        self.species = snap.species_names.clone();
        self.masses = masses;
        self.initial = initial;
        self.scaled = ScaledSpeeds::new(
            ns,
            output.histogram_max_speed * (d as f64 / 2.0).sqrt(),
            output.histogram_bins,
        );
        self.equilibrium = histograms;
        self.energy_sum = vec![0.0; ns];
        self.speed_stats = vec![RunningStats::new(); ns];
        self.energy_stats = vec![RunningStats::new(); ns];
        Ok(())
    }

    /// Pools the speeds of the snapshot when the gas has had
    /// `output.equilibration_collisions_per_particle` collisions per grain and the last
    /// pooled snapshot is `output.histogram_sample_spacing` collisions per grain back
    /// (HD appendix C.2: samples far enough apart to be independent). Under ranks each
    /// rank bins its block and the sums run in id order over the ranks (`run::grains`).
    fn observe(
        &mut self,
        simulation: &Simulation,
        observation: &Observation,
    ) -> Result<(), RunError> {
        let output = &simulation.scenario().output;
        let cpp = observation.collisions_per_particle;
        if self.species.is_empty()
            || cpp < output.equilibration_collisions_per_particle
            || cpp - self.last_sample_cpp < output.histogram_sample_spacing
        {
            return Ok(());
        }
        let Some(g) = Grains::of(simulation) else {
            return Ok(());
        };
        self.pool(&g);
        self.samples += 1;
        self.last_sample_cpp = cpp;
        Ok(())
    }

    fn finish(&mut self, simulation: &Simulation, summary: &mut Summary) -> Result<(), RunError> {
        if self.species.is_empty() {
            return Ok(());
        }
        let d = simulation.scenario().dimension;
        let fits = self.write_speed_histograms(d)?;
        self.write_velocity_histograms()?;
        let mut any_scaled = false;
        for (s, fit) in fits.into_iter().enumerate() {
            if self.samples > 0 && !self.steady(s) {
                let mut scaled = self.scaled.summary(d, s, self.samples);
                scaled.theory_a2 = cooling_theory_a2(simulation);
                summary.warnings.push(format!(
                    "species `{}`: the pooled snapshots' temperatures range from {:.4e} to {:.4e}, \
                     beyond {}% of their mean: the gas is not in a steady state, so no \
                     Maxwell-Boltzmann fit; the speeds scaled by each snapshot's thermal speed \
                     are in scaled_speed_histograms.csv (a2 = {:.4})",
                    self.species[s],
                    scaled.temperature_min,
                    scaled.temperature_max,
                    STEADY_TOLERANCE * 100.0,
                    scaled.a2
                ));
                summary
                    .scaled_speeds
                    .insert(self.species[s].clone(), scaled);
                any_scaled = true;
            }
            if let Some(fit) = fit {
                summary
                    .maxwell_boltzmann_fit
                    .insert(self.species[s].clone(), fit);
            }
            if let Some(stats) = self.species_statistics(d, s) {
                summary.species.insert(self.species[s].clone(), stats);
            }
        }
        if any_scaled {
            self.scaled.write(&self.dir, d, &self.species)?;
        }
        Ok(())
    }
}

/// The homogeneous cooling state's `a2` (van Noije and Ernst 1998, both estimates, as the
/// scenario resolved them) where it applies: one species, a periodic box, no gravity, no TC
/// model.
fn cooling_theory_a2(simulation: &crate::simulation::Simulation) -> Option<[f64; 2]> {
    use crate::boundary::AxisKind;
    let scenario = simulation.scenario();
    let homogeneous = scenario.species().len() == 1
        && scenario.axes().iter().all(|a| *a == AxisKind::Periodic)
        && scenario.gravity().iter().all(|g| *g == 0.0)
        && scenario.collisions().contact_duration == 0.0;
    let hcs_a2 = simulation.resolved().grains.as_ref()?.hcs_a2;
    homogeneous.then_some(hcs_a2)
}
