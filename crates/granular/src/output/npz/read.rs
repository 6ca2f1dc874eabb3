//! Reading `.npy` and `.npz` files (C or Fortran order) and granular's snapshots.

use super::{NpzArray, NpzData, NpzError, io_error, zip_error};
use crate::engine::Snapshot;
use npyz::{DType, NpyFile, TypeChar};
use std::fs::File;
use std::io::{self, BufReader, Read};
use std::path::Path;

/// Reads one `.npy` array from a stream.
fn read_array_from<R: Read>(reader: R, name: &str) -> Result<NpzArray, NpzError> {
    let io_err = |source: io::Error| NpzError::Format(format!("array `{name}`: {source}"));
    let file = NpyFile::new(reader).map_err(io_err)?;
    let fortran = file.order() != npyz::Order::C && file.shape().len() > 1;
    if fortran && file.shape().len() > 2 {
        return Err(NpzError::Format(format!(
            "array `{name}` is a {}-d array in Fortran order; save it in C order \
             (numpy.ascontiguousarray)",
            file.shape().len()
        )));
    }
    let shape = file.shape().to_vec();
    let DType::Plain(ts) = file.dtype() else {
        return Err(NpzError::Format(format!(
            "array `{name}` has a structured dtype, which is not supported"
        )));
    };
    let data = match (ts.type_char(), ts.size_field()) {
        (TypeChar::Float, 8) => NpzData::F64(c_order_if(
            fortran,
            &shape,
            file.into_vec().map_err(io_err)?,
        )),
        (TypeChar::Uint, 4) => NpzData::U32(c_order_if(
            fortran,
            &shape,
            file.into_vec().map_err(io_err)?,
        )),
        (TypeChar::Uint, 8) => NpzData::U64(c_order_if(
            fortran,
            &shape,
            file.into_vec().map_err(io_err)?,
        )),
        (TypeChar::Int, 8) => NpzData::I64(c_order_if(
            fortran,
            &shape,
            file.into_vec().map_err(io_err)?,
        )),
        (TypeChar::UnicodeStr, _) => NpzData::Str(c_order_if(
            fortran,
            &shape,
            file.into_vec().map_err(io_err)?,
        )),
        _ => {
            return Err(NpzError::Format(format!(
                "array `{name}` has dtype {ts}; supported are <f8, <u4, <u8, <i8 and <U"
            )));
        }
    };
    let array = NpzArray { shape, data };
    array.check(name)?;
    Ok(array)
}

/// Row-major values of a `rows x columns` matrix stored column-major.
fn c_order<T: Clone>(column_major: &[T], rows: usize, columns: usize) -> Vec<T> {
    (0..rows)
        .flat_map(|i| (0..columns).map(move |j| column_major[j * rows + i].clone()))
        .collect()
}

/// `values` in row-major order: a 2-d array in Fortran order (a transposed array saved as
/// it lies) is column-major and reordered.
fn c_order_if<T: Clone>(fortran: bool, shape: &[u64], values: Vec<T>) -> Vec<T> {
    match (fortran, shape) {
        (true, &[r, c]) if values.len() as u64 == r * c => c_order(&values, r as usize, c as usize),
        _ => values,
    }
}

/// Reads a single `.npy` file.
///
/// # Errors
/// [`NpzError::Io`] if the file cannot be read, [`NpzError::Format`] for unsupported dtypes.
#[cfg(test)]
pub(crate) fn read_npy(path: impl AsRef<Path>) -> Result<NpzArray, NpzError> {
    let path = path.as_ref();
    let file = File::open(path).map_err(io_error(path))?;
    read_array_from(BufReader::new(file), &path.display().to_string())
}

/// Reads all arrays of an `.npz` archive (stored or deflated), in archive order.
///
/// # Errors
/// [`NpzError::Io`] / [`NpzError::Zip`] if the archive cannot be read, [`NpzError::Format`]
/// for unsupported dtypes.
pub fn read_npz(path: impl AsRef<Path>) -> Result<Vec<(String, NpzArray)>, NpzError> {
    let path = path.as_ref();
    let file = File::open(path).map_err(io_error(path))?;
    let mut zip = zip::ZipArchive::new(BufReader::new(file)).map_err(zip_error(path))?;
    let mut arrays = Vec::with_capacity(zip.len());
    for index in 0..zip.len() {
        let member = zip.by_index(index).map_err(zip_error(path))?;
        let Some(name) = npyz::npz::array_name_from_file_name(member.name()).map(str::to_owned)
        else {
            continue;
        };
        let array = read_array_from(member, &name)?;
        arrays.push((name, array));
    }
    Ok(arrays)
}

/// Reads a snapshot written by [`super::write_snapshot`] (or by numpy with the same array names;
/// `dimension` may be omitted, it is then the second extent of `positions`).
///
/// # Errors
/// As [`read_npz`]; [`NpzError::Format`] if an array is missing or has the wrong type or shape.
pub fn read_snapshot(path: impl AsRef<Path>) -> Result<Snapshot, NpzError> {
    let arrays = read_npz(path)?;
    let get = |name: &str| {
        arrays
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, a)| a)
            .ok_or_else(|| NpzError::Format(format!("snapshot has no array `{name}`")))
    };
    let f64s = |name: &str| -> Result<Vec<f64>, NpzError> {
        get(name)?
            .as_f64()
            .map(<[f64]>::to_vec)
            .ok_or_else(|| NpzError::Format(format!("snapshot array `{name}` is not float64")))
    };
    let positions = get("positions")?;
    let dimension = match positions.shape.as_slice() {
        [_, d] => *d as usize,
        other => {
            return Err(NpzError::Format(format!(
                "snapshot `positions` has shape {other:?}, expected (n, D)"
            )));
        }
    };
    if let Ok(stored) = get("dimension") {
        let stored = stored.as_u64().and_then(|v| v.first().copied());
        if stored != Some(dimension as u64) {
            return Err(NpzError::Format(format!(
                "snapshot `dimension` {stored:?} disagrees with `positions` shape"
            )));
        }
    }
    let time = f64s("time")?
        .first()
        .copied()
        .ok_or_else(|| NpzError::Format("snapshot `time` is empty".into()))?;
    let species = match &get("species")?.data {
        NpzData::U32(v) => v.clone(),
        NpzData::U64(v) => v
            .iter()
            .map(|&s| u32::try_from(s))
            .collect::<Result<_, _>>()
            .map_err(|_| NpzError::Format("snapshot `species` index too large".into()))?,
        NpzData::I64(v) => v
            .iter()
            .map(|&s| u32::try_from(s))
            .collect::<Result<_, _>>()
            .map_err(|_| NpzError::Format("snapshot `species` index out of range".into()))?,
        _ => {
            return Err(NpzError::Format(
                "snapshot `species` is not an unsigned integer array".into(),
            ));
        }
    };
    let mut species_names = get("species_names")?
        .as_strings()
        .map(<[String]>::to_vec)
        .ok_or_else(|| NpzError::Format("snapshot `species_names` is not a string array".into()))?;
    // Older files: the names as one JSON list.
    if let [one] = species_names.as_slice()
        && one.starts_with('[')
        && let Ok(names) = serde_json::from_str::<Vec<String>>(one)
    {
        species_names = names;
    }
    let snapshot = Snapshot {
        time,
        dimension,
        positions: f64s("positions")?,
        velocities: f64s("velocities")?,
        radii: f64s("radii")?,
        masses: f64s("masses")?,
        species,
        species_names,
        angular_velocities: match get("angular_velocities") {
            Ok(_) => f64s("angular_velocities")?,
            Err(_) => Vec::new(),
        },
    };
    let n = snapshot.radii.len();
    if snapshot.velocities.len() != n * dimension
        || snapshot.positions.len() != n * dimension
        || snapshot.masses.len() != n
        || snapshot.species.len() != n
        || !(snapshot.angular_velocities.is_empty()
            || snapshot.angular_velocities.len() == n * dimension * (dimension - 1) / 2)
    {
        return Err(NpzError::Format(
            "snapshot arrays have inconsistent lengths".into(),
        ));
    }
    if let Some(&bad) = snapshot
        .species
        .iter()
        .find(|&&s| s as usize >= snapshot.species_names.len())
    {
        return Err(NpzError::Format(format!(
            "snapshot species index {bad} has no name ({} names)",
            snapshot.species_names.len()
        )));
    }
    Ok(snapshot)
}
