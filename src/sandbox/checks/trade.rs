//! Measuring a knob's trade in the sandbox: the main camera's view rendered by the core at the
//! knob's settings (the step's: the sampling level's steps and the player's own) against its
//! exact reference (`voxcast_core::trade`), on the `AsyncComputeTaskPool` with progress and
//! Cancel. A preview's knob is then timed as the preview's own images in the window
//! (`frame_trade`), its errors staying the core's. A result remembers what it measured, so the
//! panel can say when it no longer matches.

use crate::sandbox::checks::frame_trade::{
    Drawing, Ended, FrameRun, FrameTiming, PreviewTry, drive, preview_tries, stand_in,
};
use crate::sandbox::shared::quality::PreviewSettings;
use crate::sandbox::shared::state::{MainCamera, RenderState, View, VolumeState};
use crate::sandbox::shared::tasks::in_slices;
use bevy::prelude::*;
use bevy::tasks::{Task, futures::check_ready};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use voxcast_core::camera::Camera as CoreCamera;
use voxcast_core::knob::Knob;
use voxcast_core::settings::RenderSettings;
use voxcast_core::step::Length;
use voxcast_core::trade::{
    STEPS, Trade, TradeError, TradeJob, TradeSlices, View as TradeView, trade_in,
};

pub use crate::sandbox::checks::frame_trade::TRADE_SIZE;

/// What a trade measured: the view, the settings but their step, the transfer function and
/// the volume.
#[derive(Clone, PartialEq)]
pub struct TradeKey {
    camera: CoreCamera,
    settings: RenderSettings,
    transfer: voxcast_core::transfer::TransferFunction,
    source: String,
}

impl TradeKey {
    fn of(camera: CoreCamera, render: &RenderState, volume: &VolumeState) -> Self {
        let mut settings = render.settings.clone();
        settings.step = Length::Voxels(0.0);
        Self {
            camera,
            settings,
            transfer: render.transfer.clone(),
            source: volume.source.clone(),
        }
    }
}

/// The measurement under way and the last result.
#[derive(Resource, Default)]
pub struct StepTrade {
    /// The knob Measure measures (the step unless the player picks another).
    pub knob: Knob,
    job: Option<Job>,
    /// The core's trade of a preview's knob, waiting for the preview's images to be timed.
    frames: Option<(Trade, TradeKey, FrameRun)>,
    pub result: Option<(Trade, TradeKey)>,
    /// For a preview's knob: the result's times are these images of the preview; or why the
    /// core's renders stand in for them.
    pub timed_frames: Option<FrameTiming>,
    pub stand_in: Option<&'static str>,
    pub error: Option<String>,
    /// Set by the panel's button; the next update starts the job.
    requested: bool,
}

struct Job {
    task: Task<Result<Trade, TradeError>>,
    done: Arc<(AtomicUsize, AtomicUsize)>,
    cancel: Arc<AtomicBool>,
    key: TradeKey,
    /// A preview's knob: its settings, to time as the preview's images next; or why the
    /// core's renders stand in for them.
    preview: Option<Vec<PreviewTry>>,
    stand_in: Option<&'static str>,
    view: CoreCamera,
}

impl StepTrade {
    pub fn request(&mut self) {
        self.requested = true;
    }
    pub fn cancel(&mut self) {
        if let Some(job) = self.job.take() {
            job.cancel.store(true, Ordering::Relaxed);
        }
        if let Some((_, _, run)) = &mut self.frames {
            run.cancelled = true;
        }
    }
    /// While measuring: what is counted (renders of the core, or the preview's images), how
    /// many are done and how many in all.
    pub fn progress(&self) -> Option<(&'static str, usize, usize)> {
        if let Some((_, _, run)) = &self.frames {
            let (done, total) = run.progress();
            return Some(("preview image", done, total));
        }
        let j = self.job.as_ref()?;
        Some((
            "render",
            j.done.0.load(Ordering::Relaxed),
            j.done.1.load(Ordering::Relaxed),
        ))
    }
    /// The result, if it was measured for what is on screen now (any step).
    pub fn current(
        &self,
        view: Option<&View>,
        render: &RenderState,
        volume: &VolumeState,
    ) -> Option<&Trade> {
        let (trade, key) = self.result.as_ref()?;
        let view = view?;
        (*key == TradeKey::of(view.0, render, volume)).then_some(trade)
    }
}

pub(crate) fn plugin(app: &mut App) {
    app.init_resource::<StepTrade>()
        .add_message::<crate::sandbox::shared::pacing::KeepDrawing>()
        .add_systems(
            Update,
            (start, finish, time_frames)
                .chain()
                .in_set(crate::sandbox::shared::schedule::Frame::Results),
        );
}

fn start(
    mut trade: ResMut<StepTrade>,
    views: Query<&View, With<MainCamera>>,
    render: Res<RenderState>,
    volume: Res<VolumeState>,
    preview_settings: Option<Res<PreviewSettings>>,
) {
    if !std::mem::take(&mut trade.requested) || trade.job.is_some() || trade.frames.is_some() {
        return;
    }
    let Ok(view) = views.single() else {
        trade.error = Some("no view to measure".into());
        return;
    };
    let key = TradeKey::of(view.0, &render, &volume);
    let knob = trade.knob;
    let voxel = volume.volume.spacing().min_element();
    // A preview's knob is timed as the preview's images, where the preview draws it.
    let mut preview = preview_tries(knob, &render.settings, voxel);
    let stand_in = preview
        .as_ref()
        .and_then(|_| match preview_settings.as_deref() {
            Some(p) => stand_in(knob, p),
            None => Some("This window has no preview: the core's renders stand in for its images."),
        });
    if stand_in.is_some() {
        preview = None;
    }
    let mut steps = STEPS.to_vec();
    steps.push(render.settings.step.voxels(voxel));
    let done = Arc::new((AtomicUsize::new(0), AtomicUsize::new(steps.len() + 1)));
    let cancel = Arc::new(AtomicBool::new(false));
    let task = {
        let (v, tf, s, camera) = (
            volume.volume.clone(),
            render.transfer.clone(),
            render.settings.clone(),
            view.0,
        );
        let (done, cancel) = (done.clone(), cancel.clone());
        crate::sandbox::shared::tasks::spawn(async move {
            let report = |d: usize, total: usize| {
                done.0.store(d, Ordering::Relaxed);
                done.1.store(total, Ordering::Relaxed);
            };
            let view = TradeView {
                volume: &v,
                transfer: &tf,
                camera: &camera,
                size: TRADE_SIZE,
            };
            let job = TradeJob {
                view: &view,
                settings: &s,
                knob,
                steps: &steps,
                progress: &report,
                cancel: &cancel,
            };
            let mut slices = TradeSlices::default();
            in_slices(|d| trade_in(&job, &mut slices, d))
                .await
                .map(|(trade, _)| trade)
        })
    };
    trade.error = None;
    trade.job = Some(Job {
        task,
        done,
        cancel,
        key,
        preview,
        stand_in,
        view: view.0,
    });
}

fn finish(mut trade: ResMut<StepTrade>, preview: Option<Res<PreviewSettings>>) {
    let Some(job) = trade.job.as_mut() else {
        return;
    };
    let Some(result) = check_ready(&mut job.task) else {
        return;
    };
    let Some(job) = trade.job.take() else {
        return;
    };
    match (result, job.preview, preview) {
        (Ok(t), Some(tries), Some(p)) => {
            let run = FrameRun::new(tries, &p, job.view);
            trade.frames = Some((t, job.key, run));
        }
        (Ok(t), _, _) => {
            trade.result = Some((t, job.key));
            trade.timed_frames = None;
            trade.stand_in = job.stand_in;
        }
        (Err(e), _, _) => trade.error = Some(e.to_string()),
    }
}

/// Times a preview's knob as the preview's images, once the core has rendered its errors.
fn time_frames(
    mut trade: ResMut<StepTrade>,
    mut drawing: Drawing,
    mut keep: MessageWriter<crate::sandbox::shared::pacing::KeepDrawing>,
) {
    let Some((_, _, run)) = trade.frames.as_mut() else {
        return;
    };
    // The preview's frames are being timed: every one of them is wanted.
    keep.write(crate::sandbox::shared::pacing::KeepDrawing);
    let Some(ended) = drive(run, &mut drawing) else {
        return;
    };
    let Some((mut t, key, _)) = trade.frames.take() else {
        return;
    };
    match ended {
        Ended::Timed(frames) => {
            frames.apply(&mut t);
            trade.result = Some((t, key));
            trade.timed_frames = Some(frames);
            trade.stand_in = None;
        }
        Ended::Stopped(why) => trade.error = Some(why),
        Ended::Cancelled => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use bevy::tasks::{AsyncComputeTaskPool, TaskPool};
    use voxcast_core::composite::Method;

    /// Measure runs in the background; the result stays current while only the step changes
    /// (the step is what it is about) and goes stale when the method or the view does.
    #[test]
    fn a_measurement_is_current_until_the_view_or_settings_change() {
        AsyncComputeTaskPool::get_or_init(TaskPool::new);
        let (volume, render) = crate::sandbox::inspect::rays::tests::scene("blobs");
        let (lo, hi) = volume.volume.bounds();
        let view = View(CoreCamera::framing(lo, hi, Vec3::Z, Vec3::Y).unwrap());
        let mut app = App::new();
        app.insert_resource(volume)
            .insert_resource(render)
            .add_plugins((plugin, crate::sandbox::shared::render_change::plugin));
        crate::sandbox::shared::schedule::configure(&mut app);
        app.world_mut().spawn((MainCamera, view));
        app.world_mut().resource_mut::<StepTrade>().request();
        for _ in 0..2000 {
            app.update();
            if app.world().resource::<StepTrade>().result.is_some() {
                break;
            }
            std::thread::sleep(std::time::Duration::from_millis(2));
        }
        let current = |app: &App| {
            let w = app.world();
            w.resource::<StepTrade>()
                .current(
                    Some(&view),
                    w.resource::<RenderState>(),
                    w.resource::<VolumeState>(),
                )
                .map(|t| t.rows.iter().map(|r| r.step_voxels).collect::<Vec<_>>())
        };
        // The sampling level's steps and the player's own (½ voxel, already among them).
        assert_eq!(current(&app), Some(STEPS.to_vec()));
        app.world_mut().resource_mut::<RenderState>().settings.step = Length::Voxels(0.3);
        assert!(current(&app).is_some(), "another step: still current");
        app.world_mut()
            .resource_mut::<RenderState>()
            .settings
            .method = Method::Maximum;
        assert!(current(&app).is_none(), "another method: stale");
    }
}
