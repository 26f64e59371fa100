//! "Render image": the exact CPU render of the preview's current view — same camera, size and
//! settings — beside a capture of the preview itself, with their difference as a heat-map, the
//! mean and largest difference, and Save PNG.
//!
//! The render runs on Bevy's `AsyncComputeTaskPool` with a progress bar and Cancel, so the
//! window keeps drawing. The preview is captured at full quality (its resting resolution and the
//! settings' own step: see [`FullQuality`]) in the same frame as the view is taken for the CPU.

use crate::sandbox::shared::quality::{FullQuality, PreviewTarget, scaled_size};
use crate::sandbox::shared::state::{MainCamera, RenderState, View, VolumeState};
use crate::sandbox::shared::tasks::in_slices;
use bevy::prelude::*;
use bevy::render::gpu_readback::{Readback, ReadbackComplete};
use bevy::render::view::screenshot::{Screenshot, ScreenshotCaptured};
use bevy::tasks::{Task, futures::check_ready};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use voxcast_core::camera::Camera as CoreCamera;
use voxcast_core::cost::CostMap;
use voxcast_core::image_out::{ImageDiff, LinearImage};
use voxcast_core::render::{self, RenderStats, TileSlices};
use voxcast_core::settings::RenderSettings;
use voxcast_core::trace::Scene;
use voxcast_core::transfer::TransferFunction;

/// Frames the GPU preview draws at full quality before it is captured: the material's uniform
/// and the preview image's size follow a quality change within a frame; the rest is margin.
const SETTLE_FRAMES: u32 = 3;

/// The difference drawn at full intensity in the heat-map, as a fraction of the full range
/// (8/255: the agreement tolerance is 2/255, a quarter of the scale).
pub const HEAT_FULL_SCALE: f32 = 8.0 / 255.0;

/// The comparison's state: idle, settling, rendering, or showing a result.
#[derive(Resource, Default)]
pub struct Comparison {
    /// Frames left before capture; `Some` while a capture is requested.
    settling: Option<u32>,
    job: Option<Job>,
    /// The last finished comparison.
    pub result: Option<Compared>,
    /// Why the last request produced no result (cancelled, or an error).
    pub message: Option<String>,
    /// What Render image shows of the render: the picture (`None`) or what its rays cost.
    pub cost_view: Option<voxcast_core::cost::CostView>,
}

/// A render in flight and the preview capture it will be compared with.
struct Job {
    task: Task<Result<Rendered, String>>,
    /// Tiles done and tiles in all, written by the render's worker threads.
    progress: Arc<(AtomicUsize, AtomicUsize)>,
    cancel: Arc<AtomicBool>,
    /// The preview's capture once the GPU has delivered it (`Err` when there is none).
    gpu: Arc<Mutex<Option<Result<LinearImage, String>>>>,
    /// The CPU's image once it is finished (kept while the capture is still on its way).
    cpu: Option<Rendered>,
    snapshot: Snapshot,
}

/// What was rendered: compared with the current state to say when a result is out of date.
#[derive(Clone, PartialEq)]
pub struct Snapshot {
    pub camera: CoreCamera,
    pub size: UVec2,
    pub settings: RenderSettings,
    pub transfer: TransferFunction,
    /// The volume's source (`builtin:NAME` or a path).
    pub source: String,
    /// The preview compared was the CPU live view's image (else the GPU preview's capture).
    pub live: bool,
}

impl Snapshot {
    /// Whether this still describes what is on screen.
    pub fn is_current(
        &self,
        view: Option<&View>,
        render: &RenderState,
        volume: &VolumeState,
    ) -> bool {
        view.is_some_and(|v| v.0 == self.camera)
            && render.settings == self.settings
            && render.transfer == self.transfer
            && volume.source == self.source
    }
}

struct Rendered {
    image: LinearImage,
    stats: RenderStats,
    seconds: f64,
    /// What each pixel's rays cost (a second pass after the timed one).
    cost: Option<CostMap>,
}

/// A finished comparison.
pub struct Compared {
    pub cpu: LinearImage,
    /// The preview's capture, or why there is none (preview off, capture failed).
    pub gpu: Result<LinearImage, String>,
    /// Preview minus render, with its heat-map; `None` without a capture.
    pub diff: Option<(ImageDiff, LinearImage)>,
    pub stats: RenderStats,
    pub seconds: f64,
    /// What each pixel's rays cost (`voxcast_core::cost`).
    pub cost: Option<CostMap>,
    pub snapshot: Snapshot,
    /// Bumped for every new result, so views can tell when to re-upload their textures.
    pub generation: u64,
}

impl Comparison {
    /// Requests a comparison of the current view (ignored while one is under way).
    pub fn start(&mut self) {
        if !self.busy() {
            self.settling = Some(SETTLE_FRAMES);
            self.message = None;
        }
    }

    /// Cancels the render under way; the previous result stays.
    pub fn cancel(&mut self) {
        if let Some(job) = &self.job {
            job.cancel.store(true, Ordering::Relaxed);
        }
        self.settling = None;
    }

    pub fn busy(&self) -> bool {
        self.settling.is_some() || self.job.is_some()
    }

    /// `(tiles done, tiles in all)` of the render under way.
    pub fn progress(&self) -> Option<(usize, usize)> {
        let job = self.job.as_ref()?;
        let (done, total) = &*job.progress;
        Some((done.load(Ordering::Relaxed), total.load(Ordering::Relaxed)))
    }
}

impl Compared {
    fn new(
        cpu: Rendered,
        gpu: Result<LinearImage, String>,
        snapshot: Snapshot,
        generation: u64,
    ) -> Self {
        // Both sides as the 8-bit numbers a PNG would hold (the preview's target is 8-bit).
        let cpu_image = LinearImage::from_rgb8(&cpu.image.to_rgb8());
        let uniform = |img: &LinearImage| img.pixels.iter().all(|p| *p == img.pixels[0]);
        let gpu = gpu.and_then(|g| {
            if uniform(&g) && !uniform(&cpu_image) {
                Err(
                    "the preview had not drawn the volume yet (its shaders may still be \
                     compiling): render again"
                        .to_string(),
                )
            } else {
                Ok(g)
            }
        });
        let diff = gpu.as_ref().ok().and_then(|g| {
            let d = g.diff(&cpu_image)?;
            Some((d, g.diff_heatmap(&cpu_image, HEAT_FULL_SCALE)?))
        });
        let gpu = match (gpu, &diff) {
            (Ok(g), None) => Err(format!(
                "the capture is {}×{}, the render {}×{}",
                g.width, g.height, cpu_image.width, cpu_image.height
            )),
            (gpu, _) => gpu,
        };
        Self {
            cpu: cpu_image,
            gpu,
            diff,
            stats: cpu.stats,
            seconds: cpu.seconds,
            cost: cpu.cost,
            snapshot,
            generation,
        }
    }
}

/// `stem.png` → `stem_preview.png` (beside the render's file).
fn sibling(path: &Path, suffix: &str) -> PathBuf {
    let stem = path.file_stem().unwrap_or_default().to_string_lossy();
    path.with_file_name(format!("{stem}_{suffix}.png"))
}

/// One of the three images a comparison can save.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Part {
    /// The exact CPU render, saved as `NAME.png`.
    Render,
    /// The preview's capture, saved beside it as `NAME_preview.png`.
    Preview,
    /// The difference heat-map, saved beside it as `NAME_diff.png`.
    Difference,
}

impl Part {
    /// All three, in the order they are saved.
    pub const ALL: [Part; 3] = [Part::Preview, Part::Difference, Part::Render];

    /// What a button that saves this part says.
    pub fn label(self) -> &'static str {
        match self {
            Part::Render => "Save render PNG",
            Part::Preview => "Save preview PNG",
            Part::Difference => "Save difference PNG",
        }
    }
}

/// Writes one `part` of the comparison: the render to `path` (`.png` added when it has no
/// extension), the capture and the heat-map beside it as `NAME_preview.png` and
/// `NAME_diff.png`. Gives the file written, or `None` where the comparison has no such image
/// (the preview failed).
pub fn save_png(result: &Compared, path: &str, part: Part) -> Result<Option<PathBuf>, String> {
    let path = PathBuf::from(path.trim());
    if path.file_name().is_none() {
        return Err("give a file name ending in .png".into());
    }
    let path = if path.extension().is_none() {
        path.with_extension("png")
    } else {
        path
    };
    let (image, path) = match part {
        Part::Render => (Some(&result.cpu), path),
        Part::Preview => (result.gpu.as_ref().ok(), sibling(&path, "preview")),
        Part::Difference => (
            result.diff.as_ref().map(|(_, heat)| heat),
            sibling(&path, "diff"),
        ),
    };
    let Some(image) = image else {
        return Ok(None);
    };
    let bytes = image
        .png_bytes()
        .map_err(|e| format!("cannot save {}: {e}", path.display()))?;
    crate::sandbox::shared::files::save(&path, &bytes, "image/png")?;
    Ok(Some(path))
}

/// Writes every part the comparison has (see [`save_png`]); returns what was written.
pub fn save_pngs(result: &Compared, path: &str) -> Result<Vec<PathBuf>, String> {
    let mut written = vec![];
    for part in Part::ALL {
        written.extend(save_png(result, path, part)?);
    }
    Ok(written)
}

/// Opens (`true`) or closes the Render image window: written by whoever drives the sandbox
/// (the play-through script, as a player's click would), read by the window, which lies above.
#[derive(Message, Clone, Copy, Debug)]
pub struct ShowRenderImage(pub bool);

pub(crate) fn plugin(app: &mut App) {
    app.init_resource::<Comparison>()
        .add_message::<ShowRenderImage>()
        .add_systems(
            PostUpdate,
            (forget_on_new_scene, start_capture, collect_result)
                .chain()
                .in_set(crate::sandbox::shared::schedule::Frame::Views),
        );
}

/// A comparison belongs to the scene it was asked for: entering another level or free play
/// cancels one under way (else it would capture the new scene a few frames later) and forgets
/// the last result.
fn forget_on_new_scene(
    mode: Option<Res<State<crate::sandbox::shared::mode::Mode>>>,
    mut comparison: ResMut<Comparison>,
) {
    if mode.is_some_and(|m| m.is_changed() && !m.is_added()) {
        comparison.cancel();
        comparison.job = None; // dropping the task stops it
        comparison.result = None;
        comparison.message = None;
        comparison.cost_view = None;
    }
}

/// An 8-bit RGBA texture read back from the GPU (`data`, rows padded to the copy alignment) as
/// an image of `size`.
pub fn image_from_rows(data: &[u8], size: UVec2) -> Result<LinearImage, String> {
    let (w, h) = (size.x as usize, size.y as usize);
    let stride = data.len().checked_div(h).unwrap_or(0);
    if h == 0 || stride < w * 4 {
        return Err(format!(
            "the preview's read-back holds {} bytes, too few for {w}×{h}",
            data.len()
        ));
    }
    let mut rgb = image::RgbImage::new(size.x, size.y);
    for (y, row) in data.chunks_exact(stride).take(h).enumerate() {
        for (x, px) in row[..w * 4].chunks_exact(4).enumerate() {
            rgb.put_pixel(x as u32, y as u32, image::Rgb([px[0], px[1], px[2]]));
        }
    }
    Ok(LinearImage::from_rgb8(&rgb))
}

/// What a capture waits for: the preview's target, its volume shown, its backend's settings,
/// the progressive planner and the pipeline's compilation.
#[derive(bevy::ecs::system::SystemParam)]
struct PreviewReady<'w, 's> {
    target: Option<Res<'w, PreviewTarget>>,
    preview_visible:
        Query<'w, 's, &'static Visibility, With<crate::sandbox::shared::state::VolumeBox>>,
    preview: Option<Res<'w, crate::sandbox::shared::quality::PreviewSettings>>,
    progressive: Option<Res<'w, crate::sandbox::preview::progressive::Progressive>>,
    compiling: Res<'w, crate::sandbox::gpu::pipelines::Compiling>,
}

/// Where the preview's capture arrives (`Err` where there is none).
type Capture = Arc<Mutex<Option<Result<LinearImage, String>>>>;

/// Counts the settle frames down, then captures the preview and starts the CPU render of the
/// same view in the same frame.
fn start_capture(
    mut commands: Commands,
    mut comparison: ResMut<Comparison>,
    mut full: ResMut<FullQuality>,
    views: Query<&View, With<MainCamera>>,
    state: Res<VolumeState>,
    render_state: Res<RenderState>,
    ready: PreviewReady,
) {
    let cpu_live = ready.preview.as_ref().is_some_and(|p| p.cpu_live());
    if !settled(&mut comparison, &mut full, &ready, cpu_live) {
        return;
    }
    comparison.settling = None;
    let (Some(target), Ok(view)) = (ready.target.as_deref(), views.single()) else {
        comparison.message = Some("no preview view to compare with yet".into());
        full.0 = false;
        return;
    };
    // The CPU live view rests at the preview's resolution of the window (the main camera's
    // target, then, is the whole window: its lines are drawn sharp).
    let live_scale = ready.preview.as_ref().filter(|_| cpu_live).map(|p| p.scale);
    let size = live_scale.map_or(target.size, |scale| scaled_size(target.size, scale));
    let snapshot = Snapshot {
        live: cpu_live,
        camera: view.0,
        size,
        settings: render_state.settings.clone(),
        transfer: render_state.transfer.clone(),
        source: state.source.clone(),
    };
    let gpu = Capture::default();
    if cpu_live {
        // The CPU live view is compared as it draws this view at rest (the job renders it,
        // without the scene's spheres, which the render has not either).
        if full.0 {
            full.0 = false;
        }
    } else {
        capture_preview(&mut commands, &mut full, target, &ready, gpu.clone());
    }
    comparison.job = Some(start_render(state.volume.clone(), snapshot, gpu, cpu_live));
}

/// Whether the preview can be captured this frame; until then it is asked for at full
/// quality, its pipeline compiled and its settle frames counted down (the CPU live view's
/// capture is rendered by the job itself: nothing to wait for).
fn settled(
    comparison: &mut ResMut<Comparison>,
    full: &mut ResMut<FullQuality>,
    ready: &PreviewReady,
    cpu_live: bool,
) -> bool {
    let Some(left) = comparison.settling else {
        // Cancelled while settling: nothing will be captured, so nothing else resets it.
        if full.0 && comparison.job.is_none() {
            full.0 = false;
        }
        return false;
    };
    if !full.0 && !cpu_live {
        full.0 = true;
    }
    if ready.compiling.now() && !cpu_live {
        // The GPU preview for these settings is not drawn until its pipeline is ready.
        return false;
    }
    // On a software renderer, three frames of the page are half a second: the CPU live view
    // has no settle frames.
    if left > 0 && !cpu_live {
        comparison.settling = Some(left - 1);
        return false;
    }
    // A GPU preview drawn in strips is captured once a full-quality pass has finished, from
    // that pass's image: the window goes on answering meanwhile (settling stays at zero until
    // then).
    let strips = ready
        .progressive
        .as_deref()
        .filter(|p| !cpu_live && p.active());
    strips.is_none_or(|p| p.finished_full_image().is_some())
}

/// Captures the GPU preview into `slot`: a finished full-quality pass read back where the
/// preview is drawn in strips (a screenshot captures only what a camera draws this frame, and
/// none draws that pass's image now), else a screenshot of its target; that the preview is
/// off where it is.
fn capture_preview(
    commands: &mut Commands,
    full: &mut ResMut<FullQuality>,
    target: &PreviewTarget,
    ready: &PreviewReady,
    slot: Capture,
) {
    let previewing = ready
        .preview_visible
        .iter()
        .any(|v| *v != Visibility::Hidden);
    let finished_pass = ready
        .progressive
        .as_deref()
        .filter(|p| p.active())
        .and_then(|p| p.finished_full_image());
    match finished_pass {
        Some(pass) if previewing => {
            let size = target.size;
            commands.spawn(Readback::texture(pass)).observe(
                move |done: On<ReadbackComplete>,
                      mut full: ResMut<FullQuality>,
                      mut commands: Commands| {
                    if let Ok(mut s) = slot.lock() {
                        *s = Some(image_from_rows(&done.data, size));
                    }
                    full.0 = false;
                    commands.entity(done.entity).despawn(); // else it reads back every frame
                },
            );
        }
        _ if previewing => {
            commands
                .spawn(Screenshot::image(target.image.clone()))
                .observe(
                    move |captured: On<ScreenshotCaptured>, mut full: ResMut<FullQuality>| {
                        let image = captured
                            .image
                            .clone()
                            .try_into_dynamic()
                            .map(|img| LinearImage::from_rgb8(&img.to_rgb8()))
                            .map_err(|e| format!("the preview could not be read back: {e}"));
                        if let Ok(mut s) = slot.lock() {
                            *s = Some(image);
                        }
                        full.0 = false;
                    },
                );
        }
        _ => {
            if let Ok(mut s) = slot.lock() {
                *s = Some(Err("the preview is off".into()));
            }
            full.0 = false;
        }
    }
}

/// Starts the exact CPU render of `snapshot` (and, for the CPU live view, its capture: the
/// same view at rest, into `gpu`), with its progress and Cancel.
fn start_render(
    volume: Arc<voxcast_core::Prepared>,
    snapshot: Snapshot,
    gpu: Capture,
    cpu_live: bool,
) -> Job {
    let progress = Arc::new((AtomicUsize::new(0), AtomicUsize::new(0)));
    let cancel = Arc::new(AtomicBool::new(false));
    // The worker's own handles on the snapshot, the progress, Cancel and the capture.
    let (s, worker_progress, worker_cancel, live_slot) = (
        snapshot.clone(),
        progress.clone(),
        cancel.clone(),
        gpu.clone(),
    );
    let task = crate::sandbox::shared::tasks::spawn(async move {
        let scene = Scene::new(&volume, &s.transfer, &s.settings, s.camera.forward())
            .map_err(|e| e.to_string())?;
        let report = |done: usize, total: usize| {
            worker_progress.0.store(done, Ordering::Relaxed);
            worker_progress.1.store(total, Ordering::Relaxed);
        };
        let cancelled = |_| "cancelled".to_string();
        let size = (s.size.x, s.size.y);
        let job = render::Job::plain(&scene, &s.camera, size, &report, &worker_cancel);
        // The picture and its cost view's counts from one march; its time is the render's
        // own (what its samples a second divide by): not the CPU live view's capture below,
        // which the rate once wrongly counted in.
        let mut tiles = TileSlices::default();
        let ((image, stats, cost), seconds) =
            in_slices(|d| voxcast_core::cost::render_with_cost_in(&job, &mut tiles, d))
                .await
                .map_err(cancelled)?;
        if cpu_live {
            // The live view draws the layer over the background: with one ray a pixel, that is
            // the render bit for bit (voxcast_core's tests/layer.rs), so it is not marched
            // again; with several, the two average in different orders (within 1/255).
            let live = if s.settings.supersampling <= 1 {
                image.clone()
            } else {
                let quiet = render::Job {
                    progress: &|_, _| {},
                    ..job
                };
                let mut tiles = TileSlices::default();
                let ((layer, _), _) = in_slices(|d| render::render_layer_in(&quiet, &mut tiles, d))
                    .await
                    .map_err(cancelled)?;
                layer.over(s.settings.background)
            };
            if let Ok(mut slot) = live_slot.lock() {
                *slot = Some(Ok(LinearImage::from_rgb8(&live.to_rgb8())));
            }
        }
        Ok(Rendered {
            image,
            stats,
            seconds,
            cost: Some(cost),
        })
    });
    Job {
        task,
        progress,
        cancel,
        gpu,
        cpu: None,
        snapshot,
    }
}

/// Picks up the finished render and the capture, and builds the comparison.
fn collect_result(mut comparison: ResMut<Comparison>, mut generation: Local<u64>) {
    let Some(job) = comparison.job.as_mut() else {
        return;
    };
    if job.cpu.is_none() {
        match check_ready(&mut job.task) {
            None => return,
            Some(Err(e)) => {
                comparison.job = None;
                comparison.message = Some(e);
                return;
            }
            Some(Ok(rendered)) => job.cpu = Some(rendered),
        }
    }
    let Some(gpu) = job.gpu.lock().ok().and_then(|mut s| s.take()) else {
        return; // the capture is still on its way back from the GPU
    };
    let Some(job) = comparison.job.take() else {
        return;
    };
    let Some(cpu) = job.cpu else { return };
    *generation += 1;
    comparison.result = Some(Compared::new(cpu, gpu, job.snapshot, *generation));
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use glam::Vec3;

    /// A finished comparison as the window shows it: with a capture compared, or without one.
    pub(crate) fn example(capture: bool) -> Compared {
        let mut cpu = image(4, 3, 0.5);
        cpu.pixels[5] = Vec3::splat(0.25);
        let gpu = if capture {
            Ok(image(4, 3, 0.5))
        } else {
            Err("the preview is off".into())
        };
        let mut done = rendered(cpu);
        done.seconds = 0.123_456;
        done.stats.rays = 12;
        done.stats.capped = 3; // the sample cap's warning is drawn too
        done.cost = Some(CostMap {
            width: 4,
            height: 3,
            rays_per_pixel: 1,
            pixels: vec![[3, 9, 1, 0, 1]; 12],
            stats: done.stats,
            full_scale: 16,
            depth: None,
            background: Vec3::ZERO,
        });
        Compared::new(done, gpu, snapshot(), 1)
    }

    fn image(w: u32, h: u32, v: f32) -> LinearImage {
        let mut img = LinearImage::new(w, h);
        img.pixels.fill(Vec3::splat(v));
        img
    }

    fn snapshot() -> Snapshot {
        Snapshot {
            camera: CoreCamera::framing(Vec3::ZERO, Vec3::ONE, Vec3::Z, Vec3::Y).unwrap(),
            size: UVec2::new(4, 3),
            settings: RenderSettings::default(),
            transfer: TransferFunction::ramp(0.0, 1.0, 0.5).unwrap(),
            source: "builtin:bunny".into(),
            live: false,
        }
    }

    fn rendered(img: LinearImage) -> Rendered {
        Rendered {
            image: img,
            stats: RenderStats::default(),
            seconds: 0.0,
            cost: None,
        }
    }

    #[test]
    fn measures_the_difference_in_8_bit_steps() {
        let cpu = rendered(image(4, 3, 0.5));
        let gpu = image(4, 3, 129.0 / 255.0); // 0.5 is stored as 128
        let c = Compared::new(cpu, Ok(gpu), snapshot(), 1);
        let (d, heat) = c.diff.unwrap();
        assert!(
            (d.max_abs * 255.0 - 1.0).abs() < 1e-4,
            "{}",
            d.max_abs * 255.0
        );
        assert_eq!((heat.width, heat.height), (4, 3));
    }

    #[test]
    fn a_missing_or_mismatched_capture_is_reported_not_compared() {
        let c = Compared::new(
            rendered(image(4, 3, 0.5)),
            Err("the preview is off".into()),
            snapshot(),
            1,
        );
        assert!(c.diff.is_none());
        assert_eq!(c.gpu.unwrap_err(), "the preview is off");
        let c = Compared::new(
            rendered(image(4, 3, 0.5)),
            Ok(image(5, 3, 0.5)),
            snapshot(),
            2,
        );
        assert!(c.diff.is_none());
        assert!(c.gpu.unwrap_err().contains("5×3"));
    }

    #[test]
    fn read_back_rows_lose_their_padding() {
        // 3×2 pixels, rows padded to 16 bytes.
        let mut data = vec![0u8; 32];
        for y in 0..2usize {
            for x in 0..3usize {
                let i = y * 16 + x * 4;
                data[i..i + 4].copy_from_slice(&[(10 * x + y) as u8, 7, 200, 255]);
            }
            data[y * 16 + 12] = 99; // padding, ignored
        }
        let img = image_from_rows(&data, UVec2::new(3, 2)).unwrap();
        let rgb = img.to_rgb8();
        assert_eq!(rgb.get_pixel(2, 1).0, [21, 7, 200]);
        assert_eq!(rgb.get_pixel(0, 0).0, [0, 7, 200]);
        assert!(image_from_rows(&data[..8], UVec2::new(3, 2)).is_err());
        assert!(image_from_rows(&[], UVec2::new(3, 0)).is_err());
    }

    #[test]
    fn a_blank_capture_of_a_visible_volume_is_not_compared() {
        let mut cpu = image(4, 3, 0.0);
        cpu.pixels[5] = Vec3::splat(0.5);
        let c = Compared::new(rendered(cpu.clone()), Ok(image(4, 3, 0.0)), snapshot(), 1);
        assert!(c.gpu.unwrap_err().contains("not drawn"));
        // A blank render is compared with a blank capture as usual.
        let c = Compared::new(
            rendered(image(4, 3, 0.0)),
            Ok(image(4, 3, 0.0)),
            snapshot(),
            1,
        );
        assert_eq!(c.diff.unwrap().0.max_abs, 0.0);
    }

    #[test]
    fn saves_the_three_pictures_side_by_side() {
        let dir = std::env::temp_dir().join(format!("voxcast-compare-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let c = Compared::new(
            rendered(image(4, 3, 0.5)),
            Ok(image(4, 3, 0.5)),
            snapshot(),
            1,
        );
        let written = save_pngs(&c, dir.join("r").to_str().unwrap()).unwrap();
        let names: Vec<_> = written
            .iter()
            .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
            .collect();
        assert_eq!(names, ["r_preview.png", "r_diff.png", "r.png"]);
        assert!(written.iter().all(|p| p.exists()));
        let err = save_pngs(&c, dir.join("missing/r.png").to_str().unwrap()).unwrap_err();
        assert!(err.contains("missing"), "{err}");
        assert!(save_pngs(&c, "  ").is_err());
        // One part at a time (the page's buttons); a failed preview has no image to save.
        let one = save_png(&c, dir.join("one").to_str().unwrap(), Part::Difference).unwrap();
        assert_eq!(one, Some(dir.join("one_diff.png")));
        let failed = Compared::new(
            rendered(image(4, 3, 0.5)),
            Err("no preview".into()),
            snapshot(),
            1,
        );
        let none = save_png(&failed, dir.join("two").to_str().unwrap(), Part::Preview).unwrap();
        assert_eq!(none, None);
        assert!(!dir.join("two_preview.png").exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn cancelling_before_the_capture_clears_the_request() {
        let mut c = Comparison::default();
        c.start();
        assert!(c.busy());
        c.cancel();
        assert!(!c.busy());
    }
}
