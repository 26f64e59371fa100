//! The scene a mode sets up: the preview on or off (held by a study's run), the Ray data
//! section afresh, and what a level (or a step that sets its own) puts on screen — its data
//! set, transfer function, settings, the main and the virtual camera, the selected ray —
//! applied once its data set has loaded and the new volume has been framed.

use super::*;
use crate::sandbox::scene::orbit::Orbit;
use crate::sandbox::shared::mode::Staged;
use crate::sandbox::shared::render_change::{Author, PreviewChanges, RenderChanges};
use voxcast_core::level::{StepScene, TransferChoice};

/// A level's or a step's scene waiting to be put on screen.
#[derive(Clone, Debug, PartialEq)]
pub struct Pending {
    pub scene: StepScene,
    /// The level's own scene: the data set's defaults first, then the level's preset.
    pub fresh: bool,
    /// Its data set's load was asked for.
    pub asked: bool,
}

impl Pending {
    pub fn of_level(level: &voxcast_core::level::Level) -> Self {
        Self {
            scene: level.scene.snapshot(),
            fresh: true,
            asked: false,
        }
    }

    pub fn of_step(scene: &StepScene) -> Self {
        Self {
            scene: scene.clone(),
            fresh: false,
            asked: false,
        }
    }
}

/// Sets up the scene of the mode just entered (or of a study's next run): the preview on or
/// off, and a level's own scene waiting to be opened ([`open_scene`]). The virtual camera and
/// the light marker are spawned by their own plugins from the [`Stage`]. A study's run holds
/// the preview on or off whatever the player does.
pub(super) fn set_up_scene(
    staged: Staged,
    mut lessons: ResMut<Lessons>,
    volume: Res<VolumeState>,
    mut loading: ResMut<Loading>,
    mut preview: PreviewChanges,
    ray_choices: Option<ResMut<crate::sandbox::data::choices::RayChoices>>,
    inspect: Option<ResMut<crate::sandbox::inspect::rays::InspectSettings>>,
) {
    let (mode, stage) = (&staged.mode, &staged.stage);
    // The level's preview on a copy of the settings, sent as one change once set up.
    let Some(mut next) = preview.now.as_deref().cloned() else {
        return;
    };
    'set_up: {
        if let Some(run) = lessons.study {
            next.enabled = run.preview();
        }
        let again = std::mem::take(&mut lessons.set_up_again);
        if !mode.is_changed() && !again {
            break 'set_up;
        }
        next.enabled = lessons.study.map_or(stage.preview, StudyRun::preview);
        lessons.pending = None;
        let Mode::Level(l) = *mode.get() else {
            break 'set_up;
        };
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
            break 'set_up;
        };
        if let Some(scale) = level.scene.preview_scale {
            next.scale = scale;
        }
        // The preview shows the picture: a cost view a level before asked for is not this
        // one's.
        next.cost_view = None;
        if level.volume_source() == volume.source {
            // Nothing to load: a load the player started before is not this level's.
            loading.cancel();
        }
        lessons.pending = Some(Pending::of_level(level));
    }
    preview.edited(Author::Level, next);
}

/// Where a level's scene puts its cameras and selected ray.
#[derive(bevy::ecs::system::SystemParam)]
pub(super) struct SceneCameras<'w, 's> {
    main: Query<
        'w,
        's,
        (
            &'static mut Orbit,
            &'static mut Transform,
            &'static mut View,
        ),
        With<MainCamera>,
    >,
    cameras: Query<'w, 's, &'static mut VirtualCamera>,
    selection: ResMut<'w, RaySelection>,
}

/// Puts the waiting scene on screen: its data set loaded first (the load brings the data set's
/// defaults), then — a frame after the volume or the mode changed, once the new volume is
/// framed and the virtual camera spawned — its transfer function, settings, cameras and ray.
/// A data set that cannot be loaded is said in the level's message and the rest is opened
/// over the volume on screen.
pub(super) fn open_scene(
    staged: Staged,
    mut lessons: ResMut<Lessons>,
    volume: Res<VolumeState>,
    mut render: RenderChanges,
    mut loading: ResMut<Loading>,
    held: Res<super::files::LevelFiles>,
    mut cams: SceneCameras,
) {
    let Some(pending) = lessons.pending.clone() else {
        return;
    };
    let level = match *staged.mode.get() {
        Mode::Level(l) => lessons.levels.get(l).cloned(),
        Mode::FreePlay => None,
    };
    let Some(level) = level else {
        lessons.pending = None;
        return;
    };
    if !volume_ready(&mut lessons, &pending, &level, &volume, &mut loading, &held) {
        return;
    }
    // The new volume (or mode) is framed this frame: place the cameras over it next frame.
    let camera_missing = staged.stage.rays.is_some() && cams.cameras.is_empty();
    if volume.is_changed() || staged.mode.is_changed() || camera_missing {
        return;
    }
    let next = scene_settings(&pending, &level, &render.now, &volume, &mut lessons.message);
    render.edited(Author::Level, next);
    cams.place(&pending.scene);
    // After the level's own scene, the scene of the step it starts at (its first, or the one
    // the editor's Play chose), if that step sets one.
    lessons.pending = if pending.fresh {
        level
            .steps
            .get(lessons.step)
            .and_then(|s| s.scene.as_ref())
            .map(Pending::of_step)
    } else {
        None
    };
}

/// Whether the volume on screen is the one the waiting scene asks for (or it asks for none).
/// If not, its load is started, once; a load that failed is said in the level's message and
/// the scene goes on without its data set.
fn volume_ready(
    lessons: &mut Lessons,
    pending: &Pending,
    level: &voxcast_core::level::Level,
    volume: &VolumeState,
    loading: &mut Loading,
    held: &super::files::LevelFiles,
) -> bool {
    let Some(name) = &pending.scene.volume else {
        return true;
    };
    let source = level.resolve(name);
    if volume.source == source {
        return true;
    }
    match loading.under_way() {
        Some((loading_now, _)) if loading_now == source => {}
        _ if !pending.asked => {
            start_loading(loading, source, held);
            if let Some(p) = lessons.pending.as_mut() {
                p.asked = true;
            }
        }
        Some(_) => {}
        None => {
            let why = loading.error.clone().unwrap_or_default();
            lessons.message = Some(format!(
                "This level's data set {source} could not be loaded ({why}); the level goes on \
                 with the volume on screen."
            ));
            if let Some(p) = lessons.pending.as_mut() {
                p.scene.volume = None;
            }
        }
    }
    false
}

/// The render state the waiting scene asks for, over `now` (over the data set's defaults and
/// the level's preset where the level starts afresh); what cannot be used is said in
/// `message`.
fn scene_settings(
    pending: &Pending,
    level: &voxcast_core::level::Level,
    now: &RenderState,
    volume: &VolumeState,
    message: &mut Option<String>,
) -> RenderState {
    let mut next = now.clone();
    if pending.fresh {
        reset_to_defaults(&volume.volume, &mut next);
        level
            .scene
            .over_defaults(&mut next.transfer, &mut next.settings);
    }
    let scene = &pending.scene;
    if let Some(choice) = &scene.transfer {
        match transfer_of(choice) {
            Some(t) => next.transfer = t,
            None => {
                *message = Some(format!(
                    "This level's transfer function {choice:?} is unknown"
                ))
            }
        }
    }
    if let Some(changes) = &scene.settings {
        match voxcast_core::preset::settings_written_over(&next.settings, changes) {
            Ok(s) => next.settings = s,
            Err(e) => *message = Some(format!("This level's settings are refused: {e}")),
        }
    }
    next
}

impl SceneCameras<'_, '_> {
    /// Places the main and the virtual camera where `scene` says, and selects its ray.
    fn place(&mut self, scene: &StepScene) {
        if let Some(place) = scene.camera
            && let Ok((mut orbit, mut transform, mut view)) = self.main.single_mut()
            && let Ok(camera) = camera_at(&place, &view.0)
        {
            *orbit = Orbit::looking_at(camera.eye, camera.target, camera.up);
            *transform = orbit.transform();
            view.0 = camera;
        }
        if let Some(place) = scene.virtual_camera
            && let Ok(mut vc) = self.cameras.single_mut()
        {
            if let Ok(camera) = camera_at(&place, &vc.view) {
                vc.view = camera;
            }
            if let Some([w, h]) = place.pixels {
                (vc.width, vc.height) = (w, h);
            }
        }
        if let Some([x, y]) = scene.ray {
            self.selection.selected = Some(UVec2::new(x, y));
        }
    }
}

/// Starts loading a level's data set: from the files handed with the level where it is one
/// of them (the page), else by its name (a builtin, a path).
fn start_loading(loading: &mut Loading, source: String, held: &super::files::LevelFiles) {
    if !held.holds(&source) {
        loading.start(source);
        return;
    }
    let files = held.in_memory();
    let path = std::path::PathBuf::from(source.rsplit(['/', '\\']).next().unwrap_or(&source));
    loading.run(source, false, move |_, _| {
        voxcast_core::io::load_from(&files, &path)
            .map(|loaded| crate::sandbox::data::source::Outcome { loaded, rays: None })
            .map_err(|e| e.to_string())
    });
}

/// The camera `place` puts down, with the field of view of `now` unless it gives one.
fn camera_at(
    place: &voxcast_core::level::CameraPlace,
    now: &voxcast_core::camera::Camera,
) -> Result<voxcast_core::camera::Camera, voxcast_core::SettingsError> {
    use voxcast_core::camera::{Camera, Projection};
    let projection = match (place.fov_y_deg, now.projection) {
        (Some(fov_y_deg), _) => Projection::Perspective { fov_y_deg },
        (None, p) => p,
    };
    Camera::new(
        Vec3::from(place.eye),
        Vec3::from(place.target),
        Vec3::from(place.up),
        projection,
    )
}

/// The transfer function `choice` names: written out, or a preset's (a file was read into the
/// level when it was loaded).
fn transfer_of(choice: &TransferChoice) -> Option<voxcast_core::transfer::TransferFunction> {
    match choice {
        TransferChoice::Inline(t) => Some(t.clone()),
        TransferChoice::Named(name) => voxcast_core::preset::by_name(name).map(|p| p.transfer),
    }
}
