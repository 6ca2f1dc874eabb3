//! The rotation of rough grains at the start of a run: κ of each species and the initial
//! angular velocities (`species[i].inertia`, `species[i].angular_velocity`).

use crate::collision_law::rough::rotational_dof;
use crate::random::{self, std_normal, stream};
use crate::scenario::{AngularVelocitySpec, Scenario};

/// Path of the angular-velocity stream under the scenario's seed, below the initial state's
/// prefix: spins are drawn from their own stream, so a rough scenario starts from the same
/// positions and velocities as the smooth one with the same seed.
const ROTATION: u64 = 1;

/// κ of each species of rough grains as the scenario resolves it
/// ([`crate::scenario::RoughResolved`]); `None` for smooth grains.
pub(super) fn inertia(scenario: &Scenario) -> Option<Vec<f64>> {
    scenario
        .collisions()
        .law()
        .is_rough()
        .then(|| scenario.resolve().grains.and_then(|g| g.rough))
        .flatten()
        .map(|r| r.inertia)
}

/// κ of each species (as the scenario resolves it, [`crate::scenario::RoughResolved`]) and
/// the angular velocities of every grain in scenario order (`d_r` values per grain;
/// radians per time unit), for a rough scenario; two empty lists for a smooth one. A Maxwell-Boltzmann spin has components of variance `T_r / I`,
/// `I = κ m R²`.
pub(super) fn rotation(scenario: &Scenario) -> (Vec<f64>, Vec<f64>) {
    let Some(inertia) = inertia(scenario) else {
        return (Vec::new(), Vec::new());
    };
    let r = rotational_dof(scenario.dimension);
    let mut rng = stream(scenario.seed, &[random::INITIAL_STATE, ROTATION]);
    let mut spins = Vec::new();
    for (s, sp) in scenario.species().iter().enumerate() {
        let kappa = inertia[s];
        let radius = scenario.radius(s);
        match &sp.angular_velocity {
            None | Some(AngularVelocitySpec::Zero) => {
                spins.extend(std::iter::repeat_n(0.0, r * sp.count));
            }
            Some(AngularVelocitySpec::MaxwellBoltzmann { temperature }) => {
                let width = (temperature / (kappa * sp.mass * radius * radius)).sqrt();
                for _ in 0..r * sp.count {
                    spins.push(width * std_normal(&mut rng));
                }
            }
            Some(AngularVelocitySpec::Given { angular_velocity }) => {
                for _ in 0..sp.count {
                    spins.extend_from_slice(angular_velocity);
                }
            }
        }
    }
    (inertia, spins)
}
