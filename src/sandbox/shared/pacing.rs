//! How often the window draws: every frame while something moves, changes or is under way,
//! and only now and then once all is still — so that a student's laptop is not kept busy
//! drawing the same picture (on a software renderer such as lavapipe a resting frame of the
//! 1280×720 window is some 20 ms of both cores, drawn ~47 times a second).
//!
//! The window counts as active for [`KEEP_DRAWING`] after the student's last input, the last
//! [`KeepDrawing`] message (features send one each frame while they move: the preview until
//! its exact image shows, the rays while they grow, a timed measurement), while the view moves
//! ([`Motion`]) and while any background task runs ([`super::tasks::in_flight`]). While
//! active the window draws as the app was started ([`WinitSettings`] as inserted, Bevy's
//! default: every frame when focused); at rest it waits for input, a redraw request or
//! [`REST_WAIT`]. An app started with [`WinitSettings::continuous`] (the measurements and the
//! scripted players) is left as it is.

use super::quality::Motion;
use bevy::input::keyboard::KeyboardInput;
use bevy::input::mouse::{MouseButtonInput, MouseWheel};
use bevy::prelude::*;
use bevy::window::CursorMoved;
use bevy::winit::{UpdateMode, WinitSettings};
use bevy_egui::{EguiInput, EguiPreUpdateSet};
use std::time::Duration;

/// How long the window keeps drawing every frame after the last input or change: long enough
/// for a click's consequences (a task starting, an animation) to take over.
pub const KEEP_DRAWING: Duration = Duration::from_secs(2);

/// At rest, the longest the window waits between two frames without input: what anything
/// that sends no [`KeepDrawing`] waits at most to be shown.
pub const REST_WAIT: Duration = Duration::from_millis(100);

/// Sent by a feature in every frame in which it needs the next one soon (it moves, or waits
/// for the window to draw).
#[derive(Message, Clone, Copy, Debug, Default)]
pub struct KeepDrawing;

/// The window's pace: whether it is at rest, and how it draws while active.
#[derive(Resource, Debug)]
pub struct Pacing {
    /// The settings the app was started with, used while active.
    awake: Option<WinitSettings>,
    /// When the window was last active, seconds of real time.
    last_active: f64,
    /// Whether the window is at rest (drawing only on input, requests and [`REST_WAIT`]).
    pub resting: bool,
    /// What last kept the window drawing, in words.
    pub woken_by: &'static str,
}

impl Default for Pacing {
    fn default() -> Self {
        Self {
            awake: None,
            last_active: 0.0,
            resting: false,
            woken_by: "starting",
        }
    }
}

pub fn plugin(app: &mut App) {
    app.add_message::<KeepDrawing>()
        .init_resource::<Pacing>()
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

/// The settings at rest.
fn at_rest() -> WinitSettings {
    WinitSettings {
        focused_mode: UpdateMode::reactive(REST_WAIT),
        unfocused_mode: UpdateMode::reactive_low_power(REST_WAIT),
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
        message
            .or(self
                .motion
                .as_ref()
                .is_some_and(|m| m.moving)
                .then_some("the view moves"))
            .or((super::tasks::in_flight() > 0).then_some("a task runs"))
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
    if let Some(why) = activity.reason() {
        pacing.last_active = now;
        pacing.woken_by = why;
    }
    let resting = now - pacing.last_active >= KEEP_DRAWING.as_secs_f64();
    if resting != pacing.resting {
        pacing.resting = resting;
        *settings = if resting { at_rest() } else { awake };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use bevy::time::TimeUpdateStrategy;

    fn app(start: WinitSettings) -> App {
        let mut app = App::new();
        app.add_plugins(MinimalPlugins)
            .add_message::<KeyboardInput>()
            .add_message::<MouseButtonInput>()
            .add_message::<MouseWheel>()
            .add_message::<CursorMoved>()
            .insert_resource(start)
            .insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_millis(
                250,
            )))
            .add_plugins(plugin);
        app
    }

    fn focused(app: &App) -> UpdateMode {
        app.world().resource::<WinitSettings>().focused_mode
    }

    #[test]
    fn the_window_rests_after_a_still_while_and_wakes_on_a_request() {
        let mut app = app(WinitSettings::game());
        for _ in 0..4 {
            app.update();
            assert_eq!(focused(&app), UpdateMode::Continuous, "active at first");
        }
        // 250 ms a frame: after KEEP_DRAWING with nothing going on, it rests.
        for _ in 0..12 {
            app.update();
        }
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
    fn a_task_under_way_keeps_the_window_drawing() {
        bevy::tasks::AsyncComputeTaskPool::get_or_init(bevy::tasks::TaskPool::new);
        let mut app = app(WinitSettings::game());
        let (tx, rx) = std::sync::mpsc::channel::<()>();
        let task = super::super::tasks::spawn(async move {
            let _ = rx.recv();
        });
        for _ in 0..20 {
            app.update();
        }
        assert!(!app.world().resource::<Pacing>().resting, "the task runs");
        tx.send(()).unwrap();
        bevy::tasks::block_on(task);
        // (Whether it rests once the task is done depends on the other tests' tasks: the
        // count is the process's.)
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
