//! The readers on real files and on every way a file can be wrong: a clear, typed error naming
//! the file, never a panic and never an allocation the file cannot back.
//!
//! The embedded copies of two real volumes are always read; the real volumes of
//! `../shared/data` in `real_files.rs`.

mod common;

use flate2::Compression;
use flate2::write::GzEncoder;
use std::io::Write;
use std::path::{Path, PathBuf};
use voxcast_core::error::LoadProblem;
use voxcast_core::glam::{UVec3, Vec3};
use voxcast_core::io::load;
use voxcast_core::volume::ScalarType;
use voxcast_core::{LoadError, VoxelData};

fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("voxcast-readers-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn gzip(bytes: &[u8]) -> Vec<u8> {
    let mut e = GzEncoder::new(Vec::new(), Compression::fast());
    e.write_all(bytes).unwrap();
    e.finish().unwrap()
}

fn write(name: &str, bytes: &[u8]) -> PathBuf {
    let p = temp(name);
    std::fs::write(&p, bytes).unwrap();
    p
}

#[track_caller]
fn fails(path: &Path, check: impl Fn(&LoadProblem) -> bool) {
    match load(path) {
        Ok(_) => panic!("{} loaded but should not", path.display()),
        Err(e) => {
            assert_eq!(e.path, path, "the error names the file");
            assert!(e.to_string().contains(&path.display().to_string()));
            assert!(
                check(&e.problem),
                "{}: unexpected problem: {e}",
                path.display()
            );
        }
    }
}

#[test]
fn damaged_copies_of_the_embedded_files_fail_cleanly() {
    common::damaged_copies_fail_cleanly(vec![
        (
            "bunny.nrrd".into(),
            include_bytes!("../../../assets/volumes/bunny_sdf.nrrd").to_vec(),
        ),
        (
            "brainsmall.nrrd".into(),
            include_bytes!("../../../assets/volumes/mri_brainsmall.nrrd").to_vec(),
        ),
    ]);
}

/// A NRRD header with these fields, then the blank line.
fn nrrd(fields: &[&str]) -> Vec<u8> {
    let mut h = String::from("NRRD0004\n# test\n");
    for f in fields {
        h.push_str(f);
        h.push('\n');
    }
    h.push('\n');
    h.into_bytes()
}

#[test]
fn nrrd_encodings_types_and_endianness() {
    let values: Vec<i16> = vec![-3, 0, 7, 1000, -32768, 32767, 5, 6];
    let le: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
    let be: Vec<u8> = values.iter().flat_map(|v| v.to_be_bytes()).collect();
    let base = [
        "type: short",
        "dimension: 3",
        "sizes: 2 2 2",
        "spacings: 0.5 1 2",
    ];
    let expect = VoxelData::I16(values.clone());
    let cases: Vec<(&str, Vec<u8>)> = vec![
        (
            "raw_le.nrrd",
            [
                nrrd(&[&base[..], &["endian: little", "encoding: raw"]].concat()),
                le.clone(),
            ]
            .concat(),
        ),
        (
            "raw_be.nrrd",
            [
                nrrd(&[&base[..], &["endian: big", "encoding: raw"]].concat()),
                be.clone(),
            ]
            .concat(),
        ),
        (
            "gz_be.nrrd",
            [
                nrrd(&[&base[..], &["endian: big", "encoding: gzip"]].concat()),
                gzip(&be),
            ]
            .concat(),
        ),
        (
            "ascii.nrrd",
            [
                nrrd(&[&base[..], &["encoding: ascii"]].concat()),
                b"-3 0 7 1000\n-32768 32767 5 6\n".to_vec(),
            ]
            .concat(),
        ),
    ];
    for (name, bytes) in cases {
        let v = load(&write(name, &bytes))
            .unwrap_or_else(|e| panic!("{name}: {e}"))
            .volume;
        assert_eq!(v.data(), &expect, "{name}");
        assert_eq!(v.spacing(), Vec3::new(0.5, 1.0, 2.0), "{name}");
    }
    // Float data and 'space directions' (oblique: lengths used, with a note).
    let f: Vec<u8> = [1.5f32, -2.0]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    let bytes = [
        nrrd(&[
            "type: float",
            "dimension: 3",
            "sizes: 2 1 1",
            "space dimension: 3",
            "space directions: (0,3,4) (0,1,0) (0,0,1)",
            "endian: little",
            "encoding: raw",
        ]),
        f,
    ]
    .concat();
    let l = load(&write("float.nrrd", &bytes)).unwrap();
    assert_eq!(l.volume.data(), &VoxelData::F32(vec![1.5, -2.0]));
    assert_eq!(l.volume.spacing().x, 5.0);
    assert!(l.notes.iter().any(|n| n.contains("oblique")));
    // Two-dimensional data is one slice; a leading axis of size 1 is dropped.
    let bytes = [
        nrrd(&["type: uchar", "dimension: 2", "sizes: 3 2", "encoding: raw"]),
        vec![1, 2, 3, 4, 5, 6],
    ]
    .concat();
    assert_eq!(
        load(&write("slice.nrrd", &bytes)).unwrap().volume.dims(),
        UVec3::new(3, 2, 1)
    );
    let bytes = [
        nrrd(&[
            "type: uint8",
            "dimension: 4",
            "sizes: 1 2 1 1",
            "encoding: raw",
        ]),
        vec![9, 8],
    ]
    .concat();
    assert_eq!(
        load(&write("vec1.nrrd", &bytes)).unwrap().volume.dims(),
        UVec3::new(2, 1, 1)
    );
    // int8 is widened exactly; 64-bit floats are rounded, with notes.
    let bytes = [
        nrrd(&[
            "type: signed char",
            "dimension: 3",
            "sizes: 2 1 1",
            "encoding: raw",
        ]),
        vec![0xff, 0x7f],
    ]
    .concat();
    assert_eq!(
        load(&write("i8.nrrd", &bytes)).unwrap().volume.data(),
        &VoxelData::I16(vec![-1, 127])
    );
    let d: Vec<u8> = [0.25f64, 1e10]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    let bytes = [
        nrrd(&[
            "type: double",
            "dimension: 3",
            "sizes: 2 1 1",
            "endian: little",
            "encoding: gzip",
        ]),
        gzip(&d),
    ]
    .concat();
    let l = load(&write("f64.nrrd", &bytes)).unwrap();
    assert_eq!(l.volume.data(), &VoxelData::F32(vec![0.25, 1e10]));
    assert!(!l.notes.is_empty());
}

#[test]
fn nrrd_detached_headers_and_skips() {
    let data = temp("detached_data.raw");
    std::fs::write(
        &data,
        [b"junk line\n".as_slice(), &[0u8, 0, 0], &[10, 20, 30, 40]].concat(),
    )
    .unwrap();
    let header = [
        "NRRD0004",
        "type: uint8",
        "dimension: 3",
        "sizes: 2 2 1",
        "encoding: raw",
        "data file: detached_data.raw",
        "line skip: 1",
        "byte skip: 3",
    ]
    .join("\n");
    let p = write("detached.nhdr", header.as_bytes());
    assert_eq!(
        load(&p).unwrap().volume.data(),
        &VoxelData::U8(vec![10, 20, 30, 40])
    );
    // byte skip −1: the data are the file's last bytes.
    let p = write(
        "tail.nhdr",
        header
            .replace("byte skip: 3", "byte skip: -1")
            .replace("line skip: 1", "line skip: 0")
            .as_bytes(),
    );
    assert_eq!(
        load(&p).unwrap().volume.data(),
        &VoxelData::U8(vec![10, 20, 30, 40])
    );
    // A missing data file is named.
    let p = write(
        "missing.nhdr",
        header
            .replace("detached_data.raw", "nowhere.raw")
            .as_bytes(),
    );
    fails(&p, |e| e.to_string().contains("nowhere.raw"));
}

#[test]
fn malformed_nrrd_files_give_clear_errors() {
    let ok = [
        "type: uint8",
        "dimension: 3",
        "sizes: 2 2 2",
        "encoding: raw",
    ];
    let with = |replace: &str, by: &str| -> Vec<u8> {
        let fields: Vec<String> = ok
            .iter()
            .map(|f| {
                if f.starts_with(replace) {
                    by.to_string()
                } else {
                    f.to_string()
                }
            })
            .collect();
        let refs: Vec<&str> = fields.iter().map(String::as_str).collect();
        nrrd(&refs)
    };
    let eight = vec![1u8; 8];
    let h = |p: &LoadProblem| matches!(p, LoadProblem::Header(_));
    fails(
        &write("truncated.nrrd", &[nrrd(&ok), vec![1; 5]].concat()),
        |p| {
            matches!(
                p,
                LoadProblem::Truncated {
                    expected: 8,
                    found: 5
                }
            )
        },
    );
    fails(
        &write("extra.nrrd", &[nrrd(&ok), vec![1; 9]].concat()),
        |p| matches!(p, LoadProblem::TooMuchData { .. }),
    );
    fails(
        &write(
            "type.nrrd",
            &[with("type", "type: complex"), eight.clone()].concat(),
        ),
        |p| matches!(p, LoadProblem::UnsupportedType(_)),
    );
    fails(
        &write(
            "enc.nrrd",
            &[with("encoding", "encoding: bzip2"), eight.clone()].concat(),
        ),
        |p| matches!(p, LoadProblem::UnsupportedEncoding(_)),
    );
    fails(
        &write(
            "zero.nrrd",
            &[with("sizes", "sizes: 0 2 2"), eight.clone()].concat(),
        ),
        |p| matches!(p, LoadProblem::Volume(_)),
    );
    fails(
        &write(
            "overflow.nrrd",
            &[
                with("sizes", "sizes: 4294967296 4294967296 4294967296"),
                eight.clone(),
            ]
            .concat(),
        ),
        |p| matches!(p, LoadProblem::Volume(_)),
    );
    fails(
        &write(
            "count.nrrd",
            &[with("sizes", "sizes: 2 2"), eight.clone()].concat(),
        ),
        h,
    );
    fails(
        &write(
            "dim5.nrrd",
            &[with("dimension", "dimension: 5"), eight.clone()].concat(),
        ),
        h,
    );
    fails(
        &write(
            "neg.nrrd",
            &[with("sizes", "sizes: -2 2 2"), eight.clone()].concat(),
        ),
        h,
    );
    fails(
        &write(
            "noendian.nrrd",
            &[with("type", "type: short"), vec![0; 16]].concat(),
        ),
        h,
    );
    fails(&write("nomagic.nrrd", b"hello\n\n\x01\x02"), h);
    fails(&write("empty.nrrd", b""), h);
    fails(&write("garbage.nrrd", &[0xffu8; 4096]), h);
    fails(
        &write(
            "noblank.nrrd",
            b"NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n",
        ),
        |p| matches!(p, LoadProblem::Truncated { .. }),
    );
    fails(
        &write(
            "badline.nrrd",
            &[with("type", "this is not a field"), eight.clone()].concat(),
        ),
        h,
    );
    fails(
        &write(
            "badspacing.nrrd",
            &[
                with("encoding", "encoding: raw\nspacings: 1 0 1"),
                eight.clone(),
            ]
            .concat(),
        ),
        h,
    );
    // NaN in float data: kept as "no data" (a masked cell), counted, not refused.
    let nan: Vec<u8> = [0.0f32, f32::NAN]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    let path = write(
        "nan.nrrd",
        &[
            nrrd(&[
                "type: float",
                "dimension: 3",
                "sizes: 2 1 1",
                "endian: little",
                "encoding: raw",
            ]),
            nan,
        ]
        .concat(),
    );
    let v = load(&path).expect("no data is data of its own");
    assert_eq!(
        (v.volume.no_data_count(), v.volume.value_range()),
        (1, (0.0, 0.0))
    );
    // A header asking for far more than its tiny gzip stream could hold is refused before any
    // allocation (this would need a terabyte otherwise).
    let big = [
        nrrd(&[
            "type: uint8",
            "dimension: 3",
            "sizes: 10000 10000 10000",
            "encoding: gzip",
        ]),
        gzip(&[0; 100]),
    ]
    .concat();
    fails(&write("bomb.nrrd", &big), |p| {
        matches!(p, LoadProblem::ImplausibleSize { .. })
    });
    let big = [
        nrrd(&[
            "type: uint8",
            "dimension: 3",
            "sizes: 10000 10000 10000",
            "encoding: raw",
        ]),
        vec![0; 100],
    ]
    .concat();
    fails(&write("bigraw.nrrd", &big), |p| {
        matches!(p, LoadProblem::Truncated { .. })
    });
    // A gzip stream shorter than the header says.
    let short = [
        nrrd(&[
            "type: uint8",
            "dimension: 3",
            "sizes: 4 4 4",
            "encoding: gzip",
        ]),
        gzip(&[7; 60]),
    ]
    .concat();
    fails(&write("shortgz.nrrd", &short), |p| {
        matches!(
            p,
            LoadProblem::Truncated {
                expected: 64,
                found: 60
            }
        )
    });
}

/// A NIfTI-1 header (348 bytes) in the given byte order.
// Kept with many arguments: one per header field the tests vary, in the header's own order.
#[allow(clippy::too_many_arguments)]
fn nifti_header(
    dims: &[u16],
    datatype: i16,
    bitpix: i16,
    pixdim: [f32; 3],
    vox_offset: f32,
    slope: f32,
    inter: f32,
    big: bool,
) -> Vec<u8> {
    let mut h = vec![0u8; 348];
    let put16 = |h: &mut Vec<u8>, at: usize, v: i16| {
        h[at..at + 2].copy_from_slice(&if big {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        })
    };
    let put32 = |h: &mut Vec<u8>, at: usize, v: i32| {
        h[at..at + 4].copy_from_slice(&if big {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        })
    };
    let putf = |h: &mut Vec<u8>, at: usize, v: f32| {
        h[at..at + 4].copy_from_slice(&if big {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        })
    };
    put32(&mut h, 0, 348);
    put16(&mut h, 40, dims.len() as i16);
    for (i, &d) in dims.iter().enumerate() {
        put16(&mut h, 42 + 2 * i, d as i16);
    }
    put16(&mut h, 70, datatype);
    put16(&mut h, 72, bitpix);
    putf(&mut h, 76, 1.0);
    for (i, &p) in pixdim.iter().enumerate() {
        putf(&mut h, 80 + 4 * i, p);
    }
    putf(&mut h, 108, vox_offset);
    putf(&mut h, 112, slope);
    putf(&mut h, 116, inter);
    h[344..348].copy_from_slice(if vox_offset >= 348.0 && datatype != 0 {
        b"n+1\0"
    } else {
        b"ni1\0"
    });
    h
}

#[test]
fn nifti_files_in_every_form() {
    // Little-endian int16 with a rescale, single file.
    let vals: Vec<u8> = [1i16, -2, 3, 4]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    let nii = [
        nifti_header(&[2, 2, 1], 4, 16, [0.5, 0.5, 3.0], 352.0, 2.0, -10.0, false),
        vec![0; 4],
        vals.clone(),
    ]
    .concat();
    let l = load(&write("rescaled.nii", &nii)).unwrap();
    assert_eq!(l.volume.data(), &VoxelData::I16(vec![1, -2, 3, 4]));
    assert_eq!(l.volume.value_range(), (-14.0, -2.0), "raw × 2 − 10");
    assert_eq!(l.volume.value_at(0, 0, 0), Some(-8.0));
    assert_eq!(l.volume.spacing(), Vec3::new(0.5, 0.5, 3.0));
    assert_eq!(l.volume.dims(), UVec3::new(2, 2, 1));
    // Gzipped, big-endian float32.
    let f: Vec<u8> = [1.5f32, 2.5].iter().flat_map(|v| v.to_be_bytes()).collect();
    let nii = [
        nifti_header(&[2, 1, 1], 16, 32, [1.0; 3], 352.0, 0.0, 0.0, true),
        vec![0; 4],
        f,
    ]
    .concat();
    let l = load(&write("big.nii.gz", &gzip(&nii))).unwrap();
    assert_eq!(l.volume.data(), &VoxelData::F32(vec![1.5, 2.5]));
    // A .hdr/.img pair.
    let hdr = nifti_header(&[3, 1, 1], 2, 8, [1.0; 3], 0.0, 1.0, 0.0, false);
    let p = write("pair.hdr", &hdr);
    std::fs::write(p.with_extension("img"), [5u8, 6, 7]).unwrap();
    assert_eq!(
        load(&p).unwrap().volume.data(),
        &VoxelData::U8(vec![5, 6, 7])
    );
    // 4-D: the first volume, with a note.
    let nii = [
        nifti_header(&[2, 1, 1, 2], 2, 8, [1.0; 3], 352.0, 0.0, 0.0, false),
        vec![0; 4],
        vec![1, 2, 3, 4],
    ]
    .concat();
    let l = load(&write("four.nii", &nii)).unwrap();
    assert_eq!(l.volume.data(), &VoxelData::U8(vec![1, 2]));
    assert!(l.notes.iter().any(|n| n.contains("4-D")));
}

#[test]
fn malformed_nifti_files_give_clear_errors() {
    let good = |dims: &[u16], dt: i16, bp: i16, off: f32| {
        nifti_header(dims, dt, bp, [1.0; 3], off, 0.0, 0.0, false)
    };
    let h = |p: &LoadProblem| matches!(p, LoadProblem::Header(_));
    fails(
        &write("short.nii", &good(&[2, 2, 2], 2, 8, 352.0)[..200]),
        h,
    );
    fails(
        &write(
            "nodata.nii",
            &[good(&[2, 2, 2], 2, 8, 352.0), vec![0; 4], vec![1; 5]].concat(),
        ),
        |p| matches!(p, LoadProblem::Truncated { .. }),
    );
    fails(
        &write(
            "extra.nii",
            &[good(&[2, 1, 1], 2, 8, 352.0), vec![0; 4], vec![1; 5]].concat(),
        ),
        |p| matches!(p, LoadProblem::TooMuchData { .. }),
    );
    fails(
        &write(
            "complex.nii",
            &[good(&[1, 1, 1], 32, 64, 352.0), vec![0; 12]].concat(),
        ),
        |p| matches!(p, LoadProblem::UnsupportedType(_)),
    );
    fails(
        &write(
            "bitpix.nii",
            &[good(&[1, 1, 1], 4, 8, 352.0), vec![0; 6]].concat(),
        ),
        h,
    );
    fails(
        &write(
            "zero.nii",
            &[good(&[0, 1, 1], 2, 8, 352.0), vec![0; 4]].concat(),
        ),
        |p| matches!(p, LoadProblem::Volume(_)),
    );
    let mut inside = good(&[1, 1, 1], 2, 8, 352.0);
    inside[108..112].copy_from_slice(&100f32.to_le_bytes());
    fails(&write("offset.nii", &[inside, vec![0; 5]].concat()), h);
    let mut magic = good(&[1, 1, 1], 2, 8, 352.0);
    magic[344..348].copy_from_slice(b"xxxx");
    fails(&write("magic.nii", &[magic, vec![0; 5]].concat()), h);
    // A gzip stream that claims a huge volume: refused before allocating.
    let bomb = [good(&[10000, 10000, 1000], 2, 8, 352.0), vec![0; 4]].concat();
    fails(&write("bomb.nii.gz", &gzip(&bomb)), |p| {
        matches!(p, LoadProblem::ImplausibleSize { .. })
    });
    // An infinite float voxel is "no data", kept and counted, not an error.
    let inf: Vec<u8> = [f32::INFINITY]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    let v = load(&write(
        "inf.nii",
        &[good(&[1, 1, 1], 16, 32, 352.0), vec![0; 4], inf].concat(),
    ))
    .expect("no data loads");
    assert_eq!(v.volume.no_data_count(), 1);
    fails(&write("noimg.hdr", &good(&[1, 1, 1], 2, 8, 0.0)), h);
}

#[test]
fn raw_files_named_the_open_scivis_way() {
    let vals: Vec<u8> = (0u16..24).flat_map(|v| (v * 1000).to_le_bytes()).collect();
    let p = write("thing_2x3x4_uint16.raw", &vals);
    let v = load(&p).unwrap().volume;
    assert_eq!(
        (v.dims(), v.scalar_type()),
        (UVec3::new(2, 3, 4), ScalarType::U16)
    );
    assert_eq!(v.value_at(1, 2, 3), Some(23000.0));
    fails(&write("thing_2x3x5_uint16.raw", &vals), |p| {
        matches!(p, LoadProblem::Truncated { .. })
    });
    fails(&write("thing_2x3x3_uint16.raw", &vals), |p| {
        matches!(p, LoadProblem::TooMuchData { .. })
    });
    fails(&write("unnamed.raw", &vals), |p| {
        matches!(p, LoadProblem::Header(_))
    });
    fails(&write("volume.dat", &vals), |p| {
        matches!(p, LoadProblem::UnknownFormat)
    });
    fails(Path::new("/definitely/not/here.nrrd"), |p| {
        matches!(p, LoadProblem::Io(_))
    });
}

#[test]
fn load_error_names_the_file_in_its_message() {
    let e: LoadError = load(Path::new("/no/such/volume.nii.gz")).unwrap_err();
    let msg = e.to_string();
    assert!(msg.starts_with("/no/such/volume.nii.gz: "), "{msg}");
}

/// Files held in memory, as a browser hands them to the page: every reader reads them as it
/// reads the disk (the same volume, the same error naming the file), a detached header and a
/// `.hdr` find their data among them by name, and a data file not given is named.
#[test]
fn files_in_memory_read_as_files_on_disk() {
    use voxcast_core::io::{InMemory, load_from};
    let on_disk = |name: &str, bytes: &[u8]| load(&write(name, bytes));
    let in_memory = |files: &[(&str, &[u8])], name: &str| {
        let files = InMemory::new(
            files
                .iter()
                .map(|(n, b)| (n.to_string(), b.to_vec()))
                .collect(),
        );
        load_from(&files, Path::new(name))
    };
    // Attached NRRD, gzip-compressed.
    let mut attached = nrrd(&[
        "type: uint8",
        "dimension: 3",
        "sizes: 2 2 2",
        "encoding: gzip",
    ]);
    attached.extend(gzip(&[0, 1, 2, 3, 4, 5, 6, 7]));
    let disk = on_disk("memory.nrrd", &attached).unwrap();
    let memory = in_memory(&[("memory.nrrd", &attached)], "memory.nrrd").unwrap();
    assert_eq!(memory.volume.data(), disk.volume.data());
    assert_eq!(memory.volume.name(), disk.volume.name());
    // A detached header with its data file beside it, and without.
    let header = [
        "NRRD0004",
        "type: uint8",
        "dimension: 3",
        "sizes: 2 2 1",
        "encoding: raw",
        "data file: data.raw",
    ]
    .join("\n");
    let pair: [(&str, &[u8]); 2] = [("h.nhdr", header.as_bytes()), ("data.raw", &[1, 2, 3, 4])];
    assert_eq!(
        in_memory(&pair, "h.nhdr").unwrap().volume.data(),
        &VoxelData::U8(vec![1, 2, 3, 4])
    );
    let alone = in_memory(&pair[..1], "h.nhdr").unwrap_err().to_string();
    assert!(
        alone.contains("data.raw") && alone.contains("h.nhdr"),
        "{alone}"
    );
    // NIfTI: a .hdr and its .img.
    let hdr = nifti_header(&[2, 2, 1], 2, 8, [1.0; 3], 0.0, 0.0, 0.0, false);
    let img: &[u8] = &[5, 6, 7, 8];
    let nifti = in_memory(&[("scan.hdr", &hdr), ("scan.img", img)], "scan.hdr").unwrap();
    assert_eq!(nifti.volume.data(), &VoxelData::U8(vec![5, 6, 7, 8]));
    // Raw, named the Open SciVis way.
    let raw = in_memory(&[("r_2x1x1_uint8.raw", &[9, 10])], "r_2x1x1_uint8.raw").unwrap();
    assert_eq!(raw.volume.data(), &VoxelData::U8(vec![9, 10]));
    // A damaged file: the same words on disk and in memory, naming the file.
    let broken = &attached[..attached.len() - 6];
    let disk = on_disk("broken.nrrd", broken).unwrap_err().to_string();
    let memory = in_memory(&[("broken.nrrd", broken)], "broken.nrrd")
        .unwrap_err()
        .to_string();
    assert!(memory.starts_with("broken.nrrd"), "{memory}");
    assert!(disk.ends_with(&memory), "disk: {disk}\nmemory: {memory}");
}

/// Files held with a limit (a web page's memory): every reader refuses a header asking for more
/// voxel data than the limit before it allocates any, in words that give both sizes, and reads
/// a volume exactly at the limit.
#[test]
fn a_voxel_limit_refuses_larger_headers_before_reading() {
    use voxcast_core::io::{InMemory, load_from};
    let read = |name: &str, bytes: &[u8], limit: u64| {
        let mut files = InMemory::new(vec![(name.to_string(), bytes.to_vec())]);
        files.limit = Some(limit);
        load_from(&files, Path::new(name))
    };
    let over = |r: Result<voxcast_core::io::Loaded, voxcast_core::error::LoadError>| match r {
        Err(e) => matches!(e.problem, LoadProblem::OverLimit { .. }),
        Ok(_) => false,
    };
    let mut eight = nrrd(&[
        "type: uint16",
        "dimension: 3",
        "sizes: 2 2 1",
        "endian: little",
        "encoding: raw",
    ]);
    eight.extend([0u8; 8]);
    assert!(read("a.nrrd", &eight, 8).is_ok(), "exactly at the limit");
    assert!(over(read("a.nrrd", &eight, 7)));
    // A small compressed file whose header claims 2 GB: refused for the limit, in words.
    let mut huge = nrrd(&[
        "type: uint16",
        "dimension: 3",
        "sizes: 1024 1024 1024",
        "endian: little",
        "encoding: gzip",
    ]);
    huge.extend(gzip(&[0u8; 64]));
    let words = read("huge.nrrd", &huge, 512 << 20).unwrap_err().to_string();
    assert_eq!(
        words,
        "huge.nrrd: its voxel data takes 2 GB, more than the 512 MB that can be opened here"
    );
    let hdr = nifti_header(&[2, 2, 1], 2, 8, [1.0; 3], 0.0, 0.0, 0.0, false);
    let files = |limit| {
        let mut f = InMemory::new(vec![
            ("s.hdr".into(), hdr.clone()),
            ("s.img".into(), vec![1, 2, 3, 4]),
        ]);
        f.limit = Some(limit);
        f
    };
    assert!(load_from(&files(4), Path::new("s.hdr")).is_ok());
    assert!(over(load_from(&files(3), Path::new("s.hdr"))));
    assert!(read("r_2x1x1_uint8.raw", &[9, 10], 2).is_ok());
    assert!(over(read("r_2x1x1_uint8.raw", &[9, 10], 1)));
}
