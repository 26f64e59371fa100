//! The scene a mode sets up: the preview on or off (held by a study's run), a level's volume
//! with its default settings and preset, and the Ray data section afresh.

use super::*;

/// Sets up the scene of the mode just entered (or of a study's next run): the preview on or
/// off, and a level's volume with its default settings (so no objective is met before the
/// player acts). The virtual camera and the light marker are spawned by their own plugins from
/// the [`Stage`]. A study's run holds the preview on or off whatever the player does.
pub(super) fn set_up_scene(
    mode: Res<State<Mode>>,
    mut lessons: ResMut<Lessons>,
    stage: Res<Stage>,
    (volume, mut render): (Res<VolumeState>, ResMut<RenderState>),
    (mut loading, mut preview): (ResMut<Loading>, ResMut<PreviewSettings>),
    (ray_choices, inspect): (
        Option<ResMut<crate::sandbox::data::choices::RayChoices>>,
        Option<ResMut<crate::sandbox::inspect::rays::InspectSettings>>,
    ),
) {
    if let Some(run) = lessons.study
        && preview.enabled != run.preview()
    {
        preview.enabled = run.preview();
    }
    let again = std::mem::take(&mut lessons.set_up_again);
    if !mode.is_changed() && !again {
        return;
    }
    preview.enabled = lessons.study.map_or(stage.preview, StudyRun::preview);
    let Mode::Level(l) = *mode.get() else { return };
    // The Ray data section starts afresh too (no ray mesh left over from another level).
    if let Some(mut c) = ray_choices {
        *c = default();
    }
    // So do the skip blocks a level may have turned on.
    if let Some(mut i) = inspect
        && i.show_blocks
    {
        i.show_blocks = false;
    }
    let Some(level) = lessons.levels.get(l) else {
        return;
    };
    if let Some(scale) = level.scene.preview_scale {
        preview.scale = scale;
    }
    // The preview shows the picture: a cost view a level before asked for is not this one's.
    preview.cost_view = None;
    if level.scene.volume != volume.source {
        // The load brings the volume's defaults with it.
        loading.start(level.scene.volume.clone());
    } else {
        loading.cancel();
        reset_to_defaults(&volume.volume, &mut render);
        apply_level_preset(&level.scene, &mut render);
    }
}

/// The level's own preset over its volume's defaults, where its scene names one, and the
/// lecture's ray's settings where it shoots that ray.
pub(super) fn apply_level_preset(
    scene: &voxcast_core::level::LevelScene,
    render: &mut RenderState,
) {
    if let Some(p) = scene
        .preset
        .as_deref()
        .and_then(voxcast_core::preset::by_name)
    {
        render.transfer = p.transfer.clone();
        if let Ok(s) = p.settings_over(&render.settings) {
            render.settings = s;
        }
    }
    if scene.lecture_ray {
        render.settings = voxcast_core::worked::lecture_ray_settings(&render.settings);
    }
}

/// A level's volume that has just loaded (with its defaults): the level's preset over them.
pub(super) fn level_preset_after_load(
    mode: Res<State<Mode>>,
    lessons: Res<Lessons>,
    volume: Res<VolumeState>,
    mut render: ResMut<RenderState>,
) {
    if !volume.is_changed() || volume.is_added() {
        return;
    }
    let Mode::Level(l) = *mode.get() else { return };
    if let Some(level) = lessons.levels.get(l)
        && level.scene.volume == volume.source
    {
        apply_level_preset(&level.scene, &mut render);
    }
}
