//! The bottom layer: what every feature reads and none owns — the volume and its settings, the
//! frame's order, the preview's settings, the viewport and the mouse, render layers and markers,
//! the mode, background tasks, files and the page. Imports nothing else of the sandbox.

pub mod files;
pub mod fit;
pub mod layers;
pub mod mode;
pub mod pacing;
pub mod platform;
pub mod pointer;
pub mod quality;
pub mod render_change;
pub mod schedule;
pub mod state;
pub mod tasks;
pub mod viewport;
pub mod wake;
#[cfg(target_arch = "wasm32")]
pub mod web;
