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

/// The window's part of this layer: loading, the Ray data section's choices, estimates and
/// handed files, the density's views and the keys that toggle them.
pub(crate) fn plugin(app: &mut bevy::prelude::App) {
    app.add_plugins((
        loading::plugin,
        choices::plugin,
        estimate::plugin,
        handed_rays::plugin,
        views::plugin,
        cpu_lines::plugin,
        shortcuts::plugin,
    ));
}
