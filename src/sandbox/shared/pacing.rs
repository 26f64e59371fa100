//! How often the window draws: every frame while something moves or changes, a few times a
//! second while only background work is under way, and only now and then once all is still — so
//! that a student's laptop is not kept busy drawing the same picture (on a software renderer
//! such as lavapipe a resting frame of the 1280×720 window is some 20 ms of both cores, drawn
//! ~47 times a second; in a browser without a graphics card some 150–200 ms).
//!
//! The window counts as active for [`KEEP_DRAWING`] after the student's last input, the last
//! [`KeepDrawing`] message (features send one each frame while they move: the preview until
//! its exact image shows, the rays while they grow, a timed measurement) and while the view
//! moves ([`Motion`]). While active the window draws as the app was started ([`WinitSettings`]
//! as inserted, Bevy's default: every frame when focused); at rest it waits for input, a redraw
//! request, a wake ([`super::wake`]: a task's end, files the page hands over) or [`REST_WAIT`].
//! While a background task runs ([`super::tasks::in_flight`]) and nothing else asks for
//! frames, the window is paced for the work: it draws its progress every [`WORK_WAIT`] and
//! leaves the cores to the task (in a browser the task's slices and the frames share one
//! thread, and the browser's software drawing the other core), and the task's end wakes it for
//! [`AFTER_TASK`] of frames. An app started with [`WinitSettings::continuous`] (the
//! measurements and the scripted players) is left as it is.

use super::quality::Motion;
use bevy::input::keyboard::KeyboardInput;
use bevy::input::mouse::{MouseButtonInput, MouseWheel};
use bevy::prelude::*;
use bevy::window::CursorMoved;
use bevy::winit::{UpdateMode, WinitSettings};
use bevy_egui::{EguiInput, EguiPreUpdateSet};
use std::time::Duration;

/// How long the window keeps drawing every frame after the last input or change: long enough
/// for a click's consequences (a task starting, an animation) to take over. Not shorter: at
/// 0.5 s, clicks on the page made 1.2 s after the pointer stopped were lost in 4 of 9 tries
/// (a collapsing header left closed; none of 8 at 2 s, nor of 4 made on a page long at rest),
/// not yet understood (BENCHMARKS.md, "A pointer move or a click").
pub const KEEP_DRAWING: Duration = Duration::from_secs(2);

/// After a background task ends, how long the window draws every frame: its result's first
/// frames (egui fitting a window to it asks for its own). Shorter than [`KEEP_DRAWING`]: no
/// student is acting, and in a browser without a graphics card two seconds of frames after
/// each Render image kept some 1.4 of 2 cores busy redrawing a picture already shown
/// (BENCHMARKS.md).
pub const AFTER_TASK: Duration = Duration::from_millis(250);

/// At rest, the longest the window waits between two frames without input: what anything
/// that neither sends [`KeepDrawing`] nor wakes the window ([`super::wake`]) waits at most to
/// be shown. Long, because a resting frame is not free: in a browser without a graphics card
/// each frame of the page is some 150–200 ms of the CPU's drawing, so a frame every 0.1 s kept
/// both cores of a 2-core laptop busy with the page at rest (BENCHMARKS.md).
pub const REST_WAIT: Duration = Duration::from_secs(1);

/// While only background work runs (a render, a load, a measurement), the longest the window
/// waits between two frames without input: its progress shown four times a second, the rest
/// of the time left to the work.
pub const WORK_WAIT: Duration = Duration::from_millis(250);

/// Sent by a feature in every frame in which it needs the next one soon (it moves, or waits
/// for the window to draw).
#[derive(Message, Clone, Copy, Debug, Default)]
pub struct KeepDrawing;

/// The window's pace: whether it is at rest, and how it draws while active.
#[derive(Resource, Debug)]
pub struct Pacing {
    /// The settings the app was started with, used while active.
    awake: Option<WinitSettings>,
    /// Until when the window draws every frame (unless paced for the work), seconds of real
    /// time: [`KEEP_DRAWING`] after the last input or request, [`AFTER_TASK`] after a task's end.
    awake_until: f64,
    /// How many background tasks run ([`super::tasks::in_flight`]; the tests' own count).
    in_flight: fn() -> usize,
    /// Whether a background task ran in the last frame.
    tasks_ran: bool,
    /// Whether the window is at rest (drawing only on input, requests and [`REST_WAIT`]).
    pub resting: bool,
    /// Whether the window is paced for background work (drawing only on input, requests,
    /// a task's end and [`WORK_WAIT`]).
    pub working: bool,
    /// What last kept the window drawing, in words.
    pub woken_by: &'static str,
    /// Frames drawn since the window last woke from rest or from the work's pace (the first
    /// one's frame time is the wait: the frame time shown leaves such frames out).
    pub awake_frames: u32,
}

impl Default for Pacing {
    fn default() -> Self {
        Self {
            awake: None,
            awake_until: KEEP_DRAWING.as_secs_f64(),
            in_flight: super::tasks::in_flight,
            tasks_ran: false,
            resting: false,
            working: false,
            woken_by: "starting",
            awake_frames: 0,
        }
    }
}

pub fn plugin(app: &mut App) {
    app.add_message::<KeepDrawing>()
        .init_resource::<Pacing>()
        .add_systems(Startup, wake_through_winit)
        .add_systems(Last, pace)
        .add_systems(
            PreUpdate,
            drop_unchanged_modifiers
                .after(EguiPreUpdateSet::ProcessInput)
                .before(EguiPreUpdateSet::BeginPass),
        );
}

/// bevy_egui tells egui the modifier keys' state as an event every frame, changed or not, and
/// egui answers any event with a request for the next frame: the window could never rest.
/// The event is dropped where the state is the one egui was last told.
fn drop_unchanged_modifiers(
    mut inputs: Query<&mut EguiInput>,
    mut last: Local<Option<bevy_egui::egui::Modifiers>>,
) {
    for mut input in &mut inputs {
        input.events.retain(|e| match e {
            bevy_egui::egui::Event::ModifiersChanged(m) => {
                let changed = last.as_ref() != Some(m);
                *last = Some(*m);
                changed
            }
            _ => true,
        });
    }
}

/// The settings at rest, or (`wait` [`WORK_WAIT`]) while only background work runs.
fn waiting(wait: Duration) -> WinitSettings {
    WinitSettings {
        focused_mode: UpdateMode::reactive(wait),
        unfocused_mode: UpdateMode::reactive_low_power(wait),
    }
}

/// Gives [`super::wake`] the window's way of waking (a task's end, files the page hands over).
fn wake_through_winit(proxy: Option<Res<bevy::winit::EventLoopProxyWrapper>>) {
    if let Some(proxy) = proxy {
        let proxy = (**proxy).clone();
        super::wake::set(move || {
            // An event loop that has ended has no window to wake.
            let _ = proxy.send_event(bevy::winit::WinitUserEvent::WakeUp);
        });
    }
}

fn continuous(s: &WinitSettings) -> bool {
    s.focused_mode == UpdateMode::Continuous && s.unfocused_mode == UpdateMode::Continuous
}

/// Whether anything asked for frames this frame.
#[derive(bevy::ecs::system::SystemParam)]
struct Activity<'w, 's> {
    keep: MessageReader<'w, 's, KeepDrawing>,
    keys: MessageReader<'w, 's, KeyboardInput>,
    buttons: MessageReader<'w, 's, MouseButtonInput>,
    wheel: MessageReader<'w, 's, MouseWheel>,
    cursor: MessageReader<'w, 's, CursorMoved>,
    motion: Option<Res<'w, Motion>>,
}

impl Activity<'_, '_> {
    /// What asked for frames this frame, in words, if anything did.
    fn reason(&mut self) -> Option<&'static str> {
        // Every reader is drained: a message left unread would count again next frame.
        let messages = [
            (self.keep.read().count(), "a feature asked for frames"),
            (self.keys.read().count(), "a key"),
            (self.buttons.read().count(), "a mouse button"),
            (self.wheel.read().count(), "the mouse wheel"),
            (self.cursor.read().count(), "the pointer moved"),
        ];
        let message = messages.iter().find(|(n, _)| *n > 0).map(|(_, why)| *why);
        message.or(self
            .motion
            .as_ref()
            .is_some_and(|m| m.moving)
            .then_some("the view moves"))
    }
}

fn pace(
    time: Res<Time<Real>>,
    mut activity: Activity,
    mut pacing: ResMut<Pacing>,
    settings: Option<ResMut<WinitSettings>>,
) {
    // No window (a screenshot, Render image from the command line): nothing to pace.
    let Some(mut settings) = settings else {
        return;
    };
    let now = time.elapsed_secs_f64();
    let awake = pacing.awake.get_or_insert_with(|| settings.clone()).clone();
    if continuous(&awake) {
        return;
    }
    let asked = activity.reason();
    if let Some(why) = asked {
        pacing.awake_until = now + KEEP_DRAWING.as_secs_f64();
        pacing.woken_by = why;
    }
    let working = (pacing.in_flight)() > 0;
    if std::mem::replace(&mut pacing.tasks_ran, working) && !working {
        // The work is done: its result shows with every frame for a moment (longer where the
        // student acted lately).
        pacing.awake_until = pacing.awake_until.max(now + AFTER_TASK.as_secs_f64());
        pacing.woken_by = "a task finished";
    }
    let working = working && asked.is_none();
    let resting = !working && now >= pacing.awake_until;
    pacing.awake_frames = if working || resting {
        0
    } else {
        pacing.awake_frames.saturating_add(1)
    };
    if (working, resting) != (pacing.working, pacing.resting) {
        (pacing.working, pacing.resting) = (working, resting);
        *settings = match (working, resting) {
            (true, _) => waiting(WORK_WAIT),
            (false, true) => waiting(REST_WAIT),
            (false, false) => awake,
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use bevy::time::TimeUpdateStrategy;

    /// Each test frame's length.
    const FRAME: Duration = Duration::from_millis(250);

    fn app(start: WinitSettings) -> App {
        let mut app = App::new();
        app.add_plugins(MinimalPlugins)
            .add_message::<KeyboardInput>()
            .add_message::<MouseButtonInput>()
            .add_message::<MouseWheel>()
            .add_message::<CursorMoved>()
            .insert_resource(start)
            .insert_resource(TimeUpdateStrategy::ManualDuration(FRAME))
            .add_plugins(plugin);
        // No task of this test's (the process's count holds the other tests').
        app.world_mut().resource_mut::<Pacing>().in_flight = || 0;
        app
    }

    fn focused(app: &App) -> UpdateMode {
        app.world().resource::<WinitSettings>().focused_mode
    }

    #[test]
    fn the_window_rests_after_a_still_while_and_wakes_on_a_request() {
        let mut app = app(WinitSettings::game());
        // Active for KEEP_DRAWING, then, with nothing going on, at rest.
        let awake = (KEEP_DRAWING.as_millis() / FRAME.as_millis()) as usize;
        for _ in 0..awake {
            app.update();
            assert_eq!(focused(&app), UpdateMode::Continuous, "active at first");
        }
        app.update();
        assert!(app.world().resource::<Pacing>().resting);
        assert_eq!(focused(&app), UpdateMode::reactive(REST_WAIT));
        app.world_mut().write_message(KeepDrawing);
        app.update();
        assert!(!app.world().resource::<Pacing>().resting);
        assert_eq!(focused(&app), UpdateMode::Continuous, "awake as it started");
        // A view that moves keeps it awake.
        app.insert_resource(Motion {
            moving: true,
            last_change: 0.0,
        });
        for _ in 0..20 {
            app.update();
        }
        assert_eq!(focused(&app), UpdateMode::Continuous);
    }

    #[test]
    fn a_task_under_way_paces_the_window_for_the_work_until_input() {
        static TASKS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(1);
        let mut app = app(WinitSettings::game());
        app.world_mut().resource_mut::<Pacing>().in_flight =
            || TASKS.load(std::sync::atomic::Ordering::Relaxed);
        // Right after the click that started it (within KEEP_DRAWING), with nothing else
        // asking for frames, the window draws at the work's pace.
        app.update();
        let pacing = app.world().resource::<Pacing>();
        assert!(pacing.working && !pacing.resting, "{pacing:?}");
        assert_eq!(focused(&app), UpdateMode::reactive(WORK_WAIT));
        // A feature that moves (or the student's input) has every frame again.
        app.world_mut().write_message(KeepDrawing);
        app.update();
        assert!(!app.world().resource::<Pacing>().working);
        assert_eq!(focused(&app), UpdateMode::Continuous);
        for _ in 0..20 {
            app.update();
        }
        assert!(app.world().resource::<Pacing>().working, "the task runs");
        assert_eq!(focused(&app), UpdateMode::reactive(WORK_WAIT));
        // The task ends: every frame for a while, to show its result, then rest.
        TASKS.store(0, std::sync::atomic::Ordering::Relaxed);
        app.update();
        let pacing = app.world().resource::<Pacing>();
        assert!(!pacing.working && !pacing.resting, "{pacing:?}");
        assert_eq!(pacing.woken_by, "a task finished");
        assert_eq!(focused(&app), UpdateMode::Continuous);
        // A FRAME (AFTER_TASK) later it rests, not KEEP_DRAWING later.
        app.update();
        assert!(app.world().resource::<Pacing>().resting);
    }

    #[test]
    fn a_task_that_ends_wakes_the_window() {
        static WOKEN: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
        bevy::tasks::AsyncComputeTaskPool::get_or_init(bevy::tasks::TaskPool::new);
        super::super::wake::set(|| {
            WOKEN.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        });
        let before = WOKEN.load(std::sync::atomic::Ordering::Relaxed);
        bevy::tasks::block_on(super::super::tasks::spawn(async {}));
        assert!(WOKEN.load(std::sync::atomic::Ordering::Relaxed) > before);
    }

    #[test]
    fn an_app_started_continuous_is_left_continuous() {
        let mut app = app(WinitSettings::continuous());
        for _ in 0..20 {
            app.update();
        }
        assert!(continuous(app.world().resource::<WinitSettings>()));
        assert!(!app.world().resource::<Pacing>().resting);
    }
}
