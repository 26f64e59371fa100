//! The scene around the volume: the orbit camera, the lights and their markers, the crop box
//! and clip plane, the lattice, the overlay lines, and the meshes kept sharp over a smaller
//! preview. Imports `shared/` and `gpu/`.

pub mod cut;
pub mod lattice;
pub mod light;
pub mod orbit;
pub mod overlay;
pub mod sharp;
