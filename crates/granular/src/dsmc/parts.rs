//! Checkpoints and snapshots of a decomposed engine without gathering it on one rank
//! (see [`super::domain`] for the decomposition).
//!
//! * **Checkpoint parts**: every rank keeps its slab as an [`EnginePart`] (its cells'
//!   storage ranges and its particles in storage order); the parts, put in the order of
//!   their cells, are the whole engine's storage. A run resumed on any number of ranks
//!   reads only the parts whose cells overlap its own slab ([`DsmcEngine::load_parts`]);
//!   one rank (or the threaded build) reads them all.
//! * **Snapshots**: the particles are sent to the rank that owns their block of grain ids
//!   (rank `q` owns ids `q N / K .. (q + 1) N / K`), so each rank holds `N / K` of them in
//!   id order, the order of a snapshot's rows ([`DsmcEngine::id_block`]).

use super::domain::{Communicator, Domain};
use super::engine::DsmcEngine;
use super::grains::Grains;
use super::lattice::Lattice;
use crate::vector::Vector;
use serde::{Deserialize, Serialize};
use std::ops::Range;
use std::sync::Arc;

/// One rank's particles in a checkpoint: the cells `first_cell ..` `first_cell +
/// start.len() - 1`, their storage ranges, and the particles in storage order.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct EnginePart<const D: usize> {
    first_cell: usize,
    /// Storage offset of each cell of the part (relative to the part), then its length.
    start: Vec<u32>,
    /// The particles, in storage order.
    grains: Grains<D>,
}

impl<const D: usize> EnginePart<D> {
    /// The cells the part covers (linear cell indices).
    pub(crate) fn cells(&self) -> Range<usize> {
        self.first_cell..self.first_cell + self.start.len().saturating_sub(1)
    }

    /// Particles in the part.
    pub fn len(&self) -> usize {
        self.grains.len()
    }

    /// Whether the part holds no particle.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Whether the part is consistent (offsets rising from 0 to its length, arrays of one
    /// length): a part that reads but fails this was not written by this engine.
    fn consistent(&self, lattice: &Lattice<D>) -> bool {
        let n = self.grains.len();
        self.start.first() == Some(&0)
            && self.start.last().map(|&s| s as usize) == Some(n)
            && self.start.windows(2).all(|w| w[0] <= w[1])
            && self.grains.consistent(lattice)
    }
}

/// Where a part of a checkpoint is and what it covers (in the checkpoint's manifest).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub(crate) struct PartInfo {
    /// Its file name, relative to the run directory.
    pub file: String,
    /// The first cell it covers.
    pub first_cell: usize,
    /// One past its last cell.
    pub end_cell: usize,
    /// Its particles.
    pub particles: usize,
}

impl<const D: usize> DsmcEngine<D> {
    /// The cells this engine holds: its slab when decomposed, every cell otherwise.
    pub(super) fn owned_cells(&self) -> Range<usize> {
        self.domain
            .as_ref()
            .map_or(0..self.grid.len(), |d| d.cells.clone())
    }

    /// This rank's particles as a checkpoint part (the whole engine's when it is not
    /// decomposed). Local: no communication.
    pub fn part(&self) -> EnginePart<D> {
        EnginePart {
            first_cell: self.owned_cells().start,
            start: self.start.clone(),
            grains: self.grains.clone(),
        }
    }

    /// Puts the particles of a checkpoint's parts back into a `DsmcEngine::shell`:
    /// with `comm` of several ranks this rank's slab only (collective; the engine is then
    /// decomposed), reading only the parts whose cells overlap it; without, the whole
    /// engine from every part. `parts` lists the parts in the order of their cells, which
    /// must cover the grid once; `read` loads one. `n_global` is the particle count of
    /// the whole engine.
    pub(crate) fn load_parts(
        &mut self,
        comm: Option<Arc<dyn Communicator>>,
        n_global: usize,
        parts: &[PartInfo],
        mut read: impl FnMut(&PartInfo) -> Result<EnginePart<D>, String>,
    ) -> Result<(), String> {
        let cells = self.grid.len();
        let covered = parts.first().map(|p| p.first_cell) == Some(0)
            && parts.last().map(|p| p.end_cell) == Some(cells)
            && parts.windows(2).all(|w| w[0].end_cell == w[1].first_cell)
            && parts.iter().map(|p| p.particles).sum::<usize>() == n_global;
        if !covered {
            return Err(format!(
                "its parts do not cover the {cells} cells and {n_global} particles once \
                 (a part from another checkpoint?)"
            ));
        }
        let domain = match comm {
            Some(c) if c.size() > 1 => {
                Some(Domain::new(c, &self.grid.dims, n_global).map_err(|e| e.to_string())?)
            }
            _ => None,
        };
        let mine = domain.as_ref().map_or(0..cells, |d| d.cells.clone());
        let tc = self.config().law.has_tc();
        let rough = self.is_rough();
        let lattice = *self.grains.lattice();
        let mut start = vec![0u32; mine.len() + 1];
        let mut grains = Grains::new(lattice, tc);
        if rough {
            grains.set_spins(Some(&[]));
        }
        for info in parts {
            let lo = info.first_cell.max(mine.start);
            let hi = info.end_cell.min(mine.end);
            if lo >= hi {
                continue;
            }
            let part = read(info)?;
            if !part.consistent(&lattice)
                || part.cells() != (info.first_cell..info.end_cell)
                || part.len() != info.particles
                || part.grains.has_collision_times() != tc
                || part.grains.is_rough() != rough
            {
                return Err(format!(
                    "{} does not hold what the checkpoint lists (cells {}..{}, {} particles)",
                    info.file, info.first_cell, info.end_cell, info.particles
                ));
            }
            let at = |c: usize| part.start[c - info.first_cell] as usize;
            let (a, b) = (at(lo), at(hi));
            for c in lo..hi {
                start[c - mine.start] = (grains.len() + at(c) - a) as u32;
            }
            grains.extend_from(&part.grains, a..b);
        }
        let n = grains.len();
        start[mine.len()] = n as u32;
        self.dest = Vec::new();
        self.grains = grains;
        self.start = start;
        if let Some(d) = &domain {
            d.hold(n);
        }
        self.domain = domain;
        Ok(())
    }

    /// The grains of ids `lo .. hi` (this rank's block of `K` equal blocks of the ids,
    /// `lo = r N / K`), positions and velocities in id order: every rank sends its
    /// particles to the owners of their ids (collective), in rounds of at most
    /// `setup::round_length` grains. Together the blocks are a snapshot's rows; no rank
    /// holds more than its block and one round's buffers. Not decomposed: every grain.
    pub(crate) fn id_block(&self) -> IdBlock<D> {
        let Some(domain) = self.domain.as_ref() else {
            let (positions, velocities) = self.state_by_id();
            return IdBlock {
                first: 0,
                positions,
                velocities,
                angular_velocities: self.angular_velocities(),
            };
        };
        let (k, n, me) = (domain.size(), domain.n_global, domain.rank());
        let block = |q: usize| q * n / k..(q + 1) * n / k;
        let g = &self.grains;
        // Angular velocity components per grain (0: smooth grains).
        let r = if g.is_rough() {
            crate::collision_law::rough::rotational_dof(D)
        } else {
            0
        };
        let w = 1 + 2 * D + r;
        let mine = block(me);
        let mut positions = vec![Vector::zero(); mine.len()];
        let mut velocities = vec![Vector::zero(); mine.len()];
        let mut angular_velocities = vec![0.0; r * mine.len()];
        // In rounds of at most `round` grains of every rank's storage, so that the
        // buffers stay a small part of what a rank holds (every rank takes part in every
        // round: as many as the longest rank needs).
        let longest = domain.max_f64(g.len() as f64) as usize;
        let round = crate::dsmc::setup::round_length(n.div_ceil(k));
        for round_index in 0..longest.div_ceil(round).max(1) {
            let range =
                (round_index * round).min(g.len())..((round_index + 1) * round).min(g.len());
            let mut out: Vec<Vec<f64>> = vec![Vec::new(); k];
            for i in range {
                let id = g.id(i) as usize;
                if mine.contains(&id) {
                    // Grains of this rank's own block go straight to their rows.
                    positions[id - mine.start] = g.position(i);
                    velocities[id - mine.start] = g.velocity(i);
                    let at = r * (id - mine.start);
                    angular_velocities[at..at + r].copy_from_slice(&g.spin(i)[3 - r..]);
                    continue;
                }
                // The owner of id: the largest q with q n / k <= id.
                let mut q = (id * k / n).min(k - 1);
                while block(q).start > id {
                    q -= 1;
                }
                while block(q).end <= id {
                    q += 1;
                }
                let o = &mut out[q];
                o.push(f64::from_bits(id as u64));
                o.extend_from_slice(&g.position(i).0);
                o.extend_from_slice(&g.velocity(i).0);
                o.extend_from_slice(&g.spin(i)[3 - r..]);
            }
            let sent: usize = out.iter().map(|v| v.len() / w).sum();
            let incoming = domain.exchange(out);
            let received: usize = incoming.iter().map(|v| v.len() / w).sum();
            domain.hold(g.len() + mine.len() + sent + received);
            for rec in incoming.iter().flat_map(|v| v.chunks_exact(w)) {
                let slot = rec[0].to_bits() as usize - mine.start;
                positions[slot] = Vector::from_slice(&rec[1..1 + D]).unwrap_or_default();
                velocities[slot] = Vector::from_slice(&rec[1 + D..1 + 2 * D]).unwrap_or_default();
                angular_velocities[r * slot..r * slot + r].copy_from_slice(&rec[1 + 2 * D..w]);
            }
        }
        IdBlock {
            first: mine.start,
            positions,
            velocities,
            angular_velocities,
        }
    }
}

/// A block of consecutive grain ids with their positions and velocities
/// ([`DsmcEngine::id_block`]).
#[derive(Clone, Debug)]
pub(crate) struct IdBlock<const D: usize> {
    /// The first id of the block.
    pub first: usize,
    /// Positions of ids `first ..`.
    pub positions: Vec<Vector<D>>,
    /// Velocities of ids `first ..`.
    pub velocities: Vec<Vector<D>>,
    /// Angular velocities of ids `first ..` (`d_r` values each) of rough grains; empty for
    /// smooth grains.
    pub angular_velocities: Vec<f64>,
}
