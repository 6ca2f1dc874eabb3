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
