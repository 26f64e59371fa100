//! Loading a volume without freezing the window: the file is read on Bevy's
//! `AsyncComputeTaskPool` while the sandbox keeps drawing the previous volume; the panel shows
//! what is loading and for how long, with Cancel. A finished load replaces the volume and picks
//! its preset (or a grey ramp); a failed one leaves everything as it was and says why. Files
//! dropped on the window load the same way. A volume the player loads keeps the method and
//! step they chose (the panel says so); a level's volume brings all its defaults.

use super::state::{RenderState, VolumeState};
use bevy::prelude::*;
use bevy::tasks::{AsyncComputeTaskPool, Task, futures::check_ready};
use bevy::window::FileDragAndDrop;
use std::sync::Arc;
use std::time::Instant;
use voxcast_core::builtin::load_source;
use voxcast_core::io::Loaded;
use voxcast_core::preset;
use voxcast_core::settings::RenderSettings;
use voxcast_core::transfer::TransferFunction;
use voxcast_core::volume::Volume;

/// The load under way, if any, and the last load's error.
#[derive(Resource, Default)]
pub struct Loading {
    job: Option<Job>,
    pub error: Option<String>,
    /// What the last load kept and what it changed, in words.
    pub note: Option<String>,
}

struct Job {
    source: String,
    /// Keep the player's method and step (a load from the panel or a dropped file).
    keep_choices: bool,
    started: Instant,
    task: Task<Result<Loaded, String>>,
}

impl Loading {
    /// Starts loading `source` (`builtin:NAME` or a path) with all its defaults (a level's
    /// volume); replaces a load under way.
    pub fn start(&mut self, source: String) {
        self.begin(source, false);
    }

    /// Starts loading a volume the player chose: their method and step are kept.
    pub fn start_keeping_choices(&mut self, source: String) {
        self.begin(source, true);
    }

    fn begin(&mut self, source: String, keep_choices: bool) {
        let spec = source.clone();
        let task = AsyncComputeTaskPool::get()
            .spawn(async move { load_source(&spec).map_err(|e| e.to_string()) });
        self.job = Some(Job {
            source,
            keep_choices,
            started: Instant::now(),
            task,
        });
        self.error = None;
        self.note = None;
    }

    /// Stops waiting for the load under way (the previous volume stays). A file already being
    /// read is finished in the background and dropped.
    pub fn cancel(&mut self) {
        self.job = None;
    }

    /// What is loading and for how many seconds.
    pub fn under_way(&self) -> Option<(&str, f32)> {
        self.job
            .as_ref()
            .map(|j| (j.source.as_str(), j.started.elapsed().as_secs_f32()))
    }
}

pub(crate) fn plugin(app: &mut App) {
    app.init_resource::<Loading>().add_systems(
        Update,
        (load_dropped_files, finish_loading)
            .chain()
            .in_set(super::Frame::Rules),
    );
}

fn load_dropped_files(mut drops: MessageReader<FileDragAndDrop>, mut loading: ResMut<Loading>) {
    for drop in drops.read() {
        if let FileDragAndDrop::DroppedFile { path_buf, .. } = drop {
            loading.start_keeping_choices(path_buf.display().to_string());
        }
    }
}

pub(crate) fn finish_loading(
    mut loading: ResMut<Loading>,
    mut volume: ResMut<VolumeState>,
    mut render: ResMut<RenderState>,
) {
    let Some(job) = loading.job.as_mut() else {
        return;
    };
    let Some(result) = check_ready(&mut job.task) else {
        return;
    };
    let source = job.source.clone();
    let keep = job.keep_choices;
    loading.job = None;
    match result {
        Ok(loaded) => {
            let (method, step) = (render.settings.method, render.settings.step);
            reset_to_defaults(&loaded.volume, &mut render);
            // A ray density brings Sum (its counts mean little to the other methods).
            let keep = keep && !voxcast_core::rays::as_volume::is_density(&loaded.volume);
            if keep {
                render.settings.method = method;
                render.settings.step = step;
                let voxel = loaded.volume.spacing().min_element();
                loading.note = Some(format!(
                    "Kept your method ({}) and step ({} voxel); the transfer function, shading \
                     and the other settings are the new volume's.",
                    method.name(),
                    voxcast_core::numbers::sig(step.voxels(voxel))
                ));
            }
            *volume = VolumeState {
                preset: preset::for_loaded(&loaded.volume),
                volume: Arc::new(loaded.volume),
                source,
            };
        }
        Err(e) => loading.error = Some(e),
    }
}

/// Gives `render` the transfer function (and settings, when it has a preset) `volume` starts
/// with: a newly loaded volume, or a level's.
pub fn reset_to_defaults(volume: &Volume, render: &mut RenderState) {
    let (transfer, settings) = defaults_for(volume);
    render.transfer = transfer;
    if let Some(s) = settings {
        render.settings = s;
    }
}

/// The transfer function (and settings, when it has a preset) `volume` starts with: its
/// preset's, or a grey ramp over its value range.
fn defaults_for(volume: &Volume) -> (TransferFunction, Option<RenderSettings>) {
    if let Some(p) = preset::for_loaded(volume)
        && let Ok(settings) = p.settings_over(&RenderSettings::default())
    {
        return (p.transfer, Some(settings));
    }
    let (lo, hi) = volume.value_range();
    let ramp = TransferFunction::ramp(lo, hi, 0.5)
        .or_else(|_| TransferFunction::constant([1.0; 3], 0.5))
        .expect("a constant transfer function is valid");
    (ramp, None)
}

#[cfg(test)]
mod tests {
    use super::*;
    use bevy::tasks::TaskPool;

    fn app() -> App {
        AsyncComputeTaskPool::get_or_init(TaskPool::new);
        let mut app = App::new();
        let loaded = voxcast_core::builtin::load_builtin("bucky").unwrap();
        let (transfer, settings) = defaults_for(&loaded.volume);
        app.insert_resource(VolumeState {
            volume: Arc::new(loaded.volume),
            source: "builtin:bucky".into(),
            preset: None,
        })
        .insert_resource(RenderState {
            transfer,
            settings: settings.unwrap_or_default(),
            depth_termination: true,
        })
        .add_message::<FileDragAndDrop>()
        .add_plugins(plugin);
        app
    }

    fn run_until_idle(app: &mut App) {
        for _ in 0..2000 {
            app.update();
            if app.world().resource::<Loading>().under_way().is_none() {
                return;
            }
            std::thread::sleep(std::time::Duration::from_millis(2));
        }
        panic!("the load never finished");
    }

    #[test]
    fn a_dropped_file_replaces_the_volume() {
        let dir = std::env::temp_dir().join(format!("voxcast-drop-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("tiny.nrrd");
        let mut bytes =
            b"NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n\n".to_vec();
        bytes.extend([0u8, 10, 20, 30, 40, 50, 60, 70]);
        std::fs::write(&path, bytes).unwrap();
        let mut app = app();
        app.world_mut().write_message(FileDragAndDrop::DroppedFile {
            window: Entity::PLACEHOLDER,
            path_buf: path.clone(),
        });
        run_until_idle(&mut app);
        let state = app.world().resource::<VolumeState>();
        assert_eq!(state.source, path.display().to_string());
        assert_eq!(state.volume.value_range(), (0.0, 70.0));
        let tf = &app.world().resource::<RenderState>().transfer;
        assert_eq!(
            tf.points().last().unwrap().value,
            70.0,
            "a ramp over the new range"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A volume the player loads keeps their method and step, and says so; a level's load
    /// brings every default of the volume.
    #[test]
    fn the_players_method_and_step_survive_a_load() {
        use voxcast_core::composite::Method;
        use voxcast_core::step::Length;
        for keep in [true, false] {
            let mut app = app();
            {
                let mut render = app.world_mut().resource_mut::<RenderState>();
                render.settings.method = Method::Maximum;
                render.settings.step = Length::Voxels(0.125);
            }
            let mut loading = app.world_mut().resource_mut::<Loading>();
            if keep {
                loading.start_keeping_choices("builtin:bunny".into());
            } else {
                loading.start("builtin:bunny".into());
            }
            run_until_idle(&mut app);
            let s = &app.world().resource::<RenderState>().settings;
            let note = app.world().resource::<Loading>().note.clone();
            if keep {
                assert_eq!((s.method, s.step), (Method::Maximum, Length::Voxels(0.125)));
                let note = note.expect("the panel says what was kept");
                assert!(note.contains("maximum") && note.contains("0.125"), "{note}");
            } else {
                assert_eq!(s.method, Method::Accumulate);
                assert!(note.is_none());
            }
        }
    }

    #[test]
    fn a_bad_file_keeps_the_volume_and_says_why() {
        let mut app = app();
        app.world_mut()
            .resource_mut::<Loading>()
            .start("/no/such/volume.nrrd".into());
        run_until_idle(&mut app);
        assert_eq!(
            app.world().resource::<VolumeState>().source,
            "builtin:bucky"
        );
        let error = app.world().resource::<Loading>().error.clone().unwrap();
        assert!(error.contains("/no/such/volume.nrrd"), "{error}");
    }

    #[test]
    fn cancel_keeps_the_volume() {
        let mut app = app();
        let mut loading = app.world_mut().resource_mut::<Loading>();
        loading.start("builtin:bunny".into());
        loading.cancel();
        app.update();
        assert!(app.world().resource::<Loading>().under_way().is_none());
        assert_eq!(
            app.world().resource::<VolumeState>().source,
            "builtin:bucky"
        );
    }
}
