//! Checkpoints and snapshots of a DSMC run decomposed over ranks, written without
//! gathering the particles on any rank (`docs/output.md`, "Runs over several ranks"):
//!
//! * a checkpoint is one part per rank, `checkpoint.parts/GGGGGG_RRRR.msgpack` (its
//!   slab's particles, with the checkpoint header and CRC-32), then rank 0's
//!   `checkpoint.msgpack`, the manifest: the engine without particles, the outputs, and the
//!   list of parts of generation `GGGGGG`. The manifest is renamed into place only once
//!   every part is on disk, and the parts of earlier generations are removed only after
//!   that, so a crash at any moment leaves one complete checkpoint;
//! * a snapshot is the single `.npz` of the threaded run (same members, same bytes): every
//!   rank writes its block of grain ids to a temporary file beside it, rank 0 copies the
//!   blocks into the archive piece by piece, and the temporary files are removed.

use super::{AnyEngine, RunError, checkpoint, io_err};
use crate::dsmc::{Communicator, Domain, DsmcEngine, EnginePart, PartInfo};
use crate::engine::Engine;
use crate::output::npz::{Fill, StreamedSnapshot, write_snapshot_streamed};
use crate::simulation::Simulation;
use serde::{Deserialize, Serialize};
use std::io::{BufWriter, Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The folder of the checkpoint parts in the run directory.
pub(crate) const PARTS_DIR: &str = super::dir::CHECKPOINT_PARTS;

/// What a decomposed run's `checkpoint.msgpack` says about its parts.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub(crate) struct Manifest {
    /// The checkpoint's number, in the parts' file names.
    pub generation: u64,
    /// Particles in all parts.
    pub particles: usize,
    /// The parts in the order of their cells.
    pub parts: Vec<PartInfo>,
    /// The ranks' per-grain output state (the MSD's), one file per rank in the order of
    /// the blocks of ids: `(file, first grain, grains)`. Empty when there is none.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub rows: Vec<(String, usize, usize)>,
}

/// Every rank's `ok` (collective): the first rank that failed, if any.
pub(crate) fn first_failure(domain: &Domain, ok: bool) -> Option<usize> {
    domain
        .all_gather(&[f64::from(u8::from(ok))])
        .iter()
        .position(|v| v[0] == 0.0)
}

/// Writes this rank's part of checkpoint `generation` into `shared` (the run directory
/// all ranks see), collectively: every rank returns the manifest's list of parts, or an
/// error when any rank failed (the previous checkpoint is then intact).
pub(crate) fn write_parts(
    engine: &AnyEngine,
    shared: &Path,
    generation: u64,
) -> Result<Manifest, RunError> {
    match engine {
        AnyEngine::Dsmc2(e) => write_parts_of(e, shared, generation),
        AnyEngine::Dsmc3(e) => write_parts_of(e, shared, generation),
        other => Err(RunError::CheckpointWrite {
            path: shared.join(PARTS_DIR),
            message: format!("the {} engine is not decomposed", other.name()),
        }),
    }
}

fn write_parts_of<const D: usize>(
    e: &DsmcEngine<D>,
    shared: &Path,
    generation: u64,
) -> Result<Manifest, RunError> {
    let Some(domain) = e.domain() else {
        return Err(RunError::CheckpointWrite {
            path: shared.join(PARTS_DIR),
            message: "the engine is not decomposed".into(),
        });
    };
    let rank = domain.rank();
    let file = format!("{PARTS_DIR}/{generation:06}_{rank:04}.msgpack");
    let path = shared.join(&file);
    let part = e.part();
    let result = std::fs::create_dir_all(shared.join(PARTS_DIR))
        .map_err(io_err(&path))
        .and_then(|()| {
            let bytes = rmp_serde::to_vec(&part).map_err(|err| RunError::CheckpointWrite {
                path: path.clone(),
                message: err.to_string(),
            })?;
            checkpoint::write_atomic(&path, &checkpoint::encode(&bytes))
        });
    let cells = part.cells();
    let words: Vec<f64> = [cells.start, cells.end, part.len()]
        .iter()
        .map(|&x| f64::from_bits(x as u64))
        .collect();
    let failed = first_failure(domain, result.is_ok());
    result?;
    if let Some(r) = failed {
        return Err(RunError::CheckpointWrite {
            path: shared.join(PARTS_DIR),
            message: format!(
                "rank {r} could not write its part (its message is above); the previous \
                 checkpoint is intact"
            ),
        });
    }
    let all = domain.all_gather(&words);
    let parts = all
        .iter()
        .enumerate()
        .map(|(r, w)| PartInfo {
            file: format!("{PARTS_DIR}/{generation:06}_{r:04}.msgpack"),
            first_cell: w[0].to_bits() as usize,
            end_cell: w[1].to_bits() as usize,
            particles: w[2].to_bits() as usize,
        })
        .collect();
    Ok(Manifest {
        generation,
        particles: domain.n_global,
        parts,
        rows: Vec::new(),
    })
}

/// Writes this rank's per-grain output state (`rows`, its block of ids) into checkpoint
/// `generation`'s parts (collective): every rank returns the list of the ranks' files.
fn write_rows(
    domain: &Domain,
    shared: &Path,
    generation: u64,
    rows: Option<&crate::transport::GrainRows>,
) -> Result<Vec<(String, usize, usize)>, RunError> {
    let rank = domain.rank();
    let file = format!("{PARTS_DIR}/{generation:06}_{rank:04}.rows.msgpack");
    let path = shared.join(&file);
    let result = match rows {
        Some(r) => rmp_serde::to_vec(r)
            .map_err(|err| RunError::CheckpointWrite {
                path: path.clone(),
                message: err.to_string(),
            })
            .and_then(|bytes| checkpoint::write_atomic(&path, &checkpoint::encode(&bytes))),
        None => Ok(()),
    };
    let failed = first_failure(domain, result.is_ok());
    result?;
    if let Some(r) = failed {
        return Err(RunError::CheckpointWrite {
            path: shared.join(PARTS_DIR),
            message: format!(
                "rank {r} could not write its part (its message is above); the previous \
                 checkpoint is intact"
            ),
        });
    }
    let words: Vec<f64> = match rows {
        Some(r) => vec![f64::from_bits(r.first as u64), f64::from_bits(r.len as u64)],
        None => Vec::new(),
    };
    Ok(domain
        .all_gather(&words)
        .iter()
        .enumerate()
        .filter(|(_, w)| w.len() == 2)
        .map(|(q, w)| {
            (
                format!("{PARTS_DIR}/{generation:06}_{q:04}.rows.msgpack"),
                w[0].to_bits() as usize,
                w[1].to_bits() as usize,
            )
        })
        .collect())
}

/// Puts the per-grain output state of a checkpoint back into `outputs` for this
/// process's grains (collective only in what `simulation` already is): over ranks its
/// block of ids, cut from the ranks' files of a decomposed checkpoint or from the
/// manifest's whole state of a threaded one; on one rank every grain.
pub(super) fn restore_rows(
    outputs: &mut super::StandardOutputs,
    simulation: &Simulation,
    manifest: Option<&Manifest>,
    shared: &Path,
) -> Result<(), RunError> {
    let n = simulation.particle_count();
    let (rank, k) = simulation
        .engine()
        .domain()
        .map_or((0, 1), |d| (d.rank(), d.size()));
    let block = crate::dsmc::setup::id_block(n, rank, k);
    let parts: Vec<crate::transport::GrainRows> = match manifest {
        Some(m) if !m.rows.is_empty() => {
            let mut parts = Vec::new();
            for (file, first, len) in &m.rows {
                if first + len <= block.start || *first >= block.end {
                    continue;
                }
                let path = shared.join(file);
                let bytes = std::fs::read(&path).map_err(io_err(&path))?;
                let payload = checkpoint::decode(&path, &bytes)?;
                parts.push(
                    rmp_serde::from_slice(payload).map_err(|e| RunError::Checkpoint {
                        path: path.clone(),
                        message: e.to_string(),
                    })?,
                );
            }
            parts
        }
        _ if k > 1 => outputs.take_rows().into_iter().collect(),
        _ => return Ok(()),
    };
    if parts.is_empty() {
        return Ok(());
    }
    outputs.put_rows(crate::transport::GrainRows::cut(
        &parts,
        block.start,
        block.end,
    ));
    Ok(())
}

/// Removes the parts of checkpoints other than `generation` (after its manifest is in
/// place).
pub(crate) fn remove_other_generations(shared: &Path, generation: u64) {
    let keep = format!("{generation:06}_");
    let Ok(entries) = std::fs::read_dir(shared.join(PARTS_DIR)) else {
        return;
    };
    for entry in entries.flatten() {
        if !entry.file_name().to_string_lossy().starts_with(&keep) {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}

/// Puts the particles of `manifest`'s parts (in `shared`) into `engine`, a checkpoint's
/// engine without particles: with `comm` of several ranks only this rank's slab
/// (collective), otherwise the whole engine.
pub(crate) fn load(
    engine: &mut AnyEngine,
    comm: Option<Arc<dyn Communicator>>,
    shared: &Path,
    manifest: &Manifest,
) -> Result<(), RunError> {
    let result = match engine {
        AnyEngine::Dsmc2(e) => e.load_parts(comm, manifest.particles, &manifest.parts, |i| {
            read_part(shared, i)
        }),
        AnyEngine::Dsmc3(e) => e.load_parts(comm, manifest.particles, &manifest.parts, |i| {
            read_part(shared, i)
        }),
        other => Err(format!(
            "lists parts, but holds the {} engine, which is never decomposed",
            other.name()
        )),
    };
    result.map_err(|message| RunError::Checkpoint {
        path: checkpoint::path(shared),
        message: format!(
            "{message}. Rerun the scenario: `granular run {} --out {} --replace`",
            shared.join(super::RunFile::Scenario.name()).display(),
            shared.display()
        ),
    })
}

fn read_part<const D: usize>(shared: &Path, info: &PartInfo) -> Result<EnginePart<D>, String> {
    let path = shared.join(&info.file);
    let bytes = std::fs::read(&path).map_err(|e| {
        format!(
            "part {} cannot be read ({e}); the checkpoint is incomplete",
            path.display()
        )
    })?;
    let payload = checkpoint::decode(&path, &bytes).map_err(|e| e.to_string())?;
    rmp_serde::from_slice(payload).map_err(|e| format!("part {}: {e}", path.display()))
}

impl super::Recorder {
    /// A decomposed run's checkpoint (collective): every rank writes its part, then rank 0
    /// the manifest, then rank 0 removes the earlier parts (see the module docs).
    pub(super) fn checkpoint_in_parts(
        &mut self,
        simulation: &Simulation,
        rank: usize,
    ) -> Result<(), RunError> {
        let shared = self.shared.clone().unwrap_or_else(|| self.dir.clone());
        let generation = self.generation + 1;
        // The manifest's outputs without the per-grain state, which each rank writes for
        // its block of ids.
        let mut outputs = self.outputs.clone();
        let rows = outputs.take_rows();
        let manifest = write_parts(simulation.engine(), &shared, generation).and_then(|mut m| {
            if let Some(domain) = simulation.engine().domain() {
                m.rows = write_rows(domain, &shared, generation, rows.as_ref())?;
            }
            Ok(m)
        });
        drop(rows);
        if let Err(e) = &manifest {
            self.log(simulation.wall_seconds(), &e.to_string());
        }
        let manifest = manifest?;
        self.generation = generation;
        let written = if rank == 0 {
            let cp = super::Checkpoint {
                format: super::CHECKPOINT_FORMAT,
                scenario: simulation.initial_scenario().to_toml(),
                simulation: simulation.shell_state(),
                outputs,
                parts: Some(manifest),
            };
            self.write_checkpoint(simulation, &cp)
        } else {
            Ok(())
        };
        // Every rank learns whether the manifest is in place (collective).
        let failed = simulation
            .engine()
            .domain()
            .and_then(|d| first_failure(d, written.is_ok()));
        written?;
        if failed.is_some() {
            return Err(RunError::CheckpointWrite {
                path: checkpoint::path(&shared),
                message: "rank 0 could not write the checkpoint (its message is above); the \
                          previous checkpoint is intact"
                    .into(),
            });
        }
        if rank == 0 {
            remove_other_generations(&shared, generation);
        }
        Ok(())
    }
}

/// The simulation of a checkpoint read from `dir`: its state with the grains of its parts
/// (in `shared`) when it was written in parts; with `ranks`, this rank's slab only, the
/// simulation decomposed (collective), otherwise the whole system.
pub(super) fn restore(
    dir: &Path,
    scenario: crate::scenario::Scenario,
    mut state: crate::simulation::SimulationState,
    manifest: Option<&Manifest>,
    ranks: Option<(&Path, Arc<dyn Communicator>)>,
) -> Result<Simulation, RunError> {
    let shared = ranks.as_ref().map_or(dir, |(s, _)| *s);
    if let Some(manifest) = manifest {
        let comm = ranks.as_ref().map(|(_, c)| c.clone());
        load(&mut state.engine, comm, shared, manifest)?;
    }
    let mut simulation = Simulation::restore(scenario, state);
    if let Some((_, comm)) = ranks {
        simulation
            .decompose(comm)
            .map_err(|e| RunError::Directory {
                dir: dir.to_path_buf(),
                message: e.to_string(),
            })?;
    }
    Ok(simulation)
}

/// The temporary file of rank `rank`'s block of the snapshot `path`.
fn block_file(path: &Path, rank: usize) -> PathBuf {
    let mut name = path.as_os_str().to_owned();
    name.push(format!(".rank{rank:04}.tmp"));
    PathBuf::from(name)
}

/// Writes the snapshot `path` of a decomposed engine (collective; see the module docs).
pub(crate) fn write_snapshot(engine: &AnyEngine, path: &Path) -> Result<(), RunError> {
    with_blocks(engine, path, |frame| {
        let (k, n, dimension) = (frame.blocks, frame.n, frame.dimension);
        let from_blocks = |section: usize| -> Fill<'_, f64> {
            Box::new(move |sink| {
                for q in 0..k {
                    frame.read_block(q, section, &mut |values| sink(values))?;
                }
                Ok(())
            })
        };
        let snapshot = StreamedSnapshot {
            time: frame.time,
            dimension,
            n,
            radius: frame.radius,
            mass: frame.mass,
            species_names: frame.species.names.clone(),
            species_ends: frame.species.ends.iter().map(|&x| x as usize).collect(),
            positions: from_blocks(0),
            velocities: from_blocks(1),
            rotational: frame.rotational,
            angular_velocities: (frame.rotational > 0).then(|| from_blocks(2)),
        };
        Ok(write_snapshot_streamed(path, snapshot)?)
    })
}

/// The grains of a decomposed engine at one output, on rank 0, from the block files the
/// ranks wrote ([`with_blocks`]): read a piece at a time.
pub(crate) struct BlockFrame<'a> {
    /// The block files' common path (`path.rankRRRR.tmp`).
    path: &'a Path,
    /// Ranks (blocks).
    pub blocks: usize,
    /// Grains.
    pub n: usize,
    /// Spatial dimension.
    pub dimension: usize,
    /// Simulation time.
    pub time: f64,
    /// Grain radius and mass.
    pub radius: f64,
    /// Grain mass.
    pub mass: f64,
    /// The species.
    pub species: crate::dsmc::SpeciesTable,
    /// Angular velocity components per grain (`d_r` of rough grains, 0 for smooth ones):
    /// a block file holds them after the velocities.
    pub rotational: usize,
}

/// Grains per piece read from a block file.
const PIECE: usize = 1 << 16;

impl BlockFrame<'_> {
    /// Rows of block `q`.
    fn rows(&self, q: usize) -> std::ops::Range<usize> {
        crate::dsmc::setup::id_block(self.n, q, self.blocks)
    }

    /// The positions (`section` 0), velocities (1) or angular velocities (2) of block `q`,
    /// `PIECE` grains at a time.
    fn read_block(
        &self,
        q: usize,
        section: usize,
        sink: &mut dyn FnMut(&[f64]) -> std::io::Result<()>,
    ) -> std::io::Result<()> {
        let mut f = std::fs::File::open(block_file(self.path, q))?;
        let rows = self.rows(q).len();
        let width = if section == 2 {
            self.rotational
        } else {
            self.dimension
        };
        let count = rows * width;
        let skip = rows * self.dimension * section.min(2);
        if skip > 0 {
            f.seek(SeekFrom::Start(8 * skip as u64))?;
        }
        let mut f = std::io::BufReader::new(f);
        let piece = PIECE * width.max(1);
        let mut buf = vec![0u8; 8 * piece];
        let mut values = Vec::with_capacity(piece);
        let mut left = count;
        while left > 0 {
            let m = left.min(piece);
            f.read_exact(&mut buf[..8 * m])?;
            values.clear();
            values.extend(
                buf[..8 * m]
                    .chunks_exact(8)
                    .map(|b| f64::from_le_bytes(b.try_into().unwrap_or([0; 8]))),
            );
            sink(&values)?;
            left -= m;
        }
        Ok(())
    }
}

impl crate::trajectory::Pieces for BlockFrame<'_> {
    fn each(
        &self,
        f: &mut dyn FnMut(&crate::trajectory::Piece<'_>) -> std::io::Result<()>,
    ) -> std::io::Result<()> {
        let d = self.dimension;
        let radii = vec![self.radius; PIECE];
        let masses = vec![self.mass; PIECE];
        let mut species = Vec::with_capacity(PIECE);
        for q in 0..self.blocks {
            let rows = self.rows(q);
            let mut pos = std::io::BufReader::new(std::fs::File::open(block_file(self.path, q))?);
            let mut vel = std::fs::File::open(block_file(self.path, q))?;
            vel.seek(SeekFrom::Start(8 * (rows.len() * d) as u64))?;
            let mut vel = std::io::BufReader::new(vel);
            // Rough grains: the angular velocities follow the velocities.
            let mut spin = std::fs::File::open(block_file(self.path, q))?;
            spin.seek(SeekFrom::Start(8 * (2 * rows.len() * d) as u64))?;
            let mut spin = std::io::BufReader::new(spin);
            let read = |r: &mut dyn Read, m: usize, width: usize| -> std::io::Result<Vec<f64>> {
                let mut buf = vec![0u8; 8 * m * width];
                r.read_exact(&mut buf)?;
                Ok(buf
                    .chunks_exact(8)
                    .map(|b| f64::from_le_bytes(b.try_into().unwrap_or([0; 8])))
                    .collect())
            };
            let mut first = rows.start;
            while first < rows.end {
                let m = (rows.end - first).min(PIECE);
                let positions = read(&mut pos, m, d)?;
                let velocities = read(&mut vel, m, d)?;
                let angular_velocities = read(&mut spin, m, self.rotational)?;
                species.clear();
                species.extend((first..first + m).map(|id| self.species.of(id as u32)));
                f(&crate::trajectory::Piece {
                    first,
                    dimension: d,
                    positions: &positions,
                    velocities: &velocities,
                    radii: &radii[..m],
                    masses: &masses[..m],
                    species: &species,
                    angular_velocities: &angular_velocities,
                })?;
                first += m;
            }
        }
        Ok(())
    }
}

/// One output's grains of a decomposed engine, written without gathering them
/// (collective): every rank writes its block of grain ids (positions, then velocities)
/// to `path.rankRRRR.tmp`; once all are on disk, rank 0 calls `write` with the frame read
/// from them piece by piece; the block files are removed. An error on any rank is an
/// error on every rank. Not called for an engine that is not decomposed.
pub(crate) fn with_blocks(
    engine: &AnyEngine,
    path: &Path,
    write: impl FnOnce(&BlockFrame<'_>) -> Result<(), RunError>,
) -> Result<(), RunError> {
    match engine {
        AnyEngine::Dsmc2(e) => with_blocks_of(e, path, write),
        AnyEngine::Dsmc3(e) => with_blocks_of(e, path, write),
        _ => Ok(()),
    }
}

fn with_blocks_of<const D: usize>(
    e: &DsmcEngine<D>,
    path: &Path,
    write: impl FnOnce(&BlockFrame<'_>) -> Result<(), RunError>,
) -> Result<(), RunError> {
    let Some(domain) = e.domain() else {
        return Ok(());
    };
    let (rank, k, n) = (domain.rank(), domain.size(), domain.n_global);
    let block = e.id_block();
    let mine = block_file(path, rank);
    let written = (|| -> std::io::Result<()> {
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir)?;
        }
        let mut w = BufWriter::new(std::fs::File::create(&mine)?);
        for x in block.positions.iter().chain(&block.velocities) {
            for c in x.0 {
                w.write_all(&c.to_le_bytes())?;
            }
        }
        for c in &block.angular_velocities {
            w.write_all(&c.to_le_bytes())?;
        }
        w.flush()
    })()
    .map_err(io_err(&mine));
    let rotational = if e.is_rough() {
        crate::collision_law::rough::rotational_dof(D)
    } else {
        0
    };
    drop(block);
    let failed = first_failure(domain, written.is_ok());
    let frame = BlockFrame {
        path,
        blocks: k,
        n,
        dimension: D,
        time: e.time(),
        radius: e.radius(),
        mass: e.mass(),
        species: e.species().clone(),
        rotational,
    };
    let result = written.and_then(|()| match failed {
        Some(r) => Err(RunError::Directory {
            dir: path.to_path_buf(),
            message: format!("rank {r} could not write its block of grains"),
        }),
        None if rank == 0 => write(&frame),
        None => Ok(()),
    });
    let failed = first_failure(domain, result.is_ok());
    let _ = std::fs::remove_file(&mine);
    result?;
    match failed {
        Some(r) => Err(RunError::Directory {
            dir: path.to_path_buf(),
            message: format!("rank {r} could not write the output (its message is above)"),
        }),
        None => Ok(()),
    }
}
