//! Per-grain vectors of a scenario (`species[i].positions`, `species[i].velocity.velocities`):
//! written inline in TOML, read from a member of an `.npz` file, or given by a program (NumPy
//! arrays through the Python package) without any text.
//!
//! The values are one flat row-major `f64` block behind an `Arc`: a million grains are one
//! allocation, and cloning a scenario (Python does it at every `set`) copies a pointer.

use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::sync::Arc;

/// Where the vectors of a [`GrainVectors`] come from (kept so that the scenario writes them
/// back the way they were given).
#[derive(Clone, Debug, PartialEq)]
pub enum VectorSource {
    /// Nested TOML arrays, `[[x, y], ...]`.
    Inline,
    /// A member of an `.npz` file, `{ npz = "file.npz", array = "positions" }`: a relative
    /// path is read from the scenario file's directory.
    Npz {
        /// The `.npz` file as written in the scenario.
        npz: String,
        /// The member; `None`: the key's last name (`positions`, `velocities`).
        array: Option<String>,
    },
    /// Given by a program (NumPy arrays): written inline by `to_toml`, and to the run
    /// directory's `initial_state.npz` by a run.
    Given,
}

/// One vector per grain, row-major.
#[derive(Clone, Debug)]
pub struct GrainVectors {
    values: Arc<Vec<f64>>,
    width: usize,
    source: VectorSource,
    /// False only for an `.npz` member not read yet (right after parsing).
    loaded: bool,
}

impl Default for GrainVectors {
    fn default() -> Self {
        Self {
            values: Arc::new(Vec::new()),
            width: 0,
            source: VectorSource::Inline,
            loaded: true,
        }
    }
}

/// Two scenarios with the same vectors are the same, however they were given.
impl PartialEq for GrainVectors {
    fn eq(&self, other: &Self) -> bool {
        self.width == other.width
            && (Arc::ptr_eq(&self.values, &other.values) || self.values == other.values)
    }
}

impl GrainVectors {
    /// Vectors of `width` components from row-major `values` (whose length must be a
    /// multiple of `width`), marked as given by a program.
    pub fn given(values: Vec<f64>, width: usize) -> Option<Self> {
        (width > 0 && values.len().is_multiple_of(width)).then(|| Self {
            values: Arc::new(values),
            width,
            source: VectorSource::Given,
            loaded: true,
        })
    }

    /// Vectors from nested rows (inline TOML); `None` when the rows differ in length.
    pub(crate) fn from_rows(rows: &[Vec<f64>]) -> Result<Self, String> {
        let width = rows.first().map_or(0, Vec::len);
        if let Some((i, r)) = rows.iter().enumerate().find(|(_, r)| r.len() != width) {
            return Err(format!(
                "row {i} has {} numbers where row 0 has {width}; give one [x, y] (2D) or \
                 [x, y, z] (3D) per grain",
                r.len()
            ));
        }
        Ok(Self {
            values: Arc::new(rows.concat()),
            width,
            source: VectorSource::Inline,
            loaded: true,
        })
    }

    /// Number of grains (rows).
    pub fn len(&self) -> usize {
        self.values.len().checked_div(self.width).unwrap_or(0)
    }

    /// Whether there are none (and no file to read them from).
    pub fn is_empty(&self) -> bool {
        self.loaded && self.values.is_empty()
    }

    /// Components per grain (0 when empty).
    pub fn width(&self) -> usize {
        self.width
    }

    /// The rows, one `&[f64]` per grain.
    pub fn iter(&self) -> std::slice::ChunksExact<'_, f64> {
        self.values.chunks_exact(self.width.max(1))
    }

    /// The values, row-major.
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// Where they come from.
    pub fn source(&self) -> &VectorSource {
        &self.source
    }

    /// The `.npz` file and member still to read (the member defaulting to `default`).
    pub(crate) fn unread(&self, default: &str) -> Option<(&str, String)> {
        match (&self.source, self.loaded) {
            (VectorSource::Npz { npz, array }, false) => Some((
                npz.as_str(),
                array.clone().unwrap_or_else(|| default.to_string()),
            )),
            _ => None,
        }
    }

    /// Fills an `.npz` reference with the member's values.
    pub(crate) fn fill(&mut self, values: Vec<f64>, width: usize) {
        self.values = Arc::new(values);
        self.width = width;
        self.loaded = true;
    }

    /// The same vectors, now kept in member `array` of the `.npz` file `npz`.
    pub(crate) fn stored_in(&self, npz: &str, array: &str) -> Self {
        Self {
            source: VectorSource::Npz {
                npz: npz.to_string(),
                array: Some(array.to_string()),
            },
            ..self.clone()
        }
    }
}

/// `{ npz = "...", array = "..." }`, the file form.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct NpzRef {
    npz: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    array: Option<String>,
}

#[derive(Deserialize)]
#[serde(untagged)]
enum Written {
    Rows(Vec<Vec<f64>>),
    File(NpzRef),
}

impl Serialize for GrainVectors {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match &self.source {
            VectorSource::Npz { npz, array } => NpzRef {
                npz: npz.clone(),
                array: array.clone(),
            }
            .serialize(s),
            VectorSource::Inline | VectorSource::Given => {
                let rows: Vec<&[f64]> = self.iter().collect();
                rows.serialize(s)
            }
        }
    }
}

impl<'de> Deserialize<'de> for GrainVectors {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        match Written::deserialize(d).map_err(|_| {
            serde::de::Error::custom(
                "give one [x, y] (2D) or [x, y, z] (3D) per grain, or an .npz member as \
                 { npz = \"file.npz\", array = \"name\" }",
            )
        })? {
            Written::Rows(rows) => Self::from_rows(&rows).map_err(serde::de::Error::custom),
            Written::File(NpzRef { npz, array }) => Ok(Self {
                values: Arc::new(Vec::new()),
                width: 0,
                source: VectorSource::Npz { npz, array },
                loaded: false,
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_round_trip_and_ragged_rows_are_refused() {
        let v = GrainVectors::from_rows(&[vec![1.0, 2.0], vec![3.0, 4.0]]).unwrap();
        assert_eq!(v.len(), 2);
        assert_eq!(v.iter().nth(1), Some(&[3.0, 4.0][..]));
        let e = GrainVectors::from_rows(&[vec![1.0, 2.0], vec![3.0]]).unwrap_err();
        assert!(e.contains("row 1 has 1 numbers where row 0 has 2"), "{e}");
        let g = GrainVectors::given(vec![1.0, 2.0, 3.0, 4.0], 2).unwrap();
        assert_eq!(g, v, "equal whatever the source");
        assert!(GrainVectors::given(vec![1.0, 2.0, 3.0], 2).is_none());
    }
}
