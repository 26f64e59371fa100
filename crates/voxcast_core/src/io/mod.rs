//! Volume readers: NRRD (attached and detached), NIfTI-1 and raw, chosen by file name.
//!
//! Every reader follows the same rules so that no file can crash or exhaust the program:
//!
//! 1. Header values are validated before they are used: dimensions non-zero and without overflow
//!    ([`crate::volume::checked_voxel_count`]), spacing finite, types and encodings known.
//! 2. Nothing is allocated from a header value before it is checked against the file: the payload
//!    size a header claims is compared with the bytes the file holds (raw data) or with the most a
//!    compressed stream of that length can expand to (gzip), and the payload is then read with a
//!    hard limit of one byte more than claimed, so a lying header is caught either way.
//! 3. Every failure is a [`LoadError`] naming the file and the problem.
//!
//! Every reader opens its files through [`Files`]: the disk, or files held in memory (what a
//! browser hands the page when a student picks or drops them, [`InMemory`]), where a detached
//! header finds its data file by name among the others.
//!
//! Types other than the four Voxcast holds natively are widened exactly where possible
//! (`int8` → `int16`) and otherwise converted to `float32` (`int32`, `uint32`, `float64`), with
//! a note in [`Loaded::notes`].

pub mod nifti;
pub mod nrrd;
pub mod raw;

use crate::error::{LoadError, LoadProblem};
use crate::volume::{Volume, VoxelData};
use std::io::{BufRead, Read, Seek};
use std::path::Path;

/// A loaded volume and anything the user should know about how it was read.
#[derive(Debug)]
pub struct Loaded {
    pub volume: Volume,
    /// Conversions and simplifications made while reading (lossy types, ignored orientation).
    pub notes: Vec<String>,
}

/// Reads a volume file, choosing the reader by its name: `.nrrd`/`.nhdr` → NRRD,
/// `.nii`/`.nii.gz`/`.hdr` → NIfTI-1, `.raw` with dimensions and type in the name → raw.
pub fn load(path: &Path) -> Result<Loaded, LoadError> {
    load_from(&Disk, path)
}

/// [`load`], opening `path` (and a detached header's data file) in `files`.
pub fn load_from(files: &dyn Files, path: &Path) -> Result<Loaded, LoadError> {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    if name.ends_with(".nrrd") || name.ends_with(".nhdr") {
        nrrd::load_from(files, path)
    } else if name.ends_with(".nii") || name.ends_with(".nii.gz") || name.ends_with(".hdr") {
        nifti::load_from(files, path)
    } else if name.ends_with(".raw") {
        let spec = raw::RawSpec::from_file_name(path).map_err(|p| LoadError::new(path, p))?;
        raw::load_from(files, path, &spec)
    } else {
        Err(LoadError::new(path, LoadProblem::UnknownFormat))
    }
}

/// Whether `name` is a volume file the readers know by its name (the file types a picker
/// offers).
pub fn is_volume_name(name: &str) -> bool {
    let name = name.to_ascii_lowercase();
    VOLUME_SUFFIXES.iter().any(|s| name.ends_with(s))
}

/// The endings of the files [`load`] reads (a detached header's data file may end otherwise).
pub const VOLUME_SUFFIXES: [&str; 6] = [".nrrd", ".nhdr", ".nii", ".nii.gz", ".hdr", ".raw"];

/// A file opened for reading: buffered, and able to seek.
pub trait Opened: BufRead + Seek {}
impl<T: BufRead + Seek> Opened for T {}

/// Where the readers find files.
pub trait Files {
    /// Opens `path`: a reader at its start, and its length in bytes.
    fn open(&self, path: &Path) -> std::io::Result<(Box<dyn Opened + '_>, u64)>;
    /// Whether `path` can be opened.
    fn exists(&self, path: &Path) -> bool;
    /// The most bytes of voxel data a volume read from these files may take (a web page's
    /// memory), checked against the header before anything is allocated; `None`: no limit
    /// but the file's own size.
    fn voxel_limit(&self) -> Option<u64> {
        None
    }
}

/// Refuses a header that asks for more than `files` may hold ([`Files::voxel_limit`]).
pub(crate) fn check_limit(files: &dyn Files, expected: u64) -> Result<(), LoadProblem> {
    match files.voxel_limit() {
        Some(limit) if expected > limit => Err(LoadProblem::OverLimit {
            bytes: expected,
            limit,
        }),
        _ => Ok(()),
    }
}

/// The file system.
pub struct Disk;

impl Files for Disk {
    fn open(&self, path: &Path) -> std::io::Result<(Box<dyn Opened + '_>, u64)> {
        let file = std::fs::File::open(path)?;
        let len = file.metadata()?.len();
        Ok((Box::new(std::io::BufReader::new(file)), len))
    }

    fn exists(&self, path: &Path) -> bool {
        path.exists()
    }
}

/// Files held in memory, found by their names alone (a browser gives a page a file's name and
/// bytes, never its folder): a detached header's data file is the one of that name among them.
#[derive(Clone, Debug, Default)]
pub struct InMemory {
    pub files: Vec<(String, Vec<u8>)>,
    /// [`Files::voxel_limit`]: what the page that holds them can hold.
    pub limit: Option<u64>,
}

impl InMemory {
    /// `files`, with no limit but their own sizes.
    pub fn new(files: Vec<(String, Vec<u8>)>) -> Self {
        Self { files, limit: None }
    }

    fn find(&self, path: &Path) -> Option<&[u8]> {
        let name = path.file_name()?.to_string_lossy();
        self.files
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, b)| b.as_slice())
    }
}

impl Files for InMemory {
    fn open(&self, path: &Path) -> std::io::Result<(Box<dyn Opened + '_>, u64)> {
        let bytes = self.find(path).ok_or_else(|| {
            std::io::Error::new(
                std::io::ErrorKind::NotFound,
                "not among the files given (choose or drop it together with the header)",
            )
        })?;
        Ok((Box::new(std::io::Cursor::new(bytes)), bytes.len() as u64))
    }

    fn exists(&self, path: &Path) -> bool {
        self.find(path).is_some()
    }

    fn voxel_limit(&self) -> Option<u64> {
        self.limit
    }
}

/// Byte order of multi-byte values in a file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Endian {
    Little,
    Big,
}

/// The scalar types files may hold; see the module docs for how each is stored.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FileType {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl FileType {
    pub const fn bytes(self) -> u64 {
        match self {
            Self::I8 | Self::U8 => 1,
            Self::I16 | Self::U16 => 2,
            Self::I32 | Self::U32 | Self::F32 => 4,
            Self::F64 => 8,
        }
    }

    /// Parses the common names: NumPy/Open SciVis (`uint16`), NRRD (`unsigned short`, `ushort`),
    /// C99 (`uint16_t`).
    pub fn parse(name: &str) -> Option<Self> {
        let n = name.trim().to_ascii_lowercase();
        Some(match n.as_str() {
            "int8" | "int8_t" | "signed char" | "char" => Self::I8,
            "uint8" | "uint8_t" | "uchar" | "unsigned char" | "u8" => Self::U8,
            "int16" | "int16_t" | "short" | "short int" | "signed short" | "signed short int"
            | "i16" => Self::I16,
            "uint16" | "uint16_t" | "ushort" | "unsigned short" | "unsigned short int" | "u16" => {
                Self::U16
            }
            "int32" | "int32_t" | "int" | "signed int" | "i32" => Self::I32,
            "uint32" | "uint32_t" | "uint" | "unsigned int" | "u32" => Self::U32,
            "float" | "float32" | "f32" => Self::F32,
            "double" | "float64" | "f64" => Self::F64,
            _ => return None,
        })
    }

    /// The note to record when this type is not held natively.
    fn conversion_note(self) -> Option<&'static str> {
        match self {
            Self::I8 => Some("int8 data widened to int16 (exact)"),
            Self::I32 | Self::U32 => {
                Some("32-bit integer data converted to float32 (values above 2^24 are rounded)")
            }
            Self::F64 => Some("float64 data converted to float32 (rounded to single precision)"),
            _ => None,
        }
    }
}

/// Decodes `count` values of `ty` from `bytes` into Voxcast's native storage. `bytes` must hold
/// exactly `count · ty.bytes()` bytes (the callers check). A `u8` payload is moved, not copied.
pub(crate) fn decode(
    bytes: Vec<u8>,
    ty: FileType,
    endian: Endian,
    notes: &mut Vec<String>,
) -> VoxelData {
    if let Some(note) = ty.conversion_note() {
        notes.push(note.to_owned());
    }
    macro_rules! conv {
        ($t:ty, $n:literal, $map:expr) => {{
            bytes
                .chunks_exact($n)
                .map(|c| {
                    let a: [u8; $n] = c.try_into().expect("chunk size");
                    let v = match endian {
                        Endian::Little => <$t>::from_le_bytes(a),
                        Endian::Big => <$t>::from_be_bytes(a),
                    };
                    $map(v)
                })
                .collect()
        }};
    }
    match ty {
        FileType::U8 => VoxelData::U8(bytes),
        FileType::I8 => VoxelData::I16(bytes.iter().map(|&b| b as i8 as i16).collect()),
        FileType::I16 => VoxelData::I16(conv!(i16, 2, |v| v)),
        FileType::U16 => VoxelData::U16(conv!(u16, 2, |v| v)),
        FileType::I32 => VoxelData::F32(conv!(i32, 4, |v| v as f32)),
        FileType::U32 => VoxelData::F32(conv!(u32, 4, |v| v as f32)),
        FileType::F32 => VoxelData::F32(conv!(f32, 4, |v| v)),
        FileType::F64 => VoxelData::F32(conv!(f64, 8, |v| v as f32)),
    }
}

/// Largest expansion ratio of a DEFLATE stream (RFC 1951 allows ≈1032:1), with slack for the
/// gzip framing: a header claiming more than this many bytes per compressed byte is lying.
pub(crate) const MAX_DEFLATE_RATIO: u64 = 1032;

/// Reads exactly `expected` bytes from `reader`, never more than `expected + 1` (to detect
/// trailing data) and never allocating more than was actually read plus `prealloc`.
pub(crate) fn read_payload(
    reader: impl Read,
    expected: u64,
    prealloc: u64,
) -> Result<Vec<u8>, LoadProblem> {
    let mut buf = Vec::with_capacity(prealloc.min(expected) as usize);
    let mut limited = reader.take(expected.saturating_add(1));
    limited.read_to_end(&mut buf).map_err(|e| {
        if e.kind() == std::io::ErrorKind::InvalidInput
            || e.kind() == std::io::ErrorKind::InvalidData
        {
            LoadProblem::Decompress(e.to_string())
        } else {
            LoadProblem::Io(e)
        }
    })?;
    let found = buf.len() as u64;
    if found < expected {
        return Err(LoadProblem::Truncated { expected, found });
    }
    if found > expected {
        return Err(LoadProblem::TooMuchData { expected, found });
    }
    Ok(buf)
}

/// The file's name without directories and known volume extensions, for display.
pub(crate) fn display_name(path: &Path) -> String {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "volume".into());
    for ext in [".nii.gz", ".nrrd", ".nhdr", ".nii", ".hdr", ".raw"] {
        if name.to_ascii_lowercase().ends_with(ext) {
            return name[..name.len() - ext.len()].to_owned();
        }
    }
    name
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decode_endianness_and_widening() {
        let mut notes = vec![];
        let d = decode(
            vec![0x01, 0x02, 0xff, 0xfe],
            FileType::I16,
            Endian::Big,
            &mut notes,
        );
        assert_eq!(d, VoxelData::I16(vec![0x0102, -2]));
        let d = decode(vec![0x01, 0x02], FileType::U16, Endian::Little, &mut notes);
        assert_eq!(d, VoxelData::U16(vec![0x0201]));
        let d = decode(vec![0xff, 0x7f], FileType::I8, Endian::Little, &mut notes);
        assert_eq!(d, VoxelData::I16(vec![-1, 127]));
        assert_eq!(notes.len(), 1);
        let d = decode(
            2.5f64.to_be_bytes().to_vec(),
            FileType::F64,
            Endian::Big,
            &mut notes,
        );
        assert_eq!(d, VoxelData::F32(vec![2.5]));
    }

    #[test]
    fn payload_limits() {
        assert!(read_payload(&[1u8, 2, 3][..], 3, 3).is_ok());
        assert!(matches!(
            read_payload(&[1u8, 2][..], 3, 3),
            Err(LoadProblem::Truncated {
                expected: 3,
                found: 2
            })
        ));
        assert!(matches!(
            read_payload(&[1u8, 2, 3, 4, 5][..], 3, 3),
            Err(LoadProblem::TooMuchData {
                expected: 3,
                found: 4
            })
        ));
    }

    #[test]
    fn type_names() {
        assert_eq!(FileType::parse("unsigned short"), Some(FileType::U16));
        assert_eq!(FileType::parse("UINT8"), Some(FileType::U8));
        assert_eq!(FileType::parse("float32"), Some(FileType::F32));
        assert_eq!(FileType::parse("complex64"), None);
        assert_eq!(display_name(Path::new("/a/b/brain.nii.gz")), "brain");
    }
}
