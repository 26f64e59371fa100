//! Who draws what: the render layers of the scene's meshes, and the markers a feature puts on
//! an entity for the others to treat it as solid.

use bevy::prelude::*;

/// The render layer of the scene's opaque meshes (sample spheres, the light's marker): the
/// main camera sees it while the GPU draws the volume; with the CPU, they are in its image.
pub const OCCLUDER_LAYER: usize = 1;

/// The layer of the solid meshes' depth-only twins: the preview camera sees it (instead of
/// the meshes) while it draws below full resolution.
pub const DEPTH_LAYER: usize = 2;
/// The layer of the volume's box: every preview camera sees it, the sharp camera never.
pub const VOLUME_LAYER: usize = 3;
/// The layer of a ray density's scene meshes: the GPU's cameras see them; the CPU live view
/// has them in its image (its rays stop at the same triangles), so its camera never draws
/// them over it (they would hide the density in front of them).
pub const SCENE_LAYER: usize = 4;

/// An opaque mesh that stops the preview's rays: it gets a depth-only twin.
#[derive(Component, Clone, Copy, Default)]
pub struct Solid;

/// A sphere in the scene that stops the CPU's rays, as the depth prepass stops the GPU
/// preview's: the CPU live view finds what to stop at by this marker alone. The sphere is
/// centred on the entity, its radius `radius` times the entity's scale (the sample spheres' mesh
/// is a unit sphere, the light's marker is built to its size); it stops rays while visible and
/// while its material is opaque, and shows the material's colour.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct Occluder {
    pub radius: f32,
}
