//! The app assembled: the engine's plugins, then a window (`window.rs`) or none (a screenshot,
//! Render image from the command line), then what every sandbox has; run until it closes.

use super::args::SandboxArgs;
use super::engine::engine;
use super::start::Start;
use super::window::build_window;
use crate::cli::CliError;
use crate::sandbox::checks::compare;
use crate::sandbox::drivers::{compare_cli, screenshot};
use crate::sandbox::gpu::material::VolumeMaterial;
use crate::sandbox::gpu::{pipelines, shaders};
use crate::sandbox::preview::camera::InitialView;
use crate::sandbox::preview::sync;
use crate::sandbox::scene::light;
use crate::sandbox::shared::{self, fit, mode, quality, schedule};
use bevy::prelude::*;
use voxcast_core::error::io_words;

/// Runs the sandbox (or takes the screenshot) and returns when it closes.
pub fn run(args: &SandboxArgs) -> Result<(), CliError> {
    if args.auto_orbit != 0.0 && args.measure_frames.is_none() && args.time_frames.is_none() {
        return Err(CliError::usage(
            "--auto-orbit turns the camera while frames are measured: give it with \
             --measure-frames or --time-frames",
        ));
    }
    args.cpu.apply();
    let start = Start::from_args(args)?;
    let mut app = App::new();
    let headless = args.screenshot.is_some() || args.compare.is_some();
    if headless {
        build_headless(&mut app, args)?;
    } else {
        build_window(&mut app, args, &start.render)?;
    }
    let background = start.render.settings.background;
    schedule::configure(&mut app);
    app.add_plugins(MaterialPlugin::<VolumeMaterial>::default())
        .add_plugins((shared::pacing::plugin, shared::render_change::plugin))
        .add_plugins((
            shaders::plugin,
            pipelines::plugin,
            sync::plugin,
            mode::plugin,
            light::marker_plugin,
        ))
        .insert_resource(ClearColor(Color::srgb(
            background.x,
            background.y,
            background.z,
        )))
        .insert_resource(start.volume)
        .insert_resource(start.rays)
        .insert_resource(start.render)
        .insert_resource(InitialView(start.camera));
    match app.run() {
        AppExit::Success => Ok(()),
        AppExit::Error(code) => Err(CliError::failed(format!(
            "the sandbox stopped with code {code}"
        ))),
    }
}

/// No window: one frame of the preview into an image (`--screenshot`), or Render image
/// (`--compare`), then exit.
fn build_headless(app: &mut App, args: &SandboxArgs) -> Result<(), CliError> {
    engine(app, None, true);
    app.add_plugins(bevy::app::ScheduleRunnerPlugin::run_loop(
        std::time::Duration::ZERO,
    ));
    let (width, height) = args.size.unwrap_or(fit::DEFAULT_SIZE);
    app.insert_resource(screenshot::ImageSize(width, height))
        .add_plugins(screenshot::image_camera_plugin);
    if let Some(path) = &args.screenshot {
        if args.sweep {
            std::fs::create_dir_all(path)
                .map_err(|e| CliError::failed(format!("{}: {}", path.display(), io_words(&e))))?;
        }
        app.insert_resource(screenshot::Request {
            path: path.clone(),
            sweep: args.sweep,
            time_frames: args.time_frames.unwrap_or(0),
            orbit_degrees: args.auto_orbit,
        });
        if args.sweep {
            // The sweep is compared with the CPU render, which has no meshes: the preview is
            // captured as Render image captures it (full quality, no light markers).
            app.insert_resource(quality::FullQuality(true));
        }
        app.add_plugins(screenshot::plugin);
    }
    if let Some(path) = &args.compare {
        app.insert_resource(compare_cli::CompareRequest(path.clone()))
            .init_resource::<quality::FullQuality>()
            .add_plugins((compare::plugin, compare_cli::plugin));
    }
    Ok(())
}
