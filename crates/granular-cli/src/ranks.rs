//! Runs under `mpirun` (the `mpi` feature): one DSMC simulation decomposed over the
//! ranks (`granular run`, `granular resume`). Every rank loads the same scenario, builds
//! or restores the same simulation and keeps its slab of cells (see the library's
//! `granular::dsmc::domain`); rank 0 writes the run directory, the other ranks a
//! directory of their own under the system's temporary directory, removed at the end.
//! Without `mpirun` the binary runs as one rank.

use granular::dsmc;
use mpi::datatype::{Partition, PartitionMut};
use mpi::environment::Universe;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The world communicator as the library's [`dsmc::Communicator`].
#[derive(Debug)]
pub struct World {
    rank: usize,
    size: usize,
}

fn world() -> SimpleCommunicator {
    SimpleCommunicator::world()
}

fn displacements(counts: &[i32]) -> Vec<i32> {
    counts
        .iter()
        .scan(0, |acc, &c| {
            let d = *acc;
            *acc += c;
            Some(d)
        })
        .collect()
}

fn split(buf: &[f64], counts: &[i32]) -> Vec<Vec<f64>> {
    let mut out = Vec::with_capacity(counts.len());
    let mut at = 0;
    for &c in counts {
        out.push(buf[at..at + c as usize].to_vec());
        at += c as usize;
    }
    out
}

impl dsmc::Communicator for World {
    fn rank(&self) -> usize {
        self.rank
    }

    fn size(&self) -> usize {
        self.size
    }

    fn all_gather(&self, local: &[f64]) -> Vec<Vec<f64>> {
        let w = world();
        let mut counts = vec![0i32; self.size];
        w.all_gather_into(&(local.len() as i32), &mut counts[..]);
        let displs = displacements(&counts);
        let total: i32 = counts.iter().sum();
        let mut buf = vec![0.0f64; total as usize];
        {
            let mut part = PartitionMut::new(&mut buf[..], &counts[..], &displs[..]);
            w.all_gather_varcount_into(local, &mut part);
        }
        split(&buf, &counts)
    }

    fn exchange(&self, outgoing: Vec<Vec<f64>>) -> Vec<Vec<f64>> {
        let w = world();
        let send_counts: Vec<i32> = outgoing.iter().map(|v| v.len() as i32).collect();
        let mut recv_counts = vec![0i32; self.size];
        w.all_to_all_into(&send_counts[..], &mut recv_counts[..]);
        let send: Vec<f64> = outgoing.concat();
        let send_displs = displacements(&send_counts);
        let recv_displs = displacements(&recv_counts);
        let total: i32 = recv_counts.iter().sum();
        let mut buf = vec![0.0f64; total as usize];
        {
            let part = Partition::new(&send[..], &send_counts[..], &send_displs[..]);
            let mut recv = PartitionMut::new(&mut buf[..], &recv_counts[..], &recv_displs[..]);
            w.all_to_all_varcount_into(&part, &mut recv);
        }
        split(&buf, &recv_counts)
    }

    fn send(&self, to: usize, words: &[f64]) {
        world()
            .process_at_rank(to as i32)
            .send_with_tag(words, CHAIN_TAG);
    }

    fn receive(&self, from: usize) -> Vec<f64> {
        world()
            .process_at_rank(from as i32)
            .receive_vec_with_tag::<f64>(CHAIN_TAG)
            .0
    }
}

/// The tag of the library's point-to-point messages (the chained sums' accumulators), so
/// that they never match another point-to-point message.
const CHAIN_TAG: i32 = 27;

/// Whether any rank says yes (collective over the world).
pub fn any_rank(local: bool) -> bool {
    let w = world();
    let mut all = vec![0i32; w.size() as usize];
    w.all_gather_into(&i32::from(local), &mut all[..]);
    all.iter().any(|&x| x != 0)
}

/// Rank 0's `local`, on every rank (collective): rank 0's clock decides
/// `stop.wall_seconds` for all.
pub fn rank0_decides(local: bool) -> bool {
    let mut x = i32::from(local);
    world().process_at_rank(0).broadcast_into(&mut x);
    x != 0
}

/// Copies the files of a run directory (its subdirectories empty) to `to`, for a rank
/// other than 0 that resumes from rank 0's checkpoint.
pub fn copy_run_files(from: &Path, to: &Path) -> Result<(), String> {
    let _ = std::fs::remove_dir_all(to);
    std::fs::create_dir_all(to).map_err(|e| format!("{}: {e}", to.display()))?;
    let entries = std::fs::read_dir(from).map_err(|e| format!("{}: {e}", from.display()))?;
    for entry in entries.flatten() {
        let path = entry.path();
        let target = to.join(entry.file_name());
        if path.is_dir() {
            // Outputs write into their folders (snapshots/): empty ones will do.
            std::fs::create_dir_all(&target).map_err(|e| format!("{}: {e}", target.display()))?;
        } else if path.is_file() && entry.file_name() != ".lock" {
            std::fs::copy(&path, &target).map_err(|e| format!("{}: {e}", path.display()))?;
        }
    }
    Ok(())
}

/// MPI, initialised for the life of a command.
pub struct Ranks {
    _universe: Option<Universe>,
    world: Arc<World>,
    /// Ranks sharing this rank's node (its memory).
    on_node: usize,
}

impl Ranks {
    /// Initialises MPI (one rank when started without `mpirun`).
    pub fn start() -> Ranks {
        let universe = mpi::initialize();
        let (rank, size, on_node) = match &universe {
            Some(u) => {
                let w = u.world();
                let node = w.split_shared(w.rank());
                (w.rank() as usize, w.size() as usize, node.size() as usize)
            }
            None => (0, 1, 1),
        };
        Ranks {
            _universe: universe,
            world: Arc::new(World { rank, size }),
            on_node,
        }
    }

    /// The ranks sharing this rank's node (MPI's shared-memory split of the world).
    pub fn on_node(&self) -> usize {
        self.on_node
    }

    /// This rank.
    pub fn rank(&self) -> usize {
        self.world.rank
    }

    /// The number of ranks.
    pub fn size(&self) -> usize {
        self.world.size
    }

    /// The communicator for the library.
    pub fn communicator(&self) -> Arc<dyn dsmc::Communicator> {
        self.world.clone()
    }

    /// Whether any rank says yes (collective).
    pub fn any(&self, local: bool) -> bool {
        any_rank(local)
    }

    /// Makes every rank fail when one does (collective): rank 0 keeps its own error, the
    /// others report which rank failed.
    pub fn agree<T>(&self, result: Result<T, String>) -> Result<T, String> {
        let failed = self.any(result.is_err());
        match result {
            Err(e) => Err(if self.rank() == 0 {
                e
            } else {
                format!("rank {}: {e}", self.rank())
            }),
            Ok(_) if failed => Err(format!(
                "rank {}: stopped because another rank failed (its message is above)",
                self.rank()
            )),
            Ok(v) => Ok(v),
        }
    }

    /// The directory this rank writes: `dir` on rank 0, a scratch directory elsewhere.
    pub fn directory(&self, dir: &Path) -> PathBuf {
        if self.rank() == 0 {
            dir.to_path_buf()
        } else {
            std::env::temp_dir().join(format!(
                "granular-rank{}-{}",
                self.rank(),
                std::process::id()
            ))
        }
    }

    /// Removes this rank's scratch directory (ranks other than 0).
    pub fn clean(&self, dir: &Path) {
        if self.rank() != 0 {
            let _ = std::fs::remove_dir_all(self.directory(dir));
        }
    }
}
