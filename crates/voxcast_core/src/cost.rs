//! Acceleration made visible: what each pixel's rays cost, as a heat map.
//!
//! [`render_cost`] runs the very march of [`crate::render`] (same rays, same skipping, same
//! early termination) and keeps, per pixel instead of the colour, what it did: the samples it
//! interpolated, the sample positions it passed (interpolated or skipped as empty space: what a
//! caster without skipping would have interpolated), and how its rays stopped. [`CostMap::image`]
//! draws one of these as the Radeon Raytracing Analyzer draws its traversal counters: a heat map
//! through [`crate::colormap::inferno`], or the stop reasons in flat colours. The heat map's
//! scale is fixed by the volume and the step, not by the image, and logarithmic ([`heat`]): pale
//! yellow is every position of the longest ray through the volume ([`CostMap::full_scale`]), so
//! two maps of the same view compare by colour — turning early termination or skipping off and rendering again shows the
//! cost rise, pixel by pixel, where the work they save lies.
//!
//! With the method First the same march also keeps each ray's hit distance: the depth image,
//! "distance to the first voxel" ([`crate::depth`]), is one more view of the map. Render image
//! takes the picture and its map from one march ([`render_with_cost_in`]).

mod picture;

pub use picture::{PictureAndCost, render_with_cost_in};

use crate::camera::Camera;
use crate::colormap::inferno;
use crate::composite::Method;
use crate::depth::{DepthError, DepthMap, depth_scale};
use crate::image_out::LinearImage;
use crate::render::{Cancelled, Job, RenderStats, TileSlices};
use crate::slices::{Deadline, Step};
use crate::trace::{Scene, StopReason};
use glam::{Vec3, Vec4};
use std::sync::atomic::AtomicBool;

/// What a cost image shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CostView {
    /// Samples interpolated per pixel.
    Samples,
    /// Sample positions passed over without interpolating (empty space skipped).
    Skipped,
    /// How the rays stopped: ran through, stopped early, cut short by the cap, or missed.
    Stops,
    /// First's depth: how far from the eye each pixel's rays found the target value, on the
    /// scale the volume's box sets.
    Depth,
    /// First's depth on the hits' own range: white the nearest hit, dark grey the farthest.
    DepthOfHits,
}

impl CostView {
    pub const ALL: [CostView; 5] = [
        CostView::Samples,
        CostView::Skipped,
        CostView::Stops,
        CostView::Depth,
        CostView::DepthOfHits,
    ];

    /// The view's name in the UI and on the command line.
    pub const fn name(self) -> &'static str {
        match self {
            CostView::Samples => "samples",
            CostView::Skipped => "skipped",
            CostView::Stops => "stops",
            CostView::Depth => "depth",
            CostView::DepthOfHits => "depth-of-hits",
        }
    }

    /// The view's name on its button.
    pub const fn label(self) -> &'static str {
        match self {
            CostView::DepthOfHits => "depth, hits' range",
            other => other.name(),
        }
    }

    /// Whether it is one of First's depth images.
    pub const fn is_depth(self) -> bool {
        matches!(self, CostView::Depth | CostView::DepthOfHits)
    }

    /// Whether the view shows anything for `method`: the depth only for First.
    pub fn shows_for(self, method: Method) -> bool {
        !self.is_depth() || method == Method::First
    }

    /// What the view shows, in words (the legend).
    pub const fn doc(self) -> &'static str {
        match self {
            CostView::Samples => {
                "Samples interpolated per pixel: the work of the march, dark (none) to pale \
                 yellow (as many as the longest ray through the volume has positions)."
            }
            CostView::Skipped => {
                "Sample positions passed without interpolating, per pixel: the work empty-space \
                 skipping saved, dark (none) to pale yellow (as many as the longest ray through \
                 the volume has positions)."
            }
            CostView::Stops => {
                "How each pixel's rays stopped: blue, they left the volume; orange, early \
                 termination or a First hit stopped them; red, the sample cap; black, they missed \
                 the volume or the cut left nothing."
            }
            CostView::Depth => {
                "Distance to the first voxel (method First): how far from the eye each pixel's \
                 ray found the target value, white nearest to dark grey farthest on a scale \
                 fixed by the volume's box; the background where no ray found it."
            }
            CostView::DepthOfHits => {
                "Distance to the first voxel (method First) on the hits' own range: white the \
                 nearest hit, dark grey the farthest, so a surface that fills only part of the \
                 box's depth still shows its shape; the background where no ray found it."
            }
        }
    }

    /// The view named `name`, if any.
    pub fn parse(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|v| v.name() == name)
    }
}

/// Colours of [`CostView::Stops`].
pub const LEFT_COLOR: Vec3 = Vec3::new(0.2, 0.45, 1.0);
pub const EARLY_COLOR: Vec3 = Vec3::new(1.0, 0.55, 0.1);
pub const CAPPED_COLOR: Vec3 = Vec3::new(1.0, 0.1, 0.1);

/// Per pixel, summed over its rays: samples interpolated, positions passed, rays stopped early
/// (early termination or a First hit), rays the cap cut short, rays that took any position.
#[derive(Clone, Debug, PartialEq)]
pub struct CostMap {
    pub width: u32,
    pub height: u32,
    /// Rays per pixel (supersampling²).
    pub rays_per_pixel: u32,
    /// `[samples, positions, early, capped, marched]` per pixel, row by row.
    pub pixels: Vec<[u32; 5]>,
    pub stats: RenderStats,
    /// The count drawn pale yellow: a pixel's rays each taking every position of the longest
    /// ray through the volume at this step (its diagonal; at most the sample cap).
    pub full_scale: u32,
    /// With the method First, each pixel's hit distance (else `None`).
    pub depth: Option<DepthMap>,
    /// The render's background, where the depth view shows no hit.
    pub background: Vec3,
}

impl CostMap {
    /// The count `view` shows for one pixel (`Stops` has none: 0).
    pub fn count(&self, view: CostView, p: &[u32; 5]) -> u32 {
        match view {
            CostView::Samples => p[0],
            CostView::Skipped => p[1] - p[0],
            CostView::Stops | CostView::Depth | CostView::DepthOfHits => 0,
        }
    }

    /// The largest count `view` shows in the image.
    pub fn max(&self, view: CostView) -> u32 {
        self.pixels
            .iter()
            .map(|p| self.count(view, p))
            .max()
            .unwrap_or(0)
    }

    /// First's depth as `view` scales it (`None`: not a depth view, or no depth).
    pub fn depth_as(&self, view: CostView) -> Option<DepthMap> {
        let depth = self.depth.as_ref()?;
        match view {
            CostView::Depth => Some(depth.clone()),
            CostView::DepthOfHits => Some(depth.on_hits()),
            _ => None,
        }
    }

    /// The view as an image: counts through inferno, 0 to [`CostMap::full_scale`]; or the
    /// stops' colours, blended by the share of the pixel's rays that stopped each way.
    pub fn image(&self, view: CostView) -> LinearImage {
        if view.is_depth() {
            return match self.depth_as(view) {
                Some(depth) => depth.image(self.background),
                None => LinearImage {
                    width: self.width,
                    height: self.height,
                    pixels: vec![self.background; (self.width * self.height) as usize],
                },
            };
        }
        let mut image = LinearImage::new(self.width, self.height);
        let rays = self.rays_per_pixel.max(1) as f32;
        for (i, p) in self.pixels.iter().enumerate() {
            let c = match view {
                CostView::Stops => {
                    let (early, capped, marched) = (p[2] as f32, p[3] as f32, p[4] as f32);
                    let left = marched - early - capped;
                    (LEFT_COLOR * left + EARLY_COLOR * early + CAPPED_COLOR * capped) / rays
                }
                _ => inferno(heat(self.count(view, p), self.full_scale)),
            };
            image.set(i as u32 % self.width, i as u32 / self.width, c);
        }
        image
    }
}

/// Where `count` lies on a heat map whose pale-yellow end is `full`, in `[0, 1]`: on a log
/// scale, `ln(1 + count)/ln(1 + full)`, so a ray that early termination stopped after a tenth
/// of the longest ray's positions still shows (at about 0.6), and a map stays comparable with
/// another of the same view.
pub fn heat(count: u32, full: u32) -> f32 {
    let full = full.max(1) as f32;
    ((count as f32).ln_1p() / full.ln_1p()).clamp(0.0, 1.0)
}

/// The count at `fraction` of a heat map whose end is `full` (the inverse of [`heat`]), for
/// the legend's marks.
pub fn count_at(fraction: f32, full: u32) -> f32 {
    ((full.max(1) as f32).ln_1p() * fraction).exp_m1()
}

/// The heat map's scale in words: its middle and its pale-yellow end (`full`), and the busiest
/// pixel's count — one wording for Render image, the preview's legend and `render --cost`.
pub fn scale_words(full: u32, busiest: u32) -> String {
    format!(
        "Log scale: middle {}, pale yellow {full} a pixel (every position of the longest ray); \
         the busiest pixel here {busiest}",
        count_at(0.5, full).round()
    )
}

/// Renders what every pixel of `camera`'s view costs (see the module's text); progress and
/// cancel as [`crate::render::render`].
pub fn render_cost(
    scene: &Scene<'_>,
    camera: &Camera,
    size: (u32, u32),
    progress: &(dyn Fn(usize, usize) + Sync),
    cancel: &AtomicBool,
) -> Result<CostMap, Cancelled> {
    let job = Job::plain(scene, camera, size, progress, cancel);
    render_cost_in(&job, &mut TileSlices::default(), Deadline::NONE).map(Step::whole)
}

/// First's depth image of `camera`'s view of `scene` ([`crate::depth`]): the cost map's march,
/// its depth kept. Progress and cancel as [`crate::render::render`].
pub fn render_depth(
    scene: &Scene<'_>,
    camera: &Camera,
    size: (u32, u32),
    progress: &(dyn Fn(usize, usize) + Sync),
    cancel: &AtomicBool,
) -> Result<DepthMap, DepthError> {
    let method = scene.settings.method;
    if method != Method::First {
        return Err(DepthError::NotFirst(method.name()));
    }
    let map = render_cost(scene, camera, size, progress, cancel)?;
    Ok(map.depth.expect("First keeps its depth"))
}

/// The last channel of a ray's cost packs three counts of a pixel's rays, each below this
/// (supersampling is at most 8, so 64 rays): capped + MISSED·missed + MISSED²·early, whole
/// numbers below 2^24, where f32 holds them exactly.
const MISSED: f32 = 128.0;

/// [`render_cost`] of `job` (its occluders and surface left out) in slices, as
/// [`crate::render::render_in`].
pub fn render_cost_in(
    job: &Job<'_, '_>,
    slices: &mut TileSlices,
    deadline: Deadline,
) -> Result<Step<CostMap>, Cancelled> {
    let job = job.volume_alone();
    let step = job.run_on_volume(|out, _, _| ray_cost(out), slices, deadline)?;
    Ok(match step {
        Step::Paused => Step::Paused,
        Step::Done((pixels, stats)) => Step::Done(cost_map(&job, &pixels, |p| *p, stats)),
    })
}

/// What one ray cost, as the map's march keeps it: samples, positions, First's hit distance
/// (0 where the ray found no target) and how it stopped (packed, see [`MISSED`]).
pub(crate) fn ray_cost(out: &crate::trace::RayOutcome) -> Vec4 {
    let early = matches!(out.stop, StopReason::Cutoff | StopReason::FirstHit);
    let capped = out.stop == StopReason::SampleCap;
    let missed = matches!(out.stop, StopReason::Missed | StopReason::CutAway);
    let hit_t = if out.hit_t.is_nan() { 0.0 } else { out.hit_t };
    Vec4::new(
        out.samples as f32,
        out.positions as f32,
        hit_t,
        f32::from(u8::from(capped))
            + MISSED * f32::from(u8::from(missed))
            + MISSED * MISSED * f32::from(u8::from(early)),
    )
}

/// `x.round() as u32` for a count `x` (not negative, below 2^32), without the library call
/// `round` is on targets without a rounding instruction (x86-64's baseline, WebAssembly): the
/// whole part, and one more from a half up — the same halves away from zero. `x − ⌊x⌋` is exact
/// in f32 where counts are (below 2^24).
fn round_count(x: f32) -> u32 {
    let whole = x as u32;
    whole + u32::from(x - whole as f32 >= 0.5)
}

/// The cost map of `job` from its pixels' averaged [`ray_cost`]s, each read from a pixel by
/// `cost` (the pixels may carry more than their cost).
pub(crate) fn cost_map<V: Sync>(
    job: &Job<'_, '_>,
    pixels: &[V],
    cost: impl Fn(&V) -> Vec4 + Sync,
    stats: RenderStats,
) -> CostMap {
    let (scene, width, height) = (job.scene, job.width, job.height);
    // The job averages over a pixel's rays; multiplied back, every count is a whole number
    // again (they stay far below 2^24, where f32 holds integers exactly).
    let n = scene.settings.supersampling.max(1);
    let rays = (n * n) as f32;
    let whole = |x: f32| round_count(x * rays);
    let m = MISSED as u32;
    let counts: Vec<[u32; 5]> = pixels
        .iter()
        .map(|p| {
            let p = cost(p);
            let last = whole(p.w);
            let (early, missed, capped) = (last / (m * m), last / m % m, last % m);
            [whole(p.x), whole(p.y), early, capped, n * n - missed]
        })
        .collect();
    // First's rays stop early exactly where they hit: the depth is the mean over those.
    let depth = (scene.settings.method == Method::First).then(|| {
        let (lo, hi) = scene.volume.bounds();
        let (near, far) = depth_scale(job.camera, lo, hi);
        DepthMap {
            width,
            height,
            depth: pixels
                .iter()
                .zip(&counts)
                .map(|(p, c)| {
                    if c[2] > 0 {
                        cost(p).z * rays / c[2] as f32
                    } else {
                        f32::NAN
                    }
                })
                .collect(),
            near,
            far,
            on_hits: false,
        }
    });
    let longest = scene
        .settings
        .longest_ray_samples(scene.volume)
        .ceil()
        .min(f64::from(scene.settings.max_samples)) as u32;
    CostMap {
        width,
        height,
        rays_per_pixel: n * n,
        pixels: counts,
        stats,
        full_scale: longest.max(1) * n * n,
        depth,
        background: scene.settings.background,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::settings::RenderSettings;
    use crate::step::Length;

    #[test]
    fn counts_round_as_round_does() {
        let mut x = 0.0f32;
        let edges = [
            0.0, 0.49999997, 0.5, 1.4999999, 1.5, 2.5, 3.0000002, 8388607.5, 8388609.0,
        ];
        for v in edges.into_iter().chain([16777215.0, 1e9, 4294967040.0]) {
            assert_eq!(round_count(v), v.round() as u32, "{v}");
        }
        // Every 37th float up to 2^24, and the neighbours of each half.
        while x < 16777216.0 {
            for v in [
                x,
                (x.floor() + 0.5).next_down(),
                x.floor() + 0.5,
                (x.floor() + 0.5).next_up(),
            ] {
                assert_eq!(round_count(v), v.round() as u32, "{v}");
            }
            x = f32::from_bits(x.to_bits() + 37);
        }
    }

    fn head() -> crate::Prepared {
        crate::builtin::load_builtin("head").unwrap().volume.into()
    }

    fn cost(v: &crate::Prepared, s: &RenderSettings) -> CostMap {
        let tf = crate::preset::for_volume("head").unwrap().transfer;
        let (lo, hi) = v.bounds();
        let camera = Camera::framing(lo, hi, Vec3::new(0.3, 0.2, 1.0), Vec3::Y).unwrap();
        let scene = Scene::new(v, &tf, s, camera.forward()).unwrap();
        render_cost(
            &scene,
            &camera,
            (40, 30),
            &|_, _| {},
            &AtomicBool::new(false),
        )
        .unwrap()
    }

    /// The map's counts add up to the render's totals, and every pixel's rays are accounted
    /// for: missed, left, stopped early or capped.
    #[test]
    fn counts_add_up_to_the_renders() {
        let v = head();
        for n in [1u32, 3] {
            let s = RenderSettings {
                supersampling: n,
                ..Default::default()
            };
            let m = cost(&v, &s);
            let samples: u64 = m.pixels.iter().map(|p| p[0] as u64).sum();
            let positions: u64 = m.pixels.iter().map(|p| p[1] as u64).sum();
            assert_eq!(samples, m.stats.samples);
            assert_eq!(positions, m.stats.positions);
            assert!(m.pixels.iter().all(|p| p[0] <= p[1] && p[2] + p[3] <= p[4]));
            assert!(m.pixels.iter().all(|p| p[4] <= n * n));
            assert!(m.pixels.iter().any(|p| p[4] == 0), "some rays miss");
            assert!(
                m.pixels.iter().any(|p| p[2] > 0),
                "the opaque scalp stops rays"
            );
        }
    }

    /// Early termination off: no ray stops early, and the samples rise; skipping off: nothing
    /// is skipped, and the samples equal the positions.
    #[test]
    fn the_switches_show_in_the_map() {
        let v = head();
        let on = cost(&v, &RenderSettings::default());
        let no_early = cost(
            &v,
            &RenderSettings {
                early_termination: false,
                ..Default::default()
            },
        );
        assert!(no_early.pixels.iter().all(|p| p[2] == 0));
        assert!(no_early.stats.samples > on.stats.samples);
        let no_skip = cost(
            &v,
            &RenderSettings {
                skipping: false,
                ..Default::default()
            },
        );
        assert_eq!(no_skip.max(CostView::Skipped), 0);
        assert!(no_skip.pixels.iter().all(|p| p[0] == p[1]));
        assert!(
            on.max(CostView::Skipped) > 0,
            "the air around the head is skipped"
        );
        // One scale for both: the same count has the same colour in either map, and a map
        // without early termination is brighter where the scalp stopped the rays.
        assert_eq!(on.full_scale, no_early.full_scale);
        let (a, b) = (
            on.image(CostView::Samples),
            no_early.image(CostView::Samples),
        );
        for (i, (p, q)) in on.pixels.iter().zip(&no_early.pixels).enumerate() {
            if p[0] == q[0] {
                assert_eq!(a.pixels[i], b.pixels[i]);
            }
        }
        let lightness = |im: &LinearImage| im.pixels.iter().map(|c| c.length()).sum::<f32>();
        assert!(lightness(&b) > lightness(&a));
        // No pixel passes the scale: the longest ray's positions per ray.
        assert!(no_skip.pixels.iter().all(|p| p[1] <= no_skip.full_scale));
        let stops = on.image(CostView::Stops);
        assert!(stops.pixels.contains(&EARLY_COLOR) && stops.pixels.contains(&Vec3::ZERO));
        let coarse = cost(
            &v,
            &RenderSettings {
                step: Length::Voxels(1e6),
                ..Default::default()
            },
        );
        assert!(
            coarse.pixels.iter().all(|p| p[1] <= 1),
            "one position a ray"
        );
    }

    #[test]
    fn the_heat_scale_is_logarithmic_and_inverts() {
        assert_eq!(heat(0, 400), 0.0);
        assert_eq!(heat(400, 400), 1.0);
        assert_eq!(heat(900, 400), 1.0, "clamped");
        assert!(
            (heat(20, 440) - 0.5).abs() < 1e-6,
            "√441 − 1 = 20 is the middle"
        );
        for c in [0u32, 1, 3, 20, 150, 400] {
            assert!((count_at(heat(c, 400), 400) - c as f32).abs() < 1e-3 * (1 + c) as f32);
        }
        assert_eq!(heat(5, 0), 1.0, "an empty scale does not divide by zero");
        let words = scale_words(440, 123);
        assert!(
            words.contains("middle 20,")
                && words.contains("yellow 440 ")
                && words.contains("here 123")
        );
    }

    #[test]
    fn views_have_names_and_words() {
        for v in CostView::ALL {
            assert_eq!(CostView::parse(v.name()), Some(v));
            assert!(v.doc().len() > 40);
        }
        assert_eq!(CostView::parse("nothing"), None);
    }
}
