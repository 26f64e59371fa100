//! The window's app: the scene, its panels, the levels — each layer folder's plugin, in layer
//! order — and the drivers the command line asks for.

use super::args::SandboxArgs;
use super::engine::engine;
use crate::cli::CliError;
use crate::sandbox::data::choices;
use crate::sandbox::drivers::{self, measure, script};
use crate::sandbox::preview::camera::{InitialView, preview_camera, with_depth};
use crate::sandbox::preview::{live, progressive};
use crate::sandbox::scene::orbit::Orbit;
use crate::sandbox::shared::state::RenderState;
use crate::sandbox::shared::{fit, mode, platform, quality};
use crate::sandbox::{checks, data, gpu, inspect, levels, preview, scene, ui};
use bevy::diagnostic::FrameTimeDiagnosticsPlugin;
use bevy::prelude::*;
use bevy::window::WindowResolution;
use bevy_egui::EguiPlugin;
use voxcast_core::error::io_words;

/// The window: the scene, its panels, the levels; or a scripted play-through, or a
/// measurement of the frame time.
pub(super) fn build_window(
    app: &mut App,
    args: &SandboxArgs,
    render: &RenderState,
) -> Result<(), CliError> {
    platform::check_display()?;
    let window_size = args.size.unwrap_or(fit::DEFAULT_SIZE);
    engine(
        app,
        Some(Window {
            title: "Voxcast".into(),
            resolution: WindowResolution::new(window_size.0, window_size.1),
            // In a browser: the page's canvas, as large as the page gives it, keeping the
            // page's own handling of keys and the wheel away from it.
            #[cfg(target_arch = "wasm32")]
            canvas: Some(crate::sandbox::shared::web::CANVAS.into()),
            #[cfg(target_arch = "wasm32")]
            fit_canvas_to_parent: true,
            #[cfg(target_arch = "wasm32")]
            prevent_default_event_handling: true,
            ..default()
        }),
        args.play_levels.is_some(),
    );
    if args.size.is_none() && cfg!(not(target_arch = "wasm32")) {
        app.add_plugins(fit::plugin);
    }
    #[cfg(target_arch = "wasm32")]
    app.add_plugins((
        crate::sandbox::shared::web::plugin,
        crate::sandbox::shared::files::plugin,
    ));
    let free_play = mode::FreePlay(mode::Stage {
        rays: Some(args.rays),
        rays_shown: !args.no_rays,
        ..default()
    });
    app.insert_resource(live::render_error_handler())
        .add_plugins((EguiPlugin::default(), FrameTimeDiagnosticsPlugin::default()))
        .insert_resource(bevy_egui::EguiGlobalSettings {
            auto_create_primary_context: false,
            ..default()
        })
        .insert_resource(
            levels::Lessons::new(levels::ProgressStore::players())
                .with_added(args.levels.as_deref().map(levels::added_from_path)),
        )
        // Each layer's window features, in layer order (`tests/layers.rs`).
        .add_plugins((
            gpu::plugin,
            scene::plugin,
            inspect::plugin,
            data::plugin,
            preview::plugin,
            checks::plugin,
            levels::plugin,
            ui::plugin,
        ))
        .insert_resource(free_play)
        .insert_resource(free_play.0)
        .insert_resource(inspect::rays::InspectSettings {
            budget: args.sample_budget,
            ..default()
        })
        .insert_resource(levels::files::OpenLink(args.link.clone()))
        .add_systems(Startup, spawn_main_camera);
    if let Some(level) = &args.study {
        let added = args.levels.as_deref().map(levels::added_from_path);
        let all = levels::Lessons::new(levels::ProgressStore::Nowhere).with_added(added);
        let i = levels::level_named(&all.levels, level).map_err(CliError::usage)?;
        app.insert_resource(levels::StartStudy(Some(i)))
            .add_systems(
                Update,
                levels::start_study.in_set(crate::sandbox::shared::schedule::Frame::Drive),
            );
    }
    if let Some(dir) = &args.play_levels {
        std::fs::create_dir_all(dir)
            .map_err(|e| CliError::failed(format!("{}: {}", dir.display(), io_words(&e))))?;
        app.insert_resource(bevy::winit::WinitSettings::continuous())
            .insert_resource(
                levels::Lessons::new(levels::ProgressStore::File(dir.join("progress.json")))
                    .with_added(args.levels.as_deref().map(levels::added_from_path)),
            )
            .insert_resource(script::PlayLevels {
                dir: dir.clone(),
                added_only: args.levels.is_some(),
                range: args.play_range.clone(),
            })
            .add_plugins(script::plugin);
    }
    if let Some(knob) = args.measure_knob {
        // Draw every frame even without focus (a virtual display never gives it).
        app.insert_resource(bevy::winit::WinitSettings::continuous())
            .insert_resource(measure::KnobRequest(knob))
            .add_systems(
                Update,
                measure::measure_knob.in_set(crate::sandbox::shared::schedule::Frame::Drive),
            );
    }
    if let Some(frames) = args.measure_frames {
        // Draw every frame even without focus (a virtual display never gives it).
        app.insert_resource(bevy::winit::WinitSettings::continuous());
        app.add_plugins((measure::plugin, drivers::frame_parts::plugin))
            .insert_resource(measure::MeasureRequest {
                frames,
                orbit_degrees: args.auto_orbit,
                label: format!(
                    "{}×{} {} rays {}×{} {}, adaptive {}",
                    window_size.0,
                    window_size.1,
                    render.settings.method.name(),
                    args.rays,
                    args.rays,
                    if args.auto_orbit != 0.0 {
                        "orbiting"
                    } else {
                        "resting"
                    },
                    if args.no_adaptive { "off" } else { "on" }
                ),
            })
            .insert_resource(progressive::Progressive::whole_frames_only(
                args.whole_frames,
            ));
    }
    let mut choices = choices::RayChoices::default();
    choices.view.mesh = args.ray_view.iter().any(|v| v == "mesh");
    choices.view.field = args.ray_view.iter().any(|v| v == "field");
    if let Some(stride) = args.ray_stride {
        choices.view.stride = stride.max(1);
    }
    if let Some(cube) = args.ray_cube {
        choices.view.cube = cube.max(1);
    }
    if let Some(n) = args.ray_min_count {
        choices.view.min_count = n;
    }
    choices.view.glyphs = args.ray_glyphs;
    app.insert_resource(choices);
    app.insert_resource(quality::PreviewSettings {
        backend: match args.preview_backend.as_deref() {
            Some("cpu") => quality::Backend::Cpu,
            _ => quality::Backend::Gpu,
        },
        backend_chosen: args.preview_backend.is_some(),
        adaptive: !args.no_adaptive,
        scale: args
            .preview_scale
            .unwrap_or(voxcast_core::tunables::PREVIEW_SCALE.default),
        ..default()
    });
    Ok(())
}

fn spawn_main_camera(mut commands: Commands, view: Res<InitialView>, render: Res<RenderState>) {
    let v = view.0;
    let camera = commands.spawn((preview_camera(&v), Orbit::looking_at(v.eye, v.target, v.up)));
    with_depth(camera, render.depth_termination);
}
