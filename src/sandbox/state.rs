//! The sandbox's state: the loaded volume with its transfer function and settings (resources),
//! the volume entity, and the one system that syncs them to the material when they change.

use super::material::{VolumeMaterial, lut_image, volume_image};
use super::uniform::VolumeUniform;
use bevy::prelude::*;
use std::sync::Arc;
use voxcast_core::Volume;
use voxcast_core::preset::Preset;
use voxcast_core::settings::RenderSettings;
use voxcast_core::trace::Scene;
use voxcast_core::transfer::TransferFunction;

/// The volume being looked at: replaced whole when another is loaded.
#[derive(Resource, Clone)]
pub struct VolumeState {
    pub volume: Arc<Volume>,
    /// Where it came from (`builtin:NAME` or a path), for the UI.
    pub source: String,
    pub preset: Option<Preset>,
}

/// How it is rendered: edited by the UI, read by the preview and the CPU render.
#[derive(Resource, Clone, PartialEq)]
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

pub(super) fn plugin(app: &mut App) {
    app.add_systems(Update, (spawn_volume, sync_volume_material).chain());
}

/// (Re)spawns the box when a volume is loaded: a cuboid spanning the volume's bounds.
fn spawn_volume(
    mut commands: Commands,
    state: Res<VolumeState>,
    render: Res<RenderState>,
    existing: Query<Entity, With<VolumeBox>>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut images: ResMut<Assets<Image>>,
    mut materials: ResMut<Assets<VolumeMaterial>>,
) {
    if !state.is_changed() {
        return;
    }
    for e in &existing {
        commands.entity(e).despawn();
    }
    let v = &state.volume;
    let (lo, hi) = v.bounds();
    let (lut_lo, lut_hi) = v.value_range();
    let lut = render.transfer.bake(lut_lo, lut_hi);
    let material = VolumeMaterial {
        uniform: VolumeUniform::default(),
        volume: images.add(volume_image(v)),
        lut: images.add(lut_image(&lut)),
    };
    commands.spawn((
        VolumeBox,
        // Primitives are centred on the origin: the transform puts the box where the volume is.
        Mesh3d(meshes.add(Cuboid::from_size(hi - lo))),
        MeshMaterial3d(materials.add(material)),
        Transform::from_translation((lo + hi) * 0.5),
    ));
}

/// Writes the settings and the view into the material, only when something changed.
fn sync_volume_material(
    state: Res<VolumeState>,
    render: Res<RenderState>,
    views: Query<(Ref<View>, Ref<Camera>), With<MainCamera>>,
    boxes: Query<&MeshMaterial3d<VolumeMaterial>, With<VolumeBox>>,
    mut materials: ResMut<Assets<VolumeMaterial>>,
    mut images: ResMut<Assets<Image>>,
    mut baked: Local<Option<voxcast_core::transfer::TransferFunction>>,
) {
    let Ok((view, camera)) = views.single() else {
        return;
    };
    let view_changed = view.is_changed() || camera.is_changed();
    if !(state.is_changed() || render.is_changed() || view_changed) {
        return;
    }
    let Some(size) = camera.physical_viewport_size() else {
        return;
    };
    let Ok(handle) = boxes.single() else { return };
    let Ok(scene) = Scene::plain(
        &state.volume,
        &render.transfer,
        &render.settings,
        view.0.forward(),
    ) else {
        return; // the controls only produce valid settings
    };
    let Some(mut material) = materials.get_mut(&handle.0) else {
        return;
    };
    let rays = view.0.rays(size.x.max(1), size.y.max(1));
    material.uniform = VolumeUniform::from_scene(&scene, &rays, render.depth_termination);
    // The table only changes with the transfer function or the volume's value range.
    if state.is_changed() || baked.as_ref() != Some(&render.transfer) {
        material.lut = images.add(lut_image(&scene.lut));
        *baked = Some(render.transfer.clone());
    }
}
