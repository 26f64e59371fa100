//! Checking the preview: Render image (the exact CPU render of the same view, compared), and
//! Measure (a knob's trade of speed for accuracy, and the preview's frame time). Imports the
//! layers below (`shared/` to `preview/`).

pub mod compare;
pub mod frame_trade;
pub mod trade;

/// The window's part of this layer: Render image and the step's trade.
pub(crate) fn plugin(app: &mut bevy::prelude::App) {
    app.add_plugins((compare::plugin, trade::plugin));
}
