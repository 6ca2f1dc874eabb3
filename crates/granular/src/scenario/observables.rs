//! Validation of the opt-in observable keys of `[output]` (see `run::observers`).

use super::{OutputSpec, ScenarioError};

/// Largest `structure_factor_max_index`: the direct Fourier sum costs
/// `N (2 m + 1)^D / 2` complex products per observation.
const MAX_SK_INDEX: usize = 512;
/// Largest density-map edge in bins.
const MAX_DENSITY_BINS: usize = 4096;

impl OutputSpec {
    /// Checks `structure_factor_max_index`, `density_map` and `observable_times`.
    pub(super) fn validate_observables(&self, dimension: usize) -> Result<(), ScenarioError> {
        if self.structure_factor
            && (self.structure_factor_max_index == 0
                || self.structure_factor_max_index > MAX_SK_INDEX)
        {
            return Err(ScenarioError::new(
                "output.structure_factor_max_index",
                format!(
                    "is {}; give the largest wave-vector index between 1 and {MAX_SK_INDEX} (cost grows as its {dimension}th power; 32 resolves k up to 32 x 2 pi / L)",
                    self.structure_factor_max_index
                ),
            ));
        }
        if !self.density_map.is_empty() {
            if self.density_map.len() != dimension {
                return Err(ScenarioError::new(
                    "output.density_map",
                    format!(
                        "has {} entries; give one bin count per axis ({dimension}), e.g. [64, 64]",
                        self.density_map.len()
                    ),
                ));
            }
            if let Some(&b) = self
                .density_map
                .iter()
                .find(|&&b| b == 0 || b > MAX_DENSITY_BINS)
            {
                return Err(ScenarioError::new(
                    "output.density_map",
                    format!("has {b} bins on an axis; use between 1 and {MAX_DENSITY_BINS}"),
                ));
            }
        }
        let mut previous = 0.0;
        for (i, &t) in self.observable_times.iter().enumerate() {
            if !t.is_finite() || t < previous {
                return Err(ScenarioError::new(
                    format!("output.observable_times[{i}]"),
                    format!(
                        "is {t}; list finite, non-negative times in increasing order (the first output at or after each is an observation time)"
                    ),
                ));
            }
            previous = t;
        }
        Ok(())
    }
}

/// Most bins of `g(r)`.
const MAX_PAIR_BINS: usize = 100_000;

/// Checks the keys of `g(r)` and of the MSD: `pair_correlation` only with the
/// event-driven engine (DSMC positions carry no pair correlation: its grains are points
/// placed without excluded volume, and its contact value is the input `χ`), bins and range
/// within the box's exact normalisation, `msd_fit` a window `[from, to]`.
pub(super) fn validate_structure_and_transport(sc: &super::Scenario) -> Result<(), ScenarioError> {
    let o = &sc.output;
    if o.pair_correlation {
        if sc.kind() != super::EngineKind::Edmd {
            return Err(ScenarioError::new(
                "output.pair_correlation",
                "is true, but only the event-driven engine has pair correlations (DSMC grains are points without excluded volume; its contact value is the input chi in summary.json's resolved block); set it to false or use engine = \"edmd\"".to_string(),
            ));
        }
        if o.pair_correlation_bins == 0 || o.pair_correlation_bins > MAX_PAIR_BINS {
            return Err(ScenarioError::new(
                "output.pair_correlation_bins",
                format!(
                    "is {}; use between 1 and {MAX_PAIR_BINS} bins (default 200)",
                    o.pair_correlation_bins
                ),
            ));
        }
        let range = o.pair_correlation_range;
        let r_max_radius = (0..sc.species().len())
            .map(|s| sc.radius(s))
            .fold(0.0f64, f64::max);
        let lengths = sc.lengths();
        let axes = sc.axes();
        let limit = lengths
            .iter()
            .zip(&axes)
            .map(|(&l, a)| {
                if *a == crate::boundary::AxisKind::Periodic {
                    0.5 * l
                } else {
                    l - 2.0 * r_max_radius
                }
            })
            .fold(f64::INFINITY, f64::min);
        let largest = limit / (2.0 * r_max_radius);
        if !(range.is_finite() && range > 1.0 && range <= largest) {
            return Err(ScenarioError::new(
                "output.pair_correlation_range",
                format!(
                    "is {range}; give r_max in contact distances 2 R_max, above 1 and at most {largest:.4} in this box (half the shortest periodic edge, the shortest walled edge less a diameter; default 5)"
                ),
            ));
        }
    }
    if !o.msd_fit.is_empty() {
        let ok = o.msd_fit.len() == 2
            && o.msd_fit.iter().all(|t| t.is_finite() && *t >= 0.0)
            && o.msd_fit[0] < o.msd_fit[1];
        if !ok {
            return Err(ScenarioError::new(
                "output.msd_fit",
                format!(
                    "is {:?}; give the lag window [from, to] of the diffusion fit in time units, 0 <= from < to (or leave it out: 10 % to 50 % of the run)",
                    o.msd_fit
                ),
            ));
        }
    }
    Ok(())
}
