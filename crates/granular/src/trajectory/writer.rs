//! [`Writer`]: one trajectory being written, frame by frame, in one format.

use super::gsd::{self, GsdFile};
use super::vtk::VtkSeries;
use super::{Format, Frame, Rows, TrajectoryError, io_err, lammps, xyz};
use serde::{Deserialize, Serialize};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// A text file appended to frame by frame (extended XYZ, LAMMPS dump).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct TextFile {
    #[serde(skip)]
    path: PathBuf,
    bytes: u64,
    frames: u64,
}

/// One trajectory in one format. Its state is small and serialisable (it is part of a
/// checkpoint); files are opened only while a frame is written.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub enum Writer {
    /// Extended XYZ.
    Xyz(TextFile),
    /// LAMMPS text dump.
    Lammps(TextFile),
    /// GSD, HOOMD schema.
    Gsd(GsdFile),
    /// VTK PolyData series.
    Vtk(VtkSeries),
}

impl Writer {
    /// A new, empty trajectory in `dir` (created; an earlier file of the format is
    /// replaced), of `rough` grains (GSD lists the names of their chunks when it is
    /// created) or smooth ones.
    pub fn create(format: Format, dir: &Path, rough: bool) -> Result<Writer, TrajectoryError> {
        std::fs::create_dir_all(dir).map_err(io_err(dir))?;
        let path = dir.join(format.file_name());
        let text = || -> Result<TextFile, TrajectoryError> {
            std::fs::File::create(&path).map_err(io_err(&path))?;
            Ok(TextFile {
                path: path.clone(),
                bytes: 0,
                frames: 0,
            })
        };
        Ok(match format {
            Format::Xyz => Writer::Xyz(text()?),
            Format::Lammps => Writer::Lammps(text()?),
            Format::Gsd => Writer::Gsd(gsd::create_hoomd(&path, rough).map_err(io_err(&path))?),
            Format::Vtk => Writer::Vtk(VtkSeries::create(dir)?),
        })
    }

    /// The format.
    pub fn format(&self) -> Format {
        match self {
            Writer::Xyz(_) => Format::Xyz,
            Writer::Lammps(_) => Format::Lammps,
            Writer::Gsd(_) => Format::Gsd,
            Writer::Vtk(_) => Format::Vtk,
        }
    }

    /// The file a viewer opens.
    pub fn path(&self) -> PathBuf {
        match self {
            Writer::Xyz(t) | Writer::Lammps(t) => t.path.clone(),
            Writer::Gsd(g) => g.path().to_path_buf(),
            Writer::Vtk(v) => v.path(),
        }
    }

    /// Frames written.
    pub fn frames(&self) -> u64 {
        match self {
            Writer::Xyz(t) | Writer::Lammps(t) => t.frames,
            Writer::Gsd(g) => g.frames(),
            Writer::Vtk(v) => v.frames() as u64,
        }
    }

    /// Appends one frame.
    pub fn append(&mut self, frame: &Frame) -> Result<(), TrajectoryError> {
        self.append_rows(&frame.rows())
    }

    /// Appends one frame read piece by piece (the same bytes as [`Writer::append`] of the
    /// same grains, in memory independent of their number).
    pub fn append_rows(&mut self, frame: &Rows) -> Result<(), TrajectoryError> {
        match self {
            Writer::Xyz(t) => t.append(frame, xyz::write_rows),
            Writer::Lammps(t) => t.append(frame, lammps::write_rows),
            Writer::Gsd(g) => {
                let path = g.path().to_path_buf();
                g.append_streamed(gsd::frame_rows(frame))
                    .map_err(io_err(&path))
            }
            Writer::Vtk(v) => v.append_rows(frame),
        }
    }

    /// Points the writer at the trajectory folder `dir` (after a checkpoint is read back:
    /// the run directory may have moved).
    pub fn relocate(&mut self, dir: &Path) {
        let path = dir.join(self.format().file_name());
        match self {
            Writer::Xyz(t) | Writer::Lammps(t) => t.path = path,
            Writer::Gsd(g) => g.set_path(path),
            Writer::Vtk(v) => v.set_dir(dir.to_path_buf()),
        }
    }

    /// Cuts the files back to the frames written when this state was saved.
    pub fn rewind(&self) -> Result<(), TrajectoryError> {
        match self {
            Writer::Xyz(t) | Writer::Lammps(t) => {
                let file = std::fs::OpenOptions::new()
                    .write(true)
                    .open(&t.path)
                    .map_err(io_err(&t.path))?;
                file.set_len(t.bytes).map_err(io_err(&t.path))
            }
            Writer::Gsd(g) => g.rewind().map_err(io_err(g.path())),
            Writer::Vtk(v) => v.rewind(),
        }
    }
}

impl TextFile {
    fn append(
        &mut self,
        frame: &Rows,
        write: fn(&mut BufWriter<std::fs::File>, &Rows) -> std::io::Result<()>,
    ) -> Result<(), TrajectoryError> {
        let file = std::fs::OpenOptions::new()
            .append(true)
            .open(&self.path)
            .map_err(io_err(&self.path))?;
        let mut out = BufWriter::new(file);
        write(&mut out, frame)
            .and_then(|()| out.flush())
            .map_err(io_err(&self.path))?;
        self.bytes = std::fs::metadata(&self.path)
            .map_err(io_err(&self.path))?
            .len();
        self.frames += 1;
        Ok(())
    }
}
