//! NumPy `.npy` and `.npz` files: named, shaped `f64` / `u32` / `u64` / `i64` / string arrays.
//!
//! Arrays are written little-endian in C order, so `numpy.load` reads them on any machine
//! without `allow_pickle`; strings are fixed-width unicode (`<U{n}`), which numpy reads as
//! a `str_` array. `.npz` archives are zip files of `.npy` members, stored uncompressed by
//! [`write_npz`] (fast, and what `numpy.savez` itself writes); [`read_npz`] also reads the
//! deflate-compressed archives of `numpy.savez_compressed`.
//!
//! A snapshot written by [`write_snapshot`] reads in Python as
//!
//! ```python
//! import numpy as np
//! s = np.load("snapshot.npz")
//! s["time"]          # 0-d float64 array: s["time"][()] or float(s["time"])
//! s["positions"]     # (n, D) float64
//! s["velocities"]    # (n, D) float64
//! s["radii"], s["masses"]          # (n,) float64
//! s["species"]       # (n,) uint32, indices into s["species_names"]
//! s["species_names"] # (k,) <U…  e.g. array(['bath', 'intruder'], dtype='<U8')
//! ```
//!
//! (checked by hand with numpy 2.4; the cargo tests do not need Python: they read archives
//! that numpy wrote, stored under `testdata/`).

use std::fs::File;
use std::io::{self, BufWriter, Seek, Write};
use std::path::Path;

use npyz::{DType, TypeStr, WriterBuilder};

mod read;
mod stream;
#[cfg(test)]
pub(crate) use read::read_npy;
pub use read::{read_npz, read_snapshot};
pub(crate) use stream::{Fill, StreamedSnapshot, write_snapshot_streamed};

use crate::engine::Snapshot;

/// Why an array file could not be written or read.
#[derive(Debug, thiserror::Error)]
pub enum NpzError {
    /// The file system or the stream failed.
    #[error("I/O error on {path}: {source}")]
    Io {
        /// The file being written or read.
        path: String,
        /// The underlying error.
        source: io::Error,
    },
    /// The zip container is damaged or unsupported.
    #[error("bad npz archive {path}: {message}")]
    Zip {
        /// The archive.
        path: String,
        /// What the zip reader said.
        message: String,
    },
    /// An array is missing, has the wrong type, or has a shape that does not fit its data.
    #[error("{0}")]
    Format(String),
}

/// The values of one array, in C (row-major) order.
#[derive(Clone, Debug, PartialEq)]
pub enum NpzData {
    /// `float64` values.
    F64(Vec<f64>),
    /// `uint32` values.
    U32(Vec<u32>),
    /// `uint64` values.
    U64(Vec<u64>),
    /// `int64` values.
    I64(Vec<i64>),
    /// Unicode strings, written as fixed-width `<U{n}` with `n` the longest string.
    Str(Vec<String>),
}

impl NpzData {
    /// Number of values.
    pub fn len(&self) -> usize {
        match self {
            NpzData::F64(v) => v.len(),
            NpzData::U32(v) => v.len(),
            NpzData::U64(v) => v.len(),
            NpzData::I64(v) => v.len(),
            NpzData::Str(v) => v.len(),
        }
    }

    /// Whether there are no values.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// NumPy's name for the element type (`"float64"`, `"uint32"`, …).
    pub(crate) fn type_name(&self) -> &'static str {
        match self {
            NpzData::F64(_) => "float64",
            NpzData::U32(_) => "uint32",
            NpzData::U64(_) => "uint64",
            NpzData::I64(_) => "int64",
            NpzData::Str(_) => "str",
        }
    }
}

/// One shaped array: `shape` `[]` is a scalar (one value), `[n]` a vector, `[n, d]` a matrix.
#[derive(Clone, Debug, PartialEq)]
pub struct NpzArray {
    /// Extent along each axis; the product must equal the number of values.
    pub shape: Vec<u64>,
    /// The values, row-major.
    pub data: NpzData,
}

impl NpzArray {
    /// A 0-d (scalar) `float64` array.
    pub(crate) fn scalar(value: f64) -> Self {
        Self {
            shape: vec![],
            data: NpzData::F64(vec![value]),
        }
    }

    /// A 1-d `float64` array.
    pub fn f64_1d(values: Vec<f64>) -> Self {
        Self {
            shape: vec![values.len() as u64],
            data: NpzData::F64(values),
        }
    }

    /// A 1-d `uint32` array.
    pub fn u32_1d(values: Vec<u32>) -> Self {
        Self {
            shape: vec![values.len() as u64],
            data: NpzData::U32(values),
        }
    }

    /// A 1-d `uint64` array.
    pub(crate) fn u64_1d(values: Vec<u64>) -> Self {
        Self {
            shape: vec![values.len() as u64],
            data: NpzData::U64(values),
        }
    }

    /// A 1-d string array.
    pub(crate) fn strings(values: Vec<String>) -> Self {
        Self {
            shape: vec![values.len() as u64],
            data: NpzData::Str(values),
        }
    }

    /// A `rows x columns` `float64` matrix from row-major values.
    ///
    /// # Errors
    /// [`NpzError::Format`] if `values.len() != rows * columns`.
    pub fn f64_2d(values: Vec<f64>, rows: usize, columns: usize) -> Result<Self, NpzError> {
        let array = Self {
            shape: vec![rows as u64, columns as u64],
            data: NpzData::F64(values),
        };
        array.check("matrix")?;
        Ok(array)
    }

    /// The values as `f64` if the array is `float64`.
    pub fn as_f64(&self) -> Option<&[f64]> {
        match &self.data {
            NpzData::F64(v) => Some(v),
            _ => None,
        }
    }

    /// The values as `u32` if the array is `uint32`.
    pub fn as_u32(&self) -> Option<&[u32]> {
        match &self.data {
            NpzData::U32(v) => Some(v),
            _ => None,
        }
    }

    /// The values as `u64` if the array is `uint64`.
    pub fn as_u64(&self) -> Option<&[u64]> {
        match &self.data {
            NpzData::U64(v) => Some(v),
            _ => None,
        }
    }

    /// The values as strings if the array is a string array.
    pub(crate) fn as_strings(&self) -> Option<&[String]> {
        match &self.data {
            NpzData::Str(v) => Some(v),
            _ => None,
        }
    }

    fn element_count(&self) -> Option<u64> {
        self.shape
            .iter()
            .try_fold(1u64, |acc, &extent| acc.checked_mul(extent))
    }

    fn check(&self, name: &str) -> Result<(), NpzError> {
        match self.element_count() {
            Some(count) if count == self.data.len() as u64 => Ok(()),
            _ => Err(NpzError::Format(format!(
                "array `{name}`: shape {:?} does not hold {} values",
                self.shape,
                self.data.len()
            ))),
        }
    }
}

fn type_str(text: &str) -> DType {
    // The strings passed here are literals of valid type strings.
    DType::Plain(
        text.parse::<TypeStr>()
            .unwrap_or_else(|_| unreachable!("valid type string {text}")),
    )
}

/// Writes one array in `.npy` format to a stream (which need not be seekable).
fn write_array_to<W: Write>(writer: W, name: &str, array: &NpzArray) -> io::Result<()> {
    array
        .check(name)
        .map_err(|e| io::Error::new(io::ErrorKind::InvalidInput, e.to_string()))?;
    let shape = array.shape.as_slice();
    match &array.data {
        NpzData::F64(v) => {
            let mut w = npyz::WriteOptions::<f64>::new()
                .dtype(type_str("<f8"))
                .shape(shape)
                .writer(writer)
                .begin_nd()?;
            w.extend(v.iter().copied())?;
            w.finish()
        }
        NpzData::U32(v) => {
            let mut w = npyz::WriteOptions::<u32>::new()
                .dtype(type_str("<u4"))
                .shape(shape)
                .writer(writer)
                .begin_nd()?;
            w.extend(v.iter().copied())?;
            w.finish()
        }
        NpzData::U64(v) => {
            let mut w = npyz::WriteOptions::<u64>::new()
                .dtype(type_str("<u8"))
                .shape(shape)
                .writer(writer)
                .begin_nd()?;
            w.extend(v.iter().copied())?;
            w.finish()
        }
        NpzData::I64(v) => {
            let mut w = npyz::WriteOptions::<i64>::new()
                .dtype(type_str("<i8"))
                .shape(shape)
                .writer(writer)
                .begin_nd()?;
            w.extend(v.iter().copied())?;
            w.finish()
        }
        NpzData::Str(v) => {
            let width = v
                .iter()
                .map(|s| s.chars().count())
                .max()
                .unwrap_or(1)
                .max(1);
            let mut w = npyz::WriteOptions::<str>::new()
                .dtype(type_str(&format!("<U{width}")))
                .shape(shape)
                .writer(writer)
                .begin_nd()?;
            for s in v {
                w.push(s.as_str())?;
            }
            w.finish()
        }
    }
}

fn io_error(path: &Path) -> impl Fn(io::Error) -> NpzError + '_ {
    move |source| NpzError::Io {
        path: path.display().to_string(),
        source,
    }
}

fn zip_error(path: &Path) -> impl Fn(zip::result::ZipError) -> NpzError + '_ {
    move |e| match e {
        zip::result::ZipError::Io(source) => NpzError::Io {
            path: path.display().to_string(),
            source,
        },
        other => NpzError::Zip {
            path: path.display().to_string(),
            message: other.to_string(),
        },
    }
}

/// Writes a single array as a `.npy` file.
///
/// # Errors
/// [`NpzError::Io`] if the file cannot be written, [`NpzError::Format`] if the shape does not
/// match the number of values.
#[cfg(test)]
pub(crate) fn write_npy(path: impl AsRef<Path>, array: &NpzArray) -> Result<(), NpzError> {
    let path = path.as_ref();
    array.check(&path.display().to_string())?;
    let file = File::create(path).map_err(io_error(path))?;
    let mut writer = BufWriter::new(file);
    write_array_to(&mut writer, "array", array).map_err(io_error(path))?;
    writer.flush().map_err(io_error(path))
}

/// Writes named arrays as an (uncompressed) `.npz` archive, in the given order.
///
/// # Errors
/// [`NpzError::Io`] / [`NpzError::Zip`] if the file cannot be written, [`NpzError::Format`]
/// if a name repeats or a shape does not match its values.
pub fn write_npz(path: impl AsRef<Path>, arrays: &[(&str, NpzArray)]) -> Result<(), NpzError> {
    let path = path.as_ref();
    for (i, (name, array)) in arrays.iter().enumerate() {
        array.check(name)?;
        if arrays[..i].iter().any(|(other, _)| other == name) {
            return Err(NpzError::Format(format!("array name `{name}` repeats")));
        }
    }
    let file = File::create(path).map_err(io_error(path))?;
    write_npz_to(BufWriter::new(file), arrays, path)
}

fn write_npz_to<W: Write + Seek>(
    writer: W,
    arrays: &[(&str, NpzArray)],
    path: &Path,
) -> Result<(), NpzError> {
    let mut zip = zip::ZipWriter::new(writer);
    let options = zip::write::FileOptions::default()
        .compression_method(zip::CompressionMethod::Stored)
        .large_file(arrays.iter().any(|(_, a)| a.data.len() > (1 << 26)));
    for (name, array) in arrays {
        zip.start_file(npyz::npz::file_name_from_array_name(name), options)
            .map_err(zip_error(path))?;
        write_array_to(&mut zip, name, array).map_err(io_error(path))?;
    }
    let mut inner = zip.finish().map_err(zip_error(path))?;
    inner.flush().map_err(io_error(path))
}

/// Writes a snapshot as `.npz` with arrays `time` (0-d), `positions` and `velocities`
/// (`n x D`), `radii`, `masses` (`n`), `species` (`n`, `uint32`), `species_names` (`k`,
/// unicode) and `dimension` (0-d `uint64`).
///
/// # Errors
/// [`NpzError::Format`] if the snapshot's arrays do not have consistent lengths, otherwise
/// as [`write_npz`].
pub fn write_snapshot(path: impl AsRef<Path>, snapshot: &Snapshot) -> Result<(), NpzError> {
    let d = snapshot.dimension;
    if d == 0 {
        return Err(NpzError::Format("snapshot has dimension 0".into()));
    }
    let n = snapshot.radii.len();
    let per_particle = [
        ("positions", snapshot.positions.len(), n * d),
        ("velocities", snapshot.velocities.len(), n * d),
        ("masses", snapshot.masses.len(), n),
        ("species", snapshot.species.len(), n),
    ];
    for (name, got, want) in per_particle {
        if got != want {
            return Err(NpzError::Format(format!(
                "snapshot `{name}` has {got} values, expected {want} for {n} particles in {d}D"
            )));
        }
    }
    let mut arrays = vec![
        ("time", NpzArray::scalar(snapshot.time)),
        (
            "dimension",
            NpzArray {
                shape: vec![],
                data: NpzData::U64(vec![d as u64]),
            },
        ),
        (
            "positions",
            NpzArray::f64_2d(snapshot.positions.clone(), n, d)?,
        ),
        (
            "velocities",
            NpzArray::f64_2d(snapshot.velocities.clone(), n, d)?,
        ),
        ("radii", NpzArray::f64_1d(snapshot.radii.clone())),
        ("masses", NpzArray::f64_1d(snapshot.masses.clone())),
        ("species", NpzArray::u32_1d(snapshot.species.clone())),
        (
            "species_names",
            NpzArray::strings(snapshot.species_names.clone()),
        ),
    ];
    // Rough grains: `angular_velocities`, (n,) for disks (ω_z), (n, 3) for spheres.
    if !snapshot.angular_velocities.is_empty() {
        let r = d * (d - 1) / 2;
        if snapshot.angular_velocities.len() != n * r {
            return Err(NpzError::Format(format!(
                "snapshot `angular_velocities` has {} values, expected {} for {n} particles in {d}D",
                snapshot.angular_velocities.len(),
                n * r
            )));
        }
        let w = snapshot.angular_velocities.clone();
        let array = if r == 1 {
            NpzArray::f64_1d(w)
        } else {
            NpzArray::f64_2d(w, n, r)?
        };
        arrays.push(("angular_velocities", array));
    }
    write_npz(path, &arrays)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp_path(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("granular-npz-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        dir.join(name)
    }

    fn sample_snapshot() -> Snapshot {
        Snapshot {
            time: 12.5,
            dimension: 2,
            positions: vec![0.1, 0.2, 0.3, 0.4, 0.5, 0.6],
            velocities: vec![-1.0, 1.0, 2.0, -2.0, 0.0, 3.5],
            radii: vec![0.01, 0.01, 0.05],
            masses: vec![1.0, 1.0, 25.0],
            species: vec![0, 0, 1],
            species_names: vec!["bath".into(), "intruder".into()],
            ..Default::default()
        }
    }

    #[test]
    fn snapshot_round_trip() {
        let path = temp_path("snap.npz");
        let s = sample_snapshot();
        write_snapshot(&path, &s).expect("write");
        let r = read_snapshot(&path).expect("read");
        assert_eq!(r.time, s.time);
        assert_eq!(r.dimension, 2);
        assert_eq!(r.positions, s.positions);
        assert_eq!(r.velocities, s.velocities);
        assert_eq!(r.radii, s.radii);
        assert_eq!(r.masses, s.masses);
        assert_eq!(r.species, s.species);
        assert_eq!(r.species_names, s.species_names);
        let arrays = read_npz(&path).expect("read npz");
        let positions = &arrays
            .iter()
            .find(|(n, _)| n == "positions")
            .expect("positions")
            .1;
        assert_eq!(positions.shape, vec![3, 2]);
        let time = &arrays.iter().find(|(n, _)| n == "time").expect("time").1;
        assert!(time.shape.is_empty());
    }

    #[test]
    fn snapshot_3d_and_empty_names() {
        let path = temp_path("snap3.npz");
        let s = Snapshot {
            time: 0.0,
            dimension: 3,
            positions: vec![1.0, 2.0, 3.0],
            velocities: vec![0.0; 3],
            radii: vec![0.5],
            masses: vec![2.0],
            species: vec![0],
            species_names: vec![String::new()],
            ..Default::default()
        };
        write_snapshot(&path, &s).expect("write");
        let r = read_snapshot(&path).expect("read");
        assert_eq!(r.dimension, 3);
        assert_eq!(r.species_names, vec![String::new()]);
        assert!(r.angular_velocities.is_empty());
    }

    /// Rough grains: `angular_velocities` (n,) in 2D and (n, 3) in 3D, read back; a smooth
    /// snapshot has no such array.
    #[test]
    fn snapshot_angular_velocities() {
        let path = temp_path("snap_rough2.npz");
        let mut s = sample_snapshot();
        write_snapshot(&path, &s).expect("write");
        let arrays = read_npz(&path).expect("read npz");
        assert!(arrays.iter().all(|(n, _)| n != "angular_velocities"));
        s.angular_velocities = vec![1.0, -2.0, 0.5];
        write_snapshot(&path, &s).expect("write");
        let arrays = read_npz(&path).expect("read npz");
        let w = &arrays
            .iter()
            .find(|(n, _)| n == "angular_velocities")
            .expect("w")
            .1;
        assert_eq!(w.shape, vec![3]);
        assert_eq!(
            read_snapshot(&path).expect("read").angular_velocities,
            s.angular_velocities
        );
        let path = temp_path("snap_rough3.npz");
        let s3 = Snapshot {
            time: 0.0,
            dimension: 3,
            positions: vec![1.0, 2.0, 3.0],
            velocities: vec![0.0; 3],
            radii: vec![0.5],
            masses: vec![2.0],
            species: vec![0],
            species_names: vec!["a".into()],
            angular_velocities: vec![0.1, 0.2, 0.3],
        };
        write_snapshot(&path, &s3).expect("write");
        let arrays = read_npz(&path).expect("read npz");
        let w = &arrays
            .iter()
            .find(|(n, _)| n == "angular_velocities")
            .expect("w")
            .1;
        assert_eq!(w.shape, vec![1, 3]);
        assert_eq!(
            read_snapshot(&path).expect("read").angular_velocities,
            s3.angular_velocities
        );
        s.angular_velocities = vec![1.0];
        assert!(write_snapshot(&path, &s).is_err());
    }

    #[test]
    fn generic_npz_and_npy_round_trip() {
        let path = temp_path("generic.npz");
        let arrays = vec![
            ("a", NpzArray::f64_1d(vec![1.0, f64::NAN, -0.0])),
            (
                "b",
                NpzArray {
                    shape: vec![2, 2],
                    data: NpzData::U64(vec![1, 2, 3, u64::MAX]),
                },
            ),
            (
                "c",
                NpzArray {
                    shape: vec![3],
                    data: NpzData::I64(vec![-1, 0, 1]),
                },
            ),
            ("names", NpzArray::strings(vec!["α-β".into(), "x".into()])),
            ("empty", NpzArray::f64_1d(vec![])),
        ];
        write_npz(&path, &arrays).expect("write");
        let back = read_npz(&path).expect("read");
        assert_eq!(back.len(), arrays.len());
        for ((n1, a1), (n2, a2)) in arrays.iter().zip(&back) {
            assert_eq!(n1, n2);
            assert_eq!(a1.shape, a2.shape);
            if let (Some(x), Some(y)) = (a1.as_f64(), a2.as_f64()) {
                for (p, q) in x.iter().zip(y) {
                    assert_eq!(p.to_bits(), q.to_bits());
                }
            } else {
                assert_eq!(a1.data, a2.data);
            }
        }

        let npy = temp_path("single.npy");
        let m = NpzArray::f64_2d(vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0], 2, 3).expect("shape");
        write_npy(&npy, &m).expect("write npy");
        assert_eq!(read_npy(&npy).expect("read npy"), m);
    }

    /// Archives written by numpy 2.4 (`np.savez_compressed` with uint32 species, and
    /// `np.savez` with int64 species and no `dimension`); see `testdata/`.
    #[test]
    fn reads_numpy_written_archives() {
        for (name, bytes) in [
            (
                "compressed.npz",
                &include_bytes!("testdata/numpy_savez_compressed.npz")[..],
            ),
            ("plain.npz", &include_bytes!("testdata/numpy_savez.npz")[..]),
        ] {
            let path = temp_path(name);
            std::fs::write(&path, bytes).expect("write fixture");
            let s = read_snapshot(&path).expect("read numpy archive");
            assert_eq!(s.time, 3.0);
            assert_eq!(s.dimension, 2);
            assert_eq!(s.positions, vec![0.0, 1.0, 2.0, 3.0, 4.0, 5.0]);
            assert_eq!(s.species, vec![0, 1, 1]);
            assert_eq!(s.species_names, vec!["a".to_string(), "bb".to_string()]);
        }
    }

    #[test]
    fn bad_shapes_and_names_are_rejected() {
        assert!(NpzArray::f64_2d(vec![1.0; 5], 2, 3).is_err());
        let path = temp_path("bad.npz");
        let dup = [("x", NpzArray::scalar(1.0)), ("x", NpzArray::scalar(2.0))];
        assert!(matches!(write_npz(&path, &dup), Err(NpzError::Format(_))));
        let mut s = sample_snapshot();
        s.masses.pop();
        assert!(matches!(
            write_snapshot(&path, &s),
            Err(NpzError::Format(_))
        ));
        assert!(matches!(
            read_snapshot(temp_path("does-not-exist.npz")),
            Err(NpzError::Io { .. })
        ));
    }
}
