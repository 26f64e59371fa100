//! The preview's quality for slow hardware: it renders into an image of a fraction of the
//! window's pixels, which egui stretches over the window beneath its panels; a step multiplier
//! coarsens its sampling; adaptive quality lowers both while the camera moves; and it can be
//! turned off. The CPU render is never affected.

use super::live::{Backend, LiveView, OCCLUDER_LAYER};
use super::sharp::{GpuPlan, SharpCamera, SharpTarget};
use super::state::{MainCamera, View, VolumeBox};
use bevy::camera::RenderTarget;
use bevy::camera::visibility::RenderLayers;
use bevy::core_pipeline::prepass::DepthPrepass;
use bevy::prelude::*;
use bevy::render::render_resource::{TextureFormat, TextureUsages};
use bevy::window::PrimaryWindow;
use bevy_egui::{
    EguiContexts, EguiPrimaryContextPass, EguiTextureHandle, PrimaryEguiContext, egui,
};
use voxcast_core::tunables as t;

/// How the preview trades quality for speed (each documented in `voxcast_core::tunables`).
#[derive(Resource, Clone, PartialEq)]
pub struct PreviewSettings {
    pub enabled: bool,
    /// Who draws the volume: the GPU preview or the CPU live view.
    pub backend: Backend,
    /// The backend was chosen by the user (the command line), not from the adapter.
    pub backend_chosen: bool,
    pub scale: f32,
    pub step_multiplier: f32,
    pub adaptive: bool,
    pub moving_scale: f32,
    pub moving_step_multiplier: f32,
    /// What the preview shows: the picture (`None`) or what its rays cost, counted by the core
    /// (the CPU live view draws it, whichever backend draws the picture).
    pub cost_view: Option<voxcast_core::cost::CostView>,
}

/// Whether the GPU preview can read the depth prepass. WebGL2 cannot read a depth texture in a
/// shader (its GLSL has no fetch from one), so there the main camera has no depth prepass, the
/// preview is compiled without `DEPTH_PREPASS` (the shader def that turns the reading off) and
/// its rays pass through the scene's meshes, which are drawn over it; the CPU live view and
/// Render image still stop at them.
pub const GPU_READS_DEPTH: bool = !cfg!(all(target_arch = "wasm32", feature = "webgl2"));

impl Default for PreviewSettings {
    fn default() -> Self {
        Self {
            enabled: true,
            backend: Backend::Gpu,
            backend_chosen: false,
            scale: t::PREVIEW_SCALE.default,
            step_multiplier: t::PREVIEW_STEP_MULTIPLIER.default,
            adaptive: t::ADAPTIVE_QUALITY.default != 0.0,
            moving_scale: t::MOVING_SCALE.default,
            moving_step_multiplier: t::MOVING_STEP_MULTIPLIER.default,
            cost_view: None,
        }
    }
}

impl PreviewSettings {
    /// Whether the CPU live view draws the volume (the preview is on and drawn by the CPU, or
    /// shows a cost view: the core counts what each ray did).
    pub fn cpu_live(&self) -> bool {
        self.enabled && (self.backend == Backend::Cpu || self.cost_view.is_some())
    }

    /// Whether the GPU preview draws the volume (the preview is on, drawn by the GPU, and
    /// shows the picture).
    pub fn gpu_live(&self) -> bool {
        self.enabled && self.backend == Backend::Gpu && self.cost_view.is_none()
    }

    /// The resolution fraction and step multiplier in effect; `full` asks for the settings'
    /// own step at the resting resolution (while a comparison captures the preview).
    pub fn effective(&self, moving: bool, full: bool) -> (f32, f32) {
        if full {
            (self.scale, 1.0)
        } else if self.adaptive && moving {
            (
                self.moving_scale.min(self.scale),
                self.moving_step_multiplier.max(self.step_multiplier),
            )
        } else {
            (self.scale, self.step_multiplier)
        }
    }
}

/// The resolutions the preview drops to while moving, highest first: the measured frame time
/// picks one, so the image changes size only when the speed does.
const MOVING_LADDER: [f32; 9] = [1.0, 0.75, 0.5, 0.35, 0.25, 0.18, 0.125, 0.09, 0.05];

/// The resolution fraction for a moving frame: the highest on [`MOVING_LADDER`] whose volume
/// work (`per_work` seconds a pixel at step multiplier 1, `pixels` in the whole viewport,
/// `step` the moving step multiplier) fits in `share` seconds, within `[lowest, highest]`.
pub fn moving_scale_fit(
    per_work: f64,
    share: f64,
    pixels: f64,
    step: f32,
    lowest: f32,
    highest: f32,
) -> f32 {
    let full = per_work * pixels / f64::from(step.max(1e-3));
    let fit = (share / full).sqrt();
    let fit = if fit.is_finite() { fit as f32 } else { highest };
    MOVING_LADDER
        .iter()
        .copied()
        .find(|&s| s <= fit)
        .unwrap_or(lowest)
        .clamp(lowest.min(highest), highest)
}

/// The preview's quality controls, when the preview plugin is present.
#[derive(bevy::ecs::system::SystemParam)]
pub struct Quality<'w> {
    preview: Option<Res<'w, PreviewSettings>>,
    motion: Option<Res<'w, Motion>>,
    full: Option<Res<'w, FullQuality>>,
    /// The measured frame time, and the viewport's size, for the resolution while moving.
    progressive: Option<Res<'w, super::progressive::Progressive>>,
    viewport: Option<Res<'w, Viewport>>,
}

impl Quality<'_> {
    pub fn changed(&self) -> bool {
        self.preview.as_ref().is_some_and(|p| p.is_changed())
            || self.motion.as_ref().is_some_and(|m| m.is_changed())
            || self.full.as_ref().is_some_and(|f| f.is_changed())
    }

    /// While moving with adaptive quality: the resolution the measured frame time allows,
    /// never below `lowest` (the moving resolution `effective` gives) nor above the resting one
    /// (a GPU that draws the whole view within a frame's share keeps it, and the scene's meshes
    /// stay sharp).
    fn moving_scale(&self, p: &PreviewSettings, lowest: f32, step: f32) -> f32 {
        let fitted = self.progressive.as_ref().and_then(|pr| {
            let per_work = pr.cost.per_work?;
            let (_, size) = self.viewport.as_ref()?.physical();
            let pixels = f64::from(size.x) * f64::from(size.y);
            Some(moving_scale_fit(
                per_work,
                pr.cost.share(),
                pixels,
                step,
                lowest,
                p.scale,
            ))
        });
        fitted.unwrap_or(lowest)
    }

    /// The fraction of the window's pixels the main camera renders: the GPU preview's
    /// resolution, or 1 when the CPU draws the volume (the camera draws only spheres then).
    pub fn scale(&self) -> f32 {
        let moving = self.motion.as_ref().is_some_and(|m| m.moving);
        let full = self.full.as_ref().is_some_and(|f| f.0);
        self.preview.as_ref().map_or(1.0, |p| {
            let (scale, step) = p.effective(moving, full);
            if p.backend == Backend::Cpu {
                1.0
            } else if moving && p.adaptive && !full {
                self.moving_scale(p, scale, step)
            } else {
                scale
            }
        })
    }

    /// How many times longer the preview's step is than the settings' (1 without a preview).
    pub fn step_multiplier(&self) -> f32 {
        let moving = self.motion.as_ref().is_some_and(|m| m.moving);
        let full = self.full.as_ref().is_some_and(|f| f.0);
        self.preview
            .as_ref()
            .map_or(1.0, |p| p.effective(moving, full).1)
    }
}

/// Whether the view changed in the last moments.
#[derive(Resource, Default, Clone, Copy, PartialEq)]
pub struct Motion {
    pub moving: bool,
    last_change: f32,
}

/// How long after the last camera change the view counts as resting, seconds.
const REST_AFTER: f32 = 0.3;

/// Set while the preview must draw at full quality whatever the motion and step multiplier
/// (a comparison with the CPU render is capturing it).
#[derive(Resource, Default, Clone, Copy, PartialEq)]
pub struct FullQuality(pub bool);

/// The part of the window the scene is shown in: what the docked panels leave free (the
/// whole window before the panels are laid out, and without them). Logical points, as egui
/// lays out, and the window's pixels per point.
#[derive(Resource, Clone, Copy, Debug, PartialEq)]
pub struct Viewport {
    pub rect: egui::Rect,
    pub pixels_per_point: f32,
}

impl Viewport {
    /// The viewport in the window's physical pixels: top-left corner and size.
    pub fn physical(&self) -> (Vec2, UVec2) {
        let min = Vec2::new(self.rect.min.x, self.rect.min.y) * self.pixels_per_point;
        let size = Vec2::new(self.rect.width(), self.rect.height()) * self.pixels_per_point;
        (min, size.round().as_uvec2().max(UVec2::ONE))
    }

    /// The viewport in egui's points (the whole window when `viewport` is not known yet).
    pub fn rect(viewport: Option<&Viewport>, ctx: &egui::Context) -> egui::Rect {
        viewport.map_or(ctx.viewport_rect(), |v| v.rect)
    }

    /// The cursor in the viewport of `window` (physical pixels from its top-left corner, with
    /// the viewport's size), where the cursor is inside it.
    pub fn cursor(viewport: Option<&Viewport>, window: &Window) -> Option<(Vec2, UVec2)> {
        let (min, size) = Self::of(viewport, window);
        let cursor = window.physical_cursor_position()? - min;
        let inside = cursor.cmpge(Vec2::ZERO).all() && cursor.cmplt(size.as_vec2()).all();
        inside.then_some((cursor, size))
    }

    /// The viewport of `window` (its whole area when `viewport` is not known yet).
    pub fn of(viewport: Option<&Viewport>, window: &Window) -> (Vec2, UVec2) {
        match viewport {
            Some(v) => v.physical(),
            None => (
                Vec2::ZERO,
                UVec2::new(window.physical_width(), window.physical_height()).max(UVec2::ONE),
            ),
        }
    }
}

/// `size` pixels at `scale` of each edge, rounded, at least one pixel: the preview's target
/// and the CPU live view's resting frame for a resolution fraction.
pub fn scaled_size(size: UVec2, scale: f32) -> UVec2 {
    (size.as_vec2() * scale).round().as_uvec2().max(UVec2::ONE)
}

/// The image the main camera renders into, and its size in pixels.
#[derive(Resource)]
pub struct PreviewTarget {
    pub image: Handle<Image>,
    pub size: UVec2,
}

pub(super) fn plugin(app: &mut App) {
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
                super::progressive::give_camera_its_work,
            )
                .chain()
                .in_set(super::Frame::Show),
        )
        .add_systems(
            EguiPrimaryContextPass,
            paint_preview.in_set(super::Paint::Preview),
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
    render: Option<Res<super::state::RenderState>>,
    volume: Option<Res<super::state::VolumeState>>,
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
    render: Option<Res<'w, super::state::RenderState>>,
    inspect: Option<Res<'w, super::inspect::InspectSettings>>,
    progressive: Option<Res<'w, super::progressive::Progressive>>,
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
    let BackendChoice {
        settings,
        quality,
        render,
        inspect,
        progressive,
        live,
    } = choice;
    let cpu = settings.cpu_live();
    // With rays passing through geometry the CPU image has no spheres: the camera draws them.
    let through = render.is_some_and(|r| !r.depth_termination);
    // Below the window's resolution the CPU image has no spheres (they would be as coarse as
    // the image): the camera draws them over it, sharp (over the volume in front of them).
    let coarse = settings.scale < 1.0 || live.is_some_and(|l| l.coarse());
    let transparent = inspect.is_some_and(|i| i.shown && i.show_opacity);
    let plan = GpuPlan::for_scale(quality.scale());
    let (clear, layers, active) = if cpu {
        (
            ClearColorConfig::Custom(Color::NONE),
            if through || coarse {
                RenderLayers::from_layers(&[0, OCCLUDER_LAYER])
            } else {
                RenderLayers::layer(0)
            },
            // Nothing for it to draw: no pass at all (a software rasterizer pays for each).
            through || transparent || coarse,
        )
    } else {
        (
            if plan.transparent {
                ClearColorConfig::Custom(Color::NONE)
            } else {
                ClearColorConfig::Default
            },
            plan.preview_layers.clone(),
            true,
        )
    };
    // While strips refine, the last whole frame beneath them may be a coarse one, which needs
    // the meshes beneath it: drawn once as the refinement starts (the view rests; a software
    // rasterizer pays for every pass), kept while it lasts.
    let refining = progressive.is_some_and(|p| p.active());
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
    let wants = !cpu && GPU_READS_DEPTH && !through;
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

/// Paints the preview into the viewport, beneath every panel: the CPU live view's image and
/// its lines when the CPU draws the volume, then the main camera's image (with the CPU, only
/// spheres; at rest with a slow GPU, the progressive pass's images). Beneath a GPU preview drawn below full
/// resolution, the sharp camera's meshes, again beneath each new strip (a strip is
/// transparent where no volume is in front of them).
/// What the viewport is painted from: the preview's and the sharp camera's targets, where the
/// viewport is, and what the backend and the planner say is drawn.
#[derive(bevy::ecs::system::SystemParam)]
pub(super) struct PaintSources<'w> {
    target: Option<Res<'w, PreviewTarget>>,
    settings: Option<Res<'w, PreviewSettings>>,
    viewport: Option<Res<'w, Viewport>>,
    beneath: Res<'w, SharpBeneath>,
    sharp_target: Option<Res<'w, SharpTarget>>,
    progressive: Option<Res<'w, super::progressive::Progressive>>,
}

pub(super) fn paint_preview(
    mut contexts: EguiContexts,
    sources: PaintSources,
    mut live: Option<ResMut<LiveView>>,
    cameras: Query<&Camera, With<MainCamera>>,
    mut images: ResMut<Assets<Image>>,
    mut cpu_lines: Option<ResMut<super::cpu_lines::CpuLines>>,
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
            let (screen, uv) = super::progressive::strip_rects(rect, y0, y1);
            beneath(screen, uv);
            painter.image(id, screen, uv, egui::Color32::WHITE);
        }
    } else if camera_drew {
        beneath(rect, uv);
        painter.image(id, rect, uv, egui::Color32::WHITE);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fast GPU keeps the resting resolution while moving; a slow one drops as far as its
    /// measured speed needs, on the ladder, never below the moving resolution.
    #[test]
    fn the_moving_resolution_follows_the_measured_speed() {
        let pixels = 1280.0 * 720.0;
        // 1 ns a pixel: the whole view in under a millisecond.
        assert_eq!(moving_scale_fit(1e-9, 0.025, pixels, 2.0, 0.25, 1.0), 1.0);
        // 1.6 µs a pixel at step ×2: 0.74 s whole; 0.025 s allows √(0.025/0.74) ≈ 0.18.
        assert_eq!(
            moving_scale_fit(1.6e-6, 0.025, pixels, 2.0, 0.05, 1.0),
            0.18
        );
        assert_eq!(
            moving_scale_fit(1.6e-6, 0.025, pixels, 2.0, 0.25, 1.0),
            0.25
        );
        // Never above the resting resolution, whatever the speed.
        assert_eq!(moving_scale_fit(1e-12, 0.025, pixels, 2.0, 0.25, 0.5), 0.5);
        assert_eq!(moving_scale_fit(0.0, 0.025, pixels, 2.0, 0.25, 0.5), 0.5);
        assert_eq!(
            moving_scale_fit(f64::NAN, 0.025, pixels, 2.0, 0.25, 0.5),
            0.5
        );
    }
}
