//! Grains set from outside a running simulation ([`crate::Simulation::set_state`],
//! [`crate::Simulation::from_state`]): the arrays a user gives, checked before anything
//! changes (lengths, finite values, inside the box or the walls, and for the event-driven
//! engine no overlap), then handed to the engine's `restart` as plain arrays.

use crate::boundary::SimulationBox;
use crate::build::{AnyEngine, BuildError};
use crate::collision_law::rough::rotational_dof;
use crate::engine::Engine;
use crate::particles::ParticleSet;
use crate::vector::Vector;

/// The per-grain arrays to set, row-major `n × D` by grain id (input order: grain `i` is
/// the `i`-th grain of the scenario's species list); `None` keeps the present values.
#[derive(Clone, Copy, Debug, Default)]
pub struct GrainState<'a> {
    /// Centre positions, length units.
    pub positions: Option<&'a [f64]>,
    /// Velocities, length / time.
    pub velocities: Option<&'a [f64]>,
    /// Angular velocities of rough grains, radians per time unit: `ω_z` per grain in 2D
    /// (`n` values), `ω_x, ω_y, ω_z` per grain in 3D (`n × 3`, row-major). Refused for
    /// smooth grains, which carry no rotation.
    pub angular_velocities: Option<&'a [f64]>,
}

/// The whole arrays an engine restarts from ([`checked`]): every grain's position and
/// velocity (`n × D`) and, for rough grains, angular velocity (`n × d_r`; empty for
/// smooth grains).
#[derive(Clone, Debug, Default)]
pub(crate) struct Arrays {
    pub positions: Vec<f64>,
    pub velocities: Vec<f64>,
    pub angular_velocities: Vec<f64>,
}

/// Why a state was refused (the simulation is unchanged).
#[derive(Debug, thiserror::Error)]
pub enum StateError {
    /// The engine has no grains (the intruder engines).
    #[error(
        "the {engine} engine has no grain state to set (no positions or velocities of grains); \
         set_state and from_snapshot take the engines with grains, edmd and dsmc"
    )]
    NoGrains {
        /// The engine's name.
        engine: &'static str,
    },
    /// An array has the wrong number of values.
    #[error(
        "`{array}` has {len} values; give {n} rows of {d} (one row per grain, in input order: \
         shape ({n}, {d}))"
    )]
    Shape {
        /// `positions` or `velocities`.
        array: &'static str,
        /// Values given.
        len: usize,
        /// Grains.
        n: usize,
        /// Dimension.
        d: usize,
    },
    /// `angular_velocities` of the wrong shape (one value per disk, three per sphere).
    #[error(
        "`angular_velocities` has {len} values; give shape {shape} (one row per grain, in \
         input order: {what})"
    )]
    SpinShape {
        /// Values given.
        len: usize,
        /// The shape to give: `(n,)` in 2D, `(n, 3)` in 3D.
        shape: String,
        /// What a row holds.
        what: &'static str,
    },
    /// Angular velocities given for smooth grains.
    #[error(
        "`angular_velocities` given, but the grains are smooth \
         (collisions.tangential_restitution = -1) and carry no rotation; leave \
         angular_velocities out, or start a simulation of rough grains \
         (collisions.tangential_restitution in (-1, 1])"
    )]
    Smooth,
    /// A value is NaN or infinite.
    #[error("`{array}[{grain}{}]` is {value}; give finite numbers", axis.map_or(String::new(), |a| format!(", {a}")))]
    NotFinite {
        /// `positions`, `velocities` or `angular_velocities`.
        array: &'static str,
        /// Grain (row).
        grain: usize,
        /// Axis (column; `None` for the one-column `angular_velocities` of disks).
        axis: Option<usize>,
        /// The value.
        value: f64,
    },
    /// A centre lies outside the box or closer to a wall than its radius.
    #[error(
        "`positions[{grain}, {axis}]` = {value} lies outside the box: along axis {axis} ({kind}) \
         the centre of grain {grain} must lie in [{lo}, {hi}]; move it inside"
    )]
    Outside {
        /// Grain (row).
        grain: usize,
        /// Axis (column).
        axis: usize,
        /// The coordinate.
        value: f64,
        /// `periodic` or `walls`, with the grain's radius where it matters.
        kind: String,
        /// Lowest admissible coordinate.
        lo: f64,
        /// Highest admissible coordinate.
        hi: f64,
    },
    /// Two grains overlap (event-driven engine).
    #[error(
        "grains {a} and {b} overlap (distance {distance} < sum of radii {sigma}); hard grains \
         may touch but not overlap: move them apart"
    )]
    Overlap {
        /// First grain (input order).
        a: usize,
        /// Second grain.
        b: usize,
        /// Centre distance (minimum image), length units.
        distance: f64,
        /// Sum of the radii.
        sigma: f64,
    },
    /// A time that is not a finite number, 0 or more.
    #[error("the time of the state is {0}; give a finite time, 0 or more")]
    Time(f64),
    /// The engine refused the state (a DSMC run split over ranks).
    #[error("{0}")]
    Engine(String),
    /// The scenario could not be built (`Simulation::from_state`).
    #[error(transparent)]
    Build(#[from] BuildError),
}

/// Checks `state` against an engine and returns the whole arrays to set (the present
/// positions, velocities or angular velocities where `state` leaves one out), nothing
/// changed.
pub(crate) fn checked(engine: &AnyEngine, state: GrainState<'_>) -> Result<Arrays, StateError> {
    match engine {
        AnyEngine::Edmd2(e) => {
            let radii = e.radii();
            check::<2>(engine, e.simulation_box(), &radii, true, state)
        }
        AnyEngine::Edmd3(e) => {
            let radii = e.radii();
            check::<3>(engine, e.simulation_box(), &radii, true, state)
        }
        // DSMC grains overlap freely and meet the walls with their centres.
        AnyEngine::Dsmc2(e) => check::<2>(engine, e.sim_box(), &[], false, state),
        AnyEngine::Dsmc3(e) => check::<3>(engine, e.sim_box(), &[], false, state),
        AnyEngine::Intruder(e) => Err(StateError::NoGrains { engine: e.name() }),
    }
}

/// The checks of [`checked`] in `D` dimensions: `radii` by id for an engine of hard
/// grains (`hard`: centres a radius from the walls, no overlap), empty otherwise.
fn check<const D: usize>(
    engine: &AnyEngine,
    bx: &SimulationBox<D>,
    radii: &[f64],
    hard: bool,
    state: GrainState<'_>,
) -> Result<Arrays, StateError> {
    let n = engine.particle_count();
    let angular_velocities = spins::<D>(engine, n, state.angular_velocities)?;
    let whole = |array: &'static str, given: Option<&[f64]>, velocities: bool| {
        let values = match given {
            Some(a) => a.to_vec(),
            None => {
                let mut out = vec![0.0; n * D];
                engine.state_into(velocities, &mut out);
                return Ok(out);
            }
        };
        if values.len() != n * D {
            return Err(StateError::Shape {
                array,
                len: values.len(),
                n,
                d: D,
            });
        }
        if let Some(i) = values.iter().position(|x| !x.is_finite()) {
            return Err(StateError::NotFinite {
                array,
                grain: i / D,
                axis: Some(i % D),
                value: values[i],
            });
        }
        Ok(values)
    };
    let positions = whole("positions", state.positions, false)?;
    let velocities = whole("velocities", state.velocities, true)?;
    if state.positions.is_some() {
        for (i, row) in positions.chunks_exact(D).enumerate() {
            for (k, &x) in row.iter().enumerate() {
                let l = bx.lengths[k];
                let r = if hard { radii[i] } else { 0.0 };
                let (lo, hi, kind) = if bx.is_periodic(k) {
                    (0.0, l, "periodic".to_string())
                } else if hard {
                    (r, l - r, format!("walls; radius {r}"))
                } else {
                    (0.0, l, "walls".to_string())
                };
                if !(lo..=hi).contains(&x) {
                    return Err(StateError::Outside {
                        grain: i,
                        axis: k,
                        value: x,
                        kind,
                        lo,
                        hi,
                    });
                }
            }
        }
        if hard {
            let set = ParticleSet {
                positions: positions
                    .chunks_exact(D)
                    .map(|c| Vector::<D>::from_slice(c).unwrap_or_default())
                    .collect(),
                velocities: Vec::new(),
                radii: radii.to_vec(),
                masses: Vec::new(),
                ..Default::default()
            };
            crate::setup::check_overlaps(bx, &set).map_err(|o| StateError::Overlap {
                a: o.a,
                b: o.b,
                distance: o.distance,
                sigma: o.sigma,
            })?;
        }
    }
    Ok(Arrays {
        positions,
        velocities,
        angular_velocities,
    })
}

/// The angular velocities to set in `D` dimensions: `given` checked (rough grains only, `n`
/// values in 2D, `n × 3` in 3D, finite), or the present ones (empty for smooth grains).
fn spins<const D: usize>(
    engine: &AnyEngine,
    n: usize,
    given: Option<&[f64]>,
) -> Result<Vec<f64>, StateError> {
    let Some(values) = given else {
        return Ok(engine.angular_velocities());
    };
    if !engine.is_rough() {
        return Err(StateError::Smooth);
    }
    let r = rotational_dof(D);
    if values.len() != n * r {
        return Err(StateError::SpinShape {
            len: values.len(),
            shape: if r == 1 {
                format!("({n},)")
            } else {
                format!("({n}, {r})")
            },
            what: if r == 1 {
                "ω_z of each disk, about the axis normal to the plane"
            } else {
                "ω_x, ω_y, ω_z of each sphere"
            },
        });
    }
    if let Some(i) = values.iter().position(|x| !x.is_finite()) {
        return Err(StateError::NotFinite {
            array: "angular_velocities",
            grain: i / r,
            axis: (r > 1).then_some(i % r),
            value: values[i],
        });
    }
    Ok(values.to_vec())
}
