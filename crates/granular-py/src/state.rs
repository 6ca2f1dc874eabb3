//! Positions or velocities of every grain in input order, read straight from the engines'
//! public accessors: `Simulation.positions` without building a whole snapshot (the
//! library's `Simulation::snapshot` copies all five arrays; a single-array accessor there
//! would make this module unnecessary).

use granular::Simulation;
use granular::run::AnyEngine;

/// Which per-grain vector.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quantity {
    /// Positions (wrapped into the box).
    Positions,
    /// Velocities.
    Velocities,
}

/// `(values, n, d)`: row-major `n x d` values of grain ids `0..n`, or `None` when the
/// engine has no such accessor (the caller takes a snapshot instead).
pub fn by_id(sim: &Simulation, what: Quantity) -> Option<(Vec<f64>, usize, usize)> {
    match sim.engine() {
        AnyEngine::Edmd2(e) => Some(edmd(e, what)),
        AnyEngine::Edmd3(e) => Some(edmd(e, what)),
        AnyEngine::Dsmc2(e) => Some(dsmc(e, what)),
        AnyEngine::Dsmc3(e) => Some(dsmc(e, what)),
        AnyEngine::Intruder(_) => None,
    }
}

fn edmd<const D: usize>(e: &granular::edmd::Edmd<D>, what: Quantity) -> (Vec<f64>, usize, usize) {
    let n = e.len();
    let mut out = Vec::with_capacity(n * D);
    for id in 0..n {
        let v = match what {
            Quantity::Positions => e.position(id),
            Quantity::Velocities => e.velocity(id),
        };
        out.extend_from_slice(&v.0);
    }
    (out, n, D)
}

fn dsmc<const D: usize>(
    e: &granular::dsmc::DsmcEngine<D>,
    what: Quantity,
) -> (Vec<f64>, usize, usize) {
    let stored = match what {
        Quantity::Positions => e.positions(),
        Quantity::Velocities => e.velocities(),
    };
    let n = stored.len();
    let mut out = vec![0.0; n * D];
    for (k, &id) in e.ids().iter().enumerate() {
        let i = id as usize * D;
        out[i..i + D].copy_from_slice(&stored[k].0);
    }
    (out, n, D)
}
