//! Measure's preview knobs (resolution, step ×, the moving frame) timed as what they change:
//! images of the backend that draws the volume in the window, at the window's size — the GPU
//! preview's finished images (a whole frame, or a pass of strips), or the CPU live view's exact
//! renders — not CPU renders of the small measured image. The errors stay the core's
//! (`voxcast_core::trade`): the preview agrees with the CPU's render of the same setting.
//!
//! Timed as the core's trade times: each setting once untimed, then
//! [`TIMED_RUNS`](voxcast_core::trade::TIMED_RUNS) rounds in alternating order; a setting's time
//! is the median of its runs, with the fastest and slowest. The GPU preview draws whole frames
//! while it is timed (not strips, whose number its planner chooses), so its image's time is a
//! frame of the window: the image and what every frame pays beside it, as `voxcast
//! --measure-frames --whole-frames` times it (on a display that waits for its refresh, a cheap
//! setting reads as one refresh).

use crate::sandbox::preview::live::{LiveFrame, LiveView, render_exact};
use crate::sandbox::preview::progressive::Progressive;
use crate::sandbox::shared::quality::Backend;
use crate::sandbox::shared::quality::{PreviewSettings, PreviewTarget, scaled_size};
use crate::sandbox::shared::render_change::{Author, PreviewChanges};
use crate::sandbox::shared::state::{MainCamera, View, VolumeState};
use crate::sandbox::shared::viewport::Viewport;
use bevy::prelude::*;
use bevy::tasks::{Task, futures::check_ready};
use voxcast_core::camera::Camera as CoreCamera;
use voxcast_core::knob::{Knob, Try};
use voxcast_core::settings::RenderSettings;
use voxcast_core::trade::{TIMED_RUNS, Timing, Trade, timed_order};

/// The size of the core's measured image, in a step's trade and beside the preview's timed
/// frames: small, so the five renders and the reference take moments.
pub const TRADE_SIZE: (u32, u32) = (192, 108);

/// A GPU visit times finished images until this many seconds have passed (at least one image),
/// so that a setting drawn whole every frame is the mean of several frames, not one.
const MIN_TIMED_S: f64 = 0.3;
/// A visit that has not finished an image after this many seconds ends the measurement: the
/// preview draws nothing (hidden, or its window minimised).
const VISIT_LIMIT_S: f64 = 60.0;

/// One preview setting: the fraction of the window's pixels and the step multiplier.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PreviewTry {
    pub scale: f32,
    pub step_multiplier: f32,
}

/// The knob's preview settings, its reference first and then its tries, as the core renders
/// them ([`Knob::reference`], [`Knob::tries`]); `None` for a knob the preview does not have.
pub fn preview_tries(knob: Knob, settings: &RenderSettings, voxel: f32) -> Option<Vec<PreviewTry>> {
    if !knob.is_preview() {
        return None;
    }
    let own = settings.step.voxels(voxel);
    let of = |t: Try| PreviewTry {
        scale: t.scale,
        step_multiplier: t.settings.step.voxels(voxel) / own,
    };
    let tries = knob.tries(settings, voxel, &[]);
    Some(
        std::iter::once(knob.reference(settings))
            .chain(tries)
            .map(of)
            .collect(),
    )
}

/// Why the preview cannot time `knob` as its images now, in words (the core's renders of the
/// measured image stand in for them); `None` when it can.
pub fn stand_in(knob: Knob, preview: &PreviewSettings) -> Option<&'static str> {
    if !preview.enabled {
        Some("The preview is off, so its knob is timed as the core's renders of the small image.")
    } else if preview.cost_view.is_some() {
        Some(
            "The preview shows a cost view, so its knob is timed as the core's renders of the \
             small image.",
        )
    } else if preview.backend == Backend::Cpu && knob != Knob::PreviewScale {
        Some(
            "The CPU live view always samples at the step itself and sizes its moving frames \
             to a time budget: this knob changes only the GPU preview, so it is timed as the \
             core's renders of the small image. Draw the preview with the GPU to time its \
             images.",
        )
    } else {
        None
    }
}

/// The preview's images timed: who drew them, at what size at full resolution (the
/// viewport's pixels), and each setting's timing, the reference first.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameTiming {
    pub drawer: Backend,
    pub size: UVec2,
    pub timings: Vec<Timing>,
}

impl FrameTiming {
    /// The trade with its times replaced by these (its rows and the reference, in the same
    /// order as [`preview_tries`]).
    pub fn apply(&self, trade: &mut Trade) {
        debug_assert_eq!(self.timings.len(), trade.rows.len() + 1);
        if let Some(r) = self.timings.first() {
            trade.reference_timing = *r;
            trade.reference_seconds = r.median;
        }
        for (row, t) in trade.rows.iter_mut().zip(&self.timings[1..]) {
            row.timing = *t;
            row.seconds = t.median;
        }
    }

    /// How the times were taken, in words, for the table's footnote (`runs` timed images a
    /// setting).
    pub fn words(&self, runs: usize) -> String {
        format!(
            "time: one finished image of the {} at {}×{} pixels (full resolution), the median \
             of {runs} after an untimed one, the settings in alternating order; samples and \
             errors: the core's render at {}×{}",
            self.drawer.words(),
            self.size.x,
            self.size.y,
            TRADE_SIZE.0,
            TRADE_SIZE.1
        )
    }
}

/// Which setting the `k`-th visit draws, of `total`: each once untimed, then the timed rounds;
/// and whether it is timed.
pub fn visit(k: usize, total: usize) -> (usize, bool) {
    if k < total {
        (k, false)
    } else {
        (timed_order(k - total, total), true)
    }
}

/// What a visit is waiting for.
enum Waiting {
    /// The setting is to be put in place this frame.
    Start,
    /// GPU: the passes counter last seen, and the times images finished since the setting
    /// took effect (the preview's target at the setting's size).
    Images {
        last: u64,
        finished: Vec<f64>,
        size: UVec2,
    },
    /// CPU: the live view's render of the setting.
    Render(Task<Option<LiveFrame>>),
}

/// A measurement of the preview's frames under way.
pub struct FrameRun {
    tries: Vec<PreviewTry>,
    drawer: Backend,
    /// The player's own setting (with adaptive quality, and whether the GPU preview drew only
    /// whole frames), put back at the end.
    own: PreviewTry,
    own_adaptive: bool,
    own_whole: Option<bool>,
    /// The view it began with: a moved camera spoils the timing.
    view: CoreCamera,
    visit: usize,
    visit_began: f64,
    waiting: Waiting,
    runs: Vec<Vec<f64>>,
    size: UVec2,
    /// Set by Cancel; the next frame puts the player's setting back.
    pub cancelled: bool,
}

impl FrameRun {
    pub fn new(tries: Vec<PreviewTry>, preview: &PreviewSettings, view: CoreCamera) -> Self {
        let n = tries.len();
        Self {
            tries,
            drawer: preview.backend,
            own: PreviewTry {
                scale: preview.scale,
                step_multiplier: preview.step_multiplier,
            },
            own_adaptive: preview.adaptive,
            own_whole: None,
            view,
            visit: 0,
            visit_began: f64::NAN,
            waiting: Waiting::Start,
            runs: vec![Vec::new(); n],
            size: UVec2::ZERO,
            cancelled: false,
        }
    }

    /// Visits done and in all.
    pub fn progress(&self) -> (usize, usize) {
        (self.visit, self.tries.len() * (1 + TIMED_RUNS))
    }

    fn restore(&self, preview: &mut PreviewSettings, progressive: Option<&mut Progressive>) {
        preview.scale = self.own.scale;
        preview.step_multiplier = self.own.step_multiplier;
        preview.adaptive = self.own_adaptive;
        if let (Some(p), Some(whole)) = (progressive, self.own_whole) {
            p.set_whole_frames(whole);
        }
    }
}

/// What the frame's world offers a measurement.
#[derive(bevy::ecs::system::SystemParam)]
pub struct Drawing<'w, 's> {
    preview: PreviewChanges<'w>,
    progressive: Option<ResMut<'w, Progressive>>,
    target: Option<Res<'w, PreviewTarget>>,
    live: Option<Res<'w, LiveView>>,
    viewport: Option<Res<'w, Viewport>>,
    window: Query<'w, 's, &'static Window, With<bevy::window::PrimaryWindow>>,
    views: Query<'w, 's, &'static View, With<MainCamera>>,
    volume: Option<Res<'w, VolumeState>>,
    time: Option<Res<'w, Time<Real>>>,
}

/// How a measurement of the preview's frames ended.
#[derive(Debug)]
pub enum Ended {
    Timed(FrameTiming),
    /// Why it stopped, in words.
    Stopped(String),
    Cancelled,
}

/// Drives `run` one frame on: `None` while it goes on, else how it ended (the player's preview
/// setting is back in place either way).
pub fn drive(run: &mut FrameRun, d: &mut Drawing) -> Option<Ended> {
    // The preview's settings edited on a copy, sent as one change.
    let mut preview = d.preview.now.as_deref().cloned();
    let ended = if run.cancelled {
        Some(Ended::Cancelled)
    } else {
        advance(run, d, preview.as_mut())
    };
    if ended.is_some()
        && let Some(preview) = preview.as_mut()
    {
        run.restore(preview, d.progressive.as_deref_mut());
    }
    if let Some(preview) = preview {
        d.preview.edited(Author::Trade, preview);
    }
    ended
}

/// Puts try `i`'s setting in place and says what its visit waits for: the GPU preview's
/// images (whole frames) or the CPU live view's exact render at that setting; why not where
/// it cannot be timed.
fn begin_visit(
    run: &mut FrameRun,
    d: &mut Drawing,
    preview: &mut PreviewSettings,
    i: usize,
    volume: std::sync::Arc<voxcast_core::Prepared>,
) -> Result<Waiting, &'static str> {
    let setting = run.tries[i];
    preview.scale = setting.scale;
    preview.step_multiplier = setting.step_multiplier;
    // Exactly this setting, whatever the preview takes for motion (a settings change counts as
    // one).
    preview.adaptive = false;
    let Ok(window) = d.window.single() else {
        return Err("the preview has no window to draw in");
    };
    let (_, size) = Viewport::of(d.viewport.as_deref(), window);
    if i == 0 {
        run.size = size;
    }
    Ok(match run.drawer {
        Backend::Gpu => {
            let Some(p) = d.progressive.as_deref_mut() else {
                return Err("the GPU preview draws nothing here");
            };
            // Whole frames: strips' number is the planner's choice, not the knob's.
            run.own_whole.get_or_insert(p.whole_frames());
            p.set_whole_frames(true);
            Waiting::Images {
                last: p.passes(),
                finished: Vec::new(),
                size: scaled_size(size, setting.scale),
            }
        }
        Backend::Cpu => {
            let Some(key) = d.live.as_ref().and_then(|l| l.key()) else {
                return Err("the CPU live view has drawn nothing yet");
            };
            let mut key = key.clone();
            key.full = scaled_size(size, setting.scale);
            let spheres = setting.scale >= 1.0;
            Waiting::Render(render_exact(key, volume, spheres))
        }
    })
}

fn stopped(why: &str) -> Option<Ended> {
    Some(Ended::Stopped(why.to_string()))
}

/// [`drive`] but for putting the player's setting back.
fn advance(
    run: &mut FrameRun,
    d: &mut Drawing,
    preview: Option<&mut PreviewSettings>,
) -> Option<Ended> {
    let Some(preview) = preview else {
        return stopped("this window has no preview");
    };
    let view = d.views.single().ok().map(|v| v.0);
    if view != Some(run.view) {
        return stopped(
            "the view moved while the preview was timed: measure again with the view still",
        );
    }
    if preview.backend != run.drawer || !preview.enabled || preview.cost_view.is_some() {
        return stopped("the preview changed while it was timed: measure again");
    }
    let (Some(time), Some(volume)) = (d.time.as_ref(), d.volume.as_ref()) else {
        return stopped("this window has no clock or volume");
    };
    let now = time.elapsed_secs_f64();
    let total = run.tries.len();
    let (i, timed) = visit(run.visit, total);
    if matches!(run.waiting, Waiting::Start) {
        let volume = volume.volume.clone();
        run.visit_began = now;
        run.waiting = match begin_visit(run, d, preview, i, volume) {
            Ok(waiting) => waiting,
            Err(why) => return stopped(why),
        };
        return None;
    } else if now - run.visit_began > VISIT_LIMIT_S {
        return stopped("the preview drew no image for a minute: is its window hidden?");
    }
    let seconds = match &mut run.waiting {
        Waiting::Start => None,
        Waiting::Images {
            last,
            finished,
            size,
        } => {
            let passes = d.progressive.as_ref().map_or(0, |p| p.passes());
            // Images count once the preview draws at the setting's size.
            let at_size = d.target.as_ref().is_some_and(|t| t.size == *size);
            if !at_size {
                finished.clear();
            }
            if passes > *last {
                *last = passes;
                if at_size {
                    finished.push(now);
                }
            }
            // The first image may have begun before the setting: time from its end on.
            let n = finished.len();
            (n >= 2 && now - finished[0] >= MIN_TIMED_S)
                .then(|| (finished[n - 1] - finished[0]) / (n - 1) as f64)
        }
        Waiting::Render(task) => match check_ready(task) {
            None => None,
            Some(Some(frame)) => Some(frame.seconds),
            Some(None) => return stopped("the CPU live view could not render"),
        },
    };
    let seconds = seconds?;
    if timed {
        run.runs[i].push(seconds);
    }
    run.visit += 1;
    run.waiting = Waiting::Start;
    if run.visit < total * (1 + TIMED_RUNS) {
        return None;
    }
    Some(Ended::Timed(FrameTiming {
        drawer: run.drawer,
        size: run.size,
        timings: run.runs.iter().map(|r| Timing::of(r)).collect(),
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use voxcast_core::step::Length;

    #[test]
    fn the_preview_knobs_draw_the_cores_tries_reference_first() {
        let s = RenderSettings {
            step: Length::Voxels(0.5),
            ..Default::default()
        };
        let t = |scale, step_multiplier| PreviewTry {
            scale,
            step_multiplier,
        };
        assert_eq!(
            preview_tries(Knob::PreviewScale, &s, 1.0).unwrap(),
            [t(1.0, 1.0), t(0.25, 1.0), t(0.5, 1.0), t(0.75, 1.0)]
        );
        assert_eq!(
            preview_tries(Knob::PreviewStepMultiplier, &s, 1.0).unwrap(),
            [t(1.0, 1.0), t(1.0, 8.0), t(1.0, 4.0), t(1.0, 2.0)]
        );
        let moving = preview_tries(Knob::AdaptiveQuality, &s, 1.0).unwrap();
        assert_eq!(moving[0], t(1.0, 1.0));
        for (m, (f, x)) in moving[1..].iter().zip(voxcast_core::knob::MOVING_FRAMES) {
            assert_eq!(*m, t(f, x));
        }
        assert_eq!(preview_tries(Knob::Step, &s, 1.0), None);
    }

    /// Each setting once untimed, then every setting `TIMED_RUNS` times, alternating.
    #[test]
    fn visits_warm_up_then_alternate() {
        let total = 4;
        let visits: Vec<_> = (0..total * (1 + TIMED_RUNS))
            .map(|k| visit(k, total))
            .collect();
        assert_eq!(
            &visits[..4],
            &[(0, false), (1, false), (2, false), (3, false)]
        );
        assert_eq!(&visits[4..8], &[(0, true), (1, true), (2, true), (3, true)]);
        assert_eq!(
            &visits[8..12],
            &[(3, true), (2, true), (1, true), (0, true)]
        );
        for s in 0..total {
            let timed = visits.iter().filter(|v| **v == (s, true)).count();
            assert_eq!(timed, TIMED_RUNS);
        }
    }

    #[test]
    fn only_a_backend_that_draws_the_knob_times_it() {
        let mut p = PreviewSettings::default();
        assert_eq!(stand_in(Knob::PreviewStepMultiplier, &p), None);
        p.backend = Backend::Cpu;
        assert_eq!(stand_in(Knob::PreviewScale, &p), None);
        assert!(stand_in(Knob::PreviewStepMultiplier, &p).is_some());
        assert!(stand_in(Knob::AdaptiveQuality, &p).is_some());
        p.enabled = false;
        assert!(stand_in(Knob::PreviewScale, &p).unwrap().contains("off"));
    }

    #[test]
    fn the_frames_times_replace_the_trades() {
        let timing = |ms: f64| Timing {
            median: ms / 1e3,
            fastest: ms / 2e3,
            slowest: ms / 5e2,
        };
        let row = |label: &str| voxcast_core::trade::TradeRow {
            label: label.into(),
            step_voxels: 0.5,
            seconds: 1.0,
            timing: Timing::default(),
            samples: 1,
            max_error: 0.1,
            rmse: 0.01,
        };
        let mut trade = Trade {
            knob: Knob::PreviewScale,
            reference: "full resolution".into(),
            reference_voxels: 0.5,
            reference_seconds: 1.0,
            reference_timing: Timing::default(),
            reference_samples: 4,
            rows: vec![row("0.25"), row("0.5")],
            runs: 5,
            threads: 2,
        };
        let frames = FrameTiming {
            drawer: Backend::Gpu,
            size: UVec2::new(640, 360),
            timings: vec![timing(40.0), timing(5.0), timing(12.0)],
        };
        frames.apply(&mut trade);
        assert_eq!(trade.reference_seconds, 0.04);
        assert_eq!(trade.rows[0].timing, timing(5.0));
        assert_eq!(trade.rows[1].seconds, 0.012);
        assert_eq!(trade.rows[1].max_error, 0.1, "the errors stay the core's");
    }
}
