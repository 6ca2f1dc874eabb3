//! The set-up of a decomposed engine on its own rank: [`DsmcEngine::new_decomposed`]
//! creates only the rank's slab of the uniform gas of [`DsmcEngine::new`], bit for bit the
//! slab that [`DsmcEngine::decompose`] keeps of the whole engine, without ever holding the
//! whole system.
//!
//! The initial state is one random stream `(seed, [INITIAL_STATE])`: first every grain's
//! position (`D` uniform numbers each, in the order of the ids), then every grain's
//! velocity (`D` Gaussian numbers each). Every rank walks the whole stream (`O(N)` time,
//! no memory) and keeps the grains whose cell lies in its slab (`O(N / K)` memory). The
//! global sums of the set-up (the mean velocity that is removed, the sum of squares that
//! fixes the temperature, the initial temperature of the automatic time step) are
//! sequential sums in the order of the ids over all grains, which every rank redraws and
//! sums itself: the same bits as the whole engine without any communication, at the cost
//! of drawing the velocities again for each sum.

use super::{Derived, DsmcEngine, DsmcError};
use crate::boundary::SimulationBox;
use crate::dsmc::cells::CellIndex;
use crate::dsmc::config::DsmcConfig;
use crate::dsmc::domain::{Communicator, Domain};
use crate::random::{INITIAL_STATE, RngExt, Stream, stream};
use crate::vector::Vector;
use rand_distr::{Distribution, StandardNormal};
use std::sync::Arc;

/// The uniform gas of [`DsmcEngine::new`]: `n` grains of radius `radius` and mass `mass`
/// (simulation units) at temperature `temperature` (`k_B = 1`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UniformGas {
    /// Grains in the whole system.
    pub n: usize,
    /// Grain radius.
    pub radius: f64,
    /// Grain mass.
    pub mass: f64,
    /// Kinetic temperature of the initial state, exactly (after the rescaling).
    pub temperature: f64,
}

/// `D` standard Gaussian numbers: one grain's raw velocity, as [`DsmcEngine::new`] draws it.
fn gaussian<const D: usize>(rng: &mut Stream) -> Vector<D> {
    let mut v = Vector::<D>::zero();
    for k in 0..D {
        v[k] = StandardNormal.sample(rng);
    }
    v
}

impl<const D: usize> DsmcEngine<D> {
    /// [`DsmcEngine::new`] split over the ranks of `comm` from the start (collective): this
    /// rank's slab, bit for bit what [`DsmcEngine::decompose`] keeps of the whole engine,
    /// built in `O(N)` time and `O(N / K)` memory (see the module docs of
    /// `dsmc::engine::slab`). Errors as `new`, and when there are more ranks than cell
    /// planes along the last axis.
    pub fn new_decomposed(
        config: DsmcConfig,
        sim_box: SimulationBox<D>,
        gas: UniformGas,
        seed: u64,
        comm: Arc<dyn Communicator>,
    ) -> Result<Self, DsmcError> {
        let UniformGas {
            n,
            radius,
            mass,
            temperature,
        } = gas;
        if n < 2 {
            return Err(DsmcError::Invalid(format!(
                "need at least 2 particles, got {n}"
            )));
        }
        if !super::positive(temperature) {
            return Err(DsmcError::Invalid(format!(
                "temperature {temperature} must be > 0"
            )));
        }
        let positions = stream(seed, &[INITIAL_STATE]);
        // The velocities' part of the stream starts after every position.
        let mut velocities = positions.clone();
        for _ in 0..n * D {
            let _: f64 = velocities.random();
        }
        let draw = |each: &mut dyn FnMut(Vector<D>)| {
            let mut rng = velocities.clone();
            for _ in 0..n {
                each(gaussian::<D>(&mut rng));
            }
        };
        // The set-up sums of `new`, in the order of the ids.
        let mut mean = Vector::<D>::zero();
        draw(&mut |v| mean += v);
        mean = mean * (1.0 / n as f64);
        let mut sum2 = 0.0;
        draw(&mut |mut v| {
            v -= mean;
            sum2 += v.norm_squared();
        });
        let scale = (temperature * (D * n) as f64 / (mass * sum2)).sqrt();
        let rescaled = |mut v: Vector<D>| {
            v -= mean;
            v * scale
        };
        // The initial temperature of `from_state` (only for the automatic time step).
        let t0 = || {
            let mut u = Vector::<D>::zero();
            draw(&mut |v| u += rescaled(v));
            u = u * (1.0 / n as f64);
            let mut rng = velocities.clone();
            mass * (0..n)
                .map(|_| (rescaled(gaussian::<D>(&mut rng)) - u).norm_squared())
                .sum::<f64>()
                / (D * n) as f64
        };
        let derived = Derived::new(&config, &sim_box, n, radius, mass, t0)?;
        let domain = Domain::new(comm, &derived.grid.dims, n)?;
        let (pos, ids) = slab_positions(&derived, &sim_box, &domain, n, positions)?;
        let mut vel = Vec::with_capacity(ids.len());
        let mut rng = velocities;
        let mut next = ids.iter().peekable();
        for id in 0..n as u32 {
            let v = gaussian::<D>(&mut rng);
            if next.peek() == Some(&&id) {
                next.next();
                vel.push(rescaled(v));
            }
        }
        Ok(Self::assemble(
            config,
            sim_box,
            radius,
            mass,
            seed,
            derived,
            pos,
            vel,
            ids,
            Some(domain),
            None,
        ))
    }
}

/// The positions (drawn from `rng`, in the order of the ids) of the grains whose cell
/// lies in `domain`'s slab, with their ids.
fn slab_positions<const D: usize>(
    derived: &Derived<D>,
    sim_box: &SimulationBox<D>,
    domain: &Domain,
    n: usize,
    mut rng: Stream,
) -> Result<(Vec<Vector<D>>, Vec<u32>), DsmcError> {
    let cells = domain.cells.clone();
    let index = CellIndex::new(&derived.grid, &derived.lattice);
    // The slab's expected share, with room for the fluctuations (no doubling on the way).
    let share = n as f64 * cells.len() as f64 / derived.grid.len() as f64;
    let capacity = ((share + 6.0 * share.sqrt() + 64.0) as usize).min(n);
    let mut pos = Vec::with_capacity(capacity);
    let mut ids = Vec::with_capacity(capacity);
    for id in 0..n as u32 {
        let mut x = Vector::<D>::zero();
        for k in 0..D {
            x[k] = rng.random::<f64>() * sim_box.lengths[k];
        }
        derived.place(sim_box, &mut x)?;
        if cells.contains(&(index.of(&derived.lattice.words(&x, id)) as usize)) {
            pos.push(x);
            ids.push(id);
        }
    }
    Ok((pos, ids))
}
