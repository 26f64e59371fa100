//! Raw voxel files: no header, so dimensions and type come from the file name
//! (`bonsai_256x256x256_uint8.raw`, the Open SciVis Datasets naming) or from the caller.
//!
//! The file must hold exactly `nx·ny·nz` values (after an optional header skip); x varies
//! fastest. Endianness defaults to little (every Open SciVis file is little-endian).

use super::{
    Disk, Endian, FileType, Files, Loaded, check_limit, decode, display_name, read_payload,
};
use crate::error::{LoadError, LoadProblem};
use crate::volume::{Volume, checked_voxel_count};
use glam::{UVec3, Vec3};
use std::io::{Seek, SeekFrom};
use std::path::Path;

/// How to read a raw file.
#[derive(Clone, Debug, PartialEq)]
pub struct RawSpec {
    pub dims: [u64; 3],
    pub ty: FileType,
    pub endian: Endian,
    pub spacing: Vec3,
    /// Bytes to skip before the data.
    pub header_bytes: u64,
}

impl RawSpec {
    /// Finds `NXxNYxNZ_TYPE` in the file name (`name_256x256x113_uint16.raw`).
    pub fn from_file_name(path: &Path) -> Result<Self, LoadProblem> {
        let stem = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        let parts: Vec<&str> = stem.split('_').collect();
        for pair in parts.windows(2) {
            if let (Some(dims), Some(ty)) = (parse_dims(pair[0]), FileType::parse(pair[1])) {
                return Ok(Self {
                    dims,
                    ty,
                    endian: Endian::Little,
                    spacing: Vec3::ONE,
                    header_bytes: 0,
                });
            }
        }
        Err(LoadProblem::Header(format!(
            "raw file name '{stem}' does not give dimensions and type: name it \
             like 'name_256x256x113_uint16.raw' or pass --dims and --type"
        )))
    }
}

/// `256x256x113` → `[256, 256, 113]`.
pub fn parse_dims(s: &str) -> Option<[u64; 3]> {
    let v: Vec<u64> = s
        .split('x')
        .map(|p| p.parse::<u64>().ok())
        .collect::<Option<_>>()?;
    v.try_into().ok()
}

/// Reads a raw file as `spec` describes.
pub fn load(path: &Path, spec: &RawSpec) -> Result<Loaded, LoadError> {
    load_from(&Disk, path, spec)
}

/// Reads a raw file of `files` as `spec` describes.
pub fn load_from(files: &dyn Files, path: &Path, spec: &RawSpec) -> Result<Loaded, LoadError> {
    load_inner(files, path, spec).map_err(|p| LoadError::new(path, p))
}

fn load_inner(files: &dyn Files, path: &Path, spec: &RawSpec) -> Result<Loaded, LoadProblem> {
    let [nx, ny, nz] = spec.dims;
    let count = checked_voxel_count(nx, ny, nz)?;
    let expected = count * spec.ty.bytes();
    check_limit(files, expected)?;
    let (mut reader, len) = files.open(path)?;
    let available = len.saturating_sub(spec.header_bytes);
    if available < expected {
        return Err(LoadProblem::Truncated {
            expected,
            found: available,
        });
    }
    if available > expected {
        return Err(LoadProblem::TooMuchData {
            expected,
            found: available,
        });
    }
    reader.seek(SeekFrom::Start(spec.header_bytes))?;
    let bytes = read_payload(reader, expected, expected)?;
    let mut notes = Vec::new();
    let data = decode(bytes, spec.ty, spec.endian, &mut notes);
    let volume = Volume::new(
        display_name(path),
        UVec3::new(nx as u32, ny as u32, nz as u32),
        spec.spacing,
        data,
    )?;
    Ok(Loaded { volume, notes })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_in_the_open_scivis_style() {
        let s = RawSpec::from_file_name(Path::new("/x/skull_256x256x113_uint16.raw")).unwrap();
        assert_eq!(s.dims, [256, 256, 113]);
        assert_eq!(s.ty, FileType::U16);
        let s = RawSpec::from_file_name(Path::new("a_b_4x1x1_float32.raw")).unwrap();
        assert_eq!((s.dims, s.ty), ([4, 1, 1], FileType::F32));
        assert!(RawSpec::from_file_name(Path::new("volume.raw")).is_err());
        assert!(RawSpec::from_file_name(Path::new("v_12x12_uint8.raw")).is_err());
        assert!(parse_dims("1x2x").is_none());
    }
}
