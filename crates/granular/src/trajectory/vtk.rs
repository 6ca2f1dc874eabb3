//! VTK PolyData for ParaView: one XML file per frame, `vtp/snapshot_NNNNNN.vtp` (`NNNNNN`
//! the output index, as for the `.npz` snapshots), and the time index `trajectory.pvd` (a
//! VTK `Collection` with one `DataSet` per frame and its `timestep` = simulation time),
//! which is the file to open in ParaView.
//!
//! Each `.vtp` file holds the grains as points (`Points`, 3 x `Float64`; `z = 0` in 2D)
//! with one vertex cell each (`Verts`), and the point arrays `id` (`Int64`, from 0),
//! `species` (`Int32`, the index of the scenario's `[[species]]`; the names are listed in
//! an XML comment), `v` (the velocity, 3 x `Float64`), `radius` and `mass` (`Float64`).
//! The names `Points`, `v`, `id`, `radius`, `mass` are those of LIGGGHTS' and Aspherix'
//! particle files, which OVITO's VTP particle reader maps to its position, velocity,
//! identifier, radius and mass. Rough grains add the point array `angular_velocity` (3 x
//! `Float64`, radians per time unit; `(0, 0, ω_z)` for disks); smooth grains have none.
//! The field
//! data hold `TimeValue` (the time), `Step` (the output index), `BoxLengths` (3 values;
//! 0 along z in 2D) and `Periodic` (3 values, 1 periodic, 0 hard walls; PolyData has no
//! box of its own). Numbers are ASCII with Rust's shortest round-trip formatting, so the
//! values are exact; ASCII is about three times larger than VTK's binary encodings, which
//! matters only for very large runs. In ParaView, show the points with the "Point
//! Gaussian" representation, "Scale by array" `radius` (and "Gaussian radius" 1), to see
//! true-size grains.

use super::{Frame, Rows, TrajectoryError, io_err};
use serde::{Deserialize, Serialize};
use std::fmt::Display;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

/// A series of `.vtp` frames and its `.pvd` index.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct VtkSeries {
    #[serde(skip)]
    dir: PathBuf,
    frames: Vec<(f64, String)>,
}

impl VtkSeries {
    /// A new series in `dir` (`dir/trajectory.pvd`, `dir/vtp/`), with an empty index.
    pub fn create(dir: &Path) -> Result<VtkSeries, TrajectoryError> {
        let vtp = dir.join("vtp");
        std::fs::create_dir_all(&vtp).map_err(io_err(&vtp))?;
        let series = VtkSeries {
            dir: dir.to_path_buf(),
            frames: Vec::new(),
        };
        series.write_index()?;
        Ok(series)
    }

    /// The index file, `trajectory.pvd`.
    pub fn path(&self) -> PathBuf {
        self.dir.join(super::Format::Vtk.file_name())
    }

    pub(crate) fn set_dir(&mut self, dir: PathBuf) {
        self.dir = dir;
    }

    /// Frames written.
    pub fn frames(&self) -> usize {
        self.frames.len()
    }

    /// Writes the frame's `.vtp` file and rewrites the index.
    pub fn append(&mut self, frame: &Frame) -> Result<(), TrajectoryError> {
        self.append_rows(&frame.rows())
    }

    /// [`VtkSeries::append`] of a frame read piece by piece.
    pub fn append_rows(&mut self, frame: &Rows) -> Result<(), TrajectoryError> {
        let name = format!("vtp/snapshot_{:06}.vtp", frame.step);
        let path = self.dir.join(&name);
        let file = std::fs::File::create(&path).map_err(io_err(&path))?;
        let mut out = BufWriter::new(file);
        write_rows(&mut out, frame)
            .and_then(|()| out.flush())
            .map_err(io_err(&path))?;
        self.frames.push((frame.time, name));
        self.write_index()
    }

    /// Rewrites the index with the frames of this state (after a checkpoint is read back).
    pub fn rewind(&self) -> Result<(), TrajectoryError> {
        self.write_index()
    }

    fn write_index(&self) -> Result<(), TrajectoryError> {
        let mut text = String::from(
            "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n",
        );
        for (time, file) in &self.frames {
            text += &format!(
                "    <DataSet timestep=\"{time}\" group=\"\" part=\"0\" file=\"{file}\"/>\n"
            );
        }
        text += "  </Collection>\n</VTKFile>\n";
        let path = self.path();
        std::fs::write(&path, text).map_err(io_err(&path))
    }
}

/// One `DataArray` written value by value (12 values a line), so that its values may
/// come from several pieces.
struct Array {
    written: usize,
}

impl Array {
    fn start(
        out: &mut impl Write,
        kind: &str,
        name: &str,
        components: usize,
        tuples: usize,
    ) -> io::Result<Array> {
        write!(out, "        <DataArray type=\"{kind}\" Name=\"{name}\"")?;
        if components > 1 {
            write!(out, " NumberOfComponents=\"{components}\"")?;
        }
        write!(out, " NumberOfTuples=\"{tuples}\"")?;
        write!(out, " format=\"ascii\">")?;
        Ok(Array { written: 0 })
    }

    fn value<T: Display>(&mut self, out: &mut impl Write, v: T) -> io::Result<()> {
        if self.written > 0 {
            out.write_all(if self.written.is_multiple_of(12) {
                b"\n"
            } else {
                b" "
            })?;
        }
        self.written += 1;
        write!(out, "{v}")
    }

    fn end(self, out: &mut impl Write) -> io::Result<()> {
        writeln!(out, "</DataArray>")
    }
}

fn array<T: Display>(
    out: &mut impl Write,
    kind: &str,
    name: &str,
    components: usize,
    tuples: usize,
    values: impl Iterator<Item = T>,
) -> io::Result<()> {
    let mut a = Array::start(out, kind, name, components, tuples)?;
    for v in values {
        a.value(out, v)?;
    }
    a.end(out)
}

/// An array of a per-grain quantity read piece by piece: `values(piece, out)` gives the
/// values of the piece's grains.
fn grain_array<W: Write, T: Display>(
    out: &mut W,
    frame: &Rows,
    (kind, name, components): (&str, &str, usize),
    values: impl Fn(&super::Piece<'_>, usize) -> Vec<T>,
) -> io::Result<()> {
    let mut a = Array::start(out, kind, name, components, frame.n)?;
    frame.grains.each(&mut |p| {
        for i in 0..p.len() {
            for v in values(p, i) {
                a.value(out, v)?;
            }
        }
        Ok(())
    })?;
    a.end(out)
}

/// Writes one frame as a VTK XML PolyData file.
pub fn write_frame(out: &mut impl Write, frame: &Frame) -> io::Result<()> {
    write_rows(out, &frame.rows())
}

/// Writes one frame read piece by piece as a VTK XML PolyData file.
pub fn write_rows(out: &mut impl Write, frame: &Rows) -> io::Result<()> {
    let n = frame.n;
    let d = frame.dimension;
    let lengths = (0..3).map(|k| frame.cell.lengths.get(k).copied().unwrap_or(0.0));
    let periodic = (0..3).map(|k| u8::from(frame.periodic3()[k]));
    writeln!(
        out,
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">"
    )?;
    let names: Vec<String> = frame
        .species_names
        .iter()
        .enumerate()
        .map(|(k, name)| format!("{k} = {}", name.replace("--", "- -")))
        .collect();
    writeln!(
        out,
        "  <!-- granular, {d}D; species: {} -->",
        names.join(", ")
    )?;
    writeln!(out, "  <PolyData>\n    <FieldData>")?;
    array(
        out,
        "Float64",
        "TimeValue",
        1,
        1,
        std::iter::once(frame.time),
    )?;
    array(out, "Int64", "Step", 1, 1, std::iter::once(frame.step))?;
    writeln!(
        out,
        "    <!-- BoxLengths and Periodic have 3 tuples of one value -->"
    )?;
    array(out, "Float64", "BoxLengths", 1, 3, lengths)?;
    array(out, "UInt8", "Periodic", 1, 3, periodic)?;
    writeln!(out, "    </FieldData>")?;
    writeln!(
        out,
        "    <Piece NumberOfPoints=\"{n}\" NumberOfVerts=\"{n}\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">"
    )?;
    writeln!(out, "      <PointData Scalars=\"radius\" Vectors=\"v\">")?;
    array(out, "Int64", "id", 1, n, 0..n)?;
    grain_array(out, frame, ("Int32", "species", 1), |p, i| {
        vec![p.species[i]]
    })?;
    grain_array(out, frame, ("Float64", "v", 3), |p, i| {
        p.velocity(i).to_vec()
    })?;
    grain_array(out, frame, ("Float64", "radius", 1), |p, i| {
        vec![p.radii[i]]
    })?;
    grain_array(out, frame, ("Float64", "mass", 1), |p, i| vec![p.masses[i]])?;
    if frame.is_rough() {
        grain_array(out, frame, ("Float64", "angular_velocity", 3), |p, i| {
            p.angular_velocity(i).to_vec()
        })?;
    }
    writeln!(out, "      </PointData>\n      <Points>")?;
    grain_array(out, frame, ("Float64", "Points", 3), |p, i| {
        p.position(i).to_vec()
    })?;
    writeln!(out, "      </Points>\n      <Verts>")?;
    array(out, "Int64", "connectivity", 1, n, 0..n)?;
    array(out, "Int64", "offsets", 1, n, 1..=n)?;
    writeln!(
        out,
        "      </Verts>\n    </Piece>\n  </PolyData>\n</VTKFile>"
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::trajectory::test_frame::snapshot_2d;

    #[test]
    fn a_frame_has_points_vertices_and_the_arrays() {
        let (snap, cell) = snapshot_2d();
        let frame = Frame {
            step: 3,
            snapshot: &snap,
            cell: &cell,
            inertia: &[],
        };
        let mut out = Vec::new();
        write_frame(&mut out, &frame).unwrap();
        let text = String::from_utf8(out).unwrap();
        for piece in [
            "<VTKFile type=\"PolyData\"",
            "Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"ascii\">0.25<",
            "Name=\"Step\" NumberOfTuples=\"1\" format=\"ascii\">3<",
            "Name=\"BoxLengths\" NumberOfTuples=\"3\" format=\"ascii\">1 0.5 0<",
            "Name=\"Periodic\" NumberOfTuples=\"3\" format=\"ascii\">1 0 0<",
            "<Piece NumberOfPoints=\"2\" NumberOfVerts=\"2\"",
            "Name=\"Points\" NumberOfComponents=\"3\" NumberOfTuples=\"2\" format=\"ascii\">0.1 0.2 0 0.7 0.4 0<",
            "Name=\"v\" NumberOfComponents=\"3\" NumberOfTuples=\"2\" format=\"ascii\">1 -0.5 0 0.125 2 0<",
            "Name=\"species\" NumberOfTuples=\"2\" format=\"ascii\">0 1<",
            "Name=\"offsets\" NumberOfTuples=\"2\" format=\"ascii\">1 2<",
            "species: 0 = bath, 1 = intruder",
        ] {
            assert!(text.contains(piece), "missing {piece} in\n{text}");
        }
        assert!(
            !text.contains("angular_velocity"),
            "smooth grains have no spin"
        );
        // Every opened element is closed.
        for tag in [
            "VTKFile",
            "PolyData",
            "FieldData",
            "Piece",
            "PointData",
            "Points",
            "Verts",
        ] {
            assert_eq!(
                text.matches(&format!("<{tag}")).count(),
                text.matches(&format!("</{tag}>")).count(),
                "{tag}"
            );
        }
    }

    #[test]
    fn the_index_lists_every_frame_with_its_time() {
        let dir = tempfile::tempdir().unwrap();
        let (mut snap, cell) = snapshot_2d();
        let mut series = VtkSeries::create(dir.path()).unwrap();
        for step in [0, 5] {
            snap.time = step as f64 * 0.5;
            let frame = Frame {
                step,
                snapshot: &snap,
                cell: &cell,
                inertia: &[],
            };
            series.append(&frame).unwrap();
        }
        let index = std::fs::read_to_string(series.path()).unwrap();
        assert!(
            index.contains("timestep=\"0\" group=\"\" part=\"0\" file=\"vtp/snapshot_000000.vtp\"")
        );
        assert!(
            index.contains(
                "timestep=\"2.5\" group=\"\" part=\"0\" file=\"vtp/snapshot_000005.vtp\""
            )
        );
        assert!(dir.path().join("vtp/snapshot_000005.vtp").is_file());
    }

    #[test]
    fn rough_grains_add_the_angular_velocity_array() {
        use crate::trajectory::test_frame::{rough_2d, rough_3d};
        for ((snap, cell, inertia), values) in [
            (rough_2d(), "0 0 3.5 0 0 -0.25"),
            (rough_3d(), "1.5 -2 0.75 0 10 -4"),
        ] {
            let frame = Frame {
                step: 3,
                snapshot: &snap,
                cell: &cell,
                inertia: &inertia,
            };
            let mut out = Vec::new();
            write_frame(&mut out, &frame).unwrap();
            let text = String::from_utf8(out).unwrap();
            let array = format!(
                "Name=\"angular_velocity\" NumberOfComponents=\"3\" NumberOfTuples=\"2\" format=\"ascii\">{values}<"
            );
            assert!(text.contains(&array), "{text}");
        }
    }
}
