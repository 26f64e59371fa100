//! The sandbox: a Bevy scene with the volume's live GPU preview, an orbit camera and the
//! settings panel; or, with `--screenshot`, one frame of the preview saved to a PNG.
//!
//! **Layers.** Each folder is a layer, and a file imports only from its own folder and the
//! folders below it (`tests/layers.rs` reads every file's paths and fails on an import that
//! runs upward or a circle of files). Bottom to top:
//!
//! 1. `shared/` — the state every feature reads: the volume and its settings, the frame's
//!    order, the preview's settings, the viewport and the mouse, render layers and markers
//!    (`Solid`, `Occluder`), the mode, background tasks, files, the page;
//! 2. `gpu/` — the preview's material, its uniform, the shaders, pipeline compilation;
//! 3. `scene/` — the orbit camera, lights, the crop box and clip plane, lattice, overlay lines,
//!    the meshes kept sharp;
//! 4. `inspect/` — the virtual camera, its rays and samples, skip blocks, the ray's breakdown;
//! 5. `data/` — loading volumes; RayVis's ray data sets and their views;
//! 6. `preview/` — the GPU preview and the CPU live view, their quality, the paint;
//! 7. `checks/` — Render image and Measure;
//! 8. `levels/` — the guided levels' logic;
//! 9. `drivers/` — screenshot, comparison, frame-time measurement and play-through runs;
//! 10. `ui/` — the panels.
//!
//! This file, on top of them all, builds the app. Features talk through components,
//! resources and messages. The frame's order is one enum, [`Frame`](shared::schedule::Frame)
//! (`shared/schedule.rs`: its sets in `Update`, then in `PostUpdate`), with
//! [`Paint`](shared::schedule::Paint) for the egui pass; every feature
//! puts its systems in those sets.

pub mod checks;
pub mod data;
pub mod drivers;
pub mod gpu;
pub mod inspect;
pub(crate) mod levels;
pub mod preview;
pub mod scene;
pub mod shared;
mod ui;

use crate::cli::CliError;
use crate::cli::args::{CameraArgs, SettingsArgs, VolumeArgs, parse_size};
use bevy::diagnostic::FrameTimeDiagnosticsPlugin;
use bevy::prelude::*;
use bevy::render::RenderPlugin;
use bevy::window::WindowResolution;
use bevy_egui::EguiPlugin;
use checks::{compare, trade};
use clap::Args;
use data::{choices, cpu_lines, estimate, loading, shortcuts, source, views};
use drivers::{compare_cli, measure, screenshot, script};
use gpu::material::VolumeMaterial;
use gpu::{pipelines, shaders};
use inspect::{blocks, breakdown, virtual_camera};
use preview::camera::{InitialView, preview_camera, with_depth};
use preview::{live, paint, progressive, sync};
use scene::orbit::Orbit;
use scene::{cut, lattice, light, overlay, sharp};
use shared::state::{RenderState, VolumeState};
use shared::{fit, mode, platform, quality, schedule};
use std::path::PathBuf;
use std::sync::Arc;
use voxcast_core::error::io_words;

/// Options of the sandbox itself (no subcommand).
#[derive(Args, Debug, Clone)]
pub struct SandboxArgs {
    #[command(flatten)]
    pub volume: VolumeArgs,
    #[command(flatten)]
    pub settings: SettingsArgs,
    #[command(flatten)]
    pub camera: CameraArgs,
    #[command(flatten)]
    pub cpu: crate::cli::args::CpuArgs,
    /// Render the preview of this view once, save it to this PNG and exit (no window needed).
    #[arg(long)]
    pub screenshot: Option<PathBuf>,
    /// With --screenshot DIR: one picture per method × step (1, ½ voxel) × shading (off, on),
    /// named like `accumulate_step0.5_shaded.png` (the GPU/CPU agreement test uses this).
    #[arg(long, requires = "screenshot")]
    pub sweep: bool,
    /// With --screenshot FILE: first time this many frames of the preview drawn at full
    /// quality and the full size (no window, so a frame is the volume's), print their median
    /// and then capture — a frame to set beside another renderer's offscreen frame.
    #[arg(long, requires = "screenshot", conflicts_with = "sweep")]
    pub time_frames: Option<u32>,
    /// Capture the preview of this view and render the same view on the CPU (what the "Render
    /// image" button does), save the render here, the capture and the difference heat-map
    /// beside it (NAME_preview.png, NAME_diff.png), print the differences and exit.
    #[arg(long, conflicts_with_all = ["screenshot", "measure_frames"])]
    pub compare: Option<PathBuf>,
    /// Measure the preview's frame time over this many frames (after a warm-up), print it and
    /// exit.
    #[arg(long, conflicts_with = "screenshot")]
    pub measure_frames: Option<u32>,
    /// With --measure-frames: orbit the camera this many degrees a frame (engages adaptive
    /// quality). With --time-frames: turn the offscreen view this much each timed frame (full
    /// quality; the picture is then taken where the orbit ends).
    #[arg(long, default_value_t = 0.0)]
    pub auto_orbit: f32,
    /// With --measure-frames: turn adaptive quality off.
    #[arg(long, requires = "measure_frames")]
    pub no_adaptive: bool,
    /// With --measure-frames: draw the GPU preview's resting view whole every frame, never in
    /// strips — the window waits for each full-quality frame, so its frame time is what one
    /// costs (to compare with another renderer's frame).
    #[arg(long, requires = "measure_frames")]
    pub whole_frames: bool,
    /// Measure this knob's trade as the "Speed against accuracy" panel's Measure does (a
    /// preview's knob timed as the preview's own images in this window), print its table and
    /// exit.
    #[arg(long, value_name = "KNOB", value_parser = parse_knob,
          conflicts_with_all = ["screenshot", "compare", "measure_frames", "play_levels"])]
    pub measure_knob: Option<voxcast_core::knob::Knob>,
    /// Let preview rays pass through scene geometry (the light's marker) instead of stopping
    /// at it (the depth prepass is ignored).
    #[arg(long)]
    pub no_depth_termination: bool,
    /// The virtual camera's pixels across and down (one ray each).
    #[arg(long, default_value_t = 4, value_parser = clap::value_parser!(u32).range(1..=64))]
    pub rays: u32,
    /// Start with the virtual camera, its rays and samples hidden (the preview alone; they can
    /// be shown from the panel).
    #[arg(long)]
    pub no_rays: bool,
    /// The most sample spheres shown for the virtual camera's rays (see the Rays panel).
    #[arg(long, default_value_t = voxcast_core::tunables::SAMPLE_BUDGET.default as usize)]
    pub sample_budget: usize,
    /// Play every level to the end in the window as a player would (with --levels, only the
    /// levels added), save a screenshot of each level's first step in this folder (with the
    /// progress file and report.txt) and exit; the exit code says whether every objective
    /// behaved.
    #[arg(long, conflicts_with_all = ["screenshot", "compare", "measure_frames"])]
    pub play_levels: Option<PathBuf>,
    /// Add the levels in this file, or in the .json files of this folder, to the levels list
    /// (after the built-in ones); a file with errors is left out and said why (`voxcast
    /// levels check PATH` prints every problem).
    #[arg(long, value_name = "PATH", conflicts_with_all = ["screenshot", "compare"])]
    pub levels: Option<PathBuf>,
    /// Play the level a link holds (the page's address with #level=…, as the level editor's
    /// Copy link makes it).
    #[arg(long, value_name = "URL", conflicts_with_all = ["screenshot", "compare", "play_levels"])]
    pub link: Option<String>,
    /// Start with this level (its id, as `voxcast answers` lists them, or its number in the
    /// levels list) as a study: played to its end with the preview off, then again with it on;
    /// each run's answers are kept with the run's name.
    #[arg(long, value_name = "LEVEL", conflicts_with_all = ["screenshot", "compare", "measure_frames", "play_levels"])]
    pub study: Option<String>,
    #[arg(long, help = voxcast_core::tunables::PREVIEW_SCALE.doc, value_parser = parse_preview_scale)]
    pub preview_scale: Option<f32>,
    #[arg(long, help = voxcast_core::tunables::PREVIEW_BACKEND.doc, value_parser = ["gpu", "cpu"])]
    pub preview_backend: Option<String>,
    /// Window or screenshot size in pixels (default 1280x720; without it, a window larger than
    /// the screen is made smaller to fit).
    #[arg(long, value_parser = parse_size)]
    pub size: Option<(u32, u32)>,
    /// With a ray density as the volume (`--volume density:…`): also draw its rays as lines
    /// (`mesh`) or its vector field (`field`); repeat for both.
    #[arg(long, value_parser = ["mesh", "field"])]
    pub ray_view: Vec<String>,
    #[arg(long, help = voxcast_core::tunables::RAY_STRIDE.doc)]
    pub ray_stride: Option<usize>,
    #[arg(long, help = voxcast_core::tunables::SAMPLE_CUBE.doc)]
    pub ray_cube: Option<u32>,
    #[arg(long, help = voxcast_core::tunables::FIELD_MIN_COUNT.doc)]
    pub ray_min_count: Option<u64>,
    /// With `--ray-view mesh`: mark each ray's start with a cross and its end with an
    /// arrowhead.
    #[arg(long)]
    pub ray_glyphs: bool,
}

/// What every sandbox starts with, from the command line.
struct Start {
    volume: VolumeState,
    render: RenderState,
    camera: voxcast_core::camera::Camera,
    rays: source::RayScene,
}

impl Start {
    fn from_args(args: &SandboxArgs) -> Result<Self, CliError> {
        // A ray density keeps what it was computed from, for RayVis's views.
        let never = std::sync::atomic::AtomicBool::new(false);
        let (loaded, computed) =
            match source::compute_source(&args.volume.volume, &|_, _| {}, &never) {
                Some(outcome) => {
                    let outcome = outcome.map_err(CliError::failed)?;
                    (outcome.loaded.into(), outcome.rays)
                }
                None => (args.volume.load()?, None),
            };
        let resolved = args.settings.resolve(&loaded)?;
        for note in &resolved.notes {
            eprintln!("note: {note}");
        }
        let camera = args.camera.camera(&loaded, resolved.preset.as_ref())?;
        let volume = VolumeState {
            volume: Arc::new(loaded.volume),
            source: args.volume.volume.clone(),
            preset: resolved.preset,
        };
        let rays = source::RayScene {
            current: computed.map(|computed| {
                Arc::new(source::Shown {
                    computed,
                    volume: volume.volume.clone(),
                })
            }),
            before: None,
        };
        Ok(Self {
            rays,
            volume,
            render: RenderState {
                transfer: resolved.transfer,
                settings: resolved.settings,
                depth_termination: !args.no_depth_termination,
            },
            camera,
        })
    }
}

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
        .add_plugins(shared::pacing::plugin)
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

/// The engine's plugins, with the log as the sandbox wants it and `window` as the primary one.
/// Threads of Bevy's `AsyncComputeTaskPool`, at least (Bevy gives a quarter of the cores, at
/// least one): a live view's frame waits there for its own threads, which yield to the
/// window's (`preview/live.rs`), so on two cores a second thread keeps the virtual camera's
/// rays, loads and Render image from queueing behind it.
const ASYNC_THREADS_MIN: usize = 2;

fn engine(app: &mut App, window: Option<Window>, synchronous: bool) {
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

/// The window: the scene, its panels, the levels; or a scripted play-through, or a
/// measurement of the frame time.
fn build_window(app: &mut App, args: &SandboxArgs, render: &RenderState) -> Result<(), CliError> {
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
            canvas: Some(shared::web::CANVAS.into()),
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
    app.add_plugins((shared::web::plugin, shared::files::plugin));
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
        .add_plugins((
            (paint::plugin, pipelines::window_plugin),
            ui::plugin,
            levels::plugin,
            breakdown::plugin,
            scene::orbit::plugin,
            compare::plugin,
            (light::plugin, cut::plugin),
            loading::plugin,
            virtual_camera::plugin,
            inspect::rays::plugin,
            trade::plugin,
            (lattice::plugin, blocks::plugin, inspect::cells::plugin),
            live::plugin,
            overlay::plugin,
            (
                progressive::plugin,
                sharp::plugin,
                choices::plugin,
                estimate::plugin,
                views::plugin,
                cpu_lines::plugin,
                shortcuts::plugin,
            ),
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
            .add_systems(Update, levels::start_study);
    }
    if let Some(dir) = &args.play_levels {
        std::fs::create_dir_all(dir)
            .map_err(|e| CliError::failed(format!("{}: {}", dir.display(), io_words(&e))))?;
        app.insert_resource(bevy::winit::WinitSettings::continuous())
            .insert_resource(
                levels::Lessons::new(levels::ProgressStore::File(dir.join("progress.json")))
                    .with_added(args.levels.as_deref().map(levels::added_from_path)),
            )
            .insert_resource(script::PlayLevels(dir.clone(), args.levels.is_some()))
            .add_plugins(script::plugin);
    }
    if let Some(knob) = args.measure_knob {
        // Draw every frame even without focus (a virtual display never gives it).
        app.insert_resource(bevy::winit::WinitSettings::continuous())
            .insert_resource(measure::KnobRequest(knob))
            .add_systems(Update, measure::measure_knob);
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

/// `--preview-scale`: a fraction within the tunable's range.
fn parse_knob(s: &str) -> Result<voxcast_core::knob::Knob, String> {
    use voxcast_core::knob::Knob;
    Knob::parse(s).ok_or_else(|| {
        let names: Vec<_> = Knob::ALL.iter().map(|k| k.name()).collect();
        format!("give one of {}", names.join(", "))
    })
}

fn parse_preview_scale(s: &str) -> Result<f32, String> {
    let t = &voxcast_core::tunables::PREVIEW_SCALE;
    match s.parse::<f32>() {
        Ok(v) if (t.min..=t.max).contains(&v) => Ok(v),
        _ => Err(format!("give a number from {} to {}", t.min, t.max)),
    }
}

fn spawn_main_camera(mut commands: Commands, view: Res<InitialView>, render: Res<RenderState>) {
    let v = view.0;
    let camera = commands.spawn((preview_camera(&v), Orbit::looking_at(v.eye, v.target, v.up)));
    with_depth(camera, render.depth_termination);
}

/// The sandbox in a browser: its options from the page's address, then [`run`].
#[cfg(target_arch = "wasm32")]
pub mod page {
    use super::{SandboxArgs, shared};

    /// The sandbox's options as the page's address gives them: `?volume=builtin:head&no-rays` is
    /// `--volume builtin:head --no-rays`, the same names as the command line's.
    #[derive(clap::Parser, Debug)]
    #[command(name = "voxcast", no_binary_name = true)]
    struct PageOptions {
        #[command(flatten)]
        sandbox: SandboxArgs,
    }

    /// Starts the sandbox in the page (the wasm module's `main`).
    pub fn run() {
        shared::web::take_fetched_volumes();
        let args = address_options();
        let options = match <PageOptions as clap::Parser>::try_parse_from(&args) {
            Ok(o) => o,
            Err(e) => {
                let text = e.to_string();
                shared::web::show_error(&format!(
                    "The page's address has options the sandbox does not know: {text}"
                ));
                return;
            }
        };
        if let Err(e) = super::run(&options.sandbox) {
            shared::web::show_error(&e.to_string());
        }
    }

    /// The page's query string as command-line options.
    fn address_options() -> Vec<String> {
        let Some(search) = web_sys::window().and_then(|w| w.location().search().ok()) else {
            return Vec::new();
        };
        crate::cli::args::query_to_args(&search, |s| {
            js_sys::decode_uri_component(s)
                .ok()
                .and_then(|v| v.as_string())
                .unwrap_or_else(|| s.to_owned())
        })
    }
}
