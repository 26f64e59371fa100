//! Following rays: the virtual camera, its rays and samples, the skip blocks they crossed, and
//! the selected ray's breakdown and the cells it crosses. Imports the layers below (`shared/` to
//! `scene/`).

pub mod blocks;
pub mod breakdown;
pub mod cells;
pub mod rays;
pub mod virtual_camera;
