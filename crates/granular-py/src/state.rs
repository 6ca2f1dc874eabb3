//! Positions or velocities of every grain in input order, without building a whole
//! snapshot: the library's `Simulation::positions` / `velocities`.

use granular::Simulation;

/// Which per-grain vector.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quantity {
    /// Positions (wrapped into the box).
    Positions,
    /// Velocities.
    Velocities,
}

/// `(values, n, d)`: row-major `n x d` values of grain ids `0..n`, or `None` when the
/// engine has no grains (the caller takes a snapshot instead).
pub fn by_id(sim: &Simulation, what: Quantity) -> Option<(Vec<f64>, usize, usize)> {
    let values = match what {
        Quantity::Positions => sim.positions(),
        Quantity::Velocities => sim.velocities(),
    }?;
    Some((values, sim.particle_count(), sim.dimension()))
}
