//! The GPU preview's parts: the material and its uniform in the shaders' layout, the WGSL
//! registered from `shaders/`, and whether pipelines are still compiling. Imports `shared/`.

pub mod material;
pub mod pipelines;
pub mod shaders;
pub mod uniform;
