//! Loading a volume without freezing the window: the file is read on Bevy's
//! `AsyncComputeTaskPool` while the sandbox keeps drawing the previous volume; the panel shows
//! what is loading and for how long, with Cancel. A finished load replaces the volume and picks
//! its preset (or a grey ramp); a failed one leaves everything as it was and says why. Files
//! dropped on the window load the same way. A volume the player loads keeps the method and
//! step they chose (the panel says so); a level's volume brings all its defaults.
//!
//! A ray density (`density:…`, or the virtual camera's rays) is computed the same way, with
//! progress, and Cancel stops the computation itself; what it was computed from (the data
//! set, its rays, the sparse grid) goes to [`crate::sandbox::data::source::RayScene`] for RayVis's views.

use crate::sandbox::data::source::{Before, Outcome, RayScene};
use crate::sandbox::shared::files::{FilesChosen, Purpose, volume_entry};
use crate::sandbox::shared::render_change::{Author, RenderChanges};
use crate::sandbox::shared::state::{RenderState, VolumeState};
use bevy::platform::time::Instant;
use bevy::prelude::*;
use bevy::tasks::{Task, futures::check_ready};
use bevy::window::FileDragAndDrop;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use voxcast_core::builtin::load_source;
use voxcast_core::preset;
use voxcast_core::settings::RenderSettings;
use voxcast_core::transfer::TransferFunction;
use voxcast_core::volume::Volume;

/// The most bytes of voxel data a volume opened in a web page may take: 256 MB, a 512³ volume
/// of 16-bit values. Measured in chromium 156 (BENCHMARKS, "Large files on the page"): that
/// volume took the page's memory from 210 MB to 1.5 GB (the file read, its voxels, the GPU's
/// copy at 4 bytes a voxel), and a 512 MB one loaded (2.7 GB) but its 1 GB GPU copy made
/// WebGL2 lose its context, which leaves the page blank. A larger volume is refused in words
/// that give this limit, before it is read where the file's size already says so.
pub const PAGE_VOXEL_LIMIT: u64 = 256 << 20;

/// Why a volume file of `bytes` is refused on the page before it is read, if it is: a file
/// larger than the page's limit by more than a header's megabyte and gzip's framing cannot
/// hold less voxel data than the limit.
#[cfg_attr(not(target_arch = "wasm32"), allow(dead_code))] // the page's; tested here
pub fn refused_on_page(name: &str, bytes: u64) -> Option<String> {
    let most = PAGE_VOXEL_LIMIT + PAGE_VOXEL_LIMIT / 256 + (1 << 20);
    (bytes > most).then(|| {
        format!(
            "{name}: the file takes {}, more than the {} of voxel data this page can hold; \
             {DESKTOP_OPENS}",
            voxcast_core::numbers::bytes(bytes),
            voxcast_core::numbers::bytes(PAGE_VOXEL_LIMIT)
        )
    })
}

const DESKTOP_OPENS: &str = "Voxcast's desktop app opens larger volumes.";

/// The voxel data files held in memory may hold: [`PAGE_VOXEL_LIMIT`] in a page.
const IN_MEMORY_LIMIT: Option<u64> = if cfg!(target_arch = "wasm32") {
    Some(PAGE_VOXEL_LIMIT)
} else {
    None
};

/// Reads a volume from files held in memory (what a browser hands the page), starting at
/// `entry`, with no more than `limit` of voxel data.
fn load_in_memory(
    files: Vec<(String, Vec<u8>)>,
    entry: &str,
    limit: Option<u64>,
) -> Result<Outcome, String> {
    let mut files = voxcast_core::io::InMemory::new(files);
    files.limit = limit;
    voxcast_core::io::load_from(&files, std::path::Path::new(entry))
        .map(|loaded| Outcome { loaded, rays: None })
        .map_err(|e| match e.problem {
            voxcast_core::error::LoadProblem::OverLimit { .. } => format!("{e}; {DESKTOP_OPENS}"),
            _ => e.to_string(),
        })
}

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
    progress: Arc<Progress>,
    cancel: Arc<AtomicBool>,
    task: Task<Result<Outcome, String>>,
}

/// How far a load has come, in whatever units it counts (rays for a density); `total` 0: it
/// does not say.
#[derive(Default)]
pub struct Progress {
    done: AtomicUsize,
    total: AtomicUsize,
}

impl Progress {
    /// Records `done` of `total`.
    pub fn set(&self, done: usize, total: usize) {
        self.total.store(total, Ordering::Relaxed);
        self.done.store(done, Ordering::Relaxed);
    }

    /// The share done, when it is known.
    pub fn fraction(&self) -> Option<f32> {
        let total = self.total.load(Ordering::Relaxed);
        (total > 0).then(|| self.done.load(Ordering::Relaxed) as f32 / total as f32)
    }
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
        self.run_async(source, keep_choices, move |progress, cancel| async move {
            let report = |done, total| progress.set(done, total);
            // A density is computed in slices (a page's frames go on between them).
            match crate::sandbox::data::source::compute_source_in_slices(&spec, &report, &cancel)
                .await
            {
                Some(outcome) => outcome,
                None => {
                    // A page fetches a real dataset's file the first time it is opened.
                    #[cfg(target_arch = "wasm32")]
                    crate::sandbox::shared::web::fetch_dataset(&spec).await?;
                    load_source(&spec)
                        .map(|loaded| Outcome { loaded, rays: None })
                        .map_err(|e| e.to_string())
                }
            }
        });
    }

    /// Starts `work` (on the background pool) as the load of `label`: its progress shown, its
    /// cancel flag set by Cancel. Replaces a load under way (which is told to stop).
    pub fn run(
        &mut self,
        label: String,
        keep_choices: bool,
        work: impl FnOnce(&Progress, &AtomicBool) -> Result<Outcome, String> + Send + 'static,
    ) {
        self.run_async(label, keep_choices, move |p, c| async move { work(&p, &c) });
    }

    /// [`Loading::run`] for work that yields to the page between slices (`crate::sandbox::shared::tasks`).
    pub fn run_async<F>(
        &mut self,
        label: String,
        keep_choices: bool,
        work: impl FnOnce(Arc<Progress>, Arc<AtomicBool>) -> F,
    ) where
        F: bevy::tasks::ConditionalSendFuture<Output = Result<Outcome, String>> + 'static,
    {
        self.cancel();
        let progress = Arc::new(Progress::default());
        let cancel = Arc::new(AtomicBool::new(false));
        let task = crate::sandbox::shared::tasks::spawn(work(progress.clone(), cancel.clone()));
        self.job = Some(Job {
            source: label,
            keep_choices,
            started: Instant::now(),
            progress,
            cancel,
            task,
        });
        self.error = None;
        self.note = None;
    }

    /// Stops the load under way (the previous volume stays): a density's computation stops at
    /// its next block of rays; a file already being read is finished in the background and
    /// dropped.
    pub fn cancel(&mut self) {
        if let Some(job) = self.job.take() {
            job.cancel.store(true, Ordering::Relaxed);
        }
    }

    /// What is loading and for how many seconds.
    pub fn under_way(&self) -> Option<(&str, f32)> {
        self.job
            .as_ref()
            .map(|j| (j.source.as_str(), j.started.elapsed().as_secs_f32()))
    }

    /// The share of the load under way that is done, when it says.
    pub fn fraction(&self) -> Option<f32> {
        self.job.as_ref().and_then(|j| j.progress.fraction())
    }
}

pub(crate) fn plugin(app: &mut App) {
    app.init_resource::<Loading>()
        .init_resource::<RayScene>()
        .add_message::<FilesChosen>()
        .add_systems(
            Update,
            (
                (load_dropped_files, load_chosen_files)
                    .chain()
                    .in_set(crate::sandbox::shared::schedule::Frame::Input),
                #[cfg(target_arch = "wasm32")]
                load_handed_volumes.in_set(crate::sandbox::shared::schedule::Frame::Input),
                finish_loading.in_set(crate::sandbox::shared::schedule::Frame::SwapVolume),
            ),
        );
}

/// A volume dropped on the window loads; level files (.json) and answer files (.csv) are the
/// levels' to read.
fn load_dropped_files(mut drops: MessageReader<FileDragAndDrop>, mut loading: ResMut<Loading>) {
    for drop in drops.read() {
        if let FileDragAndDrop::DroppedFile { path_buf, .. } = drop {
            let name = path_buf.display().to_string();
            let lower = name.to_ascii_lowercase();
            if !(lower.ends_with(".json") || lower.ends_with(".csv")) {
                loading.start_keeping_choices(name);
            }
        }
    }
}

/// Volumes a browser handed the page (picked or dropped): read from memory, as a file on disk
/// is read, with the same errors.
fn load_chosen_files(mut chosen: MessageReader<FilesChosen>, mut loading: ResMut<Loading>) {
    for FilesChosen { purpose, files } in chosen.read() {
        if *purpose != Purpose::Volume {
            continue;
        }
        let Some(entry) = volume_entry(files.iter().map(|(n, _)| n.as_str())).map(str::to_owned)
        else {
            continue;
        };
        let files = files.clone();
        loading.run(entry.clone(), true, move |_, _| {
            load_in_memory(files, &entry, IN_MEMORY_LIMIT)
        });
    }
}

/// Volume files a page handed over as the browser's handles: refused at once where a file is
/// larger than the page can hold (the volume shown stays); else read piece by piece, the
/// share read shown and Cancel heard between pieces, then read as a volume.
#[cfg(target_arch = "wasm32")]
fn load_handed_volumes(
    mut handed: MessageReader<crate::sandbox::shared::web::VolumeHanded>,
    mut loading: ResMut<Loading>,
) {
    use crate::sandbox::shared::web::{read_file, take_volume_files};
    for volume in handed.read() {
        let handles = take_volume_files(volume.id);
        let refused = volume
            .files
            .iter()
            .find_map(|(name, bytes)| refused_on_page(name, *bytes));
        if let Some(refused) = refused {
            loading.error = Some(refused);
            continue;
        }
        let Some(entry) = volume_entry(volume.files.iter().map(|(n, _)| n.as_str())) else {
            continue;
        };
        let entry = entry.to_owned();
        let sizes = volume.files.clone();
        loading.run_async(entry.clone(), true, move |progress, cancel| async move {
            // Progress counts kilobytes: a page's `usize` holds only 4 GB of bytes.
            let total = sizes.iter().map(|(_, b)| b).sum::<u64>();
            let share =
                |done: u64| progress.set((done >> 10) as usize, (total >> 10).max(1) as usize);
            let mut done = 0;
            let mut files = Vec::new();
            for ((name, bytes), handle) in sizes.iter().zip(&handles) {
                let read = read_file(handle, |n| share(done + n), &cancel)
                    .await
                    .map_err(|e| format!("{name}: {e}"))?;
                let Some(read) = read else {
                    return Err("cancelled".into());
                };
                done += bytes;
                files.push((name.clone(), read));
            }
            // The share read says nothing of the reading that follows: the spinner alone.
            progress.set(0, 0);
            crate::sandbox::shared::tasks::yield_to_page().await;
            load_in_memory(files, &entry, IN_MEMORY_LIMIT)
        });
    }
}

pub(crate) fn finish_loading(
    mut loading: ResMut<Loading>,
    mut volume: ResMut<VolumeState>,
    mut render: RenderChanges,
    mut rays: ResMut<RayScene>,
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
        Ok(Outcome {
            loaded,
            rays: computed,
        }) => {
            let before = Before {
                volume: volume.clone(),
                render: render.now.clone(),
                camera: None,
            };
            let (method, step) = (render.now.settings.method, render.now.settings.step);
            let mut next = render.now.clone();
            reset_to_defaults(&loaded.volume, &mut next);
            // A ray density brings Sum (its counts mean little to the other methods).
            let keep = keep && !voxcast_core::rays::as_volume::is_density(&loaded.volume);
            if keep {
                next.settings.method = method;
                next.settings.step = step;
                let voxel = loaded.volume.spacing().min_element();
                loading.note = Some(format!(
                    "Kept your method ({}) and step ({} voxel); the transfer function, shading \
                     and the other settings are the new volume's.",
                    method.title(),
                    voxcast_core::numbers::sig(step.voxels(voxel))
                ));
            }
            render.edited(Author::Loading, next);
            *volume = VolumeState {
                preset: preset::for_loaded(&loaded.volume),
                volume: Arc::new(loaded.volume.into()),
                source,
            };
            rays.shown(computed, &volume, before);
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
    let (transfer, settings) = preset::defaults_for(volume);
    (transfer, preset::for_loaded(volume).map(|_| settings))
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use bevy::tasks::{AsyncComputeTaskPool, TaskPool};

    pub(crate) fn app() -> App {
        AsyncComputeTaskPool::get_or_init(TaskPool::new);
        let mut app = App::new();
        let loaded = voxcast_core::builtin::load_builtin("bucky").unwrap();
        let (transfer, settings) = defaults_for(&loaded.volume);
        app.insert_resource(VolumeState {
            volume: Arc::new(loaded.volume.into()),
            source: "builtin:bucky".into(),
            preset: None,
        })
        .insert_resource(RenderState {
            transfer,
            settings: settings.unwrap_or_default(),
            depth_termination: true,
        })
        .add_message::<FileDragAndDrop>()
        .add_plugins((plugin, crate::sandbox::shared::render_change::plugin));
        crate::sandbox::shared::schedule::configure(&mut app);
        app
    }

    pub(crate) fn run_until_idle(app: &mut App) {
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

    /// Files a browser hands over load from memory: a damaged one says what the desktop says
    /// of it and leaves the volume; a good one with its detached header replaces it.
    #[test]
    fn chosen_files_load_from_memory() {
        let mut app = app();
        let before = app.world().resource::<VolumeState>().volume.value_range();
        let header = b"NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n".to_vec();
        let mut damaged = header.clone();
        damaged.extend(b"\n\x01\x02");
        app.world_mut().write_message(FilesChosen {
            purpose: Purpose::Volume,
            files: vec![("damaged.nrrd".into(), damaged)],
        });
        run_until_idle(&mut app);
        let error = app.world().resource::<Loading>().error.clone().unwrap();
        assert!(error.starts_with("damaged.nrrd"), "{error}");
        assert_eq!(
            app.world().resource::<VolumeState>().volume.value_range(),
            before
        );

        let mut detached = header;
        detached.extend(b"data file: d.raw\n\n");
        app.world_mut().write_message(FilesChosen {
            purpose: Purpose::Volume,
            files: vec![
                ("d.raw".into(), (0..8).map(|i| i * 10).collect()),
                ("h.nhdr".into(), detached),
            ],
        });
        run_until_idle(&mut app);
        let state = app.world().resource::<VolumeState>();
        assert_eq!(state.source, "h.nhdr");
        assert_eq!(state.volume.value_range(), (0.0, 70.0));
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
                assert!(note.contains("Maximum") && note.contains("0.125"), "{note}");
            } else {
                assert_eq!(s.method, Method::Accumulate);
                assert!(note.is_none());
            }
        }
    }

    /// A page refuses a file larger than it can hold before reading it, and a header asking
    /// for more voxel data than it holds after reading only the header; both say the limit and
    /// where the volume opens instead.
    #[test]
    fn the_page_refuses_what_it_cannot_hold_in_words() {
        assert_eq!(refused_on_page("ct.nrrd", 256 << 20), None);
        assert_eq!(refused_on_page("big.nii", (256 << 20) + (1 << 20)), None);
        assert_eq!(
            refused_on_page("huge.raw", 3 << 29).as_deref(),
            Some(
                "huge.raw: the file takes 1.5 GB, more than the 256 MB of voxel data this page \
                 can hold; Voxcast's desktop app opens larger volumes."
            )
        );
        let mut header =
            b"NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n\n".to_vec();
        header.extend([0u8; 8]);
        let files = vec![("small.nrrd".to_string(), header)];
        assert!(load_in_memory(files.clone(), "small.nrrd", Some(8)).is_ok());
        let Err(words) = load_in_memory(files, "small.nrrd", Some(7)) else {
            panic!("8 bytes of voxels over a limit of 7 were read");
        };
        assert_eq!(
            words,
            "small.nrrd: its voxel data takes 8 bytes, more than the 7 bytes that can be opened \
             here; Voxcast's desktop app opens larger volumes."
        );
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

    /// A ray density keeps what it came from (while it is on show) and the volume before it;
    /// loading another volume forgets both.
    #[test]
    fn a_density_keeps_its_rays_until_another_volume_comes() {
        let mut app = app();
        app.world_mut()
            .resource_mut::<Loading>()
            .start("density:builtin:cornell@cell=40,trace=1".into());
        run_until_idle(&mut app);
        let world = app.world();
        let volume = world.resource::<VolumeState>();
        let rays = world.resource::<RayScene>();
        assert!(world.resource::<Loading>().error.is_none());
        let shown = rays.on_show(volume).expect("the density's rays are kept");
        assert_eq!(shown.computed.set.trace_id, 1);
        assert_eq!(shown.computed.density.params.cell, 40.0);
        assert_eq!(shown.computed.data.scene.meshes.len(), 5);
        let before = rays.before.as_ref().expect("the volume before it is kept");
        assert_eq!(before.volume.source, "builtin:bucky");
        app.world_mut()
            .resource_mut::<Loading>()
            .start("builtin:bunny".into());
        run_until_idle(&mut app);
        let rays = app.world().resource::<RayScene>();
        assert!(rays.current.is_none() && rays.before.is_none());
    }

    /// Cancel stops a density's computation itself: its flag is set, and nothing arrives.
    #[test]
    fn cancel_stops_a_density() {
        let mut app = app();
        let flag = Arc::new(AtomicBool::new(false));
        let started = Arc::new(AtomicBool::new(false));
        let (seen, running) = (flag.clone(), started.clone());
        let mut loading = app.world_mut().resource_mut::<Loading>();
        loading.run("slow".into(), false, move |_, cancel| {
            running.store(true, Ordering::Relaxed);
            while !cancel.load(Ordering::Relaxed) {
                std::thread::sleep(std::time::Duration::from_millis(1));
            }
            seen.store(true, Ordering::Relaxed);
            Err("cancelled".into())
        });
        // Under way (a task not yet started is simply never run).
        while !started.load(Ordering::Relaxed) {
            std::thread::sleep(std::time::Duration::from_millis(1));
        }
        loading.cancel();
        for _ in 0..2000 {
            if flag.load(Ordering::Relaxed) {
                break;
            }
            std::thread::sleep(std::time::Duration::from_millis(2));
        }
        assert!(flag.load(Ordering::Relaxed), "the work saw the cancel");
        app.update();
        assert_eq!(
            app.world().resource::<VolumeState>().source,
            "builtin:bucky"
        );
        assert!(app.world().resource::<Loading>().error.is_none());
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

    /// A volume that finishes loading is framed beside the main camera as the main camera is
    /// framed for it, whatever order the plugins were added in: framed in a frame before the
    /// main camera's reframing, the virtual camera sat at the edge of the view (level 1 after
    /// a larger volume).
    #[test]
    fn a_loaded_volume_puts_the_virtual_camera_beside_the_reframed_main_camera() {
        use crate::sandbox::shared::state::{MainCamera, View};
        use bevy::input::mouse::{AccumulatedMouseMotion, AccumulatedMouseScroll};
        AsyncComputeTaskPool::get_or_init(TaskPool::new);
        type Plugin = fn(&mut App);
        let plugins: [Plugin; 3] = [
            plugin,
            crate::sandbox::scene::orbit::plugin,
            crate::sandbox::inspect::virtual_camera::plugin,
        ];
        for order in [[0, 1, 2], [2, 1, 0], [1, 2, 0], [2, 0, 1]] {
            let (volume, render) = crate::sandbox::inspect::rays::tests::scene("bunny");
            let (lo, hi) = volume.volume.bounds();
            let main =
                voxcast_core::camera::Camera::framing(lo, hi, Vec3::new(1.0, 0.3, 2.0), Vec3::Y)
                    .unwrap();
            let mut app = App::new();
            app.add_plugins((MinimalPlugins, bevy::state::app::StatesPlugin))
                .insert_resource(volume)
                .insert_resource(render)
                .init_resource::<Assets<Mesh>>()
                .init_resource::<Assets<StandardMaterial>>()
                .init_resource::<ButtonInput<MouseButton>>()
                .init_resource::<AccumulatedMouseMotion>()
                .init_resource::<AccumulatedMouseScroll>()
                .init_resource::<crate::sandbox::scene::overlay::OverlayLines>()
                .add_message::<bevy::window::FileDragAndDrop>();
            crate::sandbox::shared::schedule::configure(&mut app);
            app.add_plugins((
                crate::sandbox::shared::mode::plugin,
                crate::sandbox::shared::render_change::plugin,
            ));
            for i in order {
                plugins[i](&mut app);
            }
            app.world_mut().spawn((
                MainCamera,
                View(main),
                crate::sandbox::scene::orbit::Orbit::looking_at(main.eye, main.target, main.up),
                Transform::default(),
            ));
            app.update();
            app.update();
            app.world_mut()
                .resource_mut::<Loading>()
                .start("builtin:voxel".into());
            for _ in 0..500 {
                app.update();
                if app.world().resource::<VolumeState>().source == "builtin:voxel" {
                    break;
                }
                std::thread::sleep(std::time::Duration::from_millis(2));
            }
            app.update();
            let volume = app.world().resource::<VolumeState>();
            assert_eq!(volume.source, "builtin:voxel");
            let mut q = app.world_mut().query_filtered::<&View, With<MainCamera>>();
            let main = q.single(app.world()).unwrap().0;
            let volume = app.world().resource::<VolumeState>();
            let want = crate::sandbox::inspect::virtual_camera::VirtualCamera::framing(
                volume,
                Some(&main),
            )
            .unwrap()
            .view;
            let mut q = app
                .world_mut()
                .query::<&crate::sandbox::inspect::virtual_camera::VirtualCamera>();
            let got = q.single(app.world()).unwrap().view;
            assert!(
                got.eye.distance(want.eye) < 1e-4 && got.target.distance(want.target) < 1e-4,
                "plugins in order {order:?}: virtual camera at {:?}, beside the main camera \
                 is {:?}",
                got.eye,
                want.eye
            );
        }
    }
}
