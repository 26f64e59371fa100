//! What is on show and where it came from: loading volumes, and RayVis's ray data sets — the
//! density's source, what the Ray data section computes next, the estimates before it, and the
//! views drawn around the density (the GPU's meshes, the CPU's lines). Imports the layers below
//! (`shared/` to `inspect/`).

pub mod choices;
pub mod cpu_lines;
pub mod estimate;
pub mod handed_rays;
pub mod loading;
pub mod shortcuts;
pub mod source;
pub mod views;
