//! The GPU preview's parts: the material and its uniform in the shaders' layout, the WGSL
//! registered from `shaders/`, and whether pipelines are still compiling. Imports `shared/`.

pub mod material;
pub mod pipelines;
pub mod shaders;
pub mod uniform;

/// The window's part of this layer: the pipelines' compiling note.
pub(crate) fn plugin(app: &mut bevy::prelude::App) {
    app.add_plugins(pipelines::window_plugin);
}
