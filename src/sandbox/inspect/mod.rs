//! Following rays: the virtual camera, its rays and samples, the skip blocks they crossed, and
//! the selected ray's breakdown. Imports the layers below (`shared/` to `scene/`).

pub mod blocks;
pub mod breakdown;
pub mod rays;
pub mod virtual_camera;
