//! The harness of the tests that read files a machine may lack (`../shared/data`, the VTK
//! peer's folder): they run under `libtest-mimic`, so a test whose files are missing is
//! reported as *ignored*, with the reason, instead of passing silently.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

mod harness;
pub use harness::*;

/// `dir` if it exists, else the ignored outcome that names it.
pub fn folder(dir: PathBuf) -> Result<PathBuf, Outcome> {
    if dir.is_dir() {
        Ok(dir)
    } else {
        Err(Ok(Completion::ignored_with(format!(
            "{} not found",
            dir.display()
        ))))
    }
}

/// The shared real volumes: `VOXCAST_DATA`, else `../shared/data` beside the clone.
pub fn data_dir() -> Result<PathBuf, Outcome> {
    folder(
        std::env::var_os("VOXCAST_DATA")
            .map(PathBuf::from)
            .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data")),
    )
}

/// The VTK peer's folder, `../shared/tools/peer` beside the clone.
pub fn peer_dir() -> Result<PathBuf, Outcome> {
    folder(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/tools/peer"))
}
