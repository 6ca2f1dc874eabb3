//! Snapshots as NumPy `.npz` archives: `np.load("snapshot_000010.npz")` gives arrays
//! `time` (scalar), `positions` and `velocities` (N x D), `radii`, `masses` (N),
//! `species` (N, uint32 index) and `species_names` (JSON text, as a byte string).

use crate::engine::Snapshot;
use npyz::WriterBuilder;
use std::io;
use std::path::Path;

fn opts() -> npyz::zip::write::FileOptions {
    npyz::zip::write::FileOptions::default()
        .compression_method(npyz::zip::CompressionMethod::Stored)
}

/// Writes a snapshot to `path` (`.npz`).
pub fn write_snapshot(path: &Path, snap: &Snapshot) -> io::Result<()> {
    let mut npz = npyz::npz::NpzWriter::create(path)?;
    let n = snap.radii.len() as u64;
    let d = snap.dimension as u64;
    npz.array::<f64>("time", opts())?
        .default_dtype()
        .shape(&[])
        .begin_nd()?
        .push(&snap.time)?;
    let mut w = npz
        .array::<f64>("positions", opts())?
        .default_dtype()
        .shape(&[n, d])
        .begin_nd()?;
    w.extend(snap.positions.iter().copied())?;
    w.finish()?;
    let mut w = npz
        .array::<f64>("velocities", opts())?
        .default_dtype()
        .shape(&[n, d])
        .begin_nd()?;
    w.extend(snap.velocities.iter().copied())?;
    w.finish()?;
    let mut w = npz
        .array::<f64>("radii", opts())?
        .default_dtype()
        .shape(&[n])
        .begin_nd()?;
    w.extend(snap.radii.iter().copied())?;
    w.finish()?;
    let mut w = npz
        .array::<f64>("masses", opts())?
        .default_dtype()
        .shape(&[n])
        .begin_nd()?;
    w.extend(snap.masses.iter().copied())?;
    w.finish()?;
    let mut w = npz
        .array::<u32>("species", opts())?
        .default_dtype()
        .shape(&[n])
        .begin_nd()?;
    w.extend(snap.species.iter().copied())?;
    w.finish()?;
    let names = serde_json::to_string(&snap.species_names).unwrap_or_default();
    let dtype = npyz::DType::Plain(
        format!("|S{}", names.len().max(1))
            .parse()
            .map_err(|e| io::Error::new(io::ErrorKind::InvalidData, format!("{e:?}")))?,
    );
    npz.array::<[u8]>("species_names", opts())?
        .dtype(dtype)
        .shape(&[])
        .begin_nd()?
        .push(names.as_bytes())?;
    Ok(())
}

fn read_f64<R: io::Read + io::Seek>(
    npz: &mut npyz::npz::NpzArchive<R>,
    name: &str,
) -> io::Result<Vec<f64>> {
    let arr = npz.by_name(name)?.ok_or_else(|| {
        io::Error::new(io::ErrorKind::NotFound, format!("array `{name}` missing"))
    })?;
    arr.into_vec::<f64>()
}

/// Reads a snapshot written by [`write_snapshot`].
pub fn read_snapshot(path: &Path) -> io::Result<Snapshot> {
    let mut npz = npyz::npz::NpzArchive::open(path)?;
    let time = read_f64(&mut npz, "time")?
        .first()
        .copied()
        .unwrap_or(f64::NAN);
    let positions = read_f64(&mut npz, "positions")?;
    let velocities = read_f64(&mut npz, "velocities")?;
    let radii = read_f64(&mut npz, "radii")?;
    let masses = read_f64(&mut npz, "masses")?;
    let species = npz
        .by_name("species")?
        .ok_or_else(|| io::Error::new(io::ErrorKind::NotFound, "array `species` missing"))?
        .into_vec::<u32>()?;
    let names_raw = npz
        .by_name("species_names")?
        .ok_or_else(|| io::Error::new(io::ErrorKind::NotFound, "array `species_names` missing"))?
        .into_vec::<Vec<u8>>()?;
    let names_text = names_raw
        .first()
        .map(|b| {
            String::from_utf8_lossy(b)
                .trim_end_matches('\0')
                .to_string()
        })
        .unwrap_or_default();
    let species_names: Vec<String> = serde_json::from_str(&names_text).unwrap_or_default();
    let dimension = if radii.is_empty() {
        0
    } else {
        positions.len() / radii.len()
    };
    Ok(Snapshot {
        time,
        dimension,
        positions,
        velocities,
        radii,
        masses,
        species,
        species_names,
    })
}
