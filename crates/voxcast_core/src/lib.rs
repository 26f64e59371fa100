//! Voxcast's pure core: the exact CPU volume ray caster that every other part is measured against.
//!
//! The lecture's pipeline appears here as one file per stage, and the WGSL in `shaders/` will use
//! the same file stems and function names:
//!
//! | stage | file | what it does |
//! | --- | --- | --- |
//! | data | [`volume`], [`io`], [`builtin`], [`prepared`] | the voxel grid, its readers and the embedded datasets; the structures its renders reuse |
//! | ray | [`camera`], [`ray`], [`clip`] | one ray per pixel centre; the ray–box slab test; the crop box and clip plane |
//! | step | [`step`] | where samples sit along the ray, jitter, the sample cap |
//! | sample | [`sample`] | nearest / trilinear reconstruction, the 8 corners, gradients |
//! | classify | [`transfer`], [`classify`] | value → colour and opacity (LUT, Levoy's modes) |
//! | shade | [`shade`] | Phong / Blinn–Phong with central-difference normals |
//! | composite | [`composite`], [`power`] | Accumulate, First, Average, Maximum, Minimum; the opacity correction's power for a whole step |
//! | trace | [`scene`], [`trace`], [`breakdown`], [`explain`] | what a render shares; one ray, optionally recorded sample by sample, and its formulas with the numbers put in |
//! | render | [`render`], [`entry`], [`cost`] | every pixel, in parallel, cancellable; where each pixel's rays can first meet a visible cell; what each pixel's rays cost, as a heat map |
//!
//! # Conventions (written down once)
//!
//! * **Where values sit.** A volume of `n = (nx, ny, nz)` lattice points with spacing
//!   `s = (sx, sy, sz)` holds voxel `(i, j, k)` at world position `(i·sx, j·sy, k·sz)`. The volume's
//!   box spans `[0, (n−1)·s]` on each axis, as VTK and ITK image data do. An axis with a single
//!   lattice point (`n = 1`) would have no extent under that rule, so it is given one spacing of
//!   thickness centred on the point, `[−s/2, s/2]`; this keeps 1×1×1 and single-slice volumes
//!   visible, and matches the texel-centre mapping a GPU texture uses.
//! * **Voxel space** is world space divided by the spacing: voxel `(i, j, k)` sits at the point
//!   `(i, j, k)`. Trilinear interpolation works there, with the lattice clamped at its borders.
//! * **Memory order**: x varies fastest, then y, then z (`index = i + nx·(j + ny·k)`).
//! * **World space** is right-handed. Cameras look along −z in their own view space, with +y up
//!   (the OpenGL/Bevy convention); image row 0 is the top row.
//! * **Data units** are the file's values after any rescale the format defines (NIfTI's
//!   `scl_slope`/`scl_inter`); transfer functions and target values are given in data units.
//! * **Colours** are linear floats in `[0, 1]`, written to 8-bit images without a transfer curve,
//!   as VTK does. Accumulated colour is premultiplied by opacity.
//! * **Distances along a ray** (`t`, `dt`) are in world units; the ray's direction is unit length.

pub mod breakdown;
pub mod bricks;
pub mod builtin;
pub mod camera;
pub mod cells;
pub mod classify;
pub mod clip;
pub mod colormap;
pub mod composite;
pub mod cost;
pub mod depth;
pub mod entry;
pub mod error;
pub mod explain;
pub mod hash;
pub mod histogram;
pub mod histogram2d;
pub mod image_out;
pub mod io;
pub mod knob;
pub mod level;
pub mod marker;
mod minmax;
pub mod numbers;
pub mod peer;
pub mod power;
pub mod prepared;
pub mod preset;
pub mod ray;
pub mod rays;
pub mod recompute;
pub mod render;
pub mod sample;
pub mod scene;
pub mod settings;
pub mod shade;
pub mod skip;
pub mod slices;
pub mod step;
pub mod trace;
pub mod trade;
pub mod traffic;
pub mod transfer;
pub mod transfer_edit;
pub mod tunables;
pub mod vectors;
pub mod volume;
pub mod worked;

pub use error::{LoadError, SettingsError, VolumeError};
pub use glam;
pub use prepared::Prepared;
pub use volume::{Volume, VoxelData};
