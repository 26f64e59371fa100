//! The image renderer: every pixel's ray through [`crate::trace`], in parallel, cancellable.
//!
//! [`render`] gives the finished picture, every pixel over the background. [`render_layer`]
//! gives the volume as a layer — premultiplied colour `C` and opacity `O` per pixel — with
//! rays stopped at opaque, unlit spheres standing in the volume (the sandbox's sample spheres
//! and light marker), whose colour then shows through what is in front, `C + (1 − O)·sphere`:
//! exactly what the GPU preview draws with its depth prepass. It is the sandbox's CPU live view;
//! without spheres, over a plain background, it is the rendered image bit for bit.
//!
//! The image is cut into square tiles that rayon hands to its threads; each pixel depends only
//! on its own ray(s), so the image is identical for any number of threads (tested). After each
//! tile a progress callback reports `(tiles done, tiles total)`, and before each tile the cancel
//! flag is read, so a cancelled render stops within one tile's time. The march is
//! [`crate::trace`]'s, run with [`NoRecord`].
//!
//! A render can also be done in slices ([`crate::slices`]: a browser's one thread draws the page
//! between them): [`render_in`], [`render_layer_in`], `cost::render_cost_in` and
//! `cost::render_with_cost_in` (the picture and its cost map from one march) take a
//! [`TileSlices`] that keeps the finished tiles, and stop taking tiles at a deadline. Each
//! turns a ray's outcome into its own [`RayValue`]; the march is the same.

use crate::camera::Camera;
use crate::entry::EntryBounds;
use crate::error::SettingsError;
use crate::image_out::LinearImage;
use crate::slices::{Deadline, Step};
use crate::trace::{Marcher, NoRecord, Scene, StopReason};
use crate::volume::{Grid, GridVisitor, Voxel};
use glam::{Vec3, Vec4};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// Tile edge in pixels: small enough to balance load and to react to cancel quickly.
pub const TILE: u32 = 16;

/// The largest image edge accepted (pixels).
pub const MAX_EDGE: u32 = 16_384;

/// What a finished render measured.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct RenderStats {
    /// Rays cast (pixels × supersampling²).
    pub rays: u64,
    /// Samples interpolated over all rays.
    pub samples: u64,
    /// Sample positions passed over all rays, interpolated or skipped as empty space (what a
    /// caster without empty-space skipping would interpolate).
    pub positions: u64,
    /// Rays the sample cap cut short (they stopped before leaving the volume).
    pub capped: u64,
}

impl RenderStats {
    /// A warning in words when the sample cap cut rays short; `None` when it cut none.
    pub fn cap_warning(&self, max_samples: u32) -> Option<String> {
        (self.capped > 0).then(|| {
            format!(
                "{} of {} rays ({}) reached the sample cap ({max_samples}) before leaving the \
                 volume: the image stops there. Raise the step or the cap.",
                self.capped,
                self.rays,
                crate::numbers::percent(self.capped as f32 / self.rays.max(1) as f32)
            )
        })
    }
}

/// The render was cancelled before it finished.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("render cancelled")]
pub struct Cancelled;

/// Checks an image size: both edges in `1..=MAX_EDGE`.
pub fn validate_size(width: u32, height: u32) -> Result<(), SettingsError> {
    if width == 0 || height == 0 || width > MAX_EDGE || height > MAX_EDGE {
        return Err(SettingsError::Invalid(format!(
            "image size {width}×{height}: each edge must be 1 to {MAX_EDGE} pixels"
        )));
    }
    Ok(())
}

/// Renders `camera`'s view of `scene` at `width × height` on the current rayon pool.
/// `progress(done, total)` is called after each tile (from worker threads).
pub fn render(
    scene: &Scene<'_>,
    camera: &Camera,
    width: u32,
    height: u32,
    progress: &(dyn Fn(usize, usize) + Sync),
    cancel: &AtomicBool,
) -> Result<(LinearImage, RenderStats), Cancelled> {
    let job = Job::plain(scene, camera, (width, height), progress, cancel);
    render_in(&job, &mut TileSlices::default(), Deadline::NONE).map(Step::whole)
}

/// [`render`] of `job` (its occluders and surface left out) in slices: the tiles up to
/// `deadline`, kept in `slices`; the picture once every tile is done.
pub fn render_in(
    job: &Job<'_, '_>,
    slices: &mut TileSlices,
    deadline: Deadline,
) -> Result<Step<(LinearImage, RenderStats)>, Cancelled> {
    let plain = job.volume_alone();
    let step = plain.run_on_volume(
        |out, background, _| Vec4::from((out.pixel(background), 1.0)),
        slices,
        deadline,
    )?;
    Ok(match step {
        Step::Paused => Step::Paused,
        Step::Done((pixels, stats)) => Step::Done((
            LinearImage {
                width: job.width,
                height: job.height,
                pixels: pixels.into_par_iter().map(Vec4::truncate).collect(),
            },
            stats,
        )),
    })
}

/// An opaque, unlit sphere in the scene: rays stop where they meet it, and its colour shows
/// through the volume in front of it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Occluder {
    pub centre: Vec3,
    pub radius: f32,
    /// Its flat colour (display values, as the transfer function's).
    pub color: Vec3,
}

impl Occluder {
    /// The distance along `ray` (unit direction) to the sphere's front surface, if the ray
    /// meets it ahead of its origin; a ray starting inside the sphere stops at once.
    pub fn hit(&self, ray: &crate::ray::Ray) -> Option<f32> {
        let oc = ray.origin - self.centre;
        let b = oc.dot(ray.dir);
        let c = oc.length_squared() - self.radius * self.radius;
        if c <= 0.0 {
            return Some(0.0);
        }
        let disc = b * b - c;
        if disc < 0.0 || b > 0.0 {
            return None;
        }
        Some(-b - disc.sqrt())
    }
}

/// Where on a `width × height` image of `camera` the sphere can appear: a pixel rectangle
/// `[x0, x1] × [y0, y1]` holding the projection of the cube around it, or `None` when that cube
/// reaches the eye's plane (then any ray may meet it). Only rays of pixels inside are tested
/// against it: hundreds of sample spheres cost a render little.
pub fn screen_bounds(o: &Occluder, camera: &Camera, width: u32, height: u32) -> Option<[f32; 4]> {
    let (right, up, forward) = camera.basis();
    let mut b = [
        f32::INFINITY,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::NEG_INFINITY,
    ];
    for i in 0..8 {
        let s = |bit: u32| if i & bit == 0 { -1.0 } else { 1.0 };
        let corner = o.centre + (right * s(1) + up * s(2) + forward * s(4)) * o.radius;
        let (x, y) = camera.project(corner, width, height)?;
        b = [b[0].min(x), b[1].min(y), b[2].max(x), b[3].max(y)];
    }
    Some(b)
}

/// Premultiplied colour and opacity per pixel, row 0 at the top: the volume as a layer.
#[derive(Clone, Debug, PartialEq)]
pub struct LayerImage {
    pub width: u32,
    pub height: u32,
    /// `(C.r, C.g, C.b, O)` per pixel, row by row.
    pub pixels: Vec<Vec4>,
}

impl LayerImage {
    /// The layer over a plain background: `C + (1 − O)·background` (what [`render`] gives).
    pub fn over(&self, background: Vec3) -> LinearImage {
        let mut image = LinearImage::new(self.width, self.height);
        for (i, p) in self.pixels.iter().enumerate() {
            let (x, y) = (i as u32 % self.width, i as u32 / self.width);
            image.set(
                x,
                y,
                crate::composite::blend_background(p.truncate(), p.w, background),
            );
        }
        image
    }
}

/// Renders the volume as a layer ([`LayerImage`]): rays stop at the nearest of `occluders`.
/// Progress and cancel as [`render`].
pub fn render_layer(
    scene: &Scene<'_>,
    camera: &Camera,
    size: (u32, u32),
    occluders: &[Occluder],
    progress: &(dyn Fn(usize, usize) + Sync),
    cancel: &AtomicBool,
) -> Result<(LayerImage, RenderStats), Cancelled> {
    render_layer_with(scene, camera, size, occluders, None, progress, cancel)
}

/// [`render_layer`] with rays also stopping at `surface` (a triangle scene: a ray density's),
/// whose colour then shows behind the volume as an occluder's does.
pub fn render_layer_with(
    scene: &Scene<'_>,
    camera: &Camera,
    (width, height): (u32, u32),
    occluders: &[Occluder],
    surface: Option<Surface<'_>>,
    progress: &(dyn Fn(usize, usize) + Sync),
    cancel: &AtomicBool,
) -> Result<(LayerImage, RenderStats), Cancelled> {
    let job = Job {
        occluders,
        surface,
        ..Job::plain(scene, camera, (width, height), progress, cancel)
    };
    render_layer_in(&job, &mut TileSlices::default(), Deadline::NONE).map(Step::whole)
}

/// [`render_layer_with`] of `job` in slices (see [`render_in`]).
pub fn render_layer_in(
    job: &Job<'_, '_>,
    slices: &mut TileSlices,
    deadline: Deadline,
) -> Result<Step<(LayerImage, RenderStats)>, Cancelled> {
    let step = job.run_on_volume(
        |out, _, behind| match behind {
            Some(c) => Vec4::from((out.color + c * (1.0 - out.opacity), 1.0)),
            None => Vec4::from((out.color, out.opacity)),
        },
        slices,
        deadline,
    )?;
    Ok(match step {
        Step::Paused => Step::Paused,
        Step::Done((pixels, stats)) => Step::Done((
            LayerImage {
                width: job.width,
                height: job.height,
                pixels,
            },
            stats,
        )),
    })
}

/// The threads a render started here runs on (the current rayon pool's; one in a browser
/// without threads).
pub fn threads() -> usize {
    rayon::current_num_threads()
}

/// As [`render`], on a dedicated pool of `threads` threads (for measurements and tests). In
/// WebAssembly, which has no threads here, on the calling one whatever `threads` says.
pub fn render_with_threads(
    scene: &Scene<'_>,
    camera: &Camera,
    width: u32,
    height: u32,
    threads: usize,
) -> Result<(LinearImage, RenderStats), Cancelled> {
    on_threads(threads, || {
        render(
            scene,
            camera,
            width,
            height,
            &|_, _| {},
            &AtomicBool::new(false),
        )
    })
}

/// Runs `work` on a dedicated pool of `threads` threads (at least one): what
/// [`render_with_threads`] renders on. In WebAssembly, which has no threads here, on the
/// calling one whatever `threads` says.
pub fn on_threads<R: Send>(threads: usize, work: impl FnOnce() -> R + Send) -> R {
    if cfg!(target_arch = "wasm32") {
        return work();
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads.max(1))
        .build()
        .expect("a thread pool can be built");
    pool.install(work)
}

/// What a render turns each ray into (a colour, a layer's colour and opacity, a cost map's
/// counts, or several of these at once), summed over a pixel's rays and scaled by one over
/// their number.
pub trait RayValue:
    Copy + Default + Send + Sync + std::ops::Add<Output = Self> + std::ops::Mul<f32, Output = Self>
{
}

impl<V> RayValue for V where
    V: Copy + Default + Send + Sync + std::ops::Add<Output = V> + std::ops::Mul<f32, Output = V>
{
}

/// A finished tile: its top-left corner, its pixels row by row, the samples it interpolated and
/// passed, and the rays the sample cap cut short.
type TileResult<V> = (u32, u32, Vec<V>, u64, u64, u64);

/// A render's work kept between slices ([`crate::slices`]): the tiles finished so far, and
/// where each pixel's rays can first meet a visible cell (found once, by the first slice).
/// One `TileSlices` serves one render: its job must not change between the slices.
#[derive(Clone, Debug)]
pub struct TileSlices<V = Vec4> {
    tiles: Vec<Option<TileResult<V>>>,
    entry: Option<Option<EntryBounds>>,
}

impl<V> Default for TileSlices<V> {
    fn default() -> Self {
        Self {
            tiles: Vec::new(),
            entry: None,
        }
    }
}

impl<V> TileSlices<V> {
    /// The share of the tiles finished.
    pub fn fraction(&self) -> f32 {
        let done = self.tiles.iter().filter(|t| t.is_some()).count();
        done as f32 / self.tiles.len().max(1) as f32
    }
}

/// Opaque geometry a ray may stop at: for a ray (volume coordinates, unit direction), the
/// distance to the nearest surface ahead and the colour shown there.
pub type Surface<'x> = &'x (dyn Fn(&crate::ray::Ray) -> Option<(f32, Vec3)> + Sync);

/// One render's inputs, for any of its outputs (the picture, the layer, the cost map).
#[derive(Clone, Copy)]
pub struct Job<'x, 'a> {
    pub scene: &'x Scene<'a>,
    pub camera: &'x Camera,
    pub width: u32,
    pub height: u32,
    /// Spheres the rays stop at (the layer's; the picture leaves them out).
    pub occluders: &'x [Occluder],
    /// Opaque geometry besides the occluders (a triangle scene), tested on every ray.
    pub surface: Option<Surface<'x>>,
    pub progress: &'x (dyn Fn(usize, usize) + Sync),
    pub cancel: &'x AtomicBool,
}

impl<'x, 'a> Job<'x, 'a> {
    /// A job without occluders: the plain image of `camera`'s view.
    pub fn plain(
        scene: &'x Scene<'a>,
        camera: &'x Camera,
        (width, height): (u32, u32),
        progress: &'x (dyn Fn(usize, usize) + Sync),
        cancel: &'x AtomicBool,
    ) -> Self {
        Self {
            scene,
            camera,
            width,
            height,
            occluders: &[],
            surface: None,
            progress,
            cancel,
        }
    }

    /// This job with its occluders and surface left out: what the picture and the cost map
    /// march.
    pub(crate) fn volume_alone(&self) -> Self {
        Self {
            occluders: &[],
            surface: None,
            ..*self
        }
    }
}

impl Job<'_, '_> {
    /// [`Job::run`] on the scene's own volume, whatever its voxel type.
    pub(crate) fn run_on_volume<V: RayValue>(
        &self,
        value: impl Fn(&crate::trace::RayOutcome, Vec3, Option<Vec3>) -> V + Sync,
        slices: &mut TileSlices<V>,
        deadline: Deadline,
    ) -> Result<Step<(Vec<V>, RenderStats)>, Cancelled> {
        struct Visit<'j, 'x, 'a, 's, F, V> {
            job: &'j Job<'x, 'a>,
            value: F,
            slices: &'s mut TileSlices<V>,
            deadline: Deadline,
        }
        impl<F, V: RayValue> GridVisitor for Visit<'_, '_, '_, '_, F, V>
        where
            F: Fn(&crate::trace::RayOutcome, Vec3, Option<Vec3>) -> V + Sync,
        {
            type Output = Result<Step<(Vec<V>, RenderStats)>, Cancelled>;
            fn visit<T: Voxel>(self, grid: Grid<'_, T>) -> Self::Output {
                self.job.run(grid, self.value, self.slices, self.deadline)
            }
        }
        self.scene.volume.visit(Visit {
            job: self,
            value,
            slices,
            deadline,
        })
    }

    /// Every pixel's rays through `grid`, each ray's outcome turned into a value by `value`
    /// (given the background and the colour of the occluder that stopped it, if one did) and
    /// averaged over the supersamples; row by row. The tiles `slices` holds are not done again,
    /// and no tile is begun once `deadline` has passed (but the first of each call).
    pub(crate) fn run<T: Voxel, V: RayValue>(
        &self,
        grid: Grid<'_, T>,
        value: impl Fn(&crate::trace::RayOutcome, Vec3, Option<Vec3>) -> V + Sync,
        slices: &mut TileSlices<V>,
        deadline: Deadline,
    ) -> Result<Step<(Vec<V>, RenderStats)>, Cancelled> {
        let (scene, width, height) = (self.scene, self.width, self.height);
        let spacing = grid.spacing;
        let marcher = Marcher::new(scene, grid);
        // Each occluder's pixel rectangle (None: anywhere), to test a tile's rays only
        // against the occluders that can appear in it.
        let bounds: Vec<Option<[f32; 4]>> = self
            .occluders
            .iter()
            .map(|o| screen_bounds(o, self.camera, width, height))
            .collect();
        let tiles_x = width.div_ceil(TILE);
        let tiles_y = height.div_ceil(TILE);
        let total = (tiles_x * tiles_y) as usize;
        let n = scene.settings.supersampling.max(1);
        let rays = self.camera.rays(width, height);
        // Where each pixel's rays can first meet a visible cell, for the march that uses it.
        let entry = slices
            .entry
            .get_or_insert_with(|| match scene.empty.as_deref() {
                Some((_, cells)) if marcher.reads_entry_bounds() => {
                    EntryBounds::new(cells, spacing, &rays, (width, height))
                }
                _ => None,
            });
        if slices.tiles.len() != total {
            slices.tiles = vec![None; total];
        }
        let todo: Vec<u32> = (0..total as u32)
            .filter(|&t| slices.tiles[t as usize].is_none())
            .collect();
        let done = AtomicUsize::new(total - todo.len());
        // Tiles begun by this call: the first is taken whatever the deadline, so every call
        // moves the render on.
        let begun = AtomicUsize::new(0);
        let entry = &*entry;

        let finished: Vec<Option<TileResult<V>>> = todo
            .par_iter()
            .map(|&tile| {
                if self.cancel.load(Ordering::Relaxed)
                    || (begun.fetch_add(1, Ordering::Relaxed) > 0 && deadline.passed())
                {
                    return None;
                }
                let x0 = (tile % tiles_x) * TILE;
                let y0 = (tile / tiles_x) * TILE;
                let x1 = (x0 + TILE).min(width);
                let y1 = (y0 + TILE).min(height);
                let near: Vec<&Occluder> = self
                    .occluders
                    .iter()
                    .zip(&bounds)
                    .filter(|(_, b)| {
                        b.is_none_or(|[bx0, by0, bx1, by1]| {
                            bx1 >= x0 as f32 - 1.0
                                && bx0 <= x1 as f32 + 1.0
                                && by1 >= y0 as f32 - 1.0
                                && by0 <= y1 as f32 + 1.0
                        })
                    })
                    .map(|(o, _)| o)
                    .collect();
                let (pixels, samples, positions, capped) =
                    self.tile_rays(&marcher, &rays, entry, [x0, y0, x1, y1], &near, &value);
                let d = done.fetch_add(1, Ordering::Relaxed) + 1;
                (self.progress)(d, total);
                Some((x0, y0, pixels, samples, positions, capped))
            })
            .collect();
        for (tile, result) in todo.into_iter().zip(finished) {
            slices.tiles[tile as usize] = result;
        }
        if slices.tiles.iter().any(Option::is_none) {
            return if self.cancel.load(Ordering::Relaxed) {
                Err(Cancelled)
            } else {
                Ok(Step::Paused)
            };
        }
        let tiles: Vec<TileResult<V>> = std::mem::take(&mut slices.tiles)
            .into_iter()
            .flatten()
            .collect();

        let mut stats = RenderStats {
            rays: width as u64 * height as u64 * (n * n) as u64,
            samples: 0,
            positions: 0,
            capped: 0,
        };
        for &(_, _, _, samples, positions, capped) in &tiles {
            stats.samples += samples;
            stats.positions += positions;
            stats.capped += capped;
        }
        // Each band of tile rows is one stretch of the image: copied in parallel.
        let mut image = vec![V::default(); width as usize * height as usize];
        image
            .par_chunks_mut((width * TILE) as usize)
            .zip(tiles.par_chunks(tiles_x as usize))
            .for_each(|(band, row)| {
                for (x0, _, pixels, ..) in row.iter() {
                    let w = ((x0 + TILE).min(width) - x0) as usize;
                    for (i, line) in pixels.chunks(w).enumerate() {
                        let at = i * width as usize + *x0 as usize;
                        band[at..at + w].copy_from_slice(line);
                    }
                }
            });
        Ok(Step::Done((image, stats)))
    }

    /// The pixels of the tile `[x0, y0, x1, y1)` (row by row), and its samples, positions and
    /// capped rays: each pixel's rays, stopped at the `near` occluders and the surface,
    /// marched, turned into a value and averaged over the supersamples.
    #[inline(always)]
    fn tile_rays<T: Voxel, V: RayValue>(
        &self,
        marcher: &Marcher<'_, '_, '_, T>,
        rays: &crate::camera::ImageRays,
        entry: &Option<EntryBounds>,
        [x0, y0, x1, y1]: [u32; 4],
        near: &[&Occluder],
        value: &impl Fn(&crate::trace::RayOutcome, Vec3, Option<Vec3>) -> V,
    ) -> (Vec<V>, u64, u64, u64) {
        let scene = self.scene;
        let n = scene.settings.supersampling.max(1);
        let inv_rays = 1.0 / (n * n) as f32;
        let background = scene.settings.background;
        let mut pixels = Vec::with_capacity(((x1 - x0) * (y1 - y0)) as usize);
        let (mut samples, mut positions, mut capped) = (0u64, 0u64, 0u64);
        for py in y0..y1 {
            for px in x0..x1 {
                let from = entry.as_ref().map_or(f32::NEG_INFINITY, |e| e.at(px, py));
                let mut sum = V::default();
                for sy in 0..n {
                    for sx in 0..n {
                        let x = px as f32 + (sx as f32 + 0.5) / n as f32;
                        let y = py as f32 + (sy as f32 + 0.5) / n as f32;
                        let mut ray = rays.ray(x, y);
                        let mut behind = None;
                        for o in near {
                            if let Some(t) = o.hit(&ray)
                                && t < ray.t_max
                            {
                                ray.t_max = t;
                                behind = Some(o.color);
                            }
                        }
                        if let Some(surface) = self.surface
                            && let Some((t, c)) = surface(&ray)
                            && t < ray.t_max
                        {
                            ray.t_max = t;
                            behind = Some(c);
                        }
                        let jitter = scene.jitter([px * n + sx, py * n + sy]);
                        let out = marcher.march_from(&ray, jitter, from, &mut NoRecord);
                        samples += out.samples as u64;
                        positions += out.positions as u64;
                        capped += (out.stop == StopReason::SampleCap) as u64;
                        sum = sum + value(&out, background, behind);
                    }
                }
                pixels.push(sum * inv_rays);
            }
        }
        (pixels, samples, positions, capped)
    }
}
