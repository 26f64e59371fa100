//! The CPU live view: where the GPU is a software rasterizer (lavapipe, llvmpipe, WARP) the
//! volume is ray cast by the core on background threads instead of by the GPU preview, so the
//! window never waits for a volume frame. Each frame shows the newest finished image; a new one
//! is started as soon as the last is done: small while the view moves (sized from the measured
//! speed to take about a thirtieth of a second), then, at rest, twice as fine each time up to
//! the full resolution, which is the exact render (the same pixels as Render image). A
//! refinement is cancelled as soon as the view, the settings or the scene change.
//!
//! It also draws the preview's cost views, on either backend: the core's counts of what each
//! pixel's rays did (`voxcast_core::cost`), refined the same way, on the same fixed scale as
//! Render image's.
//!
//! The scene's opaque spheres (sample spheres, the light's marker) stop the rays as the GPU
//! preview's depth prepass does, and their flat colour shows through the volume in front of
//! them (`voxcast_core::render::render_layer`) — in an image at the window's resolution. In a
//! coarser one they would be blobs of its coarse pixels: there the rays pass them, and the main
//! camera draws them sharp over the image, as it draws gizmo lines and transparent meshes.

use crate::sandbox::shared::layers::Occluder;
use crate::sandbox::shared::quality::{Backend, PreviewSettings, scaled_size};
use crate::sandbox::shared::render_change::{Author, PreviewChange, PreviewChanges};
use crate::sandbox::shared::state::{RenderState, VolumeState};
use crate::sandbox::shared::tasks::in_slices;
use crate::sandbox::shared::viewport::Viewport;
use bevy::platform::time::Instant;
use bevy::prelude::*;
use bevy::tasks::{Task, futures::check_ready};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use voxcast_core::camera::Camera as CoreCamera;
use voxcast_core::cost::{CostView, render_cost_in};
use voxcast_core::image_out::to_u8;
use voxcast_core::rays::layered::SceneSurface;
use voxcast_core::render::{Job, Occluder as CoreOccluder, Surface, TileSlices, render_layer_in};
use voxcast_core::settings::RenderSettings;
use voxcast_core::trace::Scene;
use voxcast_core::transfer::TransferFunction;

/// The nice value of the live view's moving threads (Linux; 0 is the window's, 19 the lowest):
/// on a software rasterizer the window's drawing needs every core, and the frame waited on
/// the live view's thread (BENCHMARKS.md, "The window's own cost").
#[cfg(target_os = "linux")]
const LIVE_NICE: i32 = 19;

/// How long a frame's worth of CPU rendering may take while the view moves, seconds.
pub const MOVING_BUDGET_S: f64 = 1.0 / 30.0;

/// At rest, the full resolution is rendered at once when it would take at most this long at
/// the moving frames' speed, seconds (at rest every core renders, about twice as fast on two);
/// a slower one is approached by doubling the edges.
pub const REFINE_AT_ONCE_S: f64 = 1.0;

/// What a live frame shows: when any of it changes, the frame is out of date.
#[derive(Clone, PartialEq, Debug)]
pub struct LiveKey {
    pub camera: CoreCamera,
    pub settings: RenderSettings,
    pub transfer: TransferFunction,
    /// The volume's identity (a new load is a new volume even from the same file).
    pub volume: usize,
    pub occluders: Vec<CoreOccluder>,
    /// The resting resolution.
    pub full: UVec2,
    /// A cost view instead of the picture.
    pub cost_view: Option<CostView>,
    /// A ray density's scene, which the rays stop at.
    pub surface: Option<LiveSurface>,
}

/// A ray density's triangle scene in the live view: shared, compared by identity.
#[derive(Clone)]
pub struct LiveSurface {
    pub shown: Arc<crate::sandbox::data::source::Shown>,
    pub shading: voxcast_core::rays::layered::SceneShading,
}

impl std::fmt::Debug for LiveSurface {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "LiveSurface({:?})", self.shading)
    }
}

impl PartialEq for LiveSurface {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.shown, &other.shown) && self.shading == other.shading
    }
}

/// A finished frame: the image and what it shows.
pub struct LiveFrame {
    pub key: LiveKey,
    pub size: UVec2,
    /// Display values, row by row, opaque (the volume over the scene's spheres and the
    /// background).
    pub rgb: Vec<[u8; 3]>,
    pub seconds: f64,
    /// For a cost view: its scale in words (the counts' or the depth's), for the legend.
    pub legend: Option<String>,
}

impl LiveFrame {
    /// At the resting resolution: the exact render.
    pub fn full(&self) -> bool {
        self.size == self.key.full
    }
}

/// A render in flight.
struct LiveJob {
    task: Task<Option<LiveFrame>>,
    cancel: Arc<AtomicBool>,
    key: LiveKey,
    /// A refinement at rest (cancelled when the view changes) rather than a quick frame.
    refine: bool,
}

/// The CPU live view's state.
#[derive(Resource, Default)]
pub struct LiveView {
    job: Option<LiveJob>,
    /// The newest finished frame.
    pub shown: Option<LiveFrame>,
    /// Bumped for every new frame, so the texture is uploaded once per frame.
    pub generation: u64,
    /// Pixels per second of the last frames (each frame's, smoothed).
    pub rate: Option<f64>,
    /// The image painted (a Bevy image, rewritten in place: the frame that receives a new
    /// picture draws it), and the generation it holds.
    image: Option<(u64, Handle<Image>)>,
    /// What the previous frame showed: the same again means the view rests.
    last_key: Option<LiveKey>,
}

impl LiveView {
    /// What the live view shows, in words, for the panel.
    pub fn status(&self) -> String {
        let Some(f) = &self.shown else {
            return "rendering the first frame…".into();
        };
        let what = if f.full() && self.job.is_none() {
            if f.key.cost_view.is_some_and(CostView::is_depth) {
                "the exact depth"
            } else if f.key.cost_view.is_some() {
                "the exact counts"
            } else {
                "the exact render"
            }
        } else if self.job.as_ref().is_some_and(|j| j.refine) {
            "refining…"
        } else {
            "coarse while moving"
        };
        format!(
            "{}×{} in {}: {what}",
            f.size.x,
            f.size.y,
            voxcast_core::numbers::duration(f.seconds)
        )
    }

    fn cancel(&mut self) {
        if let Some(job) = self.job.take() {
            job.cancel.store(true, Ordering::Relaxed);
        }
    }

    /// The image to paint this frame: the newest frame, written into it now if it is new.
    /// (An egui texture made for each frame was drawn black in the frame it was made in, so
    /// each picture reached the screen a frame late.)
    pub fn image(&mut self, images: &mut Assets<Image>) -> Option<Handle<Image>> {
        let frame = self.shown.as_ref()?;
        let current = self.image.as_ref().map(|(g, _)| *g);
        if current != Some(self.generation) {
            let picture = frame_image(frame);
            let handle = match self.image.take() {
                Some((_, h)) if images.get(&h).is_some() => {
                    if let Some(mut old) = images.get_mut(&h) {
                        *old = picture;
                    }
                    h
                }
                _ => images.add(picture),
            };
            self.image = Some((self.generation, handle));
        }
        self.image.as_ref().map(|(_, h)| h.clone())
    }

    /// What the last frame showed (its view, settings and resting resolution), once one was.
    pub fn key(&self) -> Option<&LiveKey> {
        self.last_key.as_ref()
    }

    /// Whether the image on screen is below the resting resolution (a quick frame, or a
    /// refinement on its way): its spheres are not in it, the main camera draws them sharp.
    pub fn coarse(&self) -> bool {
        self.shown.as_ref().is_some_and(|f| !f.full())
    }

    /// Whether the window shows the exact render of the view the last frame was made for:
    /// at full resolution, nothing under way, and its texture painted.
    pub fn showing_exact(&self) -> bool {
        self.job.is_none()
            && self.shown.as_ref().is_some_and(|f| f.full())
            && self
                .image
                .as_ref()
                .is_some_and(|(g, _)| *g == self.generation)
    }
}

/// A frame's pixels as an image the window can draw (display values, opaque).
fn frame_image(frame: &LiveFrame) -> Image {
    let rgba: Vec<u8> = frame
        .rgb
        .iter()
        .flat_map(|&[r, g, b]| [r, g, b, 255])
        .collect();
    Image::new(
        bevy::render::render_resource::Extent3d {
            width: frame.size.x,
            height: frame.size.y,
            depth_or_array_layers: 1,
        },
        bevy::render::render_resource::TextureDimension::D2,
        rgba,
        bevy::render::render_resource::TextureFormat::Rgba8UnormSrgb,
        bevy::asset::RenderAssetUsages::RENDER_WORLD | bevy::asset::RenderAssetUsages::MAIN_WORLD,
    )
}

pub(crate) fn plugin(app: &mut App) {
    app.init_resource::<LiveView>()
        .add_message::<crate::sandbox::shared::pacing::KeepDrawing>()
        .add_systems(
            Update,
            choose_backend.in_set(crate::sandbox::shared::schedule::Frame::Input),
        )
        .add_systems(
            Update,
            keep_drawing_until_exact.in_set(crate::sandbox::shared::schedule::Frame::Show),
        )
        .add_systems(
            PostUpdate,
            drive_live_view.in_set(crate::sandbox::shared::schedule::Frame::Views),
        );
}

/// The window keeps drawing until the CPU live view shows the exact render of the view (its
/// frames arrive from tasks, and the exact one is painted a frame after it arrives).
fn keep_drawing_until_exact(
    live: Res<LiveView>,
    settings: Res<PreviewSettings>,
    mut keep: MessageWriter<crate::sandbox::shared::pacing::KeepDrawing>,
) {
    if settings.cpu_live() && !live.showing_exact() {
        keep.write(crate::sandbox::shared::pacing::KeepDrawing);
    }
}

/// The GPU could not run the preview (a shader it cannot compile, a pipeline it refuses): why.
#[derive(Resource, Clone, Debug)]
pub struct GpuFailed(pub String);

/// What the window does with a rendering error, where Bevy's own handler would quit: a shader
/// or pipeline the device refuses (a validation or internal error: the volume material on a
/// browser's WebGL2, a driver's bug) leaves the volume to the CPU live view, and the window
/// goes on; running out of memory or losing the device still ends it.
pub fn render_error_handler() -> bevy::render::error_handler::RenderErrorHandler {
    use bevy::render::error_handler::{ErrorType, RenderErrorPolicy};
    bevy::render::error_handler::RenderErrorHandler(|error, main, _| match error.ty {
        ErrorType::Validation | ErrorType::Internal => {
            if !main.contains_resource::<GpuFailed>() {
                // The line that says what failed, not the nesting around it.
                let what = error
                    .description
                    .lines()
                    .map(|l| l.trim().trim_matches('\0'))
                    .rfind(|l| !l.is_empty())
                    .unwrap_or("an error");
                main.insert_resource(GpuFailed(what.to_string()));
            }
            RenderErrorPolicy::Ignore
        }
        _ => {
            error!("the GPU failed ({:?}): {}", error.ty, error.description);
            main.write_message(AppExit::error());
            RenderErrorPolicy::StopRendering
        }
    })
}

/// Once the renderer is known: the CPU live view on a software rasterizer, unless the backend
/// was chosen on the command line; and whenever the GPU cannot run the preview.
fn choose_backend(
    adapter: Option<Res<bevy::render::renderer::RenderAdapterInfo>>,
    failed: Option<Res<GpuFailed>>,
    mut preview: PreviewChanges,
    mut done: Local<bool>,
) {
    let Some((now, chosen)) = preview
        .now
        .as_deref()
        .map(|p| (p.backend, p.backend_chosen))
    else {
        return;
    };
    if let Some(failed) = failed
        && now == Backend::Gpu
    {
        warn!(
            "the GPU cannot run the preview ({}): the CPU draws it",
            failed.0
        );
        preview.ask(Author::Adapter, PreviewChange::Backend(Backend::Cpu));
        #[cfg(target_arch = "wasm32")]
        crate::sandbox::shared::web::set_notice(&format!(
            "This browser's graphics could not run the GPU preview ({}): Voxcast's CPU core \
             draws the volume instead.",
            failed.0
        ));
    }
    if *done {
        return;
    }
    let Some(adapter) = adapter else { return };
    *done = true;
    #[cfg(target_arch = "wasm32")]
    let browser = crate::sandbox::shared::web::webgpu_adapter();
    #[cfg(not(target_arch = "wasm32"))]
    let browser = None;
    let (name, kind) = crate::sandbox::shared::quality::adapter_identity(
        &adapter.name,
        &format!("{:?}", adapter.device_type),
        browser.as_ref(),
    );
    #[cfg(target_arch = "wasm32")]
    crate::sandbox::shared::web::publish(|s| s.adapter = name.clone());
    if chosen {
        return;
    }
    let backend = Backend::for_adapter(&name, &kind);
    if backend != now {
        info!(
            "the preview renders on the {} ({})",
            if backend == Backend::Cpu {
                "CPU"
            } else {
                "GPU"
            },
            name
        );
        preview.ask(Author::Adapter, PreviewChange::Backend(backend));
        #[cfg(target_arch = "wasm32")]
        if backend == Backend::Cpu {
            crate::sandbox::shared::web::set_notice(
                "No graphics card here (the browser draws in software): Voxcast's CPU core \
                 draws the volume.",
            );
        }
    }
}

/// The scene's spheres that stop rays ([`Occluder`]: the virtual camera's samples, the light's
/// marker), with their materials.
#[derive(bevy::ecs::system::SystemParam)]
pub struct SceneSpheres<'w, 's> {
    spheres: Query<
        'w,
        's,
        (
            &'static GlobalTransform,
            &'static InheritedVisibility,
            &'static Occluder,
            &'static MeshMaterial3d<StandardMaterial>,
        ),
    >,
    materials: Res<'w, Assets<StandardMaterial>>,
}

impl SceneSpheres<'_, '_> {
    /// The opaque spheres, as the CPU sees them (none while rays pass through geometry).
    /// Transparent sample spheres do not stop the preview's rays: they are drawn over it.
    pub fn occluders(&self, render: &RenderState) -> Vec<CoreOccluder> {
        if !render.depth_termination {
            return Vec::new();
        }
        let mut out = Vec::new();
        for (gt, visible, sphere, material) in &self.spheres {
            let Some(m) = self.materials.get(&material.0) else {
                continue;
            };
            if visible.get() && m.alpha_mode == AlphaMode::Opaque {
                let c = m.base_color.to_srgba();
                out.push(CoreOccluder {
                    centre: gt.translation(),
                    radius: sphere.radius * gt.affine().matrix3.x_axis.length(),
                    color: Vec3::new(c.red, c.green, c.blue),
                });
            }
        }
        out
    }
}

/// Starts, keeps or cancels the live render, and takes in a finished one.
fn drive_live_view(
    mut live: ResMut<LiveView>,
    preview: Res<PreviewSettings>,
    screen: crate::sandbox::shared::viewport::SceneOnScreen,
    scene: LiveScene,
) {
    if !preview.cpu_live() {
        live.cancel();
        return;
    }
    // A finished frame first.
    if let Some(job) = &mut live.job
        && let Some(result) = check_ready(&mut job.task)
    {
        live.job = None;
        if let Some(frame) = result {
            let rate = (frame.size.x * frame.size.y) as f64 / frame.seconds.max(1e-6);
            live.rate = Some(live.rate.map_or(rate, |r| 0.5 * r + 0.5 * rate));
            live.shown = Some(frame);
            live.generation += 1;
        }
    }
    let (Ok(window), Ok(view)) = (screen.window.single(), screen.views.single()) else {
        return;
    };
    let (_, viewport_size) = Viewport::of(screen.viewport.as_deref(), window);
    let full = scaled_size(viewport_size, preview.scale);
    let key = scene.key(view.0, full, preview.cost_view);
    // The same view as in the previous frame: it rests.
    let resting = live.last_key.as_ref() == Some(&key);
    live.last_key = Some(key.clone());
    if let Some(job) = &live.job {
        if keeps_job(job, &key, resting) {
            return;
        }
        live.cancel();
    }
    let shown = live.shown.as_ref().filter(|f| f.key == key);
    if shown.is_some_and(|f| f.full()) {
        return; // the exact render is on screen
    }
    // A frame of this very view on screen, or the view resting since the last frame: refine.
    // Otherwise it moves (or was just changed): a quick frame.
    let size = match shown {
        _ if !preview.adaptive => full,
        Some(f) => refined_size(f.size, full, live.rate),
        None if resting => refined_size(quick_size(full, live.rate), full, live.rate),
        None => quick_size(full, live.rate),
    };
    let refine = shown.is_some() || resting || size == full;
    // Spheres are painted into an image only at the window's resolution; below it the main
    // camera draws them sharp over the image (`LiveView::coarse`).
    let spheres = size == full && preview.scale >= 1.0;
    let volume = scene.volume.volume.clone();
    live.job = Some(start(key, size, volume, refine, spheres));
}

/// What the live view renders: the volume with its render settings, the scene's spheres, and
/// the ray data's surface where one is shown.
#[derive(bevy::ecs::system::SystemParam)]
struct LiveScene<'w, 's> {
    volume: Res<'w, VolumeState>,
    render: Res<'w, RenderState>,
    spheres: SceneSpheres<'w, 's>,
    rays: Option<Res<'w, crate::sandbox::data::source::RayScene>>,
    choices: Option<Res<'w, crate::sandbox::data::choices::RayChoices>>,
}

impl LiveScene<'_, '_> {
    /// The frame of this scene seen by `camera` at `full` size, drawn as `cost_view`.
    fn key(&self, camera: CoreCamera, full: UVec2, cost_view: Option<CostView>) -> LiveKey {
        LiveKey {
            camera,
            settings: self.render.settings.clone(),
            transfer: self.render.transfer.clone(),
            volume: Arc::as_ptr(&self.volume.volume) as usize,
            occluders: self.spheres.occluders(&self.render),
            full,
            cost_view,
            surface: self
                .rays
                .as_ref()
                .and_then(|r| r.on_show(&self.volume))
                .map(|s| LiveSurface {
                    shown: s.clone(),
                    shading: self
                        .choices
                        .as_ref()
                        .map(|c| c.view.shading)
                        .unwrap_or_default(),
                }),
        }
    }
}

/// Whether the render in flight goes on: when it is of the current view, or a quick frame
/// while the view moves (done at once, and the next one follows the camera). A refinement of
/// another view is out of date, and so is a quick frame of a view the camera has left once
/// it rests: the resting view's own render starts now, not after it.
fn keeps_job(job: &LiveJob, key: &LiveKey, resting: bool) -> bool {
    job.key == *key || (!job.refine && !resting)
}

/// The next size at rest after a frame of `size`: the full resolution at once when it takes at
/// most [`REFINE_AT_ONCE_S`] at `rate` pixels a second, else twice the edges (so a slow
/// machine still sees the picture sharpen).
pub fn refined_size(size: UVec2, full: UVec2, rate: Option<f64>) -> UVec2 {
    let full_time = rate.map_or(f64::INFINITY, |r| (full.x as f64 * full.y as f64) / r);
    if full_time <= REFINE_AT_ONCE_S {
        full
    } else {
        (size * 2).min(full)
    }
}

/// The size of a frame that takes about [`MOVING_BUDGET_S`] at `rate` pixels a second (an
/// eighth of each edge before the first measurement), never above `full`.
pub fn quick_size(full: UVec2, rate: Option<f64>) -> UVec2 {
    let fraction = match rate {
        Some(r) => ((r * MOVING_BUDGET_S) / (full.x as f64 * full.y as f64))
            .sqrt()
            .clamp(0.05, 1.0),
        None => 0.125,
    };
    (full.as_dvec2() * fraction)
        .round()
        .as_uvec2()
        .clamp(UVec2::ONE, full)
}

/// Runs `draw` on the live view's threads: [`resting_pool`] for a refinement, else
/// [`moving_pool`]; in a browser, which gives the page one thread, on that one.
fn on_pool<R: Send>(refine: bool, draw: impl FnOnce() -> R + Send) -> R {
    #[cfg(target_arch = "wasm32")]
    return {
        let _ = refine;
        draw()
    };
    #[cfg(not(target_arch = "wasm32"))]
    if refine {
        resting_pool().install(draw)
    } else {
        moving_pool().install(draw)
    }
}

/// The live view's threads while the view moves: one core fewer than the machine has (at
/// least one), so the window's thread and the rasterizer keep a core for the next frame. At
/// rest the refinement takes more than every core ([`resting_pool`]): the exact render sooner.
#[cfg(not(target_arch = "wasm32"))]
fn moving_pool() -> &'static rayon::ThreadPool {
    static POOL: std::sync::OnceLock<rayon::ThreadPool> = std::sync::OnceLock::new();
    POOL.get_or_init(|| {
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        rayon::ThreadPoolBuilder::new()
            .num_threads(cores.saturating_sub(1).max(1))
            .thread_name(|i| format!("voxcast-live-{i}"))
            .start_handler(|_| yield_to_the_window())
            .build()
            .expect("a thread pool can be built")
    })
}

/// Lowers the calling thread's priority (Linux: its nice value, per thread) so the window's
/// threads — the frame, the rasterizer's — take a core first when they need it.
#[cfg(not(target_arch = "wasm32"))]
fn yield_to_the_window() {
    #[cfg(target_os = "linux")]
    // SAFETY: setpriority on the calling thread (who = 0) touches no memory.
    unsafe {
        libc::setpriority(libc::PRIO_PROCESS, 0, LIVE_NICE);
    }
}

/// The live view's threads at rest: two for each core, so the exact render gets most of
/// the machine while the window's own threads (the frame, the rasterizer) keep drawing, a
/// little slower for the moment it takes. (With one thread a core the window's frames took
/// one of two cores and the bunny's exact 1280×720 frame came 320–410 ms after the camera
/// stopped; with two, 235–310 ms: BENCHMARKS.md.)
#[cfg(not(target_arch = "wasm32"))]
fn resting_pool() -> &'static rayon::ThreadPool {
    static POOL: std::sync::OnceLock<rayon::ThreadPool> = std::sync::OnceLock::new();
    POOL.get_or_init(|| {
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        rayon::ThreadPoolBuilder::new()
            .num_threads(2 * cores)
            .thread_name(|i| format!("voxcast-exact-{i}"))
            .build()
            .expect("a thread pool can be built")
    })
}

/// Renders `key`'s view at its resting resolution as the live view renders its exact frame
/// (on the resting threads, `spheres` in the image or not), beside the live view: what
/// Measure times as the CPU live view's frame.
pub fn render_exact(
    key: LiveKey,
    volume: Arc<voxcast_core::Prepared>,
    spheres: bool,
) -> Task<Option<LiveFrame>> {
    let size = key.full;
    start(key, size, volume, true, spheres).task
}

/// Starts a render of `key`'s view at `size` (a refinement at rest, or a quick frame), with the
/// scene's spheres in the image or (`spheres` false) left to the main camera.
fn start(
    key: LiveKey,
    size: UVec2,
    volume: Arc<voxcast_core::Prepared>,
    refine: bool,
    spheres: bool,
) -> LiveJob {
    let cancel = Arc::new(AtomicBool::new(false));
    let flag = cancel.clone();
    let job_key = key.clone();
    let task = crate::sandbox::shared::tasks::spawn(async move {
        let started = Instant::now();
        let scene = Scene::new(
            &volume,
            &job_key.transfer,
            &job_key.settings,
            job_key.camera.forward(),
        )
        .ok()?;
        let triangles = job_key.surface.as_ref().map(|s| SceneSurface {
            triangles: &s.shown.computed.data.scene,
            origin: s.shown.computed.origin,
            shading: s.shading,
        });
        let hit = |ray: &voxcast_core::ray::Ray| triangles.and_then(|t| t.hit(ray));
        let job = Job {
            occluders: if spheres { &job_key.occluders } else { &[] },
            surface: triangles.is_some().then_some(&hit as Surface),
            ..Job::plain(&scene, &job_key.camera, (size.x, size.y), &|_, _| {}, &flag)
        };
        let set_up = started.elapsed().as_secs_f64();
        let mut tiles = TileSlices::default();
        let ((image, legend), busy) = match job_key.cost_view {
            None => {
                let ((layer, _), busy) =
                    in_slices(|d| on_pool(refine, || render_layer_in(&job, &mut tiles, d)))
                        .await
                        .ok()?;
                ((layer.over(job_key.settings.background), None), busy)
            }
            // The volume's rays only: the scene's spheres are no work of the march.
            Some(view) => {
                let (map, busy) =
                    in_slices(|d| on_pool(refine, || render_cost_in(&job, &mut tiles, d)))
                        .await
                        .ok()?;
                let legend = match view {
                    CostView::Stops => None,
                    CostView::Depth | CostView::DepthOfHits => {
                        map.depth_as(view).map(|d| d.scale_words())
                    }
                    _ => Some(voxcast_core::cost::scale_words(
                        map.full_scale,
                        map.max(view),
                    )),
                };
                ((map.image(view), legend), busy)
            }
        };
        let rgb = image.pixels.iter().map(|p| to_u8(*p)).collect();
        Some(LiveFrame {
            key: job_key,
            size,
            rgb,
            seconds: set_up + busy,
            legend,
        })
    });
    LiveJob {
        task,
        cancel,
        key,
        refine,
    }
}

#[cfg(test)]
mod tests;
