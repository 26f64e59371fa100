//! AMD's RDF container (version 3, as GPUOpen-Drivers/libamdrdf's `docs/specification.md`
//! defines it), in which RayVis stores its `.rayvis` files: a 32-byte header (`"AMD_RDF "`,
//! version, reserved, index offset and size), chunks, and an index of 64-byte entries (a
//! 16-byte identifier, compression — 0 none, 1 Zstandard — three reserved bytes, the chunk's
//! version, and the offsets and sizes of its header and data, and the data's uncompressed
//! size). Little endian; "C" packed. Only a chunk's data is compressed, never its header.
//!
//! Every offset and size is checked against the file before it is used, and a compressed chunk
//! is decompressed no further than the size its entry declares: a damaged file is an error
//! that says where, never a panic or an allocation the file does not justify.

use std::io::Read;

/// The identifier every RDF file starts with.
pub const MAGIC: &[u8; 8] = b"AMD_RDF ";
/// The container version read and written.
pub const VERSION: u32 = 3;
const HEADER_BYTES: usize = 32;
const ENTRY_BYTES: usize = 64;
/// The largest uncompressed chunk accepted, bytes.
pub const MAX_CHUNK_BYTES: u64 = 4 << 30;

/// One chunk: its identifier (without the padding zeros), version, header and data
/// (decompressed).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Chunk {
    pub id: String,
    pub version: u32,
    pub header: Vec<u8>,
    pub data: Vec<u8>,
}

/// Why a file is not a readable RDF container.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum RdfError {
    #[error("not an RDF file: it does not start with \"AMD_RDF \"")]
    NotRdf,
    #[error("RDF version {0} (Voxcast reads version 3)")]
    Version(u32),
    #[error("the file ends inside {0}")]
    Truncated(String),
    #[error("{0}")]
    Bad(String),
}

fn u32_at(b: &[u8], at: usize) -> u32 {
    u32::from_le_bytes(b[at..at + 4].try_into().expect("4 bytes"))
}

fn i64_at(b: &[u8], at: usize) -> i64 {
    i64::from_le_bytes(b[at..at + 8].try_into().expect("8 bytes"))
}

/// The part of `file` at `offset` of `size` bytes, checked.
fn span<'f>(file: &'f [u8], offset: i64, size: i64, what: &str) -> Result<&'f [u8], RdfError> {
    if offset < 0 || size < 0 {
        return Err(RdfError::Bad(format!(
            "{what}: negative offset or size ({offset}, {size})"
        )));
    }
    let (o, s) = (offset as u64, size as u64);
    match o.checked_add(s) {
        Some(end) if end <= file.len() as u64 => Ok(&file[o as usize..end as usize]),
        _ => Err(RdfError::Truncated(format!(
            "{what} (bytes {o} … {} of a {}-byte file)",
            o.saturating_add(s),
            file.len()
        ))),
    }
}

/// Reads every chunk of an RDF file.
pub fn read(file: &[u8]) -> Result<Vec<Chunk>, RdfError> {
    if file.len() < 8 || &file[..8] != MAGIC {
        return Err(RdfError::NotRdf);
    }
    if file.len() < HEADER_BYTES {
        return Err(RdfError::Truncated("the header".into()));
    }
    let version = u32_at(file, 8);
    if version != VERSION {
        return Err(RdfError::Version(version));
    }
    let index = span(file, i64_at(file, 16), i64_at(file, 24), "the chunk index")?;
    if !index.len().is_multiple_of(ENTRY_BYTES) {
        return Err(RdfError::Bad(format!(
            "the chunk index's {} bytes are not a whole number of 64-byte entries",
            index.len()
        )));
    }
    index
        .chunks_exact(ENTRY_BYTES)
        .enumerate()
        .map(|(i, e)| read_entry(file, i, e))
        .collect()
}

fn read_entry(file: &[u8], i: usize, e: &[u8]) -> Result<Chunk, RdfError> {
    let raw_id = &e[..16];
    let id_len = raw_id.iter().position(|&b| b == 0).unwrap_or(16);
    let id = String::from_utf8_lossy(&raw_id[..id_len]).into_owned();
    let what = |part: &str| format!("chunk {i} ({id})'s {part}");
    let compression = e[16];
    let version = u32_at(e, 20);
    let header = span(file, i64_at(e, 24), i64_at(e, 32), &what("header"))?.to_vec();
    let stored = span(file, i64_at(e, 40), i64_at(e, 48), &what("data"))?;
    let uncompressed = i64_at(e, 56);
    let data = match compression {
        0 => stored.to_vec(),
        1 => {
            if uncompressed < 0 || uncompressed as u64 > MAX_CHUNK_BYTES {
                return Err(RdfError::Bad(format!(
                    "{}: uncompressed size {uncompressed} bytes is out of range",
                    what("data")
                )));
            }
            let want = uncompressed as usize;
            let decoder = ruzstd::decoding::StreamingDecoder::new(stored).map_err(|e| {
                RdfError::Bad(format!("{}: not Zstandard data ({e})", what("data")))
            })?;
            let mut data = Vec::with_capacity(want.min(stored.len().saturating_mul(64)));
            // One byte past the declared size tells a lying entry from an honest one.
            decoder
                .take(want as u64 + 1)
                .read_to_end(&mut data)
                .map_err(|e| {
                    RdfError::Bad(format!("{}: damaged Zstandard data ({e})", what("data")))
                })?;
            if data.len() != want {
                return Err(RdfError::Bad(format!(
                    "{}: {} bytes decompressed where the index says {want}",
                    what("data"),
                    if data.len() > want {
                        format!("more than {want}")
                    } else {
                        data.len().to_string()
                    }
                )));
            }
            data
        }
        c => {
            return Err(RdfError::Bad(format!(
                "{}: unknown compression {c} (0 none, 1 Zstandard)",
                what("data")
            )));
        }
    };
    Ok(Chunk {
        id,
        version,
        header,
        data,
    })
}

/// Writes `chunks` as an RDF file: the header, each chunk's header and data (uncompressed),
/// then the index. Identifiers longer than 16 bytes are cut.
pub fn write(chunks: &[Chunk]) -> Vec<u8> {
    let mut out = vec![0u8; HEADER_BYTES];
    let mut entries = Vec::with_capacity(chunks.len() * ENTRY_BYTES);
    for c in chunks {
        let header_at = out.len() as i64;
        out.extend_from_slice(&c.header);
        let data_at = out.len() as i64;
        out.extend_from_slice(&c.data);
        let mut id = [0u8; 16];
        let n = c.id.len().min(16);
        id[..n].copy_from_slice(&c.id.as_bytes()[..n]);
        entries.extend_from_slice(&id);
        entries.extend_from_slice(&[0, 0, 0, 0]); // no compression, reserved
        entries.extend_from_slice(&c.version.to_le_bytes());
        for v in [
            header_at,
            c.header.len() as i64,
            data_at,
            c.data.len() as i64,
            0, // uncompressed
        ] {
            entries.extend_from_slice(&v.to_le_bytes());
        }
    }
    let index_at = out.len() as i64;
    out.extend_from_slice(&entries);
    out[..8].copy_from_slice(MAGIC);
    out[8..12].copy_from_slice(&VERSION.to_le_bytes());
    out[16..24].copy_from_slice(&index_at.to_le_bytes());
    out[24..32].copy_from_slice(&(entries.len() as i64).to_le_bytes());
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn chunks() -> Vec<Chunk> {
        vec![
            Chunk {
                id: "RAYVIS_SCENE".into(),
                version: 1,
                header: vec![1, 2, 3],
                data: (0..200u8).collect(),
            },
            Chunk {
                id: "SIXTEEN_BYTES_ID".into(),
                version: 7,
                header: vec![],
                data: vec![9; 5],
            },
        ]
    }

    #[test]
    fn a_written_file_reads_back_and_has_the_layout_of_the_specification() {
        let file = write(&chunks());
        assert_eq!(&file[..8], MAGIC);
        assert_eq!(u32_at(&file, 8), 3);
        // The index is last: two 64-byte entries.
        assert_eq!(i64_at(&file, 24), 128);
        assert_eq!(i64_at(&file, 16) as usize + 128, file.len());
        assert_eq!(read(&file).unwrap(), chunks());
    }

    /// A Zstandard chunk as libamdrdf writes one (the data compressed, the uncompressed size
    /// in the entry).
    #[test]
    fn zstandard_chunks_are_decompressed_and_lies_about_their_size_refused() {
        let data: Vec<u8> = (0..5000u32).flat_map(|i| (i % 7).to_le_bytes()).collect();
        let packed = ruzstd::encoding::compress_to_vec(
            data.as_slice(),
            ruzstd::encoding::CompressionLevel::Fastest,
        );
        let mut file = write(&[Chunk {
            id: "RAYVIS_RAYTRACE".into(),
            version: 1,
            header: vec![4, 0, 0, 0],
            data: packed.clone(),
        }]);
        let entry = i64_at(&file, 16) as usize;
        file[entry + 16] = 1;
        file[entry + 56..entry + 64].copy_from_slice(&(data.len() as i64).to_le_bytes());
        let read_back = read(&file).unwrap();
        assert_eq!(read_back[0].data, data);
        // An entry that says less, or more, than the stream holds.
        for lie in [data.len() as i64 - 1, data.len() as i64 + 1, -5, i64::MAX] {
            let mut bad = file.clone();
            bad[entry + 56..entry + 64].copy_from_slice(&lie.to_le_bytes());
            assert!(matches!(read(&bad), Err(RdfError::Bad(_))), "{lie}");
        }
        let mut bad = file.clone();
        bad[entry + 16] = 9;
        assert!(
            read(&bad)
                .unwrap_err()
                .to_string()
                .contains("unknown compression 9")
        );
    }

    /// Every truncation and a flipped byte anywhere: an error or a file, never a panic.
    #[test]
    fn damaged_files_fail_clearly() {
        let file = write(&chunks());
        assert_eq!(read(b"PK\x03\x04"), Err(RdfError::NotRdf));
        let mut v = file.clone();
        v[8] = 2;
        assert_eq!(read(&v), Err(RdfError::Version(2)));
        for n in 0..file.len() {
            let _ = read(&file[..n]);
            assert!(read(&file[..n]).is_err(), "cut at {n}");
        }
        for i in 0..file.len() {
            for flip in [0x01u8, 0x80, 0xff] {
                let mut v = file.clone();
                v[i] ^= flip;
                let _ = read(&v);
            }
        }
        let mut v = file.clone();
        v[24..32].copy_from_slice(&100i64.to_le_bytes());
        assert!(
            read(&v)
                .unwrap_err()
                .to_string()
                .contains("64-byte entries")
        );
    }
}
