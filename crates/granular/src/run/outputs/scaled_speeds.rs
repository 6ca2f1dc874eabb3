//! Speeds of a gas that is not in a steady state: each pooled snapshot's speeds scaled by
//! that snapshot's thermal speed per species, `c = v / v_T(t)` with `v_T = sqrt(2 T_s(t) / m_s)`
//! (DSMC-4: the scaled distribution of the homogeneous cooling state), and the spread of
//! the snapshots' temperatures that decides whether pooling raw speeds means anything.

use crate::run::grains::{Grains, add_counts};
use crate::run::summary::ScaledSpeedSummary;
use crate::run::{RunError, io_err};
use crate::stats::Histogram;
use crate::theory::equilibrium;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Largest relative deviation of a pooled snapshot's temperature (per species) from the
/// pooled mean for which the raw speeds are pooled into one "equilibrium" histogram with a
/// Maxwell-Boltzmann fit. Beyond it the gas is not in a steady state (a cooling gas) and
/// only the scaled speeds are reported.
pub(crate) const STEADY_TOLERANCE: f64 = 0.1;

/// Scaled speeds pooled per species, and the range of the snapshots' temperatures.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub(crate) struct ScaledSpeeds {
    /// Histogram of `c` per species.
    histograms: Vec<Histogram>,
    /// `Σ c²` per species.
    c2: Vec<f64>,
    /// `Σ c⁴` per species.
    c4: Vec<f64>,
    /// Lowest snapshot temperature per species.
    t_min: Vec<f64>,
    /// Highest snapshot temperature per species.
    t_max: Vec<f64>,
}

impl ScaledSpeeds {
    /// Empty statistics for `species` species; `c` histogrammed on `[0, max)` in `bins` bins.
    pub(crate) fn new(species: usize, max: f64, bins: usize) -> ScaledSpeeds {
        ScaledSpeeds {
            histograms: vec![Histogram::new(0.0, max, bins); species],
            c2: vec![0.0; species],
            c4: vec![0.0; species],
            t_min: vec![f64::INFINITY; species],
            t_max: vec![f64::NEG_INFINITY; species],
        }
    }

    /// Whether statistics were set up (a checkpoint of an earlier version has none).
    pub(crate) fn is_set(&self) -> bool {
        !self.histograms.is_empty()
    }

    /// Pools one snapshot: `v2[i]` the squared speed of the block's grain `i`, `masses[s]`
    /// the mass per species, the dimension and species from `grains` (collective under
    /// ranks: the sums are chained in id order and the counts summed, see [`Grains`]).
    /// Species at rest are skipped.
    pub(crate) fn push(&mut self, grains: &Grains, v2: &[f64], masses: &[f64]) {
        let ns = self.histograms.len();
        let (d, species) = (grains.snap.dimension, &grains.snap.species);
        // [Σ v², count] per species, in id order.
        let acc = grains.chain(vec![0.0; 2 * ns], |mut a| {
            for (&x, &s) in v2.iter().zip(species) {
                a[s as usize] += x;
                a[ns + s as usize] += 1.0;
            }
            a
        });
        // Temperature T_s = m <v²> / D; thermal speed v_T² = 2 T_s / m = 2 <v²> / D.
        let mut inv_vt2 = vec![0.0; ns];
        for s in 0..ns {
            let (sum, count) = (acc[s], acc[ns + s]);
            if count == 0.0 || sum <= 0.0 {
                continue;
            }
            let mean = sum / count;
            let t = masses[s] * mean / d as f64;
            self.t_min[s] = self.t_min[s].min(t);
            self.t_max[s] = self.t_max[s].max(t);
            inv_vt2[s] = d as f64 / (2.0 * mean);
        }
        let mut histograms: Vec<Histogram> = self
            .histograms
            .iter()
            .map(|h| Histogram::new(h.min, h.max, h.counts.len()))
            .collect();
        let mut init = self.c2.clone();
        init.extend_from_slice(&self.c4);
        let acc = grains.chain(init, |mut a| {
            for (&x, &s) in v2.iter().zip(species) {
                let s = s as usize;
                if inv_vt2[s] == 0.0 {
                    continue;
                }
                let c2 = x * inv_vt2[s];
                histograms[s].push(c2.sqrt());
                a[s] += c2;
                a[ns + s] += c2 * c2;
            }
            a
        });
        self.c2 = acc[..ns].to_vec();
        self.c4 = acc[ns..].to_vec();
        grains.sum_histograms(&mut histograms);
        for (into, from) in self.histograms.iter_mut().zip(&histograms) {
            add_counts(into, from);
        }
    }

    /// Whether every snapshot's temperature of species `s` is within [`STEADY_TOLERANCE`]
    /// of `mean` (the pooled temperature).
    pub(crate) fn steady(&self, s: usize, mean: f64) -> bool {
        mean.is_nan()
            || mean <= 0.0
            || (self.t_max[s] <= mean * (1.0 + STEADY_TOLERANCE)
                && self.t_min[s] >= mean * (1.0 - STEADY_TOLERANCE))
    }

    /// Summary of species `s`: the pooled fourth cumulant
    /// `a2 = D/(D+2) <c⁴>/<c²>² - 1` (DSMC-4) and the temperature range.
    pub(crate) fn summary(&self, d: usize, s: usize, snapshots: u64) -> ScaledSpeedSummary {
        let n = self.histograms[s].total();
        let (m2, m4) = (self.c2[s] / n as f64, self.c4[s] / n as f64);
        let d = d as f64;
        ScaledSpeedSummary {
            samples: n,
            snapshots,
            a2: d / (d + 2.0) * m4 / (m2 * m2) - 1.0,
            temperature_min: self.t_min[s],
            temperature_max: self.t_max[s],
            theory_a2: None,
        }
    }

    /// Writes `scaled_speed_histograms.csv`: the pooled density of `c` per species against
    /// the Maxwell-Boltzmann density of `c`, `2 c e^{-c²}` in 2D (HD-12 with `m = 2`, `T = 1`).
    pub(crate) fn write(&self, dir: &Path, d: usize, names: &[String]) -> Result<(), RunError> {
        let path = dir.join(crate::run::RunFile::ScaledSpeedHistograms.name());
        let mut out =
            String::from("species,c_low,c_high,density,count,maxwell_boltzmann_density\n");
        for (s, h) in self.histograms.iter().enumerate() {
            let density = h.density();
            let w = h.bin_width();
            let cdf = |c: f64| equilibrium::speed_cdf(d, c, 2.0, 1.0);
            for (b, &count) in h.counts.iter().enumerate() {
                let lo = h.min + b as f64 * w;
                out.push_str(&format!(
                    "{},{:e},{:e},{:e},{},{:e}\n",
                    names[s],
                    lo,
                    lo + w,
                    if h.total() > 0 { density[b] } else { f64::NAN },
                    count,
                    (cdf(lo + w) - cdf(lo)) / w
                ));
            }
        }
        std::fs::write(&path, out).map_err(io_err(&path))
    }
}
