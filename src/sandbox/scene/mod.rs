//! The scene around the volume: the orbit camera, the lights and their markers, the crop box
//! and clip plane, the lattice, the overlay lines, and the meshes kept sharp over a smaller
//! preview. Imports `shared/` and `gpu/`.

pub mod cut;
pub mod lattice;
pub mod light;
pub mod orbit;
pub mod overlay;
pub mod sharp;

/// The window's part of this layer: the orbit, the light's and the cut's drags, the lattice,
/// the overlay lines and the sharp meshes.
pub(crate) fn plugin(app: &mut bevy::prelude::App) {
    app.add_plugins((
        orbit::plugin,
        light::plugin,
        cut::plugin,
        lattice::plugin,
        overlay::plugin,
        sharp::plugin,
    ));
}
