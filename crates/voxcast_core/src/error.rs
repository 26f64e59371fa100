//! Typed errors: every way a file, a value or a setting can be wrong, each naming what was wrong.
//!
//! Nothing in the core panics on user input; constructors validate and return these instead.

use std::path::PathBuf;
use thiserror::Error;

/// A voxel grid that cannot exist: wrong sizes, spacing or values.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum VolumeError {
    #[error("dimensions {0}×{1}×{2}: every axis needs at least one voxel")]
    ZeroDimension(u64, u64, u64),
    #[error("dimensions {0}×{1}×{2} overflow the addressable number of voxels")]
    TooManyVoxels(u64, u64, u64),
    #[error("the data holds {found} values but the dimensions need {expected}")]
    LengthMismatch { expected: u64, found: u64 },
    #[error("spacing ({0}, {1}, {2}) must be finite and positive on every axis")]
    BadSpacing(f32, f32, f32),
    #[error("rescale slope {slope} and intercept {intercept} must be finite, slope non-zero")]
    BadRescale { slope: f32, intercept: f32 },
}

/// What was wrong with a file, without the file's name (see [`LoadError`]).
#[derive(Debug, Error)]
pub enum LoadProblem {
    #[error("{}", if .0.kind() == std::io::ErrorKind::NotFound {
        "file not found".to_string()
    } else {
        format!("cannot read: {}", io_words(.0))
    })]
    Io(#[from] std::io::Error),
    #[error("no embedded dataset of that name (choose from {0})")]
    UnknownBuiltin(String),
    #[error("{0} did not come with this page (the page fetches it from its volumes/ folder)")]
    NotProvided(String),
    #[error("unknown file format (expected .nrrd, .nhdr, .nii, .nii.gz, .hdr or .raw)")]
    UnknownFormat,
    #[error("bad header: {0}")]
    Header(String),
    #[error(
        "unsupported scalar type '{0}' (Voxcast reads 8-, 16- and 32-bit integers and 32- and 64-bit floats)"
    )]
    UnsupportedType(String),
    #[error("unsupported encoding '{0}' (Voxcast reads raw, gzip and ascii)")]
    UnsupportedEncoding(String),
    #[error(
        "truncated: the header needs {expected} bytes of voxel data but the file holds {found}"
    )]
    Truncated { expected: u64, found: u64 },
    #[error(
        "size mismatch: the header needs {expected} bytes of voxel data but the file holds more ({found} or more)"
    )]
    TooMuchData { expected: u64, found: u64 },
    #[error(
        "the header asks for {bytes} bytes of voxel data, more than this file could hold ({limit} at most)"
    )]
    ImplausibleSize { bytes: u64, limit: u64 },
    #[error(
        "its voxel data takes {}, more than the {} that can be opened here",
        crate::numbers::bytes(*.bytes),
        crate::numbers::bytes(*.limit)
    )]
    OverLimit { bytes: u64, limit: u64 },
    #[error("compressed data is corrupt: {0}")]
    Decompress(String),
    #[error("invalid volume: {0}")]
    Volume(#[from] VolumeError),
    #[error("ray density: {0}")]
    RayDensity(String),
}

/// An I/O error in words, without the operating system's error number ("(os error 2)").
pub fn io_words(e: &std::io::Error) -> String {
    use std::io::ErrorKind as K;
    match e.kind() {
        K::NotFound => "no such file or folder".into(),
        K::PermissionDenied => "permission denied".into(),
        K::IsADirectory => "this is a folder, not a file".into(),
        K::UnexpectedEof => "the file ends too early".into(),
        _ => {
            let text = e.to_string();
            let text = match text.rfind(" (os error ") {
                Some(i) => text[..i].to_string(),
                None => text,
            };
            text.to_lowercase()
        }
    }
}

/// A file that could not be loaded, naming the file and the problem.
#[derive(Debug, Error)]
#[error("{}: {problem}", path.display())]
pub struct LoadError {
    pub path: PathBuf,
    pub problem: LoadProblem,
}

impl LoadError {
    pub fn new(path: impl Into<PathBuf>, problem: impl Into<LoadProblem>) -> Self {
        Self {
            path: path.into(),
            problem: problem.into(),
        }
    }
}

/// A setting, transfer function or camera value that is out of its valid range.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SettingsError {
    #[error("{name} = {value}: {why}")]
    OutOfRange {
        name: &'static str,
        value: f64,
        why: &'static str,
    },
    #[error("{0}")]
    Invalid(String),
}

impl SettingsError {
    /// Checks that `value` is finite and inside `[lo, hi]`.
    pub fn check_range(name: &'static str, value: f32, lo: f32, hi: f32) -> Result<(), Self> {
        if !value.is_finite() {
            return Err(Self::OutOfRange {
                name,
                value: value as f64,
                why: "must be a finite number",
            });
        }
        if value < lo || value > hi {
            return Err(Self::Invalid(format!(
                "{name} = {value}: must lie in [{lo}, {hi}]"
            )));
        }
        Ok(())
    }

    /// Checks that `value` is finite and strictly positive.
    pub fn check_positive(name: &'static str, value: f32) -> Result<(), Self> {
        if !(value.is_finite() && value > 0.0) {
            return Err(Self::OutOfRange {
                name,
                value: value as f64,
                why: "must be a finite number greater than zero",
            });
        }
        Ok(())
    }
}
