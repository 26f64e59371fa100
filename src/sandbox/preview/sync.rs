//! The GPU preview's material kept in step with the state: the volume's box (re)spawned when a
//! volume is loaded, and the settings, the view and the skipping textures written into its
//! material when they change.

use crate::sandbox::gpu::material::{
    MAX_RECORD_BYTES, VolumeMaterial, block_ranges_image, empty_blocks_image, lut_image,
    records_image, visible_cells_image, volume_image,
};
use crate::sandbox::gpu::uniform::{FLAG_RECORDS, FLAG_SKIP_CELLS, VolumeUniform};
use crate::sandbox::preview::quality::Quality;
use crate::sandbox::shared::state::{MainCamera, RenderState, View, VolumeBox, VolumeState};
use bevy::prelude::*;
use bevy::tasks::{Task, futures::check_ready};
use std::sync::Arc;
use voxcast_core::prepared::EmptySpace;
use voxcast_core::trace::Scene;
use voxcast_core::transfer::TransferFunction;

pub(crate) fn plugin(app: &mut App) {
    app.init_resource::<CellsUpload>()
        .add_systems(
            Update,
            spawn_volume.in_set(crate::sandbox::shared::schedule::Frame::Show),
        )
        .add_systems(
            PostUpdate,
            (sync_volume_material, upload_visible_cells, upload_records)
                .chain()
                .in_set(crate::sandbox::shared::schedule::Frame::Sync),
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
        cells: images.add(visible_cells_image(None)),
        records: images.add(records_image(None)),
    };
    commands.spawn((
        VolumeBox,
        // Primitives are centred on the origin: the transform puts the box where the volume is.
        Mesh3d(meshes.add(Cuboid::from_size(hi - lo))),
        MeshMaterial3d(materials.add(material)),
        Transform::from_translation((lo + hi) * 0.5),
        bevy::camera::visibility::RenderLayers::layer(crate::sandbox::shared::layers::VOLUME_LAYER),
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

/// Whether the GPU draws the preview (or may: a capture without the sandbox's settings), so
/// its textures are worth computing on a machine whose two cores the CPU live view needs.
fn gpu_backend(preview: Option<&crate::sandbox::shared::quality::PreviewSettings>) -> bool {
    preview.is_none_or(|p| p.backend == crate::sandbox::shared::quality::Backend::Gpu)
}

/// What the cells' visibility is made for: the volume (by identity) and the transfer function.
type CellsKey = (usize, TransferFunction);

/// The cells' visibility (`VisibleCells`) for the GPU preview: found on the background pool
/// when the volume or the transfer function changes (tens of milliseconds on a CT: not inside a
/// frame), through the volume's kept empty space (`Prepared::empty_space`, which the CPU's
/// scenes for the same table then reuse), uploaded when ready. Until then the preview skips blocks only — the same image.
#[derive(Resource, Default)]
pub(crate) struct CellsUpload {
    /// What the material's cells texture was made for.
    done: Option<CellsKey>,
    task: Option<(CellsKey, Task<EmptySpace>)>,
    /// For the current volume and settings: whether Accumulate skips, and the baked table.
    current: Option<(bool, voxcast_core::transfer::Lut)>,
    /// The volume (by identity) the records texture was made for, and whether it holds them.
    records_done: Option<(usize, bool)>,
    records_task: Option<(usize, Task<Option<Image>>)>,
}

impl CellsUpload {
    /// Whether cells or records are being computed for the preview (a capture that tests the
    /// preview waits for them).
    pub(crate) fn pending(&self) -> bool {
        self.task.is_some() || self.records_task.is_some()
    }
}

/// Starts, takes in and uploads the volume's lattice records (`Prepared::lattice_differences`:
/// for integer volumes, within [`MAX_RECORD_BYTES`]) on the background pool when the volume
/// changes, and keeps the material's flag for them set exactly while the current volume's are
/// uploaded. Until then (or without them) the preview computes gradients from the volume
/// texture — the same image.
fn upload_records(
    state: Res<VolumeState>,
    boxes: Query<&MeshMaterial3d<VolumeMaterial>, With<VolumeBox>>,
    preview: Option<Res<crate::sandbox::shared::quality::PreviewSettings>>,
    mut assets: GpuAssets,
    mut upload: ResMut<CellsUpload>,
) {
    let Ok(handle) = boxes.single() else { return };
    let key = Arc::as_ptr(&state.volume) as usize;
    if state.is_changed() {
        upload.records_done = None;
    }
    if !gpu_backend(preview.as_deref()) {
        return; // the CPU live view draws: no work for the GPU's textures until it is chosen
    }
    if upload.records_done.is_none_or(|(k, _)| k != key) {
        let finished = match upload.records_task.as_mut() {
            Some((k, task)) if *k == key => check_ready(task),
            _ => {
                let volume = state.volume.clone();
                let task = crate::sandbox::shared::tasks::spawn(async move {
                    let count = volume.voxel_count();
                    if count.saturating_mul(8) > MAX_RECORD_BYTES {
                        return None;
                    }
                    let records = volume.lattice_differences()?;
                    Some(records_image(Some((records, volume.dims()))))
                });
                upload.records_task = Some((key, task));
                None
            }
        };
        if let Some(image) = finished {
            upload.records_task = None;
            let held = image.is_some();
            if let Some(image) = image {
                let image = assets.images.add(image);
                if let Some(mut material) = assets.materials.get_mut(&handle.0) {
                    material.records = image;
                }
                info!("preview: the lattice records uploaded (values and gradients from 8 texels)");
            }
            upload.records_done = Some((key, held));
        }
    }
    let wanted = upload.records_done == Some((key, true));
    keep_flag(&mut assets, &handle.0, FLAG_RECORDS, wanted);
}

/// Sets or clears `flag` in the material's uniform to `wanted`, touching the material (a new
/// bind group) only when it changes.
fn keep_flag(assets: &mut GpuAssets<'_>, handle: &Handle<VolumeMaterial>, flag: u32, wanted: bool) {
    let has = assets
        .materials
        .get(handle)
        .is_some_and(|m| m.uniform.flags & flag != 0);
    if wanted != has
        && let Some(mut material) = assets.materials.get_mut(handle)
    {
        material.uniform.flags ^= flag;
    }
}

/// Starts, takes in and uploads the cells' visibility, and keeps the material's flag for it
/// (its uniform is rewritten whenever the settings change) true exactly while the uploaded
/// cells are the current table's and Accumulate skips.
fn upload_visible_cells(
    state: Res<VolumeState>,
    render: Res<RenderState>,
    boxes: Query<&MeshMaterial3d<VolumeMaterial>, With<VolumeBox>>,
    preview: Option<Res<crate::sandbox::shared::quality::PreviewSettings>>,
    mut assets: GpuAssets,
    mut upload: ResMut<CellsUpload>,
) {
    let Ok(handle) = boxes.single() else { return };
    if state.is_changed() {
        // A new volume has a new material (and may sit where a freed one did).
        upload.done = None;
    }
    if state.is_changed() || render.is_changed() || upload.current.is_none() {
        // Whether Accumulate skips does not depend on the view direction.
        let scene = Scene::plain(
            &state.volume,
            &render.transfer,
            &render.settings,
            Vec3::NEG_Z,
        );
        upload.current = scene.ok().map(|s| (s.skips_empty(), s.lut));
    }
    if !gpu_backend(preview.as_deref()) {
        return; // the CPU live view draws (and computes its own cells)
    }
    let Some((skips, lut)) = upload.current.clone() else {
        return;
    };
    let key: CellsKey = (Arc::as_ptr(&state.volume) as usize, render.transfer.clone());
    if skips && upload.done.as_ref() != Some(&key) {
        let finished = match upload.task.as_mut() {
            Some((k, task)) if *k == key => check_ready(task),
            _ => {
                let volume = state.volume.clone();
                let task =
                    crate::sandbox::shared::tasks::spawn(async move { volume.empty_space(&lut) });
                upload.task = Some((key.clone(), task));
                None
            }
        };
        if let Some(space) = finished {
            let cells = &space.1;
            upload.task = None;
            info!(
                "preview: the cells' visibility uploaded ({} of the cells can be seen)",
                voxcast_core::numbers::percent(cells.visible_fraction())
            );
            let image = assets.images.add(visible_cells_image(Some(cells)));
            if let Some(mut material) = assets.materials.get_mut(&handle.0) {
                material.cells = image;
            }
            upload.done = Some(key.clone());
        }
    }
    let wanted = skips && upload.done.as_ref() == Some(&key);
    keep_flag(&mut assets, &handle.0, FLAG_SKIP_CELLS, wanted);
}
