//! The `voxcast` command line: render, trace, info, bench, rays, levels and answers over the core. In a
//! browser only the sandbox's options are read (from the page's address).

#[cfg(not(target_arch = "wasm32"))]
pub mod answers;
pub mod args;
#[cfg(not(target_arch = "wasm32"))]
pub mod bench;
#[cfg(not(target_arch = "wasm32"))]
pub mod info;
#[cfg(not(target_arch = "wasm32"))]
pub mod knobs;
#[cfg(not(target_arch = "wasm32"))]
pub mod levels;
#[cfg(not(target_arch = "wasm32"))]
pub mod plot;
#[cfg(not(target_arch = "wasm32"))]
pub mod progress;
#[cfg(not(target_arch = "wasm32"))]
pub mod rays;
#[cfg(not(target_arch = "wasm32"))]
pub mod rays_input;
#[cfg(not(target_arch = "wasm32"))]
pub mod rays_render;
#[cfg(not(target_arch = "wasm32"))]
pub mod rays_study;
#[cfg(not(target_arch = "wasm32"))]
pub mod render;
#[cfg(not(target_arch = "wasm32"))]
pub mod trace;

use voxcast_core::{LoadError, SettingsError};

/// A command's failure, with the exit code it maps to.
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    /// Bad arguments (exit code 2).
    #[error("{0}")]
    Usage(String),
    /// A value out of range (exit code 2).
    #[error("{0}")]
    Settings(#[from] SettingsError),
    /// A file that could not be loaded (exit code 1).
    #[error("{0}")]
    Load(#[from] LoadError),
    /// Anything else that failed while working (exit code 1).
    #[error("{0}")]
    Failed(String),
}

impl CliError {
    pub fn usage(msg: impl Into<String>) -> Self {
        Self::Usage(msg.into())
    }

    pub fn failed(msg: impl Into<String>) -> Self {
        Self::Failed(msg.into())
    }

    #[cfg(not(target_arch = "wasm32"))]
    pub fn exit_code(&self) -> i32 {
        match self {
            Self::Usage(_) | Self::Settings(_) => 2,
            Self::Load(_) | Self::Failed(_) => 1,
        }
    }
}
