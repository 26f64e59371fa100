//! Bevy's own plugins as the sandbox wants them: the log, the task pools, pipelines compiled at
//! once where a frame is captured, and the window (or none).

use crate::sandbox::shared::platform;
use bevy::prelude::*;
use bevy::render::RenderPlugin;

/// The engine's plugins, with the log as the sandbox wants it and `window` as the primary one.
/// Threads of Bevy's `AsyncComputeTaskPool`, at least (Bevy gives a quarter of the cores, at
/// least one): a live view's frame waits there for its own threads, which yield to the
/// window's (`preview/live.rs`), so on two cores a second thread keeps the virtual camera's
/// rays, loads and Render image from queueing behind it.
const ASYNC_THREADS_MIN: usize = 2;

pub(super) fn engine(app: &mut App, window: Option<Window>, synchronous: bool) {
    let async_compute = bevy::app::TaskPoolThreadAssignmentPolicy {
        min_threads: ASYNC_THREADS_MIN,
        max_threads: 4,
        percent: 0.25,
        on_thread_spawn: None,
        on_thread_destroy: None,
    };
    let plugins = DefaultPlugins
        .set(RenderPlugin {
            synchronous_pipeline_compilation: synchronous,
            ..default()
        })
        .set(TaskPoolPlugin {
            task_pool_options: TaskPoolOptions {
                async_compute,
                ..default()
            },
        })
        .set(platform::log_plugin());
    match window {
        Some(window) => app.add_plugins(plugins.set(WindowPlugin {
            primary_window: Some(window),
            ..default()
        })),
        None => app.add_plugins(
            plugins
                .set(WindowPlugin {
                    primary_window: None,
                    exit_condition: bevy::window::ExitCondition::DontExit,
                    ..default()
                })
                .disable::<bevy::winit::WinitPlugin>(),
        ),
    };
}
