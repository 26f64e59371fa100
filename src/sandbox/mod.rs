//! The sandbox: a Bevy scene with the volume's live GPU preview, an orbit camera and the
//! settings panel; or, with `--screenshot`, one frame of the preview saved to a PNG.
//!
//! **Layers.** Each folder is a layer, and a file imports only from its own folder and the
//! folders below it (`tests/layers.rs` reads every file's paths and fails on an import that
//! runs upward or a circle of files). Bottom to top:
//!
//! 1. `shared/` — the state every feature reads: the volume and its settings, the frame's
//!    order, the preview's settings, the viewport and the mouse, render layers and markers
//!    (`Solid`, `Occluder`), the mode, background tasks, files, the page;
//! 2. `gpu/` — the preview's material, its uniform, the shaders, pipeline compilation;
//! 3. `scene/` — the orbit camera, lights, the crop box and clip plane, lattice, overlay lines,
//!    the meshes kept sharp;
//! 4. `inspect/` — the virtual camera, its rays and samples, skip blocks, the ray's breakdown;
//! 5. `data/` — loading volumes; RayVis's ray data sets and their views;
//! 6. `preview/` — the GPU preview and the CPU live view, their quality, the paint;
//! 7. `checks/` — Render image and Measure;
//! 8. `levels/` — the guided levels' logic;
//! 9. `drivers/` — screenshot, comparison, frame-time measurement and play-through runs;
//! 10. `ui/` — the panels;
//! 11. `app/` — the command line's options, what the sandbox starts with, the app built from
//!     the layers (`app/run.rs`, `app/window.rs`) and, in a browser, the page's start.
//!
//! This file is the map. Features talk through components, resources and messages. The frame's order is one enum, [`Frame`](shared::schedule::Frame)
//! (`shared/schedule.rs`: its sets in `Update`, then in `PostUpdate`), with
//! [`Paint`](shared::schedule::Paint) for the egui pass; every feature
//! puts its systems in those sets.

pub mod app;
pub mod checks;
pub mod data;
pub mod drivers;
pub mod gpu;
pub mod inspect;
pub(crate) mod levels;
pub mod preview;
pub mod scene;
pub mod shared;
mod ui;

#[cfg(target_arch = "wasm32")]
pub use app::page;
#[cfg(not(target_arch = "wasm32"))]
pub use app::{args::SandboxArgs, run::run};
