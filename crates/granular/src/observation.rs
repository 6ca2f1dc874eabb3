//! What an engine reports at one instant: the typed [`Observation`], the same for every
//! engine, read without side effects; and the rates over a window between two
//! observations ([`Rates`]), which belong to whoever holds the earlier observation.
//!
//! Names are the same everywhere: the fields here, the columns of `timeseries.csv`, the
//! `final` block of `summary.json`, the Python dictionary and `docs/output.md`.

use serde::{Deserialize, Serialize};

/// Kinetic energy and temperature of one species at one instant.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SpeciesObservation {
    /// Species name, as in the scenario.
    pub name: String,
    /// Number of grains of this species.
    pub grains: usize,
    /// Kinetic energy per grain, `Σ m v² / 2 / N_s`, energy units.
    pub kinetic_energy_per_grain: f64,
    /// Granular temperature `T_s = Σ m v² / (D N_s)` (`k_B = 1`), energy units.
    pub temperature: f64,
    /// Fourth cumulant `a2` of the species' peculiar velocities (event-driven engine;
    /// `crate::moments::a2_by_species`).
    #[serde(default)]
    pub a2: Option<f64>,
}

/// Counters of the DSMC engine.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct DsmcCounters {
    /// Time steps taken.
    pub steps: u64,
    /// Accepted collisions whose relative speed exceeded the cell's bound `v_max` (each is
    /// a sign that the bound was too low when the pair was drawn).
    pub vmax_exceeded: u64,
}

/// The state of a simulation at one instant, as every engine reports it.
///
/// Cumulative quantities (counts, sums) are totals since `t = 0`; rates over an interval
/// come from two observations through [`Observation::rates_since`]. Reading an observation
/// changes nothing in the engine.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Observation {
    /// Engine name (`"edmd"`, `"dsmc"`, `"intruder"`).
    pub engine: String,
    /// Spatial dimension `D` (1 or 2 for the intruder engines).
    pub dimension: usize,
    /// Number of grains (1 for an intruder).
    pub particles: usize,
    /// Simulation time, in the scenario's time unit.
    pub time: f64,
    /// Events processed since `t = 0` (collisions and bookkeeping events).
    pub events: u64,
    /// Collisions since `t = 0`: grain-grain pair collisions in the many-grain engines,
    /// intruder-bath collisions for the intruder.
    pub collisions: u64,
    /// Collisions per grain, `2 × collisions / N` (many-grain engines).
    pub collisions_per_particle: f64,
    /// Total kinetic energy `Σ m v² / 2` (for the needle, translational plus rotational).
    pub kinetic_energy: f64,
    /// Granular temperature `T = 2 K / (D N)` of all grains, energy units (many-grain
    /// engines; for the intruder, its running temperature estimate).
    pub temperature: f64,
    /// Per species, when the scenario has more than one.
    pub species: Vec<SpeciesObservation>,
    /// Rotational kinetic energy `Σ I |ω|² / 2` of rough grains, energy units (`None` for
    /// smooth grains, which do not rotate). `kinetic_energy` and `temperature` are the
    /// translational ones.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rotational_energy: Option<f64>,
    /// Rotational temperature `T_r = 2 E_rot / (d_r N)` per rotational degree of freedom
    /// (`d_r` = 1 for disks, 3 for spheres), energy units; rough grains only.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rotational_temperature: Option<f64>,
    /// Grain-wall collisions since `t = 0` (event-driven engine).
    pub wall_collisions: Option<u64>,
    /// Kinetic energy lost in inelastic collisions since `t = 0` (event-driven engine).
    pub dissipated_energy: Option<f64>,
    /// Collisions made elastic by the TC model (HD section 2.3) since `t = 0`.
    pub tc_elastic_collisions: Option<u64>,
    /// Collisional virial `Σ (x_i - x_j) · Δp_i` over pair collisions since `t = 0`,
    /// energy units (event-driven engine; the pressure of a window comes from its change).
    pub virial: Option<f64>,
    /// Normal momentum transferred to the walls since `t = 0` (event-driven engine).
    pub wall_impulse: Option<f64>,
    /// Volume (2D: area) of the box, for pressures.
    pub volume: f64,
    /// Total area (2D: length) of the walls, zero in a periodic box.
    pub wall_area: f64,
    /// Fourth cumulant `a2 = D/(D+2) <c⁴>/<c²>² - 1` of the peculiar velocities (DSMC-4;
    /// the event-driven engine: `crate::moments::a2_by_species`).
    pub a2: Option<f64>,
    /// DSMC counters.
    pub dsmc: Option<DsmcCounters>,
    /// Quantities of one engine only, in the engine's documented order (the intruder
    /// engines: velocity, running averages with errors; `docs/output.md`).
    pub engine_specific: Vec<(String, f64)>,
}

/// Rates over the window between two observations of the same simulation.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Rates {
    /// Length of the window, in time units.
    pub interval: f64,
    /// Collisions per grain per unit time, `2 ΔN_c / (N Δt)`.
    pub collision_frequency: f64,
    /// `1 / collision_frequency`.
    pub mean_free_time: f64,
    /// Pressure from the virial theorem, `P = (2 K + ΔW / Δt) / (D V)` with `K` the
    /// kinetic energy at the end of the window (the virial theorem of hard grains, not
    /// a numbered equation of the source documents; NaN where the engine has no virial).
    pub pressure: f64,
    /// Momentum transferred to the walls per unit area and time (NaN without walls).
    pub wall_pressure: f64,
    /// Energy put in by a steady-state driving per unit time, `Δ injected_energy / Δt`
    /// (NaN without a driving, [`crate::driving`]).
    #[serde(default)]
    pub driving_power: f64,
    /// Energy lost in collisions per unit time, `Δ dissipated_energy / Δt` (NaN without a
    /// driving).
    #[serde(default)]
    pub dissipation_rate: f64,
    /// Rough grains: the cooling rate of the total (translational plus rotational) energy
    /// per collision of a grain, `ζ/ν`: `-Δ ln E / Δ(collisions per particle)` of a freely
    /// cooling gas, or the driving's loss rate over the energy and the collision frequency
    /// of a driven one (RS-5; NaN for smooth grains).
    #[serde(default = "not_a_number", skip_serializing_if = "is_nan")]
    pub reduced_cooling_rate: f64,
}

impl Rates {
    /// The rates of a window in which none is defined (empty, or no earlier observation).
    fn undefined(interval: f64) -> Rates {
        Rates {
            interval,
            collision_frequency: f64::NAN,
            mean_free_time: f64::NAN,
            pressure: f64::NAN,
            wall_pressure: f64::NAN,
            driving_power: f64::NAN,
            dissipation_rate: f64::NAN,
            reduced_cooling_rate: f64::NAN,
        }
    }
}

impl Observation {
    /// Rates over the window from `earlier` to `self` (NaN where the window is empty or
    /// the engine does not measure the quantity).
    pub fn rates_since(&self, earlier: &Observation) -> Rates {
        let dt = self.time - earlier.time;
        if dt <= 0.0 || !dt.is_finite() {
            return Rates::undefined(dt);
        }
        let n = self.particles as f64;
        let d = self.dimension as f64;
        let rate =
            2.0 * (self.collisions - earlier.collisions.min(self.collisions)) as f64 / (n * dt);
        let pressure = match (self.virial, earlier.virial) {
            (Some(w1), Some(w0)) => {
                (2.0 * self.kinetic_energy + (w1 - w0) / dt) / (d * self.volume)
            }
            _ => f64::NAN,
        };
        let wall_pressure = match (self.wall_impulse, earlier.wall_impulse) {
            (Some(j1), Some(j0)) if self.wall_area > 0.0 => (j1 - j0) / (self.wall_area * dt),
            _ => f64::NAN,
        };
        // Driven gases only (the event-driven engine's own dissipated energy stays out of
        // its columns).
        let driven = |o: &Observation| o.specific("injected_energy").is_some();
        let (driving_power, dissipation_rate) = if driven(self) && driven(earlier) {
            let change = |f: &dyn Fn(&Observation) -> Option<f64>| match (f(self), f(earlier)) {
                (Some(a), Some(b)) => (a - b) / dt,
                _ => f64::NAN,
            };
            (
                change(&|o| o.specific("injected_energy")),
                change(&|o| o.dissipated_energy),
            )
        } else {
            (f64::NAN, f64::NAN)
        };
        let reduced_cooling_rate = match (self.total_energy(), earlier.total_energy()) {
            (Some(_), Some(_)) if driven(self) && driven(earlier) => {
                2.0 * dissipation_rate / self.degrees_of_freedom_energy() / rate
            }
            (Some(e1), Some(e0)) => {
                let per_grain = self.collisions_per_particle - earlier.collisions_per_particle;
                -(e1.ln() - e0.ln()) / per_grain
            }
            _ => f64::NAN,
        };
        Rates {
            interval: dt,
            collision_frequency: rate,
            mean_free_time: if rate > 0.0 { 1.0 / rate } else { f64::NAN },
            pressure,
            wall_pressure,
            driving_power,
            dissipation_rate,
            reduced_cooling_rate,
        }
    }

    /// Rough grains: translational plus rotational kinetic energy (`None` for smooth
    /// grains).
    fn total_energy(&self) -> Option<f64> {
        self.rotational_energy.map(|e| self.kinetic_energy + e)
    }

    /// `N Σ_dof T`, twice the energy of the temperatures: `D N T` for smooth grains,
    /// `N (d_t T_t + d_r T_r)` for rough ones.
    fn degrees_of_freedom_energy(&self) -> f64 {
        let d = self.dimension as f64;
        match self.rotational_temperature {
            Some(t) => {
                let dr = crate::collision_law::rough::rotational_dof(self.dimension) as f64;
                self.particles as f64 * (d * self.temperature + dr * t)
            }
            None => d * self.particles as f64 * self.temperature,
        }
    }

    /// The observation as named values, in the column order of `timeseries.csv` for this
    /// engine; `rates` are those of the window that ends here (the event-driven engine's
    /// columns `collision_frequency`, `mean_free_time`, `pressure`, `wall_pressure`).
    pub fn columns(&self, rates: Option<&Rates>) -> Vec<(String, f64)> {
        let mut out = vec![("time".to_string(), self.time)];
        if self.engine == "intruder" {
            out.extend(self.engine_specific.iter().cloned());
            return out;
        }
        out.push(("kinetic_energy".into(), self.kinetic_energy));
        out.push(("temperature".into(), self.temperature));
        if let (Some(e), Some(t)) = (self.rotational_energy, self.rotational_temperature) {
            // Rough grains: the two temperatures per degree of freedom and their ratio.
            out.push(("rotational_energy".into(), e));
            out.push(("translational_temperature".into(), self.temperature));
            out.push(("rotational_temperature".into(), t));
            out.push(("temperature_ratio".into(), t / self.temperature));
            out.push((
                "reduced_cooling_rate".into(),
                rates.map_or(f64::NAN, |r| r.reduced_cooling_rate),
            ));
        }
        for s in &self.species {
            out.push((
                format!("kinetic_energy_per_grain.{}", s.name),
                s.kinetic_energy_per_grain,
            ));
            out.push((format!("temperature.{}", s.name), s.temperature));
        }
        out.push(("pair_collisions".into(), self.collisions as f64));
        if let Some(w) = self.wall_collisions {
            out.push(("wall_collisions".into(), w as f64));
        }
        out.push((
            "collisions_per_particle".into(),
            self.collisions_per_particle,
        ));
        if self.virial.is_some() {
            let nan = Rates::undefined(f64::NAN);
            let r = rates.unwrap_or(&nan);
            out.push(("collision_frequency".into(), r.collision_frequency));
            out.push(("mean_free_time".into(), r.mean_free_time));
            out.push(("pressure".into(), r.pressure));
            out.push(("wall_pressure".into(), r.wall_pressure));
        }
        if let Some(e) = self.dissipated_energy {
            out.push(("dissipated_energy".into(), e));
        }
        if let Some(a2) = self.a2 {
            out.push(("a2".into(), a2));
        }
        for s in &self.species {
            if let Some(a2) = s.a2 {
                out.push((format!("a2.{}", s.name), a2));
            }
        }
        if let Some(c) = &self.dsmc {
            out.push(("steps".into(), c.steps as f64));
            out.push(("vmax_exceeded".into(), c.vmax_exceeded as f64));
        }
        if let Some(tc) = self.tc_elastic_collisions {
            out.push(("tc_elastic_collisions".into(), tc as f64));
        }
        out.extend(self.engine_specific.iter().cloned());
        if self.specific("injected_energy").is_some() {
            // A driven gas: the window's power in and loss, and the cooling rate
            // `zeta = 2 (loss rate) / (D N T)` (`crate::driving`).
            let nan = Rates::undefined(f64::NAN);
            let r = rates.unwrap_or(&nan);
            // Rough grains: the energy is `N (d_t T_t + d_r T_r) / 2`.
            let dnt = self.degrees_of_freedom_energy();
            out.push(("driving_power".into(), r.driving_power));
            out.push(("dissipation_rate".into(), r.dissipation_rate));
            out.push(("cooling_rate".into(), 2.0 * r.dissipation_rate / dnt));
        }
        out
    }

    /// An engine-specific quantity by name ([`Observation::engine_specific`]).
    pub fn specific(&self, name: &str) -> Option<f64> {
        self.engine_specific
            .iter()
            .find(|(k, _)| k == name)
            .map(|(_, v)| *v)
    }

    /// The value of one column by name (see [`Observation::columns`]), without rates.
    pub fn get(&self, name: &str) -> Option<f64> {
        self.columns(None)
            .into_iter()
            .find(|(k, _)| k == name)
            .map(|(_, v)| v)
    }
}

impl Observation {
    /// The observation of a single intruder (`engine = "intruder"`): the common fields
    /// from the engine, `quantities` (the model's own, in column order) as
    /// [`Observation::engine_specific`]; the temperature is the model's running estimate.
    pub(crate) fn intruder(
        dimension: usize,
        time: f64,
        events: u64,
        collisions: u64,
        kinetic_energy: f64,
        quantities: Vec<(String, f64)>,
    ) -> Observation {
        let find = |k: &str| quantities.iter().find(|(n, _)| n == k).map(|(_, v)| *v);
        let temperature = find("temperature")
            .or_else(|| find("translational_temperature"))
            .unwrap_or(f64::NAN);
        Observation {
            engine: "intruder".into(),
            dimension,
            particles: 1,
            time,
            events,
            collisions,
            collisions_per_particle: f64::NAN,
            kinetic_energy,
            temperature,
            species: Vec::new(),
            rotational_energy: None,
            rotational_temperature: None,
            wall_collisions: None,
            dissipated_energy: None,
            tc_elastic_collisions: None,
            virial: None,
            wall_impulse: None,
            volume: f64::NAN,
            wall_area: 0.0,
            a2: None,
            dsmc: None,
            engine_specific: quantities,
        }
    }
}

/// Serde: an absent rate is NaN (`Rates::reduced_cooling_rate` of smooth grains).
fn not_a_number() -> f64 {
    f64::NAN
}

/// Serde: NaN rates are not written.
fn is_nan(x: &f64) -> bool {
    x.is_nan()
}
