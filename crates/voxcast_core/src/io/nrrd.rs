//! NRRD reader (teem's "Nearly Raw Raster Data", <http://teem.sourceforge.net/nrrd/format.html>).
//!
//! Reads attached headers (`.nrrd`: header, blank line, data) and detached headers (`.nhdr`
//! naming a `data file`), encodings `raw`, `gzip` and `ascii`, both endiannesses, and spacing from
//! `spacings` or from the lengths of `space directions` (orientation and `space origin` are not
//! applied: Voxcast puts voxel (0,0,0) at the world origin, axis-aligned — see the crate docs).
//! Three-dimensional data is read as is; two-dimensional data as a single slice; four-dimensional
//! data whose first axis has size 1 drops that axis.

use super::{
    Disk, Endian, FileType, Files, Loaded, MAX_DEFLATE_RATIO, check_limit, decode, display_name,
    read_payload,
};
use crate::error::{LoadError, LoadProblem};
use crate::volume::{Volume, checked_voxel_count};
use glam::{UVec3, Vec3};
use std::io::{BufRead, Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};

/// A header longer than this is not a NRRD header (protects against reading binary as text).
const MAX_HEADER_BYTES: usize = 1 << 20;

/// The parsed fields Voxcast uses.
#[derive(Debug, Default)]
struct Header {
    ty: Option<FileType>,
    dimension: Option<usize>,
    sizes: Vec<u64>,
    endian: Option<Endian>,
    encoding: Option<String>,
    spacings: Option<Vec<f64>>,
    directions: Option<Vec<Option<[f64; 3]>>>,
    data_file: Option<String>,
    line_skip: u64,
    byte_skip: i64,
}

/// Reads a `.nrrd` or `.nhdr` file.
pub fn load(path: &Path) -> Result<Loaded, LoadError> {
    load_from(&Disk, path)
}

/// Reads a `.nrrd` or `.nhdr` file of `files` (a detached header's data file among them too).
pub fn load_from(files: &dyn Files, path: &Path) -> Result<Loaded, LoadError> {
    load_inner(files, path).map_err(|p| LoadError::new(path, p))
}

fn load_inner(files: &dyn Files, path: &Path) -> Result<Loaded, LoadProblem> {
    let (reader, len) = files.open(path)?;
    let name = display_name(path);
    parse(reader, len, Some((files, path)), name)
}

/// Reads an attached-header NRRD held in memory (the embedded datasets).
pub fn load_bytes(name: &str, bytes: &[u8]) -> Result<Loaded, LoadError> {
    parse(
        std::io::Cursor::new(bytes),
        bytes.len() as u64,
        None,
        name.to_owned(),
    )
    .map_err(|p| LoadError::new(format!("builtin:{name}"), p))
}

/// Parses a NRRD from `reader` (`len` bytes in all). `path` (the header's, in its files)
/// locates detached data files; without it the data must be attached.
fn parse<R: BufRead + Seek>(
    mut reader: R,
    len: u64,
    path: Option<(&dyn Files, &Path)>,
    name: String,
) -> Result<Loaded, LoadProblem> {
    let header = parse_header(&mut reader)?;
    let mut notes = Vec::new();

    let ty = header
        .ty
        .ok_or_else(|| bad("missing required field 'type'"))?;
    let dimension = header
        .dimension
        .ok_or_else(|| bad("missing required field 'dimension'"))?;
    if header.sizes.len() != dimension {
        return Err(bad(format!(
            "'sizes' lists {} axes but 'dimension' is {dimension}",
            header.sizes.len()
        )));
    }
    // Map the axes onto x, y, z (see module docs).
    let (dims, axis_of): ([u64; 3], Vec<usize>) = match dimension {
        3 => (
            [header.sizes[0], header.sizes[1], header.sizes[2]],
            vec![0, 1, 2],
        ),
        2 => {
            notes.push("two-dimensional NRRD read as a single slice".into());
            ([header.sizes[0], header.sizes[1], 1], vec![0, 1])
        }
        4 if header.sizes[0] == 1 => (
            [header.sizes[1], header.sizes[2], header.sizes[3]],
            vec![1, 2, 3],
        ),
        d => {
            return Err(bad(format!(
                "dimension {d} with sizes {:?}: Voxcast reads scalar 3-D volumes (or 2-D slices)",
                header.sizes
            )));
        }
    };
    let count = checked_voxel_count(dims[0], dims[1], dims[2])?;
    let expected = count
        .checked_mul(ty.bytes())
        .ok_or_else(|| bad("voxel data size overflows"))?;
    if let Some((files, _)) = path {
        check_limit(files, expected)?;
    }
    let encoding = header
        .encoding
        .clone()
        .ok_or_else(|| bad("missing required field 'encoding'"))?;
    let text = matches!(encoding.as_str(), "ascii" | "text" | "txt");
    let endian = match (header.endian, ty.bytes()) {
        // ASCII values are parsed, then stored little-endian (see `ascii_values`).
        _ if text => Endian::Little,
        (Some(e), _) => e,
        (None, 1) => Endian::Little,
        (None, _) => {
            return Err(bad("missing field 'endian', required for multi-byte types"));
        }
    };
    let spacing = spacing_of(&header, &axis_of, &mut notes)?;

    // The data: after the header in this file, or in the detached data file.
    let bytes = match (&header.data_file, path) {
        (None, _) => read_data(reader, len, &encoding, ty, expected, &header)?,
        (Some(file_name), Some((files, path))) => {
            let data_path = detached_path(path, file_name)?;
            let (file, data_len) = files.open(&data_path).map_err(|e| {
                LoadProblem::Header(format!(
                    "cannot open data file '{}': {e}",
                    data_path.display()
                ))
            })?;
            read_data(file, data_len, &encoding, ty, expected, &header)?
        }
        (Some(_), None) => return Err(bad("a detached header needs its data file on disk")),
    };
    let data = decode(bytes, ty, endian, &mut notes);
    let volume = Volume::new(
        name,
        UVec3::new(dims[0] as u32, dims[1] as u32, dims[2] as u32),
        spacing,
        data,
    )?;
    Ok(Loaded { volume, notes })
}

fn bad(msg: impl Into<String>) -> LoadProblem {
    LoadProblem::Header(msg.into())
}

/// Reads the magic line and header fields, stopping after the blank line (or at end of file,
/// for detached headers).
fn parse_header(reader: &mut impl BufRead) -> Result<Header, LoadProblem> {
    let mut line = Vec::new();
    let mut read_total = 0usize;
    let mut next_line =
        |reader: &mut dyn BufRead, line: &mut Vec<u8>| -> Result<bool, LoadProblem> {
            line.clear();
            let n = reader
                .take((MAX_HEADER_BYTES - read_total.min(MAX_HEADER_BYTES)) as u64 + 1)
                .read_until(b'\n', line)?;
            read_total += n;
            if read_total > MAX_HEADER_BYTES {
                return Err(bad("header longer than 1 MiB: not a NRRD header"));
            }
            while line.last().is_some_and(|&b| b == b'\n' || b == b'\r') {
                line.pop();
            }
            Ok(n > 0)
        };

    if !next_line(reader, &mut line)? || !line.starts_with(b"NRRD000") {
        return Err(bad("not a NRRD file (the first line must be NRRD000x)"));
    }
    let mut h = Header::default();
    while next_line(reader, &mut line)? {
        if line.is_empty() {
            break; // end of an attached header
        }
        let text = std::str::from_utf8(&line).map_err(|_| bad("header line is not text"))?;
        if text.starts_with('#') || text.contains(":=") {
            continue; // comment or key/value pair
        }
        let Some((key, value)) = text.split_once(": ") else {
            return Err(bad(format!(
                "cannot parse header line '{}'",
                truncate(text)
            )));
        };
        let value = value.trim();
        let number = |what: &str, s: &str| -> Result<f64, LoadProblem> {
            s.parse::<f64>()
                .map_err(|_| bad(format!("{what}: '{}' is not a number", truncate(s))))
        };
        match key.trim().to_ascii_lowercase().as_str() {
            "type" => {
                h.ty = Some(
                    FileType::parse(value)
                        .ok_or_else(|| LoadProblem::UnsupportedType(value.to_owned()))?,
                )
            }
            "dimension" => {
                h.dimension =
                    Some(value.parse().map_err(|_| {
                        bad(format!("dimension '{}' is not a count", truncate(value)))
                    })?)
            }
            "sizes" => {
                h.sizes = value
                    .split_whitespace()
                    .map(|s| {
                        s.parse::<u64>()
                            .map_err(|_| bad(format!("sizes: '{}' is not a count", truncate(s))))
                    })
                    .collect::<Result<_, _>>()?
            }
            "endian" => {
                h.endian = Some(match value.to_ascii_lowercase().as_str() {
                    "little" => Endian::Little,
                    "big" => Endian::Big,
                    other => return Err(bad(format!("unknown endian '{}'", truncate(other)))),
                })
            }
            "encoding" => h.encoding = Some(value.to_ascii_lowercase()),
            "spacings" => {
                h.spacings = Some(
                    value
                        .split_whitespace()
                        .map(|s| number("spacings", s))
                        .collect::<Result<_, _>>()?,
                )
            }
            "space directions" => h.directions = Some(parse_directions(value)?),
            "data file" | "datafile" => h.data_file = Some(value.to_owned()),
            "line skip" | "lineskip" => {
                h.line_skip = value
                    .parse()
                    .map_err(|_| bad(format!("line skip '{}' is not a count", truncate(value))))?
            }
            "byte skip" | "byteskip" => {
                h.byte_skip = value
                    .parse()
                    .map_err(|_| bad(format!("byte skip '{}' is not a number", truncate(value))))?
            }
            _ => {} // fields that do not affect how Voxcast reads the grid
        }
    }
    Ok(h)
}

fn truncate(s: &str) -> String {
    s.chars().take(60).collect()
}

/// `(a,b,c) (d,e,f) none ...` → per-axis vectors (None for non-spatial axes).
fn parse_directions(value: &str) -> Result<Vec<Option<[f64; 3]>>, LoadProblem> {
    value
        .split_whitespace()
        .map(|item| {
            if item == "none" {
                return Ok(None);
            }
            let inner = item
                .strip_prefix('(')
                .and_then(|s| s.strip_suffix(')'))
                .ok_or_else(|| {
                    bad(format!(
                        "space directions: cannot parse '{}'",
                        truncate(item)
                    ))
                })?;
            let parts: Vec<f64> = inner
                .split(',')
                .map(|s| {
                    s.trim().parse::<f64>().map_err(|_| {
                        bad(format!(
                            "space directions: '{}' is not a number",
                            truncate(s)
                        ))
                    })
                })
                .collect::<Result<_, _>>()?;
            let v: [f64; 3] = parts.try_into().map_err(|_| {
                bad("space directions: Voxcast reads 3-D spaces (three components per vector)")
            })?;
            Ok(Some(v))
        })
        .collect()
}

/// Spacing per x, y, z axis from `spacings` or `space directions` (default 1 with a note).
fn spacing_of(h: &Header, axes: &[usize], notes: &mut Vec<String>) -> Result<Vec3, LoadProblem> {
    let mut s = [1.0f64; 3];
    let mut oblique = false;
    let mut found = false;
    for (out, &axis) in axes.iter().enumerate() {
        let value = if let Some(dirs) = &h.directions {
            match dirs.get(axis).copied().flatten() {
                Some(v) => {
                    let nonzero = v.iter().filter(|c| **c != 0.0).count();
                    oblique |= nonzero > 1;
                    Some((v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt())
                }
                None => None,
            }
        } else {
            h.spacings
                .as_ref()
                .and_then(|sp| sp.get(axis).copied())
                .map(f64::abs)
        };
        if let Some(v) = value.filter(|v| v.is_finite()) {
            if v <= 0.0 {
                return Err(bad(format!(
                    "spacing of axis {axis} is {v}: must be positive"
                )));
            }
            s[out] = v;
            found = true;
        }
    }
    if !found {
        notes.push("no spacing in the header: 1 world unit per voxel assumed".into());
    }
    if oblique {
        notes.push("oblique 'space directions': their lengths are used as spacing, the rotation is ignored".into());
    }
    Ok(Vec3::new(s[0] as f32, s[1] as f32, s[2] as f32))
}

/// The data file named by a detached header, relative to the header's folder.
fn detached_path(header_path: &Path, name: &str) -> Result<PathBuf, LoadProblem> {
    if name.eq_ignore_ascii_case("list") || name.split_whitespace().count() > 1 {
        return Err(LoadProblem::Header(format!(
            "data file '{}': multi-file data sets are not supported",
            truncate(name)
        )));
    }
    let p = Path::new(name);
    Ok(if p.is_absolute() {
        p.to_owned()
    } else {
        header_path.parent().unwrap_or(Path::new(".")).join(p)
    })
}

/// Skips `line skip` lines and `byte skip` bytes, decodes and returns exactly `expected` bytes.
fn read_data<R: BufRead + Seek>(
    mut reader: R,
    len: u64,
    encoding: &str,
    ty: FileType,
    expected: u64,
    h: &Header,
) -> Result<Vec<u8>, LoadProblem> {
    let mut skip = Vec::new();
    for _ in 0..h.line_skip {
        skip.clear();
        if reader
            .by_ref()
            .take(MAX_HEADER_BYTES as u64)
            .read_until(b'\n', &mut skip)?
            == 0
        {
            return Err(bad("line skip goes past the end of the data"));
        }
    }
    let start = reader.stream_position()?;
    let available = len.saturating_sub(start);
    match encoding {
        "raw" => {
            let skip = if h.byte_skip == -1 {
                // Data is at the end of the file.
                available
                    .checked_sub(expected)
                    .ok_or(LoadProblem::Truncated {
                        expected,
                        found: available,
                    })?
            } else if h.byte_skip < 0 {
                return Err(bad(format!(
                    "byte skip {} (only -1 may be negative)",
                    h.byte_skip
                )));
            } else {
                h.byte_skip as u64
            };
            let available = available.saturating_sub(skip);
            if available < expected {
                return Err(LoadProblem::Truncated {
                    expected,
                    found: available,
                });
            }
            if available > expected && h.byte_skip != -1 {
                return Err(LoadProblem::TooMuchData {
                    expected,
                    found: available,
                });
            }
            reader.seek(SeekFrom::Current(skip as i64))?;
            read_payload(reader.take(expected), expected, expected)
        }
        "gzip" | "gz" => {
            let limit = available
                .saturating_mul(MAX_DEFLATE_RATIO)
                .saturating_add(1 << 16);
            if expected > limit {
                return Err(LoadProblem::ImplausibleSize {
                    bytes: expected,
                    limit,
                });
            }
            let mut decoder = flate2::bufread::MultiGzDecoder::new(reader);
            skip_decoded(&mut decoder, h.byte_skip)?;
            read_payload(decoder, expected, available.saturating_mul(4))
        }
        "ascii" | "text" | "txt" => {
            let mut text = String::new();
            // ASCII needs at least two bytes per value ("0 "), so the file bounds the count.
            if expected / ty.bytes() > available {
                return Err(LoadProblem::Truncated {
                    expected,
                    found: available,
                });
            }
            reader.take(available).read_to_string(&mut text)?;
            skip_text_bytes(&mut text, h.byte_skip)?;
            ascii_values(&text, ty, expected / ty.bytes())
        }
        other => Err(LoadProblem::UnsupportedEncoding(other.to_owned())),
    }
}

fn skip_decoded(reader: &mut impl Read, byte_skip: i64) -> Result<(), LoadProblem> {
    if byte_skip < 0 {
        return Err(bad("byte skip -1 is only allowed with raw encoding"));
    }
    let skipped = std::io::copy(&mut reader.take(byte_skip as u64), &mut std::io::sink())
        .map_err(|e| LoadProblem::Decompress(e.to_string()))?;
    if skipped < byte_skip as u64 {
        return Err(bad("byte skip goes past the end of the data"));
    }
    Ok(())
}

fn skip_text_bytes(text: &mut String, byte_skip: i64) -> Result<(), LoadProblem> {
    if byte_skip < 0
        || byte_skip as usize > text.len()
        || !text.is_char_boundary(byte_skip as usize)
    {
        return Err(bad("byte skip does not fit the ascii data"));
    }
    text.drain(..byte_skip as usize);
    Ok(())
}

/// Parses whitespace-separated numbers into little-endian bytes of `ty`.
fn ascii_values(text: &str, ty: FileType, count: u64) -> Result<Vec<u8>, LoadProblem> {
    let mut out = Vec::with_capacity((count * ty.bytes()) as usize);
    let mut n = 0u64;
    for token in text
        .split(|c: char| c.is_whitespace() || c == ',')
        .filter(|t| !t.is_empty())
    {
        if n == count {
            return Err(LoadProblem::TooMuchData {
                expected: count * ty.bytes(),
                found: (n + 1) * ty.bytes(),
            });
        }
        let v: f64 = token
            .parse()
            .map_err(|_| bad(format!("ascii data: '{}' is not a number", truncate(token))))?;
        let out_of_range = || bad(format!("ascii data: {v} does not fit the type"));
        macro_rules! int {
            ($t:ty) => {{
                if v.fract() != 0.0 || v < <$t>::MIN as f64 || v > <$t>::MAX as f64 {
                    return Err(out_of_range());
                }
                out.extend_from_slice(&(v as $t).to_le_bytes())
            }};
        }
        match ty {
            FileType::I8 => int!(i8),
            FileType::U8 => int!(u8),
            FileType::I16 => int!(i16),
            FileType::U16 => int!(u16),
            FileType::I32 => int!(i32),
            FileType::U32 => int!(u32),
            FileType::F32 => out.extend_from_slice(&(v as f32).to_le_bytes()),
            FileType::F64 => out.extend_from_slice(&v.to_le_bytes()),
        }
        n += 1;
    }
    if n < count {
        return Err(LoadProblem::Truncated {
            expected: count * ty.bytes(),
            found: n * ty.bytes(),
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn directions_parse_and_reject_garbage() {
        let d = parse_directions("(0.5,0,0) none (0,0,2)").unwrap();
        assert_eq!(d, vec![Some([0.5, 0.0, 0.0]), None, Some([0.0, 0.0, 2.0])]);
        assert!(parse_directions("(1,0) (0,1)").is_err());
        assert!(parse_directions("1,0,0").is_err());
    }

    #[test]
    fn ascii_counts_are_checked() {
        assert_eq!(
            ascii_values("1 2\n3", FileType::U8, 3).unwrap(),
            vec![1, 2, 3]
        );
        assert!(matches!(
            ascii_values("1 2", FileType::U8, 3),
            Err(LoadProblem::Truncated { .. })
        ));
        assert!(ascii_values("1 2 3 4", FileType::U8, 3).is_err());
        assert!(ascii_values("1 300 3", FileType::U8, 3).is_err());
        assert!(ascii_values("1 x 3", FileType::U8, 3).is_err());
    }
}
