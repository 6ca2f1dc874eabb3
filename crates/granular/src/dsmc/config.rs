//! The configuration of the DSMC engine (the scenario's `[dsmc]` table is read into it):
//! every numerical choice, and the rules of the automatic time step and cell size, written
//! once here for the engine and the scenario's resolved values.

use crate::collision_law::CollisionLaw;
use serde::{Deserialize, Serialize};

/// How the upper bound `v_max` on the relative speed (DSMC-1 and DSMC-2)
/// is obtained.
///
/// Whatever the mode, `v_max` is *raised* inside a cell as soon as a candidate pair has
/// `|v_i - v_j| > v_max` (Bird's rule); such events are counted in the scalar
/// `vmax_exceeded`. Because `|v_i - v_j| <= 2 max_k |v_k - c|` for any velocity `c`, both
/// modes give a strict bound at the start of the cell's collision stage; it can only be
/// exceeded after collisions inside the same cell and step have raised a speed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum VmaxMode {
    /// Per cell and step: `v_max = 2 max_{i in cell} |v_i - u_c|`, `u_c` the cell's mean
    /// velocity. The tightest cheap bound (best acceptance rate). Default.
    #[default]
    Cell,
    /// Global, per step: `v_max = 2 max_i |v_i - u|`, `u` the mean velocity of all
    /// particles (Müller & Herrmann's "twice the maximum particle velocity", sampled every step).
    Global,
}

/// Which packing fraction enters the dense-gas corrections (Enskog factor, free volume).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DensityScope {
    /// The packing fraction of the whole box, `phi = N v_p / V` (default; the Enskog
    /// correction is then exactly a factor `chi(phi)` on every cell's rate).
    #[default]
    Global,
    /// The packing fraction of the cell, `phi_c = N_c v_p / V_c` (resolves density
    /// inhomogeneities, e.g. clusters, but fluctuates with the cell occupation).
    Cell,
}

/// Configuration of the DSMC engine (the scenario's `[dsmc]` table).
///
/// Units: lengths in the scenario's length unit, times in its time unit; `k_B = 1`.
/// Equation numbers refer to Müller & Herrmann, "DSMC - a stochastic algorithm for
/// granular matter". See `docs/dsmc.md`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct DsmcConfig {
    /// Time step `tau` (time units) of the operator splitting: free flight, then
    /// collisions. `None`: one tenth of the initial Boltzmann (or Enskog) mean free time.
    /// Should be well below the mean free time (validity condition iii of Müller & Herrmann's DSMC paper).
    pub time_step: Option<f64>,
    /// Requested linear cell size `L` (length units), `V_c = L^D`. The number of cells
    /// along axis `k` is `max(1, floor(L_k / L))`, so the actual cell edge `L_k / n_k` is
    /// at least `L` (exactly `L` when `L_k` is a multiple). `None`: the smaller of the
    /// initial mean free path and the edge holding 10 particles on average.
    pub cell_size: Option<f64>,
    /// The collision law, the same as the event-driven engine's (the scenario's
    /// `[collisions]` table): pair restitution `e` (HD-11 with a random impact parameter;
    /// DSMC-2 picks the pair), the wall law with normal and tangential restitution (HD-3,
    /// HD-4), and the TC model with its counter. See [`CollisionLaw`].
    pub law: CollisionLaw,
    /// Constant acceleration (gravity), `D` components (length / time^2), applied
    /// analytically in the free-flight stage. Empty: no external force.
    pub gravity: Vec<f64>,
    /// Policy for the relative-speed bound `v_max` of DSMC-1 and DSMC-2.
    pub vmax_mode: VmaxMode,
    /// Multiply DSMC-1 by the Enskog contact value `chi(phi)` (Henderson in 2D,
    /// Carnahan-Starling in 3D).
    pub enskog: bool,
    /// Replace `V_c` in DSMC-1 by the free volume `V_c - V_b / nu_rcp` (`V_b` the volume
    /// of the beads in the cell, `nu_rcp` = 0.82 in 2D, 0.64 in 3D). Always uses the
    /// cell's own bead volume.
    pub free_volume: bool,
    /// Where the packing fraction for the Enskog factor is measured.
    pub density_scope: DensityScope,
    /// Consistent-Boltzmann advection (Alexander, Garcia & Alder 1995): after a
    /// collision each partner is displaced by `2R` along its momentum change.
    pub consistent_boltzmann: bool,
    /// Number of bins of the impact-parameter histogram (`b / 2R` in `[0, 1)`); the
    /// scenario key `dsmc.impact_bins`.
    pub impact_bins: usize,
}

impl Default for DsmcConfig {
    fn default() -> Self {
        Self {
            time_step: None,
            cell_size: None,
            law: CollisionLaw::default(),
            gravity: Vec::new(),
            vmax_mode: VmaxMode::Cell,
            enskog: false,
            free_volume: false,
            density_scope: DensityScope::Global,
            consistent_boltzmann: false,
            impact_bins: 20,
        }
    }
}

/// The automatic time step as a fraction of the mean free time `1 / omega` (DSMC-3): 0.1,
/// recomputed before every step from the current temperature.
pub const STEP_FRACTION: f64 = 0.1;

/// The time step of a gas that does not collide (at rest): one time unit, until it moves.
pub(crate) const AT_REST_TIME_STEP: f64 = 1.0;

/// The automatic time step, [`STEP_FRACTION`] of the mean free time `1 / omega` at the
/// collision frequency `omega` (KT-5, 1/time); `None` when `omega` gives no finite step (a
/// gas at rest). The engine applies it before every step
/// (`DsmcEngine::follow_mean_free_time`); the scenario's resolved values report it.
pub fn automatic_time_step(collision_frequency: f64) -> Option<f64> {
    let tau = STEP_FRACTION / collision_frequency;
    (collision_frequency > 0.0 && tau.is_finite()).then_some(tau)
}

/// The default cell edge: the smaller of the mean free path `mean_free_path` (KT-6) and
/// the edge of a cell holding 10 grains on average at number density `number_density`,
/// `(10 / n)^(1/D)` (length units).
pub(crate) fn default_cell_size(dimension: usize, number_density: f64, mean_free_path: f64) -> f64 {
    mean_free_path.min((10.0 / number_density).powf(1.0 / dimension as f64))
}
