//! `voxcast --screenshot FILE`: the preview of exactly the view `voxcast render` would render,
//! drawn once into an image (no window), saved, and the program exits.
//!
//! Pipelines compile synchronously in this mode; the picture is taken after a few frames, once
//! the volume's textures are on the GPU.

use crate::sandbox::preview::camera::{InitialView, preview_camera};
use crate::sandbox::shared::quality::PreviewTarget;
use crate::sandbox::shared::render_change::{Author, Change, RenderChanges};
use crate::sandbox::shared::state::MainCamera;
use crate::sandbox::shared::state::View;
use bevy::camera::RenderTarget;
use bevy::prelude::*;
use bevy::render::render_resource::{PollType, TextureFormat, TextureUsages};
use bevy::render::renderer::RenderDevice;
use bevy::render::view::screenshot::{Screenshot, ScreenshotCaptured};
use bevy::render::{Render, RenderApp, RenderSystems};
use std::path::PathBuf;

use voxcast_core::settings::RenderSettings;

/// Where to save the screenshot and its size; with `sweep`, `path` is a folder that receives
/// one picture per combination of `voxcast_core::settings::agreement_cases`.
#[derive(Resource, Clone)]
pub struct Request {
    pub path: PathBuf,
    pub sweep: bool,
    /// Frames to time before the capture (0: none).
    pub time_frames: u32,
    /// Degrees the camera turns about the view's target each timed frame (0: resting).
    pub orbit_degrees: f32,
}

/// Frames drawn before the first capture (textures uploaded, pipelines ready).
pub(crate) const WARM_UP_FRAMES: u32 = 6;
/// Frames between a settings change and its capture.
const SETTLE_FRAMES: u32 = 3;

#[derive(Resource)]
struct Target(Handle<Image>);

/// The size of the image a headless preview camera renders into.
#[derive(Resource, Clone, Copy)]
pub struct ImageSize(pub u32, pub u32);

/// A preview camera drawing into an image of [`ImageSize`] (no window).
pub(crate) fn image_camera_plugin(app: &mut App) {
    app.add_systems(Startup, spawn_image_camera);
}

pub(crate) fn plugin(app: &mut App) {
    app.init_resource::<Saved>()
        .init_resource::<Timed>()
        .add_systems(
            Update,
            (take_screenshot, orbit_while_timed)
                .chain()
                .in_set(crate::sandbox::shared::schedule::Frame::Drive),
        );
    let timing = app.world().resource::<Request>().time_frames > 0;
    if let Some(render_app) = app.get_sub_app_mut(RenderApp).filter(|_| timing) {
        render_app.add_systems(Render, wait_for_gpu.in_set(RenderSystems::Cleanup));
    }
}

/// While frames are timed, each frame waits until the GPU has finished it: without a window
/// nothing else holds the app back, and a frame timed as its submission alone would say how
/// fast the CPU records commands, not how fast the GPU draws them.
fn wait_for_gpu(device: Res<RenderDevice>) {
    if let Err(e) = device.poll(PollType::wait_indefinitely()) {
        eprintln!("warning: waiting for the GPU: {e}");
    }
}

/// With `--auto-orbit`, turns the preview camera about the view's target while frames are
/// timed, so each timed frame draws a new view (full quality: nothing adapts offscreen).
fn orbit_while_timed(
    request: Res<Request>,
    timed: Res<Timed>,
    view: Res<InitialView>,
    mut views: Query<&mut View, With<MainCamera>>,
) {
    if request.orbit_degrees == 0.0 || timed.0.is_empty() || timed.done(&request) {
        return;
    }
    let turn = Quat::from_axis_angle(view.0.up.normalize(), request.orbit_degrees.to_radians());
    for mut view in &mut views {
        let target = view.0.target;
        view.0.eye = target + turn * (view.0.eye - target);
    }
}

fn spawn_image_camera(
    mut commands: Commands,
    mut images: ResMut<Assets<Image>>,
    size: Res<ImageSize>,
    view: Res<InitialView>,
    render: Res<crate::sandbox::shared::state::RenderState>,
) {
    let ImageSize(w, h) = *size;
    let mut image = Image::new_target_texture(w, h, TextureFormat::Rgba8UnormSrgb, None);
    image.texture_descriptor.usage |= TextureUsages::COPY_SRC;
    let handle = images.add(image);
    let camera = commands.spawn((
        preview_camera(&view.0),
        RenderTarget::Image(handle.clone().into()),
    ));
    crate::sandbox::preview::camera::with_depth(camera, render.depth_termination);
    commands.insert_resource(Target(handle.clone()));
    commands.insert_resource(PreviewTarget {
        image: handle,
        size: UVec2::new(w, h),
    });
}

/// The frames timed so far (`--time-frames`), seconds each.
#[derive(Resource, Default)]
struct Timed(Vec<f64>);

impl Timed {
    fn done(&self, request: &Request) -> bool {
        self.0.len() >= request.time_frames as usize
    }
}

/// The pictures to take: each file and the settings it is taken with (made on the first
/// frame that may take one).
type Plan = Option<Vec<(PathBuf, RenderSettings)>>;

/// What the screenshot is of and when it may be taken: the request, the image and its size,
/// the volume, and whether the cells' upload and the pipeline are done.
#[derive(bevy::ecs::system::SystemParam)]
struct Shot<'w> {
    request: Res<'w, Request>,
    target: Res<'w, Target>,
    size: Res<'w, ImageSize>,
    volume: Res<'w, crate::sandbox::shared::state::VolumeState>,
    cells: Res<'w, crate::sandbox::preview::sync::CellsUpload>,
    compiling: Res<'w, crate::sandbox::gpu::pipelines::Compiling>,
    time: Res<'w, Time<Real>>,
}

fn take_screenshot(
    mut commands: Commands,
    mut frames: Local<u32>,
    mut plan: Local<Plan>,
    mut timed: ResMut<Timed>,
    mut render: RenderChanges,
    shot: Shot,
) {
    let Shot {
        request,
        target,
        size,
        volume,
        cells,
        compiling,
        time,
    } = shot;
    if cells.pending() || compiling.now() {
        return; // the preview as it will be: cells uploaded, its pipeline compiled
    }
    let shots = plan.get_or_insert_with(|| {
        if request.sweep {
            voxcast_core::settings::agreement_cases(
                &render.now.settings,
                volume.volume.volume(),
                &render.now.transfer,
            )
            .into_iter()
            .map(|(name, s)| (request.path.join(format!("{name}.png")), s))
            .collect()
        } else {
            vec![(request.path.clone(), render.now.settings.clone())]
        }
    });
    if *frames >= WARM_UP_FRAMES && !timed.done(&request) {
        // Full quality: every frame draws the whole preview.
        timed.0.push(time.delta_secs_f64());
        if timed.done(&request) {
            print_timing(&timed.0, &request, &size);
        }
        return;
    }
    *frames += 1;
    // Shot i: its settings applied at frame start_i, captured SETTLE_FRAMES later.
    let Some(i) = frames
        .checked_sub(WARM_UP_FRAMES)
        .map(|f| (f / (SETTLE_FRAMES + 1)) as usize)
    else {
        return;
    };
    let phase = (*frames - WARM_UP_FRAMES) % (SETTLE_FRAMES + 1);
    let Some((path, settings)) = shots.get(i).cloned() else {
        return;
    };
    if phase == 0 && render.now.settings != settings {
        render.ask(Author::Screenshot, Change::Settings(Box::new(settings)));
    }
    if phase != SETTLE_FRAMES {
        return;
    }
    save_shot(&mut commands, target.0.clone(), path, shots.len());
}

/// Prints the median, fastest and slowest of the preview's full-quality frames.
fn print_timing(seconds: &[f64], request: &Request, size: &ImageSize) {
    let t = voxcast_core::trade::Timing::of(seconds);
    println!(
        "preview frame: median {:.1} ms, fastest {:.1} ms, slowest {:.1} ms over {} frames at \
         {}×{}, {}",
        t.median * 1000.0,
        t.fastest * 1000.0,
        t.slowest * 1000.0,
        seconds.len(),
        size.0,
        size.1,
        match request.orbit_degrees {
            0.0 => "resting".to_string(),
            d => format!("orbiting {d}° a frame"),
        }
    );
}

/// Captures `image` to `path` once it is drawn; the app exits once all `total` shots are
/// saved, or with an error on the first that cannot be.
fn save_shot(commands: &mut Commands, image: Handle<Image>, path: PathBuf, total: usize) {
    commands.spawn(Screenshot::image(image)).observe(
        move |captured: On<ScreenshotCaptured>,
              mut saved: ResMut<Saved>,
              mut exit: MessageWriter<AppExit>| {
            let result = captured
                .image
                .clone()
                .try_into_dynamic()
                .map_err(|e| e.to_string())
                .and_then(|img| img.to_rgb8().save(&path).map_err(|e| e.to_string()));
            if let Err(e) = result {
                eprintln!("error: cannot save {}: {e}", path.display());
                exit.write(AppExit::from_code(1));
                return;
            }
            println!("wrote {}", path.display());
            saved.0 += 1;
            if saved.0 == total {
                exit.write(AppExit::Success);
            }
        },
    );
}

/// How many pictures have been written.
#[derive(Resource, Default)]
struct Saved(usize);
