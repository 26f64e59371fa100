//! The volume in the window: the GPU preview (its camera, its material kept in step, drawn a
//! strip at a time at rest) or the CPU live view, at the quality the settings and the motion
//! allow, painted beneath the panels. Imports the layers below (`shared/` to `data/`).

pub mod camera;
pub mod live;
pub mod paint;
pub mod progressive;
pub mod quality;
pub mod sync;

/// The window's part of this layer: the preview painted beneath the panels, the CPU live view,
/// the strips at rest.
pub(crate) fn plugin(app: &mut bevy::prelude::App) {
    app.add_plugins((paint::plugin, live::plugin, progressive::plugin));
}
