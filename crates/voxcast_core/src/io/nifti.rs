//! NIfTI-1 reader: `.nii`, `.nii.gz`, and `.hdr` + `.img` pairs.
//!
//! The 348-byte header is parsed by the maintained `nifti` crate (either byte order); the voxel
//! data is read here, after the header's claims are checked against the file (see [`super`]).
//! Values are rescaled by `scl_slope`/`scl_inter` as the standard says (a slope of 0 means no
//! rescale) — Voxcast keeps the native values and applies the rescale after interpolation, which
//! is exact because interpolation is linear. The orientation (qform/sform) is not applied; voxel
//! (0,0,0) sits at the world origin. A 4-D file gives its first 3-D volume.

use super::{
    Disk, Endian, FileType, Files, Loaded, MAX_DEFLATE_RATIO, check_limit, decode, display_name,
    read_payload,
};
use crate::error::{LoadError, LoadProblem};
use crate::volume::{Volume, checked_voxel_count};
use glam::{UVec3, Vec3};
use std::io::Read;
use std::path::{Path, PathBuf};

/// Size of a NIfTI-1 header.
const HEADER_BYTES: u64 = 348;

/// Reads a NIfTI-1 file.
pub fn load(path: &Path) -> Result<Loaded, LoadError> {
    load_from(&Disk, path)
}

/// Reads a NIfTI-1 file of `files` (a `.hdr`'s `.img` among them too).
pub fn load_from(files: &dyn Files, path: &Path) -> Result<Loaded, LoadError> {
    load_inner(files, path).map_err(|p| LoadError::new(path, p))
}

fn is_gz(path: &Path) -> bool {
    path.to_string_lossy().to_ascii_lowercase().ends_with(".gz")
}

/// A file, decompressed if its name ends in `.gz`, with its stored length.
fn open<'f>(files: &'f dyn Files, path: &Path) -> Result<(Box<dyn Read + 'f>, u64), LoadProblem> {
    let (reader, len) = files.open(path)?;
    Ok(if is_gz(path) {
        (Box::new(flate2::bufread::MultiGzDecoder::new(reader)), len)
    } else {
        (Box::new(reader), len)
    })
}

fn bad(msg: impl Into<String>) -> LoadProblem {
    LoadProblem::Header(msg.into())
}

fn load_inner(files: &dyn Files, path: &Path) -> Result<Loaded, LoadProblem> {
    let mut notes = Vec::new();
    let (mut stream, file_len) = open(files, path)?;
    let header = nifti::NiftiHeader::from_reader(&mut stream).map_err(|e| match e {
        nifti::NiftiError::Io(io) if io.kind() == std::io::ErrorKind::UnexpectedEof => {
            bad("file ends inside the 348-byte header")
        }
        nifti::NiftiError::Io(io) => LoadProblem::Decompress(io.to_string()),
        other => bad(format!("not a NIfTI-1 header: {other}")),
    })?;
    if header.sizeof_hdr != HEADER_BYTES as i32 {
        return Err(bad(format!(
            "sizeof_hdr is {} (NIfTI-1 headers are 348 bytes; NIfTI-2 is not supported)",
            header.sizeof_hdr
        )));
    }
    let single_file = &header.magic == b"n+1\0";
    let ty = file_type(header.datatype)?;
    if header.bitpix as u64 != ty.bytes() * 8 {
        return Err(bad(format!(
            "bitpix {} does not match datatype {} ({} bits)",
            header.bitpix,
            header.datatype,
            ty.bytes() * 8
        )));
    }

    let rank = header.dim[0] as usize;
    if !(1..=7).contains(&rank) {
        return Err(bad(format!(
            "dim[0] = {rank}: must be 1 to 7",
            rank = header.dim[0]
        )));
    }
    let axis = |i: usize| if i <= rank { header.dim[i] as u64 } else { 1 };
    let count = checked_voxel_count(axis(1), axis(2), axis(3))?;
    if (4..=rank).any(|i| header.dim[i] == 0) {
        return Err(bad("a dimension beyond the third is zero"));
    }
    if (4..=rank).any(|i| header.dim[i] > 1) {
        notes.push("4-D data: the first 3-D volume is read".into());
    }
    let is_3d_only = (4..=rank).all(|i| header.dim[i] == 1);
    let expected = count * ty.bytes();
    check_limit(files, expected)?;
    let endian = match header.endianness {
        nifti::Endianness::Little => Endian::Little,
        nifti::Endianness::Big => Endian::Big,
    };

    let vox_offset = header.vox_offset;
    if !(vox_offset.is_finite() && vox_offset >= 0.0 && vox_offset.fract() == 0.0) {
        return Err(bad(format!("vox_offset {vox_offset} is not a byte offset")));
    }
    let vox_offset = vox_offset as u64;

    let bytes = if single_file {
        if vox_offset < HEADER_BYTES {
            return Err(bad(format!(
                "vox_offset {vox_offset} lies inside the header"
            )));
        }
        check_claim(path, file_len, vox_offset + expected)?;
        skip(&mut stream, vox_offset - HEADER_BYTES)?;
        read_volume(stream, expected, is_3d_only, file_len)?
    } else {
        let img = image_path(files, path)?;
        let (mut data, img_len) = open(files, &img).map_err(|e| {
            bad(format!(
                "cannot open the image file '{}': {e}",
                img.display()
            ))
        })?;
        check_claim(&img, img_len, vox_offset + expected)?;
        skip(&mut data, vox_offset)?;
        read_volume(data, expected, is_3d_only, img_len)?
    };

    let (slope, intercept) = if header.scl_slope == 0.0 || !header.scl_slope.is_finite() {
        (1.0, 0.0)
    } else {
        let inter = if header.scl_inter.is_finite() {
            header.scl_inter
        } else {
            0.0
        };
        if header.scl_slope != 1.0 || inter != 0.0 {
            notes.push(format!(
                "values rescaled: data = raw × {} + {}",
                header.scl_slope, inter
            ));
        }
        (header.scl_slope, inter)
    };
    let mut spacing = Vec3::ONE;
    for i in 0..3 {
        let p = header.pixdim[i + 1].abs();
        if p.is_finite() && p > 0.0 {
            spacing[i] = p;
        } else if i < rank {
            notes.push(format!(
                "pixdim[{}] = {} is not a spacing: 1 assumed",
                i + 1,
                p
            ));
        }
    }
    let data = decode(bytes, ty, endian, &mut notes);
    let dims = UVec3::new(axis(1) as u32, axis(2) as u32, axis(3) as u32);
    let volume = Volume::with_rescale(display_name(path), dims, spacing, data, slope, intercept)?;
    Ok(Loaded { volume, notes })
}

fn file_type(code: i16) -> Result<FileType, LoadProblem> {
    Ok(match code {
        2 => FileType::U8,
        4 => FileType::I16,
        8 => FileType::I32,
        16 => FileType::F32,
        64 => FileType::F64,
        256 => FileType::I8,
        512 => FileType::U16,
        768 => FileType::U32,
        other => {
            let name = match other {
                32 => "complex64",
                128 => "rgb24",
                1024 => "int64",
                1280 => "uint64",
                1792 => "complex128",
                2304 => "rgba32",
                _ => "unknown",
            };
            return Err(LoadProblem::UnsupportedType(format!(
                "NIfTI datatype {other} ({name})"
            )));
        }
    })
}

/// The `.img` (or `.img.gz`) beside a `.hdr`.
fn image_path(files: &dyn Files, hdr: &Path) -> Result<PathBuf, LoadProblem> {
    let plain = hdr.with_extension("img");
    if files.exists(&plain) {
        return Ok(plain);
    }
    let gz = hdr.with_extension("img.gz");
    if files.exists(&gz) {
        return Ok(gz);
    }
    Err(bad(format!(
        "no image file '{}' beside the header",
        plain.display()
    )))
}

/// An uncompressed file must hold what the header claims; a compressed one must be able to.
fn check_claim(path: &Path, file_len: u64, claim: u64) -> Result<(), LoadProblem> {
    if is_gz(path) {
        let limit = file_len
            .saturating_mul(MAX_DEFLATE_RATIO)
            .saturating_add(1 << 16);
        if claim > limit {
            return Err(LoadProblem::ImplausibleSize {
                bytes: claim,
                limit,
            });
        }
    } else if file_len < claim {
        return Err(LoadProblem::Truncated {
            expected: claim,
            found: file_len,
        });
    }
    Ok(())
}

fn skip(stream: &mut dyn Read, n: u64) -> Result<(), LoadProblem> {
    let skipped = std::io::copy(&mut stream.take(n), &mut std::io::sink())
        .map_err(|e| LoadProblem::Decompress(e.to_string()))?;
    if skipped < n {
        return Err(bad("file ends before vox_offset"));
    }
    Ok(())
}

/// Reads one volume's bytes; for a 3-D file, trailing data is an error.
fn read_volume(
    stream: Box<dyn Read + '_>,
    expected: u64,
    strict: bool,
    file_len: u64,
) -> Result<Vec<u8>, LoadProblem> {
    let prealloc = file_len.saturating_mul(4);
    if strict {
        read_payload(stream, expected, prealloc)
    } else {
        read_payload(stream.take(expected), expected, prealloc)
    }
}
