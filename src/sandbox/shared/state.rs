//! The sandbox's state: the loaded volume with its transfer function and settings (resources),
//! the volume's box and the main camera with its view (components). The system that writes
//! them into the GPU preview's material is `preview/sync.rs`.

use bevy::prelude::*;
use std::sync::Arc;
use voxcast_core::Prepared;
use voxcast_core::preset::Preset;
use voxcast_core::settings::RenderSettings;
use voxcast_core::transfer::TransferFunction;

/// The mesh and material assets a feature adds its shapes to.
#[derive(bevy::ecs::system::SystemParam)]
pub struct MeshAssets<'w> {
    pub meshes: ResMut<'w, Assets<Mesh>>,
    pub materials: ResMut<'w, Assets<StandardMaterial>>,
}

/// The volume being looked at: replaced whole when another is loaded.
#[derive(Resource, Clone)]
pub struct VolumeState {
    pub volume: Arc<Prepared>,
    /// Where it came from (`builtin:NAME` or a path), for the UI.
    pub source: String,
    pub preset: Option<Preset>,
}

/// How it is rendered: read by the preview and the CPU render; written only by
/// `render_change.rs`, where every feature sends the changes it asks for.
#[derive(Resource, Clone, PartialEq, Debug)]
pub struct RenderState {
    pub transfer: TransferFunction,
    pub settings: RenderSettings,
    /// Stop preview rays at opaque scene geometry (the depth prepass).
    pub depth_termination: bool,
}

/// Marks the volume's box entity.
#[derive(Component)]
pub struct VolumeBox;

/// The main camera (the one that sees the preview).
#[derive(Component)]
pub struct MainCamera;

/// The main camera's view as the core describes it: the single source of its rays, for the
/// preview (through the uniform) and the CPU render alike. Its Bevy transform and projection
/// are derived from it.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct View(pub voxcast_core::camera::Camera);
