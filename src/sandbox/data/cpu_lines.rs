//! The ray mesh and the vector field drawn by the CPU for the CPU live view
//! (`voxcast_core::rays::raster`), at the viewport's full resolution, over the live view's
//! image. A software rasterizer (lavapipe) takes about 3 µs a line and a camera pass of its
//! own; the core draws a million rays in about a tenth of a second on 2 cores. While the view
//! moves every n-th ray or arrow is drawn, n chosen from the measured speed so a picture takes
//! about [`MOVING_BUDGET_S`]; at rest the whole lists. A drawing of an old view is dropped once
//! the view rests elsewhere.

use crate::sandbox::shared::quality::{Motion, PreviewSettings};
use crate::sandbox::shared::viewport::Viewport;
use bevy::platform::time::Instant;
use bevy::prelude::*;
use bevy::tasks::{Task, futures::check_ready};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use voxcast_core::camera::Camera as CoreCamera;
use voxcast_core::rays::raster::{LineImage, Lines, draw_lines};

/// How long a picture of the lines may take while the view moves, seconds.
pub const MOVING_BUDGET_S: f64 = 1.0 / 100.0;

/// Segments a second assumed before the first picture is measured.
const FIRST_RATE: f64 = 2.0e6;

/// A line list the CPU draws: positions and display colours (sRGB values, as the live view's
/// image holds them), two vertices a segment, and how many segments make one item (a ray: 1,
/// an arrow: 5), so thinning keeps whole arrows.
#[derive(Debug)]
pub struct CpuList {
    pub positions: Vec<[f32; 3]>,
    pub colours: Vec<[f32; 4]>,
    pub per_item: usize,
}

impl CpuList {
    fn segments(&self) -> usize {
        self.positions.len() / 2
    }
}

/// What a picture shows: when any of it changes, the picture is out of date.
#[derive(Clone, Debug)]
struct LinesKey {
    camera: CoreCamera,
    size: UVec2,
    lists: Vec<Arc<CpuList>>,
    offset: Vec3,
    /// Every `every`-th item is drawn.
    every: usize,
}

impl PartialEq for LinesKey {
    fn eq(&self, other: &Self) -> bool {
        self.camera == other.camera
            && self.size == other.size
            && self.offset == other.offset
            && self.every == other.every
            && self.lists.len() == other.lists.len()
            && self
                .lists
                .iter()
                .zip(&other.lists)
                .all(|(a, b)| Arc::ptr_eq(a, b))
    }
}

/// A finished picture: the part of the viewport that holds lines (a software rasterizer pays
/// for every pixel it uploads and paints).
struct LinesFrame {
    key: LinesKey,
    /// That part, `[x0, y0, x1, y1)` in the viewport's pixels (empty: no line in view).
    rect: [u32; 4],
    /// Its premultiplied RGBA bytes, row by row.
    rgba: Vec<u8>,
}

struct LinesJob {
    task: Task<Option<(LinesFrame, f64)>>,
    cancel: Arc<AtomicBool>,
    key: LinesKey,
}

/// The lists, the picture on screen and the one on its way.
#[derive(Resource, Default)]
pub struct CpuLines {
    lists: Vec<Arc<CpuList>>,
    /// Where the lists' world sits in the volume's (minus the density's origin).
    offset: Vec3,
    job: Option<LinesJob>,
    shown: Option<LinesFrame>,
    generation: u64,
    image: Option<(u64, Handle<Image>)>,
    /// Segments a second of the last pictures (smoothed).
    rate: Option<f64>,
}

impl CpuLines {
    /// The lists to draw from now on (none: nothing is drawn).
    pub fn set(&mut self, lists: Vec<Arc<CpuList>>, offset: Vec3) {
        self.lists = lists;
        self.offset = offset;
    }

    /// Pictures finished so far (for measurements).
    pub fn pictures(&self) -> u64 {
        self.generation
    }

    /// The picture on screen: how many lists it draws, and every how many items.
    pub fn on_screen(&self) -> Option<(usize, usize)> {
        self.shown
            .as_ref()
            .map(|f| (f.key.lists.len(), f.key.every))
    }

    fn clear(&mut self) {
        if let Some(job) = self.job.take() {
            job.cancel.store(true, Ordering::Relaxed);
        }
        self.shown = None;
    }

    /// The picture to paint this frame, written into its image now if it is new, and where it
    /// goes: its rectangle as fractions of the viewport (`None` when no line is in view).
    pub fn image(&mut self, images: &mut Assets<Image>) -> Option<(Handle<Image>, [f32; 4])> {
        let frame = self.shown.as_mut()?;
        let [x0, y0, x1, y1] = frame.rect;
        if x1 <= x0 || y1 <= y0 {
            return None;
        }
        let size = frame.key.size.as_vec2();
        let place = [
            x0 as f32 / size.x,
            y0 as f32 / size.y,
            x1 as f32 / size.x,
            y1 as f32 / size.y,
        ];
        if self.image.as_ref().map(|(g, _)| *g) != Some(self.generation) {
            let picture = Image::new(
                bevy::render::render_resource::Extent3d {
                    width: x1 - x0,
                    height: y1 - y0,
                    depth_or_array_layers: 1,
                },
                bevy::render::render_resource::TextureDimension::D2,
                // Painted once: its bytes move into the image.
                std::mem::take(&mut frame.rgba),
                bevy::render::render_resource::TextureFormat::Rgba8UnormSrgb,
                bevy::asset::RenderAssetUsages::RENDER_WORLD
                    | bevy::asset::RenderAssetUsages::MAIN_WORLD,
            );
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
        self.image.as_ref().map(|(_, h)| (h.clone(), place))
    }
}

pub(crate) fn plugin(app: &mut App) {
    app.init_resource::<CpuLines>().add_systems(
        PostUpdate,
        drive_cpu_lines.in_set(crate::sandbox::shared::schedule::Frame::Views),
    );
}

/// The thinning for a moving view: the smallest n for which every n-th item of the lists
/// takes at most [`MOVING_BUDGET_S`] at `rate` segments a second.
pub fn moving_every(segments: usize, rate: Option<f64>) -> usize {
    let budget = rate.unwrap_or(FIRST_RATE) * MOVING_BUDGET_S;
    ((segments as f64 / budget.max(1.0)).ceil() as usize).max(1)
}

/// Starts, keeps or cancels the picture of the lines, and takes in a finished one.
fn drive_cpu_lines(
    mut lines: ResMut<CpuLines>,
    preview: Res<PreviewSettings>,
    motion: Res<Motion>,
    screen: crate::sandbox::shared::viewport::SceneOnScreen,
    mut report: ResMut<crate::sandbox::data::choices::ViewReport>,
) {
    if !preview.cpu_live() || lines.lists.is_empty() {
        lines.clear();
        return;
    }
    if let Some(job) = &mut lines.job
        && let Some(result) = check_ready(&mut job.task)
    {
        lines.job = None;
        if let Some((frame, rate)) = result {
            lines.rate = Some(lines.rate.map_or(rate, |r| 0.5 * r + 0.5 * rate));
            lines.shown = Some(frame);
            lines.generation += 1;
        }
    }
    let (Ok(window), Ok(view)) = (screen.window.single(), screen.views.single()) else {
        return;
    };
    let (_, size) = Viewport::of(screen.viewport.as_deref(), window);
    let segments: usize = lines.lists.iter().map(|l| l.segments()).sum();
    let thinned = moving_every(segments, lines.rate);
    let every = (thinned > 1).then_some(thinned);
    if report.moving_every != every {
        report.moving_every = every;
    }
    let key = LinesKey {
        camera: view.0,
        size,
        lists: lines.lists.clone(),
        offset: lines.offset,
        every: if motion.moving { thinned } else { 1 },
    };
    if lines.shown.as_ref().is_some_and(|f| f.key == key) {
        return;
    }
    if let Some(job) = &lines.job {
        // A picture of a moving view finishes (the next follows the camera); one of a view
        // the camera has left while it rests is dropped.
        if job.key == key || motion.moving {
            return;
        }
        job.cancel.store(true, Ordering::Relaxed);
        lines.job = None;
    }
    lines.job = Some(start(key));
}

fn start(key: LinesKey) -> LinesJob {
    let cancel = Arc::new(AtomicBool::new(false));
    let flag = cancel.clone();
    let job_key = key.clone();
    let task = crate::sandbox::shared::tasks::spawn(async move {
        let started = Instant::now();
        let mut image = LineImage::new(job_key.size.x, job_key.size.y);
        // Segments looked at (drawn or not: projecting them is the work).
        let segments: usize = job_key
            .lists
            .iter()
            .map(|l| l.segments().div_ceil(job_key.every))
            .sum();
        for list in &job_key.lists {
            if flag.load(Ordering::Relaxed) {
                return None;
            }
            // Every n-th item: whole arrows, as their segments are consecutive.
            let items = Lines {
                positions: &list.positions,
                colours: &list.colours,
                offset: job_key.offset,
                every: 1,
            };
            if job_key.every == 1 || list.per_item == 1 {
                draw_lines(
                    &mut image,
                    &job_key.camera,
                    &Lines {
                        every: job_key.every,
                        ..items
                    },
                );
            } else {
                let vertices = 2 * list.per_item;
                let (p, c): (Vec<[f32; 3]>, Vec<[f32; 4]>) = list
                    .positions
                    .chunks_exact(vertices)
                    .zip(list.colours.chunks_exact(vertices))
                    .step_by(job_key.every)
                    .flat_map(|(p, c)| p.iter().copied().zip(c.iter().copied()))
                    .unzip();
                draw_lines(
                    &mut image,
                    &job_key.camera,
                    &Lines {
                        positions: &p,
                        colours: &c,
                        ..items
                    },
                );
            }
        }
        let rect = image.drawn_rect().unwrap_or([0; 4]);
        let [x0, y0, x1, y1] = rect.map(|v| v as usize);
        let rgba = image
            .pixels
            .chunks_exact(image.width as usize)
            .take(y1)
            .skip(y0)
            .flat_map(|row| &row[x0..x1])
            .flat_map(|p| {
                p.to_array()
                    .map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u8)
            })
            .collect();
        let seconds = started.elapsed().as_secs_f64();
        let rate = segments.max(1) as f64 / seconds.max(1e-6);
        let frame = LinesFrame {
            key: job_key,
            rect,
            rgba,
        };
        Some((frame, rate))
    });
    LinesJob { task, cancel, key }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sandbox::shared::quality::Backend;
    use crate::sandbox::shared::state::{MainCamera, View};

    /// A windowless app with the CPU live view, a 64×48 window, and `lists` to draw seen from
    /// `camera`.
    fn app(camera: CoreCamera, lists: Vec<Arc<CpuList>>, offset: Vec3) -> App {
        let mut app = App::new();
        app.add_plugins(MinimalPlugins)
            .insert_resource(PreviewSettings {
                backend: Backend::Cpu,
                backend_chosen: true,
                ..default()
            })
            .init_resource::<Motion>()
            .init_resource::<crate::sandbox::data::choices::ViewReport>()
            .add_plugins(plugin);
        app.world_mut()
            .resource_mut::<CpuLines>()
            .set(lists, offset);
        app.world_mut().spawn((MainCamera, View(camera)));
        crate::sandbox::shared::viewport::spawn_test_window(app.world_mut(), 64, 48);
        app
    }

    /// At rest the picture on screen is the core's drawing of every line of the view, at the
    /// window's resolution, as bytes.
    #[test]
    fn at_rest_every_line_is_drawn_as_the_core_draws_it() {
        let camera = CoreCamera::new(
            Vec3::new(0.0, 0.0, 5.0),
            Vec3::ZERO,
            Vec3::Y,
            voxcast_core::camera::Projection::Perspective { fov_y_deg: 40.0 },
        )
        .unwrap();
        let positions: Vec<[f32; 3]> = (0..50)
            .flat_map(|i| {
                let a = i as f32 * 0.3;
                [[a.cos(), a.sin(), 0.0], [-a.sin(), a.cos(), 1.0]]
            })
            .collect();
        let colours = vec![[0.2, 0.6, 1.0, 1.0]; positions.len()];
        let offset = Vec3::new(0.1, -0.2, 0.0);
        let list = Arc::new(CpuList {
            positions: positions.clone(),
            colours: colours.clone(),
            per_item: 1,
        });
        let mut app = app(camera, vec![list], offset);
        for _ in 0..2000 {
            app.update();
            if app.world().resource::<CpuLines>().on_screen().is_some() {
                break;
            }
            std::thread::sleep(std::time::Duration::from_millis(1));
        }
        let lines = app.world().resource::<CpuLines>();
        let frame = lines.shown.as_ref().expect("a picture of the lines");
        assert_eq!((frame.key.size, frame.key.every), (UVec2::new(64, 48), 1));
        let mut image = LineImage::new(64, 48);
        let drawn = draw_lines(
            &mut image,
            &camera,
            &Lines {
                positions: &positions,
                colours: &colours,
                offset,
                every: 1,
            },
        );
        assert!(drawn > 40, "{drawn} lines in view");
        // The picture is the drawn rectangle's part of the drawing, and nothing lies outside it.
        let [x0, y0, x1, y1] = frame.rect;
        assert_eq!(Some(frame.rect), image.drawn_rect());
        let mut expect = Vec::new();
        for y in 0..48 {
            for x in 0..64 {
                let p = image.get(x, y);
                if (x0..x1).contains(&x) && (y0..y1).contains(&y) {
                    expect.extend(
                        p.to_array()
                            .map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u8),
                    );
                } else {
                    assert_eq!(p.w, 0.0, "a line outside the rectangle at ({x}, {y})");
                }
            }
        }
        assert!(
            frame.rgba == expect,
            "the picture differs from the core's drawing"
        );
    }

    #[test]
    fn a_moving_picture_fits_the_budget() {
        // 2 M segments a second: 20 000 in a hundredth of a second.
        assert_eq!(moving_every(10_000, Some(2.0e6)), 1);
        assert_eq!(moving_every(1_000_000, Some(2.0e6)), 50);
        assert_eq!(moving_every(1_000_000, None), 50);
        assert_eq!(moving_every(0, Some(1.0)), 1);
        assert_eq!(moving_every(10, Some(0.0)), 10);
    }
}
