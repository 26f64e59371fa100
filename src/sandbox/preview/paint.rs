//! The preview's quality for slow hardware: it renders into an image of a fraction of the
//! window's pixels, which egui stretches over the window beneath its panels; a step multiplier
//! coarsens its sampling; adaptive quality lowers both while the camera moves; and it can be
//! turned off. The CPU render is never affected.

use crate::sandbox::preview::live::LiveView;
use crate::sandbox::preview::quality::Quality;
use crate::sandbox::scene::sharp::{GpuPlan, SharpCamera, SharpTarget};
use crate::sandbox::shared::layers::OCCLUDER_LAYER;
use crate::sandbox::shared::quality::{
    FullQuality, GPU_READS_DEPTH, Motion, PreviewSettings, PreviewTarget, scaled_size,
};
use crate::sandbox::shared::state::{MainCamera, View, VolumeBox};
use crate::sandbox::shared::viewport::Viewport;
use bevy::camera::RenderTarget;
use bevy::camera::visibility::RenderLayers;
use bevy::core_pipeline::prepass::DepthPrepass;
use bevy::prelude::*;
use bevy::render::render_resource::{TextureFormat, TextureUsages};
use bevy::window::PrimaryWindow;
use bevy_egui::{
    EguiContexts, EguiPrimaryContextPass, EguiTextureHandle, PrimaryEguiContext, egui,
};

/// How long after the last camera change the view counts as resting, seconds.
const REST_AFTER: f32 = 0.3;

pub(crate) fn plugin(app: &mut App) {
    app.init_resource::<PreviewSettings>() // kept if already inserted (measurements)
        .init_resource::<Motion>()
        .init_resource::<FullQuality>()
        .init_resource::<SharpBeneath>()
        .add_systems(Startup, spawn_display_camera)
        .add_systems(
            Update,
            (
                track_motion,
                fit_preview_target,
                show_or_hide_volume,
                camera_for_backend,
                crate::sandbox::preview::progressive::give_camera_its_work,
            )
                .chain()
                .in_set(crate::sandbox::shared::schedule::Frame::Show),
        )
        .add_systems(
            EguiPrimaryContextPass,
            paint_preview.in_set(crate::sandbox::shared::schedule::Paint::Preview),
        );
}

/// The window's camera: draws nothing but egui, which paints the preview image first. No
/// multisampling, tonemapping or dithering: each would be one more full-screen pass, which a
/// software rasterizer pays for every frame (the preview's values are display values already).
fn spawn_display_camera(mut commands: Commands) {
    commands.spawn((
        Camera2d,
        Camera {
            order: 1,
            ..default()
        },
        Msaa::Off,
        bevy::core_pipeline::tonemapping::Tonemapping::None,
        bevy::core_pipeline::tonemapping::DebandDither::Disabled,
        PrimaryEguiContext,
    ));
}

/// The view counts as moving while it or the settings change (adaptive quality draws quick
/// frames then), and comes to rest [`REST_AFTER`] later.
fn track_motion(
    time: Res<Time>,
    views: Query<(), (With<MainCamera>, Changed<View>)>,
    render: Option<Res<crate::sandbox::shared::state::RenderState>>,
    volume: Option<Res<crate::sandbox::shared::state::VolumeState>>,
    mut motion: ResMut<Motion>,
) {
    let now = time.elapsed_secs();
    let settings_changed = render.is_some_and(|r| r.is_changed() && !r.is_added())
        || volume.is_some_and(|v| v.is_changed() && !v.is_added());
    if !views.is_empty() || settings_changed {
        motion.last_change = now;
    }
    let moving = now - motion.last_change < REST_AFTER;
    if motion.moving != moving {
        motion.moving = moving;
    }
}

/// Keeps the preview image at the effective fraction of the window's size.
fn fit_preview_target(
    mut commands: Commands,
    window: Query<&Window, With<PrimaryWindow>>,
    viewport: Option<Res<Viewport>>,
    quality: Quality,
    target: Option<Res<PreviewTarget>>,
    mut images: ResMut<Assets<Image>>,
    cameras: Query<Entity, With<MainCamera>>,
) {
    let Ok(window) = window.single() else { return };
    let scale = quality.scale();
    let (_, full) = Viewport::of(viewport.as_deref(), window);
    let size = scaled_size(full, scale);
    if target.as_ref().is_some_and(|t| t.size == size) {
        return;
    }
    let mut image = Image::new_target_texture(size.x, size.y, TextureFormat::Rgba8UnormSrgb, None);
    image.texture_descriptor.usage |= TextureUsages::COPY_SRC;
    let handle = images.add(image);
    for camera in &cameras {
        commands
            .entity(camera)
            .insert(RenderTarget::Image(handle.clone().into()));
    }
    commands.insert_resource(PreviewTarget {
        image: handle,
        size,
    });
}

fn show_or_hide_volume(
    settings: Res<PreviewSettings>,
    mut boxes: Query<&mut Visibility, With<VolumeBox>>,
) {
    for mut v in &mut boxes {
        let want = if settings.gpu_live() {
            Visibility::Inherited
        } else {
            Visibility::Hidden
        };
        if *v != want {
            *v = want;
        }
    }
}

/// Whether the sharp camera's image is painted beneath the preview, and whether the
/// progressive pass was refining last frame.
#[derive(Resource, Default)]
pub struct SharpBeneath {
    shown: bool,
    refining: bool,
}

/// The main camera, not the sharp camera beneath it.
type MainOnly = (With<MainCamera>, Without<SharpCamera>);

/// With the CPU drawing the volume, the main camera draws only what lies over it — the
/// transparent sample spheres — on a transparent background; the opaque spheres (on the
/// occluders' layer) are in the CPU's image when it has the window's resolution, else drawn
/// over it, sharp. With the GPU it draws everything at full resolution; below it, the volume
/// alone over the meshes the sharp camera draws (`sharp`). (Lines are egui's: `overlay`; a ray
/// density's line lists are meshes this camera draws with the GPU, and the CPU draws them
/// with the CPU live view: `cpu_lines`.) Only the GPU preview reads the depth prepass: with
/// the CPU the camera has none (a software rasterizer would draw every sphere twice).
/// What decides which camera draws the scene: the backend and its quality, the depth
/// termination, the inspection's meshes, the planner and the live view.
#[derive(bevy::ecs::system::SystemParam)]
struct BackendChoice<'w> {
    settings: Res<'w, PreviewSettings>,
    quality: Quality<'w>,
    render: Option<Res<'w, crate::sandbox::shared::state::RenderState>>,
    inspect: Option<Res<'w, crate::sandbox::inspect::rays::InspectSettings>>,
    progressive: Option<Res<'w, crate::sandbox::preview::progressive::Progressive>>,
    live: Option<Res<'w, LiveView>>,
}

fn camera_for_backend(
    mut commands: Commands,
    prepass: Query<(Entity, Has<DepthPrepass>), MainOnly>,
    choice: BackendChoice,
    mut cameras: Query<(&mut Camera, &mut RenderLayers), MainOnly>,
    mut sharp: Query<&mut Camera, With<SharpCamera>>,
    mut beneath: ResMut<SharpBeneath>,
) {
    let cpu = choice.settings.cpu_live();
    let plan = GpuPlan::for_scale(choice.quality.scale());
    let (clear, layers, active) = choice.main_camera(&plan);
    // While strips refine, the last whole frame beneath them may be a coarse one, which needs
    // the meshes beneath it: drawn once as the refinement starts (the view rests; a software
    // rasterizer pays for every pass), kept while it lasts.
    let refining = choice.progressive.as_ref().is_some_and(|p| p.active());
    let starts = refining && !beneath.refining;
    beneath.refining = refining;
    // (With the preview off the meshes are drawn the same way, the volume's box hidden.)
    beneath.shown = !cpu && (plan.sharp || refining);
    let sharp_active = !cpu && (plan.sharp || starts);
    for mut camera in &mut sharp {
        if camera.is_active != sharp_active {
            camera.is_active = sharp_active;
        }
    }
    // The GPU preview reads the prepass only to stop its rays at geometry.
    let wants = !cpu && GPU_READS_DEPTH && !choice.through();
    for (entity, has) in &prepass {
        if has != wants {
            match wants {
                false => commands.entity(entity).remove::<DepthPrepass>(),
                true => commands.entity(entity).insert(DepthPrepass),
            };
        }
    }
    for (mut camera, mut l) in &mut cameras {
        if camera.is_active != active {
            camera.is_active = active;
        }
        let same = match (&camera.clear_color, &clear) {
            (ClearColorConfig::Default, ClearColorConfig::Default) => true,
            (ClearColorConfig::Custom(a), ClearColorConfig::Custom(b)) => a == b,
            _ => false,
        };
        if !same {
            camera.clear_color = clear;
        }
        if *l != layers {
            *l = layers.clone();
        }
    }
}

impl BackendChoice<'_> {
    /// Whether rays pass through geometry: the CPU image has no spheres then.
    fn through(&self) -> bool {
        self.render.as_ref().is_some_and(|r| !r.depth_termination)
    }

    /// How the main camera draws: what it clears to, the layers it draws and whether it draws
    /// at all.
    fn main_camera(&self, plan: &GpuPlan) -> (ClearColorConfig, RenderLayers, bool) {
        if !self.settings.cpu_live() {
            let clear = if plan.transparent {
                ClearColorConfig::Custom(Color::NONE)
            } else {
                ClearColorConfig::Default
            };
            return (clear, plan.preview_layers.clone(), true);
        }
        let through = self.through();
        // Below the window's resolution the CPU image has no spheres (they would be as coarse
        // as the image): the camera draws them over it, sharp (over the volume in front of
        // them).
        let coarse = self.settings.scale < 1.0 || self.live.as_ref().is_some_and(|l| l.coarse());
        let transparent = self
            .inspect
            .as_ref()
            .is_some_and(|i| i.shown && i.show_opacity);
        let layers = if through || coarse {
            RenderLayers::from_layers(&[0, OCCLUDER_LAYER])
        } else {
            RenderLayers::layer(0)
        };
        // Nothing for it to draw: no pass at all (a software rasterizer pays for each).
        let active = through || transparent || coarse;
        (ClearColorConfig::Custom(Color::NONE), layers, active)
    }
}

/// Paints the preview into the viewport, beneath every panel: the CPU live view's image and
/// its lines when the CPU draws the volume, then the main camera's image (with the CPU, only
/// spheres; at rest with a slow GPU, the progressive pass's images). Beneath a GPU preview drawn below full
/// resolution, the sharp camera's meshes, again beneath each new strip (a strip is
/// transparent where no volume is in front of them).
/// What the viewport is painted from: the preview's and the sharp camera's targets, where the
/// viewport is, and what the backend and the planner say is drawn.
#[derive(bevy::ecs::system::SystemParam)]
pub(crate) struct PaintSources<'w> {
    target: Option<Res<'w, PreviewTarget>>,
    settings: Option<Res<'w, PreviewSettings>>,
    viewport: Option<Res<'w, Viewport>>,
    beneath: Res<'w, SharpBeneath>,
    sharp_target: Option<Res<'w, SharpTarget>>,
    progressive: Option<Res<'w, crate::sandbox::preview::progressive::Progressive>>,
}

pub(crate) fn paint_preview(
    mut contexts: EguiContexts,
    sources: PaintSources,
    mut live: Option<ResMut<LiveView>>,
    cameras: Query<&Camera, With<MainCamera>>,
    mut images: ResMut<Assets<Image>>,
    mut cpu_lines: Option<ResMut<crate::sandbox::data::cpu_lines::CpuLines>>,
) -> Result {
    let PaintSources {
        target,
        settings,
        viewport,
        beneath,
        sharp_target,
        progressive,
    } = sources;
    let Some(target) = target else { return Ok(()) };
    let camera_drew = cameras.iter().any(|c| c.is_active);
    let id = contexts.add_image(EguiTextureHandle::Weak(target.image.id()));
    let sharp_id = sharp_target
        .filter(|_| beneath.shown)
        .map(|t| contexts.add_image(EguiTextureHandle::Weak(t.image.id())));
    let ctx = contexts.ctx_mut()?.clone();
    let rect = Viewport::rect(viewport.as_deref(), &ctx);
    let uv = egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0));
    let painter = ctx.layer_painter(egui::LayerId::background());
    let cpu = settings.is_some_and(|s| s.cpu_live());
    if cpu && let Some(live_image) = live.as_mut().and_then(|l| l.image(&mut images)) {
        let live_id = contexts.add_image(EguiTextureHandle::Weak(live_image.id()));
        painter.image(live_id, rect, uv, egui::Color32::WHITE);
    }
    // A ray density's lines, drawn by the CPU at the viewport's resolution.
    if cpu
        && let Some((lines, [x0, y0, x1, y1])) =
            cpu_lines.as_mut().and_then(|l| l.image(&mut images))
    {
        let lines_id = contexts.add_image(EguiTextureHandle::Weak(lines.id()));
        let at = |fx: f32, fy: f32| rect.min + rect.size() * egui::vec2(fx, fy);
        let place = egui::Rect::from_min_max(at(x0, y0), at(x1, y1));
        painter.image(lines_id, place, uv, egui::Color32::WHITE);
    }
    let beneath = |screen: egui::Rect, uv: egui::Rect| {
        if let Some(sharp_id) = sharp_id {
            painter.image(sharp_id, screen, uv, egui::Color32::WHITE);
        }
    };
    if let Some(p) = progressive.filter(|p| p.active()) {
        for (image, y0, y1) in p.layers() {
            let id = contexts.add_image(EguiTextureHandle::Weak(image.id()));
            let (screen, uv) = crate::sandbox::preview::progressive::strip_rects(rect, y0, y1);
            beneath(screen, uv);
            painter.image(id, screen, uv, egui::Color32::WHITE);
        }
    } else if camera_drew {
        beneath(rect, uv);
        painter.image(id, rect, uv, egui::Color32::WHITE);
    }
    Ok(())
}
