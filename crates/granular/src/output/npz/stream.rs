//! A snapshot written from arrays produced in pieces (a decomposed run's rank 0 copies
//! the ranks' blocks of grain ids into it): the same members and bytes as
//! [`super::write_snapshot`], in memory independent of the number of grains.

use super::{NpzArray, NpzData, NpzError, io_error, type_str, write_array_to, zip_error};
use npyz::WriterBuilder;
use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;

/// Values of one array produced in pieces by a snapshot writer that never holds the whole
/// array ([`write_snapshot_streamed`]): `fill` calls `sink` with consecutive slices.
pub(crate) type Fill<'a, T> =
    Box<dyn FnMut(&mut dyn FnMut(&[T]) -> io::Result<()>) -> io::Result<()> + 'a>;

/// A snapshot of equal grains whose per-grain arrays are produced in pieces; the species
/// are contiguous ranges of grains.
pub(crate) struct StreamedSnapshot<'a> {
    /// Simulation time.
    pub time: f64,
    /// Spatial dimension.
    pub dimension: usize,
    /// Number of grains.
    pub n: usize,
    /// Radius of every grain.
    pub radius: f64,
    /// Mass of every grain.
    pub mass: f64,
    /// The species' names, in order.
    pub species_names: Vec<String>,
    /// One past the last grain of each species (the last is `n`).
    pub species_ends: Vec<usize>,
    /// Positions, row after row (`n x dimension` values in all).
    pub positions: Fill<'a, f64>,
    /// Velocities, as the positions.
    pub velocities: Fill<'a, f64>,
    /// Angular velocity components per grain of rough grains (`d_r`: 1 in 2D, 3 in 3D).
    pub rotational: usize,
    /// Angular velocities of rough grains, `n x rotational` values (`None`: smooth grains,
    /// no such member).
    pub angular_velocities: Option<Fill<'a, f64>>,
}

/// Writes a snapshot with the same members, order and bytes as [`super::write_snapshot`] of the
/// same values, from arrays produced in pieces: memory independent of `n` (a decomposed
/// run's rank 0 assembles the ranks' blocks this way).
///
/// # Errors
/// As [`super::write_npz`]; the error of a `fill`.
pub(crate) fn write_snapshot_streamed(
    path: impl AsRef<Path>,
    mut s: StreamedSnapshot<'_>,
) -> Result<(), NpzError> {
    let path = path.as_ref();
    let (n, d) = (s.n, s.dimension);
    let file = File::create(path).map_err(io_error(path))?;
    let mut zip = zip::ZipWriter::new(BufWriter::new(file));
    // As write_npz: zip64 members when an array has more than 2^26 values.
    let options = zip::write::FileOptions::default()
        .compression_method(zip::CompressionMethod::Stored)
        .large_file(n * d > (1 << 26));
    let start = |zip: &mut zip::ZipWriter<_>, name: &str| {
        zip.start_file(npyz::npz::file_name_from_array_name(name), options)
            .map_err(zip_error(path))
    };
    let chunk = 1 << 16;
    let constant = |v: f64| -> Fill<'static, f64> {
        Box::new(move |sink| {
            let block = vec![v; chunk];
            (0..n)
                .step_by(chunk)
                .try_for_each(|a| sink(&block[..chunk.min(n - a)]))
        })
    };
    let ends = s.species_ends.clone();
    let species: Fill<'static, u32> = Box::new(move |sink| {
        let mut block = Vec::with_capacity(chunk);
        for a in (0..n).step_by(chunk) {
            block.clear();
            block.extend((a..(a + chunk).min(n)).map(|i| {
                (ends.partition_point(|&e| e <= i) as u32).min(ends.len().max(1) as u32 - 1)
            }));
            sink(&block)?;
        }
        Ok(())
    });
    start(&mut zip, "time")?;
    write_array_to(&mut zip, "time", &NpzArray::scalar(s.time)).map_err(io_error(path))?;
    start(&mut zip, "dimension")?;
    let dimension = NpzArray {
        shape: vec![],
        data: NpzData::U64(vec![d as u64]),
    };
    write_array_to(&mut zip, "dimension", &dimension).map_err(io_error(path))?;
    let (nn, dd) = (n as u64, d as u64);
    let members: [(&str, Vec<u64>, Fill<'_, f64>); 4] = [
        ("positions", vec![nn, dd], s.positions),
        ("velocities", vec![nn, dd], s.velocities),
        ("radii", vec![nn], constant(s.radius)),
        ("masses", vec![nn], constant(s.mass)),
    ];
    for (name, shape, mut fill) in members {
        start(&mut zip, name)?;
        let mut w = npyz::WriteOptions::<f64>::new()
            .dtype(type_str("<f8"))
            .shape(&shape)
            .writer(&mut zip)
            .begin_nd()
            .map_err(io_error(path))?;
        fill(&mut |values| w.extend(values.iter().copied())).map_err(io_error(path))?;
        w.finish().map_err(io_error(path))?;
    }
    start(&mut zip, "species")?;
    let mut w = npyz::WriteOptions::<u32>::new()
        .dtype(type_str("<u4"))
        .shape(&[n as u64])
        .writer(&mut zip)
        .begin_nd()
        .map_err(io_error(path))?;
    let mut species = species;
    species(&mut |values| w.extend(values.iter().copied())).map_err(io_error(path))?;
    w.finish().map_err(io_error(path))?;
    start(&mut zip, "species_names")?;
    let names = NpzArray::strings(std::mem::take(&mut s.species_names));
    write_array_to(&mut zip, "species_names", &names).map_err(io_error(path))?;
    if let Some(mut fill) = s.angular_velocities {
        // As `write_snapshot`: (n,) for disks, (n, 3) for spheres.
        let shape = if s.rotational == 1 {
            vec![nn]
        } else {
            vec![nn, s.rotational as u64]
        };
        start(&mut zip, "angular_velocities")?;
        let mut w = npyz::WriteOptions::<f64>::new()
            .dtype(type_str("<f8"))
            .shape(&shape)
            .writer(&mut zip)
            .begin_nd()
            .map_err(io_error(path))?;
        fill(&mut |values| w.extend(values.iter().copied())).map_err(io_error(path))?;
        w.finish().map_err(io_error(path))?;
    }
    let mut inner = zip.finish().map_err(zip_error(path))?;
    inner.flush().map_err(io_error(path))
}
