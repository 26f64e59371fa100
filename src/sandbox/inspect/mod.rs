//! Following rays: the virtual camera, its rays and samples, the skip blocks they crossed, and
//! the selected ray's breakdown and the cells it crosses. Imports the layers below (`shared/` to
//! `scene/`).

pub mod blocks;
pub mod breakdown;
pub mod cells;
pub mod rays;
pub mod virtual_camera;

/// The window's part of this layer: the virtual camera, its rays, the skip blocks and cells
/// drawn, the selected ray's breakdown.
pub(crate) fn plugin(app: &mut bevy::prelude::App) {
    app.add_plugins((
        virtual_camera::plugin,
        rays::plugin,
        blocks::plugin,
        cells::plugin,
        breakdown::plugin,
    ));
}
