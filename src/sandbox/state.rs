//! The sandbox's state: the loaded volume with its transfer function and settings (resources),
//! the volume entity, and the one system that syncs them to the material when they change.

use super::material::{
    VolumeMaterial, block_ranges_image, empty_blocks_image, lut_image, volume_image,
};
use super::preview::Quality;
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

/// The systems that write the material: after the camera's projection is updated for this
/// frame (so the uniform's rays use this frame's view and target size).
#[derive(SystemSet, Debug, Clone, PartialEq, Eq, Hash)]
pub struct SyncSystems;

pub(super) fn plugin(app: &mut App) {
    app.add_systems(Update, spawn_volume).add_systems(
        PostUpdate,
        sync_volume_material
            .in_set(SyncSystems)
            .after(bevy::camera::CameraUpdateSystems),
    );
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
        empty: images.add(empty_blocks_image(None)),
        ranges: images.add(block_ranges_image(v.block_ranges())),
    };
    commands.spawn((
        VolumeBox,
        // Primitives are centred on the origin: the transform puts the box where the volume is.
        Mesh3d(meshes.add(Cuboid::from_size(hi - lo))),
        MeshMaterial3d(materials.add(material)),
        Transform::from_translation((lo + hi) * 0.5),
        bevy::camera::visibility::RenderLayers::layer(super::sharp::VOLUME_LAYER),
    ));
}

/// Images already uploaded, and what they were made from.
#[derive(Default)]
struct Uploaded {
    /// The transfer function baked into the table.
    lut: Option<TransferFunction>,
    /// The transfer function the empty blocks were marked with (`None`: skipping off).
    empty: Option<TransferFunction>,
    /// The camera's target size the rays were written for.
    size: Option<UVec2>,
}

/// The assets the system writes: the material and its images.
#[derive(bevy::ecs::system::SystemParam)]
struct GpuAssets<'w> {
    materials: ResMut<'w, Assets<VolumeMaterial>>,
    images: ResMut<'w, Assets<Image>>,
}

/// Writes the settings and the view into the material, only when something changed.
fn sync_volume_material(
    state: Res<VolumeState>,
    render: Res<RenderState>,
    views: Query<(Ref<View>, &Camera), With<MainCamera>>,
    boxes: Query<&MeshMaterial3d<VolumeMaterial>, With<VolumeBox>>,
    mut assets: GpuAssets,
    mut uploaded: Local<Uploaded>,
    quality: Quality,
) {
    let Ok((view, camera)) = views.single() else {
        return;
    };
    // The rays span the camera's whole target (its viewport may be a strip of it: progressive).
    let Some(size) = camera.physical_target_size() else {
        return;
    };
    let view_changed = view.is_changed() || uploaded.size != Some(size);
    if !(state.is_changed() || render.is_changed() || view_changed || quality.changed()) {
        return;
    }
    // The preview may sample more coarsely than the settings say (never the CPU render).
    let mut settings = render.settings.clone();
    settings.step = settings.step.scaled(quality.step_multiplier());
    let Ok(handle) = boxes.single() else { return };
    let Ok(scene) = Scene::plain(&state.volume, &render.transfer, &settings, view.0.forward())
    else {
        return; // the controls only produce valid settings
    };
    let Some(mut material) = assets.materials.get_mut(&handle.0) else {
        return;
    };
    uploaded.size = Some(size);
    let rays = view.0.rays(size.x.max(1), size.y.max(1));
    material.uniform = VolumeUniform::from_scene(&scene, &rays, render.depth_termination);
    // The table only changes with the transfer function or the volume's value range.
    if state.is_changed() || uploaded.lut.as_ref() != Some(&render.transfer) {
        material.lut = assets.images.add(lut_image(&scene.lut));
        uploaded.lut = Some(render.transfer.clone());
    }
    // Empty-space skipping where the core would skip (`Scene::skips_empty`): the same blocks,
    // re-marked when the table changes.
    let skippable = scene.skips_empty();
    let blocks = state.volume.block_ranges();
    material.uniform.blocks = UVec3::new(blocks.blocks.x, blocks.blocks.y, blocks.blocks.z);
    material.uniform.skip_empty = skippable as u32;
    // First, Maximum and Minimum pass blocks by their value ranges, as the core does.
    material.uniform.skip_ranges = scene.skips_by_ranges() as u32;
    material.uniform.ties_skippable =
        (state.volume.scalar_type() != voxcast_core::volume::ScalarType::F32) as u32;
    let wanted = skippable.then(|| render.transfer.clone());
    if state.is_changed() || uploaded.empty != wanted {
        let empty = skippable.then(|| voxcast_core::skip::EmptyBlocks::new(blocks, &scene.lut));
        material.empty = assets.images.add(empty_blocks_image(empty.as_ref()));
        uploaded.empty = wanted;
    }
}
