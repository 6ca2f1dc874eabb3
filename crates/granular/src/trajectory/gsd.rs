//! GSD files (General Simulation Data, the format of HOOMD-blue): our own writer of the
//! version 2 file layer and the frames of the HOOMD schema, after the specification of
//! glotzerlab/gsd (`doc/file-layer.rst`, `doc/schema-hoomd.rst`). No Rust crate writes GSD.
//!
//! # File layer (version 2.0, little-endian)
//!
//! * A 256-byte header: magic `0x65DF65DF65DF65DF`, the location and capacity (entries)
//!   of the index block, the location and size (in 64-byte segments) of the name list,
//!   the schema version, the file-layer version (`major << 16 | minor`), the application
//!   and schema names (64 bytes each, zero-padded) and 80 reserved bytes.
//! * The index block: 32-byte entries `frame: u64, N: u64, location: i64, M: u32, id: u16,
//!   type: u8, flags: u8`, sorted by frame, then by name id; the first entry with location
//!   0 ends the list. When it is full a block twice as large is written at the end of the
//!   file and the header is pointed at it.
//! * The name list: the chunk names, each ending in a zero byte, then a zero byte. All
//!   names are written when the file is created (this writer writes the same chunks in
//!   every frame), so a name's id is its place in that list.
//! * Data chunks: `N x M` values of the entry's type, row-major, appended frame by frame.
//!
//! # HOOMD schema 1.4 (what [`frame_chunks`] writes per frame)
//!
//! `configuration/step` (u64: the output index), `configuration/dimensions` (u8: 2 or 3),
//! `configuration/box` (6 x f32: `Lx Ly Lz xy xz yz`, `Lz = 0` in 2D), `particles/N`
//! (u32), `particles/types` (the species names, zero-padded bytes), `particles/typeid`
//! (u32, the species index), `particles/mass`, `particles/diameter` (f32),
//! `particles/position`, `particles/velocity` (N x 3 f32; `z = 0` in 2D), and in the
//! schema's free `log/` namespace `log/time` (f64: the simulation time),
//! `log/box/periodic` (3 x u8: 1 periodic, 0 hard walls; 0 along z in 2D) and
//! `log/particles/id` (N x u64: the grain's id, from 0, as in the snapshots). HOOMD's box
//! is centred on the origin: positions are the run's minus `L/2` per axis. The schema has
//! no walls (a HOOMD box is periodic on every axis), hence `log/box/periodic`; readers
//! that know only the schema (OVITO, HOOMD-blue) see a periodic box. Positions and
//! velocities are single precision, as the schema 1.x requires.
//!
//! # Rough grains
//!
//! A rough run's file has two more names, [`SPIN_NAMES`] (ids 13 and 14, after the
//! others; a smooth run's file has neither name nor chunk), and every frame two more
//! chunks:
//!
//! * `particles/moment_inertia` (N x 3 f32): the principal moments `(I_xx, I_yy, I_zz)`
//!   with `I = κ m R²` (`κ = 4I/(mσ²)` of the grain's species, `σ = 2R`): `(I, I, I)` for a
//!   sphere, `(0, 0, I)` for a disk, because HOOMD-blue in two dimensions integrates and
//!   counts only the rotation about z (`IntegrationMethodTwoStep::getRotationalDOF` in
//!   glotzerlab/hoomd-blue, `hoomd/md/IntegrationMethodTwoStep.cc`: in 2D only a non-zero
//!   `moment_inertia.z` is a degree of freedom);
//! * `particles/angmom` (N x 4 f32): HOOMD's angular momentum conjugate quaternion
//!   `P = 2 q ⊗ (0, S)`, with `S` the angular momentum in the particle's body frame and
//!   `q` its orientation, so that `S = ½ Im(q* ⊗ P)` (glotzerlab/hoomd-blue,
//!   `sphinx-doc/aniso.rst`, "Quaternions for angular momentum", after Kamberaj, Low and
//!   Neal, J. Chem. Phys. 122, 224114 (2005); `hoomd/md/ComputeThermo.cc` computes the
//!   rotational kinetic energy from `s = 0.5 conj(q) p` and `s.v.k² / I_k`). Grains have no
//!   orientation here: the file has no `particles/orientation`, which HOOMD reads as the
//!   identity `q = (1, 0, 0, 0)`, so the body frame is the box frame and
//!   `P = (0, 2 I ω_x, 2 I ω_y, 2 I ω_z)` (a disk: `(0, 0, 0, 2 I ω_z)`). A reader gets
//!   `ω_k = P_k / (2 I_k)` back (in single precision) where `I_k > 0`.

use super::{Frame, Rows};
use serde::{Deserialize, Serialize};
use std::fs::{File, OpenOptions};
use std::io::{self, Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

const MAGIC: u64 = 0x65DF_65DF_65DF_65DF;
const HEADER_BYTES: u64 = 256;
const ENTRY_BYTES: u64 = 32;
const NAME_SEGMENT: u64 = 64;
const INITIAL_ENTRIES: u64 = 128;

fn version(major: u32, minor: u32) -> u32 {
    (major << 16) | minor
}

/// The type of a chunk's values (the file layer's type codes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ChunkType {
    /// `uint8`
    U8 = 1,
    /// `uint32`
    U32 = 3,
    /// `uint64`
    U64 = 4,
    /// `int8`
    I8 = 5,
    /// `float32`
    F32 = 9,
    /// `float64`
    F64 = 10,
}

/// One named array of a frame: `n x m` values of `kind`, as little-endian bytes.
#[derive(Clone, Debug)]
pub struct Chunk {
    /// Place of the chunk's name in the file's name list.
    pub id: u16,
    /// The value type.
    pub kind: ChunkType,
    /// Rows.
    pub n: u64,
    /// Columns.
    pub m: u32,
    /// The values.
    pub data: Vec<u8>,
}

/// One named array of a frame whose bytes are written by a function (a frame written
/// piece by piece, [`frame_rows`]).
pub struct StreamedChunk<'a> {
    /// Place of the chunk's name in the file's name list.
    pub id: u16,
    /// The value type.
    pub kind: ChunkType,
    /// Rows.
    pub n: u64,
    /// Columns.
    pub m: u32,
    /// Bytes the chunk holds (`n m` values).
    pub bytes: u64,
    /// Writes the values, little-endian.
    pub write: ChunkWriter<'a>,
}

/// Writes a streamed chunk's values into the file.
pub type ChunkWriter<'a> = Box<dyn FnMut(&mut dyn Write) -> io::Result<()> + 'a>;

/// A GSD file being appended to; the state is small and serialisable (it goes into a
/// checkpoint), and the file is opened only while a frame is written.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct GsdFile {
    #[serde(skip)]
    path: PathBuf,
    index_location: u64,
    index_capacity: u64,
    entries: u64,
    frames: u64,
    bytes: u64,
}

impl GsdFile {
    /// Creates (or truncates) `path` with an empty index and the name list `names`.
    pub fn create(
        path: &Path,
        application: &str,
        schema: &str,
        schema_version: (u32, u32),
        names: &[&str],
    ) -> io::Result<GsdFile> {
        let mut namelist: Vec<u8> = Vec::new();
        for n in names {
            namelist.extend_from_slice(n.as_bytes());
            namelist.push(0);
        }
        namelist.push(0);
        let segments = (namelist.len() as u64).div_ceil(NAME_SEGMENT);
        namelist.resize((segments * NAME_SEGMENT) as usize, 0);
        let index_location = HEADER_BYTES;
        let namelist_location = index_location + INITIAL_ENTRIES * ENTRY_BYTES;
        let mut header = Vec::with_capacity(HEADER_BYTES as usize);
        for v in [
            MAGIC,
            index_location,
            INITIAL_ENTRIES,
            namelist_location,
            segments,
        ] {
            header.extend_from_slice(&v.to_le_bytes());
        }
        header.extend_from_slice(&version(schema_version.0, schema_version.1).to_le_bytes());
        header.extend_from_slice(&version(2, 0).to_le_bytes());
        for text in [application, schema] {
            let mut field = [0u8; 64];
            let b = text.as_bytes();
            let k = b.len().min(63);
            field[..k].copy_from_slice(&b[..k]);
            header.extend_from_slice(&field);
        }
        header.resize(HEADER_BYTES as usize, 0);
        let mut file = File::create(path)?;
        file.write_all(&header)?;
        file.write_all(&vec![0u8; (INITIAL_ENTRIES * ENTRY_BYTES) as usize])?;
        file.write_all(&namelist)?;
        file.sync_data()?;
        Ok(GsdFile {
            path: path.to_path_buf(),
            index_location,
            index_capacity: INITIAL_ENTRIES,
            entries: 0,
            frames: 0,
            bytes: namelist_location + namelist.len() as u64,
        })
    }

    /// The file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    pub(crate) fn set_path(&mut self, path: PathBuf) {
        self.path = path;
    }

    /// Frames written.
    pub fn frames(&self) -> u64 {
        self.frames
    }

    /// Appends one frame; `chunks` must be in increasing order of `id`.
    pub fn append_frame(&mut self, chunks: &[Chunk]) -> io::Result<()> {
        let streamed: Vec<StreamedChunk<'_>> = chunks
            .iter()
            .map(|c| StreamedChunk {
                id: c.id,
                kind: c.kind,
                n: c.n,
                m: c.m,
                bytes: c.data.len() as u64,
                write: Box::new(move |w: &mut dyn Write| w.write_all(&c.data)),
            })
            .collect();
        self.append_streamed(streamed)
    }

    /// [`GsdFile::append_frame`] with each chunk's bytes written by its `write` (in
    /// memory independent of the chunk's size); `chunks` in increasing order of `id`,
    /// each `write` writing exactly its `bytes`.
    pub fn append_streamed(&mut self, chunks: Vec<StreamedChunk<'_>>) -> io::Result<()> {
        debug_assert!(chunks.windows(2).all(|w| w[0].id < w[1].id));
        let mut file = OpenOptions::new().read(true).write(true).open(&self.path)?;
        let mut end = self.bytes;
        let mut entries = Vec::with_capacity(chunks.len() * ENTRY_BYTES as usize);
        let mut location = end;
        for c in &chunks {
            entries.extend_from_slice(&self.frames.to_le_bytes());
            entries.extend_from_slice(&c.n.to_le_bytes());
            entries.extend_from_slice(&(location as i64).to_le_bytes());
            entries.extend_from_slice(&c.m.to_le_bytes());
            entries.extend_from_slice(&c.id.to_le_bytes());
            entries.push(c.kind as u8);
            entries.push(0);
            location += c.bytes;
        }
        file.seek(SeekFrom::Start(end))?;
        {
            let mut out = io::BufWriter::with_capacity(1 << 20, &mut file);
            for mut c in chunks {
                (c.write)(&mut out)?;
            }
            out.flush()?;
        }
        end = location;
        let needed = self.entries + (entries.len() as u64) / ENTRY_BYTES;
        if needed > self.index_capacity {
            // A larger index block at the end of the file; the old one stays unused.
            let capacity = (2 * self.index_capacity).max(needed);
            let mut block = vec![0u8; (self.entries * ENTRY_BYTES) as usize];
            file.seek(SeekFrom::Start(self.index_location))?;
            file.read_exact(&mut block)?;
            block.resize((capacity * ENTRY_BYTES) as usize, 0);
            file.seek(SeekFrom::Start(end))?;
            file.write_all(&block)?;
            self.index_location = end;
            self.index_capacity = capacity;
            end += capacity * ENTRY_BYTES;
        }
        file.seek(SeekFrom::Start(
            self.index_location + self.entries * ENTRY_BYTES,
        ))?;
        file.write_all(&entries)?;
        self.write_index_pointer(&mut file)?;
        file.sync_data()?;
        self.entries = needed;
        self.frames += 1;
        self.bytes = end;
        Ok(())
    }

    /// Cuts the file back to the frames written when this state was saved (after a
    /// checkpoint is read back).
    pub fn rewind(&self) -> io::Result<()> {
        let mut file = OpenOptions::new().read(true).write(true).open(&self.path)?;
        file.set_len(self.bytes)?;
        let unused = (self.index_capacity - self.entries) * ENTRY_BYTES;
        file.seek(SeekFrom::Start(
            self.index_location + self.entries * ENTRY_BYTES,
        ))?;
        file.write_all(&vec![0u8; unused as usize])?;
        self.write_index_pointer(&mut file)?;
        file.sync_data()
    }

    fn write_index_pointer(&self, file: &mut File) -> io::Result<()> {
        let mut bytes = self.index_location.to_le_bytes().to_vec();
        bytes.extend_from_slice(&self.index_capacity.to_le_bytes());
        file.seek(SeekFrom::Start(8))?;
        file.write_all(&bytes)
    }
}

/// The chunk names of the HOOMD frames, in id order.
pub const HOOMD_NAMES: [&str; 13] = [
    "configuration/step",
    "configuration/dimensions",
    "configuration/box",
    "particles/N",
    "particles/types",
    "particles/typeid",
    "particles/mass",
    "particles/diameter",
    "particles/position",
    "particles/velocity",
    "log/time",
    "log/box/periodic",
    "log/particles/id",
];

/// The chunk names a rough run's frames add after [`HOOMD_NAMES`] (ids 13, 14).
pub const SPIN_NAMES: [&str; 2] = ["particles/moment_inertia", "particles/angmom"];

/// A GSD file with the HOOMD schema (version 1.4) and the names of [`HOOMD_NAMES`], then,
/// for `rough` grains, [`SPIN_NAMES`].
pub fn create_hoomd(path: &Path, rough: bool) -> io::Result<GsdFile> {
    let application = format!("granular {}", env!("CARGO_PKG_VERSION"));
    let mut names = HOOMD_NAMES.to_vec();
    if rough {
        names.extend_from_slice(&SPIN_NAMES);
    }
    GsdFile::create(path, &application, "hoomd", (1, 4), &names)
}

/// The chunks of one frame in the HOOMD schema (see the module documentation), in
/// memory: the bytes of [`frame_rows`] of the frame.
pub fn frame_chunks(frame: &Frame) -> io::Result<Vec<Chunk>> {
    let rows = frame.rows();
    frame_rows(&rows)
        .into_iter()
        .map(|mut c| {
            let mut data = Vec::with_capacity(c.bytes as usize);
            (c.write)(&mut data)?;
            Ok(Chunk {
                id: c.id,
                kind: c.kind,
                n: c.n,
                m: c.m,
                data,
            })
        })
        .collect()
}

/// The chunks of one frame read piece by piece, in the HOOMD schema (see the module
/// documentation), each written in memory independent of the frame's size.
pub fn frame_rows<'a>(frame: &'a Rows<'a>) -> Vec<StreamedChunk<'a>> {
    let n = frame.n;
    let d = frame.dimension;
    let l = &frame.cell.lengths;
    let lz = if d == 3 { l[2] } else { 0.0 };
    let width = frame
        .species_names
        .iter()
        .map(String::len)
        .max()
        .unwrap_or(0)
        + 1;
    let mut types = Vec::with_capacity(width * frame.species_names.len());
    for name in frame.species_names {
        let start = types.len();
        types.extend_from_slice(name.as_bytes());
        types.resize(start + width, 0);
    }
    let fixed = |id: usize, kind, n: usize, m: usize, data: Vec<u8>| StreamedChunk {
        id: id as u16,
        kind,
        n: n as u64,
        m: m as u32,
        bytes: data.len() as u64,
        write: Box::new(move |w: &mut dyn Write| w.write_all(&data)),
    };
    // A per-grain chunk: `m` values of `size` bytes per grain, from the pieces.
    type Encode = fn(&Rows<'_>, &super::Piece<'_>, usize, &mut Vec<u8>);
    let grains = |id: usize, kind, m: usize, size: usize, encode: Encode| StreamedChunk {
        id: id as u16,
        kind,
        n: n as u64,
        m: m as u32,
        bytes: (n * m * size) as u64,
        write: Box::new(move |w: &mut dyn Write| {
            let mut buf = Vec::new();
            frame.grains.each(&mut |p| {
                buf.clear();
                for i in 0..p.len() {
                    encode(frame, p, i, &mut buf);
                }
                w.write_all(&buf)
            })
        }),
    };
    let mut chunks = vec![
        fixed(0, ChunkType::U64, 1, 1, frame.step.to_le_bytes().to_vec()),
        fixed(1, ChunkType::U8, 1, 1, vec![d as u8]),
        fixed(
            2,
            ChunkType::F32,
            6,
            1,
            f32s_of([l[0], l[1], lz, 0.0, 0.0, 0.0].into_iter()),
        ),
        fixed(3, ChunkType::U32, 1, 1, (n as u32).to_le_bytes().to_vec()),
        fixed(4, ChunkType::I8, frame.species_names.len(), width, types),
        grains(5, ChunkType::U32, 1, 4, |_, p, i, b| {
            b.extend_from_slice(&p.species[i].to_le_bytes())
        }),
        grains(6, ChunkType::F32, 1, 4, |_, p, i, b| {
            b.extend_from_slice(&(p.masses[i] as f32).to_le_bytes())
        }),
        grains(7, ChunkType::F32, 1, 4, |_, p, i, b| {
            b.extend_from_slice(&((2.0 * p.radii[i]) as f32).to_le_bytes())
        }),
        grains(8, ChunkType::F32, 3, 4, |f, p, i, b| {
            let x = p.position(i);
            for (k, xk) in x.iter().enumerate() {
                b.extend_from_slice(&((xk - half(f, k)) as f32).to_le_bytes());
            }
        }),
        grains(9, ChunkType::F32, 3, 4, |_, p, i, b| {
            for v in p.velocity(i) {
                b.extend_from_slice(&(v as f32).to_le_bytes());
            }
        }),
        fixed(10, ChunkType::F64, 1, 1, frame.time.to_le_bytes().to_vec()),
        fixed(
            11,
            ChunkType::U8,
            3,
            1,
            frame.periodic3().iter().map(|&p| u8::from(p)).collect(),
        ),
        grains(12, ChunkType::U64, 1, 8, |_, p, i, b| {
            b.extend_from_slice(&((p.first + i) as u64).to_le_bytes())
        }),
    ];
    if frame.is_rough() {
        chunks.push(grains(13, ChunkType::F32, 3, 4, |f, p, i, b| {
            for moment in principal_moments(f, p, i) {
                b.extend_from_slice(&(moment as f32).to_le_bytes());
            }
        }));
        chunks.push(grains(14, ChunkType::F32, 4, 4, |f, p, i, b| {
            for q in angmom(f, p, i) {
                b.extend_from_slice(&(q as f32).to_le_bytes());
            }
        }));
    }
    chunks
}

/// Half the box edge along axis `k` (0 along z in 2D): HOOMD's box is centred on the origin.
fn half(frame: &Rows<'_>, k: usize) -> f64 {
    if k < frame.dimension {
        0.5 * frame.cell.lengths[k]
    } else {
        0.0
    }
}

/// `particles/moment_inertia` of grain `i`: `(I, I, I)` in 3D, `(0, 0, I)` in 2D.
fn principal_moments(frame: &Rows<'_>, p: &super::Piece<'_>, i: usize) -> [f64; 3] {
    let moment = frame.moment_of_inertia(p.species[i], p.masses[i], p.radii[i]);
    if frame.dimension == 2 {
        [0.0, 0.0, moment]
    } else {
        [moment; 3]
    }
}

/// `particles/angmom` of grain `i`: `P = 2 q ⊗ (0, I ω)` with the identity orientation
/// `q`, `(0, 2 I ω_x, 2 I ω_y, 2 I ω_z)` (module documentation).
fn angmom(frame: &Rows<'_>, p: &super::Piece<'_>, i: usize) -> [f64; 4] {
    let moments = principal_moments(frame, p, i);
    let w = p.angular_velocity(i);
    [
        0.0,
        2.0 * moments[0] * w[0],
        2.0 * moments[1] * w[1],
        2.0 * moments[2] * w[2],
    ]
}

fn f32s_of(values: impl Iterator<Item = f64>) -> Vec<u8> {
    values.flat_map(|v| (v as f32).to_le_bytes()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::trajectory::test_frame::snapshot_2d;

    fn u64_at(bytes: &[u8], at: usize) -> u64 {
        u64::from_le_bytes(bytes[at..at + 8].try_into().unwrap())
    }

    #[test]
    fn the_header_index_and_chunks_follow_the_file_layer() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.gsd");
        let (snap, cell) = snapshot_2d();
        let mut file = create_hoomd(&path, false).unwrap();
        let frames = 13; // 143 entries: the index block of 128 is moved once
        for step in 0..frames {
            let frame = Frame {
                step,
                snapshot: &snap,
                cell: &cell,
                inertia: &[],
            };
            file.append_frame(&frame_chunks(&frame).unwrap()).unwrap();
        }
        let bytes = std::fs::read(&path).unwrap();
        assert_eq!(u64_at(&bytes, 0), MAGIC);
        let (index, capacity) = (u64_at(&bytes, 8) as usize, u64_at(&bytes, 16));
        assert_eq!(capacity, 256);
        // magic, index and name-list locations and sizes (5 x 8 bytes), then the schema
        // version, the file-layer version, the application name and the schema name.
        assert_eq!(&bytes[40..44], &version(1, 4).to_le_bytes());
        assert_eq!(&bytes[44..48], &version(2, 0).to_le_bytes());
        assert_eq!(&bytes[48..56], b"granular");
        assert_eq!(&bytes[112..117], b"hoomd");
        let entry = |k: usize| &bytes[index + 32 * k..index + 32 * (k + 1)];
        let count = (0..capacity as usize)
            .take_while(|&k| u64_at(entry(k), 16) != 0)
            .count();
        assert_eq!(count, HOOMD_NAMES.len() * frames as usize);
        let keys: Vec<(u64, u16)> = (0..count)
            .map(|k| {
                let e = entry(k);
                (u64_at(e, 0), u16::from_le_bytes([e[28], e[29]]))
            })
            .collect();
        assert!(keys.windows(2).all(|w| w[0] < w[1]), "sorted by frame, id");
        // The last frame's time chunk holds the snapshot's time.
        let time = entry(count - HOOMD_NAMES.len() + 10);
        let at = u64_at(time, 16) as usize;
        assert_eq!(time[30], ChunkType::F64 as u8);
        assert_eq!(
            f64::from_le_bytes(bytes[at..at + 8].try_into().unwrap()),
            0.25
        );
    }

    #[test]
    fn rewind_drops_the_frames_after_the_saved_state() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.gsd");
        let (snap, cell) = snapshot_2d();
        let mut file = create_hoomd(&path, false).unwrap();
        let frame = Frame {
            step: 0,
            snapshot: &snap,
            cell: &cell,
            inertia: &[],
        };
        file.append_frame(&frame_chunks(&frame).unwrap()).unwrap();
        let saved = file.clone();
        let before = std::fs::read(&path).unwrap();
        for _ in 0..20 {
            file.append_frame(&frame_chunks(&frame).unwrap()).unwrap();
        }
        saved.rewind().unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), before);
    }

    /// The chunk `id` of the first frame of a file with `names` names: its bytes.
    fn chunk_of(bytes: &[u8], id: u16) -> (u64, u32, Vec<u8>, u8) {
        let index = u64_at(bytes, 8) as usize;
        let entry = (0..)
            .map(|k| &bytes[index + 32 * k..index + 32 * (k + 1)])
            .take_while(|e| u64_at(e, 16) != 0)
            .find(|e| u16::from_le_bytes([e[28], e[29]]) == id)
            .expect("the chunk is in the index");
        let (n, m) = (
            u64_at(entry, 8),
            u32::from_le_bytes(entry[24..28].try_into().unwrap()),
        );
        let at = u64_at(entry, 16) as usize;
        let size = if entry[30] == ChunkType::U64 as u8 {
            8
        } else {
            4
        };
        let data = bytes[at..at + n as usize * m as usize * size].to_vec();
        (n, m, data, entry[30])
    }

    fn f32s_in(data: &[u8]) -> Vec<f32> {
        data.chunks_exact(4)
            .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
            .collect()
    }

    #[test]
    fn rough_grains_add_moment_inertia_and_angmom_and_smooth_ones_nothing() {
        use crate::trajectory::test_frame::{rough_2d, rough_3d};
        let dir = tempfile::tempdir().unwrap();
        let (snap, cell) = snapshot_2d();
        let smooth = dir.path().join("smooth.gsd");
        let mut file = create_hoomd(&smooth, false).unwrap();
        let frame = Frame {
            step: 0,
            snapshot: &snap,
            cell: &cell,
            inertia: &[],
        };
        file.append_frame(&frame_chunks(&frame).unwrap()).unwrap();
        let bytes = std::fs::read(&smooth).unwrap();
        for name in SPIN_NAMES {
            assert!(!bytes.windows(name.len()).any(|w| w == name.as_bytes()));
        }
        for (snap, cell, inertia) in [rough_2d(), rough_3d()] {
            let d = snap.dimension;
            let path = dir.path().join(format!("rough{d}.gsd"));
            let mut file = create_hoomd(&path, true).unwrap();
            let frame = Frame {
                step: 0,
                snapshot: &snap,
                cell: &cell,
                inertia: &inertia,
            };
            file.append_frame(&frame_chunks(&frame).unwrap()).unwrap();
            let bytes = std::fs::read(&path).unwrap();
            let (n, m, data, kind) = chunk_of(&bytes, 13);
            assert_eq!((n, m, kind), (2, 3, ChunkType::F32 as u8));
            let moments = f32s_in(&data);
            let (n, m, data, _) = chunk_of(&bytes, 14);
            assert_eq!((n, m), (2, 4));
            let angmom = f32s_in(&data);
            for i in 0..2 {
                let s = snap.species[i] as usize;
                let moment = inertia[s] * snap.masses[i] * snap.radii[i] * snap.radii[i];
                let want = if d == 2 {
                    [0.0, 0.0, moment]
                } else {
                    [moment; 3]
                };
                let w: Vec<f64> = if d == 2 {
                    vec![0.0, 0.0, snap.angular_velocities[i]]
                } else {
                    snap.angular_velocities[3 * i..3 * i + 3].to_vec()
                };
                assert_eq!(angmom[4 * i], 0.0);
                for k in 0..3 {
                    assert_eq!(moments[3 * i + k], want[k] as f32, "{d}D grain {i}");
                    assert_eq!(angmom[4 * i + 1 + k], (2.0 * want[k] * w[k]) as f32);
                }
            }
        }
    }
}
