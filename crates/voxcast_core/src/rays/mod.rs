//! Ray data sets, as RayVis (seed 002) visualises them: a set of rays from some renderer — their
//! origins, directions and where each stopped — and the views of it: the density of rays per
//! cell of a grid over the scene, and their mean direction per cell.
//!
//! [`set`] holds the rays and RayVis's rules (hit or miss, the counted segment, filters and
//! stride); [`density`] traverses them through a sparse grid of cells (Amanatides & Woo).
//! [`mesh`] holds triangle scenes and their brute-force tracer, [`cornell`] the embedded Cornell
//! box, and [`effects`] the sets Voxcast traces through a scene itself (primary, shadow,
//! reflection and ambient-occlusion rays); [`camera`] the virtual camera's rays through a
//! volume. [`grid`] lays a density out densely, writes it as NRRD and makes it a volume, which
//! [`as_volume`] offers as a source every volume path opens (`density:SOURCE@cell=S,…`);
//! [`layered`] renders that volume over its scene; [`lines`] makes the ray mesh view's lines
//! and [`field`] the vector field view's arrows, which [`raster`] draws on the CPU over a
//! camera's view; [`rdf`] and [`rayvis`] read and write
//! RayVis's `.rayvis` files; [`source`] finds a data set by name.

pub mod as_volume;
pub mod camera;
pub mod cornell;
pub mod data;
pub mod density;
pub mod effects;
pub mod field;
pub mod grid;
pub mod layered;
pub mod lines;
pub mod mesh;
pub mod raster;
pub mod rayvis;
pub mod rdf;
pub mod set;
pub mod source;
pub mod study;
